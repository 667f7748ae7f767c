/* Scene generator: the course generator's rules (positions uniform in
 * [0, L], velocity components uniform in [vmin, vmax]) and two placements
 * without overlaps.  A fixed PRNG (splitmix64) makes scenes reproducible on
 * every platform. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene.h"

static uint64_t splitmix64(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double uniform01(uint64_t *s)
{
    return (double)(splitmix64(s) >> 11) * 0x1.0p-53;
}

static double uniform(uint64_t *s, double lo, double hi)
{
    return lo + uniform01(s) * (hi - lo);
}

double psim_scene_density(const psim_scene *sc)
{
    const double n = (double)psim_scene_all(sc);
    if (n == 0)   /* also for a box of side 0 */
        return 0.0;
    if (isfinite(sc->L * sc->L))   /* then r^2 too: 2r < L */
        return n * M_PI * sc->r * sc->r / (sc->L * sc->L);
    /* L^2 overflows (a side past about 1.3e154): r / L first, below 1/2 */
    double q = sc->r / sc->L;
    return n * M_PI * q * q;
}

/* Random sequential addition on a grid of cells of side >= 2r. */
static int place_nonoverlap(const psim_gen_params *p, psim_scene *sc,
                            uint64_t *rng, psim_error *err)
{
    double span = p->L - 2 * p->r;
    int G = (int)fmax(1.0, fmin(floor(p->L / (2 * p->r)), 4096.0));
    double inv = G / p->L;
    long *head = malloc((size_t)G * G * sizeof *head);
    long *next = malloc(((size_t)p->n + 1) * sizeof *next);
    if (!head || !next) {
        free(head);
        free(next);
        psim_error_set(err, "out of memory placing %ld disks", p->n);
        return -1;
    }
    for (size_t c = 0; c < (size_t)G * G; c++)
        head[c] = -1;
    const long max_tries = 10000;
    for (long i = 0; i < p->n; i++) {
        long tries = 0;
        for (;; tries++) {
            if (tries == max_tries || span < 0) {
                psim_error_set(err,
                    "cannot place %ld non-overlapping disks of radius %g in a box of "
                    "side %g (stuck at disk %ld; random placement jams near density "
                    "0.54): use --place lattice or a lower density",
                    p->n, p->r, p->L, i);
                free(head);
                free(next);
                return -1;
            }
            double x = p->r + uniform01(rng) * span, y = p->r + uniform01(rng) * span;
            int cx = (int)fmin(G - 1, x * inv), cy = (int)fmin(G - 1, y * inv);
            int ok = 1;
            for (int oy = -1; oy <= 1 && ok; oy++)
                for (int ox = -1; ox <= 1 && ok; ox++) {
                    int nx = cx + ox, ny = cy + oy;
                    if (nx < 0 || ny < 0 || nx >= G || ny >= G)
                        continue;
                    for (long j = head[ny * G + nx]; j >= 0 && ok; j = next[j]) {
                        double dx = sc->x[j] - x, dy = sc->y[j] - y;
                        ok = dx * dx + dy * dy > 4 * p->r * p->r;
                    }
                }
            if (ok) {
                sc->x[i] = x;
                sc->y[i] = y;
                next[i] = head[cy * G + cx];
                head[cy * G + cx] = i;
                break;
            }
        }
    }
    free(head);
    free(next);
    return 0;
}

/* Square lattice of k x k sites, n of them used in random order, each disk
 * jittered inside its site without reaching the next. */
static int place_lattice(const psim_gen_params *p, psim_scene *sc,
                         uint64_t *rng, psim_error *err)
{
    long k = (long)ceil(sqrt((double)p->n));
    double a = p->L / (double)(k > 0 ? k : 1);
    if (a <= 2 * p->r) {
        psim_error_set(err,
            "cannot place %ld disks of radius %g on a lattice in a box of side %g: "
            "the spacing %g is not more than 2r (square lattices hold density < 0.785)",
            p->n, p->r, p->L, a);
        err->usage = 1;   /* what the options ask cannot be made */
        return -1;
    }
    long sites = k * k;
    long *order = malloc((size_t)(sites > 0 ? sites : 1) * sizeof *order);
    if (!order) {
        psim_error_set(err, "out of memory placing %ld disks", p->n);
        return -1;
    }
    for (long s = 0; s < sites; s++)
        order[s] = s;
    for (long s = sites - 1; s > 0; s--) {
        long t = (long)(splitmix64(rng) % (uint64_t)(s + 1));
        long tmp = order[s];
        order[s] = order[t];
        order[t] = tmp;
    }
    double slack = (a - 2 * p->r) * 0.5 * (1 - 1e-9);
    for (long i = 0; i < p->n; i++) {
        long s = order[i];
        sc->x[i] = (s % k + 0.5) * a + uniform(rng, -slack, slack);
        sc->y[i] = (s / k + 0.5) * a + uniform(rng, -slack, slack);
    }
    free(order);
    return 0;
}

/* The scene p asks for into *sc (all zero). */
static int generate(const psim_gen_params *p, psim_scene *sc, psim_error *err)
{
    if (p->n < 0 || !(p->L > 0) || !(p->r > 0) || p->steps < 0 ||
        !isfinite(p->vmin) || !isfinite(p->vmax) || p->vmin > p->vmax || !isfinite(p->L) ||
        !isfinite(p->r)) {
        psim_error_set(err, "invalid generator parameters: need N >= 0, L > 0, r > 0, "
                            "S >= 0 and finite vmin <= vmax");
        err->usage = 1;   /* what the options ask cannot be made */
        return -1;
    }
    if (!(2 * p->r < p->L)) {
        psim_error_set(err, "radius r = %g does not fit in the box: 2r must be less "
                            "than L = %g", p->r, p->L);
        err->usage = 1;   /* what the options ask cannot be made */
        return -1;
    }
    if (psim_scene_alloc(sc, p->n, err))
        return -1;
    sc->L = p->L;
    sc->r = p->r;
    sc->steps = p->steps;
    uint64_t rng = p->seed;
    int rc = 0;
    if (p->place == PSIM_PLACE_NONOVERLAP)
        rc = place_nonoverlap(p, sc, &rng, err);
    else if (p->place == PSIM_PLACE_LATTICE)
        rc = place_lattice(p, sc, &rng, err);
    else
        for (long i = 0; i < p->n; i++) {
            sc->x[i] = uniform01(&rng) * p->L;
            sc->y[i] = uniform01(&rng) * p->L;
        }
    for (long i = 0; i < p->n && !rc; i++) {
        sc->vx[i] = uniform(&rng, p->vmin, p->vmax);
        sc->vy[i] = uniform(&rng, p->vmin, p->vmax);
    }
    return rc;
}

int psim_scene_generate(const psim_gen_params *p, psim_scene *sc,
                        psim_error *err)
{
    psim_scene made = {0};
    if (generate(p, &made, err)) {
        psim_scene_clear(&made);
        return -1;
    }
    psim_scene_clear(sc);
    *sc = made;
    return 0;
}
