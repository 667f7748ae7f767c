/* Fuzz target: the scene reader (both formats), then, for a scene it
 * accepts that is small enough, a few checked steps of every model.  A
 * crash, a sanitizer report or a hang is a finding; an error is not. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "fuzz.h"
#include "io/scene.h"

/* The first integer of the input after blank space and an optional
 * restart line (saturating; 0 when there is none). */
static double header_count(const uint8_t *data, size_t size)
{
    size_t i = 0;
    while (i < size && (data[i] == ' ' || data[i] == '\t' || data[i] == '\r' ||
                        data[i] == '\n' || data[i] >= 0x80 || data[i] == '#')) {
        if (data[i] == '#')   /* a restart file's first line */
            while (i < size && data[i] != '\n')
                i++;
        else
            i++;
    }
    double n = 0;
    while (i < size && data[i] >= '0' && data[i] <= '9' && n < 1e18)
        n = n * 10 + (data[i++] - '0');
    return n;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0 || header_count(data, size) > FUZZ_MAX_READ)
        return 0;
    FILE *f = fmemopen((void *)data, size, "r");
    if (!f)
        return 0;
    psim_scene sc = {0};
    psim_error err = {{0}, 0};
    int rc = psim_scene_read_stream(f, "fuzz.in", &sc, &err);
    fclose(f);
    if (rc)
        return 0;
    if (sc.n <= FUZZ_MAX_DISKS)
        for (int m = 0; m < psim_model_count(); m++)
            fuzz_run(&sc, psim_model_name(m), NULL, FUZZ_STEPS);
    psim_scene_clear(&sc);
    return 0;
}
