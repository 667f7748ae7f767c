/* The force model behind the model interface: constants, options, the
 * step (neighbour lists or the naive loops), and the course's output. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "force.h"
#include "../../engine/gpu.h"
#include "../../engine/mem.h"
#include "../../io/cs267_random.h"

/* Default skin of the neighbour lists, in cutoffs (docs/performance.md,
 * "Neighbour-list skin": measured against the rebuild rate). */
#define FORCE_SKIN 2.0
/* Cells as small as the list radius allows, up to this many particles:
 * the lists are sparse (about one neighbour), so every candidate beyond
 * the radius is wasted work. */
#define FORCE_CELL_PARTICLES 1.0

/* The course's constants for its own scenes; for a scene of disks (a
 * file), the cutoff is the contact distance 2r, a step is one time unit
 * (velocities are per step there) and the mass makes the dynamics the
 * course's in units where the cutoff is 0.01 and a step 0.0005. */
static void set_law(flaw *k, const psim_sim *e, const psim_scene *sc)
{
    int course = sc->format == PSIM_SCENE_CS267;
    double cutoff = psim_engine_option(e, "cutoff", course ? CS267_CUTOFF : 2 * sc->r);
    double scale = cutoff / CS267_CUTOFF;
    /* the acceleration goes as 1 / (length mass): lengths scaled by
     * `scale` and time by 1 / dt leave it the course's for this mass */
    double mass = course ? CS267_MASS : CS267_MASS / (scale * scale * CS267_DT * CS267_DT);
    k->size = sc->L;
    k->cutoff = cutoff;
    k->mass = psim_engine_option(e, "mass", mass);
    k->dt = psim_engine_option(e, "dt", course ? CS267_DT : 1.0);
    k->cutoff2 = k->cutoff * k->cutoff;
    double min_r = k->cutoff / 100;
    k->min_r2 = min_r * min_r;
}

/* The largest box, positions and law the force's arithmetic can carry
 * out.  Positions and the box: a reflection off a wall, 2L - x, stays
 * finite.  The list radius, cutoff + skin: its square (the pair tests,
 * nlist.c) stays finite, with a factor of 1e4 to spare: past it (a cutoff
 * 2r of 1e158 in a box of 1e170) every pair's r2 is within an infinite
 * cutoff^2, the scaled mass (set_law) is 0, and the forces were NaN, a
 * state reported as overflowed although it had not.  For a scene file,
 * whose mass is scaled from the cutoff, that mass must be a normal double
 * and the largest velocity change one pair can give in a step, |coef|
 * min_r dt at the closest distance the law takes (min_r = cutoff / 100),
 * at most FORCE_MAX_KICK (2.5e3 cutoff dt).  A mass set with
 * --option mass is the user's: its forces are taken as they come. */
#define FORCE_MAX_LENGTH 1e307
#define FORCE_MAX_REACH 1e152
#define FORCE_MAX_KICK 1e300

/* Which of the scene's lines (r) or the run's options a law comes from,
 * as the start of a message ("FILE:LINE: radius r = R" or "--option
 * cutoff=C"), and whether the options are at fault (usage). */
static int law_source(const psim_sim *e, const psim_scene *sc, char *buf, size_t size)
{
    if (isnan(psim_engine_option(e, "cutoff", NAN)) && sc->format != PSIM_SCENE_CS267) {
        char at[320];
        psim_scene_where_header(sc, PSIM_LINE_R, at, sizeof at);
        snprintf(buf, size, "%sradius r = %g", at, sc->r);
        return 0;
    }
    snprintf(buf, size, "--option cutoff=%g", psim_engine_option(e, "cutoff", CS267_CUTOFF));
    return 1;
}

