/* The provenance of a run's --stats (provenance.c). */
#ifndef PSIM_CLI_PROVENANCE_H
#define PSIM_CLI_PROVENANCE_H
#include <time.h>

/* The command line as given (getopt permutes main's argv), for the
 * provenance of --stats. */
void cli_set_argv(char **argv);

/* Where a run stands at its start, for the provenance of --stats. */
typedef struct cli_start {
    time_t date;
    double load[3];         /* the load averages, over 1, 5 and 15 minutes */
    int load_ok;
} cli_start;
void cli_start_note(cli_start *st);
/* The "provenance" member of --stats (malloc'd; NULL without memory): the
 * version, git commit and build options (as --version gives them), the
 * host's name and CPU model, the date the run started (ISO 8601, UTC),
 * the command line, and the load averages at the start and now (a shared
 * machine's load is what makes timings differ). */
char *cli_provenance_json(const cli_start *st);

#endif
