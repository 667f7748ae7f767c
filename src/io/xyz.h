/* A state as an extended XYZ frame (xyz.c). */
#ifndef PSIM_IO_XYZ_H
#define PSIM_IO_XYZ_H
#include <stdio.h>

#include "state_write.h"

/* One extended XYZ frame of the columns after `step` steps, at model time
 * `time` (xyz.c; psim_write_dump), or the part of it `part` says. */
int psim_write_xyz_cols(FILE *f, long step, double time, long n, double L, double r,
                        const psim_cols *c, const psim_part *part, int threads);

#endif
