/* Fast text conversion of numbers, exactly as the C library converts them
 * (fmt.h).
 *
 * A finite double is m * 2^e (m < 2^53).  For the printf formats the
 * exact decimal value of |v| * 10^k is worked out as an integer q of 17
 * digits plus a remainder rem / 2^s, all in 128-bit integers (exact while
 * m * 10^k fits, which holds from about 1e-6 to 1e17 for %g, and for %.Nf
 * with N <= 22 below 2^63); rounding to p digits then looks at the exact
 * digits and remainder (glibc rounds to nearest, ties to even), and
 * whether such a decimal reads back to v is decided exactly too, against
 * the halfway points between v and its neighbours (strtod rounds to
 * nearest, ties to even).  Everything else goes to snprintf.
 *
 * Reading: a decimal of at most 19 significant digits D and exponent x is
 * D * 10^x.  With D < 2^53 and |x| <= 22 both D and 10^|x| are doubles and
 * one multiplication or division rounds it correctly (Clinger's fast
 * path); for x < 0 down to -27, D / 10^j = (D / 5^j) 2^-j, and D / 5^j is
 * an exact 128-by-64-bit integer division whose quotient (at least 63
 * bits) and remainder give the correctly rounded 53 bits; for 0 <= x <= 19,
 * D * 10^x is an exact 128-bit integer, rounded to 53 bits.  Anything else
 * (more digits, larger exponents) is read by strtod. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmt.h"

#if defined(__SIZEOF_INT128__)
#define FMT_FAST 1
typedef unsigned __int128 u128;
#else
#define FMT_FAST 0
#endif

static const uint64_t P10[20] = {
    1ull,
    10ull,
    100ull,
    1000ull,
    10000ull,
    100000ull,
    1000000ull,
    10000000ull,
    100000000ull,
    1000000000ull,
    10000000000ull,
    100000000000ull,
    1000000000000ull,
    10000000000000ull,
    100000000000000ull,
    1000000000000000ull,
    10000000000000000ull,
    100000000000000000ull,
    1000000000000000000ull,
    10000000000000000000ull,
};

static const char DIGITS2[201] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

int psim_io_slow(void)
{
    const char *s = getenv("PSIM_SLOW_IO");
    return s && *s && strcmp(s, "0") != 0;
}

/* ---- the references: the snprintf code the fast paths replace ------------ */

