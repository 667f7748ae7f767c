/* The distributed engine's side of a run (dist.h): a rank's share of the
 * particles, the exchanges, the ghosts' updates and the figures summed
 * for the summary (the outputs: dist_write.c). */
#include "dist.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/error.h"
#include "dist_cut.h"
#include "engine.h"
#include "mem.h"
#include "timer.h"

#ifdef PSIM_HAVE_MPI
#include <mpi.h>

/* Doubles a migrating particle or a new ghost travels as: id, x, y, vx, vy. */
#define REC 5
/* A rank holding this much more than the mean share after an exchange
 * has the domains cut again at the next one. */
#define DIST_RECUT 1.10

typedef struct psim_dist {
    dist_cuts cuts;
    psim_halo halo;
    double h;                 /* the halo's width: reach + skin */
    int comm_phase;           /* the stats' "comm" */
    int shares;               /* the model shares (model.h): every rank
                               * holds every particle, no ghosts */
    size_t n_own;             /* owned particles (the store's others are ghosts) */
    int due, exchanged, recut, regrid;
    double drift;             /* every owned particle has moved at most this
                               * since the exchange (all ranks' largest) */
    double moved;             /* this step's, as the model said (psim_engine_moved) */
    int said;                 /* the model said it this step */
    int says;                 /* the model says it every step (it did once) */
    int unsaid;               /* a step ended without its saying it: the drift
                               * is measured from the positions at the exchange */
    double path[2];           /* the two longest paths of the rank's own
                               * particles since the exchange, as the model
                               * said them this step (pathed) */
    int pathed;
    double *gathered;         /* each rank's figures at a step's end */
    int *scnt, *sdsp, *rcnt, *rdsp;   /* ghosts to / from each rank */
    int32_t *send_id, *recv_id;
    uint32_t *send_slot, *recv_slot;
    size_t nsend, nrecv;
    uint8_t *ghost;           /* by store place */
    double *x0, *y0;          /* by store place: positions at the exchange, for
                               * a model that does not say how far they moved
                               * (NULL once it has: 16 bytes a particle) */
    size_t cap0;
    uint32_t *from, *where;   /* the sort's permutation (store.from), its inverse */
    uint8_t *ghost2;
    size_t cap;
    double *usend, *urecv;    /* the ghosts' fields in an update, kept (grow only) */
    size_t usend_cap, urecv_cap;
    MPI_Request *ureq;        /* an update's sends and receives in flight */
    int nureq, upending;
    MPI_Request *sreq;        /* a sharing model's messages in flight */
    MPI_Datatype utype;       /* a ghost's fields */
    int utype_k;
    uint32_t *pick;           /* an exchange's places: leavers, then those near a side */
    int *dest;                /* the leavers' ranks */
    size_t pick_cap;
    psim_rank_stats rs;
} psim_dist;

static int R(void) { return psim_dist_ranks(); }
static int me(void) { return psim_dist_rank(); }

static int fields_of(unsigned f)
{
    return !!(f & PSIM_FIELD_X) + !!(f & PSIM_FIELD_Y) + !!(f & PSIM_FIELD_VX) +
           !!(f & PSIM_FIELD_VY);
}

/* Room for n places in the by-place arrays. */
static int places(psim_dist *d, size_t n)
{
    if (n <= d->cap)
        return 0;
    size_t c = n + n / 4 + 64;
    free(d->ghost), free(d->from), free(d->where), free(d->ghost2);
    d->ghost = malloc(c);
    d->ghost2 = malloc(c);
    d->from = malloc(c * sizeof *d->from);
    d->where = malloc(c * sizeof *d->where);
    d->cap = d->ghost && d->ghost2 && d->from && d->where ? c : 0;
    return d->cap ? 0 : -1;
}

static void *grow(void *p, size_t bytes, const char *what)
{
    void *q = realloc(p, bytes ? bytes : 1);
    if (!q)
        psim_dist_out_of_memory(what);
    return q;
}

/* MPI_Alltoallv of doubles, counts in records of k doubles; the bytes and
 * messages sent are counted. */
static void alltoallv(psim_dist *d, const double *s, const int *scnt, const int *sdsp,
                      double *r, const int *rcnt, const int *rdsp, int k)
{
    /* counts in records of k doubles: an int holds 2^31 of them */
    MPI_Datatype rec;
    MPI_Type_contiguous(k, MPI_DOUBLE, &rec);
    MPI_Type_commit(&rec);
    for (int q = 0; q < R(); q++)
        if (q != me() && scnt[q]) {
            d->rs.bytes_sent += (uint64_t)scnt[q] * (uint64_t)k * sizeof(double);
            d->rs.messages_sent++;
        }
    MPI_Alltoallv(s, scnt, sdsp, rec, r, rcnt, rdsp, rec, MPI_COMM_WORLD);
    MPI_Type_free(&rec);
}

/* Receive counts from send counts, and both displacements; the total received. */
static size_t counts(const int *scnt, int *sdsp, int *rcnt, int *rdsp)
{
    MPI_Alltoall(scnt, 1, MPI_INT, rcnt, 1, MPI_INT, MPI_COMM_WORLD);
    size_t s = 0, r = 0;
    for (int q = 0; q < R(); q++) {
        sdsp[q] = (int)s, rdsp[q] = (int)r;
        s += (size_t)scnt[q], r += (size_t)rcnt[q];
    }
    return r;
}

