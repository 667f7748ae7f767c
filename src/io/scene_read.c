/* Reader of both scene formats, strict: every problem is reported as
 * "FILE:LINE: what".
 *   AY2024/25: N, L, r, S, then N lines "i x y vx vy";
 *   AY2019/20: N, L, r, S, then "print" or "perf", then N lines
 *   "i x y vx vy" or none (the course's generator makes them). */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "psim/psim.h"

typedef struct reader {
    FILE *f;
    const char *name;
    long line;
    char *buf;
    size_t cap;
    int pushed;     /* the line in buf is to be read again */
} reader;

static int blank(const char *s)
{
    while (*s && isspace((unsigned char)*s))
        s++;
    return *s == '\0';
}

/* Next line that is not blank; NULL at end of file. */
static char *next_line(reader *rd)
{
    if (rd->pushed) {
        rd->pushed = 0;
        return rd->buf;
    }
    for (;;) {
        ssize_t got = getline(&rd->buf, &rd->cap, rd->f);
        if (got < 0)
            return NULL;
        rd->line++;
        if (!blank(rd->buf))
            return rd->buf;
    }
}

static int parse_long(const char **s, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(*s, &end, 10);
    if (end == *s || errno == ERANGE || (*end && !isspace((unsigned char)*end)))
        return -1;
    *out = v;
    *s = end;
    return 0;
}

static int parse_double(const char **s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(*s, &end);
    if (end == *s || (*end && !isspace((unsigned char)*end)))
        return -1;
    *out = v;
    *s = end;
    return 0;
}

static int only_space(const char *s) { return blank(s); }

static const char *chomp(char *s)
{
    s[strcspn(s, "\r\n")] = '\0';
    return s;
}

static int header_value(reader *rd, const char *what, int integer, double *v,
                        psim_error *err)
{
    const char *s = next_line(rd);
    if (!s && ferror(rd->f)) {
        psim_error_set(err, "%s: read error: %s", rd->name, strerror(errno));
        return -1;
    }
    if (!s) {
        psim_error_set(err, "%s:%ld: unexpected end of file: expected %s",
                       rd->name, rd->line + 1, what);
        return -1;
    }
    long iv = 0;
    int bad = integer ? parse_long(&s, &iv) : parse_double(&s, v);
    if (bad || !only_space(s)) {
        psim_error_set(err, "%s:%ld: expected %s (%s), got \"%.40s\"", rd->name,
                       rd->line, what, integer ? "an integer" : "a number",
                       chomp(rd->buf));
        return -1;
    }
    if (integer)
        *v = (double)iv;
    if (!isfinite(*v)) {
        psim_error_set(err, "%s:%ld: %s must be finite", rd->name, rd->line, what);
        return -1;
    }
    return 0;
}

static int read_header(reader *rd, psim_scene *sc, psim_error *err)
{
    double n, L, r, S;
    if (header_value(rd, "the particle count N", 1, &n, err))
        return -1;
    if (n < 0 || n > 2147483647.0) {
        psim_error_set(err, "%s:%ld: particle count N must be between 0 and 2^31-1, got %.0f",
                       rd->name, rd->line, n);
        return -1;
    }
    if (header_value(rd, "the box side L", 0, &L, err))
        return -1;
    if (!(L > 0)) {
        psim_error_set(err, "%s:%ld: box side L must be positive, got %g",
                       rd->name, rd->line, L);
        return -1;
    }
    if (header_value(rd, "the radius r", 0, &r, err))
        return -1;
    if (!(r > 0)) {
        psim_error_set(err, "%s:%ld: radius r must be positive, got %g",
                       rd->name, rd->line, r);
        return -1;
    }
    if (!(2 * r < L)) {
        /* a disk touching both walls could never resolve its wall collision;
         * nor can it move in the 2019 model */
        psim_error_set(err, "%s:%ld: radius r = %g does not fit in the box: 2r must "
                       "be less than L = %g", rd->name, rd->line, r, L);
        return -1;
    }
    if (header_value(rd, "the step count S", 1, &S, err))
        return -1;
    if (S < 0) {
        psim_error_set(err, "%s:%ld: step count S must not be negative, got %.0f",
                       rd->name, rd->line, S);
        return -1;
    }
    if (psim_scene_alloc(sc, (long)n, err))
        return -1;
    sc->L = L;
    sc->r = r;
    sc->steps = (long)S;
    return 0;
}

