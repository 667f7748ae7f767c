/* The force model's GPU path (gpu.h; docs/gpu.md).
 *
 * The state lives on the device between steps, as a structure of arrays
 * like the store's.  A step:
 *   sort       each particle's cell key (gpu_plan.h), a radix sort of
 *              (key, place) pairs (CUB DeviceRadixSort), the arrays
 *              gathered into key order, and each cell's range of places;
 *   force      a thread a particle: the forces of the particles within
 *              the cutoff in the cells around its own (law.h's flaw_force,
 *              the CPU path's arithmetic), summed from +0 in partner id
 *              order, the order of the course's naive loop, so that the
 *              sums are the CPU path's bit for bit;
 *   integrate  a thread a particle: law.h's flaw_move.
 * Compiled with --fmad=false and IEEE division and square root
 * (cmake/cuda.cmake): each operation rounds as the C code's does.  The
 * state is copied down to the store only when the engine reads it
 * (fgpu_sync). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cub/device/device_radix_sort.cuh>
#include <cub/block/block_reduce.cuh>
#include <cuda_runtime.h>

extern "C" {
#include "../../engine/timer.h"
#include "gpu.h"
#include "gpu_plan.h"
}

struct fgpu {
    psim_store *st;
    flaw law;
    fgpu_grid grid;
    uint32_t n;
    int device;
    double *x, *y, *vx, *vy;        /* the state, in cell key order */
    double *x2, *y2, *vx2, *vy2;    /* gather targets; then ax, ay */
    int32_t *id, *id2;
    uint32_t *key, *key2, *place, *place2;
    uint32_t *cstart, *cend;        /* each cell's places [start, end) */
    void *tmp;                      /* the radix sort's scratch */
    size_t tmp_bytes;
    int *lost;                      /* a particle left the box */
    unsigned long long *hits;       /* interactions, this step */
    int newer;                      /* the device's state is newer than the store's */
};

/* A CUDA call's error into err, naming the call: -1; else 0. */
static int cuda_failed(cudaError_t rc, const char *what, psim_error *err)
{
    if (rc == cudaSuccess)
        return 0;
    psim_error_set(err, "--device gpu: %s: %s", what, cudaGetErrorString(rc));
    return -1;
}

/* Each particle's cell key, and its place. */
__global__ void k_keys(fgpu_grid g, const double *x, const double *y, uint32_t *key,
                       uint32_t *place, uint32_t n)
{
    uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n)
        return;
    key[i] = fgpu_key(&g, x[i], y[i]);
    place[i] = i;
}

/* The arrays into key order: to[i] = from[place[i]]. */
__global__ void k_gather(const uint32_t *place, uint32_t n, const double *x, const double *y,
                         const double *vx, const double *vy, const int32_t *id, double *x2,
                         double *y2, double *vx2, double *vy2, int32_t *id2)
{
    uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n)
        return;
    uint32_t p = place[i];
    x2[i] = x[p], y2[i] = y[p], vx2[i] = vx[p], vy2[i] = vy[p], id2[i] = id[p];
}

/* Each occupied cell's first and end place, from the sorted keys (empty
 * cells keep start = end = 0). */
__global__ void k_ranges(const uint32_t *key, uint32_t n, uint32_t *cstart, uint32_t *cend)
{
    uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n)
        return;
    uint32_t k = key[i];
    if (i == 0 || key[i - 1] != k)
        cstart[k] = i;
    if (i == n - 1 || key[i + 1] != k)
        cend[k] = i + 1;
}

/* The particles of the cells around particle i's, as a range per row of
 * cells (the cells of a row are consecutive keys, their places one run). */
struct around {
    const uint32_t *cstart, *cend;
    fgpu_grid g;
    fgpu_range r;
};

__device__ static inline void row_run(const around &a, int32_t row, uint32_t *b, uint32_t *e)
{
    uint32_t k0 = (uint32_t)row * (uint32_t)a.g.side;
    *b = UINT32_MAX, *e = 0;
    for (int32_t cx = a.r.x0; cx <= a.r.x1; cx++) {
        uint32_t s = a.cstart[k0 + cx], t = a.cend[k0 + cx];
        if (s < t) {
            *b = *b < s ? *b : s;
            *e = *e > t ? *e : t;
        }
    }
}

