/*
 * baseline.c - plain single-threaded cell-list reference for the NUS CS3210
 * AY2024/25 "discrete" particle model.  This is the baseline that every
 * benchmark table in docs/performance.md compares psim against.  It is kept
 * deliberately simple: no threads, no SIMD tricks, no clever data layout.
 *
 * Build:  gcc -O2 -std=c11 -Wall -Wextra -Werror -o baseline bench/baseline.c -lm
 * Usage:  baseline SCENE [OUTFILE]
 *
 * Scene: lines N, L, r, S (integers), then N lines "i x y vx vy".
 *
 * One step:
 *   1. every disk moves: x += vx, y += vy;
 *   2. the cell lists are rebuilt (counting sort, cells keep id order);
 *   3. with positions frozen, full sweeps are repeated until a sweep resolves
 *      nothing.  A sweep first applies the wall rule to every particle in id
 *      order, then visits every unordered pair in the same or neighbouring
 *      cells once: for i in id order, for the 9 cells around i's cell in
 *      row-major order (dy = -1..1, dx = -1..1), for j > i in id order.
 *
 * Output (if OUTFILE is given): one line per particle in id order,
 * "S i x y vx vy" with "%.17g".  Counters go to stderr.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct {
    double x, y, vx, vy;
} particle;

static void die(const char *msg, const char *path)
{
    fprintf(stderr, "baseline: %s: %s\n", path, msg);
    exit(1);
}

static int cell_coord(double p, double cell, int g)
{
    double c = floor(p / cell);
    if (!(c >= 0.0)) /* also catches NaN */
        return 0;
    if (c >= (double)g)
        return g - 1;
    return (int)c;
}

