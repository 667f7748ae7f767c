/* The provenance of a run's --stats (provenance.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>
#include <time.h>

#include "provenance.h"
#include "version.h"
#include "psim/psim.h"

static char **main_argv;
static char **given_argv;   /* as given: getopt permutes main_argv */

void cli_set_argv(char **argv)
{
    main_argv = argv;
    int n = 0;
    while (argv[n])
        n++;
    given_argv = malloc((size_t)(n + 1) * sizeof *given_argv);
    if (given_argv)
        memcpy(given_argv, argv, (size_t)(n + 1) * sizeof *given_argv);
}

/* The load averages over 1, 5 and 15 minutes as /proc/loadavg shows them
 * (getloadavg's where it is missing): 1, or 0 if unknown. */
static int load_now(double *l)
{
    FILE *f = fopen("/proc/loadavg", "r");
    int ok = f && fscanf(f, "%lf %lf %lf", &l[0], &l[1], &l[2]) == 3;
    if (f)
        fclose(f);
    return ok || getloadavg(l, 3) == 3;
}

void cli_start_note(cli_start *st)
{
    st->date = time(NULL);
    st->load_ok = load_now(st->load);
}

/* The first "model name" of /proc/cpuinfo (x86's; NULL where there is
 * none), without its trailing white space, into buf. */
static const char *cpu_model(char *buf, size_t size)
{
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (!f)
        return NULL;
    char line[512];
    const char *found = NULL;
    while (!found && fgets(line, sizeof line, f)) {
        if (strncmp(line, "model name", 10) != 0)
            continue;
        const char *v = strchr(line, ':');
        if (!v)
            continue;
        v += 1 + strspn(v + 1, " \t");
        size_t n = strlen(v);
        while (n > 0 && (v[n - 1] == '\n' || v[n - 1] == ' ' || v[n - 1] == '\t'))
            n--;
        snprintf(buf, size, "%.*s", (int)n, v);
        found = buf;
    }
    fclose(f);
    return found;
}

/* A string member, or null. */
static void json_member(FILE *f, const char *key, const char *value)
{
    fprintf(f, ",\n    \"%s\": ", key);
    if (value)
        psim_write_json_string(f, value);
    else
        fputs("null", f);
}

/* The three load averages as an array, or null where unknown. */
static void json_load(FILE *f, const char *key, int ok, const double *l)
{
    fprintf(f, ",\n    \"%s\": ", key);
    if (!ok) {
        fputs("null", f);
        return;
    }
    for (int k = 0; k < 3; k++) {
        char b[PSIM_FORMAT_MAX];
        psim_format_double(b, l[k], -1);
        fprintf(f, "%s%s", k ? ", " : "[", b);
    }
    fputc(']', f);
}

char *cli_provenance_json(const cli_start *st)
{
    char *out = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&out, &len);
    if (!f)
        return NULL;
    fprintf(f, "  \"provenance\": {\n    \"version\": ");
    psim_write_json_string(f, PSIM_VERSION);
    json_member(f, "git_commit", psim_git_commit);
#ifdef PSIM_BUILD_OPTIONS
    json_member(f, "build", PSIM_BUILD_OPTIONS);
#else
    json_member(f, "build", NULL);
#endif
    struct utsname u;
    json_member(f, "host", uname(&u) == 0 ? u.nodename : NULL);
    char model[512];
    json_member(f, "cpu_model", cpu_model(model, sizeof model));
    char date[32];
    struct tm tm;
    json_member(f, "date", gmtime_r(&st->date, &tm) &&
                                   strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", &tm)
                               ? date
                               : NULL);
    fprintf(f, ",\n    \"command_line\": [");
    char **argv = given_argv ? given_argv : main_argv;
    for (int k = 0; argv && argv[k]; k++) {
        fputs(k ? ", " : "", f);
        psim_write_json_string(f, argv[k]);
    }
    fputc(']', f);
    json_load(f, "load_start", st->load_ok, st->load);
    double end[3];
    int end_ok = load_now(end);
    json_load(f, "load_end", end_ok, end);
    fputs("\n  }", f);
    if (fclose(f) != 0) {
        free(out);
        return NULL;
    }
    return out;
}
