/* The grid follows the disks.
 *
 * The grid's cells cover a square region (src/engine/grid.h) and a disk
 * outside it is clamped into a border cell.  That is right for a disk or
 * two and ruinous for many: one disk at x = 1e12 stretched the region of a
 * 100k-disk scene over 1e12, which put every other disk in one cell (5 steps
 * took 43 s instead of 0.06 s), and a cluster that expands past the region
 * it started in piles into the border cells (20k disks: 1.5 ms a step
 * became 37 ms).  So:
 *   - where: the disks' bounding box, unless leaving out the k = n/1024 + 1
 *     outermost centres on each side of each axis shrinks it more than
 *     twice; then the bounding box of the centres within half that trimmed
 *     box's side of it.  At most 4k far disks are left out (clamped), and a
 *     scene without far disks gets exactly the plan of its bounding box;
 *   - when: more than 4k disks lie further than a cell outside the grid's
 *     square (they have left it: a border cell then spans more than two
 *     cells' width of them), or the positions' extent has shrunk below
 *     1/sqrt(2) of the square (its cells could hold half the disks).  The
 *     drift measures the extent as it moves the disks (flight.c), and only
 *     when the extent reaches past the square are the disks of the border
 *     cells counted: a normal step pays a few compares;
 *   - how: a region that has grown is planned with an eighth of its side
 *     to spare on each side, cells as small as without it, so that a
 *     growing cluster does not ask again at once.  Right after a plan at
 *     most 4k disks are outside its square and the extent is more than
 *     1/sqrt(2) of it, so every decision changes the plan and none
 *     repeats.
 * The triggers and the plan are functions of the positions and of the
 * current plan only (counts, and minima and maxima, which do not depend on
 * the order they are taken in): never of the thread count, of time or of
 * the run's history, so the results stay the same for any thread count,
 * and a run restarted with its grid goes on as the unbroken run. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "discrete.h"

#define RG_BINS 1024                /* bins of a histogram of one axis */
#define RG_SLOTS (RG_BINS + 2)      /* below, the bins, above */
#define RG_PASSES 6                 /* each pass can narrow an axis 500-fold */
#define RG_SPARE 0.125              /* room left around a growing region */
#define RG_SHRINK 0.7071            /* extent / square below which cells hold twice the disks */
/* Fewer disks keep the plan of their bounding box: their search makes at
 * most 2016 distance tests a step whatever the grid (one cell holding them
 * all), fewer than a re-plan costs. */
#define RG_MIN_DISKS 64

/* How many centres on each side of each axis may be left out. */
static uint64_t outliers(long n) { return (uint64_t)n / 1024 + 1; }

static double side(const double *b) { return fmax(b[2] - b[0], b[3] - b[1]); }

/* {xmin, ymin, xmax, ymax} of the centres inside win (NULL: of every finite
 * centre); returns how many there are. */
static long extent_within(const psim_sim *e, const double *win, double *b)
{
    const double *x = e->st.x, *y = e->st.y;
    const long n = e->n;
    double w[4] = {-DBL_MAX, -DBL_MAX, DBL_MAX, DBL_MAX};
    if (win)
        memcpy(w, win, sizeof w);
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    long count = 0;
#pragma omp parallel for num_threads(e->threads) if (n > 65536) schedule(static) \
    reduction(min : x0, y0) reduction(max : x1, y1) reduction(+ : count)
    for (long i = 0; i < n; i++) {
        double a = x[i], c = y[i];
        if (!(a >= w[0] && a <= w[2] && c >= w[1] && c <= w[3]))
            continue;       /* NaN too */
        x0 = a < x0 ? a : x0, x1 = a > x1 ? a : x1;
        y0 = c < y0 ? c : y0, y1 = c > y1 ? c : y1;
        count++;
    }
    b[0] = x0, b[1] = y0, b[2] = x1, b[3] = y1;
    return count;
}

/* The bounding box of the finite centres: the drift's when it measured
 * them (flight.c), else a pass of its own.  0 when no centre is finite. */
