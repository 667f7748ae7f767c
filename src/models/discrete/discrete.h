/* The discrete model (NUS CS3210 AY2024/25), internal header.
 *
 * A step: drift every disk by its velocity; sort the store by cell; then,
 * with positions frozen, find the contacts (pairs at distance <= 2r) once
 * and resolve collisions to a fixpoint over the contacts only.
 *
 * Resolution runs in rounds.  A round runs, for every tile with work, one
 * generation of a first-in first-out worklist over the contacts inside the
 * tile (and the walls, for border tiles): the disks queued when the round
 * began, re-checking only disks whose velocity changed; the disks their
 * resolutions queue wait for the tile's next round (--option gens=K: K
 * generations; 0: the tile's fixpoint).  The tiles share no disk: the
 * threads take them heaviest first, each the next when it is free
 * (--option rounds=0: a task a tile, depend(inout: tile)).  Then, for
 * every pair of adjacent tiles with contacts across their border, an
 * "edge" task, depend(inout: both tiles) (or, when they are few, all of
 * them on one thread in creation order): a fixpoint over those contacts,
 * whose changed disks join their tiles' queues.  Edges that share a tile
 * run in creation order, so every velocity sees the same sequence of
 * updates whatever the thread count: output is identical for 1 or 64
 * threads.  Rounds repeat until one resolves nothing.  A round
 * of one generation keeps the one worklist's order across tile borders
 * closely enough that small tiles cost no more resolutions than one tile
 * (a tile resolved to its fixpoint against stale borders sends waves back
 * from them: up to twice the resolutions, docs/performance.md).  One tile
 * (the course's 10k scenes) on more threads runs its first round as parts:
 * the components of its contact graph split among the threads, each part a
 * worklist that pops every component's disks in the one worklist's order
 * (resolve.c), so again the same bytes. */
#ifndef PSIM_DISCRETE_H
#define PSIM_DISCRETE_H

#include <stddef.h>
#include <stdint.h>

#include "../../engine/engine.h"

/* The model's own phases and logged quantities (psim_stats). */
enum { DPHASE_CONTACTS = PSIM_PHASE_MODEL, DPHASE_RESOLVE, DPHASE_END };
enum { DC_CONTACTS, DC_ROUNDS, DC_MAX_ROUNDS, DC_PAIR_CHECKS, DC_PAIR_RES,
       DC_WALL_RES, DC_TASKS, DC_MAX_STEP_RES, DC_SEARCH_TESTS, DC_REGRIDS,
       DC_CUTS, DC_END };

/* A contact: disks i < j in store order.  Positions are frozen while
 * collisions are resolved, so dp = p_j - p_i is recomputed from them when
 * needed (the same bits every time) instead of being stored: 8 bytes a
 * contact, 4 per adjacency entry. */
typedef struct dcontact {
    int32_t i, j;
} dcontact;

/* Tile-neighbour directions: (dx+1) + 3 (dy+1); 4 is the tile itself. */
#define DIRS 9
#define DIR_OPP(d) (8 - (d))

typedef struct dlist {
    dcontact *c;
    size_t n, cap;
} dlist;

typedef struct __attribute__((aligned(64))) dtile {
    uint32_t p0, p1;            /* particles [p0, p1) */
    dlist in;                   /* contacts inside the tile */
    dlist cross[DIRS];          /* contacts found here that reach tile d */
    uint32_t *adj0;             /* CSR of the inside contacts */
    size_t adj0_cap;
    int32_t *adj;
    size_t adj_cap;
    uint32_t *queue;
    size_t queue_cap;
    uint32_t qhead, qcount;     /* its worklist, left for the next round */
    uint32_t *acts;             /* its disks edge tasks changed this round, */
    size_t acts_cap;            /* in the order they did (resolve.c) */
    uint32_t nact;
    uint64_t checks, pair_res, wall_res;  /* this step */
    uint64_t round_res;                   /* this round, tile task */
    uint8_t scheduled;          /* a tile task runs this round */
    uint8_t changed_border;     /* tile task changed a disk with contacts
                                 * across tiles this round */
    uint8_t changed_cross_prev; /* edge tasks changed it last round */
    uint8_t changed_cross_cur;  /* edge tasks changed it this round */
    uint8_t oom;
    uint8_t diverged;           /* a task ran past its resolution budget */
    double busy;                /* seconds its search, worklists and edges
                                 * took this step (over ranks: shares) */
} dtile;

