/* Collision resolution to a fixpoint, as rounds of a task graph
 * (see discrete.h for the scheme and why it is deterministic). */
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "collide.h"
#include "discrete.h"
#include "../../engine/mem.h"
#include "../../engine/poll.h"
#include "../../engine/task.h"
#include "../../engine/tstats.h"

/* Per-disk flags while resolving. */
enum { F_QUEUED = 1, F_CHANGED = 2, F_SEEN = 4 };

typedef struct wl {
    uint32_t *q;
    uint32_t cap, head, count;
} wl;

static inline void wl_push(wl *w, uint8_t *flag, uint32_t i)
{
    if (flag[i] & F_QUEUED)
        return;
    flag[i] |= F_QUEUED;
    uint32_t at = w->head + w->count++;
    w->q[at >= w->cap ? at - w->cap : at] = i;
}

static inline uint32_t wl_pop(wl *w)
{
    uint32_t i = w->q[w->head];
    w->head = (w->head + 1 == w->cap) ? 0 : w->head + 1;
    w->count--;
    return i;
}

/* Which disks a worklist takes, and what it did: all of the tile's
 * (own NULL), or the part k of its components (resolve_parts). */
typedef struct wpart {
    const uint8_t *own;   /* per disk of the tile: its component's part */
    uint8_t k;
    uint32_t *queue;      /* room for every disk of the tile */
    double *save;         /* NULL, or room for the velocities of every disk
                           * of the tile (x, then y) before its first pop */
    uint64_t checks, pres, wres;
    uint64_t polled;      /* its resolutions polled (src/engine/poll.h) */
    uint8_t diverged;
    uint8_t bchg;         /* it changed a disk with contacts across tiles */
    int tid;              /* the thread that ran it */
} wpart;

/* A worklist's resolutions, `done`, passed the number it looks again at:
 * 0 when they are past the budget (it gives up) or a poll says a stop was
 * asked; else the next number to look at, the budget or the next poll
 * before it.  Out of the loop, so that the loop keeps one number in a
 * register, as for the budget alone. */
static __attribute__((noinline, cold)) uint64_t look_again(const psim_sim *e, const dmodel *m,
                                                           wpart *wp, uint64_t done)
{
    if (done > m->budget || psim_poll(e, done - wp->polled))
        return 0;
    wp->polled = done;
    return m->budget - done < PSIM_POLL_WORK ? m->budget : done + PSIM_POLL_WORK;
}

/* Worklist fixpoint over the contacts inside tile t (and its walls).
 *
 * A pair needs a test only when one of its disks changed velocity since the
 * pair was last tested.  A disk popped with F_CHANGED tests all its
 * contacts; a disk popped unchanged tests only contacts with disks not yet
 * popped this step (F_SEEN), because every other pair was tested at the
 * later disk's last pop and a disk that changed since is queued again. */
