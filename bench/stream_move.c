/* bench/stream_move: what one pass of the force model's move costs at
 * the least on this machine: x, y, vx, vy of N particles (doubles, a
 * structure of arrays as psim's store) read and written once, with no
 * force, no bookkeeping and no other data.  It bounds the move phase from
 * below and tells whether N particles' state streams from a cache or from
 * memory (docs/performance.md, "Memory bandwidth").  With OMP_NUM_THREADS=T
 * the particles are split over T threads (static shares, each written
 * first by its own thread), which tells whether the cores share what the
 * state streams from (the same section).
 * usage: stream_move [N [PASSES]]   (default 1000000 particles, 30 passes;
 * prints the fastest pass and the median, in ns a particle and GB/s) */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <omp.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* One pass: the course's kick (with a tiny factor for the force) and drift. */
static void pass(size_t n, double *restrict x, double *restrict y, double *restrict vx,
                 double *restrict vy)
{
    const double dt = 0.0005;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) {
        double ux = vx[i] * 1.0000001, uy = vy[i] * 0.9999999;
        vx[i] = ux;
        vy[i] = uy;
        x[i] += ux * dt;
        y[i] += uy * dt;
    }
}

int main(int argc, char **argv)
{
    size_t n = argc > 1 ? (size_t)atol(argv[1]) : 1000000;
    int passes = argc > 2 ? atoi(argv[2]) : 30;
    if (n == 0 || passes < 1) {
        fprintf(stderr, "usage: stream_move [N [PASSES]]\n");
        return 2;
    }
    double *a[4], *t = malloc((size_t)passes * sizeof *t);
    for (int k = 0; k < 4; k++) {
        a[k] = aligned_alloc(64, (n * sizeof(double) + 63) / 64 * 64);
        if (!a[k] || !t) {
            fprintf(stderr, "stream_move: out of memory\n");
            return 1;
        }
#pragma omp parallel for schedule(static)
        for (size_t i = 0; i < n; i++)
            a[k][i] = k < 2 ? (double)i : 1e-3 * (k == 2 ? 1 : -1);
    }
    for (int p = 0; p < passes; p++) {
        double t0 = now();
        pass(n, a[0], a[1], a[2], a[3]);
        t[p] = now() - t0;
    }
    qsort(t, (size_t)passes, sizeof *t, by_value);
    double bytes = 64.0 * (double)n;   /* 32 read and 32 written a particle */
    printf("n %zu  threads %d  passes %d  fastest %.3f ms (%.2f ns a particle, %.1f GB/s)  "
           "median %.3f ms (%.2f ns, %.1f GB/s)  check %g\n",
           n, omp_get_max_threads(), passes, 1e3 * t[0], 1e9 * t[0] / (double)n, bytes / t[0] / 1e9,
           1e3 * t[passes / 2], 1e9 * t[passes / 2] / (double)n, bytes / t[passes / 2] / 1e9,
           a[0][n / 2] + a[1][n / 2]);
    for (int k = 0; k < 4; k++)
        free(a[k]);
    free(t);
    return 0;
}
