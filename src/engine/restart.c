/* Restart files: the state as a scene that psim reads back, with what a
 * run needs to go on exactly as if it had not stopped (docs/formats.md,
 * "Restart files"): the steps done, the model and its options, the grid
 * plan the model asked for, the particles in the store's order where the
 * model's results follow it (the discrete model resolves contacts in that
 * order; others by id) and the model's own columns (ccd: its collision
 * counts; event: each disk's own time). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "engine.h"
#include "mem.h"
#include "../io/fmt.h"
#include "../io/lines.h"
#include "../io/restart.h"

/* The model's columns in sc, each value of its column's kind and range
 * (a model converts them to its integer types): the scene reader holds a
 * file to them, and a scene made by the library's caller is held to them
 * here.  0, or -1 with err naming the first that is not. */
static int columns_ok(const psim_sim *e, const psim_scene *sc, psim_error *err)
{
    for (int k = 0; k < PSIM_RESTART_COLS && e->model->restart_cols[k].name; k++) {
        const psim_restart_col *c = &e->model->restart_cols[k];
        const double *v = psim_restart_column(sc, e->model->name, c->name);
        for (long i = 0; v && i < sc->n; i++)
            if (!(v[i] >= c->lo && v[i] <= c->hi) || (c->integer && v[i] != floor(v[i]))) {
                char at[320];
                psim_scene_where(sc, i, at, sizeof at);
                psim_error_set(err, "%sparticle %ld: %s %.17g is not %s in [%.17g, %.17g]", at,
                               i, c->name, v[i], c->integer ? "a whole number" : "a number",
                               c->lo, c->hi);
                return -1;
            }
    }
    return 0;
}

int psim_engine_restart_init(psim_sim *e, psim_scene *sc, psim_error *err)
{
    const psim_restart *rs = &sc->restart;
    e->format = sc->format;
    e->print = sc->print;
    if (!rs->present)
        return 0;
    e->step = e->step0 = rs->step;
    if (strcmp(rs->model, e->model->name))
        return 0;   /* another model's plan and order are not this one's */
    if (columns_ok(e, sc, err))
        return -1;
    if (rs->has_grid) {
        e->grid_saved = 1;
        e->grid_saved_bbox = rs->grid_has_bbox;
        memcpy(e->grid_saved_ask, rs->grid, sizeof rs->grid);
        e->ncuts_saved = rs->ncuts;
        memcpy(e->cuts_saved, rs->cuts, (size_t)rs->ncuts * sizeof *rs->cuts);
    }
    if (e->model->follows_order && rs->order && e->n > 0) {
        e->restart_order = malloc((size_t)e->n * sizeof *e->restart_order);
        if (!e->restart_order) {
            psim_error_set(err, "out of memory for %ld particles", sc->n);
            return -1;
        }
        memcpy(e->restart_order, rs->order, (size_t)e->n * sizeof *e->restart_order);
    }
    return 0;
}

/* Before the first sort the store is in id order: place i holds id i. */
void psim_engine_restart_order(psim_sim *e)
{
    psim_store *s = &e->st;
    const int32_t *o = e->restart_order;
    const long n = (long)s->n;
#pragma omp parallel for schedule(static) num_threads(e->threads) if (n > 65536)
    for (long k = 0; k < n; k++) {
        int32_t i = o[k];
        s->x2[k] = s->x[i], s->y2[k] = s->y[i];
        s->vx2[k] = s->vx[i], s->vy2[k] = s->vy[i];
        s->id2[k] = s->id[i];
    }
    psim_store_swap(s);
    free(e->restart_order);
    e->restart_order = NULL;
}

const double *psim_engine_restart_column(const psim_sim *e, const psim_scene *sc,
                                         const char *name)
{
    return psim_restart_column(sc, e->model->name, name);
}

int psim_engine_restart_value(const psim_sim *e, const psim_scene *sc, const char *name,
                              double *v)
{
    return psim_restart_value(sc, e->model->name, name, v);
}

static const char *format_name(psim_scene_format f)
{
    return f == PSIM_SCENE_2019 ? "2019" : f == PSIM_SCENE_CS267 ? "cs267" : "2024";
}

/* " KEY=A,B,C" of n numbers. */
static int put_numbers(FILE *f, const char *key, const double *v, int n)
{
    char b[PSIM_FMT_MAX];
    if (fprintf(f, " %s=", key) < 0)
        return -1;
    for (int k = 0; k < n; k++) {
        psim_fmt_shortest(b, v[k]);
        if (fprintf(f, "%s%s", k ? "," : "", b) < 0)
            return -1;
    }
    return 0;
}

/* " cuts=X0,...,XTG,Y0,...,YTG": the tiles' cuts, where a model chose them. */
static int put_cuts(FILE *f, const psim_grid *g)
{
    if (2 * (g->TG + 1) > PSIM_RESTART_CUTS)
        return 0;   /* (never chosen: psim_grid_cut's callers stay below) */
    for (int a = 0; a < 2; a++)
        for (int j = 0; j <= g->TG; j++)
            if (fprintf(f, "%s%d", a + j ? "," : " cuts=", (int)(a ? g->cut_y : g->cut_x)[j]) < 0)
                return -1;
    return 0;
}

