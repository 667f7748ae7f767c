#include "grid.h"

#include <math.h>
#include <string.h>

#include "mem.h"
#include "morton.h"

/* Cells per side: side > 2r, and about PSIM_CELL_PARTICLES particles per
 * cell on average, since the per-cell work of the contact search (finding
 * and opening the neighbour cells) costs more than a few extra distance
 * tests (docs/performance.md, "Cell size"). */
static int plan_cells(double L, double reach, long n, double occupancy)
{
    double fit = (reach > 0.0) ? floor(L / reach * (1.0 - 1e-9)) : 1e9;
    double cap = ceil(sqrt((double)(n > 0 ? n : 1) / occupancy));
    double G = fmin(fit, cap);
    if (!(G >= 1.0))
        G = 1.0;
    return (int)G;
}

static int plan_tile_shift(int G, int bits, long n, int tile_cells, double tile_particles)
{
    int shift = 0;
    if (tile_cells > 0) {
        while ((1 << shift) < tile_cells && shift < bits)
            shift++;
        return shift;
    }
    double per_cell = (double)(n > 0 ? n : 1) / ((double)G * G);
    double side = sqrt((tile_particles > 0 ? tile_particles : PSIM_TILE_PARTICLES) / per_cell);
    shift = (int)lround(log2(side));
    if (shift < 0)
        shift = 0;
    if (shift > bits)
        shift = bits;
    return shift;
}

/* Number the tiles of a W x W grid of tiles by dense Morton rank. */
static void rank_tiles(int W, int bits, uint32_t *rank_of_xy, int32_t *xs, int32_t *ys)
{
    uint32_t next = 0;
    uint64_t keys = 1ull << (2 * bits);
    for (uint64_t k = 0; k < keys; k++) {
        uint32_t x, y;
        psim_morton_decode(k, &x, &y);
        if (x >= (uint32_t)W || y >= (uint32_t)W)
            continue;
        rank_of_xy[y * (uint32_t)W + x] = next;
        xs[next] = (int32_t)x;
        ys[next] = (int32_t)y;
        next++;
    }
}

/* A tile's cells [x0, x1) x [y0, y1), ranked from *next in Morton order of
 * their offsets from (x0, y0): the quadrant of side 1 << level at offset
 * (qx, qy), its four children in key order, those outside left out. */
static void rank_quadrant(psim_grid *g, int x0, int y0, int w, int h, int qx, int qy,
                          int level, uint32_t *next)
{
    if (qx >= w || qy >= h)
        return;
    if (level == 0) {
        int cx = x0 + qx, cy = y0 + qy;
        g->rank_of_xy[(uint32_t)cy * (uint32_t)g->G + (uint32_t)cx] = *next;
        g->cell_x[*next] = cx;
        g->cell_y[*next] = cy;
        (*next)++;
        return;
    }
    int half = 1 << (level - 1);
    for (int k = 0; k < 4; k++)   /* x in the even bits: (0,0) (1,0) (0,1) (1,1) */
        rank_quadrant(g, x0, y0, w, h, qx + (k & 1) * half, qy + (k >> 1) * half, level - 1,
                      next);
}

static int bits_for(int W)
{
    int b = 0;
    while ((1 << b) < W)
        b++;
    return b;
}

/* Whether disks in cell (cx, cy) can touch a wall: border cells hold every
 * disk outside the grid; other cells only if they reach within r of a wall. */
static int cell_near_wall(const psim_grid *g, int cx, int cy, double L, double r)
{
    if (cx == 0 || cy == 0 || cx == g->G - 1 || cy == g->G - 1)
        return 1;
    double eps = 1e-9 * (fabs(L) + fabs(g->x0) + fabs(g->y0) + g->side + r);
    double xlo = g->x0 + cx * g->h, xhi = xlo + g->h;
    double ylo = g->y0 + cy * g->h, yhi = ylo + g->h;
    return xlo <= r + eps || ylo <= r + eps || xhi >= L - r - eps || yhi >= L - r - eps;
}

int psim_grid_init(psim_grid *g, double L, double r, double reach, long n,
                   int tile_cells, const double *bbox)
{
    return psim_grid_init_occ(g, L, r, reach, n, tile_cells, bbox, PSIM_CELL_PARTICLES, 0);
}

