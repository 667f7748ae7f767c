/* A state as text, from its columns (state_write.c). */
#ifndef PSIM_IO_STATE_WRITE_H
#define PSIM_IO_STATE_WRITE_H
#include <stdint.h>
#include <stdio.h>

/* The state's columns: particle i (by id) is at[i] in the arrays, or i
 * when at is NULL. */
typedef struct psim_cols {
    const double *x, *y, *vx, *vy;
    const int32_t *at;
} psim_cols;
/* Lines "STEP i x y vx vy" in id order, as psim_write_state, by `threads`
 * threads. */
int psim_write_state_cols(FILE *f, long step, long n, const psim_cols *c, int digits,
                          int threads);

#endif
