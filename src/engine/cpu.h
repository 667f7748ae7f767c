/* What the CPU can do, asked at run time: models with an AVX-512 path
 * compile it where the compiler can target it (PSIM_AVX512) and take it
 * where psim_have_avx512() says the CPU has it; the other path gives the
 * same results. */
#ifndef PSIM_ENGINE_CPU_H
#define PSIM_ENGINE_CPU_H

/* x86-64 only: on 32-bit x86 the plain paths may compute in x87's longer
 * precision, and then their results could differ from the vectors' */
#if defined(__GNUC__) && defined(__x86_64__)
#define PSIM_AVX512 1
static inline int psim_have_avx512(void)
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
}
#else
#define PSIM_AVX512 0
static inline int psim_have_avx512(void)
{
    return 0;
}
#endif

#endif
