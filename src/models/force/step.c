/* One step of the force model: the force on each particle from the
 * positions at the start of the step, then its move (law.h).
 *
 * Lists: two tasks a tile (run_step: a sweep row by row of the tiles on
 * one thread, two rounds on more):
 *   force      the tile tests its pairs in the shells that may hold pairs
 *              within the cutoff (branch-free, into a list of hits) and
 *              writes the force of each hit on both of its particles as
 *              records: its own particles' in its list, others' out;
 *   integrate  the tile takes the records of its particles from the out
 *              lists of its sources (west, east, south, south-west,
 *              south-east: the tiles whose stencils reach its cells, and
 *              so the only ones that read its positions), sums its
 *              particles' forces in the order of the naive loop (over
 *              partner ids: only a particle with three or more needs
 *              sorting, as x + a + b is x + b + a) and moves them in place.
 * A tile's integrate waits for its own force and its sources' forces.
 * Naive: one round of blocks, new positions to the store's scratch arrays
 * (x2, y2) swapped in at the end, as every block reads all positions. */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif
#include "../../engine/cpu.h"
#if PSIM_AVX512
#include <immintrin.h>
#endif

#include "force.h"
#include "../../engine/mem.h"
#include "../../engine/task.h"
#include "../../engine/timer.h"
#include "../../engine/tstats.h"

/* Particles per block of the naive loop (fixed, so that the per-block
 * sums of --force-stats do not depend on the thread count). */
#define NAIVE_BLOCK 1024

/* The older edition's statistics of one interacting pair. */
static inline void pair_stats(const flaw *k, ftile *t, double px, double py, double qx,
                              double qy)
{
    double dx = qx - px, dy = qy - py, r2 = dx * dx + dy * dy;
    if (r2 > k->cutoff2 || r2 == 0)
        return;
    double d = sqrt(r2) / k->cutoff;
    if (r2 / k->cutoff2 < t->dmin * t->dmin)
        t->dmin = d;
    t->dsum += d;
    t->dn++;
}

static void tile_reset(ftile *t)
{
    t->v2max = 0;
    t->u0 = t->w0 = INFINITY;
    t->u1 = t->w1 = -INFINITY;
    t->bounced = 0;
    t->tests = t->hits = t->sorted = 0;
    t->dmin = 1.0;
    t->dsum = 0;
    t->dn = 0;
    t->lost = 0;
}

/* Move particle i with acceleration (ax, ay); new position to x2, y2. */
static inline void move_one(const flaw *k, psim_store *s, ftile *t, uint32_t i, double ax,
                            double ay)
{
    double vx = s->vx[i], vy = s->vy[i];
    t->lost |= flaw_move(k, s->x[i], s->y[i], &vx, &vy, ax, ay, &s->x2[i], &s->y2[i]);
    s->vx[i] = vx;
    s->vy[i] = vy;
    double v2 = vx * vx + vy * vy;
    if (v2 > t->v2max)
        t->v2max = v2;
}

/* The force of one interacting pair on one of its particles, to the
 * owner's tile's records or to the outgoing ones. */
static inline void push_rec(ftile *t, uint32_t owner, uint32_t partner, double fx, double fy)
{
    int local = owner - t->first < t->n;
    frec **a = local ? &t->rec : &t->out;
    size_t *n = local ? &t->nrec : &t->nout, *cap = local ? &t->rcap : &t->ocap;
    if (*n == *cap && psim_reserve((void **)a, cap, *n + 1, sizeof **a)) {
        t->oom = 1;
        return;
    }
    (*a)[(*n)++] = (frec){owner, partner, fx, fy};
}

/* Pair (i, j) within the cutoff: the course's apply_force both ways. */
static void pair_forces(const fmodel *m, const psim_store *s, ftile *t, fpair p)
{
    const flaw *k = &m->law;
    double xi = s->x[p.i], yi = s->y[p.i], xj = s->x[p.j], yj = s->y[p.j];
    double dx = xj - xi, dy = yj - yi;
    double coef = flaw_coef(k, dx * dx + dy * dy);
    push_rec(t, p.i, p.j, coef * dx, coef * dy);
    push_rec(t, p.j, p.i, coef * (xi - xj), coef * (yi - yj));
    t->hits += 2;
    if (m->stats) {   /* over ranks, each rank's own particles' */
        if (!psim_engine_ghost(m->sim, p.i))
            pair_stats(k, t, xi, yi, xj, yj);
        if (!psim_engine_ghost(m->sim, p.j))
            pair_stats(k, t, xj, yj, xi, yi);
    }
}

/* Pairs p[from..len) within the cutoff (not farther: NaN interacts, as
 * in the course): their places in p appended to hit[nh..]; the new nh. */
static size_t test_pairs(const double *x, const double *y, const fpair *p, size_t from,
                         size_t len, double c2, uint32_t *hit, size_t nh)
{
    for (size_t q = from; q < len; q++) {
        double dx = x[p[q].j] - x[p[q].i], dy = y[p[q].j] - y[p[q].i];
        hit[nh] = (uint32_t)q;
        nh += !(dx * dx + dy * dy > c2);
    }
    return nh;
}

#if PSIM_AVX512
/* test_pairs eight pairs a vector, the positions gathered (the same
 * arithmetic: the same hits), the hits' places compressed to hit (room
 * for eight past them). */
__attribute__((target("avx512f,avx512vl,popcnt"))) static size_t
test_pairs_avx512(const double *x, const double *y, const fpair *p, size_t len, double c2,
                  uint32_t *hit)
{
    size_t nh = 0, q = 0;
    const __m512d vc = _mm512_set1_pd(c2);
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    for (; q + 8 <= len; q += 8) {
        PSIM_PREFETCH_AHEAD(p + q, 1024, 0);   /* the pair lists, 128 pairs on */
        __m512i pr = _mm512_loadu_si512(p + q);
        __m256i vi = _mm512_cvtepi64_epi32(pr), vj = _mm512_cvtepi64_epi32(_mm512_srli_epi64(pr, 32));
        __m512d dx = _mm512_sub_pd(_mm512_i32gather_pd(vj, x, 8), _mm512_i32gather_pd(vi, x, 8));
        __m512d dy = _mm512_sub_pd(_mm512_i32gather_pd(vj, y, 8), _mm512_i32gather_pd(vi, y, 8));
        __m512d d2 = _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy));
        __mmask8 in = _mm512_cmp_pd_mask(d2, vc, _CMP_NGT_UQ);   /* NaN too */
        __m256i at = _mm256_add_epi32(lane, _mm256_set1_epi32((int)q));
        _mm256_storeu_si256((__m256i *)(hit + nh), _mm256_maskz_compress_epi32(in, at));
        nh += (size_t)__builtin_popcount(in);
    }
    return test_pairs(x, y, p, q, len, c2, hit, nh);
}
#endif

