/* Free flight: the stages of a step that a scene cannot use are left out.
 *
 * The drift measures, in the same pass, the extent of the new positions
 * (every step, in SSE2 registers: the grid follows it, regrid.c) and, only
 * when a skip may follow (a gap left by the last search, a search that
 * found no contact, or a step that changed no velocity), of the velocities
 * it used, so a dense scene pays nothing for the skips.  From them:
 *   - search: a search that finds no contact also gives the nearest pair it
 *     saw, D (pairs in cells that are not neighbours are at least a cell
 *     side h apart, so min(D, h) bounds every pair).  Every velocity is
 *     within hw, the half-diagonal of the velocities' extent, of its centre,
 *     so a pair closes by at most 2 hw in a step; while the gap D - 2r is
 *     larger than what the steps since have closed (with a margin for
 *     rounding), no pair can be in contact, and the sort, the search and
 *     the resolution are left out.  Only walls are resolved then; they
 *     change velocities, so hw is measured anew each step.  Disks that move
 *     as one (hw = 0) never close in;
 *   - walls: in such a step no disk can touch a wall when every centre is
 *     more than r inside the box (x - r > 0 for the smallest x is x - r > 0
 *     for all: subtracting r is monotone in floating point);
 *   - move: a scene whose velocities are all 0 stays so (no pair
 *     approaches, no disk moves towards a wall), so after the first step,
 *     whose drift turns -0 into +0, every stage is left out.
 * A velocity that is NaN or infinite turns every skip off.  None of these
 * changes a result: a skipped stage would have done nothing
 * (tests/e2e/skips.sh compares with --option skip=0). */
#include <float.h>
#include <math.h>

#include <omp.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "collide.h"
#include "discrete.h"
#include "../../engine/nearest.h"
#include "../../engine/tstats.h"

static void extent_init(dextent *x)
{
    for (int a = 0; a < 2; a++) {
        x->pmin[a] = x->vmin[a] = INFINITY;
        x->pmax[a] = x->vmax[a] = -INFINITY;
    }
    x->nonfinite = 0;
}

static void extent_merge(dextent *to, const dextent *from)
{
    for (int a = 0; a < 2; a++) {
        to->pmin[a] = fmin(to->pmin[a], from->pmin[a]);
        to->pmax[a] = fmax(to->pmax[a], from->pmax[a]);
        to->vmin[a] = fmin(to->vmin[a], from->vmin[a]);
        to->vmax[a] = fmax(to->vmax[a], from->vmax[a]);
    }
    to->nonfinite |= from->nonfinite;
}

/* Move disks [lo, hi) and measure where they went.  Two disks at a time
 * in SSE2 with the extremes in registers (an omp simd reduction kept them
 * in memory, and the move took a third longer than without them); minpd
 * and maxpd give their second operand when the first is NaN, so NaN is
 * left out as by the comparisons of the rest. */
static void drift_range(psim_store *s, long lo, long hi, dextent *x)
{
    double *restrict px = s->x, *restrict py = s->y;
    const double *restrict vx = s->vx, *restrict vy = s->vy;
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    long i = lo;
#ifdef __SSE2__
    __m128d mx0 = _mm_set1_pd(x0), mx1 = _mm_set1_pd(x1), my0 = _mm_set1_pd(y0),
            my1 = _mm_set1_pd(y1);
    for (; i + 2 <= hi; i += 2) {
        __m128d a = _mm_add_pd(_mm_loadu_pd(px + i), _mm_loadu_pd(vx + i));
        __m128d b = _mm_add_pd(_mm_loadu_pd(py + i), _mm_loadu_pd(vy + i));
        _mm_storeu_pd(px + i, a), _mm_storeu_pd(py + i, b);
        mx0 = _mm_min_pd(a, mx0), mx1 = _mm_max_pd(a, mx1);
        my0 = _mm_min_pd(b, my0), my1 = _mm_max_pd(b, my1);
    }
    double l[2], h[2], m[2], n[2];
    _mm_storeu_pd(l, mx0), _mm_storeu_pd(h, mx1), _mm_storeu_pd(m, my0), _mm_storeu_pd(n, my1);
    x0 = l[0] < l[1] ? l[0] : l[1], x1 = h[0] > h[1] ? h[0] : h[1];
    y0 = m[0] < m[1] ? m[0] : m[1], y1 = n[0] > n[1] ? n[0] : n[1];
#endif
    for (; i < hi; i++) {
        double a = px[i] + vx[i], b = py[i] + vy[i];
        px[i] = a;
        py[i] = b;
        x0 = a < x0 ? a : x0, x1 = a > x1 ? a : x1;
        y0 = b < y0 ? b : y0, y1 = b > y1 ? b : y1;
    }
    x->pmin[0] = x0, x->pmin[1] = y0, x->pmax[0] = x1, x->pmax[1] = y1;
}

