/* The event model behind the model interface: the disks' states and
 * cells, the start (no overlaps allowed), a step as the events up to the
 * next whole time, and the state at that time written to the store. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "event.h"
#include "../../engine/mem.h"
#include "../../engine/timer.h"

static void destroy(void *p)
{
    emodel *m = p;
    if (!m)
        return;
    psim_free(m->d), psim_free(m->plan), psim_free(m->head);
    ecal_free(&m->cal);
    free(m);
}

/* Cells of side L / G >= 2r (a little more, against round-off), no more
 * than about 2 per disk. */
static int plan_cells(emodel *m)
{
    double per = m->L / (2 * m->r * (1 + 1e-9));
    double most = 2 * sqrt((double)m->n) + 1;
    double g = per < most ? per : most;
    m->G = g >= 1 ? (int)g : 1;
    m->h = m->L / m->G;
    for (int k = 0; k < 9; k++)
        m->around[k] = (k / 3 - 1) * (m->G + 2) + (k % 3 - 1);
    return 0;
}

static int cell_of(const emodel *m, double p)
{
    double c = p / m->h;   /* clamped before the conversion: p may be far outside */
    return !(c >= 0) ? 0 : c >= m->G ? m->G - 1 : (int)c;
}

/* The first overlapping pair (lowest i, then lowest j), or -1. */
/* Disks closer than 2r by a relative 1e-12 of the squared distance (about
 * 5e-13 r) touch: a close-packed crystal written with 17 digits is 2r
 * apart only to round-off.  The predictions take such pairs (a touching
 * pair that approaches collides at once); the check allows 1e-9 r. */
#define EVENT_TOUCH 1e-12

static long first_overlap(const emodel *m, long *jout)
{
    for (long i = 0; i < m->n; i++) {
        long best = -1;
        int32_t c = event_cell(m, m->d[i].cx, m->d[i].cy);
        for (int k = 0; k < 9; k++)   /* the grid's border: no bounds to check */
            for (int32_t j = m->head[c + m->around[k]]; j >= 0; j = m->d[j].next) {
                double dx = m->d[j].x - m->d[i].x, dy = m->d[j].y - m->d[i].y;
                if (j > i && dx * dx + dy * dy < m->sigma2 * (1 - EVENT_TOUCH) &&
                    (best < 0 || j < best))
                    best = j;
            }
        if (best >= 0) {
            *jout = best;
            return i;
        }
    }
    return -1;
}

/* The first disk whose centre is outside the walls [r, L - r]^2 by more
 * than round-off (1e-9 r, as --check allows), or -1.  Such a disk is an
 * overlap with a wall: the wall meets it "now" wherever it is, and pinned
 * between that and a disk it loops at one instant for ever (a fuzzed
 * scene: a disk at rest at (0, 0), r = 1, hung the run). */
static long first_outside(const emodel *m)
{
    const double tol = 1e-9 * m->r;
    for (long i = 0; i < m->n; i++)
        if (!(m->d[i].x >= m->lo - tol && m->d[i].x <= m->hi + tol &&
              m->d[i].y >= m->lo - tol && m->d[i].y <= m->hi + tol))
            return i;
    return -1;
}

static int alloc_state(emodel *m)
{
    size_t cells = (size_t)(m->G + 2) * (size_t)(m->G + 2);   /* and a border */
    m->d = psim_calloc((size_t)m->n * sizeof *m->d);   /* psim_alloc: cache-line aligned */
    m->plan = psim_calloc((size_t)m->n * sizeof *m->plan);
    m->head = psim_alloc(cells * sizeof *m->head);
    if (!m->d || !m->plan || !m->head)
        return -1;
    memset(m->head, 0xff, cells * sizeof *m->head);   /* -1: empty */
    for (long i = 0; i < m->n; i++)
        m->d[i].last = -1;
    return 0;
}

/* Kinetic energy of unit masses, summed in id order. */
static double kinetic(const emodel *m)
{
    double k = 0;
    for (long i = 0; i < m->n; i++)
        k += m->d[i].vx * m->d[i].vx + m->d[i].vy * m->d[i].vy;
    return k / 2;
}

