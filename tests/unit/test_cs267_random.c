/* The CS267 HW2 initial state (src/io/cs267_random.c): std::mt19937 and
 * libstdc++'s uniform_int_distribution<int> / uniform_real_distribution
 * <float> written out in C.  Run plainly it checks values known from the C++
 * standard and from a real C++ program (tests/unit/cs267_random_ref.cpp);
 * run as `test_cs267_random dump` it prints the draws that
 * cs267_random_ref.cpp prints, for tests/unit/cs267_random_vs_cxx.sh to
 * compare byte for byte. */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "io/cs267_random.h"

/* The same lists as in cs267_random_ref.cpp. */
static const uint32_t seeds[] = {0u, 1u, 42u, 5489u, 4294967295u};
static const int int_ranges[][2] = {
    {0, 0}, {0, 1}, {0, 999}, {0, 2147483646}, {-5, 5},
    {-1000, -1}, {INT_MIN, (1 << 30) - 1}, {INT_MIN, INT_MAX}};
static const float real_ranges[][2] = {{-1.0f, 1.0f}, {0.0f, 1.0f}, {-2.5f, 7.0f}};
static const uint32_t edge_u[] = {
    0u, 1u, 127u, 128u, 255u, 256u, 0x7fffffffu, 0x80000000u, 0xffffff7fu,
    0xffffff80u, 0xfffffffeu, 0xffffffffu};
static const int place_n[] = {1, 2, 7, 1000};
#define COUNT(a) (sizeof(a) / sizeof((a)[0]))
enum { DRAWS = 50 };

static int dump(void)
{
    psim_mt19937 g;
    for (size_t s = 0; s < COUNT(seeds); s++) {
        psim_mt19937_seed(&g, seeds[s]);
        printf("mt19937 %u\n", (unsigned)seeds[s]);
        for (int i = 0; i < DRAWS; i++)
            printf("%u\n", (unsigned)psim_mt19937_next(&g));
    }
    for (size_t s = 0; s < COUNT(seeds); s++)
        for (size_t r = 0; r < COUNT(int_ranges); r++) {
            int a = int_ranges[r][0], b = int_ranges[r][1];
            psim_mt19937_seed(&g, seeds[s]);
            printf("int %u %d %d\n", (unsigned)seeds[s], a, b);
            for (int i = 0; i < DRAWS; i++)
                printf("%d\n", psim_uniform_int(&g, a, b));
            printf("next %u\n", (unsigned)psim_mt19937_next(&g));
        }
    for (size_t s = 0; s < COUNT(seeds); s++)
        for (size_t r = 0; r < COUNT(real_ranges); r++) {
            float a = real_ranges[r][0], b = real_ranges[r][1];
            psim_mt19937_seed(&g, seeds[s]);
            printf("real %u %a %a\n", (unsigned)seeds[s], (double)a, (double)b);
            for (int i = 0; i < DRAWS; i++) {
                float v = psim_uniform_real_float(&g, a, b);
                printf("%a %.9g\n", (double)v, (double)v);
            }
        }
    for (size_t e = 0; e < COUNT(edge_u); e++) {
        float c = psim_canonical_float(edge_u[e]);
        float v = c * (1.0f - -1.0f) + -1.0f;
        printf("canonical %u %a %a\n", (unsigned)edge_u[e], (double)c, (double)v);
    }
    for (size_t s = 0; s < COUNT(seeds); s++)
        for (size_t k = 0; k < COUNT(place_n); k++) {
            int n = place_n[k];
            double size = sqrt(0.0005 * n);
            double *x = malloc(4 * (size_t)n * sizeof *x);
            if (!x || psim_cs267_place(n, seeds[s], size, x, x + n, x + 2 * n, x + 3 * n)) {
                fprintf(stderr, "out of memory\n");
                free(x);
                return 1;
            }
            printf("place %d %u %.17g\n", n, (unsigned)seeds[s], size);
            for (int i = 0; i < n; i++)
                printf("%d %.17g %.17g %.17g %.17g\n", i, x[i], x[n + i],
                       x[2 * n + i], x[3 * n + i]);
            free(x);
        }
    return fflush(stdout) == 0 ? 0 : 1;
}

