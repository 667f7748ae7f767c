/* Tiles cut where the work is.
 *
 * A step's resolution runs in rounds, and each tile's round is one task:
 * when one tile holds most of the work, its tasks are a chain no other
 * thread can share.  The course's 10k_density_0.9 piles its disks into a
 * corner; with the grid's square tiles, a quarter of the disks held 68% of
 * the resolutions, and on two threads one was busy 0.14 s while the other
 * was busy 0.10 s (docs/performance.md, "Tiles cut where the work is").
 *
 * So every BAL_EVERY steps the model counts each disk's work on that step
 * (worklist pops, and resolutions across tiles), plus one for the disk
 * itself (its search and sort), adds it up by cell, and plans cuts at the
 * quantiles of the work along each axis: each column of tiles, and each
 * row, gets an equal share.  It takes them when the heaviest tile holds
 * more than BAL_SHARE of the step's work (it would bound the speed-up of
 * 1 / BAL_SHARE threads) and the new cuts lower the heaviest tile's work
 * to BAL_GAIN of it or less, compared on the same step's work.  Cuts cost
 * resolutions where they cross the work (100k_density_0.9, 36 tiles cut
 * at every chance: +5.8%), so scenes of many tiles, none of them heavy,
 * keep theirs.  The tiles stay a TG x TG grid (the grid's own count: the
 * scene's, never the thread count's), so their neighbours and edges are as
 * before.
 *
 * Everything here is a function of exact counts of the scene's steps and of
 * the current cuts: the same cuts for any thread count, and a restart file
 * carries the cuts (the next decision needs nothing else). */
#include <string.h>

#include "discrete.h"
#include "../../engine/mem.h"

/* On a plain step nothing is counted; the step before a decision counts
 * (never where the cuts would not fit a restart file's header). */
int discrete_balance_counts(const psim_sim *e, const dmodel *m)
{
    return m->balance && m->ntiles > 1 && 2 * (e->grid.TG + 1) <= PSIM_RESTART_CUTS &&
           (e->step + 1) % BAL_EVERY == 0;
}

/* cut[0..TG]: cut[j] the first column whose cumulative work before it
 * reaches j / TG of the total, each column of tiles at least one cell. */
static void quantile_cuts(const double *w, double total, int G, int TG, int32_t *cut)
{
    double run = 0;
    cut[0] = 0;
    cut[TG] = G;
    int c = 0;
    for (int j = 1; j < TG; j++) {
        double want = total * j / TG;
        while (c < G && run + 0.5 * w[c] < want)
            run += w[c++];
        int v = c;
        if (v < cut[j - 1] + 1)
            v = cut[j - 1] + 1;
        if (v > G - (TG - j))
            v = G - (TG - j);
        cut[j] = v;
    }
}

/* The work of the heaviest tile under cuts (cx, cy), from the work by cell
 * (w[cy * G + cx]). */
static double heaviest(const double *w, int G, int TG, const int32_t *cx, const int32_t *cy,
                       double *load)
{
    memset(load, 0, (size_t)TG * TG * sizeof *load);
    for (int ty = 0; ty < TG; ty++)
        for (int y = cy[ty]; y < cy[ty + 1]; y++)
            for (int tx = 0; tx < TG; tx++) {
                double s = 0;
                for (int x = cx[tx]; x < cx[tx + 1]; x++)
                    s += w[(size_t)y * G + x];
                load[ty * TG + tx] += s;
            }
    double top = 0;
    for (int t = 0; t < TG * TG; t++)
        top = load[t] > top ? load[t] : top;
    return top;
}

/* The work counted this step, by cell (w[cy * G + cx]) and by column and
 * row; the counts are cleared for the next time.  Returns the total. */
static double work_by_cell(const psim_sim *e, dmodel *m, double *w, double *col, double *row)
{
    double total = 0;
    const psim_grid *g = &e->grid;
    const int G = g->G;
    memset(col, 0, (size_t)G * sizeof *col);
    memset(row, 0, (size_t)G * sizeof *row);
    for (uint32_t c = 0; c < g->ncells; c++) {
        double s = 0;
        for (uint32_t i = g->cellstart[c]; i < g->cellstart[c + 1]; i++) {
            s += 1.0 + m->work[i];
            m->work[i] = 0;
        }
        int x = g->cell_x[c], y = g->cell_y[c];
        w[(size_t)y * G + x] = s;
        col[x] += s;
        row[y] += s;
        total += s;
    }
    return total;
}

int discrete_balance(psim_sim *e, dmodel *m)
{
    if (!discrete_balance_counts(e, m))
        return 0;
    const psim_grid *g = &e->grid;
    const int G = g->G, TG = g->TG;
    size_t cells = (size_t)G * G;
    double *w = psim_alloc((cells + 2 * (size_t)G + (size_t)TG * TG) * sizeof *w);
    int32_t *cut = psim_alloc(2 * ((size_t)TG + 1) * sizeof *cut);
    int changed = -1;
    if (!w || !cut)
        goto done;
    double *col = w + cells, *row = col + G, *load = row + G;
    if (m->ranks > 1)
        discrete_ranks_work(e, m);
    double total = work_by_cell(e, m, w, col, row);
    quantile_cuts(col, total, G, TG, cut);
    quantile_cuts(row, total, G, TG, cut + TG + 1);
    double now = heaviest(w, G, TG, g->cut_x, g->cut_y, load);
    double then = heaviest(w, G, TG, cut, cut + TG + 1, load);
    changed = now > BAL_SHARE * total && then < BAL_GAIN * now;
    if (changed) {
        psim_engine_grid_cut(e, cut, cut + TG + 1);
        e->stats.counter[DC_CUTS] += m->rank == 0;   /* (summed over ranks) */
    }
done:
    psim_free(w);
    psim_free(cut);
    return changed;
}
