/* The GPU paths' host-side plans (engine/gpu_grid.h, the force model's
 * models/force/gpu_plan.h): cells no narrower than the reach, so that
 * every pair within it is in adjacent cells; the cells around a cell held inside the grid; blocks of
 * a launch; device memory and its overflow; and law.h's force, which the
 * kernels and the CPU path share.  Runs on every build, CUDA or not. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "check.h"
#include "engine/gpu_grid.h"
#include "models/force/gpu_plan.h"
#include "models/force/law.h"

/* A pair within the cutoff is never more than one cell apart. */
static void test_grid_reach(double size, double cutoff)
{
    psim_gpu_grid g;
    CHECK(psim_gpu_grid_plan(size, cutoff, 1000000000L, &g) == 0);
    CHECK(g.side >= 1 && g.side <= PSIM_GPU_MAX_SIDE);
    CHECK(size / g.side >= cutoff || g.side == 1);
    srand(7);
    for (int k = 0; k < 200000; k++) {
        double px = size * rand() / RAND_MAX, py = size * rand() / RAND_MAX;
        double a = 6.283185307179586 * rand() / RAND_MAX;
        double d = cutoff * rand() / RAND_MAX;
        if (k % 4 == 0)
            d = cutoff;   /* on the cutoff itself */
        double qx = px + d * cos(a), qy = py + d * sin(a);
        double dx = qx - px, dy = qy - py;
        if (qx < 0 || qx > size || qy < 0 || qy > size || dx * dx + dy * dy > cutoff * cutoff)
            continue;
        int32_t ex = psim_gpu_cell(&g, px) - psim_gpu_cell(&g, qx);
        int32_t ey = psim_gpu_cell(&g, py) - psim_gpu_cell(&g, qy);
        CHECK_MSG(ex >= -1 && ex <= 1 && ey >= -1 && ey <= 1,
                  "size %g cutoff %g: (%.17g, %.17g) and (%.17g, %.17g) %d, %d cells apart",
                  size, cutoff, px, py, qx, qy, ex, ey);
    }
}

static void test_grid(void)
{
    psim_gpu_grid g;
    /* CS267's box for 1e4 particles: sqrt(0.0005 * 1e4), cutoff 0.01 */
    CHECK(psim_gpu_grid_plan(sqrt(5.0), 0.01, 10000, &g) == 0);
    CHECK(g.side == 142);   /* cells the cutoff allows: 223; 2e4 cells: 142 */
    CHECK(g.key_bits == 15);   /* keys up to 142 * 142 - 1 = 20163 */
    CHECK(psim_gpu_grid_plan(sqrt(5.0), 0.01, 1000000000L, &g) == 0);
    CHECK(g.side == 223);   /* as many as the cutoff allows */
    CHECK(psim_gpu_grid_plan(1.0, 2.0, 100, &g) == 0 && g.side == 1 && g.key_bits == 1);
    CHECK(psim_gpu_grid_plan(1.0, 0.5, 0, &g) == 0 && g.side == 1);
    CHECK(psim_gpu_grid_plan(1.0, 1e-9, 1000000000L, &g) == 0 && g.side == 44722);
    CHECK(psim_gpu_grid_plan(1.0, 1e-9, 4000000000L, &g) == 0 && g.side == PSIM_GPU_MAX_SIDE &&
          g.key_bits == 32);
    CHECK(psim_gpu_grid_plan(0, 0.01, 10, &g) == -1);
    CHECK(psim_gpu_grid_plan(1, 0, 10, &g) == -1);
    CHECK(psim_gpu_grid_plan(NAN, 0.01, 10, &g) == -1);
    CHECK(psim_gpu_grid_plan(1, INFINITY, 10, &g) == -1);
    test_grid_reach(sqrt(0.5), 0.01);
    test_grid_reach(1.0, 0.1);   /* 10 cells wide of exactly the cutoff, but for the room */
    test_grid_reach(709.0, 4.0);
}