static void test_mt19937(void)
{
    psim_mt19937 g;
    psim_mt19937_seed(&g, 5489u);
    uint32_t v = 0;
    for (int i = 0; i < 10000; i++)
        v = psim_mt19937_next(&g);
    CHECK_MSG(v == 4123659995u, "10000th output %u", (unsigned)v); /* [rand.predef] */
    /* std::mt19937(1): from cs267_random_ref.cpp */
    psim_mt19937_seed(&g, 1u);
    CHECK(psim_mt19937_next(&g) == 1791095845u);
    CHECK(psim_mt19937_next(&g) == 4282876139u);
    CHECK(psim_mt19937_next(&g) == 3093770124u);
}

static void test_uniform_int(void)
{
    psim_mt19937 g;
    psim_mt19937_seed(&g, 42u);
    CHECK(psim_uniform_int(&g, 0, 999) == 374);
    CHECK(psim_uniform_int(&g, 0, 999) == 796);
    CHECK(psim_uniform_int(&g, 0, 999) == 950);
    CHECK(psim_uniform_int(&g, 0, 999) == 183);
    /* a range of 3 * 2^30 rejects a quarter of the draws (Lemire's loop) */
    psim_mt19937_seed(&g, 42u);
    CHECK(psim_uniform_int(&g, INT_MIN, (1 << 30) - 1) == -941005492);
    CHECK(psim_uniform_int(&g, INT_MIN, (1 << 30) - 1) == 418360902);
    CHECK(psim_uniform_int(&g, INT_MIN, (1 << 30) - 1) == -1556598838);
    for (int i = 3; i < 50; i++)
        psim_uniform_int(&g, INT_MIN, (1 << 30) - 1);
    CHECK(psim_mt19937_next(&g) == 732395540u);
    /* a one-value range still draws once */
    psim_mt19937 h;
    psim_mt19937_seed(&g, 7u);
    psim_mt19937_seed(&h, 7u);
    CHECK(psim_uniform_int(&g, 5, 5) == 5);
    psim_mt19937_next(&h);
    CHECK(psim_mt19937_next(&g) == psim_mt19937_next(&h));
    for (int i = 0; i < 1000; i++) {
        int v = psim_uniform_int(&g, -3, 4);
        CHECK(v >= -3 && v <= 4);
    }
}

static void test_uniform_real(void)
{
    psim_mt19937 g;
    psim_mt19937_seed(&g, 1u);
    CHECK(psim_uniform_real_float(&g, -1.0f, 1.0f) == -0x1.53e0cp-3f);
    CHECK(psim_uniform_real_float(&g, -1.0f, 1.0f) == 0x1.fd1e04p-1f);
    /* (float)u rounds up to 2^32 for u >= 2^32 - 128: kept below 1 */
    CHECK(psim_canonical_float(0xffffff7fu) == 0x1.fffffep-1f);
    CHECK(psim_canonical_float(0xffffffffu) == 0x1.fffffep-1f);
    CHECK(psim_canonical_float(0u) == 0.0f);
    CHECK(psim_canonical_float(0x80000000u) == 0.5f);
    for (int i = 0; i < 100000; i++) {
        float v = psim_uniform_real_float(&g, -1.0f, 1.0f);
        CHECK(v >= -1.0f && v < 1.0f);
    }
}