static int law_limits(const psim_sim *e, const psim_scene *sc, psim_error *err)
{
    flaw k;
    set_law(&k, e, sc);
    const double skin = psim_engine_option(e, "skin", FORCE_SKIN) * k.cutoff;
    const double min_r = sqrt(k.min_r2);
    const double kick = fabs((1 - k.cutoff / min_r) / k.min_r2 / k.mass) * min_r * k.dt;
    const int derived = isnan(psim_engine_option(e, "mass", NAN)) && sc->format != PSIM_SCENE_CS267;
    char what[400];
    if (!(k.cutoff + skin <= FORCE_MAX_REACH)) {
        int usage = law_source(e, sc, what, sizeof what);
        psim_error_set(err, "%s is too large for the force model: its list radius, cutoff + "
                            "skin = %g, is above %g (its square would overflow)",
                       what, k.cutoff + skin, FORCE_MAX_REACH);
        if (err)
            err->usage = usage;
        return -1;
    }
    if (derived && !(k.mass >= DBL_MIN && kick <= FORCE_MAX_KICK)) {
        int usage = law_source(e, sc, what, sizeof what);
        if (!isnan(psim_engine_option(e, "dt", NAN))) {   /* the step is at fault */
            snprintf(what, sizeof what, "--option dt=%g (cutoff %g)", k.dt, k.cutoff);
            usage = 1;
        }
        psim_error_set(err, "%s is too large for the force model: with the mass that keeps "
                            "the course's dynamics, 0.01 / (cutoff / 0.01 * 0.0005)^2 = %g, "
                            "%s (set --option mass= to choose one)",
                       what, k.mass,
                       k.mass >= DBL_MIN ? "a pair's velocity change in a step is too large "
                                           "for a double"
                                         : "below the smallest normal double, its forces "
                                           "would divide by 0");
        if (err)
            err->usage = usage;
        return -1;
    }
    return 0;
}

/* A particle whose first move takes it more than FLAW_MAX_BOUNCES + 4
 * box sides away, whatever the forces of the first step do to it (at most
 * n pairs' largest velocity change each), would leave the box for good at
 * step 1 (law.h): refused now, naming its line.  0, or -1. */
static int leaves_box(const psim_sim *e, const psim_scene *sc, psim_error *err)
{
    flaw k;
    set_law(&k, e, sc);
    const double min_r = sqrt(k.min_r2);
    const double kick = fabs((1 - k.cutoff / min_r) / k.min_r2 / k.mass) * min_r * k.dt;
    const double most = (FLAW_MAX_BOUNCES + 4) * k.size, slack = (double)psim_scene_all(sc) * kick * k.dt;
    for (long i = 0; i < sc->n; i++) {
        double v = fmax(fabs(sc->vx[i]), fabs(sc->vy[i])), p = fmax(fabs(sc->x[i]), fabs(sc->y[i]));
        if (!(v * k.dt - slack > most + p))
            continue;
        char at[320];
        psim_scene_where(sc, i, at, sizeof at);
        psim_error_set(err, "%sdisk %ld moves %g a step (v dt, dt %g): too large for the force "
                            "model in a box of L = %g: past %d box sides its reflections off "
                            "the walls (at most %d a step) cannot bring it back",
                       at, psim_scene_id(sc, i), v * k.dt, k.dt, k.size, FLAW_MAX_BOUNCES + 4,
                       FLAW_MAX_BOUNCES);
        return -1;
    }
    return 0;
}

static int limits(const psim_sim *e, const psim_scene *sc, psim_limits *lim, psim_error *err)
{
    lim->at[PSIM_LIMIT_BOX] = (psim_limit){FORCE_MAX_LENGTH,
                                           "its reflections off the walls (2L - x)"};
    lim->at[PSIM_LIMIT_POSITION] = (psim_limit){FORCE_MAX_LENGTH,
                                                "its reflections off the walls (2L - x)"};
    return law_limits(e, sc, err) || leaves_box(e, sc, err) ? -1 : 0;
}

/* Tiles for the threads: the sums do not depend on the tiles (each
 * particle's forces are added in the naive loop's order), so with more
 * than one thread there are at least FORCE_TILES_PER_THREAD tiles a thread
 * (the engine's default of about 16k particles a tile gives 1e5 particles
 * 4 tiles, which two threads share unevenly); one thread keeps the
 * default.  Cells per tile side, a power of two (0: the default). */
#define FORCE_TILES_PER_THREAD 16
/* ... but no fewer particles a tile than this: a tile's two tasks a step
 * cost about a microsecond, some 10% of a tile of 1000 particles (at 1000
 * particles, 36 tiles made two threads four times slower than one tile) */
#define FORCE_TILE_MIN 1024.0
static int tile_cells(const psim_sim *e)
{
    double want = (double)e->n / (FORCE_TILES_PER_THREAD * (double)e->threads);
    want = want > FORCE_TILE_MIN ? want : FORCE_TILE_MIN;
    if (e->threads < 2 || want >= PSIM_TILE_PARTICLES)
        return 0;
    double side = sqrt(want / FORCE_CELL_PARTICLES);
    return 1 << (int)lround(log2(side));
}

