/* --dump: frames in extended XYZ (OVITO, VMD, ASE read it): the count,
 * a comment line of key=value pairs (the box as a lattice, the columns),
 * then a line per disk in id order, z = 0. */
#include <stdio.h>

#include "psim/psim.h"

int psim_write_xyz(FILE *f, long step, long n, double L, double r, const double *x,
                   const double *y, const double *vx, const double *vy)
{
    char l[PSIM_FORMAT_MAX], d[PSIM_FORMAT_MAX], rr[PSIM_FORMAT_MAX];
    psim_format_double(l, L, -1);
    psim_format_double(d, 2 * r, -1);
    psim_format_double(rr, r, -1);
    if (fprintf(f, "%ld\nLattice=\"%s 0 0 0 %s 0 0 0 %s\" Origin=\"0 0 0\" "
                   "Properties=id:I:1:pos:R:3:velo:R:3:radius:R:1 Time=%ld step=%ld "
                   "pbc=\"F F F\"\n",
                n, l, l, d, step, step) < 0)
        return -1;
    char a[PSIM_FORMAT_MAX], b[PSIM_FORMAT_MAX], c[PSIM_FORMAT_MAX], e[PSIM_FORMAT_MAX];
    for (long i = 0; i < n; i++) {
        psim_format_double(a, x[i], -1);
        psim_format_double(b, y[i], -1);
        psim_format_double(c, vx[i], -1);
        psim_format_double(e, vy[i], -1);
        if (fprintf(f, "%ld %s %s 0 %s %s 0 %s\n", i, a, b, c, e, rr) < 0)
            return -1;
    }
    return 0;
}
