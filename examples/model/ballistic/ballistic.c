/* The ballistic model: the worked example of docs/adding-a-model.md.
 *
 * Disks fly in straight lines and bounce off the four walls of the box;
 * they pass through each other (no interactions).  A centre stays in
 * [r, L - r] on each axis.  A step advances the time by dt (the option
 * dt, default 1): each disk moves by its velocity times dt, and a wall it
 * reaches mirrors the rest of its path.  Every disk moves on its own, so
 * the result is the same on any number of threads.
 *
 * The model asks for no grid and never sorts the store: the particles
 * keep the order create found them in, and the writers read them by id. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "../../engine/engine.h"

/* Its phases are numbered from PSIM_PHASE_MODEL, its counters from 0;
 * .phases and .counters below name each by its constant, and the _END
 * constant marks where the names end. */
enum { BPHASE_FLIGHT = PSIM_PHASE_MODEL, BPHASE_END };
enum { BC_REVERSALS, BC_END };

/* What create makes, interact uses and destroy frees. */
typedef struct bmodel {
    double lo, hi;   /* the walls a centre stays between: r and L - r */
    double dt;       /* the time a step advances */
} bmodel;

/* Coordinate *p with velocity *v after time dt between walls lo < hi.  A
 * path that reaches a wall is folded back as mirrors fold it: the images
 * of the interval repeat every 2 (hi - lo), every second one reversed,
 * and the velocity is reversed when the path ends in a reversed one (fmod
 * is exact, so a disk that crosses the box many times in a step bounces
 * as often).  Returns 1 where the velocity was reversed. */
static int fly(double *p, double *v, double dt, double lo, double hi)
{
    double q = *p + *v * dt;
    if (q >= lo && q <= hi) {
        *p = q;
        return 0;
    }
    double w = hi - lo, u = fmod(q - lo, 2 * w);
    if (u < 0)
        u += 2 * w;
    if (u <= w) {
        *p = lo + u;
        return 0;
    }
    *p = lo + (2 * w - u);
    *v = -*v;
    return 1;
}

/* A step's flight, shared among the threads in blocks of PSIM_POLL_WORK
 * disks.  After each block a poll counts the work (progress inside a long
 * step) and the blocks left are skipped once a stop was asked (a signal). */
static uint64_t fly_all(psim_sim *e, const bmodel *m)
{
    psim_store *s = &e->st;
    const long n = (long)s->n, blocks = (n + PSIM_POLL_WORK - 1) / PSIM_POLL_WORK;
    uint64_t reversals = 0;
#pragma omp parallel for schedule(static) num_threads(e->threads) reduction(+ : reversals)
    for (long b = 0; b < blocks; b++) {
        if (psim_stop_requested())
            continue;
        long lo = b * PSIM_POLL_WORK, hi = lo + PSIM_POLL_WORK < n ? lo + PSIM_POLL_WORK : n;
        for (long i = lo; i < hi; i++) {
            reversals += (uint64_t)fly(&s->x[i], &s->vx[i], m->dt, m->lo, m->hi);
            reversals += (uint64_t)fly(&s->y[i], &s->vy[i], m->dt, m->lo, m->hi);
        }
        psim_poll(e, (uint64_t)(hi - lo));
    }
    return reversals;
}

static int interact(psim_sim *e, void *p, psim_error *err)
{
    const bmodel *m = p;
    uint64_t reversals;
    PSIM_TIMED(e, BPHASE_FLIGHT, reversals = fly_all(e, m));
    if (psim_stop_requested())   /* blocks were skipped: the step is void */
        return psim_engine_stopped(e, err);
    e->stats.counter[BC_REVERSALS] += reversals;
    return 0;
}

/* The largest box, positions and speeds (model.h) whose arithmetic stays
 * finite: q = p + v dt with dt <= 1, and the period 2 (hi - lo). */
static int limits(const psim_sim *e, const psim_scene *sc, psim_limits *lim, psim_error *err)
{
    (void)e, (void)sc, (void)err;
    lim->at[PSIM_LIMIT_BOX] = (psim_limit){1e300, "its mirror period 2 (L - 2r)"};
    lim->at[PSIM_LIMIT_POSITION] = (psim_limit){1e300, "its paths x + vx dt"};
    lim->at[PSIM_LIMIT_SPEED] = (psim_limit){1e300, "its paths x + vx dt"};
    return 0;
}

static void *create(psim_sim *e, const psim_scene *sc, psim_error *err)
{
    if (!(sc->L - 2 * sc->r > 0)) {
        char at[320];   /* "FILE:LINE: " of the scene's r */
        psim_scene_where_header(sc, PSIM_LINE_R, at, sizeof at);
        psim_error_set(err, "%sr = %g leaves no room between the walls of a box of side %g",
                       at, sc->r, sc->L);
        return NULL;
    }
    bmodel *m = malloc(sizeof *m);
    if (!m) {
        psim_error_set(err, "out of memory for the ballistic model");
        return NULL;
    }
    m->lo = sc->r;
    m->hi = sc->L - sc->r;
    m->dt = psim_engine_option(e, "dt", 1);
    return m;
}

static double step_time(const psim_sim *e, const void *p)
{
    (void)e;
    return ((const bmodel *)p)->dt;
}

static void destroy(void *p) { free(p); }

const psim_model psim_model_ballistic = {
    .name = "ballistic",
    .summary = "free flight between reflecting walls, no interactions (the example model)",
    .phases = {[BPHASE_FLIGHT - PSIM_PHASE_MODEL] = "flight",
               [BPHASE_END - PSIM_PHASE_MODEL] = NULL},
    .counters = {[BC_REVERSALS] = "reversals", [BC_END] = NULL},
    .thermo = {"reversals", NULL},
    .options = {{"dt", "time a step advances, velocities being per unit time (default 1)",
                 0, 1, 0},
                {NULL, NULL, 0, 0, 0}},
    .output = {.final = 1},   /* --out: the state after the last step */
    .output_digits = -1,      /* shortest decimals that read back exactly */
    .work_unit = "disks",
    .limits = limits,
    .create = create,
    .interact = interact,
    .step_time = step_time,
    .destroy = destroy,
};
