/* The discrete model behind the model interface. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "discrete.h"
#include "../../engine/cpu.h"
#include "../../engine/tstats.h"
#include "../../engine/mem.h"

/* Forward tile directions and the axis whose parity splits their chains:
 * creating even links before odd ones lets independent edge tasks start
 * together, while the depend clauses keep the order of conflicting ones. */
static const struct { int dx, dy, axis; } forward[4] = {
    {1, 0, 0}, {0, 1, 1}, {1, 1, 1}, {-1, 1, 1}};

static int build_edges(const psim_grid *g, dmodel *m)
{
    m->edges = psim_alloc(4 * (size_t)m->ntiles * sizeof *m->edges);
    m->edge_res = psim_calloc(4 * (size_t)m->ntiles * sizeof *m->edge_res);
    if (!m->edges || !m->edge_res)
        return -1;
    m->nedges = 0;
    for (int f = 0; f < 4; f++)
        for (int parity = 0; parity < 2; parity++) {
            m->level0[2 * f + parity] = m->nedges;
            for (uint32_t t = 0; t < m->ntiles; t++) {
                int tx = g->tile_x[t], ty = g->tile_y[t];
                if (((f == 0 ? tx : ty) & 1) != parity)
                    continue;
                int ux = tx + forward[f].dx, uy = ty + forward[f].dy;
                if (ux < 0 || uy < 0 || ux >= g->TG || uy >= g->TG)
                    continue;
                int dir = (forward[f].dx + 1) + 3 * (forward[f].dy + 1);
                m->edges[m->nedges++] =
                    (dedge){t, g->tile_of_xy[uy * g->TG + ux], dir};
            }
        }
    m->level0[EDGE_LEVELS] = m->nedges;
    return 0;
}

/* Split every tile's cell range into chunks of at most CHUNK_CELLS. */
static int build_chunks(const psim_grid *g, dmodel *m)
{
    m->tile_chunk0 = psim_alloc(((size_t)m->ntiles + 1) * sizeof *m->tile_chunk0);
    if (!m->tile_chunk0)
        return -1;
    uint32_t n = 0;
    for (uint32_t t = 0; t < m->ntiles; t++)
        n += (g->tile_cell0[t + 1] - g->tile_cell0[t] + CHUNK_CELLS - 1) / CHUNK_CELLS;
    m->chunks = psim_calloc((size_t)n * sizeof *m->chunks);
    if (!m->chunks)
        return -1;
    m->nchunks = 0;
    for (uint32_t t = 0; t < m->ntiles; t++) {
        m->tile_chunk0[t] = m->nchunks;
        for (uint32_t c = g->tile_cell0[t]; c < g->tile_cell0[t + 1]; c += CHUNK_CELLS) {
            dchunk *ch = &m->chunks[m->nchunks++];
            ch->tile = t;
            ch->c0 = c;
            ch->c1 = c + CHUNK_CELLS < g->tile_cell0[t + 1] ? c + CHUNK_CELLS
                                                            : g->tile_cell0[t + 1];
        }
    }
    m->tile_chunk0[m->ntiles] = m->nchunks;
    return 0;
}

/* The per-tile state: tiles, their chunks and edges, one dependence
 * object each, sized from e->grid (made anew after a re-plan). */
static void tile_state_free(dmodel *m)
{
    for (uint32_t t = 0; m->tiles && t < m->ntiles; t++) {
        dtile *d = &m->tiles[t];
        psim_free(d->in.c);
        for (int k = 0; k < DIRS; k++)
            psim_free(d->cross[k].c);
        psim_free(d->adj0);
        psim_free(d->adj);
        psim_free(d->queue);
        psim_free(d->acts);
    }
    for (uint32_t k = 0; m->chunks && k < m->nchunks; k++) {
        psim_free(m->chunks[k].in.c);
        for (int d = 0; d < DIRS; d++)
            psim_free(m->chunks[k].cross[d].c);
    }
    psim_free(m->chunks);
    psim_free(m->tile_chunk0);
    psim_free(m->tiles);
    psim_free(m->edges);
    psim_free(m->edge_res);
    psim_free(m->dep);
    psim_free(m->order);
    free(m->owner), free(m->tcost), free(m->tflags);
    m->owner = NULL, m->tcost = NULL, m->tflags = NULL;
    m->chunks = NULL, m->tile_chunk0 = NULL, m->tiles = NULL;
    m->edges = NULL, m->edge_res = NULL, m->dep = NULL, m->order = NULL;
    m->ntiles = m->nchunks = 0;
    m->nedges = 0;
}

