/* The files a command reads and writes, as named (paths.c). */
#ifndef PSIM_CLI_PATHS_H
#define PSIM_CLI_PATHS_H

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
/* The absolute name of path, whether or not it exists yet, through its
 * symbolic links (malloc'd; NULL when its folder cannot be found). */
char *cli_canonical(const char *path);

#endif
