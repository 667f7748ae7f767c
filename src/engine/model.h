/* The model interface: what the engine calls each step.
 *
 * The engine owns the particles (store), the grid and the sort; it knows
 * no model by name.  A model is one value of this type, defined in its own
 * folder under src/models/ and listed in src/models/models.c, the layer
 * that composes engine and models.
 *
 * A step (psim_step): a new step for the polls; with --check, the state
 * before it saved; interact, the whole step, moves included; the step
 * counted; with --check, check comparing the state before and after.
 * interact times its own phases (named in phases[], numbered from
 * PSIM_PHASE_MODEL) and may time its moves as the engine's "move" phase
 * (PSIM_PHASE_MOVE); it adds to its counters (named in counters[]).
 * Every loop of interact that can run long polls (poll.h): progress, and
 * a stop asked by a signal, inside the step.
 *
 * The grid (psim_engine_grid and the calls after it) and the sort by cell
 * (psim_engine_sort) are services a model calls: the engine plans no grid
 * and never sorts the store by itself.  A model that wants its particles
 * by cell plans a grid and calls the sort when it needs them sorted. */
#ifndef PSIM_ENGINE_MODEL_H
#define PSIM_ENGINE_MODEL_H
#include <stdio.h>

#include "../io/scene.h"
#include "../io/fmt.h"
#include "../io/lines.h"
#include "../io/state_write.h"
#include "dist.h"

struct psim_sim;

/* The state of every particle by id, as it was before a step. */
typedef struct psim_snapshot {
    long n;
    double *x, *y, *vx, *vy;
} psim_snapshot;

#define PSIM_MODEL_PHASES (PSIM_PHASES_MAX - PSIM_PHASE_MODEL)
#define PSIM_MODEL_OPTIONS 12

/* A model option (--option NAME=VALUE): a number in [lo, hi], a whole
 * one where whole is set (switches, counts). */
typedef struct psim_model_option {
    const char *name, *help;
    double lo, hi;
    int whole;
} psim_model_option;

/* The option that turns a model's skips off (tests compare the bytes). */
#define PSIM_SKIP_OPTION {"skip", "0: never leave out a stage the scene cannot use (for tests)", 0, 1, 1}

/* The largest magnitudes a model's arithmetic can carry out (its squared
 * distances, squared speeds, products of the two, cell counts): a scene
 * beyond one is refused before the model is made, naming the line of L,
 * r or the disk (limits.c), instead of running into numbers that
 * overflow in the middle of a step.  `speed` is the speed one disk may
 * reach, S = sqrt(sum of vx^2 + vy^2 over the disks): collisions that
 * keep the kinetic energy can give it all to one disk, so a bound on S
 * holds for the whole run.  most 0: no bound; why names the arithmetic
 * that would overflow past it, for the message. */
enum {
    PSIM_LIMIT_BOX,          /* L */
    PSIM_LIMIT_RADIUS,       /* r */
    PSIM_LIMIT_POSITION,     /* |x| and |y| of every disk */
    PSIM_LIMIT_SPEED,        /* S */
    PSIM_LIMIT_BOX_SPEED,    /* L times S */
    PSIM_LIMIT_RADIUS_SPEED, /* r times S */
    PSIM_LIMITS
};
typedef struct psim_limit {
    double most;
    const char *why;
} psim_limit;
typedef struct psim_limits {
    psim_limit at[PSIM_LIMITS];
} psim_limits;

/* A stage a model leaves out when the scene cannot use it (psim_stats). */
typedef struct psim_model_skip {
    const char *stage, *why;
} psim_model_skip;

