/* Verlet pair lists of the force model, built from the engine's sort:
 * cells are wider than the list radius (cutoff + skin), so a particle's
 * neighbours are in its own and the eight adjacent cells.  Each unordered
 * pair is listed once, by the cell that sees the other's cell in its
 * forward half of the 3 x 3 stencil (a half list: half the tests of a
 * full one), in the shell of its distance (force.h).  The order of the
 * pairs does not matter: step.c sums each particle's forces in id order.
 * A tile is listed row by row of cells from "slot rows": each cell's first
 * SLOTS particles copied into fixed slots (empty ones far away), so that a
 * particle is tested against its forward half (20 slots) in a fixed,
 * unrolled loop of SSE2 pairs without a branch (on a CPU with AVX-512:
 * three vectors of eight, the hits of a row compressed into a stage and
 * filed by shell eight at a time; the same lists in another order); the
 * few particles beyond SLOTS in a cell are listed one by one. */
#include <stdlib.h>
#include <string.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "force.h"
#include "../../engine/mem.h"
#include "../../engine/task.h"
#include "../../engine/timer.h"
#include "../../engine/tstats.h"

/* Sets of accelerations (force.h) for `want` tile tasks at once, room for
 * most particles each, all zero and free. */
static int plan_acc(fmodel *m, int threads, int want, uint32_t most)
{
    if (!m->acc && !(m->acc = calloc(1, sizeof *m->acc)))
        return -1;
    fpool *p = m->acc;
    if (threads > p->threads) {
        int *last = realloc(p->last, (size_t)threads * sizeof *last);
        if (!last)
            return -1;
        p->last = last;
        p->threads = threads;
    }
    for (int k = 0; k < p->threads; k++)
        p->last[k] = -1;
    if (want > p->n) {
        facc *a = realloc(p->set, (size_t)want * sizeof *a);
        if (!a)
            return -1;
        p->set = a;
        uint8_t *busy = realloc(p->busy, (size_t)want);
        if (!busy)
            return -1;
        p->busy = busy;
        memset(a + p->n, 0, (size_t)(want - p->n) * sizeof *a);
        p->n = want;
    }
    memset(p->busy, 0, (size_t)p->n);
    for (int k = 0; k < p->n; k++) {
        facc *a = &p->set[k];
        if (most <= a->cap)
            continue;
        size_t cap = most + most / 2 + 16;
        psim_free(a->ax), psim_free(a->ay), psim_free(a->cnt);
        a->ax = psim_calloc(cap * sizeof *a->ax);
        a->ay = psim_calloc(cap * sizeof *a->ay);
        a->cnt = psim_calloc(cap * sizeof *a->cnt);
        a->cap = a->ax && a->ay && a->cnt ? cap : 0;
        if (!a->cap)
            return -1;
    }
    return 0;
}

/* The step's order of the tiles (step.c): row by row of the tile grid,
 * and each tile's sources, the tiles whose forward stencils (east, north-
 * west, north, north-east) reach its cells: west, east, south, south-west,
 * south-east. */
static void plan_sweep(const psim_grid *g, fmodel *m)
{
    static const int off[5][2] = {{-1, 0}, {1, 0}, {0, -1}, {-1, -1}, {1, -1}};
    static const int fwd[5][2] = {{-1, 0}, {1, 0}, {-1, 1}, {0, 1}, {1, 1}};
    m->sweep_row = g->TG;
    for (int ty = 0; ty < g->TG; ty++)
        for (int tx = 0; tx < g->TG; tx++) {
            uint32_t t = g->tile_of_xy[ty * g->TG + tx];
            m->sweep[ty * g->TG + tx] = t;
            for (int k = 0; k < 5; k++) {
                int x = tx + off[k][0], y = ty + off[k][1];
                m->tiles[t].src[k] = x < 0 || y < 0 || x >= g->TG || y >= g->TG
                                         ? -1 : (int32_t)g->tile_of_xy[y * g->TG + x];
                x = tx + fwd[k][0], y = ty + fwd[k][1];
                m->tiles[t].fwd[k] = x < 0 || y < 0 || x >= g->TG || y >= g->TG
                                         ? -1 : (int32_t)g->tile_of_xy[y * g->TG + x];
            }
        }
}

