/* The force model's GPU path, host-side plan (plain C, tested on every
 * build): the cells the kernels bin the particles into, the launches'
 * blocks, the device memory a run takes, and the cells around a cell.
 * The cell functions are PSIM_HD: gpu.cu's kernels call the same ones. */
#ifndef PSIM_FORCE_GPU_PLAN_H
#define PSIM_FORCE_GPU_PLAN_H
#include <stddef.h>
#include <stdint.h>

#include "../../engine/hd.h"

#define FGPU_THREADS 256        /* threads a block, every kernel */
#define FGPU_MAX_SIDE 65535     /* cells a side: keys cy * side + cx fit 32 bits */
/* Forces a particle gathers before it sums them in partner id order
 * (more: it finds them one by one in id order instead, gpu.cu). */
#define FGPU_LOCAL 32

/* Square cells over [0, size]^2, side cells a side, each at least the
 * cutoff wide with room for rounding, so that a pair within the cutoff
 * is in the same or adjacent cells; key_bits: the bits of the largest
 * cell key (the radix sort's). */
typedef struct fgpu_grid {
    int32_t side;
    double inv;                 /* side / size: cells per unit length */
    int key_bits;
} fgpu_grid;

/* The grid for n particles in a box of size with this cutoff, with no
 * more than about FGPU_CELLS_PARTICLE cells a particle (wider cells, not
 * narrower: the memory of the cells stays that of the particles): 0, or
 * -1 where size or cutoff is not a positive finite number. */
#define FGPU_CELLS_PARTICLE 2
int fgpu_grid_plan(double size, double cutoff, long n, fgpu_grid *g);

/* The cell column (or row) of coordinate x, held inside the grid (a
 * coordinate outside the box, or NaN, is in an edge cell). */
PSIM_HD static inline int32_t fgpu_cell(const fgpu_grid *g, double x)
{
    double c = x * g->inv;
    if (!(c >= 0))
        return 0;
    return c >= (double)(g->side - 1) ? g->side - 1 : (int32_t)c;
}

PSIM_HD static inline uint32_t fgpu_key(const fgpu_grid *g, double x, double y)
{
    return (uint32_t)fgpu_cell(g, y) * (uint32_t)g->side + (uint32_t)fgpu_cell(g, x);
}

/* The cells around cell (cx, cy), itself included, inside the grid:
 * columns x0..x1 and rows y0..y1. */
typedef struct fgpu_range {
    int32_t x0, x1, y0, y1;
} fgpu_range;

PSIM_HD static inline fgpu_range fgpu_around(const fgpu_grid *g, int32_t cx, int32_t cy)
{
    fgpu_range r = {cx - 1, cx + 1, cy - 1, cy + 1};
    r.x0 = r.x0 < 0 ? 0 : r.x0;
    r.y0 = r.y0 < 0 ? 0 : r.y0;
    r.x1 = r.x1 >= g->side ? g->side - 1 : r.x1;
    r.y1 = r.y1 >= g->side ? g->side - 1 : r.y1;
    return r;
}

/* Blocks of FGPU_THREADS threads for n items, one a thread: 0 for none;
 * -1 where n is negative or needs more blocks than a launch takes. */
long fgpu_blocks(long n);

/* The device memory of a run of n particles on grid g: bytes a particle
 * (every array, double-buffered for the sort), bytes of the cells, and
 * their total with sort_tmp bytes of the sort's scratch, into *total.
 * 0, or -1 where the total does not fit a size_t or n is beyond the
 * sort's int count. */
#define FGPU_BYTES_PARTICLE (2 * (4 * sizeof(double) + sizeof(int32_t) + 2 * sizeof(uint32_t)))
#define FGPU_BYTES_CELL (2 * sizeof(uint32_t))
int fgpu_bytes(long n, const fgpu_grid *g, size_t sort_tmp, size_t *total);

#endif
