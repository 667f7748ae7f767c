/* The public API as a program sees it (include/psim/psim.h alone): the
 * version, and the scene handle: made, set value by value and from
 * arrays, each value held to a scene file's rules, read back, run, taken
 * by psim_create_taking, generated anew. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "psim/psim.h"

#define HAS(err, text) (strstr((err).msg, (text)) != NULL)

/* The state after all the scene's steps on 2 threads (discrete model). */
static int run(const psim_scene *sc, double *x, double *y, double *vx, double *vy)
{
    psim_error err = {{0}, 0};
    psim_config cfg;
    psim_config_default(&cfg);
    cfg.threads = 2;
    psim_sim *s = psim_create(sc, &cfg, &err);
    if (!s) {
        fprintf(stderr, "psim_create: %s\n", err.msg);
        return -1;
    }
    int rc = 0;
    for (long k = 0; k < psim_scene_steps(sc) && rc == 0; k++)
        rc = psim_step(s, &err);
    psim_get_state(s, x, y, vx, vy);
    psim_destroy(s);
    return rc;
}

static void version(void)
{
    char text[64];
    snprintf(text, sizeof text, "%d.%d.%d", PSIM_VERSION_MAJOR, PSIM_VERSION_MINOR,
             PSIM_VERSION_PATCH);
    CHECK_MSG(strcmp(text, PSIM_VERSION) == 0, "%s", text);
    CHECK_MSG(strcmp(psim_version(), PSIM_VERSION) == 0, "%s", psim_version());
    /* this program links no jemalloc: the library keeps the C library's */
    CHECK_MSG(strcmp(psim_allocator(), "libc") == 0, "%s", psim_allocator());
}

static void box(void)
{
    psim_error err = {{0}, 0};
    psim_scene *sc = psim_scene_new();
    CHECK(sc != NULL);
    CHECK(psim_scene_count(sc) == 0 && psim_scene_side(sc) == 0 && psim_scene_steps(sc) == 0);
    CHECK(psim_scene_get_format(sc) == PSIM_SCENE_2024);
    CHECK(psim_scene_get_state(sc, NULL, NULL, NULL, NULL) == 0);
    CHECK(psim_scene_set_box(sc, 3, 10, 1, 4, &err) == 0);
    /* each refused, the scene as it was */
    CHECK(psim_scene_set_box(sc, -1, 10, 1, 4, &err) == -1 && HAS(err, "particle count N"));
    CHECK(psim_scene_set_box(sc, PSIM_MAX_PARTICLES + 1, 10, 1, 4, &err) == -1 &&
          HAS(err, "particle count N"));
    CHECK(psim_scene_set_box(sc, 3, 0, 1, 4, &err) == -1 && HAS(err, "box side L"));
    CHECK(psim_scene_set_box(sc, 3, INFINITY, 1, 4, &err) == -1 && HAS(err, "box side L"));
    CHECK(psim_scene_set_box(sc, 3, 10, -1, 4, &err) == -1 && HAS(err, "radius r"));
    CHECK(psim_scene_set_box(sc, 3, 10, NAN, 4, &err) == -1 && HAS(err, "radius r"));
    CHECK(psim_scene_set_box(sc, 3, 10, 5, 4, &err) == -1 && HAS(err, "does not fit"));
    CHECK(psim_scene_set_box(sc, 3, 10, 1, -1, &err) == -1 && HAS(err, "step count S"));
    CHECK(psim_scene_set_box(sc, 3, 10, 1, PSIM_MAX_STEPS + 1, &err) == -1 &&
          HAS(err, "step count S"));
    CHECK(psim_scene_set_steps(sc, -2, &err) == -1 && HAS(err, "step count S"));
    CHECK(psim_scene_count(sc) == 3 && psim_scene_side(sc) == 10 && psim_scene_radius(sc) == 1 &&
          psim_scene_steps(sc) == 4);
    CHECK(psim_scene_set_steps(sc, 6, &err) == 0 && psim_scene_steps(sc) == 6);

    /* disk by disk */
    double x, y, vx, vy;
    CHECK(psim_scene_get_particle(sc, 2, &x, &y, &vx, &vy) == 0 && x == 0 && vy == 0);
    CHECK(psim_scene_set_particle(sc, 3, 1, 1, 0, 0, &err) == -1 && HAS(err, "out of range"));
    CHECK(psim_scene_set_particle(sc, -1, 1, 1, 0, 0, &err) == -1 && HAS(err, "out of range"));
    CHECK(psim_scene_set_particle(sc, 1, 2, 3, 0.5, -0.25, &err) == 0);
    CHECK(psim_scene_set_particle(sc, 1, 2, 3, NAN, 1, &err) == -1 &&
          HAS(err, "particle 1: vx is not a finite number"));
    CHECK(psim_scene_get_particle(sc, 1, &x, &y, &vx, &vy) == 0 && x == 2 && y == 3 &&
          vx == 0.5 && vy == -0.25);
    CHECK(psim_scene_get_particle(sc, 3, &x, NULL, NULL, NULL) == -1);

    /* from arrays: all checked before any is set */
    double ax[3] = {2, 5, 8}, ay[3] = {2, 5, 3}, avx[3] = {1, -0.5, 0.2},
           avy[3] = {0.5, 1, INFINITY};
    CHECK(psim_scene_set_state(sc, ax, ay, avx, avy, &err) == -1 &&
          HAS(err, "particle 2: vy is not a finite number"));
    CHECK(psim_scene_get_particle(sc, 0, &x, NULL, NULL, NULL) == 0 && x == 0);
    avy[2] = -1;
    CHECK(psim_scene_set_state(sc, ax, ay, avx, avy, &err) == 0);
    double bx[3] = {7, 7, 7};
    CHECK(psim_scene_set_state(sc, NULL, NULL, NULL, bx, &err) == 0);   /* vy alone */
    double gx[3], gvy[3];
    CHECK(psim_scene_get_state(sc, gx, NULL, NULL, gvy) == 0);
    CHECK(memcmp(gx, ax, sizeof gx) == 0 && memcmp(gvy, bx, sizeof gvy) == 0);
    CHECK(psim_scene_set_state(sc, NULL, NULL, NULL, avy, &err) == 0);
    psim_scene_free(sc);
    psim_scene_free(NULL);
}

