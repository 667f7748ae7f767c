#include "timer.h"

#include <time.h>

double psim_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#ifdef PSIM_LIKWID
#include <stdlib.h>

#include <omp.h>

#include <likwid-marker.h>

/* Under likwid-perfctr -m: the regions are measured (else every call
 * returns at once, without forking the team). */
static int markers_on;

void psim_markers_init(void)
{
    /* likwid-perfctr -m says what to measure in these; without them
     * LIKWID's own init would only print that it runs without markers */
    if (!getenv("LIKWID_MODE") || !getenv("LIKWID_FILEPATH") || !getenv("LIKWID_EVENTS") ||
        !getenv("LIKWID_THREADS"))
        return;
    LIKWID_MARKER_INIT;
    markers_on = 1;
}

void psim_markers_threads(int threads)
{
    if (!markers_on)
        return;
    /* each thread of the team registers, and is pinned to a CPU of
     * likwid-perfctr -C's list of its own */
#pragma omp parallel num_threads(threads)
    LIKWID_MARKER_THREADINIT;
}

void psim_markers_close(void)
{
    if (markers_on)
        LIKWID_MARKER_CLOSE;
    markers_on = 0;
}

/* LIKWID counts per CPU: a region is started and stopped by the thread on
 * each CPU of the team.  The team's threads are those of the parallel
 * regions of the phase (the OpenMP runtime keeps a team's threads), each
 * pinned to its CPU by psim_markers_threads. */
void psim_region_begin(int threads, const char *name)
{
    if (!markers_on)
        return;
    if (threads <= 1 || omp_in_parallel()) {
        LIKWID_MARKER_START(name);
        return;
    }
#pragma omp parallel num_threads(threads)
    LIKWID_MARKER_START(name);
}

void psim_region_end(int threads, const char *name)
{
    if (!markers_on)
        return;
    if (threads <= 1 || omp_in_parallel()) {
        LIKWID_MARKER_STOP(name);
        return;
    }
#pragma omp parallel num_threads(threads)
    LIKWID_MARKER_STOP(name);
}

void psim_region_thread_begin(const char *name)
{
    if (markers_on)
        LIKWID_MARKER_START(name);
}

void psim_region_thread_end(const char *name)
{
    if (markers_on)
        LIKWID_MARKER_STOP(name);
}
#endif
