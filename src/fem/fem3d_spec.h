/* fem3d_spec.h - the mesh specification of a 3D impact (fine-box counts and
 * size from the Hertz contact radius, layer settings), computed in one place
 * so that benches and tests build exactly the mesh the solver runs on.
 * Internal header. */
#ifndef ROCKFUZZ_FEM3D_SPEC_H
#define ROCKFUZZ_FEM3D_SPEC_H

#include "fem3d_internal.h"
#include "rockfuzz/fem3d.h"

/* Fills *ms (and the contact element size h [m] and Hertz radius a [m]) as
 * rf_fem3d_impact_ex does for (in, o, o3).  Does not validate the inputs. */
void f3_impact_mesh_spec(const rf_impact_input *in, const rf_fem_options *o, const rf_fem3d_options *o3,
                         f3_mesh_spec *ms, double *h, double *a_hertz);

/* The contact a boulder makes with the layer over the slope, for the mesh
 * sizing.  Elastic layer: the layer's Hertz impact (rf_impact_hertz_reference
 * with the layer as the slope).  Plastic layer: the depth d at which the work
 * of the mean contact pressure p over the area pi R s (a^2 = R s as in Hertz)
 * takes the normal kinetic energy, with p = min(elastic Hertz mean pressure
 * 4 E* sqrt(s / R) / (3 pi), a plastic branch): Drucker-Prager with a cap
 * X0 + 4 E*_p sqrt(s / R) / (3 pi), E*_p = E* H_c / (H_c + M), M the
 * constrained modulus E (1 - nu) / ((1 + nu)(1 - 2 nu)) (the soil under the
 * contact crushed in near-confined compression: the tangent of the elastic
 * and the cap's hardening in series); von Mises 3 Y (fully plastic, Johnson
 * 1985); Drucker-Prager without a cap: elastic (no estimate).  The fine zone
 * must cover the sphere's chord sqrt(2 R D - D^2) at twice that depth, D = 2 d
 * (no sink-in, and a margin for the estimate: soil beyond the boulder's
 * slave nodes is not held), capped at 0.95 c.  Docs:
 * docs/validation-plastic.md section 9d. */
typedef struct {
    int thick;          /* compression <= layer_thickness / 2 and radius <= layer_thickness: the boulder
                           stays in the layer and its contact's stresses spread there; its contact alone
                           sizes the mesh (else the finer of the rock's and the layer's Hertz contacts) */
    double compression; /* estimated depth [m] */
    double radius;      /* sqrt(R d) [m] (the Hertz radius for an elastic layer) */
    double zone_radius; /* radius the fine zone must cover [m] (= radius for an elastic layer) */
    double duration;    /* 2.943 d / v_n [s] (an upper bound for a plastic contact, whose unloading is short) */
} f3_layer_contact;
void f3_layer_contact_estimate(const rf_impact_input *in, f3_layer_contact *lc);

/* Radius in the boulder's half-space image (fem3d_mesh.c: the inversion about
 * (0, 0, 2r)) of the circle at horizontal distance s on a ball of radius r
 * (s capped at 0.95 r): 2 r (1 - sqrt(1 - (s/r)^2)) / (s/r). */
double f3_ball_image_radius(double s, double r);
/* A rigid boulder's fine box (of cube size b->h in the image) on a thick soft
 * layer: the image of the ball's cap of horizontal radius half_width [m],
 * half_width + travel down-slope (x > 0); r0 the ball's radius, scale_xy the
 * spheroid's horizontal scale.  A rigid boulder's box only carries the
 * contact's slave nodes, so it may cover the whole lower half of the ball. */
void f3_soft_boulder_box(f3_box *b, double half_width, double travel, double r0, double scale_xy);

#endif
