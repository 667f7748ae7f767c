/* Contact finding: once per step, per tile, in parallel.  Each disk looks at
 * its own cell and the forward half of the 8 neighbour cells, so each pair
 * is seen once.  Pairs inside the tile go to its contact list (then a CSR by
 * disk for the worklist); pairs reaching a neighbour tile go to the list of
 * that direction, which the edge task of the two tiles reads. */
#include <math.h>
#include <string.h>

#include "collide.h"
#include "discrete.h"
#include "../../engine/cpu.h"
#include "../../engine/mem.h"
#include "../../engine/tstats.h"

/* All pairs (i in cell ca, j in cell cb) at distance <= 2r, appended to
 * *to.  Room for every candidate is made first, so the append is
 * branch-free: the overlap test only decides whether the count advances. */
static inline __attribute__((always_inline)) int
scan_cells(const psim_sim *e, const dmodel *m, uint32_t ca, uint32_t cb, dlist *to, int same,
           double *d2min, const int nearest_wanted)
{
    double nearest = *d2min;
    const psim_grid *g = &e->grid;
    const double *x = e->st.x, *y = e->st.y;
    const double four_r2 = m->four_r2;
    uint32_t a0 = g->cellstart[ca], a1 = g->cellstart[ca + 1];
    uint32_t b0 = g->cellstart[cb], b1 = g->cellstart[cb + 1];
    dcontact *out = to->c;
    size_t n = to->n;
    for (uint32_t i = a0; i < a1; i++) {
        const double xi = x[i], yi = y[i];
        uint32_t j0 = same ? i + 1 : b0;
        /* room for every candidate of this disk (a crowded cell grows the
         * list as it goes, never by the square of its count at once) */
        if (n + (b1 - j0) > to->cap) {
            to->n = n;
            if (psim_reserve((void **)&to->c, &to->cap, n + (b1 - j0), sizeof *to->c))
                return -1;
            out = to->c;
        }
        for (uint32_t j = j0; j < b1; j++) {
            double dx = x[j] - xi, dy = y[j] - yi, d2 = dx * dx + dy * dy;
            out[n] = (dcontact){(int32_t)i, (int32_t)j};
            n += psim_overlaps(d2, four_r2);
            if (nearest_wanted)   /* NaN: never a contact either */
                nearest = d2 < nearest ? d2 : nearest;
        }
    }
    to->n = n;
    *d2min = nearest;
    return 0;
}

static int build_adjacency(dtile *t)
{
    size_t n = t->p1 - t->p0;
    if (2 * t->in.n >= UINT32_MAX) /* offsets are 32-bit */
        return -1;
    if (psim_reserve((void **)&t->adj0, &t->adj0_cap, n + 1, sizeof *t->adj0) ||
        psim_reserve((void **)&t->adj, &t->adj_cap, 2 * t->in.n + 1, sizeof *t->adj) ||
        psim_reserve((void **)&t->queue, &t->queue_cap, n + 1, sizeof *t->queue) ||
        psim_reserve((void **)&t->acts, &t->acts_cap, n + 1, sizeof *t->acts))
        return -1;
    memset(t->adj0, 0, (n + 1) * sizeof *t->adj0);
    for (size_t k = 0; k < t->in.n; k++) {
        t->adj0[t->in.c[k].i - t->p0 + 1]++;
        t->adj0[t->in.c[k].j - t->p0 + 1]++;
    }
    for (size_t k = 0; k < n; k++)
        t->adj0[k + 1] += t->adj0[k];
    /* fill using adj0[k] as a cursor, then shift back */
    for (size_t k = 0; k < t->in.n; k++) {
        const dcontact *c = &t->in.c[k];
        t->adj[t->adj0[c->i - t->p0]++] = c->j;
        t->adj[t->adj0[c->j - t->p0]++] = c->i;
    }
    for (size_t k = n; k > 0; k--)
        t->adj0[k] = t->adj0[k - 1];
    t->adj0[0] = 0;
    return 0;
}

static void clear_lists(dlist *in, dlist *cross)
{
    in->n = 0;
    for (int d = 0; d < DIRS; d++)
        cross[d].n = 0;
}

/* Cell c's half stencil: itself, then those of its neighbours east,
 * north-west, north and north-east that hold disks, each with the list
 * its pairs go to. */