/* A scene made by hand runs as the same scene written and read back. */
static void made_and_read(void)
{
    psim_error err = {{0}, 0};
    psim_gen_params p = {.n = 400, .L = 60, .r = 0.5, .steps = 6, .vmin = -1, .vmax = 1,
                         .seed = 9, .place = PSIM_PLACE_NONOVERLAP};
    psim_scene *gen = psim_scene_new();
    CHECK(psim_scene_generate(&p, gen, &err) == 0);
    const long n = psim_scene_count(gen);
    CHECK(n == 400);
    double *s[4], *a[4], *b[4];
    for (int k = 0; k < 4; k++) {
        s[k] = malloc((size_t)n * sizeof(double));
        a[k] = malloc((size_t)n * sizeof(double));
        b[k] = malloc((size_t)n * sizeof(double));
    }
    CHECK(psim_scene_get_state(gen, s[0], s[1], s[2], s[3]) == 0);
    psim_scene *made = psim_scene_new();
    CHECK(psim_scene_set_box(made, n, 60, 0.5, 6, &err) == 0);
    CHECK(psim_scene_set_state(made, s[0], s[1], s[2], s[3], &err) == 0);
    CHECK(run(made, a[0], a[1], a[2], a[3]) == 0);

    char path[] = "/tmp/psim_test_api_XXXXXX";
    int fd = mkstemp(path);
    FILE *f = fd >= 0 ? fdopen(fd, "w") : NULL;
    CHECK(f != NULL);
    if (f) {
        CHECK(psim_scene_write(f, made) == 0);
        fclose(f);
        psim_scene *read = psim_scene_load(path, &err);
        CHECK_MSG(read != NULL, "%s", err.msg);
        if (read) {
            CHECK(psim_scene_count(read) == n && psim_scene_steps(read) == 6);
            CHECK(run(read, b[0], b[1], b[2], b[3]) == 0);
            for (int k = 0; k < 4; k++)
                CHECK(memcmp(a[k], b[k], (size_t)n * sizeof(double)) == 0);
            /* and the run moved the disks */
            CHECK(memcmp(a[0], s[0], (size_t)n * sizeof(double)) != 0);
            psim_scene_free(read);
        }
        remove(path);
    }
    CHECK(psim_scene_load(path, &err) == NULL && HAS(err, path) && HAS(err, "cannot open"));

    /* a scene whose disks the simulation took */
    psim_sim *sim = psim_create_taking(made, NULL, &err);
    CHECK_MSG(sim != NULL, "%s", err.msg);
    psim_destroy(sim);
    CHECK(psim_scene_count(made) == n && psim_scene_steps(made) == 6);
    CHECK(psim_scene_get_state(made, a[0], NULL, NULL, NULL) == -1);
    CHECK(psim_scene_get_particle(made, 0, a[0], NULL, NULL, NULL) == -1);
    CHECK(psim_scene_set_particle(made, 0, 1, 1, 0, 0, &err) == -1 && HAS(err, "taken"));
    CHECK(psim_create(made, NULL, &err) == NULL && HAS(err, "taken"));
    CHECK(psim_scene_generate_2019(made, 3210, &err) == -1 && HAS(err, "taken"));
    f = fopen("/dev/null", "w");
    CHECK(f && psim_scene_write(f, made) == -1);
    if (f)
        fclose(f);
    /* given disks again */
    CHECK(psim_scene_set_box(made, 5, 60, 0.5, 1, &err) == 0);
    CHECK(psim_scene_generate_2019(made, 3210, &err) == 0);
    CHECK(psim_scene_get_particle(made, 4, a[0], NULL, NULL, NULL) == 0 && a[0][0] >= 0.5);

    /* generated anew: the old contents go; a refusal leaves them */
    p.n = 7;
    CHECK(psim_scene_generate(&p, made, &err) == 0 && psim_scene_count(made) == 7);
    p.r = -1;
    CHECK(psim_scene_generate(&p, made, &err) == -1 && psim_scene_count(made) == 7);
    CHECK(psim_generate_scene("force", 50, 3, made, &err) == 0 && psim_scene_count(made) == 50 &&
          psim_scene_get_format(made) == PSIM_SCENE_CS267);
    CHECK(psim_generate_scene("force", -5, 3, made, &err) == -1 && psim_scene_count(made) == 50);
    CHECK(psim_generate_scene("discrete", 5, 3, made, &err) == -1 &&
          HAS(err, "no initialisation") && psim_scene_count(made) == 50);

    for (int k = 0; k < 4; k++)
        free(s[k]), free(a[k]), free(b[k]);
    psim_scene_free(made);
    psim_scene_free(gen);
}

int main(void)
{
    version();
    box();
    made_and_read();
    return check_done();
}
