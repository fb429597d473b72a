/* block.h - rigid convex blocks for rockfall (issue 30, the core): shapes
 * and their exact mass properties (block_shape.c, block_hull.c,
 * block_mass.c), the rigid body's state and its free flight (block_body.c),
 * and non-smooth contact dynamics against planes and a ground height
 * callback (block_contact.c).  The profile and terrain engines and the
 * trajectory files use it through src/trajectory/block_traj*.c
 * (docs/block-shape.md, "Wiring").
 *
 * Frames.  Space: x, y horizontal, z up, gravity (0, 0, -g).  Body: origin
 * at the centre of mass, axes along the principal axes of inertia, ordered
 * so that I1 <= I2 <= I3.  The orientation q (a unit quaternion w, x, y, z)
 * maps body vectors to space vectors: p_space = x + R(q) p_body.
 * Units SI: m, kg, kg/m^3, kg m^2, s, m/s, rad/s, J. */
#ifndef ROCKFUZZ_BLOCK_H
#define ROCKFUZZ_BLOCK_H

#include <stddef.h>

#include "rockfuzz/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- shapes (block_shape.c) ---- */

typedef enum { RF_BLOCK_SPHERE = 0, RF_BLOCK_ELLIPSOID, RF_BLOCK_POLYHEDRON } rf_block_kind;

/* A homogeneous convex block in its body frame.  A box is a polyhedron. */
typedef struct {
    rf_block_kind kind;
    double semi[3];        /* sphere: radius in semi[0..2]; ellipsoid: semi-axes along body x, y, z [m] */
    size_t n_vertices;     /* polyhedron: hull vertices in the body frame [m] */
    double *vertices;      /* 3 n_vertices */
    size_t n_faces;        /* polyhedron: triangles of the hull, counter-clockwise seen from outside */
    int *faces;            /* 3 n_faces indices into vertices */
    double density;        /* [kg/m^3] */
    double volume;         /* [m^3] */
    double mass;           /* [kg] */
    double inertia[3];     /* principal moments about the centre of mass, I1 <= I2 <= I3 [kg m^2] */
    double bound_radius;   /* largest distance of the surface from the centre of mass [m] */
    /* Where the body frame sits in the frame the shape was given in
     * (polyhedra from points): p_given = centre + axes p_body, axes the
     * 3x3 rotation, row-major, its columns the principal axes. */
    double centre[3];
    double axes[9];
} rf_block_shape;

rf_status rf_block_sphere(double radius, double density, rf_block_shape *s, rf_error *err);
rf_status rf_block_ellipsoid(double a, double b, double c, double density, rf_block_shape *s, rf_error *err);
/* A box of edges lx, ly, lz [m] (a polyhedron of 8 vertices). */
rf_status rf_block_box(double lx, double ly, double lz, double density, rf_block_shape *s, rf_error *err);
/* The convex hull of n >= 4 points (3 n coordinates, any frame) as a
 * homogeneous polyhedron; points that are not hull vertices are dropped.
 * Fails (naming the reason) when the points are all (nearly) coplanar. */
rf_status rf_block_polyhedron(size_t n, const double *points, double density, rf_block_shape *s, rf_error *err);
/* Stand-ins for the EOTA test blocks (ETAG 027's concrete block, used by
 * WSL as "EOTA111" and, stretched 2:2:1, as the wheel "EOTA221"): a cube
 * with its eight corners cut (docs/block-shape.md says where the geometry
 * comes from), of the given volume [m^3]. */
rf_status rf_block_eota_cube(double volume, double density, rf_block_shape *s, rf_error *err);
rf_status rf_block_eota_wheel(double volume, double density, rf_block_shape *s, rf_error *err);
/* Stretch the block along its body axes by (sx, sy, sz) > 0 (a polyhedron's
 * vertices, an ellipsoid's semi-axes; a sphere becomes an ellipsoid), then,
 * if volume > 0, scale it uniformly to that volume (the seed's S3: axis
 * ratios change at constant volume).  Mass properties are recomputed
 * exactly; the body frame is re-found (principal axes may reorder). */
rf_status rf_block_stretch(rf_block_shape *s, double sx, double sy, double sz, double volume, rf_error *err);
/* Scale uniformly to the given volume [m^3]. */
rf_status rf_block_scale_to_volume(rf_block_shape *s, double volume, rf_error *err);
rf_status rf_block_copy(const rf_block_shape *src, rf_block_shape *dst, rf_error *err);
void rf_block_shape_free(rf_block_shape *s);

