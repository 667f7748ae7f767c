#include "engine.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "gpu.h"
#include "mem.h"
#include "timer.h"
#include "tstats.h"

void psim_config_default(psim_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->steps = -1;
}

const char *psim_phase_name(const psim_sim *e, int p)
{
    return (p >= 0 && p < e->stats.nphases) ? e->stats.phase_name[p] : "?";
}

int psim_engine_counter(const psim_sim *e, const char *name)
{
    for (int k = 0; k < e->stats.ncounters; k++)
        if (strcmp(e->stats.counter_name[k], name) == 0)
            return k;
    return -1;
}

uint64_t psim_counter(const psim_sim *e, const char *name)
{
    int k = psim_engine_counter(e, name);
    return k < 0 ? 0 : e->stats.counter[k];
}

double psim_value(const psim_sim *e, const char *name)
{
    for (int k = 0; k < e->stats.nvalues; k++)
        if (strcmp(e->stats.value_name[k], name) == 0)
            return e->stats.value[k];
    return NAN;
}

const char *psim_sim_model(const psim_sim *e) { return e->model->name; }

/* Phase and counter names: the engine's, then the model's. */
static void name_stats(psim_stats *st, const psim_model *m)
{
    static const char *engine_phases[PSIM_PHASE_MODEL] = {"move", "sort", "check",
                                                          "output"};
    for (int p = 0; p < PSIM_PHASE_MODEL; p++)
        st->phase_name[p] = engine_phases[p];
    st->nphases = PSIM_PHASE_MODEL;
    for (int p = 0; p < PSIM_MODEL_PHASES && m->phases[p]; p++)
        st->phase_name[st->nphases++] = m->phases[p];
    st->ncounters = 0;
    for (int k = 0; k < PSIM_COUNTERS_MAX && m->counters[k]; k++)
        st->counter_name[st->ncounters++] = m->counters[k];
    st->nvalues = 0;
    for (int k = 0; k < PSIM_VALUES_MAX && m->values[k]; k++)
        st->value_name[st->nvalues++] = m->values[k];
    st->nskips = 0;
    for (int k = 0; k < PSIM_SKIPS_MAX && m->skips[k].stage; k++) {
        st->skip_name[st->nskips] = m->skips[k].stage;
        st->skip_why[st->nskips++] = m->skips[k].why;
    }
}

/* The engine's own stage left out: every thread but one (team.h). */
static void team_stats(psim_sim *e)
{
    psim_stats *st = &e->stats;
    e->team_skip = -1;
    if (e->threads < 2 || st->nskips == PSIM_SKIPS_MAX)
        return;
    e->team_skip = st->nskips;
    st->skip_name[st->nskips] = "threads";
    st->skip_why[st->nskips++] = "one thread: tried, or measured faster";
}

void psim_engine_tile_particles(psim_sim *e, double particles)
{
    e->tile_particles = particles;
}

/* The grid's cells and tiles, as --stats and the summary show them. */
static void grid_stats(psim_sim *e)
{
    e->stats.grid_cells = e->has_grid ? e->grid.G : 0;
    e->stats.cell_side = e->grid.h;
    e->stats.tile_cells = 1 << e->grid.tile_shift;
    e->stats.tiles = (int)e->grid.ntiles;
    e->stats.tiles_per_side = e->grid.TG;
    e->stats.tiles_cut = e->grid.cut;
}

int psim_engine_grid(psim_sim *e, double reach, const double *bbox)
{
    return psim_engine_grid_occ(e, reach, bbox, 0);
}

/* The plan asked for, kept for restart files; a restart's own plan
 * answers the model's first ask (the same cells and tiles as the run
 * that wrote it: the discrete model's results follow them). */
