/* The ccd model's GPU path (gpu.h; docs/gpu.md).
 *
 * The state lives on the device between steps (the engine's device store,
 * gpu_store.cuh), with each disk's collision counts by id.  A step:
 *   detect  the largest |vx| + |vy| (a block reduction); bands along y
 *           at least ccd_reach high (re-planned only when too low or far
 *           too high, as the CPU path's cells), so that a pair that can
 *           meet is in the same or adjacent bands; the disks sorted by
 *           band, and within a band by the left edge of their swept box
 *           (two stable radix sorts), and the boxes; then a thread a
 *           disk: its wall candidate, and a sweep along x of its own band
 *           after it and of the band above, the rules (rules.h's
 *           functions) run on each pair whose boxes overlap, appended to
 *           one list; where the list overflows it grows and the search
 *           runs again.  On the course generator's scenes a disk crosses
 *           up to a third of the box a step: one band, the sweep alone;
 *   order   a stable radix sort of the candidates' places by their id
 *           key, then by their time key (cand.h): the total order;
 *   accept  rounds: each disk's first live candidate (atomic minimum of
 *           places in the order), the candidates first for both their
 *           disks accepted, those that touch a disk just taken dropped,
 *           until none is live: the greedy set (order.c says why);
 *   move    a thread an accepted candidate (as advance.c's apply), then a
 *           thread a disk for the free flight of the others.
 * Every candidate the CPU path finds is found here (the same cells'
 * reach, the same rules on the same doubles), the order is total, and the
 * arithmetic is compiled with --fmad=false and IEEE division and square
 * root (cmake/cuda.cmake): the results are the CPU path's bit for bit. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cub/block/block_reduce.cuh>
#include <cub/device/device_radix_sort.cuh>
#include <cuda_runtime.h>

#include "../../engine/gpu_store.cuh"
extern "C" {
#include "../../engine/timer.h"
#include "gpu.h"
#include "rules.h"
#include "sweep.h"
}

/* Counts the device keeps for a step, read back after its parts. */
typedef struct ccounts {
    unsigned long long found;   /* candidates found (may exceed the room) */
    unsigned long long walls;   /* wall candidates among them */
    unsigned long long tests;   /* pairs whose boxes overlap, tested */
    unsigned long long pair_colls, wall_colls;
    unsigned long long vmax;    /* bits of the largest |vx| + |vy| (>= 0) */
    int more;                   /* acceptance: a candidate is still live */
} ccounts;

struct cgpu {
    psim_store *st;
    double L, r;
    int device;
    psim_dstore d;
    psim_gpu_grid bands;        /* side: the bands along y */
    int band_bits;              /* the bits of the largest band */
    double bands_reach;         /* the reach they were planned for (0: none) */
    double grow;                /* r and the margin: the boxes' growth this step */
    unsigned long long *wbits;  /* the widest box, as bits */
    int64_t *pcoll, *wcoll;     /* by id */
    ccand *cand, *cand2;        /* found; in order */
    uint64_t *k, *k2;           /* sort keys */
    uint32_t *ix, *ix2;         /* places of candidates, sorted with them */
    uint8_t *live;              /* per candidate in order: 0 dropped, 1 live, 2 accepted */
    size_t cap;                 /* candidates every candidate array holds */
    void *tmp;                  /* the candidates' sorts' scratch */
    size_t tmp_bytes;
    uint8_t *busy;              /* per place: in an accepted collision */
    uint32_t *best;             /* per place: its first live candidate */
    ccounts *cnt;
    size_t ncand;               /* the last step's candidates */
    int newer;                  /* the device's state is newer than the store's */
};

struct dmax {
    __device__ double operator()(double a, double b) const { return a > b ? a : b; }
};

/* The largest v >= 0 of a block's threads into *bits, as bits (a double
 * >= 0 orders as its bits; NaN is never larger). */
__device__ static void block_max(double v, unsigned long long *bits)
{
    typedef cub::BlockReduce<double, PSIM_GPU_THREADS> reduce;
    __shared__ typename reduce::TempStorage shared;
    double top = reduce(shared).Reduce(v > 0 ? v : 0, dmax());
    if (threadIdx.x == 0 && top > 0)
        atomicMax(bits, (unsigned long long)__double_as_longlong(top));
}

