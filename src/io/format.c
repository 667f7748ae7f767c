/* Text output of numbers and states. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "psim/psim.h"

int psim_format_double(char *buf, double v, int digits)
{
    if (digits >= 0) {
        if (digits > PSIM_DIGITS_MAX)
            digits = PSIM_DIGITS_MAX;
        int len = snprintf(buf, PSIM_FORMAT_MAX, "%.*f", digits, v);
        /* no negative zero: "-0.000" prints as "0.000" */
        if (buf[0] == '-' && strspn(buf + 1, "0.") == (size_t)(len - 1)) {
            memmove(buf, buf + 1, (size_t)len);
            len--;
        }
        return len;
    }
    /* Any decimal of <= 15 significant digits survives a round trip, so the
     * first of %.15g, %.16g, %.17g that reads back is the shortest. */
    int len = 0;
    for (int p = 15; p <= 17; p++) {
        len = snprintf(buf, PSIM_FORMAT_MAX, "%.*g", p, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    return len;
}

int psim_write_state(FILE *f, long step, long n, const double *x,
                     const double *y, const double *vx, const double *vy,
                     int digits)
{
    char a[PSIM_FORMAT_MAX], b[PSIM_FORMAT_MAX], c[PSIM_FORMAT_MAX],
        d[PSIM_FORMAT_MAX];
    for (long i = 0; i < n; i++) {
        psim_format_double(a, x[i], digits);
        psim_format_double(b, y[i], digits);
        psim_format_double(c, vx[i], digits);
        psim_format_double(d, vy[i], digits);
        if (fprintf(f, "%ld %ld %s %s %s %s\n", step, i, a, b, c, d) < 0)
            return -1;
    }
    return 0;
}

int psim_scene_write(FILE *f, const psim_scene *sc)
{
    char L[PSIM_FORMAT_MAX], r[PSIM_FORMAT_MAX];
    psim_format_double(L, sc->L, -1);
    psim_format_double(r, sc->r, -1);
    if (fprintf(f, "%ld\n%s\n%s\n%ld\n", sc->n, L, r, sc->steps) < 0)
        return -1;
    char a[PSIM_FORMAT_MAX], b[PSIM_FORMAT_MAX], c[PSIM_FORMAT_MAX],
        d[PSIM_FORMAT_MAX];
    for (long i = 0; i < sc->n; i++) {
        psim_format_double(a, sc->x[i], -1);
        psim_format_double(b, sc->y[i], -1);
        psim_format_double(c, sc->vx[i], -1);
        psim_format_double(d, sc->vy[i], -1);
        if (fprintf(f, "%ld %s %s %s %s\n", i, a, b, c, d) < 0)
            return -1;
    }
    return 0;
}
