#include <math.h>
#include <stdio.h>

#include "fuzz.h"

/* Whether some disk crosses the box more than FUZZ_MAX_CROSSINGS times in
 * `steps`: the event model then runs that many wall events (a legitimate,
 * slow run: 6.7e7 events in 4.5 s for a disk at 1e8 a step in a box of
 * 20), which would read as a hang to the fuzzer. */
static int too_fast(const psim_scene *sc, long steps)
{
    for (long i = 0; i < sc->n; i++)
        if (!((fabs(sc->vx[i]) + fabs(sc->vy[i])) * (double)steps <= FUZZ_MAX_CROSSINGS * sc->L))
            return 1;
    return 0;
}

void fuzz_run(const psim_scene *sc, const char *model, const char *options, long steps)
{
    if (too_fast(sc, steps))
        return;
    psim_config cfg;
    psim_config_default(&cfg);
    cfg.model = model;
    cfg.threads = 1;
    cfg.check = 1;
    cfg.options = options;
    cfg.steps = sc->steps < steps ? sc->steps : steps;
    psim_error err = {{0}, 0};
    psim_sim *s = psim_create(sc, &cfg, &err);
    if (!s)
        return;
    FILE *null = fopen("/dev/null", "w");
    for (long k = 0; k < cfg.steps; k++) {
        if (psim_step(s, &err) || psim_state_finite(s, &err))
            break;
        if (null)
            psim_write_trace(s, null, k + 1, -1);
    }
    if (null)
        fclose(null);
    psim_destroy(s);
}
