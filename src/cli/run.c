/* psim [OPTIONS] [SCENE [THREADS]]: run a scene. */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>
#include <sys/stat.h>
#include <unistd.h>

#include "affinity.h"
#include "cli.h"
#include "interrupt.h"
#include "measure.h"
#include "outfile.h"
#include "pin.h"
#include "progress.h"
#include "provenance.h"
#include "report.h"
#include "run_options.h"
#include "say.h"
#include "thermo.h"
#include "threads.h"
#include "version.h"
#include "../io/scene.h"
#include "../engine/dist.h"
#include "device.h"
#include "../models/models.h"
#include "../engine/timer.h"

static int default_scene(psim_scene *sc, psim_error *err)
{
    psim_gen_params p = {.n = 20000, .r = 2, .steps = 100, .vmin = -1, .vmax = 1,
                         .seed = 1, .place = PSIM_PLACE_UNIFORM};
    p.L = round(sqrt(p.n * M_PI * p.r * p.r / 0.5));
    return psim_scene_generate(&p, sc, err);
}

/* The model's own scene of -n and -s; over MPI ranks each rank makes its
 * own block of ids alone (the engine sends them to their owners). */
static int make_scene(const run_opts *o, psim_scene *sc, psim_error *err)
{
    return psim_generate_scene_part(o->model, o->n, o->seed, psim_dist_rank(),
                                    psim_dist_ranks(), sc, err);
}

static int load_scene(run_opts *o, psim_scene *sc, psim_error *err)
{
    if (o->n >= 0) {
        snprintf(o->label, sizeof o->label, "n %ld, seed %llu", o->n, o->seed);
        return make_scene(o, sc, err);
    }
    /* the name as messages and the summary show it: control bytes escaped */
    cli_escape(o->label, sizeof o->label, o->scene ? o->scene : "default scene");
    if (!o->scene)
        return default_scene(sc, err);
    int rc;
    if (strcmp(o->scene, "-") == 0) {
        cli_io_begin("reading", "<stdin>", o->quiet);
        rc = psim_scene_read_stream(stdin, "<stdin>", sc, err);
    } else {
        o->scene_st_ok = stat(o->scene, &o->scene_st) == 0;
        cli_io_begin("reading", o->scene, o->quiet);
        rc = psim_scene_read_part(o->scene, sc, err);
    }
    cli_io_end();
    return rc;
}

/* Whether the scene is a regular file, which a second run can read again
 * (a pipe, even one named /dev/stdin or /dev/fd/N, cannot be). */
static int rereadable(const run_opts *o)
{
    return o->scene_st_ok && S_ISREG(o->scene_st.st_mode) && strcmp(o->scene, "-") != 0;
}

/* The scene again, for a second run (first_nonfinite) after its arrays
 * were freed: made again, or read again from a file that has not changed
 * since (the same device, inode, size and modification time); -1 when it
 * cannot be. */
static int reload_scene(const run_opts *o, psim_scene *sc)
{
    psim_error e = {{0}, 0};
    int rc;
    struct stat st;
    if (o->n >= 0)
        rc = make_scene(o, sc, &e);
    else if (!o->scene)
        rc = default_scene(sc, &e);
    else if (!rereadable(o) || stat(o->scene, &st) ||
             st.st_dev != o->scene_st.st_dev || st.st_ino != o->scene_st.st_ino ||
             st.st_size != o->scene_st.st_size ||
             st.st_mtim.tv_sec != o->scene_st.st_mtim.tv_sec ||
             st.st_mtim.tv_nsec != o->scene_st.st_mtim.tv_nsec)
        return -1;
    else
        rc = psim_scene_read_part(o->scene, sc, &e);
    if (rc == 0)
        psim_scene_substeps(sc, o->substeps);
    return rc;
}

typedef struct run_state {
    outfile out, trace, final, stats, thermo, dump, restart;
    cli_thermo th;
    psim_output_style style;
    int print;          /* the model's output holds every step */
} run_state;

/* Its output files, in the order of output_paths. */
enum { OUT_STATS = 3, OUT_THERMO = 4 };
static void output_files(run_state *rs, outfile **l)
{
    outfile *list[RUN_OUTPUTS] = {&rs->out,    &rs->trace, &rs->final,  &rs->stats,
                                  &rs->thermo, &rs->dump,  &rs->restart};
    memcpy(l, list, sizeof list);
}

static int write_out(const run_opts *o, psim_sim *s, const outfile *of, long step, int final)
{
    double t0 = cli_output_begin(s);
    cli_io_begin("writing", of->name, o->quiet);
    int rc = psim_write_output(s, of->f, step, final, (int)o->digits);
    cli_io_end();
    cli_output_end(s, t0);
    return rc;
}

