/* Option values of the command line. */
#ifndef PSIM_CLI_OPTIONS_H
#define PSIM_CLI_OPTIONS_H

/* Strict number parsing for option values: print one error line and
 * return -1 when text is not a number in [lo, hi]. */
int cli_long(const char *opt, const char *text, long lo, long hi, long *out);
int cli_double(const char *opt, const char *text, double lo, double hi,
               double *out);
/* One error line for an option getopt_long refused (c is what it
 * returned: ':' for a missing value, '?' otherwise); cmd is NULL or the
 * subcommand. */
void cli_bad_option(const char *cmd, char **argv, int c);

#endif
