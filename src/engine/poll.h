/* Progress and stopping inside a step.
 *
 * A step may run for hours (the event model's events, the discrete
 * model's resolutions up to its settle budget, the pair loops of a huge
 * scene).  Every loop of a model that can run long within a step calls
 * psim_poll every PSIM_POLL_WORK units of its work or so: the poll adds
 * them to the step's count, reports progress to the caller when it is
 * due (psim_set_step_progress) and says whether a stop was asked
 * (psim_request_stop, from a signal handler): then the loop ends, and the
 * model's interact returns psim_engine_stopped.  A poll reads the clock
 * only when a caller wants progress, some 20 ns every few thousand units
 * of work of 10 ns or more each. */
#ifndef PSIM_ENGINE_POLL_H
#define PSIM_ENGINE_POLL_H
#include <stdint.h>

#include "../io/scene.h"

struct psim_sim;

/* Units of a model's work between two polls. */
#define PSIM_POLL_WORK 4096

/* The step's poll state (in struct psim_sim). */
typedef struct psim_poll_state {
    psim_step_progress_fn fn;   /* NULL: no progress wanted */
    void *ctx;
    double first_s, every_s;    /* the first report, then the gap */
    double start;               /* when this step began */
    double next;                /* when a report is due (atomic) */
    uint64_t work;              /* units done in this step (atomic) */
    int busy;                   /* a report is being made (atomic) */
} psim_poll_state;

/* `work` more units of the step's work done, from any thread; nonzero when
 * the run was asked to stop.  Reports progress when it is due (one report
 * at a time, from whichever thread polls then). */
int psim_poll(const struct psim_sim *e, uint64_t work);
/* Work done without a poll (where a loop ends). */
void psim_poll_add(const struct psim_sim *e, uint64_t work);
/* "step K: interrupted" into err; returns -1 (interact's failure). */
int psim_engine_stopped(const struct psim_sim *e, psim_error *err);
/* A new step begins (psim_step). */
void psim_poll_begin(struct psim_sim *e);

#endif
