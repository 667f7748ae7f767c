/* The nearest pair of the sorted store: a lower bound on every pair's
 * distance, for models that leave out work no pair can need for a while
 * (the ccd model's free flight, the force model's list lifetime), and the
 * backoff that keeps such measurements cheap where they do not pay. */
#ifndef PSIM_ENGINE_NEAREST_H
#define PSIM_ENGINE_NEAREST_H
#include "engine.h"

/* The smallest squared distance above `above2` (-1: any) between two
 * particles in the same or adjacent cells of e's grid, or INFINITY where
 * there is none.  Needs the store sorted by cell for the current
 * positions.  A minimum, so the result does not depend on the thread
 * count; NaN positions are in no comparison and are left out.  Polls
 * (poll.h) with the pairs it looks at: a stop asked ends it early, with
 * a result of no use (the step is abandoned). */
double psim_nearest2(const psim_sim *e, double above2);

/* A distance that every pair exceeds, given d2, the squared distance of
 * the nearest pair in the same or adjacent cells (of those that count):
 * that distance, at most a cell side (pairs in cells further apart are at
 * least that far), less a relative 1e-12 for the rounding of distances. */
double psim_distance_bound(const psim_sim *e, double d2);

/* The same for the pairs farther apart than sqrt(above2), measured:
 * psim_distance_bound(e, psim_nearest2(e, above2)). */
double psim_nearest_bound(const psim_sim *e, double above2);

/* When to measure again: a measurement that paid is made again at the
 * next chance; one that did not doubles the wait before the next (in
 * chances: searches, builds), up to PSIM_BACKOFF_MAX. */
#define PSIM_BACKOFF_MAX 64
typedef struct psim_backoff {
    int wait, backoff;
} psim_backoff;

/* Whether to measure at this chance (if not, one chance fewer to wait). */
static inline int psim_backoff_due(psim_backoff *b)
{
    if (b->wait > 0) {
        b->wait--;
        return 0;
    }
    return 1;
}

/* After a measurement: whether it paid. */
static inline void psim_backoff_settle(psim_backoff *b, int paid)
{
    int next = b->backoff * 2 + 1;
    b->backoff = paid ? 0 : next < PSIM_BACKOFF_MAX ? next : PSIM_BACKOFF_MAX;
    b->wait = b->backoff;
}

#endif
