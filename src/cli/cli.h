/* The psim command line: subcommands and their shared helpers. */
#ifndef PSIM_CLI_H
#define PSIM_CLI_H
#include <stdio.h>

int cli_run(int argc, char **argv);   /* psim [OPTIONS] [SCENE [THREADS]] */
int cli_gen(int argc, char **argv);   /* psim gen [OPTIONS] */

/* Strict number parsing for option values: print one error line and
 * return -1 when text is not a number in [lo, hi]. */
int cli_long(const char *opt, const char *text, long lo, long hi, long *out);
int cli_double(const char *opt, const char *text, double lo, double hi,
               double *out);

/* An output file that appears only when complete: written to a temporary
 * file beside it and renamed by outfile_commit; "-" is standard output. */
typedef struct outfile {
    char *path, *tmp;
    FILE *f;
} outfile;

int outfile_open(outfile *o, const char *path);
int outfile_commit(outfile *o);
void outfile_abort(outfile *o);

/* A progress bar on stderr, shown only on a terminal and after ~1 s. */
typedef struct progress {
    int enabled, shown;
    double start, last;
    long total;
} progress;

void progress_init(progress *p, long total, int quiet);
void progress_update(progress *p, long done);
void progress_done(progress *p);

#endif
