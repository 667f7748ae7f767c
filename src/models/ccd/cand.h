/* The ccd model's candidates and their total order, and the reach of a
 * step's cells (plain C; PSIM_HD: the GPU path's kernels use the same).
 *
 * The order of the authors' program: by time; at equal times the lower
 * disk P first; for the same P the wall first, then the lower Q.  As two
 * unsigned keys, compared as numbers (the GPU path's radix sorts, a
 * stable sort by the id key, then by the time key): the time key orders
 * the times as numbers, -0 as +0; the id key orders (P, Q + 1). */
#ifndef PSIM_CCD_CAND_H
#define PSIM_CCD_CAND_H
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "../../engine/hd.h"

/* A candidate: disks by id, p < q, q = -1 for the wall; sp, sq their
 * places in the store this step. */
typedef struct ccand {
    double t;
    int32_t p, q;
    uint32_t sp, sq;
} ccand;

PSIM_HD static inline uint64_t ccd_time_key(double t)
{
    uint64_t u;
    t = t == 0 ? 0.0 : t;   /* -0 as +0: they are equal times */
    memcpy(&u, &t, sizeof u);
    return (u >> 63) ? ~u : u | (UINT64_C(1) << 63);
}

PSIM_HD static inline uint64_t ccd_id_key(int32_t p, int32_t q)
{
    return ((uint64_t)(uint32_t)p << 32) | ((uint32_t)q + 1u);   /* (-1: 0) */
}

/* Slack of the swept boxes, the cells and the skips against round-off:
 * the rules' arithmetic can make a candidate of a pair whose exact closest
 * approach is a little over 2r (by about sqrt(eps) of the distances
 * involved). */
PSIM_HD static inline double ccd_margin_of(double L, double r, double vmax)
{
    return 1e-6 * (L + 2 * vmax + r);
}

/* How far apart, on each axis, two disks that can meet within a step may
 * be at its start (vmax: the largest |vx| + |vy|): cells at least this
 * wide hold every pair that can be a candidate in the same or adjacent
 * cells. */
PSIM_HD static inline double ccd_reach(double L, double r, double vmax)
{
    return 2 * r + 2 * vmax + 2 * ccd_margin_of(L, r, vmax);
}

/* Whether cells `wide` wide (0: none yet), side of them a side, serve a
 * step of this reach: wide enough, and not over three times as wide while
 * more of them (up to most a side) could be had. */
PSIM_HD static inline int ccd_cells_keep(double reach, double wide, long side, long most)
{
    return wide > 0 && reach <= wide && !(reach * 3 < wide && side < most);
}

/* The width to plan cells for a step of this reach: 10% wider, so that
 * slowly growing speeds do not plan them again every step, but no wider
 * than twice the box unless the reach is. */
PSIM_HD static inline double ccd_cells_want(double L, double reach)
{
    double want = fmin(reach * 1.1, L * 2);
    return want > reach ? want : reach;
}

/* A disk's swept box over the step, grown by g = r + the margin: x0, x1,
 * y0, y1.  The boxes of a pair the rules make a candidate of overlap. */
PSIM_HD static inline void ccd_box(double x, double y, double vx, double vy, double g,
                                   double b[4])
{
    double x1 = x + vx, y1 = y + vy;
    b[0] = (x < x1 ? x : x1) - g;
    b[1] = (x < x1 ? x1 : x) + g;
    b[2] = (y < y1 ? y : y1) - g;
    b[3] = (y < y1 ? y1 : y) + g;
}

/* The first of x0[b, e) (ascending) not below x. */
PSIM_HD static inline uint32_t ccd_lower(const double *x0, uint32_t b, uint32_t e, double x)
{
    while (b < e) {
        uint32_t mid = b + (e - b) / 2;
        if (x0[mid] < x)
            b = mid + 1;
        else
            e = mid;
    }
    return b;
}

#endif
