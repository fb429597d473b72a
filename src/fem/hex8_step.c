/* hex8_step.c - the largest element eigenvalue with few eigen-solves
 * (hex8_step.h).
 *
 * Why: the exact element bound (Householder + Sturm bisection on 24 x 24,
 * f3_hex_lambda_max) costs about 83 000 instructions per element, two
 * thirds of the 3D set-up, and only the few smallest elements can set the
 * step.  Gershgorin's theorem on the symmetric M^-1/2 K M^-1/2 gives
 *   lambda_max <= G = max_i sum_j |K_ij| / sqrt(m_i m_j)   (free dofs).
 * Solving the elements by decreasing G and stopping once G (with a margin
 * for the round-off of both bounds) is below the largest exact value found
 * returns the brute-force maximum. */
#include "hex8_step.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "fem3d_internal.h"

double hex8_gershgorin_bound(const double K[576], const double m[8], const unsigned char fr[24])
{
    double w[8], g = 0;
    for (int a = 0; a < 8; a++)
        w[a] = 1 / sqrt(m[a]);
    for (int i = 0; i < 24; i++) {
        if (!fr[i])
            continue;
        double r = 0;
        for (int j = 0; j < 24; j++)
            if (fr[j])
                r += fabs(K[24 * i + j]) * w[j / 3];
        g = fmax(g, r * w[i / 3]);
    }
    return g;
}

typedef struct {
    double bound;
    long e;
} lam_bound;

/* Decreasing bound, then increasing element (a total order: the same sequence every run). */
static int by_bound_desc(const void *pa, const void *pb)
{
    const lam_bound *a = pa, *b = pb;
    return a->bound > b->bound ? -1 : a->bound < b->bound ? 1 : (a->e > b->e) - (a->e < b->e);
}

double hex8_max_eigenvalue(long ne, hex8_element_fn fn, void *ctx, double *lam_upper, long *n_exact)
{
    lam_bound *order = malloc((size_t)(ne > 0 ? ne : 1) * sizeof *order);
    double K[576], m[8];
    unsigned char fr[24];
    for (long e = 0; e < ne && (order || lam_upper); e++) {
        fn(ctx, e, K, m, fr);
        const double g = hex8_gershgorin_bound(K, m, fr);
        if (order)
            order[e] = (lam_bound){g, e};
        if (lam_upper)
            lam_upper[e] = g;
    }
    if (order)
        qsort(order, (size_t)ne, sizeof *order, by_bound_desc);
    double lam_max = 0;
    long k = 0;
    for (; k < ne; k++) {
        if (order && order[k].bound * (1 + 1e-9) < lam_max)
            break; /* every remaining bound is lower: their exact values cannot reach lam_max */
        fn(ctx, order ? order[k].e : k, K, m, fr);
        const double l = f3_hex_lambda_max(K, m, fr);
        if (l > lam_max)
            lam_max = l;
    }
    if (n_exact)
        *n_exact = k;
    free(order);
    return lam_max;
}

double hex8_min_stable_step(long ne, hex8_element_fn fn, void *ctx, double *dt_lower, long *n_exact)
{
    const double lam = hex8_max_eigenvalue(ne, fn, ctx, dt_lower, n_exact);
    for (long e = 0; dt_lower && e < ne; e++)
        dt_lower[e] = dt_lower[e] > 0 ? 2 / sqrt(dt_lower[e] * (1 + 1e-9)) : DBL_MAX;
    return lam > 0 ? 2 / sqrt(lam) : DBL_MAX;
}