/* Tiles follow the grid's; their lists are kept from build to build. */
static int plan_tiles(psim_sim *e, fmodel *m)
{
    const psim_grid *g = &e->grid;
    if (g->ntiles > m->cap_tiles) {
        ftile *t = realloc(m->tiles, g->ntiles * sizeof *t);
        if (!t)
            return -1;
        memset(t + m->cap_tiles, 0, (g->ntiles - m->cap_tiles) * sizeof *t);
        m->tiles = t;
        uint32_t *sw = realloc(m->sweep, g->ntiles * sizeof *sw);
        if (!sw)
            return -1;
        m->sweep = sw;
        m->cap_tiles = g->ntiles;
    }
    plan_sweep(g, m);
    if (e->n > m->nis_fast) {
        psim_free(m->is_fast);
        m->is_fast = psim_calloc((size_t)e->n);
        if (!m->is_fast)
            return -1;
        m->nis_fast = e->n;
    }
    m->ntiles = g->ntiles;
    uint32_t most = 0;
    for (uint32_t t = 0; t < g->ntiles; t++) {
        ftile *ft = &m->tiles[t];
        ft->first = g->cellstart[g->tile_cell0[t]];
        ft->n = g->cellstart[g->tile_cell0[t + 1]] - ft->first;
        most = ft->n > most ? ft->n : most;
    }
    uint32_t want = (uint32_t)e->threads < g->ntiles ? (uint32_t)e->threads : g->ntiles;
    return plan_acc(m, e->threads, want ? (int)want : 1, most);
}

/* Particles per cell in the slot rows; a cell's further particles (its
 * "extras", a few per cent of the particles at the course's density) are
 * listed one by one (list_extras). */
#define SLOTS 4
/* A window cell's own cell and its forward half (east, north-west,
 * north, north-east). */
static const int fwd_cells[5][2] = {{0, 0}, {1, 0}, {-1, 1}, {0, 1}, {1, 1}};

/* Which window cells (of the tile, not its border) have extras in their
 * own cell or forward half: only those need list_extras.  Two passes of
 * bytes the compiler vectorises (a cell's five lookups in list_cell were
 * a seventh of a build). */
static void plan_extras(ftile *t)
{
    const size_t W = (size_t)t->W, N = W * W;
    uint8_t *ex = t->fx + N, *fx = t->fx;
    for (size_t c = 0; c < N; c++)
        ex[c] = t->win[2 * c + 1] - t->win[2 * c] > SLOTS;
    for (size_t ly = 1; ly + 1 < W; ly++) {
        const uint8_t *o = ex + ly * W, *u = ex + (ly + 1) * W;
        uint8_t *f = fx + ly * W;
        for (size_t lx = 1; lx + 1 < W; lx++)
            f[lx] = o[lx] | o[lx + 1] | u[lx - 1] | u[lx] | u[lx + 1];
    }
}

/* The tile's cells and a border of one cell, row-major: where each
 * cell's particles are in the store.  Gathering a cell's 3 x 3
 * neighbourhood then reads this small table instead of the grid's
 * rank table and cell starts (nine scattered reads per cell). */
static int plan_window(const psim_sim *e, ftile *t, uint32_t tile)
{
    const psim_grid *g = &e->grid;
    int S = 1 << g->tile_shift, W = S + 2;
    t->wx0 = g->tile_x[tile] * S - 1;
    t->wy0 = g->tile_y[tile] * S - 1;
    t->W = W;
    if (psim_reserve((void **)&t->fx, &t->fxcap, 2 * (size_t)W * (size_t)W, 1) ||
        psim_reserve((void **)&t->win, &t->wcap, 2 * (size_t)W * (size_t)W, sizeof *t->win))
        return -1;
    for (int ly = 0; ly < W; ly++)
        for (int lx = 0; lx < W; lx++) {
            int gx = t->wx0 + lx, gy = t->wy0 + ly;
            uint32_t *w = t->win + 2 * ((size_t)ly * (size_t)W + (size_t)lx);
            if (gx < 0 || gy < 0 || gx >= g->G || gy >= g->G) {
                w[0] = w[1] = 0;
                continue;
            }
            uint32_t rank = g->rank_of_xy[(uint32_t)gy * (uint32_t)g->G + (uint32_t)gx];
            w[0] = g->cellstart[rank];
            w[1] = g->cellstart[rank + 1];
        }
    plan_extras(t);
    return 0;
}

