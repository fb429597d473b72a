/* fem_tuning.h - the numerical settings of the FE solvers that no user chooses
 * for a physical reason: mesh grading, time-step safety, the material kernels,
 * the caps, and the second methods that the validation tests compare the
 * defaults against (the lumped contact face, the faceted contact of a rigid
 * sphere, single pivoting).  Internal to src/fem and the tests and benchmarks
 * (the CLI, the study and the impact model never include it): a run takes
 * them through rf_fem_options.tuning, NULL = fem_tuning_default.  Defaults are
 * the validated ones (docs/validation*.md, docs/fem-speed.md). */
#ifndef ROCKFUZZ_FEM_TUNING_H
#define ROCKFUZZ_FEM_TUNING_H

#include "rockfuzz/fem3d.h"

/* Material kernel of a body (src/fem/fem_kernel.h): how its internal force is computed. */
typedef enum {
    RF_FEM_KERNEL_STIFFNESS = 0, /* linear elastic, the fastest (default): axisymmetric, precomputed element
                                    stiffness; 3D, matrix-free at the Gauss points (docs/fem-speed.md) */
    RF_FEM_KERNEL_POINTS         /* linear elastic stress update at the integration points: the form
                                    elasto-plastic laws take (~5x slower; in 3D the hexahedron's
                                    point kernel, without B-bar: the elastic results to round-off) */
} rf_fem_kernel;

struct rf_fem_tuning {
    double boulder_mesh_ratio; /* boulder / slope element size in the fine zone, default 1 (matching);
                                  [0.25, 1.25] (3D: 4): the boulder nodes are the contact slaves */
    double fine_zone_factor;   /* axisymmetric: the uniform fine zone extends fine_zone_factor * a, default 2.5 */
    double grading;            /* axisymmetric: element-size growth per element outside the fine zone, 1.15 */
    double dt_safety;          /* time step = dt_safety * element eigenvalue bound, default 0.9 */
    double surface_mass_kappa; /* mass redistribution at the slope's contact face of a soil (a layer, an
                                  elasto-plastic slope; docs/validation-plastic.md 9e): a face element whose
                                  eigenvalue is below kappa x the mesh's largest gives its face nodes' mass
                                  (down to a tenth) to the nodes below until it reaches it; in [0, 1],
                                  0 = off (the lumped face), default 0.1 */
    int surface_mass_3d;       /* 1 (default): the same redistribution in the 3D model; 0: its lumped face,
                                  which loses 1-4 % of KE0 on soil at a/h 2-3 (section 9e) */
    int sphere_contact_3d;     /* 1 (default): a rigid sphere's 3D contact is the slope's face nodes against its
                                  exact sphere; 0: its faceted face against the slope's face, the contact an
                                  elastic boulder has (section 9g) */
    int vtk_frames;            /* approximate number of VTK frames, default 60 */
    int history_stride;        /* record every n-th step in rf_fem_history, 0 = auto (<= ~5000 samples) */
    long max_elements;         /* refuse larger meshes (RF_ECAP), default 2 000 000 */
    double duration_threshold; /* contact counts while force > this * F_max, default 1e-6 */
    rf_fem_kernel kernel[2];   /* material kernel of the boulder [0] and the slope [1], default stiffness */
    int contact_single_pivot;  /* axisymmetric contact: 1 solves the complementarity problem by single
                                  pivoting alone (the check of the default block active-set method, which
                                  falls back to it after 200 rounds), default 0 */
    double ale_trigger;        /* ALE: rezone when a slope element's size falls below this share of its
                                  reference size, default 0.5, in (0, 1) */
    int ale_sweeps;            /* ALE: smoothing sweeps per rezone, default 10 (0: no node moves) */
    int end_at_separation;     /* 1: with gravity and the automatic end, a run may end before its least time
                                  (1.3 Hertz durations) once the contact has opened with the boulder moving
                                  away and 0.1 of a duration has passed (R_n, R_t are the state at
                                  separation, so unchanged; the end-state energies differ); default 0
                                  (docs/soil-impacts.md section 3, "Where the time goes") */
};

/* The 3D model's own settings (rf_fem3d_impact_ex's o3). */
struct rf_fem3d_options {
    int full_model;          /* 0 = half model cut by the plane of motion (default), 1 = full */
    double fine_box_factor;  /* uniform fine box half-width / Hertz contact radius, default 1.3 */
    double elongation;       /* extra fine box length down-slope / (v_t * Hertz duration), default 1 */
    double layer_aspect;     /* radial / tangential element size in the graded layers, default 1.6 */
    double boulder_inner;    /* boulder: radius (/ r0) of the contact-side half-space image, default 4 */
    int layered_mesh;        /* 1: the slope as the extruded mesh a layer uses (horizontal node planes, a
                                cylinder of radius and depth domain) even without a layer; default 0 */
};

void fem_tuning_default(rf_fem_tuning *t);
void rf_fem3d_options_default(rf_fem3d_options *o3);
/* The check of the settings (three_d: the 3D model's limits); messages name the setting and value. */
rf_status fem_tuning_validate(const rf_fem_tuning *t, int three_d, rf_error *err);
/* opt->tuning, or the defaults when opt or its tuning is NULL. */
const rf_fem_tuning *fem_tuning_of(const rf_fem_options *opt);

/* t made o's tuning, filled with the defaults unless it already was: how a test or benchmark
   sets the numerics (rf_fem_tuning t; fem_tune(&o, &t)->dt_safety = 0.5). */
static inline rf_fem_tuning *fem_tune(rf_fem_options *o, rf_fem_tuning *t)
{
    if (o->tuning != t) {
        fem_tuning_default(t);
        o->tuning = t;
    }
    return t;
}

#endif
