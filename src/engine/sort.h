/* Parallel, stable counting sort of the store by cell rank.
 *
 * A counting sort by cell is a one-digit LSD radix sort whose digit is the
 * whole dense Morton cell rank.  psim re-sorts every step, when the order is
 * already nearly right; one pass over the particles to count, a scan over
 * the cells and one scatter is the least memory traffic any radix sort can
 * do (a 2-pass LSD radix sort moves every particle twice; measured 5.9 ns vs
 * 2.4 ns per particle on a 2-core EPYC VM, docs/design.md).  The sort is
 * stable, so its result does not depend on the number of chunks. */
#ifndef PSIM_ENGINE_SORT_H
#define PSIM_ENGINE_SORT_H
#include "grid.h"
#include "store.h"
#include "tstats.h"

typedef struct psim_sorter {
    int chunks;
    uint32_t ncells;
    uint32_t *hist;        /* chunks x ncells counters, then offsets */
    uint32_t *block_total; /* chunks */
} psim_sorter;

int psim_sorter_init(psim_sorter *so, int threads, uint32_t ncells);
void psim_sorter_free(psim_sorter *so);
/* Compute every particle's cell, sort the store by it and fill
 * g->cellstart.  Returns the number of particles that changed place. */
size_t psim_sort_by_cell(psim_sorter *so, psim_store *st, psim_grid *g,
                         int threads, psim_thread_stats *ts);

#endif