int psim_grid_init_occ(psim_grid *g, double L, double r, double reach, long n,
                       int tile_cells, const double *bbox, double occupancy,
                       double tile_particles)
{
    memset(g, 0, sizeof *g);
    g->L = L;
    g->x0 = bbox ? bbox[0] : 0.0;
    g->y0 = bbox ? bbox[1] : 0.0;
    g->side = bbox ? fmax(bbox[2] - bbox[0], bbox[3] - bbox[1]) : L;
    if (!(g->side > reach)) /* one cell, or all disks at one point */
        g->side = reach * (1.0 + 1e-6) + 1e-300;
    g->G = plan_cells(g->side, reach, n, occupancy > 0 ? occupancy : PSIM_CELL_PARTICLES);
    g->h = g->side / g->G;
    g->invh = g->G / g->side;
    g->bits = bits_for(g->G);
    g->ncells = (uint32_t)g->G * (uint32_t)g->G;
    g->tile_shift = plan_tile_shift(g->G, g->bits, n, tile_cells, tile_particles);
    int S = 1 << g->tile_shift;
    g->TG = (g->G + S - 1) / S;
    g->ntiles = (uint32_t)g->TG * (uint32_t)g->TG;

    g->rank_of_xy = psim_alloc(g->ncells * sizeof *g->rank_of_xy);
    g->cell_x = psim_alloc(g->ncells * sizeof *g->cell_x);
    g->cell_y = psim_alloc(g->ncells * sizeof *g->cell_y);
    g->cellstart = psim_calloc((g->ncells + 1) * sizeof *g->cellstart);
    g->tile_of_xy = psim_alloc(g->ntiles * sizeof *g->tile_of_xy);
    g->tile_x = psim_alloc(g->ntiles * sizeof *g->tile_x);
    g->tile_y = psim_alloc(g->ntiles * sizeof *g->tile_y);
    g->tile_cell0 = psim_calloc((g->ntiles + 1) * sizeof *g->tile_cell0);
    g->tile_wall = psim_calloc(g->ntiles);
    g->cut_x = psim_alloc(((size_t)g->TG + 1) * sizeof *g->cut_x);
    g->cut_y = psim_alloc(((size_t)g->TG + 1) * sizeof *g->cut_y);
    g->tcol = psim_alloc((size_t)g->G * sizeof *g->tcol);
    g->trow = psim_alloc((size_t)g->G * sizeof *g->trow);
    if (!g->cut_x || !g->cut_y || !g->tcol || !g->trow || !g->rank_of_xy || !g->cell_x ||
        !g->cell_y || !g->cellstart || !g->tile_of_xy || !g->tile_x || !g->tile_y ||
        !g->tile_cell0 || !g->tile_wall) {
        psim_grid_free(g);
        return -1;
    }
    rank_tiles(g->TG, bits_for(g->TG), g->tile_of_xy, g->tile_x, g->tile_y);
    g->r = r;
    psim_grid_cut(g, NULL, NULL);
    return 0;
}

int psim_grid_cuts_ok(const int32_t *cut, int TG, int G)
{
    if (cut[0] != 0 || cut[TG] != G)
        return 0;
    for (int j = 0; j < TG; j++)
        if (cut[j + 1] <= cut[j])
            return 0;
    return 1;
}

/* of[c]: the column (row) of tiles of cell column (row) c, from the cuts. */
static void tile_of_line(const int32_t *cut, int TG, int32_t *of)
{
    for (int j = 0; j < TG; j++)
        for (int c = cut[j]; c < cut[j + 1]; c++)
            of[c] = j;
}

void psim_grid_cut(psim_grid *g, const int32_t *cut_x, const int32_t *cut_y)
{
    const int S = 1 << g->tile_shift;
    g->cut = cut_x || cut_y;
    for (int j = 0; j <= g->TG; j++) {
        int u = j * S < g->G ? j * S : g->G;
        g->cut_x[j] = cut_x ? cut_x[j] : u;
        g->cut_y[j] = cut_y ? cut_y[j] : u;
    }
    tile_of_line(g->cut_x, g->TG, g->tcol);
    tile_of_line(g->cut_y, g->TG, g->trow);
    /* Tiles in rank order own consecutive cell ranks. */
    uint32_t next = 0;
    for (uint32_t t = 0; t < g->ntiles; t++) {
        int x0 = g->cut_x[g->tile_x[t]], x1 = g->cut_x[g->tile_x[t] + 1];
        int y0 = g->cut_y[g->tile_y[t]], y1 = g->cut_y[g->tile_y[t] + 1];
        int w = x1 - x0, h = y1 - y0;
        g->tile_cell0[t] = next;
        rank_quadrant(g, x0, y0, w, h, 0, 0, bits_for(w > h ? w : h), &next);
        g->tile_wall[t] = 0;
        for (uint32_t c = g->tile_cell0[t]; c < next && !g->tile_wall[t]; c++)
            g->tile_wall[t] = (uint8_t)cell_near_wall(g, g->cell_x[c], g->cell_y[c], g->L, g->r);
    }
    g->tile_cell0[g->ntiles] = next;
}

void psim_grid_free(psim_grid *g)
{
    psim_free(g->rank_of_xy);
    psim_free(g->cell_x);
    psim_free(g->cell_y);
    psim_free(g->cellstart);
    psim_free(g->tile_of_xy);
    psim_free(g->tile_x);
    psim_free(g->tile_y);
    psim_free(g->tile_cell0);
    psim_free(g->tile_wall);
    psim_free(g->cut_x);
    psim_free(g->cut_y);
    psim_free(g->tcol);
    psim_free(g->trow);
    memset(g, 0, sizeof *g);
}
