/* The ccd model behind the model interface: its grid, its step, and its
 * output in the authors' format. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "ccd.h"
#include "../../engine/mem.h"
#include "../../engine/tstats.h"

/* The velocities this step: the largest displacement of one disk,
 * max |vx| + |vy| >= |v|, and whether they are all one (finite) velocity
 * (*same) and that velocity is zero (*zero). */
static double velocities(const psim_sim *e, int *same, int *zero)
{
    const psim_store *s = &e->st;
    double v = 0, u0 = INFINITY, u1 = -INFINITY, w0 = INFINITY, w1 = -INFINITY;
#pragma omp parallel for schedule(static) num_threads(e->threads) \
    reduction(max : v, u1, w1) reduction(min : u0, w0)
    for (size_t i = 0; i < s->n; i++) {
        double d = fabs(s->vx[i]) + fabs(s->vy[i]);
        v = d > v ? d : v;
        u0 = s->vx[i] < u0 ? s->vx[i] : u0, u1 = s->vx[i] > u1 ? s->vx[i] : u1;
        w0 = s->vy[i] < w0 ? s->vy[i] : w0, w1 = s->vy[i] > w1 ? s->vy[i] : w1;
    }
    /* NaN is in no comparison: it leaves u0 > u1 or a v that is not finite */
    *same = s->n > 0 && u0 == u1 && w0 == w1 && isfinite(u0) && isfinite(w0) && isfinite(v);
    *zero = *same && u0 == 0 && w0 == 0;
    return v;
}

/* Slack on the swept boxes and the cells against round-off: the rules'
 * arithmetic can make a candidate of a pair whose exact closest approach
 * is a little over 2r (by about sqrt(eps) of the distances involved). */
static double margin_for(const cmodel *m, double vmax)
{
    return 1e-6 * (m->L + 2 * vmax + m->r);
}

/* Cells must be wider than 2r plus the largest displacement of two disks;
 * re-plan when they are not, or when they are far wider than needed. */
