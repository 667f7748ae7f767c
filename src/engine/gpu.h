/* CUDA devices: which one a run uses, and which there are.
 *
 * The psim program picks the device of its runs (--device) before it
 * creates them; the engine hands the choice to the model, whose own GPU
 * path (model.h: gpu) runs there.  Built without CUDA, there are none. */
#ifndef PSIM_ENGINE_GPU_H
#define PSIM_ENGINE_GPU_H
#include <stddef.h>

/* Whether psim was built with its CUDA path. */
int psim_gpu_built(void);
/* The device the simulations created from now on run on: a CUDA device
 * number, or -1 for the CPU (the default). */
void psim_gpu_use(int device);
int psim_gpu_used(void);
/* How many CUDA devices this process sees (0 without CUDA, a driver or a
 * device); *why, where none, says why in a few words. */
int psim_gpu_count(const char **why);
/* Ends the process with one line and exit status 1: a model's sync
 * could not copy its state from the device, and the engine is about to
 * read the store (nothing it wrote would be true). */
void psim_gpu_lost(void);
/* Device k's name and memory into buf ("NVIDIA H200, 139.8 GiB"). */
void psim_gpu_describe(int k, char *buf, size_t size);

#endif
