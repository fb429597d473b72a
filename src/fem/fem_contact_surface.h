/* fem_contact_surface.h - the smooth master surface of the axisymmetric
 * large-deformation contact (fem_contact_surface.c): one segment of the
 * slope's current surface, its chord with the corners at its nodes rounded
 * by quadratic arcs, so that the normal is continuous along the surface (C1)
 * and the masters' weights are never negative; the closest-point gap of a
 * slave and its exact gradient. */
#ifndef ROCKFUZZ_FEM_CONTACT_SURFACE_H
#define ROCKFUZZ_FEM_CONTACT_SURFACE_H

/* Segment j of a surface z(r) given by its nodes p[1] = x_j and
 * p[2] = x_{j+1} and their neighbours p[0] = x_{j-1}, p[3] = x_{j+2} (r, z),
 * current positions [m].  has_prev = 0: x_j is on the axis (no p[0]: the
 * mirror image of x_{j+1} stands for it, so the tangent there is radial);
 * has_next = 0: x_{j+1} ends the surface (no p[3]: 2 x_{j+1} - x_j stands
 * for it, so the curve ends straight). */
typedef struct {
    double p[4][2];
    int has_prev, has_next;
} fem_surf_segment;

/* A slave's closest point on the segment's curve: parameter xi, gap
 * g = n . (x_s - x(xi)) [m] along the unit normal n (r, z) there (the
 * tangent turned by +90 degrees: up, n_z > 0, on a graph z(r)), and the gap's
 * gradient: n for the slave, dg[k] for the master node p[k] (exact: the
 * closest point makes xi and n drop out of it). */
typedef struct {
    double xi, g, n[2];
    double dg[4][2];
} fem_surf_gap;

/* The closest point of xs on the curve.  Returns 0 when it lies on the
 * segment (0 <= xi <= 1), -1 when before x_j, +1 when past x_{j+1}
 * (then xi is clamped to the end, and the caller moves to the neighbouring
 * segment if there is one). */
int fem_surf_project(const fem_surf_segment *S, const double xs[2], fem_surf_gap *G);

/* The same on the segment's curve extended past its ends (xi not clamped):
 * the gap and exact gradient of a slave that has just left the segment. */
int fem_surf_project_extended(const fem_surf_segment *S, const double xs[2], fem_surf_gap *G);

/* The curve's point x(xi) and unit tangent there (for the tests). */
void fem_surf_point(const fem_surf_segment *S, double xi, double x[2], double t[2]);

#endif