_Static_assert(FORCE_BUCKETS == 4, "list_cell files pairs by three thresholds");
/* Position of an empty slot: farther than any reach from any particle. */
#define FAR 1e300

#if PSIM_AVX512
#include <immintrin.h>
_Static_assert(SLOTS == 4 && 2 * SLOTS == 8, "a cell is half a vector of eight slots");
_Static_assert(sizeof(fpair) == 8 && offsetof(fpair, j) == 4, "a pair is one 64-bit lane");
/* (no auto-vectorising: it would store the cursors and load them back as one
 * vector, a store-forwarding stall per cell) */
#ifdef __clang__
#define AVX512 __attribute__((target("avx512f,avx512vl,popcnt")))
#else
#define AVX512 __attribute__((target("avx512f,avx512vl,popcnt"), optimize("no-tree-vectorize")))
#endif
#endif

static int reserve_rows(ftile *t)
{
    size_t need = 3 * (size_t)t->W * SLOTS;
    if (need <= t->rcap_slots)
        return 0;
    size_t c2 = t->rcap_slots, c3 = t->rcap_slots;
    return psim_reserve((void **)&t->ry, &c2, need, sizeof *t->ry) ||
           psim_reserve((void **)&t->rj, &c3, need, sizeof *t->rj) ||
           psim_reserve((void **)&t->rx, &t->rcap_slots, need, sizeof *t->rx);
}

/* Slot row of window row ly (a ring of three rows: below, own, above). */
static size_t row_at(const ftile *t, int ly)
{
    return (size_t)(ly % 3) * (size_t)t->W * SLOTS;
}

/* Copy window row ly's cells into its slot row: the first SLOTS particles
 * of each cell, the empty slots FAR away. */
static void fill_row(const psim_store *s, ftile *t, int ly)
{
    size_t base = row_at(t, ly);
    double *rx = t->rx + base, *ry = t->ry + base;
    uint32_t *rj = t->rj + base;
    for (int lx = 0; lx < t->W; lx++) {
        const uint32_t *w = t->win + 2 * ((size_t)ly * (size_t)t->W + (size_t)lx);
        uint32_t n = w[1] - w[0] < SLOTS ? w[1] - w[0] : SLOTS;
        for (uint32_t k = 0; k < SLOTS; k++) {
            size_t q = (size_t)lx * SLOTS + k;
            rx[q] = k < n ? s->x[w[0] + k] : FAR;
            ry[q] = k < n ? s->y[w[0] + k] : FAR;
            rj[q] = k < n ? w[0] + k : 0;
        }
    }
}

#if PSIM_AVX512
/* fill_row, a cell at a time: masked loads, the empty slots FAR. */
AVX512 static void fill_row_avx512(const psim_store *s, ftile *t, int ly)
{
    size_t base = row_at(t, ly);
    double *rx = t->rx + base, *ry = t->ry + base;
    uint32_t *rj = t->rj + base;
    const __m256d far = _mm256_set1_pd(FAR);
    const __m128i lane = _mm_setr_epi32(0, 1, 2, 3);
    const uint32_t *w = t->win + 2 * (size_t)ly * (size_t)t->W;
    for (int lx = 0; lx < t->W; lx++, w += 2) {
        uint32_t n = w[1] - w[0] < SLOTS ? w[1] - w[0] : SLOTS;
        __mmask8 k = (__mmask8)((1u << n) - 1);
        _mm256_storeu_pd(rx + (size_t)lx * SLOTS, _mm256_mask_loadu_pd(far, k, s->x + w[0]));
        _mm256_storeu_pd(ry + (size_t)lx * SLOTS, _mm256_mask_loadu_pd(far, k, s->y + w[0]));
        _mm_storeu_si128((__m128i *)(rj + (size_t)lx * SLOTS),
                         _mm_maskz_add_epi32(k, _mm_set1_epi32((int)w[0]), lane));
    }
}
#endif

static void fill(const psim_store *s, ftile *t, int ly, int simd)
{
#if PSIM_AVX512
    if (simd) {
        fill_row_avx512(s, t, ly);
        return;
    }
#endif
    (void)simd;
    fill_row(s, t, ly);
}

