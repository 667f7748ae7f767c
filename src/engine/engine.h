/* The engine: one simulation.  It owns the store, the grid and the sorter,
 * runs the phases of a step and times each of them; the model does the
 * physics (src/models/). */
#ifndef PSIM_ENGINE_ENGINE_H
#define PSIM_ENGINE_ENGINE_H

#include "../io/scene.h"
#include "../io/xyz.h"
#include "grid.h"
#include "sort.h"
#include "store.h"
#include "timer.h"
#include "model.h"
#include "poll.h"
#include "team.h"

struct psim_sim {
    psim_config cfg;
    int device;             /* CUDA device (gpu.h), or -1: the CPU */
    int threads;            /* this step's team (team.h); else --threads */
    psim_team team;
    int team_skip;          /* its "left out" counter in stats (-1: none) */
    long n;
    double L, r;
    long step;              /* steps done */
    double step_time;       /* model time a step advances (model.h) */
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
    /* restart files (restart.c): */
    long step0;             /* steps done before this run (a restart's) */
    psim_scene_format format;
    int print;              /* the scene's, written into restart files */
    int grid_asked, grid_ask_bbox;
    double grid_ask[7];     /* the last grid the model asked for: reach,
                             * occupancy, tile cells, bbox */
    double tile_particles;   /* the model's tiles, particles a tile (0: the
                              * default; psim_engine_grid_tiles) */
    int ncuts_saved;         /* a restart's tile cuts, given with its plan */
    int32_t cuts_saved[PSIM_RESTART_CUTS];
    int grid_saved, grid_saved_bbox;
    double grid_saved_ask[7]; /* a restart's, given at the model's first ask */
    int32_t *restart_order; /* a restart's store order, from the first sort */
    psim_poll_state poll;   /* progress and stopping inside a step (poll.c) */
    /* over MPI ranks (dist.h): n counts this rank's particles, its ghosts
     * included; n_all every rank's (without ranks, n) */
    struct psim_dist *dist;
    long n_all;
    /* NULL, or (a part written by BY_PARTS) the part of the outputs its
     * state is: its ids are part->id0 .. part->id0 + n - 1 */
    const psim_part *part;
};

/* restart.c: what a restart file carries into the engine at its creation
 * (the steps done, the grid plan, the store order; the model's options
 * are parsed by the caller), its model's columns held to their kinds and
 * ranges.  0, or -1 with err set. */
int psim_engine_restart_init(struct psim_sim *e, psim_scene *sc, psim_error *err);
/* The store into the restart's order (before the first sort). */
void psim_engine_restart_order(struct psim_sim *e);

/* The grid the model asked for last, planned again (over ranks, after
 * the domains were cut again).  0, or -1 (no memory). */
int psim_engine_regrid(struct psim_sim *e);

/* The store place of the least id whose x, y, vx or vy is not finite,
 * leaving out the places k where skip[k] is set (skip NULL: none), or
 * the store's n if none; and the message naming it (engine.c). */
size_t psim_engine_not_finite(const struct psim_sim *e, const uint8_t *skip);
void psim_engine_not_finite_error(const struct psim_sim *e, size_t place, psim_error *err);

/* limits.c: the scene against the model's limits (model.h): 0, or -1
 * with err naming the line of L, r or the disk and what is too large. */
int psim_engine_limits(const struct psim_sim *e, const psim_scene *sc, psim_error *err);

/* Phase p as a LIKWID marker region (timer.h) named as the model named the
 * phase: in every thread of the team, or in the calling thread only. */
#define PSIM_REGION_BEGIN(e, p) psim_region_begin((e)->threads, (e)->stats.phase_name[(p)])
#define PSIM_REGION_END(e, p) psim_region_end((e)->threads, (e)->stats.phase_name[(p)])
#define PSIM_REGION_THREAD_BEGIN(e, p) psim_region_thread_begin((e)->stats.phase_name[(p)])
#define PSIM_REGION_THREAD_END(e, p) psim_region_thread_end((e)->stats.phase_name[(p)])

/* Time fn(e, m) into phase p, inside its region (the region's own cost
 * outside the time). */
#define PSIM_TIMED(e, p, call)                                            \
    do {                                                                  \
        PSIM_REGION_BEGIN(e, p);                                          \
        double t0_ = psim_now();                                          \
        call;                                                             \
        (e)->stats.phase_s[(p)] += psim_now() - t0_;                      \
        PSIM_REGION_END(e, p);                                            \
    } while (0)

/* Over ranks: the state written by parts (dist_write.c), each part a
 * simulation v_ of a few of the ids in order (its `part` says which, and
 * whether it writes the file's header or footer) that `call` writes to f_
 * as one process would; every rank returns the same, -1 with errno set if
 * a write failed on any of them.  For a model that shares (model.h) rank
 * 0 writes the whole state, as one process. */
#define BY_PARTS(e, f, call)                                                  \
    do {                                                                      \
        if ((e)->dist && psim_dist_shares(e)) { /* rank 0 holds it all */     \
            psim_sim sv_ = *(e);                                              \
            sv_.dist = NULL;                                                  \
            psim_sim *v_ = &sv_;                                              \
            FILE *f_ = (f);                                                   \
            int rc_ = psim_dist_rank() == 0 ? (call) : 0;                     \
            (e)->stats = sv_.stats;                                           \
            return psim_dist_said(rc_);                                       \
        }                                                                     \
        if ((e)->dist) {                                                      \
            struct psim_dist_parts *w_ = psim_dist_parts_begin(e, f);         \
            psim_sim *v_;                                                     \
            FILE *f_;                                                         \
            while ((v_ = psim_dist_parts_next(w_, &f_)) != NULL)              \
                psim_dist_parts_done(w_, call);                               \
            return psim_dist_parts_end(w_);                                   \
        }                                                                     \
    } while (0)

#endif