int main(int argc, char **argv)
{
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: %s SCENE [OUTFILE]\n", argv[0]);
        return 1;
    }
    const char *scene = argv[1];
    FILE *in = fopen(scene, "r");
    if (!in) {
        perror(scene);
        return 1;
    }
    long n, L_i, r_i, steps;
    if (fscanf(in, "%ld %ld %ld %ld", &n, &L_i, &r_i, &steps) != 4)
        die("malformed header (expected N, L, r, S)", scene);
    if (n < 0 || L_i <= 0 || r_i <= 0 || steps < 0)
        die("header values out of range", scene);

    particle *p = calloc(n > 0 ? (size_t)n : 1, sizeof *p);
    unsigned char *seen = calloc(n > 0 ? (size_t)n : 1, 1);
    if (!p || !seen)
        die("out of memory", scene);
    for (long k = 0; k < n; k++) {
        long id;
        double x, y, vx, vy;
        if (fscanf(in, "%ld %lf %lf %lf %lf", &id, &x, &y, &vx, &vy) != 5)
            die("malformed particle line", scene);
        if (id < 0 || id >= n || seen[id])
            die("particle id out of range or repeated", scene);
        seen[id] = 1;
        p[id] = (particle){x, y, vx, vy};
    }
    fclose(in);
    free(seen);

    const double L = (double)L_i, r = (double)r_i;
    const double d2max = (2.0 * r) * (2.0 * r);
    long g_l = (long)floor(L / (2.0 * r));
    if (g_l < 1)
        g_l = 1;
    if (g_l > 1 << 15) /* keep the grid array sane for tiny radii */
        g_l = 1 << 15;
    const int g = (int)g_l;
    const double cell = L / g; /* >= 2r */
    const size_t ncells = (size_t)g * (size_t)g;

    int *cell_of = malloc((n > 0 ? (size_t)n : 1) * sizeof *cell_of);
    int *start = malloc((ncells + 1) * sizeof *start);
    int *fill = malloc(ncells * sizeof *fill);
    int *order = malloc((n > 0 ? (size_t)n : 1) * sizeof *order);
    if (!cell_of || !start || !fill || !order)
        die("out of memory", scene);

    long long pair_res = 0, wall_res = 0, sweeps = 0;
    struct timespec t0, t1;
    timespec_get(&t0, TIME_UTC);

    for (long step = 0; step < steps; step++) {
        /* 1. move */
        for (long i = 0; i < n; i++) {
            p[i].x += p[i].vx;
            p[i].y += p[i].vy;
        }
        /* 2. rebuild cell lists: counting sort, stable in id order */
        memset(start, 0, (ncells + 1) * sizeof *start);
        for (long i = 0; i < n; i++) {
            int c = cell_coord(p[i].y, cell, g) * g + cell_coord(p[i].x, cell, g);
            cell_of[i] = c;
            start[c + 1]++;
        }
        for (size_t c = 0; c < ncells; c++)
            start[c + 1] += start[c];
        memcpy(fill, start, ncells * sizeof *fill);
        for (long i = 0; i < n; i++)
            order[fill[cell_of[i]]++] = (int)i;

        /* 3. resolve until a sweep changes nothing */
        int changed = 1;
        while (changed) {
            changed = 0;
            sweeps++;
            for (long i = 0; i < n; i++) {
                particle *a = &p[i];
                if ((a->x - r <= 0 && a->vx < 0) || (a->x + r >= L && a->vx > 0)) {
                    a->vx = (a->x - r <= 0) ? fabs(a->vx) : -fabs(a->vx);
                    wall_res++;
                    changed = 1;
                }
                if ((a->y - r <= 0 && a->vy < 0) || (a->y + r >= L && a->vy > 0)) {
                    a->vy = (a->y - r <= 0) ? fabs(a->vy) : -fabs(a->vy);
                    wall_res++;
                    changed = 1;
                }
            }
            for (long i = 0; i < n; i++) {
                particle *a = &p[i];
                int cx = cell_of[i] % g, cy = cell_of[i] / g;
                for (int ny = cy - 1; ny <= cy + 1; ny++) {
                    if (ny < 0 || ny >= g)
                        continue;
                    for (int nx = cx - 1; nx <= cx + 1; nx++) {
                        if (nx < 0 || nx >= g)
                            continue;
                        int c = ny * g + nx;
                        for (int k = start[c]; k < start[c + 1]; k++) {
                            int j = order[k];
                            if (j <= i)
                                continue;
                            particle *b = &p[j];
                            double dx = b->x - a->x, dy = b->y - a->y;
                            double d2 = dx * dx + dy * dy;
                            if (d2 > d2max)
                                continue;
                            double dvx = b->vx - a->vx, dvy = b->vy - a->vy;
                            double dot = dvx * dx + dvy * dy;
                            if (!(dot < -1e-7))
                                continue;
                            double s = (dot < 0 ? dot : 0) / d2;
                            a->vx += s * dx;
                            a->vy += s * dy;
                            b->vx -= s * dx;
                            b->vy -= s * dy;
                            pair_res++;
                            changed = 1;
                        }
                    }
                }
            }
        }
    }

    timespec_get(&t1, TIME_UTC);
    double secs = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);

    if (argc == 3) {
        FILE *out = fopen(argv[2], "w");
        if (!out) {
            perror(argv[2]);
            return 1;
        }
        for (long i = 0; i < n; i++)
            fprintf(out, "%ld %ld %.17g %.17g %.17g %.17g\n", steps, i, p[i].x, p[i].y,
                    p[i].vx, p[i].vy);
        if (fclose(out) != 0) {
            perror(argv[2]);
            return 1;
        }
    }
    fprintf(stderr,
            "baseline: N=%ld L=%ld r=%ld S=%ld grid=%dx%d: %lld pair resolutions, "
            "%lld wall resolutions, %lld sweeps, %.3f s simulate\n",
            n, L_i, r_i, steps, g, g, pair_res, wall_res, sweeps, secs);

    free(p);
    free(cell_of);
    free(start);
    free(fill);
    free(order);
    return 0;
}