static void grid_ask(psim_sim *e, double *reach, const double **bbox, double *occupancy,
                     int *tile_cells)
{
    if (e->grid_saved) {
        e->grid_saved = 0;
        *reach = e->grid_saved_ask[0];
        *occupancy = e->grid_saved_ask[1];
        if (!e->cfg.tile_cells)
            *tile_cells = (int)e->grid_saved_ask[2];
        *bbox = e->grid_saved_bbox ? e->grid_saved_ask + 3 : NULL;
    }
    e->grid_asked = 1;
    e->grid_ask[0] = *reach;
    e->grid_ask[1] = *occupancy;
    e->grid_ask[2] = *tile_cells;
    e->grid_ask_bbox = *bbox != NULL;
    for (int k = 0; *bbox && k < 4; k++)
        e->grid_ask[3 + k] = (*bbox)[k];
}

int psim_engine_grid_occ(psim_sim *e, double reach, const double *bbox, double occupancy)
{
    return psim_engine_grid_tiles(e, reach, bbox, occupancy, 0);
}

int psim_engine_grid_tiles(psim_sim *e, double reach, const double *bbox, double occupancy,
                           int tile_cells)
{
    if (e->cfg.tile_cells)
        tile_cells = e->cfg.tile_cells;
    int restarted = e->grid_saved;
    grid_ask(e, &reach, &bbox, &occupancy, &tile_cells);
    psim_sorter_free(&e->sorter);
    psim_grid_free(&e->grid);
    e->has_grid = 0;
    if (e->cfg.steps == 0)   /* no step will use it: one cell, never sorted */
        occupancy = INFINITY;
    /* over ranks: the rank's domain and halo, its cells as many as its
     * particles would fill in the square grid around them */
    double own[4];
    long n = e->n;
    if (!bbox && e->dist && psim_dist_bbox(e, own) == 0) {
        double w = own[2] - own[0], h = own[3] - own[1], side = w > h ? w : h;
        bbox = own;
        if (w > 0 && h > 0)
            n = (long)fmin((double)n * side / w * side / h, 4.0 * (double)e->n_all + 1);
    }
    if (psim_grid_init_occ(&e->grid, e->L, e->r, reach, n, tile_cells, bbox,
                           occupancy, e->tile_particles) ||
        psim_sorter_init(&e->sorter, e->threads, e->grid.ncells))
        return -1;
    e->has_grid = e->cfg.steps != 0;
    const int TG = e->grid.TG;
    if (restarted && e->ncuts_saved == 2 * (TG + 1) &&
        psim_grid_cuts_ok(e->cuts_saved, TG, e->grid.G) &&
        psim_grid_cuts_ok(e->cuts_saved + TG + 1, TG, e->grid.G))
        psim_grid_cut(&e->grid, e->cuts_saved, e->cuts_saved + TG + 1);
    grid_stats(e);
    return 0;
}

int psim_engine_regrid(psim_sim *e)
{
    if (!e->grid_asked)
        return 0;
    return psim_engine_grid_tiles(e, e->grid_ask[0], e->grid_ask_bbox ? e->grid_ask + 3 : NULL,
                                  e->grid_ask[1], (int)e->grid_ask[2]);
}

void psim_engine_grid_cut(psim_sim *e, const int32_t *cut_x, const int32_t *cut_y)
{
    psim_grid_cut(&e->grid, cut_x, cut_y);
    grid_stats(e);
}

static int snapshot_alloc(psim_snapshot *s, long n)
{
    s->n = n;
    size_t b = (size_t)(n > 0 ? n : 1) * sizeof(double);
    s->x = psim_alloc(b);
    s->y = psim_alloc(b);
    s->vx = psim_alloc(b);
    s->vy = psim_alloc(b);
    return (s->x && s->y && s->vx && s->vy) ? 0 : -1;
}

void psim_snapshot_free(psim_snapshot *s)
{
    psim_free(s->x);
    psim_free(s->y);
    psim_free(s->vx);
    psim_free(s->vy);
    memset(s, 0, sizeof *s);
}

/* "name" of option k of the model, or -1. */
static int option_index(const psim_model *m, const char *name, size_t len)
{
    for (int k = 0; k < PSIM_MODEL_OPTIONS && m->options[k].name; k++)
        if (strlen(m->options[k].name) == len && !strncmp(m->options[k].name, name, len))
            return k;
    return -1;
}

