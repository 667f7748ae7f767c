/* Text files written line by line in parallel (lines.h). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>

#include <omp.h>

#include "lines.h"
#include "psim/psim.h"

static psim_io_progress_fn progress_fn;
static void *progress_ctx;

void psim_set_io_progress(psim_io_progress_fn fn, void *ctx)
{
    progress_fn = fn;
    progress_ctx = ctx;
}

/* a file written by parts: the lines before the part, and the file's */
static long long part_before, part_total = -1;

void psim_io_progress_part(long long before, long long total)
{
    part_before = before;
    part_total = total;
}

void psim_io_progress(int writing, long long done, long long total)
{
    if (part_total >= 0)
        done += part_before, total = part_total;
    if (progress_fn)
        progress_fn(progress_ctx, writing, done, total);
}

/* Lines per chunk: a few hundred kB of text, one thread's unit of work;
 * fewer when that would leave threads without one (10^4 lines on two
 * threads had been chunks of 8192 and 1808 lines), but not so few that
 * the ordered writes cost more than the lines. */
#define CHUNK_LINES_MAX 8192L
#define CHUNK_LINES_MIN 1024L

static long chunk_lines(long n, int threads)
{
    long per = threads > 1 ? (n + 4L * threads - 1) / (4L * threads) : CHUNK_LINES_MAX;
    return per > CHUNK_LINES_MAX ? CHUNK_LINES_MAX : per < CHUNK_LINES_MIN ? CHUNK_LINES_MIN : per;
}

typedef struct linebuf {
    char *p;
    size_t cap;
} linebuf;

/* Lines [lo, hi) into b; their length, or -1 when out of memory. */
static long make_lines(linebuf *b, long lo, long hi, size_t line_max, psim_line_fn fn,
                       const void *ctx)
{
    size_t len = 0;
    for (long i = lo; i < hi; i++) {
        if (b->cap - len < line_max) {
            size_t cap = b->cap ? 2 * b->cap : (size_t)1 << 20;
            while (cap - len < line_max)
                cap *= 2;
            char *p = realloc(b->p, cap);
            if (!p)
                return -1;
            b->p = p, b->cap = cap;
        }
        len += fn(b->p + len, i, ctx);
    }
    return (long)len;
}

int psim_write_lines(FILE *f, long n, int threads, size_t line_max, psim_line_fn fn,
                     const void *ctx)
{
    if (n <= 0)
        return 0;
    const long per = chunk_lines(n, threads);
    long chunks = (n + per - 1) / per;
    if (threads > chunks)
        threads = (int)chunks;
    int failed = 0, err = 0;
    if (threads <= 1) {
        linebuf b = {NULL, 0};
        for (long c = 0; c < chunks && !failed; c++) {
            long lo = c * per, hi = lo + per < n ? lo + per : n;
            long len = make_lines(&b, lo, hi, line_max, fn, ctx);
            if (len < 0 || fwrite(b.p, 1, (size_t)len, f) != (size_t)len) {
                failed = 1;
                err = len < 0 ? ENOMEM : errno;
            }
            psim_io_progress(1, hi, n);
        }
        free(b.p);
    } else {
        /* each thread makes every threads-th chunk; the chunks are written
         * in order (ordered), the writing of one overlapping the making of
         * the next ones by the other threads */
#pragma omp parallel num_threads(threads)
        {
            linebuf b = {NULL, 0};
#pragma omp for ordered schedule(static, 1)
            for (long c = 0; c < chunks; c++) {
                long lo = c * per, hi = lo + per < n ? lo + per : n;
                long len = make_lines(&b, lo, hi, line_max, fn, ctx);
#pragma omp ordered
                {
                    if (!failed && (len < 0 || fwrite(b.p, 1, (size_t)len, f) != (size_t)len)) {
                        failed = 1;
                        err = len < 0 ? ENOMEM : errno;
                    }
                    if (!failed)
                        psim_io_progress(1, hi, n);
                }
            }
            free(b.p);
        }
    }
    if (failed) {
        errno = err ? err : EIO;
        return -1;
    }
    return 0;
}
