/* The ccd model (NUS CS3210 AY2019/20), internal header.
 *
 * A step, from the start-of-step state (the engine has sorted the disks by
 * cell; cells are wider than 2r plus the largest displacement of two disks,
 * so every pair that can meet within the step is in the same or adjacent
 * cells):
 *   detect  candidates: each disk's wall hit, and each pair's time of
 *           impact in [0, 1] (rules.h); parallel, OpenMP tasks over runs
 *           of cells, pairs pruned by their swept boxes (sweep and prune
 *           along x; big cells, where fast disks leave one cell, also cut
 *           into bands along y first);
 *   order   the candidates in the total order of the authors' program:
 *           time, then lower disk P, then the wall before the lower Q;
 *   accept  greedily in that order, a candidate whose disks are both still
 *           free this step (sequential, or in parallel rounds of candidates
 *           that come first for both their disks: the same set);
 *   move    accepted collisions, then free flight for every other disk.
 * Candidates depend only on the start-of-step state and are found
 * exhaustively, and the order is total, so results are bit for bit those of
 * the authors' sequential program for any thread count.
 *
 * Over MPI ranks every rank holds every disk (the engine's shares mode):
 * each rank runs its share of the detection's tasks, the ranks' sorted
 * candidates are gathered on every rank and merged (the one-process list,
 * in the same order), and every rank accepts and moves the same, so the
 * copies stay equal and the results are those of one process. */
#ifndef PSIM_CCD_H
#define PSIM_CCD_H
#include <stddef.h>
#include <stdint.h>

#include "../../engine/engine.h"
#include "../../engine/nearest.h"
#include "cand.h"
#include "gpu.h"

enum { CPHASE_DETECT = PSIM_PHASE_MODEL, CPHASE_ORDER, CPHASE_ACCEPT, CPHASE_COPY, CPHASE_END };
enum { CC_PAIR_TESTS, CC_PAIR_CANDIDATES, CC_WALL_CANDIDATES, CC_PAIR_COLLISIONS,
       CC_WALL_COLLISIONS, CC_ACCEPT_ROUNDS, CC_TASKS, CC_REGRIDS, CC_END };
/* Stages left out where the scene cannot use them (ccd.c). */
enum { CS_PAIRS, CS_WALLS, CS_MOVE, CS_GRAPH };

typedef struct clist {
    ccand *c;
    size_t n, cap;
} clist;

/* How acceptance runs: sequential greedy, parallel rounds, or by size. */
typedef enum { CCD_ACCEPT_AUTO = 0, CCD_ACCEPT_SEQ, CCD_ACCEPT_PAR } ccd_accept_mode;

/* A big cell cut into nb bands along y, from ylo, 1 / invh apart; its
 * bands are band0 .. band0 + nb - 1 of the model's bands. */
typedef struct cplan {
    uint32_t cell, band0;
    int nb;
    double ylo, invh;
} cplan;

/* A band: its entries [e0, e1) (followed by CCD_PAD sentinel rows), k its
 * index in its cell (a double: the detection kernel compares it in
 * lanes of doubles). */
typedef struct cband {
    uint32_t e0, e1;
    double k;
} cband;

/* Rows after each band's entries that no box overlaps (the detection
 * kernel reads blocks of 4 entries past a band's end). */
#define CCD_PAD 4

/* Every band's entries, this step: a copy of each row whose box meets the
 * band (box x0, x1, y0, y1; first: the row's first band in its cell; the
 * disk's x, y, vx, vy; row: its sorted place), in left-edge order, so that
 * the kernel reads contiguous arrays. */
typedef struct cbands {
    double *x0, *x1, *y0, *y1, *first, *x, *y, *vx, *vy;
    uint32_t *row;
    size_t cap;             /* entries every array holds */
    cband *band;
    size_t nband, band_cap;
    cplan *plan;
    size_t nplan, plan_cap;
    size_t nentry;          /* entries of every band, with their pads */
    uint8_t *mine;          /* per band, over ranks: this rank sweeps it */
    size_t mine_cap;
    /* per thread and band: the entries the thread's rows put in the band,
     * then where the next of them goes (threads x nband) */
    uint32_t *put;
    size_t put_cap;
} cbands;

typedef struct cmodel {
    double L, r;
    double margin;          /* slack of the swept boxes against round-off */
    double vmax;            /* largest speed component bound this step */
    /* per store place, this step: each cell's disks sorted by the left
     * edge of their swept box (ord: store places; key, key2, ord2: sort
     * keys and scratch), and their boxes s* in that order ("rows") */
    uint32_t *ord, *key, *key2, *ord2;
    double *sx0, *sx1, *sy0, *sy1;
    double *wmax;           /* per cell: widest box (sized on regrid) */
    size_t wmax_cap;
    cbands bands;           /* big cells' bands */
    clist *lists;           /* one per thread */
    int nlists;
    size_t *off, *head;     /* per list: place in `all`, merge position */
    clist all;              /* every candidate, in order */
    clist acc;              /* the accepted ones, in order */
    uint8_t *busy;          /* per store place: in an accepted collision */
    uint32_t *best;         /* per store place: parallel acceptance */
    uint8_t *live;          /* per candidate: parallel acceptance */
    size_t live_cap;
    int64_t *pcoll, *wcoll; /* per id: collisions so far */
    ccd_accept_mode accept_mode;
    int skip;               /* leave out what the scene cannot use (-O skip) */
    int still;              /* the last step had every velocity 0 */
    int same;               /* the last step had one velocity for all */
    /* free flight (flight.c) */
    double gap;             /* every pair is more than 2r + gap apart (-1: unknown) */
    int measured;           /* the gap was measured in the last step */
    psim_backoff measure;   /* searches before the next measurement */
    int oom;                /* a list could not grow this step */
    /* over MPI ranks (every rank holds every disk, in the same order):
     * this rank, and how many; each detects its share, all accept */
    int rank, ranks;
    /* --device gpu: the state on the device (gpu.h), and where its copies
     * are timed */
    cgpu *gpu;
    psim_stats *gpu_stats;
} cmodel;

/* Slack of the swept boxes, the cells and the skips (cand.h). */
static inline double ccd_margin(const cmodel *m, double vmax)
{
    return ccd_margin_of(m->L, m->r, vmax);
}

void ccd_detect(psim_sim *e, cmodel *m);
/* On the GPU: the last step's candidates and accepted ones into all and
 * acc (for --check): 0, or -1 with err set. */
int ccd_gpu_lists(cmodel *m, psim_error *err);
void ccd_detect_walls(psim_sim *e, cmodel *m);
int ccd_order(psim_sim *e, cmodel *m);
void ccd_gather(psim_sim *e, cmodel *m, int fail);
size_t ccd_pair_count(const ccand *c, size_t n);
int ccd_accept(psim_sim *e, cmodel *m);
void ccd_advance(psim_sim *e, cmodel *m);
int ccd_check(psim_sim *e, void *m, const psim_snapshot *before,
              const psim_snapshot *after, psim_error *err);
/* flight.c: whether no pair can meet this step (a gap measured and kept),
 * whether no disk can reach a wall (ext: the positions' x and y extent);
 * the gap after a search with no pair candidate; the gap after a step */
int ccd_flight_clear(cmodel *m, double vmax);
int ccd_walls_clear(const cmodel *m, double vmax, const double ext[4]);
void ccd_flight_measure(psim_sim *e, cmodel *m);
void ccd_flight_step(cmodel *m, double vmax);
int ccd_cand_cmp(const ccand *a, const ccand *b);
int ccd_list_push(clist *l, const ccand *c);
void ccd_bands_free(cbands *b);

#endif
