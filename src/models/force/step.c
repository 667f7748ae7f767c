/* One step of the force model: the force on each particle from the
 * positions at the start of the step, then its move (law.h), fused per
 * tile.  New positions go to the store's scratch arrays (x2, y2), swapped
 * in when every tile is done, so no tile waits for another: each tile is a
 * task without dependencies, and its particles' results do not depend on
 * which thread ran it. */
#include <math.h>
#include <stdlib.h>

#include "force.h"
#include "../../engine/timer.h"
#include "../../engine/tstats.h"

/* Particles per block of the naive loop (fixed, so that the per-block
 * sums of --force-stats do not depend on the thread count). */
#define NAIVE_BLOCK 1024

/* The older edition's statistics of one interacting pair. */
static inline void pair_stats(const flaw *k, ftile *t, double px, double py, double qx,
                              double qy)
{
    double dx = qx - px, dy = qy - py, r2 = dx * dx + dy * dy;
    if (r2 > k->cutoff2 || r2 == 0)
        return;
    double d = sqrt(r2) / k->cutoff;
    if (r2 / k->cutoff2 < t->dmin * t->dmin)
        t->dmin = d;
    t->dsum += d;
    t->dn++;
}

static void tile_reset(ftile *t)
{
    t->v2max = 0;
    t->tests = t->hits = 0;
    t->dmin = 1.0;
    t->dsum = 0;
    t->dn = 0;
    t->lost = 0;
}

/* Move particle i with acceleration (ax, ay); new position to x2, y2. */
static inline void move_one(const flaw *k, psim_store *s, ftile *t, uint32_t i, double ax,
                            double ay)
{
    double vx = s->vx[i], vy = s->vy[i];
    t->lost |= flaw_move(k, s->x[i], s->y[i], &vx, &vy, ax, ay, &s->x2[i], &s->y2[i]);
    s->vx[i] = vx;
    s->vy[i] = vy;
    double v2 = vx * vx + vy * vy;
    if (v2 > t->v2max)
        t->v2max = v2;
}

static void tile_lists(const fmodel *m, psim_store *s, ftile *t)
{
    const flaw *k = &m->law;
    const double *x = s->x, *y = s->y;
    uint32_t b = 0;
    tile_reset(t);
    for (uint32_t q = 0; q < t->n; q++) {
        uint32_t i = t->first + q, end = t->end[q];
        double px = x[i], py = y[i], ax = 0, ay = 0;
        uint64_t hits = 0;
        for (uint32_t a = b; a < end; a++)
            hits += (uint64_t)flaw_pair(k, px, py, x[t->nbr[a]], y[t->nbr[a]], &ax, &ay);
        if (m->stats)
            for (uint32_t a = b; a < end; a++)
                pair_stats(k, t, px, py, x[t->nbr[a]], y[t->nbr[a]]);
        t->tests += end - b;
        t->hits += hits;
        b = end;
        move_one(k, s, t, i, ax, ay);
    }
}

/* The course's loops: every j, in id order (the store is, without a grid). */
static void block_naive(const fmodel *m, psim_store *s, ftile *t)
{
    const flaw *k = &m->law;
    const size_t n = s->n;
    tile_reset(t);
    for (uint32_t q = 0; q < t->n; q++) {
        uint32_t i = t->first + q;
        double px = s->x[i], py = s->y[i], ax = 0, ay = 0;
        uint64_t hits = 0;
        for (size_t j = 0; j < n; j++)
            hits += (uint64_t)flaw_pair(k, px, py, s->x[j], s->y[j], &ax, &ay);
        if (m->stats)
            for (size_t j = 0; j < n; j++)
                pair_stats(k, t, px, py, s->x[j], s->y[j]);
        t->tests += n;
        t->hits += hits - 1;   /* not itself */
        move_one(k, s, t, i, ax, ay);
    }
}

/* Totals of the tiles, in tile order; the new positions swapped in. */
static int finish(psim_sim *e, fmodel *m)
{
    double v2max = 0, dmin = 1.0, dsum = 0;
    uint64_t tests = 0, hits = 0, dn = 0;
    int lost = 0;
    for (uint32_t t = 0; t < m->ntiles; t++) {
        const ftile *ft = &m->tiles[t];
        v2max = fmax(v2max, ft->v2max);
        tests += ft->tests;
        hits += ft->hits;
        dmin = fmin(dmin, ft->dmin);
        dsum += ft->dsum;
        dn += ft->dn;
        lost |= ft->lost;
    }
    psim_store *s = &e->st;
    double *tx = s->x, *ty = s->y;
    s->x = s->x2, s->y = s->y2;
    s->x2 = tx, s->y2 = ty;
    e->stats.counter[FC_PAIR_TESTS] += tests;
    e->stats.counter[FC_INTERACTIONS] += hits;
    m->drift += sqrt(v2max) * m->law.dt;
    m->since_build++;
    if (m->stats) {            /* the course's per-step bookkeeping */
        if (dn) {
            m->absavg += dsum / (double)dn;
            m->nabsavg++;
        }
        if (dmin < m->absmin)
            m->absmin = dmin;
    }
    return lost ? -1 : 0;
}

typedef void (*tile_fn)(const fmodel *m, psim_store *s, ftile *t);

static int run_tiles(psim_sim *e, fmodel *m, tile_fn fn)
{
    psim_store *s = &e->st;
    psim_thread_stats *ts = e->tstats;
#pragma omp parallel num_threads(e->threads)
#pragma omp single
    for (uint32_t t = 0; t < m->ntiles; t++) {
        ftile *ft = &m->tiles[t];
#pragma omp task firstprivate(ft) shared(m, s, ts, fn) default(none)
        {
            double b0 = psim_now();
            fn(m, s, ft);
            psim_tstat_add(ts, FPHASE_FORCE, psim_now() - b0, 1, ft->n);
        }
    }
    e->stats.counter[FC_TASKS] += m->ntiles;
    return finish(e, m);
}

int force_step_lists(psim_sim *e, fmodel *m)
{
    return run_tiles(e, m, tile_lists);
}

int force_step_naive(psim_sim *e, fmodel *m)
{
    return run_tiles(e, m, block_naive);
}

/* Blocks of the naive loop, as tiles without lists. */
int force_plan_naive(fmodel *m, long n)
{
    uint32_t nb = (uint32_t)((n + NAIVE_BLOCK - 1) / NAIVE_BLOCK);
    m->tiles = calloc(nb ? nb : 1, sizeof *m->tiles);
    if (!m->tiles)
        return -1;
    m->ntiles = m->cap_tiles = nb;
    for (uint32_t b = 0; b < nb; b++) {
        m->tiles[b].first = b * NAIVE_BLOCK;
        m->tiles[b].n = (uint32_t)(n - (long)b * NAIVE_BLOCK < NAIVE_BLOCK
                                       ? n - (long)b * NAIVE_BLOCK : NAIVE_BLOCK);
    }
    return 0;
}
