/* ccd_baseline: a plain sequential all-pairs implementation of the CS3210
 * AY2019/20 rules, written apart from psim (no grid, no pruning, no
 * threads): every pair is tested every step.  It is the baseline of
 * bench/ccd_bench.sh and an independent oracle of the e2e tests, which
 * compare psim's ccd model with it byte for byte.
 *
 * usage: ccd_baseline SCENE   (2019 format; prints what the authors print) */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int32_t st[31];
static int fi, ri;

static int next_rand(void)
{
    uint32_t v = (uint32_t)st[fi] + (uint32_t)st[ri];
    st[fi] = (int32_t)v;
    if (++fi >= 31) {
        fi = 0;
        ++ri;
    } else if (++ri >= 31)
        ri = 0;
    return (int)(v >> 1);
}

static void seed_rand(unsigned seed)
{
    st[0] = (int32_t)seed;
    for (int i = 1; i < 31; i++) {
        long long w = 16807LL * st[i - 1] % 2147483647;
        st[i] = (int32_t)w;
    }
    fi = 3;
    ri = 0;
    for (int i = 0; i < 310; i++)
        next_rand();
}

static double U(void) { return next_rand() / (double)2147483647; }

typedef struct { double t; int p, q; } cand;

static int cmpc(const void *a, const void *b)
{
    const cand *x = a, *y = b;
    if (x->t != y->t)
        return x->t < y->t ? -1 : 1;
    if (x->p != y->p)
        return x->p < y->p ? -1 : 1;
    return (x->q > y->q) - (x->q < y->q);
}

static int N;
static double L, r;
static double *X, *Y, *VX, *VY;
static long *PC, *WC;

static void print_state(long s, int fin)
{
    for (int i = 0; i < N; i++) {
        printf("%ld %d %.8f %.8f %.8f %.8f", s, i, X[i], Y[i], VX[i], VY[i]);
        if (fin)
            printf(" %ld %ld", PC[i], WC[i]);
        printf("\n");
    }
}

/* wall time from where the disk would be after dt */
static int wall_time(int i, double dt, double *t)
{
    double m = r + 1e-14, tx = INFINITY, ty = INFINITY;
    int has = 0;
    if (VX[i] != 0) {
        if (X[i] + VX[i] * dt < m) { tx = (X[i] - r) / -VX[i]; has = 1; }
        else if (X[i] + VX[i] * dt > L - m) { tx = (L - r - X[i]) / VX[i]; has = 1; }
    }
    if (VY[i] != 0) {
        if (Y[i] + VY[i] * dt < m) { ty = (Y[i] - r) / -VY[i]; has = 1; }
        else if (Y[i] + VY[i] * dt > L - m) { ty = (L - r - Y[i]) / VY[i]; has = 1; }
    }
    *t = tx < ty ? tx : ty;
    return has;
}

static void rest(int i, double dt)
{
    double tw, tt = dt;
    if (wall_time(i, dt, &tw) && tw < tt)
        tt = tw;
    X[i] = X[i] + VX[i] * tt;
    Y[i] = Y[i] + VY[i] * tt;
}

