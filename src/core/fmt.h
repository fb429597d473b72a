/* fmt.h - a double as printf's "%.*g" writes it, byte for byte, without
 * printf: the outputs of trajectory runs write millions of numbers, and
 * glibc's printf of a double (multi-precision digits) cost more than the
 * simulation (issue 31 item 18).  The digits are exact: the double's
 * mantissa times a power of ten in 128-bit integers, rounded half to even
 * like glibc; values whose digits would need more than 128 bits (very large
 * or very small magnitudes), non-finite values and precisions above 17 go
 * through snprintf.  tests/test_fmt_g.c compares with snprintf. */
#ifndef ROCKFUZZ_CORE_FMT_H
#define ROCKFUZZ_CORE_FMT_H

#include <stddef.h>

/* Longest text rf_fmt_g writes, with its NUL. */
#define RF_FMT_G_MAX 32

/* "%.*g" of v with precision 1..17 into buf (RF_FMT_G_MAX bytes); returns the length. */
size_t rf_fmt_g(char *buf, double v, int precision);

#endif