static int read_particle(reader *rd, psim_scene *sc, unsigned char *seen,
                         long k, psim_error *err)
{
    const char *s = next_line(rd);
    if (!s) {
        psim_error_set(err, "%s:%ld: unexpected end of file: expected %ld particle "
                       "lines, found %ld", rd->name, rd->line + 1, sc->n, k);
        return -1;
    }
    long id;
    double v[4];
    static const char *field[4] = {"x", "y", "vx", "vy"};
    if (parse_long(&s, &id)) {
        psim_error_set(err, "%s:%ld: expected a particle line \"i x y vx vy\"",
                       rd->name, rd->line);
        return -1;
    }
    for (int f = 0; f < 4; f++) {
        if (parse_double(&s, &v[f])) {
            psim_error_set(err, "%s:%ld: particle %ld: missing or malformed %s",
                           rd->name, rd->line, id, field[f]);
            return -1;
        }
        if (!isfinite(v[f])) {
            psim_error_set(err, "%s:%ld: particle %ld: %s is not a finite number",
                           rd->name, rd->line, id, field[f]);
            return -1;
        }
    }
    if (!only_space(s)) {
        psim_error_set(err, "%s:%ld: particle %ld: unexpected text after vy",
                       rd->name, rd->line, id);
        return -1;
    }
    if (id < 0 || id >= sc->n) {
        psim_error_set(err, "%s:%ld: particle index %ld out of range 0..%ld",
                       rd->name, rd->line, id, sc->n - 1);
        return -1;
    }
    if (seen[id]) {
        psim_error_set(err, "%s:%ld: particle index %ld appears twice", rd->name,
                       rd->line, id);
        return -1;
    }
    seen[id] = 1;
    if (sc->line)
        sc->line[id] = rd->line;
    sc->x[id] = v[0];
    sc->y[id] = v[1];
    sc->vx[id] = v[2];
    sc->vy[id] = v[3];
    return 0;
}

/* The fifth line of a 2019 scene: "print" or "perf".  Anything else is
 * left for the particle reader (a 2024 scene). */
static int read_mode(reader *rd, psim_scene *sc)
{
    char *s = next_line(rd);
    if (!s)
        return 0;
    char word[8];
    int len = 0;
    if (sscanf(s, " %7s %n", word, &len) == 1 && s[len] == '\0' &&
        (!strcmp(word, "print") || !strcmp(word, "perf"))) {
        sc->format = PSIM_SCENE_2019;
        sc->print = word[1] == 'r';
        return 0;
    }
    rd->pushed = 1;
    return 0;
}

int psim_scene_read_stream(FILE *f, const char *name, psim_scene *sc,
                           psim_error *err)
{
    reader rd = {f, name, 0, NULL, 0, 0};
    unsigned char *seen = NULL;
    memset(sc, 0, sizeof *sc);
    int rc = -1;
    if (read_header(&rd, sc, err) || read_mode(&rd, sc))
        goto done;
    seen = calloc((size_t)sc->n + 1, 1);
    sc->line = calloc((size_t)sc->n + 1, sizeof *sc->line);
    sc->source = strdup(name);
    if (!seen || !sc->line || !sc->source) {
        psim_error_set(err, "%s: out of memory for %ld particles", name, sc->n);
        goto done;
    }
    if (sc->format == PSIM_SCENE_2019) {
        if (!next_line(&rd)) {
            /* no particle lines: the course's generator, rand() seeded 3210 */
            if (ferror(f) || psim_scene_generate_2019(sc, 3210, err))
                goto gen_failed;
            sc->generated = 1;
            rc = 0;
            goto done;
        }
        rd.pushed = 1;
    }
    for (long k = 0; k < sc->n; k++)
        if (read_particle(&rd, sc, seen, k, err))
            goto done;
    if (next_line(&rd)) {
        psim_error_set(err, "%s:%ld: more particle lines than N = %ld", name,
                       rd.line, sc->n);
        goto done;
    }
    if (ferror(f)) {
        psim_error_set(err, "%s: read error: %s", name, strerror(errno));
        goto done;
    }
    rc = 0;
    goto done;
gen_failed:
    if (ferror(f))
        psim_error_set(err, "%s: read error: %s", name, strerror(errno));
    else {
        psim_error t = *err;
        psim_error_set(err, "%s:%ld: %s", name, rd.line, t.msg);
    }
done:
    free(seen);
    free(rd.buf);
    if (rc)
        psim_scene_free(sc);
    return rc;
}

int psim_scene_read(const char *path, psim_scene *sc, psim_error *err)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        psim_error_set(err, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    int rc = psim_scene_read_stream(f, path, sc, err);
    fclose(f);
    return rc;
}

int psim_scene_alloc(psim_scene *sc, long n, psim_error *err)
{
    size_t b = (size_t)(n > 0 ? n : 1) * sizeof(double);
    sc->n = n;
    sc->source = NULL;
    sc->line = NULL;
    sc->x = calloc(1, b);
    sc->y = calloc(1, b);
    sc->vx = calloc(1, b);
    sc->vy = calloc(1, b);
    if (!sc->x || !sc->y || !sc->vx || !sc->vy) {
        psim_scene_free(sc);
        psim_error_set(err, "out of memory for %ld particles", n);
        return -1;
    }
    return 0;
}

void psim_scene_where(const psim_scene *sc, long i, char *buf, size_t size)
{
    if (size == 0)
        return;
    buf[0] = '\0';
    if (sc->source && sc->line)
        snprintf(buf, size, "%s:%ld: ", sc->source, sc->line[i]);
}

void psim_scene_free(psim_scene *sc)
{
    free(sc->x);
    free(sc->y);
    free(sc->vx);
    free(sc->vy);
    free(sc->source);
    free(sc->line);
    sc->x = sc->y = sc->vx = sc->vy = NULL;
    sc->source = NULL;
    sc->line = NULL;
}
