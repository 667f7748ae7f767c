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

/* A scene read in parts (over MPI ranks each rank reads a byte range of
 * its particle lines; src/engine/dist_read.c puts them together).
 * psim_io_scene_read_head reads the header alone into sc (N, L, r, S,
 * their lines, the format, the source; no particle arrays) and where the
 * particle lines start: byte `data`, after line line0; `whole` for a
 * scene that is read whole (a restart file with a model's own columns, a
 * 2019 scene).  Refuses a
 * file that is not a regular one.  0, or -1 with err set. */
typedef struct psim_scene_span {
    long long data, size;
    long line0;
    int whole;
} psim_scene_span;
int psim_io_scene_read_head(const char *path, psim_restart_schema_fn schema, psim_scene *sc,
                            psim_scene_span *span, psim_error *err);
/* The first line's start at or after byte off (data: the first particle
 * line's), or the file's end. */
int psim_io_line_start(const char *path, long long data, long long off, long long *start,
                       psim_error *err);
/* The newlines in bytes [a, b). */
int psim_io_count_lines(const char *path, long long a, long long b, long *lines,
                        psim_error *err);
/* The particle lines of bytes [a, b) (whole lines, `lines` newlines, the
 * first being line line0 + 1) into the part sc (n_all set: ids in
 * 0..n_all-1; its arrays allocated here), in the file's order, each with
 * its id and line; duplicates are not looked for (a part cannot see them).  Stops at the first line that is not a
 * particle line: -1 with err set and out->bad saying what it is; out->lines:
 * the lines read. */
enum { PSIM_RANGE_NOT_PARTICLE = 1, PSIM_RANGE_NOT_TEXT, PSIM_RANGE_READ_ERROR };
typedef struct psim_range_read {
    int bad;
    long line;     /* the bad line */
    long lines;
} psim_range_read;
int psim_io_scene_read_range(const char *path, psim_scene *sc, long long a, long long b,
                             long line0, long lines, psim_range_read *out, psim_error *err);

/* Tests: the scene reader's block size and smallest piece per thread
 * (0: the defaults, 8 MiB and 64 KiB). */
void psim_io_set_blocks(size_t block, size_t piece);

#endif
