/* The discrete model over MPI ranks (discrete.h; docs/scale-out.md).
 *
 * Every rank holds every disk and drifts, sorts and tiles them as one
 * process does, so the tiles, their contacts and their order are the same
 * on every rank.  The tiles go to the ranks in runs of rows, split by
 * their work in the last step.  A rank searches
 * its own tiles and resolves them round by round as one process does; a
 * round's edges run level by level (EDGE_LEVELS): an edge between two
 * tiles of one rank on that rank, an edge across two ranks on both, each
 * after the other rank's disks of that edge came with the velocities they
 * have after the edges of the levels before.  The two runs of an edge
 * across ranks start from the same velocities and do the same
 * arithmetic, so each rank ends with its own tile's velocities exactly
 * as one process would; its tile's share of the edge's work (the
 * activations, the counts) it keeps, the other tile's it drops.  So every
 * tile sees the same sequence of updates as in one process, and the
 * bytes are the same for any number of ranks.  After the step every rank
 * sends the velocities of its disks that changed to every rank. */
#include <stdlib.h>
#include <string.h>

#include "discrete.h"
#include "../../engine/mem.h"

int discrete_ranks_init(const psim_sim *e, dmodel *m)
{
    m->ranks = psim_engine_ranks(e);
    m->rank = psim_engine_rank(e);
    if (m->ranks < 2)
        return 0;
    m->sbytes = calloc(2 * (size_t)m->ranks, sizeof *m->sbytes);
    m->xn = (size_t)e->n + 1;
    m->xstamp = calloc(m->xn, sizeof *m->xstamp);
    return m->sbytes && m->xstamp ? 0 : -1;
}

void discrete_ranks_free(dmodel *m)
{
    free(m->sbytes), free(m->xstamp), free(m->xe), free(m->xdisk), free(m->v0);
    free(m->sbuf), free(m->rbuf), free(m->xpick);
    m->xpick = NULL, m->xpick_cap = 0;
    m->sbytes = NULL, m->xstamp = NULL, m->xe = NULL, m->xdisk = NULL;
    m->v0 = NULL, m->v0_cap = 0;
    m->sbuf = m->rbuf = NULL;
}

/* A tile's work: the time it took in the last step where that is known
 * (the same tiles: known), else its disks.  Where the ranks work changes
 * no result, so a time may decide it. */
static double tile_cost(const dmodel *m, uint32_t t, int known)
{
    return known ? m->tcost[t] : (double)(m->tiles[t].p1 - m->tiles[t].p0);
}

/* The tiles go to the ranks in runs of rows (row by row, each row from
 * left to right), split by their work: the border between two ranks is
 * a row's side, with one step in it at most, so few of the eight levels
 * of edges cross it. */
void discrete_ranks_own(const psim_sim *e, dmodel *m)
{
    if (m->ranks < 2)
        return;
    const int R = m->ranks, TG = e->grid.TG;
    double total = 0, before = 0;
    int known = 0;
    for (uint32_t t = 0; t < m->ntiles; t++)
        known |= m->tcost[t] > 0;
    for (uint32_t t = 0; t < m->ntiles; t++)
        total += tile_cost(m, t, known);
    for (int k = 0; k < TG * TG; k++) {
        const uint32_t t = e->grid.tile_of_xy[k];
        /* the rank whose share of the work holds the tile's middle */
        const double c = tile_cost(m, t, known);
        int q = total > 0 ? (int)((before + 0.5 * c) * R / total) : 0;
        before += c;
        m->owner[t] = q < 0 ? 0 : q < R ? q : R - 1;
    }
    m->nown = 0;   /* the rank's disks */
    for (uint32_t t = 0; t < m->ntiles; t++)
        m->nown += discrete_mine(m, t) ? m->tiles[t].p1 - m->tiles[t].p0 : 0;
}

/* Room for n bytes in a kept buffer. */
static void *room(void **p, size_t *cap, size_t n)
{
    if (psim_reserve(p, cap, n ? n : 1, 1))
        return NULL;
    return *p;
}

/* An edge's contacts as this rank's tile found them (mine) or the other
 * rank's (received). */