/* The largest |vx| + |vy|, as the CPU path's. */
__global__ static void k_vmax(const double *vx, const double *vy, uint32_t n, ccounts *c)
{
    uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    block_max(i < n ? fabs(vx[i]) + fabs(vy[i]) : 0, &c->vmax);
}

/* The left edge of each disk's swept box (grown by g) as an ordered key,
 * and its place. */
__global__ static void k_edges(const double *x, const double *vx, uint32_t n, double g,
                               uint64_t *key, uint32_t *place)
{
    uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n)
        return;
    double b[4];
    ccd_box(x[i], 0, vx[i], 0, g, b);
    key[i] = ccd_time_key(b[0]);   /* (the ordered bits of a double) */
    place[i] = i;
}

/* Each disk's band, in the order of the edges, with its place. */
__global__ static void k_bands(const uint32_t *order, const double *y, uint32_t n,
                               psim_gpu_grid bands, uint32_t *key, uint32_t *place)
{
    uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= n)
        return;
    uint32_t i = order[k];
    key[k] = (uint32_t)psim_gpu_cell(&bands, y[i]);
    place[k] = i;
}

/* The swept boxes of the sorted disks, and the widest (as bits). */
__global__ static void k_boxes(const double *x, const double *y, const double *vx,
                               const double *vy, uint32_t n, double g, double *bx0,
                               double *bx1, double *by0, double *by1,
                               unsigned long long *wmax)
{
    uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    double w = 0;
    if (i < n) {
        double b[4];
        ccd_box(x[i], y[i], vx[i], vy[i], g, b);
        bx0[i] = b[0], bx1[i] = b[1], by0[i] = b[2], by1[i] = b[3];
        w = b[1] - b[0];
    }
    block_max(w, wmax);
}

/* Candidate k of the list, where there is room. */
__device__ static inline void put(ccand *cand, size_t cap, ccounts *c, ccand v)
{
    unsigned long long k = atomicAdd(&c->found, 1ULL);
    if (k < cap)
        cand[k] = v;
}

/* Disk i's wall candidate, and its pair candidates (sweep.h). */
__global__ static void k_detect(ccd_sweep S, const double *x, const double *y, const double *vx,
                                const double *vy, const int32_t *id, const unsigned long long *wbits,
                                double L, double r, ccand *cand, size_t cap, ccounts *c)
{
    typedef cub::BlockReduce<unsigned long long, PSIM_GPU_THREADS> reduce;
    __shared__ typename reduce::TempStorage shared;
    uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    unsigned long long tests = 0, walls = 0;
    if (i < S.n) {
        ccand v;
        if (ccd_wall_time(x[i], y[i], vx[i], vy[i], 1.0, L, r, &v.t)) {
            v.p = id[i], v.q = -1, v.sp = i, v.sq = UINT32_MAX;
            put(cand, cap, c, v);
            walls++;
        }
        S.wmax = __longlong_as_double((long long)*wbits);
        ccd_walk w;
        uint32_t j;
        for (ccd_walk_start(&S, i, &w); ccd_walk_next(&S, &w, &j);) {
            tests++;
            if (ccd_pair_test(i, j, x, y, vx, vy, id, r, &v))
                put(cand, cap, c, v);
        }
    }
    unsigned long long t = reduce(shared).Sum(tests);
    __syncthreads();
    unsigned long long w = reduce(shared).Sum(walls);
    if (threadIdx.x == 0) {
        if (t)
            atomicAdd(&c->tests, t);
        if (w)
            atomicAdd(&c->walls, w);
    }
}

/* The sort keys of the candidates at ix (ix = NULL: the candidates'
 * own places, which go to ix_out): by id (time = 0), or by time. */
__global__ static void k_keys(const ccand *cand, const uint32_t *ix, uint32_t nc, int time,
                              uint64_t *key, uint32_t *ix_out)
{
    uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= nc)
        return;
    uint32_t at = ix ? ix[k] : k;
    if (!ix)
        ix_out[k] = k;
    key[k] = time ? ccd_time_key(cand[at].t) : ccd_id_key(cand[at].p, cand[at].q);
}

