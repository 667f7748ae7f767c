/* The model interface: what the engine calls each step.
 *
 * The engine owns the particles (store), the grid and the sort.  A model
 * moves the particles before the sort (drift) and does its pair work after it
 * (interact), timing its own phases into the engine's stats.  A model may
 * check a finished step against the state before it (check).  New models
 * live in their own folder under src/models/ and are listed in models.c. */
#ifndef PSIM_MODELS_MODEL_H
#define PSIM_MODELS_MODEL_H

#include "psim/psim.h"

struct psim_sim;

/* The state of every particle by id, as it was before a step. */
typedef struct psim_snapshot {
    long n;
    double *x, *y, *vx, *vy;
} psim_snapshot;

typedef struct psim_model {
    const char *name;
    void *(*create)(struct psim_sim *e, psim_error *err);
    void (*drift)(struct psim_sim *e, void *m);
    int (*interact)(struct psim_sim *e, void *m, psim_error *err);
    int (*check)(struct psim_sim *e, void *m, const psim_snapshot *before,
                 const psim_snapshot *after, psim_error *err);
    void (*destroy)(void *m);
} psim_model;

const psim_model *psim_model_get(psim_model_id id);

#endif