/* The force on particle i of the one partner with the least id above
 * `after` (-1: none yet) within the cutoff: its id, or INT32_MAX for
 * none.  For a particle with more than FGPU_LOCAL partners. */
__device__ static int32_t next_partner(const flaw &k, const around &a, uint32_t i,
                                       const double *x, const double *y, const int32_t *id,
                                       int32_t after, double *fx, double *fy)
{
    int32_t best = INT32_MAX;
    for (int32_t row = a.r.y0; row <= a.r.y1; row++) {
        uint32_t b, e;
        row_run(a, row, &b, &e);
        for (uint32_t j = b; j < e; j++) {
            double gx, gy;
            if (j == i || id[j] <= after || id[j] >= best ||
                !flaw_force(&k, x[i], y[i], x[j], y[j], &gx, &gy))
                continue;
            best = id[j], *fx = gx, *fy = gy;
        }
    }
    return best;
}

/* The forces on each particle, summed from +0 in partner id order (its
 * own term, +0 or -0 added to a sum that cannot be -0, changes nothing
 * and is left out), to ax, ay; the interactions counted a block at a
 * time. */
__global__ void k_force(flaw k, around a, const double *x, const double *y, const int32_t *id,
                        uint32_t n, double *ax_out, double *ay_out, unsigned long long *hits)
{
    typedef cub::BlockReduce<unsigned long long, FGPU_THREADS> reduce;
    __shared__ typename reduce::TempStorage shared;
    uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    unsigned long long mine = 0;
    if (i < n) {
        int32_t pid[FGPU_LOCAL];
        double pfx[FGPU_LOCAL], pfy[FGPU_LOCAL];
        int np = 0, over = 0;
        a.r = fgpu_around(&a.g, fgpu_cell(&a.g, x[i]), fgpu_cell(&a.g, y[i]));
        for (int32_t row = a.r.y0; row <= a.r.y1; row++) {
            uint32_t b, e;
            row_run(a, row, &b, &e);
            for (uint32_t j = b; j < e; j++) {
                double fx, fy;
                if (j == i || !flaw_force(&k, x[i], y[i], x[j], y[j], &fx, &fy))
                    continue;
                mine++;
                if (np == FGPU_LOCAL) {
                    over = 1;
                    continue;
                }
                int q = np++;   /* insertion by id */
                for (; q > 0 && pid[q - 1] > id[j]; q--)
                    pid[q] = pid[q - 1], pfx[q] = pfx[q - 1], pfy[q] = pfy[q - 1];
                pid[q] = id[j], pfx[q] = fx, pfy[q] = fy;
            }
        }
        double ax = 0, ay = 0;
        if (!over) {
            for (int q = 0; q < np; q++)
                ax += pfx[q], ay += pfy[q];
        } else {
            double fx = 0, fy = 0;
            for (int32_t p = next_partner(k, a, i, x, y, id, -1, &fx, &fy); p != INT32_MAX;
                 p = next_partner(k, a, i, x, y, id, p, &fx, &fy))
                ax += fx, ay += fy;
        }
        ax_out[i] = ax;
        ay_out[i] = ay;
    }
    unsigned long long sum = reduce(shared).Sum(mine);
    if (threadIdx.x == 0 && sum)
        atomicAdd(hits, sum);
}

/* The course's move of each particle (law.h), in place. */
__global__ void k_move(flaw k, double *x, double *y, double *vx, double *vy, const double *ax,
                       const double *ay, uint32_t n, int *lost)
{
    uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n)
        return;
    double u = vx[i], w = vy[i], nx, ny;
    if (flaw_move(&k, x[i], y[i], &u, &w, ax[i], ay[i], &nx, &ny))
        atomicExch(lost, 1);
    x[i] = nx, y[i] = ny, vx[i] = u, vy[i] = w;
}