int main(int argc, char **argv)
{
    FILE *f = argc > 1 ? fopen(argv[1], "r") : NULL;
    char word[16];
    long S;
    if (!f || fscanf(f, "%d %lf %lf %ld %15s", &N, &L, &r, &S, word) != 5) {
        fprintf(stderr, "usage: ccd_baseline SCENE (CS3210 AY2019/20 format)\n");
        return 2;
    }
    int print = strcmp(word, "print") == 0;
    X = calloc(N + 1, 8), Y = calloc(N + 1, 8), VX = calloc(N + 1, 8), VY = calloc(N + 1, 8);
    PC = calloc(N + 1, sizeof *PC), WC = calloc(N + 1, sizeof *WC);
    int i, got = 0;
    double a, b, c, d;
    while (fscanf(f, "%d %lf %lf %lf %lf", &i, &a, &b, &c, &d) == 5 && i >= 0 && i < N) {
        X[i] = a, Y[i] = b, VX[i] = c, VY[i] = d;
        got++;
    }
    if (!got) {
        seed_rand(3210);
        for (int k = 0; k < N; k++)
            for (int ok = 0; !ok;) {
                X[k] = r + U() * (L - 2 * r);
                Y[k] = r + U() * (L - 2 * r);
                ok = 1;
                for (int j = 0; j < k && ok; j++) {
                    double dx = X[k] - X[j], dy = Y[k] - Y[j];
                    ok = dx * dx + dy * dy > 4 * r * r;
                }
            }
        for (int k = 0; k < N; k++) {
            double s = L / (8 * r) + U() * (L / 4 - L / (8 * r)), ang = U() * 2 * M_PI;
            VX[k] = s * cos(ang);
            VY[k] = s * sin(ang);
        }
    }
    print_state(0, 0);
    cand *C = malloc(sizeof *C * ((size_t)N * (size_t)N / 2 + (size_t)N + 1));
    char *busy = malloc((size_t)N + 1);
    for (long s = 1; s <= S; s++) {
        size_t nc = 0;
        for (int p = 0; p < N; p++) {
            double t;
            if (wall_time(p, 1.0, &t))
                C[nc++] = (cand){t, p, -1};
            for (int q = p + 1; q < N; q++) {
                double dx = X[q] - X[p], dy = Y[q] - Y[p], dvx = VX[q] - VX[p], dvy = VY[q] - VY[p];
                double A = dvx * dvx + dvy * dvy, B = 2 * (dx * dvx + dy * dvy);
                double Cc = dx * dx + dy * dy - 4 * r * r, D = B * B - 4 * A * Cc;
                if (D > 0) {
                    t = (-B - sqrt(D)) / 2 / A;
                    if (t >= 0 && t <= 1)
                        C[nc++] = (cand){t, p, q};
                }
            }
        }
        qsort(C, nc, sizeof *C, cmpc);
        memset(busy, 0, (size_t)N);
        for (size_t k = 0; k < nc; k++) {
            int p = C[k].p, q = C[k].q;
            double t = C[k].t;
            if (busy[p] || (q >= 0 && busy[q]))
                continue;
            busy[p] = 1;
            X[p] += VX[p] * t;
            Y[p] += VY[p] * t;
            if (q < 0) {
                WC[p]++;
                if (X[p] - r <= 1e-14 || L - r - X[p] <= 1e-14) VX[p] = -VX[p];
                if (Y[p] - r <= 1e-14 || L - r - Y[p] <= 1e-14) VY[p] = -VY[p];
                rest(p, 1 - t);
                continue;
            }
            busy[q] = 1;
            X[q] += VX[q] * t;
            Y[q] += VY[q] * t;
            PC[p]++, PC[q]++;
            double dx = X[q] - X[p], dy = Y[q] - Y[p], dist = sqrt(dx * dx + dy * dy);
            double nx = dx / dist, ny = dy / dist, tx = -ny, ty = nx;
            double v1n = nx * VX[p] + ny * VY[p], v1t = tx * VX[p] + ty * VY[p];
            double v2n = nx * VX[q] + ny * VY[q], v2t = tx * VX[q] + ty * VY[q];
            VX[p] = v2n * nx + v1t * tx, VY[p] = v2n * ny + v1t * ty;
            VX[q] = v1n * nx + v2t * tx, VY[q] = v1n * ny + v2t * ty;
            rest(p, 1 - t);
            rest(q, 1 - t);
        }
        for (int p = 0; p < N; p++)
            if (!busy[p]) {
                X[p] += VX[p];
                Y[p] += VY[p];
            }
        if (print && s < S)
            print_state(s, 0);
    }
    print_state(S, 1);
    free(C), free(busy), free(X), free(Y), free(VX), free(VY), free(PC), free(WC);
    fclose(f);
    return 0;
}
