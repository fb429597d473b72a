/* block_mass.c - exact mass properties of a homogeneous polyhedron and the
 * principal axes of an inertia tensor (issue 30).
 *
 * Tetrahedral decomposition (Tonon 2004, J. Math. Stat. 1:8; the same
 * integrals as Mirtich 1996): each outward triangle (a, b, c) of the closed
 * surface and a reference point o (the mean of the vertices, for round-off)
 * span a signed tetrahedron; with a' = a - o etc.
 *   V_t = a' . (b' x c') / 6,   int x dV = V_t (a' + b' + c') / 4,
 *   int x x^T dV = V_t / 20 (a'a'^T + b'b'^T + c'c'^T + s s^T),  s = a' + b' + c'
 * (the second moments of a tetrahedron with one vertex at the origin).
 * Summed: V, centroid c = o + S1 / V, C = S2 - V (c - o)(c - o)^T about the
 * centroid, and the inertia tensor (density 1) I = tr(C) 1 - C. */
#include "trajectory/block_internal.h"

#include <string.h>

static void reference_point(const double *v, size_t n_faces, const int *f, double o[3])
{
    o[0] = o[1] = o[2] = 0;
    for (size_t k = 0; k < 3 * n_faces; k++)
        for (int c = 0; c < 3; c++)
            o[c] += v[3 * (size_t)f[k] + c];
    for (int c = 0; c < 3; c++)
        o[c] /= (double)(3 * n_faces);
}

void rf_block_mesh_mass(const double *vertices, size_t n_faces, const int *faces, double *volume, double centroid[3],
                        double inertia[9])
{
    double o[3], vol = 0, s1[3] = {0, 0, 0}, s2[9] = {0};
    reference_point(vertices, n_faces, faces, o);
    for (size_t k = 0; k < n_faces; k++) {
        double a[3], b[3], c[3], bc[3], s[3];
        bk_sub(vertices + 3 * (size_t)faces[3 * k], o, a);
        bk_sub(vertices + 3 * (size_t)faces[3 * k + 1], o, b);
        bk_sub(vertices + 3 * (size_t)faces[3 * k + 2], o, c);
        bk_cross(b, c, bc);
        double vt = bk_dot(a, bc) / 6;
        for (int i = 0; i < 3; i++)
            s[i] = a[i] + b[i] + c[i];
        vol += vt;
        for (int i = 0; i < 3; i++) {
            s1[i] += vt * s[i] / 4;
            for (int j = 0; j < 3; j++)
                s2[3 * i + j] += vt / 20 * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
        }
    }
    double cc[3] = {s1[0] / vol, s1[1] / vol, s1[2] / vol};
    double tr = 0, cm[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            cm[3 * i + j] = s2[3 * i + j] - vol * cc[i] * cc[j];
    tr = cm[0] + cm[4] + cm[8];
    for (int i = 0; i < 9; i++)
        inertia[i] = (i % 4 == 0 ? tr : 0) - cm[i];
    for (int i = 0; i < 3; i++)
        centroid[i] = o[i] + cc[i];
    *volume = vol;
}

/* One Jacobi rotation zeroing a[p][q], accumulated into v. */
static void jacobi_rotate(double a[9], double v[9], int p, int q)
{
    double apq = a[3 * p + q];
    if (apq == 0)
        return;
    double theta = (a[3 * q + q] - a[3 * p + p]) / (2 * apq);
    double t = copysign(1.0, theta) / (fabs(theta) + sqrt(theta * theta + 1));
    double c = 1 / sqrt(t * t + 1), s = t * c;
    for (int k = 0; k < 3; k++) { /* columns p, q of a */
        double akp = a[3 * k + p], akq = a[3 * k + q];
        a[3 * k + p] = c * akp - s * akq, a[3 * k + q] = s * akp + c * akq;
    }
    for (int k = 0; k < 3; k++) { /* rows p, q */
        double apk = a[3 * p + k], aqk = a[3 * q + k];
        a[3 * p + k] = c * apk - s * aqk, a[3 * q + k] = s * apk + c * aqk;
    }
    for (int k = 0; k < 3; k++) {
        double vkp = v[3 * k + p], vkq = v[3 * k + q];
        v[3 * k + p] = c * vkp - s * vkq, v[3 * k + q] = s * vkp + c * vkq;
    }
}

static void sort_columns(double val[3], double vec[9])
{
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2 - i; j++)
            if (val[j] > val[j + 1]) {
                double t = val[j];
                val[j] = val[j + 1], val[j + 1] = t;
                for (int k = 0; k < 3; k++) {
                    t = vec[3 * k + j];
                    vec[3 * k + j] = vec[3 * k + j + 1], vec[3 * k + j + 1] = t;
                }
            }
    double c0[3] = {vec[0], vec[3], vec[6]}, c1[3] = {vec[1], vec[4], vec[7]}, c2[3] = {vec[2], vec[5], vec[8]}, x[3];
    bk_cross(c0, c1, x);
    if (bk_dot(x, c2) < 0)
        vec[2] = -vec[2], vec[5] = -vec[5], vec[8] = -vec[8];
}

void rf_block_sym_eigen(const double m[9], double val[3], double vec[9])
{
    double a[9];
    memcpy(a, m, sizeof a);
    for (int i = 0; i < 9; i++)
        vec[i] = i % 4 == 0;
    double scale = fabs(a[0]) + fabs(a[4]) + fabs(a[8]);
    for (int sweep = 0; sweep < 60; sweep++) {
        double off = fabs(a[1]) + fabs(a[2]) + fabs(a[5]);
        if (off <= 1e-15 * scale) /* below it a rotation is round-off (e.g. a cube's equal moments) */
            break;
        jacobi_rotate(a, vec, 0, 1);
        jacobi_rotate(a, vec, 0, 2);
        jacobi_rotate(a, vec, 1, 2);
    }
    val[0] = a[0], val[1] = a[4], val[2] = a[8];
    sort_columns(val, vec);
}
