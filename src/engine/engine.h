/* The engine: one simulation.  It owns the store, the grid and the sorter,
 * runs the phases of a step and times each of them; the model does the
 * physics (src/models/). */
#ifndef PSIM_ENGINE_ENGINE_H
#define PSIM_ENGINE_ENGINE_H

#include "psim/psim.h"
#include "grid.h"
#include "sort.h"
#include "store.h"
#include "timer.h"
#include "model.h"

struct psim_sim {
    psim_config cfg;
    int threads;
    long n;
    double L, r;
    long step;              /* steps done */
    psim_store st;
    int has_grid;           /* the model asked for a grid: sort every step */
    psim_grid grid;
    psim_sorter sorter;
    psim_stats stats;
    psim_thread_stats *tstats;   /* one per thread */
    const psim_model *model;
    void *mstate;
    psim_snapshot before, after; /* by id, for checks */
    double opt_value[PSIM_MODEL_OPTIONS]; /* the model's options, as set */
    int opt_set[PSIM_MODEL_OPTIONS];
};

/* Time fn(e, m) into phase p. */
#define PSIM_TIMED(e, p, call)                                            \
    do {                                                                  \
        double t0_ = psim_now();                                          \
        call;                                                             \
        (e)->stats.phase_s[(p)] += psim_now() - t0_;                      \
    } while (0)

#endif
