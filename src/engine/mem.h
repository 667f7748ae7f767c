/* Cache-line aligned allocation through jemalloc (or the C library when
 * built without it, e.g. for sanitizer builds). */
#ifndef PSIM_ENGINE_MEM_H
#define PSIM_ENGINE_MEM_H
#include <stddef.h>
#include <stdint.h>

#define PSIM_CACHELINE 64

/* Prefetch the line `bytes` past p, to read (rw 0) or to write (rw 1):
 * for streams that the hardware prefetchers do not keep far enough ahead
 * (docs/performance.md).  The address is an integer sum, so it may lie
 * past the end of p's array: a prefetch never faults. */
#define PSIM_PREFETCH_AHEAD(p, bytes, rw) \
    __builtin_prefetch((const void *)((uintptr_t)(p) + (bytes)), (rw))

void *psim_alloc(size_t bytes);            /* aligned, uninitialised; NULL on failure */
void *psim_calloc(size_t bytes);           /* aligned, zeroed */
void psim_free(void *p);
/* Grow *p (aligned) to hold at least need elements of size elem; keeps the
 * contents.  *cap is in elements.  Returns 0, or -1 when out of memory. */
int psim_reserve(void **p, size_t *cap, size_t need, size_t elem);
const char *psim_allocator_name(void);

#endif
