/* The force model (Berkeley CS267 HW2), internal header.
 *
 * A step, as the course's starter code: the force on every particle from
 * the positions at the start of the step (law.h), then every particle
 * moves.  psim's fast path finds the pairs within the cutoff through a
 * Verlet neighbour list (cutoff + skin) built from the engine's Morton
 * sort, rebuilt (with the sort) only when the particles may have moved
 * half the skin since the last build; each particle's list is in id order,
 * so its force is summed in the order of the course's naive loop and the
 * results are bit for bit those of the naive code, for any thread count.
 * Phases:
 *   nlist  the sort and the neighbour lists (only at rebuilds);
 *   force  forces and move, fused: each tile reads the old positions and
 *          writes the new ones beside them (the store's sort scratch),
 *          so tiles are independent tasks with no dependencies.
 * --option naive=1 runs the course's O(n^2) loops instead (for tests). */
#ifndef PSIM_FORCE_H
#define PSIM_FORCE_H
#include <stddef.h>
#include <stdint.h>

#include "../../engine/engine.h"
#include "law.h"

enum { FPHASE_NLIST = PSIM_PHASE_MODEL, FPHASE_FORCE };
enum { FC_PAIR_TESTS, FC_INTERACTIONS, FC_REBUILDS, FC_LIST_ENTRIES, FC_TASKS };

/* The course's constants (common.h). */
#define CS267_DENSITY 0.0005
#define CS267_MASS 0.01
#define CS267_CUTOFF 0.01
#define CS267_DT 0.0005
#define CS267_STEPS 1000
#define CS267_SAVEFREQ 10

/* One tile's neighbour lists: the lists of its particles (store places
 * first .. first + n - 1) one after another; end[k] ends particle
 * first + k's list. */
typedef struct ftile {
    uint32_t first, n;
    uint32_t *end;
    uint32_t *nbr;          /* store places, each list in id order */
    size_t len, cap;
    double *cx, *cy;        /* candidates of the cell being listed */
    uint32_t *cj;
    size_t ccap;
    uint32_t *win;          /* the tile's cells and a border: first, end */
    size_t wcap;
    int wx0, wy0, W;        /* the window's first cell and side */
    /* this step: */
    double v2max;           /* largest squared speed after the move */
    uint64_t tests, hits;
    double dmin, dsum;      /* --force-stats: nearest distance / cutoff, sum */
    uint64_t dn;
    int lost;               /* a particle left the box for good */
} ftile;

typedef struct fmodel {
    flaw law;
    int naive, stats;
    double skin;            /* list radius = cutoff + skin */
    double drift;           /* bound on any displacement since the build */
    long since_build;       /* steps since the build */
    int built;
    ftile *tiles;
    uint32_t ntiles, cap_tiles;
    uint32_t *end_all;      /* n: storage of the tiles' end[] */
    /* --force-stats (the older edition's), over the steps so far */
    double absmin, absavg;
    long nabsavg;
    long lost_step;         /* first step a particle left the box (0: none) */
} fmodel;

/* nlist.c */
int force_build_lists(psim_sim *e, fmodel *m);
/* step.c: forces and move of every particle; -1 if one left the box */
int force_step_lists(psim_sim *e, fmodel *m);
int force_step_naive(psim_sim *e, fmodel *m);
int force_plan_naive(fmodel *m, long n);

#endif
