/* Cache-line aligned allocation from the program's allocator: through
 * jemalloc where it is the program's malloc, else through the C library
 * (mem.c). */
#ifndef PSIM_ENGINE_MEM_H
#define PSIM_ENGINE_MEM_H
#include <stddef.h>
#include <stdint.h>

#define PSIM_CACHELINE 64

/* Prefetch the line `bytes` past p, to read (rw 0) or to write (rw 1):
 * for streams that the hardware prefetchers do not keep far enough ahead
 * (docs/performance.md, "Positions loaded before the pair tests").  The
 * address is an integer sum, so it may lie past the end of p's array: a
 * prefetch never faults. */
#define PSIM_PREFETCH_AHEAD(p, bytes, rw) \
    __builtin_prefetch((const void *)((uintptr_t)(p) + (bytes)), (rw))

/* Read one word of each cache line of the n doubles at a: plain loads,
 * which bring the lines into the cache before scattered reads (gathers)
 * need them.  Software prefetches of the same lines, issued ahead in a
 * loop, are dropped once the core's miss buffers are full (an AMD EPYC
 * VM: the force model's pair tests took 1.45 times as long after them as
 * after these loads, docs/performance.md, "Positions loaded before the
 * pair tests"). */
static inline void psim_touch(const double *a, size_t n)
{
    uint64_t sum = 0, v;
    for (size_t q = 0; q < n; q += PSIM_CACHELINE / sizeof *a) {
        __builtin_memcpy(&v, a + q, sizeof v);
        sum ^= v;
    }
    if (n > 0) {   /* the last line, where a is not at a line's start */
        __builtin_memcpy(&v, a + n - 1, sizeof v);
        sum ^= v;
    }
    __asm__ volatile("" : : "r"(sum));   /* kept: nothing else reads it */
}

void *psim_alloc(size_t bytes);            /* aligned, uninitialised; NULL on failure */
void *psim_calloc(size_t bytes);           /* aligned, zeroed */
void psim_free(void *p);
/* Grow *p (aligned) to hold at least need elements of size elem; keeps the
 * contents.  *cap is in elements.  Returns 0, or -1 when out of memory. */
int psim_reserve(void **p, size_t *cap, size_t need, size_t elem);
/* "jemalloc" or "libc": the allocator psim_alloc uses in this process. */
const char *psim_allocator_name(void);

#endif
