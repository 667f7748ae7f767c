/* The event loop of the event model: predictions into the calendar, and
 * the events taken from it in time order up to a given time. */
#include <math.h>

#include "event.h"
#include "predict.h"

void event_cell_insert(emodel *m, int32_t i)
{
    int32_t c = event_cell(m, m->d[i].cx, m->d[i].cy);
    m->d[i].prev = -1;
    m->d[i].next = m->head[c];
    if (m->head[c] >= 0)
        m->d[m->head[c]].prev = i;
    m->head[c] = i;
}

void event_cell_remove(emodel *m, int32_t i)
{
    int32_t c = event_cell(m, m->d[i].cx, m->d[i].cy);
    if (m->d[i].prev >= 0)
        m->d[m->d[i].prev].next = m->d[i].next;
    else
        m->head[c] = m->d[i].next;
    if (m->d[i].next >= 0)
        m->d[m->d[i].next].prev = m->d[i].prev;
}

/* The earliest collision of disk a with the disks of the k cells at
 * offsets off[0..k) from head + c, if earlier than (*t, *b) (ties: the
 * lower partner). */
static inline void earliest_in_cells(const emodel *m, int32_t a, int32_t c, const int32_t *off,
                                     int k, double *t, int32_t *b)
{
    for (int i = 0; i < k; i++)
        for (int32_t q = m->head[c + off[i]]; q >= 0; q = m->d[q].next) {
            if (q == a)
                continue;
            double tq = event_pair_time(m, a, q);
            if (tq < *t || (tq == *t && q < *b))
                *t = tq, *b = q;
        }
}

/* Disk a's earliest collision with the disks of the 3 x 3 cells around it,
 * to its plan. */
static void plan_pairs(emodel *m, int32_t a)
{
    eplan *p = &m->plan[a];
    p->tp = INFINITY;
    p->bp = -1;
    earliest_in_cells(m, a, event_cell(m, m->d[a].cx, m->d[a].cy), m->around, 9, &p->tp,
                      &p->bp);
    p->cp = p->bp >= 0 ? m->d[p->bp].cnt : 0;
}

/* Disk a's next event along axis, to its plan: leaving its cell or, in
 * the last cell towards a wall, reaching the wall. */
static void plan_axis(emodel *m, int32_t a, int axis)
{
    eplan *p = &m->plan[a];
    double t = event_cell_time(m, a, axis);
    int32_t kind = axis ? EV_CELL_Y : EV_CELL_X;
    if (!(t < INFINITY)) {
        t = event_wall_time(m, a, axis);
        kind = axis ? EV_WALL_Y : EV_WALL_X;
    }
    p->ta[axis] = t;
    p->ka[axis] = kind;
}

/* Put the earliest event of disk a's plan in the calendar; any event of
 * a's already there goes stale (its schedule count).  One event per disk:
 * a collision planned with a partner whose path has changed since is found
 * out when it comes up, and a planned again then (event_run_until). */
static int schedule(psim_sim *e, emodel *m, int32_t a)
{
    eplan *p = &m->plan[a];
    double t = p->tp;
    int32_t kind = p->bp;
    uint32_t cb = p->cp;
    for (int axis = 0; axis < 2; axis++)
        if (p->ta[axis] < t) {
            t = p->ta[axis];
            kind = p->ka[axis];
            cb = 0;
        }
    p->sched++;
    if (!(t < INFINITY))
        return 0;
    e->stats.counter[EC_PREDICTIONS]++;
    return ecal_push(&m->cal, (eevent){t, a, kind, p->sched, cb});
}

/* Every next event of disk a (after its path changed). */
int event_predict_disk(psim_sim *e, emodel *m, int32_t a)
{
    plan_axis(m, a, 0);
    plan_axis(m, a, 1);
    plan_pairs(m, a);
    return schedule(e, m, a);
}

/* The calendar's bucket width: the time in which about EVENT_BUCKET_EVENTS
 * cell crossings happen (n v_rms / h of them a unit of time); with the
 * collisions and stale events, a bucket holds some ten events at area
 * fraction 0.4 (1 to 16 measured: 1-2 best, 16 about 15% slower). */
#define EVENT_BUCKET_EVENTS 2.0
static double bucket_width(const emodel *m)
{
    double v2 = 0;
    for (long i = 0; i < m->n; i++)
        v2 += m->d[i].vx * m->d[i].vx + m->d[i].vy * m->d[i].vy;
    double vrms = m->n ? sqrt(v2 / (double)m->n) : 0;
    return vrms > 0 ? EVENT_BUCKET_EVENTS * m->h / ((double)m->n * vrms) : 0;
}

/* Buckets in the calendar's window: about one for eight disks, so that the
 * window spans the same time for any number of disks (a bucket is the time
 * of a few events in the whole box) and the overflow beyond it, spread
 * again at every turn of the window, stays small; at least ECAL_BUCKETS
 * (about 1e4 disks and fewer), at most 2^20. */
static int64_t calendar_buckets(const emodel *m)
{
    int64_t want = m->n / 8;
    return want > ((int64_t)1 << 20) ? (int64_t)1 << 20 : want;
}

/* A fresh calendar (at the start, and when stale events have piled up):
 * every disk's next events from the disks' states as they are. */
int event_predict_all(psim_sim *e, emodel *m)
{
    if (ecal_reset(&m->cal, m->buckets, calendar_buckets(m), m->now, bucket_width(m)))
        return -1;
    for (int32_t a = 0; a < m->n; a++)
        if (event_predict_disk(e, m, a))
            return -1;
    return 0;
}

/* Bring disk a to time t along its path. */
static void advance(emodel *m, int32_t a, double t)
{
    double s = t - m->d[a].t;
    m->d[a].x += m->d[a].vx * s;
    m->d[a].y += m->d[a].vy * s;
    m->d[a].t = t;
}

