/* The event model's calendar (Paul's buckets, the current one sorted): events
 * pushed in a random order, with ties, far-future events (the overflow
 * beyond the bucket window), and pushes between pops (never earlier than
 * the last event taken, as the model does) come out in time order, every
 * one of them, and in exactly the order of the plain binary heap (buckets
 * off): each pop takes the least (time, a, b) of what is in.  A bucket
 * that never runs dry (a rattling disk) keeps only the events still in. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "check.h"
#include "models/event/calendar.h"

static uint64_t rng = 88172645463325252ull;
static double uniform(void)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (double)(rng >> 11) * 0x1.0p-53;
}

/* A time at or after now: mostly near, some ties, some far beyond the
 * window of ECAL_BUCKETS buckets of width w (the same times for every
 * calendar: w = 1). */
static double draw_time(double now, double w)
{
    double u = uniform();
    if (u < 0.1)
        return now;                                   /* ties at the present */
    if (u < 0.2)
        return now + w * (double)ECAL_BUCKETS * (1 + 3 * uniform());   /* overflow */
    if (u < 0.25)
        return now + (double)(int)(uniform() * 8) * w;   /* on bucket edges */
    if (u < 0.3) {   /* on the edges where the window of buckets moves on */
        double span = (double)ECAL_BUCKETS * w;
        return (floor(now / span) + 1 + (double)(int)(uniform() * 3)) * span;
    }
    return now + uniform() * 50 * w;
}

#define MAXOPS 60000
static eevent out[MAXOPS];

/* Returns the number of events that came out (in out[]); nb buckets. */
static long run(int buckets, int64_t nb, double w)
{
    rng = 88172645463325252ull;   /* the same pushes for every calendar */
    ecal c = {0};
    CHECK(ecal_reset(&c, buckets, nb, 0.0, w) == 0);
    CHECK(!buckets || (c.nb >= nb && c.nb >= ECAL_BUCKETS && (c.nb & (c.nb - 1)) == 0));
    long pushed = 0, popped = 0;
    for (int i = 0; i < 20000; i++, pushed++)
        CHECK(ecal_push(&c, (eevent){draw_time(0, 1.0), (int32_t)(uniform() * 100),
                                     (int32_t)(uniform() * 100) - 4, 0, 0}) == 0);
    eevent last = {-1, -1, -1, 0, 0};
    int order_ok = 1;
    for (;;) {
        const eevent *top = ecal_peek(&c);
        if (!top)
            break;
        eevent ev = *top;
        ecal_pop(&c);
        out[popped++] = ev;
        order_ok &= ev.t >= last.t;
        last = ev;
        /* new events from the present on, as a processed event makes */
        for (int k = 0; k < 2 && pushed < 60000; k++, pushed++)
            CHECK(ecal_push(&c, (eevent){draw_time(ev.t, 1.0), (int32_t)(uniform() * 100),
                                         (int32_t)(uniform() * 100) - 4, 0, 0}) == 0);
    }
    CHECK_MSG(order_ok, "buckets %d: events out of order", buckets);
    CHECK_MSG(popped == pushed, "buckets %d: %ld pushed, %ld came out", buckets, pushed, popped);
    CHECK(c.total == 0 && !c.oom);
    ecal_free(&c);
    return popped;
}

/* A disk rattling in a gap of 1e-7 between a wall and another disk: an
 * event every 1e-7, each pushed right after the last was taken, all in the
 * current bucket (of width 1), where another event waits at t = 0.9 (and,
 * the second time, none: the bucket is refilled as soon as it runs dry).
 * The bucket's list is taken from the front: it must not keep every event
 * taken (it grew by one per event, to gigabytes in a run). */
static void rattle(int far)
{
    ecal c = {0};
    CHECK(ecal_reset(&c, 1, 0, 0.0, 1.0) == 0);
    if (far)
        CHECK(ecal_push(&c, (eevent){0.9, 1, EV_WALL_X, 0, 0}) == 0);
    CHECK(ecal_push(&c, (eevent){1e-7, 0, EV_WALL_X, 0, 0}) == 0);
    long taken = 0, wrong = 0;
    for (; taken < 1000000; taken++) {
        const eevent *top = ecal_peek(&c);
        CHECK(top != NULL);
        eevent ev = *top;
        ecal_pop(&c);
        wrong += ev.a != 0 || ev.t != (double)(taken + 1) * 1e-7;
        CHECK(ecal_push(&c, (eevent){(double)(taken + 2) * 1e-7, 0, EV_WALL_X, 0, 0}) == 0);
    }
    CHECK_MSG(wrong == 0, "rattle: %ld events out of order", wrong);
    CHECK_MSG(c.heap.cap < 4 * 4096 && c.total == 1u + (unsigned)far,
              "rattle (far %d): %zu events held for %zu in the calendar after %ld taken",
              far, c.heap.cap, c.total, taken);
    const eevent *top = ecal_peek(&c);   /* the near one, then the far one */
    CHECK(top && top->a == 0);
    ecal_pop(&c);
    top = ecal_peek(&c);
    CHECK(far ? top && top->a == 1 && top->t == 0.9 : top == NULL);
    ecal_free(&c);
}

int main(void)
{
    rattle(1);
    rattle(0);
    static eevent ref[MAXOPS];
    long n = run(0, 0, 1.0);
    for (long i = 0; i < n; i++)
        ref[i] = out[i];
    /* windows of ECAL_BUCKETS buckets, and of more (5000: rounded up to 8192,
     * so that the draws' overflow and window edges fall inside its window) */
    const double widths[] = {1.0, 1e-3, 0.37, 50.0};
    const int64_t counts[] = {0, 5000};
    for (int j = 0; j < 2; j++)
        for (int k = 0; k < 4; k++) {
            long m = run(1, counts[j], widths[k]);
            int same = m == n;
            for (long i = 0; same && i < n; i++)
                same = ref[i].t == out[i].t && ref[i].a == out[i].a && ref[i].b == out[i].b;
            CHECK_MSG(same, "%lld buckets, width %g: not the heap's order",
                      (long long)counts[j], widths[k]);
        }
    return check_done();
}
