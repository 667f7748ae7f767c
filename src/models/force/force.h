/* The force model (Berkeley CS267 HW2), internal header.
 *
 * A step, as the course's starter code: the force on every particle from
 * the positions at the start of the step (law.h), then every particle
 * moves.  psim's fast path finds the pairs within the cutoff through
 * Verlet pair lists (cutoff + skin, each pair once, filed in shells by
 * distance) built from the engine's Morton sort, rebuilt (with the sort)
 * only when the particles may have moved half the skin since the last
 * build; each particle's forces are summed in the order of the course's
 * naive loop (step.c), so the results are bit for bit those of the naive
 * code, for any thread count.  Phases:
 *   nlist      the lists (only at rebuilds; the sort is the engine's);
 *   force      pair tests and forces, as records, a task per tile;
 *   integrate  records handed across tiles, sums, the move in place;
 *   copy       (--device gpu, gpu.h) the state copied to and from the
 *              device.
 * --option naive=1 runs the course's O(n^2) loops instead (for tests). */
#ifndef PSIM_FORCE_H
#define PSIM_FORCE_H
#include <float.h>
#include <stddef.h>
#include <stdint.h>

#include "../../engine/cpu.h"
#include "../../engine/engine.h"
#include "../../engine/nearest.h"
#include "gpu.h"
#include "law.h"

enum { FPHASE_NLIST = PSIM_PHASE_MODEL, FPHASE_FORCE, FPHASE_INTEGRATE, FPHASE_COPY,
       FPHASE_END };
enum { FC_PAIR_TESTS, FC_INTERACTIONS, FC_REBUILDS, FC_LIST_ENTRIES, FC_TASKS, FC_SORTED,
       FC_END };
/* Stages left out where the scene cannot use them (force.c, step.c). */
enum { FS_MOVE, FS_WALLS, FS_GRAPH, FS_LISTS };
/* How a step's two rounds (every tile's forces, then every tile's sums
 * and moves) run on more than one thread (--option rounds=K): a task a
 * tile, or a loop over the tiles shared by the threads, statically or
 * dynamically.  The same results for all three. */
enum { FORCE_ROUNDS_TASKS, FORCE_ROUNDS_STATIC, FORCE_ROUNDS_DYNAMIC };
#define FORCE_STATIC_THREADS 8   /* the default: static from this many threads */

/* The course's constants (common.h). */
#define CS267_DENSITY 0.0005
#define CS267_MASS 0.01
#define CS267_CUTOFF 0.01
#define CS267_DT 0.0005
#define CS267_STEPS 1000
#define CS267_SAVEFREQ 10

/* Pair lists are split by the pairs' distance at the build into
 * FORCE_BUCKETS shells of width skin / FORCE_BUCKETS beyond the cutoff
 * (the first shell holds the pairs within the cutoff too): a shell whose
 * pairs were farther apart than cutoff + 2 drift cannot hold a pair within
 * the cutoff yet, so a step tests only the shells that the particles may
 * have crossed since the build (half the list on average, not all of it). */
#define FORCE_BUCKETS 4

/* Most list entries a tile may hold: FORCE_LIST_BUDGET per particle, plus
 * a little.  The course's scenes have about 2.6 and a dense scene of disks
 * about 16; particles crowded into one place have n^2 / 2 (1e4 of them took
 * 7.6 GB before the lists were bounded), and are refused with a pointer to
 * --option naive=1, whose memory does not grow with the pairs. */
#define FORCE_LIST_BUDGET 64
#define FORCE_LIST_SLACK 65536

/* A pair of store places: each unordered pair once (half lists). */
typedef struct fpair {
    uint32_t i, j;
} fpair;

/* The force of one interacting pair on one of its particles (the owner,
 * a store place); partner: the other's store place (read as its id, the
 * order of the sums, only where a particle has three or more forces: the
 * ids are not in the cache). */
typedef struct frec {
    uint32_t owner;
    uint32_t partner;
    double fx, fy;
} frec;

/* A fast particle of a tile (fmodel.v2fast): its store place, its path
 * since the build (a bound on its displacement) and its position after
 * this step's move. */
typedef struct ffast {
    uint32_t q;
    double d, x, y;
} ffast;

/* A tile: its particles are store places first .. first + n - 1, its
 * pairs those found from its cells (the other particle may belong to a
 * neighbouring tile). */