static inline __attribute__((always_inline)) void
worklist_of(const psim_sim *e, dmodel *m, dtile *t, int first, wpart *wp, const int counts)
{
    double *restrict vx = e->st.vx, *restrict vy = e->st.vy;
    const double *x = e->st.x, *y = e->st.y;
    const double L = e->L, r = e->r;
    const int walls = e->grid.tile_wall[t - m->tiles] && m->fl.walls;
    uint8_t *restrict flag = m->flag, *act = m->active, *near = m->nearwall;
    const uint8_t *own = wp->own;
    double *save = wp->save;
    const uint32_t nt = t->p1 - t->p0;
    wl w = {wp->queue, nt, 0, 0};
    /* a tile among others stops after gens generations (0: at its
     * fixpoint); the queue it leaves goes on in its next round */
    const uint32_t gens = !own && m->ntiles > 1 ? m->gens : 0;
    if (!own && !first)
        w.head = t->qhead, w.count = t->qcount;
    uint64_t checks = 0, pres = 0, wres = 0;
    /* the resolutions at which to look again (look_again) */
    uint64_t look = m->budget < PSIM_POLL_WORK ? m->budget : PSIM_POLL_WORK;
    wp->polled = 0;
    const uint8_t *border = m->border;
    uint32_t *const count = counts ? m->counting : NULL;   /* the pops (balance.c) */
    int bchg = 0;   /* a disk with contacts across tiles changed */

    /* the first round: every disk of the tile; later rounds: the few that
     * edge tasks changed, in the order they did */
    const uint32_t *acts = first ? NULL : t->acts;
    const uint32_t seeds = first ? nt : t->nact;
    for (uint32_t k = 0; k < seeds; k++) {
        const uint32_t i = acts ? acts[k] : t->p0 + k;
        if (own && own[i - t->p0] != wp->k)
            continue;   /* another part's component */
        if (save) {   /* the velocity before, for a rerun */
            save[i - t->p0] = vx[i];
            save[nt + i - t->p0] = vy[i];
        }
        act[i] = 0;
        if (t->adj0[i - t->p0] == t->adj0[i - t->p0 + 1]) {
            /* no contact inside the tile: only its walls, now; its queue
             * turn would change nothing else */
            flag[i] = F_SEEN;
            if (walls && psim_wall_collides(x[i], y[i], vx[i], vy[i], L, r)) {
                psim_wall_resolve(x[i], y[i], &vx[i], &vy[i], L, r);
                wres++;
                bchg |= border[i];
            }
            continue;
        }
        if (first && walls)   /* positions are frozen: a wall's reach, once a step */
            near[i] = (uint8_t)psim_wall_reach(x[i], y[i], L, r);
        flag[i] = first ? 0 : (uint8_t)(flag[i] | F_CHANGED);
        wl_push(&w, flag, i);
    }
    if (!own)
        t->nact = 0;
    wp->diverged = 0;
    uint32_t gen_left = w.count, gen = 0;   /* pops left in this generation */
    /* pops, in runs between two looks at the resolutions (look_again: out
     * of the run's loop, which makes no call, as with the budget alone) */
    for (int looking = 1; looking;) {
        looking = 0;
        while (w.count) {
            if (gen_left == 0) {   /* the disks queued by the last generation's pops */
                if (++gen == gens)
                    break;
                gen_left = w.count;
            }
            if (pres + wres > look) {
                looking = 1;
                break;
            }
            gen_left--;
            uint32_t i = wl_pop(&w);
            if (counts)
                count[i]++;
            int full = flag[i] & F_CHANGED, changed = 0;
            flag[i] = F_SEEN;
            const double xi = x[i], yi = y[i];
            double vxi = vx[i], vyi = vy[i];
            if (walls && near[i] && psim_wall_collides(xi, yi, vxi, vyi, L, r)) {
                psim_wall_resolve(xi, yi, &vxi, &vyi, L, r);
                wres++;
                full = 1;
                bchg |= border[i];
            }
            const int32_t *a = t->adj + t->adj0[i - t->p0];
            const int32_t *end = t->adj + t->adj0[i - t->p0 + 1];
            for (; a < end; a++) {
                uint32_t j = (uint32_t)*a;
                if (!full && (flag[j] & F_SEEN))
                    continue;
                checks++;
                double dx = x[j] - xi, dy = y[j] - yi;
                double dot = psim_approach(dx, dy, vx[j] - vxi, vy[j] - vyi);
                if (psim_moving_closer(dot)) {
                    psim_pair_resolve(dot, dx, dy, dx * dx + dy * dy, &vxi, &vyi,
                                      &vx[j], &vy[j]);
                    changed = 1;
                    pres++;
                    bchg |= border[j];
                    flag[j] |= F_CHANGED;
                    wl_push(&w, flag, j);
                }
            }
            vx[i] = vxi;
            vy[i] = vyi;
            if (changed) {
                bchg |= border[i];
                flag[i] |= F_CHANGED;
                wl_push(&w, flag, i);
            }
        }
        if (looking && !(look = look_again(e, m, wp, pres + wres))) {
            wp->diverged = 1;   /* past the budget, or a stop asked */
            break;
        }
    }
    if (!own)
        t->qhead = w.head, t->qcount = w.count;
    if (pres + wres > wp->polled)
        psim_poll_add(e, pres + wres - wp->polled);
    wp->checks = checks, wp->pres = pres, wp->wres = wres;
    wp->bchg = (uint8_t)bchg;
    wp->tid = omp_get_thread_num();
}

/* The worklist of a step that counts its work (balance.c) and of one that
 * does not: two copies, so that the usual step's loop is the plain one. */
