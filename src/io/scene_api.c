/* The scene as the public API hands it out: an opaque handle, made and
 * freed here, its box and disks set and read one value at a time or as
 * arrays by id, each value held to the rules a scene file's is held to
 * (scene_read.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene.h"

psim_scene *psim_scene_new(void) { return calloc(1, sizeof(psim_scene)); }

void psim_scene_free(psim_scene *sc)
{
    if (!sc)
        return;
    psim_scene_clear(sc);
    free(sc);
}

static int has_disks(const psim_scene *sc, psim_error *err)
{
    if (sc->n == 0 || sc->x)
        return 1;
    if (err)
        psim_error_set(err, "the scene's disks were taken by psim_create_taking");
    return 0;
}

static int steps_ok(long steps, psim_error *err)
{
    if (steps >= 0 && steps <= PSIM_MAX_STEPS)
        return 1;
    psim_error_set(err, "step count S must be between 0 and %ld, got %ld", PSIM_MAX_STEPS,
                   steps);
    return 0;
}

int psim_scene_set_box(psim_scene *sc, long n, double L, double r, long steps,
                       psim_error *err)
{
    if (n < 0 || n > PSIM_MAX_PARTICLES) {
        psim_error_set(err, "particle count N must be between 0 and %ld, got %ld",
                       PSIM_MAX_PARTICLES, n);
        return -1;
    }
    if (!(L > 0) || !isfinite(L)) {
        psim_error_set(err, "box side L must be positive and finite, got %g", L);
        return -1;
    }
    if (!(r > 0) || !isfinite(r)) {
        psim_error_set(err, "radius r must be positive and finite, got %g", r);
        return -1;
    }
    if (!(2 * r < L)) {
        psim_error_set(err, "radius r = %g does not fit in the box: 2r must be less than "
                            "L = %g", r, L);
        return -1;
    }
    if (!steps_ok(steps, err))
        return -1;
    psim_scene made = {0};
    if (psim_scene_alloc(&made, n, err))
        return -1;
    made.L = L;
    made.r = r;
    made.steps = steps;
    psim_scene_clear(sc);
    *sc = made;
    return 0;
}

int psim_scene_set_steps(psim_scene *sc, long steps, psim_error *err)
{
    if (!steps_ok(steps, err))
        return -1;
    sc->steps = steps;
    return 0;
}

static const char *const field[4] = {"x", "y", "vx", "vy"};

int psim_scene_set_particle(psim_scene *sc, long i, double x, double y, double vx, double vy,
                            psim_error *err)
{
    if (i < 0 || i >= sc->n) {
        psim_error_set(err, "particle index %ld out of range 0..%ld", i, sc->n - 1);
        return -1;
    }
    if (!has_disks(sc, err))
        return -1;
    const double v[4] = {x, y, vx, vy};
    for (int f = 0; f < 4; f++)
        if (!isfinite(v[f])) {
            psim_error_set(err, "particle %ld: %s is not a finite number", i, field[f]);
            return -1;
        }
    sc->x[i] = x;
    sc->y[i] = y;
    sc->vx[i] = vx;
    sc->vy[i] = vy;
    return 0;
}

int psim_scene_set_state(psim_scene *sc, const double *x, const double *y, const double *vx,
                         const double *vy, psim_error *err)
{
    if (!has_disks(sc, err))
        return -1;
    const double *from[4] = {x, y, vx, vy};
    for (long i = 0; i < sc->n; i++)   /* all checked before any is set */
        for (int f = 0; f < 4; f++)
            if (from[f] && !isfinite(from[f][i])) {
                psim_error_set(err, "particle %ld: %s is not a finite number", i, field[f]);
                return -1;
            }
    double *to[4] = {sc->x, sc->y, sc->vx, sc->vy};
    for (int f = 0; f < 4; f++)
        if (from[f] && sc->n > 0)
            memcpy(to[f], from[f], (size_t)sc->n * sizeof(double));
    return 0;
}

int psim_scene_get_particle(const psim_scene *sc, long i, double *x, double *y, double *vx,
                            double *vy)
{
    if (i < 0 || i >= sc->n || !has_disks(sc, NULL))
        return -1;
    if (x)
        *x = sc->x[i];
    if (y)
        *y = sc->y[i];
    if (vx)
        *vx = sc->vx[i];
    if (vy)
        *vy = sc->vy[i];
    return 0;
}

int psim_scene_get_state(const psim_scene *sc, double *x, double *y, double *vx, double *vy)
{
    if (!has_disks(sc, NULL))
        return -1;
    if (sc->n == 0)
        return 0;
    double *to[4] = {x, y, vx, vy};
    const double *from[4] = {sc->x, sc->y, sc->vx, sc->vy};
    for (int f = 0; f < 4; f++)
        if (to[f])
            memcpy(to[f], from[f], (size_t)sc->n * sizeof(double));
    return 0;
}

long psim_scene_count(const psim_scene *sc) { return psim_scene_all(sc); }
double psim_scene_side(const psim_scene *sc) { return sc->L; }
double psim_scene_radius(const psim_scene *sc) { return sc->r; }
long psim_scene_steps(const psim_scene *sc) { return sc->steps; }
psim_scene_format psim_scene_get_format(const psim_scene *sc) { return sc->format; }
