/* Free flight: steps in which no pair can meet, or no disk can reach a
 * wall, leave out the pair search (and its sort) or the wall candidates.
 *
 *   pairs  a search that found no pair candidate measures the nearest pair
 *          (psim_nearest2): every pair is then more than 2r + gap apart.
 *          A step moves each disk by at most vmax = max |vx| + |vy| >= |v|
 *          (a wall collision stops the disk at the wall: a shorter path),
 *          so a pair closes by at most 2 vmax; the rules make a candidate
 *          only of a pair that can close to 2r within the step, so while
 *          gap > 2 vmax (plus the swept boxes' round-off margin) no pair
 *          candidate exists and the search is left out.
 *   walls  the rule makes a wall candidate only when x + vx < r + 1e-14 or
 *          x + vx > L - r - 1e-14 (likewise y): none while the positions'
 *          extent lies more than vmax (plus the margin) inside those lines.
 * A measurement that left out nothing makes the next wait twice as long
 * (psim_backoff, up to 64 searches), so a scene whose pairs stay close pays
 * for few measurements; its searches are the same as without. */
#include <float.h>

#include "ccd.h"
#include "rules.h"
#include "../../engine/nearest.h"

int ccd_flight_clear(cmodel *m, double vmax)
{
    int clear = m->gap >= 0 && m->gap > 2 * vmax + ccd_margin(m, vmax);
    if (m->measured) {   /* the first step after a measurement: did it pay? */
        m->measured = 0;
        psim_backoff_settle(&m->measure, clear);
    }
    return clear;
}

int ccd_walls_clear(const cmodel *m, double vmax, const double ext[4])
{
    double lo = m->r + CCD_EPS + vmax + ccd_margin(m, vmax), hi = m->L - lo;
    return ext[0] > lo && ext[1] < hi && ext[2] > lo && ext[3] < hi;
}

void ccd_flight_measure(psim_sim *e, cmodel *m)
{
    if (!psim_backoff_due(&m->measure))
        return;
    double gap = psim_nearest_bound(e, -1) - 2 * m->r * (1 + 1e-12);
    m->gap = gap >= 0 ? gap : -1;
    m->measured = 1;
}

void ccd_flight_step(cmodel *m, double vmax)
{
    if (m->gap < 0)
        return;
    /* what a pair closes by this step, and the rounding of its positions */
    double closed = 2 * vmax + 16 * DBL_EPSILON * (m->L + vmax);
    m->gap = m->gap > closed ? m->gap - closed : -1;
}