static void worklist(const psim_sim *e, dmodel *m, dtile *t, int first, wpart *wp)
{
    if (m->counting)
        worklist_of(e, m, t, first, wp, 1);
    else
        worklist_of(e, m, t, first, wp, 0);
}

/* What a tile's worklists did, to the tile. */
static void tile_done(dtile *t, uint64_t checks, uint64_t pres, uint64_t wres, int diverged,
                      int bchg)
{
    t->diverged |= (uint8_t)diverged;
    t->checks += checks;
    t->wall_res += wres;
    t->pair_res += pres;
    t->round_res = pres + wres;
    t->changed_border = (uint8_t)bchg;
}

/* A worklist, its time and its disks to its thread's profile. */
static double timed_worklist(const psim_sim *e, dmodel *m, dtile *t, int first, wpart *wp,
                             uint64_t disks)
{
    double t0 = psim_now();
    worklist(e, m, t, first, wp);
    const double dt = psim_now() - t0;
    psim_tstat_add(e->tstats, DPHASE_RESOLVE, dt, 1, disks);
    return dt;
}

/* Disk i (of tile a or b) changed by an edge task: to its tile's next
 * round, once. */
static inline void activate(dmodel *m, dtile *a, dtile *b, uint32_t i)
{
    if (m->active[i])
        return;
    m->active[i] = 1;
    dtile *t = i - a->p0 < a->p1 - a->p0 ? a : b;
    t->acts[t->nact++] = i;
}

/* One pass over a list of contacts across the border of tiles a and b. */
static uint64_t cross_pass(const psim_sim *e, dmodel *m, const dlist *l, dtile *a, dtile *b,
                           uint64_t *checks)
{
    double *restrict vx = e->st.vx, *restrict vy = e->st.vy;
    const double *x = e->st.x, *y = e->st.y;
    uint64_t res = 0;
    for (size_t k = 0; k < l->n; k++) {
        const dcontact *c = &l->c[k];
        double dx = x[c->j] - x[c->i], dy = y[c->j] - y[c->i];
        double dot = psim_approach(dx, dy, vx[c->j] - vx[c->i], vy[c->j] - vy[c->i]);
        if (psim_moving_closer(dot)) {
            psim_pair_resolve(dot, dx, dy, dx * dx + dy * dy, &vx[c->i], &vy[c->i],
                              &vx[c->j], &vy[c->j]);
            activate(m, a, b, (uint32_t)c->i);
            activate(m, a, b, (uint32_t)c->j);
            if (m->counting)
                m->counting[c->i]++, m->counting[c->j]++;
            res++;
        }
    }
    *checks += l->n;
    return res;
}

/* Fixpoint over the contacts between tiles a and b. */
static void edge_task(const psim_sim *e, dmodel *m, size_t k, int first)
{
    const dedge *ed = &m->edges[k];
    dtile *a = &m->tiles[ed->a], *b = &m->tiles[ed->b];
    m->edge_res[k] = 0;
    if (!first && !(a->changed_border || b->changed_border ||
                    a->changed_cross_prev || b->changed_cross_prev))
        return;
    const dlist *la = &a->cross[ed->dir], *lb = &b->cross[DIR_OPP(ed->dir)];
    uint64_t total = 0, res, checks = 0, polled = 0;
    const uint64_t budget = m->budget;
    do {
        res = cross_pass(e, m, la, a, b, &checks) + cross_pass(e, m, lb, a, b, &checks);
        total += res;
        if (total > budget) {
            a->diverged = 1;
            break;
        }
        if (total - polled >= PSIM_POLL_WORK) {
            if (psim_poll(e, total - polled)) {
                a->diverged = 1;   /* a stop asked */
                break;
            }
            polled = total;
        }
    } while (res);
    if (total > polled)
        psim_poll_add(e, total - polled);
    a->checks += checks;
    a->pair_res += total;
    if (total)   /* (its disks are in a's and b's acts) */
        a->changed_cross_cur = b->changed_cross_cur = 1;
    m->edge_res[k] = total;
}

