/* Candidate detection: every wall hit and every pair time of impact in
 * [0, 1] of the step, found in parallel.
 *
 * Cells are wider than 2r plus the largest displacement of two disks (with
 * a margin for round-off), so a pair that can be a candidate lies in the
 * same or adjacent cells.  Within a cell and between a cell and its four
 * forward neighbours, pairs are pruned by their swept boxes (the box a disk
 * sweeps during the step, grown by r and the margin): each cell's disks
 * are sorted by the left edge of their box, and a sweep along x tests only
 * pairs whose boxes overlap.  Slow disks get small cells and O(N) work;
 * disks that cross a quarter of the box each step get few big cells, where
 * the sweep still skips most pairs, and never more than all pairs are
 * tested.  The pruning is conservative: every pair the rules make a
 * candidate is tested with the exact rule (rules.h). */
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "ccd.h"
#include "rules.h"
#include "../../engine/mem.h"
#include "../../engine/tstats.h"

int ccd_list_push(clist *l, const ccand *c)
{
    if (l->n == l->cap && psim_reserve((void **)&l->c, &l->cap, l->n + 1, sizeof *l->c))
        return -1;
    l->c[l->n++] = *c;
    return 0;
}

/* Insertion sort of a cell's places by box left edge (cells hold a few
 * disks); big cells use qsort_r. */
static int cmp_key(const void *a, const void *b, void *key)
{
    const double *sort_key = key;
    double x = sort_key[*(const uint32_t *)a], y = sort_key[*(const uint32_t *)b];
    if (x != y)
        return x < y ? -1 : 1;
    return (*(const uint32_t *)a > *(const uint32_t *)b) - (*(const uint32_t *)a < *(const uint32_t *)b);
}

static void sort_places(uint32_t *o, uint32_t n, const double *key)
{
    if (n > 48) {
        qsort_r(o, n, sizeof *o, cmp_key, (void *)key);
        return;
    }
    for (uint32_t i = 1; i < n; i++) {
        uint32_t v = o[i];
        double k = key[v];
        uint32_t j = i;
        while (j > 0 && (key[o[j - 1]] > k || (key[o[j - 1]] == k && o[j - 1] > v))) {
            o[j] = o[j - 1];
            j--;
        }
        o[j] = v;
    }
}

/* Swept boxes of every disk and each cell's places sorted by box left
 * edge, with the boxes gathered in that order. */
static void sort_cells(psim_sim *e, cmodel *m)
{
    const psim_store *s = &e->st;
    const psim_grid *g = &e->grid;
    const double grow = m->r + m->margin;
    const uint32_t nc = g->ncells;
#pragma omp parallel num_threads(e->threads)
    {
        double t0 = psim_now();
        uint64_t done = 0;
#pragma omp for schedule(static)
        for (size_t i = 0; i < s->n; i++) {
            double x1 = s->x[i] + s->vx[i], y1 = s->y[i] + s->vy[i];
            m->bx0[i] = (s->x[i] < x1 ? s->x[i] : x1) - grow;
            m->bx1[i] = (s->x[i] < x1 ? x1 : s->x[i]) + grow;
            m->by0[i] = (s->y[i] < y1 ? s->y[i] : y1) - grow;
            m->by1[i] = (s->y[i] < y1 ? y1 : s->y[i]) + grow;
        }
#pragma omp for schedule(dynamic, 64)
        for (uint32_t c = 0; c < nc; c++) {
            uint32_t a = g->cellstart[c], b = g->cellstart[c + 1];
            for (uint32_t k = a; k < b; k++)
                m->ord[k] = k;
            sort_places(m->ord + a, b - a, m->bx0);
            done += b - a;
        }
#pragma omp for schedule(static)
        for (size_t k = 0; k < s->n; k++) {
            uint32_t i = m->ord[k];
            m->sx0[k] = m->bx0[i];
            m->sx1[k] = m->bx1[i];
            m->sy0[k] = m->by0[i];
            m->sy1[k] = m->by1[i];
        }
        psim_tstat_add(e->tstats, CPHASE_DETECT, psim_now() - t0, 0, done);
    }
}

