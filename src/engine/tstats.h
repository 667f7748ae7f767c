/* Per-thread accounting of the phases (psim_thread_stats). */
#ifndef PSIM_ENGINE_TSTATS_H
#define PSIM_ENGINE_TSTATS_H
#include <sched.h>

#include <omp.h>

#include "../io/scene.h"

/* Start of part k of n items split into `parts` near-equal parts: the one
 * static split of the move, the sort and the first touch of the store, so a
 * thread works on the particles whose pages it touched first. */
static inline size_t psim_part_lo(size_t n, int parts, int k)
{
    return n * (size_t)k / (size_t)parts;
}

/* Add one work item's busy time to the calling thread's record.  ts may be
 * NULL (no accounting). */
static inline void psim_tstat_add(psim_thread_stats *ts, int p, double busy,
                                  uint64_t items, uint64_t particles)
{
    if (!ts)
        return;
    psim_thread_stats *t = &ts[omp_get_thread_num()];
    t->busy_s[p] += busy;
    t->items[p] += items;
    t->particles[p] += particles;
    t->cpu = sched_getcpu();
}

#endif
