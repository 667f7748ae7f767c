/* A restart file held to the model it names: the header's options, values
 * and columns are the model's (none unknown, none given twice, every
 * column there), and each particle's column values are read as the model
 * declares them: integer columns as integers, never through a double
 * (2.5, 1e23 and text are refused, not rounded or converted), and every
 * value within its column's range.  The schema comes from the composing
 * layer (src/models/scene.c). */
#include <float.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "fmt.h"
#include "restart_schema.h"

/* "FILE:LINE: restart header: " and the message. */
static int fail(psim_error *err, const psim_restart *rs, const char *name, const char *fmt,
                ...)
{
    char msg[sizeof err->msg];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    psim_error_set(err, "%s:%ld: restart header: %s", name, rs->line, msg);
    return -1;
}

/* "A,B,C" of the names (or "none"), count of them. */
static void list_names(const char *const *names, int count, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int k = 0; k < count && used < size; k++)
        used += (size_t)snprintf(buf + used, size - used, "%s%s", k ? "," : "", names[k]);
    if (!buf[0])
        snprintf(buf, size, "none");
}

static int name_in(const char *const *names, int count, const char *name)
{
    for (int k = 0; k < count; k++)
        if (!strcmp(names[k], name))
            return k;
    return -1;
}

/* The file's columns: each one of the model's, once, and all of them;
 * each gets the model's declaration. */
static int check_columns(psim_restart *rs, const psim_restart_schema *sch, const char *name,
                         psim_error *err)
{
    const char *want[PSIM_RESTART_COLS], *have[PSIM_RESTART_COLS];
    int nwant = 0;
    while (nwant < PSIM_RESTART_COLS && sch->cols[nwant].name)
        want[nwant] = sch->cols[nwant].name, nwant++;
    char names[256];
    list_names(want, nwant, names, sizeof names);
    for (int c = 0; c < rs->ncols; c++) {
        int k = name_in(want, nwant, rs->colname[c]);
        if (k < 0)
            return fail(err, rs, name, "unknown column '%s' (the %s model's columns: %s)",
                        rs->colname[c], rs->model, names);
        if (name_in(have, c, rs->colname[c]) >= 0)
            return fail(err, rs, name, "column given twice: '%s'", rs->colname[c]);
        have[c] = rs->colname[c];
        rs->colspec[c] = sch->cols[k];
    }
    for (int k = 0; k < nwant; k++)
        if (name_in(have, rs->ncols, want[k]) < 0)
            return fail(err, rs, name, "missing column '%s' (the %s model's columns: %s)",
                        want[k], rs->model, names);
    return 0;
}

/* The file's values: each one of the model's, once. */
static int check_values(const psim_restart *rs, const psim_restart_schema *sch,
                        const char *name, psim_error *err)
{
    int nwant = 0;
    while (sch->values && sch->values[nwant])
        nwant++;
    const char *have[8];
    for (int k = 0; k < rs->nvalues; k++) {
        if (name_in(sch->values, nwant, rs->valname[k]) < 0) {
            char names[256];
            list_names(sch->values, nwant, names, sizeof names);
            return fail(err, rs, name, "unknown value '%s' (the %s model's values: %s)",
                        rs->valname[k], rs->model, names);
        }
        if (name_in(have, k, rs->valname[k]) >= 0)
            return fail(err, rs, name, "value given twice: '%s'", rs->valname[k]);
        have[k] = rs->valname[k];
    }
    return 0;
}

int psim_restart_check(psim_scene *sc, psim_restart_schema_fn schema, const char *name,
                       psim_error *err)
{
    psim_restart *rs = &sc->restart;
    psim_restart_schema sch;
    if (schema(rs->model, &sch))
        return fail(err, rs, name, "unknown model '%s' (psim models lists them)", rs->model);
    psim_error e = {{0}, 0};
    if (rs->options && sch.options_ok(sch.ctx, rs->options, &e))
        return fail(err, rs, name, "%s", e.msg);
    if (check_values(rs, &sch, name, err))
        return -1;
    return check_columns(rs, &sch, name, err);
}

/* Integers are read up to 2^53, past any column's range (every one of
 * them a double). */
#define WHOLE_MAX 9007199254740992LL

/* [+-]digits at s, within c's range. */
static const char *scan_integer(const psim_restart_col *c, const char *s, double *out)
{
    const char *p = s;
    int neg = *p == '-';
    p += *p == '-' || *p == '+';
    const char *d0 = p;
    long long v = 0;
    for (; *p >= '0' && *p <= '9'; p++)
        if ((v = v * 10 + (*p - '0')) > WHOLE_MAX)
            return NULL;
    if (p == d0)
        return NULL;
    v = neg ? -v : v;
    if (v < (long long)c->lo || v > (long long)c->hi)
        return NULL;
    *out = (double)v;
    return p;
}

const char *psim_restart_scan(const psim_restart_col *c, const char *s, int padded,
                              double *out)
{
    if (c->integer)
        return scan_integer(c, s, out);
    const char *end = padded ? psim_scan_double_padded(s, out) : psim_scan_double(s, out);
    return end && *out >= c->lo && *out <= c->hi ? end : NULL;
}

/* "a whole number in LO..HI", "a finite number" or "a number in [LO, HI]". */
static void range_text(const psim_restart_col *c, char *buf, size_t size)
{
    if (c->integer)
        snprintf(buf, size, "a whole number in %.0f..%.0f", c->lo, c->hi);
    else if (c->lo == -DBL_MAX && c->hi == DBL_MAX)
        snprintf(buf, size, "a finite number");
    else
        snprintf(buf, size, "a number in [%.17g, %.17g]", c->lo, c->hi);
}

void psim_restart_field_error(const psim_restart *rs, int k, long id, const char *s,
                              char *buf, size_t size)
{
    const psim_restart_col *c = &rs->colspec[k];
    size_t len = s ? strcspn(s, " \t\r\n") : 0;
    if (len == 0) {
        snprintf(buf, size, "particle %ld: missing %s (field %d)", id, c->name, 6 + k);
        return;
    }
    char range[96];
    range_text(c, range, sizeof range);
    snprintf(buf, size, "particle %ld: %s (field %d) must be %s, got '%.*s'", id, c->name,
             6 + k, range, (int)(len < 40 ? len : 40), s);
}