/* The elastic collision of equal disks a and b at their contact: the
 * relative velocity's component along the line of centres is exchanged. */
static void collide(emodel *m, int32_t a, int32_t b)
{
    double dx = m->d[b].x - m->d[a].x, dy = m->d[b].y - m->d[a].y;
    double dvx = m->d[b].vx - m->d[a].vx, dvy = m->d[b].vy - m->d[a].vy;
    double bb = dx * dvx + dy * dvy, k = bb / (dx * dx + dy * dy);
    m->d[a].vx += k * dx, m->d[a].vy += k * dy;
    m->d[b].vx -= k * dx, m->d[b].vy -= k * dy;
    m->virial += -bb;
}

/* Replaced in the calendar since (disk a planned again). */
static int replaced(const emodel *m, const eevent *ev)
{
    return ev->ca != m->plan[ev->a].sched;
}

/* Disk a's centre crossed into the next cell along axis: its next event
 * on that axis, and its earliest collision with the disks of the new row
 * or column of neighbours if earlier than the one planned (if that one's
 * partner has changed path since, a full plan). */
static int cross(psim_sim *e, emodel *m, int32_t a, int axis)
{
    double v = axis ? m->d[a].vy : m->d[a].vx;
    int d = v > 0 ? 1 : -1;
    event_cell_remove(m, a);
    if (axis)
        m->d[a].cy += d;
    else
        m->d[a].cx += d;
    event_cell_insert(m, a);
    e->stats.counter[EC_CROSSINGS]++;
    eplan *p = &m->plan[a];
    plan_axis(m, a, axis);
    if (p->bp >= 0 && p->cp != m->d[p->bp].cnt)
        plan_pairs(m, a);
    else {   /* the new row (around[6..8] or [0..2]) or column of neighbours */
        int32_t c = event_cell(m, m->d[a].cx, m->d[a].cy);
        int32_t line[3];
        for (int k = 0; k < 3; k++)
            line[k] = m->around[axis ? (d > 0 ? 6 : 0) + k : 3 * k + (d > 0 ? 2 : 0)];
        earliest_in_cells(m, a, c, line, 3, &p->tp, &p->bp);
    }
    p->cp = p->bp >= 0 ? m->d[p->bp].cnt : 0;
    return schedule(e, m, a);
}

/* A disk's state (position at its own time) changes only with its path,
 * at collisions and wall hits, not at cell crossings: every prediction
 * in the calendar that is still valid (its disks' path counts unchanged)
 * is then a function of the two disks' current states alone, whenever it
 * was made, so the calendar predicted afresh from those states (a restart
 * file's) holds the same events at the same times, bit for bit. */
static int process(psim_sim *e, emodel *m, const eevent *ev)
{
    int32_t a = ev->a, b = ev->b;
    m->now = ev->t;
    if (b >= 0) {
        advance(m, a, ev->t);
        advance(m, b, ev->t);
        collide(m, a, b);
        m->d[a].cnt++, m->d[b].cnt++;
        m->d[a].last = b, m->d[b].last = a;
        e->stats.counter[EC_COLLISIONS]++;
        return event_predict_disk(e, m, a) || event_predict_disk(e, m, b) ? -1 : 0;
    }
    if (b == EV_WALL_X || b == EV_WALL_Y) {
        advance(m, a, ev->t);
        double *v = b == EV_WALL_X ? &m->d[a].vx : &m->d[a].vy;
        m->wall_impulse += 2 * fabs(*v);
        *v = -*v;
        m->d[a].cnt++;
        m->d[a].last = -1;
        e->stats.counter[EC_WALLS]++;
        return event_predict_disk(e, m, a);
    }
    return cross(e, m, a, b == EV_CELL_Y);
}

/* The plan and the disk of the event after next in the current bucket,
 * into the cache while this one is done (the check of a popped event's
 * plan missed the cache at 1e5 disks). */
static inline void prefetch_next(const emodel *m)
{
    const ecal *c = &m->cal;
    if (c->heap.n > c->first + 1) {
        int32_t a = c->heap.e[c->first + 1].a;
        __builtin_prefetch(&m->plan[a]);
        __builtin_prefetch(&m->d[a]);
    }
}

/* Take the events up to time T in order (those at T included): 0, -1
 * when out of memory, 1 when a stop was asked (a poll every
 * PSIM_POLL_WORK events taken). */
int event_run_until(psim_sim *e, emodel *m, double T)
{
    for (uint32_t poll = PSIM_POLL_WORK;;) {
        const eevent *top = ecal_peek(&m->cal);
        if (m->cal.oom)
            return -1;
        if (!top || top->t > T)
            break;
        if (--poll == 0) {
            if (psim_poll(e, PSIM_POLL_WORK))
                return 1;
            poll = PSIM_POLL_WORK;
        }
        eevent ev = *top;
        ecal_pop(&m->cal);
        prefetch_next(m);
        if (replaced(m, &ev)) {
            e->stats.counter[EC_STALE]++;
            continue;
        }
        if (ev.b >= 0 && ev.cb != m->d[ev.b].cnt) {
            /* a's planned collision: the partner's path changed since */
            e->stats.counter[EC_STALE]++;
            m->now = ev.t;
            plan_pairs(m, ev.a);
            if (schedule(e, m, ev.a))
                return -1;
            continue;
        }
        if (process(e, m, &ev))
            return -1;
        /* stale events pile up: start afresh when they are most of it */
        if (m->cal.total > 32 * (size_t)m->n + 1024 && event_predict_all(e, m))
            return -1;
    }
    m->now = T;
    return 0;
}