typedef struct dstencil {
    int n;
    uint32_t cell[5];
    dlist *to[5];
    uint64_t nbs;   /* disks in the neighbours */
} dstencil;

static inline __attribute__((always_inline)) void
half_stencil_of(const psim_grid *g, uint32_t c, int tx, int ty, uint32_t t0, uint32_t tn,
                dlist *in, dlist *cross, dstencil *s)
{
    s->n = 1;
    s->cell[0] = c;
    s->to[0] = in;
    s->nbs = 0;
    int cx = g->cell_x[c], cy = g->cell_y[c];
    for (int k = 0; k < 4; k++) {
        int nx, ny;
        uint32_t c2 = psim_grid_forward(g, cx, cy, k, &nx, &ny);
        if (c2 == UINT32_MAX)
            continue;
        uint32_t nb = g->cellstart[c2 + 1] - g->cellstart[c2];
        if (nb == 0)
            continue;
        s->nbs += nb;
        s->cell[s->n] = c2;
        if (c2 - t0 < tn) {   /* the tile's own cells are one rank range */
            s->to[s->n++] = in;
            continue;
        }
        int dtx = g->tcol[nx] - tx, dty = g->trow[ny] - ty;
        s->to[s->n++] = &cross[(dtx + 1) + 3 * (dty + 1)];
    }
}

#if PSIM_AVX512
#include <immintrin.h>
#define AVX512 __attribute__((target("avx512f,avx512vl,popcnt")))

/* Lane tables of the blocks (scan_block_avx512): the k-th pair of two
 * cells of na and nb disks, i-major, is (blk_i, blk_j)[na][nb][k]; of one
 * cell's na disks, the pairs i < j, (tri_i, tri_j)[na][k].  Eight bytes
 * past the last pair are read (zero).  Filled when the program starts,
 * before any thread. */
#define BLOCK 8
static uint8_t blk_i[BLOCK + 1][BLOCK + 1][BLOCK * BLOCK + 8];
static uint8_t blk_j[BLOCK + 1][BLOCK + 1][BLOCK * BLOCK + 8];
static uint8_t tri_i[BLOCK + 1][BLOCK * (BLOCK - 1) / 2 + 8];
static uint8_t tri_j[BLOCK + 1][BLOCK * (BLOCK - 1) / 2 + 8];

__attribute__((constructor)) static void block_init(void)
{
    for (int na = 0; na <= BLOCK; na++) {
        int k = 0;
        for (int i = 0; i < na; i++)
            for (int j = i + 1; j < na; j++, k++)
                tri_i[na][k] = (uint8_t)i, tri_j[na][k] = (uint8_t)j;
        for (int nb = 0; nb <= BLOCK; nb++)
            for (int p = 0; p < na * nb; p++)
                blk_i[na][nb][p] = (uint8_t)(p / nb), blk_j[na][nb][p] = (uint8_t)(p % nb);
    }
}

/* The pairs of `pair` (its lanes in use) within reach, d2 <= 4r^2,
 * compressed to the front of a vector stored at out + n (room for eight
 * reserved), and the nearest d2 kept; returns the list's new length. */
AVX512 static inline __attribute__((always_inline)) size_t
file_hits(dcontact *out, size_t n, __mmask8 lanes, __m512d d2, __m512d four_r2, __m512i pair,
          __m512d *nearest, const int nearest_wanted)
{
    __mmask8 hit = _mm512_mask_cmp_pd_mask(lanes, d2, four_r2, _CMP_LE_OQ);
    _mm512_storeu_si512(out + n, _mm512_maskz_compress_epi64(hit, pair));
    if (nearest_wanted) {   /* NaN: never the nearest */
        __mmask8 lt = _mm512_mask_cmp_pd_mask(lanes, d2, *nearest, _CMP_LT_OQ);
        *nearest = _mm512_mask_mov_pd(*nearest, lt, d2);
    }
    return n + (size_t)__builtin_popcount(hit);
}

/* scan_cells, the disks of cell cb eight at a time: the same pairs in the
 * same order (the hits of each vector compressed to its front and stored
 * whole at the list's end, with room for eight reserved). */
