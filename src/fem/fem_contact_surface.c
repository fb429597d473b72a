/* fem_contact_surface.c - the smooth master surface of the axisymmetric
 * large-deformation contact.
 *
 * Why: on the faceted surface (straight segments) the normal jumps by the
 * kink angle at every slope node.  A boulder node sitting on a slope node
 * (matching meshes) crosses it back and forth; each step the pair is
 * linearised on the segment under the predicted position, whose straight
 * line, extended back to the slave's position at the start of the step,
 * misses it by about kink angle x radial offset: the closed pair finds a
 * penetration it did not have and the multiplier pushes it out, doing work
 * (issue 29 item 1, docs/validation-plastic.md).  On a G1 curve through the
 * same nodes the gap is continuously differentiable across the nodes, and
 * the linearisation error of a step falls to second order in the step's
 * motion (curvature x offset^2).
 *
 * The curve of segment j: cubic Hermite interpolation of x_j, x_{j+1} with
 * tangents L tau_j, L tau_{j+1} (L the chord's length, tau the unit nodal
 * tangent: the normalised sum of the unit directions of the two segments at
 * the node; radial on the axis, by symmetry; the last segment's own at the
 * surface's end).  Both segments at a node use the same tau: the tangent
 * direction, hence the normal, is continuous there.  Wriggers, Krstulovic-
 * Opara & Korelc 2001 (Comput. Mech. 28:33) smooth 2D node-to-segment contact
 * the same way (Hermite or Bezier segments from four master nodes). */
#include "fem_contact_surface.h"

#include <math.h>

/* Hermite basis at xi: h[0..3] = H00, H10, H01, H11; d = 0, 1, 2 the derivative. */
static void hermite(double xi, int d, double h[4])
{
    const double x2 = xi * xi, x3 = x2 * xi;
    if (d == 0)
        h[0] = 2 * x3 - 3 * x2 + 1, h[1] = x3 - 2 * x2 + xi, h[2] = -2 * x3 + 3 * x2, h[3] = x3 - x2;
    else if (d == 1)
        h[0] = 6 * x2 - 6 * xi, h[1] = 3 * x2 - 4 * xi + 1, h[2] = -6 * x2 + 6 * xi, h[3] = 3 * x2 - 2 * xi;
    else
        h[0] = 12 * xi - 6, h[1] = 6 * xi - 4, h[2] = -12 * xi + 6, h[3] = 6 * xi - 2;
}

/* The curve's data: unit directions e[m] and lengths len[m] of the chords
 * p[m] -> p[m+1], the sums w[i] whose directions are the tangents tau[i] at
 * p[1] and p[2] (wn their lengths). */
typedef struct {
    double e[3][2], len[3];
    double w[2][2], wn[2], tau[2][2];
} surf_frame;

static void frame(const fem_surf_segment *S, surf_frame *F)
{
    for (int m = 0; m < 3; m++) {
        const double dr = S->p[m + 1][0] - S->p[m][0], dz = S->p[m + 1][1] - S->p[m][1];
        const int there = (m != 0 || S->has_prev) && (m != 2 || S->has_next);
        F->len[m] = there ? hypot(dr, dz) : 1;
        F->e[m][0] = there ? dr / F->len[m] : 0, F->e[m][1] = there ? dz / F->len[m] : 0;
    }
    for (int k = 0; k < 2; k++) {
        F->w[k][0] = F->e[k][0] + F->e[k + 1][0], F->w[k][1] = F->e[k][1] + F->e[k + 1][1];
        if (k == 0 && !S->has_prev) /* on the axis: radial, fixed */
            F->w[0][0] = 1, F->w[0][1] = 0;
        F->wn[k] = hypot(F->w[k][0], F->w[k][1]);
        F->tau[k][0] = F->w[k][0] / F->wn[k], F->tau[k][1] = F->w[k][1] / F->wn[k];
    }
}

/* x(xi) (d = 0) or its d-th derivative with respect to xi. */
static void curve(const fem_surf_segment *S, const surf_frame *F, double xi, int d, double x[2])
{
    double h[4];
    hermite(xi, d, h);
    const double L = F->len[1];
    for (int a = 0; a < 2; a++)
        x[a] = h[0] * S->p[1][a] + h[2] * S->p[2][a] + L * (h[1] * F->tau[0][a] + h[3] * F->tau[1][a]);
}

void fem_surf_point(const fem_surf_segment *S, double xi, double x[2], double t[2])
{
    surf_frame F;
    frame(S, &F);
    double d[2];
    curve(S, &F, xi, 0, x), curve(S, &F, xi, 1, d);
    const double n = hypot(d[0], d[1]);
    t[0] = d[0] / n, t[1] = d[1] / n;
}

