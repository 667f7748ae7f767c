/* The list of models: the layer that composes the engine with the models
 * (the engine itself knows none of them). */
#ifndef PSIM_MODELS_MODELS_H
#define PSIM_MODELS_MODELS_H
#include "../engine/model.h"

const psim_model *psim_model_find(const char *name);
/* Whether model k runs over MPI ranks (it has a halo). */
int psim_model_distributed(int k);

#endif
