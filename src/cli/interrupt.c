/* SIGINT and SIGTERM: taken by a thread of their own (interrupt.h).  While a
 * run steps, the first is a request to stop: the run stops at its next
 * poll (src/engine/poll.h), fails with one line, removes its temporary
 * outputs as any failed run does, and psim then ends by the signal. */
#include <pthread.h>
#include <signal.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "interrupt.h"
#include "outfile.h"
#include "../io/scene.h"

static const int stops[] = {SIGINT, SIGTERM};
#define NSTOPS ((int)(sizeof stops / sizeof stops[0]))

static sigset_t watched;   /* the signals the thread waits for */
static sigset_t before;    /* the mask psim started with */
static int armed;          /* a run steps (atomic) */
static int asked;          /* the signal that asked to stop; 0: none (atomic) */

/* One line on stderr. */
static void say(const char *line)
{
    ssize_t w = write(STDERR_FILENO, line, strlen(line));
    (void)w;
}

/* End psim by sig now, its named temporary files removed. */
static void end_now(int sig)
{
    cli_remove_temps();
    signal(sig, SIG_DFL);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, sig);
    pthread_sigmask(SIG_UNBLOCK, &one, NULL);
    raise(sig);
    _exit(128 + sig);   /* not reached: the shell's status for sig */
}

/* The first signal while a run steps: ask it to stop, then wait for it
 * (main ends psim once it has stopped) or for a second signal. */
static void stop_then_wait(int sig)
{
    __atomic_store_n(&asked, sig, __ATOMIC_RELEASE);
    psim_request_stop();
    struct timespec grace = {CLI_STOP_GRACE_S, 0};
    int again = sigtimedwait(&watched, NULL, &grace);
    /* the steps have stopped and main is ending psim: no more to say (a
     * launcher such as mpirun ends the ranks left once one has exited) */
    if (again > 0 && !__atomic_load_n(&armed, __ATOMIC_ACQUIRE))
        end_now(again);
    const char *name = sig == SIGTERM ? "SIGTERM" : "SIGINT";
    char line[96];
    if (again > 0)
        snprintf(line, sizeof line, "psim: %s again: ended at once\n",
                 again == SIGTERM ? "SIGTERM" : "SIGINT");
    else
        snprintf(line, sizeof line, "psim: %s: the run did not stop in time: ended at once\n",
                 name);
    say(line);
    end_now(again > 0 ? again : sig);
}

static void *watch(void *unused)
{
    (void)unused;
    for (;;) {
        int sig;
        if (sigwait(&watched, &sig) != 0)
            continue;
        if (__atomic_load_n(&armed, __ATOMIC_ACQUIRE))
            stop_then_wait(sig);
        else
            end_now(sig);
    }
    return NULL;
}

void cli_interrupt_start(void)
{
    sigemptyset(&watched);
    for (int k = 0; k < NSTOPS; k++) {
        struct sigaction was;
        if (sigaction(stops[k], NULL, &was) == 0 && was.sa_handler != SIG_IGN)
            sigaddset(&watched, stops[k]);   /* (ignored by the parent: it stays so) */
    }
    pthread_sigmask(SIG_BLOCK, &watched, &before);
}

void cli_interrupt_watch(void)
{
    static int started;
    if (started++)
        return;
    pthread_attr_t attr;
    pthread_t t;
    int ok = pthread_attr_init(&attr) == 0;
    if (ok) {
        pthread_attr_setstacksize(&attr, 256 * 1024);
        pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
        ok = pthread_create(&t, &attr, watch, NULL) == 0;
        pthread_attr_destroy(&attr);
    }
    if (!ok)   /* no thread: the signals' handlers (outfile.c) take them */
        pthread_sigmask(SIG_SETMASK, &before, NULL);
}

void cli_interrupt_arm(void) { __atomic_store_n(&armed, 1, __ATOMIC_RELEASE); }

void cli_interrupt_disarm(void) { __atomic_store_n(&armed, 0, __ATOMIC_RELEASE); }

int cli_interrupted(void) { return __atomic_load_n(&asked, __ATOMIC_ACQUIRE); }

const char *cli_interrupt_name(void)
{
    return cli_interrupted() == SIGTERM ? "SIGTERM" : "SIGINT";
}

void cli_interrupt_raise(void)
{
    int sig = cli_interrupted();
    if (sig)
        end_now(sig);
}
