/* Candidate detection: every wall hit and every pair time of impact in
 * [0, 1] of the step, found in parallel.
 *
 * Cells are wider than 2r plus the largest displacement of two disks (with
 * a margin for round-off), so a pair that can be a candidate lies in the
 * same or adjacent cells.  Pairs are pruned by their swept boxes (the box a
 * disk sweeps during the step, grown by r and the margin): each cell's
 * disks are sorted by the left edge of their box ("rows": the boxes in
 * that order), and a sweep along x looks only at pairs whose boxes overlap
 * in x.
 *
 * Small cells (slow disks: O(N) work) sweep within the cell and into its
 * four forward neighbours, testing the pairs whose boxes overlap.  Big
 * cells (fast disks: on the generator's scenes every disk crosses
 * 1/8..1/4 of the box per step and the grid is one cell) are cut into
 * bands along y about 1.3 mean box heights high; each row is copied, with
 * its disk, into every band its box meets, and a pair is looked at only in
 * the band of the larger of its boxes' bottom edges, which holds both boxes
 * when they overlap.  Inside a band the sweep runs over blocks of 4
 * entries with vector arithmetic: the rules' discriminant for every lane,
 * and the box filter and the exact rule only for the rare lanes where it
 * is positive.
 *
 * The pruning is conservative: the box left edges are rounded down to
 * float (32-bit sort keys; the boxes only grow), and every pair whose boxes
 * overlap is decided by the exact rule (rules.h, called as before on the
 * store's doubles); the kernel skips only pairs whose discriminant,
 * computed with the same IEEE operations in the same order, is not
 * positive, which the rule rejects too.  pair_tests counts discriminants
 * computed. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "ccd.h"
#include "rules.h"
#include "../../engine/mem.h"
#include "../../engine/task.h"
#include "../../engine/tstats.h"

/* Cells with at least this many disks are cut into bands. */
#define BIG_CELL 64
/* Cells with more disks than this are radix sorted. */
#define RADIX_MIN 48
/* Band height in mean box heights: 1.2..1.6 minimise the pairs looked at
 * on the generator's scenes (fewer bands: more x-overlapping pairs in
 * each; more: each box copied into more bands). */
#define BAND_SPAN 1.3
/* At most this many band entries per disk: fewer bands when boxes are
 * tall against the cell. */
#define BAND_ENTRIES_MAX 4
/* At least this many disks per band. */
#define BAND_MIN_ROWS 16

int ccd_list_push(clist *l, const ccand *c)
{
    if (l->n == l->cap && psim_reserve((void **)&l->c, &l->cap, l->n + 1, sizeof *l->c))
        return -1;
    l->c[l->n++] = *c;
    return 0;
}

/* ---- rows: keys, sort, gather ------------------------------------------ */

/* Largest float not above v.  Box left edges are rounded down to it: the
 * boxes only grow (pruning stays conservative), and sort on 32-bit keys. */
static inline float round_down(double v)
{
    float f = (float)v;
    /* when f is above v, one float step down, without a branch (it would
     * mispredict half the time): the bits go down by one for a positive f,
     * up by one for a negative f (-0 included: v < 0 rounds to -0, never
     * to +0) */
    uint32_t u, down = (double)f > v;
    memcpy(&u, &f, sizeof u);
    u += down * ((u >> 31) * 2u - 1u);
    memcpy(&f, &u, sizeof f);
    return f;
}

/* Left edge of the swept box of a disk at x moving by vx, grown by g. */
static inline double left_edge(double x, double vx, double g)
{
    double x1 = x + vx;
    return (double)round_down((x < x1 ? x : x1) - g);
}

/* An unsigned key in the order of the float left edge. */
static inline uint32_t edge_key(double x, double vx, double g)
{
    float f = (float)left_edge(x, vx, g);
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u ^ (-(u >> 31) | 0x80000000u); /* negative: all bits flipped */
}

/* Stable insertion sort of n (key, place) pairs by key: small cells. */
static void insertion_sort(uint32_t *key, uint32_t *ord, uint32_t n)
{
    for (uint32_t i = 1; i < n; i++) {
        uint32_t k = key[i], o = ord[i], j = i;
        for (; j > 0 && key[j - 1] > k; j--) {
            key[j] = key[j - 1];
            ord[j] = ord[j - 1];
        }
        key[j] = k;
        ord[j] = o;
    }
}

/* Stable LSD radix sort of n (key, place) pairs by key, bytes at a time,
 * through the scratch arrays key2, ord2; bytes all keys share are
 * skipped (the high bytes, in a cell). */