AVX512 static inline __attribute__((always_inline)) int
scan_cells_avx512(const psim_sim *e, const dmodel *m, uint32_t ca, uint32_t cb, dlist *to,
                  int same, __m512d *nearest, const int nearest_wanted)
{
    const psim_grid *g = &e->grid;
    const double *x = e->st.x, *y = e->st.y;
    const __m512d four_r2 = _mm512_set1_pd(m->four_r2);
    const __m512i lane = _mm512_set_epi64(7, 6, 5, 4, 3, 2, 1, 0);
    uint32_t a0 = g->cellstart[ca], a1 = g->cellstart[ca + 1];
    uint32_t b0 = g->cellstart[cb], b1 = g->cellstart[cb + 1];
    size_t n = to->n;
    dcontact *out = to->c;
    for (uint32_t i = a0; i < a1; i++) {
        uint32_t j0 = same ? i + 1 : b0;
        if (n + (b1 - j0) + 8 > to->cap) {   /* as scan_cells, and a vector's room */
            to->n = n;
            if (psim_reserve((void **)&to->c, &to->cap, n + (b1 - j0) + 8, sizeof *to->c))
                return -1;
            out = to->c;
        }
        const __m512d px = _mm512_set1_pd(x[i]), py = _mm512_set1_pd(y[i]);
        const __m512i pi = _mm512_set1_epi64(i);
        for (uint32_t j = j0; j < b1; j += 8) {
            __mmask8 lanes = b1 - j >= 8 ? (__mmask8)0xff : (__mmask8)((1u << (b1 - j)) - 1);
            __m512d dx = _mm512_sub_pd(_mm512_maskz_loadu_pd(lanes, x + j), px);
            __m512d dy = _mm512_sub_pd(_mm512_maskz_loadu_pd(lanes, y + j), py);
            __m512d d2 = _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy));
            __m512i pj = _mm512_slli_epi64(_mm512_add_epi64(_mm512_set1_epi64(j), lane), 32);
            n = file_hits(out, n, lanes, d2, four_r2, _mm512_or_si512(pj, pi), nearest,
                          nearest_wanted);
        }
    }
    to->n = n;
    return 0;
}

/* scan_cells for two cells of at most BLOCK disks each: all the pairs of
 * the block eight to a vector, in scan_cells' order (i, then j), each
 * lane's two disks taken from the cells' vectors by the lane tables
 * (block_init): one pass over the pairs instead of one per disk of ca. */
AVX512 static inline __attribute__((always_inline)) int
scan_block_avx512(const psim_sim *e, const dmodel *m, uint32_t ca, uint32_t cb, dlist *to,
                  int same, __m512d *nearest, const int nearest_wanted)
{
    const psim_grid *g = &e->grid;
    const double *x = e->st.x, *y = e->st.y;
    uint32_t a0 = g->cellstart[ca], na = g->cellstart[ca + 1] - a0;
    uint32_t b0 = g->cellstart[cb], nb = g->cellstart[cb + 1] - b0;
    const uint8_t *li = same ? tri_i[na] : blk_i[na][nb], *lj = same ? tri_j[na] : blk_j[na][nb];
    uint32_t np = same ? na * (na - 1) / 2 : na * nb;
    size_t n = to->n;
    if (n + np + 8 > to->cap &&
        psim_reserve((void **)&to->c, &to->cap, n + np + 8, sizeof *to->c))
        return -1;
    dcontact *out = to->c;
    const __m512d four_r2 = _mm512_set1_pd(m->four_r2);
    const __mmask8 ma = (__mmask8)((1u << na) - 1), mb = (__mmask8)((1u << nb) - 1);
    const __m512d xa = _mm512_maskz_loadu_pd(ma, x + a0), ya = _mm512_maskz_loadu_pd(ma, y + a0);
    const __m512d xb = _mm512_maskz_loadu_pd(mb, x + b0), yb = _mm512_maskz_loadu_pd(mb, y + b0);
    const __m512i ia = _mm512_set1_epi64(a0), jb = _mm512_set1_epi64(b0);
    for (uint32_t p = 0; p < np; p += 8) {
        __mmask8 lanes = np - p >= 8 ? (__mmask8)0xff : (__mmask8)((1u << (np - p)) - 1);
        __m512i ii = _mm512_cvtepu8_epi64(_mm_loadl_epi64((const __m128i *)(li + p)));
        __m512i jj = _mm512_cvtepu8_epi64(_mm_loadl_epi64((const __m128i *)(lj + p)));
        __m512d dx = _mm512_sub_pd(_mm512_permutexvar_pd(jj, xb), _mm512_permutexvar_pd(ii, xa));
        __m512d dy = _mm512_sub_pd(_mm512_permutexvar_pd(jj, yb), _mm512_permutexvar_pd(ii, ya));
        __m512d d2 = _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy));
        __m512i pair = _mm512_or_si512(_mm512_slli_epi64(_mm512_add_epi64(jj, jb), 32),
                                       _mm512_add_epi64(ii, ia));
        n = file_hits(out, n, lanes, d2, four_r2, pair, nearest, nearest_wanted);
    }
    to->n = n;
    return 0;
}