/* The state as a restart file (--restart) whose step count is steps. */
static int write_restart(const run_opts *o, psim_sim *s, const outfile *of, long steps)
{
    double t0 = cli_output_begin(s);
    cli_io_begin("writing", of->name, o->quiet);
    int rc = psim_write_restart(s, of->f, steps);
    cli_io_end();
    cli_output_end(s, t0);
    return rc;
}

static int write_trace(const run_opts *o, psim_sim *s, const outfile *of, long step)
{
    double t0 = cli_output_begin(s);
    cli_io_begin("writing", of->name, o->quiet);
    int rc = psim_write_trace(s, of->f, step, (int)o->digits);
    cli_io_end();
    cli_output_end(s, t0);
    return rc;
}

static void print_summary(FILE *f, const run_opts *o, const psim_scene *sc,
                          const psim_sim *s, double secs)
{
    const psim_stats *st = psim_get_stats(s);
    double steps = st->steps > 0 ? (double)st->steps : 1.0;
    fprintf(f, "psim %s: %s model, %s: %ld disks, L %g, r %g, density %.3f\n",
            PSIM_VERSION, psim_sim_model(s), o->label, psim_scene_count(sc),
            sc->L, sc->r, psim_scene_density(sc));
    fprintf(f, "  %ld steps on %d threads in %.3f s (%.3f ms/step)%s\n", st->steps,
            st->threads, secs, 1e3 * secs / steps, o->check ? ", every step checked" : "");
    fprintf(f, "  phases:");
    for (int p = 0; p < st->nphases; p++)
        if ((p != PSIM_PHASE_CHECK || o->check) &&
            (p != PSIM_PHASE_SORT || st->grid_cells > 0) &&
            (p != PSIM_PHASE_OUTPUT || st->phase_s[p] > 0))
            fprintf(f, " %s %.3f s", psim_phase_name(s, p), st->phase_s[p]);
    fputc('\n', f);
    psim_print_step_summary(f, s);
    psim_print_skips(f, s);
    if (cli_wait_note())
        fprintf(f, "  OpenMP wait policy %s\n", cli_wait_note());
    if (cli_threads_note())
        fprintf(f, "  threads: %s\n", cli_threads_note());
    if (st->grid_cells > 0 && st->tiles_cut)
        fprintf(f, "  grid %d x %d cells of side %g, %d x %d tiles cut where the work was "
                   "(%d tiles)\n",
                st->grid_cells, st->grid_cells, st->cell_side, st->tiles_per_side,
                st->tiles_per_side, st->tiles);
    else if (st->grid_cells > 0)
        fprintf(f, "  grid %d x %d cells of side %g, tiles of %d x %d cells (%d tiles)\n",
                st->grid_cells, st->grid_cells, st->cell_side, st->tile_cells,
                st->tile_cells, st->tiles);
}

/* Output file of at path; over ranks (dist.h) rank 0's, and the others
 * write into it (in_parts: the states' outputs) or nothing (/dev/null
 * stands for it).  Ranks on other machines open it by its name: a named
 * temporary file then, which a rank killed by SIGKILL leaves (an unnamed
 * one goes with rank 0, whatever ends it). */
static int open_output(outfile *of, const char *path, int in_parts)
{
    if (psim_dist_ranks() < 2)
        return outfile_open(of, path);
    if (psim_dist_rank() != 0)
        return outfile_open(of, "/dev/null");
    return in_parts && !psim_dist_one_node() ? outfile_open_named(of, path)
                                             : outfile_open(of, path);
}

/* Open the outputs; 0, 1 when one cannot be opened, 2 when the model's
 * output goes to standard output (its source prints there) and another
 * output or an input is there already (named "the MODEL model's output"). */
static int open_outputs(const run_opts *o, run_state *rs, const char *model)
{
    const char *path[RUN_OUTPUTS];
    outfile *of[RUN_OUTPUTS];
    output_paths(o, path);
    output_files(rs, of);
    if (psim_dist_ranks() > 1)
        psim_dist_one_node();   /* (collective the first time) */
    if (!path[0] && rs->style.to_stdout) {
        char label[64];
        snprintf(label, sizeof label, "the %s model's output", model);
        if (check_outputs(o, label))
            return 2;
        path[0] = "-";
    }
    for (int k = 0; k < RUN_OUTPUTS; k++)
        if (path[k] && open_output(of[k], path[k], k != OUT_STATS && k != OUT_THERMO))
            return 1;
    return 0;
}

/* Over ranks, collective: output of opened by every rank, to write its
 * parts of it (dist.h); 0, or -1 with errno set. */