__global__ static void k_gather(const ccand *cand, const uint32_t *ix, uint32_t nc, ccand *out)
{
    uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k < nc)
        out[k] = cand[ix[k]];
}

/* Acceptance, a round's parts (order.c's accept_par). */
__global__ static void k_best_reset(const ccand *c, uint32_t nc, uint32_t *best)
{
    uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= nc)
        return;
    best[c[k].sp] = UINT32_MAX;
    if (c[k].q >= 0)
        best[c[k].sq] = UINT32_MAX;
}

__global__ static void k_best_min(const ccand *c, uint32_t nc, const uint8_t *live,
                                  uint32_t *best)
{
    uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= nc || live[k] != 1)
        return;
    atomicMin(&best[c[k].sp], k);
    if (c[k].q >= 0)
        atomicMin(&best[c[k].sq], k);
}

__global__ static void k_take(const ccand *c, uint32_t nc, uint8_t *live, const uint32_t *best,
                              uint8_t *busy)
{
    uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= nc || live[k] != 1 || best[c[k].sp] != k || (c[k].q >= 0 && best[c[k].sq] != k))
        return;
    busy[c[k].sp] = 1;
    if (c[k].q >= 0)
        busy[c[k].sq] = 1;
    live[k] = 2;
}

__global__ static void k_drop(const ccand *c, uint32_t nc, uint8_t *live, const uint8_t *busy,
                              ccounts *cnt)
{
    uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= nc || live[k] != 1)
        return;
    if (busy[c[k].sp] || (c[k].q >= 0 && busy[c[k].sq]))
        live[k] = 0;
    else
        cnt->more = 1;
}

/* An accepted collision (rules.h's ccd_apply, as the CPU path's). */
__global__ static void k_apply(const ccand *cand, uint32_t nc, const uint8_t *live, double L,
                               double r, double *x, double *y, double *vx, double *vy,
                               int64_t *pcoll, int64_t *wcoll, ccounts *cnt)
{
    uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= nc || live[k] != 2)
        return;
    const ccand c = cand[k];
    int wall = ccd_apply(&c, x, y, vx, vy, pcoll, wcoll, L, r);
    atomicAdd(wall ? &cnt->wall_colls : &cnt->pair_colls, 1ULL);
}

/* Free flight of every disk not in an accepted collision. */
__global__ static void k_flight(uint32_t n, const uint8_t *busy, double *x, double *y,
                                const double *vx, const double *vy)
{
    uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || busy[i])
        return;
    x[i] += vx[i];
    y[i] += vy[i];
}

/* Blocks for n items (n fits a launch: at most 2^32 - 1 items). */
static unsigned blocks_of(size_t n)
{
    return (unsigned)psim_gpu_blocks((long)n);
}

static void free_cands(cgpu *g)
{
    void *all[] = {g->cand, g->cand2, g->k, g->k2, g->ix, g->ix2, g->live, g->tmp};
    for (void *p : all)
        if (p)
            cudaFree(p);
    g->cand = g->cand2 = NULL, g->k = g->k2 = NULL, g->ix = g->ix2 = NULL;
    g->live = NULL, g->tmp = NULL, g->cap = 0;
}

/* Room for cap candidates (what was held is dropped). */
static int cands_room(cgpu *g, size_t cap, psim_error *err)
{
    free_cands(g);
    if (cap > INT32_MAX) {   /* (the radix sort counts in an int) */
        psim_error_set(err, "--device gpu: %zu candidates in a step: more than the device's "
                            "lists take", cap);
        return -1;
    }
    if (psim_dalloc(&g->cand, cap * sizeof(ccand), err) ||
        psim_dalloc(&g->cand2, cap * sizeof(ccand), err) ||
        psim_dalloc(&g->k, cap * sizeof(uint64_t), err) ||
        psim_dalloc(&g->k2, cap * sizeof(uint64_t), err) ||
        psim_dalloc(&g->ix, cap * sizeof(uint32_t), err) ||
        psim_dalloc(&g->ix2, cap * sizeof(uint32_t), err) ||
        psim_dalloc(&g->live, cap, err))
        return -1;
    g->tmp_bytes = 0;
    if (psim_cuda_failed(cub::DeviceRadixSort::SortPairs(nullptr, g->tmp_bytes, g->k, g->k2,
                                                         g->ix, g->ix2, (int)cap, 0, 64),
                         "the candidates' sort", err) ||
        psim_dalloc(&g->tmp, g->tmp_bytes, err))
        return -1;
    g->cap = cap;
    return 0;
}

