/* Reader of both scene formats, strict: every problem is reported as
 * "FILE:LINE: what".
 *   AY2024/25: N, L, r, S, then N lines "i x y vx vy";
 *   AY2019/20: N, L, r, S, then "print" or "perf", then N lines
 *   "i x y vx vy" or none (the course's generator makes them).
 *
 * The header is read line by line.  The particle lines are read in large
 * blocks, each block parsed in parallel: split at newlines into one piece
 * per thread, the lines of each piece numbered from the newlines counted
 * before it, and every line of the plain form (fields separated by spaces
 * or tabs, decimal numbers, an optional CR before the newline) read with
 * psim_scan_double (fmt.c: strtod's values exactly) and stored by id; an
 * id is claimed with an atomic exchange on its `seen` byte, so only its
 * first claimant writes it.  A block with anything else in it (a line of
 * another form, an error of any kind, more lines than N) is read again by
 * the line-by-line reader from the block's start, which then says exactly
 * what the line-by-line reader always said, at the same line.  A duplicate
 * id is one seen on an earlier line (seen[id] with line[id] below this
 * line), so a claim made by a later line of the same block in the parallel
 * pass does not count. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <omp.h>

#include "fmt.h"
#include "lines.h"
#include "restart.h"
#include "scene_read.h"
#include "scene.h"

/* The longest line a scene may have: five numbers of 17 digits with their
 * signs and exponents fit many times over.  A longer "line" is binary data
 * (a file of zero bytes has no newline at all). */
#define MAX_LINE 4096
/* A restart file's first line may be longer: its tiles' cuts alone are up
 * to PSIM_RESTART_CUTS cell numbers of up to 5 digits (46341 cells a side
 * at most), some 6 KB.  (Below the smallest block, 4 MAX_LINE.) */
#define MAX_FIRST_LINE 8192

typedef struct reader {
    FILE *f;
    const char *name;
    long line;
    char *buf;      /* the current line: MAX_FIRST_LINE + 1 bytes */
    int pushed;     /* the line in buf is to be read again */
    int failed;     /* next_line found what no scene has (err is set) */
    psim_error *err;
    char *chunk;    /* the file, read a chunk at a time (NUL after end) */
    size_t pos, end;
    int eof;
    long long consumed;  /* bytes of the file read as lines so far */
    long long size;      /* the file's size, -1 when unknown (a pipe) */
    size_t cap;          /* chunk's size (block_bytes) */
    size_t max;          /* the longest line taken now (MAX_LINE, or more for
                          * the first: MAX_FIRST_LINE) */
    int ranged;          /* a byte range of the file alone: left bytes to read */
    long long left;
    int head_only;       /* the header alone: no particle arrays */
    long long mark;      /* where read_mode's line began (bytes read before it) */
    long mark_line;
} reader;

/* Zero bytes kept after the data read (a NUL, and 8 bytes that
 * psim_scan_double_padded may read past a number). */
#define PAD 16

/* Bytes read at a time (blocks of particle lines are parsed in parallel,
 * one piece per thread of at least piece_min bytes); tests make them
 * small (psim_io_set_blocks). */
static size_t block_bytes = (size_t)8 << 20, piece_min = (size_t)1 << 16;

void psim_io_set_blocks(size_t block, size_t piece)
{
    block_bytes = block ? block : (size_t)8 << 20;
    if (block_bytes < 4 * MAX_LINE)
        block_bytes = 4 * MAX_LINE;
    piece_min = piece ? piece : (size_t)1 << 16;
}


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
    size_t want = rd->cap - rd->end;
    if (rd->ranged && (long long)want > rd->left)
        want = (size_t)rd->left;
    size_t got = want ? fread(rd->chunk + rd->end, 1, want, rd->f) : 0;
    if (rd->ranged)
        rd->left -= (long long)got;
    rd->end += got;
    memset(rd->chunk + rd->end, 0, PAD);   /* a NUL after the data, and room
                                            * for psim_scan_double_padded */
    if (got == 0)
        rd->eof = 1;
    return rd->end;
}

/* Whether the n bytes of a line hold a CR with text after it: a file whose
 * lines end in CR alone (old Mac line ends) is one line of LF-ended text
 * (a long one: "binary data"), whose first number was all the reader saw.
 * A CR before the LF (CR LF), and spaces after a CR, are no line ends. */