static void option_names(const psim_model *m, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = 0;
    for (int k = 0; k < PSIM_MODEL_OPTIONS && m->options[k].name && used < size; k++)
        used += (size_t)snprintf(buf + used, size - used, "%s%s", k ? ", " : "",
                                 m->options[k].name);
    if (!buf[0])
        snprintf(buf, size, "none");
}

/* Why a number strtod read (v, with its errno) cannot be taken, or NULL:
 * beyond the largest double, or so small that it read as zero.  A number
 * below the smallest normal double that reads as a subnormal one is taken
 * as it reads. */
static const char *option_beyond_double(double v, int read_errno)
{
    if (read_errno != ERANGE)
        return NULL;
    if (isinf(v))
        return "too large for a double (beyond 1.8e308)";
    return v == 0 ? "too small for a double (below 4.9e-324: it reads as 0)" : NULL;
}

/* Parse "KEY=VALUE,KEY=VALUE" against model m's options into value[]
 * and set[]; with once, a name given twice (a restart file's header has
 * each once) or an empty item is an error too. */
static int options_parse(const psim_model *m, const char *text, int once, double *value,
                         int *set, psim_error *err)
{
    char names[256];
    while (text && (*text || once)) {
        const char *end = strchr(text, ','), *eq = strchr(text, '=');
        size_t len = end ? (size_t)(end - text) : strlen(text);
        if (!eq || eq >= text + len) {
            psim_error_set(err, "option '%.*s': expected NAME=VALUE", (int)len, text);
            err->usage = 1;
            return -1;
        }
        int k = option_index(m, text, (size_t)(eq - text));
        if (k < 0) {
            option_names(m, names, sizeof names);
            psim_error_set(err, "the %s model has no option '%.*s' (its options: %s)",
                           m->name, (int)(eq - text), text, names);
            err->usage = 1;
            return -1;
        }
        if (once && set[k]) {
            psim_error_set(err, "option %s given twice", m->options[k].name);
            return -1;
        }
        const psim_model_option *o = &m->options[k];
        char *stop;
        errno = 0;
        double v = strtod(eq + 1, &stop);
        const int read = stop != eq + 1 && stop == text + len;
        const char *beyond = read ? option_beyond_double(v, errno) : NULL;
        if (beyond) {
            psim_error_set(err, "option %s: '%.*s' is %s", o->name,
                           (int)(text + len - eq - 1), eq + 1, beyond);
            err->usage = 1;
            return -1;
        }
        if (!read || !(v >= o->lo && v <= o->hi) || (o->whole && v != floor(v))) {
            psim_error_set(err, "option %s: '%.*s' is not %s in [%g, %g]", o->name,
                           (int)(text + len - eq - 1), eq + 1,
                           o->whole ? "a whole number" : "a number", o->lo, o->hi);
            err->usage = 1;
            return -1;
        }
        value[k] = v;
        set[k] = 1;
        text = end ? end + 1 : NULL;
    }
    return 0;
}

static int parse_options(psim_sim *e, const char *text, psim_error *err)
{
    return options_parse(e->model, text, 0, e->opt_value, e->opt_set, err);
}

int psim_engine_options_check(const psim_model *m, const char *text, psim_error *err)
{
    double value[PSIM_MODEL_OPTIONS];
    int set[PSIM_MODEL_OPTIONS] = {0};
    return options_parse(m, text, 1, value, set, err);
}

/* A bad option in a restart file's header is the file's fault, not the
 * command line's: its name and line go first. */
static void restart_option_error(const psim_scene *sc, psim_error *err)
{
    char msg[sizeof err->msg];
    memcpy(msg, err->msg, sizeof msg);
    psim_error_set(err, "%s:%ld: restart header: %s", sc->source ? sc->source : "<restart>",
                   sc->restart.line, msg);
    err->usage = 0;
}

double psim_engine_option(const psim_sim *e, const char *name, double dflt)
{
    int k = option_index(e->model, name, strlen(name));
    return (k >= 0 && e->opt_set[k]) ? e->opt_value[k] : dflt;
}

