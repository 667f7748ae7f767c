/* The force model's GPU path (gpu.cu; docs/gpu.md): the store on a CUDA
 * device between steps, sorted by cell each step with a device radix
 * sort, forces a thread a particle over the cells around it, summed in
 * partner id order as the CPU path sums them (law.h), then the move.
 * Built without CUDA, fgpu_create says so and nothing else is called. */
#ifndef PSIM_FORCE_GPU_H
#define PSIM_FORCE_GPU_H
#include <stdint.h>

#include "../../base/error.h"
#include "../../engine/store.h"
#include "law.h"

typedef struct fgpu fgpu;

/* The seconds of a step's parts, added to (fgpu_step). */
typedef struct fgpu_times {
    double sort, force, integrate, copy;
} fgpu_times;

#ifdef __cplusplus
extern "C" {
#endif
#ifdef PSIM_HAVE_CUDA
/* The store's n particles onto device `device` (copied up, timed into
 * *copy_s): the state, or NULL with err set. */
fgpu *fgpu_create(psim_store *st, const flaw *law, int device, double *copy_s,
                  psim_error *err);
/* One step on the device: 0; 1 when a particle left the box for good;
 * -1 with err set on a CUDA error.  *interactions: the pairs within the
 * cutoff, counted from both sides. */
int fgpu_step(fgpu *g, fgpu_times *t, uint64_t *interactions, psim_error *err);
/* The store brought up to date (copied down) where a step changed the
 * device's state since; the seconds it took, or 0.  Out of sync on a CUDA
 * error: -1. */
double fgpu_sync(fgpu *g);
void fgpu_destroy(fgpu *g);
#else
static inline fgpu *fgpu_create(psim_store *st, const flaw *law, int device, double *copy_s,
                                psim_error *err)
{
    (void)st, (void)law, (void)device, (void)copy_s;
    psim_error_set(err, "--device gpu: psim was built without CUDA");
    return NULL;
}
static inline int fgpu_step(fgpu *g, fgpu_times *t, uint64_t *interactions, psim_error *err)
{
    (void)g, (void)t, (void)interactions, (void)err;
    return -1;
}
static inline double fgpu_sync(fgpu *g) { (void)g; return 0; }
static inline void fgpu_destroy(fgpu *g) { (void)g; }
#endif
#ifdef __cplusplus
}
#endif

#endif
