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

/* Eight doubles: one element's 8 forces in one AVX-512 register (two AVX2, four SSE2). */
#if defined(__GNUC__) || defined(__clang__)
typedef double qvec __attribute__((vector_size(8 * sizeof(double))));
#else
#error "quad4_kernel.c needs the GCC/clang vector extension"
#endif

/* y = K x for one element, as 8 column updates acc += K[:, j] x_j (K symmetric: column j = row j);
   the one product both entry points use, so the fused and the element-vector paths give the same
   bits. */
static inline void quad4_product(const double *k, const double x[8], double y[8])
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
