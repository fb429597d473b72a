/* block_internal.h - small vector and quaternion helpers shared by the
 * block_*.c files (issue 30).  Quaternions are (w, x, y, z). */
#ifndef ROCKFUZZ_BLOCK_INTERNAL_H
#define ROCKFUZZ_BLOCK_INTERNAL_H

#include <math.h>

#include "rockfuzz/block.h"

static inline double bk_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void bk_cross(const double a[3], const double b[3], double c[3])
{
    double c0 = a[1] * b[2] - a[2] * b[1], c1 = a[2] * b[0] - a[0] * b[2], c2 = a[0] * b[1] - a[1] * b[0];
    c[0] = c0, c[1] = c1, c[2] = c2;
}

static inline void bk_sub(const double a[3], const double b[3], double c[3])
{
    c[0] = a[0] - b[0], c[1] = a[1] - b[1], c[2] = a[2] - b[2];
}

/* max without fmax's NaN rules (a libm call unless -ffinite-math-only) */
static inline double bk_max(double a, double b)
{
    return a > b ? a : b;
}

static inline double bk_norm(const double a[3])
{
    return sqrt(bk_dot(a, a));
}

/* a <- a b (a then b in the body: the rotation of a followed by b about a's
 * body axes). */
static inline void bk_quat_mul(const double a[4], const double b[4], double c[4])
{
    double w = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
    double x = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
    double y = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
    double z = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
    c[0] = w, c[1] = x, c[2] = y, c[3] = z;
}

static inline void bk_quat_normalize(double q[4])
{
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    q[0] /= n, q[1] /= n, q[2] /= n, q[3] /= n;
}

/* Rotation matrix (row-major) of a unit quaternion, body -> space. */
static inline void bk_quat_matrix(const double q[4], double r[9])
{
    double w = q[0], x = q[1], y = q[2], z = q[3];
    r[0] = 1 - 2 * (y * y + z * z), r[1] = 2 * (x * y - w * z), r[2] = 2 * (x * z + w * y);
    r[3] = 2 * (x * y + w * z), r[4] = 1 - 2 * (x * x + z * z), r[5] = 2 * (y * z - w * x);
    r[6] = 2 * (x * z - w * y), r[7] = 2 * (y * z + w * x), r[8] = 1 - 2 * (x * x + y * y);
}

static inline void bk_mat_vec(const double r[9], const double a[3], double b[3])
{
    double b0 = r[0] * a[0] + r[1] * a[1] + r[2] * a[2];
    double b1 = r[3] * a[0] + r[4] * a[1] + r[5] * a[2];
    double b2 = r[6] * a[0] + r[7] * a[1] + r[8] * a[2];
    b[0] = b0, b[1] = b1, b[2] = b2;
}

static inline void bk_mat_tvec(const double r[9], const double a[3], double b[3])
{
    double b0 = r[0] * a[0] + r[3] * a[1] + r[6] * a[2];
    double b1 = r[1] * a[0] + r[4] * a[1] + r[7] * a[2];
    double b2 = r[2] * a[0] + r[5] * a[1] + r[8] * a[2];
    b[0] = b0, b[1] = b1, b[2] = b2;
}

#endif
