/* Option values read strictly, and the error line for an option getopt
 * refused (options.h). */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "options.h"
#include "say.h"

int cli_long(const char *opt, const char *text, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (end == text || *end || errno == ERANGE) {
        cli_err("psim: %s: expected an integer, got '%s'", opt, text);
        return -1;
    }
    if (v < lo || v > hi) {
        cli_err("psim: %s: %ld is out of range %ld..%ld", opt, v, lo, hi);
        return -1;
    }
    *out = v;
    return 0;
}

int cli_double(const char *opt, const char *text, double lo, double hi,
               double *out)
{
    char *end;
    errno = 0;
    double v = strtod(text, &end);
    if (end == text || *end || !isfinite(v)) {
        cli_err("psim: %s: expected a finite number, got '%s'", opt, text);
        return -1;
    }
    if (errno == ERANGE && v == 0) {   /* below the smallest double: read as 0 */
        cli_err("psim: %s: '%s' is too small for a double (below 4.9e-324)", opt,
                text);
        return -1;
    }
    if (v < lo || v > hi) {
        cli_err("psim: %s: %g is out of range %g..%g", opt, v, lo, hi);
        return -1;
    }
    *out = v;
    return 0;
}

void cli_bad_option(const char *cmd, char **argv, int c)
{
    /* a long option is argv[optind - 1] (up to any '='); a short one,
     * possibly inside a cluster like -Zq, is optopt */
    const char *arg = argv[optind - 1];
    char name[64];
    if (strncmp(arg, "--", 2) == 0)
        snprintf(name, sizeof name, "%.*s", (int)strcspn(arg, "="), arg);
    else
        snprintf(name, sizeof name, "-%c", optopt);
    const char *sp = cmd ? " " : "", *sub = cmd ? cmd : "";
    if (c == ':')
        cli_err("psim%s%s: option '%s' needs a value (see psim%s%s --help)", sp,
                sub, name, sp, sub);
    else
        cli_err("psim%s%s: unknown option '%s' (see psim%s%s --help)", sp, sub,
                name, sp, sub);
}