/* Disks a tile, about (the grid's own default is 16384): the course's 10k
 * scenes in four tiles, its 100k scenes in 36.  The tiles are part of the
 * resolution order, so they follow the scene, never the thread count. */
#define DISCRETE_TILE_PARTICLES 4096.0

/* A chunk of a tile's cells for the contact search: chunks are searched in
 * parallel, then each tile joins its chunks' lists in chunk order, which
 * gives the same lists as one search of the whole tile. */
#define CHUNK_CELLS 1024

typedef struct __attribute__((aligned(64))) dchunk {
    uint32_t tile, c0, c1;      /* cells [c0, c1) of tile */
    dlist in;
    dlist cross[DIRS];
    double d2min;               /* nearest pair seen (squared distance) */
    uint64_t tests;             /* distance tests made (pairs of disks looked at) */
    uint8_t oom;
} dchunk;

typedef struct dedge {
    uint32_t a, b;  /* tiles: b is a's neighbour in direction dir */
    int dir;
} dedge;

/* The edges come in EDGE_LEVELS levels, contiguous in creation order (a
 * direction and a parity each): the edges of a level share no tile, and
 * every edge of a tile runs after those of the levels before. */
#define EDGE_LEVELS 8

/* Over MPI ranks (ranks.c): an edge whose tiles two ranks own, as this
 * rank sees it: the edge, the other rank, whether this rank owns its
 * tile a; the disks of this rank's tile in its contacts (mine, from
 * m->xdisk + m0) and of the other's (n1 from m->xdisk + m1). */
typedef struct dxedge {
    uint32_t k;
    int q, mine_a, lv;
    uint32_t m0, n0, m1, n1;
} dxedge;

/* The model's skips (psim_stats.skipped), in the order of .skips. */
enum { DS_SEARCH, DS_WALLS, DS_MOVE, DS_GRAPH };

/* What a drift saw: the extent of the positions after it (every step) and
 * of the velocities it used (when measured). */
typedef struct dextent {
    double pmin[2], pmax[2];
    double vmin[2], vmax[2];
    int nonfinite;              /* a velocity was NaN or infinite, or the
                                 * drift did not look at them */
} dextent;

/* Free flight: what the drift saw and what the last search left. */
typedef struct dflight {
    int enabled;                /* --option skip (default 1) */
    dextent ext;                /* this step's drift */
    int quiet;                  /* the last step changed no velocity */
    int measured;               /* this step's drift measured the velocities */
    int drifted;                /* ext holds the positions' extent (a drift ran) */
    double gap;                 /* every pair is more than 2r + gap apart
                                 * after the last drift (< 0: unknown) */
    int walls;                  /* a disk may reach a wall this step */
    int resting;                /* every velocity is 0 for good */
} dflight;