int psim_fmt_shortest_ref(char *buf, double v)
{
    /* the first of %.15g, %.16g, %.17g that reads back */
    int len = 0;
    for (int p = 15; p <= 17; p++) {
        len = snprintf(buf, PSIM_FMT_MAX, "%.*g", p, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    return len;
}

int psim_fmt_fixed_ref(char *buf, double v, int decimals, int keep_negzero)
{
    int len = snprintf(buf, PSIM_FMT_MAX, "%.*f", decimals, v);
    /* no negative zero: "-0.000" prints as "0.000" */
    if (!keep_negzero && buf[0] == '-' && strspn(buf + 1, "0.") == (size_t)(len - 1)) {
        memmove(buf, buf + 1, (size_t)len);
        len--;
    }
    return len;
}

int psim_fmt_general_ref(char *buf, double v, int prec)
{
    return snprintf(buf, PSIM_FMT_MAX, "%.*g", prec, v);
}

/* ---- integers ------------------------------------------------------------- */

/* Exactly 8 digits of v < 10^8 at p: two independent halves. */
static inline void put8(char *p, uint32_t v)
{
    uint32_t a = v / 10000, b = v % 10000;
    memcpy(p, DIGITS2 + 2 * (a / 100), 2);
    memcpy(p + 2, DIGITS2 + 2 * (a % 100), 2);
    memcpy(p + 4, DIGITS2 + 2 * (b / 100), 2);
    memcpy(p + 6, DIGITS2 + 2 * (b % 100), 2);
}

/* The decimal digits of v, right-aligned to end at `end`; returns their
 * start (at least one digit). */
static char *digits_back(char *end, uint64_t v)
{
    while (v >= 100000000) {
        uint64_t q = v / 100000000;
        end -= 8;
        put8(end, (uint32_t)(v - q * 100000000));
        v = q;
    }
    uint32_t w = (uint32_t)v;
    while (w >= 100) {
        uint32_t r = w % 100;
        w /= 100;
        end -= 2;
        memcpy(end, DIGITS2 + 2 * r, 2);
    }
    if (w >= 10) {
        end -= 2;
        memcpy(end, DIGITS2 + 2 * w, 2);
    } else {
        *--end = (char)('0' + w);
    }
    return end;
}

char *psim_fmt_ulong(char *p, unsigned long long v)
{
    char tmp[24];
    char *s = digits_back(tmp + sizeof tmp, v);
    size_t n = (size_t)(tmp + sizeof tmp - s);
    memcpy(p, s, n);
    return p + n;
}

char *psim_fmt_long(char *p, long long v)
{
    if (v < 0) {
        *p++ = '-';
        return psim_fmt_ulong(p, 0ull - (unsigned long long)v);
    }
    return psim_fmt_ulong(p, (unsigned long long)v);
}

#if FMT_FAST

/* ---- doubles as m * 2^e ----------------------------------------------------- */

typedef struct fbits {
    uint64_t m;   /* significand, with the hidden bit */
    int e;        /* v = m * 2^e */
    int be;       /* biased exponent field: 0 subnormal or zero, 0x7ff not finite */
} fbits;

static fbits split(double a)
{
    uint64_t bits;
    memcpy(&bits, &a, sizeof bits);
    fbits f;
    f.be = (int)((bits >> 52) & 0x7ff);
    f.m = bits & ((1ull << 52) - 1);
    if (f.be == 0) {
        f.e = -1074;
    } else {
        f.m |= 1ull << 52;
        f.e = f.be - 1075;
    }
    return f;
}

static u128 pow10_128(int k)
{
    return k <= 19 ? (u128)P10[k] : (u128)P10[19] * P10[k - 19];
}

/* |v| * 10^k = q + rem / 2^s exactly, q of 17 digits. */
typedef struct dec17 {
    uint64_t q;   /* in [1e16, 1e17) */
    u128 rem;     /* < 2^s */
    int s;
    int E;        /* floor(log10 |v|) = 16 - k */
    u128 ulp;     /* the spacing of doubles at v, in units of 10^-k 2^-s */
    int asym;     /* the spacing below v is half of ulp (m a power of two) */
    int even;     /* m even: a decimal exactly halfway reads back to v */
} dec17;

static int scale17(double a, dec17 *d)
{
    fbits f = split(a);
    if (f.be == 0 || f.be == 0x7ff)
        return -1;   /* zero, subnormal, not finite */
    d->even = (f.m & 1) == 0;
    d->asym = f.m == (1ull << 52) && f.be > 1;
    if (f.e >= 0) {
        if (f.e > 10)
            return -1;   /* >= 2^63 */
        uint64_t V = f.m << f.e;
        int E = 0;
        while (E < 18 && V >= P10[E + 1])
            E++;
        if (E > 16)
            return -1;
        int k = 16 - E;
        d->q = V * P10[k];
        d->rem = 0;
        d->s = 0;
        d->E = E;
        d->ulp = (u128)P10[k] << f.e;
        return 0;
    }
    int s = -f.e;
    /* floor(log10 a), or one off: corrected below */
    int E = (int)(((int64_t)(f.e + 52) * 78913) >> 18);
    for (int tries = 0; tries < 3; tries++) {
        int k = 16 - E;
        if (k > 22 || k < 0 || s > 120)
            return -1;   /* m * 10^k would not fit in 128 bits */
        u128 P = (u128)f.m * pow10_128(k);
        u128 q = P >> s;
        if (q >= P10[17]) {
            E++;
            continue;
        }
        if (q < P10[16]) {
            E--;
            continue;
        }
        /* 10^16 <= m 10^k / 2^s bounds 2^s below 2^53 10^6, so every
         * product below stays under 2^127 */
        d->q = (uint64_t)q;
        d->rem = P - (q << s);
        d->s = s;
        d->E = E;
        d->ulp = pow10_128(k);
        return 0;
    }
    return -1;
}

/* q rounded to p significant digits (1..17), to nearest, ties to even:
 * R (before the carry), whether it went up, and the remainder below the
 * p digits (low) with its unit, for the round-trip test. */
typedef struct rounded {
    uint64_t R;
    int up;
    u128 low, unit;
} rounded;

static inline rounded round_to(const dec17 *d, int p)
{
    rounded r;
    uint64_t T = P10[17 - p];
    r.R = d->q / T;
    r.low = ((u128)(d->q % T) << d->s) + d->rem;
    r.unit = (u128)T << d->s;
    u128 twice = r.low << 1;
    r.up = twice > r.unit || (twice == r.unit && (r.R & 1));
    return r;
}

/* Whether the rounded decimal reads back to v: it lies closer to v than
 * the halfway point to v's neighbour on its side (or on it, and m even). */
static inline int reads_back(const dec17 *d, const rounded *r)
{
    u128 dist = r->up ? r->unit - r->low : r->low;
    u128 lhs = dist << ((!r->up && d->asym) ? 2 : 1);
    return lhs < d->ulp || (lhs == d->ulp && d->even);
}

/* printf's %.Pg of the p-digit decimal R (+ up) * 10^(E - p + 1). */
static int put_g(char *buf, int neg, uint64_t R, int p, int up, int E, int P)
{
    int X = E;
    R += (uint64_t)up;
    if (R == P10[p]) {
        R = P10[p - 1];
        X++;
    }
    int nd = p;
    while (nd > 1 && R % 10 == 0) {
        R /= 10;
        nd--;
    }
    char dig[24];
    char *d0 = digits_back(dig + sizeof dig, R);   /* exactly nd digits */
    char *o = buf;
    if (neg)
        *o++ = '-';
    if (X < -4 || X >= P) {
        *o++ = d0[0];
        if (nd > 1) {
            *o++ = '.';
            memcpy(o, d0 + 1, (size_t)nd - 1);
            o += nd - 1;
        }
        *o++ = 'e';
        *o++ = X < 0 ? '-' : '+';
        int ax = X < 0 ? -X : X;
        if (ax >= 100) {
            *o++ = (char)('0' + ax / 100);
            ax %= 100;
        }
        memcpy(o, DIGITS2 + 2 * ax, 2);
        o += 2;
    } else if (X >= 0) {
        int ip = X + 1;
        if (nd <= ip) {
            memcpy(o, d0, (size_t)nd);
            o += nd;
            memset(o, '0', (size_t)(ip - nd));
            o += ip - nd;
        } else {
            memcpy(o, d0, (size_t)ip);
            o += ip;
            *o++ = '.';
            memcpy(o, d0 + ip, (size_t)(nd - ip));
            o += nd - ip;
        }
    } else {
        *o++ = '0';
        *o++ = '.';
        memset(o, '0', (size_t)(-X - 1));
        o += -X - 1;
        memcpy(o, d0, (size_t)nd);
        o += nd;
    }
    *o = '\0';
    return (int)(o - buf);
}

static int put_zero_g(char *buf, int neg)
{
    char *o = buf;
    if (neg)
        *o++ = '-';
    *o++ = '0';
    *o = '\0';
    return (int)(o - buf);
}

int psim_fmt_shortest(char *buf, double v)
{
    if (v == 0)
        return put_zero_g(buf, signbit(v) != 0);
    dec17 d;
    if (scale17(fabs(v), &d))
        return psim_fmt_shortest_ref(buf, v);
    /* one call per precision, so that the divisions by 10^(17-p) are by
     * constants */
    rounded r = round_to(&d, 15);
    if (reads_back(&d, &r))
        return put_g(buf, v < 0, r.R, 15, r.up, d.E, 15);
    r = round_to(&d, 16);
    if (reads_back(&d, &r))
        return put_g(buf, v < 0, r.R, 16, r.up, d.E, 16);
    r = round_to(&d, 17);
    return put_g(buf, v < 0, r.R, 17, r.up, d.E, 17);
}

int psim_fmt_general(char *buf, double v, int prec)
{
    int P = prec > 0 ? prec : 1;
    if (P > 17 || !isfinite(v))
        return psim_fmt_general_ref(buf, v, prec);
    if (v == 0)
        return put_zero_g(buf, signbit(v) != 0);
    dec17 d;
    if (scale17(fabs(v), &d))
        return psim_fmt_general_ref(buf, v, prec);
    rounded r = round_to(&d, P);
    return put_g(buf, v < 0, r.R, P, r.up, d.E, P);
}

int psim_fmt_fixed(char *buf, double v, int decimals, int keep_negzero)
{
    if (!isfinite(v) || decimals < 0 || decimals > 22)
        return psim_fmt_fixed_ref(buf, v, decimals, keep_negzero);
    int neg = signbit(v) != 0;
    fbits f = split(fabs(v));
    char tmp[64];
    char *end = tmp + sizeof tmp, *s;
    if (f.e >= 0) {
        if (f.e > 10)
            return psim_fmt_fixed_ref(buf, v, decimals, keep_negzero);
        /* an integer below 2^63: its digits, then the point and zeros */
        memset(end - decimals, '0', (size_t)decimals);
        s = digits_back(end - decimals, f.m << f.e);
    } else {
        /* |v| 10^N = m 10^N / 2^s, rounded to an integer Q */
        int sh = -f.e;
        u128 P = (u128)f.m * pow10_128(decimals);   /* < 2^127 */
        u128 Q = 0;
        if (sh < 128) {
            Q = P >> sh;
            u128 rem = P - (Q << sh), half = (u128)1 << (sh - 1);
            if (rem > half || (rem == half && (Q & 1)))
                Q++;
        } /* else P < 2^127 <= half: Q = 0 */
        if (Q == 0 && !keep_negzero)
            neg = 0;
        s = end;
        while (Q >> 64) {
            uint64_t lo = (uint64_t)(Q % P10[19]);
            Q /= P10[19];
            char *t = digits_back(s, lo);
            while (t > s - 19)
                *--t = '0';
            s = t;
        }
        s = digits_back(s, (uint64_t)Q);
        while (end - s < decimals + 1)
            *--s = '0';
    }
    char *o = buf;
    if (neg)
        *o++ = '-';
    size_t len = (size_t)(end - s), ip = len - (size_t)decimals;
    memcpy(o, s, ip);
    o += ip;
    if (decimals > 0) {
        *o++ = '.';
        memcpy(o, s + ip, (size_t)decimals);
        o += decimals;
    }
    *o = '\0';
    return (int)(o - buf);
}

/* ---- reading --------------------------------------------------------------- */

static const double P10D[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

static const uint64_t P5[28] = {
    1ull, 5ull, 25ull, 125ull, 625ull, 3125ull, 15625ull, 78125ull, 390625ull,
    1953125ull, 9765625ull, 48828125ull, 244140625ull, 1220703125ull, 6103515625ull,
    30517578125ull, 152587890625ull, 762939453125ull, 3814697265625ull,
    19073486328125ull, 95367431640625ull, 476837158203125ull, 2384185791015625ull,
    11920928955078125ull, 59604644775390625ull, 298023223876953125ull,
    1490116119384765625ull, 7450580596923828125ull};

static int bitlen64(uint64_t x) { return x ? 64 - __builtin_clzll(x) : 0; }

static int bitlen128(u128 x)
{
    uint64_t hi = (uint64_t)(x >> 64);
    return hi ? 64 + bitlen64(hi) : bitlen64((uint64_t)x);
}

/* 2^k for a normal k */
static double pow2(int k)
{
    uint64_t b = (uint64_t)(k + 1023) << 52;
    double d;
    memcpy(&d, &b, sizeof d);
    return d;
}

/* (hi 2^64 + lo) / d with hi < d: the quotient, and the remainder in *r */
static uint64_t div128(uint64_t hi, uint64_t lo, uint64_t d, uint64_t *r)
{
#if defined(__x86_64__)
    uint64_t q, rr;
    __asm__("divq %4" : "=a"(q), "=d"(rr) : "a"(lo), "d"(hi), "r"(d));
    *r = rr;
    return q;
#else
    u128 n = ((u128)hi << 64) | lo;
    *r = (uint64_t)(n % d);
    return (uint64_t)(n / d);
#endif
}

static inline int is_digit(char c) { return (unsigned)(c - '0') < 10u; }

/* The eight bytes at p as eight decimal digits (1), or 0 when they are
 * not all digits (SWAR: a byte is a digit when its high nibble is 3 and
 * adding 6 leaves it 3). */
static inline int eight_digits(const char *p, uint64_t *v)
{
    uint64_t w;
    memcpy(&w, p, sizeof w);
    if (((w & 0xF0F0F0F0F0F0F0F0ull) | (((w + 0x0606060606060606ull) & 0xF0F0F0F0F0F0F0F0ull) >> 4)) !=
        0x3333333333333333ull)
        return 0;
    /* digit values d0..d7, d0 (the first, most significant) in the lowest
     * byte; pairs d0 d1 -> 10 d0 + d1 in 16-bit lanes, then 100 a + b in
     * 32-bit lanes, then 10000 a + b */
    w -= 0x3030303030303030ull;
    w = (w & 0x00FF00FF00FF00FFull) * 10 + ((w >> 8) & 0x00FF00FF00FF00FFull);
    w = (w & 0x0000FFFF0000FFFFull) * 100 + ((w >> 16) & 0x0000FFFF0000FFFFull);
    w = (w & 0xFFFFFFFFull) * 10000 + (w >> 32);
    *v = w;
    return 1;
}

/* psim_scan_double, and with `padded` the reader's variant that may read
 * up to 8 bytes past the number (its buffer has room there). */
static inline const char *scan(const char *s, double *out, int padded)
{
#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
    padded = 0;   /* eight_digits reads the text as a little-endian word */
#endif
    const char *p = s;
    int neg = 0;
    if (*p == '-' || *p == '+')
        neg = *p++ == '-';
    uint64_t D = 0, v8;
    int nd = 0, x = 0, any = 0;
    while (*p == '0')
        p++, any = 1;
    if (padded)
        while (nd <= 11 && eight_digits(p, &v8))
            D = D * 100000000 + v8, nd += 8, p += 8, any = 1;
    for (; is_digit(*p); p++, any = 1)
        if (nd++ < 19)
            D = D * 10 + (uint64_t)(*p - '0');
        else
            x++;
    if (*p == '.') {
        p++;
        if (nd == 0)
            for (; *p == '0'; p++)
                x--, any = 1;
        if (padded)
            while (nd <= 11 && eight_digits(p, &v8))
                D = D * 100000000 + v8, nd += 8, x -= 8, p += 8, any = 1;
        for (; is_digit(*p); p++, any = 1)
            if (nd++ < 19)
                D = D * 10 + (uint64_t)(*p - '0'), x--;
    }
    if (!any || *p == 'x' || *p == 'X')
        return NULL;   /* no digits, or hexadecimal ("0x...") */
    if (*p == 'e' || *p == 'E') {
        const char *q = p + 1;
        int eneg = 0, ex = 0;
        if (*q == '+' || *q == '-')
            eneg = *q++ == '-';
        if (!is_digit(*q))
            return NULL;
        for (; is_digit(*q); q++)
            if (ex < 100000)
                ex = ex * 10 + (*q - '0');
        x += eneg ? -ex : ex;
        p = q;
    }
    double r;
    if (nd > 19) {
        /* more digits than 64 bits hold: strtod */
        char *end;
        r = strtod(s, &end);
        if (end != p)
            return NULL;
        *out = r;
        return p;
    }
    if (D == 0) {
        r = 0;
    } else if (D < (1ull << 53) && x >= -22 && x <= 22) {
        r = x < 0 ? (double)D / P10D[-x] : (double)D * P10D[x];
    } else if (x < 0 && x >= -27) {
        int j = -x;
        uint64_t n = P5[j];
        int t = bitlen64(n) + 63 - bitlen64(D);   /* D 2^t < n 2^64 */
        u128 num = (u128)D << t;
        uint64_t rem, q = div128((uint64_t)(num >> 64), (uint64_t)num, n, &rem);
        int sh = bitlen64(q) - 53;                /* q >= 2^62: 10 or 11 */
        uint64_t mant = q >> sh, rest = q & ((1ull << sh) - 1), half = 1ull << (sh - 1);
        if (rest > half || (rest == half && (rem != 0 || (mant & 1))))
            mant++;
        r = (double)mant * pow2(sh - t - j);
    } else if (x >= 0 && x <= 19) {
        u128 P = (u128)D * P10[x];
        int sh = bitlen128(P) - 53;
        if (sh <= 0) {
            r = (double)(uint64_t)P;
        } else {
            u128 mant = P >> sh, rest = P - (mant << sh), half = (u128)1 << (sh - 1);
            if (rest > half || (rest == half && (mant & 1)))
                mant++;
            r = (double)(uint64_t)mant * pow2(sh);
        }
    } else {
        char *end;
        r = strtod(s, &end);
        if (end != p)
            return NULL;
        *out = r;
        return p;
    }
    *out = neg ? -r : r;
    return p;
}

const char *psim_scan_double(const char *s, double *out) { return scan(s, out, 0); }

const char *psim_scan_double_padded(const char *s, double *out) { return scan(s, out, 1); }

#else /* no 128-bit integers: the C library throughout */

int psim_fmt_shortest(char *buf, double v) { return psim_fmt_shortest_ref(buf, v); }
int psim_fmt_general(char *buf, double v, int prec) { return psim_fmt_general_ref(buf, v, prec); }
int psim_fmt_fixed(char *buf, double v, int decimals, int keep_negzero)
{
    return psim_fmt_fixed_ref(buf, v, decimals, keep_negzero);
}

const char *psim_scan_double(const char *s, double *out)
{
    const char *p = s;
    if (*p == '-' || *p == '+')
        p++;
    if (!(*p >= '0' && *p <= '9') && !(*p == '.' && p[1] >= '0' && p[1] <= '9'))
        return NULL;
    char *end;
    *out = strtod(s, &end);
    return end;
}

const char *psim_scan_double_padded(const char *s, double *out)
{
    return psim_scan_double(s, out);
}

#endif