static int share_output(const outfile *of)
{
    char proc[48];
    const char *name = of->tmp;
    if (of->unnamed) {   /* (rank 0's) */
        snprintf(proc, sizeof proc, "/proc/%ld/fd/%d", (long)getpid(), of->fd);
        name = proc;
    }
    return psim_dist_output_open(of->f, name);
}

/* Over ranks, collective: the outputs of states opened by every rank, to
 * write its parts of them; 0, or 1 after rank 0 said why not. */
static int share_outputs(run_state *rs)
{
    outfile *of[RUN_OUTPUTS];
    output_files(rs, of);
    for (int k = 0; k < RUN_OUTPUTS; k++)
        if (of[k]->f && k != OUT_STATS && k != OUT_THERMO && share_output(of[k])) {
            if (psim_dist_rank() == 0)
                cli_err("psim: %s: cannot write: %s", of[k]->name, strerror(errno));
            return 1;
        }
    return 0;
}

static void abort_outputs(run_state *rs)
{
    psim_dist_outputs_close();   /* (over ranks: collective) */
    outfile *of[RUN_OUTPUTS];
    output_files(rs, of);
    for (int k = 0; k < RUN_OUTPUTS; k++)
        outfile_abort(of[k]);
}

/* Whether the model's output holds the state after step k, last being
 * the run's last step (written after the loop with its own columns, if
 * final). */
static int out_due(const run_state *rs, long k, long last)
{
    if (rs->style.final && k == last)
        return 0;
    return rs->print || (rs->style.period > 0 && (k - 1) % rs->style.period == 0);
}

/* "NAME: write failed: REASON", the reason from errno (EIO if none). */
static void set_write_failed(psim_error *err, const char *name)
{
    if (psim_dist_rank() != 0) {   /* rank 0 says why (errno: every rank's) */
        psim_error_set(err, "%s", "");
        return;
    }
    int e = errno ? errno : EIO;
    psim_error_set(err, "%s: write failed: %s", name, strerror(e));
}

/* An extended XYZ frame of the state after step k (--dump). */
static int write_dump(psim_sim *s, run_state *rs, long k)
{
    double t0 = cli_output_begin(s);
    int rc = psim_write_dump(s, rs->dump.f, k);
    cli_output_end(s, t0);
    return rc;
}

/* The states due after step k (last: the run's last step): the trace
 * every step, the model's output as its source writes it, the dump every
 * --dump-every steps and after the last. */
static int write_step(const run_opts *o, psim_sim *s, long k, long last, run_state *rs,
                      psim_error *err)
{
    if (rs->dump.f && (k % o->dump_every == 0 || k == last) && write_dump(s, rs, k)) {
        set_write_failed(err, o->dump);
        return -1;
    }
    if (rs->trace.f && write_trace(o, s, &rs->trace, k)) {
        set_write_failed(err, o->trace);
        return -1;
    }
    if (rs->out.f && out_due(rs, k, last) && write_out(o, s, &rs->out, k, 0)) {
        set_write_failed(err, rs->out.name);
        return -1;
    }
    return 0;
}

/* Over ranks: whether a step of the start that some rank failed (rc)
 * failed on any; the lowest rank that failed with a message (msg) says
 * why, the others keep quiet.  Without ranks: rc, said. */
static int ranks_failed(int rc, const char *msg)
{
    const int said = rc != 0 && msg && *msg;
    if (psim_dist_agree(said) == psim_dist_rank() && said)
        cli_err("psim: %s", msg);
    return psim_dist_agree(rc != 0) >= 0;
}

/* --restart-every: the state after step k as the restart file, in place
 * of the last one (renamed into place, so a run killed at any time leaves
 * a whole file); its step count is what remains of the run, so running it
 * ends where this run will. */
static int checkpoint(const run_opts *o, psim_sim *s, run_state *rs, long k, long last,
                      psim_error *err)
{
    if (!o->restart_every || k % o->restart_every || k == last)
        return 0;
    if (write_restart(o, s, &rs->restart, last - k)) {
        set_write_failed(err, o->restart);
        return -1;
    }
    /* over ranks every rank closes the file, rank 0 puts it in place
     * and opens the next, as open_outputs; a failure is every rank's */
    int failed = psim_dist_output_close(rs->restart.f) != 0;
    failed = failed || outfile_commit(&rs->restart) || open_output(&rs->restart, o->restart, 1);
    if (ranks_failed(failed, NULL)) {
        if (failed)
            psim_error_set(err, "%s: checkpoint failed", o->restart);
        else
            psim_error_set(err, "%s", "");
        return -1;
    }
    if (psim_dist_ranks() > 1 && share_output(&rs->restart)) {
        set_write_failed(err, o->restart);
        return -1;
    }
    return 0;
}

