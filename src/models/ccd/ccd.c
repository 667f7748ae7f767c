/* The ccd model behind the model interface: its grid, its step, and its
 * output in the authors' format. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "ccd.h"
#include "../../engine/gpu.h"
#include "../../engine/mem.h"
#include "../../engine/tstats.h"

/* The velocities this step: the largest displacement of one disk,
 * max |vx| + |vy| >= |v|, and whether they are all one (finite) velocity
 * (same) and that velocity is zero (zero); with `extent`, also the
 * positions' extent (for the wall skip, flight.c). */
typedef struct cvel {
    double vmax;
    int same, zero;
    int has_ext;
    double ext[4];          /* x min, x max, y min, y max */
} cvel;

static cvel velocities(const psim_sim *e, int extent)
{
    const psim_store *s = &e->st;
    double v = 0, u0 = INFINITY, u1 = -INFINITY, w0 = INFINITY, w1 = -INFINITY;
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    const long n = (long)s->n;
    if (extent) {
#pragma omp parallel for schedule(static) num_threads(e->threads) \
    reduction(max : x1, y1) reduction(min : x0, y0)
        for (long i = 0; i < n; i++) {
            x0 = s->x[i] < x0 ? s->x[i] : x0, x1 = s->x[i] > x1 ? s->x[i] : x1;
            y0 = s->y[i] < y0 ? s->y[i] : y0, y1 = s->y[i] > y1 ? s->y[i] : y1;
        }
    }
#pragma omp parallel for schedule(static) num_threads(e->threads) \
    reduction(max : v, u1, w1) reduction(min : u0, w0)
    for (long i = 0; i < n; i++) {
        double d = fabs(s->vx[i]) + fabs(s->vy[i]);
        v = d > v ? d : v;
        u0 = s->vx[i] < u0 ? s->vx[i] : u0, u1 = s->vx[i] > u1 ? s->vx[i] : u1;
        w0 = s->vy[i] < w0 ? s->vy[i] : w0, w1 = s->vy[i] > w1 ? s->vy[i] : w1;
    }
    cvel r = {.vmax = v, .has_ext = extent, .ext = {x0, x1, y0, y1}};
    /* NaN is in no comparison: it leaves u0 > u1 or a v that is not finite */
    r.same = s->n > 0 && u0 == u1 && w0 == w1 && isfinite(u0) && isfinite(w0) && isfinite(v);
    r.zero = r.same && u0 == 0 && w0 == 0;
    return r;
}

/* Cells must be wider than 2r plus the largest displacement of two disks;
 * re-plan when they are not, or when they are far wider than needed. */
static int fit_grid(psim_sim *e, cmodel *m, double vmax, int *regridded)
{
    m->vmax = vmax;
    m->margin = ccd_margin(m, vmax);
    double reach = ccd_reach(m->L, m->r, vmax);
    *regridded = 0;
    if (ccd_cells_keep(reach, e->has_grid ? e->grid.h : 0, e->grid.G,
                       (long)ceil(sqrt((double)e->n / 3.0))))
        return 0;
    *regridded = 1;
    if (psim_engine_grid(e, ccd_cells_want(m->L, reach), NULL))
        return -1;
    /* per-cell state of the detection, sized here rather than every step */
    return psim_reserve((void **)&m->wmax, &m->wmax_cap, e->grid.ncells + 1, sizeof *m->wmax);
}

static void destroy(void *p)
{
    cmodel *m = p;
    if (!m)
        return;
    psim_free(m->sx0), psim_free(m->sx1), psim_free(m->sy0), psim_free(m->sy1);
    psim_free(m->wmax);
    psim_free(m->ord), psim_free(m->key), psim_free(m->key2), psim_free(m->ord2);
    ccd_bands_free(&m->bands);
    cgpu_destroy(m->gpu);
    for (int t = 0; m->lists && t < m->nlists; t++)
        psim_free(m->lists[t].c);
    free(m->lists);
    free(m->off);
    free(m->head);
    psim_free(m->all.c);
    psim_free(m->acc.c);
    psim_free(m->busy);
    psim_free(m->best);
    psim_free(m->live);
    free(m->pcoll);
    free(m->wcoll);
    free(m);
}

