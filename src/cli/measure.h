/* What the program measures of a run around the library (measure.c). */
#ifndef PSIM_CLI_MEASURE_H
#define PSIM_CLI_MEASURE_H
#include "psim/psim.h"

/* The output phase around a write: cli_output_begin opens its LIKWID
 * region (src/engine/timer.h) and returns the time it began, which
 * cli_output_end adds to the phase before it closes the region. */
double cli_output_begin(const psim_sim *s);
void cli_output_end(psim_sim *s, double t0);

/* The process's peak resident memory in bytes (VmHWM; 0 if unknown). */
long long cli_peak_rss(void);

#endif