/* err, naming the step a state was seen not finite at, when no second run
 * could find the first: that step is only the latest it can be. */
static void uncertain_step(psim_error *err, long checked)
{
    if (!*err->msg)   /* over ranks: another rank names it */
        return;
    char was[sizeof err->msg];
    memcpy(was, err->msg, sizeof was);
    psim_error_set(err, "%s (the first bad step lies after step %ld, where the state was "
                        "finite; the scene could not be read again to find it)",
                   was, checked);
}

/* The first step whose state is not finite, found again: a state that
 * overflowed is seen at step `seen`, and the last check before it was at
 * step `checked` (finite).  The run is deterministic, so a second engine
 * from the same scene and configuration steps to `checked` and checks
 * every step after it (this costs at most the steps run so far, and only
 * when a run fails); the scene's arrays having been freed, it makes or
 * reads the scene again.  err: the first bad step and disk; or, when the
 * second run cannot say (the scene file changed since, or no memory), the
 * step it was seen at, said to be no more than that. */
static void first_nonfinite(const run_opts *o, const psim_scene *sc, const psim_config *cfg,
                            long checked, long seen, psim_error *err)
{
    psim_error e2 = {{0}, 0};
    psim_scene again = {0};
    if (!sc->x)
        sc = reload_scene(o, &again) ? NULL : &again;
    psim_sim *s2 = sc ? psim_create(sc, cfg, &e2) : NULL;
    int looked = s2 != NULL;   /* at every step before `seen` */
    for (long k = s2 ? psim_step_index(s2) + 1 : seen; k < seen; k++) {
        if (psim_step(s2, &e2)) {
            looked = 0;
            break;
        }
        if (k > checked && psim_state_finite(s2, &e2)) {
            *err = e2;
            break;
        }
    }
    if (!looked)
        uncertain_step(err, checked);
    psim_destroy(s2);
    psim_scene_clear(&again);
}

/* The state is finite (0), or err names the disk that is not, at the
 * first step it was not (found again when the step before was not
 * checked). */
static int finite_since(const run_opts *o, const psim_sim *s, const psim_scene *sc,
                        const psim_config *cfg, long checked, psim_error *err)
{
    if (psim_state_finite(s, err) == 0)
        return 0;
    if (psim_step_index(s) - checked > 1)
        first_nonfinite(o, sc, cfg, checked, psim_step_index(s), err);
    return -1;
}

/* Progress inside a long step: the run's progress, and its first step. */
typedef struct inside {
    progress *pb;
    long first;
} inside;

static void show_inside(void *ctx, const psim_step_progress *r)
{
    const inside *in = ctx;
    progress_inside(in->pb, r->step - in->first, r);
}

/* The steps' progress: between steps and inside long ones; a thermo table
 * shows the steps itself (then only long steps show, as lines, which keep
 * the table whole). */
static void watch_steps(const run_opts *o, psim_sim *s, long steps, progress *pb, inside *in)
{
    progress_init(pb, steps, o->quiet);
    if (o->thermo)
        pb->inside_only = 1, pb->tty = 0;
    *in = (inside){pb, psim_step_index(s)};
    double first_s, every_s;
    progress_inside_times(pb, &first_s, &every_s);
    if (pb->enabled)
        psim_set_step_progress(s, show_inside, in, first_s, every_s);
}

/* The steps: 0, -1 with err set, or -2 when a signal stopped them. */
/* Steps between the checks that the state is finite, over ranks (a pass
 * over the particles and an allreduce: well under 1% of the steps). */
#define RANKS_CHECK_EVERY 16

