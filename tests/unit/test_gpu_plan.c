/* The GPU paths' host-side plans (engine/gpu_grid.h, the force model's
 * models/force/gpu_plan.h): cells no narrower than the reach, so that
 * every pair within it is in adjacent cells; the cells around a cell held inside the grid; blocks of
 * a launch; device memory and its overflow; law.h's force, which the
 * kernels and the CPU path share; and the ccd model's: its candidates'
 * sort keys give the CPU path's total order, and its cells hold every
 * pair the rules can make a candidate of in adjacent cells.  Runs on every build, CUDA or not. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "engine/gpu_grid.h"
#include "models/ccd/cand.h"
#include "models/ccd/ccd.h"
#include "models/ccd/rules.h"
#include "models/ccd/sweep.h"
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

/* The ccd model's order (order.c's ccd_cand_cmp): time, then P, then Q
 * with the wall (-1) first. */
static int cand_cmp(const void *a, const void *b)
{
    return ccd_cand_cmp(a, b);
}

/* The GPU path's order: by the time key, then the id key (its stable
 * radix sorts, by id key then by time key). */
static int key_cmp(const void *pa, const void *pb)
{
    const ccand *a = pa, *b = pb;
    uint64_t ta = ccd_time_key(a->t), tb = ccd_time_key(b->t);
    if (ta != tb)
        return ta < tb ? -1 : 1;
    uint64_t ia = ccd_id_key(a->p, a->q), ib = ccd_id_key(b->p, b->q);
    return (ia > ib) - (ia < ib);
}

static void test_ccd_keys(void)
{
    enum { N = 20000 };
    static ccand a[N], b[N];
    const double times[] = {0.0, -0.0, 1.0, 0.5, 0.25, 1e-300, 4.9e-324, -1e-300, -2.5,
                            0.9999999999999999, INFINITY, -INFINITY, 1e300, 0.1};
    srand(11);
    for (int k = 0; k < N; k++) {
        a[k].t = k % 3 ? (double)rand() / RAND_MAX
                       : times[rand() % (int)(sizeof times / sizeof times[0])];
        a[k].p = rand() % 50;
        a[k].q = rand() % 4 == 0 ? -1 : a[k].p + 1 + rand() % 50;
        if (k % 97 == 0)
            a[k].p = INT32_MAX - 1, a[k].q = k % 2 ? -1 : INT32_MAX;
    }
    memcpy(b, a, sizeof a);
    qsort(a, N, sizeof *a, cand_cmp);
    qsort(b, N, sizeof *b, key_cmp);
    int same = 1;
    for (int k = 0; k < N && same; k++)
        same = a[k].p == b[k].p && a[k].q == b[k].q && a[k].t == b[k].t;
    CHECK_MSG(same, "the keys' order is not the total order");
    CHECK(ccd_time_key(-0.0) == ccd_time_key(0.0));
    CHECK(ccd_time_key(-1.0) < ccd_time_key(-0.5) && ccd_time_key(0.5) < ccd_time_key(1.0));
    CHECK(ccd_id_key(3, -1) < ccd_id_key(3, 4) && ccd_id_key(3, INT32_MAX) < ccd_id_key(4, -1));
}

/* Every pair the rules make a candidate of (within a step, speeds up to
 * vmax = |vx| + |vy|) is in adjacent cells of a grid at least ccd_reach
 * wide, and their swept boxes (ccd_box) overlap. */
