/* The event model: exact event-driven dynamics of equal hard disks.
 *
 * Disks fly free between events; each disk's state is kept at its own
 * time (the time of its last event) and brought forward only when an
 * event involves it.  Events: disk-disk collisions at the contact time
 * (elastic, equal masses), reflections off the walls x, y = r and L - r,
 * and crossings of the cells of the model's grid (cells at least 2r wide,
 * so a disk is tested only against the disks of the 3 x 3 cells around
 * it).  Each disk has a plan (its earliest collision, its next event on
 * each axis) and one event in the calendar (calendar.h), the earliest of
 * its plan; an event goes stale when its disk is planned again, and a
 * planned collision is planned again when the partner's path has changed.
 * One time unit is one step of the scene (velocities are per step), and
 * the state is written to the store at every whole step, for output.
 * The run is sequential: its results do not depend on the thread count. */
#ifndef PSIM_EVENT_H
#define PSIM_EVENT_H
#include <stdint.h>

#include "../../engine/engine.h"
#include "calendar.h"

enum { EPHASE_EVENTS = PSIM_PHASE_MODEL, EPHASE_SYNC, EPHASE_END };
enum { EC_COLLISIONS, EC_WALLS, EC_CROSSINGS, EC_STALE, EC_PREDICTIONS, EC_END };
enum { EV_TIME, EV_KINETIC0, EV_KINETIC, EV_VIRIAL, EV_WALL_IMPULSE, EV_END };

/* A disk at its own time t, in one cache line: a prediction reads the
 * whole of each partner. */
typedef struct edisk {
    double x, y, vx, vy, t;
    uint32_t cnt;           /* path changes (collisions, walls) */
    int32_t last;           /* last collision partner (-1: none since) */
    int32_t cx, cy;         /* cell */
    int32_t next, prev;     /* the cell's other disks, as a list */
} edisk;

/* A disk's plan: its earliest collision (tp with bp, whose path count was
 * cp) and its next event on each axis (ta, of kind ka: cell or wall); the
 * earliest of them is its one event in the calendar, with the schedule
 * count sched. */
typedef struct eplan {
    double tp, ta[2];
    int32_t bp, ka[2];
    uint32_t cp, sched;
} eplan;

typedef struct emodel {
    long n;
    double L, r, sigma2;    /* box side, radius, (2r)^2 */
    double lo, hi;          /* walls for centres: r and L - r */
    int G;                  /* cells per side */
    int32_t around[9];      /* head offsets of the 3 x 3 cells around one */
    double h;               /* cell side L / G >= 2r */
    edisk *d;               /* n disks */
    eplan *plan;            /* n: their plans */
    int32_t *head;          /* first disk of each cell (-1: none), on a grid
                             * with a border of empty cells: see event_cell */
    ecal cal;
    int buckets;            /* the calendar's buckets on (off: a heap) */
    double now;             /* time of the event being processed */
    double virial;          /* sum over collisions of -dr.dv (= r_ab . dp_a) */
    double wall_impulse;    /* sum over wall hits of 2 |v_n| (unit masses) */
} emodel;

/* Cell (cx, cy)'s place in head: the grid has a border of one empty cell
 * on every side, so that the 3 x 3 cells around any cell are there to be
 * read without bounds. */
static inline int32_t event_cell(const emodel *m, int cx, int cy)
{
    return (cy + 1) * (m->G + 2) + (cx + 1);
}

/* run.c */
int event_predict_disk(psim_sim *e, emodel *m, int32_t a);
int event_predict_all(psim_sim *e, emodel *m);
int event_run_until(psim_sim *e, emodel *m, double T);
void event_cell_insert(emodel *m, int32_t i);
void event_cell_remove(emodel *m, int32_t i);

#endif