static int simulate(const run_opts *o, psim_sim *s, const psim_scene *sc,
                    const psim_config *cfg, long steps, run_state *rs, psim_error *err)
{
    progress pb;
    inside in;
    watch_steps(o, s, steps, &pb, &in);
    /* SIGINT and SIGTERM from here to the last step: stop at the next poll */
    cli_interrupt_arm();
    int rc = 0;
    /* steps are numbered on from a restart file's */
    const long first = psim_step_index(s), last = first + steps;
    if (rs->dump.f && write_dump(s, rs, first)) {
        set_write_failed(err, o->dump);
        rc = -1;
    }
    if (rc == 0 && thermo_start(&rs->th, s, o->quiet ? NULL : stderr, rs->thermo.f, err))
        rc = -1;
    if (rs->out.f && (psim_write_header(s, rs->out.f) ||
                      (rs->style.initial && write_out(o, s, &rs->out, first, 0)))) {
        set_write_failed(err, rs->out.name);
        rc = -1;
    }
    /* A state that overflowed is found at the step it happened: states
     * written every step are checked every step, and the states of thermo
     * rows (whose sums a state that is not finite would make infinite,
     * not too large); otherwise as often as
     * costs about 1% of the steps' time (a check reads the whole state,
     * so every step where a step is cheap, every few where it is not),
     * and the final state in any case; a state found not finite after
     * unchecked steps sends a second run to find the first bad step. */
    const int each = rs->trace.f || rs->print;
    /* PSIM_CHECK_EVERY=N: a fixed interval instead (tests, docs/reliability.md) */
    const char *ev = getenv("PSIM_CHECK_EVERY");
    const long every = ev && atol(ev) > 0 ? atol(ev) : 0;
    const int ranks = psim_dist_ranks();
    double check_s = 0, steps_s = 0;
    long checked = first;   /* the last step whose state was seen finite */
    for (long k = first + 1; k <= last && rc == 0; k++) {
        double t0 = psim_now();
        if (psim_step(s, err)) {
            rc = psim_stop_requested() ? -2 : -1;
            break;
        }
        steps_s += psim_now() - t0;
        /* (under --check the engine has checked this state already) */
        /* (over ranks the check is collective: every rank on the same
         * steps, RANKS_CHECK_EVERY apart at most) */
        if (!cfg->check &&
            (each || k == last || thermo_due(&rs->th, k, last) ||
             (every ? k % every == 0
                    : ranks > 1 ? k % RANKS_CHECK_EVERY == 0 : 0.01 * steps_s >= check_s))) {
            double t1 = psim_now();
            if (finite_since(o, s, sc, cfg, checked, err)) {
                rc = -1;
                break;
            }
            check_s = psim_now() - t1, steps_s = 0, checked = k;
        }
        if (write_step(o, s, k, last, rs, err) || checkpoint(o, s, rs, k, last, err))
            rc = -1;
        else if (thermo_step(&rs->th, s, k, last, err))
            rc = -1;
        else
            progress_update(&pb, k - first);
    }
    progress_done(&pb); /* also on failure: the error line starts clean */
    psim_set_step_progress(s, NULL, NULL, 0, 0);
    /* from here a signal ends psim at once; one that came after the last
     * step's end stops the run all the same */
    cli_interrupt_disarm();
    if (rc == 0 && cli_interrupted()) {
        psim_error_set(err, "after step %ld: interrupted", psim_step_index(s));
        rc = -2;
    }
    return rc;
}

static int on_stdout(const outfile *o)
{
    return o->f == stdout;
}

/* The run's OpenMP threads first, then the thread that takes SIGINT and
 * SIGTERM: a tool that places threads in the order they start
 * (likwid-pin) gives its CPUs to the threads that work. */
static void start_threads(void)
{
    static int started;   /* (a region with no work would be left out) */
#pragma omp parallel
    __atomic_fetch_add(&started, 1, __ATOMIC_RELAXED);
    cli_interrupt_watch();
}

/* The signal that stopped the run, as its line names it. */
static const char *stop_signal_name = "SIGINT";

/* The steps' end (ran: simulate's), over ranks: a signal that stopped any
 * rank stops every rank, also one that came to one rank alone after its
 * last step; the ranks agree on it, so that rank 0 alone names it and
 * every rank leaves the run (the others exit 1, the ranks it came to end
 * by it).  A failure of several ranks at once is said by the lowest of
 * them (err's message emptied on the others).  Without ranks: ran. */
static int ranks_stopped(int ran, const psim_sim *s, psim_error *err)
{
    if (psim_dist_ranks() < 2) {
        stop_signal_name = cli_interrupt_name();
        return ran;
    }
    /* (every rank comes here once its steps end: both are collective) */
    const int said = ran == -1 && *err->msg;
    if (psim_dist_agree(said) != psim_dist_rank() && said)
        psim_error_set(err, "%s", "");
    /* (SIGTERM outranks SIGINT in the largest) */
    const int sig = (int)psim_dist_max((double)cli_interrupted());
    if (!sig)
        return ran;
    stop_signal_name = sig == SIGTERM ? "SIGTERM" : "SIGINT";
    if (ran == 0)
        psim_error_set(err, "after step %ld: interrupted", psim_step_index(s));
    return -2;
}

/* parse_run; over MPI ranks, whose command lines are the same, what it
 * prints (a usage error, --help, --version) comes from rank 0 alone. */
static int ranks_parse(int argc, char **argv, run_opts *o)
{
    if (psim_dist_rank() == 0)
        return parse_run(argc, argv, o);
    fflush(stdout), fflush(stderr);
    int out = dup(1), err = dup(2), nul = open("/dev/null", O_WRONLY);
    if (nul >= 0)
        dup2(nul, 1), dup2(nul, 2), close(nul);
    int rc = parse_run(argc, argv, o);
    fflush(stdout), fflush(stderr);
    if (out >= 0)
        dup2(out, 1), close(out);
    if (err >= 0)
        dup2(err, 2), close(err);
    return rc;
}