static void destroy(void *p)
{
    fmodel *m = p;
    if (!m)
        return;
    fgpu_destroy(m->gpu);
    for (uint32_t t = 0; m->tiles && t < m->cap_tiles; t++) {
        ftile *t_ = &m->tiles[t];
        for (int b = 0; b < FORCE_BUCKETS; b++)
            psim_free(t_->pair[b]);
        psim_free(t_->rx), psim_free(t_->ry), psim_free(t_->rj), psim_free(t_->win), psim_free(t_->fx);
        psim_free(t_->stage_pair), psim_free(t_->stage_d2);
        psim_free(t_->fast);
        psim_free(t_->hit), psim_free(t_->rec), psim_free(t_->out), psim_free(t_->slow);
    }
    for (int k = 0; m->acc && k < m->acc->n; k++) {
        facc *a = &m->acc->set[k];
        psim_free(a->ax), psim_free(a->ay), psim_free(a->cnt);
    }
    if (m->acc)
        free(m->acc->set), free(m->acc->busy), free(m->acc->last);
    free(m->acc);
    free(m->sweep);
    psim_free(m->is_fast), psim_free(m->fs_v2);
    psim_free(m->fp), psim_free(m->fp_next);
    psim_free(m->fh_key), psim_free(m->fh_head);
    free(m->tiles);
    free(m);
}

/* The naive loops test n^2 pairs a step: a run that would take more than
 * FORCE_REFUSE_S at FORCE_NAIVE_RATE pair tests a second a thread (some
 * eight times the rate measured: 1.3e8 a second) is certainly absurd and
 * refused up front; a shorter one runs, with progress inside its steps. */
#define FORCE_NAIVE_RATE 1e9
#define FORCE_REFUSE_S 86400.0

static int naive_too_long(const psim_sim *e, psim_error *err)
{
    double steps = e->cfg.steps > 0 ? (double)e->cfg.steps : 1.0;
    double tests = (double)e->n * (double)e->n * steps;
    double least_s = tests / (FORCE_NAIVE_RATE * e->threads);
    if (!(least_s > FORCE_REFUSE_S))
        return 0;
    psim_error_set(err, "--option naive=1 on %ld particles: about %.3g pair tests in %.0f "
                        "steps, at least %.3g days on %d threads at %g a second a thread, "
                        "more than psim runs (a day); the neighbour lists (the default) take "
                        "this scene",
                   e->n, tests, steps, least_s / 86400, e->threads, FORCE_NAIVE_RATE);
    return 1;
}

/* --device gpu (gpu.h): the store onto the device; the naive option
 * changes nothing there (the same sums in the same order). */
static void *gpu_create(psim_sim *e, fmodel *m, psim_error *err)
{
    if (m->stats) {
        psim_error_set(err, "--device gpu: --force-stats runs on the CPU only (--device cpu)");
        err->usage = 1;
        destroy(m);
        return NULL;
    }
    m->gpu_stats = &e->stats;
    m->gpu = fgpu_create(&e->st, &m->law, psim_engine_device(e),
                         &e->stats.phase_s[FPHASE_COPY], err);
    if (!m->gpu) {
        destroy(m);
        return NULL;
    }
    return m;
}

static void *create(psim_sim *e, const psim_scene *sc, psim_error *err)
{
    fmodel *m = calloc(1, sizeof *m);
    if (!m)
        goto oom;
    m->sim = e;
    set_law(&m->law, e, sc);
    m->skin = psim_engine_option(e, "skin", FORCE_SKIN) * m->law.cutoff;
    m->naive = psim_engine_option(e, "naive", 0) != 0;
    m->stats = psim_engine_option(e, "stats", 0) != 0;
    m->skip = psim_engine_option(e, "skip", 1) != 0;
    m->simd = psim_engine_option(e, "simd", 1) != 0 && psim_have_avx512();
    /* dynamic on few threads (2 threads, 1e5 particles: 3% faster than
     * static), static on many, whose tiles then stay in their caches (8
     * threads: 1.2-1.5x faster than dynamic; 16: either) */
    m->rounds = (int)psim_engine_option(
        e, "rounds", e->threads >= FORCE_STATIC_THREADS ? FORCE_ROUNDS_STATIC : FORCE_ROUNDS_DYNAMIC);
    m->absmin = 1.0;
    if (psim_engine_ranks(e) > 1 && m->naive) {
        psim_error_set(err, "--option naive=1 runs in one process only, not over MPI ranks");
        err->usage = 1;
        destroy(m);
        return NULL;
    }
    if (psim_engine_device(e) >= 0)
        return gpu_create(e, m, err);
    if (m->naive && naive_too_long(e, err)) {
        destroy(m);
        return NULL;
    }
    if (m->naive) {
        if (force_plan_naive(m, e->n))
            goto oom;
        return m;
    }
    if (psim_engine_grid_tiles(e, m->law.cutoff + m->skin, NULL, FORCE_CELL_PARTICLES,
                               tile_cells(e)))
        goto oom;
    return m;
oom:
    destroy(m);
    psim_error_set(err, "out of memory for the force model");
    return NULL;
}

