/* A scene file read in parts over MPI ranks (dist.h): each rank reads the
 * particle lines of one byte range of the file, so that no rank holds more
 * than its part, and the ranks agree on what one process would say of a
 * bad file (the first bad line of it, and the same message).
 *
 * The ranges split the particle lines' bytes evenly, each moved on to the
 * next line's start; a rank counts the newlines of its range, and the sum
 * over the ranks before it numbers its lines.  What a part cannot see
 * alone is put together from every rank's figures: the count of particle
 * lines before the first bad one (one process reads N of them, then says
 * "more particle lines than N" at the next line that is not blank, or
 * "unexpected end of file"), and the ids seen twice (each id's lines are
 * sent to the rank of its block of ids, which finds the second line that
 * has it, where one process says so).  Of every rank's candidate, the
 * earliest line is said, by the rank that found it. */
#include "dist.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

#ifdef PSIM_HAVE_MPI
#include <mpi.h>
#endif

#include "../io/scene_read.h"

#ifdef PSIM_HAVE_MPI

/* What a rank saw in its range: its particle lines before the first bad
 * line (if any), and its lines. */
typedef struct seen {
    long count, bad_line, lines;
    long bad;   /* PSIM_RANGE_*, 0: none */
} seen;

/* The rank that says a problem at `line` (LONG_MAX: none here) and every
 * other rank agree on the earliest; 0 when there is none anywhere, else
 * -1 with err emptied where it was not found. */
static int earliest(long line, psim_error *err)
{
    long low = line;
    MPI_Allreduce(&line, &low, 1, MPI_LONG, MPI_MIN, MPI_COMM_WORLD);
    if (low == LONG_MAX)
        return 0;
    int mine = line == low ? psim_dist_rank() : psim_dist_ranks(), first;
    MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first != psim_dist_rank())
        psim_error_set(err, "%s", "");
    return -1;
}

/* The rank of block q of ids (q's block: n q / R .. n (q + 1) / R - 1)
 * that holds id. */
static int block_of(long id, long n, int R)
{
    int q = (int)((double)id * R / (double)n);
    while (q > 0 && n * q / R > id)
        q--;
    while (q < R - 1 && n * (q + 1) / R <= id)
        q++;
    return q;
}

/* The earliest line that repeats an id of an earlier line (LONG_MAX: none):
 * the ids and lines of every rank's part sent to the ranks of their
 * blocks, each of which keeps the two first lines of each id. */
static long repeated(const psim_scene *sc, long n, psim_error *err)
{
    const int R = psim_dist_ranks(), me = psim_dist_rank();
    int *scnt = calloc(4 * (size_t)R, sizeof *scnt), *sdsp = scnt + R, *rcnt = sdsp + R,
        *rdsp = rcnt + R;
    long *sbuf = malloc(2 * (size_t)(sc->n ? sc->n : 1) * sizeof *sbuf);
    if (!scnt || !sbuf)
        psim_dist_out_of_memory("the scene");
    for (long i = 0; i < sc->n; i++)
        scnt[block_of(sc->id[i], n, R)] += 2;
    for (int q = 1; q < R; q++)
        sdsp[q] = sdsp[q - 1] + scnt[q - 1];
    int *at = malloc((size_t)R * sizeof *at);
    if (!at)
        psim_dist_out_of_memory("the scene");
    memcpy(at, sdsp, (size_t)R * sizeof *at);
    for (long i = 0; i < sc->n; i++) {
        int q = block_of(sc->id[i], n, R);
        sbuf[at[q]++] = sc->id[i], sbuf[at[q]++] = sc->line[i];
    }
    free(at);
    MPI_Alltoall(scnt, 1, MPI_INT, rcnt, 1, MPI_INT, MPI_COMM_WORLD);
    size_t got = 0;
    for (int q = 0; q < R; q++)
        rdsp[q] = (int)got, got += (size_t)rcnt[q];
    const long lo = n * me / R, hi = n * (me + 1) / R;
    long *rbuf = malloc((got ? got : 1) * sizeof *rbuf);
    long *first = malloc((size_t)(hi > lo ? hi - lo : 1) * 2 * sizeof *first);
    if (!rbuf || !first)
        psim_dist_out_of_memory("the scene");
    MPI_Alltoallv(sbuf, scnt, sdsp, MPI_LONG, rbuf, rcnt, rdsp, MPI_LONG, MPI_COMM_WORLD);
    free(sbuf), free(scnt);
    long *second = first + (hi - lo);
    for (long k = 0; k < hi - lo; k++)
        first[k] = second[k] = LONG_MAX;
    for (size_t k = 0; k < got; k += 2) {
        long i = rbuf[k] - lo, line = rbuf[k + 1];
        if (line < first[i])
            second[i] = first[i], first[i] = line;
        else if (line < second[i])
            second[i] = line;
    }
    free(rbuf);
    long best = LONG_MAX, id = -1;
    for (long k = 0; k < hi - lo; k++)
        if (second[k] < best)
            best = second[k], id = lo + k;
    free(first);
    if (id >= 0)
        psim_error_set(err, "%s:%ld: particle index %ld appears twice", sc->source, best, id);
    return best;
}