/* The extent of the velocities of disks [lo, hi). */
static void velocity_range(const psim_store *s, long lo, long hi, dextent *x)
{
    const double *restrict vx = s->vx, *restrict vy = s->vy;
    double u0 = INFINITY, u1 = -INFINITY, w0 = INFINITY, w1 = -INFINITY;
    int bad = 0;
#pragma omp simd reduction(min : u0, w0) reduction(max : u1, w1) reduction(| : bad)
    for (long i = lo; i < hi; i++) {
        u0 = vx[i] < u0 ? vx[i] : u0, u1 = vx[i] > u1 ? vx[i] : u1;
        w0 = vy[i] < w0 ? vy[i] : w0, w1 = vy[i] > w1 ? vy[i] : w1;
        bad |= !(fabs(vx[i]) <= DBL_MAX) | !(fabs(vy[i]) <= DBL_MAX);
    }
    x->vmin[0] = u0, x->vmin[1] = w0, x->vmax[0] = u1, x->vmax[1] = w1;
    x->nonfinite = bad;
}

__attribute__((noinline)) void discrete_drift(psim_sim *e, dmodel *m)
{
    dflight *f = &m->fl;
    if (f->resting)
        return;
    /* the velocities' extent matters when a skip may follow: a gap to
     * spend, a search that found no contact (it leaves a gap), or a step
     * that changed no velocity (a scene at rest); the positions' extent,
     * measured in the move itself, every step (the grid follows it:
     * regrid.c) */
    const int velocities = f->enabled && (f->gap >= 0 || f->quiet || m->step_contacts == 0);
    dextent all;
    extent_init(&all);
    psim_store *s = &e->st;
    const long n = e->n;
#pragma omp parallel num_threads(e->threads)
    {
        double t0 = psim_now();
        int T = omp_get_num_threads(), k = omp_get_thread_num();
        long lo = (long)psim_part_lo((size_t)n, T, k), hi = (long)psim_part_lo((size_t)n, T, k + 1);
        dextent mine;
        extent_init(&mine);
        if (velocities)
            velocity_range(s, lo, hi, &mine);
        drift_range(s, lo, hi, &mine);
#pragma omp critical(discrete_extent)
        extent_merge(&all, &mine);
        psim_tstat_add(e->tstats, PSIM_PHASE_MOVE, psim_now() - t0, 1, (uint64_t)(hi - lo));
    }
    f->ext = all;
    f->ext.nonfinite |= !velocities;
    f->measured = velocities;
    f->drifted = 1;
}

/* The rounding of a position as large as the scene's largest. */
static double rounding(const dextent *f)
{
    double scale = fmax(fmax(fabs(f->pmin[0]), fabs(f->pmax[0])),
                        fmax(fabs(f->pmin[1]), fabs(f->pmax[1])));
    return 16 * DBL_EPSILON * scale;
}

/* How much closer any pair can have come in this step's drift. */
static double closing(const dextent *f)
{
    double hx = 0.5 * (f->vmax[0] - f->vmin[0]), hy = 0.5 * (f->vmax[1] - f->vmin[1]);
    return 2.0 * sqrt(hx * hx + hy * hy) * (1 + 1e-12) + rounding(f);
}

static int all_inside(const dextent *f, double L, double r)
{
    return f->pmin[0] - r > 0 && f->pmax[0] + r < L && f->pmin[1] - r > 0 &&
           f->pmax[1] + r < L;
}

int discrete_free_flight(psim_sim *e, dmodel *m)
{
    dflight *f = &m->fl;
    uint64_t *skipped = e->stats.skipped;
    if (f->resting) {
        skipped[DS_MOVE]++, skipped[DS_SEARCH]++, skipped[DS_WALLS]++;
        return 1;
    }
    f->walls = !f->measured || e->n == 0 || !all_inside(&f->ext, e->L, e->r);
    skipped[DS_WALLS] += !f->walls;
    if (!f->enabled || e->n == 0 || f->ext.nonfinite) {
        f->gap = -1;
        return 0;
    }
    /* resting from the next step: nothing can change a zero velocity */
    const dextent *x = &f->ext;
    f->resting = x->vmin[0] == 0 && x->vmax[0] == 0 && x->vmin[1] == 0 && x->vmax[1] == 0;
    double c = closing(x);
    if (f->gap >= 0 && f->gap > c) {
        f->gap -= c;
        skipped[DS_SEARCH]++;
        return 1;
    }
    f->gap = -1;
    return 0;
}

void discrete_flight_searched(const psim_sim *e, dmodel *m)
{
    dflight *f = &m->fl;
    if (!f->enabled || !f->measured || m->step_contacts)
        return;
    f->gap = psim_distance_bound(e, m->d2min) - 2 * e->r * (1 + 1e-12) - rounding(&f->ext);
}

void discrete_walls_only(psim_sim *e, dmodel *m)
{
    psim_store *s = &e->st;
    const long n = e->n;
    const double L = e->L, r = e->r;
    uint64_t res = 0;
#pragma omp parallel for num_threads(e->threads) reduction(+ : res) schedule(static)
    for (long i = 0; i < n; i++)
        if (psim_wall_collides(s->x[i], s->y[i], s->vx[i], s->vy[i], L, r)) {
            psim_wall_resolve(s->x[i], s->y[i], &s->vx[i], &s->vy[i], L, r);
            res++;
        }
    e->stats.counter[DC_WALL_RES] += m->rank == 0 ? res : 0;   /* (every rank's: summed) */
    discrete_step_resolved(e, m, res);
}

void discrete_step_resolved(psim_sim *e, dmodel *m, uint64_t total)
{
    if (total > e->stats.counter[DC_MAX_STEP_RES])
        e->stats.counter[DC_MAX_STEP_RES] = total;
    m->fl.quiet = total == 0;
}
