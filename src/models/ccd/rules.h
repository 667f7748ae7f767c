/* The CS3210 AY2019/20 collision rules, with the arithmetic exactly as the
 * course's authors wrote it: the same operations in the same order, double
 * precision, no fused multiply-add (-ffp-contract=off), so that results
 * match their program bit for bit.  An algebraically equal formula is not
 * the same bits: change nothing here without re-running
 * tests/e2e/ccd_reference.sh.  Shared by the model, its --check and its
 * GPU path (PSIM_HD: the kernels run these very functions). */
#ifndef PSIM_CCD_RULES_H
#define PSIM_CCD_RULES_H
#include <math.h>

#include "../../engine/hd.h"
#include "cand.h"

/* The authors' tolerance at the walls. */
#define CCD_EPS 1e-14

/* Wall candidate, from where the disk would be after a time dt (the whole
 * step: dt = 1): with m = r + 1e-14, if vx != 0 and x + vx dt < m,
 * t_x = (x - r) / -vx; else if x + vx dt > L - m, t_x = (L - r - x) / vx;
 * likewise y.  Returns 1 and the smaller of t_x, t_y when one exists. */
PSIM_HD static inline int ccd_wall_time(double x, double y, double vx, double vy, double dt,
                                double L, double r, double *t)
{
    const double m = r + CCD_EPS;
    double tx = INFINITY, ty = INFINITY;
    int has = 0;
    if (vx != 0) {
        if (x + vx * dt < m) {
            tx = (x - r) / -vx;
            has = 1;
        } else if (x + vx * dt > L - m) {
            tx = (L - r - x) / vx;
            has = 1;
        }
    }
    if (vy != 0) {
        if (y + vy * dt < m) {
            ty = (y - r) / -vy;
            has = 1;
        } else if (y + vy * dt > L - m) {
            ty = (L - r - y) / vy;
            has = 1;
        }
    }
    *t = tx < ty ? tx : ty;
    return has;
}

/* Pair candidate of P (lower id) and Q: A = |dv|^2, B = 2 dp.dv,
 * C = |dp|^2 - 4r^2, D = B^2 - 4AC; a candidate when D > 0 and
 * t = (-B - sqrt(D)) / 2 / A lies in [0, 1].  (Pairs that already overlap
 * have a negative first root and pass through each other.) */
PSIM_HD static inline int ccd_pair_time(double xp, double yp, double vxp, double vyp, double xq,
                                double yq, double vxq, double vyq, double r, double *t)
{
    double dx = xq - xp, dy = yq - yp, dvx = vxq - vxp, dvy = vyq - vyp;
    double A = dvx * dvx + dvy * dvy;
    double B = 2 * (dx * dvx + dy * dvy);
    double C = dx * dx + dy * dy - 4 * r * r;
    double D = B * B - 4 * A * C;
    if (!(D > 0))
        return 0;
    *t = (-B - sqrt(D)) / 2 / A;
    return *t >= 0 && *t <= 1;
}

/* Reverse each velocity component whose position is within 1e-14 of its
 * walls' contact position (r or L - r): the authors' test is one-sided,
 * x - r <= 1e-14 or L - r - x <= 1e-14 (a corner reverses both). */
PSIM_HD static inline void ccd_wall_reflect(double x, double y, double *vx, double *vy, double L,
                                    double r)
{
    if (x - r <= CCD_EPS || L - r - x <= CCD_EPS)
        *vx = -*vx;
    if (y - r <= CCD_EPS || L - r - y <= CCD_EPS)
        *vy = -*vy;
}

/* Exchange the normal velocity components of two touching disks, through
 * the normal and tangent unit vectors along the line of centres. */
PSIM_HD static inline void ccd_pair_bounce(double xp, double yp, double *vxp, double *vyp,
                                   double xq, double yq, double *vxq, double *vyq)
{
    double dx = xq - xp, dy = yq - yp;
    double dist = sqrt(dx * dx + dy * dy);
    double nx = dx / dist, ny = dy / dist, tx = -ny, ty = nx;
    double v1n = nx * *vxp + ny * *vyp, v1t = tx * *vxp + ty * *vyp;
    double v2n = nx * *vxq + ny * *vyq, v2t = tx * *vxq + ty * *vyq;
    *vxp = v2n * nx + v1t * tx;
    *vyp = v2n * ny + v1t * ty;
    *vxq = v1n * nx + v2t * tx;
    *vyq = v1n * ny + v2t * ty;
}

/* The rest of the step after a collision: move for dt, but stop where the
 * disk first touches a wall (found as a wall candidate over dt), without
 * reflecting: it reflects next step. */
PSIM_HD static inline void ccd_rest(double *x, double *y, double vx, double vy, double dt,
                            double L, double r)
{
    double tw, tt = dt;
    if (ccd_wall_time(*x, *y, vx, vy, dt, L, r, &tw) && tw < tt)
        tt = tw;
    *x = *x + vx * tt;
    *y = *y + vy * tt;
}

/* Accepted candidate c applied to the arrays of places (x, y, vx, vy)
 * and the collision counts by id: the disks move to the time of impact,
 * reflect or bounce, and rest for the rest of the step.  Returns 1 for a
 * wall collision, 0 for a pair's. */
PSIM_HD static inline int ccd_apply(const ccand *c, double *x, double *y, double *vx,
                                    double *vy, int64_t *pcoll, int64_t *wcoll, double L,
                                    double r)
{
    const double t = c->t;
    uint32_t p = c->sp;
    x[p] += vx[p] * t;
    y[p] += vy[p] * t;
    if (c->q < 0) {
        wcoll[c->p]++;
        ccd_wall_reflect(x[p], y[p], &vx[p], &vy[p], L, r);
        ccd_rest(&x[p], &y[p], vx[p], vy[p], 1 - t, L, r);
        return 1;
    }
    uint32_t q = c->sq;
    x[q] += vx[q] * t;
    y[q] += vy[q] * t;
    pcoll[c->p]++;
    pcoll[c->q]++;
    ccd_pair_bounce(x[p], y[p], &vx[p], &vy[p], x[q], y[q], &vx[q], &vy[q]);
    ccd_rest(&x[p], &y[p], vx[p], vy[p], 1 - t, L, r);
    ccd_rest(&x[q], &y[q], vx[q], vy[q], 1 - t, L, r);
    return 0;
}

#endif