/* The first disk whose centre is outside the box [0, L]^2 (NaN too), or
 * -1.  The authors' wall time (x - r) / -vx is not limited to the step, so
 * a disk outside would jump to the wall from any distance (a disk at
 * x = -1e6 moving at 0.5 reached x = 999927.5 in five steps): psim refuses
 * the scene, as the event model refuses overlaps.  With lo = 0 and
 * hi = L (a 2024 scene: disks that straddle a wall, centre within r of
 * it, as in that course's scenes, run as the authors' program runs them);
 * with lo = r and hi = L - r, to --check's tolerance, a 2019 scene's rule
 * (below). */
static long first_outside(const psim_sim *e, double lo, double hi)
{
    const psim_store *s = &e->st;   /* by id before the first sort */
    for (long i = 0; i < (long)s->n; i++)
        if (!(s->x[i] >= lo && s->x[i] <= hi && s->y[i] >= lo && s->y[i] <= hi))
            return i;
    return -1;
}

/* A 2019 scene's disks do not overlap the walls: the course's generator
 * puts centres in [r, L - r], as are all its hand-made scenes', and the
 * authors' wall time (x - r) / -vx of a disk that overlaps a wall lies
 * outside the step (a disk at x = 0.5, r = 1, moving at -1 moved 2 in
 * one step, to 2.5; one at rest fails --check at once). */
static int overlaps_wall(const psim_sim *e, const psim_scene *sc, psim_error *err)
{
    const double tol = 1e-9 * fmax(1.0, e->L);   /* ccd_check's */
    long i = first_outside(e, e->r - tol, e->L - e->r + tol);
    if (i < 0)
        return 0;
    char at[320];
    psim_scene_where(sc, i, at, sizeof at);
    psim_error_set(err, "%sdisk %ld at (%.17g, %.17g) overlaps a wall: a 2019 scene's "
                        "centres lie in [r, L - r] = [%.17g, %.17g] (the course's generator "
                        "puts them there; the authors' wall rule has no time for a disk "
                        "already past its contact)",
                   at, i, e->st.x[i], e->st.y[i], e->r, e->L - e->r);
    return 1;
}

/* Restart files carry each disk's collision counts, which the authors'
 * program prints with the last step: whole numbers from 0 up to 2^53 (the
 * largest below which every integer is a double, as the columns are
 * kept; a disk collides at most a few times a step, and runs have at most
 * 10^9 steps). */
#define CCD_COUNT_MAX 9007199254740992.0
static void restart_save(const psim_sim *e, const void *p, int k, double *by_id)
{
    const cmodel *m = p;
    const int64_t *c = k ? m->wcoll : m->pcoll;
    for (long i = 0; i < e->n; i++)
        by_id[i] = (double)c[i];
}

static void restart_load(const psim_sim *e, const psim_scene *sc, cmodel *m)
{
    const double *pc = psim_engine_restart_column(e, sc, "pair_collisions");
    const double *wc = psim_engine_restart_column(e, sc, "wall_collisions");
    for (long i = 0; pc && wc && i < e->n; i++) {
        m->pcoll[i] = (int64_t)pc[i];
        m->wcoll[i] = (int64_t)wc[i];
    }
}

/* The largest box and speeds the rules' times of impact can be computed
 * for.  With every centre inside the box (create) and S the speed one
 * disk may reach (model.h), a pair's |dp| <= sqrt(2) L and |dv| <=
 * sqrt(2) S, so the rules' arithmetic (rules.h) stays below: C = |dp|^2 -
 * 4r^2 <= 2 L^2, A = |dv|^2 <= 2 S^2, B^2 <= 16 (S L)^2, D = B^2 - 4AC <=
 * 32 (S L)^2.  Past them D is NaN or infinite, no time of impact exists
 * and disks pass through each other.  The bounds leave a factor of 1e4
 * below the largest double. */
#define CCD_MAX_LENGTH 1e152
#define CCD_MAX_SPEED 1e152
#define CCD_MAX_LENGTH_SPEED 1e151