/* Which of the n slots (x, y) are within reach (r2 <= reach2) of (px, py),
 * as bits; their squared distances to r2.  n is even and a constant where
 * this is inlined, so the loop unrolls, without a branch. */
static inline unsigned near_mask(const double *x, const double *y, int n, double px, double py,
                                 double reach2, double *r2)
{
    unsigned m = 0;
#ifdef __SSE2__
    __m128d vx = _mm_set1_pd(px), vy = _mm_set1_pd(py), vr = _mm_set1_pd(reach2);
    for (int q = 0; q < n; q += 2) {
        __m128d dx = _mm_sub_pd(_mm_loadu_pd(x + q), vx);
        __m128d dy = _mm_sub_pd(_mm_loadu_pd(y + q), vy);
        __m128d d2 = _mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy));
        _mm_storeu_pd(r2 + q, d2);
        m |= (unsigned)_mm_movemask_pd(_mm_cmple_pd(d2, vr)) << q;
    }
#else
    for (int q = 0; q < n; q++) {
        double dx = x[q] - px, dy = y[q] - py;
        r2[q] = dx * dx + dy * dy;
        m |= (unsigned)(r2[q] <= reach2) << q;
    }
#endif
    return m;
}

/* Room for the slotted pairs of a row of the tile's cells: each cell's
 * SLOTS particles with 5 SLOTS slots, and the eight pairs the vector path
 * stores past a shell's cursor. */
static size_t row_room(const ftile *t)
{
    return (size_t)(t->W - 2) * (5 * SLOTS * SLOTS + 8);
}

/* Room for `more` pairs in every shell. */
static int reserve_pairs(ftile *t, size_t more)
{
    size_t total = more;
    for (int b = 0; b < FORCE_BUCKETS; b++)
        total += t->len[b];
    if (total > (size_t)FORCE_LIST_BUDGET * t->n + FORCE_LIST_SLACK) {
        t->crowded = 1;
        return -1;
    }
    for (int b = 0; b < FORCE_BUCKETS; b++)
        if (t->len[b] + more > t->cap[b] &&
            psim_reserve((void **)&t->pair[b], &t->cap[b], t->len[b] + more, sizeof *t->pair[b]))
            return -1;
    return 0;
}

/* File pair (i, j) at squared distance r2 in its shell (room reserved). */
static inline void file_pair(ftile *t, uint32_t i, uint32_t j, double r2, const double *thr)
{
    int b = 0;
    for (int m = 0; m < FORCE_BUCKETS - 1; m++)
        b += r2 > thr[m];
    t->pair[b][t->len[b]++] = (fpair){i, j};
}

/* A cell's pairs beyond its slots, with the particles beyond SLOTS in a
 * cell (its "extras", a few per cent of the particles at the course's
 * density), listed one by one: each slotted particle of the cell with
 * the extras of the cell and of its forward half; each extra with the
 * later extras of the cell and every particle of the forward half.  So
 * every pair is listed by the cell of the one whose cell sees the other's
 * in its forward half, as the slotted pairs are (step.c relies on it: a
 * tile's pairs reach only its own and its forward tiles). */
static int list_extras(const psim_store *s, ftile *t, int lx, int ly, const double *thr)
{
    const double reach2 = thr[FORCE_BUCKETS - 1];
    const uint32_t *own = t->win + 2 * ((size_t)ly * (size_t)t->W + (size_t)lx);
    for (int f = 0; f < 5; f++) {
        const uint32_t *w =
            t->win + 2 * ((size_t)(ly + fwd_cells[f][1]) * (size_t)t->W + (size_t)(lx + fwd_cells[f][0]));
        for (uint32_t o = own[0]; o < own[1]; o++) {
            /* a slotted o: the cell's extras; an extra o: all of it, after o in its own cell */
            uint32_t j0 = o - own[0] < SLOTS ? w[0] + SLOTS : f == 0 ? o + 1 : w[0];
            for (uint32_t j = j0; j < w[1]; j++) {
                double ex = s->x[j] - s->x[o], ey = s->y[j] - s->y[o], r2 = ex * ex + ey * ey;
                if (!(r2 <= reach2))
                    continue;
                if (reserve_pairs(t, 1 + row_room(t)))   /* and the rest of the row */
                    return -1;
                file_pair(t, o, j, r2, thr);
            }
        }
    }
    return 0;
}