static void radix_sort(uint32_t *key, uint32_t *ord, uint32_t *key2, uint32_t *ord2,
                       uint32_t n)
{
    uint32_t cnt[4][256];
    memset(cnt, 0, sizeof cnt);
    for (uint32_t i = 0; i < n; i++)
        for (int d = 0; d < 4; d++)
            cnt[d][(key[i] >> (8 * d)) & 255]++;
    uint32_t *k0 = key, *o0 = ord, *k1 = key2, *o1 = ord2;
    for (int d = 0; d < 4; d++) {
        if (cnt[d][(key[0] >> (8 * d)) & 255] == n)
            continue;
        uint32_t sum = 0;
        for (int v = 0; v < 256; v++) {
            uint32_t c = cnt[d][v];
            cnt[d][v] = sum;
            sum += c;
        }
        for (uint32_t i = 0; i < n; i++) {
            uint32_t at = cnt[d][(k0[i] >> (8 * d)) & 255]++;
            k1[at] = k0[i];
            o1[at] = o0[i];
        }
        uint32_t *t = k0;
        k0 = k1, k1 = t;
        t = o0, o0 = o1, o1 = t;
    }
    if (k0 != key) {
        memcpy(key, k0, n * sizeof *key);
        memcpy(ord, o0, n * sizeof *ord);
    }
}

/* The float left edge back from its key. */
static inline double key_edge(uint32_t key)
{
    uint32_t u = key ^ (((key >> 31) - 1u) | 0x80000000u);
    float f;
    memcpy(&f, &u, sizeof f);
    return (double)f;
}

/* Row k of the sorted boxes from store place i (the disks themselves
 * stay in the store: copying them costs more than the indirection saves
 * on small cells; the bands copy theirs). */
static inline void gather_row(cmodel *m, const psim_store *s, uint32_t k, uint32_t i,
                              double g)
{
    double x = s->x[i], y = s->y[i], x1 = x + s->vx[i], y1 = y + s->vy[i];
    m->sx0[k] = key_edge(m->key[k]); /* left_edge(x, vx, g), sorted with it */
    m->sx1[k] = (x < x1 ? x1 : x) + g;
    m->sy0[k] = (y < y1 ? y : y1) - g;
    m->sy1[k] = (y < y1 ? y1 : y) + g;
}

/* Cell c's rows, in left-edge order, and its widest box. */
static void prepare_cell(cmodel *m, const psim_store *s, const psim_grid *g, uint32_t c)
{
    const double grow = m->r + m->margin;
    uint32_t a = g->cellstart[c], b = g->cellstart[c + 1], n = b - a;
    for (uint32_t k = a; k < b; k++) {
        m->ord[k] = k;
        m->key[k] = edge_key(s->x[k], s->vx[k], grow);
    }
    if (n > RADIX_MIN)
        radix_sort(m->key + a, m->ord + a, m->key2 + a, m->ord2 + a, n);
    else
        insertion_sort(m->key + a, m->ord + a, n);
    double w = 0;
    for (uint32_t k = a; k < b; k++) {
        gather_row(m, s, k, m->ord[k], grow);
        w = m->sx1[k] - m->sx0[k] > w ? m->sx1[k] - m->sx0[k] : w;
    }
    m->wmax[c] = w;
}

static void prepare_cells(psim_sim *e, cmodel *m)
{
    const psim_grid *g = &e->grid;
#pragma omp parallel num_threads(e->threads)
    {
        double t0 = psim_now();
        uint64_t done = 0;
#pragma omp for schedule(dynamic, 64)
        for (uint32_t c = 0; c < g->ncells; c++) {
            prepare_cell(m, &e->st, g, c);
            done += g->cellstart[c + 1] - g->cellstart[c];
        }
        psim_tstat_add(e->tstats, CPHASE_DETECT, psim_now() - t0, 0, done);
    }
}

/* ---- bands of big cells ------------------------------------------------ */

void ccd_bands_free(cbands *b)
{
    psim_free(b->x0), psim_free(b->x1), psim_free(b->y0), psim_free(b->y1);
    psim_free(b->first), psim_free(b->x), psim_free(b->y), psim_free(b->vx);
    psim_free(b->vy), psim_free(b->row);
    psim_free(b->band), psim_free(b->plan), psim_free(b->mine), psim_free(b->put);
    memset(b, 0, sizeof *b);
}

/* Room for need entries in every array (contents are rebuilt each step,
 * so nothing is copied; grows by half again to settle quickly). */
static int bands_reserve(cbands *b, size_t need)
{
    if (need <= b->cap && b->x0)
        return 0;
    size_t cap = need + need / 2 + 64, d = cap * sizeof(double);
    psim_free(b->x0), psim_free(b->x1), psim_free(b->y0), psim_free(b->y1);
    psim_free(b->first), psim_free(b->x), psim_free(b->y), psim_free(b->vx);
    psim_free(b->vy), psim_free(b->row);
    b->x0 = psim_alloc(d), b->x1 = psim_alloc(d), b->y0 = psim_alloc(d);
    b->y1 = psim_alloc(d), b->first = psim_alloc(d), b->x = psim_alloc(d);
    b->y = psim_alloc(d), b->vx = psim_alloc(d), b->vy = psim_alloc(d);
    b->row = psim_alloc(cap * sizeof *b->row);
    b->cap = cap;
    if (b->x0 && b->x1 && b->y0 && b->y1 && b->first && b->x && b->y && b->vx && b->vy &&
        b->row)
        return 0;
    b->cap = 0;
    return -1;
}