/* A run whose events cannot end in reasonable time is refused up front,
 * naming the fastest disk (a disk at 1e300 a step would hit the walls
 * 1e298 times a step, and the run would never end).  A disk moving
 * (vx, vy) a step hits the walls (|vx| + |vy|) / w times a step, w apart,
 * and crosses G - 1 cell borders between two hits: G (|vx| + |vy|) / w
 * events a step, its collisions aside.  At EVENT_RATE_MAX events a second,
 * the fastest measured (one disk, all in the cache: more disks run slower),
 * the run takes at least events / EVENT_RATE_MAX seconds; beyond
 * EVENT_REFUSE_S it is certainly absurd.  A shorter run runs, with
 * progress inside its steps (poll.h). */
#define EVENT_RATE_MAX 2e7
#define EVENT_REFUSE_S 86400.0

static int too_many_events(const psim_sim *e, const emodel *m, psim_error *err)
{
    double w = m->hi - m->lo, rate = 0, fastest = 0;
    long who = 0;
    for (long i = 0; i < m->n; i++) {
        double v = fabs(m->d[i].vx) + fabs(m->d[i].vy);
        rate += v / w;
        if (v > fastest)
            fastest = v, who = i;
    }
    double steps = e->cfg.steps > 0 ? (double)e->cfg.steps : 1.0;
    double events = rate * m->G * steps, least_s = events / EVENT_RATE_MAX;
    if (!(least_s > EVENT_REFUSE_S) && isfinite(rate))
        return 0;
    psim_error_set(err, "disk %ld moves %g a step between walls %g apart: about %.3g wall and "
                        "cell events in %.0f steps, at least %.3g days at the event model's "
                        "fastest (%g events a second), more than it runs (a day); the "
                        "discrete and ccd models take such speeds",
                   who, fastest, w, events, steps, least_s / 86400, EVENT_RATE_MAX);
    return 1;
}

/* Restart files carry each disk as the model keeps it: its state at its
 * own time (the time of its last event), its cell (moved at crossing
 * events, not recomputed from the position) and its last partner.  From
 * these the calendar is predicted afresh at the file's time: every event
 * still to come is a function of the two disks' states alone, so the run
 * goes on with the same events at the same times, bit for bit. */
enum { ER_T, ER_X, ER_Y, ER_CX, ER_CY, ER_LAST, ER_COLS };
static const char *const restart_names[ER_COLS] = {"t_own", "x_own",  "y_own",
                                                   "cell_x", "cell_y", "last"};

static void restart_save(const psim_sim *e, const void *p, int k, double *by_id)
{
    const emodel *m = p;
    for (long i = 0; i < e->n; i++) {
        const edisk *d = &m->d[i];
        const double v[ER_COLS] = {d->t, d->x, d->y, d->cx, d->cy, d->last};
        by_id[i] = v[k];
    }
}

/* What the reader cannot know of disk i's columns c (each of its kind
 * and in its range already): its own time is not after the file's, its
 * cell is one of the grid's and that of its position at the file's time
 * but for round-off (crossings are events: a centre just past a side may
 * not have crossed yet), its last partner another disk.  0, or 1 with
 * err set to "FILE:LINE: disk I: ...". */
static int restart_disk_bad(const psim_sim *e, const psim_scene *sc, const emodel *m,
                            const double *const *c, long i, psim_error *err)
{
    char at[320];
    const double cx = c[ER_CX][i], cy = c[ER_CY][i], last = c[ER_LAST][i];
    const int px = cell_of(m, e->st.x[i]), py = cell_of(m, e->st.y[i]);
    psim_scene_where(sc, i, at, sizeof at);
    if (c[ER_T][i] > (double)e->step)
        psim_error_set(err, "%sdisk %ld: t_own %.17g is after the file's step=%ld", at, i,
                       c[ER_T][i], e->step);
    else if (cx >= m->G || cy >= m->G)
        psim_error_set(err, "%sdisk %ld: cell_x, cell_y (%.0f, %.0f) is outside the event "
                            "model's %d x %d cells", at, i, cx, cy, m->G, m->G);
    else if (fabs(cx - px) > 1 || fabs(cy - py) > 1)
        psim_error_set(err, "%sdisk %ld: cell_x, cell_y (%.0f, %.0f) is not the cell of its "
                            "position, (%d, %d)", at, i, cx, cy, px, py);
    else if (last >= (double)m->n || last == (double)i)
        psim_error_set(err, "%sdisk %ld: last %.0f is not another disk (0..%ld, or -1 for "
                            "none)", at, i, last, m->n - 1);
    else
        return 0;
    return 1;
}