static const dlist *side_list(const dmodel *m, const dxedge *x, int mine)
{
    const dedge *ed = &m->edges[x->k];
    return (x->mine_a == mine) ? &m->tiles[ed->a].cross[ed->dir]
                               : &m->tiles[ed->b].cross[DIR_OPP(ed->dir)];
}

/* The edges across this rank's side, in creation order. */
static int list_cross(dmodel *m)
{
    m->nxe = 0;
    for (size_t k = 0; k < m->nedges; k++) {
        const dedge *ed = &m->edges[k];
        int oa = m->owner[ed->a], ob = m->owner[ed->b];
        if (oa == ob || (oa != m->rank && ob != m->rank))
            continue;
        if (psim_reserve((void **)&m->xe, &m->xe_cap, m->nxe + 1, sizeof *m->xe))
            return -1;
        m->xe[m->nxe++] = (dxedge){.k = (uint32_t)k, .q = oa == m->rank ? ob : oa,
                                   .mine_a = oa == m->rank};
    }
    return 0;
}

/* The disks of a list in tile t (mine) or not, each once, appended to
 * m->xdisk in the order of the lists (the same order on both ranks). */
static int list_disks(dmodel *m, const dlist *const *l, const dtile *t, int in_t)
{
    if (++m->xnow == 0) {   /* the stamps wrapped */
        memset(m->xstamp, 0, m->xn * sizeof *m->xstamp);
        m->xnow = 1;
    }
    for (int s = 0; s < 2; s++)
        for (size_t c = 0; c < l[s]->n; c++)
            for (int h = 0; h < 2; h++) {
                uint32_t i = (uint32_t)(h ? l[s]->c[c].j : l[s]->c[c].i);
                if (m->xstamp[i] == m->xnow || ((i >= t->p0 && i < t->p1) != in_t))
                    continue;
                m->xstamp[i] = m->xnow;
                if (psim_reserve((void **)&m->xdisk, &m->xdisk_cap, m->nxdisk + 1,
                                 sizeof *m->xdisk))
                    return -1;
                m->xdisk[m->nxdisk++] = i;
            }
    return 0;
}

/* The bytes to and from each rank (m->sbytes, m->sbytes + R), zeroed.
 * A message to a rank packs the records of its edges in their order, the
 * order both ranks list them in. */
static void clear_bytes(dmodel *m)
{
    memset(m->sbytes, 0, 2 * (size_t)m->ranks * sizeof *m->sbytes);
}