static void put_rec(double *o, const psim_store *st, size_t i)
{
    o[0] = st->id[i], o[1] = st->x[i], o[2] = st->y[i], o[3] = st->vx[i], o[4] = st->vy[i];
}

/* The domains cut again where the owned particles are: a histogram of x
 * over every rank, then one of y in each column. */
static void cut(psim_dist *d, double L, const double *x, const double *y, size_t n, int all)
{
    dist_cuts *c = &d->cuts;
    uint64_t *h = calloc((size_t)c->px * DIST_BINS, sizeof *h);
    if (!h)
        psim_dist_out_of_memory("the domains");
    for (size_t i = 0; i < n; i++)
        h[dist_bin(x[i], L)]++;
    if (all)
        MPI_Allreduce(MPI_IN_PLACE, h, DIST_BINS, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    dist_cuts_from_hist(h, L, c->px, c->cx);
    memset(h, 0, (size_t)c->px * DIST_BINS * sizeof *h);
    for (size_t i = 0; i < n; i++)
        h[(size_t)dist_cuts_column(c, x[i]) * DIST_BINS + dist_bin(y[i], L)]++;
    if (all)
        MPI_Allreduce(MPI_IN_PLACE, h, c->px * DIST_BINS, MPI_UINT64_T, MPI_SUM,
                      MPI_COMM_WORLD);
    for (int i = 0; i < c->px; i++)
        dist_cuts_from_hist(h + (size_t)i * DIST_BINS, L, c->py, c->cy + (size_t)i * (c->py + 1));
    free(h);
    d->rs.recuts++;
}

/* The same from every rank's own particles (ghosts left out). */
static void recut(psim_sim *e)
{
    psim_dist *d = e->dist;
    const psim_store *st = &e->st;
    double *x = malloc((d->n_own ? d->n_own : 1) * sizeof *x);
    double *y = malloc((d->n_own ? d->n_own : 1) * sizeof *y);
    if (!x || !y)
        psim_dist_out_of_memory("the domains");
    size_t m = 0;
    for (size_t i = 0; i < st->n; i++)
        if (!d->ghost[i])
            x[m] = st->x[i], y[m++] = st->y[i];
    cut(d, e->L, x, y, m, 1);
    free(x), free(y);
}

/* Records of the store's places idx[0..n) (NULL: 0..n) for rank dest[k],
 * grouped by rank; scnt[q] of them for rank q. */
static double *pack_by_rank(const psim_store *st, const uint32_t *idx, const int *dest,
                            size_t n, const int *scnt, int *sdsp)
{
    size_t off = 0;
    for (int q = 0; q < R(); q++)
        sdsp[q] = (int)off, off += (size_t)scnt[q];
    double *buf = malloc((off ? off : 1) * REC * sizeof *buf);
    if (!buf)
        psim_dist_out_of_memory("an exchange");
    int *at = malloc((size_t)R() * sizeof *at);
    if (!at)
        psim_dist_out_of_memory("an exchange");
    memcpy(at, sdsp, (size_t)R() * sizeof *at);
    for (size_t k = 0; k < n; k++)
        put_rec(buf + (size_t)at[dest[k]]++ * REC, st, idx ? idx[k] : k);
    free(at);
    return buf;
}

/* This rank's own domain: [x0, x1) x [y0, y1). */
typedef struct rect {
    double x0, x1, y0, y1;
} rect;

static rect own_rect(const dist_cuts *c)
{
    int i = me() / c->py, j = me() % c->py;
    const double *cy = c->cy + (size_t)i * (c->py + 1);
    return (rect){c->cx[i], c->cx[i + 1], cy[j], cy[j + 1]};
}

/* Whether (x, y) lies in the domain (its cells' rule: lower sides in,
 * upper sides out). */
static inline int inside(const rect *r, double x, double y)
{
    return x >= r->x0 && x < r->x1 && y >= r->y0 && y < r->y1;
}

/* Whether (x, y) lies deeper than h inside the domain: then it is near
 * no other. */
static inline int deep_inside(const rect *r, double x, double y, double h)
{
    return x - r->x0 > h && r->x1 - x > h && y - r->y0 > h && r->y1 - y > h;
}

/* Room for n places in the exchange's kept arrays. */
static void pick_room(psim_dist *d, size_t n)
{
    if (n <= d->pick_cap && d->pick)
        return;
    size_t c = n + n / 4 + 64;
    d->pick = grow(d->pick, c * sizeof *d->pick, "an exchange");
    d->dest = grow(d->dest, c * sizeof *d->dest, "an exchange");
    d->pick_cap = c;
}

/* Migration: every owned particle that left this rank's domain goes to
 * the rank that owns its place now; those that stay are moved to the
 * front of the store (places 0..*stay), in their order.  The records
 * received are returned (*got of them). */
static double *migrate(psim_sim *e, size_t *stay, size_t *got)
{
    psim_dist *d = e->dist;
    psim_store *st = &e->st;
    int n = R();
    pick_room(d, d->n_own);
    uint32_t *out = d->pick;
    int *dest = d->dest;
    int *c = calloc(4 * (size_t)n, sizeof *c);
    if (!c)
        psim_dist_out_of_memory("an exchange");
    size_t m = 0, w = 0;
    const rect own = own_rect(&d->cuts);
    for (size_t i = 0; i < st->n; i++) {
        if (d->ghost[i] || inside(&own, st->x[i], st->y[i]))
            continue;
        int q = dist_cuts_owner(&d->cuts, st->x[i], st->y[i]);
        if (q != me())
            out[m] = (uint32_t)i, dest[m++] = q, c[q]++, d->ghost[i] = 2;   /* leaves */
    }
    int *sd = c + n, *rc = sd + n, *rd = rc + n;
    double *sbuf = pack_by_rank(st, out, dest, m, c, sd);
    /* the particles that stay to places 0..w: the last of them into the
     * first places of ghosts and leavers (few moves; the order does not
     * matter, the model sorts after an exchange) */
    size_t hi = st->n;
    for (;;) {
        while (w < hi && !d->ghost[w])
            w++;
        while (hi > w && d->ghost[hi - 1])
            hi--;
        if (w >= hi)
            break;
        size_t i = --hi;
        st->x[w] = st->x[i], st->y[w] = st->y[i], st->vx[w] = st->vx[i];
        st->vy[w] = st->vy[i], st->id[w] = st->id[i];
        d->ghost[w++] = 0, d->ghost[i] = 1;
    }
    size_t r = counts(c, sd, rc, rd);
    double *rbuf = malloc((r ? r : 1) * REC * sizeof *rbuf);
    if (!rbuf)
        psim_dist_out_of_memory("an exchange");
    alltoallv(d, sbuf, c, sd, rbuf, rc, rd, REC);
    free(sbuf), free(c);
    *stay = w;
    *got = r;
    return rbuf;
}

/* The ghosts: each owned particle (store places 0..m) to every other rank
 * whose domain it lies within the halo of.  The records received are
 * returned; the ids sent and received are kept, by rank, for the updates. */
static double *ghosts(psim_sim *e, size_t m, size_t *got)
{
    psim_dist *d = e->dist;
    const psim_store *st = &e->st;
    int n = R();
    memset(d->scnt, 0, (size_t)n * sizeof *d->scnt);
    /* the particles near the domain's sides (few), then their ranks */
    const rect own = own_rect(&d->cuts);
    pick_room(d, m);
    uint32_t *near = d->pick;
    size_t nn = 0, ns = 0;
    for (size_t k = 0; k < m; k++)
        if (!deep_inside(&own, st->x[k], st->y[k], d->h))
            near[nn++] = (uint32_t)k;
    for (int pass = 0; pass < 2; pass++) {
        if (pass) {
            d->send_id = grow(d->send_id, (ns ? ns : 1) * sizeof *d->send_id, "the ghosts");
            d->send_slot = grow(d->send_slot, (ns ? ns : 1) * sizeof *d->send_slot, "the ghosts");
            for (int q = 0, off = 0; q < n; q++)
                d->sdsp[q] = off, off += d->scnt[q], d->scnt[q] = 0;
        }
        for (size_t a = 0; a < nn; a++) {
            size_t k = near[a];
            double x = st->x[k], y = st->y[k];
            for (int q = 0; q < n; q++) {
                if (q == me() || !dist_cuts_near(&d->cuts, q, x, y, d->h))
                    continue;
                if (pass) {
                    size_t at = (size_t)d->sdsp[q] + (size_t)d->scnt[q];
                    d->send_id[at] = st->id[k];
                    d->send_slot[at] = (uint32_t)k;
                }
                d->scnt[q]++;
                ns += !pass;
            }
        }
    }
    d->nsend = ns;
    double *sbuf = malloc((ns ? ns : 1) * REC * sizeof *sbuf);
    if (!sbuf)
        psim_dist_out_of_memory("the ghosts");
    for (size_t k = 0; k < ns; k++)
        put_rec(sbuf + k * REC, st, d->send_slot[k]);
    size_t r = counts(d->scnt, d->sdsp, d->rcnt, d->rdsp);
    double *rbuf = malloc((r ? r : 1) * REC * sizeof *rbuf);
    if (!rbuf)
        psim_dist_out_of_memory("the ghosts");
    alltoallv(d, sbuf, d->scnt, d->sdsp, rbuf, d->rcnt, d->rdsp, REC);
    free(sbuf);
    d->nrecv = r;
    d->recv_id = grow(d->recv_id, (r ? r : 1) * sizeof *d->recv_id, "the ghosts");
    d->recv_slot = grow(d->recv_slot, (r ? r : 1) * sizeof *d->recv_slot, "the ghosts");
    for (size_t k = 0; k < r; k++)
        d->recv_id[k] = (int32_t)rbuf[k * REC], d->recv_slot[k] = (uint32_t)(m + k);
    *got = r;
    return rbuf;
}

static void get_rec(psim_store *st, size_t i, const double *p)
{
    st->id[i] = (int32_t)p[0], st->x[i] = p[1], st->y[i] = p[2], st->vx[i] = p[3],
    st->vy[i] = p[4];
}

/* The positions of every place as they are now: the drift is measured
 * from them. */
static void mark(psim_sim *e)
{
    psim_dist *d = e->dist;
    if (e->st.n > d->cap0) {
        d->cap0 = e->st.n + e->st.n / 4 + 64;
        d->x0 = grow(d->x0, d->cap0 * sizeof *d->x0, "the particles");
        d->y0 = grow(d->y0, d->cap0 * sizeof *d->y0, "the particles");
    }
    memcpy(d->x0, e->st.x, e->st.n * sizeof *d->x0);
    memcpy(d->y0, e->st.y, e->st.n * sizeof *d->y0);
    d->drift = 0;
}

/* The exchange: migration, then the ghosts; the store becomes the owned
 * particles followed by the ghosts. */
static void exchange(psim_sim *e)
{
    psim_dist *d = e->dist;
    psim_store *st = &e->st;
    if (d->recut)
        recut(e);
    size_t stay, in, g;
    double *arrived = migrate(e, &stay, &in);
    const size_t m = stay + in;
    st->n = stay;
    if (psim_store_keep(st, m))
        psim_dist_out_of_memory("the particles");
    for (size_t i = 0; i < in; i++)
        get_rec(st, stay + i, arrived + i * REC);
    free(arrived);
    double *gh = ghosts(e, m, &g);
    if (psim_store_keep(st, m + g) || places(d, m + g))
        psim_dist_out_of_memory("the particles");
    for (size_t i = 0; i < g; i++)
        get_rec(st, m + i, gh + i * REC);
    free(gh);
    d->n_own = m;
    e->n = (long)(m + g);
    memset(d->ghost, 0, m);
    memset(d->ghost + m, 1, g);
    st->from = d->from;   /* the next sort says where it took each particle */
    if (d->unsaid)
        mark(e);
    d->drift = 0;
    d->exchanged = 1;
    d->rs.exchanges++;
    if ((d->recut || d->regrid) && psim_engine_regrid(e))   /* the grid over the new domain */
        psim_dist_out_of_memory("the grid");
    d->regrid = 0;
    /* cut again at the next exchange if the shares drifted apart */
    double most = psim_dist_max((double)m);
    d->recut = most > DIST_RECUT * (double)e->n_all / R() + 1;
}

/* A buffer of n doubles kept in *p (room for *cap), grown when short. */
static double *keep_room(double **p, size_t *cap, size_t n, const char *what)
{
    if (n > *cap) {
        size_t c = n + n / 4 + 64;
        *p = grow(*p, c * sizeof **p, what);
        *cap = c;
    }
    return *p;
}

/* The ghosts' fields from their owners: sent, and the receives posted
 * (one message to and from each neighbour); update_finish waits for them
 * and puts them in place. */
static void update_start(psim_sim *e)
{
    psim_dist *d = e->dist;
    psim_store *st = &e->st;
    const unsigned f = d->halo.fields;
    const int k = fields_of(f);
    double *const col[4] = {st->x, st->y, st->vx, st->vy};
    double *s = keep_room(&d->usend, &d->usend_cap, d->nsend * (size_t)k, "the ghosts");
    double *r = keep_room(&d->urecv, &d->urecv_cap, d->nrecv * (size_t)k, "the ghosts");
    if (!d->ureq) {
        d->ureq = grow(NULL, 2 * (size_t)R() * sizeof *d->ureq, "the ghosts");
        /* counts in records of k doubles: an int holds 2^31 of them */
        MPI_Type_contiguous(k, MPI_DOUBLE, &d->utype);
        MPI_Type_commit(&d->utype);
        d->utype_k = k;
    }
    d->nureq = 0;
    for (int q = 0; q < R(); q++)
        if (d->rcnt[q])
            MPI_Irecv(r + (size_t)d->rdsp[q] * (size_t)k, d->rcnt[q], d->utype, q, 0,
                      MPI_COMM_WORLD, &d->ureq[d->nureq++]);
    for (size_t i = 0; i < d->nsend; i++)
        for (int c = 0, o = 0; c < 4; c++)
            if (f & (1u << c))
                s[i * (size_t)k + (size_t)o++] = col[c][d->send_slot[i]];
    for (int q = 0; q < R(); q++)
        if (d->scnt[q]) {
            MPI_Isend(s + (size_t)d->sdsp[q] * (size_t)k, d->scnt[q], d->utype, q, 0,
                      MPI_COMM_WORLD, &d->ureq[d->nureq++]);
            d->rs.bytes_sent += (uint64_t)d->scnt[q] * (uint64_t)k * sizeof(double);
            d->rs.messages_sent++;
        }
    d->upending = 1;
}

static void update_finish(psim_sim *e)
{
    psim_dist *d = e->dist;
    psim_store *st = &e->st;
    const unsigned f = d->halo.fields;
    const int k = d->utype_k;
    double *const col[4] = {st->x, st->y, st->vx, st->vy};
    const double *r = d->urecv;
    MPI_Waitall(d->nureq, d->ureq, MPI_STATUSES_IGNORE);
    for (size_t i = 0; i < d->nrecv; i++)
        for (int c = 0, o = 0; c < 4; c++)
            if (f & (1u << c))
                col[c][d->recv_slot[i]] = r[i * (size_t)k + (size_t)o++];
    d->upending = 0;
}

double psim_engine_halo_wait(psim_sim *e)
{
    psim_dist *d = e->dist;
    if (!d || !d->upending)
        return 0;
    double t0 = psim_now();
    update_finish(e);
    double dt = psim_now() - t0;
    d->rs.update_s += dt;
    e->stats.phase_s[d->comm_phase] += dt;
    return dt;
}

int psim_engine_halo_pending(const psim_sim *e)
{
    return e->dist && e->dist->upending;
}

size_t psim_engine_ghosts(const psim_sim *e, const uint32_t **place)
{
    const psim_dist *d = e->dist;
    *place = d ? d->recv_slot : NULL;
    return d ? d->nrecv : 0;
}

/* The store for a rank's own particles, with a little room for the
 * ghosts; empty. */
static int own_store(psim_sim *e, size_t own, psim_error *err)
{
    psim_dist *d = e->dist;
    if (psim_store_init(&e->st, own + own / 32 + 1024) || places(d, own + own / 32 + 1024)) {
        psim_error_set(err, "out of memory for %zu particles", own);
        return -1;
    }
    e->st.n = 0;
    d->n_own = own;
    memset(d->ghost, 0, own);
    e->n = (long)own;
    return 0;
}

/* A part of a scene on each rank (scene.h): the domains cut from every
 * rank's part together, and each particle sent to its owner, so that no
 * rank holds more than its part and its own particles. */
static int keep_part(psim_sim *e, psim_scene *sc, int take, psim_error *err)
{
    psim_dist *d = e->dist;
    const size_t n = (size_t)sc->n;
    cut(d, sc->L, sc->x, sc->y, n, 1);
    int *dest = malloc((n ? n : 1) * sizeof *dest);
    if (!dest)
        psim_dist_out_of_memory("the scene");
    memset(d->scnt, 0, (size_t)R() * sizeof *d->scnt);
    for (size_t i = 0; i < n; i++)
        d->scnt[dest[i] = dist_cuts_owner(&d->cuts, sc->x[i], sc->y[i])]++;
    size_t own = counts(d->scnt, d->sdsp, d->rcnt, d->rdsp);
    double *sbuf = malloc((n ? n : 1) * REC * sizeof *sbuf);
    int *at = malloc((size_t)R() * sizeof *at);
    if (!sbuf || !at)
        psim_dist_out_of_memory("the scene");
    memcpy(at, d->sdsp, (size_t)R() * sizeof *at);
    for (size_t i = 0; i < n; i++) {
        double *o = sbuf + (size_t)at[dest[i]]++ * REC;
        o[0] = sc->id[i], o[1] = sc->x[i], o[2] = sc->y[i], o[3] = sc->vx[i], o[4] = sc->vy[i];
    }
    free(at), free(dest);
    if (take) {   /* packed: the part's copy goes first */
        free(sc->x), free(sc->y), free(sc->vx), free(sc->vy);
        sc->x = sc->y = sc->vx = sc->vy = NULL;
    }
    double *rbuf = malloc((own ? own : 1) * REC * sizeof *rbuf);
    if (!rbuf)
        psim_dist_out_of_memory("the scene");
    alltoallv(d, sbuf, d->scnt, d->sdsp, rbuf, d->rcnt, d->rdsp, REC);
    free(sbuf);
    int rc = own_store(e, own, err);
    for (size_t k = 0; rc == 0 && k < own; k++)
        get_rec(&e->st, e->st.n++, rbuf + k * REC);
    free(rbuf);
    return rc;
}

int psim_dist_attach(psim_sim *e, psim_scene *sc, int take, psim_error *err)
{
    const psim_model *m = e->model;
    if (!m->halo && !m->shares) {
        if (m->one_process)
            psim_error_set(err, "the %s model runs in one process only: %s", m->name,
                           m->one_process);
        else
            psim_error_set(err, "the %s model runs in one process only (over MPI ranks: "
                                "psim models says which run over ranks)", m->name);
        err->usage = 1;
        return -1;
    }
    psim_dist *d = calloc(1, sizeof *d);
    if (!d || dist_cuts_alloc(&d->cuts, R(), sc->L)) {
        if (d)
            dist_cuts_free(&d->cuts);
        free(d);
        psim_error_set(err, "out of memory");
        return -1;
    }
    e->dist = d;
    int n = R();
    d->scnt = calloc(4 * (size_t)n, sizeof *d->scnt);
    if (!d->scnt) {
        psim_error_set(err, "out of memory");
        return -1;
    }
    d->sdsp = d->scnt + n, d->rcnt = d->sdsp + n, d->rdsp = d->rcnt + n;
    d->due = d->regrid = 1;
    d->comm_phase = e->stats.nphases;
    e->stats.phase_name[e->stats.nphases++] = "comm";
    if ((d->shares = !m->halo))   /* the engine fills the store as one process */
        return 0;
    if (sc->id)
        return keep_part(e, sc, take, err);
    /* every rank holds the whole scene here: each cuts the domains from it
     * alike and keeps its own particles (a little room for the ghosts) */
    cut(d, sc->L, sc->x, sc->y, (size_t)sc->n, 0);
    size_t own = 0;
    for (long i = 0; i < sc->n; i++)
        own += dist_cuts_owner(&d->cuts, sc->x[i], sc->y[i]) == me();
    if (own_store(e, own, err))
        return -1;
    for (long i = 0; i < sc->n; i++)
        if (dist_cuts_owner(&d->cuts, sc->x[i], sc->y[i]) == me())
            get_rec(&e->st, e->st.n++, (const double[REC]){(double)i, sc->x[i], sc->y[i],
                                                             sc->vx[i], sc->vy[i]});
    return 0;
}

int psim_dist_ready(psim_sim *e, psim_error *err)
{
    psim_dist *d = e->dist;
    d->gathered = grow(d->gathered, 5 * (size_t)R() * sizeof *d->gathered, "the ranks' figures");
    if (d->shares) {
        d->n_own = e->st.n;
        return 0;
    }
    e->model->halo(e, e->mstate, &d->halo);
    d->h = d->halo.reach + d->halo.skin;
    /* domains narrower than the halo: most particles would be ghosts
     * somewhere else too */
    double side = e->L / (d->cuts.px > d->cuts.py ? d->cuts.px : d->cuts.py);
    if (!(side >= d->h)) {
        psim_error_set(err, "%d ranks cut a box of side %g into domains %g wide, narrower "
                            "than the halo of the %s model (reach + skin = %g): use fewer ranks",
                       R(), e->L, side, e->model->name, d->h);
        err->usage = 1;
        return -1;
    }
    return 0;
}

void psim_dist_detach(psim_sim *e)
{
    psim_dist *d = e->dist;
    if (!d)
        return;
    dist_cuts_free(&d->cuts);
    free(d->scnt), free(d->send_id), free(d->recv_id), free(d->send_slot), free(d->recv_slot);
    free(d->ghost), free(d->x0), free(d->y0), free(d->from), free(d->where), free(d->ghost2);
    free(d->usend), free(d->urecv), free(d->pick), free(d->dest);
    if (d->ureq)
        MPI_Type_free(&d->utype);
    free(d->ureq), free(d->sreq), free(d->gathered);
    free(d);
    e->dist = NULL;
    e->st.from = NULL;
}

int psim_dist_prestep(psim_sim *e, psim_error *err)
{
    psim_dist *d = e->dist;
    (void)err;
    if (d->shares)
        return 0;
    double t0 = psim_now();
    if (d->due)
        exchange(e);
    else {
        update_start(e);
        if (!d->halo.waits)
            update_finish(e);
    }
    double dt = psim_now() - t0;
    *(d->due ? &d->rs.exchange_s : &d->rs.update_s) += dt;
    d->due = 0;
    e->stats.phase_s[d->comm_phase] += dt;
    return 0;
}

/* The largest squared displacement of an owned particle since the
 * exchange. */
static double drift2(const psim_sim *e)
{
    const psim_dist *d = e->dist;
    const psim_store *st = &e->st;
    double m = 0;
    if (!d->x0)   /* no origin yet: exchange, and measure from there */
        return INFINITY;
    for (size_t i = 0; i < st->n; i++) {
        if (d->ghost[i])
            continue;
        double dx = st->x[i] - d->x0[i], dy = st->y[i] - d->y0[i], d2 = dx * dx + dy * dy;
        if (!(d2 <= m))
            m = d2;
    }
    return m;
}

void psim_engine_paths(psim_sim *e, double p1, double p2)
{
    psim_dist *d = e->dist;
    if (!d)
        return;
    d->path[0] = p1, d->path[1] = p2;
    d->pathed = 1;
}

void psim_engine_moved(psim_sim *e, double most)
{
    psim_dist *d = e->dist;
    if (!d)
        return;
    if (!(most <= d->moved))
        d->moved = most;
    d->said = d->says = 1;
}

int psim_dist_poststep(psim_sim *e, int rc, psim_error *err)
{
    psim_dist *d = e->dist;
    psim_engine_halo_wait(e);   /* a step that ended before it read the ghosts */
    double t0 = psim_now();
    const int stopped = psim_stop_requested();
    /* the drift: the step's as the model said it (summed), or measured;
     * the two longest paths, as the model said them (else none known) */
    d->unsaid |= !d->said && !d->shares;
    const double moved = rc || d->shares ? 0 : d->said ? d->moved : drift2(e);
    double v[5] = {rc && !stopped ? 1 : 0, stopped, moved,
                   d->pathed ? d->path[0] : INFINITY, d->pathed ? d->path[1] : INFINITY};
    for (int k = 2; k < 5; k++)
        if (v[k] != v[k])
            v[k] = INFINITY;
    double *all = d->gathered;
    double t1 = psim_now();
    MPI_Allgather(v, 5, MPI_DOUBLE, all, 5, MPI_DOUBLE, MPI_COMM_WORLD);
    d->rs.wait_s += psim_now() - t1;
    e->stats.phase_s[d->comm_phase] += psim_now() - t0;
    double p1 = 0, p2 = 0;   /* the two longest paths over the ranks */
    for (int q = 0; q < R(); q++) {
        const double *w = all + 5 * q;
        for (int k = 0; k < 3; k++)
            v[k] = w[k] > v[k] ? w[k] : v[k];
        for (int k = 3; k < 5; k++)
            if (w[k] > p1)
                p2 = p1, p1 = w[k];
            else if (w[k] > p2)
                p2 = w[k];
    }
    if (v[0] || v[1]) {
        if (!rc && v[1])
            return psim_engine_stopped(e, err);
        if (!rc)
            psim_error_set(err, "%s", "");   /* the rank that failed says why */
        return -1;
    }
    if (d->shares)
        return 0;
    d->drift = d->said ? d->drift + v[2] : sqrt(v[2]);
    if (d->said && d->x0) {   /* the model says it: no origin needed */
        free(d->x0), free(d->y0);
        d->x0 = d->y0 = NULL, d->cap0 = 0;
    }
    d->said = 0, d->moved = 0, d->pathed = 0;
    /* two particles have closed in by at most twice the drift, and by at
     * most the two longest paths */
    d->due = !(2 * d->drift <= d->halo.skin) && !(p1 + p2 <= d->halo.skin);
    return 0;
}

void psim_engine_reduce(psim_sim *e, double *sum, int nsum, double *least, int nleast)
{
    if (!e->dist)
        return;
    double t0 = psim_now();
    if (nsum)
        MPI_Allreduce(MPI_IN_PLACE, sum, nsum, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    if (nleast)
        MPI_Allreduce(MPI_IN_PLACE, least, nleast, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
    e->stats.phase_s[e->dist->comm_phase] += psim_now() - t0;
}

int psim_dist_finite(const psim_sim *e, psim_error *err)
{
    const psim_store *s = &e->st;
    size_t bad = psim_engine_not_finite(e, e->dist->ghost);
    /* the least id not finite over the ranks; its owner names it */
    double v = bad < s->n ? -(double)s->id[bad] : -INFINITY;
    MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    if (v == -INFINITY)
        return 0;
    if (bad < s->n && -(double)s->id[bad] == v)
        psim_engine_not_finite_error(e, bad, err);
    else
        psim_error_set(err, "%s", "");
    return -1;
}

int psim_dist_bbox(const psim_sim *e, double *bb)
{
    const psim_dist *d = e->dist;
    if (!(d->h > 0))
        return -1;
    const dist_cuts *c = &d->cuts;
    int i = me() / c->py, j = me() % c->py;
    const double *cy = c->cy + (size_t)i * (c->py + 1);
    bb[0] = fmax(c->cx[i] - d->h, 0), bb[2] = fmin(c->cx[i + 1] + d->h, e->L);
    bb[1] = fmax(cy[j] - d->h, 0), bb[3] = fmin(cy[j + 1] + d->h, e->L);
    if (!(bb[0] < bb[2] && bb[1] < bb[3]))   /* an empty domain: the box */
        bb[0] = bb[1] = 0, bb[2] = bb[3] = e->L;
    return 0;
}

void psim_dist_sorted(psim_sim *e)
{
    psim_dist *d = e->dist;
    if (d->shares)
        return;
    if (!e->st.from) {   /* a sort before the first exchange */
        d->due = 1;
        return;
    }
    double t0 = psim_now();
    const size_t n = e->st.n;
    const uint32_t *from = d->from;
    for (size_t k = 0; k < n; k++) {
        d->where[from[k]] = (uint32_t)k;
        d->ghost2[k] = d->ghost[from[k]];
    }
    uint8_t *t = d->ghost;
    d->ghost = d->ghost2, d->ghost2 = t;
    for (size_t k = 0; k < d->nsend; k++)
        d->send_slot[k] = d->where[d->send_slot[k]];
    for (size_t k = 0; k < d->nrecv; k++)
        d->recv_slot[k] = d->where[d->recv_slot[k]];
    /* a sort without an exchange loses the drift's origin (measured from
     * the places): the next step exchanges */
    if (!d->exchanged && !d->says)
        d->due = 1;
    if (d->unsaid)
        mark(e);
    d->exchanged = 0;
    e->stats.phase_s[d->comm_phase] += psim_now() - t0;
}

void psim_dist_reduce_stats(psim_sim *e, psim_rank_stats *per)
{
    psim_dist *d = e->dist;
    psim_stats *st = &e->stats;
    d->rs.comm_s = st->phase_s[d->comm_phase];
    memcpy(d->rs.phase_s, st->phase_s, sizeof d->rs.phase_s);
    d->rs.owned = (long)d->n_own;
    d->rs.ghosts = (long)(e->st.n - d->n_own);
    MPI_Gather(&d->rs, sizeof d->rs, MPI_BYTE, per, sizeof d->rs, MPI_BYTE, 0, MPI_COMM_WORLD);
    uint64_t sum[PSIM_COUNTERS_MAX], most[PSIM_COUNTERS_MAX];
    MPI_Reduce(st->counter, sum, PSIM_COUNTERS_MAX, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    MPI_Reduce(st->counter, most, PSIM_COUNTERS_MAX, MPI_UINT64_T, MPI_MAX, 0, MPI_COMM_WORLD);
    double t[PSIM_PHASES_MAX];
    MPI_Reduce(st->phase_s, t, PSIM_PHASES_MAX, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
    if (me() != 0)
        return;
    for (int k = 0; k < st->ncounters; k++)
        st->counter[k] = strncmp(st->counter_name[k], "max_", 4) ? sum[k] : most[k];
    memcpy(st->phase_s, t, sizeof t);
}

int psim_engine_exchanged(const psim_sim *e)
{
    return e->dist && e->dist->exchanged;
}

double psim_engine_drift(const psim_sim *e)
{
    return e->dist ? e->dist->drift : 0;
}

int psim_engine_ghost(const psim_sim *e, size_t place)
{
    return e->dist && e->dist->ghost && e->dist->ghost[place];
}

int psim_dist_shares(const psim_sim *e)
{
    return e->dist && e->dist->shares;
}

int psim_engine_rank(const psim_sim *e)
{
    return e->dist ? me() : 0;
}

int psim_dist_said(int rc)
{
    int v[2] = {rc, rc ? errno : 0};
    MPI_Bcast(v, 2, MPI_INT, 0, MPI_COMM_WORLD);
    errno = v[1];
    return v[0];
}

void psim_engine_sendrecv(psim_sim *e, const void *send, const size_t *sbytes, void *recv,
                          const size_t *rbytes)
{
    psim_dist *d = e->dist;
    const int n = R();
    double t0 = psim_now();
    d->sreq = grow(d->sreq, 2 * (size_t)n * sizeof *d->sreq, "an exchange");
    int nreq = 0;
    size_t s = 0, r = 0;
    for (int q = 0; q < n; q++) {
        if (sbytes[q] > INT_MAX || rbytes[q] > INT_MAX) {
            fprintf(stderr, "psim: rank %d: more than 2 GiB in one message\n", me());
            psim_dist_abort(1);
        }
        if (q == me())
            memcpy((char *)recv + r, (const char *)send + s, sbytes[q]);
        else {
            if (rbytes[q])
                MPI_Irecv((char *)recv + r, (int)rbytes[q], MPI_BYTE, q, 7, MPI_COMM_WORLD,
                          &d->sreq[nreq++]);
            if (sbytes[q]) {
                MPI_Isend((const char *)send + s, (int)sbytes[q], MPI_BYTE, q, 7,
                          MPI_COMM_WORLD, &d->sreq[nreq++]);
                d->rs.bytes_sent += sbytes[q];
                d->rs.messages_sent++;
            }
        }
        s += sbytes[q], r += rbytes[q];
    }
    MPI_Waitall(nreq, d->sreq, MPI_STATUSES_IGNORE);
    e->stats.phase_s[d->comm_phase] += psim_now() - t0;
}

void psim_engine_share(psim_sim *e, const void *mine, size_t bytes, void **all, size_t *each)
{
    psim_dist *d = e->dist;
    const int n = R();
    double t0 = psim_now();
    if (bytes > INT_MAX) {
        fprintf(stderr, "psim: rank %d: more than 2 GiB to share at once\n", me());
        psim_dist_abort(1);
    }
    int b = (int)bytes;
    MPI_Allgather(&b, 1, MPI_INT, d->rcnt, 1, MPI_INT, MPI_COMM_WORLD);
    size_t r = 0;
    for (int q = 0; q < n; q++) {
        if (r > INT_MAX - (size_t)d->rcnt[q]) {
            fprintf(stderr, "psim: rank %d: more than 2 GiB to share at once\n", me());
            psim_dist_abort(1);
        }
        d->rdsp[q] = (int)r, each[q] = (size_t)d->rcnt[q], r += (size_t)d->rcnt[q];
    }
    *all = grow(NULL, r, "an exchange");
    MPI_Allgatherv(mine, b, MPI_BYTE, *all, d->rcnt, d->rdsp, MPI_BYTE, MPI_COMM_WORLD);
    d->rs.bytes_sent += (uint64_t)(n - 1) * bytes;
    d->rs.messages_sent += (uint64_t)(n - 1);
    e->stats.phase_s[d->comm_phase] += psim_now() - t0;
}

#else /* without MPI no run has ranks: never called */

int psim_dist_attach(psim_sim *e, psim_scene *sc, int take, psim_error *err)
{
    (void)take, (void)e, (void)sc;
    psim_error_set(err, "built without MPI");
    return -1;
}
void psim_dist_detach(psim_sim *e) { (void)e; }
int psim_dist_ready(psim_sim *e, psim_error *err) { (void)e, (void)err; return 0; }
int psim_dist_bbox(const psim_sim *e, double *bb) { (void)e, (void)bb; return -1; }
int psim_dist_prestep(psim_sim *e, psim_error *err) { (void)e, (void)err; return 0; }
int psim_dist_poststep(psim_sim *e, int rc, psim_error *err) { (void)e, (void)err; return rc; }
void psim_dist_sorted(psim_sim *e) { (void)e; }
void psim_dist_reduce_stats(psim_sim *e, psim_rank_stats *per) { (void)e, (void)per; }
int psim_engine_exchanged(const psim_sim *e) { (void)e; return 0; }
void psim_engine_moved(psim_sim *e, double most) { (void)e, (void)most; }
void psim_engine_paths(psim_sim *e, double p1, double p2) { (void)e, (void)p1, (void)p2; }
void psim_engine_reduce(psim_sim *e, double *sum, int nsum, double *least, int nleast)
{
    (void)e, (void)sum, (void)nsum, (void)least, (void)nleast;
}
int psim_dist_finite(const psim_sim *e, psim_error *err) { (void)e, (void)err; return 0; }
double psim_engine_drift(const psim_sim *e) { (void)e; return 0; }
int psim_engine_ghost(const psim_sim *e, size_t place) { (void)e, (void)place; return 0; }
int psim_dist_shares(const psim_sim *e) { (void)e; return 0; }
int psim_engine_rank(const psim_sim *e) { (void)e; return 0; }
int psim_dist_said(int rc) { return rc; }
void psim_engine_sendrecv(psim_sim *e, const void *send, const size_t *sbytes, void *recv,
                          const size_t *rbytes)
{
    (void)e, (void)rbytes;
    memcpy(recv, send, sbytes[0]);
}
void psim_engine_share(psim_sim *e, const void *mine, size_t bytes, void **all, size_t *each)
{
    (void)e;
    if (!(*all = malloc(bytes ? bytes : 1)))
        psim_dist_out_of_memory("an exchange");
    if (bytes)
        memcpy(*all, mine, bytes);
    each[0] = bytes;
}
int psim_engine_halo_pending(const psim_sim *e) { (void)e; return 0; }
double psim_engine_halo_wait(psim_sim *e) { (void)e; return 0; }
size_t psim_engine_ghosts(const psim_sim *e, const uint32_t **place)
{
    (void)e;
    *place = NULL;
    return 0;
}

#endif
