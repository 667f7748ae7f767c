/* The CS3210 AY2024/25 collision rules, exactly as the course states them.
 * Shared by the model, its checker, the tests and nothing else. */
#ifndef PSIM_DISCRETE_COLLIDE_H
#define PSIM_DISCRETE_COLLIDE_H
#include <math.h>

#define PSIM_APPROACH_EPS 1e-7

/* x - r <= 0 moving left, or x + r >= L moving right; likewise y. */
static inline int psim_wall_collides(double x, double y, double vx, double vy,
                                     double L, double r)
{
    return (x - r <= 0 && vx < 0) || (x + r >= L && vx > 0) ||
           (y - r <= 0 && vy < 0) || (y + r >= L && vy > 0);
}

/* Within reach of a wall (the position clauses of psim_wall_collides):
 * only then can a wall collide, whatever the velocity. */
static inline int psim_wall_reach(double x, double y, double L, double r)
{
    return (x - r <= 0) | (x + r >= L) | (y - r <= 0) | (y + r >= L);
}

static inline void psim_wall_resolve(double x, double y, double *vx,
                                     double *vy, double L, double r)
{
    if (x - r <= 0)
        *vx = fabs(*vx);
    else if (x + r >= L)
        *vx = -fabs(*vx);
    if (y - r <= 0)
        *vy = fabs(*vy);
    else if (y + r >= L)
        *vy = -fabs(*vy);
}

/* Overlap: squared distance <= (2r)^2, touching included. */
static inline int psim_overlaps(double d2, double four_r2)
{
    return d2 <= four_r2;
}

/* dv.dp with dp = p2 - p1, dv = v2 - v1; moving closer when < -1e-7. */
static inline double psim_approach(double dx, double dy, double dvx, double dvy)
{
    return dvx * dx + dvy * dy;
}

static inline int psim_moving_closer(double dot)
{
    return dot < -PSIM_APPROACH_EPS;
}

/* s = min(dv.dp, 0) / |dp|^2; v1 += s dp; v2 -= s dp. */
static inline void psim_pair_resolve(double dot, double dx, double dy,
                                     double d2, double *vx1, double *vy1,
                                     double *vx2, double *vy2)
{
    double s = (0.0 < dot ? 0.0 : dot) / d2; /* std::min(dot, 0.0) */
    *vx1 += s * dx;
    *vy1 += s * dy;
    *vx2 -= s * dx;
    *vy2 -= s * dy;
}

#endif