static int limits(const psim_sim *e, const psim_scene *sc, psim_limits *lim, psim_error *err)
{
    (void)e, (void)sc, (void)err;
    lim->at[PSIM_LIMIT_BOX] = (psim_limit){CCD_MAX_LENGTH,
                                           "its squared distances (up to 2 L^2)"};
    lim->at[PSIM_LIMIT_SPEED] = (psim_limit){CCD_MAX_SPEED,
                                             "its squared relative speeds (up to 2 S^2)"};
    lim->at[PSIM_LIMIT_BOX_SPEED] = (psim_limit){
        CCD_MAX_LENGTH_SPEED, "its times of impact's B^2 - 4AC (up to 32 (S L)^2)"};
    return 0;
}

/* --device gpu (gpu.h): the store and the collision counts onto the
 * device. */
static void *gpu_create(psim_sim *e, cmodel *m, psim_error *err)
{
    m->gpu_stats = &e->stats;
    m->gpu = cgpu_create(&e->st, m->L, m->r, m->pcoll, m->wcoll, psim_engine_device(e),
                         &e->stats.phase_s[CPHASE_COPY], err);
    if (!m->gpu) {
        destroy(m);
        return NULL;
    }
    return m;
}

static void *create(psim_sim *e, const psim_scene *sc, psim_error *err)
{
    /* (the model's own restart file holds a state the rule reached: a disk
     * that bounced off a wall may be a little outside) */
    int own = psim_engine_restart_column(e, sc, "pair_collisions") != NULL;
    long out = own ? -1 : first_outside(e, 0, e->L);
    if (out >= 0) {
        char at[320];
        psim_scene_where(sc, out, at, sizeof at);
        psim_error_set(err, "%sdisk %ld at (%.17g, %.17g) is outside the box [0, %.17g]^2: "
                            "the ccd model's wall rule needs every centre inside it",
                       at, out, e->st.x[out], e->st.y[out], sc->L);
        return NULL;
    }
    if (!own && sc->format == PSIM_SCENE_2019 && overlaps_wall(e, sc, err))
        return NULL;
    cmodel *m = calloc(1, sizeof *m);
    if (!m)
        goto oom;
    m->L = e->L;
    m->r = e->r;
    m->rank = psim_engine_rank(e);
    m->ranks = psim_engine_ranks(e);
    const char *mode = getenv("PSIM_CCD_ACCEPT");
    m->accept_mode = !mode ? CCD_ACCEPT_AUTO
                   : !strcmp(mode, "seq") ? CCD_ACCEPT_SEQ
                   : !strcmp(mode, "par") ? CCD_ACCEPT_PAR : CCD_ACCEPT_AUTO;
    size_t n = (size_t)e->n + 1, d = n * sizeof(double), u = n * sizeof(uint32_t);
    m->sx0 = psim_alloc(d), m->sx1 = psim_alloc(d), m->sy0 = psim_alloc(d), m->sy1 = psim_alloc(d);
    m->ord = psim_alloc(u), m->key = psim_alloc(u), m->key2 = psim_alloc(u), m->ord2 = psim_alloc(u);
    m->busy = psim_calloc(n);
    m->best = psim_alloc(n * sizeof *m->best);
    m->pcoll = calloc(n, sizeof *m->pcoll);
    m->wcoll = calloc(n, sizeof *m->wcoll);
    m->nlists = e->threads;
    m->lists = calloc((size_t)m->nlists, sizeof *m->lists);
    m->off = calloc((size_t)m->nlists, sizeof *m->off);
    m->head = calloc((size_t)m->nlists, sizeof *m->head);
    m->skip = psim_engine_option(e, "skip", 1) != 0;
    m->gap = -1;
    int regridded;
    if (!m->sx0 || !m->sx1 || !m->sy0 || !m->sy1 || !m->ord || !m->key || !m->key2 ||
        !m->ord2 || !m->busy || !m->best || !m->pcoll || !m->wcoll || !m->lists || !m->off || !m->head ||
        fit_grid(e, m, velocities(e, 0).vmax, &regridded))
        goto oom;
    restart_load(e, sc, m);
    if (psim_engine_device(e) >= 0)
        return gpu_create(e, m, err);
    return m;
oom:
    destroy(m);
    psim_error_set(err, "out of memory for the ccd model");
    return NULL;
}

/* A step on the device (gpu.h), timed and counted as the CPU path's
 * phases and counters (its pair tests: the pairs whose swept boxes
 * overlap).  The host's grid is planned for the step's speeds as the CPU
 * path plans it where it searches for pairs, so that restart files carry
 * the same plan. */
