#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "../engine/timer.h"

int cli_long(const char *opt, const char *text, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (end == text || *end || errno == ERANGE) {
        fprintf(stderr, "psim: %s: expected an integer, got '%s'\n", opt, text);
        return -1;
    }
    if (v < lo || v > hi) {
        fprintf(stderr, "psim: %s: %ld is out of range %ld..%ld\n", opt, v, lo, hi);
        return -1;
    }
    *out = v;
    return 0;
}

int cli_double(const char *opt, const char *text, double lo, double hi,
               double *out)
{
    char *end;
    double v = strtod(text, &end);
    if (end == text || *end || !isfinite(v)) {
        fprintf(stderr, "psim: %s: expected a finite number, got '%s'\n", opt, text);
        return -1;
    }
    if (v < lo || v > hi) {
        fprintf(stderr, "psim: %s: %g is out of range %g..%g\n", opt, v, lo, hi);
        return -1;
    }
    *out = v;
    return 0;
}

int outfile_open(outfile *o, const char *path)
{
    memset(o, 0, sizeof *o);
    if (strcmp(path, "-") == 0) {
        o->f = stdout;
        return 0;
    }
    o->path = strdup(path);
    size_t len = strlen(path) + 16;
    o->tmp = malloc(len);
    if (!o->path || !o->tmp) {
        fprintf(stderr, "psim: %s: out of memory\n", path);
        outfile_abort(o);
        return -1;
    }
    snprintf(o->tmp, len, "%s.tmpXXXXXX", path);
    int fd = mkstemp(o->tmp);
    if (fd < 0) {
        fprintf(stderr, "psim: %s: cannot write: %s\n", path, strerror(errno));
        free(o->tmp);
        o->tmp = NULL;
        outfile_abort(o);
        return -1;
    }
    fchmod(fd, 0644);
    o->f = fdopen(fd, "w");
    if (!o->f) {
        fprintf(stderr, "psim: %s: cannot write: %s\n", path, strerror(errno));
        close(fd);
        outfile_abort(o);
        return -1;
    }
    return 0;
}

int outfile_commit(outfile *o)
{
    if (!o->f)
        return 0;
    if (o->f == stdout) {
        o->f = NULL;
        return fflush(stdout) ? -1 : 0;
    }
    int bad = ferror(o->f);
    bad |= fclose(o->f) != 0;
    o->f = NULL;
    if (bad || rename(o->tmp, o->path) != 0) {
        fprintf(stderr, "psim: %s: write failed: %s\n", o->path, strerror(errno));
        outfile_abort(o);
        return -1;
    }
    free(o->tmp);
    free(o->path);
    o->tmp = o->path = NULL;
    return 0;
}

void outfile_abort(outfile *o)
{
    if (o->f && o->f != stdout)
        fclose(o->f);
    if (o->tmp)
        unlink(o->tmp);
    free(o->tmp);
    free(o->path);
    memset(o, 0, sizeof *o);
}

void progress_init(progress *p, long total, int quiet)
{
    memset(p, 0, sizeof *p);
    p->enabled = !quiet && isatty(STDERR_FILENO);
    p->total = total;
    p->start = p->last = psim_now();
}

void progress_update(progress *p, long done)
{
    if (!p->enabled)
        return;
    double now = psim_now();
    if (now - p->start < 1.0 || now - p->last < 0.1)
        return;
    p->last = now;
    p->shown = 1;
    int width = 30, fill = p->total ? (int)(width * done / p->total) : width;
    double eta = done ? (now - p->start) * (double)(p->total - done) / (double)done : 0;
    fprintf(stderr, "\r[%.*s%*s] step %ld/%ld, %.1f s left ", fill,
            "##############################", width - fill, "", done, p->total, eta);
    fflush(stderr);
}

void progress_done(progress *p)
{
    if (p->shown)
        fprintf(stderr, "\r%*s\r", 70, "");
}