/* Round 1: the tile's pairs in the shells that may hold pairs within the
 * cutoff (t->shells). */
static void tile_force(const fmodel *m, psim_store *s, ftile *t)
{
    const int nb = t->shells;
    const double *x = s->x, *y = s->y, c2 = m->law.cutoff2;
    tile_reset(t);
    t->nrec = t->nout = 0;
    psim_touch(x + t->first, t->n);   /* the gathers' lines, in order */
    psim_touch(y + t->first, t->n);
    for (int b = 0; b < nb; b++) {
        const fpair *p = t->pair[b];
        size_t len = t->len[b], nh;
        if (psim_reserve((void **)&t->hit, &t->hcap, len + 8, sizeof *t->hit)) {
            t->oom = 1;
            return;
        }
#if PSIM_AVX512
        if (m->simd)
            nh = test_pairs_avx512(x, y, p, len, c2, t->hit);
        else
#endif
            nh = test_pairs(x, y, p, 0, len, c2, t->hit, 0);
        t->tests += len;
        for (size_t h = 0; h < nh; h++)
            pair_forces(m, s, t, p[t->hit[h]]);
    }
}

static int by_owner_partner(const void *a, const void *b)
{
    const frec *p = a, *q = b;
    if (p->owner != q->owner)
        return p->owner < q->owner ? -1 : 1;
    int32_t a_ = (int32_t)p->partner, b_ = (int32_t)q->partner;   /* ids, signed */
    return (a_ > b_) - (a_ < b_);
}

/* Sum the forces on the tile's particles in partner id order, from +0 as
 * the course's loop does; a particle with one or two is summed as they
 * come (+0 + a + b is +0 + b + a), the others after a sort. */
static int tile_sum(const psim_store *s, ftile *t, facc *acc)
{
    if (psim_reserve((void **)&t->slow, &t->scap, t->nrec, sizeof *t->slow))
        return -1;
    for (size_t r = 0; r < t->nrec; r++)
        acc->cnt[t->rec[r].owner - t->first]++;
    size_t ns = 0;
    for (size_t r = 0; r < t->nrec; r++) {
        const frec *f = &t->rec[r];
        uint32_t q = f->owner - t->first;
        if (acc->cnt[q] > 2) {
            t->slow[ns] = *f;
            t->slow[ns++].partner = (uint32_t)s->id[f->partner];
            continue;
        }
        acc->ax[q] += f->fx;
        acc->ay[q] += f->fy;
    }
    if (ns > 1)
        qsort(t->slow, ns, sizeof *t->slow, by_owner_partner);
    t->sorted = ns;
    for (size_t r = 0; r < ns; r++) {
        uint32_t q = t->slow[r].owner - t->first;
        acc->ax[q] += t->slow[r].fx;
        acc->ay[q] += t->slow[r].fy;
    }
    return 0;
}

/* The course's move of particles [q0, q1) of the tile, in place: kicks
 * and drifts two at a time, with the largest squared speed and the
 * velocities' extent (into the tile: bounds for the lists) and whether
 * one is outside [0, size]^2 (NaN left out of all three, as the course's
 * comparisons leave it), in one pass that also zeroes the accelerations
 * and counts it has read, for the next step (cheaper than zeroing them a
 * force record at a time); then the reflections (rare: a particle that
 * crossed a wall), in a chunk that has one.  Returns whether one left the
 * box for good. */
#define MOVE_CHUNK 64   /* a bit of a 64-bit word each (the fast particles) */
#if PSIM_AVX512
/* The kicks and drifts of move_chunk eight at a time (the same operations
 * in the same order: the same bits), from q0 while eight are left; the
 * extents into *m .. *w1.  Returns where it stopped. */
__attribute__((target("avx512f"))) static uint32_t
move_avx512(const flaw *k, double *restrict ax, double *restrict ay, uint32_t *restrict cnt,
            double *restrict x, double *restrict y, double *restrict vx, double *restrict vy,
            uint32_t q0, uint32_t q1, double *m, double *lo, double *hi, double *u0, double *u1,
            double *w0, double *w1, double v2fast, uint64_t *fast)
{
    const __m512d vf = _mm512_set1_pd(v2fast);
    uint64_t bits = 0;
    __m512d dt = _mm512_set1_pd(k->dt), mm = _mm512_set1_pd(*m), mlo = _mm512_set1_pd(*lo),
            mhi = _mm512_set1_pd(*hi), mu0 = _mm512_set1_pd(*u0), mu1 = _mm512_set1_pd(*u1),
            mw0 = _mm512_set1_pd(*w0), mw1 = _mm512_set1_pd(*w1);
    uint32_t q = q0;
    for (; q + 8 <= q1; q += 8) {
        /* 128 particles on (at 1e6 the streams come from the L3) */
        PSIM_PREFETCH_AHEAD(x + q, 1024, 0);
        PSIM_PREFETCH_AHEAD(y + q, 1024, 0);
        PSIM_PREFETCH_AHEAD(vx + q, 1024, 0);
        PSIM_PREFETCH_AHEAD(vy + q, 1024, 0);
        __m512d ux = _mm512_add_pd(_mm512_loadu_pd(vx + q),
                                   _mm512_mul_pd(_mm512_loadu_pd(ax + q), dt));
        __m512d uy = _mm512_add_pd(_mm512_loadu_pd(vy + q),
                                   _mm512_mul_pd(_mm512_loadu_pd(ay + q), dt));
        _mm512_storeu_pd(ax + q, _mm512_setzero_pd());   /* zero for the next step */
        _mm512_storeu_pd(ay + q, _mm512_setzero_pd());
        _mm256_storeu_si256((__m256i *)(cnt + q), _mm256_setzero_si256());
        __m512d nx = _mm512_add_pd(_mm512_loadu_pd(x + q), _mm512_mul_pd(ux, dt));
        __m512d ny = _mm512_add_pd(_mm512_loadu_pd(y + q), _mm512_mul_pd(uy, dt));
        _mm512_storeu_pd(vx + q, ux), _mm512_storeu_pd(vy + q, uy);
        _mm512_storeu_pd(x + q, nx), _mm512_storeu_pd(y + q, ny);
        __m512d v2 = _mm512_add_pd(_mm512_mul_pd(ux, ux), _mm512_mul_pd(uy, uy));
        mm = _mm512_max_pd(v2, mm);   /* the second operand when the first is NaN */
        bits |= (uint64_t)_mm512_cmp_pd_mask(v2, vf, _CMP_GT_OQ) << (q - q0);
        mlo = _mm512_min_pd(_mm512_min_pd(nx, ny), mlo);
        mhi = _mm512_max_pd(_mm512_max_pd(nx, ny), mhi);
        mu0 = _mm512_min_pd(ux, mu0), mu1 = _mm512_max_pd(ux, mu1);
        mw0 = _mm512_min_pd(uy, mw0), mw1 = _mm512_max_pd(uy, mw1);
    }
    /* the lanes hold no NaN (it is never the second operand), so any
     * order of the last reductions gives the same extents */
    *m = _mm512_reduce_max_pd(mm);
    *lo = _mm512_reduce_min_pd(mlo), *hi = _mm512_reduce_max_pd(mhi);
    *u0 = _mm512_reduce_min_pd(mu0), *u1 = _mm512_reduce_max_pd(mu1);
    *w0 = _mm512_reduce_min_pd(mw0), *w1 = _mm512_reduce_max_pd(mw1);
    *fast |= bits;
    return q;
}
#endif