static int gpu_interact(psim_sim *e, cmodel *m, psim_error *err)
{
    cgpu_step_out o = {0};
    int rc = cgpu_step(m->gpu, &o, err), regridded = 0;
    double *s = e->stats.phase_s;
    s[CPHASE_DETECT] += o.detect, s[PSIM_PHASE_SORT] += o.sort, s[CPHASE_ORDER] += o.order;
    s[CPHASE_ACCEPT] += o.accept, s[PSIM_PHASE_MOVE] += o.move;
    if (rc)
        return rc;
    if (e->st.n > 0 && fit_grid(e, m, o.vmax, &regridded)) {
        psim_error_set(err, "out of memory for the ccd model's grid");
        return -1;
    }
    uint64_t *c = e->stats.counter;
    c[CC_PAIR_TESTS] += o.tests, c[CC_PAIR_CANDIDATES] += o.pair_cands;
    c[CC_WALL_CANDIDATES] += o.wall_cands, c[CC_PAIR_COLLISIONS] += o.pair_colls;
    c[CC_WALL_COLLISIONS] += o.wall_colls, c[CC_ACCEPT_ROUNDS] += o.rounds;
    c[CC_REGRIDS] += (uint64_t)regridded;
    return 0;
}

/* The store and the collision counts brought up to date from the device
 * (model.h: sync). */
static void gpu_sync(const psim_sim *e, void *p)
{
    cmodel *m = p;
    (void)e;
    if (!m->gpu)
        return;
    double s = cgpu_sync(m->gpu, m->pcoll, m->wcoll);
    if (s < 0)
        psim_gpu_lost();
    m->gpu_stats->phase_s[CPHASE_COPY] += s;
}

int ccd_gpu_lists(cmodel *m, psim_error *err)
{
    size_t n = cgpu_candidates(m->gpu);
    if (psim_reserve((void **)&m->all.c, &m->all.cap, n + 1, sizeof *m->all.c) ||
        psim_reserve((void **)&m->acc.c, &m->acc.cap, n + 1, sizeof *m->acc.c)) {
        psim_error_set(err, "out of memory in --check");
        return -1;
    }
    m->all.n = n;
    if (cgpu_lists(m->gpu, m->all.c, m->acc.c, &m->acc.n)) {
        psim_error_set(err, "--device gpu: the candidates could not be copied from the device");
        return -1;
    }
    return 0;
}

/* Clear the candidate lists: a step with neither pairs nor walls. */
static void detect_none(cmodel *m)
{
    for (int t = 0; t < m->nlists; t++)
        m->lists[t].n = 0;
}

/* A step.  Where the scene cannot use a stage it is left out (the same
 * bytes as without: tests/e2e/skips.sh):
 *   move   every velocity is 0: no candidate, and after one such step
 *          (which may turn a -0 position into +0) x + 0 = x for every
 *          disk, so nothing at all happens;
 *   pairs  every disk has the same velocity (no pair approaches: |dv|^2 =
 *          0 gives no candidate), or free flight (no pair can close the
 *          gap this step, flight.c): the sort and the pair search are left
 *          out and only walls are found (in any order of the store: the
 *          candidates' order is the rules' total order);
 *   walls  with the pairs left out, no disk can reach a wall this step. */
