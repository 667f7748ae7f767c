/* Ordering and acceptance of the candidates.
 *
 * Order: the authors' total order, by time; at equal times the lower disk
 * P first; for the same P the wall first, then the lower Q.  Each thread's
 * candidates are sorted in parallel, then merged.
 *
 * Acceptance: greedily in that order, a candidate whose disks are both
 * still free this step.  The greedy pass is sequential by definition; its
 * parallel formulation: a candidate that comes first among the live
 * candidates of each of its disks is accepted by the greedy pass too
 * (nothing earlier can take its disks), so each round accepts every such
 * candidate at once, in parallel, then drops the candidates that touch a
 * disk just taken.  Rounds repeat until none is live.  This yields exactly
 * the greedy set (the greedy set of a fixed edge order is the unique set
 * built by repeatedly taking locally first edges), for any thread count.
 * Measured against the sequential pass in docs/performance.md. */
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "ccd.h"
#include "../../engine/mem.h"
#include "../../engine/tstats.h"

int ccd_cand_cmp(const ccand *a, const ccand *b)
{
    if (a->t != b->t)
        return a->t < b->t ? -1 : 1;
    if (a->p != b->p)
        return a->p < b->p ? -1 : 1;
    return (a->q > b->q) - (a->q < b->q); /* the wall (q = -1) first */
}

/* a before b in the total order (ccd_cand_cmp, inlined for the sort). */
static inline int cand_before(const ccand *a, const ccand *b)
{
    if (a->t != b->t)
        return a->t < b->t;
    if (a->p != b->p)
        return a->p < b->p;
    return a->q < b->q;
}

/* Insertion sort of c[0, n): the short runs of the merge sort. */
static void insertion_sort(ccand *c, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        ccand v = c[i];
        size_t j = i;
        for (; j > 0 && cand_before(&v, &c[j - 1]); j--)
            c[j] = c[j - 1];
        c[j] = v;
    }
}

/* Merge the sorted runs a[0, na) and b[0, nb) into out. */
static void merge(const ccand *a, size_t na, const ccand *b, size_t nb, ccand *out)
{
    size_t i = 0, j = 0, o = 0;
    while (i < na && j < nb)
        out[o++] = cand_before(&b[j], &a[i]) ? b[j++] : a[i++];
    while (i < na)
        out[o++] = a[i++];
    while (j < nb)
        out[o++] = b[j++];
}

/* Sort c[0, n) through scratch tmp[0, n): runs of 16 by insertion, then
 * bottom-up merges (qsort's callback per comparison cost a tenth of the
 * step on the 1000-disk scene; the order is total, so any sort gives the
 * same result). */
static void sort_cands(ccand *c, ccand *tmp, size_t n)
{
    enum { RUN = 16 };
    for (size_t i = 0; i < n; i += RUN)
        insertion_sort(c + i, n - i < RUN ? n - i : RUN);
    ccand *from = c, *to = tmp;
    for (size_t w = RUN; w < n; w *= 2) {
        for (size_t i = 0; i < n; i += 2 * w) {
            size_t na = n - i < w ? n - i : w;
            size_t nb = n - i - na < w ? n - i - na : w;
            merge(from + i, na, from + i + na, nb, to + i);
        }
        ccand *t = from;
        from = to, to = t;
    }
    if (from != c)
        memcpy(c, from, n * sizeof *c);
}

/* The pair candidates among the first n of c[]. */
size_t ccd_pair_count(const ccand *c, size_t n)
{
    size_t pairs = 0;
    for (size_t k = 0; k < n; k++)
        pairs += c[k].q >= 0;
    return pairs;
}

int ccd_order(psim_sim *e, cmodel *m)
{
    size_t total = 0, *off = m->off, *head = m->head;
    for (int t = 0; t < m->nlists; t++) {
        off[t] = total;
        total += m->lists[t].n;
    }
    if (psim_reserve((void **)&m->all.c, &m->all.cap, total + 1, sizeof *m->all.c))
        return -1;
    /* each list sorted through its own part of `all` (filled by the merge
     * only afterwards) */
#pragma omp parallel for schedule(dynamic, 1) num_threads(e->threads)
    for (int t = 0; t < m->nlists; t++) {
        double t0 = psim_now();
        sort_cands(m->lists[t].c, m->all.c + off[t], m->lists[t].n);
        psim_tstat_add(e->tstats, CPHASE_ORDER, psim_now() - t0, 1, m->lists[t].n);
    }
    /* k-way merge of the sorted lists (k = threads) */
    int k = m->nlists;
    memset(head, 0, (size_t)k * sizeof *head);
    for (size_t o = 0; o < total; o++) {
        int best = -1;
        for (int t = 0; t < k; t++)
            if (head[t] < m->lists[t].n &&
                (best < 0 || cand_before(&m->lists[t].c[head[t]],
                                         &m->lists[best].c[head[best]])))
                best = t;
        m->all.c[o] = m->lists[best].c[head[best]++];
    }
    m->all.n = total;
    return 0;
}

/* Over ranks: every rank's sorted candidates to every rank, merged into
 * `all` in the total order.  Each rank found those of its own share of
 * the detection's tasks, each candidate on exactly one rank, from the
 * same state (the store is the same on every rank, in the same order, so
 * the places sp, sq hold on every rank): the merge is the candidates of
 * one process in its order.  A rank that failed this step (fail) sends
 * none; the others' step is then of no use, and the engine ends it on
 * every rank (psim_dist_poststep). */
