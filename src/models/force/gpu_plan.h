/* The force model's GPU path, host-side plan (plain C, tested on every
 * build): its cells (the engine's, gpu_grid.h, no narrower than the
 * cutoff) and the device memory a run takes. */
#ifndef PSIM_FORCE_GPU_PLAN_H
#define PSIM_FORCE_GPU_PLAN_H
#include <stddef.h>
#include <stdint.h>

#include "../../engine/gpu_grid.h"

/* Forces a particle gathers before it sums them in partner id order
 * (more: it finds them one by one in id order instead, gpu.cu). */
#define FGPU_LOCAL 32

/* The device memory of a run of n particles on grid g: bytes a particle
 * (every array, double-buffered for the sort), bytes of the cells, and
 * their total with sort_tmp bytes of the sort's scratch, into *total.
 * 0, or -1 where the total does not fit a size_t or n is beyond the
 * sort's int count. */
#define FGPU_BYTES_PARTICLE (2 * (4 * sizeof(double) + sizeof(int32_t) + 2 * sizeof(uint32_t)))
#define FGPU_BYTES_CELL (2 * sizeof(uint32_t))
int fgpu_bytes(long n, const psim_gpu_grid *g, size_t sort_tmp, size_t *total);

#endif
