/* Text output of numbers and states.  Numbers are made by the exact fast
 * conversions of fmt.c, lines in parallel chunks written in order
 * (psim_write_lines, lines.c); PSIM_SLOW_IO=1 keeps the old fprintf code paths,
 * the reference the tests compare the bytes with. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "fmt.h"
#include "lines.h"
#include "scene.h"
#include "state_write.h"

int psim_format_double(char *buf, double v, int digits)
{
    if (digits >= 0)
        return psim_fmt_fixed(buf, v, digits > PSIM_DIGITS_MAX ? PSIM_DIGITS_MAX : digits, 0);
    return psim_fmt_shortest(buf, v);
}

/* one number: shortest (digits < 0) or fixed without negative zero */
static inline char *put_num(char *p, double v, int digits)
{
    return p + (digits >= 0 ? psim_fmt_fixed(p, v, digits, 0) : psim_fmt_shortest(p, v));
}

/* The longest line of four numbers and two integers. */
#define STATE_LINE_MAX (2 * 24 + 4 * (PSIM_FMT_MAX + 1))

typedef struct state_ctx {
    const psim_cols *c;
    int with_step;   /* 0: scene lines "i x y vx vy" */
    long step;
    int digits;
} state_ctx;

static size_t state_line(char *out, long i, const void *vctx)
{
    const state_ctx *s = vctx;
    const psim_cols *c = s->c;
    long k = c->at ? c->at[i] : i;
    char *p = out;
    if (s->with_step) {
        p = psim_fmt_long(p, s->step);
        *p++ = ' ';
    }
    p = psim_fmt_long(p, c->id0 + i);
    *p++ = ' ';
    p = put_num(p, c->x[k], s->digits);
    *p++ = ' ';
    p = put_num(p, c->y[k], s->digits);
    *p++ = ' ';
    p = put_num(p, c->vx[k], s->digits);
    *p++ = ' ';
    p = put_num(p, c->vy[k], s->digits);
    *p++ = '\n';
    return (size_t)(p - out);
}

/* The plain writer: snprintf per number, fprintf per line. */
static int write_state_slow(FILE *f, int with_step, long step, long n, const psim_cols *c,
                            int digits)
{
    char a[PSIM_FMT_MAX], b[PSIM_FMT_MAX], cc[PSIM_FMT_MAX], d[PSIM_FMT_MAX];
    for (long i = 0; i < n; i++) {
        long k = c->at ? c->at[i] : i;
        if (digits >= 0) {
            psim_fmt_fixed_ref(a, c->x[k], digits, 0);
            psim_fmt_fixed_ref(b, c->y[k], digits, 0);
            psim_fmt_fixed_ref(cc, c->vx[k], digits, 0);
            psim_fmt_fixed_ref(d, c->vy[k], digits, 0);
        } else {
            psim_fmt_shortest_ref(a, c->x[k]);
            psim_fmt_shortest_ref(b, c->y[k]);
            psim_fmt_shortest_ref(cc, c->vx[k]);
            psim_fmt_shortest_ref(d, c->vy[k]);
        }
        int w = with_step ? fprintf(f, "%ld %ld %s %s %s %s\n", step, c->id0 + i, a, b, cc, d)
                          : fprintf(f, "%ld %s %s %s %s\n", c->id0 + i, a, b, cc, d);
        if (w < 0)
            return -1;
    }
    return 0;
}

static int write_cols(FILE *f, int with_step, long step, long n, const psim_cols *c,
                      int digits, int threads)
{
    if (digits > PSIM_DIGITS_MAX)
        digits = PSIM_DIGITS_MAX;
    if (psim_io_slow())
        return write_state_slow(f, with_step, step, n, c, digits);
    state_ctx s = {c, with_step, step, digits};
    return psim_write_lines(f, n, threads, STATE_LINE_MAX, state_line, &s);
}

int psim_write_state_cols(FILE *f, long step, long n, const psim_cols *c, int digits,
                          int threads)
{
    return write_cols(f, 1, step, n, c, digits, threads);
}

int psim_write_state(FILE *f, long step, long n, const double *x,
                     const double *y, const double *vx, const double *vy,
                     int digits)
{
    psim_cols c = {x, y, vx, vy, NULL, 0};
    return write_cols(f, 1, step, n, &c, digits, omp_get_max_threads());
}

int psim_scene_write(FILE *f, const psim_scene *sc)
{
    if (sc->n > 0 && !sc->x)   /* taken by psim_create_taking */
        return -1;
    char L[PSIM_FORMAT_MAX], r[PSIM_FORMAT_MAX];
    psim_fmt_shortest(L, sc->L);
    psim_fmt_shortest(r, sc->r);
    if (fprintf(f, "%ld\n%s\n%s\n%ld\n", sc->n, L, r, sc->steps) < 0)
        return -1;
    psim_cols c = {sc->x, sc->y, sc->vx, sc->vy, NULL, 0};
    return write_cols(f, 0, 0, sc->n, &c, -1, omp_get_max_threads());
}