/* The store: every particle of the scene, by id. */
static int store_fill(psim_sim *e, const psim_scene *sc, psim_error *err)
{
    if (psim_store_init(&e->st, (size_t)sc->n)) {
        psim_error_set(err, "out of memory for %ld particles", sc->n);
        return -1;
    }
    /* first touch by the threads that will work on these particles (the
     * split of the move), so pages land on their NUMA nodes */
    const size_t n = (size_t)sc->n;
#pragma omp parallel num_threads(e->threads)
    {
        int T = omp_get_num_threads(), k = omp_get_thread_num();
        for (size_t i = psim_part_lo(n, T, k); i < psim_part_lo(n, T, k + 1); i++) {
            e->st.x[i] = sc->x[i];
            e->st.y[i] = sc->y[i];
            e->st.vx[i] = sc->vx[i];
            e->st.vy[i] = sc->vy[i];
            e->st.id[i] = (int32_t)i;
        }
    }
    return 0;
}

/* The device the program chose (gpu.h), for a model with a GPU path, one
 * process only: 0, or -1 with a usage error. */
static int device_check(psim_sim *e, psim_error *err)
{
    e->device = psim_gpu_used();
    if (e->device < 0)
        return 0;
    const char *why = NULL;
    if (!e->model->gpu)
        why = e->model->no_gpu ? e->model->no_gpu : "has no GPU path";
    else if (e->dist)
        why = "runs on a GPU in one process only, not over MPI ranks";
    if (why) {
        psim_error_set(err, "--device gpu: the %s model %s (--device cpu runs it)",
                       e->model->name, why);
        err->usage = 1;
        return -1;
    }
    const char *none = "";
    int count = psim_gpu_count(&none);
    if (e->device < count)
        return 0;
    if (count == 0)
        psim_error_set(err, "--device gpu: no CUDA device (%s)", none);
    else
        psim_error_set(err, "--device gpu:%d: no such CUDA device (this machine has %d: "
                            "psim topo lists them)", e->device, count);
    err->usage = 1;
    return -1;
}

int psim_engine_device(const psim_sim *e) { return e->device; }

void psim_engine_sync(const psim_sim *e)
{
    if (e->model->sync && e->mstate)
        e->model->sync(e, e->mstate);
}

psim_sim *psim_engine_create(psim_scene *sc, const psim_config *cfg,
                             const psim_model *model, int take, psim_error *err)
{
    psim_sim *e = calloc(1, sizeof *e);
    if (!e) {
        psim_error_set(err, "out of memory");
        return NULL;
    }
    e->cfg = *cfg;
    e->threads = cfg->threads > 0 ? cfg->threads : omp_get_max_threads();
    if (e->threads > omp_get_thread_limit())   /* no team gets more (OMP_THREAD_LIMIT) */
        e->threads = omp_get_thread_limit();
    /* a model that shares holds the whole scene on every rank */
    const int ranks = psim_dist_ranks() > 1;
    if (ranks && model->shares && sc->id && psim_dist_scene_whole(sc, err))
        goto fail;
    e->n = e->n_all = psim_scene_all(sc);
    e->L = sc->L;
    e->r = sc->r;
    e->model = model;
    name_stats(&e->stats, model);
    /* a restart file's options (those of the model that wrote it), then
     * the run's own */
    if (sc->restart.present && !strcmp(sc->restart.model, model->name) &&
        parse_options(e, sc->restart.options, err)) {
        restart_option_error(sc, err);
        goto fail;
    }
    if (parse_options(e, cfg->options, err))
        goto fail;
    /* before any memory is taken for a scene the model cannot run */
    if (psim_engine_limits(e, sc, err))
        goto fail;
    if (psim_engine_restart_init(e, sc, err))
        goto fail;
    if (ranks) {
        if (cfg->check && !model->shares) {
            psim_error_set(err, "--check runs in one process only, not over MPI ranks");
            err->usage = 1;
            goto fail;
        }
        if (psim_dist_attach(e, sc, take, err) || (model->shares && store_fill(e, sc, err)))
            goto fail;
    } else if (sc->id) {   /* (scene.h: each rank's part) */
        psim_error_set(err, "a part of a scene runs over MPI ranks only");
        goto fail;
    } else if (store_fill(e, sc, err))
        goto fail;
    if (take) {
        /* the store holds the particles: the scene's copy goes before the
         * model allocates its own memory */
        free(sc->x), free(sc->y), free(sc->vx), free(sc->vy);
        sc->x = sc->y = sc->vx = sc->vy = NULL;
    }
    if (cfg->check &&
        (snapshot_alloc(&e->before, e->n) || snapshot_alloc(&e->after, e->n))) {
        psim_error_set(err, "out of memory for checks");
        goto fail;
    }
    e->tstats = psim_calloc((size_t)e->threads * sizeof *e->tstats);
    if (!e->tstats) {
        psim_error_set(err, "out of memory");
        goto fail;
    }
    for (int k = 0; k < e->threads; k++)
        e->tstats[k].cpu = -1;
    e->stats.threads = e->threads;
    psim_team_init(&e->team, e->threads, cfg->fixed_threads);
    team_stats(e);
    if (device_check(e, err))
        goto fail;
    e->mstate = e->model->create(e, sc, err);
    if (!e->mstate || (e->dist && psim_dist_ready(e, err)))
        goto fail;
    e->step_time = e->model->step_time ? e->model->step_time(e, e->mstate) : 1.0;
    return e;
fail:
    psim_destroy(e);
    return NULL;
}

