/* Scene reading (strict, with file:line errors), writing and generating. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <omp.h>

#include "check.h"
#include "io/fmt.h"
#include "io/scene.h"
#include "io/scene_read.h"

static int read_text(const char *text, psim_scene *sc, psim_error *err)
{
    FILE *f = fmemopen((void *)text, strlen(text), "r");
    int rc = psim_scene_read_stream(f, "t.in", sc, err);
    fclose(f);
    return rc;
}

static void same_both_ways(const char *text, size_t len, const char *what);

static void expect_error(const char *text, const char *where, const char *what)
{
    same_both_ways(text, strlen(text), text);
    psim_scene sc = {0};
    psim_error err = {{0}, 0};
    CHECK_MSG(read_text(text, &sc, &err) != 0, "accepted: %s", text);
    CHECK_MSG(strstr(err.msg, where) != NULL, "'%s' lacks '%s'", err.msg, where);
    CHECK_MSG(strstr(err.msg, what) != NULL, "'%s' lacks '%s'", err.msg, what);
    CHECK(strchr(err.msg, '\n') == NULL);
}

static void test_read_ok(void)
{
    psim_scene sc = {0};
    psim_error err = {{0}, 0};
    CHECK(read_text("2\n10\n1\n5\n1 2 3 -1 0.5\n0 4.5 6 0 -0\n\n", &sc, &err) == 0);
    CHECK(sc.n == 2 && sc.L == 10 && sc.r == 1 && sc.steps == 5);
    /* stored by id, whatever the line order */
    CHECK(sc.x[1] == 2 && sc.y[1] == 3 && sc.vx[1] == -1 && sc.vy[1] == 0.5);
    CHECK(sc.x[0] == 4.5 && sc.y[0] == 6);
    psim_scene_clear(&sc);
    CHECK(read_text("0\n10\n1\n5\n", &sc, &err) == 0);
    CHECK(sc.n == 0);
    psim_scene_clear(&sc);
}

static void test_read_errors(void)
{
    expect_error("", "t.in:1:", "particle count");
    expect_error("x\n", "t.in:1:", "particle count");
    expect_error("-1\n10\n1\n5\n", "t.in:1:", "between 0");
    expect_error("1\n0\n1\n5\n", "t.in:2:", "L must be positive");
    expect_error("1\n10\n-1\n5\n", "t.in:3:", "r must be positive");
    expect_error("1\n10\n5\n1\n", "t.in:3:", "does not fit");
    expect_error("1\n10\n1\n-5\n", "t.in:4:", "must be between 0 and 1000000000");
    expect_error("1\n10\n1\n2.5\n", "t.in:4:", "integer");
    expect_error("2\n10\n1\n5\n0 1 1 0 0\n", "t.in:6:", "expected 2 particle lines, found 1");
    expect_error("1\n10\n1\n5\n0 1 1 0 0\n1 2 2 0 0\n", "t.in:6:", "more particle lines");
    expect_error("1\n10\n1\n5\n0 1 nan 0 0\n", "t.in:5:", "y is not a finite");
    expect_error("1\n10\n1\n5\n0 1 1 inf 0\n", "t.in:5:", "vx is not a finite");
    expect_error("1\n10\n1\n5\n0 1 1 0\n", "t.in:5:", "vy");
    expect_error("1\n10\n1\n5\n0 1 1 0 0 7\n", "t.in:5:", "unexpected text");
    expect_error("2\n10\n1\n5\n0 1 1 0 0\n0 2 2 0 0\n", "t.in:6:", "appears twice");
    expect_error("1\n10\n1\n5\n3 1 1 0 0\n", "t.in:5:", "out of range");
    expect_error("1\n10\n1\n5\nhello\n", "t.in:5:", "particle line");
}

