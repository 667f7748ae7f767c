/* Morton keys and the grid: ranks, tiles, clamping of disks outside. */
#include <stdlib.h>

#include "check.h"
#include "engine/grid.h"
#include "engine/morton.h"

static void test_morton(void)
{
    CHECK(psim_morton_encode(0, 0) == 0);
    CHECK(psim_morton_encode(1, 0) == 1);
    CHECK(psim_morton_encode(0, 1) == 2);
    CHECK(psim_morton_encode(1, 1) == 3);
    CHECK(psim_morton_encode(2, 0) == 4);
    CHECK(psim_morton_encode(3, 5) == 0x27); /* x=011 y=101 -> 100111 */
    for (uint32_t x = 0; x < 300; x += 7)
        for (uint32_t y = 0; y < 300; y += 11) {
            uint32_t a, b;
            psim_morton_decode(psim_morton_encode(x, y), &a, &b);
            CHECK(a == x && b == y);
        }
    uint32_t a, b;
    psim_morton_decode(psim_morton_encode(0xFFFFFFFFu, 12345), &a, &b);
    CHECK(a == 0xFFFFFFFFu && b == 12345);
}

static void test_grid_ranks(void)
{
    psim_grid g;
    /* L / 2r = 50 cells would fit; 10000 particles allow up to 200 */
    CHECK(psim_grid_init(&g, 100.0, 1.0, 2.0 * (1.0), 10000, 4, NULL) == 0);
    CHECK(g.G == 49 || g.G == 50);
    CHECK(g.h > 2.0);
    /* ranks are a permutation that follows Morton order */
    uint64_t prev = 0;
    for (uint32_t c = 0; c < g.ncells; c++) {
        uint64_t key = psim_morton_encode((uint32_t)g.cell_x[c], (uint32_t)g.cell_y[c]);
        CHECK(c == 0 || key > prev);
        prev = key;
        CHECK(g.rank_of_xy[g.cell_y[c] * g.G + g.cell_x[c]] == c);
    }
    /* tiles: 4 x 4 cells, contiguous rank ranges in tile order */
    CHECK(g.tile_shift == 2);
    CHECK(g.TG == (g.G + 3) / 4);
    CHECK(g.tile_cell0[0] == 0 && g.tile_cell0[g.ntiles] == g.ncells);
    for (uint32_t t = 0; t < g.ntiles; t++) {
        CHECK(g.tile_cell0[t] < g.tile_cell0[t + 1]);
        for (uint32_t c = g.tile_cell0[t]; c < g.tile_cell0[t + 1]; c++)
            CHECK(psim_grid_tile_of_cell(&g, c) == t);
        int border = g.tile_x[t] == 0 || g.tile_y[t] == 0 ||
                     g.tile_x[t] == g.TG - 1 || g.tile_y[t] == g.TG - 1;
        CHECK(g.tile_wall[t] == border);
    }
    psim_grid_free(&g);
}

/* Tiles cut elsewhere: each tile one contiguous rank range, in the tiles'
 * Morton order, its cells in Morton order of their offsets; the default
 * cuts give the dense Morton ranks back; bad cuts are refused. */
static void test_grid_cuts(void)
{
    psim_grid g;
    CHECK(psim_grid_init(&g, 100.0, 1.0, 2.0 * (1.0), 10000, 16, NULL) == 0);
    CHECK(g.TG == (g.G + 15) / 16 && g.TG >= 3);
    uint32_t *dense = malloc(g.ncells * sizeof *dense);
    for (uint32_t c = 0; c < g.ncells; c++)
        dense[c] = g.rank_of_xy[g.cell_y[c] * g.G + g.cell_x[c]];
    int32_t cx[8], cy[8];
    for (int j = 0; j <= g.TG; j++) {   /* uneven: 1 cell, then most, then the rest */
        cx[j] = j == 0 ? 0 : j == g.TG ? g.G : j == 1 ? 1 : g.G - (g.TG - j) * 3;
        cy[j] = j == 0 ? 0 : j == g.TG ? g.G : g.G - (g.TG - j) * 2;
    }
    CHECK(psim_grid_cuts_ok(cx, g.TG, g.G) && psim_grid_cuts_ok(cy, g.TG, g.G));
    psim_grid_cut(&g, cx, cy);
    CHECK(g.cut);
    CHECK(g.tile_cell0[0] == 0 && g.tile_cell0[g.ntiles] == g.ncells);
    uint32_t seen = 0;
    for (uint32_t t = 0; t < g.ntiles; t++) {
        int tx = g.tile_x[t], ty = g.tile_y[t];
        uint32_t want = (uint32_t)(cx[tx + 1] - cx[tx]) * (uint32_t)(cy[ty + 1] - cy[ty]);
        CHECK(g.tile_cell0[t + 1] - g.tile_cell0[t] == want);
        uint64_t prev = 0;
        for (uint32_t c = g.tile_cell0[t]; c < g.tile_cell0[t + 1]; c++, seen++) {
            CHECK(psim_grid_tile_of_cell(&g, c) == t);
            CHECK(g.cell_x[c] >= cx[tx] && g.cell_x[c] < cx[tx + 1]);
            CHECK(g.cell_y[c] >= cy[ty] && g.cell_y[c] < cy[ty + 1]);
            CHECK(g.rank_of_xy[g.cell_y[c] * g.G + g.cell_x[c]] == c);
            uint64_t key = psim_morton_encode((uint32_t)(g.cell_x[c] - cx[tx]),
                                              (uint32_t)(g.cell_y[c] - cy[ty]));
            CHECK(c == g.tile_cell0[t] || key > prev);
            prev = key;
        }
    }
    CHECK(seen == g.ncells);
    psim_grid_cut(&g, NULL, NULL);   /* the default cuts: the dense Morton ranks */
    CHECK(!g.cut);
    for (uint32_t c = 0; c < g.ncells; c++)
        CHECK(g.rank_of_xy[g.cell_y[c] * g.G + g.cell_x[c]] == c && dense[c] == c);
    for (uint32_t c = 0; c < g.ncells; c++)
        CHECK(psim_grid_tile_of_cell(&g, c) ==
              g.tile_of_xy[(g.cell_y[c] >> 4) * g.TG + (g.cell_x[c] >> 4)]);
    cx[1] = 0;   /* an empty column of tiles */
    CHECK(!psim_grid_cuts_ok(cx, g.TG, g.G));
    cx[1] = 1, cx[g.TG] = g.G + 1;   /* past the grid */
    CHECK(!psim_grid_cuts_ok(cx, g.TG, g.G));
    free(dense);
    psim_grid_free(&g);
}

