/* Shared by the fuzz targets (tests/fuzz, docs/reliability.md). */
#ifndef PSIM_FUZZ_H
#define PSIM_FUZZ_H
#include <stddef.h>
#include <stdint.h>

#include "io/scene.h"

/* Scenes larger than this are only read, not run (a target must stay
 * fast: thousands of inputs a second). */
#define FUZZ_MAX_DISKS 64
#define FUZZ_STEPS 3
/* Scenes with a disk crossing the box more often than this are not run
 * (fuzz_run.c: the event model's wall events would take seconds). */
#define FUZZ_MAX_CROSSINGS 1e4

/* Scenes whose particle count N (their first number) is larger than this
 * are not read: the reader allocates N particles before their lines (a
 * 2e9-disk header asks for 64 GB, past the fuzzer's memory limit, where
 * the OS would hand out untouched pages), and a 2019 scene without lines
 * is generated (11 million disks: 18 s).  Both are the inputs' size, not
 * a defect; the limit keeps each input fast. */
#define FUZZ_MAX_READ 100000

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Up to `steps` checked steps of `model` on sc on one thread, with
 * `options` (NULL: none); errors are expected and ignored. */
void fuzz_run(const psim_scene *sc, const char *model, const char *options, long steps);

#endif
