/* A program built against the installed psim package, once with CMake
 * (find_package(psim), psim::psim) and once with pkg-config (tests/install/
 * install.sh).  It reads a scene, runs all its steps through the public API
 * at 2 threads and writes the final state as `psim --final` does; the test
 * compares that file with the installed psim's.  On the way it checks the
 * version and allocator it was told to expect, formats a number and loads
 * the machine's topology (hwloc).  Any failure: a line on stderr, exit 1.
 *
 * usage: consumer SCENE OUT VERSION ALLOCATOR */
#include <stdio.h>
#include <string.h>

#include <psim/psim.h>
#include <psim/topology.h>

static int fail(const char *what, const char *detail)
{
    fprintf(stderr, "consumer: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
    return 1;
}

int main(int argc, char **argv)
{
    if (argc != 5)
        return fail("usage: consumer SCENE OUT VERSION ALLOCATOR", NULL);
    if (strcmp(PSIM_VERSION, argv[3]) != 0)
        return fail("psim/psim.h is of another version", PSIM_VERSION);
    if (strcmp(psim_version(), PSIM_VERSION) != 0)
        return fail("the library is of another version than its header", psim_version());
    if (strcmp(psim_allocator(), argv[4]) != 0)
        return fail("the library's allocator is not the one expected", psim_allocator());
    char buf[PSIM_FORMAT_MAX];
    if (psim_format_double(buf, 0.1, -1) != 3 || strcmp(buf, "0.1") != 0)
        return fail("psim_format_double(0.1) is not \"0.1\"", buf);

    psim_error err = {{0}, 0};
    psim_topo *topo = psim_topo_load(NULL, &err);
    if (!topo)
        return fail("psim_topo_load", err.msg);
    psim_topo_free(topo);

    psim_scene *sc = psim_scene_load(argv[1], &err);
    if (!sc)
        return fail("psim_scene_load", err.msg);
    const long steps = psim_scene_steps(sc), n = psim_scene_count(sc);
    psim_config cfg;
    psim_config_default(&cfg);
    cfg.threads = 2;
    cfg.steps = steps;
    psim_sim *s = psim_create(sc, &cfg, &err);
    psim_scene_free(sc);   /* the simulation holds its own copy */
    if (!s)
        return fail("psim_create", err.msg);
    int rc = 0;
    for (long k = 0; k < steps && rc == 0; k++)
        if (psim_step(s, &err))
            rc = fail("psim_step", err.msg);
    if (rc == 0 && (psim_step_index(s) != steps || psim_count(s) != n))
        rc = fail("the step index or particle count is wrong", NULL);
    if (rc == 0 && psim_state_finite(s, &err))
        rc = fail("psim_state_finite", err.msg);
    if (rc == 0) {
        FILE *f = fopen(argv[2], "w");
        if (!f)
            rc = fail("cannot write", argv[2]);
        else if (psim_write_trace(s, f, psim_step_index(s), -1) != 0)
            rc = fail("psim_write_trace failed", NULL);
        if (f && fclose(f) != 0 && rc == 0)
            rc = fail("cannot write", argv[2]);
    }
    if (rc == 0)
        printf("consumer: %s model, %ld disks, %ld steps, psim %s, %s\n", psim_sim_model(s),
               psim_count(s), psim_step_index(s), PSIM_VERSION, psim_allocator());
    psim_destroy(s);
    return rc;
}
