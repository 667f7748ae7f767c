/* The ccd model (NUS CS3210 AY2019/20), internal header.
 *
 * A step, from the start-of-step state (the engine has sorted the disks by
 * cell; cells are wider than 2r plus the largest displacement of two disks,
 * so every pair that can meet within the step is in the same or adjacent
 * cells):
 *   detect  candidates: each disk's wall hit, and each pair's time of
 *           impact in [0, 1] (rules.h); parallel, OpenMP tasks over tiles
 *           of cells, pairs pruned by their swept boxes (sweep and prune
 *           along x inside each cell pair);
 *   order   the candidates in the total order of the authors' program:
 *           time, then lower disk P, then the wall before the lower Q;
 *   accept  greedily in that order, a candidate whose disks are both still
 *           free this step (sequential, or in parallel rounds of candidates
 *           that come first for both their disks: the same set);
 *   move    accepted collisions, then free flight for every other disk.
 * Candidates depend only on the start-of-step state and are found
 * exhaustively, and the order is total, so results are bit for bit those of
 * the authors' sequential program for any thread count. */
#ifndef PSIM_CCD_H
#define PSIM_CCD_H
#include <stddef.h>
#include <stdint.h>

#include "../../engine/engine.h"

enum { CPHASE_DETECT = PSIM_PHASE_MODEL, CPHASE_ORDER, CPHASE_ACCEPT };
enum { CC_PAIR_TESTS, CC_PAIR_CANDIDATES, CC_WALL_CANDIDATES, CC_PAIR_COLLISIONS,
       CC_WALL_COLLISIONS, CC_ACCEPT_ROUNDS, CC_TASKS, CC_REGRIDS };

/* A candidate: disks by id, p < q, q = -1 for the wall; sp, sq their
 * places in the store this step. */
typedef struct ccand {
    double t;
    int32_t p, q;
    uint32_t sp, sq;
} ccand;

typedef struct clist {
    ccand *c;
    size_t n, cap;
} clist;

/* How acceptance runs: sequential greedy, parallel rounds, or by size. */
typedef enum { CCD_ACCEPT_AUTO = 0, CCD_ACCEPT_SEQ, CCD_ACCEPT_PAR } ccd_accept_mode;

typedef struct cmodel {
    double L, r;
    double margin;          /* slack of the swept boxes against round-off */
    double vmax;            /* largest speed component bound this step */
    /* per store place, this step: swept box, and the cell's disks sorted
     * by the box's left edge (ord: store places; b*: boxes in that order) */
    double *bx0, *bx1, *by0, *by1;
    uint32_t *ord;
    double *sx0, *sx1, *sy0, *sy1;
    clist *lists;           /* one per thread */
    int nlists;
    clist all;              /* every candidate, in order */
    clist acc;              /* the accepted ones, in order */
    uint8_t *busy;          /* per store place: in an accepted collision */
    uint32_t *best;         /* per store place: parallel acceptance */
    uint8_t *live;          /* per candidate: parallel acceptance */
    size_t live_cap;
    int64_t *pcoll, *wcoll; /* per id: collisions so far */
    ccd_accept_mode accept_mode;
    int oom;                /* a list could not grow this step */
} cmodel;

void ccd_detect(psim_sim *e, cmodel *m);
int ccd_order(psim_sim *e, cmodel *m);
int ccd_accept(psim_sim *e, cmodel *m);
void ccd_advance(psim_sim *e, cmodel *m);
int ccd_check(psim_sim *e, void *m, const psim_snapshot *before,
              const psim_snapshot *after, psim_error *err);
int ccd_cand_cmp(const ccand *a, const ccand *b);
int ccd_list_push(clist *l, const ccand *c);

#endif