static int tile_state_build(const psim_sim *e, dmodel *m)
{
    tile_state_free(m);
    m->ntiles = e->grid.ntiles;
    m->tiles = psim_calloc(m->ntiles * sizeof *m->tiles);
    m->dep = psim_calloc(m->ntiles);
    m->order = psim_alloc(m->ntiles * sizeof *m->order);
    if (!m->tiles || !m->dep || !m->order || build_edges(&e->grid, m) ||
        build_chunks(&e->grid, m))
        return -1;
    if (m->ranks > 1 && (!(m->owner = calloc(m->ntiles, sizeof *m->owner)) ||
                         !(m->tcost = calloc(m->ntiles, sizeof *m->tcost)) ||
                         !(m->tflags = calloc((size_t)m->ntiles + 3, sizeof *m->tflags))))
        return -1;
    return 0;
}

static void destroy(void *p)
{
    dmodel *m = p;
    if (!m)
        return;
    tile_state_free(m);
    psim_free(m->active);
    psim_free(m->border);
    psim_free(m->flag);
    psim_free(m->nearwall);
    psim_free(m->work);
    discrete_parts_free(m);
    discrete_ranks_free(m);
    free(m);
}

/* The largest radius, positions and speeds the collision rule can be
 * carried out for (collide.h), where there is a pair: a lone disk only
 * moves, and a move past the largest double is a state that overflowed
 * (reported as such after the step).  With S the speed one disk may reach
 * (model.h), a contact has |dp| <= 2r and |dv| <= sqrt(2) S: (2r)^2,
 * dv.dp <= 2.9 r S and a new velocity <= 2.5 S stay finite below these
 * bounds, and so do the positions, which stay within max(|x|, L) + 2 S
 * (walls turn a disk back), their differences and the grid's extent.
 * Past (2r)^2 every pair is a contact and the rule divides infinities;
 * past dv.dp a collision gives NaN velocities although the state is
 * finite.  The bounds leave a factor of at least 3 below the largest
 * double (1e4 for the radius). */
#define DISCRETE_MAX_LENGTH 1e307
#define DISCRETE_MAX_RADIUS 1e152
#define DISCRETE_MAX_SPEED 1e307
#define DISCRETE_MAX_RADIUS_SPEED 1e306

static int limits(const psim_sim *e, const psim_scene *sc, psim_limits *lim, psim_error *err)
{
    (void)sc, (void)err;
    if (e->n < 2)
        return 0;
    lim->at[PSIM_LIMIT_BOX] = (psim_limit){DISCRETE_MAX_LENGTH,
                                           "its positions after a move (up to L + 2 S)"};
    lim->at[PSIM_LIMIT_POSITION] = (psim_limit){
        DISCRETE_MAX_LENGTH, "its differences of positions (up to 2 (|x| + 2 S))"};
    lim->at[PSIM_LIMIT_RADIUS] = (psim_limit){DISCRETE_MAX_RADIUS,
                                              "its contact distance (2r)^2"};
    lim->at[PSIM_LIMIT_SPEED] = (psim_limit){
        DISCRETE_MAX_SPEED, "its velocities after a collision (up to 2.5 S)"};
    lim->at[PSIM_LIMIT_RADIUS_SPEED] = (psim_limit){
        DISCRETE_MAX_RADIUS_SPEED, "its contacts' dv.dp (up to 2.9 r S)"};
    return 0;
}

