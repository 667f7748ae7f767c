/* What a model allows in its restart files (restart_schema.c): the header
 * held to it, and its columns' values read as it declares them. */
#ifndef PSIM_IO_RESTART_SCHEMA_H
#define PSIM_IO_RESTART_SCHEMA_H
#include <stddef.h>

#include "scene.h"

/* What a model's restart files hold beyond a scene; the reader refuses
 * anything else.  The composing layer gives one per model
 * (src/models/scene.c): this layer knows no model. */
typedef struct psim_restart_schema {
    const psim_restart_col *cols;   /* its columns, name NULL ends them: all required */
    const char *const *values;      /* the values it may carry, NULL ends them */
    /* its options "K=V,..." (each once): 0, or -1 with err set */
    int (*options_ok)(const void *ctx, const char *text, psim_error *err);
    const void *ctx;
} psim_restart_schema;
/* The schema of the model called name: 0 with *out set, or -1 (none such). */
typedef int (*psim_restart_schema_fn)(const char *name, psim_restart_schema *out);

/* The header read into sc->restart against the schema of its model: the
 * model known, its options, values and columns (sc->restart.colspec set).
 * 0, or -1 with err set to "FILE:LINE: restart header: ...". */
int psim_restart_check(psim_scene *sc, psim_restart_schema_fn schema, const char *name,
                       psim_error *err);

/* The value of column c at s (a field of a particle line, s at its first
 * byte): the end of the number, with *out set, or NULL where the text is
 * not a value of the column (not a number, not a whole number for an
 * integer column, outside its range).  With padded, up to 8 bytes past
 * the number may be read (the block reader's buffer has room there). */
const char *psim_restart_scan(const psim_restart_col *c, const char *s, int padded,
                              double *out);

/* "particle ID: COL (field K) must be ..., got 'TEXT'" for the field of
 * column k at s (NULL or blank: missing) into buf. */
void psim_restart_field_error(const psim_restart *rs, int k, long id, const char *s,
                              char *buf, size_t size);

#endif