static int bounding_box(const psim_sim *e, const dmodel *m, double *b)
{
    const dextent *x = &m->fl.ext;
    if (m->fl.drifted && fabs(x->pmin[0]) <= DBL_MAX && fabs(x->pmin[1]) <= DBL_MAX &&
        fabs(x->pmax[0]) <= DBL_MAX && fabs(x->pmax[1]) <= DBL_MAX) {
        b[0] = x->pmin[0], b[1] = x->pmin[1], b[2] = x->pmax[0], b[3] = x->pmax[1];
        return 1;
    }
    return extent_within(e, NULL, b) > 0;
}

/* Per axis a whose span is live: h[a * RG_SLOTS] counts the centres below
 * the box b, the last slot those above, slot 1 + j those in bin j. */
static void histogram(const psim_sim *e, const double *b, const int *live, uint32_t *h)
{
    const double *x = e->st.x, *y = e->st.y;
    const long n = e->n;
    double scale[2];
    for (int a = 0; a < 2; a++)
        scale[a] = live[a] ? RG_BINS / (b[2 + a] - b[a]) : 0;
    memset(h, 0, 2 * RG_SLOTS * sizeof *h);
#pragma omp parallel for num_threads(e->threads) if (n > 65536) schedule(static) \
    reduction(+ : h[:2 * RG_SLOTS])
    for (long i = 0; i < n; i++)
        for (int a = 0; a < 2; a++) {
            double v = a ? y[i] : x[i];
            int s;
            if (!live[a])
                continue;
            if (v >= b[a] && v <= b[2 + a]) {
                s = 1 + (int)((v - b[a]) * scale[a]);
                s = s > RG_BINS ? RG_BINS : s;
            } else if (v < b[a]) {
                s = 0;
            } else if (v > b[2 + a]) {
                s = RG_SLOTS - 1;
            } else {
                continue;   /* NaN */
            }
            h[a * RG_SLOTS + s]++;
        }
}

/* Narrow [*lo, *hi] to the bins holding its (k+1)-th smallest and
 * (k+1)-th largest centre. */
static void narrow(const uint32_t *h, uint64_t k, double *lo, double *hi)
{
    double w = (*hi - *lo) / RG_BINS;
    uint64_t below = h[0], above = h[RG_SLOTS - 1];
    int j0 = 0, j1 = RG_BINS - 1;
    while (j0 < RG_BINS - 1 && below + h[1 + j0] <= k)
        below += h[1 + j0++];
    while (j1 > j0 && above + h[1 + j1] <= k)
        above += h[1 + j1--];
    double nlo = *lo + j0 * w, nhi = j1 == RG_BINS - 1 ? *hi : *lo + (j1 + 1) * w;
    *lo = nlo;
    *hi = nhi;
}

/* Shrink the box t around all but the k outermost centres on each side of
 * each axis: histograms, each zooming into the bins that hold the cut,
 * while one of them narrows an axis more than twice. */
static void trim(const psim_sim *e, uint64_t k, double *t)
{
    uint32_t h[2 * RG_SLOTS];
    for (int pass = 0; pass < RG_PASSES; pass++) {
        int live[2], shrunk = 0;
        for (int a = 0; a < 2; a++) {   /* spans whose bins have a finite width */
            double span = t[2 + a] - t[a];
            live[a] = span > 0 && span <= DBL_MAX && RG_BINS / span <= DBL_MAX;
        }
        if (!live[0] && !live[1])
            return;
        histogram(e, t, live, h);
        for (int a = 0; a < 2; a++) {
            if (!live[a])
                continue;
            double before = t[2 + a] - t[a];
            narrow(h + a * RG_SLOTS, k, &t[a], &t[2 + a]);
            shrunk |= t[2 + a] - t[a] < 0.5 * before;
        }
        if (!shrunk)
            return;
    }
}

/* The region the grid should span (see the top).  0 when no centre is
 * finite. */
static int disks_region(const psim_sim *e, const dmodel *m, double *region)
{
    double b[4], t[4];
    if (!bounding_box(e, m, b))
        return 0;
    memcpy(region, b, sizeof b);
    if (e->n < RG_MIN_DISKS)
        return 1;
    uint64_t k = outliers(e->n);
    memcpy(t, b, sizeof t);
    trim(e, k, t);
    double s = side(t);
    if (!(s < 0.5 * side(b)))
        return 1;
    double win[4] = {t[0] - 0.5 * s, t[1] - 0.5 * s, t[2] + 0.5 * s, t[3] + 0.5 * s};
    extent_within(e, win, region);  /* holds all but at most 4k centres */
    return 1;
}

