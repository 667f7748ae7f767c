/* The CPUs and the OpenMP settings a run starts with, fixed before the
 * OpenMP runtime starts (docs/experiments.md, "Pinning").
 *
 * The runtime reads OMP_* in its constructor, and there binds the initial
 * thread when OMP_PROC_BIND, OMP_PLACES or GOMP_CPU_AFFINITY ask it to:
 * after that, the process's mask no longer says which CPUs psim was given.
 * So this runs from the executable's .preinit_array, before every
 * library's constructor, and uses system calls and allocation-free C only:
 *   - it keeps the affinity mask psim was started with (taskset, numactl,
 *     a cpuset, likwid-pin's list): the CPUs psim may use, whatever the
 *     runtime then does to its initial thread.  psim never narrows it;
 *   - on a shared machine a run of several threads needs
 *     OMP_WAIT_POLICY=passive (docs/design.md, "Waiting threads on a
 *     shared machine").  The environment cannot grow here (the C library
 *     sets environ to the array the kernel gave after this has run), so
 *     psim starts itself again at once with it: nothing has started yet,
 *     no thread, no runtime, no binding, and the new start inherits the
 *     very mask this one was given;
 *   - a run given --pin POLICY (not none) places its threads itself, so
 *     the runtime's binding variables are taken out of the environment
 *     (in place) before the runtime reads them.
 * The command line is read here only to learn the threads and the --pin
 * policy of a run; psim's own parser checks it later, and anything this
 * reading does not follow leaves the runtime's defaults alone. */
#include <fcntl.h>
#include <getopt.h>
#include <sched.h>
#include <stdlib.h>
#include <string.h>
#include <sys/auxv.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include "affinity.h"
#include "pin.h"
#include "run_options.h"
#include "startup.h"
#include "threads.h"


static cpu_set_t start_cpus;   /* the mask psim was started with */
static int start_cpus_known;

/* The runtime's binding variables, taken out for --pin. */
static const char *const binders[] = {"OMP_PROC_BIND", "OMP_PLACES", "GOMP_CPU_AFFINITY"};
#define NBINDERS ((int)(sizeof binders / sizeof binders[0]))
static const char *removed[NBINDERS];   /* "NAME=VALUE" of each taken out */
static int nremoved;

static struct {
    int chosen;                 /* OMP_WAIT_POLICY=passive was set here */
    long others, threads, cores;
} wait_choice;

/* The command line as far as the start needs it. */
typedef struct start_args {
    int run;        /* a run that steps (not gen, plan, models, --help,
                     * --version or --dry-run) */
    long threads;   /* --threads or THREADS; 0: not given */
    int pins;       /* --pin with a policy other than none */
    int ok;         /* read to the end without surprise */
} start_args;

/* ---- small helpers, with no allocation --------------------------------- */

CLI_EARLY static int same(const char *a, const char *b)
{
    while (*a && *a == *b)
        a++, b++;
    return *a == *b;
}

/* "NAME=VALUE" of name in env, its VALUE; NULL if absent. */
CLI_EARLY static const char *env_value(char **env, const char *name)
{
    size_t len = strlen(name);
    for (char **e = env; e && *e; e++)
        if (strncmp(*e, name, len) == 0 && (*e)[len] == '=')
            return *e + len + 1;
    return NULL;
}

/* The decimal number text starts with, up to stop (a byte not a digit
 * ends it: that byte must be stop or the end); -1 if none or above max. */
CLI_EARLY static long leading_count(const char *text, char stop, long max)
{
    long v = 0;
    const char *p = text;
    for (; *p >= '0' && *p <= '9'; p++)
        if ((v = v * 10 + (*p - '0')) > max)
            return -1;
    return p > text && (*p == '\0' || *p == stop) ? v : -1;
}

/* ---- the command line ---------------------------------------------------- */

/* The long option called (a unique prefix of) name, of length len; NULL
 * if none or ambiguous, as getopt_long has it. */