/* What a run over ranks cannot do yet: 0, or 2 after saying so (rank 0). */
static int ranks_refuse(const run_opts *o)
{
    const char *what = o->thermo || o->thermo_file ? "--thermo"
                       : o->scene && strcmp(o->scene, "-") == 0 ? "a scene on standard input"
                                                                 : NULL;
    if (!what || psim_dist_ranks() < 2)
        return 0;
    if (psim_dist_rank() == 0)
        cli_err("psim: %s: not over MPI ranks (run it in one process)", what);
    return 2;
}

/* The figures of every rank, as --stats JSON members (rank 0). */
static char *ranks_json(const psim_sim *s, const psim_rank_stats *per, int n, int pinned)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    if (!f)
        return NULL;
    const psim_stats *st = psim_get_stats(s);
    /* the imbalance: the busiest rank's work (its phases less its waiting
     * for the others) over the mean */
    double most = 0, sum = 0;
    for (int q = 0; q < n; q++) {
        double busy = -per[q].wait_s;
        for (int p = 0; p < st->nphases; p++)
            busy += per[q].phase_s[p];
        most = busy > most ? busy : most, sum += busy;
    }
    /* (pinned under a launcher, the pin section has "rank" and "ranks") */
    if (!pinned)
        fprintf(f, "  \"ranks\": %d,\n", n);
    fprintf(f, "  \"rank_imbalance\": %.4f,\n  \"per_rank\": [", sum > 0 ? most / (sum / n) : 1.0);
    for (int q = 0; q < n; q++) {
        const psim_rank_stats *r = &per[q];
        fprintf(f, "%s\n    {\"rank\": %d, \"threads\": %d, \"owned\": %ld, \"ghosts\": %ld, "
                   "\"comm_s\": %.6f, \"exchange_s\": %.6f, \"update_s\": %.6f, "
                   "\"wait_s\": %.6f, \"bytes_sent\": %llu, \"messages_sent\": %llu, "
                   "\"exchanges\": %llu, \"recuts\": %llu, \"phases_s\": {",
                q ? "," : "", q, st->threads, r->owned, r->ghosts, r->comm_s, r->exchange_s,
                r->update_s, r->wait_s,
                (unsigned long long)r->bytes_sent, (unsigned long long)r->messages_sent,
                (unsigned long long)r->exchanges, (unsigned long long)r->recuts);
        for (int p = 0; p < st->nphases; p++)
            fprintf(f, "%s\"%s\": %.6f", p ? ", " : "", st->phase_name[p], r->phase_s[p]);
        fprintf(f, "}}");
    }
    fprintf(f, "\n  ]");
    return fclose(f) ? (free(buf), NULL) : buf;
}

/* The summary's lines for ranks: each rank's share, time and traffic. */
static void ranks_summary(FILE *f, const psim_sim *s, const psim_rank_stats *per, int n)
{
    const psim_stats *st = psim_get_stats(s);
    fprintf(f, "  %d MPI ranks x %d threads:\n", n, st->threads);
    for (int q = 0; q < n; q++) {
        double busy = 0;
        for (int p = 0; p < st->nphases; p++)
            busy += per[q].phase_s[p];
        fprintf(f, "    rank %d: %ld disks + %ld ghosts, %.3f s in phases (comm %.3f s: exchanges "
                   "%.3f, ghosts %.3f, waiting %.3f), %.1f MB in %llu messages sent, %llu "
                   "exchanges\n",
                q, per[q].owned, per[q].ghosts, busy, per[q].comm_s, per[q].exchange_s,
                per[q].update_s, per[q].wait_s,
                (double)per[q].bytes_sent / 1e6, (unsigned long long)per[q].messages_sent,
                (unsigned long long)per[q].exchanges);
    }
}

