/* Fast text conversion of numbers, byte for byte what the C library gives.
 *
 * Writers: each function writes exactly what the snprintf call it names
 * writes, for every double.  The common cases are done with exact integer
 * arithmetic (the decimal digits of m * 2^e worked out with 128-bit
 * integers, rounded as glibc rounds: to nearest, ties to even); every case
 * that arithmetic cannot prove (values too large or too small for it,
 * subnormals, non-finite values, more digits than it holds) is handed to
 * snprintf itself.  The *_ref functions are the snprintf versions, kept
 * for tests and for PSIM_SLOW_IO=1.
 *
 * Reader: psim_scan_double reads a plain decimal number ([+-] digits
 * [. digits] [e [+-] digits]) and gives strtod's value, again exactly:
 * short significands with exact powers of ten in one floating-point
 * operation, up to 19 digits with exact integer division, anything else
 * through strtod. */
#ifndef PSIM_IO_FMT_H
#define PSIM_IO_FMT_H
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* The longest text any of the writers below makes (sign, 309 integer
 * digits, point, 30 decimals; PSIM_FORMAT_MAX in psim.h). */
#define PSIM_FMT_MAX 352

/* The first of %.15g, %.16g and %.17g that reads back to v (strtod). */
int psim_fmt_shortest(char *buf, double v);
/* %.*f with `decimals` (0..30) decimals; keep_negzero 0 drops the sign
 * of a result whose digits are all zero ("-0.000" -> "0.000"). */
int psim_fmt_fixed(char *buf, double v, int decimals, int keep_negzero);
/* %.*g with precision prec (0..30; 0 means 1, as printf). */
int psim_fmt_general(char *buf, double v, int prec);

/* The snprintf versions, the reference of the ones above. */
int psim_fmt_shortest_ref(char *buf, double v);
int psim_fmt_fixed_ref(char *buf, double v, int decimals, int keep_negzero);
int psim_fmt_general_ref(char *buf, double v, int prec);

/* Decimal digits of v at p; returns the end (no NUL written). */
char *psim_fmt_ulong(char *p, unsigned long long v);
char *psim_fmt_long(char *p, long long v);

/* A plain decimal number at s (no leading space; "inf", "nan", hex and
 * anything else not of that form give NULL): its value, as strtod reads
 * it, in *out, and the end of the number. */
const char *psim_scan_double(const char *s, double *out);
/* The same, reading digits eight at a time: the 8 bytes after the number
 * must be readable (the scene reader's buffer has room there). */
const char *psim_scan_double_padded(const char *s, double *out);

/* PSIM_SLOW_IO=1 in the environment: the plain code paths (snprintf and
 * fprintf, strtod line by line), for tests that compare the bytes. */
int psim_io_slow(void);

#endif