int discrete_ranks_contacts(psim_sim *e, dmodel *m)
{
    const int R = m->ranks;
    int oom = 0;
    for (uint32_t t = 0; t < m->ntiles; t++)
        oom |= discrete_mine(m, t) && m->tiles[t].oom;
    oom |= list_cross(m) != 0;
    double v[3] = {(double)m->step_contacts, (double)m->step_tests, oom};
    psim_engine_reduce(e, v, 3, &m->d2min, 1);
    m->step_contacts = (uint64_t)v[0], m->step_tests = (uint64_t)v[1];
    if (v[2] > 0)
        return -1;
    /* the sizes of the lists, then the lists: each rank sends its side's */
    size_t *to = m->sbytes, *from = m->sbytes + R;
    clear_bytes(m);
    for (size_t r = 0; r < m->nxe; r++)
        to[m->xe[r].q] += sizeof(uint64_t), from[m->xe[r].q] += sizeof(uint64_t);
    uint64_t *sn = room(&m->sbuf, &m->sbuf_cap, m->nxe * sizeof *sn);
    uint64_t *rn = room(&m->rbuf, &m->rbuf_cap, m->nxe * sizeof *rn);
    if (!sn || !rn)
        psim_dist_out_of_memory("the contacts across ranks");
    size_t at = 0;
    for (int q = 0; q < R; q++)
        for (size_t r = 0; r < m->nxe; r++)
            if (m->xe[r].q == q)
                sn[at++] = side_list(m, &m->xe[r], 1)->n;
    psim_engine_sendrecv(e, sn, to, rn, from);
    /* (rn by rank, then record: the other side's list sizes) */
    size_t *count = malloc((m->nxe ? m->nxe : 1) * sizeof *count);
    if (!count)
        psim_dist_out_of_memory("the contacts across ranks");
    at = 0;
    for (int q = 0; q < R; q++)
        for (size_t r = 0; r < m->nxe; r++)
            if (m->xe[r].q == q)
                count[r] = (size_t)rn[at++];
    clear_bytes(m);
    size_t sall = 0, rall = 0;
    for (size_t r = 0; r < m->nxe; r++) {
        size_t s = side_list(m, &m->xe[r], 1)->n * sizeof(dcontact);
        to[m->xe[r].q] += s, sall += s;
        from[m->xe[r].q] += count[r] * sizeof(dcontact), rall += count[r] * sizeof(dcontact);
    }
    char *sb = room(&m->sbuf, &m->sbuf_cap, sall), *rb = room(&m->rbuf, &m->rbuf_cap, rall);
    if (!sb || !rb)
        psim_dist_out_of_memory("the contacts across ranks");
    size_t so = 0;
    for (int q = 0; q < R; q++)
        for (size_t r = 0; r < m->nxe; r++)
            if (m->xe[r].q == q) {
                const dlist *l = side_list(m, &m->xe[r], 1);
                if (l->n)
                    memcpy(sb + so, l->c, l->n * sizeof(dcontact));
                so += l->n * sizeof(dcontact);
            }
    psim_engine_sendrecv(e, sb, to, rb, from);
    size_t ro = 0;
    for (int q = 0; q < R; q++)
        for (size_t r = 0; r < m->nxe; r++)
            if (m->xe[r].q == q) {
                dlist *l = (dlist *)side_list(m, &m->xe[r], 0);
                if (psim_reserve((void **)&l->c, &l->cap, count[r] + 1, sizeof *l->c))
                    psim_dist_out_of_memory("the contacts across ranks");
                memcpy(l->c, rb + ro, count[r] * sizeof(dcontact));
                l->n = count[r];
                ro += count[r] * sizeof(dcontact);
            }
    free(count);
    /* each edge's disks on either side, and room for the other tile's
     * activations (dropped after each edge) */
    m->nxdisk = 0;
    for (size_t r = 0; r < m->nxe; r++) {
        dxedge *x = &m->xe[r];
        const dedge *ed = &m->edges[x->k];
        const dlist *l[2] = {&m->tiles[ed->a].cross[ed->dir],
                             &m->tiles[ed->b].cross[DIR_OPP(ed->dir)]};
        dtile *mt = &m->tiles[x->mine_a ? ed->a : ed->b];
        dtile *ot = &m->tiles[x->mine_a ? ed->b : ed->a];
        x->m0 = (uint32_t)m->nxdisk;
        if (list_disks(m, l, mt, 1))
            psim_dist_out_of_memory("the contacts across ranks");
        x->n0 = (uint32_t)m->nxdisk - x->m0;
        x->m1 = (uint32_t)m->nxdisk;
        if (list_disks(m, l, mt, 0))
            psim_dist_out_of_memory("the contacts across ranks");
        x->n1 = (uint32_t)m->nxdisk - x->m1;
        x->lv = 0;
        while (x->lv + 1 < EDGE_LEVELS && m->level0[x->lv + 1] <= x->k)
            x->lv++;
        if (psim_reserve((void **)&ot->acts, &ot->acts_cap, (size_t)(ot->p1 - ot->p0) + 1,
                         sizeof *ot->acts))
            psim_dist_out_of_memory("the contacts across ranks");
        ot->nact = 0;
    }
    return 0;
}

/* A tile's flags that edges across ranks read: whether it runs in the
 * next round, whether edges changed it in this one (from the round's end)
 * and whether its worklist changed a disk on its border (with the
 * velocities of each edge's level). */
enum { XF_SCHEDULED = 1, XF_CROSS_PREV = 2 };