static int move_chunk(const flaw *law, ftile *t, facc *acc, double *restrict x,
                      double *restrict y, double *restrict vx, double *restrict vy, uint32_t q0,
                      uint32_t q1, int simd, double v2fast, uint64_t *fast)
{
    const flaw kl = *law, *k = &kl;   /* a copy: no store can change it */
    double *restrict ax = acc->ax, *restrict ay = acc->ay;
    uint32_t *restrict cnt = acc->cnt;
    double m = t->v2max, lo = 0, hi = k->size, u0 = t->u0, u1 = t->u1, w0 = t->w0, w1 = t->w1;
    uint32_t q = q0;
    *fast = 0;
#if PSIM_AVX512
    if (simd)
        q = move_avx512(k, ax, ay, cnt, x, y, vx, vy, q0, q1, &m, &lo, &hi, &u0, &u1, &w0, &w1,
                        v2fast, fast);
#endif
#ifdef __SSE2__
    __m128d dt = _mm_set1_pd(k->dt), mm = _mm_set1_pd(m), mlo = _mm_set1_pd(lo),
            mhi = _mm_set1_pd(hi), mu0 = _mm_set1_pd(u0), mu1 = _mm_set1_pd(u1),
            mw0 = _mm_set1_pd(w0), mw1 = _mm_set1_pd(w1);
    for (; q + 2 <= q1; q += 2) {
        __m128d ux = _mm_add_pd(_mm_loadu_pd(vx + q), _mm_mul_pd(_mm_loadu_pd(ax + q), dt));
        __m128d uy = _mm_add_pd(_mm_loadu_pd(vy + q), _mm_mul_pd(_mm_loadu_pd(ay + q), dt));
        _mm_storeu_pd(ax + q, _mm_setzero_pd()), _mm_storeu_pd(ay + q, _mm_setzero_pd());
        cnt[q] = cnt[q + 1] = 0;
        __m128d nx = _mm_add_pd(_mm_loadu_pd(x + q), _mm_mul_pd(ux, dt));
        __m128d ny = _mm_add_pd(_mm_loadu_pd(y + q), _mm_mul_pd(uy, dt));
        _mm_storeu_pd(vx + q, ux), _mm_storeu_pd(vy + q, uy);
        _mm_storeu_pd(x + q, nx), _mm_storeu_pd(y + q, ny);
        __m128d v2 = _mm_add_pd(_mm_mul_pd(ux, ux), _mm_mul_pd(uy, uy));
        mm = _mm_max_pd(v2, mm);   /* the second operand when the first is NaN */
        *fast |= (uint64_t)_mm_movemask_pd(_mm_cmpgt_pd(v2, _mm_set1_pd(v2fast))) << (q - q0);
        mlo = _mm_min_pd(_mm_min_pd(nx, ny), mlo);
        mhi = _mm_max_pd(_mm_max_pd(nx, ny), mhi);
        mu0 = _mm_min_pd(ux, mu0), mu1 = _mm_max_pd(ux, mu1);
        mw0 = _mm_min_pd(uy, mw0), mw1 = _mm_max_pd(uy, mw1);
    }
    double l[2], h[2], v[2], a[2], b[2], c[2], d[2];
    _mm_storeu_pd(v, mm), _mm_storeu_pd(l, mlo), _mm_storeu_pd(h, mhi);
    _mm_storeu_pd(a, mu0), _mm_storeu_pd(b, mu1), _mm_storeu_pd(c, mw0), _mm_storeu_pd(d, mw1);
    m = v[0] > v[1] ? v[0] : v[1];
    lo = l[0] < l[1] ? l[0] : l[1];
    hi = h[0] > h[1] ? h[0] : h[1];
    u0 = a[0] < a[1] ? a[0] : a[1], u1 = b[0] > b[1] ? b[0] : b[1];
    w0 = c[0] < c[1] ? c[0] : c[1], w1 = d[0] > d[1] ? d[0] : d[1];
#endif
    for (; q < q1; q++) {
        double ux = flaw_kick(k, vx[q], ax[q]), uy = flaw_kick(k, vy[q], ay[q]);
        ax[q] = ay[q] = 0;
        cnt[q] = 0;
        double nx = flaw_drift(k, x[q], ux), ny = flaw_drift(k, y[q], uy);
        vx[q] = ux, vy[q] = uy, x[q] = nx, y[q] = ny;
        double v2 = ux * ux + uy * uy;
        m = v2 > m ? v2 : m;
        *fast |= (uint64_t)(v2 > v2fast) << (q - q0);
        lo = nx < lo ? nx : lo, lo = ny < lo ? ny : lo;
        hi = nx > hi ? nx : hi, hi = ny > hi ? ny : hi;
        u0 = ux < u0 ? ux : u0, u1 = ux > u1 ? ux : u1;
        w0 = uy < w0 ? uy : w0, w1 = uy > w1 ? uy : w1;
    }
    t->v2max = m;
    t->u0 = u0, t->u1 = u1, t->w0 = w0, t->w1 = w1;
    if (!(lo < 0 || hi > k->size))
        return 0;
    int lost = 0;
    t->bounced = 1;
    for (q = q0; q < q1; q++)
        lost |= flaw_bounce(k->size, &x[q], &vx[q]) | flaw_bounce(k->size, &y[q], &vy[q]);
    return lost;
}