/* The slotted particles' pairs of one cell, SSE2 (or scalar): each
 * particle's distances to the forward half as a mask, then its pairs
 * filed one by one. */
static void list_slots_sse2(ftile *t, const double *ox, const double *oy, const uint32_t *oj,
                            const double *ux, const double *uy, const uint32_t *uj,
                            uint32_t first, uint32_t ns, const double *thr)
{
    const double reach2 = thr[FORCE_BUCKETS - 1], t0 = thr[0], t1 = thr[1], t2 = thr[2];
    fpair *wp[FORCE_BUCKETS];   /* write cursors, in registers or L1 */
    for (int b = 0; b < FORCE_BUCKETS; b++)
        wp[b] = t->pair[b] + t->len[b];
    for (uint32_t k = 0; k < ns; k++) {
        double r2[5 * SLOTS], px = ox[k], py = oy[k];
        unsigned m = near_mask(ox, oy, 2 * SLOTS, px, py, reach2, r2) & ~((2u << k) - 1);
        m |= near_mask(ux, uy, 3 * SLOTS, px, py, reach2, r2 + 2 * SLOTS) << (2 * SLOTS);
        for (; m; m &= m - 1) {
            int q = __builtin_ctz(m);
            int b = (r2[q] > t0) + (r2[q] > t1) + (r2[q] > t2);
            *wp[b]++ = (fpair){first + k, q < 2 * SLOTS ? oj[q] : uj[q - 2 * SLOTS]};
        }
    }
    for (int b = 0; b < FORCE_BUCKETS; b++)
        t->len[b] = (size_t)(wp[b] - t->pair[b]);
}

#if PSIM_AVX512

/* A row's pairs in the order they are found, with their squared
 * distances, before they are filed by shell (file_staged): a vector of
 * slots holds one pair within reach or two, and filing them there (four
 * masks, compresses and stores) was most of a build's instructions; eight
 * at a time, it is an eighth of that a pair. */
typedef struct fstage {
    uint64_t *pair;
    double *d2;
} fstage;

/* Append the lanes of `hit` (pairs (i, js), i in every lane of vi) and
 * their squared distances d2 to the stage (room for eight past it). */
AVX512 static inline void stage_lanes(fstage *st, __mmask8 hit, __m512d d2, __m256i js,
                                      __m512i vi)
{
    __m512i pair = _mm512_or_si512(_mm512_slli_epi64(_mm512_cvtepu32_epi64(js), 32), vi);
    _mm512_storeu_si512(st->pair, _mm512_maskz_compress_epi64(hit, pair));
    _mm512_storeu_pd(st->d2, _mm512_maskz_compress_pd(hit, d2));
    st->pair += __builtin_popcount(hit);
    st->d2 += __builtin_popcount(hit);
}

/* File the n staged pairs in their shells, eight at a time: the lanes of
 * each shell compressed to the front of a vector stored at the shell's
 * cursor (room for eight past it reserved). */
AVX512 static void file_staged(ftile *t, const uint64_t *pair, const double *d2, size_t n,
                               const double *thr)
{
    fpair *wp[FORCE_BUCKETS];
    for (int b = 0; b < FORCE_BUCKETS; b++)
        wp[b] = t->pair[b] + t->len[b];
    for (size_t q = 0; q < n; q += 8) {
        __mmask8 k = n - q >= 8 ? 0xff : (__mmask8)((1u << (n - q)) - 1);
        __m512i p = _mm512_maskz_loadu_epi64(k, pair + q);
        __m512d d = _mm512_maskz_loadu_pd(k, d2 + q);
        __mmask8 inner = 0;
        for (int b = 0; b < FORCE_BUCKETS; b++) {
            __mmask8 le = b < FORCE_BUCKETS - 1
                              ? _mm512_mask_cmp_pd_mask(k, d, _mm512_set1_pd(thr[b]), _CMP_LE_OQ)
                              : k;
            __mmask8 sh = le & (__mmask8)~inner;
            _mm512_storeu_si512(wp[b], _mm512_maskz_compress_epi64(sh, p));
            wp[b] += __builtin_popcount(sh);
            inner = le;
        }
    }
    for (int b = 0; b < FORCE_BUCKETS; b++)
        t->len[b] = (size_t)(wp[b] - t->pair[b]);
}

