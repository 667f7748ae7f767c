/* Progress on stderr (progress.c). */
#ifndef PSIM_CLI_PROGRESS_H
#define PSIM_CLI_PROGRESS_H
#include "psim/psim.h"

/* Progress on stderr after ~1 s: a bar on a terminal; elsewhere (batch
 * jobs, logs) a line every PROGRESS_LINE_S seconds. */
#define PROGRESS_LINE_S 10.0
typedef struct progress {
    int enabled, tty, shown;
    int inside_only;    /* only inside long steps (a --thermo table shows the rest) */
    int width;          /* the widest bar drawn */
    double start, last, every;
    long total;
} progress;

void progress_init(progress *p, long total, int quiet);
void progress_update(progress *p, long done);
void progress_done(progress *p);
/* Inside a step that has run PROGRESS_LINE_S seconds (psim_set_step_progress,
 * with the times of progress_inside_times): "psim: step 2 of 5: 3.2e9
 * events so far, 40 s in this step" every PROGRESS_LINE_S seconds, or the
 * bar on a terminal; done is the step's number in the run. */
void progress_inside(progress *p, long done, const psim_step_progress *r);
void progress_inside_times(const progress *p, double *first_s, double *every_s);

/* The same progress for one read or write that takes more than a second
 * (psim_set_io_progress): on a terminal the bar, "[####  ] reading s.in:
 * 412/850 MB, 2.1 s left", cleared by cli_io_end; elsewhere a line every
 * PROGRESS_LINE_S seconds; nothing under -q. */
void cli_io_begin(const char *verb, const char *name, int quiet);
void cli_io_end(void);

#endif