void ccd_gather(psim_sim *e, cmodel *m, int fail)
{
    const int R = m->ranks;
    const size_t n = fail ? 0 : m->all.n;
    size_t *rbytes = calloc((size_t)R, sizeof *rbytes);
    if (!rbytes)
        psim_dist_out_of_memory("the candidates");
    void *recv = NULL;
    psim_engine_share(e, m->all.c, n * sizeof *m->all.c, &recv, rbytes);
    const ccand *c = recv;
    size_t total = 0;
    for (int q = 0; q < R; q++)
        total += rbytes[q] / sizeof *c;
    size_t *at = calloc((size_t)R + 1, sizeof *at), *head = calloc((size_t)R, sizeof *head);
    if (!at || !head || psim_reserve((void **)&m->all.c, &m->all.cap, total + 1, sizeof *m->all.c))
        psim_dist_out_of_memory("the candidates");
    for (int q = 0; q < R; q++) {   /* rank q's run: [at[q], at[q + 1]) of recv */
        at[q + 1] = at[q] + rbytes[q] / sizeof *c;
        head[q] = at[q];
    }
    for (size_t o = 0; o < total; o++) {   /* R-way merge */
        int best = -1;
        for (int q = 0; q < R; q++)
            if (head[q] < at[q + 1] && (best < 0 || cand_before(&c[head[q]], &c[head[best]])))
                best = q;
        m->all.c[o] = c[head[best]++];
    }
    m->all.n = total;
    free(at), free(head), free(recv), free(rbytes);
}

/* The greedy pass, sequential. */
static void accept_seq(cmodel *m)
{
    m->acc.n = 0;
    for (size_t k = 0; k < m->all.n; k++) {
        const ccand *c = &m->all.c[k];
        if (m->busy[c->sp] || (c->q >= 0 && m->busy[c->sq]))
            continue;
        m->busy[c->sp] = 1;
        if (c->q >= 0)
            m->busy[c->sq] = 1;
        m->acc.c[m->acc.n++] = *c;
    }
}

static inline void atomic_min_u32(uint32_t *p, uint32_t v)
{
    uint32_t cur = __atomic_load_n(p, __ATOMIC_RELAXED);
    while (v < cur && !__atomic_compare_exchange_n(p, &cur, v, 1, __ATOMIC_RELAXED,
                                                   __ATOMIC_RELAXED))
        ;
}

/* The same set in parallel rounds of locally first candidates. */
static uint64_t accept_par(psim_sim *e, cmodel *m)
{
    const size_t n = m->all.n;
    const ccand *c = m->all.c;
    uint64_t rounds = 0;
    int more = 1;
    memset(m->live, 1, n);
    /* a chain of candidates, each after the one before it, takes a round
     * a candidate: a poll a round (of n >= PAR_ACCEPT_MIN candidates) */
    while (more && !psim_poll(e, 0)) {
        rounds++;
        more = 0;
#pragma omp parallel num_threads(e->threads)
        {
#pragma omp for schedule(static)
            for (size_t k = 0; k < n; k++) {   /* a disk may be in several: atomic */
                __atomic_store_n(&m->best[c[k].sp], UINT32_MAX, __ATOMIC_RELAXED);
                if (c[k].q >= 0)
                    __atomic_store_n(&m->best[c[k].sq], UINT32_MAX, __ATOMIC_RELAXED);
            }
#pragma omp for schedule(static)
            for (size_t k = 0; k < n; k++)
                if (m->live[k]) {
                    atomic_min_u32(&m->best[c[k].sp], (uint32_t)k);
                    if (c[k].q >= 0)
                        atomic_min_u32(&m->best[c[k].sq], (uint32_t)k);
                }
#pragma omp for schedule(static)
            for (size_t k = 0; k < n; k++)
                if (m->live[k] && m->best[c[k].sp] == k &&
                    (c[k].q < 0 || m->best[c[k].sq] == k)) {
                    m->busy[c[k].sp] = 1;
                    if (c[k].q >= 0)
                        m->busy[c[k].sq] = 1;
                    m->live[k] = 2; /* accepted */
                }
#pragma omp for schedule(static) reduction(|| : more)
            for (size_t k = 0; k < n; k++)
                if (m->live[k] == 1) {
                    if (m->busy[c[k].sp] || (c[k].q >= 0 && m->busy[c[k].sq]))
                        m->live[k] = 0;
                    else
                        more = 1;
                }
        }
    }
    m->acc.n = 0;
    for (size_t k = 0; k < n; k++)
        if (m->live[k] == 2)
            m->acc.c[m->acc.n++] = c[k];
    return rounds;
}

/* Candidates at or above this count are accepted in parallel rounds when
 * the mode is automatic (measured: docs/performance.md). */
#define PAR_ACCEPT_MIN 65536

int ccd_accept(psim_sim *e, cmodel *m)
{
    const size_t n = m->all.n;
    if (psim_reserve((void **)&m->acc.c, &m->acc.cap, n + 1, sizeof *m->acc.c) ||
        psim_reserve((void **)&m->live, &m->live_cap, n + 1, 1))
        return -1;
    double t0 = psim_now();
    int par = m->accept_mode == CCD_ACCEPT_PAR ||
              (m->accept_mode == CCD_ACCEPT_AUTO && e->threads > 1 && n >= PAR_ACCEPT_MIN);
    uint64_t rounds = 1;
    if (par)
        rounds = accept_par(e, m);
    else
        accept_seq(m);
    psim_tstat_add(e->tstats, CPHASE_ACCEPT, psim_now() - t0, rounds, n);
    /* over ranks every rank accepts the same: rank 0 counts (the run's
     * counters are summed over the ranks) */
    if (m->rank == 0)
        e->stats.counter[CC_ACCEPT_ROUNDS] += rounds;
    return 0;
}
