/* Scene reading (strict, with file:line errors), writing and generating. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "psim/psim.h"

static int read_text(const char *text, psim_scene *sc, psim_error *err)
{
    FILE *f = fmemopen((void *)text, strlen(text), "r");
    int rc = psim_scene_read_stream(f, "t.in", sc, err);
    fclose(f);
    return rc;
}

static void expect_error(const char *text, const char *where, const char *what)
{
    psim_scene sc;
    psim_error err = {{0}, 0};
    CHECK_MSG(read_text(text, &sc, &err) != 0, "accepted: %s", text);
    CHECK_MSG(strstr(err.msg, where) != NULL, "'%s' lacks '%s'", err.msg, where);
    CHECK_MSG(strstr(err.msg, what) != NULL, "'%s' lacks '%s'", err.msg, what);
    CHECK(strchr(err.msg, '\n') == NULL);
}

static void test_read_ok(void)
{
    psim_scene sc;
    psim_error err = {{0}, 0};
    CHECK(read_text("2\n10\n1\n5\n1 2 3 -1 0.5\n0 4.5 6 0 -0\n\n", &sc, &err) == 0);
    CHECK(sc.n == 2 && sc.L == 10 && sc.r == 1 && sc.steps == 5);
    /* stored by id, whatever the line order */
    CHECK(sc.x[1] == 2 && sc.y[1] == 3 && sc.vx[1] == -1 && sc.vy[1] == 0.5);
    CHECK(sc.x[0] == 4.5 && sc.y[0] == 6);
    psim_scene_free(&sc);
    CHECK(read_text("0\n10\n1\n5\n", &sc, &err) == 0);
    CHECK(sc.n == 0);
    psim_scene_free(&sc);
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
        psim_scene a, b;
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
        psim_scene_free(&a);
        psim_scene_free(&b);
    }
    /* too dense for random placement: a clear error, not a hang */
    psim_gen_params p = {.n = 2000, .L = 100, .r = 1.5, .steps = 1, .vmin = 0,
                         .vmax = 1, .seed = 1, .place = PSIM_PLACE_NONOVERLAP};
    psim_scene a;
    psim_error err = {{0}, 0};
    CHECK(psim_scene_generate(&p, &a, &err) != 0);
    CHECK(strstr(err.msg, "cannot place") != NULL);
}

int main(void)
{
    test_read_ok();
    test_read_errors();
    test_generate_roundtrip();
    return check_done();
}