static void *create(psim_sim *e, const psim_scene *sc, psim_error *err)
{
    (void)sc;
    dmodel *m = calloc(1, sizeof *m);
    if (!m)
        goto oom;
    m->regrid = psim_engine_option(e, "regrid", 1) != 0;
    m->balance = psim_engine_option(e, "balance", 1) != 0;
    m->simd = psim_engine_option(e, "simd", 1) != 0 && psim_have_avx512();
    psim_engine_tile_particles(e, DISCRETE_TILE_PARTICLES);
    /* cells wider than 2r over the region the disks occupy: contacts are
     * in the same or adjacent cells (regrid.c) */
    if (discrete_plan_grid(e, m))
        goto oom;
    m->four_r2 = 4.0 * e->r * e->r;
    double settle = psim_engine_option(e, "settle", SETTLE_DEFAULT);
    m->budget = (uint64_t)(settle * (double)(e->n > 0 ? e->n : 1));
    m->gens = (uint32_t)psim_engine_option(e, "gens", 1);
    m->take = psim_engine_option(e, "rounds", 1) != 0;
    m->fl.enabled = psim_engine_option(e, "skip", 1) != 0;
    if (discrete_ranks_init(e, m))
        goto oom;
    m->fl.gap = -1;
    m->fl.walls = 1;
    m->fl.quiet = 1;   /* the first drift looks at the velocities */
    m->active = psim_calloc((size_t)e->n + 1);
    m->border = psim_calloc((size_t)e->n + 1);
    m->flag = psim_calloc((size_t)e->n + 1);
    m->nearwall = psim_calloc((size_t)e->n + 1);
    m->work = psim_calloc(((size_t)e->n + 1) * sizeof *m->work);
    if (!m->active || !m->border || !m->flag || !m->nearwall || !m->work ||
        tile_state_build(e, m))
        goto oom;
    return m;
oom:
    destroy(m);
    psim_error_set(err, "out of memory for the discrete model");
    return NULL;
}

/* The sort, and a new grid when the disks have left the old one (the
 * tiles made anew and the store sorted by it). */
static int sort_and_fit(psim_sim *e, dmodel *m, psim_error *err)
{
    psim_engine_sort(e);
    int rc;
    PSIM_TIMED(e, PSIM_PHASE_SORT, rc = discrete_regrid(e, m));
    if (rc > 0 && tile_state_build(e, m) == 0) {
        psim_engine_sort(e);
        return 0;
    }
    if (rc == 0)
        return 0;
    psim_error_set(err, "out of memory for the grid at step %ld", e->step + 1);
    return -1;
}

static int contacts_oom(const psim_sim *e, psim_error *err)
{
    psim_error_set(err, "out of memory for contacts at step %ld", e->step + 1);
    return -1;
}

static int interact(psim_sim *e, void *p, psim_error *err)
{
    dmodel *m = p;
    PSIM_TIMED(e, PSIM_PHASE_MOVE, discrete_drift(e, m));
    if (discrete_free_flight(e, m)) {
        m->fl.quiet = 1;
        if (m->fl.walls)
            PSIM_TIMED(e, DPHASE_RESOLVE, discrete_walls_only(e, m));
        return 0;
    }
    if (sort_and_fit(e, m, err))
        return -1;
    PSIM_TIMED(e, DPHASE_CONTACTS, discrete_find_contacts(e, m));
    /* (over ranks, the ranks agree on it in the first round) */
    for (uint32_t t = 0; m->ranks < 2 && t < m->ntiles; t++)
        if (m->tiles[t].oom)
            return contacts_oom(e, err);
    int rc;
    PSIM_TIMED(e, DPHASE_RESOLVE, rc = discrete_resolve(e, m));
    if (rc == -2)
        return contacts_oom(e, err);
    /* (the search's figures, over ranks every rank's once resolved) */
    discrete_flight_searched(e, m);
    if (rc && psim_stop_requested())
        return psim_engine_stopped(e, err);
    if (rc) {
        dgroup g;
        discrete_unsettled(e, m, &g);
        psim_error_set(err,
            "step %ld: collisions did not settle within %llu resolutions "
            "(%g per disk, --option settle=K): %llu disks in [%g, %g] x [%g, %g] "
            "(lowest id %d) still approach each other; the scene is too dense "
            "for the discrete model's fixpoint",
            e->step + 1, (unsigned long long)m->budget,
            psim_engine_option(e, "settle", SETTLE_DEFAULT), (unsigned long long)g.disks,
            g.x0, g.x1, g.y0, g.y1, g.first_id);
        return -1;
    }
    PSIM_TIMED(e, PSIM_PHASE_SORT, rc = discrete_balance(e, m));
    if (rc > 0)
        rc = tile_state_build(e, m);
    if (rc < 0) {
        psim_error_set(err, "out of memory for the tiles at step %ld", e->step + 1);
        return -1;
    }
    return 0;
}