/* The disks at their own times, if sc is this model's restart file (the
 * reader requires all its columns; checked for overlaps at the file's
 * time before).  0, or -1 with err set. */
static int restart_load(psim_sim *e, const psim_scene *sc, emodel *m, psim_error *err)
{
    const double *c[ER_COLS];
    double k0;
    for (int k = 0; k < ER_COLS; k++)
        if (!(c[k] = psim_engine_restart_column(e, sc, restart_names[k])))
            return 0;
    for (long i = 0; i < m->n; i++)
        if (restart_disk_bad(e, sc, m, c, i, err))
            return -1;
    /* the sums go on too (the thermo's pressure is their change) */
    if (psim_engine_restart_value(e, sc, "virial", &m->virial) ||
        psim_engine_restart_value(e, sc, "wall_impulse", &m->wall_impulse) ||
        psim_engine_restart_value(e, sc, "kinetic0", &k0))
        m->virial = m->wall_impulse = 0;
    else {
        e->stats.value[EV_KINETIC0] = k0;
        e->stats.value[EV_VIRIAL] = m->virial;
        e->stats.value[EV_WALL_IMPULSE] = m->wall_impulse;
    }
    for (long i = 0; i < m->n; i++) {
        edisk *d = &m->d[i];
        event_cell_remove(m, (int32_t)i);
        d->t = c[ER_T][i], d->x = c[ER_X][i], d->y = c[ER_Y][i];
        d->cx = (int32_t)c[ER_CX][i], d->cy = (int32_t)c[ER_CY][i];
        d->last = (int32_t)c[ER_LAST][i];
        event_cell_insert(m, (int32_t)i);
    }
    return 0;
}

/* The smallest radius the model takes, relative to the box and absolute.
 * Coordinates near L are kept to a double's round-off, about 2.2e-16 L:
 * a contact, centres 2r apart, must span hundreds of those, or its line
 * of centres is round-off (centres a few units apart), or nothing (both
 * centres at one point: the collision divides 0 by 0).  And (2r)^2 times
 * a squared speed must not underflow (r = 1e-170 in a box of 1e-160: NaN
 * again). */
#define EVENT_MIN_R_OVER_L 1e-13
#define EVENT_MIN_R 1e-100

static int radius_too_small(const psim_scene *sc, psim_error *err)
{
    if (sc->r >= EVENT_MIN_R_OVER_L * sc->L && sc->r >= EVENT_MIN_R)
        return 0;
    char at[320];
    psim_scene_where_header(sc, PSIM_LINE_R, at, sizeof at);
    if (sc->r < EVENT_MIN_R)
        psim_error_set(err, "%sradius r = %g is below %g, the least the event model takes "
                            "(its squared distances times squared speeds would underflow)",
                       at, sc->r, EVENT_MIN_R);
    else
        psim_error_set(err, "%sradius r = %g is below %g of the box side (L = %g: r >= %g), "
                            "the least the event model takes: coordinates near L are kept to "
                            "about 2.2e-16 L, too coarse for contacts 2r apart",
                       at, sc->r, EVENT_MIN_R_OVER_L, sc->L, EVENT_MIN_R_OVER_L * sc->L);
    return 1;
}

/* The largest box and speeds the contact times can be computed for.  With
 * every centre inside the box and S the speed one disk may reach (model.h),
 * a pair's |dr| <= sqrt(2) L and |dv| <= sqrt(2) S, so its arithmetic
 * (predict.h, collide) stays below: |dr|^2 <= 2 L^2, |dv|^2 sigma^2 <= 2
 * (S L)^2, (dr x dv)^2 <= 4 (S L)^2, the kinetic energy S^2 / 2, the
 * virial's terms 2 S L.  Past L = 1e155 the squared distances overflow, a
 * contact time is NaN, taken as "now", and the collision that changes
 * nothing is found again at the same instant for ever.  The bounds leave
 * a factor of 1e4 below the largest double. */
#define EVENT_MAX_LENGTH 1e152
#define EVENT_MAX_SPEED 1e152
#define EVENT_MAX_LENGTH_SPEED 1e152

static int limits(const psim_sim *e, const psim_scene *sc, psim_limits *lim, psim_error *err)
{
    (void)e, (void)sc, (void)err;
    lim->at[PSIM_LIMIT_BOX] = (psim_limit){EVENT_MAX_LENGTH,
                                           "its squared distances (up to 2 L^2)"};
    lim->at[PSIM_LIMIT_SPEED] = (psim_limit){EVENT_MAX_SPEED,
                                             "its squared speeds (up to S^2)"};
    lim->at[PSIM_LIMIT_BOX_SPEED] = (psim_limit){
        EVENT_MAX_LENGTH_SPEED, "its contact times' (dr x dv)^2 (up to 4 (S L)^2)"};
    return 0;
}

