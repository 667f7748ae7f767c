/* Verlet pair lists of the force model, built from the engine's sort:
 * cells are wider than the list radius (cutoff + skin), so a particle's
 * neighbours are in its own and the eight adjacent cells.  Each unordered
 * pair is listed once, by the cell that sees the other's cell in its
 * forward half of the 3 x 3 stencil (a half list: half the tests of a
 * full one), in the shell of its distance (force.h).  The order of the
 * pairs does not matter: step.c sums each particle's forces in id order. */
#include <stdlib.h>
#include <string.h>

#include "force.h"
#include "../../engine/mem.h"
#include "../../engine/timer.h"
#include "../../engine/tstats.h"

/* Tiles follow the grid's; their lists are kept from build to build. */
static int plan_tiles(psim_sim *e, fmodel *m)
{
    const psim_grid *g = &e->grid;
    if (g->ntiles > m->cap_tiles) {
        ftile *t = realloc(m->tiles, g->ntiles * sizeof *t);
        if (!t)
            return -1;
        memset(t + m->cap_tiles, 0, (g->ntiles - m->cap_tiles) * sizeof *t);
        m->tiles = t;
        m->cap_tiles = g->ntiles;
    }
    m->ntiles = g->ntiles;
    for (uint32_t t = 0; t < g->ntiles; t++) {
        ftile *ft = &m->tiles[t];
        ft->first = g->cellstart[g->tile_cell0[t]];
        ft->n = g->cellstart[g->tile_cell0[t + 1]] - ft->first;
        if (ft->n > ft->acap) {
            size_t cap = ft->n + ft->n / 2 + 16;
            psim_free(ft->ax), psim_free(ft->ay), psim_free(ft->cnt);
            ft->ax = psim_alloc(cap * sizeof *ft->ax);
            ft->ay = psim_alloc(cap * sizeof *ft->ay);
            ft->cnt = psim_alloc(cap * sizeof *ft->cnt);
            ft->acap = ft->ax && ft->ay && ft->cnt ? cap : 0;
            if (!ft->acap)
                return -1;
        }
        if (ft->n) {
            memset(ft->ax, 0, ft->n * sizeof *ft->ax);
            memset(ft->ay, 0, ft->n * sizeof *ft->ay);
            memset(ft->cnt, 0, ft->n * sizeof *ft->cnt);
        }
    }
    return 0;
}

/* The tile's cells and a border of one cell, row-major: where each
 * cell's particles are in the store.  Gathering a cell's 3 x 3
 * neighbourhood then reads this small table instead of the grid's
 * rank table and cell starts (nine scattered reads per cell). */
static int plan_window(const psim_sim *e, ftile *t, uint32_t tile)
{
    const psim_grid *g = &e->grid;
    int S = 1 << g->tile_shift, W = S + 2;
    t->wx0 = g->tile_x[tile] * S - 1;
    t->wy0 = g->tile_y[tile] * S - 1;
    t->W = W;
    if (psim_reserve((void **)&t->win, &t->wcap, 2 * (size_t)W * (size_t)W, sizeof *t->win))
        return -1;
    for (int ly = 0; ly < W; ly++)
        for (int lx = 0; lx < W; lx++) {
            int gx = t->wx0 + lx, gy = t->wy0 + ly;
            uint32_t *w = t->win + 2 * ((size_t)ly * (size_t)W + (size_t)lx);
            if (gx < 0 || gy < 0 || gx >= g->G || gy >= g->G) {
                w[0] = w[1] = 0;
                continue;
            }
            uint32_t rank = g->rank_of_xy[(uint32_t)gy * (uint32_t)g->G + (uint32_t)gx];
            w[0] = g->cellstart[rank];
            w[1] = g->cellstart[rank + 1];
        }
    return 0;
}

static int reserve_candidates(ftile *t, size_t need)
{
    if (need <= t->ccap)
        return 0;
    size_t c2 = t->ccap, c3 = t->ccap, c4 = t->ccap, c5 = t->ccap;
    return psim_reserve((void **)&t->cy, &c2, need, sizeof *t->cy) ||
           psim_reserve((void **)&t->cj, &c3, need, sizeof *t->cj) ||
           psim_reserve((void **)&t->near, &c4, need, sizeof *t->near) ||
           psim_reserve((void **)&t->nr2, &c5, need, sizeof *t->nr2) ||
           psim_reserve((void **)&t->cx, &t->ccap, need, sizeof *t->cx);
}

/* The forward half of the 3 x 3 stencil: the cell itself first, then
 * the cells to the east, north-west, north and north-east. */
static const int fwd_dx[5] = {0, 1, -1, 0, 1}, fwd_dy[5] = {0, 0, 1, 1, 1};

/* Gather the particles of cell c and its forward cells into the tile's
 * candidate buffer (cell c's first); returns their number, or -1. */