/* Support point: the point of the body-frame surface farthest along the
 * body-frame direction d (need not be unit); returns d . p. */
double rf_block_support(const rf_block_shape *s, const double d[3], double p[3]);

/* ---- mass properties of a closed triangulated surface (block_mass.c) ---- */

/* Volume, centroid and inertia tensor (about the centroid, row-major 3x3,
 * density 1) of the solid bounded by n_faces outward triangles, by
 * tetrahedral decomposition (Tonon 2004). */
void rf_block_mesh_mass(const double *vertices, size_t n_faces, const int *faces, double *volume, double centroid[3],
                        double inertia[9]);
/* Eigen-decomposition of a symmetric 3x3 matrix (cyclic Jacobi):
 * eigenvalues ascending, eigenvectors as the columns of vec (row-major),
 * a right-handed rotation. */
void rf_block_sym_eigen(const double a[9], double val[3], double vec[9]);

/* ---- convex hull (block_hull.c) ---- */

/* Incremental 3D convex hull with a relative tolerance: a point counts as
 * outside a face only farther than eps = 1e-10 x the points' extent.
 * Returns the hull's triangles (outward, counter-clockwise) as indices into
 * points in *faces (malloc'd, 3 *n_faces). */
rf_status rf_block_hull(size_t n, const double *points, int **faces, size_t *n_faces, rf_error *err);

/* ---- the rigid body (block_body.c) ---- */

typedef struct {
    double x[3];   /* centre of mass, space [m] */
    double q[4];   /* orientation, unit quaternion (w, x, y, z), body -> space */
    double v[3];   /* velocity of the centre, space [m/s] */
    double w[3];   /* angular velocity, body frame [rad/s] */
} rf_block_state;

/* A body vector to space and back. */
void rf_block_to_space(const double q[4], const double b[3], double s[3]);
void rf_block_to_body(const double q[4], const double s[3], double b[3]);
/* The unit quaternion of a rotation matrix (row-major): with q of a
 * shape's axes the body sits as the shape was given (up to its centre). */
void rf_block_quat_from_matrix(const double r[9], double q[4]);
/* Angular momentum about the centre of mass in space [kg m^2/s]. */
void rf_block_angular_momentum(const rf_block_shape *s, const rf_block_state *st, double L[3]);
/* Kinetic energy, translational + rotational [J], and the rotational part
 * about each body axis (rot may be NULL). */
double rf_block_kinetic_energy(const rf_block_shape *s, const rf_block_state *st, double rot[3]);
/* Kinetic + potential (m g z) energy [J]. */
double rf_block_energy(const rf_block_shape *s, const rf_block_state *st, double g);
/* The free rotor over h: the symplectic splitting of T = sum L_i^2/(2 I_i)
 * into rotations about the body axes, R1(h/2) R2(h/2) R3(h) R2(h/2)
 * R1(h/2), each exact; keeps the space angular momentum and |L| to
 * round-off, the energy to O(h^2) (docs/block-shape.md). */
void rf_block_rotor_step(const double inertia[3], double q[4], double w[3], double h);
/* Free flight over h under gravity g: exact translation, rotor step. */
void rf_block_flight_step(const rf_block_shape *s, rf_block_state *st, double g, double h);
/* Lowest point of the block along the unit space direction `up` (its
 * passing height is up . p): returns up . p and the point in space. */
double rf_block_lowest_point(const rf_block_shape *s, const rf_block_state *st, const double up[3], double p[3]);

/* ---- contact (block_contact.c) ---- */

/* The ground as a height field: z and the unit upward normal at (x, y);
 * returns 0 outside (no ground there).  A one-line wrapper of
 * rf_terrain_height (terrain.h) with the terrain as ctx is one. */
typedef int (*rf_block_ground_fn)(void *ctx, double x, double y, double *z, double normal[3]);
/* An upper bound over the rectangle [x0, x1] x [y0, y1] of the ground's
 * height above the plane z = plane[0] + plane[1] x + plane[2] y:
 * *dz >= z_ground(x, y) - (plane[0] + plane[1] x + plane[2] y) there [m];
 * returns 0 when no ground lies in the rectangle.  Optional
 * (rf_block_world.ground_bound; the block passes the ground's tangent plane
 * under its centre): with it rf_block_advance takes long flight steps and
 * a contact step evaluates the ground only at the vertices within the
 * bound.  For a bilinear DEM the bound can be exact: the ground minus a
 * plane is bilinear in each cell, so its largest value over the rectangle
 * lies at one of the points (x, y) with x in {x0, x1, the grid lines
 * between} and y likewise (bench/bench_block.c has one). */