/* The closest point: Newton on f(xi) = (x_s - x(xi)) . x'(xi) = 0 from the
 * chord's projection (near contact the gap is far smaller than the segment
 * and the curve nearly straight: two or three iterations; far slaves, whose
 * exact point does not matter, get a damped Gauss-Newton step). */
static double closest(const fem_surf_segment *S, const surf_frame *F, const double xs[2])
{
    const double *a = S->p[1];
    double xi = ((xs[0] - a[0]) * F->e[1][0] + (xs[1] - a[1]) * F->e[1][1]) / F->len[1];
    for (int it = 0; it < 30; it++) {
        double x[2], d1[2], d2[2];
        curve(S, F, xi, 0, x), curve(S, F, xi, 1, d1), curve(S, F, xi, 2, d2);
        const double q[2] = {xs[0] - x[0], xs[1] - x[1]};
        const double f = q[0] * d1[0] + q[1] * d1[1];
        const double a = d1[0] * d1[0] + d1[1] * d1[1];
        double df = -a + q[0] * d2[0] + q[1] * d2[1];
        if (!(df < -0.5 * a)) /* far from a curved piece: Gauss-Newton, which descends */
            df = -a;
        const double step = fmin(fmax(f / df, -0.5), 0.5);
        xi -= step;
        if (fabs(step) < 1e-15)
            break;
    }
    return xi;
}

/* The gap's gradient with respect to the master nodes at fixed xi:
 * dg/dp_k = -(dx(xi)/dp_k)' n, through the end points, the chord length L
 * and the nodal tangents tau (each a function of its two chords). */
static void master_gradient(const fem_surf_segment *S, const surf_frame *F, double xi, const double n[2],
                            double dg[4][2])
{
    double h[4];
    hermite(xi, 0, h);
    const double L = F->len[1];
    for (int k = 0; k < 4; k++)
        dg[k][0] = dg[k][1] = 0;
    /* the end points */
    for (int a = 0; a < 2; a++)
        dg[1][a] -= h[0] * n[a], dg[2][a] -= h[2] * n[a];
    /* L = |p2 - p1| */
    const double sL = h[1] * (n[0] * F->tau[0][0] + n[1] * F->tau[0][1]) +
                      h[3] * (n[0] * F->tau[1][0] + n[1] * F->tau[1][1]);
    for (int a = 0; a < 2; a++)
        dg[2][a] -= sL * F->e[1][a], dg[1][a] += sL * F->e[1][a];
    /* tau_k = w_k / |w_k|, w_k = e_k + e_{k+1}: n . dtau = (n . tau_perp)(tau_perp . dw) / |w|,
       tau_perp . de_m = (tau_perp . e_perp_m)(e_perp_m . dd_m) / len_m, d_m = p_{m+1} - p_m */
    for (int k = 0; k < 2; k++) {
        if (k == 0 && !S->has_prev)
            continue;
        const double tp[2] = {-F->tau[k][1], F->tau[k][0]};
        const double alpha = L * h[1 + 2 * k] * (n[0] * tp[0] + n[1] * tp[1]) / F->wn[k];
        for (int m = k; m <= k + 1; m++) {
            if ((m == 0 && !S->has_prev) || (m == 2 && !S->has_next))
                continue;
            const double ep[2] = {-F->e[m][1], F->e[m][0]};
            const double beta = alpha * (tp[0] * ep[0] + tp[1] * ep[1]) / F->len[m];
            for (int a = 0; a < 2; a++)
                dg[m + 1][a] -= beta * ep[a], dg[m][a] += beta * ep[a];
        }
    }
}

static int project(const fem_surf_segment *S, const double xs[2], fem_surf_gap *G, int clamp)
{
    surf_frame F;
    frame(S, &F);
    double xi = closest(S, &F, xs);
    const int side = xi < 0 ? -1 : xi > 1 ? 1 : 0;
    if (clamp)
        xi = fmin(fmax(xi, 0), 1);
    double x[2], d[2];
    curve(S, &F, xi, 0, x), curve(S, &F, xi, 1, d);
    const double dn = hypot(d[0], d[1]);
    G->xi = xi, G->n[0] = -d[1] / dn, G->n[1] = d[0] / dn;
    G->g = G->n[0] * (xs[0] - x[0]) + G->n[1] * (xs[1] - x[1]);
    master_gradient(S, &F, xi, G->n, G->dg);
    return side;
}

int fem_surf_project(const fem_surf_segment *S, const double xs[2], fem_surf_gap *G)
{
    return project(S, xs, G, 1);
}

int fem_surf_project_extended(const fem_surf_segment *S, const double xs[2], fem_surf_gap *G)
{
    return project(S, xs, G, 0);
}