typedef struct dmodel {
    uint32_t ntiles;
    dtile *tiles;
    uint32_t nchunks;
    dchunk *chunks;
    uint32_t *tile_chunk0;  /* ntiles + 1: first chunk of each tile */
    dedge *edges;       /* in task-creation order */
    size_t nedges;
    uint64_t *edge_res; /* per edge, this round */
    uint8_t *active;    /* per particle: changed by an edge task */
    uint8_t *border;    /* per particle, while resolving: has contacts
                         * across tiles (resolve.c) */
    uint8_t *flag;      /* per particle: worklist state (resolve.c) */
    uint8_t *nearwall;  /* per particle, this step: within r of a wall (resolve.c) */
    char *dep;          /* one dependence object per tile */
    double four_r2;
    uint64_t step_contacts;  /* contacts found this step */
    uint64_t step_tests;     /* distance tests of this step's search */
    uint64_t budget;         /* resolutions a step may take (settle x n) */
    uint32_t gens;           /* generations a tile's round takes (0: all) */
    double d2min;            /* nearest pair the last search saw, squared */
    dflight fl;              /* what the scene can use this step (flight.c) */
    int simd;                /* contact search with AVX-512 (contacts.c;
                              * --option simd, default 1 where the CPU has it) */
    int regrid;              /* the grid follows the disks (regrid.c; --option
                              * regrid, default 1) */
    int balance;             /* tiles cut where the work is (balance.c;
                              * --option balance, default 1) */
    uint32_t *work;          /* per disk, on a step that counts: its work */
    uint32_t *counting;      /* work, on such a step; else NULL */
    /* one tile's resolution in parts, one a thread (resolve.c) */
    uint32_t *part_seen;     /* per disk: the stamp of the walk that met it */
    uint32_t part_stamp;
    uint8_t *part_of;        /* each disk's part */
    double *part_v;          /* the velocities before, for a rerun */
    uint32_t *part_queue;    /* a worklist's room a part */
    uint32_t parts_cap;      /* disks they have room for */
    int parts_n;             /* parts they have room for */
    /* a round's tiles taken by whichever thread is free (resolve.c) */
    int take;                /* --option rounds (default 1); 0: a task a tile */
    uint64_t *order;         /* per tile: the round's tiles, heaviest first
                              * (keys: the tile in the low 32 bits) */
    uint32_t norder;
    uint32_t next;           /* the next of them to take */
    size_t level0[EDGE_LEVELS + 1];   /* each level's first edge */
    /* over MPI ranks (ranks.c): every rank holds every disk, and each
     * resolves the tiles it owns this step */
    int ranks, rank;
    int *owner;              /* per tile: its rank this step */
    double *tflags;          /* per tile and a round's end: XF_* from its rank */
    double *tcost;           /* per tile: its work in the last step (the
                              * seconds its rank spent on it; all 0: not
                              * known, its disks stand for it) */
    size_t nown;             /* the rank's disks this step (its tiles') */
    dxedge *xe;              /* the edges across this rank's side, in order */
    size_t nxe, xe_cap;
    uint32_t *xpick;         /* a level's edges across ranks that run */
    size_t xpick_cap;
    uint32_t *xdisk;         /* their disks (dxedge) */
    size_t nxdisk, xdisk_cap;
    uint32_t *xstamp;        /* per disk: the edge that last listed it */
    uint32_t xnow;           /* (the latest stamp) */
    size_t xn;               /* disks xstamp holds */
    double *v0;              /* the rank's disks' velocities at the step's
                              * start (x, y), to send only those that changed */
    size_t v0_cap;
    void *sbuf, *rbuf;       /* messages, kept (grow only) */
    size_t sbuf_cap, rbuf_cap;
    size_t *sbytes;          /* 2 x ranks: bytes to and from each rank */
} dmodel;

/* Whether this rank owns tile t (always in one process). */
static inline int discrete_mine(const dmodel *m, uint32_t t)
{
    return m->ranks < 2 || m->owner[t] == m->rank;
}

/* Most parts of one tile's resolution (resolve.c). */
#define PARTS_MAX 255
void discrete_parts_free(dmodel *m);

/* A step's collisions must settle within this many resolutions (pair and
 * wall) per disk, on average over the scene (--option settle=K).  The
 * course's dense scenes need at most about 60 (docs/stability.md).  Past
 * it the fixpoint is taken not to converge and the run stops with an error
 * naming the disks that still approach, instead of hanging: the budget
 * grows with the disks, not with their contacts, so 2000 disks piled on
 * one point give up in a fraction of a second. */
#define SETTLE_DEFAULT 1000

/* The disks of the contacts that still approach when a step gives up:
 * how many, their bounding box and their lowest id. */
typedef struct dgroup {
    uint64_t disks;
    double x0, y0, x1, y1;
    int32_t first_id;
} dgroup;

void discrete_find_contacts(psim_sim *e, dmodel *m);
/* balance.c: every BAL_EVERY steps, tiles cut anew where that step's work
 * was, when the heaviest tile holds more than BAL_SHARE of it and the cut
 * brings it down to BAL_GAIN of what it was or less. */
#define BAL_EVERY 8
#define BAL_GAIN 0.9
#define BAL_SHARE 0.125
/* Whether this step counts its work (m->work) for a decision. */
int discrete_balance_counts(const psim_sim *e, const dmodel *m);
/* After the step's resolution: 1 when the tiles were cut anew (make the
 * tile state anew; the next sort follows them), 0 when not, -1 when out
 * of memory. */
