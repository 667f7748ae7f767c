/* Output files that appear only when whole (outfile.h): an unnamed file in
 * the output's folder (O_TMPFILE), linked into place at the commit, so
 * that nothing is left whatever ends the process; where the file system
 * or /proc does not allow that, a hidden temporary file beside it,
 * removed on failure and on the signals that end a run. */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "outfile.h"
#include "paths.h"
#include "say.h"

/* Named temporary files (the fallback's, and an unnamed file's name for
 * the moment between its link and the rename over the old file) to
 * remove if a signal ends the run. */
#define MAX_TEMPS 8
static char *volatile temps[MAX_TEMPS];

void cli_remove_temps(void)
{
    for (int k = 0; k < MAX_TEMPS; k++)
        if (temps[k])
            unlink(temps[k]);
}

static void on_signal(int sig)
{
    cli_remove_temps();
    signal(sig, SIG_DFL);
    raise(sig);
}

static void catch_each(const int *sigs, size_t n)
{
    for (size_t k = 0; k < n; k++) {
        void (*was)(int) = signal(sigs[k], on_signal);
        if (was == SIG_IGN)   /* ignored by the parent (nohup): keep it so */
            signal(sigs[k], SIG_IGN);
    }
}

/* Handlers that remove the named temporary files: for every signal whose
 * default action ends the process and that a run can meet (interrupts, a
 * closed pipe, limits, timers); with `faults`, also for those of a fault
 * (SEGV, BUS, ABRT, TRAP, FPE, ILL, SYS), which only the fallback needs:
 * an unnamed file vanishes with the process, and a sanitizer keeps its
 * own handlers for them. */
static void catch_signals(int faults)
{
    static const int ending[] = {SIGINT,  SIGTERM, SIGHUP,    SIGQUIT, SIGPIPE, SIGALRM,
                                 SIGXCPU, SIGXFSZ, SIGVTALRM, SIGPROF, SIGUSR1, SIGUSR2};
    static const int fault[] = {SIGSEGV, SIGBUS, SIGABRT, SIGTRAP, SIGFPE, SIGILL, SIGSYS};
    static int ending_caught, faults_caught;
    if (!ending_caught)
        catch_each(ending, sizeof ending / sizeof ending[0]);
    if (faults && !faults_caught)
        catch_each(fault, sizeof fault / sizeof fault[0]);
    ending_caught = 1;
    faults_caught |= faults;
}

static void track_temp(char *path, int add)
{
    for (int k = 0; k < MAX_TEMPS; k++)
        if (add ? temps[k] == NULL : temps[k] == path) {
            temps[k] = add ? path : NULL;
            return;
        }
}

/* The folder of an absolute path (malloc'd; "/" for a file at the root). */
static char *folder_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    return !slash || slash == path ? strdup("/") : strndup(path, (size_t)(slash - path));
}

/* "DIR/.psim-XXXXXX": a short hidden name in dir, whatever the length of
 * the output's name (malloc'd); with `pattern`, the X's stay for mkstemp,
 * otherwise they are six random letters or digits. */