typedef struct psim_model {
    const char *name;
    const char *summary;                          /* one line for psim models */
    const char *phases[PSIM_MODEL_PHASES + 1];    /* its own phases, NULL-terminated */
    const char *counters[PSIM_COUNTERS_MAX + 1];  /* logged quantities, NULL-terminated */
    const char *values[PSIM_VALUES_MAX + 1];      /* measured ones (double), likewise */
    /* --thermo columns: counters, by name (shown as the change since the
     * last row), NULL-terminated */
    const char *thermo[PSIM_THERMO_MAX + 1];
    psim_output_style output;                     /* how its source prints */
    int output_digits;                            /* default decimals; -1: shortest */
    psim_model_option options[PSIM_MODEL_OPTIONS + 1]; /* name NULL ends them */
    psim_model_skip skips[PSIM_SKIPS_MAX + 1];          /* stage NULL ends them */
    int follows_order;  /* its results depend on the store's order (the
                         * order of equal keys the sort keeps): restart
                         * files list the particles in that order, not by id */
    /* what its polls count (poll.h), for progress inside a step:
     * "events", "resolutions", ... */
    const char *work_unit;

    /* optional: its limits for this scene and the run's options (0), or
     * -1 with err set where a quantity it derives from them (a force
     * law's constant) cannot be carried out */
    int (*limits)(const struct psim_sim *e, const psim_scene *sc, psim_limits *lim,
                  psim_error *err);
    void *(*create)(struct psim_sim *e, const psim_scene *sc, psim_error *err);
    int (*interact)(struct psim_sim *e, void *m, psim_error *err);
    int (*check)(struct psim_sim *e, void *m, const psim_snapshot *before,
                 const psim_snapshot *after, psim_error *err);  /* optional */
    /* optional: its source's output format (default psim_write_state) */
    int (*write_state)(struct psim_sim *e, void *m, FILE *f, long step,
                       int final, int digits);
    /* optional: the header line of its source's output files */
    int (*write_header)(struct psim_sim *e, void *m, FILE *f);
    /* optional: the "per step:" line of the run summary */
    void (*step_summary)(FILE *f, const psim_stats *st);
    /* optional: what its source prints at the end of a run */
    void (*source_summary)(FILE *f, const struct psim_sim *e, const void *m,
                           double seconds);
    /* optional: each particle's own state beyond x, y, vx and vy, for
     * restart files: the columns (name NULL ends them; the reader holds a
     * file's values to each one's kind and range, and requires them all)
     * and column k by id; create reads them back
     * (psim_engine_restart_column) */
    psim_restart_col restart_cols[PSIM_RESTART_COLS + 1];
    void (*restart_save)(const struct psim_sim *e, const void *m, int k, double *by_id);
    /* optional: the model time one step advances (what its velocities are
     * per: a step's dt), for this run, which the engine asks for once the
     * model is made; without it a step is one time unit */
    double (*step_time)(const struct psim_sim *e, const void *m);
    /* optional: what it needs to run over MPI ranks (dist.h): its reach,
     * the skin of its ghosts and the fields they need each step.  A model
     * without it runs in one process only.  Over ranks the store holds
     * ghosts beside the rank's own particles: the model rebuilds what it
     * derives from the store (and sorts) after an exchange, and only then
     * (psim_engine_exchanged); what it sums over particles, it sums over
     * its own (psim_engine_ghost). */
    int (*halo)(const struct psim_sim *e, const void *m, psim_halo *h);
    /* or: over MPI ranks every rank holds every particle, and the model
     * shares out each step's work and keeps the copies equal itself
     * (psim_engine_rank, psim_engine_sendrecv, psim_engine_share,
     * psim_engine_reduce): for a model whose results follow an order over
     * the whole scene.  The engine then runs the steps as one process does
     * on every rank and rank 0 writes the outputs. */
    int shares;
    /* optional, for a model that neither has a halo nor shares: why it
     * runs in one process only, a clause for the refusal over ranks ("its
     * events ...") */
    const char *one_process;
    /* optional: its source's own initial state of n particles from seed,
     * particles lo..hi-1 of it alone (sc then holds hi - lo; over MPI
     * ranks each rank makes its own block of ids) */
    int (*generate)(psim_scene *sc, long n, uint64_t seed, long lo, long hi, psim_error *err);
    /* optional: its GPU path (--device gpu, gpu.h; docs/gpu.md).  With gpu
     * set, its create reads psim_engine_device and, given a device, keeps
     * the state there between steps; sync then brings the store up to date
     * from the device before the engine reads it (outputs, --check,
     * restart files).  A model without one is refused a device, saying
     * why in no_gpu ("has no GPU path" if NULL). */
    int gpu;
    void (*sync)(const struct psim_sim *e, void *m);
    const char *no_gpu;
    void (*destroy)(void *m);
} psim_model;

/* The state by id (allocated; free with psim_snapshot_free). */
int psim_snapshot_take(const struct psim_sim *e, psim_snapshot *s);
void psim_snapshot_free(psim_snapshot *s);
/* The state by id without copying it, for writers: the store's arrays and
 * where each id is in them (4 bytes a particle, allocated; free with
 * psim_state_cols_free).  0, or -1 when out of memory. */
int psim_state_cols_take(const struct psim_sim *e, psim_cols *c);
void psim_state_cols_free(psim_cols *c);

/* Create a simulation of sc with model m (the composing layer's call);
 * with take, sc's particle arrays are freed once the store holds them,
 * before m's create, which reads the particles from the store (in id
 * order until the first sort) and only the rest of the scene from sc. */
struct psim_sim *psim_engine_create(psim_scene *sc, const psim_config *cfg,
                                    const psim_model *m, int take, psim_error *err);
/* Give the simulation a grid of cells no narrower than reach, the one
 * psim_engine_sort sorts by, over bbox = {xmin, ymin, xmax, ymax} or, if
 * NULL, the box.  May be called again to re-plan it.  Returns 0 or -1 (no
 * memory). */
int psim_engine_grid(struct psim_sim *e, double reach, const double *bbox);
/* The same with cells of about `occupancy` particles (0: the default). */
int psim_engine_grid_occ(struct psim_sim *e, double reach, const double *bbox,
                         double occupancy);
/* The same with tiles of tile_cells cells a side (a power of two; 0: about
 * PSIM_TILE_PARTICLES particles), unless the run set --tile: for a model
 * whose results do not depend on the tiles, which may then size them by
 * the thread count. */
int psim_engine_grid_tiles(struct psim_sim *e, double reach, const double *bbox,
                           double occupancy, int tile_cells);
/* Tiles of about `particles` particles (0: PSIM_TILE_PARTICLES) in the
 * grids planned from now on with tile_cells 0, unless the run set --tile. */
