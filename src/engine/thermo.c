/* Thermodynamic quantities of the current state (--thermo): kinetic
 * energy, momentum and overlapping pairs, over the store in id order
 * (psim_state_cols_take), so that they do not depend on the store's order,
 * the thread count or how a run was chained (a restart sorts afresh). */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "engine.h"

/* Cells of at least `reach` a side, clamped into [0, G): clamping keeps
 * pairs closer than reach in the same or adjacent cells. */
static int cell_of(double v, double h, int G)
{
    double c = floor(v / h);
    return !(c > 0) ? 0 : c >= G ? G - 1 : (int)c;
}

/* Pairs (i < j) with squared distance below d2 in cell list a against
 * cell list b (a == b: within the cell); ord holds store places. */
static long count_pairs(const double *x, const double *y, const uint32_t *ord,
                        uint32_t a0, uint32_t a1, uint32_t b0, uint32_t b1, int same, double d2)
{
    long n = 0;
    for (uint32_t p = a0; p < a1; p++)
        for (uint32_t q = same ? p + 1 : b0; q < b1; q++) {
            double dx = x[ord[q]] - x[ord[p]], dy = y[ord[q]] - y[ord[p]];
            n += dx * dx + dy * dy < d2;
        }
    return n;
}

/* The same where (2r)^2 overflows: distances in units of 2r. */
static long count_pairs_scaled(const double *x, const double *y, const uint32_t *ord,
                               uint32_t a0, uint32_t a1, uint32_t b0, uint32_t b1, int same,
                               double reach)
{
    long n = 0;
    for (uint32_t p = a0; p < a1; p++)
        for (uint32_t q = same ? p + 1 : b0; q < b1; q++) {
            double dx = (x[ord[q]] - x[ord[p]]) / reach, dy = (y[ord[q]] - y[ord[p]]) / reach;
            n += dx * dx + dy * dy < 1;
        }
    return n;
}

/* Pairs of cell lists a and b closer than reach. */
static long count_cells(const double *x, const double *y, const uint32_t *ord,
                        const uint32_t *start, size_t a, size_t b, double reach)
{
    const double d2 = reach * reach;
    if (!isfinite(d2))
        return count_pairs_scaled(x, y, ord, start[a], start[a + 1], start[b], start[b + 1],
                                  a == b, reach);
    return count_pairs(x, y, ord, start[a], start[a + 1], start[b], start[b + 1], a == b, d2);
}

/* Pairs closer than 2r, through a cell list of its own (O(n) for any
 * scene the models run); -1 without memory. */
static long count_overlaps(const psim_cols *c, long n, double L, double r)
{
    const double *x = c->x, *y = c->y;
    double reach = 2 * r;
    if (n < 2 || !(reach > 0))
        return 0;
    /* at most about 4n cells: a small r in a large box does not cost
     * memory, only pairs per cell */
    double g = fmin(floor(L / reach), ceil(2 * sqrt((double)n)));
    int G = g >= 1 ? (int)g : 1;
    double h = L / G;
    size_t cells = (size_t)G * (size_t)G;
    uint32_t *start = calloc(cells + 1, sizeof *start), *ord = malloc((size_t)n * sizeof *ord),
             *cell = malloc((size_t)n * sizeof *cell);
    long found = -1;
    if (!start || !ord || !cell)
        goto out;
    for (long i = 0; i < n; i++) {   /* by id */
        long k = c->at[i];
        cell[i] = (uint32_t)cell_of(y[k], h, G) * (uint32_t)G + (uint32_t)cell_of(x[k], h, G);
        start[cell[i] + 1]++;
    }
    for (size_t q = 0; q < cells; q++)
        start[q + 1] += start[q];
    for (long i = 0; i < n; i++)   /* stable: ids ascending within a cell */
        ord[start[cell[i]]++] = (uint32_t)c->at[i];
    for (size_t q = cells; q > 0; q--)
        start[q] = start[q - 1];
    start[0] = 0;
    static const int fwd[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};
    found = 0;
    for (int cy = 0; cy < G; cy++)
        for (int cx = 0; cx < G; cx++) {
            size_t a = (size_t)cy * (size_t)G + (size_t)cx;
            if (start[a] == start[a + 1])
                continue;
            found += count_cells(x, y, ord, start, a, a, reach);
            for (int k = 0; k < 4; k++) {
                int nx = cx + fwd[k][0], ny = cy + fwd[k][1];
                if (nx < 0 || nx >= G || ny >= G)
                    continue;
                found += count_cells(x, y, ord, start, a, (size_t)ny * (size_t)G + (size_t)nx,
                                     reach);
            }
        }
out:
    free(start), free(ord), free(cell);
    return found;
}

/* The kinetic energy again where its plain sum overflowed (velocities
 * near 1e154 and above): in units of a power of two at or above the
 * largest component, as --check sums energies, then scaled back; still
 * not finite only when the energy itself is beyond the largest double
 * (t->too_large names it).  The plain sum is kept wherever it is finite:
 * the same bytes as ever for ordinary scenes.  (Momentum cannot overflow
 * then: every |v| is below 2e154.) */
static void rescale_ke(const psim_cols *c, long n, psim_thermo *t)
{
    double m = 0;
    for (long i = 0; i < n; i++) {
        double u = fabs(c->vx[c->at[i]]), w = fabs(c->vy[c->at[i]]);
        if (!(u <= DBL_MAX && w <= DBL_MAX))
            return;   /* the state itself is not finite: not the sum's fault */
        m = fmax(m, fmax(u, w));
    }
    int ex;
    frexp(m, &ex);
    const double k = ldexp(1.0, -ex);   /* exact, as a power of two */
    double ke = 0;
    for (long i = 0; i < n; i++) {   /* in id order */
        double vx = c->vx[c->at[i]] * k, vy = c->vy[c->at[i]] * k;
        ke += 0.5 * (vx * vx + vy * vy);
    }
    t->ke = ldexp(ke, 2 * ex);
    if (!isfinite(t->ke))
        t->too_large = "kinetic energy (half the sum of vx^2 + vy^2)";
}

int psim_thermo_measure(const psim_sim *e, psim_thermo *t)
{
    psim_cols c;
    if (psim_state_cols_take(e, &c))
        return -1;
    const long n = e->n;
    t->step = e->step;
    t->area = e->L * e->L;
    t->side = e->L;
    t->ke = t->px = t->py = 0;
    t->too_large = NULL;
    for (long i = 0; i < n; i++) {   /* in id order */
        double vx = c.vx[c.at[i]], vy = c.vy[c.at[i]];
        t->ke += 0.5 * (vx * vx + vy * vy);
        t->px += vx;
        t->py += vy;
    }
    if (!isfinite(t->ke))
        rescale_ke(&c, n, t);
    t->overlaps = t->too_large ? 0 : count_overlaps(&c, n, e->L, e->r);
    psim_state_cols_free(&c);
    return t->overlaps < 0 ? -1 : t->too_large ? -2 : 0;
}

const char *psim_thermo_column(const psim_sim *e, int k)
{
    if (k < 0 || k >= PSIM_THERMO_MAX)
        return NULL;
    return e->model->thermo[k];
}