/* Cell c and cell ck (k-th of the stencil, k == 0 itself): as a block
 * when both are small enough, else disk by disk. */
AVX512 static inline __attribute__((always_inline)) int
scan_pair_avx512(const psim_sim *e, const dmodel *m, uint32_t c, const dstencil *s, int k,
                 __m512d *nearest, const int nearest_wanted)
{
    const uint32_t *cs = e->grid.cellstart;
    if (cs[c + 1] - cs[c] <= BLOCK && cs[s->cell[k] + 1] - cs[s->cell[k]] <= BLOCK)
        return scan_block_avx512(e, m, c, s->cell[k], s->to[k], k == 0, nearest,
                                 nearest_wanted);
    return scan_cells_avx512(e, m, c, s->cell[k], s->to[k], k == 0, nearest, nearest_wanted);
}

/* Cell c against its half stencil. */
AVX512 static int search_cell_avx512(const psim_sim *e, const dmodel *m, uint32_t c,
                                     const dstencil *s, double *d2min, const int nearest_wanted)
{
    __m512d nearest = _mm512_set1_pd(*d2min);
    int bad = 0;
    for (int k = 0; k < s->n; k++)
        bad |= nearest_wanted ? scan_pair_avx512(e, m, c, s, k, &nearest, 1)
                              : scan_pair_avx512(e, m, c, s, k, &nearest, 0);
    if (nearest_wanted)
        *d2min = _mm512_reduce_min_pd(nearest);
    return bad;
}
#endif

/* Search cells [c0, c1) of tile tid; pairs go to in / cross[direction].
 * *tests counts the pairs of disks looked at: the work of the search,
 * which tells when the grid no longer fits the disks (regrid.c). */
static inline __attribute__((always_inline)) int
search_cells(const psim_sim *e, const dmodel *m, uint32_t tid, uint32_t c0, uint32_t c1,
             dlist *in, dlist *cross, double *d2min, uint64_t *tests, const int nearest_wanted)
{
    const psim_grid *g = &e->grid;
    int bad = 0;
    int tx = g->tile_x[tid], ty = g->tile_y[tid];
    const uint32_t t0 = g->tile_cell0[tid], tn = g->tile_cell0[tid + 1] - t0;
    uint64_t looked = 0;
    for (uint32_t c = c0; c < c1 && !bad; c++) {
        uint32_t na = g->cellstart[c + 1] - g->cellstart[c];
        if (na == 0)
            continue;
        dstencil s;
        half_stencil_of(g, c, tx, ty, t0, tn, in, cross, &s);
        looked += (uint64_t)na * (na - 1) / 2 + na * s.nbs;
#if PSIM_AVX512
        if (m->simd) {
            bad |= search_cell_avx512(e, m, c, &s, d2min, nearest_wanted);
            continue;
        }
#endif
        for (int k = 0; k < s.n; k++)
            bad |= scan_cells(e, m, c, s.cell[k], s.to[k], k == 0, d2min, nearest_wanted);
    }
    *tests = looked;
    return bad;
}

static int append(dlist *to, const dlist *from)
{
    if (from->n == 0)
        return 0;
    if (to->n + from->n > to->cap &&
        psim_reserve((void **)&to->c, &to->cap, to->n + from->n, sizeof *to->c))
        return -1;
    memcpy(to->c + to->n, from->c, from->n * sizeof *from->c);
    to->n += from->n;
    return 0;
}

