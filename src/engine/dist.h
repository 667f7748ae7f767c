/* The distributed engine: one simulation over MPI ranks (docs/scale-out.md).
 *
 * Each rank owns the particles whose centres lie in its domain, one box
 * of a 2D grid of ranks cut where the particles are (dist_cut.c), and
 * keeps ghost copies of the particles of other domains within its halo:
 * the model's reach plus a skin (psim_model.halo).  Owned particles and
 * ghosts share the rank's store, sorted and tiled as in one process; a
 * ghost carries its global id, so a model whose sums follow the ids (the
 * force model) adds every owned particle's forces in the order one
 * process does.
 *
 * The exchange: particles that left their domain migrate to their owner
 * (any rank, however far they went) and the ghosts are chosen anew, only
 * when some particle has moved more than half the skin since the last
 * exchange (one allreduce a step decides it for every rank); in between,
 * the ghosts' fields (psim_halo.fields) are sent from their owners every
 * step, by non-blocking sends and receives started before the step and
 * waited for by the model where it needs them (psim_halo.waits), else by
 * the engine before the step.  The model rebuilds what it derives from the store (lists, its
 * sort) after an exchange, and only then (psim_engine_exchanged).
 *
 * Outputs: every rank writes its parts of each file in parallel, at
 * their offsets (dist_write.c), through the same writers as one process,
 * so the bytes are the same for any rank and thread count; no rank holds
 * the whole state.
 *
 * MPI is started only when a launcher started psim (psim_dist_start): a
 * run without one makes no MPI call. */
#ifndef PSIM_ENGINE_DIST_H
#define PSIM_ENGINE_DIST_H
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "psim/psim.h"
#include "../io/restart_schema.h"

struct psim_sim;

/* What a model needs from the exchange (psim_model.halo): the distance
 * within which particles act on each other, the skin the ghosts reach
 * beyond it (an exchange every time some particle has moved half of it),
 * and the fields of a ghost sent every step.  waits: the model calls
 * psim_engine_halo_wait (model.h) in its step before it reads a ghost's
 * fields, and may work on its other particles while they travel; else
 * the engine waits for them before the step. */
enum { PSIM_FIELD_X = 1, PSIM_FIELD_Y = 2, PSIM_FIELD_VX = 4, PSIM_FIELD_VY = 8 };
typedef struct psim_halo {
    double reach, skin;
    unsigned fields;
    int waits;
} psim_halo;

/* Per-rank figures of a run over ranks, for the summary and --stats. */
typedef struct psim_rank_stats {
    double phase_s[PSIM_PHASES_MAX];
    double comm_s;             /* exchanges, ghost updates and the step's allreduce */
    double exchange_s, update_s;   /* of which the exchanges, the ghosts' updates
                                    * (sending them and waiting for them) */
    double wait_s;             /* and the step's allreduce: waiting for the slowest rank */
    long owned, ghosts;        /* at the end of the run */
    uint64_t bytes_sent, messages_sent;
    uint64_t exchanges, recuts;
} psim_rank_stats;

/* Start MPI when a launcher started psim (Open MPI's, PMIx's, PMI's or
 * Slurm's variables); without one, nothing.  The number of ranks (1
 * without a launcher), or -1 with err set (a launcher's ranks > 1 in a
 * build without MPI). */
int psim_dist_start(int *argc, char ***argv, psim_error *err);
/* End MPI if it was started. */
void psim_dist_finish(void);
int psim_dist_rank(void);
int psim_dist_ranks(void);
/* Collective: the lowest rank whose `failed` is set, or -1 if none. */
int psim_dist_agree(int failed);
/* Collective: the largest of every rank's v. */
double psim_dist_max(double v);
/* Collective: the sum of every rank's v, added in an order of MPI's. */
double psim_dist_sum(double v);
/* End every rank of the job now (a failure past which ranks cannot agree). */
_Noreturn void psim_dist_abort(int code);
/* End every rank of the job after this rank said it has no memory for `what`. */
_Noreturn void psim_dist_out_of_memory(const char *what);

/* Collective: the scene file path read in parts, each rank its own
 * byte range of the particle lines (dist_read.c): sc becomes this rank's
 * part of it (scene.h), which psim_dist_attach sends to the particles'
 * owners.  A restart file with a model's own columns or a 2019 scene is
 * read whole by every rank.
 * 0, or -1 with err set on the rank that says why (emptied elsewhere). */
int psim_dist_scene_read(const char *path, psim_restart_schema_fn schema, psim_scene *sc,
                         psim_error *err);

