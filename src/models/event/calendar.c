/* Paul's calendar: the current bucket's events in order, lists for later
 * buckets; without buckets, one binary heap (calendar.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "calendar.h"
#include "../../engine/mem.h"

static int before(const eevent *p, const eevent *q)
{
    if (p->t != q->t)
        return p->t < q->t;
    if (p->a != q->a)
        return p->a < q->a;
    return p->b < q->b;
}

static int vec_push(evec *v, eevent ev)
{
    if (v->n == v->cap && psim_reserve((void **)&v->e, &v->cap, v->n + 1, sizeof *v->e))
        return -1;
    v->e[v->n++] = ev;
    return 0;
}

static void sift_down(eevent *h, size_t n, size_t k, eevent ev)
{
    for (;;) {
        size_t l = 2 * k + 1;
        if (l >= n)
            break;
        size_t s = l + 1 < n && before(&h[l + 1], &h[l]) ? l + 1 : l;
        if (!before(&h[s], &ev))
            break;
        h[k] = h[s];
        k = s;
    }
    h[k] = ev;
}

static int heap_push(evec *h, eevent ev)
{
    if (vec_push(h, ev))
        return -1;
    size_t k = h->n - 1;
    while (k > 0) {   /* sift up */
        size_t p = (k - 1) / 2;
        if (!before(&ev, &h->e[p]))
            break;
        h->e[k] = h->e[p];
        k = p;
    }
    h->e[k] = ev;
    return 0;
}

/* ev into its place among the ordered e[lo..i), moving the later ones up
 * (from the end: i is free).  Inlined: a call costs the bucket sort a
 * quarter more instructions (cachegrind). */
static inline __attribute__((always_inline)) void
sink(eevent *e, size_t lo, size_t i, eevent ev)
{
    while (i > lo && before(&ev, &e[i - 1])) {
        e[i] = e[i - 1];
        i--;
    }
    e[i] = ev;
}

/* The current bucket's run: ev into its place (from the end: most events
 * that arrive are later than those in). */
static int run_insert(evec *r, size_t first, eevent ev)
{
    if (vec_push(r, ev))
        return -1;
    sink(r->e, first, r->n - 1, ev);
    return 0;
}

static int by_time(const void *p, const void *q)
{
    return before(p, q) ? -1 : before(q, p) ? 1 : 0;
}

/* A bucket's events (in the order they came) in order. */
static void run_sort(evec *r)
{
    if (r->n > 24) {
        qsort(r->e, r->n, sizeof *r->e, by_time);
        return;
    }
    for (size_t k = 1; k < r->n; k++)   /* insertion sort */
        sink(r->e, 0, k, r->e[k]);
}

/* The current bucket's run is taken from the front (first) and events that
 * arrive for it meanwhile go in from the end, so a bucket that never runs
 * dry grows by one entry per event taken: a disk rattling in a gap of
 * 1e-7 r between a wall and another disk makes some 10^7 events a step,
 * far more than the few a bucket's width was chosen for, and they grew the
 * run to gigabytes.  Once the events taken are at least as many as those
 * left (and a few thousand), the rest moves to the front, when the list is
 * full (so the usual insertion pays nothing): at most one move per event
 * taken since the last, and the list never grows past twice its events (or
 * a few thousand).  The order of the events is unchanged. */
#define ECAL_COMPACT 4096
static void run_compact(ecal *c)
{
    size_t live = c->heap.n - c->first;
    if (c->first < ECAL_COMPACT || c->first < live)
        return;
    memmove(c->heap.e, c->heap.e + c->first, live * sizeof *c->heap.e);
    c->heap.n = live;
    c->first = 0;
}

static int place(ecal *c, eevent ev)
{
    int64_t k = ecal_bucket_of(c, ev.t);
    if (k == c->cur) {
        if (c->heap.n == c->heap.cap)   /* full: the events taken go before it grows */
            run_compact(c);
        return run_insert(&c->heap, c->first, ev);
    }
    if (k - c->cur < c->nb) {
        c->inbuckets++;
        return vec_push(&c->bucket[k & (c->nb - 1)], ev);
    }
    return vec_push(&c->over, ev);
}

