/* --device cpu|gpu|gpu:K, and psim topo's list of CUDA devices. */
#ifndef PSIM_CLI_DEVICE_H
#define PSIM_CLI_DEVICE_H
#include <stdio.h>

/* --device's value into *device (-1: the CPU; K: CUDA device K): 0, or 2
 * after one line on a value that is none of cpu, gpu and gpu:K. */
int cli_device_parse(const char *text, int *device);
/* The runs from now on on *device (engine/gpu.h): 0, or 2 after one line
 * when it is a GPU and psim was built without CUDA. */
int cli_device_use(int device);
/* The CUDA devices this process sees, a line each, or one line saying
 * why there are none. */
void cli_device_list(FILE *f);

#endif
