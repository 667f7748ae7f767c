/* --dump: frames in extended XYZ (OVITO, VMD, ASE read it): the count,
 * a comment line of key=value pairs (the box as a lattice, the columns),
 * then a line per disk in id order, z = 0, made by psim_write_lines. */
#include <stdio.h>

#include "fmt.h"
#include "scene.h"

typedef struct xyz_ctx {
    const psim_cols *c;
    char r[PSIM_FMT_MAX];   /* the radius, formatted once */
    int rlen;
} xyz_ctx;

/* "i x y 0 vx vy 0 r": four numbers, an id, the radius. */
#define XYZ_LINE_MAX (24 + 5 * (PSIM_FMT_MAX + 1) + 8)

static size_t xyz_line(char *out, long i, const void *vctx)
{
    const xyz_ctx *x = vctx;
    const psim_cols *c = x->c;
    long k = c->at ? c->at[i] : i;
    char *p = psim_fmt_long(out, i);
    *p++ = ' ';
    p += psim_fmt_shortest(p, c->x[k]);
    *p++ = ' ';
    p += psim_fmt_shortest(p, c->y[k]);
    *p++ = ' ', *p++ = '0', *p++ = ' ';
    p += psim_fmt_shortest(p, c->vx[k]);
    *p++ = ' ';
    p += psim_fmt_shortest(p, c->vy[k]);
    *p++ = ' ', *p++ = '0', *p++ = ' ';
    for (int q = 0; q < x->rlen; q++)
        *p++ = x->r[q];
    *p++ = '\n';
    return (size_t)(p - out);
}

int psim_write_xyz_cols(FILE *f, long step, long n, double L, double r, const psim_cols *c,
                        int threads)
{
    char l[PSIM_FMT_MAX], d[PSIM_FMT_MAX];
    xyz_ctx x = {c, {0}, 0};
    psim_fmt_shortest(l, L);
    psim_fmt_shortest(d, 2 * r);
    x.rlen = psim_fmt_shortest(x.r, r);
    if (fprintf(f, "%ld\nLattice=\"%s 0 0 0 %s 0 0 0 %s\" Origin=\"0 0 0\" "
                   "Properties=id:I:1:pos:R:3:velo:R:3:radius:R:1 Time=%ld step=%ld "
                   "pbc=\"F F F\"\n",
                n, l, l, d, step, step) < 0)
        return -1;
    return psim_write_lines(f, n, threads, XYZ_LINE_MAX, xyz_line, &x);
}