int discrete_balance(psim_sim *e, dmodel *m);
/* regrid.c: the grid over the region the disks occupy (at the start), and
 * again when they leave it or gather far inside it.  discrete_regrid runs
 * after the sort: 1 when it planned the grid again (sort again, and size
 * the tiles anew), 0 when not, -1 when out of memory. */
int discrete_plan_grid(psim_sim *e, dmodel *m);
int discrete_regrid(psim_sim *e, dmodel *m);
/* flight.c: the drift with its extents, and the step's choice. */
void discrete_drift(psim_sim *e, dmodel *m);
/* Returns 1 when no pair can be in contact after this drift (the search
 * is left out), 0 when the search must run. */
int discrete_free_flight(psim_sim *e, dmodel *m);
/* After a search with no contact: the gap it leaves. */
void discrete_flight_searched(const psim_sim *e, dmodel *m);
/* Wall resolutions alone, when no pair is in contact. */
void discrete_walls_only(psim_sim *e, dmodel *m);
/* A step resolved `total` collisions: the largest step, and whether it
 * changed no velocity. */
void discrete_step_resolved(psim_sim *e, dmodel *m, uint64_t total);
void discrete_unsettled(psim_sim *e, dmodel *m, dgroup *g);
/* Returns 0, or -1 when collisions did not settle (m->budget), or -2
 * (over ranks) when a rank had no memory for its contacts. */
int discrete_resolve(psim_sim *e, dmodel *m);
int discrete_check(psim_sim *e, void *m, const psim_snapshot *before,
                   const psim_snapshot *after, psim_error *err);

/* ranks.c: the model over MPI ranks.  Each rank holds every disk; the
 * tiles go to the ranks in runs of rows, split by their work; a rank
 * searches and resolves its own tiles, and runs every edge that touches
 * one of them, an edge across two ranks on both, each with the other's
 * disks' velocities received just before the edge's level. */
int discrete_ranks_init(const psim_sim *e, dmodel *m);
void discrete_ranks_free(dmodel *m);
/* After the sort: each tile's rank (tiles' p0, p1 set). */
void discrete_ranks_own(const psim_sim *e, dmodel *m);
/* After the search of the rank's own tiles and the first round's tiles
 * (which need nothing from other ranks): the search's counts summed and
 * its nearest pair over the ranks (m->step_contacts, step_tests, d2min),
 * and the contacts of the edges across two ranks sent to both.  0, or -1
 * when out of memory (on any rank: every rank says so). */
int discrete_ranks_contacts(psim_sim *e, dmodel *m);
/* One round's edges at level lv: the other ranks' disks of this level's
 * edges across ranks received, then the edges that touch this rank's
 * tiles run; returns how many of them this rank counts. */
uint64_t discrete_ranks_level(psim_sim *e, dmodel *m, int lv, int first);
/* After a round's tiles: the other ranks' tiles' flags, as the last
 * round's end left them (whether a tile runs, whether edges changed it). */
void discrete_ranks_flags(dmodel *m, int first);
/* At a round's end (after round_total): the round's resolutions, a
 * divergence and a stop summed over the ranks, with each tile's flags for
 * the next round from its rank; returns the resolutions, *diverged set. */
uint64_t discrete_ranks_round_end(psim_sim *e, dmodel *m, uint64_t res, int *diverged);
/* Before the resolution: the rank's disks' velocities kept.  After it:
 * every rank's disks that changed (and its disks in edges across ranks,
 * which other ranks ran too) to every rank. */
void discrete_ranks_keep(psim_sim *e, dmodel *m);
void discrete_ranks_sync(psim_sim *e, dmodel *m);
/* The work counted on every rank, summed (balance.c). */
void discrete_ranks_work(psim_sim *e, dmodel *m);
/* The disks still approaching (discrete_unsettled), over the ranks:
 * marks (m->flag) put together on every rank. */
void discrete_ranks_marks(psim_sim *e, dmodel *m);
/* Run edge k (resolve.c). */
void discrete_edge(const psim_sim *e, dmodel *m, size_t k, int first);
int discrete_edge_runs(const dmodel *m, size_t k, int first);

#endif
