/* Cache-line aligned memory (mem.h).
 *
 * The library links no allocator of its own: it allocates from the
 * program's.  Where jemalloc is the program's malloc (the psim program
 * links it, as may any program), the library asks it through mallocx, for
 * the alignment and for zeroed memory without writing the pages (fresh
 * pages stay untouched until the threads that work on them first write
 * them); otherwise through aligned_alloc and free.  jemalloc's functions
 * are weak references, resolved only where the program already has
 * jemalloc, so that a program loading libpsim.so (Python, say) keeps its
 * own malloc.  The choice is made once for the process, before the first
 * allocation, so that memory is always freed by the allocator that gave
 * it. */
#include "mem.h"

#include <stdlib.h>
#include <string.h>

#include "psim/psim.h"

#ifdef PSIM_USE_JEMALLOC
#include <dlfcn.h>
#include <jemalloc/jemalloc.h>

#pragma weak mallocx
#pragma weak dallocx

/* Whether the program's malloc is jemalloc: its mallocx resolved, from
 * the same object as the malloc the library's own calls reach. */
static int jemalloc_serves(void)
{
    static int known;   /* 0: not yet looked; 1: jemalloc; 2: another */
    int k = __atomic_load_n(&known, __ATOMIC_RELAXED);
    if (k == 0) {
        void *(*const mx)(size_t, int) = mallocx;
        void (*const dx)(void *, int) = dallocx;
        void *(*const m)(size_t) = malloc;
        Dl_info a, b;
        k = mx && dx && dladdr((void *)mx, &a) && dladdr((void *)m, &b) &&
                    a.dli_fbase == b.dli_fbase
                ? 1
                : 2;
        /* every thread that looks finds the same */
        __atomic_store_n(&known, k, __ATOMIC_RELAXED);
    }
    return k == 1;
}
#else
static int jemalloc_serves(void) { return 0; }
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
    if (jemalloc_serves())
        return mallocx(round_up(bytes), MALLOCX_ALIGN(PSIM_CACHELINE));
#endif
    return aligned_alloc(PSIM_CACHELINE, round_up(bytes));
}

void *psim_calloc(size_t bytes)
{
#ifdef PSIM_USE_JEMALLOC
    if (jemalloc_serves())
        return mallocx(round_up(bytes), MALLOCX_ALIGN(PSIM_CACHELINE) | MALLOCX_ZERO);
#endif
    void *p = aligned_alloc(PSIM_CACHELINE, round_up(bytes));
    if (p)
        memset(p, 0, round_up(bytes));
    return p;
}

void psim_free(void *p)
{
    if (!p)
        return;
#ifdef PSIM_USE_JEMALLOC
    if (jemalloc_serves()) {
        dallocx(p, 0);
        return;
    }
#endif
    free(p);
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

const char *psim_allocator_name(void) { return jemalloc_serves() ? "jemalloc" : "libc"; }

const char *psim_allocator(void) { return psim_allocator_name(); }
