/* The GPU path's pair search for one disk (plain C; PSIM_HD: the kernel
 * runs it, and tests/unit/test_gpu_plan.c runs it on the CPU against
 * every pair).
 *
 * The disks are sorted by band along y (bands at least ccd_reach high:
 * a pair that can meet is in the same or adjacent bands), and within a
 * band by the left edge of their swept boxes (ccd_box).  Disk i meets
 * each pair it owns once: the disks after it in its band whose boxes'
 * left edges lie within its box, and the disks of the band above whose
 * left edges lie from its own less the widest box to its right edge;
 * each such pair whose boxes overlap is a pair to test with the rules.
 * Every pair of disks is owned by one of them. */
#ifndef PSIM_CCD_SWEEP_H
#define PSIM_CCD_SWEEP_H
#include <stdint.h>

#include "../../engine/hd.h"
#include "cand.h"
#include "rules.h"

/* The sorted disks: n of them, band[k] the band of place k, each band's
 * places [start, end) (empty: start = end), the boxes x0, x1, y0, y1 and
 * the widest box's width. */
typedef struct ccd_sweep {
    uint32_t n, nbands;
    const uint32_t *band, *start, *end;
    const double *x0, *x1, *y0, *y1;
    double wmax;
} ccd_sweep;

/* Where disk i's search stands: in its own band (up = 0) or the band
 * above (up = 1), at place j of [j, e). */
typedef struct ccd_walk {
    uint32_t i, j, e;
    int up;
} ccd_walk;

PSIM_HD static inline void ccd_walk_start(const ccd_sweep *s, uint32_t i, ccd_walk *w)
{
    w->i = i, w->j = i + 1, w->e = s->end[s->band[i]], w->up = 0;
}

/* The next place j whose box overlaps disk i's, among the pairs i owns:
 * 1 and *j, or 0 when there are none left. */
PSIM_HD static inline int ccd_walk_next(const ccd_sweep *s, ccd_walk *w, uint32_t *j)
{
    const uint32_t i = w->i;
    const double ax0 = s->x0[i], ax1 = s->x1[i], ay0 = s->y0[i], ay1 = s->y1[i];
    for (;;) {
        for (; w->j < w->e && s->x0[w->j] <= ax1; w->j++) {
            uint32_t k = w->j;
            if (s->x1[k] >= ax0 && s->y0[k] <= ay1 && ay0 <= s->y1[k]) {
                *j = k;
                w->j++;
                return 1;
            }
        }
        uint32_t b = s->band[i] + 1;
        if (w->up || b >= s->nbands)
            return 0;
        w->up = 1;
        w->e = s->end[b];
        w->j = s->start[b] < w->e ? ccd_lower(s->x0, s->start[b], w->e,
                                              ax0 - s->wmax * (1 + 1e-9))
                                  : w->e;
    }
}

/* The rules on the pair of places i and j, the lower id as P: 1 and the
 * candidate in *v, or 0. */
PSIM_HD static inline int ccd_pair_test(uint32_t i, uint32_t j, const double *x,
                                        const double *y, const double *vx, const double *vy,
                                        const int32_t *id, double r, ccand *v)
{
    if (id[i] > id[j]) {
        uint32_t t = i;
        i = j, j = t;
    }
    v->p = id[i], v->q = id[j], v->sp = i, v->sq = j;
    return ccd_pair_time(x[i], y[i], vx[i], vy[i], x[j], y[j], vx[j], vy[j], r, &v->t);
}

#endif