/* A free set of accelerations for a tile task (there are as many as
 * tasks that can run at once), the one this thread used last if it is
 * free (its cache holds it); and back. */
static facc *acc_take(fpool *p)
{
    int me = omp_get_thread_num(), k;
#pragma omp critical(psim_force_acc)
    {
        k = me < p->threads ? p->last[me] : -1;
        if (k < 0 || p->busy[k])
            for (k = 0; p->busy[k]; k++)
                ;
        p->busy[k] = 1;
        if (me < p->threads)
            p->last[me] = k;
    }
    return &p->set[k];
}

static void acc_give(fpool *p, facc *a)
{
#pragma omp critical(psim_force_acc)
    p->busy[a - p->set] = 0;
}

/* The records of the tile's particles from its sources' out lists, to
 * its own. */
static int take_records(const fmodel *m, ftile *t)
{
    for (int k = 0; k < 5; k++) {
        if (t->src[k] < 0)
            continue;
        const ftile *u = &m->tiles[t->src[k]];
        for (size_t r = 0; r < u->nout; r++) {
            if (u->out[r].owner - t->first >= t->n)
                continue;
            if (t->nrec == t->rcap &&
                psim_reserve((void **)&t->rec, &t->rcap, t->nrec + 1, sizeof *t->rec))
                return -1;
            t->rec[t->nrec++] = u->out[r];
        }
    }
    return 0;
}

/* The particles q0 + b for the bits b of `fast` (faster than v2fast) that
 * were not yet fast: to the tile's fast ones, their paths so far at most
 * `slow`. */
static int join_fast(const fmodel *m, ftile *t, uint32_t q0, uint64_t fast)
{
    for (; fast; fast &= fast - 1) {
        uint32_t q = q0 + (uint32_t)__builtin_ctzll(fast);
        if (m->is_fast[q])
            continue;
        if (t->nfast == t->fastcap &&
            psim_reserve((void **)&t->fast, &t->fastcap, t->nfast + 1, sizeof *t->fast))
            return -1;
        m->is_fast[q] = 1;
        t->fast[t->nfast++] = (ffast){.q = q, .d = m->slow};
    }
    return 0;
}

/* The tile's fast particles after its move: each one's path grows by its
 * speed times dt, and its position is kept for fast_pairs, here where
 * both are still in the cache (the step's end read them scattered over
 * the store, on one thread). */
static void tile_fast_paths(const fmodel *m, const psim_store *s, ftile *t)
{
    for (size_t k = 0; k < t->nfast; k++) {
        ffast *f = &t->fast[k];
        f->d += sqrt(s->vx[f->q] * s->vx[f->q] + s->vy[f->q] * s->vy[f->q]) * m->law.dt;
        f->x = s->x[f->q];
        f->y = s->y[f->q];
    }
}

/* Sum and move the tile's particles in place (the forces of its sources,
 * the only other readers of its positions, are done). */
static void tile_integrate(const fmodel *m, psim_store *s, ftile *t)
{
    if (take_records(m, t)) {
        t->oom = 1;
        return;
    }
    facc *acc = acc_take(m->acc);
    if (tile_sum(s, t, acc)) {
        t->oom = 1;
        acc_give(m->acc, acc);
        return;
    }
    uint32_t f = t->first;
    double *x = s->x + f, *y = s->y + f, *vx = s->vx + f, *vy = s->vy + f;
    int lost = 0;
    for (uint32_t q = 0; q < t->n; q += MOVE_CHUNK) {
        uint32_t q1 = t->n - q < MOVE_CHUNK ? t->n : q + MOVE_CHUNK;
        uint64_t fast;
        lost |= move_chunk(&m->law, t, acc, x, y, vx, vy, q, q1, m->simd, m->v2fast, &fast);
        if (fast && join_fast(m, t, f + q, fast)) {
            t->oom = 1;
            break;
        }
    }
    tile_fast_paths(m, s, t);
    acc_give(m->acc, acc);
    t->lost = lost;
}

/* The course's loops: every j, in id order (the store is, without a grid). */
static void block_naive(const fmodel *m, psim_store *s, ftile *t)
{
    const flaw *k = &m->law;
    const size_t n = s->n;
    tile_reset(t);
    uint64_t polled = 0;   /* n pair tests a particle: a poll every PSIM_POLL_WORK */
    for (uint32_t q = 0; q < t->n; q++) {
        if (t->tests - polled >= PSIM_POLL_WORK) {
            if (psim_poll(m->sim, t->tests - polled))
                return;   /* a stop asked: the step is abandoned */
            polled = t->tests;
        }
        uint32_t i = t->first + q;
        double px = s->x[i], py = s->y[i], ax = 0, ay = 0;
        uint64_t hits = 0;
        for (size_t j = 0; j < n; j++)
            hits += (uint64_t)flaw_pair(k, px, py, s->x[j], s->y[j], &ax, &ay);
        if (m->stats)
            for (size_t j = 0; j < n; j++)
                pair_stats(k, t, px, py, s->x[j], s->y[j]);
        t->tests += n;
        t->hits += hits - 1;   /* not itself */
        move_one(k, s, t, i, ax, ay);
    }
}

/* Over ranks: whether one of tile t's own particles (not a ghost, whose
 * move misses the forces from beyond the halo) is outside the box. */
static int owned_outside(const psim_sim *e, const fmodel *m, const ftile *t)
{
    const psim_store *s = &e->st;
    const double L = m->law.size;
    for (uint32_t i = t->first; i < t->first + t->n; i++)
        if (!psim_engine_ghost(e, i) && !(s->x[i] >= 0 && s->x[i] <= L && s->y[i] >= 0 &&
                                          s->y[i] <= L))
            return 1;
    return 0;
}

/* Totals of the tiles, in tile order: -1 if a particle left the box,
 * -2 if a tile ran out of memory. */
