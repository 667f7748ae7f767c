/* A scene against its model's limits (model.h): the largest box, radius,
 * positions and speeds whose arithmetic the model can carry out.  A scene
 * beyond one is refused before the model is made, with one line naming
 * the line of L, r or the disk and what is too large: past them a step
 * meets numbers that overflow (a contact time that is NaN at every
 * instant, and the run never ends; a force that is NaN, reported as a
 * state that overflowed although it had not). */
#include <float.h>
#include <math.h>
#include <stdio.h>

#include "dist.h"
#include "engine.h"

/* S = sqrt(sum of vx^2 + vy^2), the speed one disk may reach, summed in
 * units of a power of two at or above the largest component (as --check
 * sums energies) so that the sum itself cannot overflow; infinite only
 * when S is beyond the largest double.  *fastest: the disk with the
 * largest speed (the lowest id of equals).  Of a part of a scene (over
 * MPI ranks) S is the whole scene's, its sum added up rank by rank (its
 * last bits may differ from one process's: a limit of overflow is far
 * from them), and *fastest is -1 on the ranks that do not hold that disk. */
static double speed_reach(const psim_scene *sc, long *fastest)
{
    const int part = sc->id != NULL;
    double m = 0;
    *fastest = 0;
    for (long i = 0; i < sc->n; i++)
        m = fmax(m, fmax(fabs(sc->vx[i]), fabs(sc->vy[i])));
    if (part)
        m = psim_dist_max(m);
    if (m == 0)
        return 0;
    int ex;
    frexp(m, &ex);
    const double k = ldexp(1.0, -ex);   /* exact, as a power of two */
    double sum = 0, best = -1;
    *fastest = -1;
    for (long i = 0; i < sc->n; i++) {
        double u = sc->vx[i] * k, w = sc->vy[i] * k, q = u * u + w * w;
        sum += q;
        if (q > best)
            best = q, *fastest = i;
    }
    if (part) {
        sum = psim_dist_sum(sum);
        if (best < psim_dist_max(best))
            *fastest = -1;
    }
    return ldexp(sqrt(sum), ex);
}

/* S as the message shows it. */
static void speed_text(double S, char *buf, size_t size)
{
    if (isfinite(S))
        snprintf(buf, size, "%g", S);
    else
        snprintf(buf, size, "more than %g", DBL_MAX);
}

/* A header value (what, on header line `line`) within its limit. */
static int header_value(const psim_sim *e, const psim_scene *sc, const psim_limit *lim,
                        int line, const char *what, double v, psim_error *err)
{
    if (!(lim->most > 0) || v <= lim->most)
        return 0;
    char at[320];
    psim_scene_where_header(sc, line, at, sizeof at);
    psim_error_set(err, "%s%s = %g is too large for the %s model (at most %g: %s would overflow)",
                   at, what, v, e->model->name, lim->most, lim->why);
    return -1;
}

static int box_radius(const psim_sim *e, const psim_scene *sc, const psim_limits *lim,
                      psim_error *err)
{
    return header_value(e, sc, &lim->at[PSIM_LIMIT_BOX], PSIM_LINE_L, "box side L", sc->L, err) ||
                   header_value(e, sc, &lim->at[PSIM_LIMIT_RADIUS], PSIM_LINE_R, "radius r",
                                sc->r, err)
               ? -1
               : 0;
}

static int positions(const psim_sim *e, const psim_scene *sc, const psim_limit *p,
                     psim_error *err)
{
    if (!(p->most > 0))
        return 0;
    for (long i = 0; i < sc->n; i++) {
        if (fabs(sc->x[i]) <= p->most && fabs(sc->y[i]) <= p->most)
            continue;
        int is_x = !(fabs(sc->x[i]) <= p->most);
        char at[320];
        psim_scene_where(sc, i, at, sizeof at);
        psim_error_set(err, "%sdisk %ld: %s = %g is too large for the %s model (|x| and |y| "
                            "at most %g: %s would overflow)",
                       at, psim_scene_id(sc, i), is_x ? "x" : "y", is_x ? sc->x[i] : sc->y[i], e->model->name,
                       p->most, p->why);
        return -1;
    }
    return 0;
}

/* S alone, and S times L and r: the line of the fastest disk. */
static int speeds(const psim_sim *e, const psim_scene *sc, const psim_limits *lim,
                  psim_error *err)
{
    const psim_limit *s = &lim->at[PSIM_LIMIT_SPEED], *bs = &lim->at[PSIM_LIMIT_BOX_SPEED],
                     *rs = &lim->at[PSIM_LIMIT_RADIUS_SPEED];
    if (!(s->most > 0) && !(bs->most > 0) && !(rs->most > 0))
        return 0;
    long i;
    const double S = speed_reach(sc, &i);
    const int over_s = s->most > 0 && !(S <= s->most),
              over_bs = bs->most > 0 && !(S <= bs->most / sc->L),
              over_rs = rs->most > 0 && !(S <= rs->most / sc->r);
    if (!over_s && !over_bs && !over_rs)
        return 0;
    if (i < 0) {   /* a part: the rank that holds the disk says it */
        psim_error_set(err, "%s", "");
        return -1;
    }
    char at[320], st[48];
    psim_scene_where(sc, i, at, sizeof at);
    speed_text(S, st, sizeof st);
    const double v = hypot(sc->vx[i], sc->vy[i]);
    const char *model = e->model->name;
    if (over_s)
        psim_error_set(err, "%sdisk %ld moves %g a step: the speeds are too large for the %s "
                            "model (S = sqrt(sum of vx^2 + vy^2), the speed one disk may reach, "
                            "is %s, at most %g: %s would overflow)",
                       at, i, v, model, st, s->most, s->why);
    else if (over_bs)
        psim_error_set(err, "%sdisk %ld moves %g a step: the speeds are too large for the %s "
                            "model in a box of L = %g (S = sqrt(sum of vx^2 + vy^2) is %s; S L "
                            "at most %g: %s would overflow)",
                       at, i, v, model, sc->L, st, bs->most, bs->why);
    else
        psim_error_set(err, "%sdisk %ld moves %g a step: the speeds are too large for the %s "
                            "model with r = %g (S = sqrt(sum of vx^2 + vy^2) is %s; S r at "
                            "most %g: %s would overflow)",
                       at, i, v, model, sc->r, st, rs->most, rs->why);
    return -1;
}

int psim_engine_limits(const psim_sim *e, const psim_scene *sc, psim_error *err)
{
    if (!e->model->limits)
        return 0;
    psim_limits lim = {0};
    int rc = e->model->limits(e, sc, &lim, err) ? -1 : 0;   /* (its err->usage) */
    if (!rc && (box_radius(e, sc, &lim, err) || positions(e, sc, &lim.at[PSIM_LIMIT_POSITION], err)))
        rc = -2;
    /* a part of a scene (over MPI ranks): a disk beyond a limit is on one
     * rank, which says it, and every rank stops before S, which all make */
    if (sc->id && psim_dist_agree(rc != 0) >= 0 && !rc) {
        psim_error_set(err, "%s", "");
        return -1;
    }
    if (!rc && speeds(e, sc, &lim, err))
        rc = -2;
    if (rc == -2 && err)
        err->usage = 0;
    return rc ? -1 : 0;
}
