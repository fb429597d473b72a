/* hex8_step.c - the smallest element stable step with few eigen-solves
 * (hex8_step.h).
 *
 * Why: the exact element bound (Householder + Sturm bisection on 24 x 24,
 * f3_hex_lambda_max) costs about 83 000 instructions per element, two
 * thirds of the 3D set-up, and only the few smallest elements can set the
 * step.  Gershgorin's theorem on the symmetric M^-1/2 K M^-1/2 gives
 *   lambda_max <= G = max_i sum_j |K_ij| / sqrt(m_i m_j)   (free dofs),
 * so dt_e >= 2/sqrt(G_e).  Visiting the elements by increasing 2/sqrt(G_e)
 * and stopping once that exceeds the smallest exact step found returns the
 * brute-force minimum. */
#include "hex8_step.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "fem3d_internal.h"

static double gershgorin_step(const double K[576], const double m[8], const unsigned char fr[24])
{
    double g = 0;
    for (int i = 0; i < 24; i++) {
        if (!fr[i])
            continue;
        double s = 0;
        for (int j = 0; j < 24; j++)
            if (fr[j])
                s += fabs(K[24 * i + j]) / sqrt(m[i / 3] * m[j / 3]);
        g = fmax(g, s);
    }
    return g > 0 ? 2 / sqrt(g * (1 + 1e-12)) : DBL_MAX; /* margin for the round-off of both bounds */
}

typedef struct {
    double dt;
    long e;
} bound;

static int bound_cmp(const void *pa, const void *pb)
{
    const bound *a = pa, *b = pb;
    if (a->dt != b->dt)
        return a->dt < b->dt ? -1 : 1;
    return a->e < b->e ? -1 : a->e > b->e;
}

double hex8_min_stable_step(long ne, hex8_element_fn fn, void *ctx, double *dt_lower, long *n_exact)
{
    bound *b = malloc((size_t)(ne > 0 ? ne : 1) * sizeof *b);
    if (!b)
        return -1;
    double K[576], m[8];
    unsigned char fr[24];
    for (long e = 0; e < ne; e++) {
        fn(ctx, e, K, m, fr);
        b[e].dt = gershgorin_step(K, m, fr), b[e].e = e;
        if (dt_lower)
            dt_lower[e] = b[e].dt;
    }
    qsort(b, (size_t)ne, sizeof *b, bound_cmp);
    double best = DBL_MAX;
    long k = 0;
    for (; k < ne && b[k].dt < best; k++) {
        fn(ctx, b[k].e, K, m, fr);
        const double lam = f3_hex_lambda_max(K, m, fr);
        if (lam > 0 && 2 / sqrt(lam) < best)
            best = 2 / sqrt(lam);
    }
    if (n_exact)
        *n_exact = k;
    free(b);
    return best;
}
