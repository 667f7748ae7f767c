/* --thermo N: the state's totals every N steps, as LAMMPS' thermo output
 * and HOOMD's loggers: a table on stderr and, with --thermo-file, CSV. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "cli.h"
#include "../engine/timer.h"

void thermo_init(cli_thermo *t, long every)
{
    memset(t, 0, sizeof *t);
    t->every = every;
}

/* The columns of a row: the engine's totals, the model's counters since
 * the last row, the pressure where the model keeps a collision virial. */
static void columns(cli_thermo *t, const psim_sim *s)
{
    for (t->ncols = 0; t->ncols < PSIM_THERMO_MAX && psim_thermo_column(s, t->ncols); t->ncols++)
        t->col[t->ncols] = psim_thermo_column(s, t->ncols);
    t->pressure = !isnan(psim_value(s, "virial"));
}

static void header(cli_thermo *t)
{
    static const char *const base[] = {"step", "ke", "px", "py"};
    for (int k = 0; k < 4; k++) {
        if (t->table)
            fprintf(t->table, k ? " %14s" : "%10s", base[k]);
        if (t->csv)
            fprintf(t->csv, k ? ",%s" : "%s", base[k]);
    }
    for (int k = 0; k < t->ncols; k++) {
        if (t->table)
            fprintf(t->table, " %16s", t->col[k]);
        if (t->csv)
            fprintf(t->csv, ",%s", t->col[k]);
    }
    if (t->pressure) {
        if (t->table)
            fprintf(t->table, " %14s", "pressure");
        if (t->csv)
            fputs(",pressure", t->csv);
    }
    if (t->table)
        fprintf(t->table, " %9s\n", "overlaps");
    if (t->csv)
        fputs(",overlaps\n", t->csv);
}

/* A number for the CSV: the shortest text that reads back to it. */
static void csv_num(FILE *f, double v)
{
    char b[PSIM_FORMAT_MAX];
    psim_format_double(b, v, -1);
    fprintf(f, ",%s", b);
}

/* The pressure over the interval since the last row, 2D, unit masses:
 * P A = K + W / (2 dt) (K = N kT); NAN for the first row.  Where the area
 * L^2 or the sum overflows, each term is divided by L twice: infinite
 * then only when the pressure itself is beyond the largest double. */
static double pressure(const cli_thermo *t, const psim_thermo *th, double w)
{
    double dt = (double)(th->step - t->last_step);
    if (!(dt > 0))
        return NAN;
    double p = (th->ke + (w - t->last_virial) / (2 * dt)) / th->area;
    if (isfinite(p))
        return p;
    return th->ke / th->side / th->side + (w - t->last_virial) / (2 * dt) / th->side / th->side;
}

/* A row's total that no double holds: one line naming it. */
static void too_large(const cli_thermo *t, long step, const char *what, psim_error *err)
{
    psim_error_set(err, "%s: step %ld: the %s is too large for a double (above %g), so no "
                        "row can hold it",
                   t->table ? "--thermo" : "--thermo-file", step, what, DBL_MAX);
}

/* A row (after the header, first), measured whole before any of it is
 * written: a failure leaves nothing half written. */
static int row(cli_thermo *t, const psim_sim *s, int first, psim_error *err)
{
    psim_thermo th;
    int rc = psim_thermo_measure(s, &th);
    if (rc == -2)
        too_large(t, th.step, th.too_large, err);
    else if (rc)
        psim_error_set(err, "out of memory for --thermo");
    if (rc)
        return -1;
    double w = t->pressure ? psim_value(s, "virial") : 0,
           p = t->pressure ? pressure(t, &th, w) : NAN;
    if (t->pressure && !isnan(p) && !isfinite(p)) {
        too_large(t, th.step, "pressure", err);
        return -1;
    }
    if (first)
        header(t);
    if (t->table)
        fprintf(t->table, "%10ld %14.8g %14.6g %14.6g", th.step, th.ke, th.px, th.py);
    if (t->csv) {
        fprintf(t->csv, "%ld", th.step);
        csv_num(t->csv, th.ke), csv_num(t->csv, th.px), csv_num(t->csv, th.py);
    }
    for (int k = 0; k < t->ncols; k++) {
        uint64_t c = psim_counter(s, t->col[k]), d = c - t->last[k];
        t->last[k] = c;
        if (t->table)
            fprintf(t->table, " %16llu", (unsigned long long)d);
        if (t->csv)
            fprintf(t->csv, ",%llu", (unsigned long long)d);
    }
    if (t->pressure) {
        t->last_virial = w;
        if (t->table && isnan(p))
            fprintf(t->table, " %14s", "-");
        else if (t->table)
            fprintf(t->table, " %14.8g", p);
        if (t->csv) {
            if (isnan(p))
                fputc(',', t->csv);
            else
                csv_num(t->csv, p);
        }
    }
    if (t->table)
        fprintf(t->table, " %9ld\n", th.overlaps);
    if (t->csv)
        fprintf(t->csv, ",%ld\n", th.overlaps);
    t->last_step = th.step;
    return 0;
}

int thermo_start(cli_thermo *t, psim_sim *s, FILE *table, FILE *csv, psim_error *err)
{
    if (t->every <= 0)
        return 0;
    double t0 = cli_output_begin(s);
    t->table = table, t->csv = csv;
    t->last_step = psim_step_index(s);
    t->last_virial = psim_value(s, "virial");
    columns(t, s);
    for (int k = 0; k < t->ncols; k++)
        t->last[k] = psim_counter(s, t->col[k]);
    int rc = row(t, s, 1, err);
    cli_output_end(s, t0);
    return rc;
}

int thermo_due(const cli_thermo *t, long k, long steps)
{
    return t->every > 0 && (k % t->every == 0 || k == steps);
}

int thermo_step(cli_thermo *t, psim_sim *s, long k, long steps, psim_error *err)
{
    if (!thermo_due(t, k, steps))
        return 0;
    double t0 = cli_output_begin(s);
    int rc = row(t, s, 0, err);
    if (t->table)
        fflush(t->table);
    cli_output_end(s, t0);
    return rc;
}
