/* traj_impact.h - the bounce law `impact_model`: the adapter to rockfuzz's
 * impact models (traj_impact_adapter.c) and the adaptive table of R_n, R_t
 * and spin over (normal speed, incidence) (traj_impact_table.c). */
#ifndef ROCKFUZZ_TRAJ_IMPACT_H
#define ROCKFUZZ_TRAJ_IMPACT_H

#include "rockfuzz/trajectory.h"

#include "rockfuzz/model.h"

#include <stdatomic.h>

typedef struct traj_impact_setup_s {
    int solver;           /* rf_impact_solver */
    double radius, density, friction;
    double refinement;    /* FE a/h, 0 = default */
    const atomic_int *stop; /* non-zero: an FE impact stops between two steps (RF_EINTERRUPTED); may be NULL */
    int has_ground;       /* a material's own impact model: ground applies (else elastic granite) */
    rf_traj_impact_ground ground;
} traj_impact_setup;

/* Where the impacts of a table are kept across runs (a study's store):
 * load appends the rows (v_n, theta, radius, R_n, R_t, spin) known for the
 * setup (any radius) to *memo, each checked as traj_impact_cache_load does;
 * put keeps one new row. */
struct traj_impact_store {
    void *user;
    rf_status (*load)(void *user, const traj_impact_setup *s, double **memo, size_t *n, size_t *cap, rf_error *err);
    rf_status (*put)(void *user, const traj_impact_setup *s, const double row[6], rf_error *err);
};

/* The k-th impact solver's name (rockfuzz impact --solver), NULL past the last:
 * the names bounce.impact.solver takes. */
const char *traj_impact_solver_name(size_t k);
rf_status traj_impact_setup_init(traj_impact_setup *s, const rf_traj_spec *spec, rf_error *err);
/* The setup of material k: its own impact model (materials.NAME.impact; the
 * friction bounce.impact.friction, else tan of its friction_angle), else
 * traj_impact_setup_init's. */
rf_status traj_impact_setup_material(traj_impact_setup *s, const rf_traj_spec *spec, size_t k, rf_error *err);
/* The impact input (rf_impact_fields) of ground number k, NULL past the last:
 * the row materials.NAME.impact.<it> holds rf_traj_impact_ground.v[k]. */
const char *traj_impact_ground_field(size_t k);
/* Check a material's impact model at load: its solver and materials named,
 * the ground's inputs admissible for the impact model and its solver. */
rf_status traj_impact_ground_check(const rf_traj_impact_ground *g, const char *run_solver, rf_error *err);
/* The identity of the setup without the radius: "solver=..,rho=..,mu=..,ref=..[,ground=HASH]"
 * (the cache file's key and the store's), into key[size]. */
void traj_impact_setup_key(const traj_impact_setup *s, char *key, size_t size);
/* Why a row (v_n, theta, radius, R_n, R_t, spin) cannot be an impact of a sphere, or NULL. */
const char *traj_impact_row_invalid(const double r[6]);
/* The block radii of a run [m]: lo = hi = the sphere's radius unless block.radius is random. */
void traj_impact_radius_range(const rf_traj_spec *s, double *lo, double *hi);
/* The ground's soil layer thickness [m] (the row impact.layer_thickness; 0: rock only). */
double traj_impact_layer_thickness(const rf_traj_impact_ground *g);
/* The table preset of a soil layer (docs/soil-impacts.md sections 3-4): an FE
 * setup on a layer (layer_thickness > 0), at any refinement (0: the 3D
 * model's default a/h 3; every tabulated impact is oblique, at least 1 deg,
 * so 3D; docs/soil-surrogate.md sec. 4 runs a/h 2 with it), carries the rock
 * under the layer at 100 times its inertia
 * (rock_mass_scale): the rock, not the layer, sets the explicit step; on the
 * S5 layer on a 30 deg incline the same mesh moves R_n, R_t by 3e-4 for 4.6x
 * less CPU.  1 when it applies (the setup's key then says so: rows computed
 * without it are not reused). */
int traj_impact_layer_preset(const traj_impact_setup *s);

/* 1 if the setup's impacts are the FE's (whose ground is then no steeper than
 * a layer stands, rf_fem_options.ground stable: the setup's key says so). */
int traj_impact_fem(const traj_impact_setup *s);
/* One impact: normal speed vn [m/s] > 0, incidence theta [rad] from the normal. */
rf_status traj_impact_coefficients(const traj_impact_setup *s, double vn, double theta, double *R_n, double *R_t,
                                   double *spin, rf_error *err);

/* traj_impact_store.c: the impacts kept in a study's store (side rows): a
 * traj_impact_store over side (which must outlive it). */
void traj_impact_store_from_side(const rf_model_side_store *side, traj_impact_store *out);

/* traj_impact_cache.c: rows of (v_n, theta, radius, R_n, R_t, spin) for this
 * setup (any radius) appended to *memo from the file, each checked (finite,
 * v_n > 0, theta in [0, pi/2), radius > 0, R_n in [0, 1], |R_t| <= 1, no
 * energy gained beyond 1 %), an identical repeat kept once, a conflicting one
 * refused with both lines; and new rows appended to the file (the radius is
 * the row's, not the setup's). */
rf_status traj_impact_cache_load(const char *path, const traj_impact_setup *s, double **memo, size_t *n,
                                 size_t *cap, rf_error *err);
void traj_impact_cache_append(const char *path, const traj_impact_setup *s, const double *rows, size_t count);

/* traj_impact_table.c: a table that is the weighted sum of n others (not
 * copied: they must outlive it; w[k] >= 0 summing to 1), looked up as one
 * (the impact surrogate's table at a point of the material parameters). */
struct traj_impact_table;
rf_status traj_impact_table_blend(const struct traj_impact_table *const *parts, const double *w, size_t n,
                                  struct traj_impact_table **out, rf_error *err);

#endif
