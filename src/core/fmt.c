/* fmt.c - "%.*g" without printf (fmt.h).  v = m 2^e (m < 2^53 an integer);
 * for a decimal exponent X guessed from the binary one the P digits are
 * N = round(v 10^(P-1-X)) = round(A / B), A = m 10^max(s,0) 2^max(e,0),
 * B = 10^max(-s,0) 2^max(-e,0), s = P-1-X, in 128-bit integers, rounded half
 * to even as glibc does; X is corrected when N has P-1 or P+1 digits, and
 * when N = 10^(P-1) came from a carry (v just below 10^X: then X - 1 gives
 * P digits of nines).  The
 * text then follows C's %g: style e when X < -4 or X >= P, trailing zeros
 * and a bare point removed. */
#include "core/fmt.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

typedef unsigned __int128 u128;

static int bits(u128 x)
{
    uint64_t hi = (uint64_t)(x >> 64), lo = (uint64_t)x;
    return hi ? 128 - __builtin_clzll(hi) : lo ? 64 - __builtin_clzll(lo) : 0;
}

static u128 pow10_u128(int k)
{
    u128 p = 1;
    while (k-- > 0)
        p *= 10;
    return p;
}

/* round(m 2^e 10^s) into *n; 0 when the exact numbers would not fit in 127 bits. */
static int scaled(uint64_t m, int e, int s, u128 *n)
{
    if (s > 38 || s < -38 || e > 120 || e < -126)
        return 0;
    u128 a = m, b = 1, p = pow10_u128(s > 0 ? s : -s);
    if (s > 0) {
        if (bits(a) + bits(p) > 127)
            return 0;
        a *= p;
    } else {
        b = p;
    }
    if (e > 0 && bits(a) + e > 127)
        return 0;
    if (e < 0 && bits(b) - e > 127)
        return 0;
    if (e > 0)
        a <<= e;
    u128 q, r, rest;
    if (b == 1 && e < 0) { /* a power of two: a shift (the common case of a value near 1) */
        q = a >> -e, r = a & (((u128)1 << -e) - 1), rest = ((u128)1 << -e) - r;
    } else {
        if (e < 0)
            b <<= -e;
        q = a / b, r = a - q * b, rest = b - r;
    }
    *n = q + (r > rest || (r == rest && (q & 1)));
    return 1;
}

/* The P digits of v > 0 into d and its exponent X; 0 when out of range. */
static int digits(double v, int P, char *d, int *X)
{
    int E;
    double f = frexp(v, &E);
    uint64_t m = (uint64_t)ldexp(f, 53);
    /* v in [2^(E-1), 2^E): log10 v in [(E-1) log10 2, E log10 2), so x is X or X - 1 (the loop corrects it) */
    int e = E - 53, x = (int)floor((E - 1) * 0.30102999566398120);
    const u128 lo = pow10_u128(P - 1), hi = lo * 10;
    u128 n = 0;
    for (int tries = 0;; tries++) {
        if (tries == 4 || !scaled(m, e, P - 1 - x, &n))
            return 0;
        if (n >= hi)
            x++;
        else if (n < lo)
            x--;
        else
            break;
    }
    u128 below;
    if (n == lo) { /* 10^(P-1) may be a carry: v just below 10^x */
        if (!scaled(m, e, P - x, &below))
            return 0;
        if (below < hi)
            n = below, x--;
    }
    uint64_t n64 = (uint64_t)n; /* < 10^17 */
    for (int k = P - 1; k >= 0; k--, n64 /= 10)
        d[k] = (char)('0' + (int)(n64 % 10));
    *X = x;
    return 1;
}

/* Digits d[0..len) with trailing zeros dropped: the new length. */
static int trim(const char *d, int len)
{
    while (len > 0 && d[len - 1] == '0')
        len--;
    return len;
}

size_t rf_fmt_g(char *buf, double v, int P)
{
    char d[20];
    int X = 0;
    const double v0 = v;
    if (P < 1 || P > 17 || !isfinite(v))
        return (size_t)snprintf(buf, RF_FMT_G_MAX, "%.*g", P, v);
    char *q = buf;
    if (signbit(v))
        *q++ = '-', v = -v;
    if (v == 0) {
        *q++ = '0', *q = '\0';
        return (size_t)(q - buf);
    }
    if (!digits(v, P, d, &X))
        return (size_t)snprintf(buf, RF_FMT_G_MAX, "%.*g", P, v0);
    if (X < -4 || X >= P) { /* style e: d.ddde+XX */
        int len = trim(d, P);
        *q++ = d[0];
        if (len > 1)
            *q++ = '.', memcpy(q, d + 1, (size_t)(len - 1)), q += len - 1;
        q += sprintf(q, "e%c%02d", X < 0 ? '-' : '+', X < 0 ? -X : X);
        return (size_t)(q - buf);
    }
    if (X >= 0) { /* style f: X + 1 integer digits, the rest after the point */
        memcpy(q, d, (size_t)(X + 1)), q += X + 1;
        int len = trim(d, P);
        if (len > X + 1)
            *q++ = '.', memcpy(q, d + X + 1, (size_t)(len - X - 1)), q += len - X - 1;
    } else { /* 0.000ddd */
        *q++ = '0', *q++ = '.';
        for (int k = 0; k < -X - 1; k++)
            *q++ = '0';
        int len = trim(d, P);
        memcpy(q, d, (size_t)len), q += len;
    }
    *q = '\0';
    return (size_t)(q - buf);
}