static int cr_alone(const char *p, size_t n)
{
    const char *cr = memchr(p, '\r', n);
    if (!cr)
        return 0;
    for (const char *q = cr + 1; q < p + n; q++)
        if (!isspace((unsigned char)*q))
            return 1;
    return 0;
}

/* One line into rd->buf (without its newline); its length, or -1 at end
 * of file, or -2 after an error (NUL byte, CR line ends, line too long). */
static long read_line(reader *rd)
{
    if (!rd->buf) {
        rd->buf = malloc(MAX_FIRST_LINE + 1);
        rd->chunk = malloc(rd->cap + PAD);
        if (!rd->buf || !rd->chunk) {
            psim_error_set(rd->err, "%s: out of memory", rd->name);
            return -2;
        }
    }
    const char *nl;
    size_t avail = rd->end - rd->pos;
    while (!(nl = memchr(rd->chunk + rd->pos, '\n', avail)) && avail <= rd->max && !rd->eof)
        avail = refill(rd);
    size_t len = nl ? (size_t)(nl - (rd->chunk + rd->pos)) : avail;
    if (!nl && len == 0)
        return -1;
    const char *zero = memchr(rd->chunk + rd->pos, '\0', len < rd->max ? len : rd->max);
    if (zero) {
        psim_error_set(rd->err, "%s:%ld: a NUL byte at column %ld: binary data, not a "
                       "scene (scenes are text)", rd->name, rd->line + 1,
                       (long)(zero - (rd->chunk + rd->pos)) + 1);
        return -2;
    }
    if (cr_alone(rd->chunk + rd->pos, len < rd->max ? len : rd->max)) {
        psim_error_set(rd->err, "%s:%ld: lines end in CR alone (old Mac line ends), not LF "
                       "or CR LF: convert the file, e.g. tr '\\r' '\\n' < OLD > NEW",
                       rd->name, rd->line + 1);
        return -2;
    }
    if (len > rd->max) {
        psim_error_set(rd->err, "%s:%ld: line longer than %zu bytes: binary data, not a "
                       "scene?", rd->name, rd->line + 1, rd->max);
        return -2;
    }
    memcpy(rd->buf, rd->chunk + rd->pos, len);
    rd->buf[len] = '\0';
    rd->pos += len + (nl != NULL);
    rd->consumed += (long long)(len + (nl != NULL));
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

/* The value of the restart file's column c at *s (after spaces), as the
 * model declares it; *s is left at the field. */
static int parse_column(const psim_restart *rs, int c, const char **s, double *out)
{
    *s += strspn(*s, " \t");
    const char *end = psim_restart_scan(&rs->colspec[c], *s, 0, out);
    if (!end || (*end && !isspace((unsigned char)*end)))
        return -1;
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
    long at[4];
    if (header_value(rd, "the particle count N", 1, &n, err))
        return -1;
    at[PSIM_LINE_N] = rd->line;
    if (n < 0 || n > 2147483647.0) {
        psim_error_set(err, "%s:%ld: particle count N must be between 0 and 2^31-1, got %.0f",
                       rd->name, rd->line, n);
        return -1;
    }
    if (header_value(rd, "the box side L", 0, &L, err))
        return -1;
    at[PSIM_LINE_L] = rd->line;
    if (!(L > 0)) {
        psim_error_set(err, "%s:%ld: box side L must be positive, got %g",
                       rd->name, rd->line, L);
        return -1;
    }
    if (header_value(rd, "the radius r", 0, &r, err))
        return -1;
    at[PSIM_LINE_R] = rd->line;
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
    at[PSIM_LINE_S] = rd->line;
    if (S < 0 || S > PSIM_MAX_STEPS) {
        psim_error_set(err, "%s:%ld: step count S must be between 0 and %ld (as --steps), "
                       "got %.0f", rd->name, rd->line, PSIM_MAX_STEPS, S);
        return -1;
    }
    if (rd->head_only)
        sc->n = (long)n;
    else if (psim_scene_alloc(sc, (long)n, err))
        return -1;
    sc->L = L;
    sc->r = r;
    sc->steps = (long)S;
    memcpy(sc->header_line, at, sizeof at);
    return 0;
}

/* A particle line s (line rd->line): its id, in 0..n-1, its four values
 * and the restart file's columns rs (NULL: none).  0, or -1 with err set. */
static int parse_particle(const reader *rd, const psim_restart *rs, long n, const char *s,
                          long *idp, double v[4], double *extra, psim_error *err)
{
    long id;
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
    const int ncols = rs ? rs->ncols : 0;
    for (int c = 0; c < ncols; c++)
        if (parse_column(rs, c, &s, &extra[c])) {
            char what[256];
            psim_restart_field_error(rs, c, id, s, what, sizeof what);
            psim_error_set(err, "%s:%ld: %s", rd->name, rd->line, what);
            return -1;
        }
    if (!only_space(s)) {
        psim_error_set(err, "%s:%ld: particle %ld: unexpected text after %s",
                       rd->name, rd->line, id, ncols ? rs->colname[ncols - 1] : "vy");
        return -1;
    }
    if (id < 0 || id >= n) {
        psim_error_set(err, "%s:%ld: particle index %ld out of range 0..%ld",
                       rd->name, rd->line, id, n - 1);
        return -1;
    }
    *idp = id;
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
    const psim_restart *rs = &sc->restart;
    double extra[PSIM_RESTART_COLS];
    if (parse_particle(rd, rs, sc->n, s, &id, v, extra, err))
        return -1;
    /* (an id claimed by a later line of this block in the parallel pass
     * is not seen yet) */
    if (seen[id] && sc->line[id] < rd->line) {
        psim_error_set(err, "%s:%ld: particle index %ld appears twice", rd->name,
                       rd->line, id);
        return -1;
    }
    seen[id] = 1;
    sc->line[id] = rd->line;
    sc->x[id] = v[0];
    sc->y[id] = v[1];
    sc->vx[id] = v[2];
    sc->vy[id] = v[3];
    for (int c = 0; c < rs->ncols; c++)
        rs->col[c][id] = extra[c];
    return 0;
}

/* ---- particle lines in parallel blocks ------------------------------------ */

static inline int sep(char c) { return c == ' ' || c == '\t'; }

/* The end of a field: a separator, the line's end or the data's end. */
static inline int field_end(const char *p, const char *lim)
{
    return sep(*p) || *p == '\n' || *p == '\r' || p == lim;
}

typedef struct block_job {
    psim_scene *sc;
    unsigned char *seen;
    const char *lim;   /* the end of the data read (NUL there) */
    long part_line0;   /* a part (sc->id): each line at its place in the range,
                        * line - part_line0 - 1 (parts.c compacts them) */
} block_job;

/* Parse the lines of [p, b), the first being line line0 + 1: store every
 * particle line of the plain form and count them in *count; 0, or -1 at
 * the first line that is not of that form or not acceptable (the line by
 * line reader then says why). */
static int parse_piece(const block_job *j, const char *p, const char *b, long line0,
                       long *count)
{
    psim_scene *sc = j->sc;
    const char *lim = j->lim;
    long line = line0, c = 0;
    while (p < b) {
        const char *start = p;
        line++;
        while (sep(*p))
            p++;
        if (*p == '\r')
            p += p[1] == '\n' || p + 1 == lim;
        if (*p == '\n' || p == lim) {   /* blank */
            if ((size_t)(p - start) > MAX_LINE)
                return -1;
            p += p < lim;
            continue;
        }
        uint64_t id = 0;
        const char *d0 = p;
        while ((unsigned)(*p - '0') < 10u && p - d0 < 18)
            id = id * 10 + (uint64_t)(*p++ - '0');
        if (p == d0 || !sep(*p))
            return -1;
        double v[4 + PSIM_RESTART_COLS];
        for (int f = 0; f < 4 + sc->restart.ncols; f++) {
            if (!sep(*p))
                return -1;
            while (sep(*p))
                p++;
            p = f < 4 ? psim_scan_double_padded(p, &v[f])
                      : psim_restart_scan(&sc->restart.colspec[f - 4], p, 1, &v[f]);
            if (!p || !field_end(p, lim) || !isfinite(v[f]))
                return -1;
        }
        while (sep(*p))
            p++;
        if (*p == '\r')
            p++;
        if (!(*p == '\n' || p == lim) || (size_t)(p - start) > MAX_LINE)
            return -1;
        p += p < lim;
        if (sc->id) {   /* a part: ids seen twice are looked for later */
            if (id >= (uint64_t)sc->n_all)
                return -1;
            size_t at = (size_t)(line - j->part_line0 - 1);
            sc->x[at] = v[0], sc->y[at] = v[1], sc->vx[at] = v[2], sc->vy[at] = v[3];
            sc->id[at] = (int32_t)id, sc->line[at] = line;
            c++;
            continue;
        }
        if (id >= (uint64_t)sc->n || __atomic_exchange_n(&j->seen[id], 1, __ATOMIC_RELAXED))
            return -1;   /* out of range, or a duplicate */
        sc->x[id] = v[0];
        sc->y[id] = v[1];
        sc->vx[id] = v[2];
        sc->vy[id] = v[3];
        for (int q = 0; q < sc->restart.ncols; q++)
            sc->restart.col[q][id] = v[4 + q];
        sc->line[id] = line;
        c++;
    }
    *count = c;
    return 0;
}

#define MAX_PIECES 256

/* The whole lines of [base, cut), from line rd->line + 1, in parallel:
 * 0 with the lines and the particle lines among them, or -1 when a line
 * needs the line by line reader. */
static int parse_block(const reader *rd, const block_job *j, const char *base,
                       const char *cut, long *lines, long *count)
{
    size_t len = (size_t)(cut - base);
    int T = omp_get_max_threads();
    if (T > MAX_PIECES)
        T = MAX_PIECES;
    if (len < piece_min * (size_t)T)
        T = len / piece_min > 1 ? (int)(len / piece_min) : 1;
    const char *start[MAX_PIECES + 1];
    long nl[MAX_PIECES], cnt[MAX_PIECES];
    int bad[MAX_PIECES];
    start[0] = base;
    for (int t = 1; t < T; t++) {
        const char *s0 = base + len * (size_t)t / (size_t)T;
        if (s0 < start[t - 1])
            s0 = start[t - 1];
        const char *q = memchr(s0, '\n', (size_t)(cut - s0));
        start[t] = q ? q + 1 : cut;
    }
    start[T] = cut;
#pragma omp parallel num_threads(T) if (T > 1)
    {
        int nt = omp_get_num_threads(), me = omp_get_thread_num();
        for (int t = me; t < T; t += nt) {
            long c = 0;
            for (const char *q = start[t]; q < start[t + 1]; q++)
                c += *q == '\n';
            nl[t] = c;
        }
#pragma omp barrier
        for (int t = me; t < T; t += nt) {
            long line0 = rd->line;
            for (int u = 0; u < t; u++)
                line0 += nl[u];
            bad[t] = parse_piece(j, start[t], start[t + 1], line0, &cnt[t]);
        }
    }
    long L = 0, C = 0;
    for (int t = 0; t < T; t++) {
        if (bad[t])
            return -1;
        L += nl[t];
        C += cnt[t];
    }
    *lines = L + (cut > base && cut[-1] != '\n');   /* a last line without newline */
    *count = C;
    return 0;
}

/* The particle lines, k of them read already: blocks in parallel, and
 * the line by line reader for any block it does not take whole. */
static int read_particles(reader *rd, psim_scene *sc, unsigned char *seen, long *k,
                          psim_error *err)
{
    const int fast = !psim_io_slow();
    block_job j = {sc, seen, NULL, 0};
    while (*k < sc->n) {
        if (fast && !rd->pushed) {
            if (!rd->eof && rd->end - rd->pos < rd->cap / 2)
                refill(rd);
            const char *base = rd->chunk + rd->pos, *lim = rd->chunk + rd->end;
            const char *cut = rd->eof ? lim : memrchr(base, '\n', (size_t)(lim - base));
            if (cut && !rd->eof)
                cut++;
            if (cut && cut > base) {
                long lines = 0, count = 0;
                j.lim = lim;
                if (parse_block(rd, &j, base, cut, &lines, &count) == 0 &&
                    count <= sc->n - *k) {
                    rd->pos += (size_t)(cut - base);
                    rd->consumed += cut - base;
                    rd->line += lines;
                    *k += count;
                    psim_io_progress(0, rd->consumed, rd->size);
                    continue;
                }
                /* the line by line reader, over this block */
                long long stop = rd->consumed + (cut - base);
                while (rd->consumed < stop && *k < sc->n) {
                    if (read_particle(rd, sc, seen, *k, err))
                        return -1;
                    ++*k;
                }
                continue;
            }
        }
        if (read_particle(rd, sc, seen, *k, err))
            return -1;
        ++*k;
    }
    return 0;
}

/* The fifth line of a 2019 scene: "print" or "perf".  Anything else is
 * left for the particle reader (a 2024 scene). */
static int read_mode(reader *rd, psim_scene *sc)
{
    rd->mark = rd->consumed, rd->mark_line = rd->line;
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

/* A restart file's first line, "#psim restart 1 ...": read into
 * sc->restart; any other first line is left for the header. */
static int read_restart_line(reader *rd, psim_scene *sc, psim_restart_schema_fn schema,
                             psim_error *err)
{
    rd->max = MAX_FIRST_LINE;
    char *s = next_line(rd);
    rd->max = MAX_LINE;
    if (!s)
        return rd->failed ? -1 : 0;
    if (s[0] != '#' && strlen(s) > MAX_LINE) {   /* (as any other line) */
        psim_error_set(err, "%s:%ld: line longer than %d bytes: binary data, not a scene?",
                       rd->name, rd->line, MAX_LINE);
        return -1;
    }
    if (s[0] != '#') {
        rd->pushed = 1;
        return 0;
    }
    return psim_restart_header(sc, chomp(s), rd->name, rd->line, schema, err);
}

int psim_io_scene_read_stream(FILE *f, const char *name, psim_restart_schema_fn schema,
                              psim_scene *sc, psim_error *err)
{
    reader rd = {.f = f, .name = name, .err = err, .size = -1, .cap = block_bytes,
                 .max = MAX_LINE};
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode))
        rd.size = (long long)st.st_size;
    unsigned char *seen = NULL;
    memset(sc, 0, sizeof *sc);
    int rc = -1;
    if (read_restart_line(&rd, sc, schema, err) || read_header(&rd, sc, err) ||
        (!sc->restart.present && read_mode(&rd, sc)) ||
        (sc->restart.present && psim_restart_alloc_columns(sc, err)))
        goto done;
    seen = calloc((size_t)sc->n + 1, 1);
    sc->line = calloc((size_t)sc->n + 1, sizeof *sc->line);
    sc->source = strdup(name);
    if (!seen || !sc->line || !sc->source) {
        psim_error_set(err, "%s: out of memory for %ld particles", name, sc->n);
        goto done;
    }
    if (sc->format == PSIM_SCENE_2019 && !sc->restart.present) {
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
    long k = 0;
    if (read_particles(&rd, sc, seen, &k, err))
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
    if (sc->restart.present && psim_restart_order(sc, err))
        goto done;
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
        psim_scene_clear(sc);
    return rc;
}

int psim_io_scene_read(const char *path, psim_restart_schema_fn schema, psim_scene *sc,
                       psim_error *err)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        psim_error_set(err, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    int rc = psim_io_scene_read_stream(f, path, schema, sc, err);
    fclose(f);
    return rc;
}

int psim_scene_alloc(psim_scene *sc, long n, psim_error *err)
{
    size_t b = (size_t)(n > 0 ? n : 1) * sizeof(double);
    sc->n = n;
    sc->source = NULL;
    sc->line = NULL;
    sc->id = NULL;
    sc->x = calloc(1, b);
    sc->y = calloc(1, b);
    sc->vx = calloc(1, b);
    sc->vy = calloc(1, b);
    if (!sc->x || !sc->y || !sc->vx || !sc->vy) {
        psim_scene_clear(sc);
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

void psim_scene_where_header(const psim_scene *sc, int k, char *buf, size_t size)
{
    if (size == 0)
        return;
    buf[0] = '\0';
    if (sc->source && k >= 0 && k < 4 && sc->header_line[k] > 0)
        snprintf(buf, size, "%s:%ld: ", sc->source, sc->header_line[k]);
}

void psim_scene_clear(psim_scene *sc)
{
    if (sc->id)   /* a part's numbers become its whole scene's */
        sc->n = sc->n_all;
    free(sc->x);
    free(sc->y);
    free(sc->vx);
    free(sc->vy);
    free(sc->source);
    free(sc->line);
    free(sc->id);
    psim_restart_free(&sc->restart);
    sc->x = sc->y = sc->vx = sc->vy = NULL;
    sc->source = NULL;
    sc->line = NULL;
    sc->id = NULL;
}

/* ---- a part of a scene: a byte range of its particle lines --------------- */

int psim_io_scene_read_head(const char *path, psim_restart_schema_fn schema, psim_scene *sc,
                            psim_scene_span *span, psim_error *err)
{
    memset(sc, 0, sizeof *sc);
    memset(span, 0, sizeof *span);
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {   /* (not opened: a FIFO would wait) */
        psim_error_set(err, "%s: not a regular file: over MPI ranks every rank reads its "
                            "own part of the scene", path);
        return -1;
    }
    FILE *f = fopen(path, "r");
    if (!f) {
        psim_error_set(err, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    reader rd = {.f = f, .name = path, .err = err, .size = -1, .cap = 4 * MAX_FIRST_LINE,
                 .max = MAX_LINE, .head_only = 1};
    int rc = -1;
    if (fstat(fileno(f), &st) || !S_ISREG(st.st_mode)) {
        psim_error_set(err, "%s: not a regular file: over MPI ranks every rank reads its "
                            "own part of the scene", path);
        goto done;
    }
    rd.size = span->size = (long long)st.st_size;
    if (read_restart_line(&rd, sc, schema, err) || read_header(&rd, sc, err) ||
        (!sc->restart.present && read_mode(&rd, sc)))
        goto done;
    if (ferror(f)) {
        psim_error_set(err, "%s: read error: %s", path, strerror(errno));
        goto done;
    }
    /* (a restart file without a model's own columns is particle lines as
     * any scene's; the order of its lines is not kept in parts) */
    span->whole = (sc->restart.present && sc->restart.ncols > 0) ||
                  sc->format == PSIM_SCENE_2019;
    /* the particle lines start with the line read_mode looked at */
    span->data = rd.pushed ? rd.mark : rd.consumed;
    span->line0 = rd.pushed ? rd.mark_line : rd.line;
    if (!(sc->source = strdup(path))) {
        psim_error_set(err, "%s: out of memory", path);
        goto done;
    }
    rc = 0;
done:
    free(rd.buf);
    free(rd.chunk);
    fclose(f);
    if (rc)
        psim_scene_clear(sc);
    return rc;
}

/* path opened at byte off; NULL with err set. */
static FILE *open_at(const char *path, long long off, psim_error *err)
{
    FILE *f = fopen(path, "r");
    if (f && fseeko(f, (off_t)off, SEEK_SET) == 0)
        return f;
    psim_error_set(err, "%s: cannot read: %s", path, strerror(errno));
    if (f)
        fclose(f);
    return NULL;
}

int psim_io_line_start(const char *path, long long data, long long off, long long *start,
                       psim_error *err)
{
    if (off <= data) {
        *start = data;
        return 0;
    }
    FILE *f = open_at(path, off - 1, err);
    if (!f)
        return -1;
    int c;
    long long at = off - 1;
    while ((c = getc(f)) != EOF && c != '\n')
        at++;
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        psim_error_set(err, "%s: read error: %s", path, strerror(errno));
        return -1;
    }
    *start = at + 1;   /* after the newline, or the end of the file */
    return 0;
}

int psim_io_count_lines(const char *path, long long a, long long b, long *lines,
                        psim_error *err)
{
    *lines = 0;
    if (a >= b)
        return 0;
    FILE *f = open_at(path, a, err);
    if (!f)
        return -1;
    size_t cap = (size_t)1 << 20;
    char *buf = malloc(cap);
    long long left = b - a;
    int rc = buf ? 0 : -1;
    while (rc == 0 && left > 0) {
        size_t want = (long long)cap < left ? cap : (size_t)left;
        size_t got = fread(buf, 1, want, f);
        for (const char *p = buf, *q; (q = memchr(p, '\n', (size_t)(buf + got - p)));
             p = q + 1)
            ++*lines;
        left -= (long long)got;
        if (got < want)
            rc = -1;
    }
    if (rc)
        psim_error_set(err, buf ? "%s: read error: %s" : "%s: out of memory%s", path,
                       buf ? strerror(errno) : "");
    free(buf);
    fclose(f);
    return rc;
}

/* The part's arrays for `lines` lines, a place for each (id -1: none). */
static int part_alloc(psim_scene *sc, long lines)
{
    size_t c = (size_t)(lines > 0 ? lines : 1);
    sc->x = malloc(c * sizeof *sc->x), sc->y = malloc(c * sizeof *sc->y);
    sc->vx = malloc(c * sizeof *sc->vx), sc->vy = malloc(c * sizeof *sc->vy);
    sc->id = malloc(c * sizeof *sc->id), sc->line = malloc(c * sizeof *sc->line);
    if (!sc->x || !sc->y || !sc->vx || !sc->vy || !sc->id || !sc->line)
        return -1;
    for (size_t i = 0; i < c; i++)
        sc->id[i] = -1;
    return 0;
}

/* The part's particles moved to its first places, in the file's order. */
static void part_compact(psim_scene *sc, long places)
{
    long k = 0;
    for (long i = 0; i < places; i++) {
        if (sc->id[i] < 0)
            continue;
        sc->x[k] = sc->x[i], sc->y[k] = sc->y[i], sc->vx[k] = sc->vx[i], sc->vy[k] = sc->vy[i];
        sc->id[k] = sc->id[i], sc->line[k] = sc->line[i];
        k++;
    }
    sc->n = k;
}

int psim_io_scene_read_range(const char *path, psim_scene *sc, long long a, long long b,
                             long line0, long lines, psim_range_read *out, psim_error *err)
{
    memset(out, 0, sizeof *out);
    sc->n = 0;
    const long places = lines + 1;   /* (a last line without its newline) */
    if (part_alloc(sc, places)) {
        psim_error_set(err, "%s: out of memory for %ld particles", path, places);
        out->bad = PSIM_RANGE_READ_ERROR;
        return -1;
    }
    if (a >= b)
        return 0;
    FILE *f = open_at(path, a, err);
    if (!f) {
        out->bad = PSIM_RANGE_READ_ERROR;
        return -1;
    }
    reader rd = {.f = f, .name = path, .err = err, .size = -1, .cap = block_bytes,
                 .max = MAX_LINE, .ranged = 1, .left = b - a, .line = line0};
    rd.buf = malloc(MAX_FIRST_LINE + 1);
    rd.chunk = malloc(rd.cap + PAD);
    if (!rd.buf || !rd.chunk) {
        psim_error_set(err, "%s: out of memory", path);
        out->bad = PSIM_RANGE_READ_ERROR;
        free(rd.buf), free(rd.chunk);
        fclose(f);
        return -1;
    }
    block_job j = {sc, NULL, NULL, line0};
    const int fast = !psim_io_slow();
    int rc = 0;
    while (rc == 0) {
        long long stop = -1;   /* the line by line reader: up to here (-1: one line) */
        if (fast && !rd.pushed) {
            if (!rd.eof && rd.end - rd.pos < rd.cap / 2)
                refill(&rd);
            const char *base = rd.chunk + rd.pos, *lim = rd.chunk + rd.end;
            const char *cut = rd.eof ? lim : memrchr(base, '\n', (size_t)(lim - base));
            if (cut && !rd.eof)
                cut++;
            if (cut && cut > base) {
                long nl = 0, count = 0;
                j.lim = lim;
                if (parse_block(&rd, &j, base, cut, &nl, &count) == 0) {
                    rd.pos += (size_t)(cut - base);
                    rd.consumed += cut - base;
                    rd.line += nl;
                    continue;
                }
                stop = rd.consumed + (cut - base);
            }
        }
        do {
            const char *s = next_line(&rd);
            if (!s) {
                if (rd.failed)   /* a line no scene has (read_line said) */
                    out->bad = PSIM_RANGE_NOT_TEXT, out->line = rd.line + 1, rc = -1;
                else
                    rc = 1;   /* the range's end */
                break;
            }
            long id;
            double v[4];
            if (parse_particle(&rd, NULL, sc->n_all, s, &id, v, NULL, err)) {
                out->bad = PSIM_RANGE_NOT_PARTICLE, out->line = rd.line, rc = -1;
                break;
            }
            size_t at = (size_t)(rd.line - line0 - 1);
            sc->x[at] = v[0], sc->y[at] = v[1], sc->vx[at] = v[2], sc->vy[at] = v[3];
            sc->id[at] = (int32_t)id, sc->line[at] = rd.line;
        } while (rd.consumed < stop);
    }
    if (rc >= 0 && ferror(f)) {
        psim_error_set(err, "%s: read error: %s", path, strerror(errno));
        out->bad = PSIM_RANGE_READ_ERROR, rc = -1;
    }
    /* the particles before the bad line (those after it, read in its
     * block, dropped) */
    part_compact(sc, rc < 0 && out->line ? out->line - line0 - 1 : rd.line - line0);
    out->lines = rd.line - line0;
    free(rd.buf);
    free(rd.chunk);
    fclose(f);
    return rc < 0 ? -1 : 0;
}
