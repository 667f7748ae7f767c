/* The force model's GPU path (gpu.h; docs/gpu.md).
 *
 * The state lives on the device between steps, as a structure of arrays
 * like the store's.  A step:
 *   sort       the engine's device sort by cell key (gpu_store.cuh), on
 *              cells no narrower than the cutoff (gpu_grid.h);
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

#include <cub/block/block_reduce.cuh>
#include <cuda_runtime.h>

#include "../../engine/gpu_store.cuh"
extern "C" {
#include "../../engine/timer.h"
#include "gpu.h"
#include "gpu_plan.h"
}

struct fgpu {
    psim_store *st;
    flaw law;
    psim_gpu_grid grid;
    psim_dstore d;                  /* the state; after the sort x2, y2 hold ax, ay */
    int device;
    int *lost;                      /* a particle left the box */
    unsigned long long *hits;       /* interactions, this step */
    int newer;                      /* the device's state is newer than the store's */
};

/* The particles of the cells around particle i's, as a range per row of
 * cells. */
struct around {
    const uint32_t *cstart, *cend;
    psim_gpu_grid g;
    psim_gpu_range r;
};

__device__ static inline void row_run(const around &a, int32_t row, uint32_t *b, uint32_t *e)
{
    psim_drow_run(a.cstart, a.cend, a.g, a.r, row, b, e);
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
    typedef cub::BlockReduce<unsigned long long, PSIM_GPU_THREADS> reduce;
    __shared__ typename reduce::TempStorage shared;
    uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    unsigned long long mine = 0;
    if (i < n) {
        int32_t pid[FGPU_LOCAL];
        double pfx[FGPU_LOCAL], pfy[FGPU_LOCAL];
        int np = 0, over = 0;
        a.r = psim_gpu_around(&a.g, psim_gpu_cell(&a.g, x[i]), psim_gpu_cell(&a.g, y[i]));
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

extern "C" fgpu *fgpu_create(psim_store *st, const flaw *law, int device, double *copy_s,
                             psim_error *err)
{
    fgpu *g = (fgpu *)calloc(1, sizeof *g);
    if (!g) {
        psim_error_set(err, "out of memory");
        return NULL;
    }
    g->st = st, g->law = *law, g->device = device;
    size_t total;
    if (psim_gpu_grid_plan(law->size, law->cutoff, (long)st->n, &g->grid) ||
        fgpu_bytes((long)st->n, &g->grid, 0, &total)) {
        psim_error_set(err, "--device gpu: %zu particles in a box of %g cells a side do not "
                            "fit the device's arrays", st->n, (double)g->grid.side);
        free(g);
        return NULL;
    }
    double t0 = psim_now();
    if (psim_cuda_failed(cudaSetDevice(device), "device", err) ||
        psim_dstore_create(&g->d, st, (size_t)g->grid.side * (size_t)g->grid.side, err) ||
        psim_dalloc(&g->lost, sizeof(int), err) ||
        psim_dalloc(&g->hits, sizeof(unsigned long long), err)) {
        fgpu_destroy(g);
        return NULL;
    }
    *copy_s += psim_now() - t0;
    return g;
}

extern "C" int fgpu_step(fgpu *g, fgpu_times *t, uint64_t *interactions, psim_error *err)
{
    psim_dstore *d = &g->d;
    cudaSetDevice(g->device);   /* (the runtime's device is per host thread) */
    long nb = psim_gpu_blocks((long)d->n);
    if (nb <= 0)
        return 0;
    const unsigned blocks = (unsigned)nb, th = PSIM_GPU_THREADS;
    double t0 = psim_now();
    psim_dstore_sort(d, g->grid, blocks);
    t->sort += psim_dlap(&t0);
    cudaMemsetAsync(g->hits, 0, sizeof *g->hits);
    cudaMemsetAsync(g->lost, 0, sizeof *g->lost);
    around a = {d->cstart, d->cend, g->grid, {0, 0, 0, 0}};
    /* x2, y2: free after the gather, the accelerations */
    k_force<<<blocks, th>>>(g->law, a, d->x, d->y, d->id, d->n, d->x2, d->y2, g->hits);
    t->force += psim_dlap(&t0);
    k_move<<<blocks, th>>>(g->law, d->x, d->y, d->vx, d->vy, d->x2, d->y2, d->n, g->lost);
    int lost = 0;
    unsigned long long hits = 0;
    cudaError_t rc = cudaMemcpy(&lost, g->lost, sizeof lost, cudaMemcpyDeviceToHost);
    if (rc == cudaSuccess)
        rc = cudaMemcpy(&hits, g->hits, sizeof hits, cudaMemcpyDeviceToHost);
    t->integrate += psim_dlap(&t0);
    g->newer = 1;
    if (rc == cudaSuccess)
        rc = cudaGetLastError();
    if (psim_cuda_failed(rc, "step", err))
        return -1;
    *interactions = hits;
    return lost;
}

extern "C" double fgpu_sync(fgpu *g)
{
    if (!g->newer)
        return 0;
    double t0 = psim_now();
    if (cudaSetDevice(g->device) != cudaSuccess || psim_dstore_download(&g->d, g->st) != cudaSuccess)
        return -1;
    g->newer = 0;
    return psim_now() - t0;
}

extern "C" void fgpu_destroy(fgpu *g)
{
    if (!g)
        return;
    cudaSetDevice(g->device);
    psim_dstore_free(&g->d);
    if (g->lost)
        cudaFree(g->lost);
    if (g->hits)
        cudaFree(g->hits);
    free(g);
}
