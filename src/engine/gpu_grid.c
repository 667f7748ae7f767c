/* The cells of a GPU path (gpu_grid.h). */
#include <float.h>
#include <math.h>
#include <stdint.h>

#include "gpu_grid.h"

int32_t psim_gpu_grid_most(long n)
{
    double most = ceil(sqrt(PSIM_GPU_CELLS_PARTICLE * (double)(n > 1 ? n : 1)));
    return most > PSIM_GPU_MAX_SIDE ? PSIM_GPU_MAX_SIDE : (int32_t)most;
}

int psim_gpu_grid_plan(double size, double reach, long n, psim_gpu_grid *g)
{
    if (!(size > 0 && size <= DBL_MAX && reach > 0 && reach <= DBL_MAX))
        return -1;
    /* wider than the reach by more than the rounding of x * inv and of
     * the distances compared with it */
    double wide = reach * (1 + 1e-9) + 8 * DBL_EPSILON * size;
    double side = floor(size / wide), most = psim_gpu_grid_most(n);
    side = side < most ? side : most;
    g->side = side < 1 ? 1 : (int32_t)side;
    g->inv = (double)g->side / size;
    g->key_bits = psim_gpu_bits((uint64_t)g->side * (uint64_t)g->side - 1);
    return 0;
}

int psim_gpu_bits(uint64_t top)
{
    int bits = 1;
    while (bits < 32 && (top >> bits) != 0)
        bits++;
    return bits;
}

long psim_gpu_blocks(long n)
{
    if (n < 0)
        return -1;
    long blocks = n / PSIM_GPU_THREADS + (n % PSIM_GPU_THREADS != 0);
    return blocks > INT32_MAX ? -1 : blocks;   /* gridDim.x < 2^31 */
}
