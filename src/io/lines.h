/* Text files written line by line in parallel, the same bytes whatever
 * the thread count, and the progress of long reads and writes. */
#ifndef PSIM_IO_LINES_H
#define PSIM_IO_LINES_H
#include <stddef.h>
#include <stdio.h>

/* Write n lines, line i made by fn into a buffer of at least line_max
 * bytes (returning its length), to f in order.  Lines are made in chunks
 * by `threads` OpenMP threads and written in order, so the bytes do not
 * depend on the thread count.  0, or -1 when a write failed. */
typedef size_t (*psim_line_fn)(char *out, long i, const void *ctx);
int psim_write_lines(FILE *f, long n, int threads, size_t line_max, psim_line_fn fn,
                     const void *ctx);

/* Progress of long reads and writes (psim_set_io_progress in psim.h). */
void psim_io_progress(int writing, long long done, long long total);
/* While a file is written by parts (each written as a whole file would
 * be): the progress of a part counts on from `before` lines, out of the
 * `total` lines of every part; total < 0: parts no more. */
void psim_io_progress_part(long long before, long long total);

#endif