static void timed_tile(const psim_sim *e, dmodel *m, dtile *t, int first)
{
    wpart wp = {.queue = t->queue};
    t->busy += timed_worklist(e, m, t, first, &wp, t->p1 - t->p0);   /* (a task a tile at a time) */
    e->tstats[wp.tid].wall_resolutions += wp.wres;
    tile_done(t, wp.checks, wp.pres, wp.wres, wp.diverged, wp.bchg);
}

static void timed_edge(const psim_sim *e, dmodel *m, size_t k, int first)
{
    double t0 = psim_now();
    edge_task(e, m, k, first);
    const double dt = psim_now() - t0;
    psim_tstat_add(e->tstats, DPHASE_RESOLVE, dt, 1, 0);
    m->tiles[m->edges[k].a].busy += dt;   /* (its tiles' edges in order) */
}

void discrete_edge(const psim_sim *e, dmodel *m, size_t k, int first)
{
    timed_edge(e, m, k, first);
}

/* One tile and more threads (the course's 10k scenes): with positions
 * frozen, the contacts are fixed for the step, and a pop reads and writes
 * only disks of its own component of the contact graph; the FIFO keeps
 * each component's pops in the order they have in the one worklist over
 * all.  So worklists over any grouping of the components resolve every
 * disk as the one worklist does, bit for bit: the components are split
 * into parts (by the store place of their first disk, which keeps a part
 * together in space), a part per thread.  A step that runs past its
 * budget is run again as one worklist (from the velocities kept), so that
 * where it gives up, and the error, do not depend on the threads. */
#define PARTS_MIN_CONTACTS 256

/* Contacts of disk d (its place in tile t) inside the tile. */
static inline uint32_t degree(const dtile *t, uint32_t d)
{
    return t->adj0[d + 1] - t->adj0[d];
}

void discrete_parts_free(dmodel *m)
{
    psim_free(m->part_seen), psim_free(m->part_of), psim_free(m->part_v), psim_free(m->part_queue);
    m->part_seen = NULL, m->part_of = NULL, m->part_v = NULL, m->part_queue = NULL;
    m->parts_cap = 0;
}

/* Each disk's part: by its store place (parts of equal size), except the
 * components that a split cuts, each of which goes whole to the part of
 * the disk it is first met from (a walk over its contacts; seen[] holds
 * the call's stamp for a disk walked). */
static int plan_parts(dmodel *m, const dtile *t, int parts)
{
    const uint32_t n = t->p1 - t->p0;
    if (n > m->parts_cap || parts > m->parts_n) {   /* room for n disks and the parts */
        discrete_parts_free(m);
        m->part_seen = psim_calloc((size_t)n * sizeof *m->part_seen);
        m->part_of = psim_alloc(n);
        m->part_v = psim_alloc(2 * (size_t)n * sizeof *m->part_v);
        m->part_queue = psim_alloc((size_t)parts * n * sizeof *m->part_queue);
        m->parts_cap = m->part_seen && m->part_of && m->part_v && m->part_queue ? n : 0;
        m->parts_n = parts;
        m->part_stamp = 0;
        if (!m->parts_cap)
            return -1;
    }
    if (++m->part_stamp == 0) {   /* the stamps wrapped: clear them */
        memset(m->part_seen, 0, (size_t)n * sizeof *m->part_seen);
        m->part_stamp = 1;
    }
    uint8_t *of = m->part_of;
    uint32_t *seen = m->part_seen, *walk = m->part_queue, stamp = m->part_stamp;
    uint64_t load[PARTS_MAX];   /* each part's contacts (twice), the work's measure */
    for (int k = 0; k < parts; k++) {
        uint32_t a = (uint32_t)((uint64_t)n * (uint64_t)k / (uint64_t)parts);
        uint32_t b = (uint32_t)((uint64_t)n * (uint64_t)(k + 1) / (uint64_t)parts);
        memset(of + a, k, b - a);
        load[k] = t->adj0[b] - t->adj0[a];
    }
    for (size_t c = 0; c < t->in.n; c++) {
        uint32_t i = (uint32_t)t->in.c[c].i - t->p0, j = (uint32_t)t->in.c[c].j - t->p0;
        if (of[i] == of[j])
            continue;
        /* a cut component: all of it to the least loaded of its parts */
        uint32_t head = 0, tail = 0;
        walk[tail++] = i;
        seen[i] = stamp;
        while (head < tail) {
            uint32_t d = walk[head++];
            load[of[d]] -= degree(t, d);
            for (uint32_t a = t->adj0[d]; a < t->adj0[d + 1]; a++) {
                uint32_t q = (uint32_t)t->adj[a] - t->p0;
                if (seen[q] != stamp) {
                    seen[q] = stamp;
                    walk[tail++] = q;
                }
            }
        }
        uint8_t best = of[i];
        for (uint32_t h = 0; h < tail; h++)
            if (load[of[walk[h]]] < load[best])
                best = of[walk[h]];
        for (uint32_t h = 0; h < tail; h++) {
            of[walk[h]] = best;
            load[best] += degree(t, walk[h]);
        }
    }
    return 0;
}