uint64_t discrete_ranks_round_end(psim_sim *e, dmodel *m, uint64_t res, int *diverged)
{
    double *v = m->tflags;
    v[0] = (double)res, v[1] = *diverged, v[2] = psim_stop_requested();
    for (uint32_t t = 0; t < m->ntiles; t++) {
        const dtile *d = &m->tiles[t];
        const int runs = d->p0 != d->p1 && (d->nact || d->qcount);
        v[3 + t] = discrete_mine(m, t) ? (runs ? XF_SCHEDULED : 0) +
                                             (d->changed_cross_prev ? XF_CROSS_PREV : 0)
                                       : 0;
    }
    psim_engine_reduce(e, v, (int)m->ntiles + 3, NULL, 0);
    if (v[2] > 0)
        psim_request_stop();
    *diverged = v[1] > 0;
    return (uint64_t)v[0];
}

void discrete_ranks_flags(dmodel *m, int first)
{
    for (uint32_t t = 0; t < m->ntiles; t++) {
        dtile *d = &m->tiles[t];
        if (discrete_mine(m, t))
            continue;
        const int f = (int)m->tflags[3 + t];
        d->scheduled = first ? d->p0 != d->p1 : (f & XF_SCHEDULED) != 0;
        d->changed_cross_prev = !first && (f & XF_CROSS_PREV) != 0;
    }
}

/* Forget what an edge did to another rank's tile t: its owner keeps it. */
static void drop_other(dmodel *m, dtile *t)
{
    for (uint32_t j = 0; j < t->nact; j++)
        m->active[t->acts[j]] = 0;
    t->nact = 0;
}

/* This level's edges across ranks that run this round, in the messages'
 * order (by rank, then as listed), into m->xpick; how many. */
static size_t level_edges(dmodel *m, int lv, int first)
{
    if (psim_reserve((void **)&m->xpick, &m->xpick_cap, m->nxe + 1, sizeof *m->xpick))
        psim_dist_out_of_memory("the edges across ranks");
    size_t n = 0;
    for (int q = 0; q < m->ranks; q++)
        for (size_t r = 0; r < m->nxe; r++) {
            const dxedge *x = &m->xe[r];
            if (x->q == q && x->lv == lv && discrete_edge_runs(m, x->k, first))
                m->xpick[n++] = (uint32_t)r;
        }
    return n;
}

uint64_t discrete_ranks_level(psim_sim *e, dmodel *m, int lv, int first)
{
    const int R = m->ranks;
    size_t *to = m->sbytes, *from = m->sbytes + R;
    clear_bytes(m);
    const size_t V = 2 * sizeof(double), np = level_edges(m, lv, first);
    size_t sall = 0, rall = 0;
    for (size_t p = 0; p < np; p++) {
        const dxedge *x = &m->xe[m->xpick[p]];
        to[x->q] += 1 + V * x->n0, sall += 1 + V * x->n0;
        from[x->q] += 1 + V * x->n1, rall += 1 + V * x->n1;
    }
    if (np) {
        /* this level's edges across ranks: for each, this rank's tile's
         * flag (its worklist changed a disk on the border) and its disks'
         * velocities; the other rank's, likewise */
        char *sb = room(&m->sbuf, &m->sbuf_cap, sall), *rb = room(&m->rbuf, &m->rbuf_cap, rall);
        if (!sb || !rb)
            psim_dist_out_of_memory("the velocities across ranks");
        double *vx = e->st.vx, *vy = e->st.vy;
        size_t so = 0, ro = 0;
        for (size_t p = 0; p < np; p++) {
            const dxedge *x = &m->xe[m->xpick[p]];
            const dedge *ed = &m->edges[x->k];
            sb[so++] = (char)m->tiles[x->mine_a ? ed->a : ed->b].changed_border;
            for (uint32_t h = 0; h < x->n0; h++, so += V) {
                uint32_t i = m->xdisk[x->m0 + h];
                memcpy(sb + so, &vx[i], sizeof(double));
                memcpy(sb + so + sizeof(double), &vy[i], sizeof(double));
            }
        }
        psim_engine_sendrecv(e, sb, to, rb, from);
        for (size_t p = 0; p < np; p++) {
            const dxedge *x = &m->xe[m->xpick[p]];
            const dedge *ed = &m->edges[x->k];
            m->tiles[x->mine_a ? ed->b : ed->a].changed_border = (uint8_t)(rb[ro++] != 0);
            for (uint32_t h = 0; h < x->n1; h++, ro += V) {
                uint32_t i = m->xdisk[x->m1 + h];
                memcpy(&vx[i], rb + ro, sizeof(double));
                memcpy(&vy[i], rb + ro + sizeof(double), sizeof(double));
            }
        }
    }
    uint64_t tasks = 0;
    for (size_t k = m->level0[lv]; k < m->level0[lv + 1]; k++) {
        const dedge *ed = &m->edges[k];
        const int ma = discrete_mine(m, ed->a), mb = discrete_mine(m, ed->b);
        if ((!ma && !mb) || !discrete_edge_runs(m, k, first))
            continue;
        /* the edge's work is counted where its tile a is */
        uint32_t *counting = m->counting;
        if (!ma)
            m->counting = NULL;
        discrete_edge(e, m, k, first);
        m->counting = counting;
        tasks += ma;
        if (!ma)
            drop_other(m, &m->tiles[ed->a]);
        if (!mb)
            drop_other(m, &m->tiles[ed->b]);
    }
    return tasks;
}

