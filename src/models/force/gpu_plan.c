/* The force model's GPU path, host-side plan (gpu_plan.h). */
#include <stdint.h>

#include "gpu_plan.h"

int fgpu_bytes(long n, const psim_gpu_grid *g, size_t sort_tmp, size_t *total)
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
