/* Reading scenes: the scene reader (src/io/scene_read.c) given what each
 * model allows in its restart files, which only this layer, the one that
 * knows the models, can tell it: the model's columns, the values it
 * measures and its options. */
#include "models.h"
#include "../io/scene_read.h"
#include "../engine/dist.h"

static int options_ok(const void *ctx, const char *text, psim_error *err)
{
    return psim_engine_options_check(ctx, text, err);
}

static int schema_of(const char *name, psim_restart_schema *out)
{
    const psim_model *m = psim_model_find(name);
    if (!m)
        return -1;
    *out = (psim_restart_schema){.cols = m->restart_cols, .values = m->values,
                                 .options_ok = options_ok, .ctx = m};
    return 0;
}

int psim_scene_read(const char *path, psim_scene *sc, psim_error *err)
{
    return psim_io_scene_read(path, schema_of, sc, err);
}

int psim_scene_read_part(const char *path, psim_scene *sc, psim_error *err)
{
    if (psim_dist_ranks() < 2)
        return psim_scene_read(path, sc, err);
    return psim_dist_scene_read(path, schema_of, sc, err);
}

int psim_scene_read_stream(FILE *f, const char *name, psim_scene *sc, psim_error *err)
{
    return psim_io_scene_read_stream(f, name, schema_of, sc, err);
}

psim_scene *psim_scene_load(const char *path, psim_error *err)
{
    psim_scene *sc = psim_scene_new();
    if (!sc) {
        psim_error_set(err, "%s: out of memory", path);
        return NULL;
    }
    if (psim_scene_read(path, sc, err)) {
        psim_scene_free(sc);
        return NULL;
    }
    return sc;
}
