/* psim — public API of the psim library.
 *
 * A scene is read (or built) by id; a simulation owns the particles in its
 * own structure-of-arrays store, re-sorted every step, and hands the state
 * back by id.  Nothing here depends on the CLI. */
#ifndef PSIM_PSIM_H
#define PSIM_PSIM_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PSIM_VERSION "0.1.0"

/* One error message, "FILE:LINE: what" where a file is involved. */
typedef struct psim_error {
    char msg[512];
} psim_error;

void psim_error_set(psim_error *err, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* ---- scenes ------------------------------------------------------------ */

/* A scene, by particle id 0..n-1. */
typedef struct psim_scene {
    long n;         /* particles */
    double L;       /* box side: the box is [0, L] x [0, L] */
    double r;       /* disk radius */
    long steps;     /* steps to run */
    double *x, *y, *vx, *vy;
} psim_scene;

/* Allocate the arrays of a scene of n particles (zeroed). */
int psim_scene_alloc(psim_scene *sc, long n, psim_error *err);
void psim_scene_free(psim_scene *sc);

/* Read a CS3210 AY2024/25 scene: lines N, L, r, S, then N lines
 * "i x y vx vy".  On error fills err with "PATH:LINE: message". */
int psim_scene_read(const char *path, psim_scene *sc, psim_error *err);
int psim_scene_read_stream(FILE *f, const char *name, psim_scene *sc,
                           psim_error *err);
/* Write a scene in the same format (shortest round-trip numbers). */
int psim_scene_write(FILE *f, const psim_scene *sc);

/* Scene generator (the course generator's rules, plus placements). */
typedef enum {
    PSIM_PLACE_UNIFORM = 0,   /* positions uniform in [0, L] (course) */
    PSIM_PLACE_NONOVERLAP,    /* random sequential addition, no overlap */
    PSIM_PLACE_LATTICE        /* jittered square lattice, no overlap */
} psim_place;

typedef struct psim_gen_params {
    long n;
    double L, r;
    long steps;
    double vmin, vmax;        /* velocity components uniform in [vmin, vmax] */
    uint64_t seed;
    psim_place place;
} psim_gen_params;

int psim_scene_generate(const psim_gen_params *p, psim_scene *sc,
                        psim_error *err);
/* Area fraction n * pi * r^2 / L^2. */
double psim_scene_density(const psim_scene *sc);

/* ---- simulation ---------------------------------------------------------- */

typedef enum { PSIM_MODEL_DISCRETE = 0 } psim_model_id;

typedef struct psim_config {
    psim_model_id model;
    int threads;        /* <= 0: omp_get_max_threads() */
    int tile_cells;     /* cells per tile side (power of two); 0: automatic */
    int check;          /* validate every step (the course's checks) */
} psim_config;

void psim_config_default(psim_config *cfg);

/* Timed phases of a step (CoMD-style timers around every phase). */
typedef enum {
    PSIM_PHASE_MOVE = 0,
    PSIM_PHASE_SORT,
    PSIM_PHASE_CONTACTS,
    PSIM_PHASE_RESOLVE,
    PSIM_PHASE_CHECK,
    PSIM_PHASE_OUTPUT,
    PSIM_PHASE_COUNT
} psim_phase;

const char *psim_phase_name(psim_phase p);

typedef struct psim_stats {
    long steps;
    int threads;
    double phase_s[PSIM_PHASE_COUNT]; /* wall time per phase, seconds */
    uint64_t contacts;       /* contacts found (pairs at distance <= 2r), sum over steps */
    uint64_t rounds;         /* resolution rounds (task-graph sweeps), sum */
    uint64_t max_rounds;     /* most rounds in one step */
    uint64_t pair_checks;    /* contact tests made while resolving */
    uint64_t pair_resolutions;
    uint64_t wall_resolutions;
    uint64_t tasks;          /* OpenMP tasks created */
    int grid_cells;          /* cells per side */
    double cell_side;        /* side of a cell (> 2r) */
    int tile_cells;          /* cells per tile side */
    int tiles;               /* tiles holding cells */
} psim_stats;

typedef struct psim_sim psim_sim;

psim_sim *psim_create(const psim_scene *sc, const psim_config *cfg,
                      psim_error *err);
/* Advance one step.  Returns 0, or -1 with err set: a --check violation,
 * collisions that do not settle, or no memory for the contacts. */
int psim_step(psim_sim *s, psim_error *err);
long psim_step_index(const psim_sim *s);   /* steps done so far */
long psim_count(const psim_sim *s);
/* Current state by id; any pointer may be NULL. */
void psim_get_state(const psim_sim *s, double *x, double *y, double *vx,
                    double *vy);
const psim_stats *psim_get_stats(const psim_sim *s);

/* What one OpenMP thread did, per phase: time busy in its own work items
 * (a waiting thread is not busy), work items (tiles, tasks, chunks) and
 * particles handled, and the CPU it was last seen on. */
typedef struct psim_thread_stats {
    double busy_s[PSIM_PHASE_COUNT];
    uint64_t items[PSIM_PHASE_COUNT];
    uint64_t particles[PSIM_PHASE_COUNT];
    uint64_t wall_resolutions;
    int cpu;
} __attribute__((aligned(64))) psim_thread_stats;

const psim_thread_stats *psim_get_thread_stats(const psim_sim *s, int *threads);
/* Account time the caller spent writing output (phase "output"). */
void psim_add_output_time(psim_sim *s, double seconds);
void psim_destroy(psim_sim *s);

/* ---- output -------------------------------------------------------------- */

/* Room for any double: 309 integer digits, sign, point, 30 decimals. */
#define PSIM_FORMAT_MAX 352
#define PSIM_DIGITS_MAX 30

/* Format v into buf (PSIM_FORMAT_MAX bytes): digits < 0 gives the shortest
 * text that reads back to the same double; 0 <= digits <= PSIM_DIGITS_MAX
 * gives fixed notation with that many decimals and no negative zero.
 * Returns the length written. */
int psim_format_double(char *buf, double v, int digits);

/* Write lines "STEP i x y vx vy" for every particle in id order. */
int psim_write_state(FILE *f, long step, long n, const double *x,
                     const double *y, const double *vx, const double *vy,
                     int digits);

/* Write the run's statistics as one JSON object.  scene_name may be NULL;
 * extra, if not NULL, holds more members ("key": value, ...) to include. */
int psim_write_stats_json(FILE *f, const psim_sim *s, const char *scene_name,
                          double total_s, const char *extra);

/* Name of the allocator psim was built with ("jemalloc" or "libc"). */
const char *psim_allocator(void);

#ifdef __cplusplus
}
#endif
#endif
