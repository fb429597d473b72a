/* quad4_kernel.c - the axisymmetric quad's internal force from stored 8 x 8
 * stiffness matrices shared by shape (quad4_kernel.h).
 *
 * Why: the solver's loop (fem_solver.c, force_kernel) writes K_e u_e as 64
 * separate scalar products and sums, which -std=c17 neither fuses (no FMA)
 * nor vectorises: about 230 instructions per element-step.  Written as eight
 * column updates acc += K[:, j] u_j, the product is 8 vector multiply-adds;
 * sharing K_e between elements of the same shape keeps the table in L1. */
#include "quad4_kernel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=fast")
#elif defined(__clang__)
#pragma clang fp contract(fast)
#endif

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define QUAD4_CLONES __attribute__((target_clones("default", "arch=x86-64-v3", "arch=x86-64-v4")))
#else
#define QUAD4_CLONES
#endif

/* Helpers of the cloned entry points must be inlined into each clone (an out-of-line copy would be
   compiled for the default target: no FMA, other bits). */
#if defined(__GNUC__) || defined(__clang__)
#define QUAD4_INLINE static inline __attribute__((always_inline))
#else
#define QUAD4_INLINE static inline
#endif

/* Eight doubles: one element's 8 forces in one AVX-512 register (two AVX2, four SSE2). */
#if defined(__GNUC__) || defined(__clang__)
typedef double qvec __attribute__((vector_size(8 * sizeof(double))));
#else
#error "quad4_kernel.c needs the GCC/clang vector extension"
#endif

/* y = K x for one element, as 8 column updates acc += K[:, j] x_j (K symmetric: column j = row j);
   the one product both entry points use, so the fused and the element-vector paths give the same
   bits. */
QUAD4_INLINE void quad4_product(const double *k, const double x[8], double y[8])
{
    qvec acc = {0}, col;
    for (int j = 0; j < 8; j++) {
        memcpy(&col, k + 8 * j, sizeof col);
        acc += col * x[j];
    }
    memcpy(y, &acc, sizeof acc);
}

QUAD4_CLONES
void quad4_force(const double *Kg, const int *kidx, const int *conn, long e0, long e1, const double *u, double *f)
{
    for (long e = e0; e < e1; e++) {
        const int *c = conn + 4 * e;
        const double *k = Kg + 64 * (kidx ? (long)kidx[e] : e);
        double x[8], y[8];
        for (int a = 0; a < 4; a++)
            x[2 * a] = u[2 * (long)c[a]], x[2 * a + 1] = u[2 * (long)c[a] + 1];
        quad4_product(k, x, y);
        for (int a = 0; a < 4; a++) {
            f[2 * (long)c[a]] += y[2 * a];
            f[2 * (long)c[a] + 1] += y[2 * a + 1];
        }
    }
}

QUAD4_CLONES
void quad4_force_elements(const double *Kg, long e0, long e1, const double *ue, double *fe)
{
    for (long e = e0; e < e1; e++)
        quad4_product(Kg + 64 * e, ue + 8 * (e - e0), fe + 8 * (e - e0));
}

/* Index of K[i][j] = K[j][i] among the 36 entries of the upper triangle (row by row). */
#define QUAD4_TRI(i, j) ((i) <= (j) ? 8 * (i) - (i) * ((i) - 1) / 2 + (j) - (i) : 8 * (j) - (j) * ((j) - 1) / 2 + (i) - (j))

long quad4_packed_size(long ne)
{
    return 288 * ((ne + 7) / 8);
}

int quad4_packed_pays(long ne)
{
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
    if (!__builtin_cpu_supports("x86-64-v4")) /* the AVX2 clone splits the 8-wide shuffles: 3.5x the instructions */
        return 0;
#else
    return 0; /* no AVX-512 clone */
#endif
    long l2 = 0;
#ifdef _SC_LEVEL2_CACHE_SIZE
    l2 = sysconf(_SC_LEVEL2_CACHE_SIZE);
#endif
    if (l2 <= 0)
        l2 = 2L << 20;
    return 512.0 * (double)ne > 0.75 * (double)l2;
}

int quad4_pack(const double *Kg, long ne, double *pk)
{
    memset(pk, 0, (size_t)quad4_packed_size(ne) * sizeof *pk);
    for (long e = 0; e < ne; e++) {
        const double *k = Kg + 64 * e;
        for (int i = 0; i < 8; i++)
            for (int j = i; j < 8; j++) {
                if (memcmp(k + 8 * i + j, k + 8 * j + i, sizeof *k) != 0)
                    return -1;
                pk[288 * (e / 8) + 8 * QUAD4_TRI(i, j) + e % 8] = k[8 * i + j];
            }
    }
    return 0;
}

/* y_i = K_e x for the 8 elements of one packed group, element in the lane: for every i the chain
   acc_i += K[j][i] x_j, j = 0..7, of quad4_product (K[j][i] = K[i][j] bit for bit). */
