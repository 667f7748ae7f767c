/* What runs before any library starts (startup.c). */
#ifndef PSIM_CLI_STARTUP_H
#define PSIM_CLI_STARTUP_H
#include <stddef.h>
#include <sys/types.h>

/* For what runs before any library starts (startup.c, affinity.c: the
 * executable's .preinit_array), with system calls only and no sanitizer's
 * instrumentation: v as decimal text at p (returns the end); a small file
 * into buf, NUL-terminated (its length, or -1). */
#define CLI_EARLY __attribute__((no_sanitize("address", "thread", "undefined")))
CLI_EARLY char *cli_early_put_long(char *p, long v);
CLI_EARLY ssize_t cli_early_read(const char *path, char *buf, size_t size);

#endif
