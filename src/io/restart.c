/* The parts of a restart file (--restart) beyond a scene: its first line,
 *   #psim restart 1 model=NAME step=K [format=2024|2019|cs267] [print=0|1]
 *                   [options=K=V,...] [grid=REACH,OCC,TILE[,X0,Y0,X1,Y1]]
 *                   [cuts=X0,...,XT,Y0,...,YT]
 *                   [values=NAME:V,...] [columns=NAME,...]
 * and the order of its particle lines (the run's own order, which the
 * discrete model's results follow).  The scene reader calls these; the
 * engine writes the file (src/engine/restart.c). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fmt.h"
#include "restart.h"

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

/* Up to max numbers separated by commas: their count, or -1. */
static int number_list(const char *v, double *out, int max)
{
    int k = 0;
    while (*v) {
        if (k == max)
            return -1;
        const char *end = psim_scan_double(v, &out[k]);
        if (!end || !isfinite(out[k]) || (*end && *end != ','))
            return -1;
        k++;
        v = *end ? end + 1 : end;
        if (*end && !*v)
            return -1;   /* a trailing comma */
    }
    return k;
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

/* X0,...,XT,Y0,...,YT: the tiles' cuts (the engine checks them against its
 * grid: a plan that no longer fits is left at its default cuts). */
static int cut_list(psim_restart *rs, const char *v)
{
    rs->ncuts = 0;
    while (*v) {
        char *end;
        errno = 0;
        long c = strtol(v, &end, 10);
        if (end == v || errno || c < 0 || c > INT32_MAX || (*end && *end != ',') ||
            rs->ncuts == PSIM_RESTART_CUTS || (*end && !end[1]))
            return -1;
        rs->cuts[rs->ncuts++] = (int32_t)c;
        v = *end ? end + 1 : end;
    }
    return rs->ncuts >= 4 && rs->ncuts % 2 == 0 ? 0 : -1;
}

/* NAME:V,NAME:V: the model's values. */
static int value_list(psim_restart *rs, const char *v)
{
    rs->nvalues = 0;
    while (*v) {
        size_t len = strcspn(v, ":,");
        if (rs->nvalues == 8 || v[len] != ':' || !word_ok(v, len, sizeof rs->valname[0]))
            return -1;
        memcpy(rs->valname[rs->nvalues], v, len);
        rs->valname[rs->nvalues][len] = '\0';
        const char *end = psim_scan_double(v + len + 1, &rs->value[rs->nvalues]);
        if (!end || (*end && *end != ',') || (*end && !end[1]))
            return -1;
        rs->nvalues++;
        v = *end ? end + 1 : end;
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
        char *end;
        errno = 0;
        long step = strtol(v, &end, 10);
        if (end == v || *end || errno || step < 0 || step > PSIM_MAX_STEPS)
            return bad(err, name, line, "step must be an integer in 0..10^9, got", v);
        rs->step = step;
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
        free(rs->options);
        if (!(rs->options = strdup(v))) {
            psim_error_set(err, "%s: out of memory", name);
            return -1;
        }
    } else if (k == HK_GRID) {
        int got = number_list(v, rs->grid, 7);
        if ((got != 3 && got != 7) || !(rs->grid[0] > 0) || !(rs->grid[1] >= 0) ||
            rs->grid[2] < 0 || rs->grid[2] > 65536 || rs->grid[2] != floor(rs->grid[2]))
            return bad(err, name, line,
                       "grid must be REACH,OCC,TILE or REACH,OCC,TILE,X0,Y0,X1,Y1, got", v);
        rs->has_grid = 1;
        rs->grid_has_bbox = got == 7;
    } else if (k == HK_CUTS) {
        if (cut_list(rs, v))
            return bad(err, name, line,
                       "cuts must be 2 (T + 1) increasing cell numbers (0,...,G,0,...,G), got", v);
    } else if (k == HK_VALUES) {
        if (value_list(rs, v))
            return bad(err, name, line, "values must be NAME:NUMBER,..., got", v);
    } else {   /* HK_COLUMNS */
        rs->ncols = 0;
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

int psim_restart_header(psim_scene *sc, const char *text, const char *name, long line,
                        psim_error *err)
{
    static const char magic[] = "#psim restart 1";
    if (strncmp(text, magic, sizeof magic - 1) ||
        (text[sizeof magic - 1] && text[sizeof magic - 1] != ' ' && text[sizeof magic - 1] != '\t'))
        return bad(err, name, line, "expected '#psim restart 1 ...', got", text);
    sc->restart.present = 1;
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
    if (!sc->restart.model[0])
        return bad(err, name, line, "missing", "model=NAME");
    return 0;
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