extern "C" cgpu *cgpu_create(psim_store *st, double L, double r, const int64_t *pcoll,
                             const int64_t *wcoll, int device, double *copy_s, psim_error *err)
{
    cgpu *g = (cgpu *)calloc(1, sizeof *g);
    if (!g) {
        psim_error_set(err, "out of memory");
        return NULL;
    }
    g->st = st, g->L = L, g->r = r, g->device = device;
    const size_t n = st->n, counts = n * sizeof(int64_t);
    if (n > (size_t)INT32_MAX - 1024) {   /* (the radix sorts count in an int) */
        psim_error_set(err, "--device gpu: %zu disks: more than the device's sorts take", n);
        free(g);
        return NULL;
    }
    double t0 = psim_now();
    int rc = psim_cuda_failed(cudaSetDevice(device), "device", err) ||
             psim_dstore_create(&g->d, st, (size_t)psim_gpu_grid_most((long)n), err) ||
             psim_dalloc(&g->pcoll, counts, err) || psim_dalloc(&g->wcoll, counts, err) ||
             psim_dalloc(&g->busy, n, err) || psim_dalloc(&g->best, n * sizeof(uint32_t), err) ||
             psim_dalloc(&g->cnt, sizeof(ccounts), err) ||
             psim_dalloc(&g->wbits, sizeof *g->wbits, err) || cands_room(g, n + 1024, err);
    const char *what = "copy to the device";
    rc = rc ||
         psim_cuda_failed(cudaMemcpy(g->pcoll, pcoll, counts, cudaMemcpyHostToDevice), what, err) ||
         psim_cuda_failed(cudaMemcpy(g->wcoll, wcoll, counts, cudaMemcpyHostToDevice), what, err) ||
         psim_cuda_failed(cudaMemset(g->busy, 0, n ? n : 1), what, err);
    if (rc) {
        cgpu_destroy(g);
        return NULL;
    }
    *copy_s += psim_now() - t0;
    return g;
}

/* The counts into *h (waits for the device). */
static cudaError_t read_counts(const cgpu *g, ccounts *h)
{
    return cudaMemcpy(h, g->cnt, sizeof *h, cudaMemcpyDeviceToHost);
}

/* The bands for this step's speeds (as ccd.c's fit_grid plans cells): 1
 * when they were planned again, 0, or -1 with err set. */
static int fit_bands(cgpu *g, double vmax, psim_error *err)
{
    double reach = ccd_reach(g->L, g->r, vmax);
    g->grow = g->r + ccd_margin_of(g->L, g->r, vmax);
    if (ccd_cells_keep(reach, g->bands_reach, g->bands.side, psim_gpu_grid_most((long)g->d.n)))
        return 0;
    double want = ccd_cells_want(g->L, reach);
    if (psim_gpu_grid_plan(g->L, want, (long)g->d.n, &g->bands)) {
        psim_error_set(err, "--device gpu: no bands for a reach of %g in a box of %g", want,
                       g->L);
        return -1;
    }
    g->bands_reach = want;
    g->band_bits = psim_gpu_bits((uint64_t)g->bands.side - 1);
    return 1;
}

/* The disks sorted by band, and within a band by their boxes' left
 * edges (a stable sort by edge, then one by band), and their boxes
 * (into the store's free gather arrays) and the widest (on the device,
 * wbits), enqueued: the sweep (sweep.h) but its wmax. */
