/* Collision resolution to a fixpoint, as rounds of a task graph
 * (see discrete.h for the scheme and why it is deterministic). */
#include <string.h>

#include <omp.h>

#include "collide.h"
#include "discrete.h"
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

/* Worklist fixpoint over the contacts inside tile t (and its walls).
 *
 * A pair needs a test only when one of its disks changed velocity since the
 * pair was last tested.  A disk popped with F_CHANGED tests all its
 * contacts; a disk popped unchanged tests only contacts with disks not yet
 * popped this step (F_SEEN), because every other pair was tested at the
 * later disk's last pop and a disk that changed since is queued again. */
static void tile_task(const psim_sim *e, dmodel *m, dtile *t, int first)
{
    double *restrict vx = e->st.vx, *restrict vy = e->st.vy;
    const double *x = e->st.x, *y = e->st.y;
    const double L = e->L, r = e->r;
    const int walls = e->grid.tile_wall[t - m->tiles] && m->fl.walls;
    uint8_t *restrict flag = m->flag, *act = m->active, *near = m->nearwall;
    wl w = {t->queue, t->p1 - t->p0, 0, 0};
    uint64_t checks = 0, pres = 0, wres = 0;
    const uint64_t budget = m->budget;

    for (uint32_t i = t->p0; i < t->p1; i++) {
        if (!first) {   /* later rounds: the few disks edge tasks changed */
            uint64_t word;
            if (i + 8 <= t->p1 && (memcpy(&word, act + i, 8), word == 0)) {
                i += 7;
                continue;
            }
            if (!act[i])
                continue;
        }
        act[i] = 0;
        if (t->adj0[i - t->p0] == t->adj0[i - t->p0 + 1]) {
            /* no contact inside the tile: only its walls, now; its queue
             * turn would change nothing else */
            flag[i] = F_SEEN;
            if (walls && psim_wall_collides(x[i], y[i], vx[i], vy[i], L, r)) {
                psim_wall_resolve(x[i], y[i], &vx[i], &vy[i], L, r);
                wres++;
            }
            continue;
        }
        if (first && walls)   /* positions are frozen: a wall's reach, once a step */
            near[i] = (uint8_t)psim_wall_reach(x[i], y[i], L, r);
        flag[i] = first ? 0 : (uint8_t)(flag[i] | F_CHANGED);
        wl_push(&w, flag, i);
    }
    t->has_active = 0;
    while (w.count) {
        if (pres + wres > budget) {
            t->diverged = 1;
            break;
        }
        uint32_t i = wl_pop(&w);
        int full = flag[i] & F_CHANGED, changed = 0;
        flag[i] = F_SEEN;
        const double xi = x[i], yi = y[i];
        double vxi = vx[i], vyi = vy[i];
        if (walls && near[i] && psim_wall_collides(xi, yi, vxi, vyi, L, r)) {
            psim_wall_resolve(xi, yi, &vxi, &vyi, L, r);
            wres++;
            full = 1;
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
                flag[j] |= F_CHANGED;
                wl_push(&w, flag, j);
            }
        }
        vx[i] = vxi;
        vy[i] = vyi;
        if (changed) {
            flag[i] |= F_CHANGED;
            wl_push(&w, flag, i);
        }
    }
    t->checks += checks;
    t->wall_res += wres;
    e->tstats[omp_get_thread_num()].wall_resolutions += wres;
    t->pair_res += pres;
    t->round_res = pres + wres;
    t->changed_inner = (pres + wres) != 0;
}

/* One pass over a list of contacts across a tile border. */
static uint64_t cross_pass(const psim_sim *e, dmodel *m, const dlist *l,
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
            m->active[c->i] = 1;
            m->active[c->j] = 1;
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
    if (!first && !(a->changed_inner || b->changed_inner ||
                    a->changed_cross_prev || b->changed_cross_prev))
        return;
    const dlist *la = &a->cross[ed->dir], *lb = &b->cross[DIR_OPP(ed->dir)];
    uint64_t total = 0, res, checks = 0;
    const uint64_t budget = m->budget;
    do {
        res = cross_pass(e, m, la, &checks) + cross_pass(e, m, lb, &checks);
        total += res;
        if (total > budget) {
            a->diverged = 1;
            break;
        }
    } while (res);
    a->checks += checks;
    a->pair_res += total;
    if (total) {
        a->changed_cross_cur = b->changed_cross_cur = 1;
        a->has_active = b->has_active = 1;
    }
    m->edge_res[k] = total;
}

static int edge_has_work(const dmodel *m, const dedge *ed)
{
    return m->tiles[ed->a].cross[ed->dir].n + m->tiles[ed->b].cross[DIR_OPP(ed->dir)].n > 0;
}