/* Band of height y in plan p: monotone in y, so the band of the larger of
 * two bottom edges is the larger of their bands. */
static inline int band_of(const cplan *p, double y)
{
    double f = (y - p->ylo) * p->invh;
    if (!(f > 0))
        return 0;
    return f >= p->nb ? p->nb - 1 : (int)f;
}

static size_t plan_entries(const cmodel *m, const cplan *p, uint32_t a, uint32_t b)
{
    size_t cnt = 0;
    for (uint32_t k = a; k < b; k++)
        cnt += (size_t)(band_of(p, m->sy1[k]) - band_of(p, m->sy0[k]) + 1);
    return cnt;
}

/* Bands of big cell c: about BAND_SPAN mean box heights each, halved in
 * number while the entries would exceed BAND_ENTRIES_MAX per disk (bounded
 * by the tallest box, counted only when that bound is not enough). */
static cplan plan_cell(const cmodel *m, const psim_grid *g, uint32_t c)
{
    uint32_t a = g->cellstart[c], b = g->cellstart[c + 1], n = b - a;
    double ylo = INFINITY, yhi = -INFINITY, hsum = 0, hmax = 0;
    for (uint32_t k = a; k < b; k++) {
        double h = m->sy1[k] - m->sy0[k];
        ylo = m->sy0[k] < ylo ? m->sy0[k] : ylo;
        yhi = m->sy1[k] > yhi ? m->sy1[k] : yhi;
        hsum += h;
        hmax = h > hmax ? h : hmax;
    }
    double want = (yhi - ylo) / (BAND_SPAN * hsum / n);
    int cap = (int)(n / BAND_MIN_ROWS);
    cplan p = {.cell = c, .nb = want >= 1 ? (want < cap ? (int)ceil(want) : cap) : 1,
               .ylo = ylo};
    for (;;) {
        p.invh = p.nb > 1 ? p.nb / (yhi - ylo) : 0;
        /* a box meets at most floor(h invh) + 2 bands (+1 for round-off) */
        if (p.nb == 1 || hmax * p.invh + 3 <= BAND_ENTRIES_MAX ||
            plan_entries(m, &p, a, b) <= (size_t)BAND_ENTRIES_MAX * n)
            return p;
        p.nb = (p.nb + 1) / 2;
    }
}

/* Copy row k (its box, and its disk from the store) into entry at e of
 * its band (first: its first band). */
static inline void put_entry(cbands *B, const cmodel *m, const psim_store *s, size_t e,
                             uint32_t k, double first)
{
    uint32_t i = m->ord[k];
    B->x0[e] = m->sx0[k], B->x1[e] = m->sx1[k], B->y0[e] = m->sy0[k], B->y1[e] = m->sy1[k];
    B->first[e] = first;
    B->x[e] = s->x[i], B->y[e] = s->y[i], B->vx[e] = s->vx[i], B->vy[e] = s->vy[i];
    B->row[e] = k;
}

/* Rows no box overlaps, after a band's entries. */
static void put_sentinels(cbands *B, size_t e)
{
    for (size_t u = e; u < e + CCD_PAD; u++) {
        B->x0[u] = INFINITY, B->x1[u] = -INFINITY, B->y0[u] = INFINITY, B->y1[u] = -INFINITY;
        B->first[u] = -1;
        B->x[u] = B->y[u] = B->vx[u] = B->vy[u] = 0;
        B->row[u] = 0;
    }
}

/* The bands are laid out and filled by every thread of the detection,
 * each over its own contiguous part of every big cell's rows (part t of
 * T): each counts the entries its rows put in each band, the counts give
 * each part its place in every band (the parts in row order), and each
 * part copies its rows there.  A band's entries are thus in row order
 * whatever the number of parts. */

/* Rows [*k0, *k1) of plan p: part t of T. */
static void part_rows(const psim_grid *g, const cplan *p, int t, int T, uint32_t *k0,
                      uint32_t *k1)
{
    uint32_t a = g->cellstart[p->cell], n = g->cellstart[p->cell + 1] - a;
    *k0 = a + (uint32_t)psim_part_lo(n, T, t);
    *k1 = a + (uint32_t)psim_part_lo(n, T, t + 1);
}

/* Part t's rows: each row's first and last band (kept in the sort's
 * scratch arrays key2, ord2, free by now), and the entries they put in
 * each band, counted in put's row t.  Returns the rows. */