static char *temp_name(const char *dir, int pattern)
{
    static const char abc[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
    static unsigned long long seq;
    char x[7] = "XXXXXX";
    if (!pattern) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        /* splitmix64 of the time, process and call */
        unsigned long long z = (unsigned long long)ts.tv_nsec ^
                               ((unsigned long long)ts.tv_sec << 30) ^
                               ((unsigned long long)getpid() << 44) ^
                               (++seq * 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        z ^= z >> 31;
        for (int k = 0; k < 6; k++, z /= 62)
            x[k] = abc[z % 62];
    }
    char *out = NULL;
    if (asprintf(&out, "%s/.psim-%s", strcmp(dir, "/") ? dir : "", x) < 0)
        return NULL;
    return out;
}

/* An unnamed file in folder dir with permissions `mode`, that /proc lets
 * link into place later: its descriptor; -1 with errno set; -2 when the
 * file system has no unnamed files or /proc is not there (the fallback
 * then), or PSIM_TMPFILE=0 asks for the fallback (tests). */
static int open_unnamed(const char *dir, mode_t mode)
{
    const char *env = getenv("PSIM_TMPFILE");
    if (env && strcmp(env, "0") == 0)
        return -2;
    int fd = open(dir, O_WRONLY | O_TMPFILE | O_CLOEXEC, 0600);
    if (fd < 0)
        return errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL ? -2 : -1;
    char proc[32];
    struct stat a, b;
    snprintf(proc, sizeof proc, "/proc/self/fd/%d", fd);
    if (stat(proc, &a) || fstat(fd, &b) || a.st_dev != b.st_dev || a.st_ino != b.st_ino) {
        close(fd);
        return -2;
    }
    fchmod(fd, mode);
    return fd;
}

/* The fallback: a temporary file "DIR/.psim-XXXXXX" beside the output
 * (o->tmp), renamed into place at the commit; its descriptor, or -1. */
static int open_named(outfile *o, const char *dir, mode_t mode)
{
    o->tmp = temp_name(dir, 1);
    int fd = o->tmp ? mkstemp(o->tmp) : -1;
    if (fd < 0) {
        int e = o->tmp ? errno : ENOMEM;
        free(o->tmp);
        o->tmp = NULL;
        errno = e;
        return -1;
    }
    track_temp(o->tmp, 1);
    catch_signals(1);
    fchmod(fd, mode);
    return fd;
}

static int open_direct(outfile *o, const char *path)
{
    o->f = fopen(path, "w");
    if (!o->f) {
        cli_err("psim: %s: cannot write: %s", path, strerror(errno));
        outfile_abort(o);
        return -1;
    }
    return 0;
}

/* The file the output will be (o->path, through its links), written
 * first to an unnamed file, else to the fallback's named one: the
 * descriptor to write, or -1 with errno set. */
static int open_hidden(outfile *o, const char *path, mode_t mode, int named)
{
    struct stat st;
    o->path = cli_canonical(path);
    if (!o->path)
        return -1;
    /* a name too long for its folder fails now, not at the commit */
    if (lstat(o->path, &st) != 0 && errno != ENOENT)
        return -1;
    char *dir = folder_of(o->path);
    if (!dir)
        return -1;
    int fd = named ? -2 : open_unnamed(dir, mode);
    if (fd >= 0) {
        /* one descriptor to write through, and one that keeps the file
         * to link after the other is closed (above 2, whatever is open) */
        o->unnamed = 1;
        o->fd = fd;
        catch_signals(0);
        fd = fcntl(fd, F_DUPFD_CLOEXEC, 3);
    } else if (fd == -2)
        fd = open_named(o, dir, mode);
    int e = errno;
    free(dir);
    errno = e;
    return fd;
}

static int open_as(outfile *o, const char *path, int named)
{
    memset(o, 0, sizeof *o);
    o->name = path;
    if (!*path) {
        cli_err("psim: an output file name is empty");
        return -1;
    }
    if (strcmp(path, "-") == 0) {
        o->name = "<stdout>";
        o->f = stdout;
        return 0;
    }
    struct stat st;
    int exists = stat(path, &st) == 0;
    if (exists && !S_ISREG(st.st_mode))
        return open_direct(o, path); /* a device or FIFO: no rename over it */
    /* A rename replaces a file that may not be written (and root may write
     * any): a file without write permission, for this user or for anyone,
     * is kept, as a shell's '>' would keep it. */
    if (exists && (access(path, W_OK) != 0 || !(st.st_mode & 0222))) {
        cli_err("psim: %s: cannot write: the file is read-only", path);
        return -1;
    }
    /* the permissions of the file replaced, or those of a new file */
    mode_t mask = umask(0);
    umask(mask);
    errno = 0;
    int fd = open_hidden(o, path, exists ? (st.st_mode & 07777) : (0666 & ~mask), named);
    o->f = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (!o->f) {
        cli_err("psim: %s: cannot write: %s", path, strerror(errno ? errno : ENOMEM));
        if (fd >= 0)
            close(fd);
        outfile_abort(o);
        return -1;
    }
    return 0;
}

int outfile_open(outfile *o, const char *path)
{
    return open_as(o, path, 0);
}

int outfile_open_named(outfile *o, const char *path)
{
    return open_as(o, path, 1);
}

/* Flush and close; 0, or -1 after one error line.  An unnamed file stays
 * open on o->fd, to be linked. */
static int outfile_close(outfile *o)
{
    if (!o->f)
        return 0;
    int bad = fflush(o->f) != 0 || ferror(o->f);
    int err = errno;
    if (o->f != stdout && fclose(o->f) != 0 && !bad) {
        bad = 1;
        err = errno;
    }
    o->f = NULL;
    if (bad)
        cli_err("psim: %s: write failed: %s", o->name, strerror(err ? err : EIO));
    return bad ? -1 : 0;
}

/* Give the unnamed file open on fd the name path: a link, or where a file
 * is there already, a link under a temporary name renamed over it (so the
 * old file is replaced whole, never removed first); 0, or -1 with errno
 * set. */
static int link_unnamed(int fd, const char *path)
{
    char proc[32];
    snprintf(proc, sizeof proc, "/proc/self/fd/%d", fd);
    if (linkat(AT_FDCWD, proc, AT_FDCWD, path, AT_SYMLINK_FOLLOW) == 0)
        return 0;
    if (errno != EEXIST)
        return -1;
    char *dir = folder_of(path);
    int rc = -1, e = ENOMEM;
    for (int tries = 0; dir && tries < 100; tries++) {
        char *tmp = temp_name(dir, 0);
        if (!tmp)
            break;
        if (linkat(AT_FDCWD, proc, AT_FDCWD, tmp, AT_SYMLINK_FOLLOW) == 0) {
            track_temp(tmp, 1);
            rc = rename(tmp, path);
            e = errno;
            if (rc)
                unlink(tmp);
            track_temp(tmp, 0);
            free(tmp);
            break;
        }
        e = errno;
        free(tmp);
        if (e != EEXIST)
            break;
    }
    free(dir);
    errno = e;
    return rc;
}

/* Put o's file in place; 0, or -1 with errno set. */
static int publish(outfile *o)
{
    if (o->tmp) {
        if (rename(o->tmp, o->path) != 0)
            return -1;
        track_temp(o->tmp, 0);
        free(o->tmp);
        o->tmp = NULL;
    } else if (o->unnamed) {
        if (link_unnamed(o->fd, o->path) != 0)
            return -1;
        close(o->fd);
        o->unnamed = 0;
    }
    return 0;
}

int outfile_commit_all(outfile *const *list, int n)
{
    int bad = 0;
    for (int k = 0; k < n && !bad; k++)
        bad = outfile_close(list[k]);
    for (int k = 0; k < n && !bad; k++)
        if (publish(list[k]) != 0) {
            cli_err("psim: %s: write failed: %s", list[k]->name, strerror(errno));
            bad = 1;
        }
    for (int k = 0; k < n; k++)
        if (bad)
            outfile_abort(list[k]);
        else {
            free(list[k]->path);
            list[k]->path = NULL;
        }
    return bad ? -1 : 0;
}

int outfile_commit(outfile *o)
{
    outfile *one[1] = {o};
    return outfile_commit_all(one, 1);
}

void outfile_abort(outfile *o)
{
    if (o->f && o->f != stdout)
        fclose(o->f);
    if (o->unnamed)
        close(o->fd);   /* the file goes with its last descriptor */
    if (o->tmp) {
        unlink(o->tmp);
        track_temp(o->tmp, 0);
    }
    free(o->tmp);
    free(o->path);
    memset(o, 0, sizeof *o);
}
