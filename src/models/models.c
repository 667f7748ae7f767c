/* The models psim knows, in the order psim models lists them.  Adding a
 * model (docs/adding-a-model.md): a folder under src/models/ that defines
 * one psim_model, psim_model_NAME, and one line PSIM_MODEL(NAME) in the
 * list below; CMake compiles every src/models/<folder>/<file>.c. */
#include <stdlib.h>
#include <string.h>

#include "models.h"

#define PSIM_MODELS \
    PSIM_MODEL(discrete)   /* CS3210 AY2024/25: move, then collisions to a fixpoint */ \
    PSIM_MODEL(ccd)        /* CS3210 AY2019/20: time-of-impact collisions */ \
    PSIM_MODEL(force)      /* Berkeley CS267 HW2: short-range repulsion */ \
    PSIM_MODEL(event)      /* exact event-driven hard disks */

/* The list twice: each model's value declared, then a pointer to it. */
#define PSIM_MODEL(name) extern const psim_model psim_model_##name;
PSIM_MODELS
#undef PSIM_MODEL
#define PSIM_MODEL(name) &psim_model_##name,
static const psim_model *const models[] = {PSIM_MODELS};
#undef PSIM_MODEL

#define NMODELS ((int)(sizeof models / sizeof models[0]))

int psim_model_count(void) { return NMODELS; }

const char *psim_model_name(int k)
{
    return k >= 0 && k < NMODELS ? models[k]->name : NULL;
}

const char *psim_model_summary(int k)
{
    return k >= 0 && k < NMODELS ? models[k]->summary : NULL;
}

int psim_model_distributed(int k)
{
    return k >= 0 && k < NMODELS && (models[k]->halo != NULL || models[k]->shares);
}

int psim_model_gpu(int k) { return k >= 0 && k < NMODELS && models[k]->gpu; }

const psim_model *psim_model_find(const char *name)
{
    for (int k = 0; k < NMODELS; k++)
        if (strcmp(models[k]->name, name) == 0)
            return models[k];
    return NULL;
}

const char *psim_default_model(const psim_scene *sc)
{
    const psim_model *m = sc->restart.present ? psim_model_find(sc->restart.model) : NULL;
    if (m)   /* a restart file: the model that wrote it */
        return m->name;
    return sc->format == PSIM_SCENE_2019    ? "ccd"
           : sc->format == PSIM_SCENE_CS267 ? "force"
                                            : "discrete";
}

int psim_model_option_info(int k, int i, const char **name, const char **help)
{
    if (k < 0 || k >= NMODELS || i < 0 || i >= PSIM_MODEL_OPTIONS ||
        !models[k]->options[i].name)
        return -1;
    *name = models[k]->options[i].name;
    *help = models[k]->options[i].help;
    return 0;
}

int psim_generate_scene(const char *name, long n, uint64_t seed, psim_scene *sc,
                        psim_error *err)
{
    return psim_generate_scene_part(name, n, seed, 0, 1, sc, err);
}

int psim_generate_scene_part(const char *name, long n, uint64_t seed, int part, int parts,
                             psim_scene *sc, psim_error *err)
{
    const psim_model *m = name ? psim_model_find(name) : NULL;
    for (int k = 0; !name && !m && k < NMODELS; k++)   /* the first that has one */
        if (models[k]->generate)
            m = models[k];
    if (!m || !m->generate) {
        psim_error_set(err, "the %s model has no initialisation of its own: give a scene",
                       m ? m->name : name);
        err->usage = 1;   /* -n with this model: the command line's fault */
        return -1;
    }
    if (n < 0 || n > PSIM_MAX_PARTICLES) {
        psim_error_set(err, "particle count must be between 0 and %ld, got %ld",
                       PSIM_MAX_PARTICLES, n);
        err->usage = 1;
        return -1;
    }
    psim_scene made = {0};
    const long lo = n * part / parts, hi = n * (part + 1) / parts;
    if (m->generate(&made, n, seed, lo, hi, err)) {
        psim_scene_clear(&made);
        return -1;
    }
    if (parts > 1 && !(made.id = malloc((size_t)(hi > lo ? hi - lo : 1) * sizeof *made.id))) {
        psim_error_set(err, "out of memory for %ld particles", hi - lo);
        psim_scene_clear(&made);
        return -1;
    }
    if (parts > 1) {
        made.n_all = n;
        for (long i = lo; i < hi; i++)
            made.id[i - lo] = (int32_t)i;
    }
    psim_scene_clear(sc);
    *sc = made;
    return 0;
}

static psim_sim *create(psim_scene *sc, const psim_config *cfg, int take, psim_error *err)
{
    psim_config dflt;
    if (!cfg) {
        psim_config_default(&dflt);
        cfg = &dflt;
    }
    if (sc->n > 0 && !sc->x) {
        psim_error_set(err, "the scene's disks were taken by an earlier psim_create_taking");
        return NULL;
    }
    const char *name = cfg->model ? cfg->model : psim_default_model(sc);
    const psim_model *m = psim_model_find(name);
    if (!m) {
        psim_error_set(err, "unknown model '%s' (psim models lists them)", name);
        if (err)
            err->usage = 1;
        return NULL;
    }
    return psim_engine_create(sc, cfg, m, take, err);
}

psim_sim *psim_create(const psim_scene *sc, const psim_config *cfg, psim_error *err)
{
    /* not taken: the engine only reads it */
    return create((psim_scene *)sc, cfg, 0, err);
}

psim_sim *psim_create_taking(psim_scene *sc, const psim_config *cfg, psim_error *err)
{
    return create(sc, cfg, 1, err);
}