static ccd_sweep sort_disks(cgpu *g, unsigned blocks)
{
    psim_dstore *d = &g->d;
    const unsigned th = PSIM_GPU_THREADS;
    k_edges<<<blocks, th>>>(d->x, d->vx, d->n, g->grow, g->k, g->ix);
    cub::DeviceRadixSort::SortPairs(g->tmp, g->tmp_bytes, g->k, g->k2, g->ix, g->ix2,
                                    (int)d->n, 0, 64);
    k_bands<<<blocks, th>>>(g->ix2, d->y, d->n, g->bands, d->key, d->place);
    psim_dstore_sort_keys(d, (size_t)g->bands.side, g->band_bits, blocks);
    cudaMemsetAsync(g->wbits, 0, sizeof *g->wbits);
    k_boxes<<<blocks, th>>>(d->x, d->y, d->vx, d->vy, d->n, g->grow, d->x2, d->y2, d->vx2,
                            d->vy2, g->wbits);
    ccd_sweep S = {d->n, (uint32_t)g->bands.side, d->key2, d->cstart, d->cend,
                   d->x2, d->y2, d->vx2, d->vy2, 0};
    return S;
}

/* The candidates of this step, into cand (the room grown and the search
 * run again where they did not fit): their count, or -1 with err set. */
static long detect(cgpu *g, const ccd_sweep &S, cgpu_step_out *o, psim_error *err)
{
    psim_dstore *d = &g->d;
    for (;;) {
        cudaMemsetAsync(g->cnt, 0, sizeof(ccounts));
        k_detect<<<blocks_of(d->n), PSIM_GPU_THREADS>>>(S, d->x, d->y, d->vx, d->vy, d->id,
                                                       g->wbits, g->L, g->r, g->cand, g->cap,
                                                       g->cnt);
        ccounts h;
        if (psim_cuda_failed(read_counts(g, &h), "detect", err))
            return -1;
        if (h.found <= g->cap) {
            o->tests = h.tests, o->wall_cands = h.walls, o->pair_cands = h.found - h.walls;
            return (long)h.found;
        }
        unsigned long long want = h.found + h.found / 2 + 1024;
        if (h.found <= INT32_MAX && want > INT32_MAX)
            want = INT32_MAX;
        if (cands_room(g, (size_t)want, err))
            return -1;
    }
}

/* The total order: a stable sort by the id key, then by the time key;
 * the candidates in order into cand2. */
static void order(cgpu *g, uint32_t nc)
{
    const unsigned b = blocks_of(nc), th = PSIM_GPU_THREADS;
    k_keys<<<b, th>>>(g->cand, NULL, nc, 0, g->k, g->ix);
    cub::DeviceRadixSort::SortPairs(g->tmp, g->tmp_bytes, g->k, g->k2, g->ix, g->ix2, (int)nc,
                                    0, 64);
    k_keys<<<b, th>>>(g->cand, g->ix2, nc, 1, g->k, NULL);
    cub::DeviceRadixSort::SortPairs(g->tmp, g->tmp_bytes, g->k, g->k2, g->ix2, g->ix, (int)nc,
                                    0, 64);
    k_gather<<<b, th>>>(g->cand, g->ix, nc, g->cand2);
}

/* The greedy set of cand2, in rounds: the rounds, or -1 with err set. */
static long accept(cgpu *g, uint32_t nc, psim_error *err)
{
    const unsigned b = blocks_of(nc), th = PSIM_GPU_THREADS;
    long rounds = 0;
    cudaMemsetAsync(g->live, 1, nc);
    for (int more = 1; more;) {
        rounds++;
        cudaMemsetAsync(&g->cnt->more, 0, sizeof(int));
        k_best_reset<<<b, th>>>(g->cand2, nc, g->best);
        k_best_min<<<b, th>>>(g->cand2, nc, g->live, g->best);
        k_take<<<b, th>>>(g->cand2, nc, g->live, g->best, g->busy);
        k_drop<<<b, th>>>(g->cand2, nc, g->live, g->busy, g->cnt);
        if (psim_cuda_failed(cudaMemcpy(&more, &g->cnt->more, sizeof more,
                                        cudaMemcpyDeviceToHost), "accept", err))
            return -1;
    }
    return rounds;
}