static void test_cells(void)
{
    psim_gpu_grid g;
    CHECK(psim_gpu_grid_plan(10.0, 1.0, 1000, &g) == 0);
    CHECK(g.side == 9);
    CHECK(psim_gpu_cell(&g, 0) == 0);
    CHECK(psim_gpu_cell(&g, 10.0) == 8);
    CHECK(psim_gpu_cell(&g, -3.0) == 0);
    CHECK(psim_gpu_cell(&g, 1e300) == 8);
    CHECK(psim_gpu_cell(&g, NAN) == 0);
    CHECK(psim_gpu_cell(&g, 5.0) == 4);
    CHECK(psim_gpu_key(&g, 5.0, 10.0) == 8 * 9 + 4);
    psim_gpu_range r = psim_gpu_around(&g, 0, 0);
    CHECK(r.x0 == 0 && r.x1 == 1 && r.y0 == 0 && r.y1 == 1);
    r = psim_gpu_around(&g, 8, 8);
    CHECK(r.x0 == 7 && r.x1 == 8 && r.y0 == 7 && r.y1 == 8);
    r = psim_gpu_around(&g, 4, 0);
    CHECK(r.x0 == 3 && r.x1 == 5 && r.y0 == 0 && r.y1 == 1);
    CHECK(psim_gpu_grid_plan(1.0, 2.0, 1000, &g) == 0);
    r = psim_gpu_around(&g, 0, 0);
    CHECK(r.x0 == 0 && r.x1 == 0 && r.y0 == 0 && r.y1 == 0);
}

static void test_blocks(void)
{
    CHECK(psim_gpu_blocks(0) == 0);
    CHECK(psim_gpu_blocks(1) == 1);
    CHECK(psim_gpu_blocks(PSIM_GPU_THREADS) == 1);
    CHECK(psim_gpu_blocks(PSIM_GPU_THREADS + 1) == 2);
    CHECK(psim_gpu_blocks(10000000) == (10000000 + PSIM_GPU_THREADS - 1) / PSIM_GPU_THREADS);
    CHECK(psim_gpu_blocks(-1) == -1);
    CHECK(psim_gpu_blocks((long)INT32_MAX * PSIM_GPU_THREADS) == INT32_MAX);
    CHECK(psim_gpu_blocks((long)INT32_MAX * PSIM_GPU_THREADS + 1) == -1);
}

static void test_bytes(void)
{
    psim_gpu_grid g;
    size_t total = 0;
    CHECK(FGPU_BYTES_PARTICLE == 88);   /* x y vx vy id key place, twice */
    CHECK(psim_gpu_grid_plan(sqrt(0.5), 0.01, 1000, &g) == 0);
    CHECK(g.side == 45);   /* 2025 cells, about 2 a particle */
    CHECK(fgpu_bytes(1000, &g, 4096, &total) == 0);
    CHECK(total == 1000 * 88 + 2025 * 8 + 4096);
    CHECK(fgpu_bytes(0, &g, 0, &total) == 0 && total == 2025 * 8);
    CHECK(fgpu_bytes(-1, &g, 0, &total) == -1);
    CHECK(fgpu_bytes((long)INT32_MAX + 1, &g, 0, &total) == -1);
    CHECK(fgpu_bytes((long)INT32_MAX, &g, 0, &total) == 0);
    CHECK(fgpu_bytes(1000, &g, SIZE_MAX - 10, &total) == -1);
    CHECK(psim_gpu_grid_plan(1.0, 1e-9, 4000000000L, &g) == 0);   /* 65535^2 cells, 34 GB */
    CHECK(fgpu_bytes(1, &g, 0, &total) == 0 && total == 88 + (size_t)65535 * 65535 * 8);
}

/* flaw_pair, which the CPU path sums with, is flaw_force's force added:
 * the kernels' sums of flaw_force's forces in the same order are the
 * same bits. */
static void test_law(void)
{
    flaw k = {.size = 1, .cutoff = 0.01, .mass = 0.01, .dt = 0.0005};
    k.cutoff2 = k.cutoff * k.cutoff;
    k.min_r2 = (k.cutoff / 100) * (k.cutoff / 100);
    double ax = 0.25, ay = -0.5, fx, fy;
    CHECK(flaw_force(&k, 0.5, 0.5, 0.503, 0.4991, &fx, &fy) == 1);
    CHECK(flaw_pair(&k, 0.5, 0.5, 0.503, 0.4991, &ax, &ay) == 1);
    CHECK(ax == 0.25 + fx && ay == -0.5 + fy);
    CHECK(fx < 0 && fy > 0);   /* repulsion: away from q */
    CHECK(flaw_force(&k, 0.5, 0.5, 0.52, 0.5, &fx, &fy) == 0);
}

int main(void)
{
    test_grid();
    test_cells();
    test_blocks();
    test_bytes();
    test_law();
    return check_done();
}