/* The same pairs as list_slots_sse2, eight slots a vector (the cell and
 * the one to the east in one, the three above in one and a half), to the
 * stage. */
AVX512 static inline void list_slots_avx512(fstage *st, const double *ox, const double *oy,
                                            const uint32_t *oj, const double *ux,
                                            const double *uy, const uint32_t *uj,
                                            uint32_t first, uint32_t ns, double reach2)
{
    const __m512d vr = _mm512_set1_pd(reach2);
    const __m512d ax = _mm512_loadu_pd(ox), ay = _mm512_loadu_pd(oy);
    const __m512d bx = _mm512_loadu_pd(ux), by = _mm512_loadu_pd(uy);
    const __m512d cx = _mm512_maskz_loadu_pd(0x0f, ux + 8), cy = _mm512_maskz_loadu_pd(0x0f, uy + 8);
    const __m256i aj = _mm256_loadu_si256((const __m256i *)oj);
    const __m256i bj = _mm256_loadu_si256((const __m256i *)uj);
    const __m256i cj = _mm256_maskz_loadu_epi32(0x0f, uj + 8);
    for (uint32_t k = 0; k < ns; k++) {
        __m512d px = _mm512_set1_pd(ox[k]), py = _mm512_set1_pd(oy[k]);
        __m512i vi = _mm512_set1_epi64(first + k);
        __m512d dx = _mm512_sub_pd(ax, px), dy = _mm512_sub_pd(ay, py);
        __m512d da = _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy));
        dx = _mm512_sub_pd(bx, px), dy = _mm512_sub_pd(by, py);
        __m512d db = _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy));
        dx = _mm512_sub_pd(cx, px), dy = _mm512_sub_pd(cy, py);
        __m512d dc = _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy));
        stage_lanes(st, _mm512_cmp_pd_mask(da, vr, _CMP_LE_OQ) & (__mmask8)~((2u << k) - 1), da,
                    aj, vi);
        stage_lanes(st, _mm512_cmp_pd_mask(db, vr, _CMP_LE_OQ), db, bj, vi);
        stage_lanes(st, _mm512_mask_cmp_pd_mask(0x0f, dc, vr, _CMP_LE_OQ), dc, cj, vi);
    }
}
#endif

/* The pairs of window cell (lx, ly)'s slotted particles with the slots of
 * the forward half: the later slots of the cell and the cell to the east
 * (2 SLOTS contiguous slots), the three cells above (3 SLOTS), tested
 * without a branch; then its extras. */
static inline __attribute__((always_inline)) int
list_cell(const psim_store *s, ftile *t, int lx, int ly, const double *thr, void *stage)
{
    const uint32_t *w = t->win + 2 * ((size_t)ly * (size_t)t->W + (size_t)lx);
    uint32_t cnt = w[1] - w[0], ns = cnt < SLOTS ? cnt : SLOTS;
    if (cnt == 0)
        return 0;
    /* room reserved for the row (list_row) */
    size_t own = row_at(t, ly) + (size_t)lx * SLOTS, up = row_at(t, ly + 1) + (size_t)(lx - 1) * SLOTS;
    const double *ox = t->rx + own, *oy = t->ry + own, *ux = t->rx + up, *uy = t->ry + up;
    const uint32_t *oj = t->rj + own, *uj = t->rj + up;
#if PSIM_AVX512
    if (stage)
        list_slots_avx512(stage, ox, oy, oj, ux, uy, uj, w[0], ns, thr[FORCE_BUCKETS - 1]);
    else
#endif
        list_slots_sse2(t, ox, oy, oj, ux, uy, uj, w[0], ns, thr);
    return t->fx[(size_t)ly * (size_t)t->W + (size_t)lx] ? list_extras(s, t, lx, ly, thr) : 0;
}

#if PSIM_AVX512
/* A row of cells, AVX-512: list_cell and its vector kernel inlined in one
 * function a row (not two calls a cell). */
