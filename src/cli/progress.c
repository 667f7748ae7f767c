/* Progress on stderr: of a run's steps, inside a long step, and of one
 * long read or write (progress.h). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "progress.h"
#include "say.h"
#include "../engine/timer.h"

void progress_init(progress *p, long total, int quiet)
{
    memset(p, 0, sizeof *p);
    p->tty = isatty(STDERR_FILENO);
    p->enabled = !quiet;
    /* PSIM_PROGRESS_S=T: start after T s and show a line every T s, on
     * a terminal too (tests) */
    const char *ev = getenv("PSIM_PROGRESS_S");
    p->every = ev ? atof(ev) : -1;
    if (p->every >= 0)
        p->tty = 0;
    p->total = total;
    p->start = p->last = psim_now();
}

/* Whether p is due to show at time now (then marked shown at now): a bar
 * on a terminal after 1 s, every 0.1 s; elsewhere a line every
 * PROGRESS_LINE_S seconds; PSIM_PROGRESS_S, both. */
static int progress_due(progress *p, double now)
{
    double delay = p->every >= 0 ? p->every : 1.0,
           gap = p->every >= 0 ? p->every : p->tty ? 0.1 : PROGRESS_LINE_S;
    if (now - p->start < delay || now - p->last < gap)
        return 0;
    p->last = now;
    return 1;
}

/* The bar on a terminal, "[####    ] " then what, over any wider bar
 * drawn before. */
static void progress_bar(progress *p, long done, const char *what)
{
    int width = 30, fill = p->total ? (int)(width * done / p->total) : width;
    fill = fill < 0 ? 0 : fill > width ? width : fill;
    char line[256];
    int w = snprintf(line, sizeof line, "[%.*s%*s] %s ", fill, "##############################",
                     width - fill, "", what);
    fprintf(stderr, "\r%-*s", p->width, line);
    p->width = w > p->width ? w : p->width;
    p->shown = 1;
    fflush(stderr);
}

void progress_update(progress *p, long done)
{
    if (!p->enabled || p->inside_only)
        return;
    double now = psim_now();
    if (!progress_due(p, now))
        return;
    double eta = done ? (now - p->start) * (double)(p->total - done) / (double)done : 0;
    if (!p->tty) {
        cli_err("psim: step %ld of %ld (%.0f%%), %.0f s so far, about %.0f s left",
                done, p->total, p->total ? 100.0 * (double)done / (double)p->total : 100.0,
                now - p->start, eta);
        return;
    }
    char what[96];
    snprintf(what, sizeof what, "step %ld/%ld, %.1f s left", done, p->total, eta);
    progress_bar(p, done, what);
}

void progress_done(progress *p)
{
    if (p->shown)
        fprintf(stderr, "\r%*s\r", p->width > 70 ? p->width : 70, "");
}

void progress_inside_times(const progress *p, double *first_s, double *every_s)
{
    *first_s = p->every >= 0 ? p->every : PROGRESS_LINE_S;
    *every_s = p->every >= 0 ? p->every : p->tty ? 0.1 : PROGRESS_LINE_S;
}

/* A count as "41203" or, from a million, "3.2e9". */
static void count_text(char *buf, size_t size, uint64_t v)
{
    if (v < 1000000) {
        snprintf(buf, size, "%llu", (unsigned long long)v);
        return;
    }
    char e[32];
    snprintf(e, sizeof e, "%.1e", (double)v);   /* "3.2e+09" */
    char *x = strchr(e, 'e');
    snprintf(buf, size, "%.*se%d", (int)(x - e), e, atoi(x + 1));
}

void progress_inside(progress *p, long done, const psim_step_progress *r)
{
    if (!p->enabled)
        return;
    char work[32];
    count_text(work, sizeof work, r->work);
    if (!p->tty) {
        cli_err("psim: step %ld of %ld: %s %s so far, %.0f s in this step", done,
                p->total, work, r->unit, r->seconds);
        return;
    }
    char what[160];
    snprintf(what, sizeof what, "step %ld/%ld: %s %s, %.0f s in this step", done, p->total,
             work, r->unit, r->seconds);
    progress_bar(p, done - 1, what);
}

/* One read or write at a time: its bar, label and how wide it was drawn. */
static struct {
    progress pb;
    char what[200];
    int on, width;
} io;

static void io_show(void *ctx, int writing, long long done, long long total)
{
    (void)ctx;
    progress *p = &io.pb;
    if (!io.on || !p->enabled)
        return;
    double now = psim_now();
    if (!progress_due(p, now))
        return;
    double frac = total > 0 ? (double)done / (double)total : 0;
    double eta = total > 0 && done > 0 ? (now - p->start) * (1 - frac) / frac : 0;
    /* lines, or millions of them; bytes in MB (kB below 10 MB) */
    char count[64];
    double u = writing ? (total >= 1000000 ? 1e6 : 1) : (total >= 0 && total < 10000000 ? 1e3 : 1e6);
    const char *unit = writing ? (u > 1 ? " M lines" : " lines") : (u < 1e6 ? " kB" : " MB");
    int dec = writing && u > 1 ? 1 : 0;
    if (total >= 0)
        snprintf(count, sizeof count, "%.*f/%.*f%s", dec, (double)done / u, dec,
                 (double)total / u, unit);
    else
        snprintf(count, sizeof count, "%.*f%s", dec, (double)done / u, unit);
    char left[40] = "";
    if (total > 0)
        snprintf(left, sizeof left, p->tty ? ", %.1f s left" : ", about %.0f s left", eta);
    if (!p->tty) {
        cli_err("psim: %s: %s (%.0f%%), %.0f s so far%s", io.what, count,
                100 * frac, now - p->start, left);
        return;
    }
    p->shown = 1;
    int width = 30, fill = (int)(width * frac);
    fill = fill < 0 ? 0 : fill > width ? width : fill;
    int w = fprintf(stderr, "\r[%.*s%*s] %s: %s%s ", fill, "##############################",
                    width - fill, "", io.what, count, left);
    if (w > io.width)
        io.width = w;
    fflush(stderr);
}

void cli_io_begin(const char *verb, const char *name, int quiet)
{
    progress_init(&io.pb, 0, quiet);
    int n = snprintf(io.what, sizeof io.what, "%s ", verb);
    cli_escape(io.what + n, sizeof io.what - (size_t)n, name);   /* shown on a terminal */
    io.on = 1;
    io.width = 0;
    psim_set_io_progress(io_show, NULL);
}

void cli_io_end(void)
{
    if (io.pb.shown)
        fprintf(stderr, "\r%*s\r", io.width, "");
    io.on = 0;
    io.pb.shown = 0;
    psim_set_io_progress(NULL, NULL);
}

