/* The parts of a restart file (--restart) beyond a scene: its first line,
 *   #psim restart 1 model=NAME step=K [format=2024|2019|cs267] [print=0|1]
 *                   [options=K=V,...] [grid=REACH,OCC,TILE[,X0,Y0,X1,Y1]]
 *                   [cuts=X0,...,XT,Y0,...,YT]
 *                   [values=NAME:V,...] [columns=NAME,...]
 * and the order of its particle lines (the run's own order, which the
 * discrete model's results follow).  The scene reader calls these; the
 * engine writes the file (src/engine/restart.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fmt.h"
#include "restart.h"
#include "restart_schema.h"

static int bad(psim_error *err, const char *name, long line, const char *what,
               const char *tok)
{
    psim_error_set(err, "%s:%ld: restart header: %s '%.60s'", name, line, what, tok);
    return -1;
}

/* A name of letters, digits, '_' and '-', shorter than size. */
static int word_ok(const char *s, size_t len, size_t size)
{
    if (len == 0 || len >= size)
        return 0;
    for (size_t i = 0; i < len; i++)
        if (!(s[i] == '_' || s[i] == '-' || (s[i] >= 'a' && s[i] <= 'z') ||
              (s[i] >= 'A' && s[i] <= 'Z') || (s[i] >= '0' && s[i] <= '9')))
            return 0;
    return 1;
}

/* A whole number of decimal digits at s, at most max: the end, with *v
 * set, or NULL (no digits, or more than max). */
static const char *scan_whole(const char *s, long max, long *v)
{
    long k = 0;
    const char *p = s;
    for (; *p >= '0' && *p <= '9'; p++) {
        k = k * 10 + (*p - '0');
        if (k > max)
            return NULL;
    }
    *v = k;
    return p == s ? NULL : p;
}

/* One item of a list at *v: a finite number (whole with `whole`, then at
 * most max), followed by a comma and more or by the end.  0 with *v moved
 * past it, or -1. */
static int list_item(const char **v, int whole, long max, double *out)
{
    const char *end;
    long k = 0;
    if (whole) {
        end = scan_whole(*v, max, &k);
        *out = (double)k;
    } else {
        end = psim_scan_double(*v, out);
        if (end && !isfinite(*out))
            return -1;
    }
    if (!end || (*end && (*end != ',' || !end[1])))
        return -1;   /* not a number, or text or a trailing comma after it */
    *v = *end ? end + 1 : end;
    return 0;
}

static int column_names(psim_restart *rs, const char *v)
{
    while (*v) {
        size_t len = strcspn(v, ",");
        if (rs->ncols == PSIM_RESTART_COLS || !word_ok(v, len, sizeof rs->colname[0]))
            return -1;
        memcpy(rs->colname[rs->ncols], v, len);
        rs->colname[rs->ncols++][len] = '\0';
        v += len;
        if (*v == ',' && !*++v)
            return -1;
    }
    return rs->ncols > 0 ? 0 : -1;
}

/* REACH,OCC,TILE[,X0,Y0,X1,Y1]: the grid the model asked for.  The
 * engine plans from it as from the model's own ask, so it holds to what
 * a model asks: a positive reach, an occupancy of 0 (the default) or at
 * least 1 (fewer particles a cell plans more cells than the engine
 * numbers: sqrt(2^31 / OCC) a side), TILE 0 or a power of two up to 2^20
 * (as --tile) and a region whose corners are in order. */
static int grid_plan(psim_restart *rs, const char *v)
{
    double *g = rs->grid;
    int k = 0;
    for (; *v && k < 7; k++)
        if (list_item(&v, k == 2, 1L << 20, &g[k]))
            return -1;
    long tile = (long)g[2];
    if (*v || (k != 3 && k != 7) || !(g[0] > 0) || !(g[1] == 0 || g[1] >= 1) ||
        (tile & (tile - 1)) || (k == 7 && !(g[3] <= g[5] && g[4] <= g[6])))
        return -1;
    rs->has_grid = 1;
    rs->grid_has_bbox = k == 7;
    return 0;
}

/* Cuts 0 = c[0] < c[1] < ... < c[T] of one axis. */
static int cuts_increase(const int32_t *c, int T)
{
    if (c[0] != 0)
        return 0;
    for (int j = 0; j < T; j++)
        if (c[j + 1] <= c[j])
            return 0;
    return 1;
}

/* X0,...,XT,Y0,...,YT: the tiles' cuts, each axis from 0 up to the same
 * G (the engine checks them against its grid: a plan that no longer fits
 * is left at its default cuts). */