/* Whether some pair within the cutoff may be missing from the lists: two
 * particles may have closed in by `closing` (step.c) since the build, so
 * pairs closer than the cutoff were within cutoff + room then (room: the
 * skin, or more where the nearest unlisted pair was measured, nlist.c)
 * unless closing > room. */
static int lists_stale(const psim_sim *e, const fmodel *m)
{
    /* over ranks the engine's exchange decides, for every rank at once */
    if (psim_engine_ranks(e) > 1)
        return !m->built || psim_engine_exchanged(e);
    return !m->built || m->closing > m->room;
}

/* The message of a step in which a particle left the box for good. */
static int lost_error(const psim_sim *e, fmodel *m, psim_error *err)
{
    if (m->lost_step)
        return 0;
    m->lost_step = e->step + 1;
    psim_error_set(err, "step %ld: a particle left the box for good (dt %g is too large "
                        "for the force: try --option dt=...)", e->step + 1, m->law.dt);
    return -1;
}

/* A step on the device (gpu.h), timed as the CPU path's phases. */
static int gpu_interact(psim_sim *e, fmodel *m, psim_error *err)
{
    fgpu_times t = {0};
    uint64_t hits = 0;
    int rc = fgpu_step(m->gpu, &t, &hits, err);
    e->stats.phase_s[PSIM_PHASE_SORT] += t.sort;
    e->stats.phase_s[FPHASE_FORCE] += t.force;
    e->stats.phase_s[FPHASE_INTEGRATE] += t.integrate;
    e->stats.counter[FC_INTERACTIONS] += hits / 2;   /* pairs, as the lists count them */
    if (rc < 0)
        return -1;
    return rc ? lost_error(e, m, err) : 0;
}

/* The store brought up to date from the device (model.h: sync). */
static void gpu_sync(const psim_sim *e, void *p)
{
    fmodel *m = p;
    (void)e;
    if (!m->gpu)
        return;
    double s = fgpu_sync(m->gpu);
    if (s < 0)
        psim_gpu_lost();
    m->gpu_stats->phase_s[FPHASE_COPY] += s;
}

static int interact(psim_sim *e, void *p, psim_error *err)
{
    fmodel *m = p;
    int rc = 0;
    if (m->gpu)
        return gpu_interact(e, m, err);
    if (m->quiet >= 2 && m->skip && !m->naive && psim_engine_ranks(e) == 1) {   /* at rest: nothing can change */
        e->stats.skipped[FS_MOVE]++;
        return 0;
    }
    /* kept past the skin: a rebuild that the skin alone would have made */
    e->stats.skipped[FS_LISTS] += !m->naive && m->built && !lists_stale(e, m) &&
                                  m->closing > m->skin;
    if (!m->naive && lists_stale(e, m) && (rc = force_build_lists(e, m)) != 0) {
        if (rc == -2)
            psim_error_set(err, "step %ld: the particles are too crowded for neighbour lists "
                                "(more than %d pairs per particle within cutoff + skin): "
                                "run this scene with --option naive=1",
                           e->step + 1, FORCE_LIST_BUDGET);
        else
            psim_error_set(err, "out of memory for the neighbour lists of step %ld",
                           e->step + 1);
        return -1;
    }
    rc = m->naive ? force_step_naive(e, m) : force_step_lists(e, m);
    if (psim_stop_requested())   /* the tiles ended early */
        return psim_engine_stopped(e, err);
    if (rc == -2) {
        psim_error_set(err, "out of memory for the forces of step %ld", e->step + 1);
        return -1;
    }
    return rc ? lost_error(e, m, err) : 0;
}