static uint64_t count_part(cmodel *m, const psim_grid *g, int t, int T)
{
    uint64_t rows = 0;
    cbands *B = &m->bands;
    uint32_t *put = B->put + (size_t)t * B->nband;
    memset(put, 0, B->nband * sizeof *put);
    for (size_t i = 0; i < B->nplan; i++) {
        const cplan *p = &B->plan[i];
        uint32_t k0, k1;
        part_rows(g, p, t, T, &k0, &k1);
        rows += k1 - k0;
        for (uint32_t k = k0; k < k1; k++) {
            uint32_t j0 = (uint32_t)band_of(p, m->sy0[k]), j1 = (uint32_t)band_of(p, m->sy1[k]);
            m->key2[k] = j0;
            m->ord2[k] = j1;
            for (uint32_t j = p->band0 + j0; j <= p->band0 + j1; j++)
                put[j]++;
        }
    }
    return rows;
}

/* Each band's place (its entries, then a pad) and each part's place in
 * it, from the T parts' counts.  Returns -1 when out of memory. */
static int lay_out(cmodel *m, int T)
{
    cbands *B = &m->bands;
    size_t at = 0;
    for (size_t i = 0; i < B->nplan; i++)
        for (int j = 0; j < B->plan[i].nb; j++) {
            size_t b = B->plan[i].band0 + (size_t)j;
            B->band[b] = (cband){(uint32_t)at, 0, (double)j};
            for (int t = 0; t < T; t++) {
                uint32_t cnt = B->put[(size_t)t * B->nband + b];
                B->put[(size_t)t * B->nband + b] = (uint32_t)at;
                at += cnt;
                if (at > UINT32_MAX - CCD_PAD)
                    return -1;
            }
            B->band[b].e1 = (uint32_t)at;
            at += CCD_PAD;
        }
    B->nentry = at;
    if (bands_reserve(B, at) || psim_reserve((void **)&B->mine, &B->mine_cap, B->nband + 1, 1))
        return -1;
    return 0;
}

/* Part t's rows copied into their bands (over ranks, into the bands
 * marked in B->mine alone, when `mine`), and the pads after the bands of
 * part t. */
static void fill_part(cmodel *m, const psim_store *s, const psim_grid *g, int mine, int t,
                      int T)
{
    cbands *B = &m->bands;
    uint32_t *put = B->put + (size_t)t * B->nband;
    for (size_t i = 0; i < B->nplan; i++) {
        const cplan *p = &B->plan[i];
        const uint8_t *my = mine ? B->mine + p->band0 : NULL;
        uint32_t k0, k1, *at = put + p->band0;
        part_rows(g, p, t, T, &k0, &k1);
        for (uint32_t k = k0; k < k1; k++)
            for (uint32_t j = m->key2[k]; j <= m->ord2[k]; j++) {
                uint32_t e = at[j]++;
                if (!my || my[j])
                    put_entry(B, m, s, e, k, (double)m->key2[k]);
            }
    }
    for (size_t b = psim_part_lo(B->nband, T, t); b < psim_part_lo(B->nband, T, t + 1); b++)
        if (!mine || B->mine[b])
            put_sentinels(B, B->band[b].e1);
}

/* The plans of every big cell's bands, and room to count their entries
 * for T parts.  Returns -1 when out of memory. */
static int plan_bands(psim_sim *e, cmodel *m, int T)
{
    const psim_grid *g = &e->grid;
    cbands *B = &m->bands;
    B->nplan = B->nband = 0;
    for (uint32_t c = 0; c < g->ncells; c++) {
        if (g->cellstart[c + 1] - g->cellstart[c] < BIG_CELL)
            continue;
        cplan p = plan_cell(m, g, c);
        if (psim_reserve((void **)&B->plan, &B->plan_cap, B->nplan + 1, sizeof *B->plan) ||
            psim_reserve((void **)&B->band, &B->band_cap, B->nband + (size_t)p.nb,
                         sizeof *B->band))
            return -1;
        p.band0 = (uint32_t)B->nband;
        B->plan[B->nplan++] = p;
        B->nband += (size_t)p.nb;
    }
    return psim_reserve((void **)&B->put, &B->put_cap, (size_t)T * B->nband + 1, sizeof *B->put);
}


/* ---- pair tests ---------------------------------------------------------- */

typedef struct detect_ctx {
    const psim_sim *e;      /* for polls (a stop asked ends the tasks early) */
    cmodel *m;
    const psim_store *s;
    const psim_grid *g;
    double L, r;
    psim_thread_stats *ts;
    uint64_t tests;         /* pairs with overlapping boxes (added atomically) */
    int graph;              /* tasks (more than one thread), else direct calls */
    /* over ranks: this rank's share of each kind of task (cells, slices,
     * bands), by weight; `count` a pass that only sums the weights */
    int rank, ranks, count;
    double total[3], done[3];
} detect_ctx;

/* The exact rule on rows a, b (their boxes overlap), lower id first. */
static inline void test_rows(detect_ctx *c, uint32_t a, uint32_t b, clist *out)
{
    const psim_store *s = c->s;
    uint32_t i = c->m->ord[a], j = c->m->ord[b];
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
}