static int cut_list(psim_restart *rs, const char *v)
{
    rs->ncuts = 0;
    while (*v) {
        double c;
        if (rs->ncuts == PSIM_RESTART_CUTS || list_item(&v, 1, INT32_MAX, &c))
            return -1;
        rs->cuts[rs->ncuts++] = (int32_t)c;
    }
    int T = rs->ncuts / 2 - 1;
    return rs->ncuts >= 4 && rs->ncuts % 2 == 0 && cuts_increase(rs->cuts, T) &&
                   cuts_increase(rs->cuts + T + 1, T) && rs->cuts[T] == rs->cuts[2 * T + 1]
               ? 0
               : -1;
}

/* NAME:V,NAME:V: the model's values (finite numbers). */
static int value_list(psim_restart *rs, const char *v)
{
    rs->nvalues = 0;
    while (*v) {
        size_t len = strcspn(v, ":,");
        if (rs->nvalues == 8 || v[len] != ':' || !word_ok(v, len, sizeof rs->valname[0]))
            return -1;
        memcpy(rs->valname[rs->nvalues], v, len);
        rs->valname[rs->nvalues][len] = '\0';
        v += len + 1;
        if (list_item(&v, 0, 0, &rs->value[rs->nvalues]))
            return -1;
        rs->nvalues++;
    }
    return rs->nvalues > 0 ? 0 : -1;
}

/* The header's keys, indices into header_keys. */
enum { HK_MODEL, HK_STEP, HK_FORMAT, HK_PRINT, HK_OPTIONS, HK_GRID, HK_CUTS, HK_VALUES,
       HK_COLUMNS, HK_COUNT };
static const char *const header_keys[HK_COUNT] = {
    "model", "step", "format", "print", "options", "grid", "cuts", "values", "columns"};

/* The value v of header key k into sc. */
static int header_pair(psim_scene *sc, int k, char *v, const char *name, long line,
                       psim_error *err)
{
    psim_restart *rs = &sc->restart;
    if (k == HK_MODEL) {
        if (!word_ok(v, strlen(v), sizeof rs->model))
            return bad(err, name, line, "not a model name:", v);
        strcpy(rs->model, v);
    } else if (k == HK_STEP) {
        const char *end = scan_whole(v, PSIM_MAX_STEPS, &rs->step);
        if (!end || *end)
            return bad(err, name, line, "step must be an integer in 0..10^9, got", v);
    } else if (k == HK_FORMAT) {
        if (!strcmp(v, "2024"))
            sc->format = PSIM_SCENE_2024;
        else if (!strcmp(v, "2019"))
            sc->format = PSIM_SCENE_2019;
        else if (!strcmp(v, "cs267"))
            sc->format = PSIM_SCENE_CS267;
        else
            return bad(err, name, line, "format must be 2024, 2019 or cs267, got", v);
    } else if (k == HK_PRINT) {
        if (strcmp(v, "0") && strcmp(v, "1"))
            return bad(err, name, line, "print must be 0 or 1, got", v);
        sc->print = v[0] == '1';
    } else if (k == HK_OPTIONS) {
        if (!*v)
            return bad(err, name, line, "options must be NAME=VALUE,..., got", v);
        if (!(rs->options = strdup(v))) {
            psim_error_set(err, "%s: out of memory", name);
            return -1;
        }
    } else if (k == HK_GRID) {
        if (grid_plan(rs, v))
            return bad(err, name, line,
                       "grid must be REACH,OCC,TILE[,X0,Y0,X1,Y1] (REACH > 0; OCC 0 or at "
                       "least 1; TILE 0 or a power of two up to 2^20; X0 <= X1, Y0 <= Y1), got",
                       v);
    } else if (k == HK_CUTS) {
        if (cut_list(rs, v))
            return bad(err, name, line,
                       "cuts must be 2 (T + 1) increasing cell numbers (0,...,G,0,...,G), got", v);
    } else if (k == HK_VALUES) {
        if (value_list(rs, v))
            return bad(err, name, line, "values must be NAME:NUMBER,... (finite), got", v);
    } else {   /* HK_COLUMNS */
        if (column_names(rs, v))
            return bad(err, name, line, "columns must be up to 8 names separated by commas, got", v);
    }
    return 0;
}

/* One KEY=VALUE of the header (len characters at tok) into sc; *seen holds
 * the keys given before (a key given twice is an error). */
static int header_key(psim_scene *sc, const char *tok, size_t len, const char *name,
                      long line, unsigned *seen, psim_error *err)
{
    char *t = strndup(tok, len);
    if (!t) {
        psim_error_set(err, "%s: out of memory", name);
        return -1;
    }
    char *v = strchr(t, '=');
    int k = 0, rc;
    if (v)
        *v++ = '\0';
    while (v && k < HK_COUNT && strcmp(t, header_keys[k]))
        k++;
    if (!v)
        rc = bad(err, name, line, "expected KEY=VALUE, got", t);
    else if (k == HK_COUNT)
        rc = bad(err, name, line, "unknown key", t);
    else if (*seen & (1u << k))
        rc = bad(err, name, line, "key given twice:", t);
    else {
        *seen |= 1u << k;
        rc = header_pair(sc, k, v, name, line, err);
    }
    free(t);
    return rc;
}