/* Collective, for a model that shares (model.h): every rank's part of
 * the scene gathered, so that sc is the whole scene on every rank (of a
 * restart file, its particles' order too).  0 (out of memory ends the job). */
int psim_dist_scene_whole(psim_scene *sc, psim_error *err);
/* Whether the run over ranks is of a model that shares. */
int psim_dist_shares(const struct psim_sim *e);
/* Collective: rank 0's rc (0, or -1 with errno set) on every rank. */
int psim_dist_said(int rc);

/* Engine side (engine.c). */
/* Set up the run over ranks: the domains cut where sc's particles are,
 * and this rank's own particles kept: of a whole scene those in its
 * domain, of a part (scene.h) those every rank's part sends it.  take:
 * sc's particle arrays may be freed once copied.  0, or -1 with err set
 * (a model that cannot run over ranks). */
int psim_dist_attach(struct psim_sim *e, psim_scene *sc, int take, psim_error *err);
void psim_dist_detach(struct psim_sim *e);
/* Once the model is made: its halo, held to the domains' size.  0, or -1
 * with err set (more ranks than the box can be cut into). */
int psim_dist_ready(struct psim_sim *e, psim_error *err);
/* Before a step: the exchange when it is due, else the ghosts' fields
 * (sent, and received unless the model waits for them itself). */
int psim_dist_prestep(struct psim_sim *e, psim_error *err);
/* After a step (rc: interact's): the ranks agree on failure and stop and
 * measure the drift since the exchange.  0, or -1 with err set (its
 * message empty on ranks that did not fail themselves). */
int psim_dist_poststep(struct psim_sim *e, int rc, psim_error *err);
/* The rank's domain and halo, {xmin, ymin, xmax, ymax} inside the box,
 * for its grid: 0, or -1 before the model's halo is known. */
int psim_dist_bbox(const struct psim_sim *e, double *bb);
/* Collective: whether every rank's own particles are finite (0), or -1
 * with err naming the least id that is not (on its owner; empty on the
 * other ranks). */
int psim_dist_finite(const struct psim_sim *e, psim_error *err);
/* After the model sorted the store: the ghosts' and the sent particles'
 * places found again. */
void psim_dist_sorted(struct psim_sim *e);
/* Writing the state by parts (dist_write.c, through BY_PARTS in
 * engine.h), collective: begin for output f (rank 0's stream; any on
 * the other ranks), then while next gives a part (a simulation of a few
 * ids in order, and the stream its text goes to), done with its writer's
 * result; end: 0, or -1 on every rank with errno set when a write failed
 * on any.  Out of memory, or a particle on no rank or on two, ends the
 * job (psim_dist_abort). */
struct psim_dist_parts;
struct psim_dist_parts *psim_dist_parts_begin(struct psim_sim *e, FILE *f);
struct psim_sim *psim_dist_parts_next(struct psim_dist_parts *w, FILE **mem);
void psim_dist_parts_done(struct psim_dist_parts *w, int rc);
int psim_dist_parts_end(struct psim_dist_parts *w);
/* Collective the first time: whether every rank runs on rank 0's
 * machine (then they can open rank 0's unnamed files, through /proc). */
int psim_dist_one_node(void);
/* Collective: an output every rank writes its parts of at their offsets.
 * path: on rank 0, a name of the regular file that holds the bytes of its
 * stream f, which every rank opens (its temporary file in a folder every
 * rank sees, or where every rank runs on one machine, its unnamed file as
 * /proc/PID/fd/N), or NULL for an output rank 0 writes alone, the other
 * ranks' parts sent to it (standard output, a pipe, a device); NULL on
 * the other ranks.  Each rank's f (a stream the writes are given there,
 * never written) stands for the output in the writes.  0, or -1 on every
 * rank with errno set (the file could not be opened). */
int psim_dist_output_open(FILE *f, const char *path);
/* Collective: the output of f closed on every rank (before rank 0 puts
 * the file in place or removes it); nothing for an output never opened
 * so.  0, or -1 on every rank with errno set. */
int psim_dist_output_close(FILE *f);
/* Collective: every output still open so, closed: 0, or -1 on every
 * rank with errno set. */
int psim_dist_outputs_close(void);
/* Collective: counters and phase times of every rank into rank 0's stats
 * (counters summed, times the largest), and each rank's own figures into
 * per (rank 0, psim_dist_ranks() entries; NULL elsewhere). */
void psim_dist_reduce_stats(struct psim_sim *e, psim_rank_stats *per);

#endif
