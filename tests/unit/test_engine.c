/* Whole steps through the library: after every step no overlapping pair
 * approaches and no wall collision is left (checked by brute force, apart
 * from the model's own checker), and the result is the same for any thread
 * count and for any number of tiles' worth of threads. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "models/discrete/collide.h"
#include "io/scene.h"

static void brute_force_quiet(const psim_sim *s, const psim_scene *sc)
{
    long n = psim_count(s);
    double *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y);
    double *vx = malloc(n * sizeof *vx), *vy = malloc(n * sizeof *vy);
    psim_get_state(s, x, y, vx, vy);
    int bad = 0;
    for (long i = 0; i < n && !bad; i++) {
        bad |= psim_wall_collides(x[i], y[i], vx[i], vy[i], sc->L, sc->r);
        for (long j = i + 1; j < n && !bad; j++) {
            double dx = x[j] - x[i], dy = y[j] - y[i], d2 = dx * dx + dy * dy;
            bad |= psim_overlaps(d2, 4 * sc->r * sc->r) &&
                   psim_moving_closer(psim_approach(dx, dy, vx[j] - vx[i], vy[j] - vy[i]));
        }
    }
    CHECK_MSG(!bad, "unresolved collision after step %ld", psim_step_index(s));
    free(x), free(y), free(vx), free(vy);
}

static double *run(const psim_scene *sc, int threads, int tile, int steps)
{
    psim_config cfg;
    psim_config_default(&cfg);
    cfg.threads = threads;
    cfg.tile_cells = tile;
    cfg.check = 1;
    psim_error err = {{0}, 0};
    psim_sim *s = psim_create(sc, &cfg, &err);
    CHECK(s != NULL);
    for (int k = 0; k < steps; k++) {
        int rc = psim_step(s, &err);
        CHECK_MSG(rc == 0, "%s", err.msg);
        brute_force_quiet(s, sc);
    }
    double *state = malloc(4 * sc->n * sizeof *state);
    psim_get_state(s, state, state + sc->n, state + 2 * sc->n, state + 3 * sc->n);
    const psim_stats *st = psim_get_stats(s);
    CHECK(st->steps == steps);
    CHECK(psim_counter(s, "pair_resolutions") > 0);
    CHECK(psim_counter(s, "rounds") >= (uint64_t)steps);
    psim_destroy(s);
    return state;
}

/* psim_create_taking: every model gives the same states as with
 * psim_create, and the scene's particle arrays are gone once created */
static void test_taking(void)
{
    psim_gen_params p = {.n = 600, .L = 120, .r = 1, .steps = 0, .vmin = -0.5, .vmax = 0.5,
                         .seed = 9, .place = PSIM_PLACE_LATTICE};
    CHECK(psim_model_count() > 0);
    for (int k = 0; k < psim_model_count(); k++) {
        const char *model = psim_model_name(k);
        psim_scene a = {0}, b = {0};
        psim_error err = {{0}, 0};
        CHECK(psim_scene_generate(&p, &a, &err) == 0 && psim_scene_generate(&p, &b, &err) == 0);
        psim_config cfg;
        psim_config_default(&cfg);
        cfg.model = model;
        cfg.threads = 2;
        psim_sim *s = psim_create(&a, &cfg, &err), *t = psim_create_taking(&b, &cfg, &err);
        CHECK_MSG(s && t, "%s: %s", model, err.msg);
        CHECK(a.x != NULL && b.x == NULL && b.y == NULL && b.vx == NULL && b.vy == NULL);
        CHECK(b.n == a.n && b.L == a.L && b.r == a.r);
        for (int step = 0; s && t && step < 10; step++)
            CHECK(psim_step(s, &err) == 0 && psim_step(t, &err) == 0);
        double *u = malloc(8 * (size_t)a.n * sizeof *u), *v = u + 4 * a.n;
        if (s && t) {
            psim_get_state(s, u, u + a.n, u + 2 * a.n, u + 3 * a.n);
            psim_get_state(t, v, v + a.n, v + 2 * a.n, v + 3 * a.n);
            CHECK_MSG(memcmp(u, v, 4 * (size_t)a.n * sizeof *u) == 0, "%s: taking differs",
                      model);
        }
        free(u);
        psim_destroy(s);
        psim_destroy(t);
        psim_scene_clear(&a);
        psim_scene_clear(&b);
    }
}

/* A restart scene made by the library's caller, not read from a file: its
 * model's columns are held to their kinds and ranges all the same (the
 * ccd model converts its counts to integers). */
static void test_restart_columns(void)
{
    static const char text[] = "#psim restart 1 model=ccd step=2 "
                               "columns=pair_collisions,wall_collisions\n"
                               "2\n10\n1\n5\n0 2 2 1 0 3 1\n1 7 7 0 0 0 4\n";
    static const double bad[] = {1e23, 2.5, -1, NAN, INFINITY, 9007199254740994.0};
    for (size_t k = 0; k <= sizeof bad / sizeof bad[0]; k++) {
        FILE *f = fmemopen((void *)text, sizeof text - 1, "r");
        psim_scene sc = {0};
        psim_error err = {{0}, 0};
        CHECK(psim_scene_read_stream(f, "r.in", &sc, &err) == 0);
        fclose(f);
        if (k < sizeof bad / sizeof bad[0])
            sc.restart.col[1][1] = bad[k];
        psim_config cfg;
        psim_config_default(&cfg);
        psim_sim *s = psim_create(&sc, &cfg, &err);
        if (k == sizeof bad / sizeof bad[0])
            CHECK_MSG(s != NULL, "the file as read: %s", err.msg);
        else
            CHECK_MSG(!s && strstr(err.msg, "r.in:7: particle 1: wall_collisions ") &&
                          strstr(err.msg, "is not a whole number in [0, 9007199254740992]"),
                      "wall_collisions %g: %s", bad[k], s ? "accepted" : err.msg);
        psim_destroy(s);
        psim_scene_clear(&sc);
    }
}

int main(void)
{
    test_taking();
    test_restart_columns();
    /* dense, all velocities positive: the corner pile-up, with disks
     * leaving the box */
    psim_gen_params p = {.n = 800, .r = 1, .steps = 0, .vmin = 0.2, .vmax = 0.6,
                         .seed = 3, .place = PSIM_PLACE_UNIFORM};
    p.L = sqrt(p.n * M_PI / 0.85);
    psim_scene sc = {0};
    psim_error err = {{0}, 0};
    CHECK(psim_scene_generate(&p, &sc, &err) == 0);
    double *ref = run(&sc, 1, 2, 12);
    for (int threads = 2; threads <= 4; threads++) {
        double *o = run(&sc, threads, 2, 12);
        CHECK_MSG(memcmp(ref, o, 4 * sc.n * sizeof *o) == 0, "threads %d differ", threads);
        free(o);
    }
    /* another tiling is another valid resolution order, equally quiet */
    free(run(&sc, 2, 8, 12));
    free(ref);
    psim_scene_clear(&sc);
    return check_done();
}
