/* The uniform cell grid and its tiles.
 *
 * Cells have side h > reach (2r for contacts), so overlapping disks are in the same or adjacent
 * cells.  Cells are numbered by their dense Morton rank: the Morton keys of
 * the G x G cells, renumbered 0..G*G-1 in key order, so a counting sort by
 * rank is a sort by Morton key with no empty buckets outside the grid.
 * Tiles are aligned blocks of S x S cells (S a power of two); in Morton order
 * the cells of a tile are one contiguous rank range, and so are its
 * particles after the sort.  A model may cut the tiles elsewhere
 * (psim_grid_cut: the same TG x TG tiles, each column and row of tiles as
 * wide as it chooses); cells are then ranked tile by tile, in the tiles'
 * Morton order, and in Morton order within each tile, which for the
 * default cuts is the dense Morton rank itself.  The grid spans the region
 * its model asks for (the discrete model: where its disks are, planned again as they move, so
 * a cluster in a corner of a huge box still gets small cells:
 * src/models/discrete/regrid.c); positions outside it are clamped into the
 * border cells, which keeps adjacent disks in adjacent cells. */
#ifndef PSIM_ENGINE_GRID_H
#define PSIM_ENGINE_GRID_H
#include <stdint.h>

/* Default tile size, in particles.  Each tile border costs extra
 * resolutions on dense scenes (the fixpoint inside a tile runs against a
 * stale border until the next round), so tiles are as large as parallelism
 * allows: measured in docs/performance.md ("Tile size"). */
#define PSIM_TILE_PARTICLES 16384.0
/* Default cell occupancy, in particles (cells are never narrower than 2r). */
#define PSIM_CELL_PARTICLES 3.0

typedef struct psim_grid {
    double L, r, h, invh;   /* r: the disks' radius (which cells touch a wall) */
    double x0, y0, side;    /* the gridded square [x0, x0+side] x [y0, y0+side] */
    int G;                  /* cells per side */
    int bits;               /* 2^bits >= G */
    uint32_t ncells;        /* G * G */
    uint32_t *rank_of_xy;   /* [cy * G + cx] -> rank */
    int32_t *cell_x, *cell_y; /* rank -> coordinates */
    uint32_t *cellstart;    /* ncells + 1: first particle of each cell */

    int tile_shift;         /* S = 1 << tile_shift cells per tile side,
                             * unless cut otherwise (psim_grid_cut) */
    int TG;                 /* tiles per side */
    int32_t *cut_x, *cut_y; /* TG + 1 each: the first cell column (row) of
                             * each column (row) of tiles; [TG] = G */
    int32_t *tcol, *trow;   /* G each: the tile column (row) of a cell column (row) */
    int cut;                /* the cuts are not the multiples of S */
    uint32_t ntiles;
    uint32_t *tile_of_xy;   /* [ty * TG + tx] -> tile rank */
    int32_t *tile_x, *tile_y;
    uint32_t *tile_cell0;   /* ntiles + 1: first cell rank of each tile */
    uint8_t *tile_wall;     /* tile holds a cell whose disks can touch a wall */
} psim_grid;

/* Plan a grid for n disks of radius r in the box [0, L]^2 whose cells are
 * wider than reach (2r for contacts; more for swept paths), over the region
 * bbox = {xmin, ymin, xmax, ymax} (NULL: the box).  tile_cells: cells per
 * tile side (a power of two), or 0 to choose about PSIM_TILE_PARTICLES
 * particles per tile. */
int psim_grid_init(psim_grid *g, double L, double r, double reach, long n,
                   int tile_cells, const double *bbox);
/* The same with about `occupancy` particles per cell at most (cells stay
 * wider than reach): sparse pair searches want cells close to reach; and
 * with tile_cells 0, tiles of about tile_particles particles (0:
 * PSIM_TILE_PARTICLES). */
int psim_grid_init_occ(psim_grid *g, double L, double r, double reach, long n,
                       int tile_cells, const double *bbox, double occupancy,
                       double tile_particles);
void psim_grid_free(psim_grid *g);
/* Cut the tiles of g at cell columns cut_x[0..TG] and rows cut_y[0..TG]
 * (cut[0] = 0, cut[TG] = G, increasing; NULL: the multiples of S) and rank
 * the cells anew.  The particles must be sorted again. */
void psim_grid_cut(psim_grid *g, const int32_t *cut_x, const int32_t *cut_y);
/* Whether cut[0..TG] cuts G cells into TG columns of at least one cell. */
int psim_grid_cuts_ok(const int32_t *cut, int TG, int G);

/* Cell coordinate of position v along an axis whose grid starts at origin. */
static inline int psim_grid_coord(const psim_grid *g, double v, double origin)
{
    double c = (v - origin) * g->invh;
    if (!(c >= 0.0))        /* negative or NaN */
        return 0;
    if (c >= (double)(g->G - 1))
        return g->G - 1;
    return (int)c;
}

static inline uint32_t psim_grid_cell(const psim_grid *g, double x, double y)
{
    return g->rank_of_xy[(uint32_t)psim_grid_coord(g, y, g->y0) * (uint32_t)g->G +
                         (uint32_t)psim_grid_coord(g, x, g->x0)];
}

/* Forward neighbour k (0..3) of cell (cx, cy) in the half stencil the
 * contact searches walk, so that each pair of cells is met once: east,
 * north-west, north, north-east.  Its rank, or UINT32_MAX when it is
 * outside the grid; *nx, *ny its coordinates. */
static inline uint32_t psim_grid_forward(const psim_grid *g, int cx, int cy, int k, int *nx,
                                         int *ny)
{
    static const int fwd[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};
    *nx = cx + fwd[k][0], *ny = cy + fwd[k][1];
    if (*nx < 0 || *ny < 0 || *nx >= g->G || *ny >= g->G)
        return UINT32_MAX;
    return g->rank_of_xy[*ny * g->G + *nx];
}

static inline uint32_t psim_grid_tile_of_cell(const psim_grid *g, uint32_t cell)
{
    return g->tile_of_xy[g->trow[g->cell_y[cell]] * g->TG + g->tcol[g->cell_x[cell]]];
}

#endif
