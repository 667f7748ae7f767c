/* The random initial state of Berkeley CS267 HW2 and the three C++ library
 * algorithms it depends on.
 *
 * The course's starter code (2020 and later, init_particles in main.cpp or
 * common.cpp) places particles with
 *
 *     std::random_device rd;
 *     std::mt19937 gen(part_seed ? part_seed : rd());   // int part_seed
 *     int sx = (int)ceil(sqrt((double)num_parts));
 *     int sy = (num_parts + sx - 1) / sx;
 *     std::vector<int> shuffle(num_parts);              // shuffle[i] = i
 *     for (int i = 0; i < num_parts; ++i) {
 *         std::uniform_int_distribution<int> rand_int(0, num_parts - i - 1);
 *         int j = rand_int(gen);
 *         int k = shuffle[j];
 *         shuffle[j] = shuffle[num_parts - i - 1];
 *         parts[i].x = size * (1. + (k % sx)) / (1 + sx);
 *         parts[i].y = size * (1. + (k / sx)) / (1 + sy);
 *         std::uniform_real_distribution<float> rand_real(-1.0, 1.0);
 *         parts[i].vx = rand_real(gen);
 *         parts[i].vy = rand_real(gen);
 *     }
 *
 * with size = sqrt(0.0005 * num_parts) computed by the caller.  The draws
 * per particle are, in this order: one uniform_int (one or, rarely, more
 * gen() calls), then vx, then vy (one gen() each).  k % sx and k / sx are
 * int arithmetic; 1. + ... converts to double; the product with size is
 * taken first, then the quotient by the int (1 + sx) converted to double.
 * vx and vy are floats widened to double.
 *
 * The seed: part_seed ? part_seed : rd() has type unsigned int (int and
 * unsigned int), so a negative -s value becomes 2^32 + s; mt19937's
 * constructor takes its result_type and keeps the value mod 2^32.  psim's
 * 64-bit seed is therefore reduced mod 2^32 here.  The course's seed 0
 * means "ask std::random_device", which cannot be reproduced; here 0 seeds
 * the generator with 0.
 *
 * The libraries reproduced, written out so that a generated scene is the
 * same on every machine and equal to what the course's program (built with
 * GCC 11 or 12 and its libstdc++) produces; tests/unit/cs267_random_ref.cpp
 * is the C++ program that the tests compare this file with, bit for bit.
 *
 * 1. std::mt19937 (the C++ standard's mersenne_twister_engine<uint_fast32_t,
 *    32, 624, 397, 31, 0x9908b0df, 11, 0xffffffff, 7, 0x9d2c5680, 15,
 *    0xefc60000, 18, 1812433253>, libstdc++ random.tcc): seeding
 *    x[0] = seed, x[i] = 1812433253 * (x[i-1] ^ (x[i-1] >> 30)) + i mod 2^32;
 *    the whole state regenerated every 624 outputs; outputs tempered.  The
 *    standard requires the 10000th output of a default-seeded (5489) engine
 *    to be 4123659995.
 *
 * 2. std::uniform_int_distribution<int>::operator() of libstdc++ 11 and 12
 *    (bits/uniform_int_dist.h).  In unsigned arithmetic (the common type of
 *    the generator's result type and unsigned int), urange = b - a.  The
 *    generator's range urngrange is 2^32 - 1.  If urange < urngrange
 *    ("downscaling"), uerange = urange + 1 and, since urngrange ==
 *    UINT32_MAX, the draw is Lemire's nearly divisionless method _S_nd with
 *    64-bit products:
 *        product = (uint64_t)gen() * uerange; low = (uint32_t)product;
 *        if (low < uerange) {
 *            threshold = (uint32_t)-uerange % uerange;
 *            while (low < threshold) { product = (uint64_t)gen() * uerange;
 *                                      low = (uint32_t)product; }
 *        }
 *        ret = product >> 32;
 *    If urange == urngrange (a = INT_MIN, b = INT_MAX), ret = gen().  The
 *    "upscaling" branch cannot occur for int.  The result is ret + a.
 *    (libstdc++ 10 and older downscaled by rejection and a division
 *    instead, which gives other numbers.)
 *
 * 3. std::uniform_real_distribution<float>::operator() (bits/random.h):
 *    (generate_canonical<float, 24>(gen) * (b - a)) + a, all in float.
 *    generate_canonical (bits/random.tcc) computes r = 2^32 as a long
 *    double, log2r = 32, m = max(1, (24 + 32 - 1) / 32) = 1 draw; then in
 *    float: sum = (float)(gen() - 0) * 1.0f, tmp = (float)(1.0f * r) = 2^32,
 *    ret = sum / tmp; where (float)gen() rounds up to 2^32 (gen() >=
 *    2^32 - 128) ret is 1 and becomes nextafter(1.0f, 0.0f).  For [-1, 1)
 *    the product by 2 is exact, so a fused multiply-add would round the same.
 */