static int put_header(FILE *f, const psim_sim *e, long steps)
{
    const psim_model *m = e->model;
    char b[PSIM_FMT_MAX];
    if (fprintf(f, "#psim restart 1 model=%s step=%ld format=%s print=%d", m->name, e->step,
                format_name(e->format), e->print) < 0)
        return -1;
    for (int k = 0, any = 0; k < PSIM_MODEL_OPTIONS && m->options[k].name; k++)
        if (e->opt_set[k]) {
            psim_fmt_shortest(b, e->opt_value[k]);
            if (fprintf(f, "%s%s=%s", any++ ? "," : " options=", m->options[k].name, b) < 0)
                return -1;
        }
    /* (only finite numbers: the reader takes no other; a plan or a sum
     * that is not finite is left out, and the next run starts it afresh) */
    int ng = e->grid_ask_bbox ? 7 : 3, finite = e->grid_asked;
    for (int k = 0; k < ng; k++)
        finite &= isfinite(e->grid_ask[k]) != 0;
    if (finite && put_numbers(f, "grid", e->grid_ask, ng))
        return -1;
    if (finite && e->has_grid && e->grid.cut && put_cuts(f, &e->grid))
        return -1;
    for (int k = 0, any = 0; k < e->stats.nvalues; k++) {
        if (!isfinite(e->stats.value[k]))
            continue;
        psim_fmt_shortest(b, e->stats.value[k]);
        if (fprintf(f, "%s%s:%s", any++ ? "," : " values=", e->stats.value_name[k], b) < 0)
            return -1;
    }
    for (int k = 0; m->restart_cols[k].name; k++)
        if (fprintf(f, "%s%s", k ? "," : " columns=", m->restart_cols[k].name) < 0)
            return -1;
    char l[PSIM_FMT_MAX], r[PSIM_FMT_MAX];
    psim_fmt_shortest(l, e->L);
    psim_fmt_shortest(r, e->r);
    return fprintf(f, "\n%ld\n%s\n%s\n%ld\n", e->n_all, l, r, steps) < 0 ? -1 : 0;
}

typedef struct restart_lines {
    const psim_store *st;
    const int32_t *at;      /* NULL: in the store's order; else by id */
    double *col[PSIM_RESTART_COLS];
    int integer[PSIM_RESTART_COLS];   /* written as integers (the reader reads them so) */
    int ncols;
} restart_lines;

#define RESTART_LINE_MAX (24 + (4 + PSIM_RESTART_COLS) * (PSIM_FMT_MAX + 1))

/* Line j: "i x y vx vy" and the model's columns of the particle at store
 * place j, or of id j. */
static size_t restart_line(char *out, long j, const void *vctx)
{
    const restart_lines *c = vctx;
    const psim_store *s = c->st;
    long k = c->at ? c->at[j] : j;
    int32_t i = s->id[k];
    char *p = psim_fmt_long(out, i);
    const double v[4] = {s->x[k], s->y[k], s->vx[k], s->vy[k]};
    for (int q = 0; q < 4; q++) {
        *p++ = ' ';
        p += psim_fmt_shortest(p, v[q]);
    }
    for (int q = 0; q < c->ncols; q++) {
        *p++ = ' ';
        if (c->integer[q])
            p = psim_fmt_long(p, (long long)c->col[q][i]);
        else
            p += psim_fmt_shortest(p, c->col[q][i]);
    }
    *p++ = '\n';
    return (size_t)(p - out);
}

int psim_write_restart(psim_sim *e, FILE *f, long steps)
{
    BY_PARTS(e, f, psim_write_restart(v_, f_, steps));
    psim_engine_sync(e);
    restart_lines c = {.st = &e->st};
    psim_cols by_id = {0};
    int rc = -1;
    if (e->part && e->model->restart_cols[0].name) {
        /* (a model's columns are saved by id over its whole state: no
         * model with columns runs over ranks, where the parts are) */
        errno = ENOTSUP;
        return -1;
    }
    /* the store's order where the model's results follow it; else by id,
     * whatever order the model last sorted into */
    if (!e->model->follows_order) {
        if (psim_state_cols_take(e, &by_id))
            goto done;
        c.at = by_id.at;
    }
    for (; c.ncols < PSIM_RESTART_COLS && e->model->restart_cols[c.ncols].name; c.ncols++) {
        c.integer[c.ncols] = e->model->restart_cols[c.ncols].integer;
        c.col[c.ncols] = psim_alloc((size_t)(e->n > 0 ? e->n : 1) * sizeof(double));
        if (!c.col[c.ncols])
            goto done;
        e->model->restart_save(e, e->mstate, c.ncols, c.col[c.ncols]);
    }
    if (e->part && !e->part->head)
        rc = 0;
    else
        rc = put_header(f, e, steps);
    if (rc == 0)
        rc = psim_write_lines(f, e->n, e->threads, RESTART_LINE_MAX, restart_line, &c);
done:
    psim_state_cols_free(&by_id);
    for (int q = 0; q < PSIM_RESTART_COLS; q++)
        psim_free(c.col[q]);
    return rc;
}
