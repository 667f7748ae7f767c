/* How many threads a step takes: all of --threads, or one.
 *
 * A team costs its start and its barriers, a few microseconds each on a
 * VM; a scene of a hundred disks makes steps of tens of microseconds,
 * which two threads make slower, not faster.  The engine decides from
 * what it measures of each step: its wall time S and the work its
 * threads did, W (their busy seconds, psim_thread_stats).
 *   - A step on every thread whose work W is at least TEAM_SURE x S had
 *     its threads working together: the threads pay, nothing is tried.
 *   - Otherwise one thread is tried against all of them, alternately, two
 *     steps each (a probe); the faster takes the next steps (a hold).  A
 *     hold starts at TEAM_HOLD_MIN steps and doubles while probes keep
 *     choosing the same, up to TEAM_HOLD_MAX; steps whose time moves
 *     past a factor TEAM_DRIFT of the choice's (a moving average) end it
 *     early: the scene's work changed.
 * Every model's results are the same bytes for any number of threads, so
 * the choice cannot change them.  With --fixed-threads every step takes
 * every thread (tests, scaling measurements). */
#ifndef PSIM_ENGINE_TEAM_H
#define PSIM_ENGINE_TEAM_H

typedef struct psim_team {
    int max;          /* the threads asked for */
    int fixed;        /* every step on max */
    int now;          /* this step's */
    int warm;         /* the first step: not measured (first touch) */
    int probe;        /* probe steps left; 0: holding */
    double best[2];   /* the fastest probe step: [0] one thread, [1] max */
    int choice;       /* 0: one thread, 1: max (holding) */
    double base;      /* the choice's step time */
    double avg;       /* the held steps' time, a moving average */
    long hold, left;  /* the hold's steps, and those left of it */
} psim_team;

void psim_team_init(psim_team *t, int max, int fixed);
/* The threads for the next step. */
int psim_team_next(psim_team *t);
/* The step's wall seconds and its threads' busy seconds. */
void psim_team_done(psim_team *t, double wall, double work);

#endif