CLI_EARLY static const struct option *long_option(const char *name, size_t len)
{
    const struct option *found = NULL;
    for (const struct option *o = cli_run_longs; o->name; o++) {
        if (strncmp(o->name, name, len) != 0)
            continue;
        if (o->name[len] == '\0')
            return o;
        if (found)
            return NULL;
        found = o;
    }
    return found;
}

/* Note one option of a run: code c, its value (NULL: none). */
CLI_EARLY static void note_option(start_args *a, int c, const char *value)
{
    if (c == 't')
        a->threads = leading_count(value, '\0', CLI_MAX_THREADS);
    else if (c == CLI_OPT_PIN)
        a->pins = !same(value, "none");
    else if (c == CLI_OPT_DRY_RUN || c == 'h' || c == 'V')
        a->run = 0;
    if (a->threads < 0)
        a->ok = 0;
}

/* A cluster of short options, "-qt4" (argv[*i]); 0, or -1 past the end. */
CLI_EARLY static int short_options(start_args *a, int argc, char **argv, int *i)
{
    for (const char *p = argv[*i] + 1; *p; p++) {
        const char *spec = strchr(cli_run_shorts + 1, *p);
        if (*p == ':' || !spec)
            return a->ok = 0, -1;
        if (spec[1] != ':') {
            note_option(a, *p, NULL);
            continue;
        }
        const char *value = p[1] ? p + 1 : *i + 1 < argc ? argv[++*i] : NULL;
        if (!value)
            return a->ok = 0, -1;
        note_option(a, *p, value);
        return 0;
    }
    return 0;
}

/* A long option, "--threads=4" or "--threads 4" (argv[*i]). */
CLI_EARLY static int long_opt(start_args *a, int argc, char **argv, int *i)
{
    const char *name = argv[*i] + 2, *eq = strchr(name, '=');
    const struct option *o = long_option(name, eq ? (size_t)(eq - name) : strlen(name));
    if (!o)
        return a->ok = 0, -1;
    const char *value = NULL;
    if (o->has_arg == required_argument) {
        value = eq ? eq + 1 : *i + 1 < argc ? argv[++*i] : NULL;
        if (!value)
            return a->ok = 0, -1;
    }
    note_option(a, o->val, value);
    return 0;
}

/* Read the command line of a run as psim's parser (getopt_long, GNU
 * order: options and operands mixed, "--" ends the options) will. */
CLI_EARLY static start_args read_args(int argc, char **argv, char **env)
{
    start_args a = {1, 0, 0, 1};
    int first = 1;
    if (argc > 1 && (same(argv[1], "gen") || same(argv[1], "plan") ||
                     same(argv[1], "topo") || same(argv[1], "models")))
        return a.run = 0, a;
    if (argc > 1 && same(argv[1], "run"))
        first = 2;
    int operands = 0, options = 1, posix = env_value(env, "POSIXLY_CORRECT") != NULL;
    for (int i = first; i < argc && a.ok; i++) {
        const char *s = argv[i];
        if (options && same(s, "--")) {
            options = 0;
        } else if (options && s[0] == '-' && s[1] == '-') {
            long_opt(&a, argc, argv, &i);
        } else if (options && s[0] == '-' && s[1]) {
            short_options(&a, argc, argv, &i);
        } else if (++operands == 2) {   /* SCENE THREADS */
            a.threads = leading_count(s, '\0', CLI_MAX_THREADS);
            a.ok = a.threads > 0;
        } else if (posix) {
            options = 0;
        }
    }
    return a;
}

/* ---- the environment ------------------------------------------------------ */

/* Take the entries called name (all of them, in place) out of env;
 * *kept (if not NULL) gets the first one's "NAME=VALUE".  The count. */
CLI_EARLY static int remove_env(char **env, const char *name, const char **kept)
{
    size_t len = strlen(name);
    char **out = env;
    int gone = 0;
    for (char **e = env; e && *e; e++) {
        if (strncmp(*e, name, len) == 0 && (*e)[len] == '=') {
            if (kept && !gone)
                *kept = *e;
            gone++;
        } else {
            *out++ = *e;
        }
    }
    if (out)
        *out = NULL;
    return gone;
}

/* ---- the wait policy ------------------------------------------------------ */