typedef struct detect_ctx {
    const psim_store *s;
    const psim_grid *g;
    cmodel *m;
    double L, r;
} detect_ctx;

/* Test the pair of sorted places a, b (their boxes overlap) with the
 * exact rule. */
static inline int test_pair(const detect_ctx *c, uint32_t a, uint32_t b, clist *out)
{
    const cmodel *m = c->m;
    const psim_store *s = c->s;
    uint32_t i = m->ord[a], j = m->ord[b];
    if (s->id[i] > s->id[j]) {
        uint32_t t = i;
        i = j;
        j = t;
    }
    ccand k;
    if (ccd_pair_time(s->x[i], s->y[i], s->vx[i], s->vy[i], s->x[j], s->y[j], s->vx[j],
                      s->vy[j], c->r, &k.t)) {
        k.p = s->id[i];
        k.q = s->id[j];
        k.sp = i;
        k.sq = j;
        if (ccd_list_push(out, &k))
            c->m->oom = 1;
    }
    return 1;
}

/* First sorted place of cell [b0, b1) whose box may reach x (boxes are at
 * most w wide). */
static uint32_t lower(const double *sx0, uint32_t b0, uint32_t b1, double x)
{
    while (b0 < b1) {
        uint32_t mid = b0 + (b1 - b0) / 2;
        if (sx0[mid] < x)
            b0 = mid + 1;
        else
            b1 = mid;
    }
    return b0;
}

static const int fwd[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};

/* Candidates of the sorted places [k0, k1) of cell c: their wall hits,
 * their pairs with later places of c, and their pairs with the four
 * forward neighbour cells.  Returns the exact pair tests made. */
static uint64_t detect_range(const detect_ctx *c, uint32_t cell, uint32_t k0, uint32_t k1,
                             const double *wmax, clist *out)
{
    const psim_store *s = c->s;
    const psim_grid *g = c->g;
    const cmodel *m = c->m;
    uint64_t tests = 0;
    uint32_t a1 = g->cellstart[cell + 1];
    for (uint32_t a = k0; a < k1; a++) {
        uint32_t i = m->ord[a];
        ccand k;
        if (ccd_wall_time(s->x[i], s->y[i], s->vx[i], s->vy[i], 1.0, c->L, c->r, &k.t)) {
            k.p = s->id[i];
            k.q = -1;
            k.sp = i;
            k.sq = UINT32_MAX;
            if (ccd_list_push(out, &k))
                c->m->oom = 1;
        }
        /* places whose boxes overlap a's in y, gathered without a branch,
         * then tested (a data-dependent branch here mispredicts often) */
        const double ya0 = m->sy0[a], ya1 = m->sy1[a], xa1 = m->sx1[a];
        uint32_t buf[256], nb = 0;
        for (uint32_t b = a + 1; b < a1 && m->sx0[b] <= xa1; b++) {
            buf[nb] = b;
            nb += (m->sy0[b] <= ya1) & (ya0 <= m->sy1[b]);
            if (nb == 256) {
                for (uint32_t u = 0; u < nb; u++)
                    tests += (uint64_t)test_pair(c, a, buf[u], out);
                nb = 0;
            }
        }
        for (uint32_t u = 0; u < nb; u++)
            tests += (uint64_t)test_pair(c, a, buf[u], out);
    }
    int cx = g->cell_x[cell], cy = g->cell_y[cell];
    for (int d = 0; d < 4; d++) {
        int nx = cx + fwd[d][0], ny = cy + fwd[d][1];
        if (nx < 0 || ny < 0 || nx >= g->G || ny >= g->G)
            continue;
        uint32_t nb = g->rank_of_xy[ny * g->G + nx];
        uint32_t b0 = g->cellstart[nb], b1 = g->cellstart[nb + 1];
        if (b0 == b1)
            continue;
        for (uint32_t a = k0; a < k1; a++) {
            /* boxes of nb are at most wmax[nb] wide: those starting before
             * sx0[a] - wmax[nb] end before a's box starts */
            for (uint32_t b = lower(m->sx0, b0, b1, m->sx0[a] - wmax[nb]);
                 b < b1 && m->sx0[b] <= m->sx1[a]; b++)
                if (m->sx1[b] >= m->sx0[a] && m->sy0[b] <= m->sy1[a] && m->sy0[a] <= m->sy1[b])
                    tests += (uint64_t)test_pair(c, a, b, out);
        }
    }
    return tests;
}

