/* The distributed engine (dist.h): MPI start-up, the exchanges of
 * particles between ranks, the gathered state for the writers. */
#include "dist.h"

#include <errno.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef PSIM_HAVE_MPI
#include <mpi.h>
#endif

#include "../base/error.h"
#include "dist_cut.h"
#include "engine.h"
#include "mem.h"
#include "timer.h"

static int g_rank, g_ranks = 1;

/* The variables a launcher sets in each process it starts. */
static const char *const launcher_vars[] = {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK",
                                            "PMI_SIZE"};

static int launched(void)
{
    for (size_t k = 0; k < sizeof launcher_vars / sizeof *launcher_vars; k++)
        if (getenv(launcher_vars[k]))
            return 1;
    return 0;
}

int psim_dist_rank(void) { return g_rank; }
int psim_dist_ranks(void) { return g_ranks; }

#ifdef PSIM_HAVE_MPI

static int g_started;

int psim_dist_start(int *argc, char ***argv, psim_error *err)
{
    if (!launched())
        return 1;
    int provided;
    /* MPI is called by the thread that runs main alone */
    if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS ||
        provided < MPI_THREAD_FUNNELED) {
        psim_error_set(err, "MPI could not start with threads (MPI_THREAD_FUNNELED)");
        return -1;
    }
    g_started = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &g_ranks);
    return g_ranks;
}

void psim_dist_finish(void)
{
    if (g_started)
        MPI_Finalize();
    g_started = 0;
}

int psim_dist_agree(int failed)
{
    if (g_ranks < 2)
        return failed ? 0 : -1;
    int mine = failed ? g_rank : g_ranks, low;
    MPI_Allreduce(&mine, &low, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    return low < g_ranks ? low : -1;
}

double psim_dist_max(double v)
{
    double m = v;
    if (g_ranks > 1)
        MPI_Allreduce(&v, &m, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    return m;
}

double psim_dist_sum(double v)
{
    double m = v;
    if (g_ranks > 1)
        MPI_Allreduce(&v, &m, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    return m;
}

_Noreturn void psim_dist_abort(int code)
{
    if (g_started)
        MPI_Abort(MPI_COMM_WORLD, code);
    exit(code);
}

#else /* without MPI: one process; a launcher's ranks are refused */

int psim_dist_start(int *argc, char ***argv, psim_error *err)
{
    (void)argc, (void)argv;
    const char *n = getenv("OMPI_COMM_WORLD_SIZE");
    if (!n)
        n = getenv("PMI_SIZE");
    if (launched() && n && atoi(n) > 1) {
        psim_error_set(err, "this psim was built without MPI (cmake -DPSIM_MPI=ON needs "
                            "libopenmpi-dev): it cannot run as %d ranks", atoi(n));
        return -1;
    }
    return 1;
}

void psim_dist_finish(void) {}
int psim_dist_agree(int failed) { return failed ? 0 : -1; }
double psim_dist_max(double v) { return v; }
double psim_dist_sum(double v) { return v; }
_Noreturn void psim_dist_abort(int code) { exit(code); }
#endif

_Noreturn void psim_dist_out_of_memory(const char *what)
{
    fprintf(stderr, "psim: rank %d: out of memory for %s\n", psim_dist_rank(), what);
    psim_dist_abort(1);
}