/* Wall candidates of store places [i0, i1). */
static void detect_walls(detect_ctx *c, uint32_t i0, uint32_t i1, clist *out)
{
    const psim_store *s = c->s;
    for (uint32_t i = i0; i < i1; i++) {
        ccand w;
        if (ccd_wall_time(s->x[i], s->y[i], s->vx[i], s->vy[i], 1.0, c->L, c->r, &w.t)) {
            w.p = s->id[i];
            w.q = -1;
            w.sp = i;
            w.sq = UINT32_MAX;
            if (ccd_list_push(out, &w))
                c->m->oom = 1;
        }
    }
}

/* Pairs of rows [k0, k1) with the later rows of their (small) cell, up to
 * a1: the sweep, with the y filter gathered without a branch (a
 * data-dependent branch here mispredicts often). */
static uint64_t sweep_cell(detect_ctx *c, uint32_t k0, uint32_t k1, uint32_t a1, clist *out)
{
    const cmodel *m = c->m;
    const double *restrict sx0 = m->sx0, *restrict sy0 = m->sy0, *restrict sy1 = m->sy1;
    uint64_t tests = 0;
    for (uint32_t a = k0; a < k1; a++) {
        const double ya0 = sy0[a], ya1 = sy1[a], xa1 = m->sx1[a];
        uint32_t buf[256], nb = 0;
        for (uint32_t b = a + 1; b < a1 && sx0[b] <= xa1; b++) {
            buf[nb] = b;
            nb += (sy0[b] <= ya1) & (ya0 <= sy1[b]);
            if (nb == 256) {
                for (uint32_t u = 0; u < nb; u++)
                    test_rows(c, a, buf[u], out);
                tests += nb;
                nb = 0;
            }
        }
        for (uint32_t u = 0; u < nb; u++)
            test_rows(c, a, buf[u], out);
        tests += nb;
    }
    return tests;
}

/* Pairs of rows [k0, k1) of cell `cell` with the four forward neighbour
 * cells. */
static uint64_t sweep_neighbours(detect_ctx *c, uint32_t cell, uint32_t k0, uint32_t k1,
                                 clist *out)
{
    const psim_grid *g = c->g;
    const cmodel *m = c->m;
    uint64_t tests = 0;
    int cx = g->cell_x[cell], cy = g->cell_y[cell];
    for (int d = 0; d < 4; d++) {
        int nx, ny;
        uint32_t nb = psim_grid_forward(g, cx, cy, d, &nx, &ny);
        if (nb == UINT32_MAX)
            continue;
        uint32_t b0 = g->cellstart[nb], b1 = g->cellstart[nb + 1];
        if (b0 == b1)
            continue;
        for (uint32_t a = k0; a < k1; a++) {
            /* boxes of nb are at most wmax[nb] wide: those starting before
             * sx0[a] - wmax[nb] end before a's box starts */
            for (uint32_t b = ccd_lower(m->sx0, b0, b1, m->sx0[a] - m->wmax[nb]);
                 b < b1 && m->sx0[b] <= m->sx1[a]; b++)
                if (m->sx1[b] >= m->sx0[a] && m->sy0[b] <= m->sy1[a] &&
                    m->sy0[a] <= m->sy1[b]) {
                    test_rows(c, a, b, out);
                    tests++;
                }
        }
    }
    return tests;
}

/* Lanes of 2 doubles (GCC vector extensions: one SSE2 operation each on
 * x86-64; 4-wide vectors were lowered to scalar compares without AVX and
 * ran slower), loaded from 8-byte aligned doubles, which vector types may
 * alias. */
typedef double v2d __attribute__((vector_size(16)));
typedef double v2du __attribute__((vector_size(16), aligned(8)));
typedef long long v2l __attribute__((vector_size(16)));
#define LOAD2(p) ((v2d)(*(const v2du *)(p)))
#define SPLAT(s) ((v2d){(s), (s)})

/* Entry a, splat across lanes, against 2 lanes at b: "in" when the boxes
 * overlap and the pair's bottom-edge band is this one (own: a's first band
 * is; k: this band), and D > 0 for the rules' discriminant D. */
typedef struct lane_row {
    v2d x1, y0, y1, x, y, vx, vy, k, r4;
    v2l own;
} lane_row;

static inline v2l lane_in(const cbands *B, const lane_row *q, uint32_t b)
{
    return (LOAD2(B->x0 + b) <= q->x1) & (LOAD2(B->y0 + b) <= q->y1) &
           (q->y0 <= LOAD2(B->y1 + b)) & (q->own | (LOAD2(B->first + b) == q->k));
}