static int fit_grid(psim_sim *e, cmodel *m, double vmax, int *regridded)
{
    m->vmax = vmax;
    m->margin = margin_for(m, vmax);
    double reach = 2 * m->r + 2 * vmax + 2 * m->margin;
    *regridded = 0;
    if (e->has_grid && reach <= e->grid.h &&
        !(reach * 3 < e->grid.h && e->grid.G < (int)ceil(sqrt((double)e->n / 3.0))))
        return 0;
    *regridded = 1;
    /* 10% slack so that slowly growing speeds do not re-plan every step */
    double want = fmin(reach * 1.1, m->L * 2);
    if (psim_engine_grid(e, want > reach ? want : reach, NULL))
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
 * the scene, as the event model refuses overlaps.  Disks that straddle a
 * wall (centre within r of it, as in the course's scenes) run as the
 * authors' program runs them. */
static long first_outside(const psim_scene *sc)
{
    for (long i = 0; i < sc->n; i++)
        if (!(sc->x[i] >= 0 && sc->x[i] <= sc->L && sc->y[i] >= 0 && sc->y[i] <= sc->L))
            return i;
    return -1;
}

static void *create(psim_sim *e, const psim_scene *sc, psim_error *err)
{
    long out = first_outside(sc);
    if (out >= 0) {
        char at[320];
        psim_scene_where(sc, out, at, sizeof at);
        psim_error_set(err, "%sdisk %ld at (%.17g, %.17g) is outside the box [0, %.17g]^2: "
                            "the ccd model's wall rule needs every centre inside it",
                       at, out, sc->x[out], sc->y[out], sc->L);
        return NULL;
    }
    cmodel *m = calloc(1, sizeof *m);
    if (!m)
        goto oom;
    m->L = e->L;
    m->r = e->r;
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
    int regridded, same, zero;
    if (!m->sx0 || !m->sx1 || !m->sy0 || !m->sy1 || !m->ord || !m->key || !m->key2 ||
        !m->ord2 || !m->busy || !m->best || !m->pcoll || !m->wcoll || !m->lists || !m->off || !m->head ||
        fit_grid(e, m, velocities(e, &same, &zero), &regridded))
        goto oom;
    return m;
oom:
    destroy(m);
    psim_error_set(err, "out of memory for the ccd model");
    return NULL;
}

/* A step.  Where the scene cannot use a stage it is left out (the same
 * bytes as without: tests/e2e/skips.sh):
 *   move   every velocity is 0: no candidate, and after one such step
 *          (which may turn a -0 position into +0) x + 0 = x for every
 *          disk, so nothing at all happens;
 *   pairs  every disk has the same velocity: no pair approaches (|dv|^2 =
 *          0 gives no candidate), so the sort and the pair search are left
 *          out and only walls are found (in any order of the store: the
 *          candidates' order is the rules' total order). */
static int interact(psim_sim *e, void *p, psim_error *err)
{
    cmodel *m = p;
    int regridded = 0, same, zero, rc = 0;
    double vmax = 0;
    PSIM_TIMED(e, CPHASE_DETECT, vmax = velocities(e, &same, &zero));
    same &= m->skip, zero &= m->skip;
    /* the first step at rest still runs: its move turns a -0 position
     * into +0 (x + 0), after which x + 0 = x for every disk */
    int rest = zero && m->still;
    m->still = zero;
    if (rest) {
        e->stats.skipped[CS_MOVE]++;
        e->stats.skipped[CS_PAIRS]++;
        return 0;
    }
    if (!same)
        PSIM_TIMED(e, CPHASE_DETECT, rc = fit_grid(e, m, vmax, &regridded));
    if (rc == 0 && regridded)
        e->stats.counter[CC_REGRIDS]++;
    if (rc == 0 && !same)
        psim_engine_sort(e);
    e->stats.skipped[CS_PAIRS] += same;
    m->oom = 0;
    if (rc == 0)
        PSIM_TIMED(e, CPHASE_DETECT, same ? ccd_detect_walls(e, m) : ccd_detect(e, m));
    if (rc == 0 && !m->oom)
        PSIM_TIMED(e, CPHASE_ORDER, rc = ccd_order(e, m));
    if (rc == 0 && !m->oom)
        PSIM_TIMED(e, CPHASE_ACCEPT, rc = ccd_accept(e, m));
    if (rc || m->oom) {
        psim_error_set(err, "out of memory for the candidates of step %ld", e->step + 1);
        return -1;
    }
    PSIM_TIMED(e, PSIM_PHASE_MOVE, ccd_advance(e, m));
    return 0;
}

/* The authors' lines: "step i x y vx vy" with %.8f numbers (printf's, so
 * -0.00000000 for negative zero), and the final step with each disk's
 * pair and wall collision counts. */
static int write_state(psim_sim *e, void *p, FILE *f, long step, int final, int digits)
{
    cmodel *m = p;
    psim_snapshot s;
    int rc = psim_snapshot_take(e, &s);
    for (long i = 0; i < e->n && rc == 0; i++) {
        int w = final ? fprintf(f, "%ld %ld %.*f %.*f %.*f %.*f %lld %lld\n", step, i, digits,
                                s.x[i], digits, s.y[i], digits, s.vx[i], digits, s.vy[i],
                                (long long)m->pcoll[i], (long long)m->wcoll[i])
                      : fprintf(f, "%ld %ld %.*f %.*f %.*f %.*f\n", step, i, digits, s.x[i],
                                digits, s.y[i], digits, s.vx[i], digits, s.vy[i]);
        if (w < 0)
            rc = -1;
    }
    psim_snapshot_free(&s);
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
    .phases = {"detect", "order", "accept", NULL},
    .counters = {"pair_tests", "pair_candidates", "wall_candidates", "pair_collisions",
                 "wall_collisions", "accept_rounds", "tasks", "regrids", NULL},
    .output = {.to_stdout = 1, .initial = 1, .every_step = 1, .final = 1},
    .output_digits = 8,
    .options = {PSIM_SKIP_OPTION},
    .skips = {[CS_PAIRS] = {"pairs", "one velocity for all: sort and pair search"},
              [CS_MOVE] = {"move", "every velocity 0: nothing moves"},
              [CS_GRAPH] = {"task_graph", "one thread: detection runs in order, no tasks"}},
    .sorts_itself = 1,
    .create = create,
    .interact = interact,
    .check = ccd_check,
    .write_state = write_state,
    .step_summary = step_summary,
    .destroy = destroy,
};
