/* Which file a path names, whatever its spelling, and the rule that no
 * output overwrites an input or shares its file or stream with another
 * output. */
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "paths.h"
#include "say.h"

/* Where a symbolic link points, as a path from the link's folder; NULL
 * when path is not a link. */
static char *link_target(const char *path)
{
    struct stat st;
    if (lstat(path, &st) || !S_ISLNK(st.st_mode))
        return NULL;
    char buf[PATH_MAX];
    ssize_t k = readlink(path, buf, sizeof buf - 1);
    if (k <= 0)
        return NULL;
    buf[k] = '\0';
    const char *slash = strrchr(path, '/');
    char *out = NULL;
    if (buf[0] == '/' || !slash)
        return strdup(buf);
    if (asprintf(&out, "%.*s/%s", (int)(slash - path), path, buf) < 0)
        return NULL;
    return out;
}

char *cli_canonical(const char *path)
{
    char *r = realpath(path, NULL);
    if (r)
        return r;
    /* a link to a file not made yet: its target (at most 40 links, as the
     * kernel follows) */
    char *p = strdup(path), *t = NULL;
    for (int hop = 0; p && hop <= 40 && (t = link_target(p)); hop++) {
        free(p);
        p = t;
    }
    if (t) {   /* still a link after 40 */
        free(p);
        errno = ELOOP;
        return NULL;
    }
    if (!p)
        return NULL;
    const char *slash = strrchr(p, '/');
    char *dir = slash ? strndup(p, (size_t)(slash - p) + 1) : strdup(".");
    char *rdir = dir ? realpath(dir, NULL) : NULL;
    char *out = NULL;
    if (rdir && asprintf(&out, "%s/%s", rdir, slash ? slash + 1 : p) < 0)
        out = NULL;
    free(dir), free(rdir), free(p);
    return out;
}

/* What a path names: the file, pipe, socket or device it reaches now
 * (through links, /dev/stdout, /proc/self/fd/N; "-" is the standard
 * descriptor `fd`), or, when nothing is there yet, the absolute name the
 * file will have (NULL if its folder cannot be found). */
typedef struct place {
    int exists;
    struct stat st;
    char *canon;
} place;

static void place_find(place *p, const char *path, int fd)
{
    memset(p, 0, sizeof *p);
    p->exists = strcmp(path, "-") ? stat(path, &p->st) == 0 : fstat(fd, &p->st) == 0;
    if (!p->exists && strcmp(path, "-"))
        p->canon = cli_canonical(path);
}

/* Whether a and b (named pa and pb) are one file, pipe, socket or
 * device: the same inode, the same device number for two character
 * devices (a terminal under two names), or the same name to be. */
static int same_place(const place *a, const char *pa, const place *b, const char *pb)
{
    if (a->exists && b->exists) {
        if (S_ISCHR(a->st.st_mode) && S_ISCHR(b->st.st_mode))
            return a->st.st_rdev == b->st.st_rdev;
        return a->st.st_dev == b->st.st_dev && a->st.st_ino == b->st.st_ino;
    }
    if (a->exists || b->exists)
        return 0;
    if (a->canon && b->canon)
        return strcmp(a->canon, b->canon) == 0;
    return strcmp(pa, pb) == 0;
}

/* /dev/null (by its device number, under any name) keeps nothing, so any
 * number of outputs may write to it. */
static int keeps_nothing(const place *p)
{
    struct stat null;
    return p->exists && S_ISCHR(p->st.st_mode) && stat("/dev/null", &null) == 0 &&
           S_ISCHR(null.st_mode) && p->st.st_rdev == null.st_rdev;
}

/* An input is overwritten by an output that reaches its file, or a pipe
 * it reads; a terminal or a socket may be read and written. */
static int may_overwrite(const place *p)
{
    return !p->exists || S_ISREG(p->st.st_mode) || S_ISFIFO(p->st.st_mode);
}

static const char *kind(const place *p)
{
    if (!p->exists || S_ISREG(p->st.st_mode))
        return "file";
    return S_ISFIFO(p->st.st_mode) ? "pipe" : S_ISSOCK(p->st.st_mode) ? "socket" : "device";
}

/* "--out 'x'", or "standard output" for an output without an option. */
static void describe(char *buf, size_t size, const cli_path *p)
{
    if (p->opt)
        snprintf(buf, size, "%s '%s'", p->opt, p->path);
    else
        snprintf(buf, size, "standard output");
}

int cli_check_paths(const char *who, const cli_path *in, int nin, const cli_path *out,
                    int nout)
{
    place *pi = calloc((size_t)nin + 1, sizeof *pi), *po = calloc((size_t)nout + 1, sizeof *po);
    char da[PATH_MAX + 64], db[PATH_MAX + 64];
    int rc = 0;
    if (!pi || !po) {
        cli_err("%s: out of memory", who);
        rc = 2;
    }
    for (int k = 0; !rc && k < nin; k++)
        if (in[k].path)
            place_find(&pi[k], in[k].path, 0);
    for (int k = 0; !rc && k < nout; k++)
        if (out[k].path)
            place_find(&po[k], out[k].path, 1);
    for (int a = 0; !rc && a < nout; a++) {
        if (!out[a].path)
            continue;
        describe(da, sizeof da, &out[a]);
        for (int b = a + 1; !rc && b < nout; b++)
            if (out[b].path && same_place(&po[a], out[a].path, &po[b], out[b].path) &&
                !keeps_nothing(&po[a])) {
                describe(db, sizeof db, &out[b]);
                cli_err("%s: %s and %s are one %s: it is named for two outputs",
                        who, da, db, kind(&po[a]));
                rc = 2;
            }
        for (int k = 0; !rc && k < nin; k++)
            if (in[k].path && same_place(&po[a], out[a].path, &pi[k], in[k].path) &&
                may_overwrite(&po[a])) {
                cli_err("%s: %s is the %s: an output must not overwrite it", who,
                        da, in[k].opt);
                rc = 2;
            }
    }
    for (int k = 0; pi && k < nin; k++)
        free(pi[k].canon);
    for (int k = 0; po && k < nout; k++)
        free(po[k].canon);
    free(pi), free(po);
    return rc;
}
