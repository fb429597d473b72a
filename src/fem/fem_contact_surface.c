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
 * (issue 29 item 1, docs/validation-plastic.md 6f).  On a C1 curve over the
 * same nodes the gap is continuously differentiable across the nodes, and,
 * with the impulse along the gradient at the start of the step
 * (fem_contact.c), a closed pair's force does no work to the step's order.
 *
 * The curve: the surface polygon with its corners rounded.  Within
 * f = FILLET (a quarter) of a segment from node x_k it is the quadratic
 * Bezier arc of control points x_k + f (x_{k-1} - x_k), x_k,
 * x_k + f (x_{k+1} - x_k), tangent to both chords where it meets them;
 * between the arcs, on the middle half of each segment, the chord itself.
 * On the axis the missing x_{-1} is the mirror image of x_1 (r -> -r): the
 * curve meets the axis at right angles, by symmetry; past the surface's
 * last node the missing node is 2 x_{j+1} - x_j (the curve ends straight).
 *
 * The gap's gradient on the master nodes is the force distribution,
 * -(dx(xi)/dx_k)' n, and here every weight dx/dx_k is >= 0 (the arc's
 * f (1-s)^2, 1 - f ((1-s)^2 + s^2), f s^2; the chord's 1 - xi, xi): every
 * master node is pushed away from a slave, never pulled.  Two curves were
 * measured before (docs/validation-plastic.md 6f):
 * - the interpolating cubic Hermite curve with averaged nodal tangents: its
 *   weights of the neighbours (H11 <= 0) pulled the free surface node beyond
 *   the last loaded segment up into the next boulder node (energy error on
 *   dense sand 6.7e-3 KE0).  Any interpolating C1 curve whose tangent at x_j
 *   depends on x_{j+1} has such a weight: that of x_{j+1} is zero at x_{j-1}
 *   and at x_j with a non-zero slope at x_j, so it is negative on one side;
 * - the uniform cubic B-spline over the nodes (weights >= 0): it lies h^2
 *   kappa / 6 inside the polygon, and, mirrored at the axis, gives the axis
 *   node 7/30 of 2 pi p h^2 under a uniform pressure p where the lumped mass
 *   (the hat function) has 1/6: the node was accelerated 1.4 times as fast
 *   as the surface around it and crushed its element in a J2 soil at 8 m/s.
 * The rounded polygon departs from the chords only within f h of a node: it
 * lies at most f/4 of the second difference (h^2 kappa / 16 for f = 1/4)
 * inside the polygon, and the axis node takes h^2 (1/6 + f^2/6 - f^3/24)
 * (+5.9 %), the next one h^2 (1 + f^3/24), every other one exactly its
 * share (tests/test_fem_contact_surface.c).  Wriggers, Krstulovic-Opara &
 * Korelc 2001 (Comput. Mech. 28:33) smooth 2D node-to-segment contact with
 * Hermite or Bezier segments. */
#include "fem_contact_surface.h"

#include <math.h>

/* The fillet's half-width, as a fraction of the segment: the curve is
 * straight on the middle half of every segment. */
#define FILLET 0.25

/* W += c times virtual node v of the segment: v = -1 the node before x_j
 * (p[0]; on the axis the mirror image of x_{j+1}: (-r, z)), 0 and 1 the
 * segment's ends x_j = p[1], x_{j+1} = p[2], 2 the node after (p[3]; past
 * the surface's end the straight extension 2 x_{j+1} - x_j). */
static void add_node(const fem_surf_segment *S, double W[2][4], int v, double c)
{
    if (v == -1 && !S->has_prev)
        W[0][2] -= c, W[1][2] += c;
    else if (v == 2 && !S->has_next)
        for (int a = 0; a < 2; a++)
            W[a][2] += 2 * c, W[a][1] -= c;
    else
        for (int a = 0; a < 2; a++)
            W[a][v + 1] += c;
}

/* The curve's weights of the segment's nodes at xi (d-th derivative with
 * respect to xi, d = 0, 1, 2): x(xi)_a = sum_m W[a][m] p[m]_a.  Within FILLET
 * of a node the curve is the quadratic Bezier arc of control points
 * x_k + FILLET (x_{k-1} - x_k), x_k, x_k + FILLET (x_{k+1} - x_k), of
 * parameter s = 1/2 at the node; between the arcs the chord. */