static void test_ccd_reach(double L, double r, double vmax)
{
    psim_gpu_grid g;
    CHECK(psim_gpu_grid_plan(L, ccd_reach(L, r, vmax), 1000000000L, &g) == 0);
    srand(13);
    int found = 0;
    for (int k = 0; k < 400000; k++) {
        double R = ccd_reach(L, r, vmax);
        double px = L * rand() / RAND_MAX, py = L * rand() / RAND_MAX;
        double qx = px + R * (2.0 * rand() / RAND_MAX - 1);
        double qy = py + R * (2.0 * rand() / RAND_MAX - 1);
        double v[4], t;
        for (int j = 0; j < 4; j += 2) {
            double share = (double)rand() / RAND_MAX, s = vmax * rand() / RAND_MAX;
            v[j] = (rand() % 2 ? s : -s) * share;
            v[j + 1] = (rand() % 2 ? s : -s) * (1 - share);
        }
        if (qx < 0 || qx > L || qy < 0 || qy > L ||
            !ccd_pair_time(px, py, v[0], v[1], qx, qy, v[2], v[3], r, &t))
            continue;
        found++;
        double bp[4], bq[4], grow = r + ccd_margin_of(L, r, vmax);
        ccd_box(px, py, v[0], v[1], grow, bp);
        ccd_box(qx, qy, v[2], v[3], grow, bq);
        CHECK_MSG(bp[0] <= bq[1] && bq[0] <= bp[1] && bp[2] <= bq[3] && bq[2] <= bp[3],
                  "L %g r %g vmax %g: a candidate whose boxes do not overlap", L, r, vmax);
        int32_t ex = psim_gpu_cell(&g, px) - psim_gpu_cell(&g, qx);
        int32_t ey = psim_gpu_cell(&g, py) - psim_gpu_cell(&g, qy);
        CHECK_MSG(ex >= -1 && ex <= 1 && ey >= -1 && ey <= 1,
                  "L %g r %g vmax %g: a candidate %d, %d cells apart", L, r, vmax, ex, ey);
    }
    CHECK_MSG(found > 1000, "L %g r %g vmax %g: %d candidates made", L, r, vmax, found);
}

/* The GPU path's ccd search (sweep.h) run on the CPU, its sort and boxes
 * made as the device makes them, against every pair: the same
 * candidates, each pair met once. */
typedef struct sdisk {
    uint32_t band;
    uint64_t edge;
    uint32_t place;
} sdisk;

static int sdisk_cmp(const void *pa, const void *pb)
{
    const sdisk *a = pa, *b = pb;
    if (a->band != b->band)
        return a->band < b->band ? -1 : 1;
    if (a->edge != b->edge)
        return a->edge < b->edge ? -1 : 1;
    return (a->place > b->place) - (a->place < b->place);   /* (stable) */
}

static int cand_pq_cmp(const void *pa, const void *pb)
{
    const ccand *a = pa, *b = pb;
    if (a->p != b->p)
        return a->p < b->p ? -1 : 1;
    return (a->q > b->q) - (a->q < b->q);
}

/* n disks in a box of L, radius r, velocity components up to v (and
 * `fast` of them up to 40 v): the sweep's candidates are every pair's. */
