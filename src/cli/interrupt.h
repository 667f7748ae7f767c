/* SIGINT and SIGTERM (interrupt.c). */
#ifndef PSIM_CLI_INTERRUPT_H
#define PSIM_CLI_INTERRUPT_H

/* SIGINT and SIGTERM (interrupt.c).  cli_interrupt_start, first thing in
 * main, blocks them in every thread psim will start; cli_interrupt_watch
 * hands them to a thread of their own that waits for them (sigwait),
 * started after a run's OpenMP threads, so that a tool that places
 * threads in the order they start (likwid-pin) places those: they are taken at
 * once whatever the other threads run (an instrumented build delays a
 * handler until its thread calls into the runtime), and nothing is done
 * in a signal handler.  While a run steps (cli_interrupt_arm ..
 * cli_interrupt_disarm) the first of them is a request to stop
 * (psim_request_stop), which the step running sees at its next poll; the
 * run then fails with one line, removes its temporary outputs, and
 * cli_interrupt_raise ends psim by that signal (a calling shell sees the
 * interrupt; status 128 + the signal: 130 for SIGINT, 143 for SIGTERM).
 * A second signal, a run still going CLI_STOP_GRACE_S seconds after the
 * first, or a signal outside the steps ends psim at once, its named
 * temporary files removed (a second signal after the steps have stopped,
 * as a launcher sends the ranks left when one has ended, without a line).  A signal the parent ignored (nohup) stays
 * ignored.  Where the thread cannot start, the handlers of outfile.c end
 * psim at once, as for the other signals. */
#define CLI_STOP_GRACE_S 3
void cli_interrupt_start(void);
void cli_interrupt_watch(void);
void cli_interrupt_arm(void);
void cli_interrupt_disarm(void);
int cli_interrupted(void);          /* the signal that asked to stop; 0: none */
const char *cli_interrupt_name(void);   /* "SIGINT", "SIGTERM" */
void cli_interrupt_raise(void);     /* end by it, if one asked */

#endif
