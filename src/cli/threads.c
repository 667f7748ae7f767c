/* How many threads a run gets, and whether they can start: the OpenMP
 * thread limit caps them (the run reports the threads that ran), and under
 * a limit on processes or address space the threads are started once
 * before the OpenMP runtime needs them, so that a limit too tight for them
 * gets psim's own error line instead of the runtime's. */
#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include <omp.h>

#include "options.h"
#include "say.h"
#include "threads.h"

static char note[160];

const char *cli_threads_note(void) { return note[0] ? note : NULL; }

int cli_threads_cap(int asked)
{
    int limit = omp_get_thread_limit();
    if (asked <= limit || limit < 1)
        return asked;
    snprintf(note, sizeof note, "%d of the %d threads asked (OMP_THREAD_LIMIT=%d)", limit,
             asked, limit);
    return limit;
}

/* The probe's threads wait until they are all started, so that each one
 * counts against the limits while the next starts. */
static struct {
    pthread_mutex_t lock;
    pthread_cond_t go;
    int released;
} probe = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER, 0};

static void *probe_wait(void *unused)
{
    (void)unused;
    pthread_mutex_lock(&probe.lock);
    while (!probe.released)
        pthread_cond_wait(&probe.go, &probe.lock);
    pthread_mutex_unlock(&probe.lock);
    return NULL;
}

/* The threads of every process on the machine (/proc/loadavg's fourth
 * field, "runnable/total"); -1 if unknown. */
static long tasks_now(void)
{
    FILE *f = fopen("/proc/loadavg", "r");
    long running, total = -1;
    if (f && fscanf(f, "%*s %*s %*s %ld/%ld", &running, &total) != 2)
        total = -1;
    if (f)
        fclose(f);
    return total;
}

/* Whether a limit that can stop `threads` threads from starting is set:
 * on address space, or on processes (ulimit -u, which counts the user's
 * threads) below the machine's threads now and the run's. */
static int limits_set(int threads, struct rlimit *nproc, struct rlimit *as)
{
    long tasks = -1;
    int a = getrlimit(RLIMIT_NPROC, nproc) == 0 && nproc->rlim_cur != RLIM_INFINITY &&
            ((tasks = tasks_now()) < 0 || nproc->rlim_cur < (rlim_t)(tasks + threads));
    int b = getrlimit(RLIMIT_AS, as) == 0 && as->rlim_cur != RLIM_INFINITY;
    if (!a)
        nproc->rlim_cur = RLIM_INFINITY;
    if (!b)
        as->rlim_cur = RLIM_INFINITY;
    return a || b;
}

/* Start threads - 1 threads beside this one, all alive at once; 0, or the
 * error of the first that could not start. */
static int start_all(int threads, int *started)
{
    pthread_t *t = calloc((size_t)threads, sizeof *t);
    if (!t)
        return ENOMEM;
    int err = 0, k = 0;
    probe.released = 0;
    for (; k < threads - 1 && !err; k++)
        err = pthread_create(&t[k], NULL, probe_wait, NULL);
    int n = err ? k - 1 : k;
    pthread_mutex_lock(&probe.lock);
    probe.released = 1;
    pthread_cond_broadcast(&probe.go);
    pthread_mutex_unlock(&probe.lock);
    for (int j = 0; j < n; j++)
        pthread_join(t[j], NULL);
    free(t);
    *started = n + 1;
    return err;
}

int cli_threads_startable(int threads)
{
    struct rlimit nproc, as;
    if (threads <= 1 || !limits_set(threads, &nproc, &as))
        return 0;
    int started = 0, err = start_all(threads, &started);
    if (!err)
        return 0;
    char lim[120] = "", *p = lim;
    if (nproc.rlim_cur != RLIM_INFINITY)
        p += snprintf(p, sizeof lim, "; processes limited to %llu (ulimit -u)",
                      (unsigned long long)nproc.rlim_cur);
    if (as.rlim_cur != RLIM_INFINITY)
        snprintf(p, sizeof lim - (size_t)(p - lim), "; address space limited to %llu kB "
                 "(ulimit -v)", (unsigned long long)(as.rlim_cur / 1024));
    cli_err("psim: cannot start %d threads (%d started): %s%s", threads, started,
            strerror(err), lim);
    return -1;
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