static void test_generate_roundtrip(void)
{
    psim_place places[] = {PSIM_PLACE_UNIFORM, PSIM_PLACE_NONOVERLAP, PSIM_PLACE_LATTICE};
    for (int k = 0; k < 3; k++) {
        psim_gen_params p = {.n = 500, .L = 100, .r = 1.5, .steps = 7, .vmin = 2,
                             .vmax = 5, .seed = 42, .place = places[k]};
        psim_scene a = {0}, b = {0};
        psim_error err = {{0}, 0};
        CHECK(psim_scene_generate(&p, &a, &err) == 0);
        for (long i = 0; i < a.n; i++) {
            CHECK(a.vx[i] >= 2 && a.vx[i] <= 5 && a.vy[i] >= 2 && a.vy[i] <= 5);
            CHECK(a.x[i] >= 0 && a.x[i] <= 100 && a.y[i] >= 0 && a.y[i] <= 100);
        }
        if (p.place != PSIM_PLACE_UNIFORM)
            for (long i = 0; i < a.n; i++)
                for (long j = i + 1; j < a.n; j++) {
                    double dx = a.x[i] - a.x[j], dy = a.y[i] - a.y[j];
                    CHECK(dx * dx + dy * dy > 4 * p.r * p.r);
                }
        CHECK(fabs(psim_scene_density(&a) - 500 * M_PI * 2.25 / 1e4) < 1e-12);
        char *text = NULL;
        size_t len = 0;
        FILE *f = open_memstream(&text, &len);
        CHECK(psim_scene_write(f, &a) == 0);
        fclose(f);
        CHECK(read_text(text, &b, &err) == 0);
        CHECK(b.n == a.n && b.L == a.L && b.r == a.r && b.steps == a.steps);
        CHECK(memcmp(a.x, b.x, (size_t)a.n * sizeof(double)) == 0);
        CHECK(memcmp(a.vy, b.vy, (size_t)a.n * sizeof(double)) == 0);
        free(text);
        psim_scene_clear(&a);
        psim_scene_clear(&b);
    }
    /* too dense for random placement: a clear error, not a hang */
    psim_gen_params p = {.n = 2000, .L = 100, .r = 1.5, .steps = 1, .vmin = 0,
                         .vmax = 1, .seed = 1, .place = PSIM_PLACE_NONOVERLAP};
    psim_scene a = {0};
    psim_error err = {{0}, 0};
    CHECK(psim_scene_generate(&p, &a, &err) != 0);
    CHECK(strstr(err.msg, "cannot place") != NULL);
}

/* ---- the block reader against the line-by-line reader ---------------- */

static int read_mem(const char *text, size_t len, psim_scene *sc, psim_error *err)
{
    FILE *f = fmemopen((void *)text, len, "r");
    int rc = psim_scene_read_stream(f, "t.in", sc, err);
    fclose(f);
    return rc;
}

static int same_scene(const psim_scene *a, const psim_scene *b)
{
    size_t d = (size_t)a->n * sizeof(double);
    int cols = a->restart.ncols == b->restart.ncols;
    for (int c = 0; cols && c < a->restart.ncols; c++)
        cols = memcmp(a->restart.col[c], b->restart.col[c], d) == 0;
    return cols && a->n == b->n && a->L == b->L && a->r == b->r && a->steps == b->steps &&
           a->format == b->format && a->print == b->print && a->generated == b->generated &&
           memcmp(a->x, b->x, d) == 0 && memcmp(a->y, b->y, d) == 0 &&
           memcmp(a->vx, b->vx, d) == 0 && memcmp(a->vy, b->vy, d) == 0 &&
           memcmp(a->line, b->line, (size_t)a->n * sizeof(long)) == 0;
}

static long both_ways_runs, parts_runs;

/* A scene read whole (ref), read again as k parts of its file's particle
 * lines (src/io's part reader, as the ranks of an MPI run read it): every
 * particle of a part is the whole scene's, with its line, in the file's
 * order, and the parts hold them all. */
static void same_in_parts(const char *text, size_t len, const psim_scene *ref, const char *what)
{
    if (len && text[0] == '#')   /* a restart file is read whole */
        return;
    char path[] = "/tmp/psim-parts-XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    FILE *f = fdopen(fd, "w");
    CHECK(fwrite(text, 1, len, f) == len);
    fclose(f);
    psim_scene head = {0};
    psim_scene_span sp;
    psim_error err = {{0}, 0};
    CHECK_MSG(psim_io_scene_read_head(path, NULL, &head, &sp, &err) == 0, "%s: %s", what, err.msg);
    if (sp.whole) {   /* a 2019 scene */
        psim_scene_clear(&head);
        unlink(path);
        return;
    }
    CHECK(head.n == ref->n && head.L == ref->L && head.r == ref->r);
    for (int k = 1; k <= 5; k += 2) {
        long got = 0, line0 = sp.line0;
        long long a = sp.data;
        for (int q = 0; q < k; q++) {
            long long b = sp.size;
            if (q + 1 < k)
                CHECK(psim_io_line_start(path, sp.data,
                                         sp.data + (sp.size - sp.data) * (q + 1) / k, &b, &err) == 0);
            long nl;
            CHECK(psim_io_count_lines(path, a, b, &nl, &err) == 0);
            psim_scene part = {0};
            part.n_all = head.n;
            psim_range_read rr;
            int rc = psim_io_scene_read_range(path, &part, a, b, line0, nl, &rr, &err);
            CHECK_MSG(rc == 0, "%s: part %d of %d: %s", what, q, k, err.msg);
            for (long i = 0; i < part.n; i++) {
                long id = part.id[i];
                CHECK_MSG(part.x[i] == ref->x[id] && part.y[i] == ref->y[id] &&
                              part.vx[i] == ref->vx[id] && part.vy[i] == ref->vy[id] &&
                              part.line[i] == ref->line[id],
                          "%s: part %d of %d: particle %ld", what, q, k, id);
                CHECK(i == 0 || part.line[i] > part.line[i - 1]);
            }
            got += part.n;
            line0 += rr.lines;
            a = b;
            psim_scene_clear(&part);
            parts_runs++;
        }
        CHECK_MSG(got == ref->n, "%s: %d parts hold %ld of %ld particles", what, k, got, ref->n);
    }
    psim_scene_clear(&head);
    unlink(path);
}