static int interact(psim_sim *e, void *p, psim_error *err)
{
    cmodel *m = p;
    if (m->gpu)
        return gpu_interact(e, m, err);
    int regridded = 0, rc = 0;
    cvel v;
    /* the extent matters only where the pair search may be left out */
    PSIM_TIMED(e, CPHASE_DETECT, v = velocities(e, m->skip && (m->gap >= 0 || m->same)));
    int same = v.same && m->skip, zero = v.zero && m->skip;
    m->same = same;
    /* the first step at rest still runs: its move turns a -0 position
     * into +0 (x + 0), after which x + 0 = x for every disk */
    int rest = zero && m->still;
    m->still = zero;
    if (rest) {
        e->stats.skipped[CS_MOVE]++;
        e->stats.skipped[CS_PAIRS]++;
        e->stats.skipped[CS_WALLS]++;
        return 0;
    }
    int pairs = !same && !(m->skip && ccd_flight_clear(m, v.vmax));
    int walls = pairs || !(v.has_ext && ccd_walls_clear(m, v.vmax, v.ext));
    if (pairs)
        PSIM_TIMED(e, CPHASE_DETECT, rc = fit_grid(e, m, v.vmax, &regridded));
    if (rc == 0 && regridded && m->rank == 0)   /* (over ranks, every rank's) */
        e->stats.counter[CC_REGRIDS]++;
    if (rc == 0 && pairs)
        psim_engine_sort(e);
    e->stats.skipped[CS_PAIRS] += !pairs;
    e->stats.skipped[CS_WALLS] += !walls;
    m->oom = 0;
    if (rc == 0)
        PSIM_TIMED(e, CPHASE_DETECT, pairs   ? ccd_detect(e, m)
                                     : walls ? ccd_detect_walls(e, m)
                                             : detect_none(m));
    /* the tasks ended early, or a list could not grow */
    int stopped = psim_stop_requested(), failed = rc || m->oom;
    if (!stopped && !failed)
        PSIM_TIMED(e, CPHASE_ORDER, rc = ccd_order(e, m));
    /* over ranks, every rank's candidates to every rank, also from a rank
     * that failed (the step ends on every rank then: psim_dist_poststep) */
    if (m->ranks > 1)
        ccd_gather(e, m, stopped || failed || rc);   /* (timed as comm) */
    if (stopped)
        return psim_engine_stopped(e, err);
    /* a search that found no pair candidate: how long no pair can meet */
    if (rc == 0 && pairs && m->skip && !m->oom && ccd_pair_count(m->all.c, m->all.n) == 0)
        PSIM_TIMED(e, CPHASE_DETECT, ccd_flight_measure(e, m));
    /* the candidates, counted once (over ranks, by rank 0) */
    for (size_t k = 0; rc == 0 && !m->oom && m->rank == 0 && k < m->all.n; k++)
        e->stats.counter[m->all.c[k].q < 0 ? CC_WALL_CANDIDATES : CC_PAIR_CANDIDATES]++;
    if (rc == 0 && !m->oom)
        PSIM_TIMED(e, CPHASE_ACCEPT, rc = ccd_accept(e, m));
    if (psim_stop_requested())   /* acceptance ended early */
        return psim_engine_stopped(e, err);
    if (rc || m->oom) {
        psim_error_set(err, "out of memory for the candidates of step %ld", e->step + 1);
        return -1;
    }
    PSIM_TIMED(e, PSIM_PHASE_MOVE, ccd_advance(e, m));
    ccd_flight_step(m, v.vmax);
    return 0;
}

/* The authors' lines: "step i x y vx vy" with %.8f numbers (printf's, so
 * -0.00000000 for negative zero), and the final step with each disk's
 * pair and wall collision counts. */
typedef struct ccd_out {
    psim_cols c;
    const int64_t *pcoll, *wcoll;   /* NULL: not the final step */
    long step;
    int digits;
} ccd_out;

#define CCD_LINE_MAX (4 * 24 + 4 * (PSIM_FMT_MAX + 1))

static size_t ccd_line(char *out, long i, const void *ctx)
{
    const ccd_out *o = ctx;
    long k = o->c.at[i];
    char *p = psim_fmt_long(out, o->step);
    *p++ = ' ';
    p = psim_fmt_long(p, i);
    const double v[4] = {o->c.x[k], o->c.y[k], o->c.vx[k], o->c.vy[k]};
    for (int j = 0; j < 4; j++) {
        *p++ = ' ';
        p += psim_fmt_fixed(p, v[j], o->digits, 1);
    }
    if (o->pcoll) {
        *p++ = ' ';
        p = psim_fmt_long(p, o->pcoll[i]);
        *p++ = ' ';
        p = psim_fmt_long(p, o->wcoll[i]);
    }
    *p++ = '\n';
    return (size_t)(p - out);
}

/* the authors' fprintf, line by line (PSIM_SLOW_IO=1: the reference) */
static int ccd_lines_slow(FILE *f, long n, const ccd_out *o)
{
    const int digits = o->digits;
    for (long i = 0; i < n; i++) {
        long k = o->c.at[i];
        const double x = o->c.x[k], y = o->c.y[k], vx = o->c.vx[k], vy = o->c.vy[k];
        int w = o->pcoll ? fprintf(f, "%ld %ld %.*f %.*f %.*f %.*f %lld %lld\n", o->step, i,
                                   digits, x, digits, y, digits, vx, digits, vy,
                                   (long long)o->pcoll[i], (long long)o->wcoll[i])
                         : fprintf(f, "%ld %ld %.*f %.*f %.*f %.*f\n", o->step, i, digits, x,
                                   digits, y, digits, vx, digits, vy);
        if (w < 0)
            return -1;
    }
    return 0;
}