/* D of ccd_pair_time, the same operations in the same order. */
static inline v2l lane_d_positive(const cbands *B, const lane_row *q, uint32_t b)
{
    v2d dx = LOAD2(B->x + b) - q->x, dy = LOAD2(B->y + b) - q->y;
    v2d dvx = LOAD2(B->vx + b) - q->vx, dvy = LOAD2(B->vy + b) - q->vy;
    v2d A = dvx * dvx + dvy * dvy;
    v2d Bq = SPLAT(2.0) * (dx * dvx + dy * dvy);
    v2d C = dx * dx + dy * dy - q->r4;
    v2d D = Bq * Bq - SPLAT(4.0) * A * C;
    return D > SPLAT(0.0);
}

/* Lane l alone, for the rare blocks with a hit: is it "in" and a hit? */
static int lane_hit(const cbands *B, const lane_row *q, uint32_t l)
{
    v2l in = lane_in(B, q, l) & lane_d_positive(B, q, l);
    return in[0] != 0;
}

/* Entry a of band bd against the entries after it, 4 at a time.  Only the
 * rules' discriminant D is computed for every lane, exactly as
 * ccd_pair_time computes it (same operations, same order, no contraction;
 * b - a instead of a - b only flips signs, exactly), so a lane with
 * D <= 0 is one the rule rejects; the rare lanes with D > 0 then pass the
 * box filter ("in") before the exact rule.  Every pair whose boxes overlap
 * is thus decided by the rule (the band sweep reaches every such pair),
 * and the box filter costs nothing on the common path.  Sentinel rows past
 * the band are never "in" and end the sweep.  Returns the lanes computed. */
static uint64_t band_row(detect_ctx *c, const cband *bd, uint32_t a, clist *out)
{
    const cbands *B = &c->m->bands;
    const double xa1 = B->x1[a], rr4 = 4 * c->r * c->r; /* as the rule: (4 r) r */
    const long long o = -(long long)(B->first[a] == bd->k);
    const lane_row q = {SPLAT(xa1), SPLAT(B->y0[a]), SPLAT(B->y1[a]), SPLAT(B->x[a]),
                        SPLAT(B->y[a]), SPLAT(B->vx[a]), SPLAT(B->vy[a]), SPLAT(bd->k),
                        SPLAT(rr4), (v2l){o, o}};
    uint64_t lanes = 0;
    for (uint32_t b = a + 1; b < bd->e1; b += 4) {
        lanes += 4;
        v2l hit = lane_d_positive(B, &q, b) | lane_d_positive(B, &q, b + 2);
        if (hit[0] | hit[1])
            for (uint32_t l = b; l < b + 4; l++)
                if (lane_hit(B, &q, l))
                    test_rows(c, B->row[a], B->row[l], out);
        if (B->x0[b + 3] > xa1)
            break;
    }
    return lanes;
}

/* ---- tasks --------------------------------------------------------------- */

/* A task's pair tests so far, `tests` (`polled` of them polled): a poll
 * every PSIM_POLL_WORK of them; nonzero when a stop was asked. */
static inline int poll_tests(const detect_ctx *c, uint64_t tests, uint64_t *polled)
{
    if (tests - *polled < PSIM_POLL_WORK)
        return 0;
    uint64_t add = tests - *polled;
    *polled = tests;
    return psim_poll(c->e, add);
}

/* A task's tests to the step's (those not polled to the poll count). */
static void add_tests(detect_ctx *c, uint64_t tests, uint64_t polled)
{
#pragma omp atomic
    c->tests += tests;
    if (tests > polled)
        psim_poll_add(c->e, tests - polled);
}

/* Walls and pairs of whole small cells [c0, c1). */
static void task_cells(detect_ctx *c, uint32_t c0, uint32_t c1)
{
    double t0 = psim_now();
    const psim_grid *g = c->g;
    clist *out = &c->m->lists[omp_get_thread_num()];
    uint64_t tests = 0, polled = 0;
    for (uint32_t cc = c0; cc < c1; cc++) {
        uint32_t a = g->cellstart[cc], b = g->cellstart[cc + 1];
        detect_walls(c, a, b, out);
        tests += sweep_cell(c, a, b, b, out) + sweep_neighbours(c, cc, a, b, out);
        if (poll_tests(c, tests, &polled))
            break;
    }
    add_tests(c, tests, polled);
    psim_tstat_add(c->ts, CPHASE_DETECT, psim_now() - t0, 1,
                   g->cellstart[c1] - g->cellstart[c0]);
}

/* Walls and neighbour pairs of rows [k0, k1) of a big cell (its own
 * pairs are the bands'), SLICE_ROWS rows at a time between polls (the
 * candidates' order in the lists does not matter: they are sorted into
 * the rules' total order). */
#define SLICE_ROWS 256
static void task_slice(detect_ctx *c, uint32_t cell, uint32_t k0, uint32_t k1)
{
    double t0 = psim_now();
    clist *out = &c->m->lists[omp_get_thread_num()];
    detect_walls(c, k0, k1, out);
    uint64_t tests = 0, polled = 0;
    for (uint32_t k = k0; k < k1; k += SLICE_ROWS) {
        tests += sweep_neighbours(c, cell, k, k1 - k > SLICE_ROWS ? k + SLICE_ROWS : k1, out);
        if (poll_tests(c, tests, &polled))
            break;
    }
    add_tests(c, tests, polled);
    psim_tstat_add(c->ts, CPHASE_DETECT, psim_now() - t0, 1, k1 - k0);
}