/* Threads runnable on the machine now, psim's own included (the fourth
 * field of /proc/loadavg, "RUNNING/TOTAL": the kernel's nr_running, as
 * /proc/stat's procs_running); -1 if unknown. */
CLI_EARLY static long runnable_now(void)
{
    char buf[128];
    if (cli_early_read("/proc/loadavg", buf, sizeof buf) < 0)
        return -1;
    const char *p = buf;
    for (int field = 0; field < 3; field++) {
        p = strchr(p, ' ');
        if (!p)
            return -1;
        p++;
    }
    return leading_count(p, '/', 1L << 30);
}

/* The fewest threads runnable, psim's own included, in up to WAIT_SAMPLES
 * looks WAIT_GAP_NS apart (5 ms in all), stopping at the first that shows
 * at most `room`: threads that stay runnable, as another program's busy
 * ones do, and not those that are for a moment, as the shell that has just
 * started psim, the other commands of its pipeline starting beside it, or
 * the kernel's threads that clear up after the program before (one look
 * saw one to three of those more often than not: docs/design.md); one
 * look when even psim alone is too many; -1 if unknown. */
#define WAIT_SAMPLES 20
#define WAIT_GAP_NS 250000L
CLI_EARLY static long runnable_steadily(long room)
{
    long least = -1;
    const int looks = room >= 1 ? WAIT_SAMPLES : 1;   /* psim alone is 1 */
    for (int k = 0; k < looks && !(least >= 0 && least <= room); k++) {
        if (k > 0) {
            struct timespec gap = {0, WAIT_GAP_NS};
            nanosleep(&gap, NULL);
        }
        long n = runnable_now();
        if (n < 0)
            return -1;
        least = least < 0 || n < least ? n : least;
    }
    return least;
}

/* The threads a run will start: as asked, else OMP_NUM_THREADS's first
 * number, else one per CPU it may use; at most OMP_THREAD_LIMIT. */
CLI_EARLY static long run_threads(const start_args *a, char **env, long cpus)
{
    long t = a->threads;
    const char *v = env_value(env, "OMP_NUM_THREADS");
    if (t <= 0 && v)
        t = leading_count(v, ',', CLI_MAX_THREADS);
    if (t <= 0)
        t = cpus;
    const char *limit = env_value(env, "OMP_THREAD_LIMIT");
    long cap = limit ? leading_count(limit, '\0', 1L << 30) : -1;
    return cap > 0 && cap < t ? cap : t;
}

#define CHOSEN "PSIM_WAIT_CHOSEN"

/* Start psim again, as the kernel started it (its path, argv), with
 * OMP_WAIT_POLICY=passive and PSIM_WAIT_CHOSEN=OTHERS,THREADS,CORES added
 * to env; returns only if that fails (the run goes on as it is). */