/* A tile's lists: its chunks' lists in chunk order, then its adjacency. */
static void join_chunks(dmodel *m, uint32_t tid)
{
    dtile *t = &m->tiles[tid];
    int bad = 0;
    clear_lists(&t->in, t->cross);
    for (uint32_t k = m->tile_chunk0[tid]; k < m->tile_chunk0[tid + 1] && !bad; k++) {
        const dchunk *ch = &m->chunks[k];
        bad |= ch->oom || append(&t->in, &ch->in);
        for (int d = 0; d < DIRS && !bad; d++)
            bad |= append(&t->cross[d], &ch->cross[d]);
    }
    if (!bad)
        bad = build_adjacency(t);
    t->oom = (uint8_t)(bad != 0);
}

__attribute__((noinline)) void discrete_find_contacts(psim_sim *e, dmodel *m)
{
    const psim_grid *g = &e->grid;
    for (uint32_t t = 0; t < m->ntiles; t++) {
        m->tiles[t].p0 = g->cellstart[g->tile_cell0[t]];
        m->tiles[t].p1 = g->cellstart[g->tile_cell0[t + 1]];
    }
    discrete_ranks_own(e, m);
    uint64_t found = 0;
    const int nearest = m->fl.enabled && m->step_contacts == 0;
#pragma omp parallel num_threads(e->threads) reduction(+ : found)
    {
#pragma omp for schedule(dynamic, 1)
        for (uint32_t k = 0; k < m->nchunks; k++) {
            dchunk *ch = &m->chunks[k];
            clear_lists(&ch->in, ch->cross);
            ch->d2min = INFINITY;
            ch->tests = 0;
            uint32_t a = g->cellstart[ch->c0], b = g->cellstart[ch->c1];
            if (a == b || !discrete_mine(m, ch->tile))
                continue; /* an empty region, or another rank's: no work */
            double t0 = psim_now();
            /* the nearest pair matters only where the search may find no
             * contact: after one that found none (flight.c) */
            int bad = nearest
                          ? search_cells(e, m, ch->tile, ch->c0, ch->c1, &ch->in, ch->cross,
                                         &ch->d2min, &ch->tests, 1)
                          : search_cells(e, m, ch->tile, ch->c0, ch->c1, &ch->in, ch->cross,
                                         &ch->d2min, &ch->tests, 0);
            ch->oom = (uint8_t)(bad != 0);
            const double dt = psim_now() - t0;
            psim_tstat_add(e->tstats, DPHASE_CONTACTS, dt, 1, b - a);
            if (m->ranks > 1)   /* the tile's work, to share the tiles out */
#pragma omp atomic
                m->tiles[ch->tile].busy += dt;
        }
#pragma omp for schedule(dynamic, 1)
        for (uint32_t t = 0; t < m->ntiles; t++) {
            dtile *tile = &m->tiles[t];
            if (tile->p0 == tile->p1 || !discrete_mine(m, t)) {
                clear_lists(&tile->in, tile->cross);
                continue;
            }
            double t0 = psim_now();
            join_chunks(m, t);
            psim_tstat_add(e->tstats, DPHASE_CONTACTS, psim_now() - t0, 0, 0);
            found += tile->in.n;
            for (int d = 0; d < DIRS; d++)
                found += tile->cross[d].n;
        }
    }
    e->stats.counter[DC_CONTACTS] += found;
    m->d2min = nearest ? INFINITY : 0;
    uint64_t tests = 0;
    for (uint32_t k = 0; k < m->nchunks; k++) {
        m->d2min = m->chunks[k].d2min < m->d2min ? m->chunks[k].d2min : m->d2min;
        tests += m->chunks[k].tests;
    }
    e->stats.counter[DC_SEARCH_TESTS] += tests;
    /* (over ranks, this rank's: every rank's once the first round's tiles
     * are done, resolve.c) */
    m->step_contacts = found;
    m->step_tests = tests;
    for (uint32_t t = 0; m->ranks > 1 && t < m->ntiles; t++) {
        dtile *d = &m->tiles[t];
        if (discrete_mine(m, t))
            continue;
        d->in.n = 0;   /* another rank's: only what it sends is here */
        for (int k = 0; k < DIRS; k++)
            d->cross[k].n = 0;
    }
}
