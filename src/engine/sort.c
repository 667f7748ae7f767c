#include "sort.h"

#include <string.h>

#include "mem.h"
#include "timer.h"

#define MAX_CHUNKS 16
/* Stores of more particles than this are beyond a core's L2: the scatter
 * then prefetches its streams a kilobyte ahead (the write streams too,
 * whose places follow the read's in a nearly sorted store).  At 1e5 and
 * 1e6 particles the sort took 0.75-0.95 of its time with them, at 1e4
 * slightly more (docs/performance.md, "Sort chunks"). */
#define SORT_PREFETCH_MIN 65536
/* Particles a chunk, at least: the sort takes 5-20 ns a particle, and a
 * parallel region with its four barriers some tens of microseconds on 16
 * threads of a VM (1e4 particles in 16 chunks sorted twice as slowly on 16
 * threads as on one: docs/performance.md, "Sort chunks").  Fewer than
 * two chunks' particles are sorted by the calling thread alone, more in
 * chunks of at least this many, by a team of all the threads: with a team
 * of fewer (12 of 16), libgomp ran the steps' later full teams 65 times
 * slower under --pin (measured; why, not established: docs/design.md,
 * "Teams").  4096 puts the course's 10k scenes in two chunks: their sort,
 * 11% of a step on one thread, then halves on two (8192 kept it on one
 * thread: docs/performance.md, "Sort chunks").  The order is
 * the same for any number of chunks. */
#define SORT_GRAIN 4096

int psim_sorter_init(psim_sorter *so, int threads, uint32_t ncells)
{
    so->chunks = threads < 1 ? 1 : (threads > MAX_CHUNKS ? MAX_CHUNKS : threads);
    so->ncells = ncells;
    so->hist = psim_alloc((size_t)so->chunks * ncells * sizeof(uint32_t));
    so->block_total = psim_alloc((size_t)so->chunks * sizeof(uint32_t));
    return (so->hist && so->block_total) ? 0 : -1;
}

void psim_sorter_free(psim_sorter *so)
{
    psim_free(so->hist);
    psim_free(so->block_total);
    memset(so, 0, sizeof *so);
}

__attribute__((noinline)) size_t psim_sort_by_cell(psim_sorter *so,
                                                   psim_store *st,
                                                   psim_grid *g, int threads,
                                                   psim_thread_stats *ts)
{
    const uint32_t B = so->ncells;
    const size_t n = st->n;
    const size_t most = n / SORT_GRAIN > 0 ? n / SORT_GRAIN : 1;
    const int C = (size_t)so->chunks < most ? so->chunks : (int)most;
    size_t moved = 0;

#pragma omp parallel num_threads(threads) if (C > 1) reduction(+ : moved)
    {
        /* 1. cell of every particle, counted per chunk of particles */
#pragma omp for schedule(static)
        for (int c = 0; c < C; c++) {
            double t0 = psim_now();
            uint32_t *h = so->hist + (size_t)c * B;
            memset(h, 0, B * sizeof *h);
            for (size_t i = psim_part_lo(n, C, c); i < psim_part_lo(n, C, c + 1); i++) {
                uint32_t k = psim_grid_cell(g, st->x[i], st->y[i]);
                st->cell[i] = k;
                h[k]++;
            }
            psim_tstat_add(ts, PSIM_PHASE_SORT, psim_now() - t0, 1,
                           psim_part_lo(n, C, c + 1) - psim_part_lo(n, C, c));
        }
        /* 2. exclusive scan in (cell, chunk) order, by blocks of cells */
#pragma omp for schedule(static)
        for (int b = 0; b < C; b++) {
            uint32_t sum = 0;
            for (size_t k = psim_part_lo(B, C, b); k < psim_part_lo(B, C, b + 1); k++)
                for (int c = 0; c < C; c++)
                    sum += so->hist[(size_t)c * B + k];
            so->block_total[b] = sum;
        }
#pragma omp single
        {
            uint32_t run = 0;
            for (int b = 0; b < C; b++) {
                uint32_t t = so->block_total[b];
                so->block_total[b] = run;
                run += t;
            }
            g->cellstart[B] = run;
        }
#pragma omp for schedule(static)
        for (int b = 0; b < C; b++) {
            uint32_t run = so->block_total[b];
            for (size_t k = psim_part_lo(B, C, b); k < psim_part_lo(B, C, b + 1); k++) {
                g->cellstart[k] = run;
                for (int c = 0; c < C; c++) {
                    uint32_t *h = so->hist + (size_t)c * B + k;
                    uint32_t cnt = *h;
                    *h = run;
                    run += cnt;
                }
            }
        }
        /* 3. stable scatter */
#pragma omp for schedule(static)
        for (int c = 0; c < C; c++) {
            double t0 = psim_now();
            uint32_t *restrict h = so->hist + (size_t)c * B;
            /* the arrays in registers: a store through one cannot move another */
            const double *restrict x = st->x, *restrict y = st->y, *restrict vx = st->vx,
                                   *restrict vy = st->vy;
            double *restrict x2 = st->x2, *restrict y2 = st->y2, *restrict vx2 = st->vx2,
                           *restrict vy2 = st->vy2;
            const uint32_t *restrict cell = st->cell;
            const int32_t *restrict id = st->id;
            const int far = n > SORT_PREFETCH_MIN;
            int32_t *restrict id2 = st->id2;
            uint32_t *restrict from = st->from;
            for (size_t i = psim_part_lo(n, C, c); i < psim_part_lo(n, C, c + 1); i++) {
                if (far && (i & 7) == 0) {   /* a line of each array */
                    PSIM_PREFETCH_AHEAD(x + i, 1024, 0);
                    PSIM_PREFETCH_AHEAD(y + i, 1024, 0);
                    PSIM_PREFETCH_AHEAD(vx + i, 1024, 0);
                    PSIM_PREFETCH_AHEAD(vy + i, 1024, 0);
                    PSIM_PREFETCH_AHEAD(x2 + i, 1024, 1);
                    PSIM_PREFETCH_AHEAD(y2 + i, 1024, 1);
                    PSIM_PREFETCH_AHEAD(vx2 + i, 1024, 1);
                    PSIM_PREFETCH_AHEAD(vy2 + i, 1024, 1);
                }
                uint32_t d = h[cell[i]]++;
                moved += (d != i);
                x2[d] = x[i];
                y2[d] = y[i];
                vx2[d] = vx[i];
                vy2[d] = vy[i];
                id2[d] = id[i];
                if (from)
                    from[d] = (uint32_t)i;
            }
            psim_tstat_add(ts, PSIM_PHASE_SORT, psim_now() - t0, 1, 0);
        }
    }
    psim_store_swap(st);
    return moved;
}
