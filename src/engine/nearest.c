#include "nearest.h"

#include <math.h>

/* The closest pair above above2 of rows [i0, i1) with rows [j0, j1), or
 * with the rows after each up to j1 when j0 is NONE (a cell with itself:
 * each pair once), below best. */
#define NONE UINT32_MAX
static double cell_pairs(const psim_store *s, uint32_t i0, uint32_t i1, uint32_t j0,
                         uint32_t j1, double above2, double best)
{
    const double *x = s->x, *y = s->y;
    for (uint32_t i = i0; i < i1; i++) {
        double px = x[i], py = y[i];
        for (uint32_t j = j0 == NONE ? i + 1 : j0; j < j1; j++) {
            double dx = x[j] - px, dy = y[j] - py, d2 = dx * dx + dy * dy;
            best = d2 > above2 && d2 < best ? d2 : best;
        }
    }
    return best;
}

/* A thread's pairs looked at in cells of many particles, and how many of
 * them it has polled (poll.h): fast disks on a one-cell grid are O(n^2)
 * pairs. */
typedef struct pair_count {
    uint64_t pairs, polled;
    int stop;
} pair_count;

/* The same, POLL_ROWS rows at a time with a poll between, for a cell of
 * more rows than that (the minimum does not depend on the order); after a
 * stop asked it ends early, with a result of no use. */
#define POLL_ROWS 64
static inline __attribute__((always_inline)) double
rows_pairs(const psim_sim *e, uint32_t i0, uint32_t i1, uint32_t j0, uint32_t j1,
           double above2, double best, pair_count *pc)
{
    if (i1 - i0 <= POLL_ROWS)
        return cell_pairs(&e->st, i0, i1, j0, j1, above2, best);
    for (uint32_t i = i0; i < i1 && !pc->stop; i += POLL_ROWS) {
        uint32_t k = i1 - i > POLL_ROWS ? i + POLL_ROWS : i1;
        best = cell_pairs(&e->st, i, k, j0, j1, above2, best);
        pc->pairs += (uint64_t)(k - i) * (j1 - (j0 == NONE ? i : j0));
        if (pc->pairs - pc->polled >= PSIM_POLL_WORK) {
            pc->stop = psim_poll(e, pc->pairs - pc->polled);
            pc->polled = pc->pairs;
        }
    }
    return best;
}

double psim_nearest2(const psim_sim *e, double above2)
{
    const psim_grid *g = &e->grid;
    const psim_store *s = &e->st;
    double best = INFINITY;
    const long n = (long)s->n;
    /* the non-empty cells, each at its first particle: O(n), not O(cells) */
#pragma omp parallel num_threads(e->threads)
    {
        pair_count pc = {0, 0, 0};
#pragma omp for schedule(static) reduction(min : best)
        for (long i = 0; i < n; i++) {
            uint32_t c = psim_grid_cell(g, s->x[i], s->y[i]);
            uint32_t a0 = g->cellstart[c], a1 = g->cellstart[c + 1];
            if (a0 != (uint32_t)i || pc.stop)
                continue;
            best = rows_pairs(e, a0, a1, NONE, a1, above2, best, &pc);
            int cx = g->cell_x[c], cy = g->cell_y[c];
            for (int k = 0; k < 4; k++) {   /* the forward half: each pair of cells once */
                int nx, ny;
                uint32_t r = psim_grid_forward(g, cx, cy, k, &nx, &ny);
                if (r == UINT32_MAX)
                    continue;
                best = rows_pairs(e, a0, a1, g->cellstart[r], g->cellstart[r + 1], above2,
                                  best, &pc);
            }
        }
        if (pc.pairs > pc.polled)
            psim_poll_add(e, pc.pairs - pc.polled);
    }
    return best;
}

double psim_distance_bound(const psim_sim *e, double d2)
{
    return fmin(sqrt(d2), e->grid.h) * (1 - 1e-12);
}

double psim_nearest_bound(const psim_sim *e, double above2)
{
    return psim_distance_bound(e, psim_nearest2(e, above2));
}
