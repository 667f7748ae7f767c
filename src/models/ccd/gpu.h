/* The ccd model's GPU path (gpu.cu; docs/gpu.md): the store on a CUDA
 * device between steps, sorted by cell each step with the engine's device
 * sort; the candidates found a thread a disk over the cells around it
 * with the rules' own functions (rules.h), put in the total order by
 * radix sorts of their keys (cand.h), accepted in rounds of candidates
 * that come first for both their disks (the greedy set, order.c), and
 * the move.  Built without CUDA, cgpu_create says so and nothing else is
 * called. */
#ifndef PSIM_CCD_GPU_H
#define PSIM_CCD_GPU_H
#include <stddef.h>
#include <stdint.h>

#include "../../base/error.h"
#include "../../engine/store.h"
#include "cand.h"

typedef struct cgpu cgpu;

/* A step's seconds (added to), and its largest |vx| + |vy| and counts
 * (set). */
typedef struct cgpu_step_out {
    double detect, sort, order, accept, move;
    double vmax;
    uint64_t tests, pair_cands, wall_cands, pair_colls, wall_colls, rounds;
} cgpu_step_out;

#ifdef __cplusplus
extern "C" {
#endif
#ifdef PSIM_HAVE_CUDA
/* The store's n disks in a box of side L, radius r, onto device `device`
 * with each disk's collisions so far (by id: pcoll, wcoll), copied up
 * (timed into *copy_s): the state, or NULL with err set. */
cgpu *cgpu_create(psim_store *st, double L, double r, const int64_t *pcoll,
                  const int64_t *wcoll, int device, double *copy_s, psim_error *err);
/* One step on the device: 0, or -1 with err set on a CUDA error. */
int cgpu_step(cgpu *g, cgpu_step_out *o, psim_error *err);
/* The store and the collision counts by id brought up to date (copied
 * down) where a step changed them since: the seconds it took, or 0; -1 on
 * a CUDA error. */
double cgpu_sync(cgpu *g, int64_t *pcoll, int64_t *wcoll);
/* The last step's candidates in order: how many. */
size_t cgpu_candidates(const cgpu *g);
/* They (all, room for cgpu_candidates), and the accepted ones in order
 * (acc, as many at most; *nacc): 0, or -1 on a CUDA error. */
int cgpu_lists(cgpu *g, ccand *all, ccand *acc, size_t *nacc);
void cgpu_destroy(cgpu *g);
#else
static inline cgpu *cgpu_create(psim_store *st, double L, double r, const int64_t *pcoll,
                                const int64_t *wcoll, int device, double *copy_s,
                                psim_error *err)
{
    (void)st, (void)L, (void)r, (void)pcoll, (void)wcoll, (void)device, (void)copy_s;
    psim_error_set(err, "--device gpu: psim was built without CUDA");
    return NULL;
}
static inline int cgpu_step(cgpu *g, cgpu_step_out *o, psim_error *err)
{
    (void)g, (void)o, (void)err;
    return -1;
}
static inline double cgpu_sync(cgpu *g, int64_t *pcoll, int64_t *wcoll)
{
    (void)g, (void)pcoll, (void)wcoll;
    return 0;
}
static inline size_t cgpu_candidates(const cgpu *g) { (void)g; return 0; }
static inline int cgpu_lists(cgpu *g, ccand *all, ccand *acc, size_t *nacc)
{
    (void)g, (void)all, (void)acc, (void)nacc;
    return -1;
}
static inline void cgpu_destroy(cgpu *g) { (void)g; }
#endif
#ifdef __cplusplus
}
#endif

#endif