/* Device arrays of the state, every one or none. */
static int alloc_all(fgpu *g, psim_error *err)
{
    size_t d = (size_t)g->n * sizeof(double), w = (size_t)g->n * sizeof(uint32_t);
    size_t cells = (size_t)g->grid.side * (size_t)g->grid.side * sizeof(uint32_t);
    void **dbl[] = {(void **)&g->x, (void **)&g->y, (void **)&g->vx, (void **)&g->vy,
                    (void **)&g->x2, (void **)&g->y2, (void **)&g->vx2, (void **)&g->vy2};
    void **word[] = {(void **)&g->id, (void **)&g->id2, (void **)&g->key, (void **)&g->key2,
                     (void **)&g->place, (void **)&g->place2};
    for (void **p : dbl)
        if (cuda_failed(cudaMalloc(p, d ? d : 1), "device memory", err))
            return -1;
    for (void **p : word)
        if (cuda_failed(cudaMalloc(p, w ? w : 1), "device memory", err))
            return -1;
    if (cuda_failed(cudaMalloc((void **)&g->cstart, cells), "device memory", err) ||
        cuda_failed(cudaMalloc((void **)&g->cend, cells), "device memory", err) ||
        cuda_failed(cudaMalloc((void **)&g->lost, sizeof(int)), "device memory", err) ||
        cuda_failed(cudaMalloc((void **)&g->hits, sizeof(unsigned long long)), "device memory",
                    err))
        return -1;
    cub::DeviceRadixSort::SortPairs(nullptr, g->tmp_bytes, g->key, g->key2, g->place,
                                    g->place2, (int)g->n, 0, g->grid.key_bits);
    return cuda_failed(cudaMalloc(&g->tmp, g->tmp_bytes ? g->tmp_bytes : 1),
                       "device memory for the sort", err);
}

extern "C" fgpu *fgpu_create(psim_store *st, const flaw *law, int device, double *copy_s,
                             psim_error *err)
{
    fgpu *g = (fgpu *)calloc(1, sizeof *g);
    if (!g) {
        psim_error_set(err, "out of memory");
        return NULL;
    }
    g->st = st, g->law = *law, g->device = device, g->n = (uint32_t)st->n;
    size_t total;
    if (fgpu_grid_plan(law->size, law->cutoff, (long)st->n, &g->grid) ||
        fgpu_bytes((long)st->n, &g->grid, 0, &total)) {
        psim_error_set(err, "--device gpu: %zu particles in a box of %g cells a side do not "
                            "fit the device's arrays", st->n, (double)g->grid.side);
        free(g);
        return NULL;
    }
    double t0 = psim_now();
    size_t d = st->n * sizeof(double);
    if (cuda_failed(cudaSetDevice(device), "device", err) || alloc_all(g, err) ||
        cuda_failed(cudaMemcpy(g->x, st->x, d, cudaMemcpyHostToDevice), "copy", err) ||
        cuda_failed(cudaMemcpy(g->y, st->y, d, cudaMemcpyHostToDevice), "copy", err) ||
        cuda_failed(cudaMemcpy(g->vx, st->vx, d, cudaMemcpyHostToDevice), "copy", err) ||
        cuda_failed(cudaMemcpy(g->vy, st->vy, d, cudaMemcpyHostToDevice), "copy", err) ||
        cuda_failed(cudaMemcpy(g->id, st->id, st->n * sizeof(int32_t), cudaMemcpyHostToDevice),
                    "copy", err)) {
        fgpu_destroy(g);
        return NULL;
    }
    *copy_s += psim_now() - t0;
    return g;
}

/* Seconds since *t0, the device's work done; *t0 moved on. */
static double lap(double *t0)
{
    cudaDeviceSynchronize();
    double t = psim_now(), dt = t - *t0;
    *t0 = t;
    return dt;
}

template <typename T> static void swap_ptr(T **a, T **b)
{
    T *t = *a;
    *a = *b, *b = t;
}

