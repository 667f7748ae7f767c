/* PSIM_HD marks a static inline function that both the C code and the
 * CUDA kernels call (__host__ __device__ under nvcc, nothing in C): one
 * copy of the arithmetic, so that the CPU's tests run the very operations
 * the GPU runs (docs/gpu.md). */
#ifndef PSIM_ENGINE_HD_H
#define PSIM_ENGINE_HD_H
#ifdef __CUDACC__
#define PSIM_HD __host__ __device__
#else
#define PSIM_HD
#endif
#endif