static void *create(psim_sim *e, const psim_scene *sc, psim_error *err)
{
    if (radius_too_small(sc, err))
        return NULL;
    emodel *m = calloc(1, sizeof *m);
    if (!m)
        goto oom;
    m->n = sc->n;
    m->L = sc->L;
    m->r = sc->r;
    m->sigma2 = (2 * sc->r) * (2 * sc->r);
    m->lo = sc->r;
    m->hi = sc->L - sc->r;
    m->buckets = psim_engine_option(e, "calendar", 1) != 0;
    if (plan_cells(m) || alloc_state(m))
        goto oom;
    const psim_store *st = &e->st;   /* by id before the first sort */
    for (long i = 0; i < m->n; i++) {
        m->d[i].x = st->x[i], m->d[i].y = st->y[i];
        m->d[i].vx = st->vx[i], m->d[i].vy = st->vy[i];
        m->d[i].t = (double)e->step;   /* time goes on from a restart file's */
        m->d[i].cx = cell_of(m, m->d[i].x);
        m->d[i].cy = cell_of(m, m->d[i].y);
        event_cell_insert(m, (int32_t)i);
    }
    long j = -1, i = first_overlap(m, &j);
    if (i >= 0) {
        double dx = m->d[j].x - m->d[i].x, dy = m->d[j].y - m->d[i].y;
        char at[320], also[48] = "";   /* "FILE:LINE: " and " (line LINE)" */
        psim_scene_where(sc, i, at, sizeof at);
        if (sc->line)
            snprintf(also, sizeof also, " (line %ld)", sc->line[j]);
        psim_error_set(err, "%sdisk %ld overlaps disk %ld%s: squared distance of centres %.17g, "
                            "less than (2r)^2 = %.17g (the event model needs a scene without "
                            "overlaps: psim gen --place nonoverlap or lattice)",
                       at, i, j, also, dx * dx + dy * dy, m->sigma2);
        destroy(m);
        return NULL;
    }
    /* (overlaps at the file's time, walls at each disk's own: a restart
     * file's own-time columns are checked too) */
    m->now = (double)e->step;
    e->stats.value[EV_KINETIC0] = e->stats.value[EV_KINETIC] = kinetic(m);
    if (restart_load(e, sc, m, err)) {
        destroy(m);
        return NULL;
    }
    if ((i = first_outside(m)) >= 0) {
        char at[320];
        psim_scene_where(sc, i, at, sizeof at);
        psim_error_set(err, "%sdisk %ld at (%.17g, %.17g) is outside the walls: the event "
                            "model needs every centre in [r, L - r] = [%.17g, %.17g] (psim gen "
                            "--place nonoverlap or lattice)",
                       at, i, m->d[i].x, m->d[i].y, m->lo, m->hi);
        destroy(m);
        return NULL;
    }
    if (too_many_events(e, m, err)) {
        destroy(m);
        return NULL;
    }
    if (event_predict_all(e, m))
        goto oom;
    return m;
oom:
    destroy(m);
    psim_error_set(err, "out of memory for the event model");
    return NULL;
}

/* The state at time T, to the store (the disks stay at their own times),
 * and the measured values. */
static void sync_store(psim_sim *e, const emodel *m, double T)
{
    psim_store *s = &e->st;
    double *v = e->stats.value;
    v[EV_TIME] = T;
    v[EV_KINETIC] = kinetic(m);
    v[EV_VIRIAL] = m->virial;
    v[EV_WALL_IMPULSE] = m->wall_impulse;
    for (size_t k = 0; k < s->n; k++) {
        int32_t i = s->id[k];
        double dt = T - m->d[i].t;
        s->x[k] = m->d[i].x + m->d[i].vx * dt;
        s->y[k] = m->d[i].y + m->d[i].vy * dt;
        s->vx[k] = m->d[i].vx;
        s->vy[k] = m->d[i].vy;
    }
}