AVX512 static int list_row_avx512(const psim_store *s, ftile *t, int ly, const double *thr)
{
    size_t room = row_room(t), c2 = t->stage_cap;
    if (psim_reserve((void **)&t->stage_d2, &c2, room, sizeof *t->stage_d2) ||
        psim_reserve((void **)&t->stage_pair, &t->stage_cap, room, sizeof *t->stage_pair))
        return -1;
    fstage st = {t->stage_pair, t->stage_d2};
    for (int lx = 1; lx <= t->W - 2; lx++)
        if (list_cell(s, t, lx, ly, thr, &st))
            return -1;
    file_staged(t, t->stage_pair, t->stage_d2, (size_t)(st.pair - t->stage_pair), thr);
    return 0;
}
#endif

/* Window row ly's cells, room reserved for all of them at once. */
static int list_row(const psim_store *s, ftile *t, int ly, const double *thr, int simd)
{
    if (reserve_pairs(t, row_room(t)))
        return -1;
#if PSIM_AVX512
    if (simd)
        return list_row_avx512(s, t, ly, thr);
#endif
    for (int lx = 1; lx <= t->W - 2; lx++)
        if (list_cell(s, t, lx, ly, thr, NULL))
            return -1;
    return 0;
}

/* The tile's cells row by row, with the slot rows of the row below, its
 * own and the row above. */
static int list_tile(const psim_sim *e, ftile *t, uint32_t tile, const double *thr, int simd)
{
    for (int b = 0; b < FORCE_BUCKETS; b++)
        t->len[b] = 0;
    t->crowded = 0;
    if (t->n == 0)
        return 0;
    if (plan_window(e, t, tile) || reserve_rows(t))
        return -1;
    int S = t->W - 2;
    psim_touch(e->st.x + t->first, t->n);   /* the rows' lines, in order */
    psim_touch(e->st.y + t->first, t->n);
    fill(&e->st, t, 0, simd);
    fill(&e->st, t, 1, simd);
    for (int ly = 1; ly <= S; ly++) {
        fill(&e->st, t, ly + 1, simd);
        if (list_row(&e->st, t, ly, thr, simd))
            return -1;
    }
    return 0;
}

/* Tile ft's list build as a task (src/engine/task.h); *oom set on failure. */
PSIM_TASK_SPAWN static void task_spawn_list(psim_sim *e, ftile *ft, uint32_t t, const double *thr,
                                            int simd, int graph, int *oom)
{
    psim_thread_stats *ts = e->tstats;
#pragma omp task firstprivate(ft, t, simd, thr, oom, ts, e) default(none) if (graph)
    {
        double b0 = psim_now();
        if (list_tile(e, ft, t, thr, simd)) {
#pragma omp atomic write
            *oom = 1;
        }
        psim_tstat_add(ts, FPHASE_NLIST, psim_now() - b0, 1, ft->n);
    }
}

/* How far beyond the list radius the nearest unlisted pair was at the
 * build: sparse lists (a dilute gas) may leave far more room than the
 * skin.  Unlisted pairs in adjacent cells are more than reach apart and
 * measured (psim_nearest2); pairs in cells further apart are at least a
 * cell side h apart.  A measurement that gains little makes the next wait
 * twice as long (up to 64 builds). */
static void measure_room(psim_sim *e, fmodel *m, uint64_t entries, double reach2)
{
    m->room = m->skin;
    if (!m->skip || entries * FORCE_SPARSE >= (uint64_t)e->n)
        return;
    if (!psim_backoff_due(&m->measure))
        return;
    double room = psim_nearest_bound(e, reach2) - m->law.cutoff;
    if (room > m->skin)
        m->room = room;
    psim_backoff_settle(&m->measure, room > 1.5 * m->skin);
}

/* Fast particles (force.h): at a build, the threshold is the speed that
 * FORCE_FAST_SHARE of the particles pass, estimated from every
 * FORCE_FAST_SAMPLE-th particle in store order (deterministic: the store
 * is sorted).  No fast particles at rest or with a speed not finite. */
#define FORCE_FAST_SHARE (1.0 / 512)
#define FORCE_FAST_MOST 256.0
#define FORCE_FAST_SAMPLE 64