#include <limits.h>
#include <math.h>
#include <stdlib.h>

#include "io/cs267_random.h"

enum { MT_N = 624, MT_M = 397 };

void psim_mt19937_seed(psim_mt19937 *g, uint32_t seed)
{
    g->mt[0] = seed;
    for (uint32_t i = 1; i < MT_N; i++) {
        uint32_t x = g->mt[i - 1];
        g->mt[i] = UINT32_C(1812433253) * (x ^ (x >> 30)) + i;
    }
    g->i = MT_N;
}

static uint32_t twist(uint32_t hi, uint32_t lo, uint32_t far)
{
    uint32_t y = (hi & UINT32_C(0x80000000)) | (lo & UINT32_C(0x7fffffff));
    return far ^ (y >> 1) ^ ((y & 1) ? UINT32_C(0x9908b0df) : 0);
}

static void regenerate(psim_mt19937 *g)
{
    uint32_t *x = g->mt;
    int k = 0;
    for (; k < MT_N - MT_M; k++)
        x[k] = twist(x[k], x[k + 1], x[k + MT_M]);
    for (; k < MT_N - 1; k++)
        x[k] = twist(x[k], x[k + 1], x[k + MT_M - MT_N]);
    x[MT_N - 1] = twist(x[MT_N - 1], x[0], x[MT_M - 1]);
    g->i = 0;
}

uint32_t psim_mt19937_next(psim_mt19937 *g)
{
    if (g->i >= MT_N)
        regenerate(g);
    uint32_t z = g->mt[g->i++];
    z ^= z >> 11;
    z ^= (z << 7) & UINT32_C(0x9d2c5680);
    z ^= (z << 15) & UINT32_C(0xefc60000);
    z ^= z >> 18;
    return z;
}

int psim_uniform_int(psim_mt19937 *g, int a, int b)
{
    uint32_t urange = (uint32_t)b - (uint32_t)a, ret;
    if (urange < UINT32_MAX) {
        uint32_t uerange = urange + 1;
        uint64_t product = (uint64_t)psim_mt19937_next(g) * uerange;
        uint32_t low = (uint32_t)product;
        if (low < uerange) {
            uint32_t threshold = (uint32_t)(UINT32_C(0) - uerange) % uerange;
            while (low < threshold) {
                product = (uint64_t)psim_mt19937_next(g) * uerange;
                low = (uint32_t)product;
            }
        }
        ret = (uint32_t)(product >> 32);
    } else
        ret = psim_mt19937_next(g);
    return (int)((int64_t)a + ret); /* in [a, b]: no wraparound needed */
}

float psim_canonical_float(uint32_t u)
{
    float sum = (float)u * 1.0f, tmp = 4294967296.0f;
    float ret = sum / tmp;
    if (ret >= 1.0f)
        ret = nextafterf(1.0f, 0.0f);
    return ret;
}

float psim_uniform_real_float(psim_mt19937 *g, float a, float b)
{
    float c = psim_canonical_float(psim_mt19937_next(g));
    float scaled = c * (b - a); /* rounded on its own, as the course's */
    return scaled + a;
}

int psim_cs267_place_part(long n, uint64_t seed, double size, long lo, long hi, double *x,
                          double *y, double *vx, double *vy)
{
    if (n < 0 || n > INT_MAX || lo < 0 || hi > n || lo > hi)
        return -1;
    int num = (int)n;
    int *shuffle = malloc((num ? (size_t)num : 1) * sizeof *shuffle);
    if (!shuffle)
        return -1;
    psim_mt19937 *g = malloc(sizeof *g);
    if (!g) {
        free(shuffle);
        return -1;
    }
    psim_mt19937_seed(g, (uint32_t)seed); /* mod 2^32, as std::mt19937 */
    int sx = (int)ceil(sqrt((double)num));
    int sy = num ? (num + sx - 1) / sx : 0;
    for (int i = 0; i < num; i++)
        shuffle[i] = i;
    /* the particles before lo draw as many numbers as in the whole run
     * (the shuffle and both velocities), kept by none */
    for (int i = 0; i < (int)hi; i++) {
        int j = psim_uniform_int(g, 0, num - i - 1);
        int k = shuffle[j];
        shuffle[j] = shuffle[num - i - 1];
        float u = psim_uniform_real_float(g, -1.0f, 1.0f);
        float w = psim_uniform_real_float(g, -1.0f, 1.0f);
        if (i < lo)
            continue;
        long o = i - lo;
        x[o] = size * (1. + (k % sx)) / (1 + sx);
        y[o] = size * (1. + (k / sx)) / (1 + sy);
        vx[o] = u;
        vy[o] = w;
    }
    free(g);
    free(shuffle);
    return 0;
}

int psim_cs267_place(long n, uint64_t seed, double size, double *x, double *y,
                     double *vx, double *vy)
{
    return psim_cs267_place_part(n, seed, size, 0, n, x, y, vx, vy);
}
