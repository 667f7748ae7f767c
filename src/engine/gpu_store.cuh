/* The store on a CUDA device, for a model's GPU path (CUDA C++, included
 * by the models' .cu files; docs/gpu.md).
 *
 * The particles as a structure of arrays like the store's, which stay on
 * the device between steps:
 *   sort      each particle's cell key (gpu_grid.h), or a model's own
 *             key, a radix sort of (key, place) pairs (CUB
 *             DeviceRadixSort, stable), the arrays gathered into key
 *             order, and each key's range of places: the engine's sort
 *             by cell key, on the device;
 *   download  the arrays into the host's store, in the device's order
 *             (the store's ids say where each particle is), only when the
 *             engine reads the state.
 * Everything here is static: each .cu file has its own copy. */
#ifndef PSIM_ENGINE_GPU_STORE_CUH
#define PSIM_ENGINE_GPU_STORE_CUH
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cub/device/device_radix_sort.cuh>
#include <cuda_runtime.h>

extern "C" {
#include "../base/error.h"
#include "gpu_grid.h"
#include "store.h"
#include "timer.h"
}

typedef struct psim_dstore {
    uint32_t n;
    size_t cells;                   /* cells the cell arrays hold */
    double *x, *y, *vx, *vy;        /* the state, in cell key order */
    double *x2, *y2, *vx2, *vy2;    /* gather targets; free between sorts */
    int32_t *id, *id2;
    uint32_t *key, *key2, *place, *place2;
    uint32_t *cstart, *cend;        /* each cell's places [start, end) */
    void *tmp;                      /* the radix sort's scratch */
    size_t tmp_bytes;
} psim_dstore;

/* A CUDA call's error into err, naming the call: -1; else 0. */
static inline int psim_cuda_failed(cudaError_t rc, const char *what, psim_error *err)
{
    if (rc == cudaSuccess)
        return 0;
    psim_error_set(err, "--device gpu: %s: %s", what, cudaGetErrorString(rc));
    return -1;
}

/* Device memory of bytes (at least 1) into *p. */
static inline int psim_dalloc(void *p, size_t bytes, psim_error *err)
{
    return psim_cuda_failed(cudaMalloc((void **)p, bytes ? bytes : 1), "device memory", err);
}

/* Each particle's cell key, and its place. */
__global__ static void psim_dk_keys(psim_gpu_grid g, const double *x, const double *y,
                                    uint32_t *key, uint32_t *place, uint32_t n)
{
    uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n)
        return;
    key[i] = psim_gpu_key(&g, x[i], y[i]);
    place[i] = i;
}

/* The arrays into key order: to[i] = from[place[i]]. */
__global__ static void psim_dk_gather(const uint32_t *place, uint32_t n, const double *x,
                                      const double *y, const double *vx, const double *vy,
                                      const int32_t *id, double *x2, double *y2, double *vx2,
                                      double *vy2, int32_t *id2)
{
    uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n)
        return;
    uint32_t p = place[i];
    x2[i] = x[p], y2[i] = y[p], vx2[i] = vx[p], vy2[i] = vy[p], id2[i] = id[p];
}

/* Each occupied cell's first and end place, from the sorted keys (empty
 * cells keep start = end = 0). */
__global__ static void psim_dk_ranges(const uint32_t *key, uint32_t n, uint32_t *cstart,
                                      uint32_t *cend)
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

/* The places of the cells of row `row` within range r: one run [*b, *e)
 * (the cells of a row are consecutive keys, their places consecutive);
 * *b = UINT32_MAX, *e = 0 where they hold none. */
__device__ static inline void psim_drow_run(const uint32_t *cstart, const uint32_t *cend,
                                            const psim_gpu_grid &g, const psim_gpu_range &r,
                                            int32_t row, uint32_t *b, uint32_t *e)
{
    uint32_t k0 = (uint32_t)row * (uint32_t)g.side;
    *b = UINT32_MAX, *e = 0;
    for (int32_t cx = r.x0; cx <= r.x1; cx++) {
        uint32_t s = cstart[k0 + cx], t = cend[k0 + cx];
        if (s < t) {
            *b = *b < s ? *b : s;
            *e = *e > t ? *e : t;
        }
    }
}

static inline void psim_dstore_free(psim_dstore *d)
{
    void *all[] = {d->x,   d->y,    d->vx,   d->vy,     d->x2,     d->y2,   d->vx2,
                   d->vy2, d->id,   d->id2,  d->key,    d->key2,   d->place, d->place2,
                   d->cstart, d->cend, d->tmp};
    for (void *p : all)
        if (p)
            cudaFree(p);
    memset(d, 0, sizeof *d);
}

/* The store's n particles (n < 2^31) onto the device (device chosen
 * already), with `cells` cells for their keys: 0, or -1 with err set (and
 * nothing held). */