/* Entries [a0, a1) of band bd against the rest of the band. */
static void task_band(detect_ctx *c, const cband *bd, uint32_t a0, uint32_t a1)
{
    double t0 = psim_now();
    clist *out = &c->m->lists[omp_get_thread_num()];
    uint64_t tests = 0, polled = 0;
    for (uint32_t a = a0; a < a1; a++) {
        tests += band_row(c, bd, a, out);
        if (poll_tests(c, tests, &polled))
            break;
    }
    add_tests(c, tests, polled);
    psim_tstat_add(c->ts, CPHASE_DETECT, psim_now() - t0, 1, a1 - a0);
}

/* The three kinds of detection task (src/engine/task.h). */
PSIM_TASK_SPAWN static void task_spawn_cells(detect_ctx *c, uint32_t f0, uint32_t f1)
{
#pragma omp task firstprivate(c, f0, f1) default(none) if (c->graph)
    task_cells(c, f0, f1);
}

PSIM_TASK_SPAWN static void task_spawn_slice(detect_ctx *c, uint32_t cell, uint32_t k0,
                                             uint32_t k1)
{
#pragma omp task firstprivate(c, cell, k0, k1) default(none) if (c->graph)
    task_slice(c, cell, k0, k1);
}

PSIM_TASK_SPAWN static void task_spawn_band(detect_ctx *c, const cband *bd, uint32_t a0,
                                            uint32_t a1)
{
#pragma omp task firstprivate(c, bd, a0, a1) default(none) if (c->graph)
    task_band(c, bd, a0, a1);
}

/* Whether this rank runs the next task of `kind`, of weight w (the rows
 * or entries it holds; a band's entries weighed by the band's size, as
 * each sweeps the band).  Each kind's tasks, in the order spawn_tasks
 * makes them, are dealt to the ranks in contiguous runs of about equal
 * weight: a task goes to the rank whose share holds its middle.  Every
 * rank deals the same tasks the same way (the state is the same on
 * all), so each task runs on exactly one rank, whole.  In the counting
 * pass no task runs. */
static int share(detect_ctx *c, int kind, double w)
{
    w += 1;   /* no task weighs nothing */
    if (c->count) {
        c->total[kind] += w;
        return 0;
    }
    if (c->ranks == 1)
        return 1;
    double mid = c->done[kind] + w / 2;
    c->done[kind] += w;
    int q = (int)(mid / c->total[kind] * c->ranks);
    return (q < c->ranks ? q : c->ranks - 1) == c->rank;
}

/* Tasks of about `unit` rows or entries: runs of whole small cells, slices
 * of big cells, slices of bands; OpenMP tasks with no dependences
 * (detection only reads the start-of-step state).  Returns their number. */
static uint64_t spawn_tasks(detect_ctx *c, size_t unit)
{
    const psim_grid *g = c->g;
    const cbands *B = &c->m->bands;
    uint64_t tasks = 0;
    uint32_t c0 = 0;
    size_t held = 0;
    for (uint32_t cc = 0; cc <= g->ncells; cc++) {
        size_t cn = cc < g->ncells ? g->cellstart[cc + 1] - g->cellstart[cc] : 0;
        int big = cn >= BIG_CELL;
        if ((cc == g->ncells || held + cn > unit || big) && cc > c0) {
            uint32_t f0 = c0, f1 = cc;
            if (share(c, 0, (double)(g->cellstart[f1] - g->cellstart[f0]))) {
                tasks++;
                task_spawn_cells(c, f0, f1);
            }
            c0 = cc;
            held = 0;
        }
        if (cc == g->ncells)
            break;
        if (!big) {
            held += cn;
            continue;
        }
        uint32_t end = g->cellstart[cc + 1];
        for (uint32_t k = g->cellstart[cc]; k < end; k += (uint32_t)unit) {
            uint32_t cell = cc, k0 = k, k1 = end - k > unit ? k + (uint32_t)unit : end;
            if (share(c, 1, (double)(k1 - k0))) {
                tasks++;
                task_spawn_slice(c, cell, k0, k1);
            }
        }
        c0 = cc + 1;
    }
    for (size_t i = 0; i < B->nband; i++) {
        const cband *bd = &B->band[i];
        const uint32_t end = bd->e1;
        for (uint32_t a = bd->e0; a < end; a += (uint32_t)unit) {
            uint32_t a0 = a, a1 = end - a > unit ? a + (uint32_t)unit : end;
            if (share(c, 2, (double)(a1 - a0) * (double)(end - bd->e0))) {
                tasks++;
                task_spawn_band(c, bd, a0, a1);
            }
        }
    }
    return tasks;
}

