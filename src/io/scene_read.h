/* The scene reader (scene_read.c), given the restart files' schemas: the
 * public psim_scene_read and psim_scene_read_stream are these with the
 * models' own (src/models/scene.c), since this layer knows no model. */
#ifndef PSIM_IO_SCENE_READ_H
#define PSIM_IO_SCENE_READ_H
#include <stdio.h>

#include "scene.h"
#include "restart_schema.h"

int psim_io_scene_read(const char *path, psim_restart_schema_fn schema, psim_scene *sc,
                       psim_error *err);
int psim_io_scene_read_stream(FILE *f, const char *name, psim_restart_schema_fn schema,
                              psim_scene *sc, psim_error *err);

/* Tests: the scene reader's block size and smallest piece per thread
 * (0: the defaults, 8 MiB and 64 KiB). */
void psim_io_set_blocks(size_t block, size_t piece);

#endif