CLI_EARLY static void start_passive(char **argv, char **env, long others,
                                         long threads, long cores)
{
    const char *path = (const char *)getauxval(AT_EXECFN);
    if (!path)
        return;
    static char passive[] = "OMP_WAIT_POLICY=passive", why[96] = CHOSEN "=";
    char *p = why + sizeof CHOSEN;
    p = cli_early_put_long(p, others);
    *p++ = ',';
    p = cli_early_put_long(p, threads);
    *p++ = ',';
    p = cli_early_put_long(p, cores);
    *p = '\0';
    size_t n = 0;
    while (env && env[n])
        n++;
    char **next = mmap(NULL, (n + 3) * sizeof *next, PROT_READ | PROT_WRITE,
                       MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (next == MAP_FAILED)
        return;
    for (size_t k = 0; k < n; k++)
        next[k] = env[k];
    next[n] = passive;
    next[n + 1] = why;
    next[n + 2] = NULL;
    execve(path, argv, next);
    munmap(next, (n + 3) * sizeof *next);
}

/* Passive when the fewest threads seen besides psim's, and its own, would
 * not each have a CPU of those it may use: a spinning thread would then
 * take the CPU that the thread it waits for needs.  The user's
 * OMP_WAIT_POLICY or GOMP_SPINCOUNT is never overridden. */
CLI_EARLY static void choose_wait_policy(const start_args *a, char **argv, char **env)
{
    if (!a->run || !a->ok || !start_cpus_known || env_value(env, "OMP_WAIT_POLICY") ||
        env_value(env, "GOMP_SPINCOUNT"))
        return;
    long cores = CPU_COUNT(&start_cpus), threads = run_threads(a, env, cores);
    if (threads <= 1 || cores <= 0)
        return;
    long others = runnable_steadily(cores - threads + 1) - 1;
    if (others < 0 || others + threads <= cores)   /* unknown (-1), or room */
        return;
    start_passive(argv, env, others, threads, cores);
}

/* A start of psim's own with the wait policy chosen: PSIM_WAIT_CHOSEN
 * says why (taken out of the environment, kept for the summary). */
CLI_EARLY static void chosen_before(char **env)
{
    const char *v = env_value(env, CHOSEN);
    long n[3] = {-1, -1, -1};
    for (int k = 0; v && k < 3; k++) {
        n[k] = leading_count(v, k < 2 ? ',' : '\0', 1L << 30);
        v = n[k] >= 0 ? strchr(v, ',') : NULL;
        v = v ? v + 1 : NULL;
    }
    remove_env(env, CHOSEN, NULL);
    const char *policy = env_value(env, "OMP_WAIT_POLICY");
    if (n[2] >= 0 && policy && same(policy, "passive")) {
        wait_choice.chosen = 1;
        wait_choice.others = n[0];
        wait_choice.threads = n[1];
        wait_choice.cores = n[2];
    }
}

CLI_EARLY static void start_affinity(int argc, char **argv, char **env)
{
    start_cpus_known = sched_getaffinity(0, sizeof start_cpus, &start_cpus) == 0;
    chosen_before(env);
    start_args a = read_args(argc, argv, env);
    choose_wait_policy(&a, argv, env);
    if (a.run && a.ok && a.pins)
        for (int k = 0; k < NBINDERS; k++)
            if (remove_env(env, binders[k], &removed[nremoved]))
                nremoved++;
}

__attribute__((section(".preinit_array"), used)) static void (*const start_affinity_entry)(
    int, char **, char **) = start_affinity;

/* ---- what the run reports --------------------------------------------------- */

const char *cli_wait_note(void)
{
    static char note[160];
    if (!wait_choice.chosen)
        return NULL;
    snprintf(note, sizeof note, "passive (machine shared: %ld other threads runnable, "
             "%ld threads asked, %ld cores)", wait_choice.others, wait_choice.threads,
             wait_choice.cores);
    return note;
}

const char *cli_binders_removed(void)
{
    static char note[256];
    size_t len = 0;
    note[0] = '\0';
    for (int k = 0; k < nremoved && len < sizeof note; k++)
        len += (size_t)snprintf(note + len, sizeof note - len, "%s%s", k ? " " : "",
                                removed[k]);
    return nremoved ? note : NULL;
}

const char *cli_outside_placement(void)
{
    static char note[256];
    size_t len = 0;
    note[0] = '\0';
    for (int k = 0; k < NBINDERS && len < sizeof note; k++) {
        const char *v = getenv(binders[k]);
        if (v)
            len += (size_t)snprintf(note + len, sizeof note - len, "%s%s=%s",
                                    len ? " " : "", binders[k], v);
    }
    if (getenv("LIKWID_PIN") && len < sizeof note)
        len += (size_t)snprintf(note + len, sizeof note - len, "%slikwid-pin",
                                len ? " " : "");
    return len ? note : NULL;
}

int cli_with_start_cpus(int (*fn)(void *), void *ctx)
{
    cpu_set_t now;
    int restore = start_cpus_known && sched_getaffinity(0, sizeof now, &now) == 0 &&
                  !CPU_EQUAL(&now, &start_cpus) &&
                  sched_setaffinity(0, sizeof start_cpus, &start_cpus) == 0;
    int rc = fn(ctx);
    if (restore)
        sched_setaffinity(0, sizeof now, &now);
    return rc;
}
