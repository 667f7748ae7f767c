/* CUDA devices (gpu.h): the CUDA runtime's count and properties, or none
 * in a build without CUDA. */
#include <stdio.h>
#include <stdlib.h>

#include "gpu.h"
#ifdef PSIM_HAVE_CUDA
#include <cuda_runtime_api.h>
#endif

static int gpu_device = -1;

int psim_gpu_built(void)
{
#ifdef PSIM_HAVE_CUDA
    return 1;
#else
    return 0;
#endif
}

void psim_gpu_use(int device) { gpu_device = device; }
int psim_gpu_used(void) { return gpu_device; }

int psim_gpu_count(const char **why)
{
#ifdef PSIM_HAVE_CUDA
    int n = 0;
    cudaError_t rc = cudaGetDeviceCount(&n);
    if (rc != cudaSuccess) {
        *why = cudaGetErrorString(rc);
        return 0;
    }
    if (n == 0)
        *why = "the CUDA runtime sees no device";
    return n;
#else
    *why = "psim was built without CUDA";
    return 0;
#endif
}

void psim_gpu_lost(void)
{
    fputs("psim: --device gpu: the state could not be copied from the device\n", stderr);
    exit(1);
}

void psim_gpu_describe(int k, char *buf, size_t size)
{
#ifdef PSIM_HAVE_CUDA
    struct cudaDeviceProp p;
    if (cudaGetDeviceProperties(&p, k) == cudaSuccess) {
        snprintf(buf, size, "%s, %.1f GiB, compute capability %d.%d", p.name,
                 (double)p.totalGlobalMem / (1024.0 * 1024 * 1024), p.major, p.minor);
        return;
    }
#endif
    snprintf(buf, size, "device %d", k);
}