static int write_state(psim_sim *e, void *p, FILE *f, long step, int final, int digits)
{
    cmodel *m = p;
    ccd_out o = {.pcoll = final ? m->pcoll : NULL, .wcoll = final ? m->wcoll : NULL,
                 .step = step, .digits = digits > PSIM_DIGITS_MAX ? PSIM_DIGITS_MAX : digits};
    if (psim_state_cols_take(e, &o.c))
        return -1;
    int rc = psim_io_slow() ? ccd_lines_slow(f, e->n, &o)
                            : psim_write_lines(f, e->n, e->threads, CCD_LINE_MAX, ccd_line, &o);
    psim_state_cols_free(&o.c);
    return rc;
}

static void step_summary(FILE *f, const psim_stats *st)
{
    double steps = st->steps > 0 ? (double)st->steps : 1.0;
    const uint64_t *c = st->counter;
    fprintf(f, "  per step: %.0f pair tests, %.1f pair and %.1f wall candidates, "
               "%.1f pair and %.1f wall collisions, %.0f tasks, %.1f accept rounds\n",
            (double)c[CC_PAIR_TESTS] / steps, (double)c[CC_PAIR_CANDIDATES] / steps,
            (double)c[CC_WALL_CANDIDATES] / steps, (double)c[CC_PAIR_COLLISIONS] / steps,
            (double)c[CC_WALL_COLLISIONS] / steps, (double)c[CC_TASKS] / steps,
            (double)c[CC_ACCEPT_ROUNDS] / steps);
}

const psim_model psim_model_ccd = {
    .name = "ccd",
    .summary = "CS3210 AY2019/20: time-of-impact collisions, one per disk per step",
    .phases = {[CPHASE_DETECT - PSIM_PHASE_MODEL] = "detect",
               [CPHASE_ORDER - PSIM_PHASE_MODEL] = "order",
               [CPHASE_ACCEPT - PSIM_PHASE_MODEL] = "accept",
               [CPHASE_COPY - PSIM_PHASE_MODEL] = "copy",
               [CPHASE_END - PSIM_PHASE_MODEL] = NULL},
    .thermo = {"pair_collisions", "wall_collisions", NULL},
    .counters = {[CC_PAIR_TESTS] = "pair_tests",
                 [CC_PAIR_CANDIDATES] = "pair_candidates",
                 [CC_WALL_CANDIDATES] = "wall_candidates",
                 [CC_PAIR_COLLISIONS] = "pair_collisions",
                 [CC_WALL_COLLISIONS] = "wall_collisions",
                 [CC_ACCEPT_ROUNDS] = "accept_rounds",
                 [CC_TASKS] = "tasks",
                 [CC_REGRIDS] = "regrids",
                 [CC_END] = NULL},
    .output = {.to_stdout = 1, .initial = 1, .every_step = 1, .final = 1},
    .output_digits = 8,
    .options = {PSIM_SKIP_OPTION},
    .skips = {[CS_PAIRS] = {"pairs", "no pair can meet, one velocity or free flight: sort and pair search"},
              [CS_WALLS] = {"walls", "no disk can reach a wall in free flight"},
              [CS_MOVE] = {"move", "every velocity 0: nothing moves"},
              [CS_GRAPH] = {"task_graph", "one thread: detection runs in order, no tasks"}},
    .limits = limits,
    .work_unit = "pair tests",
    .create = create,
    .interact = interact,
    .check = ccd_check,
    .write_state = write_state,
    .restart_cols = {{"pair_collisions", 1, 0, CCD_COUNT_MAX},
                     {"wall_collisions", 1, 0, CCD_COUNT_MAX}},
    .restart_save = restart_save,
    .step_summary = step_summary,
    .shares = 1,
    .gpu = 1,
    .sync = gpu_sync,
    .destroy = destroy,
};