void psim_engine_tile_particles(struct psim_sim *e, double particles);
/* Cut the grid's tiles at cell columns cut_x[0..TG] and rows cut_y[0..TG]
 * (psim_grid_cut; NULL: the default cuts) and rank its cells anew: the
 * next sort follows them.  Restart files carry the cuts, so a model whose
 * results follow its tiles may choose them from what its steps did. */
void psim_engine_grid_cut(struct psim_sim *e, const int32_t *cut_x, const int32_t *cut_y);
/* Sort the store by the grid's cells now, timed as the engine's sort
 * phase (without a grid it leaves the order as it is).  In a run from a
 * restart file of a model that follows_order, the first sort starts from
 * the order the file saved. */
void psim_engine_sort(struct psim_sim *e);
/* Whether text "K=V,..." holds options of model m, each once (a restart
 * file's): 0, or -1 with err set. */
int psim_engine_options_check(const psim_model *m, const char *text, psim_error *err);
/* Value of the model's option called name (one of its options[]), or dflt
 * when the run did not set it. */
double psim_engine_option(const struct psim_sim *e, const char *name, double dflt);
/* The restart file's column called name (by id), if sc is a restart file
 * written by this model; else NULL (the model starts afresh). */
const double *psim_engine_restart_column(const struct psim_sim *e, const psim_scene *sc,
                                         const char *name);
/* The restart file's value of the model's measured quantity called name
 * (its stats value when the file was written), likewise: 0 with *v set,
 * or -1. */
int psim_engine_restart_value(const struct psim_sim *e, const psim_scene *sc,
                              const char *name, double *v);
/* Over MPI ranks (dist.h): how many ranks run the simulation (1: one
 * process); whether the store was exchanged since the model last sorted
 * it; how far any particle has moved since the exchange, at most; whether
 * store place k holds a ghost. */
int psim_engine_ranks(const struct psim_sim *e);
int psim_engine_exchanged(const struct psim_sim *e);
double psim_engine_drift(const struct psim_sim *e);
int psim_engine_ghost(const struct psim_sim *e, size_t place);
/* Over ranks, for a model whose halo waits (dist.h): whether the ghosts'
 * fields of this step are still on their way; wait for them (from the
 * main thread, outside parallel regions: MPI calls are funneled),
 * returning the seconds waited (nothing where none are on their way; the
 * engine times them as its comm phase); the store places of the ghosts,
 * *place[0..n), as the last exchange and sort left them. */
int psim_engine_halo_pending(const struct psim_sim *e);
double psim_engine_halo_wait(struct psim_sim *e);
size_t psim_engine_ghosts(const struct psim_sim *e, const uint32_t **place);
/* Over ranks: every particle of the store moved at most `most` in this
 * step (a model that says so each step spares the engine a pass over the
 * store to measure it). */
void psim_engine_moved(struct psim_sim *e, double most);
/* Over ranks, in a step: the two longest paths (p1 >= p2) of this rank's
 * own particles since the exchange, bounds on how far each has moved (a
 * model that tracks them).  Two particles have closed in by at most the
 * sum of the two longest over the ranks, and by at most twice the drift:
 * the next exchange comes when both pass the skin (without paths, when
 * the drift passes half the skin). */
void psim_engine_paths(struct psim_sim *e, double p1, double p2);
/* Over ranks, collective (every rank calls it at the same point of the
 * same step): sum[0..nsum) summed and least[0..nleast) the least over
 * the ranks, in place.  One process: nothing. */
void psim_engine_reduce(struct psim_sim *e, double *sum, int nsum, double *least, int nleast);
/* Over ranks: this rank (0 .. psim_engine_ranks - 1; 0 in one process). */
int psim_engine_rank(const struct psim_sim *e);
/* Over ranks, for a model that shares: sbytes[q] bytes of send, packed
 * in rank order, to each rank q, and rbytes[q] bytes from each rank q
 * into recv (in rank order), sizes both sides know (point to point: a
 * rank that sends nothing to another and expects nothing from it makes
 * no call for it).  Timed as the comm phase; the bytes and messages to
 * other ranks are counted.  Out of memory ends the job. */
void psim_engine_sendrecv(struct psim_sim *e, const void *send, const size_t *sbytes,
                          void *recv, const size_t *rbytes);
/* Over ranks, collective, for a model that shares: each rank's `bytes`
 * bytes of mine to every rank; *all (allocated, the caller frees it)
 * holds every rank's in rank order, each[q] bytes from rank q.  Timed
 * and counted as psim_engine_sendrecv. */
void psim_engine_share(struct psim_sim *e, const void *mine, size_t bytes, void **all,
                       size_t *each);
/* The CUDA device the simulation runs on (gpu.h), or -1: the CPU. */
int psim_engine_device(const struct psim_sim *e);
/* The store brought up to date from the model's device (model.h: sync),
 * where its state lives there; else nothing. */
void psim_engine_sync(const struct psim_sim *e);
/* Index of the counter called name in the stats (-1 if none). */
int psim_engine_counter(const struct psim_sim *e, const char *name);

#endif
