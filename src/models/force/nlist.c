/* Verlet neighbour lists of the force model, built from the engine's sort:
 * cells are wider than the list radius (cutoff + skin), so a particle's
 * neighbours are in its own and the eight adjacent cells.  Each list is in
 * id order: summing a particle's forces in that order is the course's
 * naive loop over j = 0 .. n-1 with the pairs beyond the cutoff left out,
 * so the fast path gives the naive code's bits. */
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
        ft->end = m->end_all + ft->first;
    }
    return 0;
}

/* Insert the last entry of list[0 .. len-1] in id order. */
static void insert_by_id(uint32_t *list, size_t len, const int32_t *id)
{
    uint32_t v = list[len - 1];
    size_t k = len - 1;
    while (k > 0 && id[list[k - 1]] > id[v]) {
        list[k] = list[k - 1];
        k--;
    }
    list[k] = v;
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
    size_t c2 = t->ccap, c3 = t->ccap;
    return psim_reserve((void **)&t->cy, &c2, need, sizeof *t->cy) ||
           psim_reserve((void **)&t->cj, &c3, need, sizeof *t->cj) ||
           psim_reserve((void **)&t->cx, &t->ccap, need, sizeof *t->cx);
}

/* Gather the particles of the 3 x 3 cells around cell c into the tile's
 * candidate buffer; returns their number, or -1 (no memory). */
static long gather(const psim_sim *e, ftile *t, uint32_t c)
{
    const psim_store *s = &e->st;
    const psim_grid *g = &e->grid;
    int lx = g->cell_x[c] - t->wx0, ly = g->cell_y[c] - t->wy0;
    size_t k = 0;
    for (int dy = -1; dy <= 1; dy++) {
        const uint32_t *w = t->win + 2 * ((size_t)(ly + dy) * (size_t)t->W + (size_t)(lx - 1));
        uint32_t n = (w[1] - w[0]) + (w[3] - w[2]) + (w[5] - w[4]);
        if (reserve_candidates(t, k + n))
            return -1;
        for (int dx = 0; dx < 3; dx++)
            for (uint32_t j = w[2 * dx]; j < w[2 * dx + 1]; j++, k++) {
                t->cx[k] = s->x[j];
                t->cy[k] = s->y[j];
                t->cj[k] = j;
            }
    }
    return (long)k;
}

/* Append particle i's neighbours among the nc candidates, in id order.
 * The test is branch-free: every candidate is written, and the length
 * grows by whether it is within reach. */
static int list_one(const psim_sim *e, ftile *t, uint32_t i, long nc, double reach2)
{
    if (t->len + (size_t)nc > t->cap &&
        psim_reserve((void **)&t->nbr, &t->cap, t->len + (size_t)nc, sizeof *t->nbr))
        return -1;
    double px = e->st.x[i], py = e->st.y[i];
    size_t begin = t->len, len = begin;
    for (long k = 0; k < nc; k++) {
        double dx = t->cx[k] - px, dy = t->cy[k] - py;
        t->nbr[len] = t->cj[k];
        len += (dx * dx + dy * dy <= reach2) & (t->cj[k] != i);
    }
    for (size_t a = begin + 1; a < len; a++)
        insert_by_id(t->nbr + begin, a - begin + 1, e->st.id);
    t->len = len;
    return 0;
}

static int list_tile(const psim_sim *e, ftile *t, uint32_t tile, double reach2)
{
    const psim_grid *g = &e->grid;
    uint32_t c0 = g->tile_cell0[tile], c1 = g->tile_cell0[tile + 1];
    t->len = 0;
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
        for (uint32_t i = i0; i < i1; i++) {
            if (list_one(e, t, i, nc, reach2))
                return -1;
            t->end[i - t->first] = (uint32_t)t->len;
        }
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
    double reach = m->law.cutoff + m->skin, reach2 = reach * reach;
    int oom = 0;
    psim_thread_stats *ts = e->tstats;
#pragma omp parallel num_threads(e->threads)
#pragma omp single
    for (uint32_t t = 0; t < m->ntiles; t++) {
        ftile *ft = &m->tiles[t];
#pragma omp task firstprivate(ft, t, reach2) shared(oom, ts, e) default(none)
        {
            double b0 = psim_now();
            if (list_tile(e, ft, t, reach2)) {
#pragma omp atomic write
                oom = 1;
            }
            psim_tstat_add(ts, FPHASE_NLIST, psim_now() - b0, 1, ft->n);
        }
    }
    uint64_t entries = 0;
    for (uint32_t t = 0; t < m->ntiles; t++)
        entries += m->tiles[t].len;
    e->stats.counter[FC_LIST_ENTRIES] += entries;
    e->stats.counter[FC_REBUILDS]++;
    e->stats.counter[FC_TASKS] += m->ntiles;
    e->stats.phase_s[FPHASE_NLIST] += psim_now() - t0;
    m->drift = 0;
    m->since_build = 0;
    m->built = 1;
    return oom ? -1 : 0;
}
