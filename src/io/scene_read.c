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
    char *buf;      /* the current line: MAX_LINE + 1 bytes */
    int pushed;     /* the line in buf is to be read again */
    int failed;     /* next_line found what no scene has (err is set) */
    psim_error *err;
    char *chunk;    /* the file, read a chunk at a time */
    size_t pos, end;
    int eof;
} reader;

#define CHUNK (1u << 20)

/* The longest line a scene may have: five numbers of 17 digits with their
 * signs and exponents fit many times over.  A longer "line" is binary data
 * (a file of zero bytes has no newline at all). */
#define MAX_LINE 4096

static int blank(const char *s)
{
    while (*s && isspace((unsigned char)*s))
        s++;
    return *s == '\0';
}

/* Bytes from rd->pos to the chunk's end, more read after them; 0 at end
 * of file or on a read error. */
static size_t refill(reader *rd)
{
    if (rd->eof)
        return rd->end - rd->pos;
    memmove(rd->chunk, rd->chunk + rd->pos, rd->end - rd->pos);
    rd->end -= rd->pos;
    rd->pos = 0;
    size_t got = fread(rd->chunk + rd->end, 1, CHUNK - rd->end, rd->f);
    rd->end += got;
    if (got == 0)
        rd->eof = 1;
    return rd->end;
}

/* One line into rd->buf (without its newline); its length, or -1 at end
 * of file, or -2 after an error (NUL byte, line too long). */
static long read_line(reader *rd)
{
    if (!rd->buf) {
        rd->buf = malloc(MAX_LINE + 1);
        rd->chunk = malloc(CHUNK);
        if (!rd->buf || !rd->chunk) {
            psim_error_set(rd->err, "%s: out of memory", rd->name);
            return -2;
        }
    }
    const char *nl;
    size_t avail = rd->end - rd->pos;
    while (!(nl = memchr(rd->chunk + rd->pos, '\n', avail)) && avail <= MAX_LINE && !rd->eof)
        avail = refill(rd);
    size_t len = nl ? (size_t)(nl - (rd->chunk + rd->pos)) : avail;
    if (!nl && len == 0)
        return -1;
    const char *zero = memchr(rd->chunk + rd->pos, '\0', len < MAX_LINE ? len : MAX_LINE);
    if (zero) {
        psim_error_set(rd->err, "%s:%ld: a NUL byte at column %ld: binary data, not a "
                       "scene (scenes are text)", rd->name, rd->line + 1,
                       (long)(zero - (rd->chunk + rd->pos)) + 1);
        return -2;
    }
    if (len > MAX_LINE) {
        psim_error_set(rd->err, "%s:%ld: line longer than %d bytes: binary data, not a "
                       "scene?", rd->name, rd->line + 1, MAX_LINE);
        return -2;
    }
    memcpy(rd->buf, rd->chunk + rd->pos, len);
    rd->buf[len] = '\0';
    rd->pos += len + (nl != NULL);
    rd->line++;
    /* a UTF-8 byte-order mark (editors on Windows write one) is not text */
    if (rd->line == 1 && len >= 3 && memcmp(rd->buf, "\xEF\xBB\xBF", 3) == 0) {
        memmove(rd->buf, rd->buf + 3, len - 2);
        len -= 3;
    }
    return (long)len;
}

/* Next line that is not blank; NULL at end of file or after an error
 * (rd->failed). */
static char *next_line(reader *rd)
{
    if (rd->pushed) {
        rd->pushed = 0;
        return rd->buf;
    }
    for (;;) {
        long got = read_line(rd);
        if (got == -2)
            rd->failed = 1;
        if (got < 0)
            return NULL;
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
    if (!s && rd->failed)
        return -1;
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
    if (S < 0 || S > PSIM_MAX_STEPS) {
        psim_error_set(err, "%s:%ld: step count S must be between 0 and %ld (as --steps), "
                       "got %.0f", rd->name, rd->line, PSIM_MAX_STEPS, S);
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
    if (!s && rd->failed)
        return -1;
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
        return rd->failed ? -1 : 0;
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
    reader rd = {.f = f, .name = name, .err = err};
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
            if (rd.failed)
                goto done;
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
    if (rd.failed)
        goto done;
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
    free(rd.chunk);
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
