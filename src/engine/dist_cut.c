#include "dist_cut.h"

#include <math.h>
#include <stdlib.h>

void dist_cuts_shape(int R, int *px, int *py)
{
    int best = 1;
    for (int d = 1; (long)d * d <= R; d++)
        if (R % d == 0)
            best = d;
    *py = best;
    *px = R / best;
}

int dist_cuts_alloc(dist_cuts *c, int R, double L)
{
    dist_cuts_shape(R, &c->px, &c->py);
    c->L = L;
    c->cx = malloc((size_t)(c->px + 1) * sizeof *c->cx);
    c->cy = malloc((size_t)c->px * (size_t)(c->py + 1) * sizeof *c->cy);
    if (!c->cx || !c->cy)
        return -1;
    /* equal strips until the first cut from the particles */
    for (int i = 0; i <= c->px; i++)
        c->cx[i] = L * i / c->px;
    for (int i = 0; i < c->px; i++)
        for (int j = 0; j <= c->py; j++)
            c->cy[i * (c->py + 1) + j] = L * j / c->py;
    for (int i = 0; i < c->px; i++) {
        c->cy[i * (c->py + 1)] = -INFINITY;
        c->cy[i * (c->py + 1) + c->py] = INFINITY;
    }
    c->cx[0] = -INFINITY;
    c->cx[c->px] = INFINITY;
    return 0;
}

void dist_cuts_free(dist_cuts *c)
{
    free(c->cx);
    free(c->cy);
    c->cx = c->cy = NULL;
}

void dist_cuts_from_hist(const uint64_t *hist, double L, int parts, double *cuts)
{
    uint64_t total = 0;
    for (int b = 0; b < DIST_BINS; b++)
        total += hist[b];
    cuts[0] = -INFINITY;
    cuts[parts] = INFINITY;
    uint64_t run = 0;
    int b = 0;
    for (int k = 1; k < parts; k++) {
        /* the first edge at or past k / parts of the particles */
        long double want = (long double)total * k / parts;
        while (b < DIST_BINS && (long double)(run + hist[b]) <= want)
            run += hist[b++];
        cuts[k] = L * b / DIST_BINS;
    }
}

/* The last k in [0, parts) with cuts[k] <= v (cuts[0] is -inf). */
static int slot_of(const double *cuts, int parts, double v)
{
    int lo = 0, hi = parts - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (cuts[mid] <= v)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

int dist_cuts_column(const dist_cuts *c, double x)
{
    return x == x ? slot_of(c->cx, c->px, x) : 0;
}

int dist_cuts_owner(const dist_cuts *c, double x, double y)
{
    int i = dist_cuts_column(c, x);
    int j = y == y ? slot_of(c->cy + (size_t)i * (c->py + 1), c->py, y) : 0;
    return i * c->py + j;
}

/* How far v lies outside [lo, hi] (0 inside). */
static double outside(double v, double lo, double hi)
{
    return v < lo ? lo - v : (v > hi ? v - hi : 0);
}

int dist_cuts_near(const dist_cuts *c, int q, double x, double y, double h)
{
    int i = q / c->py, j = q % c->py;
    const double *cy = c->cy + (size_t)i * (c->py + 1);
    double dx = outside(x, c->cx[i], c->cx[i + 1]), dy = outside(y, cy[j], cy[j + 1]);
    return dx <= h && dy <= h && dx * dx + dy * dy <= h * h;
}
