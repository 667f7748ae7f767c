/* Start-up under tight limits.  What runs here runs before any library is
 * initialised (the executable's .preinit_array comes before every
 * constructor, the OpenMP runtime's and the allocator's included), so it
 * uses system calls only: no allocation, no stdio.
 *
 * Under an address-space limit (ulimit -v), two things fail before psim
 * could say why: the OpenMP runtime's constructor allocates, and
 * jemalloc's per-thread caches crash (SIGSEGV) when their memory cannot be
 * mapped, instead of returning NULL.  So, when such a limit is set:
 *   - a limit below what psim needs to start is refused at once, with one
 *     line naming it;
 *   - otherwise jemalloc runs without per-thread caches (tcache:false, as
 *     its compiled-in options; MALLOC_CONF still overrides it), so that an allocation that does not fit returns NULL
 *     and psim names what it could not allocate. */
#include <fcntl.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "startup.h"

/* What psim needs mapped to start and run a small scene, beyond what the
 * program and its libraries already map when this runs (measured: the
 * allocator's first arena, the OpenMP runtime's structures, one thread's
 * stack, stdio's buffers). */
#define START_HEADROOM_KB 16384L

CLI_EARLY char *cli_early_put_long(char *p, long v)
{
    char digits[24];
    int n = 0;
    do
        digits[n++] = (char)('0' + v % 10);
    while ((v /= 10) > 0 && n < 23);
    while (n > 0)
        *p++ = digits[--n];
    return p;
}

/* The kilobytes of address space mapped now (/proc/self/statm's first
 * field, in pages); -1 if unknown. */
CLI_EARLY ssize_t cli_early_read(const char *path, char *buf, size_t size)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return -1;
    ssize_t n = read(fd, buf, size - 1);
    close(fd);
    if (n <= 0)
        return -1;
    buf[n] = '\0';
    return n;
}

CLI_EARLY static long mapped_kb(void)
{
    char buf[128];
    ssize_t n = cli_early_read("/proc/self/statm", buf, sizeof buf);
    if (n < 0)
        return -1;
    long pages = 0;
    for (ssize_t k = 0; k < n && buf[k] >= '0' && buf[k] <= '9'; k++)
        pages = pages * 10 + (buf[k] - '0');
    long page = sysconf(_SC_PAGESIZE);
    return page > 0 ? pages * (page / 1024) : -1;
}

CLI_EARLY static void refuse(long limit_kb, long need_kb)
{
    char line[256], *p = line;
    static const char a[] = "psim: the address-space limit (ulimit -v) of ",
                      b[] = " kB is too small: psim needs at least ",
                      c[] = " kB to start\n";
    memcpy(p, a, sizeof a - 1), p += sizeof a - 1;
    p = cli_early_put_long(p, limit_kb);
    memcpy(p, b, sizeof b - 1), p += sizeof b - 1;
    p = cli_early_put_long(p, need_kb);
    memcpy(p, c, sizeof c - 1), p += sizeof c - 1;
    ssize_t w = write(STDERR_FILENO, line, (size_t)(p - line));
    (void)w;
    _exit(1);
}

#ifdef PSIM_USE_JEMALLOC
#include <jemalloc/jemalloc.h>

/* jemalloc's compiled-in options, read when it starts (after this runs,
 * before MALLOC_CONF, which still overrides them). */
const char *malloc_conf;

/* psim's malloc is jemalloc, and the library's allocations follow the
 * program's malloc (src/engine/mem.c): a reference that keeps libjemalloc
 * linked where the linker drops libraries no call needs (--as-needed). */
__attribute__((used)) static void *(*const jemalloc_kept)(size_t, int) = mallocx;
#endif

CLI_EARLY static void allocator_without_caches(void)
{
#ifdef PSIM_USE_JEMALLOC
    malloc_conf = "tcache:false";
#endif
}

CLI_EARLY static void start_limits(int argc, char **argv, char **envp)
{
    (void)argc, (void)argv, (void)envp;
    struct rlimit as;
    if (getrlimit(RLIMIT_AS, &as) != 0 || as.rlim_cur == RLIM_INFINITY)
        return;
    long limit_kb = (long)(as.rlim_cur / 1024), now_kb = mapped_kb();
    if (now_kb >= 0 && limit_kb < now_kb + START_HEADROOM_KB)
        refuse(limit_kb, now_kb + START_HEADROOM_KB);
    allocator_without_caches();
}

__attribute__((section(".preinit_array"), used)) static void (*const start_limits_entry)(
    int, char **, char **) = start_limits;
