/* psim --version (version.h). */
#include <stdio.h>

#ifndef PSIM_NO_HWLOC
#include <hwloc.h>
#endif
#include <omp.h>

#include "version.h"
#include "psim/psim.h"

/* psim --version (and every subcommand's): the release, the git commit
 * psim was built from, the build's options and what it runs with. */
void cli_version(FILE *f)
{
    fprintf(f, "psim %s (git %s)\n", PSIM_VERSION, psim_git_commit);
#ifdef PSIM_BUILD_OPTIONS
    fprintf(f, "built: %s\n", PSIM_BUILD_OPTIONS);
#endif
#ifdef PSIM_BUILD_FEATURES
    fprintf(f, "features: %s\n", PSIM_BUILD_FEATURES);
#endif
#ifdef PSIM_NO_HWLOC
    fprintf(f, "with: OpenMP %d, no hwloc\n", _OPENMP);
#else
    unsigned h = hwloc_get_api_version();
    fprintf(f, "with: OpenMP %d, hwloc API %u.%u\n", _OPENMP, h >> 16, (h >> 8) & 0xff);
#endif
}