static int interact(psim_sim *e, void *p, psim_error *err)
{
    emodel *m = p;
    double T = (double)(e->step + 1);
    int rc;
    PSIM_TIMED(e, EPHASE_EVENTS, rc = event_run_until(e, m, T));
    if (rc > 0)
        return psim_engine_stopped(e, err);
    if (rc) {
        psim_error_set(err, "out of memory for the event calendar at step %ld", e->step + 1);
        return -1;
    }
    PSIM_TIMED(e, EPHASE_SYNC, sync_store(e, m, T));
    return 0;
}

/* --check: after every step, every disk inside the walls, no two disks
 * closer than 2r (both to a relative 1e-9: round-off), and the kinetic
 * energy that of the start to a relative 1e-12. */
static int check(psim_sim *e, void *p, const psim_snapshot *before,
                 const psim_snapshot *after, psim_error *err)
{
    const emodel *m = p;
    (void)before;
    const double tol = 1e-9 * m->r, lim = m->sigma2 * (1 - 2e-9);
    double k = 0;
    for (long i = 0; i < after->n; i++) {
        double x = after->x[i], y = after->y[i];
        k += after->vx[i] * after->vx[i] + after->vy[i] * after->vy[i];
        if (!(x >= m->lo - tol && x <= m->hi + tol && y >= m->lo - tol && y <= m->hi + tol)) {
            psim_error_set(err, "step %ld: disk %ld at (%.17g, %.17g) is outside the walls",
                           e->step, i, x, y);
            return -1;
        }
        int32_t c = event_cell(m, m->d[i].cx, m->d[i].cy);
        for (int o = 0; o < 9; o++)   /* the grid's border: no bounds to check */
            for (int32_t j = m->head[c + m->around[o]]; j >= 0; j = m->d[j].next) {
                double dx = after->x[j] - x, dy = after->y[j] - y;
                if (j > i && dx * dx + dy * dy < lim) {
                    psim_error_set(err, "step %ld: disks %ld and %d overlap (centres "
                                        "%.17g apart, 2r = %g)",
                                   e->step, i, j, sqrt(dx * dx + dy * dy), 2 * m->r);
                    return -1;
                }
            }
    }
    double k0 = e->stats.value[EV_KINETIC0];
    if (fabs(k / 2 - k0) > 1e-12 * k0) {
        psim_error_set(err, "step %ld: kinetic energy %.17g, %.3g relative from the start's",
                       e->step, k / 2, (k / 2 - k0) / k0);
        return -1;
    }
    return 0;
}

const psim_model psim_model_event = {
    .name = "event",
    .summary = "exact event-driven hard disks: the truth for accuracy reports",
    .phases = {[EPHASE_EVENTS - PSIM_PHASE_MODEL] = "events",
               [EPHASE_SYNC - PSIM_PHASE_MODEL] = "sync",
               [EPHASE_END - PSIM_PHASE_MODEL] = NULL},
    .thermo = {"collisions", "wall_hits", NULL},
    .counters = {[EC_COLLISIONS] = "collisions",
                 [EC_WALLS] = "wall_hits",
                 [EC_CROSSINGS] = "cell_crossings",
                 [EC_STALE] = "stale_events",
                 [EC_PREDICTIONS] = "predictions",
                 [EC_END] = NULL},
    .values = {[EV_TIME] = "time",
               [EV_KINETIC0] = "kinetic0",
               [EV_KINETIC] = "kinetic",
               [EV_VIRIAL] = "virial",
               [EV_WALL_IMPULSE] = "wall_impulse",
               [EV_END] = NULL},
    .output = {.final = 1},
    .output_digits = -1,
    .work_unit = "events",
    /* (the model checks what depends on the scene: restart_disk_bad) */
    .restart_cols = {{"t_own", 0, 0, PSIM_MAX_STEPS},
                     {"x_own", 0, -DBL_MAX, DBL_MAX},
                     {"y_own", 0, -DBL_MAX, DBL_MAX},
                     {"cell_x", 1, 0, INT32_MAX},
                     {"cell_y", 1, 0, INT32_MAX},
                     {"last", 1, -1, INT32_MAX - 1}},
    .restart_save = restart_save,
    .options = {{"calendar", "1: Paul's calendar (buckets, the current one sorted; default); "
                             "0: one binary heap (the baseline)", 0, 1, 1},
                {NULL, NULL, 0, 0, 0}},
    .limits = limits,
    .create = create,
    .interact = interact,
    .check = check,
    .one_process = "its events near a domain's side can change the other side's future "
                   "at any time (docs/scale-out.md)",
    .destroy = destroy,
};