/* Every particle inside the box, positions and velocities finite. */
static int check(psim_sim *e, void *p, const psim_snapshot *before,
                 const psim_snapshot *after, psim_error *err)
{
    const fmodel *m = p;
    (void)before;
    for (long i = 0; i < after->n; i++) {
        double x = after->x[i], y = after->y[i];
        if (!(x >= 0 && x <= m->law.size && y >= 0 && y <= m->law.size) ||
            !isfinite(after->vx[i]) || !isfinite(after->vy[i])) {
            psim_error_set(err, "step %ld: particle %ld at (%g, %g) with velocity (%g, %g) "
                                "is not inside the box [0, %g]",
                           e->step, i, x, y, after->vx[i], after->vy[i], m->law.size);
            return -1;
        }
    }
    return 0;
}

/* The course's file: "n size", then per frame n lines "x y" as C++ streams
 * print doubles (%g: 6 significant digits; --digits N: N) and a blank line. */
static int write_header(psim_sim *e, void *p, FILE *f)
{
    const fmodel *m = p;
    return fprintf(f, "%ld %g\n", e->n, m->law.size) < 0 ? -1 : 0;
}

typedef struct force_out {
    psim_cols c;
    int prec;
} force_out;

#define FORCE_LINE_MAX (2 * (PSIM_FMT_MAX + 1))

static size_t force_line(char *out, long i, const void *ctx)
{
    const force_out *o = ctx;
    long k = o->c.at[i];
    char *p = out;
    p += psim_fmt_general(p, o->c.x[k], o->prec);
    *p++ = ' ';
    p += psim_fmt_general(p, o->c.y[k], o->prec);
    *p++ = '\n';
    return (size_t)(p - out);
}

/* the course's stream output, line by line (PSIM_SLOW_IO=1: the reference) */
static int force_lines_slow(FILE *f, long n, const force_out *o)
{
    for (long i = 0; i < n; i++) {
        long k = o->c.at[i];
        if (fprintf(f, "%.*g %.*g\n", o->prec, o->c.x[k], o->prec, o->c.y[k]) < 0)
            return -1;
    }
    return 0;
}

static int write_state(psim_sim *e, void *p, FILE *f, long step, int final, int digits)
{
    (void)p, (void)step, (void)final;
    force_out o = {.prec = digits < 0 ? 6 : digits};
    if (psim_state_cols_take(e, &o.c))
        return -1;
    int rc = psim_io_slow() ? force_lines_slow(f, e->n, &o)
                            : psim_write_lines(f, e->n, e->threads, FORCE_LINE_MAX, force_line, &o);
    /* a frame ends with a blank line (written by the frame's last part
     * where parts of it are written apart: psim_part) */
    if (rc == 0 && (!e->part || e->part->foot) && fputc('\n', f) == EOF)
        rc = -1;
    psim_state_cols_free(&o.c);
    return rc;
}

static void source_summary(FILE *f, const psim_sim *e, const void *p, double seconds)
{
    const fmodel *m = p;
    fprintf(f, "Simulation Time = %g seconds for %ld particles.\n", seconds, e->n_all);
    if (!m->stats)
        return;
    double absavg = m->nabsavg ? m->absavg / (double)m->nabsavg : m->absavg;
    fprintf(f, "absmin = %lf, absavg = %lf\n", m->absmin, absavg);
    if (m->absmin < 0.4)
        fprintf(f, "The minimum distance is below 0.4 meaning that some particle is not "
                   "interacting\n");
    if (absavg < 0.8)
        fprintf(f, "The average distance is below 0.8 meaning that most particles are not "
                   "interacting\n");
}

static void step_summary(FILE *f, const psim_stats *st)
{
    double steps = st->steps > 0 ? (double)st->steps : 1.0;
    const uint64_t *c = st->counter;
    fprintf(f, "  per step: %.0f pair tests, %.1f interactions; %.1f steps per list rebuild",
            (double)c[FC_PAIR_TESTS] / steps, (double)c[FC_INTERACTIONS] / steps,
            c[FC_REBUILDS] ? steps / (double)c[FC_REBUILDS] : 0.0);
    if (c[FC_REBUILDS])
        fprintf(f, ", %.0f list entries each", (double)c[FC_LIST_ENTRIES] / (double)c[FC_REBUILDS]);
    fputc('\n', f);
}

/* A step's dt: the law's (its option dt, CS267's 0.0005 for its scenes,
 * one time unit, a step, for scene files). */
