/* bench/task_overhead: the cost of one OpenMP task with depend clauses, as
 * psim's resolution creates them (tile tasks with one inout, edge tasks
 * with two), measured with empty task bodies.
 * usage: task_overhead [TASKS [TILES]] (threads from OMP_NUM_THREADS) */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
    long tasks = argc > 1 ? atol(argv[1]) : 200000;
    int tiles = argc > 2 ? atoi(argv[2]) : 100;
    char *dep = calloc((size_t)tiles + 1, 1);
    volatile long sink = 0;
    double best = 1e30;
    for (int rep = 0; rep < 5; rep++) {
        double t0 = omp_get_wtime();
#pragma omp parallel
#pragma omp single
        {
            for (long k = 0; k < tasks; k += tiles) {
                for (int t = 0; t < tiles; t++) {
#pragma omp task depend(inout : dep[t])
                    sink++;
                }
                for (int t = 0; t + 1 < tiles; t++) {
#pragma omp task depend(inout : dep[t]) depend(inout : dep[t + 1])
                    sink++;
                }
#pragma omp taskwait
            }
        }
        double dt = omp_get_wtime() - t0;
        if (dt < best)
            best = dt;
    }
    long made = (tasks / tiles) * (2L * tiles - 1);
    printf("threads %d: %.3f us per task (%ld tasks, %d tiles, best of 5)\n",
           omp_get_max_threads(), 1e6 * best / (double)made, made, tiles);
    free(dep);
    return 0;
}