static int finish(psim_sim *e, fmodel *m)
{
    double v2max = 0, dmin = 1.0, dsum = 0, u0 = INFINITY, u1 = -INFINITY, w0 = INFINITY,
           w1 = -INFINITY;
    uint64_t tests = 0, hits = 0, dn = 0, sorted = 0;
    int lost = 0, oom = 0, bounced = m->naive;   /* naive: no extents, the plain bound */
    for (uint32_t t = 0; t < m->ntiles; t++) {
        const ftile *ft = &m->tiles[t];
        oom |= ft->oom;
        v2max = fmax(v2max, ft->v2max);
        u0 = fmin(u0, ft->u0), u1 = fmax(u1, ft->u1);
        w0 = fmin(w0, ft->w0), w1 = fmax(w1, ft->w1);
        bounced |= ft->bounced;
        tests += ft->tests;
        hits += ft->hits;
        sorted += ft->sorted;
        dmin = fmin(dmin, ft->dmin);
        dsum += ft->dsum;
        dn += ft->dn;
        lost |= ft->lost && (psim_engine_ranks(e) == 1 || owned_outside(e, m, ft));
    }
    e->stats.counter[FC_PAIR_TESTS] += tests;
    e->stats.counter[FC_INTERACTIONS] += hits;
    e->stats.counter[FC_SORTED] += sorted;
    /* half of any pair's closing this step: the largest speed, or without
     * reflections (they move a particle elsewhere than v dt) the
     * half-diagonal of the velocities' extent when smaller */
    double vmax = sqrt(v2max), hw = 0.5 * hypot(u1 - u0, w1 - w0) * (1 + 1e-12);
    /* over ranks: how far any particle went (v dt, the rounding of x) */
    psim_engine_moved(e, vmax * m->law.dt + 8 * DBL_EPSILON * m->law.size);
    m->drift += (bounced || !m->skip || !(hw < vmax) ? vmax : hw) * m->law.dt;
    m->since_build++;
    e->stats.skipped[FS_WALLS] += !bounced && !m->naive;
    /* at rest from the next step but one (a first quiet step may still turn
     * -0 into +0): no force, no speed, no wall */
    m->quiet = hits == 0 && v2max == 0 && !bounced && !lost ? m->quiet + 1 : 0;
    if (m->stats) {            /* the course's per-step bookkeeping, every rank's */
        double sum[2] = {dsum, (double)dn};
        psim_engine_reduce(e, sum, 2, &dmin, 1);
        dsum = sum[0], dn = (uint64_t)sum[1];
        if (dn) {
            m->absavg += dsum / (double)dn;
            m->nabsavg++;
        }
        if (dmin < m->absmin)
            m->absmin = dmin;
    }
    return oom ? -2 : lost ? -1 : 0;
}

/* How many shells may hold pairs within the cutoff: shell b's pairs
 * were more than cutoff + b skin / B apart at the build, and have closed
 * in by at most `closing` since. */
static int active_shells(const fmodel *m, double closing)
{
    double width = m->skin / FORCE_BUCKETS;
    int nb = 1;
    while (nb < FORCE_BUCKETS && nb * width <= closing)
        nb++;
    return nb;
}

/* Tile t's particles and those of the tiles in nb[0..5) (-1: none): how
 * far two of them may have closed in since the build, from the tiles'
 * drifts (each particle of a tile moved at most its tile's drift, plus
 * the same few ulps a step as force_drift_bound), at most 2 drift
 * bounds. */
static double tiles_closing(const fmodel *m, uint32_t t, const int32_t *nb)
{
    double most = m->tiles[t].drift, ulps = force_drift_bound(m) - m->drift;
    for (int k = 0; k < 5; k++)
        if (nb[k] >= 0 && m->tiles[nb[k]].drift > most)
            most = m->tiles[nb[k]].drift;
    double c = m->tiles[t].drift + most + 2 * ulps, all = 2 * force_drift_bound(m);
    return c < all ? c : all;
}

/* Two fast particles close in by at most the sum of their paths; but
 * only a pair within the cutoff now needs to be listed.  The largest sum
 * over such pairs (0: none), found through a hash of the fast particles'
 * cells (cells a cutoff wide: a pair within the cutoff is in the same or
 * adjacent cells), with the same test as the pair tests' (NaN counts);
 * with more than FORCE_FAST_MAX_SHARE of the particles fast, or a
 * position not finite, the sum of the two longest paths (p1 + second). */
#define FORCE_FAST_MAX_SHARE (1.0 / 64)
static uint64_t fast_key(int64_t cx, int64_t cy)
{
    return ((uint64_t)cx << 32) ^ (uint64_t)(uint32_t)cy;
}

/* The slot of key in this step's table (2^(64 - fh_shift) entries, the
 * first of the arrays): where it is, or the empty slot it would take. */
static size_t fast_slot(const fmodel *m, uint64_t key)
{
    const size_t mask = ((size_t)1 << (64 - m->fh_shift)) - 1;
    size_t h = (size_t)((key * 0x9E3779B97F4A7C15ull) >> m->fh_shift);   /* the top bits */
    while (m->fh_head[h] >= 0 && m->fh_key[h] != key)
        h = (h + 1) & mask;
    return h;
}

/* (nf fast particles; p1 and second the two longest paths) */
static double fast_pairs(fmodel *m, const psim_store *s, size_t nf, double p1, double second)
{
    if (nf < 2)
        return 0;
    size_t size = 16;   /* the table: a power of two, at most half full */
    int shift = 60;
    while (size < 2 * nf)
        size *= 2, shift--;
    size_t c1 = m->fp_cap, c3 = m->fh_cap;
    if ((double)nf > FORCE_FAST_MAX_SHARE * (double)s->n ||
        psim_reserve((void **)&m->fp, &c1, nf, sizeof *m->fp) ||
        psim_reserve((void **)&m->fp_next, &m->fp_cap, nf, sizeof *m->fp_next) ||
        psim_reserve((void **)&m->fh_key, &c3, size, sizeof *m->fh_key) ||
        psim_reserve((void **)&m->fh_head, &m->fh_cap, size, sizeof *m->fh_head))
        return p1 + second;
    m->fh_shift = shift;
    for (size_t h = 0; h < size; h++)
        m->fh_head[h] = -1;
    /* cells a little wider than the cutoff, and at most 1e6 of them from
     * 0: a pair within the cutoff is in the same or adjacent cells however
     * x / side rounds */
    const double inv = 1 / (m->law.cutoff * (1 + 1e-9));
    /* a pair adds more than the longest path plus `slow` only if one of
     * the two is more than half as far beyond `slow` as the longest: only
     * those look for partners (the others are only found) */
    const double half = m->slow + 0.5 * (p1 - m->slow);
    size_t k = 0;
    for (uint32_t t = 0; t < m->ntiles; t++)
        for (size_t f = 0; f < m->tiles[t].nfast; f++, k++) {
            const ffast *p = &m->tiles[t].fast[f];
            double cx = floor(p->x * inv), cy = floor(p->y * inv);
            if (!(fabs(cx) < 1e6 && fabs(cy) < 1e6))   /* not finite, or far out */
                return p1 + second;
            m->fp[k] = *p;
            size_t h = fast_slot(m, fast_key((int64_t)cx, (int64_t)cy));
            m->fh_key[h] = fast_key((int64_t)cx, (int64_t)cy);
            m->fp_next[k] = m->fh_head[h];
            m->fh_head[h] = (int32_t)k;
        }
    double most = 0;
    for (k = 0; k < nf; k++) {
        if (!(m->fp[k].d >= half))
            continue;
        const double xi = m->fp[k].x, yi = m->fp[k].y;
        int64_t cx = (int64_t)floor(xi * inv), cy = (int64_t)floor(yi * inv);
        for (int64_t dy = -1; dy <= 1; dy++)
            for (int64_t dx = -1; dx <= 1; dx++) {
                size_t h = fast_slot(m, fast_key(cx + dx, cy + dy));
                for (int32_t l = m->fh_head[h]; l >= 0; l = m->fp_next[l]) {
                    if ((size_t)l == k || ((size_t)l < k && m->fp[l].d >= half))
                        continue;   /* itself, or a pair met from l */
                    double ex = m->fp[l].x - xi, ey = m->fp[l].y - yi;
                    double d = m->fp[k].d + m->fp[l].d;
                    if (!(ex * ex + ey * ey > m->law.cutoff2) && d > most)
                        most = d;
                }
            }
    }
    return most;
}

