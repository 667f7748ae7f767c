/* SIGINT and SIGTERM while a run steps: a request to stop, not a kill
 * (cli.h).  The run stops at its next poll (src/engine/poll.h), fails with
 * one line, removes its temporary outputs as any failed run does, and
 * psim then ends by the signal.  Outside the steps, and for a second
 * signal, the handlers there were before (src/cli/util.c's, which remove
 * the temporary files and end psim at once) stay in charge. */
#include <signal.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "psim/psim.h"

static const int stops[] = {SIGINT, SIGTERM};
#define NSTOPS ((int)(sizeof stops / sizeof stops[0]))

static struct sigaction before[NSTOPS], before_alarm;
static int armed[NSTOPS];
static volatile sig_atomic_t asked;        /* the signal that asked; 0: none */
static volatile sig_atomic_t alarm_taken;  /* SIGALRM is on_grace's */

/* One line on stderr from a handler (write is async-signal-safe). */
static void say(const char *line)
{
    ssize_t w = write(STDERR_FILENO, line, strlen(line));
    (void)w;
}

/* End now by sig, through the handler there was before (it is delivered
 * once this handler returns, or at once from another handler). */
static void end_now(int sig)
{
    for (int k = 0; k < NSTOPS; k++)
        if (stops[k] == sig && armed[k])
            sigaction(sig, &before[k], NULL);
    raise(sig);
}

static void on_grace(int sig)
{
    (void)sig;
    say(asked == SIGTERM ? "psim: SIGTERM: the run did not stop in time: ended at once\n"
                         : "psim: SIGINT: the run did not stop in time: ended at once\n");
    end_now(asked);
}

static void on_stop(int sig)
{
    if (asked) {   /* a second one */
        say(sig == SIGTERM ? "psim: SIGTERM again: ended at once\n"
                           : "psim: SIGINT again: ended at once\n");
        end_now(sig);
        return;
    }
    asked = sig;
    psim_request_stop();
    struct sigaction a;
    memset(&a, 0, sizeof a);
    a.sa_handler = on_grace;
    sigemptyset(&a.sa_mask);
    if (sigaction(SIGALRM, &a, NULL) == 0) {
        alarm_taken = 1;
        alarm(CLI_STOP_GRACE_S);
    }
}

void cli_interrupt_arm(void)
{
    sigaction(SIGALRM, NULL, &before_alarm);
    struct sigaction a;
    memset(&a, 0, sizeof a);
    a.sa_handler = on_stop;
    a.sa_flags = SA_RESTART;   /* writes and reads go on */
    sigemptyset(&a.sa_mask);
    for (int k = 0; k < NSTOPS; k++) {
        if (sigaction(stops[k], NULL, &before[k]) || before[k].sa_handler == SIG_IGN)
            continue;   /* ignored by the parent (nohup): it stays so */
        armed[k] = sigaction(stops[k], &a, NULL) == 0;
    }
}

void cli_interrupt_disarm(void)
{
    for (int k = 0; k < NSTOPS; k++)
        if (armed[k]) {
            sigaction(stops[k], &before[k], NULL);
            armed[k] = 0;
        }
    if (alarm_taken) {
        alarm(0);
        sigaction(SIGALRM, &before_alarm, NULL);
        alarm_taken = 0;
    }
}

int cli_interrupted(void) { return asked; }

const char *cli_interrupt_name(void) { return asked == SIGTERM ? "SIGTERM" : "SIGINT"; }

void cli_interrupt_raise(void)
{
    int sig = asked;
    if (!sig)
        return;
    cli_interrupt_disarm();
    signal(sig, SIG_DFL);
    raise(sig);
    _exit(128 + sig);   /* the signal blocked: the shell's status for it */
}
