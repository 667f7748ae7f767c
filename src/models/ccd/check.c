/* --check for the ccd model, after every step, from the state before it:
 *  - the accepted collisions are exactly the greedy choice over the step's
 *    ordered candidates (recomputed here sequentially, by id);
 *  - every collision conserves energy (|v|^2 summed over its disks, to a
 *    relative 1e-9), and no accepted collision is left unapplied: every
 *    disk's new state is what the rules give from its old one, to the bit;
 *  - no disk is outside [r, L - r] (to 1e-9 of L: the rules stop disks at
 *    walls up to round-off). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ccd.h"
#include "rules.h"

static int energy_ok(double before, double after)
{
    return fabs(before - after) <= 1e-9 * fmax(before, 1e-300);
}

static int expected_state(const cmodel *m, const psim_snapshot *b, const ccand *acc,
                          size_t na, double *x, double *y, double *vx, double *vy,
                          long step, psim_error *err)
{
    const long n = b->n;
    memcpy(x, b->x, (size_t)n * sizeof *x);
    memcpy(y, b->y, (size_t)n * sizeof *y);
    memcpy(vx, b->vx, (size_t)n * sizeof *vx);
    memcpy(vy, b->vy, (size_t)n * sizeof *vy);
    char *hit = calloc((size_t)n + 1, 1);
    if (!hit) {
        psim_error_set(err, "out of memory in --check");
        return -1;
    }
    for (size_t k = 0; k < na; k++) {
        const ccand *c = &acc[k];
        int p = c->p, q = c->q;
        double e0 = vx[p] * vx[p] + vy[p] * vy[p];
        x[p] += vx[p] * c->t;
        y[p] += vy[p] * c->t;
        hit[p] = 1;
        if (q < 0) {
            ccd_wall_reflect(x[p], y[p], &vx[p], &vy[p], m->L, m->r);
            ccd_rest(&x[p], &y[p], vx[p], vy[p], 1 - c->t, m->L, m->r);
            continue;
        }
        e0 += vx[q] * vx[q] + vy[q] * vy[q];
        x[q] += vx[q] * c->t;
        y[q] += vy[q] * c->t;
        hit[q] = 1;
        ccd_pair_bounce(x[p], y[p], &vx[p], &vy[p], x[q], y[q], &vx[q], &vy[q]);
        double e1 = vx[p] * vx[p] + vy[p] * vy[p] + vx[q] * vx[q] + vy[q] * vy[q];
        if (!energy_ok(e0, e1)) {
            psim_error_set(err, "--check: step %ld: collision of disks %d and %d changes "
                           "the energy from %.17g to %.17g", step, p, q, e0, e1);
            free(hit);
            return -1;
        }
        ccd_rest(&x[p], &y[p], vx[p], vy[p], 1 - c->t, m->L, m->r);
        ccd_rest(&x[q], &y[q], vx[q], vy[q], 1 - c->t, m->L, m->r);
    }
    for (long i = 0; i < n; i++)
        if (!hit[i]) {
            x[i] += vx[i];
            y[i] += vy[i];
        }
    free(hit);
    return 0;
}

/* The greedy choice, sequentially, by id. */
static int greedy_matches(const cmodel *m, long n, long step, psim_error *err)
{
    char *taken = calloc((size_t)n + 1, 1);
    if (!taken) {
        psim_error_set(err, "out of memory in --check");
        return -1;
    }
    size_t a = 0;
    int rc = 0;
    for (size_t k = 0; k < m->all.n && rc == 0; k++) {
        const ccand *c = &m->all.c[k];
        if (k > 0 && ccd_cand_cmp(&m->all.c[k - 1], c) >= 0) {
            psim_error_set(err, "--check: step %ld: candidates out of order at %zu", step, k);
            rc = -1;
        } else if (!taken[c->p] && (c->q < 0 || !taken[c->q])) {
            taken[c->p] = 1;
            if (c->q >= 0)
                taken[c->q] = 1;
            if (a >= m->acc.n || ccd_cand_cmp(&m->acc.c[a], c) != 0) {
                psim_error_set(err, "--check: step %ld: the collision of disk %d with %s%d "
                               "at t = %.17g was not applied", step, c->p,
                               c->q < 0 ? "the wall" : "disk ", c->q < 0 ? 0 : c->q, c->t);
                rc = -1;
            }
            a++;
        }
    }
    if (rc == 0 && a != m->acc.n) {
        psim_error_set(err, "--check: step %ld: %zu collisions applied, the greedy choice "
                       "has %zu", step, m->acc.n, a);
        rc = -1;
    }
    free(taken);
    return rc;
}

int ccd_check(psim_sim *e, void *p, const psim_snapshot *before,
              const psim_snapshot *after, psim_error *err)
{
    const cmodel *m = p;
    const long n = after->n, step = e->step;
    if (m->gpu && ccd_gpu_lists(p, err))   /* (the lists are on the device) */
        return -1;
    const double tol = 1e-9 * fmax(1.0, m->L);
    for (long i = 0; i < n; i++)
        if (!(after->x[i] >= m->r - tol && after->x[i] <= m->L - m->r + tol &&
              after->y[i] >= m->r - tol && after->y[i] <= m->L - m->r + tol)) {
            psim_error_set(err, "--check: step %ld: disk %ld at (%.17g, %.17g) is outside "
                           "the box", step, i, after->x[i], after->y[i]);
            return -1;
        }
    if (greedy_matches(m, n, step, err))
        return -1;
    size_t b = (size_t)(n > 0 ? n : 1) * sizeof(double);
    double *x = malloc(b), *y = malloc(b), *vx = malloc(b), *vy = malloc(b);
    int rc = -1;
    if (!x || !y || !vx || !vy)
        psim_error_set(err, "out of memory in --check");
    else if (expected_state(m, before, m->acc.c, m->acc.n, x, y, vx, vy, step, err) == 0) {
        rc = 0;
        for (long i = 0; i < n && rc == 0; i++)
            if (memcmp(&x[i], &after->x[i], sizeof x[i]) || memcmp(&y[i], &after->y[i], sizeof y[i]) ||
                memcmp(&vx[i], &after->vx[i], sizeof vx[i]) ||
                memcmp(&vy[i], &after->vy[i], sizeof vy[i])) {
                psim_error_set(err, "--check: step %ld: disk %ld is not where the rules put "
                               "it: (%.17g, %.17g) instead of (%.17g, %.17g)", step, i,
                               after->x[i], after->y[i], x[i], y[i]);
                rc = -1;
            }
    }
    free(x), free(y), free(vx), free(vy);
    return rc;
}
