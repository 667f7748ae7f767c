/* Messages on stderr (say.c). */
#ifndef PSIM_CLI_SAY_H
#define PSIM_CLI_SAY_H
#include <stddef.h>

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

#endif