/* Plan the grid over region; with room to spare, grown by RG_SPARE of its
 * side on each side, with as many more cells as keeps them the size a plan
 * of the region alone gives (the cap on cells is per disk, so it is given
 * as the occupancy of the grown square). */
static int plan(psim_sim *e, const double *region, int spare)
{
    double s = side(region), d = RG_SPARE * s;
    if (!spare || !(s > 0 && s <= DBL_MAX))
        return psim_engine_grid(e, 2.0 * e->r, region);
    double grown[4] = {region[0] - d, region[1] - d, region[2] + d, region[3] + d};
    double f = s / (s + 2 * d);
    return psim_engine_grid_occ(e, 2.0 * e->r, grown, PSIM_CELL_PARTICLES * f * f);
}

/* Whether box b (min and max per axis) lies within the grid's square
 * grown by d on each side. */
static int within_square(const psim_grid *g, const double *b, double d)
{
    return b[0] >= g->x0 - d && b[1] >= g->y0 - d && b[2] <= g->x0 + g->side + d &&
           b[3] <= g->y0 + g->side + d;
}

/* How many disks of cell (cx, cy) lie outside box b. */
static uint64_t cell_outside(const psim_sim *e, int cx, int cy, const double *b)
{
    const psim_grid *g = &e->grid;
    const double *x = e->st.x, *y = e->st.y;
    uint32_t c = g->rank_of_xy[(uint32_t)cy * (uint32_t)g->G + (uint32_t)cx];
    uint64_t out = 0;
    for (uint32_t i = g->cellstart[c]; i < g->cellstart[c + 1]; i++)
        out += x[i] < b[0] || y[i] < b[1] || x[i] > b[2] || y[i] > b[3];
    return out;
}

/* The disks further than a cell outside the grid's square: all of them
 * are in its border cells, so only those are looked at. */
static uint64_t disks_outside(const psim_sim *e)
{
    const psim_grid *g = &e->grid;
    const int G = g->G;
    const double b[4] = {g->x0 - g->h, g->y0 - g->h, g->x0 + g->side + g->h,
                         g->y0 + g->side + g->h};
    uint64_t out = 0;
    for (int c = 0; c < G; c++) {
        out += cell_outside(e, c, 0, b);
        if (G > 1)
            out += cell_outside(e, c, G - 1, b);
    }
    for (int c = 1; c < G - 1; c++)
        out += cell_outside(e, 0, c, b) + cell_outside(e, G - 1, c, b);
    return out;
}

int discrete_plan_grid(psim_sim *e, dmodel *m)
{
    double region[4];
    int found = e->n > 0 && (m->regrid ? disks_region(e, m, region)
                                       : extent_within(e, NULL, region) > 0);
    return psim_engine_grid(e, 2.0 * e->r, found ? region : NULL);
}

int discrete_regrid(psim_sim *e, dmodel *m)
{
    if (!m->regrid || !e->has_grid || e->n < RG_MIN_DISKS || !m->fl.drifted)
        return 0;
    const psim_grid *g = &e->grid;
    const double ext[4] = {m->fl.ext.pmin[0], m->fl.ext.pmin[1], m->fl.ext.pmax[0],
                           m->fl.ext.pmax[1]};
    int left = !within_square(g, ext, g->h) && disks_outside(e) > 4 * outliers(e->n);
    int gathered = fmax(side(ext), 2.0 * e->r) < RG_SHRINK * g->side;
    if (!left && !gathered)
        return 0;
    double region[4];
    if (!disks_region(e, m, region))
        return 0;
    int grew = !within_square(g, region, 0);
    int shrank = fmax(side(region), 2.0 * e->r) < RG_SHRINK * g->side;
    if (!grew && !shrank)
        return 0;
    if (plan(e, region, grew))
        return -1;
    e->stats.counter[DC_REGRIDS] += m->rank == 0;   /* (summed over ranks) */
    return 1;
}
