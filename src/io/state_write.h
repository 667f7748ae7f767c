/* A state as text, from its columns (state_write.c). */
#ifndef PSIM_IO_STATE_WRITE_H
#define PSIM_IO_STATE_WRITE_H
#include <stdint.h>
#include <stdio.h>

/* The state's columns: particle id0 + i is at[i] in the arrays, or i
 * when at is NULL (id0: the first id of a part, psim_part; else 0). */
typedef struct psim_cols {
    const double *x, *y, *vx, *vy;
    const int32_t *at;
    long id0;
} psim_cols;

/* A part of a file that several processes write (over MPI ranks, each its
 * parts at their offsets): the lines of ids id0 .. id0 + n - 1 of a state
 * of `total` particles, with the file's header only where `head` and its
 * footer only where `foot`.  A writer given none (NULL) writes the whole
 * file. */
typedef struct psim_part {
    long id0, total;
    int head, foot;
} psim_part;
/* Lines "STEP i x y vx vy" in id order, as psim_write_state, by `threads`
 * threads. */
int psim_write_state_cols(FILE *f, long step, long n, const psim_cols *c, int digits,
                          int threads);

#endif
