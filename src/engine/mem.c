#include "mem.h"

#include <stdlib.h>
#include <string.h>

#ifdef PSIM_USE_JEMALLOC
#include <jemalloc/jemalloc.h>
#endif

static size_t round_up(size_t bytes)
{
    if (bytes == 0)
        bytes = 1;
    return (bytes + PSIM_CACHELINE - 1) / PSIM_CACHELINE * PSIM_CACHELINE;
}

void *psim_alloc(size_t bytes)
{
#ifdef PSIM_USE_JEMALLOC
    return mallocx(round_up(bytes), MALLOCX_ALIGN(PSIM_CACHELINE));
#else
    return aligned_alloc(PSIM_CACHELINE, round_up(bytes));
#endif
}

void *psim_calloc(size_t bytes)
{
#ifdef PSIM_USE_JEMALLOC
    return mallocx(round_up(bytes), MALLOCX_ALIGN(PSIM_CACHELINE) | MALLOCX_ZERO);
#else
    void *p = aligned_alloc(PSIM_CACHELINE, round_up(bytes));
    if (p)
        memset(p, 0, round_up(bytes));
    return p;
#endif
}

void psim_free(void *p)
{
    if (!p)
        return;
#ifdef PSIM_USE_JEMALLOC
    dallocx(p, 0);
#else
    free(p);
#endif
}

int psim_reserve(void **p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap && *p)
        return 0;
    size_t ncap = *cap ? *cap : 16;
    while (ncap < need)
        ncap += ncap / 2 + 16;
    void *q = psim_alloc(ncap * elem);
    if (!q)
        return -1;
    if (*p) {
        memcpy(q, *p, *cap * elem);
        psim_free(*p);
    }
    *p = q;
    *cap = ncap;
    return 0;
}

const char *psim_allocator_name(void)
{
#ifdef PSIM_USE_JEMALLOC
    return "jemalloc";
#else
    return "libc";
#endif
}
