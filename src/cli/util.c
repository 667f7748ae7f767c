#include <errno.h>
#include <sched.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>

#include <hwloc.h>

#include "cli.h"
#include "../io/scene.h"
#include "../engine/timer.h"

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

int cli_env_threads(void)
{
    const char *v = getenv("OMP_NUM_THREADS");
    if (!v)
        return 0;
    size_t len = strcspn(v, ",");
    if (len > 20) {
        cli_err("psim: OMP_NUM_THREADS: expected an integer, got '%.40s'", v);
        return -1;
    }
    char first[24];
    long t;
    snprintf(first, sizeof first, "%.*s", (int)len, v);
    return cli_long("OMP_NUM_THREADS", first, 1, CLI_MAX_THREADS, &t);
}

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

void progress_init(progress *p, long total, int quiet)
{
    memset(p, 0, sizeof *p);
    p->tty = isatty(STDERR_FILENO);
    p->enabled = !quiet;
    /* PSIM_PROGRESS_S=T: start after T s and show a line every T s, on
     * a terminal too (tests) */
    const char *ev = getenv("PSIM_PROGRESS_S");
    p->every = ev ? atof(ev) : -1;
    if (p->every >= 0)
        p->tty = 0;
    p->total = total;
    p->start = p->last = psim_now();
}

/* Whether p is due to show at time now (then marked shown at now): a bar
 * on a terminal after 1 s, every 0.1 s; elsewhere a line every
 * PROGRESS_LINE_S seconds; PSIM_PROGRESS_S, both. */
static int progress_due(progress *p, double now)
{
    double delay = p->every >= 0 ? p->every : 1.0,
           gap = p->every >= 0 ? p->every : p->tty ? 0.1 : PROGRESS_LINE_S;
    if (now - p->start < delay || now - p->last < gap)
        return 0;
    p->last = now;
    return 1;
}

/* The bar on a terminal, "[####    ] " then what, over any wider bar
 * drawn before. */
static void progress_bar(progress *p, long done, const char *what)
{
    int width = 30, fill = p->total ? (int)(width * done / p->total) : width;
    fill = fill < 0 ? 0 : fill > width ? width : fill;
    char line[256];
    int w = snprintf(line, sizeof line, "[%.*s%*s] %s ", fill, "##############################",
                     width - fill, "", what);
    fprintf(stderr, "\r%-*s", p->width, line);
    p->width = w > p->width ? w : p->width;
    p->shown = 1;
    fflush(stderr);
}

void progress_update(progress *p, long done)
{
    if (!p->enabled || p->inside_only)
        return;
    double now = psim_now();
    if (!progress_due(p, now))
        return;
    double eta = done ? (now - p->start) * (double)(p->total - done) / (double)done : 0;
    if (!p->tty) {
        cli_err("psim: step %ld of %ld (%.0f%%), %.0f s so far, about %.0f s left",
                done, p->total, p->total ? 100.0 * (double)done / (double)p->total : 100.0,
                now - p->start, eta);
        return;
    }
    char what[96];
    snprintf(what, sizeof what, "step %ld/%ld, %.1f s left", done, p->total, eta);
    progress_bar(p, done, what);
}

void progress_done(progress *p)
{
    if (p->shown)
        fprintf(stderr, "\r%*s\r", p->width > 70 ? p->width : 70, "");
}

void progress_inside_times(const progress *p, double *first_s, double *every_s)
{
    *first_s = p->every >= 0 ? p->every : PROGRESS_LINE_S;
    *every_s = p->every >= 0 ? p->every : p->tty ? 0.1 : PROGRESS_LINE_S;
}

/* A count as "41203" or, from a million, "3.2e9". */
static void count_text(char *buf, size_t size, uint64_t v)
{
    if (v < 1000000) {
        snprintf(buf, size, "%llu", (unsigned long long)v);
        return;
    }
    char e[32];
    snprintf(e, sizeof e, "%.1e", (double)v);   /* "3.2e+09" */
    char *x = strchr(e, 'e');
    snprintf(buf, size, "%.*se%d", (int)(x - e), e, atoi(x + 1));
}

void progress_inside(progress *p, long done, const psim_step_progress *r)
{
    if (!p->enabled)
        return;
    char work[32];
    count_text(work, sizeof work, r->work);
    if (!p->tty) {
        cli_err("psim: step %ld of %ld: %s %s so far, %.0f s in this step", done,
                p->total, work, r->unit, r->seconds);
        return;
    }
    char what[160];
    snprintf(what, sizeof what, "step %ld/%ld: %s %s, %.0f s in this step", done, p->total,
             work, r->unit, r->seconds);
    progress_bar(p, done - 1, what);
}