/* The same scene, or the same error message, from the block reader (blocks
 * of 16 kB and more, pieces from 512 bytes, 1 to 3 threads) as from the
 * line-by-line reader (PSIM_SLOW_IO=1). */
static void same_both_ways(const char *text, size_t len, const char *what)
{
    psim_scene ref = {0};
    psim_error eref = {{0}, 0};
    setenv("PSIM_SLOW_IO", "1", 1);
    int rref = read_mem(text, len, &ref, &eref);
    unsetenv("PSIM_SLOW_IO");
    static const size_t blocks[][2] = {{0, 0}, {16384, 512}, {20011, 4096}, {65536, 1}};
    for (size_t b = 0; b < sizeof blocks / sizeof blocks[0]; b++)
        for (int t = 1; t <= 3; t++) {
            omp_set_num_threads(t);
            psim_io_set_blocks(blocks[b][0], blocks[b][1]);
            psim_scene sc = {0};
            psim_error e = {{0}, 0};
            int r = read_mem(text, len, &sc, &e);
            both_ways_runs++;
            CHECK_MSG(r == rref, "%s: rc %d, line by line %d (%s)", what, r, rref,
                      r ? e.msg : eref.msg);
            if (r == 0 && rref == 0) {
                CHECK_MSG(same_scene(&sc, &ref), "%s: another scene (block %zu, %d threads)",
                          what, blocks[b][0], t);
                psim_scene_clear(&sc);
            } else if (r && rref) {
                CHECK_MSG(strcmp(e.msg, eref.msg) == 0, "%s: '%s', line by line '%s'", what,
                          e.msg, eref.msg);
            } else if (r == 0) {
                psim_scene_clear(&sc);
            }
        }
    if (rref == 0)
        for (size_t b = 0; b < sizeof blocks / sizeof blocks[0]; b++) {
            psim_io_set_blocks(blocks[b][0], blocks[b][1]);
            same_in_parts(text, len, &ref, what);
        }
    psim_io_set_blocks(0, 0);
    omp_set_num_threads(2);
    if (rref == 0)
        psim_scene_clear(&ref);
}

/* text lines of a scene (header and particle lines) */
typedef struct lines {
    char **l;
    long n;
} lines;

static lines split_lines(char *text)
{
    lines L = {NULL, 0};
    long cap = 0;
    for (char *p = text; *p;) {
        char *nl = strchr(p, '\n');
        if (L.n == cap)
            L.l = realloc(L.l, (size_t)(cap = cap ? 2 * cap : 1024) * sizeof *L.l);
        L.l[L.n++] = strndup(p, nl ? (size_t)(nl - p) : strlen(p));
        p = nl ? nl + 1 : p + strlen(p);
    }
    return L;
}

/* lines joined with `eol`, without it after the last one if `last` is 0;
 * *len is the length (the text may hold NUL bytes) */
static char *join(const lines *L, const char *eol, int last, size_t *len)
{
    size_t cap = 16, n = 0;
    for (long i = 0; i < L->n; i++)
        cap += strlen(L->l[i]) + 8;
    char *t = malloc(cap);
    for (long i = 0; i < L->n; i++) {
        size_t k = strlen(L->l[i]);
        memcpy(t + n, L->l[i], k);
        n += k;
        if (i + 1 < L->n || last) {
            memcpy(t + n, eol, strlen(eol));
            n += strlen(eol);
        }
    }
    t[n] = '\0';
    *len = n;
    return t;
}

static void free_lines(lines *L)
{
    for (long i = 0; i < L->n; i++)
        free(L->l[i]);
    free(L->l);
}