/* The sort: keys, the radix sort, the gather, the cells' ranges. */
static void sort_step(fgpu *g, unsigned blocks)
{
    const unsigned th = FGPU_THREADS;
    size_t cells = (size_t)g->grid.side * (size_t)g->grid.side * sizeof(uint32_t);
    k_keys<<<blocks, th>>>(g->grid, g->x, g->y, g->key, g->place, g->n);
    cub::DeviceRadixSort::SortPairs(g->tmp, g->tmp_bytes, g->key, g->key2, g->place,
                                    g->place2, (int)g->n, 0, g->grid.key_bits);
    k_gather<<<blocks, th>>>(g->place2, g->n, g->x, g->y, g->vx, g->vy, g->id, g->x2, g->y2,
                             g->vx2, g->vy2, g->id2);
    swap_ptr(&g->x, &g->x2), swap_ptr(&g->y, &g->y2);
    swap_ptr(&g->vx, &g->vx2), swap_ptr(&g->vy, &g->vy2), swap_ptr(&g->id, &g->id2);
    cudaMemsetAsync(g->cstart, 0, cells);
    cudaMemsetAsync(g->cend, 0, cells);
    k_ranges<<<blocks, th>>>(g->key2, g->n, g->cstart, g->cend);
}

extern "C" int fgpu_step(fgpu *g, fgpu_times *t, uint64_t *interactions, psim_error *err)
{
    long nb = fgpu_blocks((long)g->n);
    if (nb <= 0)
        return 0;
    const unsigned blocks = (unsigned)nb, th = FGPU_THREADS;
    double t0 = psim_now();
    sort_step(g, blocks);
    t->sort += lap(&t0);
    cudaMemsetAsync(g->hits, 0, sizeof *g->hits);
    cudaMemsetAsync(g->lost, 0, sizeof *g->lost);
    around a = {g->cstart, g->cend, g->grid, {0, 0, 0, 0}};
    /* x2, y2: free after the gather, the accelerations */
    k_force<<<blocks, th>>>(g->law, a, g->x, g->y, g->id, g->n, g->x2, g->y2, g->hits);
    t->force += lap(&t0);
    k_move<<<blocks, th>>>(g->law, g->x, g->y, g->vx, g->vy, g->x2, g->y2, g->n, g->lost);
    int lost = 0;
    unsigned long long hits = 0;
    cudaError_t rc = cudaMemcpy(&lost, g->lost, sizeof lost, cudaMemcpyDeviceToHost);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(&hits, g->hits, sizeof hits, cudaMemcpyDeviceToHost);
    t->integrate += lap(&t0);
    g->newer = 1;
    if (rc == cudaSuccess)
        rc = cudaGetLastError();
    if (cuda_failed(rc, "step", err))
        return -1;
    *interactions = hits;
    return lost;
}

extern "C" double fgpu_sync(fgpu *g)
{
    if (!g->newer)
        return 0;
    double t0 = psim_now();
    psim_store *st = g->st;
    size_t d = st->n * sizeof(double);
    cudaError_t rc = cudaMemcpy(st->x, g->x, d, cudaMemcpyDeviceToHost);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(st->y, g->y, d, cudaMemcpyDeviceToHost);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(st->vx, g->vx, d, cudaMemcpyDeviceToHost);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(st->vy, g->vy, d, cudaMemcpyDeviceToHost);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(st->id, g->id, st->n * sizeof(int32_t), cudaMemcpyDeviceToHost);
    if (rc != cudaSuccess)
        return -1;
    g->newer = 0;
    return psim_now() - t0;
}

extern "C" void fgpu_destroy(fgpu *g)
{
    if (!g)
        return;
    void *all[] = {g->x,   g->y,    g->vx,   g->vy,     g->x2,     g->y2,   g->vx2,
                   g->vy2, g->id,   g->id2,  g->key,    g->key2,   g->place, g->place2,
                   g->cstart, g->cend, g->tmp, g->lost, g->hits};
    for (void *p : all)
        if (p)
            cudaFree(p);
    free(g);
}
