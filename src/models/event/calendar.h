/* The event calendar of the event model, after Paul (J. Comput. Phys.
 * 221, 2007): the events of the current time bucket (width w) in order,
 * later ones appended to the list of their bucket (a window of nb
 * buckets, then an overflow list, spread again when the window moves on),
 * so that pushing an event costs O(1) and the current bucket is small and
 * in cache.  Paul keeps the current bucket in a binary heap; here it is
 * sorted once when it becomes current (some ten events) and taken from the
 * front, an event that arrives for it meanwhile (rare: a bucket is the
 * time of a few events in all the box) inserted in place.  With buckets
 * off, every event goes to one binary heap (the baseline).  Either way
 * events come out in (time, a, b) order: the results do not depend on the
 * calendar.  Stale events stay in and are dropped when they come up: each
 * event carries its disk's schedule count and its partner's path count
 * (event.h). */
#ifndef PSIM_EVENT_CALENDAR_H
#define PSIM_EVENT_CALENDAR_H
#include <stddef.h>
#include <stdint.h>

/* b >= 0: a collision of disks a and b; negative: an event of disk a. */
enum { EV_WALL_X = -1, EV_WALL_Y = -2, EV_CELL_X = -3, EV_CELL_Y = -4 };

typedef struct eevent {
    double t;
    int32_t a, b;
    uint32_t ca, cb;   /* a's schedule count, b's path count at the prediction */
} eevent;

typedef struct evec {
    eevent *e;
    size_t n, cap;
} evec;

/* Buckets in the window: ECAL_BUCKETS, or more for many disks (the
 * event model: event.c), always a power of two. */
#define ECAL_BUCKETS 4096

typedef struct ecal {
    evec heap;          /* without buckets: all events, a binary heap; with
                         * them: the current bucket's, heap.e[first..n) in
                         * order */
    size_t first;
    int buckets;        /* 0: heap only */
    double t0, w, iw;   /* bucket k holds t with (t - t0) iw in [k, k + 1),
                         * iw = 1 / w */
    int64_t cur;        /* the current bucket */
    evec *bucket;       /* nb buckets: bucket k at k mod nb */
    int64_t nb;         /* a power of two */
    size_t inbuckets;   /* events in the buckets */
    evec over;          /* events beyond the window */
    size_t total;       /* events in the calendar */
    int oom;
} ecal;

/* Empty the calendar; with buckets, nb of them (a power of two, at least
 * ECAL_BUCKETS: 0 for that) of width w from time t0.  -1: no memory. */
int ecal_reset(ecal *c, int buckets, int64_t nb, double t0, double w);
void ecal_free(ecal *c);
/* calendar.c: what the inline calls below do but for their common case */
int ecal_push_any(ecal *c, eevent ev);
const eevent *ecal_peek_next(ecal *c);
void ecal_pop_heap(ecal *c);

/* The bucket of time t (clamped to the current one: an event is never
 * earlier than the current bucket but for rounding).  Any function of t
 * that never decreases as t grows keeps the events in order; this one
 * multiplies by 1 / w and truncates (floor for what is not clamped), where
 * a division and floor() (a call without SSE4.1) cost a push more. */
static inline int64_t ecal_bucket_of(const ecal *c, double t)
{
    double k = (t - c->t0) * c->iw;
    if (!(k >= 0))
        return c->cur;
    if (!(k < 9.0e18))
        return INT64_MAX;
    return (int64_t)k < c->cur ? c->cur : (int64_t)k;
}

/* Add an event (at or after the current bucket); -1 when out of memory.
 * Inline: a later bucket of the window with room in its list (most
 * pushes). */
static inline int ecal_push(ecal *c, eevent ev)
{
    if (c->buckets) {
        int64_t k = ecal_bucket_of(c, ev.t);
        if (k > c->cur && k - c->cur < c->nb) {
            evec *v = &c->bucket[k & (c->nb - 1)];
            if (v->n < v->cap) {
                v->e[v->n++] = ev;
                c->inbuckets++;
                c->total++;
                return 0;
            }
        }
    }
    return ecal_push_any(c, ev);
}

/* The earliest event, or NULL when there is none (or c->oom is set). */
static inline const eevent *ecal_peek(ecal *c)
{
    if (c->heap.n > c->first && !c->oom)
        return &c->heap.e[c->first];
    return ecal_peek_next(c);
}

/* Remove the earliest event (after ecal_peek returned it). */
static inline void ecal_pop(ecal *c)
{
    c->total--;
    if (c->buckets)
        c->first++;
    else
        ecal_pop_heap(c);
}

#endif
