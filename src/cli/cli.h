/* The psim command line: subcommands and their shared helpers. */
#ifndef PSIM_CLI_H
#define PSIM_CLI_H
#include <getopt.h>
#include <sched.h>
#include <stdio.h>

#include <stdint.h>
#include <sys/types.h>
#include <time.h>

#include "../io/scene.h"
#include "psim/topology.h"

int cli_run(int argc, char **argv);   /* psim [OPTIONS] [SCENE [THREADS]] */
int cli_gen(int argc, char **argv);   /* psim gen [OPTIONS] */
int cli_plan(int argc, char **argv);  /* psim plan | psim topo */
int cli_models(int argc, char **argv); /* psim models */

/* The most threads psim runs (--threads, THREADS, OMP_NUM_THREADS). */
#define CLI_MAX_THREADS 4096
/* OMP_NUM_THREADS, if set, within 1..CLI_MAX_THREADS (its first number:
 * the runtime gives the outer level that many threads); one error line
 * and -1 if not. */
int cli_env_threads(void);

/* The CPUs and OpenMP settings a run starts with (affinity.c, fixed
 * before the OpenMP runtime starts; docs/experiments.md, "Pinning").
 * cli_wait_note: why OMP_WAIT_POLICY=passive was chosen (NULL if it
 * was not: the runtime's default, or the user's own setting).
 * cli_binders_removed: the runtime's binding variables taken out because
 * --pin places the threads ("OMP_PROC_BIND=spread ..."; NULL: none).
 * cli_outside_placement: what places the threads when psim does not
 * (those variables, likwid-pin; NULL: nothing).  cli_with_start_cpus
 * calls fn with the calling thread's mask widened back to the start mask
 * (the runtime may have bound it), then restores it. */
const char *cli_wait_note(void);
const char *cli_binders_removed(void);
const char *cli_outside_placement(void);
int cli_with_start_cpus(int (*fn)(void *), void *ctx);
/* For what runs before any library starts (startup.c, affinity.c: the
 * executable's .preinit_array), with system calls only and no sanitizer's
 * instrumentation: v as decimal text at p (returns the end); a small file
 * into buf, NUL-terminated (its length, or -1). */
#define CLI_EARLY __attribute__((no_sanitize("address", "thread", "undefined")))
CLI_EARLY char *cli_early_put_long(char *p, long v);
CLI_EARLY ssize_t cli_early_read(const char *path, char *buf, size_t size);

/* Threads (threads.c): the count asked, capped by the OpenMP thread limit
 * (OMP_THREAD_LIMIT; cli_threads_note then says so, else NULL); and, under
 * a limit on processes or address space (ulimit -u, -v), whether that many
 * threads can start at once: 0, or -1 after one error line. */
int cli_threads_cap(int asked);
const char *cli_threads_note(void);
int cli_threads_startable(int threads);

/* Messages (say.c).  cli_err prints one line on stderr, "psim: ...",
 * from a printf format without its newline, with every control byte it
 * holds (from a file name, an argument, an input's bytes) escaped as \n,
 * \t, \r or \xHH, and C1 controls and invalid UTF-8 bytes as \xHH: a
 * message is always one line and cannot drive the terminal.  cli_escape
 * writes src so escaped into dst (cap bytes with its NUL; cut short if
 * it does not fit) and returns its length; cli_shown returns a malloc'd
 * escaped copy (NULL without memory). */
