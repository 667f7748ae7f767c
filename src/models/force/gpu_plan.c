/* The force model's GPU path, host-side plan (gpu_plan.h). */
#include <float.h>
#include <math.h>
#include <stdint.h>

#include "gpu_plan.h"

int fgpu_grid_plan(double size, double cutoff, long n, fgpu_grid *g)
{
    if (!(size > 0 && size <= DBL_MAX && cutoff > 0 && cutoff <= DBL_MAX))
        return -1;
    /* wider than the cutoff by more than the rounding of x * inv and of
     * the pair's distance */
    double reach = cutoff * (1 + 1e-9) + 8 * DBL_EPSILON * size;
    double side = floor(size / reach);
    double most = ceil(sqrt(FGPU_CELLS_PARTICLE * (double)(n > 1 ? n : 1)));
    side = side < most ? side : most;
    g->side = side < 1 ? 1 : side > FGPU_MAX_SIDE ? FGPU_MAX_SIDE : (int32_t)side;
    g->inv = (double)g->side / size;
    uint64_t top = (uint64_t)g->side * (uint64_t)g->side - 1;
    g->key_bits = 1;
    while (g->key_bits < 32 && (top >> g->key_bits) != 0)
        g->key_bits++;
    return 0;
}

long fgpu_blocks(long n)
{
    if (n < 0)
        return -1;
    long blocks = n / FGPU_THREADS + (n % FGPU_THREADS != 0);
    return blocks > INT32_MAX ? -1 : blocks;   /* gridDim.x < 2^31 */
}

int fgpu_bytes(long n, const fgpu_grid *g, size_t sort_tmp, size_t *total)
{
    if (n < 0 || n > INT32_MAX)
        return -1;
    size_t cells = (size_t)g->side * (size_t)g->side;
    size_t a = (size_t)n, b = cells;
    if (a > SIZE_MAX / FGPU_BYTES_PARTICLE || b > SIZE_MAX / FGPU_BYTES_CELL)
        return -1;
    a *= FGPU_BYTES_PARTICLE;
    b *= FGPU_BYTES_CELL;
    if (a > SIZE_MAX - b || a + b > SIZE_MAX - sort_tmp)
        return -1;
    *total = a + b + sort_tmp;
    return 0;
}