PSIM_TASK_SPAWN static void task_spawn_part(const psim_sim *e, dmodel *m, dtile *t, wpart *wp)
{
#pragma omp task default(none) firstprivate(e, m, t, wp)
    timed_worklist(e, m, t, 1, wp, 0);
}

/* Whether tile t's first round runs as parts: more than one thread, the
 * only tile (no contacts across tiles) and contacts enough. */
static int use_parts(const psim_sim *e, const dmodel *m, const dtile *t, int first)
{
    return first && e->threads > 1 && m->ntiles == 1 && m->nedges == 0 &&
           t->in.n >= PARTS_MIN_CONTACTS && e->threads <= PARTS_MAX;
}

/* Tile t's first round as parts (inside the parallel region's single);
 * 0, or -1 when out of memory (then run it as one worklist). */
static int resolve_parts(const psim_sim *e, dmodel *m, dtile *t)
{
    const int parts = e->threads;
    if (plan_parts(m, t, parts))
        return -1;
    const uint32_t n = t->p1 - t->p0;
    wpart wp[PARTS_MAX];
    for (int k = 0; k < parts; k++) {
        wp[k] = (wpart){.own = m->part_of, .k = (uint8_t)k, .queue = m->part_queue + (size_t)k * n,
                        .save = m->part_v};
        task_spawn_part(e, m, t, &wp[k]);
    }
#pragma omp taskwait
    uint64_t checks = 0, pres = 0, wres = 0;
    int diverged = 0;
    for (int k = 0; k < parts; k++) {
        checks += wp[k].checks, pres += wp[k].pres, wres += wp[k].wres;
        diverged |= wp[k].diverged;
    }
    if (diverged || pres + wres > m->budget) {   /* as one worklist, from the start */
        memcpy(e->st.vx + t->p0, m->part_v, n * sizeof *m->part_v);
        memcpy(e->st.vy + t->p0, m->part_v + n, n * sizeof *m->part_v);
        timed_tile(e, m, t, 1);
        return 0;
    }
    for (int k = 0; k < parts; k++)   /* (a rerun's own walls count instead) */
        e->tstats[wp[k].tid].wall_resolutions += wp[k].wres;
    tile_done(t, checks, pres, wres, 0, 0);   /* one tile: no edges */
    return 0;
}

/* A tile's task and an edge's (src/engine/task.h): a tile depends on its
 * own slot, an edge on both of its tiles'. */
PSIM_TASK_SPAWN static void task_spawn_tile(const psim_sim *e, dmodel *m, dtile *t, uint32_t ti,
                                            int first)
{
#pragma omp task default(none) firstprivate(e, m, t, first) depend(inout : m->dep[ti])
    timed_tile(e, m, t, first);
}

PSIM_TASK_SPAWN static void task_spawn_edge(const psim_sim *e, dmodel *m, size_t k, int first)
{
    const dedge *ed = &m->edges[k];
#pragma omp task default(none) firstprivate(e, m, k, first) \
    depend(inout : m->dep[ed->a]) depend(inout : m->dep[ed->b])
    timed_edge(e, m, k, first);
}

/* A round's tiles taken by whichever thread is free (--option rounds=1,
 * the default): the tiles that run, heaviest first (the disks each pops;
 * in the first round, its disks), are a list that each thread takes the
 * next of when it is free.  That is the classic list schedule, largest
 * first; with the task graph the runtime chose which thread ran which
 * tile, and with four tiles on two threads the two heaviest often landed
 * on one (docs/performance.md, "Tiles taken heaviest first").  The tiles
 * of a round share nothing, so the order they run in changes no result. */