/* After a step: each tile's drift, and how far any two particles may
 * have closed in since the build (the least of three bounds):
 *   - twice the largest tile drift (two particles of any tiles t, u close
 *     in by at most drift t + drift u);
 *   - 2 drift bounds (the sum over the steps of the largest of the tiles'
 *     speeds is no less than the largest tile's sum);
 *   - from the fast particles: each fast one's path (the sum of its speeds
 *     times dt since it became fast, plus `slow` before), and `slow`, the
 *     steps since the build times the speed sqrt(v2fast), for the others:
 *     the two longest paths, or the longest and `slow`, or twice `slow`.
 * The box's fastest particle sets the first two; a few fast particles
 * each close in at their own speed with the slow rest (fewer rebuilds). */
static void tiles_drift(fmodel *m, const psim_store *s)
{
    double most = 0, ulps = force_drift_bound(m) - m->drift, all = 2 * force_drift_bound(m);
    double p1 = 0, p2 = 0;   /* the two longest paths of fast particles */
    size_t nf = 0;
    m->slow += sqrt(m->v2fast) * m->law.dt;
    for (uint32_t t = 0; t < m->ntiles; t++) {
        ftile *ft = &m->tiles[t];
        ft->drift += sqrt(ft->v2max) * m->law.dt;
        most = ft->drift > most ? ft->drift : most;
        nf += ft->nfast;
        for (size_t k = 0; k < ft->nfast; k++) {
            double d = ft->fast[k].d;   /* grown by the tile's move (tile_fast_paths) */
            if (d > p1)
                p2 = p1, p1 = d;
            else if (d > p2)
                p2 = d;
        }
    }
    double slow = m->slow, fast = 2 * slow;
    double pair = fast_pairs(m, s, nf, p1, p2);   /* p1 + p2 when not looked at */
    fast = p1 + slow > fast ? p1 + slow : fast;
    fast = pair > fast ? pair : fast;
    fast += 2 * ulps;
    double c = 2 * (most + ulps) < all ? 2 * (most + ulps) : all;
    m->closing = fast < c ? fast : c;   /* NaN speeds: the box's bound (all) */
    if (!(m->closing == m->closing))
        m->closing = all;
}

/* Over ranks: the two longest paths of the rank's own particles since the
 * build (the exchange), for the engine's choice of the next exchange: a
 * fast one's (ffast.d), `slow` for every other, each with the rounding of
 * its positions (a ghost's own moves are not its owner's: left out). */
static void owned_paths(psim_sim *e, const fmodel *m)
{
    double p1 = m->slow, p2 = m->slow, ulps = force_drift_bound(m) - m->drift;
    for (uint32_t t = 0; t < m->ntiles; t++)
        for (size_t k = 0; k < m->tiles[t].nfast; k++) {
            const ffast *f = &m->tiles[t].fast[k];
            double d = f->d == f->d ? f->d : INFINITY;   /* NaN: no bound */
            if (psim_engine_ghost(e, f->q))
                continue;
            if (d > p1)
                p2 = p1, p1 = d;
            else if (d > p2)
                p2 = d;
        }
    psim_engine_paths(e, p1 + ulps, p2 + ulps);
}

typedef void (*tile_fn)(const fmodel *m, psim_store *s, ftile *t);

/* Tile ft's fn, timed as phase (its seconds kept in the tile: tf for the
 * force, ti for the rest), and a poll with its pair tests (the naive
 * loop's own polls count those); after a stop asked, nothing (the step is
 * abandoned).  region: the tile is its own LIKWID region of the phase, in
 * the thread that runs it (where the force and the integrate tiles
 * interleave: src/engine/timer.h). */
static void tile_timed(const fmodel *m, psim_store *s, psim_thread_stats *ts, tile_fn fn,
                       int phase, int region, ftile *ft)
{
    if (psim_stop_requested())
        return;
    if (region)
        PSIM_REGION_THREAD_BEGIN(m->sim, phase);
    double b0 = psim_now();
    fn(m, s, ft);
    double dt = psim_now() - b0;
    if (region)
        PSIM_REGION_THREAD_END(m->sim, phase);
    *(phase == FPHASE_FORCE ? &ft->tf : &ft->ti) = dt;
    psim_tstat_add(ts, phase, dt, 1, ft->n);
    psim_poll(m->sim, phase == FPHASE_FORCE && !m->naive ? ft->tests : 0);
}

/* Tile ft's task running fn, timed as phase, a region of its own if
 * region (src/engine/task.h). */
PSIM_TASK_SPAWN static void task_spawn_tile(const fmodel *m, psim_store *s, psim_thread_stats *ts,
                                            tile_fn fn, int phase, int region, int graph,
                                            ftile *ft)
{
#pragma omp task firstprivate(ft, m, s, ts, fn, phase, region) default(none) if (graph)
    tile_timed(m, s, ts, fn, phase, region, ft);
}