/* The k-th smallest of a[0..n) (no NaN), a reordered: quickselect. */
static double kth_smallest(double *a, size_t n, size_t k)
{
    size_t lo = 0, hi = n - 1;
    while (lo < hi) {
        double pivot = a[lo + (hi - lo) / 2];
        size_t i = lo, j = hi;
        while (i <= j) {
            while (a[i] < pivot)
                i++;
            while (a[j] > pivot)
                j--;
            if (i <= j) {
                double t = a[i];
                a[i] = a[j], a[j] = t;
                i++;
                if (j == 0)
                    break;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            return a[k];
    }
    return a[k];
}

static int restart_fast(const psim_sim *e, fmodel *m)
{
    for (uint32_t t = 0; t < m->cap_tiles; t++) {
        ftile *ft = &m->tiles[t];
        for (size_t k = 0; k < ft->nfast; k++)
            m->is_fast[ft->fast[k].q] = 0;
        ft->nfast = 0;
        ft->drift = 0;
    }
    m->slow = 0;
    m->v2fast = INFINITY;
    const psim_store *s = &e->st;
    size_t ns = ((size_t)e->n + FORCE_FAST_SAMPLE - 1) / FORCE_FAST_SAMPLE, c = m->fs_cap;
    if (!ns)
        return 0;
    if (psim_reserve((void **)&m->fs_v2, &c, ns, sizeof *m->fs_v2))
        return -1;
    m->fs_cap = c;
    for (size_t k = 0; k < ns; k++) {
        size_t q = k * FORCE_FAST_SAMPLE;
        m->fs_v2[k] = s->vx[q] * s->vx[q] + s->vy[q] * s->vy[q];
        if (!(m->fs_v2[k] < INFINITY))
            return 0;
    }
    double share = FORCE_FAST_SHARE * (double)e->n < FORCE_FAST_MOST
                       ? FORCE_FAST_SHARE : FORCE_FAST_MOST / (double)e->n;
    double v2 = kth_smallest(m->fs_v2, ns, (size_t)((1 - share) * (double)(ns - 1)));
    m->v2fast = v2 > 0 ? v2 : INFINITY;
    return 0;
}

/* Sort by cell and build every tile's lists, one task per tile (the tiles
 * write only their own lists: no dependencies). */
int force_build_lists(psim_sim *e, fmodel *m)
{
    psim_engine_sort(e);
    PSIM_REGION_BEGIN(e, FPHASE_NLIST);
    double t0 = psim_now();
    if (plan_tiles(e, m)) {
        PSIM_REGION_END(e, FPHASE_NLIST);
        return -1;
    }
    /* shell b holds the pairs with r2 <= thr[b]: thr[b] = (cutoff + (b + 1) skin / B)^2 */
    double thr[FORCE_BUCKETS];
    for (int b = 0; b < FORCE_BUCKETS; b++) {
        double d = m->law.cutoff + (b + 1) * (m->skin / FORCE_BUCKETS);
        thr[b] = d * d;
    }
    int oom = 0;
    /* one thread, or one tile: the same calls in order */
    const int graph = e->threads > 1 && m->ntiles > 1;
    const int simd = m->simd;
#pragma omp parallel num_threads(e->threads) if (graph)
#pragma omp single
    for (uint32_t t = 0; t < m->ntiles; t++)
        task_spawn_list(e, &m->tiles[t], t, thr, simd, graph, &oom);
    uint64_t entries = 0;
    int crowded = 0;
    for (uint32_t t = 0; t < m->ntiles; t++) {
        crowded |= m->tiles[t].crowded;
        for (int b = 0; b < FORCE_BUCKETS; b++)
            entries += m->tiles[t].len[b];
    }
    e->stats.counter[FC_LIST_ENTRIES] += entries;
    if (!crowded && !oom)
        measure_room(e, m, entries, thr[FORCE_BUCKETS - 1]);
    e->stats.counter[FC_REBUILDS]++;
    e->stats.counter[FC_TASKS] += graph ? m->ntiles : 0;
    if (restart_fast(e, m))
        oom = 1;
    e->stats.phase_s[FPHASE_NLIST] += psim_now() - t0;
    PSIM_REGION_END(e, FPHASE_NLIST);
    m->drift = 0;
    m->since_build = 0;
    m->closing = 2 * force_drift_bound(m);
    m->built = 1;
    return crowded ? -2 : oom ? -1 : 0;
}
