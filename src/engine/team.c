#include "team.h"

/* Work at least this many times the wall time: the threads worked
 * together for most of the step. */
#define TEAM_SURE 1.3
/* Probe steps: one thread and every thread in turn, this many each. */
#define TEAM_PROBE 2
#define TEAM_HOLD_MIN 64
#define TEAM_HOLD_MAX 4096
/* Held steps this many times slower or faster than the choice's probe
 * (their moving average) end the hold. */
#define TEAM_DRIFT 2.0

void psim_team_init(psim_team *t, int max, int fixed)
{
    *t = (psim_team){.max = max, .fixed = fixed || max < 2, .now = max, .warm = 1,
                     .choice = 1, .hold = TEAM_HOLD_MIN / 2};
}

static void start_probe(psim_team *t)
{
    t->probe = 2 * TEAM_PROBE;
    t->best[0] = t->best[1] = -1;
}

int psim_team_next(psim_team *t)
{
    if (t->fixed || t->warm)
        t->now = t->max;
    else if (t->probe)   /* one thread first, then every thread, in turn */
        t->now = (t->probe & 1) ? t->max : 1;
    else
        t->now = t->choice ? t->max : 1;
    return t->now;
}

static void decide(psim_team *t)
{
    const int choice = t->best[0] < t->best[1] ? 0 : 1;
    t->hold = choice == t->choice && t->hold < TEAM_HOLD_MAX ? 2 * t->hold : TEAM_HOLD_MIN;
    t->choice = choice;
    t->base = t->avg = t->best[choice];
    t->left = t->hold;
}

void psim_team_done(psim_team *t, double wall, double work)
{
    if (t->fixed)
        return;
    if (t->warm) {
        t->warm = 0;
        return;
    }
    if (t->probe) {
        const int k = t->now == 1 ? 0 : 1;
        if (t->best[k] < 0 || wall < t->best[k])
            t->best[k] = wall;
        if (--t->probe == 0)
            decide(t);
        return;
    }
    /* every thread, working together: no probe (and a hold of one
     * thread's ends when its time drifts) */
    if (t->now == t->max && work >= TEAM_SURE * wall)
        return;
    t->avg += (wall - t->avg) / 8;   /* (one slow step is no drift) */
    const int drift = t->base > 0 && (t->avg > TEAM_DRIFT * t->base || t->avg * TEAM_DRIFT < t->base);
    if (--t->left <= 0 || drift || t->base <= 0)
        start_probe(t);
}