extern "C" int cgpu_step(cgpu *g, cgpu_step_out *o, psim_error *err)
{
    psim_dstore *d = &g->d;
    const unsigned nb = blocks_of(d->n), th = PSIM_GPU_THREADS;
    memset(&o->tests, 0, sizeof *o - offsetof(cgpu_step_out, tests));
    o->rounds = 1;   /* (as the CPU path counts a step without candidates) */
    g->ncand = 0;
    if (d->n == 0)
        return 0;
    if (psim_cuda_failed(cudaSetDevice(g->device), "device", err))   /* (per host thread) */
        return -1;
    g->newer = 1;
    double t0 = psim_now();
    cudaMemsetAsync(g->cnt, 0, sizeof(ccounts));
    k_vmax<<<nb, th>>>(d->vx, d->vy, d->n, g->cnt);
    ccounts h;
    if (psim_cuda_failed(read_counts(g, &h), "step", err))
        return -1;
    memcpy(&o->vmax, &h.vmax, sizeof o->vmax);
    if (fit_bands(g, o->vmax, err) < 0)
        return -1;
    o->detect += psim_dlap(&t0);
    ccd_sweep S = sort_disks(g, nb);
    o->sort += psim_dlap(&t0);
    long nc = detect(g, S, o, err);
    if (nc < 0)
        return -1;
    o->detect += psim_dlap(&t0);
    g->ncand = (size_t)nc;
    if (nc > 0) {
        order(g, (uint32_t)nc);
        o->order += psim_dlap(&t0);
        long rounds = accept(g, (uint32_t)nc, err);
        if (rounds < 0)
            return -1;
        o->rounds = (uint64_t)rounds;
        o->accept += psim_dlap(&t0);
        cudaMemsetAsync(&g->cnt->pair_colls, 0, 2 * sizeof(unsigned long long));
        k_apply<<<blocks_of((size_t)nc), th>>>(g->cand2, (uint32_t)nc, g->live, g->L, g->r,
                                               d->x, d->y, d->vx, d->vy, g->pcoll, g->wcoll,
                                               g->cnt);
    }
    k_flight<<<nb, th>>>(d->n, g->busy, d->x, d->y, d->vx, d->vy);
    cudaMemsetAsync(g->busy, 0, d->n);
    cudaError_t rc = read_counts(g, &h);
    if (rc == cudaSuccess)
        rc = cudaGetLastError();
    o->move += psim_dlap(&t0);
    if (psim_cuda_failed(rc, "step", err))
        return -1;
    if (nc > 0)
        o->pair_colls = h.pair_colls, o->wall_colls = h.wall_colls;
    return 0;
}

extern "C" double cgpu_sync(cgpu *g, int64_t *pcoll, int64_t *wcoll)
{
    if (!g->newer)
        return 0;
    double t0 = psim_now();
    size_t counts = g->st->n * sizeof(int64_t);
    cudaError_t rc = cudaSetDevice(g->device);
    if (rc == cudaSuccess)
        rc = psim_dstore_download(&g->d, g->st);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(pcoll, g->pcoll, counts, cudaMemcpyDeviceToHost);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(wcoll, g->wcoll, counts, cudaMemcpyDeviceToHost);
    if (rc != cudaSuccess)
        return -1;
    g->newer = 0;
    return psim_now() - t0;
}

extern "C" size_t cgpu_candidates(const cgpu *g) { return g->ncand; }

extern "C" int cgpu_lists(cgpu *g, ccand *all, ccand *acc, size_t *nacc)
{
    size_t nc = g->ncand;
    *nacc = 0;
    if (nc == 0)
        return 0;
    uint8_t *live = (uint8_t *)malloc(nc);
    if (!live)
        return -1;
    cudaError_t rc = cudaSetDevice(g->device);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(all, g->cand2, nc * sizeof *all, cudaMemcpyDeviceToHost);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(live, g->live, nc, cudaMemcpyDeviceToHost);
    for (size_t k = 0; rc == cudaSuccess && k < nc; k++)
        if (live[k] == 2)
            acc[(*nacc)++] = all[k];
    free(live);
    return rc == cudaSuccess ? 0 : -1;
}

extern "C" void cgpu_destroy(cgpu *g)
{
    if (!g)
        return;
    cudaSetDevice(g->device);
    psim_dstore_free(&g->d);
    free_cands(g);
    void *all[] = {g->pcoll, g->wcoll, g->busy, g->best, g->cnt, g->wbits};
    for (void *p : all)
        if (p)
            cudaFree(p);
    free(g);
}
