/* Restart files (--restart): the header line and the line order the
 * scene reader keeps (restart.c). */
#ifndef PSIM_IO_RESTART_H
#define PSIM_IO_RESTART_H
#include "scene.h"
#include "restart_schema.h"

/* The first line "#psim restart 1 KEY=VALUE ..." of file name at line:
 * into sc->restart (and sc->format, sc->print), checked against the
 * schema of the model it names.  0, or -1 with err set. */
int psim_restart_header(psim_scene *sc, const char *text, const char *name, long line,
                        psim_restart_schema_fn schema, psim_error *err);
/* The model's columns of sc->n particles (after the header is read). */
int psim_restart_alloc_columns(psim_scene *sc, psim_error *err);
/* sc->restart.order from sc->line (after the particles are read). */
int psim_restart_order(psim_scene *sc, psim_error *err);
void psim_restart_free(psim_restart *rs);
/* The column called name if the file was written by model (by id), or NULL. */
const double *psim_restart_column(const psim_scene *sc, const char *model, const char *name);
/* The model's value called name if the file was written by model: 0 with
 * *v set, or -1. */
int psim_restart_value(const psim_scene *sc, const char *model, const char *name, double *v);

#endif
