/* How many threads a step takes (src/engine/team.c), driven by made-up
 * step times: one thread chosen where it is faster, every thread where
 * they are, no probe while the threads work together, holds that grow
 * and end when the work changes, and --fixed-threads. */
#include "check.h"
#include "engine/team.h"

/* A made-up machine: a step takes one[] on one thread and all[] on every
 * thread, whose busy seconds are work_all (one thread: its wall time). */
typedef struct scene {
    double one, all, work_all;
} scene;

/* Run steps on sc; returns the steps on one thread. */
static long run(psim_team *t, const scene *sc, long steps)
{
    long single = 0;
    for (long s = 0; s < steps; s++) {
        const int n = psim_team_next(t);
        CHECK(n == 1 || n == t->max);
        single += n == 1;
        const double wall = n == 1 ? sc->one : sc->all;
        psim_team_done(t, wall, n == 1 ? wall : sc->work_all);
    }
    return single;
}

static void one_thread_faster(void)
{
    psim_team t;
    psim_team_init(&t, 2, 0);
    const scene tiny = {1e-5, 1.5e-5, 1.2e-5};   /* threads idle at barriers */
    long single = run(&t, &tiny, 1000);
    /* the first step warms up, then every probe runs two steps on every
     * thread: the rest on one */
    CHECK_MSG(single > 950, "%ld of 1000 steps on one thread", single);
    CHECK(t.choice == 0);
    CHECK(t.hold > 64);   /* the same choice made again: a longer hold */
}

static void threads_faster(void)
{
    psim_team t;
    psim_team_init(&t, 4, 0);
    /* the threads idle half the step (work < 1.3 x wall), but the step is
     * faster than one thread's */
    const scene mid = {4e-4, 2e-4, 2.4e-4};
    long single = run(&t, &mid, 1000);
    CHECK(t.choice == 1);
    CHECK_MSG(single <= 20, "%ld of 1000 steps on one thread", single);
    CHECK(single >= 2);   /* it was tried */
}

static void threads_sure(void)
{
    psim_team t;
    psim_team_init(&t, 2, 0);
    const scene busy = {2e-3, 1.1e-3, 2.0e-3};   /* both threads at work */
    CHECK(run(&t, &busy, 500) == 0);
}

static void work_changes(void)
{
    psim_team t;
    psim_team_init(&t, 2, 0);
    const scene tiny = {1e-5, 1.5e-5, 1.2e-5};
    run(&t, &tiny, 200);
    CHECK(t.choice == 0);
    /* the scene grows heavy: the hold ends within some steps, a probe
     * finds the threads faster and sure of it */
    const scene heavy = {1e-3, 5.5e-4, 1.0e-3};
    long single = run(&t, &heavy, 100);
    CHECK(t.choice == 1);
    CHECK_MSG(single < 30, "%ld of 100 heavy steps on one thread", single);
    CHECK(run(&t, &heavy, 100) == 0);
}

static void fixed(void)
{
    psim_team t;
    psim_team_init(&t, 2, 1);
    const scene tiny = {1e-5, 1.5e-5, 1.2e-5};
    CHECK(run(&t, &tiny, 300) == 0);
    psim_team_init(&t, 1, 0);   /* one thread asked for: nothing to choose */
    CHECK(run(&t, &tiny, 300) == 300);
    CHECK(t.fixed && t.probe == 0);
}

int main(void)
{
    one_thread_faster();
    threads_faster();
    threads_sure();
    work_changes();
    fixed();
    return check_done();
}
