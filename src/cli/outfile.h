/* Output files that appear only when complete (outfile.c). */
#ifndef PSIM_CLI_OUTFILE_H
#define PSIM_CLI_OUTFILE_H
#include <stdio.h>

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
/* The same, a regular file written to a named temporary file (o->tmp,
 * the fallback's), never to an unnamed one: other processes (MPI ranks)
 * open it by that name to write into it. */
int outfile_open_named(outfile *o, const char *path);
/* Close every open file of list, then, if all were written, put them in
 * place; otherwise remove them all.  One error line on failure. */
int outfile_commit_all(outfile *const *list, int n);
int outfile_commit(outfile *o);
void outfile_abort(outfile *o);
/* Remove the named temporary files of the outputs (outfile.c). */
void cli_remove_temps(void);

#endif