/* Over ranks, while the ghosts' positions travel, a step does first the
 * work that reads none (part 1), then waits for them and does the rest
 * (part 2); part 0 is the whole step.  Whether tile t's force (force) or
 * its sums and moves (!force) belong to part `part`. */
enum { PART_ALL, PART_INNER, PART_REST };
static inline int in_part(const ftile *t, int part, int force)
{
    int inner = force ? t->inner : t->early;
    return part == PART_ALL || (part == PART_INNER) == (inner != 0);
}

/* The same in the one-thread sweep, whose part 1 runs only the forces
 * that early tiles' sums need (ftile.lead): another inner tile's force
 * there would be far from its sums and moves in part 2, out of the cache
 * the sweep keeps them in. */
static inline int in_sweep_part(const ftile *t, int part, int force)
{
    int inner = force ? t->lead : t->early;
    return part == PART_ALL || (part == PART_INNER) == (inner != 0);
}

/* After a build over ranks: which tiles are inner and early (ftile), from
 * the ghosts' places (tiles are runs of places in tile order). */
static void tiles_inner(const psim_sim *e, fmodel *m)
{
    const uint32_t *g;
    size_t ng = psim_engine_ghosts(e, &g);
    for (uint32_t t = 0; t < m->ntiles; t++)
        m->tiles[t].early = 0;   /* here: holds a ghost */
    for (size_t k = 0; k < ng; k++) {
        uint32_t lo = 0, hi = m->ntiles;   /* the last tile starting at or before g[k] */
        while (hi - lo > 1) {
            uint32_t mid = lo + (hi - lo) / 2;
            if (m->tiles[mid].first <= g[k])
                lo = mid;
            else
                hi = mid;
        }
        ftile *ft = &m->tiles[lo];
        if (m->ntiles && g[k] - ft->first < ft->n)
            ft->early = 1;
        else   /* outside every tile: no tile runs early */
            for (uint32_t t = 0; t < m->ntiles; t++)
                m->tiles[t].early = 1;
    }
    for (uint32_t t = 0; t < m->ntiles; t++) {
        int in = !m->tiles[t].early;
        for (int k = 0; k < 5; k++)
            in &= m->tiles[t].fwd[k] < 0 || !m->tiles[m->tiles[t].fwd[k]].early;
        m->tiles[t].inner = (uint8_t)in;
    }
    for (uint32_t t = 0; t < m->ntiles; t++) {
        int in = m->tiles[t].inner;
        for (int k = 0; k < 5; k++)
            in &= m->tiles[t].src[k] < 0 || m->tiles[m->tiles[t].src[k]].inner;
        m->tiles[t].early = (uint8_t)in;
    }
    m->nlead = 0;
    for (uint32_t t = 0; t < m->ntiles; t++) {
        int lead = m->tiles[t].early;
        for (int k = 0; k < 5; k++)   /* its lists reach the tiles it is a source of */
            lead |= m->tiles[t].fwd[k] >= 0 && m->tiles[m->tiles[t].fwd[k]].early;
        m->tiles[t].lead = (uint8_t)lead;
        m->nlead += (uint32_t)lead;
    }
}

/* One task per tile running fn, timed as phase, each a region of its own
 * if region; returns when all are done (called inside a parallel region's
 * single). */
static void run_tiles(const fmodel *m, psim_store *s, psim_thread_stats *ts, tile_fn fn,
                      int phase, int region, int graph)
{
    for (uint32_t t = 0; t < m->ntiles; t++)
        task_spawn_tile(m, s, ts, fn, phase, region, graph, &m->tiles[t]);
#pragma omp taskwait
}

/* The tasks of the forces of part `part`'s tiles, not waited for. */
static void spawn_forces(const fmodel *m, psim_store *s, psim_thread_stats *ts, int part)
{
    for (uint32_t t = 0; t < m->ntiles; t++)
        if (in_part(&m->tiles[t], part, 1))
            task_spawn_tile(m, s, ts, tile_force, FPHASE_FORCE, 1, 1, &m->tiles[t]);
}

/* A round of fn over every tile as a loop shared by the team (called by
 * every thread of a parallel region; its end is the round's barrier).
 * The tiles of a round do not depend on each other, so a loop gives what
 * a task a tile gives without libgomp's one lock on the team's task queue:
 * at 8 and 16 threads, 1e5 particles, 1.7-2x faster (docs/performance.md,
 * "Rounds as loops on many threads").  Static: each thread keeps its tiles, and their
 * particles in its cache, from round to round and step to step; dynamic:
 * the threads share the tiles as they come.  Only part `part`'s tiles. */
static void run_round(const fmodel *m, psim_store *s, psim_thread_stats *ts, tile_fn fn,
                      int phase, int part)
{
    const int force = fn == tile_force;
    if (m->rounds == FORCE_ROUNDS_STATIC) {
#pragma omp for schedule(static)
        for (uint32_t t = 0; t < m->ntiles; t++)
            if (in_part(&m->tiles[t], part, force))
                tile_timed(m, s, ts, fn, phase, 0, &m->tiles[t]);
    } else {
#pragma omp for schedule(dynamic, 1)
        for (uint32_t t = 0; t < m->ntiles; t++)
            if (in_part(&m->tiles[t], part, force))
                tile_timed(m, s, ts, fn, phase, 0, &m->tiles[t]);
    }
}

/* One thread (or one tile): a sweep row by row of the tile grid, each
 * tile's force, then the integrate of the tile to its west (whose
 * sources' forces are all done once its east neighbour's is), and the
 * row's last tile's: the positions the forces have just read are still
 * in the cache when they move (1e6 particles: forces and moves 11% less
 * than in two rounds).  Only part `part`'s work (in_sweep_part): a
 * tile's integrate in part 1 needs only forces of part 1, and no later
 * force reads its positions (ftile.early, ftile.lead), so the two parts'
 * sweeps keep the order. */
static void run_sweep(const fmodel *m, psim_store *s, psim_thread_stats *ts, int part)
{
    const uint32_t row = (uint32_t)m->sweep_row;
    for (uint32_t k = 0; k < m->ntiles; k++) {
        ftile *t = &m->tiles[m->sweep[k]], *w = k % row > 0 ? &m->tiles[m->sweep[k - 1]] : NULL;
        if (in_sweep_part(t, part, 1))
            tile_timed(m, s, ts, tile_force, FPHASE_FORCE, 1, t);
        if (w && in_sweep_part(w, part, 0))
            tile_timed(m, s, ts, tile_integrate, FPHASE_INTEGRATE, 1, w);
        if (k % row == row - 1 && in_sweep_part(t, part, 0))
            tile_timed(m, s, ts, tile_integrate, FPHASE_INTEGRATE, 1, t);
    }
}