/* Over ranks, after the counting pass: the bands this rank sweeps (the
 * same dealing as spawn_tasks', replayed), so that only they are filled. */
static void mark_bands(detect_ctx *c, size_t unit)
{
    cbands *B = &c->m->bands;
    const double done = c->done[2];
    for (size_t i = 0; i < B->nband; i++) {
        const uint32_t e0 = B->band[i].e0, end = B->band[i].e1;
        B->mine[i] = 0;
        for (uint32_t a = e0; a < end; a += (uint32_t)unit) {
            uint32_t a1 = end - a > unit ? a + (uint32_t)unit : end;
            B->mine[i] |= (uint8_t)share(c, 2, (double)(a1 - a) * (double)(end - e0));
        }
    }
    c->done[2] = done;
}

/* Each band's place and each part's in it (T parts), and over ranks,
 * the bands this rank sweeps (a pass that only weighs the tasks first);
 * m->oom set when out of memory. */
static void place_bands(detect_ctx *c, size_t unit, int T)
{
    if (lay_out(c->m, T)) {
        c->m->oom = 1;
        return;
    }
    if (c->count) {
        spawn_tasks(c, unit);
        c->count = 0;
        mark_bands(c, unit);
    }
}

void ccd_detect(psim_sim *e, cmodel *m)
{
    /* sized on regrid; checked here in case the grid changed elsewhere */
    if (psim_reserve((void **)&m->wmax, &m->wmax_cap, e->grid.ncells + 1, sizeof *m->wmax)) {
        m->oom = 1;
        return;
    }
    prepare_cells(e, m);
    if (plan_bands(e, m, e->threads)) {
        m->oom = 1;
        return;
    }
    for (int t = 0; t < m->nlists; t++)
        m->lists[t].n = 0;
    size_t unit = e->st.n / (8 * (size_t)e->threads);
    unit = unit < 256 ? 256 : (unit > 16384 ? 16384 : unit);
    detect_ctx ctx = {e, m, &e->st, &e->grid, m->L, m->r, e->tstats, 0, e->threads > 1,
                      m->rank, m->ranks, m->ranks > 1, {0, 0, 0}, {0, 0, 0}};
    detect_ctx *c = &ctx;
    uint64_t tasks = 0;
    if (c->graph) {
#pragma omp parallel num_threads(e->threads) firstprivate(c) shared(tasks, unit) default(none)
        {
            int t = omp_get_thread_num(), T = omp_get_num_threads();
            double t0 = psim_now();
            uint64_t rows = count_part(c->m, c->g, t, T);
            double busy = psim_now() - t0;
#pragma omp barrier
#pragma omp single
            place_bands(c, unit, T);
            if (!c->m->oom) {
                t0 = psim_now();
                fill_part(c->m, c->s, c->g, c->ranks > 1, t, T);
                psim_tstat_add(c->ts, CPHASE_DETECT, busy + psim_now() - t0, 0, rows);
#pragma omp barrier
#pragma omp single nowait
                tasks = spawn_tasks(c, unit);
            }
        }
        e->stats.counter[CC_TASKS] += tasks;
    } else {
        count_part(m, &e->grid, 0, 1);
        place_bands(c, unit, 1);
        if (!m->oom) {
            fill_part(m, &e->st, &e->grid, m->ranks > 1, 0, 1);
            spawn_tasks(c, unit);   /* one thread: the same calls in order, no tasks */
        }
        e->stats.skipped[CS_GRAPH]++;
    }
    e->stats.counter[CC_PAIR_TESTS] += ctx.tests;
}

/* Wall candidates only (no pair can meet this step): every disk in store
 * order, in static parts, with no grid. */
void ccd_detect_walls(psim_sim *e, cmodel *m)
{
    for (int t = 0; t < m->nlists; t++)
        m->lists[t].n = 0;
    detect_ctx ctx = {e, m, &e->st, NULL, m->L, m->r, e->tstats, 0, 0, m->rank, m->ranks, 0,
                      {0, 0, 0}, {0, 0, 0}};
    detect_ctx *c = &ctx;
    /* over ranks: this rank's part of the store */
    const size_t from = psim_part_lo(e->st.n, m->ranks, m->rank);
    const size_t n = psim_part_lo(e->st.n, m->ranks, m->rank + 1) - from;
#pragma omp parallel num_threads(e->threads) firstprivate(c) default(none) shared(n, from)
    {
        double t0 = psim_now();
        int T = omp_get_num_threads(), k = omp_get_thread_num();
        size_t lo = psim_part_lo(n, T, k), hi = psim_part_lo(n, T, k + 1);
        detect_walls(c, (uint32_t)(from + lo), (uint32_t)(from + hi), &c->m->lists[k]);
        psim_tstat_add(c->ts, CPHASE_DETECT, psim_now() - t0, 1, hi - lo);
    }
}