/* This rank's byte range of the particle lines, and its first line. */
static int my_range(const char *path, const psim_scene_span *sp, long long *a, long long *b,
                    long *line0, long *lines, psim_error *err)
{
    const int R = psim_dist_ranks(), q = psim_dist_rank();
    const long long bytes = sp->size - sp->data;
    long nl = 0;
    int rc = psim_io_line_start(path, sp->data, sp->data + bytes * q / R, a, err) ||
             (q + 1 < R ? psim_io_line_start(path, sp->data, sp->data + bytes * (q + 1) / R,
                                             b, err)
                        : (*b = sp->size, 0)) ||
             psim_io_count_lines(path, *a, *b, &nl, err);
    if (psim_dist_agree(rc) >= 0) {   /* a read error: its rank says it */
        if (!rc)
            psim_error_set(err, "%s", "");
        return -1;
    }
    long before = 0;
    MPI_Exscan(&nl, &before, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
    *line0 = sp->line0 + (q ? before : 0);
    *lines = nl;
    return 0;
}

/* What one process says of the particle lines as a whole, from every
 * rank's figures all[0..R) (this rank's part sc): the line of this rank's
 * problem (LONG_MAX: none) with err set. */
static long as_one(const psim_scene *sc, const seen *all, long n, long line0, psim_error *err)
{
    const int R = psim_dist_ranks(), me = psim_dist_rank();
    int qe = 0;   /* the first rank with a bad line */
    while (qe < R && !all[qe].bad)
        qe++;
    long before = 0, t = 0, lines = line0;
    for (int q = 0; q < R && q <= qe; q++)
        t += all[q].count, lines += all[q].lines;
    for (int q = 0; q < me; q++)
        before += all[q].count;
    if (t > n) {   /* the N+1-th particle line: more than N */
        if (me <= qe && before <= n && n < before + all[me].count) {
            psim_error_set(err, "%s:%ld: more particle lines than N = %ld", sc->source,
                           sc->line[n - before], n);
            return sc->line[n - before];
        }
        return LONG_MAX;
    }
    if (qe < R) {   /* the first bad line, said by its rank */
        if (me != qe)
            return LONG_MAX;
        if (all[qe].bad == PSIM_RANGE_READ_ERROR)
            return -1;
        if (t == n && all[qe].bad == PSIM_RANGE_NOT_PARTICLE)   /* a line after N of them */
            psim_error_set(err, "%s:%ld: more particle lines than N = %ld", sc->source,
                           all[qe].bad_line, n);
        return all[qe].bad_line;
    }
    if (t < n) {   /* the lines ended first: said by rank 0 */
        if (me)
            return LONG_MAX;
        psim_error_set(err, "%s:%ld: unexpected end of file: expected %ld particle lines, "
                            "found %ld", sc->source, lines + 1, n, t);
        return lines + 1;
    }
    return LONG_MAX;
}

int psim_dist_scene_read(const char *path, psim_restart_schema_fn schema, psim_scene *sc,
                         psim_error *err)
{
    psim_scene_span sp;
    if (psim_io_scene_read_head(path, schema, sc, &sp, err))   /* alike on every rank */
        return -1;
    if (sp.whole) {   /* every rank reads it whole (scene_read.h) */
        psim_scene_clear(sc);
        return psim_io_scene_read(path, schema, sc, err);
    }
    const long n = sc->n;
    const int R = psim_dist_ranks();
    long long a, b;
    long line0, lines;
    if (my_range(path, &sp, &a, &b, &line0, &lines, err)) {
        psim_scene_clear(sc);
        return -1;
    }
    sc->n_all = n;
    psim_range_read rr;
    psim_error mine = {{0}, 0};
    psim_io_scene_read_range(path, sc, a, b, line0, lines, &rr, &mine);
    if (!sc->id) {   /* (no memory for its arrays) */
        fprintf(stderr, "psim: rank %d: %s\n", psim_dist_rank(), mine.msg);
        psim_dist_abort(1);
    }
    seen s = {sc->n, rr.bad ? rr.line : 0, rr.lines, rr.bad}, *all = malloc((size_t)R * sizeof *all);
    if (!all)
        psim_dist_out_of_memory("the scene");
    MPI_Allgather(&s, 4, MPI_LONG, all, 4, MPI_LONG, MPI_COMM_WORLD);
    *err = mine;
    long line = as_one(sc, all, n, sp.line0, err);
    free(all);
    psim_error dup = {{0}, 0};
    long twice = repeated(sc, n, &dup);
    if (twice < line)
        line = twice, *err = dup;
    if (earliest(line, err)) {
        psim_scene_clear(sc);
        return -1;
    }
    return 0;
}

/* A particle of a part as it travels to every rank: id, x, y, vx, vy and
 * its line (0 for a made scene). */
#define WHOLE_REC 6

int psim_dist_scene_whole(psim_scene *sc, psim_error *err)
{
    (void)err;
    const int R = psim_dist_ranks();
    const long n = sc->n, all = sc->n_all;
    int *cnt = malloc(2 * (size_t)R * sizeof *cnt);
    double *mine = malloc((size_t)(n ? n : 1) * WHOLE_REC * sizeof *mine);
    double *got = malloc((size_t)(all ? all : 1) * WHOLE_REC * sizeof *got);
    if (!cnt || !mine || !got)
        psim_dist_out_of_memory("the scene");
    int *dsp = cnt + R, c = (int)n;
    for (long i = 0; i < n; i++) {
        double *o = mine + i * WHOLE_REC;
        o[0] = sc->id[i], o[1] = sc->x[i], o[2] = sc->y[i], o[3] = sc->vx[i], o[4] = sc->vy[i];
        o[5] = sc->line ? (double)sc->line[i] : 0;
    }
    MPI_Allgather(&c, 1, MPI_INT, cnt, 1, MPI_INT, MPI_COMM_WORLD);
    long total = 0;
    for (int q = 0; q < R; q++)
        dsp[q] = (int)total, total += cnt[q];
    if (total != all) {
        fprintf(stderr, "psim: rank %d: the parts hold %ld particles, not %ld\n",
                psim_dist_rank(), total, all);
        psim_dist_abort(1);
    }
    MPI_Datatype rec;
    MPI_Type_contiguous(WHOLE_REC, MPI_DOUBLE, &rec);
    MPI_Type_commit(&rec);
    MPI_Allgatherv(mine, c, rec, got, cnt, dsp, rec, MPI_COMM_WORLD);
    MPI_Type_free(&rec);
    free(mine), free(cnt);
    /* the parts in rank order are the file's lines in order: a restart
     * file's order of the particles */
    const int order = sc->restart.present && !sc->restart.order;
    free(sc->x), free(sc->y), free(sc->vx), free(sc->vy), free(sc->id), free(sc->line);
    sc->id = NULL, sc->line = NULL;
    sc->n = all;
    const size_t b = (size_t)(all ? all : 1) * sizeof(double);
    sc->x = malloc(b), sc->y = malloc(b), sc->vx = malloc(b), sc->vy = malloc(b);
    if (!sc->x || !sc->y || !sc->vx || !sc->vy)
        psim_dist_out_of_memory("the scene");
    if (sc->source && !(sc->line = calloc((size_t)(all ? all : 1), sizeof *sc->line)))
        psim_dist_out_of_memory("the scene");
    if (order && !(sc->restart.order = malloc((size_t)(all ? all : 1) * sizeof(int32_t))))
        psim_dist_out_of_memory("the scene");
    for (long k = 0; k < all; k++) {
        const double *p = got + k * WHOLE_REC;
        long i = (long)p[0];
        if (i < 0 || i >= all) {
            fprintf(stderr, "psim: rank %d: particle %ld is not one of %ld\n", psim_dist_rank(),
                    i, all);
            psim_dist_abort(1);
        }
        sc->x[i] = p[1], sc->y[i] = p[2], sc->vx[i] = p[3], sc->vy[i] = p[4];
        if (sc->line)
            sc->line[i] = (long)p[5];
        if (order)
            sc->restart.order[k] = (int32_t)i;
    }
    free(got);
    return 0;
}

#else

int psim_dist_scene_whole(psim_scene *sc, psim_error *err)
{
    (void)sc, (void)err;
    return 0;
}

int psim_dist_scene_read(const char *path, psim_restart_schema_fn schema, psim_scene *sc,
                         psim_error *err)
{
    return psim_io_scene_read(path, schema, sc, err);
}

#endif