/* The step's tasks, each tile a region of its own: one thread, the sweep
 * (run_sweep); threads: two rounds, every force, then every integrate
 * (the same work as dependencies of the sweep cost 7-10% more at 1e5
 * particles, some 32 tasks a step: docs/performance.md).  split: the
 * ghosts' positions are on their way; the forces that read none first,
 * the wait (in the main thread: MPI calls are funneled), then the rest;
 * the seconds waited to *waited.  Called by the team's main thread. */
static void run_step(psim_sim *e, const fmodel *m, psim_store *s, psim_thread_stats *ts,
                     int graph, int split, double *waited)
{
    if (!graph) {
        if (split && !m->nlead)   /* nothing to do before the ghosts */
            *waited = psim_engine_halo_wait(e), split = 0;
        run_sweep(m, s, ts, split ? PART_INNER : PART_ALL);
        if (split) {
            *waited = psim_engine_halo_wait(e);
            run_sweep(m, s, ts, PART_REST);
        }
        return;
    }
    if (split) {
        spawn_forces(m, s, ts, PART_INNER);   /* the team runs them while this one waits */
        *waited = psim_engine_halo_wait(e);
        spawn_forces(m, s, ts, PART_REST);
#pragma omp taskwait
    } else
        run_tiles(m, s, ts, tile_force, FPHASE_FORCE, 1, graph);
    run_tiles(m, s, ts, tile_integrate, FPHASE_INTEGRATE, 1, graph);
}

int force_step_lists(psim_sim *e, fmodel *m)
{
    psim_store *s = &e->st;
    psim_thread_stats *ts = e->tstats;
    /* over ranks the ghosts' motion is their owners': the shells from
     * every rank's largest drift since the exchange (the build) */
    const int ranks = psim_engine_ranks(e) > 1;
    const double across = 2 * psim_engine_drift(e) + 2 * (force_drift_bound(m) - m->drift);
    for (uint32_t t = 0; t < m->ntiles; t++) {
        double c = tiles_closing(m, t, m->tiles[t].fwd);
        m->tiles[t].shells = active_shells(m, ranks ? across : c < m->closing ? c : m->closing);
    }
    if (ranks && m->since_build == 0)
        tiles_inner(e, m);
    const int split = psim_engine_halo_pending(e);
    double t0 = psim_now(), waited = 0;
    /* one thread, or one tile: the same calls in order */
    const int graph = e->threads > 1 && m->ntiles > 1;
    if (graph && m->rounds != FORCE_ROUNDS_TASKS) {
#pragma omp parallel num_threads(e->threads)
        {
            /* a region a round in every thread, to the round's barrier */
            PSIM_REGION_THREAD_BEGIN(e, FPHASE_FORCE);
            run_round(m, s, ts, tile_force, FPHASE_FORCE, split ? PART_INNER : PART_ALL);
            if (split) {
#pragma omp master
                waited = psim_engine_halo_wait(e);
#pragma omp barrier
                run_round(m, s, ts, tile_force, FPHASE_FORCE, PART_REST);
            }
            PSIM_REGION_THREAD_END(e, FPHASE_FORCE);
            PSIM_REGION_THREAD_BEGIN(e, FPHASE_INTEGRATE);
            run_round(m, s, ts, tile_integrate, FPHASE_INTEGRATE, PART_ALL);
            PSIM_REGION_THREAD_END(e, FPHASE_INTEGRATE);
        }
    } else if (graph) {
#pragma omp parallel num_threads(e->threads)
#pragma omp master
        run_step(e, m, s, ts, graph, split, &waited);
    } else
        run_step(e, m, s, ts, graph, split, &waited);
    e->stats.skipped[FS_GRAPH] += !graph;
    /* the phases interleave: the step's time split as the tasks' (the
     * wait for the ghosts is the engine's comm phase) */
    double wall = psim_now() - t0 - waited, tf = 0, ti = 0;
    for (uint32_t t = 0; t < m->ntiles; t++)
        tf += m->tiles[t].tf, ti += m->tiles[t].ti;
    double share = tf + ti > 0 ? tf / (tf + ti) : 0.5;
    e->stats.phase_s[FPHASE_FORCE] += wall * share;
    e->stats.phase_s[FPHASE_INTEGRATE] += wall * (1 - share);
    e->stats.counter[FC_TASKS] += graph && m->rounds == FORCE_ROUNDS_TASKS ? 2 * m->ntiles : 0;
    int rc = finish(e, m);
    /* the bookkeeping of the moves: timed with them */
    PSIM_TIMED(e, FPHASE_INTEGRATE, tiles_drift(m, s));
    if (ranks)
        owned_paths(e, m);
    return rc;
}

/* The course's loops, new positions to the scratch arrays, swapped in. */
int force_step_naive(psim_sim *e, fmodel *m)
{
    psim_store *s = &e->st;
    PSIM_REGION_BEGIN(e, FPHASE_FORCE);
    double t0 = psim_now();
#pragma omp parallel num_threads(e->threads)
#pragma omp single
    run_tiles(m, s, e->tstats, block_naive, FPHASE_FORCE, 0, 1);
    e->stats.phase_s[FPHASE_FORCE] += psim_now() - t0;
    PSIM_REGION_END(e, FPHASE_FORCE);
    e->stats.counter[FC_TASKS] += m->ntiles;
    double *tx = s->x, *ty = s->y;
    s->x = s->x2, s->y = s->y2;
    s->x2 = tx, s->y2 = ty;
    return finish(e, m);
}

/* Blocks of the naive loop, as tiles without lists. */
int force_plan_naive(fmodel *m, long n)
{
    uint32_t nb = (uint32_t)((n + NAIVE_BLOCK - 1) / NAIVE_BLOCK);
    m->tiles = calloc(nb ? nb : 1, sizeof *m->tiles);
    if (!m->tiles)
        return -1;
    m->ntiles = m->cap_tiles = nb;
    for (uint32_t b = 0; b < nb; b++) {
        m->tiles[b].first = b * NAIVE_BLOCK;
        m->tiles[b].n = (uint32_t)(n - (long)b * NAIVE_BLOCK < NAIVE_BLOCK
                                       ? n - (long)b * NAIVE_BLOCK : NAIVE_BLOCK);
    }
    return 0;
}