void cli_err(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
size_t cli_escape(char *dst, size_t cap, const char *src);
char *cli_shown(const char *name);

/* An output file that appears only when complete.  A regular file (or a
 * path that does not exist yet; a symbolic link is followed) is written to
 * an unnamed file in its folder (O_TMPFILE) and linked into place by
 * outfile_commit_all (over an old file: linked as ".psim-XXXXXX" beside it
 * and renamed over it), so that nothing is left whatever ends the process,
 * SIGKILL and faults included.  Where the file system has no unnamed files
 * or /proc is missing, the fallback writes a temporary file ".psim-XXXXXX"
 * beside it and renames it into place; that file is removed on failure,
 * on the signals that end a run (INT, TERM, HUP, QUIT, PIPE, ALRM, XCPU,
 * XFSZ, VTALRM, PROF, USR1, USR2) and on faults (SEGV, BUS, ABRT, TRAP,
 * FPE, ILL, SYS), and is left only by SIGKILL or a lost machine.  Any
 * other path (a device, a FIFO) is written directly; "-" is standard
 * output.  The file replaced keeps its permissions; a new one gets
 * 0666 less the umask; a read-only file is refused. */
typedef struct outfile {
    char *path;         /* the file to replace; NULL when writing directly */
    char *tmp;          /* the fallback's temporary file, or NULL */
    int unnamed, fd;    /* fd keeps the unnamed file to link, if unnamed */
    const char *name;   /* for messages */
    FILE *f;
} outfile;

int outfile_open(outfile *o, const char *path);
/* The absolute name of path, whether or not it exists yet, through its
 * symbolic links (malloc'd; NULL when its folder cannot be found). */
char *cli_canonical(const char *path);
/* Close every open file of list, then, if all were written, put them in
 * place; otherwise remove them all.  One error line on failure. */
int outfile_commit_all(outfile *const *list, int n);
int outfile_commit(outfile *o);
void outfile_abort(outfile *o);

/* A file a command reads or writes, as the command line names it: opt is
 * the option ("--out") or, for an input, what it is ("scene"); NULL for
 * an output names standard output.  path NULL: not given; "-": standard
 * input (an input) or standard output (an output). */
typedef struct cli_path {
    const char *opt, *path;
} cli_path;

/* No output may overwrite an input or share a file or a stream with
 * another output, whatever the paths' spelling: by the same name, through
 * links, /dev/stdout, /dev/stdin or /proc/self/fd/N, or through standard
 * input or output bound to the file.  Two outputs are one when they reach
 * the same file, pipe, socket or device (character devices by device
 * number) or will be the same new file; /dev/null may take any number.
 * An output overwrites an input that is the same file or pipe (a
 * terminal or socket may be read and written).  0, or 2 after one line
 * starting "who: ". */
int cli_check_paths(const char *who, const cli_path *in, int nin, const cli_path *out,
                    int nout);

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
 * temporary files removed.  A signal the parent ignored (nohup) stays
 * ignored.  Where the thread cannot start, the handlers of outfile.c end
 * psim at once, as for the other signals. */
#define CLI_STOP_GRACE_S 3
void cli_interrupt_start(void);
void cli_interrupt_watch(void);
void cli_interrupt_arm(void);
void cli_interrupt_disarm(void);
int cli_interrupted(void);          /* the signal that asked to stop; 0: none */
const char *cli_interrupt_name(void);   /* "SIGINT", "SIGTERM" */
/* Remove the named temporary files of the outputs (outfile.c). */
void cli_remove_temps(void);
void cli_interrupt_raise(void);     /* end by it, if one asked */

/* --thermo N and --thermo-file (thermo.c): rows at the start, every
 * `every` steps and after the last step; the table to `table` (NULL: none),
 * CSV to `csv` (NULL: none).  With speed (--thermo-speed), a last column
 * of steps per second of wall time since the previous row: the one
 * column read from the clock, so left out unless asked for, which keeps
 * the rows the same bytes from run to run. */
typedef struct cli_thermo {
    long every;             /* 0: no rows */
    int speed;
    FILE *table, *csv;
    int ncols, pressure;
    const char *col[PSIM_THERMO_MAX];
    uint64_t last[PSIM_THERMO_MAX];
    double last_virial;
    long last_step;
    double last_wall;       /* psim_now() at the previous row */
} cli_thermo;

void thermo_init(cli_thermo *t, long every, int speed);
/* The header and the row of the state before the first step; then after
 * step k of steps.  0, or -1 with err set: no memory, or a total beyond
 * the largest double (a state whose squared speeds overflow is summed
 * in units of a power of two: only a total that no double holds fails). */
int thermo_start(cli_thermo *t, psim_sim *s, FILE *table, FILE *csv, psim_error *err);
int thermo_step(cli_thermo *t, psim_sim *s, long k, long steps, psim_error *err);
/* Whether step k of steps has a row. */
int thermo_due(const cli_thermo *t, long k, long steps);

/* Pinning options shared by the run and plan commands. */
enum { CLI_OPT_PIN = 1000, CLI_OPT_TOPOLOGY, CLI_OPT_MEM, CLI_OPT_DRY_RUN };

typedef struct cli_pin {
    psim_pin_policy policy;
    const char *topology;
    psim_mem_policy mem;
    int dry_run;
    psim_topo *topo;      /* loaded only when the options need it */
    psim_pin_plan plan;
    int *observed;        /* PU each thread was seen on after binding */
} cli_pin;

int cli_pin_option(cli_pin *p, int opt, const char *arg);
/* Load, plan, set the memory policy and bind; -1 after printing an error. */
int cli_pin_setup(cli_pin *p, int threads, int quiet);
/* The run summary's placement line: the plan and where each thread ran
 * (with --pin), or where each ran when the OpenMP runtime or likwid-pin
 * placed them. */
void cli_pin_summary(FILE *f, const cli_pin *p, const psim_sim *s);
char *cli_pin_json(const cli_pin *p);  /* malloc'd JSON members */
void cli_pin_free(cli_pin *p);

/* --report table and the per-thread members of --stats (report.c). */
void cli_report(FILE *f, const psim_sim *s, const cli_pin *p);
char *cli_threads_json(const psim_sim *s, const cli_pin *p);

#endif
