/* The outputs of a run over ranks, written in parallel (dist.h).
 *
 * A file is written in rounds.  Round j holds the lines of a span of
 * consecutive ids, cut into one part per rank (rank q the q-th part);
 * the spans follow each other through the ids, so the parts of a round
 * follow each other in the file, and the rounds too.  In a round each
 * rank receives the particles of its part from their owners (one
 * alltoallv of records id, x, y, vx, vy), makes them a simulation of
 * those ids in order (psim_part says which, and whether its text begins
 * or ends the file: the header goes with the first part, the footer with
 * the last), formats it through the same writer as one process into
 * memory, and learns from every rank's length where its bytes go.  Into
 * a regular file every rank writes its bytes at their offset, all
 * together (MPI_File_write_at_all, on the temporary file rank 0 opened
 * and every rank opened by a name rank 0 gave, psim_dist_output_open:
 * /proc/PID/fd/N for an unnamed file on one machine); rank 0's
 * own stream, which wrote what came before (the header of --out), is
 * flushed first and set after the last byte at the end.  Anything else
 * (standard output, a pipe, a device) is written by rank 0 alone, the
 * other ranks' parts sent to it in order.  The bytes are those of one
 * process, whatever the ranks and threads.
 *
 * Memory: a rank keeps, besides its state, the order of its own
 * particles by round (4 bytes each) and the buffers of one round: the
 * records it sends (at most its own particles of the round) and
 * receives, its part as a simulation and that part as text: a round's
 * part is at most PARTS_LINES lines, so the whole state is on no rank,
 * and a rank holds little more than its own share at any time.
 *
 * Failure: a rank whose formatting or writing fails says so in the
 * round's exchange of lengths (or in the last one, after the last
 * round); every rank then stops and returns -1 with errno the lowest
 * failed rank's, and the caller removes the file (rank 0's outfile
 * layer: no partial file and no temporary file are left). */
#include "dist.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine.h"
#include "../io/lines.h"

#ifdef PSIM_HAVE_MPI
#include <mpi.h>

/* Lines of a rank's part in a round, at most (PSIM_PART_LINES=N: fewer,
 * for tests that write many rounds). */
#define PARTS_LINES (1L << 18)
/* Doubles a particle travels as: id, x, y, vx, vy. */
#define REC 5

/* The outputs every rank opened for the writes in parallel: each rank's
 * stream that names one, and its MPI file. */
#define OUTPUTS_MAX 16
static struct {
    FILE *f;
    MPI_File fh;
} outputs[OUTPUTS_MAX];
static int noutputs;

struct psim_dist_parts {
    psim_sim *e;
    FILE *f;
    MPI_File *fh;          /* the file written at offsets; NULL: rank 0 writes */
    int R, me;
    long N, rounds, j;
    uint32_t *order;       /* own store places by (round, rank of the part) */
    size_t *start;         /* where each (round, rank) begins in order */
    double *sbuf, *rbuf;
    int *cnt;              /* send and receive counts and displacements */
    psim_sim view;
    psim_part part;
    size_t cap;            /* room in the view's columns */
    FILE *mem;
    char *text;
    size_t len;
    long long base;        /* rank 0's offset of the first part */
    long long at;          /* the offset of this round's first part */
    long long lines_before, lines_all;   /* this rank's, for the progress */
    int err;               /* this rank's failure (an errno), 0 if none */
    int failed;            /* every rank's: the lowest failed rank's errno */
};

static MPI_File *output_of(FILE *f)
{
    for (int k = 0; k < noutputs; k++)
        if (outputs[k].f == f)
            return &outputs[k].fh;
    return NULL;
}

/* An errno for an MPI error code. */
static int mpi_errno(int rc)
{
    int cls = MPI_ERR_OTHER;
    MPI_Error_class(rc, &cls);
    return cls == MPI_ERR_NO_SPACE ? ENOSPC
           : cls == MPI_ERR_QUOTA  ? EDQUOT
           : cls == MPI_ERR_ACCESS ? EACCES
           : cls == MPI_ERR_READ_ONLY ? EROFS
           : cls == MPI_ERR_NO_SUCH_FILE ? ENOENT
                                         : EIO;
}

