/* Fuzz target: a model's options ("KEY=VALUE,..."), as --option passes
 * them: the first byte picks the model, the rest is the text; the run is
 * a small fixed scene, a few checked steps. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"
#include "io/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1 || size > 4096)
        return 0;
    const char *model = psim_model_name(data[0] % psim_model_count());
    char *options = malloc(size);
    if (!options)
        return 0;
    memcpy(options, data + 1, size - 1);
    options[size - 1] = '\0';
    psim_scene sc = {0};
    psim_error err = {{0}, 0};
    psim_gen_params p = {.n = 40, .L = 60, .r = 1, .steps = 3, .vmin = -1, .vmax = 1,
                         .seed = 1, .place = PSIM_PLACE_NONOVERLAP};
    if (psim_scene_generate(&p, &sc, &err) == 0) {
        fuzz_run(&sc, model, options, FUZZ_STEPS);
        psim_scene_clear(&sc);
    }
    free(options);
    return 0;
}
