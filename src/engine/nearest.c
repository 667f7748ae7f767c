#include "nearest.h"

#include <math.h>

/* The closest pair above above2 between cells [a0, a1) and [b0, b1), or
 * within cell [a0, a1) when b0 is NONE (each pair once), below best. */
#define NONE UINT32_MAX
static double cell_pairs(const psim_store *s, uint32_t a0, uint32_t a1, uint32_t b0,
                         uint32_t b1, double above2, double best)
{
    const double *x = s->x, *y = s->y;
    for (uint32_t i = a0; i < a1; i++) {
        double px = x[i], py = y[i];
        for (uint32_t j = b0 == NONE ? i + 1 : b0; j < (b0 == NONE ? a1 : b1); j++) {
            double dx = x[j] - px, dy = y[j] - py, d2 = dx * dx + dy * dy;
            best = d2 > above2 && d2 < best ? d2 : best;
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
#pragma omp parallel for schedule(static) num_threads(e->threads) reduction(min : best)
    for (long i = 0; i < n; i++) {
        uint32_t c = psim_grid_cell(g, s->x[i], s->y[i]);
        uint32_t a0 = g->cellstart[c], a1 = g->cellstart[c + 1];
        if (a0 != (uint32_t)i)
            continue;
        best = cell_pairs(s, a0, a1, NONE, 0, above2, best);
        int cx = g->cell_x[c], cy = g->cell_y[c];
        for (int k = 0; k < 4; k++) {   /* the forward half: each pair of cells once */
            int nx, ny;
            uint32_t r = psim_grid_forward(g, cx, cy, k, &nx, &ny);
            if (r == UINT32_MAX)
                continue;
            best = cell_pairs(s, a0, a1, g->cellstart[r], g->cellstart[r + 1], above2, best);
        }
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
