/* run_scene: run a scene file through psim's library and print the final
 * state, as `psim --final FILE SCENE` writes it (docs/api.md).
 *
 *   usage: run_scene SCENE [THREADS]
 *
 * The scene runs all its steps with its format's model.  The final state
 * goes to standard output, one line "STEP i x y vx vy" a disk by id, each
 * number the shortest text that reads back to the same double; a summary
 * goes to standard error.  Any failure: one line on standard error, exit
 * status 1 (2 for a wrong command line).
 *
 * Build it with CMake (this folder's CMakeLists.txt) or with pkg-config:
 *
 *   cc run_scene.c $(pkg-config --cflags --libs psim) -o run_scene */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <psim/psim.h>

int main(int argc, char **argv)
{
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: run_scene SCENE [THREADS]\n");
        return 2;
    }
    /* The library this program runs with must be the major version its
     * headers are (the SONAME makes sure of that; the check shows how). */
    if (atoi(psim_version()) != PSIM_VERSION_MAJOR) {
        fprintf(stderr, "run_scene: built for psim %s, runs with %s\n", PSIM_VERSION,
                psim_version());
        return 1;
    }

    /* Every function that can fail fills a psim_error, owned here. */
    psim_error err = {{0}, 0};

    /* 1. The scene: read from its file into a new handle. */
    psim_scene *sc = psim_scene_load(argv[1], &err);
    if (!sc) {
        fprintf(stderr, "run_scene: %s\n", err.msg);
        return 1;
    }
    const long steps = psim_scene_steps(sc), n = psim_scene_count(sc);

    /* 2. The configuration: the defaults (the scene's model, all threads),
     * the threads asked for, and the number of steps the run will take. */
    psim_config cfg;
    psim_config_default(&cfg);
    cfg.threads = argc == 3 ? atoi(argv[2]) : 0;
    cfg.steps = steps;

    /* 3. The simulation holds its own copy of the particles: the scene
     * can go at once. */
    psim_sim *sim = psim_create(sc, &cfg, &err);
    psim_scene_free(sc);
    if (!sim) {
        fprintf(stderr, "run_scene: %s\n", err.msg);
        return 1;
    }

    /* 4. The steps. */
    int rc = 0;
    for (long k = 0; k < steps && rc == 0; k++)
        if (psim_step(sim, &err) != 0 || psim_state_finite(sim, &err) != 0) {
            fprintf(stderr, "run_scene: %s\n", err.msg);
            rc = 1;
        }

    /* 5. The state, by id, into arrays of this program's own. */
    double *x = malloc((size_t)n * sizeof *x + 1), *y = malloc((size_t)n * sizeof *y + 1);
    double *vx = malloc((size_t)n * sizeof *vx + 1), *vy = malloc((size_t)n * sizeof *vy + 1);
    if (rc == 0 && (!x || !y || !vx || !vy)) {
        fprintf(stderr, "run_scene: out of memory for %ld disks\n", n);
        rc = 1;
    }
    if (rc == 0) {
        psim_get_state(sim, x, y, vx, vy);
        char num[4][PSIM_FORMAT_MAX];
        for (long i = 0; i < n; i++) {
            psim_format_double(num[0], x[i], -1);
            psim_format_double(num[1], y[i], -1);
            psim_format_double(num[2], vx[i], -1);
            psim_format_double(num[3], vy[i], -1);
            printf("%ld %ld %s %s %s %s\n", psim_step_index(sim), i, num[0], num[1], num[2],
                   num[3]);
        }
        if (fflush(stdout) != 0 || ferror(stdout)) {
            fprintf(stderr, "run_scene: cannot write the state\n");
            rc = 1;
        }
    }

    /* 6. Statistics: the model's counters, and the time of each phase. */
    if (rc == 0) {
        const psim_stats *st = psim_get_stats(sim);
        fprintf(stderr, "run_scene: psim %s, %s model, %ld disks, %ld steps on %d threads\n",
                psim_version(), psim_sim_model(sim), psim_count(sim), psim_step_index(sim),
                st->threads);
        for (int c = 0; c < st->ncounters; c++)
            fprintf(stderr, "  %s %llu\n", st->counter_name[c],
                    (unsigned long long)st->counter[c]);
        for (int p = 0; p < st->nphases; p++)
            fprintf(stderr, "  phase %s %.6f s\n", st->phase_name[p], st->phase_s[p]);
    }

    free(x), free(y), free(vx), free(vy);
    psim_destroy(sim);
    return rc;
}