static void test_ccd_sweep(uint32_t n, double L, double r, double v, uint32_t fast,
                           unsigned seed)
{
    double *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y);
    double *vx = malloc(n * sizeof *vx), *vy = malloc(n * sizeof *vy);
    double *b4 = malloc(4 * (size_t)n * sizeof *b4);
    int32_t *id = malloc(n * sizeof *id);
    uint32_t *band = malloc(n * sizeof *band);
    sdisk *sd = malloc(n * sizeof *sd);
    size_t most = (size_t)n * (n - 1) / 2 + 1;
    ccand *got = malloc(most * sizeof *got), *want = malloc(most * sizeof *want);
    uint8_t *met = calloc((size_t)n * n, 1);
    srand(seed);
    double vmax = 0;
    for (uint32_t k = 0; k < n; k++) {
        double s = k < fast ? 40 * v : v;
        x[k] = L * rand() / RAND_MAX, y[k] = L * rand() / RAND_MAX;
        vx[k] = s * (2.0 * rand() / RAND_MAX - 1), vy[k] = s * (2.0 * rand() / RAND_MAX - 1);
        id[k] = (int32_t)((k * 7919u) % n);   /* ids not in place order */
        double d = fabs(vx[k]) + fabs(vy[k]);
        vmax = d > vmax ? d : vmax;
    }
    /* the bands and the sort, as gpu.cu's fit_bands and sort_disks */
    double reach = ccd_reach(L, r, vmax), want_h = fmin(reach * 1.1, L * 2);
    psim_gpu_grid g;
    CHECK(psim_gpu_grid_plan(L, want_h > reach ? want_h : reach, (long)n, &g) == 0);
    const double grow = r + ccd_margin_of(L, r, vmax);
    for (uint32_t k = 0; k < n; k++) {
        double b[4];
        ccd_box(x[k], 0, vx[k], 0, grow, b);
        sd[k] = (sdisk){(uint32_t)psim_gpu_cell(&g, y[k]), ccd_time_key(b[0]), k};
    }
    qsort(sd, n, sizeof *sd, sdisk_cmp);
    double *sx = malloc(n * sizeof *sx), *sy = malloc(n * sizeof *sy);
    double *su = malloc(n * sizeof *su), *sw = malloc(n * sizeof *sw);
    int32_t *sid = malloc(n * sizeof *sid);
    uint32_t *start = calloc((size_t)g.side, sizeof *start), *end = calloc((size_t)g.side, sizeof *end);
    double wmax = 0;
    for (uint32_t k = 0; k < n; k++) {
        uint32_t i = sd[k].place;
        sx[k] = x[i], sy[k] = y[i], su[k] = vx[i], sw[k] = vy[i], sid[k] = id[i];
        band[k] = sd[k].band;
        if (k == 0 || band[k - 1] != band[k])
            start[band[k]] = k;
        end[band[k]] = k + 1;
        double *b = b4 + 4 * (size_t)k;
        ccd_box(sx[k], sy[k], su[k], sw[k], grow, b);
        wmax = b[1] - b[0] > wmax ? b[1] - b[0] : wmax;
    }
    double *bx0 = malloc(n * sizeof *bx0), *bx1 = malloc(n * sizeof *bx1);
    double *by0 = malloc(n * sizeof *by0), *by1 = malloc(n * sizeof *by1);
    for (uint32_t k = 0; k < n; k++)
        bx0[k] = b4[4 * k], bx1[k] = b4[4 * k + 1], by0[k] = b4[4 * k + 2], by1[k] = b4[4 * k + 3];
    ccd_sweep S = {n, (uint32_t)g.side, band, start, end, bx0, bx1, by0, by1, wmax};
    size_t ng = 0, nw = 0, twice = 0;
    for (uint32_t i = 0; i < n; i++) {
        ccd_walk w;
        uint32_t j;
        for (ccd_walk_start(&S, i, &w); ccd_walk_next(&S, &w, &j);) {
            uint8_t *m = &met[(size_t)(i < j ? i : j) * n + (i < j ? j : i)];
            twice += *m + (i == j);   /* (a disk with itself counts too) */
            *m = 1;
            if (ccd_pair_test(i, j, sx, sy, su, sw, sid, r, &got[ng]))
                ng++;
        }
    }
    /* every pair, the lower id first */
    for (uint32_t a = 0; a < n; a++)
        for (uint32_t b = a + 1; b < n; b++) {
            uint32_t p = id[a] < id[b] ? a : b, q = id[a] < id[b] ? b : a;
            ccand c = {0, id[p], id[q], 0, 0};
            if (ccd_pair_time(x[p], y[p], vx[p], vy[p], x[q], y[q], vx[q], vy[q], r, &c.t))
                want[nw++] = c;
        }
    qsort(got, ng, sizeof *got, cand_pq_cmp);
    qsort(want, nw, sizeof *want, cand_pq_cmp);
    int same = ng == nw;
    for (size_t k = 0; same && k < nw; k++)
        same = got[k].p == want[k].p && got[k].q == want[k].q &&
               memcmp(&got[k].t, &want[k].t, sizeof got[k].t) == 0;
    CHECK_MSG(same, "n %u L %g v %g: the sweep found %zu candidates, every pair gives %zu", n,
              L, v, ng, nw);
    CHECK_MSG(twice == 0, "n %u L %g v %g: %zu pairs met twice (or a disk itself)", n, L, v,
              twice);
    CHECK_MSG(nw >= 20, "n %u L %g v %g: only %zu candidates", n, L, v, nw);
    free(x), free(y), free(vx), free(vy), free(b4), free(id), free(band), free(sd);
    free(got), free(want), free(met), free(sx), free(sy), free(su), free(sw), free(sid);
    free(start), free(end), free(bx0), free(bx1), free(by0), free(by1);
}

int main(void)
{
    test_grid();
    test_cells();
    test_blocks();
    test_bytes();
    test_law();
    test_ccd_keys();
    test_ccd_reach(1000.0, 1.0, 2.0);
    test_ccd_reach(20000.0, 0.5, 10.0);
    test_ccd_reach(50.0, 2.0, 0.1);
    test_ccd_reach(1000.0, 10.0, 300.0);
    test_ccd_sweep(2000, 28284.3, 1.0, 28284.3 / 6, 0, 3);   /* the course generator's */
    test_ccd_sweep(3000, 137.3, 1.0, 1.0, 0, 5);             /* slow and crowded: bands */
    test_ccd_sweep(3000, 300.0, 1.0, 0.5, 30, 7);            /* a few fast among slow */
    test_ccd_sweep(1500, 60.0, 2.0, 3.0, 0, 9);              /* fast and crowded */   /* the course generator's: a third of the box a step */
    return check_done();
}