static long gather(const psim_sim *e, ftile *t, uint32_t c)
{
    const psim_store *s = &e->st;
    const psim_grid *g = &e->grid;
    int lx = g->cell_x[c] - t->wx0, ly = g->cell_y[c] - t->wy0;
    const uint32_t *w[5];
    size_t k = 0, need = 0;
    for (int f = 0; f < 5; f++) {
        w[f] = t->win + 2 * ((size_t)(ly + fwd_dy[f]) * (size_t)t->W + (size_t)(lx + fwd_dx[f]));
        need += w[f][1] - w[f][0];
    }
    if (reserve_candidates(t, need))
        return -1;
    for (int f = 0; f < 5; f++)
        for (uint32_t j = w[f][0]; j < w[f][1]; j++, k++) {
            t->cx[k] = s->x[j];
            t->cy[k] = s->y[j];
            t->cj[k] = j;
        }
    return (long)k;
}

/* Append the pairs of particle i with candidates a .. nc - 1 within
 * reach, each to the shell of its distance: first those within reach are
 * picked out (branch-free, the count in a register), then only they are
 * given a shell. */
static int list_one(const psim_sim *e, ftile *t, uint32_t i, long a, long nc,
                    const double *thr)
{
    double px = e->st.x[i], py = e->st.y[i], reach2 = thr[FORCE_BUCKETS - 1];
    const double *cx = t->cx, *cy = t->cy;
    const uint32_t *cj = t->cj;
    uint32_t *near = t->near;
    double *nr2 = t->nr2;
    size_t nn = 0;
    for (long k = a; k < nc; k++) {
        double dx = cx[k] - px, dy = cy[k] - py, r2 = dx * dx + dy * dy;
        near[nn] = cj[k];
        nr2[nn] = r2;
        nn += r2 <= reach2;
    }
    for (size_t h = 0; h < nn; h++) {
        int b = 0;
        for (int m = 0; m < FORCE_BUCKETS - 1; m++)
            b += nr2[h] > thr[m];
        if (t->len[b] == t->cap[b] &&
            psim_reserve((void **)&t->pair[b], &t->cap[b], t->len[b] + 1, sizeof *t->pair[b]))
            return -1;
        t->pair[b][t->len[b]++] = (fpair){i, near[h]};
    }
    return 0;
}

static int list_tile(const psim_sim *e, ftile *t, uint32_t tile, const double *thr)
{
    const psim_grid *g = &e->grid;
    uint32_t c0 = g->tile_cell0[tile], c1 = g->tile_cell0[tile + 1];
    for (int b = 0; b < FORCE_BUCKETS; b++)
        t->len[b] = 0;
    if (t->n == 0)
        return 0;
    if (plan_window(e, t, tile))
        return -1;
    for (uint32_t c = c0; c < c1; c++) {
        uint32_t i0 = g->cellstart[c], i1 = g->cellstart[c + 1];
        if (i0 == i1)
            continue;
        long nc = gather(e, t, c);
        if (nc < 0)
            return -1;
        for (uint32_t i = i0; i < i1; i++)
            if (list_one(e, t, i, (long)(i - i0) + 1, nc, thr))
                return -1;
    }
    return 0;
}

/* Sort by cell and build every tile's lists, one task per tile (the tiles
 * write only their own lists: no dependencies). */
int force_build_lists(psim_sim *e, fmodel *m)
{
    psim_engine_sort(e);
    double t0 = psim_now();
    if (plan_tiles(e, m))
        return -1;
    /* shell b holds the pairs with r2 <= thr[b]: thr[b] = (cutoff + (b + 1) skin / B)^2 */
    double thr[FORCE_BUCKETS];
    for (int b = 0; b < FORCE_BUCKETS; b++) {
        double d = m->law.cutoff + (b + 1) * (m->skin / FORCE_BUCKETS);
        thr[b] = d * d;
    }
    int oom = 0;
    psim_thread_stats *ts = e->tstats;
#pragma omp parallel num_threads(e->threads)
#pragma omp single
    for (uint32_t t = 0; t < m->ntiles; t++) {
        ftile *ft = &m->tiles[t];
#pragma omp task firstprivate(ft, t) shared(thr) shared(oom, ts, e) default(none)
        {
            double b0 = psim_now();
            if (list_tile(e, ft, t, thr)) {
#pragma omp atomic write
                oom = 1;
            }
            psim_tstat_add(ts, FPHASE_NLIST, psim_now() - b0, 1, ft->n);
        }
    }
    uint64_t entries = 0;
    for (uint32_t t = 0; t < m->ntiles; t++)
        for (int b = 0; b < FORCE_BUCKETS; b++)
            entries += m->tiles[t].len[b];
    e->stats.counter[FC_LIST_ENTRIES] += entries;
    e->stats.counter[FC_REBUILDS]++;
    e->stats.counter[FC_TASKS] += m->ntiles;
    e->stats.phase_s[FPHASE_NLIST] += psim_now() - t0;
    m->drift = 0;
    m->since_build = 0;
    m->built = 1;
    return oom ? -1 : 0;
}