void discrete_ranks_keep(psim_sim *e, dmodel *m)
{
    const size_t n = m->nown;
    if (psim_reserve((void **)&m->v0, &m->v0_cap, 2 * n + 1, sizeof *m->v0))
        psim_dist_out_of_memory("the velocities");
    size_t at = 0;   /* the rank's tiles in their order */
    for (uint32_t t = 0; t < m->ntiles; t++) {
        const dtile *d = &m->tiles[t];
        if (!discrete_mine(m, t) || d->p0 == d->p1)
            continue;
        memcpy(m->v0 + at, e->st.vx + d->p0, (d->p1 - d->p0) * sizeof *m->v0);
        memcpy(m->v0 + n + at, e->st.vy + d->p0, (d->p1 - d->p0) * sizeof *m->v0);
        at += d->p1 - d->p0;
    }
}

/* The end of a step sends, for each of the rank's tiles in order, a
 * header (the tile, how many of its disks changed, the seconds its work
 * took), a bitmap of its disks whose velocities changed (or that other
 * ranks' edges moved too), then their velocities (vx, vy) in store
 * order.  The tiles are the same on every rank, so their places need no
 * indices: 16 bytes a changed disk and a bit for every disk. */
typedef struct vhead {
    uint32_t tile, changed;
    double busy;
} vhead;

static size_t words_of(const dtile *d)
{
    return (d->p1 - d->p0 + 63) / 64;
}

/* The bytes of tile d's bitmap and of `changed` disks' velocities. */
static size_t tile_bytes(const dtile *d, size_t changed)
{
    return words_of(d) * sizeof(uint64_t) + 2 * changed * sizeof(double);
}

/* Tile d's bitmap and velocities at out (room for all of them); returns
 * the bytes written.  h: d's first disk's place in m->v0. */
static size_t pack_tile(const psim_sim *e, const dmodel *m, const dtile *d, size_t h,
                        char *out, uint32_t *changed)
{
    const size_t n = m->nown, W = words_of(d);
    const double *vx = e->st.vx, *vy = e->st.vy;
    uint64_t *bits = (uint64_t *)(void *)out;
    double *v = (double *)(void *)(out + W * sizeof *bits);
    uint32_t c = 0;
    for (size_t w = 0; w < W; w++) {
        uint64_t word = 0;
        const uint32_t k0 = d->p0 + (uint32_t)(w * 64);
        const uint32_t k1 = d->p1 - k0 < 64 ? d->p1 : k0 + 64;
        for (uint32_t k = k0; k < k1; k++, h++) {
            uint64_t a, b, a0, b0;
            memcpy(&a, &vx[k], sizeof a), memcpy(&b, &vy[k], sizeof b);
            memcpy(&a0, &m->v0[h], sizeof a0), memcpy(&b0, &m->v0[n + h], sizeof b0);
            const uint64_t ch = (m->xstamp[k] == m->xnow) | (a != a0) | (b != b0);
            word |= ch << (k - k0);
            v[2 * c] = vx[k], v[2 * c + 1] = vy[k];   /* (kept if changed) */
            c += (uint32_t)ch;
        }
        bits[w] = word;
    }
    *changed = c;
    return tile_bytes(d, c);
}

