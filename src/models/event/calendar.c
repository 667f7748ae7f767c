/* A binary min-heap of events (calendar.h). */
#include "calendar.h"
#include "../../engine/mem.h"

int ecal_push(ecal *c, eevent ev)
{
    if (c->n == c->cap && psim_reserve((void **)&c->heap, &c->cap, c->n + 1, sizeof *c->heap))
        return -1;
    size_t k = c->n++;
    while (k > 0) {   /* sift up */
        size_t p = (k - 1) / 2;
        if (!ecal_before(&ev, &c->heap[p]))
            break;
        c->heap[k] = c->heap[p];
        k = p;
    }
    c->heap[k] = ev;
    return 0;
}

eevent ecal_pop(ecal *c)
{
    eevent top = c->heap[0], last = c->heap[--c->n];
    size_t k = 0, n = c->n;
    for (;;) {   /* sift the last event down from the root */
        size_t l = 2 * k + 1;
        if (l >= n)
            break;
        size_t s = l + 1 < n && ecal_before(&c->heap[l + 1], &c->heap[l]) ? l + 1 : l;
        if (!ecal_before(&c->heap[s], &last))
            break;
        c->heap[k] = c->heap[s];
        k = s;
    }
    if (n > 0)
        c->heap[k] = last;
    return top;
}

void ecal_clear(ecal *c) { c->n = 0; }

void ecal_free(ecal *c)
{
    psim_free(c->heap);
    c->heap = NULL;
    c->n = c->cap = 0;
}