QUAD4_INLINE void packed_product(const double *pb, const qvec x[8], qvec y[8])
{
    qvec acc[8] = {{0}}, k;
    for (int j = 0; j < 8; j++)
        for (int i = 0; i < 8; i++) {
            memcpy(&k, pb + 8 * QUAD4_TRI(i, j), sizeof k);
            acc[i] += k * x[j];
        }
    memcpy(y, acc, sizeof acc);
}

/* The lanes [l0, l1) of group g: x[j][l] = dof j of element 8 g + l (other lanes 0). */
QUAD4_INLINE void packed_gather(const int *conn, long g, int l0, int l1, const double *u, double xs[8][8])
{
    memset(xs, 0, 64 * sizeof(double));
    for (int l = l0; l < l1; l++) {
        const int *c = conn + 4 * (8 * g + l);
        for (int a = 0; a < 4; a++)
            xs[2 * a][l] = u[2 * (long)c[a]], xs[2 * a + 1][l] = u[2 * (long)c[a] + 1];
    }
}

#if defined(__has_builtin)
#if __has_builtin(__builtin_shufflevector)
#define QUAD4_SHUFFLE 1
#endif
#endif

#ifdef QUAD4_SHUFFLE
typedef double qpair __attribute__((vector_size(2 * sizeof(double))));
typedef double qquad __attribute__((vector_size(4 * sizeof(double))));
#define SV __builtin_shufflevector

/* in[l][j] -> out[j][l] for 8 x 8 doubles, in 24 two-register shuffles (exact: moves only). */
QUAD4_INLINE void transpose8(const qvec in[8], qvec out[8])
{
    qvec t[8], w[8];
    for (int p = 0; p < 4; p++) {
        t[2 * p] = SV(in[2 * p], in[2 * p + 1], 0, 8, 2, 10, 4, 12, 6, 14);
        t[2 * p + 1] = SV(in[2 * p], in[2 * p + 1], 1, 9, 3, 11, 5, 13, 7, 15);
    }
    for (int h = 0; h < 2; h++) /* rows 4 h .. 4 h + 3: w[4 h + q] holds columns (q', q' + 4) */
        for (int q = 0; q < 2; q++) {
            w[4 * h + 2 * q] = SV(t[4 * h + q], t[4 * h + q + 2], 0, 1, 8, 9, 4, 5, 12, 13);
            w[4 * h + 2 * q + 1] = SV(t[4 * h + q], t[4 * h + q + 2], 2, 3, 10, 11, 6, 7, 14, 15);
        }
    static const int col[4] = {0, 2, 1, 3}; /* w[q] holds columns col[q] and col[q] + 4 */
    for (int q = 0; q < 4; q++) {
        out[col[q]] = SV(w[q], w[4 + q], 0, 1, 2, 3, 8, 9, 10, 11);
        out[col[q] + 4] = SV(w[q], w[4 + q], 4, 5, 6, 7, 12, 13, 14, 15);
    }
}

/* A whole group (8 elements from 8 g): gather each element's 4 node pairs, transpose to one vector
   per dof, the product, transpose back, add each node pair to f in element order. */
QUAD4_INLINE void packed_group_full(const double *pk, const int *conn, long g, const double *u, double *f)
{
    const int *c = conn + 32 * g;
    qvec r[8], x[8], y[8];
    for (int l = 0; l < 8; l++) {
        qpair p[4];
        for (int a = 0; a < 4; a++)
            memcpy(&p[a], u + 2 * (long)c[4 * l + a], sizeof p[a]);
        qquad lo = SV(p[0], p[1], 0, 1, 2, 3), hi = SV(p[2], p[3], 0, 1, 2, 3);
        r[l] = SV(lo, hi, 0, 1, 2, 3, 4, 5, 6, 7);
    }
    transpose8(r, x);
    packed_product(pk + 288 * g, x, y);
    transpose8(y, r);
    for (int l = 0; l < 8; l++) {
        const qpair ya[4] = {SV(r[l], r[l], 0, 1), SV(r[l], r[l], 2, 3), SV(r[l], r[l], 4, 5), SV(r[l], r[l], 6, 7)};
        for (int a = 0; a < 4; a++) {
            double *fa = f + 2 * (long)c[4 * l + a];
            qpair s;
            memcpy(&s, fa, sizeof s);
            s += ya[a];
            memcpy(fa, &s, sizeof s);
        }
    }
}
#else
/* A whole group (8 elements from 8 g): gather, product, scatter in element order, fixed bounds. */
QUAD4_INLINE void packed_group_full(const double *pk, const int *conn, long g, const double *u, double *f)
{
    const int *c = conn + 32 * g;
    double xs[8][8], ys[8][8];
    qvec x[8], y[8];
    for (int l = 0; l < 8; l++)
        for (int a = 0; a < 4; a++)
            xs[2 * a][l] = u[2 * (long)c[4 * l + a]], xs[2 * a + 1][l] = u[2 * (long)c[4 * l + a] + 1];
    memcpy(x, xs, sizeof x);
    packed_product(pk + 288 * g, x, y);
    memcpy(ys, y, sizeof ys);
    for (int l = 0; l < 8; l++)
        for (int a = 0; a < 4; a++) {
            f[2 * (long)c[4 * l + a]] += ys[2 * a][l];
            f[2 * (long)c[4 * l + a] + 1] += ys[2 * a + 1][l];
        }
}