int ecal_reset(ecal *c, int buckets, int64_t nb, double t0, double w)
{
    c->heap.n = c->over.n = 0;
    c->first = 0;
    c->total = c->inbuckets = 0;
    c->oom = 0;
    c->buckets = buckets && w > 0 && isfinite(w);
    c->t0 = t0;
    c->w = w;
    c->iw = 1 / w;
    c->cur = 0;
    if (!c->buckets)
        return 0;
    int64_t p = ECAL_BUCKETS;   /* a power of two, at least nb */
    while (p < nb && p < ((int64_t)1 << 40))
        p <<= 1;
    nb = p;
    if (c->bucket && c->nb != nb) {   /* another count: new lists */
        for (int64_t k = 0; k < c->nb; k++)
            psim_free(c->bucket[k].e);
        psim_free(c->bucket);
        c->bucket = NULL;
    }
    c->nb = nb;
    if (!c->bucket && !(c->bucket = psim_calloc((size_t)nb * sizeof *c->bucket)))
        return -1;
    for (int64_t k = 0; k < nb; k++)
        c->bucket[k].n = 0;
    return 0;
}

/* Any push (ecal_push takes the common case inline). */
int ecal_push_any(ecal *c, eevent ev)
{
    c->total++;
    if (!c->buckets)
        return heap_push(&c->heap, ev);
    return place(c, ev);
}

/* The overflow events that the window now reaches, to their buckets. */
static int spread_overflow(ecal *c)
{
    size_t keep = 0, n = c->over.n;
    c->over.n = 0;
    for (size_t i = 0; i < n; i++) {
        eevent ev = c->over.e[i];
        int64_t k = ecal_bucket_of(c, ev.t);
        if (k - c->cur < c->nb) {
            if (place(c, ev))
                return -1;
        } else
            c->over.e[keep++] = ev;
    }
    c->over.n = keep;
    return 0;
}

/* Move on to the next bucket that holds events, into the run. */
static int next_bucket(ecal *c)
{
    while (c->heap.n == c->first && c->total > 0) {
        c->heap.n = c->first = 0;
        if (c->inbuckets == 0) {   /* only the overflow: jump to its earliest */
            int64_t k = INT64_MAX;
            for (size_t i = 0; i < c->over.n; i++) {
                int64_t b = ecal_bucket_of(c, c->over.e[i].t);
                k = b < k ? b : k;
            }
            c->cur = k;
            if (spread_overflow(c))
                return -1;
            continue;
        }
        c->cur++;
        if ((c->cur & (c->nb - 1)) == 0 && spread_overflow(c))
            return -1;
        evec *b = &c->bucket[c->cur & (c->nb - 1)];
        if (b->n == 0)
            continue;
        c->inbuckets -= b->n;
        if (c->heap.n > 0) {   /* the overflow put some in already */
            for (size_t k = 0; k < b->n; k++)
                if (run_insert(&c->heap, 0, b->e[k]))
                    return -1;
            b->n = 0;
            continue;
        }
        evec tmp = c->heap;   /* swap the bucket's list in as the run */
        c->heap = *b;
        *b = tmp;
        run_sort(&c->heap);
    }
    return 0;
}

/* ecal_peek when the current bucket is used up: the next that has events. */
const eevent *ecal_peek_next(ecal *c)
{
    if (c->heap.n == c->first && c->buckets && next_bucket(c))
        c->oom = 1;
    return c->heap.n > c->first && !c->oom ? &c->heap.e[c->first] : NULL;
}

void ecal_pop_heap(ecal *c)
{
    evec *h = &c->heap;
    eevent last = h->e[--h->n];
    if (h->n > 0)
        sift_down(h->e, h->n, 0, last);
}

void ecal_free(ecal *c)
{
    psim_free(c->heap.e);
    psim_free(c->over.e);
    for (int64_t k = 0; c->bucket && k < c->nb; k++)
        psim_free(c->bucket[k].e);
    psim_free(c->bucket);
    memset(c, 0, sizeof *c);
}