int cli_run(int argc, char **argv)
{
    run_opts o;
    cli_start start;
    cli_start_note(&start);
    int rc = ranks_parse(argc, argv, &o);
    if (rc) {
        free(o.options);
        return rc < 0 ? 0 : rc;   /* -1: --help or --version, done */
    }
    if ((rc = ranks_refuse(&o)) != 0) {
        free(o.options);
        return rc;
    }
    const int ranks = psim_dist_ranks();
    psim_rank_stats *per = NULL;
    if (psim_dist_rank() != 0)   /* rank 0 speaks for the run */
        o.quiet = 1, o.report = 0;
    psim_error err = {{0}, 0};
    psim_scene sc = {0};
    run_state rs = {0};
    psim_sim *s = NULL;
    rc = 1;
    /* LIKWID's marker API (a -DPSIM_LIKWID=ON build under likwid-perfctr
     * -m), closed at done: started before the OpenMP runtime has threads,
     * as its start forks children whose exit would wait on LLVM's libomp's
     * threads, which a child has not */
    psim_markers_init();
    omp_set_dynamic(0);
    const int asked = o.threads ? (int)o.threads : omp_get_max_threads(),
              threads = cli_threads_cap(asked);
    if (threads < asked)
        o.threads = threads;   /* the runtime would start no more */
    if (!o.pin.dry_run && cli_threads_startable(threads))
        goto done;
    if (o.pin.dry_run) {
        if (cli_pin_setup(&o.pin, (int)o.threads, o.quiet) == 0) {
            psim_pin_plan_print(stdout, o.pin.topo, &o.pin.plan);
            rc = 0;
        }
        goto done;
    }
    /* the scene is read with the threads asked for (all by default) */
    if (o.threads)
        omp_set_num_threads((int)o.threads);
    if (cli_device_use(o.device)) {
        rc = 2;
        goto done;
    }
    start_threads();
    double t_read = psim_now();
    int failed = load_scene(&o, &sc, &err);
    if (ranks_failed(failed, err.msg)) {
        rc = failed && err.usage ? 2 : 1;
        goto done;
    }
    o.read_s = psim_now() - t_read;
    psim_scene_substeps(&sc, o.substeps);
    long steps = o.steps >= 0 ? o.steps * o.substeps : sc.steps;
    /* pinned before the engine allocates, so first touch lands on the
     * planned cores */
    int pin_rc = cli_pin_setup(&o.pin, (int)o.threads, o.quiet);
    if (pin_rc) {
        rc = pin_rc == -2 ? 2 : 1;
        goto done;
    }
    /* the team's threads register with LIKWID, which pins them, before
     * the engine's first touch of its memory */
    psim_markers_threads(o.pin.plan.threads);
    psim_config cfg;
    psim_config_default(&cfg);
    cfg.model = o.model;
    cfg.threads = o.pin.plan.threads;
    cfg.tile_cells = (int)o.tile;
    cfg.check = o.check;
    /* (PSIM_FIXED_THREADS=1 as well: the test suite's parallel paths run
     * on every thread in every step) */
    const char *fx = getenv("PSIM_FIXED_THREADS");
    cfg.fixed_threads = o.fixed_threads || (fx && atoi(fx) > 0);
    cfg.options = o.options;
    cfg.steps = steps;
    /* The engine takes the scene's particles (freed once its store holds
     * them), except from what cannot be read twice (standard input, a
     * pipe, a FIFO, a device): that scene is kept whole for a second run
     * that looks for the first non-finite step; any other is made or read
     * again for it. */
    const int keep_scene = o.scene && !rereadable(&o);
    s = keep_scene ? psim_create(&sc, &cfg, &err) : psim_create_taking(&sc, &cfg, &err);
    if (ranks_failed(!s, err.msg)) {
        rc = !s && err.usage ? 2 : 1;
        goto done;
    }
    /* and the line numbers go too (8 bytes a particle), now that the
     * model has set itself up */
    if (!keep_scene)
        psim_scene_clear(&sc);
    rs.style = psim_get_output_style(s);
    rs.print = rs.style.every_step && sc.print;
    thermo_init(&rs.th, o.thermo, o.thermo_speed);
    int opened = open_outputs(&o, &rs, psim_sim_model(s));
    if (ranks_failed(opened, NULL)) {   /* (outfile_open said why) */
        rc = opened ? opened : 1;
        goto done;
    }
    if (ranks > 1 && share_outputs(&rs))
        goto done;
    double t0 = psim_now();
    int ran = ranks_stopped(simulate(&o, s, &sc, &cfg, steps, &rs, &err), s, &err);
    /* (over ranks, a rank that did not fail itself has no message) */
    if (ran == -2 && psim_dist_rank() == 0)   /* and psim ends by the signal (main) */
        cli_err("psim: %s: %s by %s", o.label, err.msg, stop_signal_name);
    else if (ran && ran != -2 && *err.msg)
        cli_err("psim: %s: %s", o.label, err.msg);
    if (ran)
        goto done;
    /* the steps' time, without the states written between them (the
     * course's own figure, for the source's summary, includes them) */
    double loop_s = psim_now() - t0;
    double secs = loop_s - psim_get_stats(s)->phase_s[PSIM_PHASE_OUTPUT];
    const long last = psim_step_index(s);
    if (rs.out.f && rs.style.final && write_out(&o, s, &rs.out, last, 1)) {
        set_write_failed(&err, rs.out.name);
        if (*err.msg)   /* (over ranks, rank 0's) */
            cli_err("psim: %s", err.msg);
        goto done;
    }
    if (rs.final.f && write_trace(&o, s, &rs.final, last)) {
        set_write_failed(&err, rs.final.name);
        if (*err.msg)   /* (over ranks, rank 0's) */
            cli_err("psim: %s", err.msg);
        goto done;
    }
    if (rs.restart.f && write_restart(&o, s, &rs.restart, steps)) {
        set_write_failed(&err, rs.restart.name);
        if (*err.msg)   /* (over ranks, rank 0's) */
            cli_err("psim: %s", err.msg);
        goto done;
    }
    if (ranks > 1) {   /* every rank's figures to rank 0 */
        if (psim_dist_rank() == 0 && !(per = calloc((size_t)ranks, sizeof *per))) {
            cli_err("psim: out of memory");
            psim_dist_abort(1);
        }
        psim_dist_reduce_stats(s, per);
    }
    if ((o.report || o.stats) && !o.pin.topo)
        o.pin.topo = psim_topo_load(NULL, &err); /* for the CPU kinds; may fail */
    if (rs.stats.f) {
        char *pin_json = cli_pin_json(&o.pin), *thr_json = cli_threads_json(s, &o.pin),
             *prov_json = cli_provenance_json(&start);
        char *extra = NULL, *rk_json = per ? ranks_json(s, per, ranks, o.pin.ranked)
                                  : strdup(o.pin.ranked ? "  \"rank_imbalance\": 1" : "  \"ranks\": 1");
        if (pin_json && thr_json && prov_json && rk_json &&
            asprintf(&extra, "  \"read_s\": %.6f,\n  \"peak_rss_bytes\": %lld,\n%s,\n%s,\n%s,\n%s\n",
                     o.read_s, cli_peak_rss(), pin_json, thr_json, prov_json, rk_json) < 0)
            extra = NULL;
        free(rk_json);
        psim_write_stats_json(rs.stats.f, s,
                              o.scene ? o.scene : o.n >= 0 ? o.label : "default", secs, extra);
        free(pin_json), free(thr_json), free(prov_json), free(extra);
    }
    /* the summary goes to stderr when an output is on stdout */
    outfile *outs[RUN_OUTPUTS];
    output_files(&rs, outs);
    FILE *info = stdout;
    for (int k = 0; k < RUN_OUTPUTS; k++)
        if (on_stdout(outs[k]))
            info = stderr;
    /* (over ranks every rank's writes end before rank 0 puts the files
     * in place) */
    if (psim_dist_outputs_close()) {
        set_write_failed(&err, "the outputs");
        if (*err.msg)
            cli_err("psim: %s", err.msg);
        goto done;
    }
    if (ranks_failed(outfile_commit_all(outs, RUN_OUTPUTS), NULL))
        goto done;
    if (!o.quiet) {
        psim_print_source_summary(info, s, loop_s);
        print_summary(info, &o, &sc, s, secs);
        if (per)
            ranks_summary(info, s, per, ranks);
        cli_pin_summary(info, &o.pin, s);
    }
    if (o.report)
        cli_report(info, s, &o.pin);
    rc = 0;   /* main reports a standard output that could not be written */
done:
    free(per);
    psim_markers_close();
    abort_outputs(&rs);
    cli_pin_free(&o.pin);
    free(o.options);
    psim_destroy(s);
    psim_scene_clear(&sc);
    return rc;
}