/* one line replaced (a copy of L) */
static void with_line(const lines *L, long at, const char *line, const char *what)
{
    lines M = {malloc((size_t)L->n * sizeof(char *)), L->n};
    for (long i = 0; i < L->n; i++)
        M.l[i] = (char *)(i == at ? line : L->l[i]);
    size_t len;
    char *t = join(&M, "\n", 1, &len);
    char label[160];
    snprintf(label, sizeof label, "%s at line %ld", what, at + 1);
    same_both_ways(t, len, label);
    free(t);
    free(M.l);
}

static void test_block_reader(void)
{
    psim_gen_params p = {.n = 3000, .L = 300, .r = 1, .steps = 5, .vmin = -1, .vmax = 1,
                         .seed = 7, .place = PSIM_PLACE_UNIFORM};
    psim_scene a = {0};
    psim_error err = {{0}, 0};
    CHECK(psim_scene_generate(&p, &a, &err) == 0);
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    CHECK(psim_scene_write(f, &a) == 0);
    fclose(f);
    psim_scene_clear(&a);
    same_both_ways(text, len, "a generated scene");
    lines L = split_lines(text);
    size_t tl;
    char *t;
    /* other line ends, separators, blank lines, a last line without newline */
    t = join(&L, "\r\n", 1, &tl), same_both_ways(t, tl, "CR LF"), free(t);
    t = join(&L, "\n", 0, &tl), same_both_ways(t, tl, "no last newline"), free(t);
    t = join(&L, "\r", 0, &tl), same_both_ways(t, tl, "CR only"), free(t);
    t = join(&L, "\n \t\n", 1, &tl), same_both_ways(t, tl, "blank lines"), free(t);
    t = join(&L, " \t\r\n\n", 0, &tl), same_both_ways(t, tl, "trailing space"), free(t);
    /* reversed particle lines (ids in any order) */
    lines R = {malloc((size_t)L.n * sizeof(char *)), L.n};
    for (long i = 0; i < L.n; i++)
        R.l[i] = L.l[i < 4 ? i : L.n - 1 - (i - 4)];
    t = join(&R, "\n", 1, &tl), same_both_ways(t, tl, "reversed"), free(t);
    free(R.l);
    /* one line changed, at the first particle line, in the middle, near
     * the end and at the last */
    const long at[] = {4, 5, 1100, L.n / 2, L.n - 2, L.n - 1};
    static const char *bad[] = {
        "0 1 1 0 0",                 /* a duplicate of id 0 (or the same line) */
        "2999 1 1 0 0",              /* a duplicate of the last id */
        "3000 1 1 0 0", "-1 1 1 0 0", "+5 1 1 0 0", "0005 1 1 0 0", "5 1.2.3 1 0 0",
        "5 nan 1 0 0", "5 1 inf 0 0", "5 1 1 1e999 0", "5 0x1p3 1 0 0", "5 1 1 0",
        "5 1 1 0 0 0", "5\t1\t1\t0\t0", "  5  1 1 0 0  ", "5 1\r1 0 0", "5 1 1 0 0\v",
        "5 1e-30 1e+2 .5 5.", "5 1.00000000000000000000000001 1 0 0",
        "5 123456789012345678901234 1 0 0", "x", "", "5 1 1 0 -", "5 1e 1 0 0",
        "99999999999999999999 1 1 0 0"};
    for (size_t k = 0; k < sizeof at / sizeof at[0]; k++)
        for (size_t b = 0; b < sizeof bad / sizeof bad[0]; b++)
            with_line(&L, at[k], bad[b], bad[b]);
    /* a line longer than 4096 bytes, a NUL byte */
    char *longl = malloc(5001);
    memset(longl, ' ', 5000);
    longl[0] = '7', longl[4999] = '0', longl[5000] = '\0';
    with_line(&L, 2000, longl, "a long line");
    free(longl);
    t = join(&L, "\n", 1, &tl);
    t[tl / 2] = '\0';
    same_both_ways(t, tl, "a NUL byte");
    free(t);
    /* fewer and more lines than N */
    L.n--;
    t = join(&L, "\n", 1, &tl), same_both_ways(t, tl, "a line short"), free(t);
    L.n++;
    lines M = {malloc((size_t)(L.n + 1) * sizeof(char *)), L.n + 1};
    memcpy(M.l, L.l, (size_t)L.n * sizeof(char *));
    M.l[L.n] = "3000 1 1 0 0";
    t = join(&M, "\n", 1, &tl), same_both_ways(t, tl, "a line more"), free(t);
    free(M.l);
    /* the 2019 format with its particle lines */
    lines P = {malloc((size_t)(L.n + 1) * sizeof(char *)), L.n + 1};
    memcpy(P.l, L.l, 4 * sizeof(char *));
    P.l[4] = "print";
    memcpy(P.l + 5, L.l + 4, (size_t)(L.n - 4) * sizeof(char *));
    t = join(&P, "\n", 1, &tl), same_both_ways(t, tl, "2019 print"), free(t);
    free(P.l);
    free_lines(&L);
    free(text);
}

