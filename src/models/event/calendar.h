/* The event calendar of the event model: a binary min-heap of pending
 * events ordered by (time, a, b), so that events at the same time are
 * taken in a fixed order.  Stale events (a disk's path changed since the
 * prediction) stay in the heap and are dropped when they come up: each
 * event carries the path counters of its disks at the prediction. */
#ifndef PSIM_EVENT_CALENDAR_H
#define PSIM_EVENT_CALENDAR_H
#include <stddef.h>
#include <stdint.h>

/* b >= 0: a collision of disks a and b; negative: an event of disk a. */
enum { EV_WALL_X = -1, EV_WALL_Y = -2, EV_CELL_X = -3, EV_CELL_Y = -4 };

typedef struct eevent {
    double t;
    int32_t a, b;
    uint32_t ca, cb;   /* path counters of a and b at the prediction */
} eevent;

typedef struct ecal {
    eevent *heap;
    size_t n, cap;
} ecal;

/* Add an event; -1 when out of memory. */
int ecal_push(ecal *c, eevent ev);
/* Remove and return the earliest event (c->n > 0). */
eevent ecal_pop(ecal *c);
void ecal_clear(ecal *c);
void ecal_free(ecal *c);

static inline int ecal_before(const eevent *p, const eevent *q)
{
    if (p->t != q->t)
        return p->t < q->t;
    if (p->a != q->a)
        return p->a < q->a;
    return p->b < q->b;
}

#endif
