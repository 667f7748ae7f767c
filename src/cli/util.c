#include <errno.h>
#include <sched.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
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

void cli_set_argv(char **argv) { main_argv = argv; }

/* Threads runnable on the machine now, psim's own included (/proc/stat's
 * procs_running); -1 if unknown. */
static long runnable_now(void)
{
    FILE *f = fopen("/proc/stat", "r");
    if (!f)
        return -1;
    char line[256];
    long n = -1;
    while (fgets(line, sizeof line, f))
        if (sscanf(line, "procs_running %ld", &n) == 1)
            break;
    fclose(f);
    return n;
}

/* The fewest threads runnable, psim's own included, in up to WAIT_SAMPLES
 * looks WAIT_GAP_NS apart (5 ms in all), stopping at the first that shows
 * at most `room`: threads that stay runnable, as another program's busy
 * ones do, and not those that are for a moment, as the shell that has just
 * started psim, the other commands of its pipeline starting beside it, or
 * the kernel's threads that clear up after the program before (one look
 * saw one to three of those more often than not, and two threads waiting
 * passively took 1.3-1.5 times as long on a quiet machine: docs/design.md);
 * one look when even psim alone is too many; -1 if unknown. */
#define WAIT_SAMPLES 20
#define WAIT_GAP_NS 250000L
static long runnable_steadily(long room)
{
    long least = -1;
    const int looks = room >= 1 ? WAIT_SAMPLES : 1;   /* psim alone is 1 */
    for (int k = 0; k < looks && !(least >= 0 && least <= room); k++) {
        if (k > 0)
            nanosleep(&(struct timespec){0, WAIT_GAP_NS}, NULL);
        long n = runnable_now();
        if (n < 0)
            return -1;
        least = least < 0 || n < least ? n : least;
    }
    return least;
}

const char *cli_wait_note(void) { return getenv("PSIM_WAIT_NOTE"); }

void cli_choose_wait_policy(int threads)
{
    if (threads <= 1 || !main_argv || getenv("OMP_WAIT_POLICY") || getenv("GOMP_SPINCOUNT"))
        return;
    cpu_set_t cpus;
    int cores = sched_getaffinity(0, sizeof cpus, &cpus) == 0 ? CPU_COUNT(&cpus) : 0;
    long others = cores > 0 ? runnable_steadily(cores - threads + 1) - 1 : -1;
    if (others < 0 || others + threads <= cores)   /* unknown (-1), or room */
        return;   /* waiting threads may spin */
    /* Shared: a spinning thread would take the core that the thread it
     * waits for needs.  The OpenMP runtime reads its wait policy when it
     * is loaded, so psim starts again with it set (the scene is not read
     * yet); if that fails, it runs on as it is. */
    char note[160];
    snprintf(note, sizeof note, "passive (machine shared: %ld other threads runnable, "
             "%d threads asked, %d cores)", others, threads, cores);
    if (setenv("OMP_WAIT_POLICY", "passive", 1) || setenv("PSIM_WAIT_NOTE", note, 1))
        return;
    /* by argv[0], as the shell found it: /proc/self/exe would name the
     * tool, not psim, under valgrind and such */
    execvp(main_argv[0], main_argv);
    unsetenv("OMP_WAIT_POLICY");
    unsetenv("PSIM_WAIT_NOTE");
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

/* psim --version (and every subcommand's): the release, the git commit
 * psim was built from, the build's options and what it runs with. */
extern const char psim_git_commit[];

void cli_version(FILE *f)
{
    fprintf(f, "psim %s (git %s)\n", PSIM_VERSION, psim_git_commit);
#ifdef PSIM_BUILD_OPTIONS
    fprintf(f, "built: %s\n", PSIM_BUILD_OPTIONS);
#endif
    unsigned h = hwloc_get_api_version();
    fprintf(f, "with: OpenMP %d, allocator %s, hwloc API %u.%u\n", _OPENMP, psim_allocator(),
            h >> 16, (h >> 8) & 0xff);
}
