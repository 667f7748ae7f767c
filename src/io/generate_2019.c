/* The CS3210 AY2019/20 scene generator and glibc's rand().
 *
 * The course's program draws with the C library's rand() seeded with 3210.
 * glibc's rand() is random() with its default TYPE_3 state: an additive
 * lagged Fibonacci generator r[i] = r[i-3] + r[i-31] (mod 2^32), seeded by
 * the "minimal standard" LCG r[i] = 16807 r[i-1] mod (2^31 - 1), its first
 * 310 outputs discarded, each output r[i] >> 1.  Written out here so that a
 * generated scene is the same on every machine and for every thread count,
 * and equal to what glibc's own rand() gives (tests/unit/test_scene_io.c
 * compares the two). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene.h"

void psim_glibc_srand(psim_glibc_rand_state *g, unsigned seed)
{
    int32_t *r = g->r;
    r[0] = (int32_t)(seed ? seed : 1);
    for (int i = 1; i < 31; i++) {
        /* 16807 * r mod (2^31 - 1) without overflow (Schrage), as glibc */
        int32_t hi = r[i - 1] / 127773, lo = r[i - 1] % 127773;
        int32_t w = 16807 * lo - 2836 * hi;
        r[i] = w < 0 ? w + 2147483647 : w;
    }
    g->f = 3;
    g->b = 0;
    for (int i = 0; i < 310; i++)
        psim_glibc_rand(g);
}

int psim_glibc_rand(psim_glibc_rand_state *g)
{
    uint32_t v = (uint32_t)g->r[g->f] + (uint32_t)g->r[g->b];
    g->r[g->f] = (int32_t)v;
    if (++g->f >= 31) {
        g->f = 0;
        ++g->b;
    } else if (++g->b >= 31)
        g->b = 0;
    return (int)(v >> 1);
}

static double draw(psim_glibc_rand_state *g)
{
    return psim_glibc_rand(g) / (double)2147483647; /* rand() / (double)RAND_MAX */
}

/* Whether (x, y) overlaps (distance <= 2r) a disk placed before, found
 * through a grid of cells of side >= 2r: the same answer as testing every
 * disk placed before, as the course's program does. */
typedef struct placed {
    int G;
    double inv;
    long *head, *next;
} placed;

static int overlaps_any(const placed *p, const psim_scene *sc, double x, double y)
{
    int cx = (int)fmin(p->G - 1, x * p->inv), cy = (int)fmin(p->G - 1, y * p->inv);
    double four_r2 = 4 * sc->r * sc->r;
    for (int oy = -1; oy <= 1; oy++)
        for (int ox = -1; ox <= 1; ox++) {
            int nx = cx + ox, ny = cy + oy;
            if (nx < 0 || ny < 0 || nx >= p->G || ny >= p->G)
                continue;
            for (long j = p->head[ny * p->G + nx]; j >= 0; j = p->next[j]) {
                double dx = x - sc->x[j], dy = y - sc->y[j];
                if (dx * dx + dy * dy <= four_r2)
                    return 1;
            }
        }
    return 0;
}

/* Draws allowed for one disk before the scene is declared too dense for
 * random placement (which jams near density 0.55). */
#define MAX_DRAWS 1000000L

int psim_scene_generate_2019(psim_scene *sc, unsigned seed, psim_error *err)
{
    const double L = sc->L, r = sc->r;
    if (sc->n > 0 && !sc->x) {
        psim_error_set(err, "the scene's disks were taken by an earlier psim_create_taking");
        return -1;
    }
    if (!(L >= 2 * r) || (double)sc->n * r * r > L * L) {
        psim_error_set(err, "%ld disks of radius %g cannot fit in a box of side %g "
                            "(need L >= 2r and N r^2 <= L^2)", sc->n, r, L);
        return -1;
    }
    placed p;
    p.G = (int)fmax(1.0, fmin(floor(L / (2 * r)), ceil(2 * sqrt((double)sc->n + 1))));
    p.inv = p.G / L;
    p.head = malloc((size_t)p.G * (size_t)p.G * sizeof *p.head);
    p.next = malloc(((size_t)sc->n + 1) * sizeof *p.next);
    if (!p.head || !p.next) {
        free(p.head), free(p.next);
        psim_error_set(err, "out of memory generating %ld disks", sc->n);
        return -1;
    }
    for (size_t c = 0; c < (size_t)p.G * (size_t)p.G; c++)
        p.head[c] = -1;
    psim_glibc_rand_state g;
    psim_glibc_srand(&g, seed);
    int rc = 0;
    for (long i = 0; i < sc->n && rc == 0; i++) {
        long draws = 0;
        do {
            if (++draws > MAX_DRAWS) {
                psim_error_set(err, "cannot place disk %ld of %ld without overlap after "
                               "%ld draws: the box (L %g, r %g) is too crowded for random "
                               "placement", i, sc->n, MAX_DRAWS, L, r);
                rc = -1;
                break;
            }
            sc->x[i] = r + draw(&g) * (L - 2 * r);
            sc->y[i] = r + draw(&g) * (L - 2 * r);
        } while (overlaps_any(&p, sc, sc->x[i], sc->y[i]));
        if (rc == 0) {
            int cx = (int)fmin(p.G - 1, sc->x[i] * p.inv);
            int cy = (int)fmin(p.G - 1, sc->y[i] * p.inv);
            p.next[i] = p.head[cy * p.G + cx];
            p.head[cy * p.G + cx] = i;
        }
    }
    for (long i = 0; i < sc->n && rc == 0; i++) {
        double speed = L / (8 * r) + draw(&g) * (L / 4 - L / (8 * r));
        double angle = draw(&g) * 2 * M_PI;
        sc->vx[i] = speed * cos(angle);
        sc->vy[i] = speed * sin(angle);
    }
    free(p.head), free(p.next);
    return rc;
}

void psim_scene_substeps(psim_scene *sc, long k)
{
    if (k <= 1)
        return;
    for (long i = 0; i < sc->n && sc->vx; i++) {
        sc->vx[i] /= (double)k;
        sc->vy[i] /= (double)k;
    }
    sc->steps *= k;
}