/* The keys every restart file has, and the values that go together. */
static int header_whole(const psim_scene *sc, unsigned seen, const char *name, long line,
                        psim_error *err)
{
    if (!(seen & (1u << HK_MODEL)))
        return bad(err, name, line, "missing", "model=NAME");
    if (!(seen & (1u << HK_STEP)))
        return bad(err, name, line, "missing", "step=K");
    if (sc->print && sc->format != PSIM_SCENE_2019)
        return bad(err, name, line, "print=1 is for format=2019 scenes, got", "print=1");
    return 0;
}

int psim_restart_header(psim_scene *sc, const char *text, const char *name, long line,
                        psim_restart_schema_fn schema, psim_error *err)
{
    static const char magic[] = "#psim restart 1";
    if (strncmp(text, magic, sizeof magic - 1) ||
        (text[sizeof magic - 1] && text[sizeof magic - 1] != ' ' && text[sizeof magic - 1] != '\t'))
        return bad(err, name, line, "expected '#psim restart 1 ...', got", text);
    sc->restart.present = 1;
    sc->restart.line = line;
    const char *p = text + sizeof magic - 1;
    unsigned seen = 0;
    for (;;) {
        p += strspn(p, " \t\r");
        if (!*p)
            break;
        size_t len = strcspn(p, " \t\r");
        if (header_key(sc, p, len, name, line, &seen, err))
            return -1;
        p += len;
    }
    if (header_whole(sc, seen, name, line, err))
        return -1;
    return psim_restart_check(sc, schema, name, err);
}

int psim_restart_alloc_columns(psim_scene *sc, psim_error *err)
{
    psim_restart *rs = &sc->restart;
    size_t b = (size_t)(sc->n > 0 ? sc->n : 1) * sizeof(double);
    for (int c = 0; c < rs->ncols; c++)
        if (!(rs->col[c] = calloc(1, b))) {
            psim_error_set(err, "%s: out of memory for %ld particles", sc->source, sc->n);
            return -1;
        }
    return 0;
}

/* The ids in the order of their lines: lines are distinct and increase
 * down the file, so a counting pass over the line numbers' range. */
int psim_restart_order(psim_scene *sc, psim_error *err)
{
    long n = sc->n, lo = 0, hi = -1;
    for (long i = 0; i < n; i++) {
        if (i == 0 || sc->line[i] < lo)
            lo = sc->line[i];
        if (sc->line[i] > hi)
            hi = sc->line[i];
    }
    int32_t *slot = n ? malloc((size_t)(hi - lo + 1) * sizeof *slot) : NULL;
    int32_t *order = malloc((size_t)(n > 0 ? n : 1) * sizeof *order);
    if ((n && !slot) || !order) {
        free(slot), free(order);
        psim_error_set(err, "%s: out of memory for %ld particles", sc->source, n);
        return -1;
    }
    for (long k = 0; k < hi - lo + 1; k++)
        slot[k] = -1;
    for (long i = 0; i < n; i++)
        slot[sc->line[i] - lo] = (int32_t)i;
    long k = 0;
    for (long s = 0; s < hi - lo + 1; s++)
        if (slot[s] >= 0)
            order[k++] = slot[s];
    free(slot);
    sc->restart.order = order;
    return 0;
}

void psim_restart_free(psim_restart *rs)
{
    free(rs->options);
    for (int c = 0; c < PSIM_RESTART_COLS; c++)
        free(rs->col[c]);
    free(rs->order);
    rs->options = NULL;
    rs->order = NULL;
    for (int c = 0; c < PSIM_RESTART_COLS; c++)
        rs->col[c] = NULL;
}

int psim_restart_value(const psim_scene *sc, const char *model, const char *name, double *v)
{
    const psim_restart *rs = &sc->restart;
    if (!rs->present || strcmp(rs->model, model))
        return -1;
    for (int k = 0; k < rs->nvalues; k++)
        if (!strcmp(rs->valname[k], name)) {
            *v = rs->value[k];
            return 0;
        }
    return -1;
}

const double *psim_restart_column(const psim_scene *sc, const char *model, const char *name)
{
    const psim_restart *rs = &sc->restart;
    if (!rs->present || strcmp(rs->model, model))
        return NULL;
    for (int c = 0; c < rs->ncols; c++)
        if (!strcmp(rs->colname[c], name))
            return rs->col[c];
    return NULL;
}