/* psim models: one line per model. */
int cli_models(int argc, char **argv)
{
    if (argc == 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        printf("usage: psim models\n\nList the models, one line each, with their options "
               "(--option NAME=V)\nand whether they run over MPI ranks.\n\noptions:\n  -h, --help     show this help\n"
               "  -V, --version  show the version\n");
        return 0;
    }
    if (argc == 2 && (!strcmp(argv[1], "--version") || !strcmp(argv[1], "-V"))) {
        cli_version(stdout);
        return 0;
    }
    if (argc > 1) {
        cli_err("psim models: unexpected argument '%s'", argv[1]);
        return 2;
    }
    for (int k = 0; k < psim_model_count(); k++) {
        printf("%-10s %s\n", psim_model_name(k), psim_model_summary(k));
        if (psim_model_distributed(k))
            printf("%-10s   runs over MPI ranks (mpirun -np R psim ...: docs/scale-out.md)\n", "");
        if (psim_model_gpu(k))
            printf("%-10s   runs on a CUDA device (--device gpu: docs/gpu.md)\n", "");
        const char *name, *help;
        for (int i = 0; psim_model_option_info(k, i, &name, &help) == 0; i++)
            printf("%-10s   --option %s=V: %s\n", "", name, help);
    }
    return 0;
}
