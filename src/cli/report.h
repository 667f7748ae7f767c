/* The per-thread profile of a run (report.c). */
#ifndef PSIM_CLI_REPORT_H
#define PSIM_CLI_REPORT_H
#include <stdio.h>

#include "pin.h"
#include "psim/psim.h"

/* --report table and the per-thread members of --stats (report.c). */
void cli_report(FILE *f, const psim_sim *s, const cli_pin *p);
char *cli_threads_json(const psim_sim *s, const cli_pin *p);

#endif
