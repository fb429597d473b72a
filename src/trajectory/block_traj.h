/* block_traj.h - rigid convex blocks in the trajectory engines (issue 30,
 * the wiring; docs/block-shape.md "Wiring"): the block of a trajectory file
 * (block_traj_yaml.c), its shape, orientation, spin, material mapping and
 * placement (block_traj_setup.c), the 2D profile run (block_traj_profile.c)
 * and the terrain run (block_traj_terrain.c).  The dynamics are block.h's. */
#ifndef ROCKFUZZ_BLOCK_TRAJ_H
#define ROCKFUZZ_BLOCK_TRAJ_H

#include "rockfuzz/block.h"
#include "trajectory/traj_internal.h"
#include "rockfuzz/terrain.h"

/* An impact is counted when the block touches the ground after at least
 * this long in the air [s]; shorter lifts (a tumbling block's corners
 * rocking) belong to the same ground contact. */
#define BLOCK_TRAJ_IMPACT_FLIGHT 0.02
/* Events of a recorded trajectory: at every impact, launch and the end, and
 * every so long in between [s]. */
#define BLOCK_TRAJ_EVENT_EVERY 0.01

/* The hash of what a block spec holds outside the rows: kind, dimensions,
 * points, orientation, spin (the model identity). */
uint64_t traj_block_hash(uint64_t h, const rf_traj_spec *s);
/* The block's shape name ("box") for messages and outputs. */
const char *traj_block_kind_name(int kind);
/* The block in words for the reports: "point, mass ...", "sphere, radius ...",
 * "rigid box, volume ..., density ..., mass ..." (block_traj_output.c). */
void traj_block_describe(const rf_traj_spec *s, char *buf, size_t size);

/* The shape with the spec's values (volume, axis ratios, density). */
rf_status traj_block_shape(const rf_traj_spec *s, rf_block_shape *shape, rf_error *err);
/* Initial orientation of the shape (as given, turned by block_q0, or drawn
 * for sample `sample`: uniform on SO(3), or about y only when planar) and
 * spin in the body frame (from the space vector w_space). */
void traj_block_orientation(const rf_traj_spec *s, const rf_block_shape *shape, uint64_t seed, uint64_t sample,
                            int planar, double q[4]);
/* Contact material: e_n = R_n, e_t from R_t, mu = tan(friction_angle). */
void traj_block_material(const rf_traj_material *m, double *e_n, double *e_t, double *mu);
/* Put the block (orientation st->q set) with its lowest point at p
 * (x, y, z), then lift it until no vertex (or the support point) lies
 * below the ground; returns 0 if the ground is missing under it. */
int traj_block_place(const rf_block_shape *shape, rf_block_ground_fn ground, void *ctx, const double p[3],
                     rf_block_state *st);
/* Space angular velocity of the state. */
void traj_block_omega_space(const rf_block_state *st, double w[3]);
/* Planar motion (a profile): the velocity projected, in the kinetic
 * metric, onto the x-z plane's motions (v_y = 0; space w along y with the
 * angular momentum about y kept: never gains energy), y = 0, and the
 * orientation turned back to a rotation about y of the initial one q0. */
void traj_block_planar(const rf_block_shape *shape, const double q0[4], rf_block_state *st);

/* ---- one running block (block_traj_run.c), shared by both engines ---- */

/* Called after every step (tests: energy, path): the time, the shape, the
 * state after the step and what the step did. */
typedef void (*traj_block_observer)(void *ctx, double t, const rf_block_shape *s, const rf_block_state *st,
                                    const rf_block_step_info *info);

enum { BLOCK_STEP_IMPACT = 1, BLOCK_STEP_LAUNCH = 2, BLOCK_STEP_REST = 4 };

/* The longest flight step [s] (rf_block_advance's h_max): a flight is the
 * exact parabola and the rotor in sub-steps of at most 0.05 rad, so this
 * bounds only how often the engines record and test the ground's bound. */
#define BLOCK_TRAJ_FLIGHT_MAX 0.064

typedef struct {
    rf_block_shape shape;
    rf_block_state st, prev;      /* after and before the last step */
    rf_block_world bw;            /* contact law, ground and its bound; material set per step */
    rf_block_step_info info;
    double q0[4];                 /* planar: the initial orientation (the turns are about y from it) */
    int planar;
    double t, dt, air;            /* time [s]; the last step's length [s]; time since the last contact [s] */
    double calm;                  /* time the kinetic energy has stayed below e_rest [s] */
    double e_rest;                /* m v_stop^2 / 2 [J] */
    double rest_time, max_time;   /* [s] */
    double rise_z;                /* centre height at the last impact [m] (rebound height) */
    int after_impact;             /* in the flight after an impact */
    double next_event;            /* the next regular event [s] (the engines set it at each event) */
    int done;                     /* the run has ended (set by the engines) */
    size_t *n_steps;              /* the result's step count */
    double *rebound_height;       /* the result's rebound height [m] */
    traj_block_observer obs;
    void *obs_ctx;
} block_run;

/* What an engine does around the shared loop (block_run_loop): its ground
 * lookup and its records. */