void psim_destroy(psim_sim *e)
{
    if (!e)
        return;
    if (e->mstate)
        e->model->destroy(e->mstate);
    psim_dist_detach(e);
    psim_sorter_free(&e->sorter);
    psim_grid_free(&e->grid);
    psim_store_free(&e->st);
    psim_snapshot_free(&e->before);
    psim_snapshot_free(&e->after);
    psim_free(e->tstats);
    free(e->restart_order);
    free(e);
}

void psim_get_state(const psim_sim *e, double *x, double *y, double *vx,
                    double *vy)
{
    psim_engine_sync(e);
    const psim_store *s = &e->st;
    for (size_t k = 0; k < s->n; k++) {
        int32_t i = s->id[k];
        if (x)
            x[i] = s->x[k];
        if (y)
            y[i] = s->y[k];
        if (vx)
            vx[i] = s->vx[k];
        if (vy)
            vy[i] = s->vy[k];
    }
}

static void take_snapshot(const psim_sim *e, psim_snapshot *s)
{
    psim_get_state(e, s->x, s->y, s->vx, s->vy);
}

int psim_snapshot_take(const psim_sim *e, psim_snapshot *s)
{
    if (snapshot_alloc(s, e->n))
        return -1;
    take_snapshot(e, s);
    return 0;
}

__attribute__((noinline)) static void phase_sort(psim_sim *e)
{
    psim_sort_by_cell(&e->sorter, &e->st, &e->grid, e->threads, e->tstats);
}

void psim_engine_sort(psim_sim *e)
{
    psim_engine_halo_wait(e);   /* the ghosts' fields land in their places first */
    if (e->restart_order)
        psim_engine_restart_order(e);
    if (e->has_grid)
        PSIM_TIMED(e, PSIM_PHASE_SORT, phase_sort(e));
    if (e->dist)
        psim_dist_sorted(e);
}

int psim_engine_ranks(const psim_sim *e)
{
    return e->dist ? psim_dist_ranks() : 1;
}

/* The threads' busy seconds so far. */
static double busy_sum(const psim_sim *e, int threads)
{
    double s = 0;
    for (int k = 0; k < threads; k++)
        for (int p = 0; p < e->stats.nphases; p++)
            s += e->tstats[k].busy_s[p];
    return s;
}

/* The model's step on the threads the team gives it (team.h). */
static int team_interact(psim_sim *e, psim_error *err)
{
    const int all = e->threads;
    e->threads = psim_team_next(&e->team);
    if (e->team_skip >= 0)
        e->stats.skipped[e->team_skip] += e->threads == 1;
    const double w0 = busy_sum(e, all), t0 = psim_now();
    int rc = e->model->interact(e, e->mstate, err);
    psim_team_done(&e->team, psim_now() - t0, busy_sum(e, all) - w0);
    e->threads = all;
    return rc;
}