static double step_time(const psim_sim *e, const void *m)
{
    (void)e;
    return ((const fmodel *)m)->law.dt;
}

/* Over MPI ranks: ghosts as far as the lists reach (cutoff + skin);
 * the forces need their positions only. */
static int halo(const psim_sim *e, const void *p, psim_halo *h)
{
    (void)e;
    const fmodel *m = p;
    /* waits: the tiles that read no ghost run while the ghosts travel (step.c) */
    *h = (psim_halo){m->law.cutoff, m->skin, PSIM_FIELD_X | PSIM_FIELD_Y, 1};
    return 0;
}

/* CS267's initial state: n particles on a shuffled grid in a box of side
 * sqrt(density n), velocities uniform in [-1, 1] (cs267_random.c). */
static int generate(psim_scene *sc, long n, uint64_t seed, long lo, long hi, psim_error *err)
{
    if (psim_scene_alloc(sc, hi - lo, err))
        return -1;
    sc->L = sqrt(CS267_DENSITY * (double)n);
    sc->r = CS267_CUTOFF / 2;
    sc->steps = CS267_STEPS;
    sc->format = PSIM_SCENE_CS267;
    if (psim_cs267_place_part(n, seed, sc->L, lo, hi, sc->x, sc->y, sc->vx, sc->vy)) {
        psim_error_set(err, "out of memory for %ld particles", n);
        return -1;
    }
    return 0;
}

const psim_model psim_model_force = {
    .name = "force",
    .summary = "Berkeley CS267 HW2: short-range repulsion within a cutoff, O(n)",
    .phases = {[FPHASE_NLIST - PSIM_PHASE_MODEL] = "nlist",
               [FPHASE_FORCE - PSIM_PHASE_MODEL] = "force",
               [FPHASE_INTEGRATE - PSIM_PHASE_MODEL] = "integrate",
               [FPHASE_COPY - PSIM_PHASE_MODEL] = "copy",
               [FPHASE_END - PSIM_PHASE_MODEL] = NULL},
    .thermo = {"interactions", NULL},
    .counters = {[FC_PAIR_TESTS] = "pair_tests",
                 [FC_INTERACTIONS] = "interactions",
                 [FC_REBUILDS] = "rebuilds",
                 [FC_LIST_ENTRIES] = "list_entries",
                 [FC_TASKS] = "tasks",
                 [FC_SORTED] = "sorted_sums",
                 [FC_END] = NULL},
    .output = {.period = CS267_SAVEFREQ},
    .output_digits = -1,
    .options = {{"dt", "time step (CS267 scenes: 0.0005; scene files: 1, a step)", 0, 1e300, 0},
                {"mass", "particle mass (CS267: 0.01)", 1e-300, 1e300, 0},
                {"cutoff", "interaction cutoff (CS267: 0.01; scene files: 2r)", 1e-300, 1e300, 0},
                {"skin", "neighbour list skin, in cutoffs (default 2)", 0, 1e6, 0},
                {"naive", "1: the course's O(n^2) loops (for tests)", 0, 1, 1},
                {"stats", "1: the older edition's absmin/absavg (--force-stats)", 0, 1, 1},
                {"simd", "0: list builds, pair tests and moves without AVX-512 even where the CPU has it (same results)", 0, 1, 1},
                {"rounds", "a step's two rounds on threads: 0 a task a tile, 1 a static loop over the tiles (default from 8 threads), 2 a dynamic one (default below; same results)", 0, 2, 1},
                PSIM_SKIP_OPTION,
                {NULL, NULL, 0, 0, 0}},
    .skips = {[FS_MOVE] = {"move", "at rest: no force, no speed"},
              [FS_WALLS] = {"walls", "no particle crossed a wall: no reflections"},
              [FS_GRAPH] = {"task_graph", "one thread or one tile: tiles run in order, no tasks"},
              [FS_LISTS] = {"rebuilds", "lists kept past the skin: the nearest unlisted pair is farther"}},
    .limits = limits,
    .work_unit = "pair tests",
    .create = create,
    .interact = interact,
    .check = check,
    .write_header = write_header,
    .write_state = write_state,
    .step_summary = step_summary,
    .source_summary = source_summary,
    .step_time = step_time,
    .generate = generate,
    .halo = halo,
    .gpu = 1,
    .sync = gpu_sync,
    .destroy = destroy,
};