void ccd_detect(psim_sim *e, cmodel *m)
{
    sort_cells(e, m);
    const psim_grid *g = &e->grid;
    const size_t n = e->st.n;
    detect_ctx ctx = {&e->st, g, m, m->L, m->r};
    /* widest box of each cell, for the neighbour sweeps' start */
    double *wmax = psim_alloc((size_t)g->ncells * sizeof *wmax);
    if (!wmax) {
        m->oom = 1;
        return;
    }
#pragma omp parallel for schedule(static) num_threads(e->threads)
    for (uint32_t c = 0; c < g->ncells; c++) {
        double w = 0;
        for (uint32_t k = g->cellstart[c]; k < g->cellstart[c + 1]; k++)
            if (m->sx1[k] - m->sx0[k] > w)
                w = m->sx1[k] - m->sx0[k];
        wmax[c] = w;
    }
    for (int t = 0; t < m->nlists; t++)
        m->lists[t].n = 0;
    /* work units of about `unit` disks: runs of whole cells, or slices of
     * one big cell, each an OpenMP task (no dependences: detection only
     * reads the start-of-step state) */
    size_t unit = n / (8 * (size_t)e->threads);
    unit = unit < 256 ? 256 : (unit > 16384 ? 16384 : unit);
    uint64_t tests = 0, tasks = 0;
    psim_thread_stats *ts = e->tstats;
#pragma omp parallel num_threads(e->threads)
#pragma omp single
    {
        uint32_t c0 = 0;
        size_t held = 0;
        for (uint32_t c = 0; c <= g->ncells; c++) {
            size_t cn = c < g->ncells ? g->cellstart[c + 1] - g->cellstart[c] : 0;
            if ((c == g->ncells || held + cn > unit || cn > unit) && c > c0) {
                uint32_t f0 = c0, f1 = c;
                tasks++;
#pragma omp task firstprivate(f0, f1) shared(ctx, wmax, tests, ts) default(none)
                {
                    double t0 = psim_now();
                    clist *out = &ctx.m->lists[omp_get_thread_num()];
                    uint64_t mine = 0;
                    for (uint32_t cc = f0; cc < f1; cc++)
                        mine += detect_range(&ctx, cc, ctx.g->cellstart[cc],
                                             ctx.g->cellstart[cc + 1], wmax, out);
#pragma omp atomic
                    tests += mine;
                    psim_tstat_add(ts, CPHASE_DETECT, psim_now() - t0, 1,
                                   ctx.g->cellstart[f1] - ctx.g->cellstart[f0]);
                }
                c0 = c;
                held = 0;
            }
            if (c == g->ncells)
                break;
            if (cn > unit) {
                /* a big cell: slices of its sorted places */
                uint32_t end = g->cellstart[c + 1];
                for (uint32_t k = g->cellstart[c]; k < end; k += (uint32_t)unit) {
                    uint32_t cc = c, k0 = k, k1 = end - k > unit ? k + (uint32_t)unit : end;
                    tasks++;
#pragma omp task firstprivate(cc, k0, k1) shared(ctx, wmax, tests, ts) default(none)
                    {
                        double t0 = psim_now();
                        uint64_t mine = detect_range(&ctx, cc, k0, k1, wmax,
                                                     &ctx.m->lists[omp_get_thread_num()]);
#pragma omp atomic
                        tests += mine;
                        psim_tstat_add(ts, CPHASE_DETECT, psim_now() - t0, 1, k1 - k0);
                    }
                }
                c0 = c + 1;
            } else
                held += cn;
        }
    }
    psim_free(wmax);
    e->stats.counter[CC_PAIR_TESTS] += tests;
    e->stats.counter[CC_TASKS] += tasks;
}
