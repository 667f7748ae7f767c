/* The thermodynamic rows of a run (thermo.c). */
#ifndef PSIM_CLI_THERMO_H
#define PSIM_CLI_THERMO_H
#include <stdint.h>
#include <stdio.h>

#include "psim/psim.h"

/* --thermo N and --thermo-file (thermo.c): rows at the start, every
 * `every` steps and after the last step; the table to `table` (NULL: none),
 * CSV to `csv` (NULL: none).  With speed (--thermo-speed), a last column
 * of steps per second of wall time since the previous row: the one
 * column read from the clock, so left out unless asked for, which keeps
 * the rows the same bytes from run to run. */
typedef struct cli_thermo {
    long every;             /* 0: no rows */
    int speed;
    FILE *table, *csv;
    int ncols, pressure;
    const char *col[PSIM_THERMO_MAX];
    uint64_t last[PSIM_THERMO_MAX];
    double last_virial;
    long last_step;
    double last_wall;       /* psim_now() at the previous row */
} cli_thermo;

void thermo_init(cli_thermo *t, long every, int speed);
/* The header and the row of the state before the first step; then after
 * step k of steps.  0, or -1 with err set: no memory, or a total beyond
 * the largest double (a state whose squared speeds overflow is summed
 * in units of a power of two: only a total that no double holds fails). */
int thermo_start(cli_thermo *t, psim_sim *s, FILE *table, FILE *csv, psim_error *err);
int thermo_step(cli_thermo *t, psim_sim *s, long k, long steps, psim_error *err);
/* Whether step k of steps has a row. */
int thermo_due(const cli_thermo *t, long k, long steps);

#endif