typedef struct ftile {
    uint32_t first, n;
    int32_t src[5];         /* the tiles whose lists reach this one's
                             * particles: W, E, S, SW, SE (-1: none) */
    int32_t fwd[5];         /* the tiles its lists reach: W, E, NW, N, NE */
    double drift;           /* the sum over the steps since the build of
                             * its largest speed times dt */
    int shells;             /* this step: the shells to test */
    fpair *pair[FORCE_BUCKETS];
    size_t len[FORCE_BUCKETS], cap[FORCE_BUCKETS];
    double *rx, *ry;        /* slot rows of the window rows being listed */
    uint32_t *rj;           /* their places */
    size_t rcap_slots;
    uint64_t *stage_pair;   /* a row's pairs before they are filed (nlist.c) */
    double *stage_d2;
    size_t stage_cap;
    uint32_t *win;          /* the tile's cells and a border: first, end */
    uint8_t *fx;            /* window cells whose forward half has extras,
                             * then whose cell has */
    size_t fxcap;
    size_t wcap;
    int wx0, wy0, W;        /* the window's first cell and side */
    uint32_t *hit;          /* this step: pairs within the cutoff */
    size_t hcap;
    frec *rec;              /* forces on this tile's particles */
    size_t nrec, rcap;
    frec *out;              /* forces on other tiles' particles */
    size_t nout, ocap;
    frec *slow;             /* forces on particles with 3 or more */
    size_t scap;
    /* this step: */
    double v2max;           /* largest squared speed after the move */
    double u0, u1, w0, w1;  /* extent of the velocities the drift used */
    int bounced;            /* a particle was reflected off a wall */
    uint64_t tests, hits, sorted;
    double dmin, dsum;      /* --force-stats: nearest distance / cutoff, sum */
    uint64_t dn;
    double tf, ti;          /* this step: seconds in its force, its integrate */
    ffast *fast;            /* its fast particles since the build */
    size_t nfast, fastcap;
    int lost;               /* a particle left the box for good */
    int oom;
    int crowded;            /* the build passed FORCE_LIST_BUDGET */
    /* over ranks, since the build: */
    uint8_t inner;          /* neither it nor a tile its lists reach holds
                             * a ghost: its forces read no ghost */
    uint8_t early;          /* it and its sources are inner: its sums and
                             * moves need no ghost, and no force that
                             * does reads its positions */
    uint8_t lead;           /* early, or a source of an early tile: the
                             * one-thread sweep's forces before the wait */
} ftile;

/* The accelerations of the tile being summed and moved, and how many
 * forces each particle has: a set for each tile task that may run at
 * once (min(threads, tiles)), taken from a pool by the task and given
 * back, a thread taking the set it used last when it is free, so that its
 * set stays in the core's cache tile after tile (one set per tile, 20 MB
 * at 1e6 particles, came from memory); zero between uses. */
typedef struct facc {
    double *ax, *ay;
    uint32_t *cnt;
    size_t cap;
} facc;

typedef struct fpool {
    facc *set;
    int n;
    uint8_t *busy;          /* n: in use by a task */
    int *last;              /* per thread: the set it used last (-1: none) */
    int threads;
} fpool;

typedef struct fmodel {
    const psim_sim *sim;    /* the simulation, for polls (poll.h) */
    flaw law;
    int naive, stats, skip;
    int simd;               /* list builds, pair tests and moves with AVX-512 */
    int rounds;             /* a step's rounds with threads: FORCE_ROUNDS_* */
    double skin;            /* list radius = cutoff + skin */
    double room;            /* every unlisted pair was more than cutoff +
                             * room apart at the build (room >= skin) */
    psim_backoff measure;   /* builds before the next measurement */
    double drift;           /* bound on half of any pair's relative
                             * displacement since the build */
    int quiet;              /* steps in a row with no force, speed or wall */
    long since_build;       /* steps since the build */
    double closing;         /* how far any two particles may have closed
                             * in since the build: 2 drift bounds, twice
                             * the largest tile drift, or from the fast
                             * particles' paths, the least (step.c) */
    double v2fast;          /* a particle faster than this is "fast": its
                             * path is summed (ffast.d); every other
                             * has moved at most `slow` since the build */
    double slow;
    double *fs_v2;          /* a sample of squared speeds (nlist.c) */
    size_t fs_cap;
    uint8_t *is_fast;       /* n: a fast particle since the build */
    long nis_fast;
    ffast *fp;              /* this step's fast particles (step.c) */
    int32_t *fp_next;       /* the next in the same cell (-1: none) */
    size_t fp_cap;
    uint64_t *fh_key;       /* a hash of their cells: key, first particle */
    int32_t *fh_head;
    size_t fh_cap;          /* their room */
    int fh_shift;           /* this step's table: 2^(64 - fh_shift) entries */
    int built;
    ftile *tiles;
    uint32_t ntiles, cap_tiles;
    uint32_t *sweep;        /* the tiles row by row of the tile grid */
    uint32_t nlead;         /* over ranks, since the build: tiles that lead */
    int sweep_row;          /* tiles a row */
    fpool *acc;             /* the tasks' sets of accelerations */
    /* --force-stats (the older edition's), over the steps so far */
    double absmin, absavg;
    long nabsavg;
    long lost_step;         /* first step a particle left the box (0: none) */
    fgpu *gpu;              /* --device gpu: the state on the device (gpu.h) */
    psim_stats *gpu_stats;  /* where its copies are timed */
} fmodel;

/* A bound on half of how far any two particles have moved relative to
 * each other since the lists were built: the sum over the steps of the
 * largest speed times dt (or, in a step without wall reflections, the
 * half-diagonal of the velocities' extent if smaller: particles moving as
 * one do not close in), plus a few ulps of the box a step (the rounding
 * of the positions), plus one step's. */
static inline double force_drift_bound(const fmodel *m)
{
    return m->drift + (double)(m->since_build + 1) * 8 * DBL_EPSILON * m->law.size;
}

/* Sparse lists (fewer than one entry per FORCE_SPARSE particles) may have
 * room beyond the skin: nlist.c then measures the nearest unlisted pair. */
#define FORCE_SPARSE 8

/* nlist.c: 0, -1 out of memory, -2 past the budget (crowded) */
int force_build_lists(psim_sim *e, fmodel *m);
/* step.c: forces and move of every particle; -1 if one left the box, -2
 * when out of memory */
int force_step_lists(psim_sim *e, fmodel *m);
int force_step_naive(psim_sim *e, fmodel *m);
int force_plan_naive(fmodel *m, long n);

#endif
