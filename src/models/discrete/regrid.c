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
 *     box's side of it.  At most 4k far disks are clamped, and a scene
 *     without far disks keeps exactly the plan of its bounding box;
 *   - when: the contact search counts its distance tests (the pairs of
 *     disks it looks at).  A search that makes more than twice the fewest
 *     of the searches on this plan, plus one a disk, asks for a decision at
 *     the next step; border cells (where clamped disks gather) that would
 *     cost that much ask for one before their search;
 *   - what: plan again when the region has grown out of the grid's square
 *     (then with an eighth of its side to spare on each side, cells as small
 *     as without it, so that a growing cluster does not ask again at once),
 *     or shrunk to less than half of it; else keep the grid.  Either way the
 *     count starts afresh, so work that grows with no better plan to be had
 *     (a pile) is looked at once per doubling, not every step.
 * All of it is a function of the positions (counts, and minima and maxima,
 * which do not depend on the order they are taken in), never of the thread
 * count or of time, so the results stay the same for any thread count. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "discrete.h"

#define RG_BINS 1024                /* bins of a histogram of one axis */
#define RG_SLOTS (RG_BINS + 2)      /* below, the bins, above */
#define RG_PASSES 6                 /* each pass can narrow an axis 500-fold */
#define RG_SPARE 0.125              /* room left around a growing region */

/* How many centres on each side of each axis may be left out. */
static uint64_t outliers(long n)
{
    uint64_t k = (uint64_t)n / 1024 + 1;
    return 2 * k < (uint64_t)n ? k : 0;
}

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

/* The bounding box: the drift's when it measured one (flight.c), else a
 * pass of its own.  0 when no centre is finite. */
static int bounding_box(const psim_sim *e, const dmodel *m, double *b)
{
    const dextent *x = &m->fl.ext;
    if (m->fl.measured && fabs(x->pmin[0]) <= DBL_MAX && fabs(x->pmin[1]) <= DBL_MAX &&
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
        for (int a = 0; a < 2; a++)
            live[a] = t[2 + a] > t[a] && t[2 + a] - t[a] <= DBL_MAX;
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
    uint64_t k = outliers(e->n);
    if (k == 0)
        return 1;
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

/* The number of centres in cell (cx, cy); 0 outside the grid. */
static uint64_t cell_count(const psim_grid *g, int cx, int cy)
{
    if (cx < 0 || cy < 0 || cx >= g->G || cy >= g->G)
        return 0;
    uint32_t c = g->rank_of_xy[(uint32_t)cy * (uint32_t)g->G + (uint32_t)cx];
    return g->cellstart[c + 1] - g->cellstart[c];
}

/* The distance tests the search makes from cell (cx, cy) (contacts.c:
 * the cell's own pairs and the forward half of its neighbours). */
static uint64_t cell_tests(const psim_grid *g, int cx, int cy)
{
    uint64_t na = cell_count(g, cx, cy);
    if (na == 0)
        return 0;
    return na * (na - 1) / 2 +
           na * (cell_count(g, cx + 1, cy) + cell_count(g, cx - 1, cy + 1) +
                 cell_count(g, cx, cy + 1) + cell_count(g, cx + 1, cy + 1));
}

/* The tests of the border cells, which hold every disk outside the grid:
 * O(G), after the sort. */
static uint64_t border_tests(const psim_grid *g)
{
    const int G = g->G;
    uint64_t t = 0;
    for (int k = 0; k < G; k++) {
        t += cell_tests(g, k, 0);
        if (G > 1)
            t += cell_tests(g, k, G - 1);
        if (k > 0 && k < G - 1)
            t += cell_tests(g, 0, k) + cell_tests(g, G - 1, k);
    }
    return t;
}

/* The most tests a search may make before the plan is looked at again. */
static uint64_t work_limit(const dregrid *rg, long n) { return 2 * rg->base + (uint64_t)n; }

int discrete_plan_grid(psim_sim *e, dmodel *m)
{
    double region[4];
    int found = e->n > 0 && (m->rg.enabled ? disks_region(e, m, region)
                                           : extent_within(e, NULL, region) > 0);
    return psim_engine_grid(e, 2.0 * e->r, found ? region : NULL);
}

int discrete_regrid(psim_sim *e, dmodel *m)
{
    dregrid *rg = &m->rg;
    if (!rg->enabled || !e->has_grid)
        return 0;
    if (!rg->pending && !(rg->have_base && border_tests(&e->grid) > work_limit(rg, e->n)))
        return 0;
    rg->pending = 0;
    rg->have_base = 0;  /* the count starts afresh, whatever is decided */
    double region[4];
    if (!disks_region(e, m, region))
        return 0;
    const psim_grid *g = &e->grid;
    int grew = region[0] < g->x0 || region[1] < g->y0 || region[2] > g->x0 + g->side ||
               region[3] > g->y0 + g->side;
    int shrank = fmax(side(region), 2.0 * e->r) < 0.5 * g->side;
    if (!grew && !shrank)
        return 0;
    if (plan(e, region, grew))
        return -1;
    e->stats.counter[DC_REGRIDS]++;
    return 1;
}

void discrete_regrid_searched(const psim_sim *e, dmodel *m)
{
    dregrid *rg = &m->rg;
    if (!rg->enabled)
        return;
    if (rg->have_base && m->step_tests > work_limit(rg, e->n)) {
        rg->pending = 1;
        return;
    }
    if (!rg->have_base || m->step_tests < rg->base)
        rg->base = m->step_tests;
    rg->have_base = 1;
}
