/* Shared by the fuzz targets (tests/fuzz, docs/reliability.md). */
#ifndef PSIM_FUZZ_H
#define PSIM_FUZZ_H
#include <stddef.h>
#include <stdint.h>

#include "psim/psim.h"

/* Scenes larger than this are only read, not run (a target must stay
 * fast: thousands of inputs a second). */
#define FUZZ_MAX_DISKS 64
#define FUZZ_STEPS 3
/* Scenes with a disk crossing the box more often than this are not run
 * (fuzz_run.c: the event model's wall events would take seconds). */
#define FUZZ_MAX_CROSSINGS 1e4

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Up to `steps` checked steps of `model` on sc on one thread, with
 * `options` (NULL: none); errors are expected and ignored. */
void fuzz_run(const psim_scene *sc, const char *model, const char *options, long steps);

#endif
