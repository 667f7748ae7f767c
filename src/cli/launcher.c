/* The rank an MPI launcher started this process as, from its environment
 * (see launcher.h). */
#include "launcher.h"

#include <stdlib.h>

/* A non-negative integer variable, or -1 when unset or not one. */
static int env_int(const char *name)
{
    const char *s = getenv(name);
    char *end;
    if (!s || !*s)
        return -1;
    long v = strtol(s, &end, 10);
    return *end || v < 0 || v > 1 << 30 ? -1 : (int)v;
}

/* One launcher's variable names: rank, size, local rank, local size. */
static const char *const names[][4] = {
    {"OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_LOCAL_RANK",
     "OMPI_COMM_WORLD_LOCAL_SIZE"},
    {"PMIX_RANK", NULL, NULL, NULL},
    {"PMI_RANK", "PMI_SIZE", "MPI_LOCALRANKID", "MPI_LOCALNRANKS"},
    {"SLURM_PROCID", "SLURM_NTASKS", "SLURM_LOCALID", "SLURM_NTASKS_PER_NODE"},
};

static void set(int *p, int v)
{
    if (p)
        *p = v;
}

int cli_launcher_rank(int *rank, int *size, int *local_rank, int *local_size)
{
    int v[4] = {0, 1, 0, 1}, found = 0;
    for (size_t k = 0; k < sizeof names / sizeof names[0] && !found; k++) {
        int r = env_int(names[k][0]);
        int n = names[k][1] ? env_int(names[k][1]) : -1;
        if (r < 0 || (n >= 0 && r >= n))
            continue;
        int lr = names[k][2] ? env_int(names[k][2]) : -1;
        int ln = names[k][3] ? env_int(names[k][3]) : -1;
        found = 1;
        v[0] = r;
        v[1] = n > 0 ? n : 0;
        v[2] = lr >= 0 && lr < ln ? lr : r;
        v[3] = lr >= 0 && lr < ln ? ln : v[1];
    }
    set(rank, v[0]);
    set(size, v[1]);
    set(local_rank, v[2]);
    set(local_size, v[3]);
    return found;
}
