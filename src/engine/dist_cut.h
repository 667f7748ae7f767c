/* The domains of a run over ranks: a grid of px columns of py ranks,
 * columns cut where the particles are along x, each column's ranks cut
 * along y where its particles are (dist_cut.c).  No MPI here: the
 * histograms the cuts come from are summed over the ranks by dist.c. */
#ifndef PSIM_ENGINE_DIST_CUT_H
#define PSIM_ENGINE_DIST_CUT_H
#include <stdint.h>

/* Bins of the histograms the cuts are chosen from, a side. */
#define DIST_BINS 4096

typedef struct dist_cuts {
    int px, py;      /* ranks = px * py; rank = column * py + row */
    double L;
    double *cx;      /* px + 1: column i is [cx[i], cx[i + 1]) */
    double *cy;      /* px * (py + 1): row j of column i is
                      * [cy[i (py + 1) + j], cy[i (py + 1) + j + 1]) */
} dist_cuts;

/* The grid of ranks for R ranks in a square box: px columns of py, py
 * the largest divisor of R not above its square root. */
void dist_cuts_shape(int R, int *px, int *py);
int dist_cuts_alloc(dist_cuts *c, int R, double L);
void dist_cuts_free(dist_cuts *c);
/* The histogram bin of coordinate v in [0, L) (clamped). */
static inline int dist_bin(double v, double L)
{
    double b = v / L * DIST_BINS;
    return b >= 0 ? (b < DIST_BINS ? (int)b : DIST_BINS - 1) : 0;
}
/* parts + 1 cuts from a histogram of DIST_BINS bins over [0, L): the
 * outer two infinite, cut k at the bin edge where the count reaches k /
 * parts of the whole. */
void dist_cuts_from_hist(const uint64_t *hist, double L, int parts, double *cuts);
/* The column of x: the last i with cx[i] <= x (positions past the box's
 * sides and NaNs go to the outer ones). */
int dist_cuts_column(const dist_cuts *c, double x);
/* The rank that owns a particle at (x, y). */
int dist_cuts_owner(const dist_cuts *c, double x, double y);
/* Whether (x, y) lies within h of rank q's domain (on it included). */
int dist_cuts_near(const dist_cuts *c, int q, double x, double y, double h);

#endif
