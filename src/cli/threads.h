/* How many threads a run gets (threads.c). */
#ifndef PSIM_CLI_THREADS_H
#define PSIM_CLI_THREADS_H

/* The most threads psim runs (--threads, THREADS, OMP_NUM_THREADS). */
#define CLI_MAX_THREADS 4096
/* OMP_NUM_THREADS, if set, within 1..CLI_MAX_THREADS (its first number:
 * the runtime gives the outer level that many threads); one error line
 * and -1 if not. */
int cli_env_threads(void);

/* Threads (threads.c): the count asked, capped by the OpenMP thread limit
 * (OMP_THREAD_LIMIT; cli_threads_note then says so, else NULL); and, under
 * a limit on processes or address space (ulimit -u, -v), whether that many
 * threads can start at once: 0, or -1 after one error line. */
int cli_threads_cap(int asked);
const char *cli_threads_note(void);
int cli_threads_startable(int threads);

#endif