int psim_step(psim_sim *e, psim_error *err)
{
    /* over ranks, the ranks agree on a stop at the step's end */
    if (!e->dist && psim_stop_requested())
        return psim_engine_stopped(e, err);
    psim_poll_begin(e);
    if (e->dist && psim_dist_prestep(e, err))
        return -1;
    if (e->cfg.check)
        PSIM_TIMED(e, PSIM_PHASE_CHECK, take_snapshot(e, &e->before));
    int rc = team_interact(e, err);
    if (e->dist)
        rc = psim_dist_poststep(e, rc, err);
    if (rc)
        return -1;
    if (!e->dist && psim_stop_requested())   /* a poll ended a loop early: the state is of no use */
        return psim_engine_stopped(e, err);
    e->step++;
    e->stats.steps = e->step - e->step0;
    if (e->cfg.check && e->model->check) {
        PSIM_REGION_BEGIN(e, PSIM_PHASE_CHECK);
        double t0 = psim_now();
        /* an overflowed state is named as such, not as a broken rule */
        rc = psim_state_finite(e, err);
        if (rc == 0) {
            take_snapshot(e, &e->after);
            rc = e->model->check(e, e->mstate, &e->before, &e->after, err);
            double dt = psim_now() - t0;
            e->stats.phase_s[PSIM_PHASE_CHECK] += dt;
            psim_tstat_add(e->tstats, PSIM_PHASE_CHECK, dt, 1, (uint64_t)e->n); /* thread 0 */
        }
        PSIM_REGION_END(e, PSIM_PHASE_CHECK);
        if (rc)
            return -1;
    }
    return 0;
}

size_t psim_engine_not_finite(const psim_sim *e, const uint8_t *skip)
{
    const psim_store *s = &e->st;
    size_t bad = s->n;
    for (size_t k = 0; k < s->n; k++)
        if (!(skip && skip[k]) &&
            !(fabs(s->x[k]) <= DBL_MAX && fabs(s->y[k]) <= DBL_MAX &&
              fabs(s->vx[k]) <= DBL_MAX && fabs(s->vy[k]) <= DBL_MAX) &&
            (bad == s->n || s->id[k] < s->id[bad]))
            bad = k;
    return bad;
}

void psim_engine_not_finite_error(const psim_sim *e, size_t place, psim_error *err)
{
    const psim_store *s = &e->st;
    psim_error_set(err, "step %ld: disk %d is no longer finite (x %g, y %g, vx %g, vy %g): "
                        "the numbers overflowed, so no state is written",
                   e->step, s->id[place], s->x[place], s->y[place], s->vx[place], s->vy[place]);
}

int psim_state_finite(const psim_sim *e, psim_error *err)
{
    if (e->dist)   /* every rank's, together */
        return psim_dist_finite(e, err);
    psim_engine_sync(e);
    size_t bad = psim_engine_not_finite(e, NULL);
    if (bad == e->st.n)
        return 0;
    psim_engine_not_finite_error(e, bad, err);
    return -1;
}

long psim_step_index(const psim_sim *e) { return e->step; }
double psim_step_time(const psim_sim *e) { return e->step_time; }
double psim_time_at(const psim_sim *e, long step) { return (double)step * e->step_time; }
long psim_count(const psim_sim *e) { return e->n_all; }
const psim_stats *psim_get_stats(const psim_sim *e) { return &e->stats; }

const psim_thread_stats *psim_get_thread_stats(const psim_sim *e, int *threads)
{
    *threads = e->threads;
    return e->tstats;
}

void psim_add_output_time(psim_sim *e, double seconds)
{
    e->stats.phase_s[PSIM_PHASE_OUTPUT] += seconds;
    psim_tstat_add(e->tstats, PSIM_PHASE_OUTPUT, seconds, 1, 0); /* thread 0 */
}