static void test_place(void)
{
    /* init_particles(parts, 7, sqrt(0.0005 * 7), 1) of the course, as the
     * C++ program computes it: k, x, y, vx, vy of each particle */
    static const double want[7][5] = {
        {2, 0x1.6b7be39d58736p-5, 0x1.e4a52f7c75ef2p-7, 0x1.fd1e04p-1, 0x1.c3398p-2},
        {5, 0x1.6b7be39d58736p-5, 0x1.e4a52f7c75ef2p-6, -0x1.ffe204p-1, -0x1.7cccf2p-1},
        {1, 0x1.e4a52f7c75ef2p-6, 0x1.e4a52f7c75ef2p-7, 0x1.ff047cp-1, -0x1.69b8d4p-1},
        {0, 0x1.e4a52f7c75ef2p-7, 0x1.e4a52f7c75ef2p-7, -0x1.a171fep-1, -0x1.a79af8p-3},
        {3, 0x1.e4a52f7c75ef2p-7, 0x1.e4a52f7c75ef2p-6, -0x1.cb1e18p-3, -0x1.3c4aa8p-2},
        {4, 0x1.e4a52f7c75ef2p-6, 0x1.e4a52f7c75ef2p-6, -0x1.a6d728p-3, 0x1.bdfdf4p-1},
        {6, 0x1.e4a52f7c75ef2p-7, 0x1.6b7be39d58736p-5, 0x1.629f54p-1, -0x1.4afabp-3}};
    double x[7], y[7], vx[7], vy[7];
    double size = sqrt(0.0005 * 7);
    CHECK(psim_cs267_place(7, 1, size, x, y, vx, vy) == 0);
    for (int i = 0; i < 7; i++)
        CHECK_MSG(x[i] == want[i][1] && y[i] == want[i][2] && vx[i] == want[i][3] &&
                      vy[i] == want[i][4],
                  "particle %d", i);
    /* a 64-bit seed is taken mod 2^32, as std::mt19937's constructor does */
    double x2[7], y2[7], vx2[7], vy2[7];
    CHECK(psim_cs267_place(7, (UINT64_C(1) << 32) + 1, size, x2, y2, vx2, vy2) == 0);
    CHECK(memcmp(x, x2, sizeof x) == 0 && memcmp(y, y2, sizeof y) == 0);
    CHECK(memcmp(vx, vx2, sizeof vx) == 0 && memcmp(vy, vy2, sizeof vy) == 0);
    /* every lattice place used once */
    enum { N = 1000 };
    static double px[N], py[N], pvx[N], pvy[N];
    double s = sqrt(0.0005 * N);
    CHECK(psim_cs267_place(N, 5, s, px, py, pvx, pvy) == 0);
    int sx = 32, sy = 32;
    static char used[32 * 32];
    int dup = 0;
    for (int i = 0; i < N; i++) {
        int cx = (int)lround(px[i] * (1 + sx) / s - 1), cy = (int)lround(py[i] * (1 + sy) / s - 1);
        if (cx < 0 || cy < 0 || cx >= sx || cy >= sy || used[cy * sx + cx]++)
            dup++;
    }
    CHECK(dup == 0);
    /* a block of ids alone (each MPI rank's): the whole run's particles */
    static const long cuts[][2] = {{0, 1}, {0, 333}, {333, 334}, {500, 1000}, {999, 1000},
                                   {400, 400}};
    for (size_t c = 0; c < sizeof cuts / sizeof cuts[0]; c++) {
        long lo = cuts[c][0], hi = cuts[c][1];
        static double bx[N], by[N], bvx[N], bvy[N];
        CHECK(psim_cs267_place_part(N, 5, s, lo, hi, bx, by, bvx, bvy) == 0);
        size_t b = (size_t)(hi - lo) * sizeof(double);
        CHECK_MSG(memcmp(bx, px + lo, b) == 0 && memcmp(by, py + lo, b) == 0 &&
                      memcmp(bvx, pvx + lo, b) == 0 && memcmp(bvy, pvy + lo, b) == 0,
                  "block %ld..%ld", lo, hi);
    }
    CHECK(psim_cs267_place_part(N, 5, s, 10, 5, x, y, vx, vy) == -1);
    CHECK(psim_cs267_place_part(N, 5, s, 0, N + 1, px, py, pvx, pvy) == -1);
    /* n = 0 places nothing; n outside the course's int is refused */
    CHECK(psim_cs267_place(0, 1, 0.0, NULL, NULL, NULL, NULL) == 0);
    CHECK(psim_cs267_place(-1, 1, 1.0, x, y, vx, vy) == -1);
    CHECK(psim_cs267_place((long)INT_MAX + 1, 1, 1.0, x, y, vx, vy) == -1);
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "dump") == 0)
        return dump();
    if (argc != 1) {
        fprintf(stderr, "usage: %s [dump]\n", argv[0]);
        return 2;
    }
    test_mt19937();
    test_uniform_int();
    test_uniform_real();
    test_place();
    return check_done();
}
