/* Morton (Z-order) keys of 2D cell coordinates: x in the even bits, y in the
 * odd bits. */
#ifndef PSIM_ENGINE_MORTON_H
#define PSIM_ENGINE_MORTON_H
#include <stdint.h>

static inline uint64_t psim_morton_spread(uint32_t v)
{
    uint64_t x = v;
    x = (x | (x << 16)) & 0x0000FFFF0000FFFFull;
    x = (x | (x << 8)) & 0x00FF00FF00FF00FFull;
    x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Full;
    x = (x | (x << 2)) & 0x3333333333333333ull;
    x = (x | (x << 1)) & 0x5555555555555555ull;
    return x;
}

static inline uint32_t psim_morton_compact(uint64_t x)
{
    x &= 0x5555555555555555ull;
    x = (x | (x >> 1)) & 0x3333333333333333ull;
    x = (x | (x >> 2)) & 0x0F0F0F0F0F0F0F0Full;
    x = (x | (x >> 4)) & 0x00FF00FF00FF00FFull;
    x = (x | (x >> 8)) & 0x0000FFFF0000FFFFull;
    x = (x | (x >> 16)) & 0x00000000FFFFFFFFull;
    return (uint32_t)x;
}

static inline uint64_t psim_morton_encode(uint32_t x, uint32_t y)
{
    return psim_morton_spread(x) | (psim_morton_spread(y) << 1);
}

static inline void psim_morton_decode(uint64_t key, uint32_t *x, uint32_t *y)
{
    *x = psim_morton_compact(key);
    *y = psim_morton_compact(key >> 1);
}

#endif