/* One read or write at a time: its bar, label and how wide it was drawn. */
static struct {
    progress pb;
    char what[200];
    int on, width;
} io;

static void io_show(void *ctx, int writing, long long done, long long total)
{
    (void)ctx;
    progress *p = &io.pb;
    if (!io.on || !p->enabled)
        return;
    double now = psim_now();
    if (!progress_due(p, now))
        return;
    double frac = total > 0 ? (double)done / (double)total : 0;
    double eta = total > 0 && done > 0 ? (now - p->start) * (1 - frac) / frac : 0;
    /* lines, or millions of them; bytes in MB (kB below 10 MB) */
    char count[64];
    double u = writing ? (total >= 1000000 ? 1e6 : 1) : (total >= 0 && total < 10000000 ? 1e3 : 1e6);
    const char *unit = writing ? (u > 1 ? " M lines" : " lines") : (u < 1e6 ? " kB" : " MB");
    int dec = writing && u > 1 ? 1 : 0;
    if (total >= 0)
        snprintf(count, sizeof count, "%.*f/%.*f%s", dec, (double)done / u, dec,
                 (double)total / u, unit);
    else
        snprintf(count, sizeof count, "%.*f%s", dec, (double)done / u, unit);
    char left[40] = "";
    if (total > 0)
        snprintf(left, sizeof left, p->tty ? ", %.1f s left" : ", about %.0f s left", eta);
    if (!p->tty) {
        cli_err("psim: %s: %s (%.0f%%), %.0f s so far%s", io.what, count,
                100 * frac, now - p->start, left);
        return;
    }
    p->shown = 1;
    int width = 30, fill = (int)(width * frac);
    fill = fill < 0 ? 0 : fill > width ? width : fill;
    int w = fprintf(stderr, "\r[%.*s%*s] %s: %s%s ", fill, "##############################",
                    width - fill, "", io.what, count, left);
    if (w > io.width)
        io.width = w;
    fflush(stderr);
}

void cli_io_begin(const char *verb, const char *name, int quiet)
{
    progress_init(&io.pb, 0, quiet);
    int n = snprintf(io.what, sizeof io.what, "%s ", verb);
    cli_escape(io.what + n, sizeof io.what - (size_t)n, name);   /* shown on a terminal */
    io.on = 1;
    io.width = 0;
    psim_set_io_progress(io_show, NULL);
}

void cli_io_end(void)
{
    if (io.pb.shown)
        fprintf(stderr, "\r%*s\r", io.width, "");
    io.on = 0;
    io.pb.shown = 0;
    psim_set_io_progress(NULL, NULL);
}

long long cli_peak_rss(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    long long kb = 0;
    if (f) {
        char line[256];
        while (fgets(line, sizeof line, f))
            if (sscanf(line, "VmHWM: %lld kB", &kb) == 1)
                break;
        fclose(f);
    }
    if (kb <= 0) {
        struct rusage ru;
        if (getrusage(RUSAGE_SELF, &ru) == 0)
            kb = ru.ru_maxrss;   /* kilobytes on Linux */
    }
    return kb * 1024;
}

double cli_output_begin(const psim_sim *s)
{
    (void)s;   /* in a build without LIKWID markers */
    psim_region_begin(psim_get_stats(s)->threads, psim_phase_name(s, PSIM_PHASE_OUTPUT));
    return psim_now();
}

void cli_output_end(psim_sim *s, double t0)
{
    psim_add_output_time(s, psim_now() - t0);
    psim_region_end(psim_get_stats(s)->threads, psim_phase_name(s, PSIM_PHASE_OUTPUT));
}

/* psim --version (and every subcommand's): the release, the git commit
 * psim was built from, the build's options and what it runs with. */
extern const char psim_git_commit[];

void cli_version(FILE *f)
{
    fprintf(f, "psim %s (git %s)\n", PSIM_VERSION, psim_git_commit);
#ifdef PSIM_BUILD_OPTIONS
    fprintf(f, "built: %s\n", PSIM_BUILD_OPTIONS);
#endif
#ifdef PSIM_BUILD_FEATURES
    fprintf(f, "features: %s\n", PSIM_BUILD_FEATURES);
#endif
    unsigned h = hwloc_get_api_version();
    fprintf(f, "with: OpenMP %d, hwloc API %u.%u\n", _OPENMP, h >> 16, (h >> 8) & 0xff);
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