static uint32_t tile_weight(const dtile *t, int first)
{
    return first ? t->p1 - t->p0 : t->qcount + t->nact;
}

static int cmp_key(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* m->order: the scheduled tiles, heaviest first, ties in tile order (a
 * key's high half is the weight's complement, its low half the tile). */
static void order_tiles(dmodel *m, int first)
{
    uint32_t n = 0;
    for (uint32_t ti = 0; ti < m->ntiles; ti++)
        if (m->tiles[ti].scheduled)
            m->order[n++] = (uint64_t)(UINT32_MAX - tile_weight(&m->tiles[ti], first)) << 32 | ti;
    qsort(m->order, n, sizeof *m->order, cmp_key);
    m->norder = n;
    m->next = 0;
}

static void take_tiles(const psim_sim *e, dmodel *m, int first)
{
    for (;;) {
        uint32_t k;
#pragma omp atomic capture
        k = m->next++;
        if (k >= m->norder)
            return;
        timed_tile(e, m, &m->tiles[(uint32_t)m->order[k]], first);
    }
}

PSIM_TASK_SPAWN static void task_spawn_taker(const psim_sim *e, dmodel *m, int first)
{
#pragma omp task default(none) firstprivate(e, m, first)
    take_tiles(e, m, first);
}

/* The round's tiles, taken (inside the parallel region's single): a task
 * for each other thread that can have a tile, and this thread takes too. */
static void take_round(const psim_sim *e, dmodel *m, int first)
{
    order_tiles(m, first);
    uint32_t helpers = (uint32_t)e->threads - 1;
    if (helpers + 1 > m->norder)
        helpers = m->norder ? m->norder - 1 : 0;
    for (uint32_t k = 0; k < helpers; k++)
        task_spawn_taker(e, m, first);
    take_tiles(e, m, first);
#pragma omp taskwait
}

/* Edges whose contacts, over the round, are fewer than this run on the
 * thread that made the round, one after the other: an edge task of ~50
 * contacts (the course's scenes) costs as much to make and hand over as
 * its work. */
#define EDGES_INLINE_CONTACTS 1024

static size_t edge_contacts(const dmodel *m, const dedge *ed)
{
    return m->tiles[ed->a].cross[ed->dir].n + m->tiles[ed->b].cross[DIR_OPP(ed->dir)].n;
}

/* An edge can only find work if it has contacts and a tile task runs on
 * one of its tiles this round or edges changed one of them last round. */
static int edge_runs(const dmodel *m, const dedge *ed, int first)
{
    const dtile *a = &m->tiles[ed->a], *b = &m->tiles[ed->b];
    return edge_contacts(m, ed) > 0 &&
           (first || a->scheduled || b->scheduled || a->changed_cross_prev ||
            b->changed_cross_prev);
}

int discrete_edge_runs(const dmodel *m, size_t k, int first)
{
    return edge_runs(m, &m->edges[k], first);
}

/* Run the round's tiles; returns how many. */
static uint64_t round_tiles(const psim_sim *e, dmodel *m, int first)
{
    uint64_t tiles = 0;
    const int graph = e->threads > 1;
    for (uint32_t ti = 0; ti < m->ntiles; ti++) {
        dtile *t = &m->tiles[ti];
        t->changed_border = 0;
        t->round_res = 0;
        t->scheduled = t->p0 != t->p1 && (first || t->nact || t->qcount) &&
                       discrete_mine(m, ti) && !t->oom;
        tiles += t->scheduled;
    }
    if (graph && m->take && m->ntiles > 1) {
        take_round(e, m, first);
        return tiles;
    }
    uint64_t extra = 0;
    for (uint32_t ti = 0; ti < m->ntiles; ti++) {
        dtile *t = &m->tiles[ti];
        if (!t->scheduled)
            continue;
        if (!graph)
            timed_tile(e, m, t, first);
        else if (use_parts(e, m, t, first) && resolve_parts(e, m, t) == 0)
            extra += (uint64_t)e->threads - 1;
        else
            task_spawn_tile(e, m, t, ti, first);
    }
    return tiles + extra;
}

/* One round over ranks: the rank's tiles, then the edges that touch
 * them, level by level, each level after the disks of its edges across
 * ranks came (ranks.c); returns the work items this rank counts. */
static void mark_border(dmodel *m, uint8_t v);

static uint64_t ranks_round(psim_sim *e, dmodel *m, int first, int *failed)
{
    uint64_t tasks = round_tiles(e, m, first);
#pragma omp taskwait
    /* the first round's tiles ran while the other ranks searched: now the
     * search's figures and the contacts across ranks */
    if (first && (*failed = discrete_ranks_contacts(e, m) != 0))
        return tasks;
    if (first)
        mark_border(m, 1);   /* (the other ranks' lists too) */
    for (size_t k = 0; k < m->nedges; k++)
        m->edge_res[k] = 0;
    discrete_ranks_flags(m, first);
    for (int lv = 0; lv < EDGE_LEVELS; lv++)
        tasks += discrete_ranks_level(e, m, lv, first);
    return tasks;
}

/* Emit one round: its tiles, then its edges (with one thread, or a round
 * whose edges are few, they run in creation order on this thread, which
 * the dependences allow: no graph); returns the number of work items. */
static uint64_t emit_round(const psim_sim *e, dmodel *m, int first)
{
    uint64_t tasks = round_tiles(e, m, first);
    size_t contacts = 0;
    for (size_t k = 0; k < m->nedges; k++) {
        m->edge_res[k] = 0;
        if (edge_runs(m, &m->edges[k], first))
            contacts += edge_contacts(m, &m->edges[k]);
    }
    const int graph = e->threads > 1 && !(m->take && contacts < EDGES_INLINE_CONTACTS);
    for (size_t k = 0; k < m->nedges; k++) {
        if (!edge_runs(m, &m->edges[k], first))
            continue;
        tasks++;
        if (graph)
            task_spawn_edge(e, m, k, first);
        else
            timed_edge(e, m, k, first);
    }
    return tasks;
}

/* The round's resolutions (over ranks, of this rank's tiles and of the
 * edges whose tile a it owns). */
static uint64_t round_total(dmodel *m)
{
    uint64_t res = 0;
    for (uint32_t ti = 0; ti < m->ntiles; ti++) {
        dtile *t = &m->tiles[ti];
        res += t->round_res;
        t->changed_cross_prev = t->changed_cross_cur;
        t->changed_cross_cur = 0;
    }
    for (size_t k = 0; k < m->nedges; k++)
        res += discrete_mine(m, m->edges[k].a) ? m->edge_res[k] : 0;
    return res;
}

static int any_diverged(const dmodel *m)
{
    for (uint32_t ti = 0; ti < m->ntiles; ti++)
        if (m->tiles[ti].diverged)
            return 1;
    return 0;
}

/* Mark (v 1) or clear (v 0) the disks with contacts across tiles: an edge
 * task needs to run again only when a tile task changed one of them. */
static void mark_border(dmodel *m, uint8_t v)
{
    for (uint32_t ti = 0; ti < m->ntiles; ti++)
        for (int d = 0; d < DIRS; d++) {
            const dlist *l = &m->tiles[ti].cross[d];
            for (size_t k = 0; k < l->n; k++)
                m->border[l->c[k].i] = m->border[l->c[k].j] = v;
        }
}

__attribute__((noinline)) int discrete_resolve(psim_sim *e, dmodel *m)
{
    uint64_t rounds = 0, tasks = 0, total = 0;
    const uint64_t budget = m->budget;
    int settled = 1, failed = 0;
    for (uint32_t ti = 0; ti < m->ntiles; ti++) {
        dtile *t = &m->tiles[ti];
        t->checks = t->pair_res = t->wall_res = 0;
        t->nact = 0;
        t->changed_cross_prev = t->changed_cross_cur = 0;
        t->diverged = 0;
    }
    mark_border(m, 1);
    if (m->ranks > 1)
        discrete_ranks_keep(e, m);
    m->counting = discrete_balance_counts(e, m) ? m->work : NULL;
    /* rounds of few resolutions each poll every PSIM_POLL_WORK of them
     * (their worklists and edges count them) */
    uint64_t look = PSIM_POLL_WORK;
    /* (the main thread makes the rounds: over ranks it sends and receives) */
#pragma omp parallel num_threads(e->threads) if (e->threads > 1)
#pragma omp master
    {
        for (int first = 1;; first = 0) {
            tasks += m->ranks > 1 ? ranks_round(e, m, first, &failed) : emit_round(e, m, first);
#pragma omp taskwait
            if (failed) {
                settled = 0;
                break;
            }
            rounds++;
            uint64_t res = round_total(m);
            int diverged = any_diverged(m);
            if (m->ranks > 1)   /* every rank's, and a stop asked on any */
                res = discrete_ranks_round_end(e, m, res, &diverged);
            total += res;
            if (diverged || total > budget) {
                settled = 0;
                break;
            }
            if (res == 0)
                break;
            if (total >= look) {
                if (psim_poll(e, 0)) {
                    settled = 0;
                    break;
                }
                look = total + PSIM_POLL_WORK;
            }
        }
    }
    mark_border(m, 0);
    if (m->ranks > 1)
        discrete_ranks_sync(e, m);
    for (uint32_t ti = 0; ti < m->ntiles; ti++) {
        const dtile *t = &m->tiles[ti];
        if (!discrete_mine(m, ti))
            continue;
        e->stats.counter[DC_PAIR_CHECKS] += t->checks;
        e->stats.counter[DC_PAIR_RES] += t->pair_res;
        e->stats.counter[DC_WALL_RES] += t->wall_res;
    }
    e->stats.counter[DC_ROUNDS] += m->rank == 0 ? rounds : 0;   /* (summed over ranks) */
    if (rounds > e->stats.counter[DC_MAX_ROUNDS])
        e->stats.counter[DC_MAX_ROUNDS] = rounds;
    e->stats.counter[DC_TASKS] += tasks;
    e->stats.skipped[DS_GRAPH] += e->threads == 1;
    discrete_step_resolved(e, m, total);
    return failed ? -2 : settled ? 0 : -1;
}

static void group_add(const psim_sim *e, dmodel *m, dgroup *g, int32_t i)
{
    if (m->flag[i])
        return;
    m->flag[i] = 1;
    double x = e->st.x[i], y = e->st.y[i];
    if (g->disks++ == 0) {
        g->x0 = g->x1 = x;
        g->y0 = g->y1 = y;
        g->first_id = e->st.id[i];
    }
    g->x0 = x < g->x0 ? x : g->x0, g->x1 = x > g->x1 ? x : g->x1;
    g->y0 = y < g->y0 ? y : g->y0, g->y1 = y > g->y1 ? y : g->y1;
    if (e->st.id[i] < g->first_id)
        g->first_id = e->st.id[i];
}

static void group_list(const psim_sim *e, dmodel *m, dgroup *g, const dlist *l)
{
    const double *x = e->st.x, *y = e->st.y, *vx = e->st.vx, *vy = e->st.vy;
    for (size_t k = 0; k < l->n; k++) {
        int32_t i = l->c[k].i, j = l->c[k].j;
        double dot = psim_approach(x[j] - x[i], y[j] - y[i], vx[j] - vx[i], vy[j] - vy[i]);
        if (psim_moving_closer(dot)) {
            group_add(e, m, g, i);
            group_add(e, m, g, j);
        }
    }
}

/* After a step gave up (serial; the flags are free again). */
void discrete_unsettled(psim_sim *e, dmodel *m, dgroup *g)
{
    *g = (dgroup){0};
    memset(m->flag, 0, (size_t)e->n + 1);
    for (uint32_t ti = 0; ti < m->ntiles; ti++) {
        const dtile *t = &m->tiles[ti];
        if (!discrete_mine(m, ti))
            continue;
        group_list(e, m, g, &t->in);
        for (int d = 0; d < DIRS; d++)
            group_list(e, m, g, &t->cross[d]);
    }
    if (m->ranks > 1) {   /* every rank's marks, and the group of them all */
        discrete_ranks_marks(e, m);
        *g = (dgroup){0};
        for (long k = 0; k < e->n; k++)
            if (m->flag[k]) {
                m->flag[k] = 0;
                group_add(e, m, g, (int32_t)k);
            }
    }
    memset(m->flag, 0, (size_t)e->n + 1);
}
