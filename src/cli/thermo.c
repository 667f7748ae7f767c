/* --thermo N: the state's totals every N steps, as LAMMPS' thermo output
 * and HOOMD's loggers: a table on stderr and, with --thermo-file, CSV
 * whose every cell is a number (a value that is not defined, as the
 * pressure of the first row, is nan), for numpy.loadtxt and the like. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "measure.h"
#include "thermo.h"
#include "../base/error.h"
#include "../engine/timer.h"

void thermo_init(cli_thermo *t, long every, int speed)
{
    memset(t, 0, sizeof *t);
    t->every = every;
    t->speed = speed;
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
    static const char *const base[] = {"step", "time", "ke", "temperature", "px", "py"};
    for (int k = 0; k < 6; k++) {
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
        fprintf(t->table, t->speed ? " %9s %10s\n" : " %9s\n", "overlaps", "steps/s");
    if (t->csv)
        fputs(t->speed ? ",overlaps,steps_per_s\n" : ",overlaps\n", t->csv);
}

/* A number for the CSV: the shortest text that reads back to it, or nan
 * where it is not defined. */
static void csv_num(FILE *f, double v)
{
    char b[PSIM_FORMAT_MAX] = "nan";
    if (!isnan(v))
        psim_format_double(b, v, -1);
    fprintf(f, ",%s", b);
}

/* A number for the table, rounded for reading; "-" where it is not
 * defined. */
static void table_num(FILE *f, int width, double v)
{
    if (isnan(v))
        fprintf(f, " %*s", width, "-");
    else
        fprintf(f, " %*.8g", width, v);
}

/* The pressure over the interval since the last row, 2D, unit masses:
 * P A = K + W / (2 dt) (K = N kT), dt the interval in model time; NAN for
 * the first row.  Where the area L^2 or the sum overflows, each term is
 * divided by L twice: infinite then only when the pressure itself is
 * beyond the largest double. */
static double pressure(const cli_thermo *t, const psim_sim *s, const psim_thermo *th,
                       double w)
{
    double dt = psim_time_at(s, th->step) - psim_time_at(s, t->last_step);
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
           p = t->pressure ? pressure(t, s, &th, w) : NAN;
    if (t->pressure && !isnan(p) && !isfinite(p)) {
        too_large(t, th.step, "pressure", err);
        return -1;
    }
    /* the temperature: the kinetic energy per disk (2D, unit masses,
     * k_B = 1: two degrees of freedom of kT / 2 each) */
    const double time = psim_time_at(s, th.step), temp = th.ke / (double)psim_count(s);
    const double now = psim_now(), wall = now - t->last_wall;
    const double sps = first || !(wall > 0) ? NAN : (double)(th.step - t->last_step) / wall;
    if (first)
        header(t);
    if (t->table) {
        fprintf(t->table, "%10ld", th.step);
        table_num(t->table, 14, time), table_num(t->table, 14, th.ke);
        table_num(t->table, 14, temp);
        fprintf(t->table, " %14.6g %14.6g", th.px, th.py);
    }
    if (t->csv) {
        fprintf(t->csv, "%ld", th.step);
        csv_num(t->csv, time), csv_num(t->csv, th.ke), csv_num(t->csv, temp);
        csv_num(t->csv, th.px), csv_num(t->csv, th.py);
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
        if (t->table)
            table_num(t->table, 14, p);
        if (t->csv)
            csv_num(t->csv, p);
    }
    if (t->table)
        fprintf(t->table, " %9ld", th.overlaps);
    if (t->csv)
        fprintf(t->csv, ",%ld", th.overlaps);
    if (t->speed && t->table) {
        if (isnan(sps))
            fprintf(t->table, " %10s", "-");
        else
            fprintf(t->table, " %10.4g", sps);
    }
    if (t->speed && t->csv)
        csv_num(t->csv, sps);
    if (t->table)
        fputc('\n', t->table);
    if (t->csv)
        fputc('\n', t->csv);
    t->last_step = th.step;
    t->last_wall = now;
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
