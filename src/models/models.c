#include "model.h"

extern const psim_model psim_model_discrete;

const psim_model *psim_model_get(psim_model_id id)
{
    switch (id) {
    case PSIM_MODEL_DISCRETE:
        return &psim_model_discrete;
    }
    return NULL;
}