void psim_print_step_summary(FILE *f, const psim_sim *e)
{
    const psim_stats *st = &e->stats;
    if (e->model->step_summary) {
        e->model->step_summary(f, st);
        return;
    }
    double steps = st->steps > 0 ? (double)st->steps : 1.0;
    fprintf(f, "  per step:");
    for (int k = 0; k < st->ncounters; k++)
        fprintf(f, "%s %.1f %s", k ? "," : "", (double)st->counter[k] / steps,
                st->counter_name[k]);
    fputc('\n', f);
}

void psim_print_skips(FILE *f, const psim_sim *e)
{
    const psim_stats *st = &e->stats;
    int any = 0;
    for (int k = 0; k < st->nskips; k++) {
        if (!st->skipped[k])
            continue;
        fprintf(f, "%s %s in %llu of %ld steps (%s)", any ? "," : "  left out:",
                st->skip_name[k], (unsigned long long)st->skipped[k], st->steps,
                st->skip_why[k]);
        any = 1;
    }
    if (any)
        fputc('\n', f);
}

int psim_write_output(psim_sim *e, FILE *f, long step, int final, int digits)
{
    BY_PARTS(e, f, psim_write_output(v_, f_, step, final, digits));
    psim_engine_sync(e);
    if (e->model->write_state)
        return e->model->write_state(e, e->mstate, f, step, final,
                                     digits >= 0 ? digits : e->model->output_digits);
    return psim_write_trace(e, f, step, digits);
}

int psim_state_cols_take(const psim_sim *e, psim_cols *c)
{
    psim_engine_sync(e);
    const psim_store *s = &e->st;
    int32_t *at = psim_alloc((s->n > 0 ? s->n : 1) * sizeof *at);
    const long id0 = e->part ? e->part->id0 : 0;
    *c = (psim_cols){s->x, s->y, s->vx, s->vy, at, id0};
    if (!at) {
        errno = ENOMEM;
        return -1;
    }
    const long n = (long)s->n;
#pragma omp parallel for schedule(static) num_threads(e->threads) if (n > 65536)
    for (long k = 0; k < n; k++)
        at[s->id[k] - id0] = (int32_t)k;
    return 0;
}

void psim_state_cols_free(psim_cols *c)
{
    psim_free((void *)c->at);
    c->at = NULL;
}

int psim_write_trace(psim_sim *e, FILE *f, long step, int digits)
{
    BY_PARTS(e, f, psim_write_trace(v_, f_, step, digits));
    psim_cols c;
    if (psim_state_cols_take(e, &c))
        return -1;
    int rc = psim_write_state_cols(f, step, e->n, &c,
                                   digits >= 0 ? digits : e->model->output_digits, e->threads);
    psim_state_cols_free(&c);
    return rc;
}

int psim_write_dump(psim_sim *e, FILE *f, long step)
{
    BY_PARTS(e, f, psim_write_dump(v_, f_, step));
    psim_cols c;
    if (psim_state_cols_take(e, &c))
        return -1;
    int rc = psim_write_xyz_cols(f, step, psim_time_at(e, step), e->n, e->L, e->r, &c,
                                 e->part, e->threads);
    psim_state_cols_free(&c);
    return rc;
}

int psim_write_header(psim_sim *e, FILE *f)
{
    if (e->dist) {   /* rank 0, with every rank's count */
        int rc = 0;
        if (psim_dist_rank() == 0 && e->model->write_header) {
            psim_sim v = *e;
            v.n = e->n_all, v.dist = NULL;
            rc = e->model->write_header(&v, e->mstate, f);
        }
        return psim_dist_agree(rc != 0) >= 0 ? -1 : 0;
    }
    return e->model->write_header ? e->model->write_header(e, e->mstate, f) : 0;
}

void psim_print_source_summary(FILE *f, const psim_sim *e, double seconds)
{
    if (e->model->source_summary)
        e->model->source_summary(f, e, e->mstate, seconds);
}

psim_output_style psim_get_output_style(const psim_sim *e) { return e->model->output; }
