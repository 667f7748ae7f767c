#ifndef PSIM_EVENT_PREDICT_H
#define PSIM_EVENT_PREDICT_H
#include <math.h>

#include "event.h"

/* When the next events of a disk happen, from the disks' states at their
 * own times, robust to round-off: a pair that touches or overlaps by a few
 * ulps while approaching collides at once (it cannot tunnel), and a pair
 * that has just collided is not made to collide again by the ulps left
 * of its overlap (it cannot stick). */

/* The contact time of disks a and b: with dr, dv their relative position
 * and velocity at the later of their times t0, b = dr.dv < 0 (approaching)
 * and c = |dr|^2 - sigma^2, the smaller root of |dr + dv s|^2 = sigma^2
 * is s = c / (-b + sqrt(b^2 - |dv|^2 c)): no cancellation. */
static inline double event_pair_time(const emodel *m, int32_t a, int32_t b)
{
    double t0 = m->d[a].t > m->d[b].t ? m->d[a].t : m->d[b].t;
    double sa = t0 - m->d[a].t, sb = t0 - m->d[b].t;
    double dx = (m->d[b].x + m->d[b].vx * sb) - (m->d[a].x + m->d[a].vx * sa);
    double dy = (m->d[b].y + m->d[b].vy * sb) - (m->d[a].y + m->d[a].vy * sa);
    double dvx = m->d[b].vx - m->d[a].vx, dvy = m->d[b].vy - m->d[a].vy;
    double bb = dx * dvx + dy * dvy;
    if (!(bb < 0))
        return INFINITY;   /* apart, or moving apart */
    double c = dx * dx + dy * dy - m->sigma2;
    if (c <= 0) {          /* touching: now, unless they have just collided */
        if (m->d[a].last == b && m->d[b].last == a)
            return INFINITY;
        return t0 > m->now ? t0 : m->now;
    }
    /* b^2 - |dv|^2 c = |dv|^2 sigma^2 - (dr x dv)^2 (Lagrange's identity):
     * as b^2 - |dv|^2 c it cancels to nothing where sigma^2 is below the
     * round-off of |dr|^2 (r = 1e-9 in a box of 10: a head-on pair met at
     * one point, and the collision divided 0 by 0) */
    double cross = dx * dvy - dy * dvx;
    double dv2 = dvx * dvx + dvy * dvy, d = dv2 * m->sigma2 - cross * cross;
    if (d < 0)
        return INFINITY;   /* they miss */
    double t = t0 + c / (-bb + sqrt(d));
    return t > m->now ? t : m->now;
}

/* The time disk a reaches the wall it moves towards along axis (0: x). */
static inline double event_wall_time(const emodel *m, int32_t a, int axis)
{
    double p = axis ? m->d[a].y : m->d[a].x, v = axis ? m->d[a].vy : m->d[a].vx, s;
    if (v > 0)
        s = (m->hi - p) / v;
    else if (v < 0)
        s = (m->lo - p) / v;
    else
        return INFINITY;
    double t = m->d[a].t + (s > 0 ? s : 0);
    return t > m->now ? t : m->now;
}

/* The time disk a's centre leaves its cell along axis (0: x); never for
 * the edge cells towards the wall. */
static inline double event_cell_time(const emodel *m, int32_t a, int axis)
{
    double p = axis ? m->d[a].y : m->d[a].x, v = axis ? m->d[a].vy : m->d[a].vx, s;
    int c = axis ? m->d[a].cy : m->d[a].cx;
    if (v > 0 && c + 1 < m->G)
        s = ((c + 1) * m->h - p) / v;
    else if (v < 0 && c > 0)
        s = (c * m->h - p) / v;
    else
        return INFINITY;
    double t = m->d[a].t + (s > 0 ? s : 0);
    return t > m->now ? t : m->now;
}

#endif