/* Tile d's velocities from another rank's bitmap at in; returns the
 * bytes read. */
static size_t unpack_tile(psim_sim *e, const dtile *d, const char *in, uint32_t changed)
{
    const size_t W = words_of(d);
    const uint64_t *bits = (const uint64_t *)(const void *)in;
    const double *v = (const double *)(const void *)(in + W * sizeof *bits);
    double *vx = e->st.vx, *vy = e->st.vy;
    for (size_t w = 0; w < W; w++)
        for (uint64_t word = bits[w]; word; word &= word - 1) {
            const uint32_t k = d->p0 + (uint32_t)(w * 64) + (uint32_t)__builtin_ctzll(word);
            vx[k] = v[0], vy[k] = v[1];
            v += 2;
        }
    return tile_bytes(d, changed);
}

void discrete_ranks_sync(psim_sim *e, dmodel *m)
{
    /* the rank's disks that other ranks' edges moved too: always sent */
    if (++m->xnow == 0) {
        memset(m->xstamp, 0, m->xn * sizeof *m->xstamp);
        m->xnow = 1;
    }
    for (size_t r = 0; r < m->nxe; r++)
        for (uint32_t h = 0; h < m->xe[r].n0; h++)
            m->xstamp[m->xdisk[m->xe[r].m0 + h]] = m->xnow;
    size_t most = 0;
    for (uint32_t t = 0; t < m->ntiles; t++)
        if (discrete_mine(m, t))
            most += sizeof(vhead) + tile_bytes(&m->tiles[t], m->tiles[t].p1 - m->tiles[t].p0);
    char *sb = room(&m->sbuf, &m->sbuf_cap, most);
    if (!sb)
        psim_dist_out_of_memory("the velocities");
    size_t so = 0, h = 0;
    for (uint32_t t = 0; t < m->ntiles; t++) {
        const dtile *d = &m->tiles[t];
        if (!discrete_mine(m, t))
            continue;
        vhead hd = {t, 0, d->busy};
        const size_t at = so;
        so += sizeof hd;
        so += pack_tile(e, m, d, h, sb + so, &hd.changed);
        memcpy(sb + at, &hd, sizeof hd);
        h += d->p1 - d->p0;
    }
    for (uint32_t t = 0; t < m->ntiles; t++)
        m->tcost[t] = m->tiles[t].busy = 0;
    char *all;
    size_t *each = m->sbytes, at = 0;
    psim_engine_share(e, sb, so, (void **)&all, each);
    for (int q = 0; q < m->ranks; q++) {
        for (size_t o = at; o < at + each[q];) {
            vhead hd;
            memcpy(&hd, all + o, sizeof hd);
            o += sizeof hd;
            m->tcost[hd.tile] = hd.busy;
            const dtile *d = &m->tiles[hd.tile];
            o += q != m->rank ? unpack_tile(e, d, all + o, hd.changed) : tile_bytes(d, hd.changed);
        }
        at += each[q];
    }
    free(all);
}

/* A per-disk array of counts summed over the ranks. */
static void sum_counts(psim_sim *e, uint32_t *a, size_t n, const char *what)
{
    double *d = malloc((n ? n : 1) * sizeof *d);
    if (!d)
        psim_dist_out_of_memory(what);
    for (size_t k = 0; k < n; k++)
        d[k] = a[k];
    psim_engine_reduce(e, d, (int)n, NULL, 0);
    for (size_t k = 0; k < n; k++)
        a[k] = (uint32_t)d[k];
    free(d);
}

void discrete_ranks_work(psim_sim *e, dmodel *m)
{
    sum_counts(e, m->work, (size_t)e->n, "the work of the tiles");
}

void discrete_ranks_marks(psim_sim *e, dmodel *m)
{
    const size_t n = (size_t)e->n;
    double *d = malloc((n ? n : 1) * sizeof *d);
    if (!d)
        psim_dist_out_of_memory("the disks that did not settle");
    for (size_t k = 0; k < n; k++)
        d[k] = m->flag[k] != 0;
    psim_engine_reduce(e, d, (int)n, NULL, 0);
    for (size_t k = 0; k < n; k++)
        m->flag[k] = d[k] > 0;
    free(d);
}