static void test_grid_clamp(void)
{
    psim_grid g;
    CHECK(psim_grid_init(&g, 10.0, 1.0, 2.0 * (1.0), 100, 0, NULL) == 0);
    CHECK(g.G == 4); /* side 2.5 > 2r */
    CHECK(psim_grid_coord(&g, -5.0, 0.0) == 0);
    CHECK(psim_grid_coord(&g, -1e300, 0.0) == 0);
    CHECK(psim_grid_coord(&g, 0.0 / 0.0, 0.0) == 0);
    CHECK(psim_grid_coord(&g, 1e300, 0.0) == g.G - 1);
    CHECK(psim_grid_coord(&g, 10.0, 0.0) == g.G - 1);
    CHECK(psim_grid_coord(&g, 2.4, 0.0) == 0);
    CHECK(psim_grid_coord(&g, 2.6, 0.0) == 1);
    /* disks within 2r are never more than one cell apart, also outside */
    double xs[] = {-7.0, -1.5, -0.1, 0.0, 1.9, 2.5, 4.9, 7.4, 9.99, 10.0, 11.5, 30.0};
    for (size_t i = 0; i < sizeof xs / sizeof xs[0]; i++)
        for (double d = -2.0; d <= 2.0; d += 0.125) {
            int a = psim_grid_coord(&g, xs[i], 0.0), b = psim_grid_coord(&g, xs[i] + d, 0.0);
            CHECK(abs(a - b) <= 1);
        }
    psim_grid_free(&g);

    /* a huge sparse box: cells capped by the particle count */
    CHECK(psim_grid_init(&g, 1e9, 0.5, 2.0 * (0.5), 100, 0, NULL) == 0);
    CHECK(g.G <= 20);
    psim_grid_free(&g);
    /* radius larger than the box: one cell */
    CHECK(psim_grid_init(&g, 1.0, 5.0, 2.0 * (5.0), 100, 0, NULL) == 0);
    CHECK(g.G == 1 && g.ntiles == 1);
    psim_grid_free(&g);
}

/* The grid spans the disks' bounding box; walls only near the box's walls. */
static void test_grid_bbox(void)
{
    psim_grid g;
    /* a cluster in [100, 200]^2 of a box of side 1e6 */
    double bbox[4] = {100, 100, 200, 200};
    CHECK(psim_grid_init(&g, 1e6, 1.0, 2.0 * (1.0), 30000, 4, bbox) == 0);
    CHECK(g.G == 49 && g.h > 2.0 && g.x0 == 100 && g.y0 == 100);
    CHECK(psim_grid_coord(&g, 150.0, g.x0) == (int)(50.0 / g.h));
    CHECK(psim_grid_coord(&g, 99.0, g.x0) == 0);     /* clamped */
    CHECK(psim_grid_coord(&g, 5e5, g.x0) == g.G - 1);
    /* far from every wall: only border tiles (holding clamped disks) test walls */
    for (uint32_t t = 0; t < g.ntiles; t++) {
        int border = g.tile_x[t] == 0 || g.tile_y[t] == 0 ||
                     g.tile_x[t] == g.TG - 1 || g.tile_y[t] == g.TG - 1;
        CHECK(g.tile_wall[t] == border);
    }
    psim_grid_free(&g);

    /* a region reaching past the right wall: cells within r of x = L are
     * wall cells even inside the grid */
    double over[4] = {0, 0, 200, 200};
    CHECK(psim_grid_init(&g, 100.0, 1.0, 2.0 * (1.0), 40000, 1, over) == 0);
    for (uint32_t c = 0; c < g.ncells; c++) {
        double xlo = g.x0 + g.cell_x[c] * g.h, xhi = xlo + g.h;
        if (xlo < 99.0 && xhi > 99.0) /* holds x + r = L */
            CHECK(g.tile_wall[psim_grid_tile_of_cell(&g, c)]);
        if (g.cell_x[c] > 1 && g.cell_y[c] > 1 && xhi < 98.0 && g.cell_y[c] < g.G - 1 &&
            g.y0 + (g.cell_y[c] + 1) * g.h < 98.0)
            CHECK(!g.tile_wall[psim_grid_tile_of_cell(&g, c)]);
    }
    psim_grid_free(&g);

    /* all disks at one point: one cell */
    double point[4] = {5, 5, 5, 5};
    CHECK(psim_grid_init(&g, 10.0, 1.0, 2.0 * (1.0), 100, 0, point) == 0);
    CHECK(g.G == 1);
    psim_grid_free(&g);
}

int main(void)
{
    test_morton();
    test_grid_ranks();
    test_grid_cuts();
    test_grid_clamp();
    test_grid_bbox();
    return check_done();
}
