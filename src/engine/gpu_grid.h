/* The cells a GPU path bins particles into (plain C, tested on every
 * build): square cells over [0, size]^2, each at least a given reach wide
 * with room for rounding, so that two particles within the reach of each
 * other on each axis are in the same or adjacent cells; the launches'
 * blocks.  The cell functions are PSIM_HD: the kernels (gpu_store.cuh and
 * the models' .cu files) call the same ones as the tests. */
#ifndef PSIM_ENGINE_GPU_GRID_H
#define PSIM_ENGINE_GPU_GRID_H
#include <stddef.h>
#include <stdint.h>

#include "hd.h"

#define PSIM_GPU_THREADS 256        /* threads a block, every kernel */
#define PSIM_GPU_MAX_SIDE 65535     /* cells a side: keys cy * side + cx fit 32 bits */
/* Cells a particle, at most (about): wider cells, not narrower, so that
 * the memory of the cells stays that of the particles. */
#define PSIM_GPU_CELLS_PARTICLE 2

/* side cells a side; key_bits: the bits of the largest cell key (the
 * radix sort's). */
typedef struct psim_gpu_grid {
    int32_t side;
    double inv;                 /* side / size: cells per unit length */
    int key_bits;
} psim_gpu_grid;

/* The grid for n particles in a box of size, cells at least reach wide,
 * no more than about PSIM_GPU_CELLS_PARTICLE a particle: 0, or -1 where
 * size or reach is not a positive finite number. */
int psim_gpu_grid_plan(double size, double reach, long n, psim_gpu_grid *g);
/* The most cells a side psim_gpu_grid_plan gives n particles. */
int32_t psim_gpu_grid_most(long n);
/* The bits a radix sort of keys up to top needs (1 to 32; 32 for any
 * larger top). */
int psim_gpu_bits(uint64_t top);

/* The cell column (or row) of coordinate x, held inside the grid (a
 * coordinate outside the box, or NaN, is in an edge cell). */
PSIM_HD static inline int32_t psim_gpu_cell(const psim_gpu_grid *g, double x)
{
    double c = x * g->inv;
    if (!(c >= 0))
        return 0;
    return c >= (double)(g->side - 1) ? g->side - 1 : (int32_t)c;
}

PSIM_HD static inline uint32_t psim_gpu_key(const psim_gpu_grid *g, double x, double y)
{
    return (uint32_t)psim_gpu_cell(g, y) * (uint32_t)g->side + (uint32_t)psim_gpu_cell(g, x);
}

/* The cells around cell (cx, cy), itself included, inside the grid:
 * columns x0..x1 and rows y0..y1. */
typedef struct psim_gpu_range {
    int32_t x0, x1, y0, y1;
} psim_gpu_range;

PSIM_HD static inline psim_gpu_range psim_gpu_around(const psim_gpu_grid *g, int32_t cx,
                                                     int32_t cy)
{
    psim_gpu_range r = {cx - 1, cx + 1, cy - 1, cy + 1};
    r.x0 = r.x0 < 0 ? 0 : r.x0;
    r.y0 = r.y0 < 0 ? 0 : r.y0;
    r.x1 = r.x1 >= g->side ? g->side - 1 : r.x1;
    r.y1 = r.y1 >= g->side ? g->side - 1 : r.y1;
    return r;
}

/* Blocks of PSIM_GPU_THREADS threads for n items, one a thread: 0 for
 * none; -1 where n is negative or needs more blocks than a launch takes. */
long psim_gpu_blocks(long n);

#endif
