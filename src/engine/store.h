/* The particle store: a structure of arrays, cache-line aligned, with a
 * second set of arrays the sort scatters into. */
#ifndef PSIM_ENGINE_STORE_H
#define PSIM_ENGINE_STORE_H
#include <stddef.h>
#include <stdint.h>

typedef struct psim_store {
    size_t n;
    size_t cap;                  /* room in every array */
    double *x, *y, *vx, *vy;
    int32_t *id;
    double *x2, *y2, *vx2, *vy2; /* sort targets, swapped in after a sort */
    int32_t *id2;
    uint32_t *cell;              /* cell rank of each particle, by the sort */
    uint32_t *from;              /* NULL, or (over MPI ranks) where the sort
                                  * took each particle from */
} psim_store;

int psim_store_init(psim_store *s, size_t n);
void psim_store_free(psim_store *s);
/* Room for n particles (their contents lost when it grows); n set.  0, or
 * -1 when out of memory (the store then empty). */
int psim_store_resize(psim_store *s, size_t n);
/* The same, keeping the particles the store holds (its first n, if fewer). */
int psim_store_keep(psim_store *s, size_t n);
/* Swap the arrays with the sort targets. */
void psim_store_swap(psim_store *s);

#endif