static void node_weights(const fem_surf_segment *S, double xi, int d, double W[2][4])
{
    for (int a = 0; a < 2; a++)
        for (int m = 0; m < 4; m++)
            W[a][m] = 0;
    const double f = FILLET;
    if (xi > f && xi < 1 - f) { /* the chord */
        add_node(S, W, 0, d == 0 ? 1 - xi : d == 1 ? -1 : 0);
        add_node(S, W, 1, d == 0 ? xi : d == 1 ? 1 : 0);
        return;
    }
    const int k = xi <= f ? 0 : 1; /* the arc of x_j or of x_{j+1} */
    const double s = (xi - k + f) / (2 * f), q = pow(1 / (2 * f), d);
    double w[3]; /* of x_{k-1}, x_k, x_{k+1} */
    if (d == 0)
        w[0] = f * (1 - s) * (1 - s), w[2] = f * s * s, w[1] = 1 - w[0] - w[2];
    else if (d == 1)
        w[0] = -2 * f * (1 - s), w[2] = 2 * f * s, w[1] = f * (2 - 4 * s);
    else
        w[0] = 2 * f, w[2] = 2 * f, w[1] = -4 * f;
    for (int i = 0; i < 3; i++)
        add_node(S, W, k - 1 + i, q * w[i]);
}

/* x(xi) (d = 0) or its d-th derivative with respect to xi. */
static void curve(const fem_surf_segment *S, double xi, int d, double x[2])
{
    double W[2][4];
    node_weights(S, xi, d, W);
    for (int a = 0; a < 2; a++)
        x[a] = W[a][0] * S->p[0][a] + W[a][1] * S->p[1][a] + W[a][2] * S->p[2][a] + W[a][3] * S->p[3][a];
}

void fem_surf_point(const fem_surf_segment *S, double xi, double x[2], double t[2])
{
    double d[2];
    curve(S, xi, 0, x), curve(S, xi, 1, d);
    const double n = hypot(d[0], d[1]);
    t[0] = d[0] / n, t[1] = d[1] / n;
}

/* The closest point: Newton on f(xi) = (x_s - x(xi)) . x'(xi) = 0 from the
 * chord's projection (near contact the gap is far smaller than the segment
 * and the curve nearly straight: two or three iterations; far slaves, whose
 * exact point does not matter, get a damped Gauss-Newton step). */
static double closest(const fem_surf_segment *S, const double xs[2])
{
    const double *a = S->p[1], e[2] = {S->p[2][0] - a[0], S->p[2][1] - a[1]};
    double xi = ((xs[0] - a[0]) * e[0] + (xs[1] - a[1]) * e[1]) / (e[0] * e[0] + e[1] * e[1]);
    for (int it = 0; it < 30; it++) {
        double x[2], d1[2], d2[2];
        curve(S, xi, 0, x), curve(S, xi, 1, d1), curve(S, xi, 2, d2);
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
 * dg/dp_m = -(dx(xi)/dp_m)' n = -(W_r n_r, W_z n_z) with the node weights W
 * (a node the curve does not use, p[0] of segment 0 or p[3] past the
 * surface's end, has weight 0). */
static void master_gradient(const fem_surf_segment *S, double xi, const double n[2], double dg[4][2])
{
    double W[2][4];
    node_weights(S, xi, 0, W);
    for (int m = 0; m < 4; m++)
        dg[m][0] = -W[0][m] * n[0], dg[m][1] = -W[1][m] * n[1];
}

static int project(const fem_surf_segment *S, const double xs[2], fem_surf_gap *G, int clamp)
{
    double xi = closest(S, xs);
    const int side = xi < 0 ? -1 : xi > 1 ? 1 : 0;
    if (clamp)
        xi = fmin(fmax(xi, 0), 1);
    double x[2], d[2];
    curve(S, xi, 0, x), curve(S, xi, 1, d);
    const double dn = hypot(d[0], d[1]);
    G->xi = xi, G->n[0] = -d[1] / dn, G->n[1] = d[0] / dn;
    G->g = G->n[0] * (xs[0] - x[0]) + G->n[1] * (xs[1] - x[1]);
    master_gradient(S, xi, G->n, G->dg);
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
