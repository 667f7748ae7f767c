/* --dump: frames in extended XYZ (ASE, OVITO, VMD read it): the count, a
 * comment line of key=value pairs (the box as a lattice, the columns, the
 * model time and the step), then a line per disk in id order, z = 0, made
 * by psim_write_lines.  The column names are the readers' own: species
 * (X, ASE's dummy element, whose mass is 1: psim's masses are unit
 * masses), id, pos, momenta (ASE's get_momenta and get_velocities read
 * them: with unit masses they are the velocities), velo (the same numbers,
 * the name OVITO maps to Velocity) and radius. */
#include <stdio.h>

#include "fmt.h"
#include "lines.h"
#include "scene.h"
#include "xyz.h"

typedef struct xyz_ctx {
    const psim_cols *c;
    char r[PSIM_FMT_MAX];   /* the radius, formatted once */
    int rlen;
} xyz_ctx;

/* "X i x y 0 vx vy 0 vx vy 0 r": six numbers, an id, the radius. */
#define XYZ_LINE_MAX (2 + 24 + 7 * (PSIM_FMT_MAX + 1) + 16)

static size_t xyz_line(char *out, long i, const void *vctx)
{
    const xyz_ctx *x = vctx;
    const psim_cols *c = x->c;
    long k = c->at ? c->at[i] : i;
    char *p = out;
    *p++ = 'X', *p++ = ' ';
    p = psim_fmt_long(p, c->id0 + i);
    *p++ = ' ';
    p += psim_fmt_shortest(p, c->x[k]);
    *p++ = ' ';
    p += psim_fmt_shortest(p, c->y[k]);
    *p++ = ' ', *p++ = '0', *p++ = ' ';
    char *v = p;   /* momenta, then the same as velo */
    p += psim_fmt_shortest(p, c->vx[k]);
    *p++ = ' ';
    p += psim_fmt_shortest(p, c->vy[k]);
    *p++ = ' ', *p++ = '0', *p++ = ' ';
    size_t vlen = (size_t)(p - v);
    for (size_t q = 0; q < vlen; q++)
        p[q] = v[q];
    p += vlen;
    for (int q = 0; q < x->rlen; q++)
        *p++ = x->r[q];
    *p++ = '\n';
    return (size_t)(p - out);
}

int psim_write_xyz_cols(FILE *f, long step, double time, long n, double L, double r,
                        const psim_cols *c, const psim_part *part, int threads)
{
    char l[PSIM_FMT_MAX], d[PSIM_FMT_MAX], t[PSIM_FMT_MAX];
    xyz_ctx x = {c, {0}, 0};
    psim_fmt_shortest(l, L);
    psim_fmt_shortest(d, 2 * r);
    psim_fmt_shortest(t, time);
    x.rlen = psim_fmt_shortest(x.r, r);
    if ((!part || part->head) &&
        fprintf(f, "%ld\nLattice=\"%s 0 0 0 %s 0 0 0 %s\" Origin=\"0 0 0\" "
                   "Properties=species:S:1:id:I:1:pos:R:3:momenta:R:3:velo:R:3:radius:R:1 Time=%s "
                   "step=%ld pbc=\"F F F\"\n",
                part ? part->total : n, l, l, d, t, step) < 0)
        return -1;
    return psim_write_lines(f, n, threads, XYZ_LINE_MAX, xyz_line, &x);
}
