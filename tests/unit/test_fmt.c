/* The fast number conversions (src/io/fmt.c) against the C library, byte
 * for byte: every writer against its snprintf reference and the reader
 * against strtod, on millions of doubles of every kind (random bit
 * patterns, typical ranges, integers, powers of ten, exact ties of the
 * fixed and %g formats and their neighbours, subnormals, zeros, extremes,
 * infinities and NaN).  PSIM_FMT_TEST_N sets the number of random values
 * per kind (default 100000, some 2.5 million doubles; sanitizer builds 10000). */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "io/fmt.h"

static uint64_t rng = 0x9E3779B97F4A7C15ull;

static uint64_t next(void)
{
    uint64_t z = (rng += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double unit(void) { return (double)(next() >> 11) * 0x1.0p-53; }

static double from_bits(uint64_t b)
{
    double d;
    memcpy(&d, &b, sizeof d);
    return d;
}

static long failures;

static void report(const char *what, double v, int arg, const char *got, const char *want)
{
    if (failures++ < 20)
        fprintf(stderr, "%s(%a, %d): got '%s', want '%s'\n", what, v, arg, got, want);
}

static void same(const char *what, double v, int arg, int glen, const char *got, int wlen,
                 const char *want)
{
    check_count++;
    if (glen != wlen || strcmp(got, want) != 0 || (int)strlen(got) != glen) {
        check_failures++;
        report(what, v, arg, got, want);
    }
}

/* every writer on v: shortest, fixed with N decimals (and 8, the course's;
 * both signs of zero), %g with precision P (and 6, C++ streams') */
static void writers(double v, int N, int P)
{
    char a[PSIM_FMT_MAX], b[PSIM_FMT_MAX];
    int la = psim_fmt_shortest(a, v), lb = psim_fmt_shortest_ref(b, v);
    same("shortest", v, -1, la, a, lb, b);
    for (int keep = 0; keep < 2; keep++) {
        la = psim_fmt_fixed(a, v, N, keep), lb = psim_fmt_fixed_ref(b, v, N, keep);
        same(keep ? "fixed_keep" : "fixed", v, N, la, a, lb, b);
    }
    la = psim_fmt_fixed(a, v, 8, 1), lb = psim_fmt_fixed_ref(b, v, 8, 1);
    same("fixed8", v, 8, la, a, lb, b);
    la = psim_fmt_general(a, v, P), lb = psim_fmt_general_ref(b, v, P);
    same("general", v, P, la, a, lb, b);
    la = psim_fmt_general(a, v, 6), lb = psim_fmt_general_ref(b, v, 6);
    same("general6", v, 6, la, a, lb, b);
}

static void all(double v)
{
    writers(v, (int)(next() % 31), (int)(next() % 31));
    writers(-v, (int)(next() % 23), (int)(next() % 18));
}

/* the reader on text: the same value and end as strtod, also for the
 * variant that reads past the number (digits there, after a NUL) */
static void reads(const char *text)
{
    char *end;
    double want = strtod(text, &end);
    char padded[PSIM_FMT_MAX + 32];
    size_t len = strlen(text);
    memcpy(padded, text, len + 1);
    memset(padded + len + 1, '7', 16);
    for (int pad = 0; pad < 2; pad++) {
        double got;
        const char *s = pad ? padded : text;
        const char *e = pad ? psim_scan_double_padded(s, &got) : psim_scan_double(s, &got);
        check_count++;
        if (!e)
            continue;   /* not a plain decimal: the caller asks strtod */
        if (e - s != end - text || memcmp(&got, &want, sizeof got) != 0) {
            check_failures++;
            if (failures++ < 20)
                fprintf(stderr, "scan%s('%s'): got %a (end +%ld), want %a (end +%ld)\n",
                        pad ? "_padded" : "", text, got, (long)(e - s), want,
                        (long)(end - text));
        }
    }
}

/* text forms of v the reader must read back */
static void reads_of(double v)
{
    char t[PSIM_FMT_MAX + 8];
    psim_fmt_shortest_ref(t, v);
    reads(t);
    snprintf(t, sizeof t, "%.17g", v);
    reads(t);
    snprintf(t, sizeof t, "%.8f", v);
    reads(t);
    snprintf(t, sizeof t, "%.*e", (int)(next() % 20), v);
    reads(t);
    snprintf(t, sizeof t, "%.*g", (int)(next() % 21) + 1, v);
    reads(t);
}

/* random decimal text: signs, leading zeros, points, exponents, 1..25 digits */
static void random_text(void)
{
    char t[96];
    int k = 0;
    uint64_t r = next();
    if (r & 1)
        t[k++] = (r & 2) ? '-' : '+';
    int lead = (int)((r >> 2) % 4);
    for (int i = 0; i < lead; i++)
        t[k++] = '0';
    int nd = (int)((r >> 4) % 25) + 1, point = (int)((r >> 9) % (nd + 2)) - 1;
    for (int i = 0; i < nd; i++) {
        if (i == point)
            t[k++] = '.';
        t[k++] = (char)('0' + next() % 10);
    }
    if (point == nd)
        t[k++] = '.';
    if ((r >> 14) & 1)
        k += snprintf(t + k, sizeof t - (size_t)k, "e%d", (int)((r >> 15) % 81) - 40);
    t[k] = '\0';
    reads(t);
}

int main(void)
{
    long n = 100000;
#ifdef PSIM_TEST_SANITIZED
    n = 10000;
#endif
    const char *env = getenv("PSIM_FMT_TEST_N");
    if (env && atol(env) > 0)
        n = atol(env);

    /* fixed points: zeros, extremes, subnormals, infinities, NaN */
    const double fixed[] = {0.0, -0.0, 1.0, 0.5, 0.1, 0.3, 1e-5, 1e-4, 1.5e20, 123456789012345678.0,
                            DBL_MAX, DBL_MIN, DBL_TRUE_MIN, 2 * DBL_TRUE_MIN, DBL_MIN / 3,
                            nextafter(DBL_MIN, 0), INFINITY, -INFINITY, NAN, -NAN,
                            9.5, 0.95, 0.095, 2.5, 0.125, 0.375, 1e15, 1e16, 1e17, 9.999999999999999e15,
                            99999999999999999.0, 0.1 + 0.2, 5e-324, 1.7976931348623157e308,
                            4503599627370496.0, 4503599627370497.0, 9007199254740993.0,
                            9223372036854775808.0, 18446744073709551616.0};
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++)
        for (int N = 0; N <= 30; N++)
            writers(fixed[i], N, N), writers(-fixed[i], N, N);

    /* powers of ten and their neighbours, every precision */
    for (int k = -330; k <= 310; k++) {
        double p = pow(10.0, k);
        double near[5] = {p, nextafter(p, 0), nextafter(p, INFINITY), p * 0.5, p * 1.5};
        for (int j = 0; j < 5; j++)
            for (int N = 0; N <= 30; N += 3)
                writers(near[j], N, N + 1);
    }
    /* powers of two (the uneven gap below them) and neighbours */
    for (int k = -1074; k <= 1023; k++) {
        double p = ldexp(1.0, k);
        all(p), all(nextafter(p, 0)), all(nextafter(p, INFINITY));
    }

    for (long i = 0; i < n; i++) {
        /* random bit patterns: every exponent, subnormals, NaN, inf */
        double v = from_bits(next());
        all(v);
        if (isfinite(v))
            reads_of(v);
        /* typical ranges: positions in boxes of side 1 to 1e6, velocities */
        double L = pow(10.0, (double)(next() % 7));
        v = unit() * L;
        all(v), reads_of(v);
        v = (2 * unit() - 1) * pow(10.0, -(double)(next() % 8));
        all(v), reads_of(v);
        /* integers, small and up to 2^63 */
        v = (double)(next() >> (next() % 64));
        all(v), reads_of(v);
        v = (double)(next() % 100000);
        all(v);
        /* exact ties of %.Nf: odd / 2^(N+1), and their neighbours */
        int N = (int)(next() % 23);
        v = ldexp((double)((next() >> (11 + next() % 40)) | 1), -(N + 1));
        writers(v, N, (int)(next() % 18));
        writers(nextafter(v, 0), N, 6);
        writers(nextafter(v, INFINITY), N, 6);
        /* exact ties of %.Pg: integers ending in 5, dyadic fractions */
        int P = (int)(next() % 17) + 1;
        uint64_t D = next() % 1000000000000000ull;
        v = (double)(D * 10 + 5);
        writers(v, N, P);
        v = ldexp((double)((next() >> (11 + next() % 50)) | 1), -(int)(next() % 30));
        writers(v, N, P);
        /* decimals of 15 to 17 digits (what psim gen writes) and neighbours */
        char t[64];
        snprintf(t, sizeof t, "%.*e", 14 + (int)(next() % 3), unit() * pow(10.0, (double)(next() % 12) - 6));
        v = strtod(t, NULL);
        all(v), all(nextafter(v, 0)), all(nextafter(v, INFINITY));
        reads(t);
        /* subnormals */
        v = from_bits(next() >> 12);
        all(v), reads_of(v);
        random_text();
        random_text();
    }
    /* reader edge cases */
    const char *texts[] = {"0", "-0", "+0", "0.0", "-0.000", ".5", "5.", "-.5e1", "1e0", "1e-0",
                           "00012.50", "1e22", "1e23", "9007199254740993", "9007199254740992.5",
                           "0.1", "0.30000000000000004", "2.2250738585072014e-308",
                           "4.9406564584124654e-324", "1.7976931348623157e308", "1e309",
                           "123456789012345678901234567890", "0.000000000000000000000000001",
                           "1e-27", "1.8446744073709551615e19", "18446744073709551615",
                           "18446744073709551616", "9999999999999999999", "1e", "1e+", "e5", ".",
                           "-", "inf", "nan", "0x1p3", "1.5.3", "1..5", "12345678901234567890e-10"};
    for (size_t i = 0; i < sizeof texts / sizeof texts[0]; i++)
        reads(texts[i]);
    /* the integers */
    char buf[32];
    const long long ints[] = {0, 1, -1, 9, 10, 99, 100, 12345, -987654321, 9223372036854775807LL,
                              -9223372036854775807LL - 1};
    for (size_t i = 0; i < sizeof ints / sizeof ints[0]; i++) {
        char want[32];
        snprintf(want, sizeof want, "%lld", ints[i]);
        *psim_fmt_long(buf, ints[i]) = '\0';
        CHECK_MSG(strcmp(buf, want) == 0, "%s != %s", buf, want);
    }
    return check_done();
}
