/* When the next events of a disk happen, from the disks' states at their
 * own times, robust to round-off: a pair that touches or overlaps by a few
 * ulps while approaching collides at once (it cannot tunnel), and a pair
 * that has just collided is not made to collide again by the ulps left
 * of its overlap (it cannot stick). */
#include <math.h>

#include "event.h"

/* The contact time of disks a and b: with dr, dv their relative position
 * and velocity at the later of their times t0, b = dr.dv < 0 (approaching)
 * and c = |dr|^2 - sigma^2, the smaller root of |dr + dv s|^2 = sigma^2
 * is s = c / (-b + sqrt(b^2 - |dv|^2 c)): no cancellation. */
double event_pair_time(const emodel *m, int32_t a, int32_t b)
{
    double t0 = m->t[a] > m->t[b] ? m->t[a] : m->t[b];
    double sa = t0 - m->t[a], sb = t0 - m->t[b];
    double dx = (m->x[b] + m->vx[b] * sb) - (m->x[a] + m->vx[a] * sa);
    double dy = (m->y[b] + m->vy[b] * sb) - (m->y[a] + m->vy[a] * sa);
    double dvx = m->vx[b] - m->vx[a], dvy = m->vy[b] - m->vy[a];
    double bb = dx * dvx + dy * dvy;
    if (!(bb < 0))
        return INFINITY;   /* apart, or moving apart */
    double c = dx * dx + dy * dy - m->sigma2;
    if (c <= 0) {          /* touching: now, unless they have just collided */
        if (m->last[a] == b && m->last[b] == a)
            return INFINITY;
        return t0 > m->now ? t0 : m->now;
    }
    double dv2 = dvx * dvx + dvy * dvy, d = bb * bb - dv2 * c;
    if (d < 0)
        return INFINITY;   /* they miss */
    double t = t0 + c / (-bb + sqrt(d));
    return t > m->now ? t : m->now;
}

/* The time disk a reaches the wall it moves towards along axis (0: x). */
double event_wall_time(const emodel *m, int32_t a, int axis)
{
    double p = axis ? m->y[a] : m->x[a], v = axis ? m->vy[a] : m->vx[a], s;
    if (v > 0)
        s = (m->hi - p) / v;
    else if (v < 0)
        s = (m->lo - p) / v;
    else
        return INFINITY;
    double t = m->t[a] + (s > 0 ? s : 0);
    return t > m->now ? t : m->now;
}

/* The time disk a's centre leaves its cell along axis (0: x); never for
 * the edge cells towards the wall. */
double event_cell_time(const emodel *m, int32_t a, int axis)
{
    double p = axis ? m->y[a] : m->x[a], v = axis ? m->vy[a] : m->vx[a], s;
    int c = axis ? m->cy[a] : m->cx[a];
    if (v > 0 && c + 1 < m->G)
        s = ((c + 1) * m->h - p) / v;
    else if (v < 0 && c > 0)
        s = (c * m->h - p) / v;
    else
        return INFINITY;
    double t = m->t[a] + (s > 0 ? s : 0);
    return t > m->now ? t : m->now;
}
