/* The list of models: the layer that composes the engine with the models
 * (the engine itself knows none of them). */
#ifndef PSIM_MODELS_MODELS_H
#define PSIM_MODELS_MODELS_H
#include "../engine/model.h"

const psim_model *psim_model_find(const char *name);
/* Whether model k runs over MPI ranks (it has a halo, or shares the work). */
int psim_model_distributed(int k);
/* Whether model k has a GPU path (--device gpu; model.h: gpu). */
int psim_model_gpu(int k);
/* psim_generate_scene's part `part` of `parts`: the block of ids
 * n*part/parts .. n*(part+1)/parts - 1 (a part of a scene, scene.h),
 * which is the whole scene when parts is 1. */
/* psim_scene_read, over MPI ranks each rank's part of the scene
 * (psim_dist_scene_read; collective); in one process the whole scene. */
int psim_scene_read_part(const char *path, psim_scene *sc, psim_error *err);
int psim_generate_scene_part(const char *name, long n, uint64_t seed, int part, int parts,
                             psim_scene *sc, psim_error *err);

#endif
