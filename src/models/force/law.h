/* The CS267 HW2 force law and integrator, with the arithmetic of the
 * course's starter code (common.h / serial.cpp, 2020+ edition) operation
 * for operation, so that psim's results equal the course's naive code's
 * bit for bit:
 *
 *   apply_force(p, q): dx = q.x - p.x; dy = q.y - p.y; r2 = dx*dx + dy*dy;
 *     if (r2 > cutoff*cutoff) return; r2 = fmax(r2, min_r*min_r);
 *     r = sqrt(r2); coef = (1 - cutoff / r) / r2 / mass;
 *     p.ax += coef*dx; p.ay += coef*dy;
 *   move(p): vx += ax*dt; vy += ay*dt; x += vx*dt; y += vy*dt;
 *     while (x < 0 || x > size) { x = x < 0 ? -x : 2*size - x; vx = -vx; }
 *     and likewise y.
 *
 * Built without fused multiply-add (-ffp-contract=off; nvcc --fmad=false),
 * as the course's code is compiled for x86-64 without FMA.  The CPU path
 * and the CUDA kernels (gpu.cu) both call these functions (PSIM_HD). */
#ifndef PSIM_FORCE_LAW_H
#define PSIM_FORCE_LAW_H
#include <math.h>

#include "../../engine/hd.h"

typedef struct flaw {
    double size, cutoff, mass, dt;
    double cutoff2;   /* cutoff * cutoff */
    double min_r2;    /* min_r * min_r, min_r = cutoff / 100 */
} flaw;

/* The force coefficient of a pair at squared distance r2 within the
 * cutoff: the force on p is (coef dx, coef dy), dx = q.x - p.x. */
PSIM_HD static inline double flaw_coef(const flaw *k, double r2)
{
    r2 = r2 >= k->min_r2 ? r2 : k->min_r2;   /* fmax(r2, min_r2), NaN too, inline */
    double r = sqrt(r2);
    return (1 - k->cutoff / r) / r2 / k->mass;
}

/* Force of q on p, to (*fx, *fy); returns whether they interact. */
PSIM_HD static inline int flaw_force(const flaw *k, double px, double py, double qx,
                                     double qy, double *fx, double *fy)
{
    double dx = qx - px, dy = qy - py;
    double r2 = dx * dx + dy * dy;
    if (r2 > k->cutoff2)
        return 0;
    double coef = flaw_coef(k, r2);
    *fx = coef * dx;
    *fy = coef * dy;
    return 1;
}

/* Force of q on p, added to (*ax, *ay); returns whether they interact. */
PSIM_HD static inline int flaw_pair(const flaw *k, double px, double py, double qx, double qy,
                                    double *ax, double *ay)
{
    double fx, fy;
    if (!flaw_force(k, px, py, qx, qy, &fx, &fy))
        return 0;
    *ax += fx;
    *ay += fy;
    return 1;
}

/* Reflections of one coordinate off the walls 0 and size.  The course
 * loops until the particle is inside; a particle more than one box away
 * (a step far too large for the force) would loop for ever, so psim
 * stops after FLAW_MAX_BOUNCES and reports it (returns -1). */
#define FLAW_MAX_BOUNCES 64
PSIM_HD static inline int flaw_bounce(double size, double *x, double *v)
{
    for (int b = 0; *x < 0 || *x > size; b++) {
        if (b == FLAW_MAX_BOUNCES)
            return -1;
        *x = *x < 0 ? -*x : 2 * size - *x;
        *v = -*v;
    }
    return 0;
}

/* The course's move of one coordinate before the walls: v += a dt, then
 * x += v dt. */
PSIM_HD static inline double flaw_kick(const flaw *k, double v, double a) { return v + a * k->dt; }
PSIM_HD static inline double flaw_drift(const flaw *k, double x, double v) { return x + v * k->dt; }

/* The course's move of one particle given its acceleration; new position
 * to (*nx, *ny).  Returns -1 when it left the box for good. */
PSIM_HD static inline int flaw_move(const flaw *k, double x, double y, double *vx, double *vy,
                            double ax, double ay, double *nx, double *ny)
{
    *vx = flaw_kick(k, *vx, ax);
    *vy = flaw_kick(k, *vy, ay);
    x = flaw_drift(k, x, *vx);
    y = flaw_drift(k, y, *vy);
    int rc = flaw_bounce(k->size, &x, vx) | flaw_bounce(k->size, &y, vy);
    *nx = x;
    *ny = y;
    return rc;
}

#endif
