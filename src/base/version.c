/* The library's version (psim_version, include/psim/psim.h). */
#include "psim/psim.h"

const char *psim_version(void) { return PSIM_VERSION; }