static inline int psim_dstore_create(psim_dstore *d, const psim_store *st, size_t cells,
                                     psim_error *err)
{
    memset(d, 0, sizeof *d);
    d->n = (uint32_t)st->n, d->cells = cells;
    size_t n = st->n, dbl = n * sizeof(double), w = n * sizeof(uint32_t);
    size_t cbytes = cells * sizeof(uint32_t);
    double **dbls[] = {&d->x, &d->y, &d->vx, &d->vy, &d->x2, &d->y2, &d->vx2, &d->vy2};
    uint32_t **words[] = {&d->key, &d->key2, &d->place, &d->place2};
    int rc = 0;
    for (double **p : dbls)
        rc = rc || psim_dalloc(p, dbl, err);
    for (uint32_t **p : words)
        rc = rc || psim_dalloc(p, w, err);
    rc = rc || psim_dalloc(&d->id, w, err) || psim_dalloc(&d->id2, w, err) ||
         psim_dalloc(&d->cstart, cbytes, err) || psim_dalloc(&d->cend, cbytes, err);
    if (!rc)   /* the scratch of a sort of every key bit */
        rc = psim_cuda_failed(cub::DeviceRadixSort::SortPairs(nullptr, d->tmp_bytes, d->key,
                                                              d->key2, d->place, d->place2,
                                                              (int)d->n, 0, 32),
                              "the sort's scratch", err) ||
             psim_dalloc(&d->tmp, d->tmp_bytes, err);
    const char *what = "copy to the device";
    rc = rc || psim_cuda_failed(cudaMemcpy(d->x, st->x, dbl, cudaMemcpyHostToDevice), what, err) ||
         psim_cuda_failed(cudaMemcpy(d->y, st->y, dbl, cudaMemcpyHostToDevice), what, err) ||
         psim_cuda_failed(cudaMemcpy(d->vx, st->vx, dbl, cudaMemcpyHostToDevice), what, err) ||
         psim_cuda_failed(cudaMemcpy(d->vy, st->vy, dbl, cudaMemcpyHostToDevice), what, err) ||
         psim_cuda_failed(cudaMemcpy(d->id, st->id, w, cudaMemcpyHostToDevice), what, err);
    if (rc)
        psim_dstore_free(d);
    return rc ? -1 : 0;
}

template <typename T> static inline void psim_dswap(T **a, T **b)
{
    T *t = *a;
    *a = *b, *b = t;
}

/* The particles into the order of their keys, enqueued: key[k] the key
 * of the particle at place[k] (any places, each once), keys below
 * 2^key_bits and cells of them; a stable radix sort of (key, place), the
 * arrays gathered into that order, each key's range of places.
 * Afterwards key2 holds the sorted keys. */
static inline void psim_dstore_sort_keys(psim_dstore *d, size_t cells, int key_bits, unsigned blocks)
{
    const unsigned th = PSIM_GPU_THREADS;
    cub::DeviceRadixSort::SortPairs(d->tmp, d->tmp_bytes, d->key, d->key2, d->place,
                                    d->place2, (int)d->n, 0, key_bits);
    psim_dk_gather<<<blocks, th>>>(d->place2, d->n, d->x, d->y, d->vx, d->vy, d->id, d->x2,
                                   d->y2, d->vx2, d->vy2, d->id2);
    psim_dswap(&d->x, &d->x2), psim_dswap(&d->y, &d->y2);
    psim_dswap(&d->vx, &d->vx2), psim_dswap(&d->vy, &d->vy2), psim_dswap(&d->id, &d->id2);
    cudaMemsetAsync(d->cstart, 0, cells * sizeof(uint32_t));
    cudaMemsetAsync(d->cend, 0, cells * sizeof(uint32_t));
    psim_dk_ranges<<<blocks, th>>>(d->key2, d->n, d->cstart, d->cend);
}

/* The sort by cell key on grid g (g.side^2 cells at most d->cells),
 * enqueued. */
static inline void psim_dstore_sort(psim_dstore *d, const psim_gpu_grid &g, unsigned blocks)
{
    psim_dk_keys<<<blocks, PSIM_GPU_THREADS>>>(g, d->x, d->y, d->key, d->place, d->n);
    psim_dstore_sort_keys(d, (size_t)g.side * (size_t)g.side, g.key_bits, blocks);
}

/* Seconds since *t0, the device's work done; *t0 moved on (a step's
 * phases timed). */
static inline double psim_dlap(double *t0)
{
    cudaDeviceSynchronize();
    double t = psim_now(), dt = t - *t0;
    *t0 = t;
    return dt;
}

/* The device's arrays into the store (waits for the device): a CUDA
 * error, or cudaSuccess. */
static inline cudaError_t psim_dstore_download(const psim_dstore *d, psim_store *st)
{
    size_t dbl = st->n * sizeof(double);
    cudaError_t rc = cudaMemcpy(st->x, d->x, dbl, cudaMemcpyDeviceToHost);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(st->y, d->y, dbl, cudaMemcpyDeviceToHost);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(st->vx, d->vx, dbl, cudaMemcpyDeviceToHost);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(st->vy, d->vy, dbl, cudaMemcpyDeviceToHost);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(st->id, d->id, st->n * sizeof(int32_t), cudaMemcpyDeviceToHost);
    return rc;
}

#endif
