/* The random initial state of Berkeley CS267 HW2 (2020+ starter code):
 * std::mt19937 and libstdc++'s (GCC 11/12) uniform_int_distribution<int>
 * and uniform_real_distribution<float>, written out in C.  See
 * src/io/cs267_random.c and docs/cs267-random.md. */
#ifndef PSIM_IO_CS267_RANDOM_H
#define PSIM_IO_CS267_RANDOM_H
#include <stdint.h>

/* std::mt19937: 624 words of state and the index of the next one. */
typedef struct {
    uint32_t mt[624];
    int i;
} psim_mt19937;

/* std::mt19937 gen(seed) / gen.seed(seed). */
void psim_mt19937_seed(psim_mt19937 *g, uint32_t seed);
/* gen(): the next 32-bit output. */
uint32_t psim_mt19937_next(psim_mt19937 *g);

/* std::uniform_int_distribution<int>(a, b)(gen) as libstdc++ 11/12 draws
 * it (Lemire's nearly divisionless method); a <= b. */
int psim_uniform_int(psim_mt19937 *g, int a, int b);

/* std::generate_canonical<float, 24>(gen) for the draw u = gen(): one draw,
 * (float)u / 2^32 in float, and nextafterf(1, 0) where that rounds to 1. */
float psim_canonical_float(uint32_t u);

/* std::uniform_real_distribution<float>(a, b)(gen):
 * canonical * (b - a) + a, in float. */
float psim_uniform_real_float(psim_mt19937 *g, float a, float b);

/* init_particles(parts, n, size, seed) of the course: positions on a
 * sx-by-sy lattice in a shuffled order, velocities uniform in [-1, 1) drawn
 * as floats, all stored as doubles in x, y, vx, vy (n entries each).  The
 * generator is seeded with seed mod 2^32 (std::mt19937 takes a 32-bit
 * value); the course's seed 0 asks std::random_device instead, which cannot
 * be reproduced, and here seeds the generator with 0.  Returns 0, or -1
 * when n is negative or above INT_MAX (the course's int) or the shuffle
 * array cannot be allocated. */
int psim_cs267_place(long n, uint64_t seed, double size, double *x, double *y,
                     double *vx, double *vy);
/* The same, particles lo..hi-1 of them alone into x, y, vx, vy (hi - lo
 * entries each): the numbers drawn for the others are drawn and dropped,
 * the shuffle array (n ints) is the only memory of n. */
int psim_cs267_place_part(long n, uint64_t seed, double size, long lo, long hi, double *x,
                          double *y, double *vx, double *vy);

#endif