/* A restart file's own columns, read as their model declares them: the
 * same values or the same error both ways; integer columns refuse what is
 * not a whole number in range, and say where. */
static void test_restart_columns(void)
{
    lines L = {malloc(2005 * sizeof(char *)), 2005};
    L.l[0] = strdup("#psim restart 1 model=ccd step=3 columns=pair_collisions,wall_collisions");
    L.l[1] = strdup("2000"), L.l[2] = strdup("300"), L.l[3] = strdup("1"), L.l[4] = strdup("5");
    for (long i = 0; i < 2000; i++) {
        char b[96];
        snprintf(b, sizeof b, "%ld %.17g 7.5 -0.25 0.5 %ld %ld", i, 1.5 + 0.14 * (double)i,
                 i * 1000003 % 9007199254740993, i % 3);
        L.l[5 + i] = strdup(b);
    }
    size_t tl;
    char *t = join(&L, "\n", 1, &tl);
    same_both_ways(t, tl, "a restart file with columns");
    psim_scene sc = {0};
    psim_error err = {{0}, 0};
    CHECK(read_mem(t, tl, &sc, &err) == 0);
    CHECK(sc.restart.ncols == 2 && sc.restart.col[0][1999] == 1999.0 * 1000003 &&
          sc.restart.col[1][1999] == 1);
    psim_scene_clear(&sc);
    free(t);
    static const char *ok[] = {"5 1 1 0 0 9007199254740992 0", "5 1 1 0 0 +7 007",
                               "5 1 1 0 0 -0 0"};
    static const char *bad[] = {"5 1 1 0 0 2.5 0", "5 1 1 0 0 1e23 0", "5 1 1 0 0 -1 0",
                                "5 1 1 0 0 9007199254740993 0", "5 1 1 0 0 x 0",
                                "5 1 1 0 0 0", "5 1 1 0 0 0 0 0", "5 1 1 0 0 1.0 0",
                                "5 1 1 0 0 0 99999999999999999999"};
    const long at[] = {5, 2004};
    for (size_t k = 0; k < sizeof at / sizeof at[0]; k++) {
        for (size_t b = 0; b < sizeof ok / sizeof ok[0]; b++)
            with_line(&L, at[k], ok[b], ok[b]);
        for (size_t b = 0; b < sizeof bad / sizeof bad[0]; b++)
            with_line(&L, at[k], bad[b], bad[b]);
    }
    lines M = L;
    M.l = malloc((size_t)L.n * sizeof(char *));
    memcpy(M.l, L.l, (size_t)L.n * sizeof(char *));
    M.l[1505] = "1500 1 1 0 0 2.5 0";
    t = join(&M, "\n", 1, &tl);
    CHECK(read_mem(t, tl, &sc, &err) != 0);
    CHECK_MSG(strstr(err.msg, "t.in:1506: particle 1500: pair_collisions (field 6) must be a "
                              "whole number in 0..9007199254740992, got '2.5'") != NULL,
              "%s", err.msg);
    free(t);
    free(M.l);
    free_lines(&L);
    expect_error("#psim restart 1 model=ccd step=3 columns=pair_collisions\n1\n10\n1\n5\n"
                 "0 1 1 0 0 0\n", "t.in:1:", "missing column 'wall_collisions'");
    expect_error("#psim restart 1 model=ccd step=3 columns=pair_collisions,wall_collisions,x\n"
                 "1\n10\n1\n5\n0 1 1 0 0 0 0 0\n", "t.in:1:", "unknown column 'x'");
    expect_error("\n#psim restart 1 model=ccd step=3 columns=pair_collisions,wall_collisions\n"
                 "1\n10\n1\n5\n0 1 1 0 0 0 -3\n", "t.in:7:", "wall_collisions (field 7)");
    expect_error("\n\n#psim restart 1 model=discrete step=3 options=settle=0\n1\n10\n1\n5\n"
                 "0 1 1 0 0\n", "t.in:3:", "option settle");
}

int main(void)
{
    test_read_ok();
    test_read_errors();
    test_generate_roundtrip();
    test_block_reader();
    test_restart_columns();
    printf("%ld reads compared with the line-by-line reader\n", both_ways_runs);
    printf("%ld scene parts compared with whole scenes\n", parts_runs);
    CHECK(parts_runs > 0);
    return check_done();
}