typedef int (*rf_block_ground_bound_fn)(void *ctx, double x0, double y0, double x1, double y1,
                                        const double plane[3], double *dz);

/* A contact plane: the points p with n . (p - point) >= 0 are free. */
typedef struct {
    double point[3];
    double normal[3]; /* unit */
} rf_block_plane;

/* A profile in the x-z plane extruded along y (segments between
 * increasing x[i], z[i]): rf_block_ground_profile is its callback. */
typedef struct {
    size_t n;
    const double *x, *z;
} rf_block_profile;
int rf_block_ground_profile(void *profile, double x, double y, double *z, double normal[3]);

typedef struct {
    double e_n, e_t;     /* Newton's normal and tangential restitution, in [0, 1] */
    double mu;           /* Coulomb friction coefficient */
    double g;            /* gravity [m/s^2] */
    double h;            /* time step [s] */
    double tol;          /* prox iteration: relative change of the impulses to stop (e.g. 1e-12) */
    int max_iter;        /* prox iteration cap (e.g. 500) */
    size_t n_planes;     /* contact planes (may be 0) */
    const rf_block_plane *planes;
    rf_block_ground_fn ground; /* may be NULL */
    void *ground_ctx;
    rf_block_ground_bound_fn ground_bound; /* may be NULL (ground_ctx is its ctx) */
} rf_block_world;

/* What the last step did. */
typedef struct {
    int n_contacts;      /* active contact points at the midpoint */
    int iterations;      /* prox Gauss-Seidel sweeps */
    int converged;       /* 1 if the sweeps met tol */
    double impulse_n;    /* sum of normal impulses [N s] */
    double energy_cap;   /* energy (kinetic + m g z) removed so that a contact step gains none [J]:
                          * the step's end velocities and displacement scaled alike (block_contact.c) */
} rf_block_step_info;

/* One Moreau midpoint step: half a free step, the contacts active at the
 * midpoint (gap <= 1e-9 m), Newton's impact law and set-valued Coulomb friction
 * solved by a prox Gauss-Seidel over the contact points, half a free step
 * with the new velocity.  Contact points: a polyhedron's vertices; a
 * sphere's or ellipsoid's support point along the ground's -n.  A step
 * with contacts never ends with more energy (kinetic + m g z) than it
 * started with: the scheme's O(h) gain on a turning persistent contact is
 * capped (block_contact.c).  A step that continues the calling thread's
 * last step (same shape and world, from the state it ended in) starts the
 * prox sweeps from that step's impulses (the same solution to tol, fewer
 * sweeps).  With w->ground_bound the ground is evaluated only at the
 * vertices within the bound. */
void rf_block_step(const rf_block_shape *s, const rf_block_world *w, rf_block_state *st, rf_block_step_info *info);

/* One step of adaptive length (docs/block-shape.md, "Speed"): when the
 * block provably stays clear of every plane (its bounding sphere) and of
 * the ground (its bounding sphere or each vertex against
 * w->ground_bound's plane over the swept rectangle) for tau = 2^k h, k >= 1,
 * a free flight of the longest such tau <= h_max (exact parabola; the
 * rotor in sub-steps turning at most 0.05 rad each); otherwise one
 * rf_block_step of w->h.  Without w->ground_bound, a world with a ground
 * always takes the contact step.  Returns the time advanced [s]; info as
 * rf_block_step's (n_contacts 0 in flight). */
double rf_block_advance(const rf_block_shape *s, const rf_block_world *w, rf_block_state *st, double h_max,
                        rf_block_step_info *info);

/* ---- ParaView output (block_vtk.c) ---- */

/* The block's surface at each of the n recorded states (times [s],
 * increasing) for ParaView: dir/stem.pvd, a VTK collection of
 * dir/stem_NNNN.vtp (NNNN = 0000, 0001, ...), each VTK XML PolyData (ASCII)
 * of the hull's triangles in space at that pose (a sphere or ellipsoid as a
 * 12 x 24 latitude-longitude tessellation), with the time as field data and
 * each point's velocity [m/s]; coordinates in m.  dir must exist; stem is a
 * file name without '/'. */
rf_status rf_block_write_vtk(const char *dir, const char *stem, const rf_block_shape *s, const rf_block_state *states,
                             const double *times, size_t n, rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