#endif

/* Lanes [l0, l1) of group g (a range that starts or ends inside it). */
QUAD4_INLINE void packed_group_part(const double *pk, const int *conn, long g, int l0, int l1, const double *u, double *f)
{
    double xs[8][8], ys[8][8];
    qvec x[8], y[8];
    packed_gather(conn, g, l0, l1, u, xs);
    memcpy(x, xs, sizeof x);
    packed_product(pk + 288 * g, x, y);
    memcpy(ys, y, sizeof ys);
    for (int l = l0; l < l1; l++) { /* element order */
        const int *c = conn + 4 * (8 * g + l);
        for (int a = 0; a < 4; a++) {
            f[2 * (long)c[a]] += ys[2 * a][l];
            f[2 * (long)c[a] + 1] += ys[2 * a + 1][l];
        }
    }
}

QUAD4_CLONES
void quad4_force_packed(const double *pk, const int *conn, long e0, long e1, const double *u, double *f)
{
    for (long g = e0 / 8; 8 * g < e1; g++) {
        if (8 * g >= e0 && 8 * g + 8 <= e1)
            packed_group_full(pk, conn, g, u, f);
        else
            packed_group_part(pk, conn, g, 8 * g < e0 ? (int)(e0 - 8 * g) : 0,
                              8 * g + 8 > e1 ? (int)(e1 - 8 * g) : 8, u, f);
    }
}

QUAD4_CLONES
void quad4_force_packed_elements(const double *pk, long e0, long e1, const double *ue, double *fe)
{
    for (long g = e0 / 8; 8 * g < e1; g++) {
        const int l0 = 8 * g < e0 ? (int)(e0 - 8 * g) : 0, l1 = 8 * g + 8 > e1 ? (int)(e1 - 8 * g) : 8;
        double xs[8][8] = {{0}}, ys[8][8];
        qvec x[8], y[8];
        for (int l = l0; l < l1; l++)
            for (int j = 0; j < 8; j++)
                xs[j][l] = ue[8 * (8 * g + l - e0) + j];
        memcpy(x, xs, sizeof x);
        packed_product(pk + 288 * g, x, y);
        memcpy(ys, y, sizeof ys);
        for (int l = l0; l < l1; l++)
            for (int j = 0; j < 8; j++)
                fe[8 * (8 * g + l - e0) + j] = ys[j][l];
    }
}

typedef struct {
    long key[7]; /* quantised r0..r3, z1-z0, z2-z0, z3-z0 */
    int e;
} shape_key;

static int key_cmp(const void *pa, const void *pb)
{
    const shape_key *a = pa, *b = pb;
    for (int i = 0; i < 7; i++)
        if (a->key[i] != b->key[i])
            return a->key[i] < b->key[i] ? -1 : 1;
    return a->e < b->e ? -1 : a->e > b->e; /* stable: groups keep element order */
}

/* Two elements of one group must agree within tol, not just share a rounded key. */
static int same_shape(const double *r, const double *z, const int *ca, const int *cb, double tol)
{
    for (int a = 0; a < 4; a++) {
        if (fabs(r[ca[a]] - r[cb[a]]) > tol)
            return 0;
        if (fabs((z[ca[a]] - z[ca[0]]) - (z[cb[a]] - z[cb[0]])) > tol)
            return 0;
    }
    return 1;
}

long quad4_group_by_shape(const double *r, const double *z, const int *conn, long ne, double tol, int *kidx,
                          int *rep)
{
    shape_key *s = malloc((size_t)(ne > 0 ? ne : 1) * sizeof *s);
    if (!s)
        return -1;
    for (long e = 0; e < ne; e++) {
        const int *c = conn + 4 * e;
        for (int a = 0; a < 4; a++)
            s[e].key[a] = lround(r[c[a]] / tol);
        for (int a = 1; a < 4; a++)
            s[e].key[3 + a] = lround((z[c[a]] - z[c[0]]) / tol);
        s[e].e = (int)e;
    }
    qsort(s, (size_t)ne, sizeof *s, key_cmp);
    for (long e = 0; e < ne; e++)
        kidx[e] = -1;
    long ng = 0;
    for (long i = 0; i < ne; i++) { /* the first element (lowest id) of each run of equal keys leads */
        const int e = s[i].e;
        if (i > 0 && memcmp(s[i].key, s[i - 1].key, sizeof s[i].key) == 0 &&
            same_shape(r, z, conn + 4 * (long)rep[kidx[s[i - 1].e]], conn + 4 * (long)e, tol))
            kidx[e] = kidx[s[i - 1].e];
        else
            kidx[e] = (int)ng, rep[ng++] = e;
    }
    free(s);
    return ng;
}