/* An edge can only find work if a tile task runs on one of its tiles this
 * round or edges changed one of them last round. */
static int edge_may_change(const dmodel *m, const dedge *ed, int first)
{
    const dtile *a = &m->tiles[ed->a], *b = &m->tiles[ed->b];
    return first || a->scheduled || b->scheduled || a->changed_cross_prev ||
           b->changed_cross_prev;
}

static void timed_tile(const psim_sim *e, dmodel *m, dtile *t, int first)
{
    double t0 = psim_now();
    tile_task(e, m, t, first);
    psim_tstat_add(e->tstats, DPHASE_RESOLVE, psim_now() - t0, 1, t->p1 - t->p0);
}

static void timed_edge(const psim_sim *e, dmodel *m, size_t k, int first)
{
    double t0 = psim_now();
    edge_task(e, m, k, first);
    psim_tstat_add(e->tstats, DPHASE_RESOLVE, psim_now() - t0, 1, 0);
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

/* Emit one round's task graph (with one thread, run its tasks in creation
 * order, which the dependences allow: no graph); returns the number of
 * work items. */
static uint64_t emit_round(const psim_sim *e, dmodel *m, int first)
{
    uint64_t tasks = 0;
    const int graph = e->threads > 1;
    for (uint32_t ti = 0; ti < m->ntiles; ti++) {
        dtile *t = &m->tiles[ti];
        t->changed_inner = 0;
        t->round_res = 0;
        t->scheduled = t->p0 != t->p1 && (first || t->has_active);
    }
    for (uint32_t ti = 0; ti < m->ntiles; ti++) {
        dtile *t = &m->tiles[ti];
        if (!t->scheduled)
            continue;
        tasks++;
        if (!graph) {
            timed_tile(e, m, t, first);
            continue;
        }
        task_spawn_tile(e, m, t, ti, first);
    }
    for (size_t k = 0; k < m->nedges; k++) {
        const dedge *ed = &m->edges[k];
        m->edge_res[k] = 0;
        if (!edge_has_work(m, ed) || !edge_may_change(m, ed, first))
            continue;
        tasks++;
        if (!graph) {
            timed_edge(e, m, k, first);
            continue;
        }
        task_spawn_edge(e, m, k, first);
    }
    return tasks;
}

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
        res += m->edge_res[k];
    return res;
}

static int any_diverged(const dmodel *m)
{
    for (uint32_t ti = 0; ti < m->ntiles; ti++)
        if (m->tiles[ti].diverged)
            return 1;
    return 0;
}

__attribute__((noinline)) int discrete_resolve(psim_sim *e, dmodel *m)
{
    uint64_t rounds = 0, tasks = 0, total = 0;
    const uint64_t budget = m->budget;
    int settled = 1;
    for (uint32_t ti = 0; ti < m->ntiles; ti++) {
        dtile *t = &m->tiles[ti];
        t->checks = t->pair_res = t->wall_res = 0;
        t->has_active = t->changed_cross_prev = t->changed_cross_cur = 0;
        t->diverged = 0;
    }
#pragma omp parallel num_threads(e->threads) if (e->threads > 1)
#pragma omp single
    {
        for (int first = 1;; first = 0) {
            tasks += emit_round(e, m, first);
#pragma omp taskwait
            rounds++;
            uint64_t res = round_total(m);
            total += res;
            if (any_diverged(m) || total > budget) {
                settled = 0;
                break;
            }
            if (res == 0)
                break;
        }
    }
    for (uint32_t ti = 0; ti < m->ntiles; ti++) {
        const dtile *t = &m->tiles[ti];
        e->stats.counter[DC_PAIR_CHECKS] += t->checks;
        e->stats.counter[DC_PAIR_RES] += t->pair_res;
        e->stats.counter[DC_WALL_RES] += t->wall_res;
    }
    e->stats.counter[DC_ROUNDS] += rounds;
    if (rounds > e->stats.counter[DC_MAX_ROUNDS])
        e->stats.counter[DC_MAX_ROUNDS] = rounds;
    e->stats.counter[DC_TASKS] += tasks;
    e->stats.skipped[DS_GRAPH] += e->threads == 1;
    discrete_step_resolved(e, m, total);
    return settled ? 0 : -1;
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
void discrete_unsettled(const psim_sim *e, dmodel *m, dgroup *g)
{
    *g = (dgroup){0};
    memset(m->flag, 0, (size_t)e->n + 1);
    for (uint32_t ti = 0; ti < m->ntiles; ti++) {
        const dtile *t = &m->tiles[ti];
        group_list(e, m, g, &t->in);
        for (int d = 0; d < DIRS; d++)
            group_list(e, m, g, &t->cross[d]);
    }
    memset(m->flag, 0, (size_t)e->n + 1);
}