/* Collective: every rank's err; the lowest rank's that is not 0, or 0. */
static int agree_err(int err)
{
    int low = psim_dist_agree(err != 0);
    if (low < 0)
        return 0;
    MPI_Bcast(&err, 1, MPI_INT, low, MPI_COMM_WORLD);
    return err ? err : EIO;
}

int psim_dist_one_node(void)
{
    static int one = -1;
    if (one < 0) {
        MPI_Comm node;
        int size = 0;
        MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
        MPI_Comm_size(node, &size);
        MPI_Comm_free(&node);
        one = size == psim_dist_ranks();
    }
    return one;
}

int psim_dist_output_open(FILE *f, const char *path)
{
    long long len = path ? (long long)strlen(path) : -1;
    MPI_Bcast(&len, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
    if (len < 0)
        return 0;   /* rank 0 writes it alone */
    char *name = malloc((size_t)len + 1);
    if (!name)
        psim_dist_out_of_memory("an output's name");
    if (path)
        memcpy(name, path, (size_t)len + 1);
    MPI_Bcast(name, (int)len + 1, MPI_CHAR, 0, MPI_COMM_WORLD);
    int err = noutputs == OUTPUTS_MAX ? EMFILE : 0;
    MPI_File fh = MPI_FILE_NULL;
    int rc = MPI_File_open(MPI_COMM_WORLD, name, MPI_MODE_WRONLY, MPI_INFO_NULL, &fh);
    free(name);
    if (rc != MPI_SUCCESS)
        err = mpi_errno(rc);
    const int opened = rc == MPI_SUCCESS;
    err = agree_err(err);
    if (err) {
        /* (MPI opens a file on every rank or on none; a rank that did
         * open it while another could not cannot close it alone) */
        if (psim_dist_agree(!opened) >= 0 && psim_dist_agree(opened) >= 0) {
            fprintf(stderr, "psim: rank %d: an output opened on some ranks only\n",
                    psim_dist_rank());
            psim_dist_abort(1);
        }
        if (opened)
            MPI_File_close(&fh);
        errno = err;
        return -1;
    }
    outputs[noutputs].f = f;
    outputs[noutputs++].fh = fh;
    return 0;
}

int psim_dist_output_close(FILE *f)
{
    int k = 0;
    while (k < noutputs && outputs[k].f != f)
        k++;
    if (k == noutputs)
        return 0;
    int rc = MPI_File_close(&outputs[k].fh);
    memmove(&outputs[k], &outputs[k + 1], (size_t)(noutputs - k - 1) * sizeof outputs[0]);
    noutputs--;
    int err = agree_err(rc == MPI_SUCCESS ? 0 : mpi_errno(rc));
    if (err) {
        errno = err;
        return -1;
    }
    return 0;
}

int psim_dist_outputs_close(void)
{
    int rc = 0, err = 0;
    while (noutputs > 0)
        if (psim_dist_output_close(outputs[0].f))
            rc = -1, err = errno;
    errno = err;
    return rc;
}

/* The first id of round j's span, and of rank q's part of it (q = R: the
 * span's end). */
static long span_lo(const struct psim_dist_parts *w, long j)
{
    return (long)((long long)j * w->N / w->rounds);
}

static long part_lo(const struct psim_dist_parts *w, long j, int q)
{
    long s = span_lo(w, j), len = span_lo(w, j + 1) - s;
    return s + (long)((long long)q * len / w->R);
}

/* The round and part (j * R + q) of id i. */
static size_t key_of(const struct psim_dist_parts *w, long i)
{
    long j = (long)((long long)i * w->rounds / w->N);
    while (j + 1 < w->rounds && span_lo(w, j + 1) <= i)
        j++;
    while (j > 0 && span_lo(w, j) > i)
        j--;
    long s = span_lo(w, j), len = span_lo(w, j + 1) - s;
    int q = (int)((long long)(i - s) * w->R / len);
    while (q + 1 < w->R && part_lo(w, j, q + 1) <= i)
        q++;
    while (q > 0 && part_lo(w, j, q) > i)
        q--;
    return (size_t)j * (size_t)w->R + (size_t)q;
}

/* The order of the rank's own particles by round and part (a counting
 * sort of their store places). */
static void order_own(struct psim_dist_parts *w)
{
    const psim_sim *e = w->e;
    const psim_store *st = &e->st;
    const size_t keys = (size_t)w->rounds * (size_t)w->R;
    w->start = calloc(keys + 1, sizeof *w->start);
    size_t own = 0;
    for (size_t k = 0; k < st->n; k++)
        own += !psim_engine_ghost(e, k);
    w->order = malloc((own ? own : 1) * sizeof *w->order);
    if (!w->start || !w->order)
        psim_dist_out_of_memory("the outputs");
    for (size_t k = 0; k < st->n; k++)
        if (!psim_engine_ghost(e, k)) {
            if (st->id[k] < 0 || st->id[k] >= w->N) {
                fprintf(stderr, "psim: rank %d: particle %d is not one of %ld\n", w->me,
                        st->id[k], w->N);
                psim_dist_abort(1);
            }
            w->start[key_of(w, st->id[k]) + 1]++;
        }
    for (size_t k = 0; k < keys; k++)
        w->start[k + 1] += w->start[k];
    size_t *at = malloc((keys ? keys : 1) * sizeof *at);
    if (!at)
        psim_dist_out_of_memory("the outputs");
    memcpy(at, w->start, keys * sizeof *at);
    for (size_t k = 0; k < st->n; k++)
        if (!psim_engine_ghost(e, k))
            w->order[at[key_of(w, st->id[k])]++] = (uint32_t)k;
    free(at);
}

struct psim_dist_parts *psim_dist_parts_begin(psim_sim *e, FILE *f)
{
    struct psim_dist_parts *w = calloc(1, sizeof *w);
    if (!w)
        psim_dist_out_of_memory("the outputs");
    w->e = e, w->f = f;
    w->R = psim_dist_ranks(), w->me = psim_dist_rank();
    w->N = e->n_all;
    w->fh = output_of(f);
    long per = PARTS_LINES;
    const char *ev = getenv("PSIM_PART_LINES");
    if (ev && atol(ev) > 0 && atol(ev) < per)
        per = atol(ev);
    const long each = (w->N + w->R - 1) / w->R;   /* a rank's lines */
    w->rounds = each > per ? (each + per - 1) / per : 1;
    /* rank 0's stream up to date, and where the parts begin in it */
    long long head[2] = {w->fh != NULL, 0};
    if (w->me == 0) {
        if (fflush(f) != 0)
            w->err = errno ? errno : EIO;
        else if (w->fh && (head[1] = ftello(f)) < 0)
            w->err = errno ? errno : EIO;
    }
    MPI_Bcast(head, 2, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
    if (head[0] != (w->fh != NULL)) {
        fprintf(stderr, "psim: rank %d: an output is shared on some ranks only\n", w->me);
        psim_dist_abort(1);
    }
    w->base = w->at = head[1];
    order_own(w);
    long most = 1;
    for (long j = 0; j < w->rounds; j++) {
        long m = part_lo(w, j, w->me + 1) - part_lo(w, j, w->me);
        w->lines_all += m;
        most = m > most ? m : most;
    }
    w->cap = (size_t)most;
    w->view = *e;
    w->view.dist = NULL;
    w->view.part = &w->part;
    memset(&w->view.st, 0, sizeof w->view.st);
    psim_store *vs = &w->view.st;
    vs->cap = w->cap;
    vs->x = malloc(w->cap * sizeof *vs->x), vs->y = malloc(w->cap * sizeof *vs->y);
    vs->vx = malloc(w->cap * sizeof *vs->vx), vs->vy = malloc(w->cap * sizeof *vs->vy);
    vs->id = malloc(w->cap * sizeof *vs->id);
    w->rbuf = malloc(w->cap * REC * sizeof *w->rbuf);
    w->cnt = malloc(4 * (size_t)w->R * sizeof *w->cnt);
    if (!vs->x || !vs->y || !vs->vx || !vs->vy || !vs->id || !w->rbuf || !w->cnt)
        psim_dist_out_of_memory("the outputs");
    w->j = -1;
    return w;
}

/* Round j's particles of this rank's part into the view, in id order. */
static void gather_part(struct psim_dist_parts *w, long j)
{
    const psim_store *st = &w->e->st;
    const int R = w->R;
    int *scnt = w->cnt, *sdsp = scnt + R, *rcnt = sdsp + R, *rdsp = rcnt + R;
    const size_t *s = w->start + (size_t)j * (size_t)R;
    const size_t ns = s[R] - s[0];
    free(w->sbuf);
    w->sbuf = malloc((ns ? ns : 1) * REC * sizeof *w->sbuf);
    if (!w->sbuf)
        psim_dist_out_of_memory("the outputs");
    for (size_t a = 0; a < ns; a++) {
        size_t k = w->order[s[0] + a];
        double *o = w->sbuf + a * REC;
        o[0] = st->id[k], o[1] = st->x[k], o[2] = st->y[k], o[3] = st->vx[k], o[4] = st->vy[k];
    }
    for (int q = 0; q < R; q++)
        scnt[q] = (int)(s[q + 1] - s[q]), sdsp[q] = (int)(s[q] - s[0]);
    MPI_Alltoall(scnt, 1, MPI_INT, rcnt, 1, MPI_INT, MPI_COMM_WORLD);
    const long lo = part_lo(w, j, w->me), n = part_lo(w, j, w->me + 1) - lo;
    long got = 0;
    for (int q = 0; q < R; q++)
        rdsp[q] = (int)got, got += rcnt[q];
    if (got != n) {   /* a particle lost or doubled: never written */
        fprintf(stderr, "psim: rank %d: %ld particles for ids %ld..%ld, not %ld\n", w->me, got,
                lo, lo + n - 1, n);
        psim_dist_abort(1);
    }
    MPI_Datatype rec;
    MPI_Type_contiguous(REC, MPI_DOUBLE, &rec);
    MPI_Type_commit(&rec);
    MPI_Alltoallv(w->sbuf, scnt, sdsp, rec, w->rbuf, rcnt, rdsp, rec, MPI_COMM_WORLD);
    MPI_Type_free(&rec);
    free(w->sbuf);
    w->sbuf = NULL;
    psim_store *vs = &w->view.st;
    memset(vs->id, 0xff, (size_t)n * sizeof *vs->id);
    for (long a = 0; a < n; a++) {
        const double *p = w->rbuf + a * REC;
        long i = (long)p[0] - lo;
        if (i < 0 || i >= n || vs->id[i] >= 0) {
            fprintf(stderr, "psim: rank %d: particle %ld twice or not of ids %ld..%ld\n", w->me,
                    (long)p[0], lo, lo + n - 1);
            psim_dist_abort(1);
        }
        vs->id[i] = (int32_t)p[0];
        vs->x[i] = p[1], vs->y[i] = p[2], vs->vx[i] = p[3], vs->vy[i] = p[4];
    }
    vs->n = (size_t)n;
    w->view.n = n;
    w->part = (psim_part){lo, w->N, j == 0 && w->me == 0, j == w->rounds - 1 && w->me == R - 1};
}

psim_sim *psim_dist_parts_next(struct psim_dist_parts *w, FILE **mem)
{
    if (++w->j >= w->rounds || w->failed)
        return NULL;
    gather_part(w, w->j);
    w->text = NULL, w->len = 0;
    w->mem = open_memstream(&w->text, &w->len);
    if (!w->mem)
        psim_dist_out_of_memory("the outputs");
    psim_io_progress_part(w->lines_before, w->lines_all);
    *mem = w->mem;
    return &w->view;
}

/* Rank 0 alone writes: its own bytes, then every other rank's in turn. */
static int funnel(struct psim_dist_parts *w, const long long *len)
{
    int err = 0;
    if (w->me != 0) {
        MPI_Send(w->text, (int)w->len, MPI_BYTE, 0, 0, MPI_COMM_WORLD);
        return 0;
    }
    if (fwrite(w->text, 1, w->len, w->f) != w->len)
        err = errno ? errno : EIO;
    char *b = NULL;
    for (int q = 1; q < w->R; q++) {
        char *c = realloc(b, len[2 * q] ? (size_t)len[2 * q] : 1);
        if (!c)
            psim_dist_out_of_memory("the outputs");
        b = c;
        MPI_Recv(b, (int)len[2 * q], MPI_BYTE, q, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (!err && fwrite(b, 1, (size_t)len[2 * q], w->f) != (size_t)len[2 * q])
            err = errno ? errno : EIO;
    }
    free(b);
    return err;
}

void psim_dist_parts_done(struct psim_dist_parts *w, int rc)
{
    psim_io_progress_part(0, -1);
    if (rc != 0 && !w->err)
        w->err = errno ? errno : EIO;
    if (fclose(w->mem) != 0 && !w->err)
        w->err = errno ? errno : ENOMEM;
    w->mem = NULL;
    w->lines_before += w->view.n;
    if (!w->err && w->len > INT_MAX)
        w->err = EFBIG;   /* (never: a part has at most PARTS_LINES lines) */
    /* every rank's length and failure so far: where each writes, or stop */
    long long mine[2] = {w->err ? -1 : (long long)w->len, w->err};
    long long *all = malloc(2 * (size_t)w->R * sizeof *all);
    if (!all)
        psim_dist_out_of_memory("the outputs");
    MPI_Allgather(mine, 2, MPI_LONG_LONG, all, 2, MPI_LONG_LONG, MPI_COMM_WORLD);
    long long off = w->at, total = 0;
    for (int q = 0; q < w->R; q++) {
        if (all[2 * q] < 0 && !w->failed)
            w->failed = all[2 * q + 1] ? (int)all[2 * q + 1] : EIO;
        if (q < w->me)
            off += all[2 * q];
        total += all[2 * q];
    }
    if (!w->failed) {
        if (w->fh) {
            MPI_Status st;
            int wrote = -1;
            int r = MPI_File_write_at_all(*w->fh, (MPI_Offset)off, w->text, (int)w->len,
                                          MPI_BYTE, &st);
            if (r != MPI_SUCCESS)
                w->err = mpi_errno(r);
            else if (MPI_Get_count(&st, MPI_BYTE, &wrote) != MPI_SUCCESS ||
                     wrote != (int)w->len)
                w->err = ENOSPC;
        } else
            w->err = funnel(w, all);
        w->at += total;
    }
    free(all);
    free(w->text);
    w->text = NULL;
}

int psim_dist_parts_end(struct psim_dist_parts *w)
{
    /* rank 0's stream after the last byte; then whether every rank's
     * last write went well */
    if (!w->failed && w->fh && w->me == 0 && !w->err && fseeko(w->f, w->at, SEEK_SET) != 0)
        w->err = errno ? errno : EIO;
    int failed = w->failed ? w->failed : agree_err(w->err);
    psim_store *vs = &w->view.st;
    free(vs->x), free(vs->y), free(vs->vx), free(vs->vy), free(vs->id);
    free(w->rbuf), free(w->sbuf), free(w->cnt), free(w->order), free(w->start);
    free(w);
    if (failed) {
        errno = failed;
        return -1;
    }
    return 0;
}

#else /* without MPI no run has ranks: the parts are never written */

struct psim_dist_parts *psim_dist_parts_begin(psim_sim *e, FILE *f)
{
    (void)e, (void)f;
    return NULL;
}
psim_sim *psim_dist_parts_next(struct psim_dist_parts *w, FILE **mem)
{
    (void)w, (void)mem;
    return NULL;
}
void psim_dist_parts_done(struct psim_dist_parts *w, int rc) { (void)w, (void)rc; }
int psim_dist_parts_end(struct psim_dist_parts *w)
{
    (void)w;
    errno = ENOTSUP;
    return -1;
}
int psim_dist_one_node(void) { return 1; }
int psim_dist_output_open(FILE *f, const char *path)
{
    (void)f, (void)path;
    return 0;
}
int psim_dist_output_close(FILE *f)
{
    (void)f;
    return 0;
}
int psim_dist_outputs_close(void) { return 0; }

#endif