typedef struct {
    /* The material under the lowest point p and where it is (the segment, or
     * the material index) for the impact record; NULL: no ground (exit). */
    const rf_traj_material *(*locate)(void *eng, const double p[3], size_t *where);
    void (*after_step)(void *eng);                      /* crossings, barriers, rasters of the last step */
    void (*impact)(void *eng, size_t where);            /* the impact record of the last step */
    void (*event)(void *eng, rf_traj_event_kind kind, int flying);
    void (*finish)(void *eng, rf_traj_state state, rf_traj_event_kind kind);
} block_engine;

/* Shape, orientation, spin (space vector w_space), contact settings; the
 * ground is set by the caller.  Frees nothing on failure. */
rf_status block_run_init(block_run *b, const rf_traj_spec *s, uint64_t seed, uint64_t sample, int planar,
                         const double w_space[3], rf_error *err);
/* One step with the material m (rf_block_advance: a flight of up to
 * BLOCK_TRAJ_FLIGHT_MAX when the ground's bound proves it clear, else a
 * contact step of h): returns BLOCK_STEP_* flags. */
int block_run_step(block_run *b, const rf_traj_material *m);
/* The one stepper of both engines: until b->done, a step with the material
 * under the lowest point, the engine's after_step, the exit check (locate),
 * impact, launch and regular events, rest and the time limit. */
void block_run_loop(block_run *b, const block_engine *e, void *eng);
/* The state at the fraction f of the last step: in flight the exact
 * parabola and the rotor from the state before it; in contact (one step of
 * h) the centre and its velocity interpolated linearly, the end's
 * orientation and spin. */
void block_run_state_at(const block_run *b, double f, rf_block_state *out);
/* The lowest point of the state (p) and its height (returned). */
double block_run_lowest(const block_run *b, const rf_block_state *st, double p[3]);
/* Rotational energy about each body axis [J] and the total kinetic energy [J]. */
double block_run_energy(const block_run *b, const rf_block_state *st, double rot[3]);

/* ---- the ground adapters (block_traj_ground.c) ---- */

/* The profile's (rf_block_profile, ctx) bound above a plane over a
 * rectangle (rf_block_ground_bound_fn): exact, from the rectangle's ends in
 * x and the profile's nodes between. */
int traj_block_profile_bound(void *profile, double x0, double y0, double x1, double y1, const double plane[3],
                             double *dz);
/* The terrain (rf_terrain, ctx) as the block's ground: rf_terrain_height,
 * and its bound above a plane over a rectangle, exact: the ground minus the
 * plane is bilinear in each cell, so its largest value over the part of a
 * valid cell inside the rectangle lies at one of that part's corners. */
int traj_block_terrain_ground(void *dem, double x, double y, double *z, double n[3]);
int traj_block_terrain_bound(void *dem, double x0, double y0, double x1, double y1, const double plane[3],
                             double *dz);

/* The 2D engine: a profile extruded along y (block_traj_profile.c). */
rf_status traj_block_simulate(const rf_traj_world *w, const rf_traj_spec *s, uint64_t seed, uint64_t sample,
                              rf_traj_result *res, rf_error *err);
rf_status traj_block_simulate_observed(const rf_traj_world *w, const rf_traj_spec *s, uint64_t seed,
                                       uint64_t sample, rf_traj_result *res, traj_block_observer obs, void *ctx,
                                       rf_error *err);

/* The terrain engine (block_traj_terrain.c): terrain_simulate_hazard's
 * branch for a rigid block; hazard may be NULL; obs (tests) may be NULL. */
struct rf_terrain_hazard;
rf_status terrain_block_simulate(const rf_terrain_world *w, const rf_traj_spec *s, uint64_t seed, uint64_t sample,
                                 const double start[3], struct rf_terrain_hazard *hazard, rf_terrain_result *res,
                                 traj_block_observer obs, void *ctx, rf_error *err);

/* block_traj_output.c: the JSON additions of a rigid block (after an
 * impact's members: "q", "rotational_energy_axes" [J]; after a recorded
 * trajectory's: "orientation": [[t, w, x, y, z], ...] at its events). */
void traj_block_json_impact(FILE *f, const double q[4], const double rot_energy[3]);
void traj_block_json_orientation(FILE *f, const rf_traj_result *r);
void terrain_block_json_orientation(FILE *f, const rf_terrain_result *r);

/* block_traj_vtk.c: with outputs.vtk of a rigid block, DIR/vtk/block_K.pvd (+
 * .vtp frames) of the hull along each recorded trajectory K, at sample K's
 * shape; on terrain (outputs.vtk or not) also DIR/trajectories.csv
 * (traj_block_write_terrain_paths). */
rf_status traj_block_write_vtk_runs(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                                    rf_error *err);

/* block_traj_paths.c: a terrain run of a rigid block: DIR/trajectories.csv,
 * every event of each recorded trajectory (lowest point [m], centre's
 * velocity [m/s], space angular velocity [rad/s], event, q). */
rf_status traj_block_write_terrain_paths(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                                         rf_error *err);

#endif