static void step_summary(FILE *f, const psim_stats *st)
{
    double steps = st->steps > 0 ? (double)st->steps : 1.0;
    const uint64_t *c = st->counter;
    fprintf(f, "  per step: %.0f contacts, %.1f rounds (max %llu), %.0f pair and %.0f wall "
               "resolutions, %.0f tasks\n",
            (double)c[DC_CONTACTS] / steps, (double)c[DC_ROUNDS] / steps,
            (unsigned long long)c[DC_MAX_ROUNDS], (double)c[DC_PAIR_RES] / steps,
            (double)c[DC_WALL_RES] / steps, (double)c[DC_TASKS] / steps);
    if (c[DC_CUTS])
        fprintf(f, "  tiles cut anew %llu time%s, where the work was\n",
                (unsigned long long)c[DC_CUTS], c[DC_CUTS] == 1 ? "" : "s");
    if (c[DC_REGRIDS])
        fprintf(f, "  grid planned again %llu times: the disks left it or gathered inside it\n",
                (unsigned long long)c[DC_REGRIDS]);
}

const psim_model psim_model_discrete = {
    .name = "discrete",
    .summary = "CS3210 AY2024/25: move every disk, then resolve collisions to a fixpoint",
    .phases = {[DPHASE_CONTACTS - PSIM_PHASE_MODEL] = "contacts",
               [DPHASE_RESOLVE - PSIM_PHASE_MODEL] = "resolve",
               [DPHASE_END - PSIM_PHASE_MODEL] = NULL},
    .thermo = {"pair_resolutions", "wall_resolutions", NULL},
    .counters = {[DC_CONTACTS] = "contacts",
                 [DC_ROUNDS] = "rounds",
                 [DC_MAX_ROUNDS] = "max_rounds",
                 [DC_PAIR_CHECKS] = "pair_checks",
                 [DC_PAIR_RES] = "pair_resolutions",
                 [DC_WALL_RES] = "wall_resolutions",
                 [DC_TASKS] = "tasks",
                 [DC_MAX_STEP_RES] = "max_step_resolutions",
                 [DC_SEARCH_TESTS] = "search_tests",
                 [DC_REGRIDS] = "regrids",
                 [DC_CUTS] = "tile_cuts",
                 [DC_END] = NULL},
    .options = {{"settle", "resolutions a step may take per disk before the run stops "
                           "(default 1000)", 1, 1e9, 1},
                {"simd", "0: contact search without AVX-512 even where the CPU has it "
                         "(same results)", 0, 1, 1},
                {"regrid", "0: plan the grid once, over the disks' bounding box at the start, "
                           "and keep it (default 1: follow the disks)", 0, 1, 1},
                {"balance", "0: tiles of the grid's square blocks of cells (default 1: "
                            "cut where the work is, every 8 steps)", 0, 1, 1},
                {"gens", "generations of its worklist a tile resolves in a round, before "
                         "the contacts across tiles (default 1; 0: to its fixpoint)", 0, 1e9, 1},
                {"rounds", "a round's tiles on threads: 1 heaviest first, each taken by the "
                           "first thread free (default); 0 a task a tile, in the task graph "
                           "with the edges (same results)", 0, 1, 1},
                PSIM_SKIP_OPTION,
                {NULL, NULL, 0, 0, 0}},
    .skips = {[DS_SEARCH] = {"search", "no pair could meet: sort, contacts, resolution"},
              [DS_WALLS] = {"walls", "no disk could reach a wall"},
              [DS_MOVE] = {"move", "nothing moves"},
              [DS_GRAPH] = {"task_graph", "one thread: resolution tasks run in order"}},
    .work_unit = "resolutions",
    .output = {.final = 1},
    .output_digits = -1,
    .step_summary = step_summary,
    .follows_order = 1,
    .shares = 1,
    .limits = limits,
    .create = create,
    .interact = interact,
    .check = discrete_check,
    .destroy = destroy,
};
