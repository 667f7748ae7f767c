/* The course's validator, re-implemented independently of the engine (its
 * own binning, its own loops), run after every step with --check:
 *  - new position = old position + old velocity;
 *  - groups = connected components of disks at distance^2 <= 4r^2 + 1e-7;
 *    per group, energy sum(vx^2 + vy^2) is conserved, and so is momentum
 *    where no disk of the group touches a wall (a wall bounce changes it);
 *  - no wall collision and no particle collision is left unhandled.
 * Tolerance: 1e-4, absolute or relative. */
#include <math.h>
#include <stdlib.h>

#include "collide.h"
#include "discrete.h"

#define TOL 1e-4
#define GROUP_EPS 1e-7

static int close_enough(double a, double b)
{
    double d = fabs(a - b);
    return d <= TOL || d <= TOL * fmax(fabs(a), fabs(b));
}

static long find(long *parent, long i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

static void unite(long *parent, long a, long b)
{
    a = find(parent, a);
    b = find(parent, b);
    if (a != b)
        parent[a < b ? b : a] = a < b ? a : b;
}

typedef struct bins {
    int G;
    double inv;
    long *start, *order;
} bins;

static int bin_of(const bins *b, double v)
{
    double c = v * b->inv;
    if (!(c >= 0))
        return 0;
    return c >= b->G - 1 ? b->G - 1 : (int)c;
}

static int bins_build(bins *b, const psim_snapshot *s, double L, double reach)
{
    double fit = floor(L / reach * (1.0 - 1e-9)), cap = ceil(2 * sqrt((double)s->n + 1));
    b->G = (int)fmax(1.0, fmin(fit, cap));
    b->inv = b->G / L;
    size_t cells = (size_t)b->G * (size_t)b->G;
    b->start = calloc(cells + 1, sizeof *b->start);
    b->order = malloc(((size_t)s->n + 1) * sizeof *b->order);
    if (!b->start || !b->order)
        return -1;
    for (long i = 0; i < s->n; i++)
        b->start[(size_t)bin_of(b, s->y[i]) * b->G + bin_of(b, s->x[i]) + 1]++;
    for (size_t c = 0; c < cells; c++)
        b->start[c + 1] += b->start[c];
    long *fill = malloc((cells + 1) * sizeof *fill);
    if (!fill)
        return -1;
    for (size_t c = 0; c <= cells; c++)
        fill[c] = b->start[c];
    for (long i = 0; i < s->n; i++)
        b->order[fill[(size_t)bin_of(b, s->y[i]) * b->G + bin_of(b, s->x[i])]++] = i;
    free(fill);
    return 0;
}

/* Visit every pair in the same or adjacent bins once; stop at a violation. */
static int scan_pairs(const bins *b, const psim_snapshot *s, double r,
                      long *parent, long step, psim_error *err)
{
    const double four_r2 = 4.0 * r * r;
    for (int cy = 0; cy < b->G; cy++)
        for (int cx = 0; cx < b->G; cx++) {
            size_t c = (size_t)cy * b->G + cx;
            for (int oy = 0; oy <= 1; oy++)
                for (int ox = -1; ox <= 1; ox++) {
                    if (oy == 0 && ox < 0)
                        continue;
                    int nx = cx + ox, ny = cy + oy;
                    if (nx < 0 || nx >= b->G || ny >= b->G)
                        continue;
                    size_t c2 = (size_t)ny * b->G + nx;
                    for (long p = b->start[c]; p < b->start[c + 1]; p++) {
                        long i = b->order[p];
                        long q0 = (c2 == c) ? p + 1 : b->start[c2];
                        for (long q = q0; q < b->start[c2 + 1]; q++) {
                            long j = b->order[q];
                            double dx = s->x[j] - s->x[i], dy = s->y[j] - s->y[i];
                            double d2 = dx * dx + dy * dy;
                            if (d2 > four_r2 + GROUP_EPS)
                                continue;
                            unite(parent, i, j);
                            double dot = psim_approach(dx, dy, s->vx[j] - s->vx[i],
                                                       s->vy[j] - s->vy[i]);
                            if (psim_overlaps(d2, four_r2) && psim_moving_closer(dot)) {
                                psim_error_set(err,
                                    "check failed at step %ld: particles %ld and %ld "
                                    "overlap (distance^2 %.17g <= %.17g) and move closer "
                                    "(dv.dp = %.17g): unhandled particle collision",
                                    step, i < j ? i : j, i < j ? j : i, d2, four_r2, dot);
                                return -1;
                            }
                        }
                    }
                }
        }
    return 0;
}

static int check_moves_and_walls(const psim_snapshot *b, const psim_snapshot *a,
                                 double L, double r, long step, psim_error *err)
{
    for (long i = 0; i < a->n; i++) {
        double ex = b->x[i] + b->vx[i], ey = b->y[i] + b->vy[i];
        if (!close_enough(a->x[i], ex) || !close_enough(a->y[i], ey)) {
            psim_error_set(err,
                "check failed at step %ld: particle %ld is at (%.17g, %.17g), "
                "expected old position + old velocity (%.17g, %.17g)",
                step, i, a->x[i], a->y[i], ex, ey);
            return -1;
        }
        if (psim_wall_collides(a->x[i], a->y[i], a->vx[i], a->vy[i], L, r)) {
            psim_error_set(err,
                "check failed at step %ld: particle %ld at (%.17g, %.17g) with "
                "velocity (%.17g, %.17g): unhandled wall collision",
                step, i, a->x[i], a->y[i], a->vx[i], a->vy[i]);
            return -1;
        }
    }
    return 0;
}

typedef struct gsum {
    double e0, e1, px0, px1, py0, py1;
    double vmax;   /* largest velocity component, before or after */
    double scale;  /* 0, or the power of two its energy was summed in */
    int wall;
} gsum;

static double max4(double a, double b, double c, double d)
{
    return fmax(fmax(fabs(a), fabs(b)), fmax(fabs(c), fabs(d)));
}

/* Energies of groups whose sum overflowed (velocities near 1e154 and
 * above), summed again in units of a power of two above their largest
 * component, so that a valid run is not failed by the sum itself. */
static void rescale_overflowed(const psim_snapshot *b, const psim_snapshot *a, long *parent,
                               gsum *g)
{
    int any = 0;
    for (long i = 0; i < a->n; i++) {
        gsum *s = &g[i];
        if (find(parent, i) != i || (isfinite(s->e0) && isfinite(s->e1)) ||
            !isfinite(s->vmax) || s->vmax == 0)
            continue;
        int ex;
        frexp(s->vmax, &ex);
        s->scale = ldexp(1.0, -ex);   /* exact, as a power of two */
        s->e0 = s->e1 = 0;
        any = 1;
    }
    for (long i = 0; any && i < a->n; i++) {
        gsum *s = &g[find(parent, i)];
        if (!s->scale)
            continue;
        double k = s->scale, u = b->vx[i] * k, v = b->vy[i] * k, w = a->vx[i] * k,
               z = a->vy[i] * k;
        s->e0 += u * u + v * v;
        s->e1 += w * w + z * z;
    }
}

static int check_groups(const psim_snapshot *b, const psim_snapshot *a,
                        long *parent, double L, double r, long step,
                        psim_error *err)
{
    gsum *g = calloc((size_t)a->n + 1, sizeof *g);
    if (!g) {
        psim_error_set(err, "out of memory in --check");
        return -1;
    }
    for (long i = 0; i < a->n; i++) {
        gsum *s = &g[find(parent, i)];
        s->e0 += b->vx[i] * b->vx[i] + b->vy[i] * b->vy[i];
        s->e1 += a->vx[i] * a->vx[i] + a->vy[i] * a->vy[i];
        s->px0 += b->vx[i];
        s->px1 += a->vx[i];
        s->py0 += b->vy[i];
        s->py1 += a->vy[i];
        s->vmax = fmax(s->vmax, max4(b->vx[i], b->vy[i], a->vx[i], a->vy[i]));
        s->wall |= (a->x[i] - r <= 0) || (a->x[i] + r >= L) ||
                   (a->y[i] - r <= 0) || (a->y[i] + r >= L);
    }
    rescale_overflowed(b, a, parent, g);
    int rc = 0;
    for (long i = 0; i < a->n && !rc; i++) {
        if (find(parent, i) != i)
            continue;
        const gsum *s = &g[i];
        if (s->scale ? !(fabs(s->e0 - s->e1) <= TOL * fmax(s->e0, s->e1))
                      : !close_enough(s->e0, s->e1)) {
            psim_error_set(err,
                "check failed at step %ld: group of particle %ld: energy %.17g "
                "before, %.17g after%s", step, i, s->e0, s->e1,
                s->scale ? " (in units of a power of two: the sum overflowed)" : "");
            rc = -1;
        } else if (!s->wall && (!close_enough(s->px0, s->px1) ||
                                !close_enough(s->py0, s->py1))) {
            psim_error_set(err,
                "check failed at step %ld: group of particle %ld: momentum "
                "(%.17g, %.17g) before, (%.17g, %.17g) after",
                step, i, s->px0, s->py0, s->px1, s->py1);
            rc = -1;
        }
    }
    free(g);
    return rc;
}

int discrete_check(psim_sim *e, void *m, const psim_snapshot *before,
                   const psim_snapshot *after, psim_error *err)
{
    (void)m;
    long step = e->step;
    if (check_moves_and_walls(before, after, e->L, e->r, step, err))
        return -1;
    bins b = {0};
    long *parent = malloc(((size_t)after->n + 1) * sizeof *parent);
    int rc = -1;
    if (!parent || bins_build(&b, after, e->L, sqrt(4 * e->r * e->r + GROUP_EPS))) {
        psim_error_set(err, "out of memory in --check");
        goto done;
    }
    for (long i = 0; i < after->n; i++)
        parent[i] = i;
    if (scan_pairs(&b, after, e->r, parent, step, err))
        goto done;
    rc = check_groups(before, after, parent, e->L, e->r, step, err);
done:
    free(parent);
    free(b.start);
    free(b.order);
    return rc;
}
