/* trajectory.h - 2D rockfall trajectories on a slope profile: exact
 * parabolic flight, bounce laws, sliding/rolling, collectors (barrier lines),
 * Monte Carlo ensembles, and the trajectory model that `rockfuzz run`
 * studies bind fuzzy parameters to.  Algorithm and conventions:
 * docs/trajectories.md.
 *
 * Units SI: m, kg, s, m/s, rad/s, J.  Angles are given in DEGREES in a
 * trajectory file and in bindings (friction_angle, roughness, release.angle,
 * bounce.impact.max_incidence) and stored in RADIANS in the structs: the
 * input tables (rf_traj_field_tables) convert them once, at parse.  Axes: x to the right, y up; the profile is a
 * polyline with x non-decreasing; segment i joins point i to point i+1, its
 * tangent t points from i to i+1 and its normal n = (-t_y, t_x) points out of
 * the ground.  Spin omega is positive when it rolls the block forward along t
 * of the segment it touches (clockwise for travel to the right).
 *
 * The block is one point for contact (lumped mass): the simulated point is
 * the block's contact point, i.e. its lowest point when it lies on flat
 * ground; a sphere's centre is taken r above it.  The radius enters only the
 * inertia, the rotational energy, rolling, the rigid_sphere law and the
 * passing height of the centre. */
#ifndef ROCKFUZZ_TRAJECTORY_H
#define ROCKFUZZ_TRAJECTORY_H

#include <stddef.h>
#include <stdio.h>
#include <stdint.h>

#include "rockfuzz/status.h"
#include "rockfuzz/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- the trajectory file (spec) ---- */

/* Largest |x|, |y| of a profile vertex and |y| of the release [m]: beyond it a
 * value is not a physical height or distance (e.g. a DEM's undeclared no-data). */
#define RF_TRAJ_MAX_COORD 1e7

/* A material's own impact model (materials.NAME.impact, the impact_model
 * law; docs/trajectories.md sec. 3): the ground of `rockfuzz impact` (its
 * slope_* and layer_* inputs, same names and units) under the block.  The
 * numbers are the rows materials.NAME.impact.* of the material table, as
 * given (angles in degrees), with the impact model's defaults; the impact
 * friction is bounce.impact.friction, else tan(friction_angle) of the material. */
#define RF_TRAJ_IMPACT_N 16
typedef struct {
    int given;                  /* the material names its impact model (impact:) */
    char solver[16];            /* "" = bounce.impact.solver */
    char boulder_material[16];  /* "" = elastic (the block); elastic | von_mises | rigid */
    char slope_material[16];    /* "" = elastic; elastic | von_mises | drucker_prager */
    char layer_material[16];    /* "" = elastic */
    double v[RF_TRAJ_IMPACT_N]; /* the rows impact.slope_E ... impact.layer_cap_hardening (traj_fields.c) */
    /* The material's rolling_resistance against this impact model (rf_traj_rolling_resolve; not part of
       the impact model's identity): */
    int rolling_given;          /* given in the file or bound by a study: it wins over a derived value */
    int rolling_source;         /* 0 file, 1 default, 2 derived from the impact model, 3 rock (no layer) */
    double rolling_sinkage;     /* [m] derived: the rut depth under the rolling block (0 otherwise) */
} rf_traj_impact_ground;

typedef struct {
    char *name;
    double R_n;                 /* normal COR [-], in [0, 1] */
    double R_t;                 /* tangential COR [-], in [0, 1] */
    double friction_angle;      /* [rad] (given in deg), sliding mu = tan(phi); also the impact friction of rigid_sphere */
    double rolling_resistance;  /* [-] rolling resistance coefficient mu_r (force mu_r N) */
    double roughness;           /* [rad] (given in deg) SD of the slope-angle perturbation at each impact */
    rf_traj_impact_ground impact; /* impact_model law: this material's impact model (impact.given = 0: bounce.impact) */
} rf_traj_material;

typedef enum {
    RF_BOUNCE_CONSTANT = 0,     /* v_n' = -R_n v_n, v_t' = R_t v_t */
    RF_BOUNCE_VELOCITY_SCALED,  /* R_n / (1 + (|v_n|/K)^2), Pfeiffer & Bowen 1989, K = scale_speed */
    RF_BOUNCE_RIGID_SPHERE,     /* rigid sphere with spin and Coulomb friction, e_n = R_n */
    RF_BOUNCE_IMPACT_MODEL,     /* R_n, R_t, spin tabulated from a rockfuzz impact model */
    RF_BOUNCE_N_LAWS
} rf_bounce_law;
/* The law's name in a trajectory file and in the outputs (bounce.c). */
extern const char *const rf_traj_bounce_law_names[RF_BOUNCE_N_LAWS];

/* Pfeiffer & Bowen (1989) / RocFall / CRSP velocity-scaling constant: 30 ft/s. */
#define RF_TRAJ_PFEIFFER_BOWEN_K 9.144

/* Where a trajectory starts: the point (x0, y0); a point drawn uniformly (by
 * length) along a polyline; or one drawn uniformly along the ground inside a
 * zone (a polygon, or an x-range), on the ground. */
typedef enum { RF_TRAJ_RELEASE_POINT = 0, RF_TRAJ_RELEASE_LINE, RF_TRAJ_RELEASE_ZONE,
               RF_TRAJ_RELEASE_MAP   /* a terrain file: points, lines, polygons on the map (terrain.h) */
} rf_traj_release_kind;

typedef enum { RF_DIST_FIXED = 0, RF_DIST_UNIFORM, RF_DIST_NORMAL } rf_traj_dist;

/* A random numeric input: `path` (e.g. "release.vx", "materials.rock.R_n")
 * drawn per trajectory; uniform [a, b] or normal (mean a, SD b) truncated
 * to [lo, hi] by clamping the probability to the truncated range. */
typedef struct {
    char *path;
    rf_traj_dist dist;
    double a, b;
    double lo, hi;              /* truncation (-inf/inf: none) */
} rf_traj_random;

/* Lengths of the user's lists of percentiles and thresholds (`outputs:`, collectors). */
#define RF_TRAJ_MAX_PERCENTILES 16
#define RF_TRAJ_MAX_THRESHOLDS 16
#define RF_TRAJ_MAX_BINS 200

typedef struct {
    char *name;
    double x;                   /* [m] vertical line x = const (a profile; on terrain the line is
                                   spec->terrain->barrier_*) */
    double capacity;            /* [J] barrier energy capacity; 0 = a pure collector */
    double height;              /* [m] barrier height; 0 = unlimited (only with capacity) */
    /* User thresholds of P(total_energy > E) and P(height_lowest > h); the
     * barrier's capacity and height (when > 0) are added before them
     * (rf_traj_thresholds), so at most RF_TRAJ_MAX_THRESHOLDS - 1 each. */
    size_t n_energy_thresholds, n_height_thresholds;
    double energy_thresholds[RF_TRAJ_MAX_THRESHOLDS];   /* [J] */
    double height_thresholds[RF_TRAJ_MAX_THRESHOLDS];   /* [m] */
} rf_traj_collector;

/* `outputs:` of the trajectory file: which statistics are reported. */
typedef struct {
    size_t n_percentiles;                     /* default 3: 50, 95, 99 (max is always reported) */
    double percentiles[RF_TRAJ_MAX_PERCENTILES];  /* [%], increasing, in (0, 100) */
    size_t n_runout_thresholds;
    double runout_thresholds[RF_TRAJ_MAX_THRESHOLDS];  /* [m]: P(runout_x > x) */
    size_t runout_bins;                       /* bins of the runout histogram, default 20 */
    int vtk;                                  /* a rigid block: ParaView files of the recorded trajectories */
} rf_traj_outputs;

typedef struct {
    char *name;
    char *file;                 /* the file it was read from (messages), may be NULL */
    uint64_t text_hash;         /* FNV-1a of the trajectory file's text (0: built in memory); with the
                                   profile's vertices it makes the trajectory model's identity */
    double gravity;             /* [m/s^2], default 9.81 */
    size_t n_points;
    double *px, *py;            /* profile vertices [m] */
    size_t *seg_material;       /* n_points - 1 material indices */
    size_t n_materials;
    rf_traj_material *materials;
    int sphere;                 /* 0: point block, 1: sphere */
    double mass;                /* [kg] (point: given; sphere: from radius and density) */
    double radius, density;     /* [m], [kg/m^3] (sphere) */
    double x0, y0, vx0, vy0, omega0;  /* release [m], [m/s], [rad/s] */
    int release_by_speed;       /* the release velocity is speed0 at angle0 (not vx0, vy0) */
    double speed0, angle0;      /* [m/s], [rad] from the horizontal (given in deg), up positive */
    double vz0;                 /* terrain: release velocity up [m/s] (vx0 east, vy0 north) */
    double height0;             /* terrain: release height of the lowest point above the ground [m] */
    double azimuth0, dip0;      /* terrain: direction of speed0 [rad] (given in deg): azimuth clockwise
                                   from north, dip below the horizontal (down positive) */
    double omega0_xyz[3];       /* terrain: release spin vector [rad/s] (omega0 is the 2D spin) */
    struct rf_terrain_def *terrain;  /* a terrain file (terrain.h), NULL for a profile */
    rf_traj_release_kind release_kind;
    size_t n_release;           /* LINE: polyline vertices; ZONE polygon: its vertices (0: an x-range) */
    double *release_px, *release_py;  /* [m] */
    double zone_x0, zone_x1;    /* ZONE without polygon: the ground over [zone_x0, zone_x1] [m] */
    rf_bounce_law law;
    double scale_speed;         /* K of velocity_scaled [m/s], default RF_TRAJ_PFEIFFER_BOWEN_K */
    double contact_speed;       /* normal rebound speed below which the block stays on the ground [m/s], default 0.1 */
    double v_stop;              /* [m/s] default 0.1 */
    size_t max_steps;           /* events per trajectory, default 10000 */
    size_t n_collectors;
    rf_traj_collector *collectors;
    size_t samples;             /* Monte Carlo samples, default 1 */
    uint64_t seed;
    int lhs;                    /* Latin hypercube sampling of the random inputs */
    size_t record;              /* trajectories kept with their events (default min(samples, 200)) */
    size_t n_random;
    rf_traj_random *random;
    rf_traj_outputs outputs;
    /* impact_model law: settings of the tabulation (traj_impact_table.c) */
    char impact_solver[16];     /* "rigid" | "hunter" | "hertz" | "fem" */
    double impact_tolerance;    /* target interpolation error of R_n, R_t [-], default 0.01 */
    double impact_friction;     /* Coulomb coefficient inside the impact model; NaN = tan(friction_angle) of material 0 */
    double impact_refinement;   /* FE solver: a/h in the fine zone, 0 = the solver's default */
    double impact_speed_min, impact_speed_max; /* normal speeds tabulated [m/s], default 0.25 .. 40 */
    double impact_max_incidence;  /* largest incidence tabulated [rad] from the normal (given in deg), default 80 deg */
    char *impact_cache;         /* file of impacts already computed (read, then appended), or NULL */
    size_t impact_start_nodes;  /* nodes per axis (v_n, incidence) of a table's first grid, default 5 */
    size_t impact_surrogate_nodes; /* nodes per bound impact input of the surrogate's first grid, default 3 */
    /* A rigid convex block (block.shape ellipsoid, box, polyhedron, eota_cube,
     * eota_wheel; block.h, docs/block-shape.md "Wiring"): run by the rigid-body
     * dynamics (block_traj*.c) instead of the point/sphere engines. */
    int block_kind;             /* rf_traj_block_kind; RF_TRAJ_BLOCK_NONE: point or sphere (`sphere`) */
    double block_dims[3];       /* ellipsoid: semi-axes a, b, c; box: edges lx, ly, lz [m] */
    size_t block_n_points;      /* polyhedron: its points (3 per point) in block_points [m] */
    double *block_points;
    double block_volume;        /* [m^3] scale to it (NaN: as given; required by eota_*) */
    double block_ratio_b, block_ratio_c;  /* axis_ratios [1, b/a, c/a] at constant volume (1: none) */
    int block_random_orientation;  /* orientation: random (drawn per trajectory) */
    double block_q0[4];         /* initial orientation (w, x, y, z) of the block as given, body to space */
    int block_spin_given;       /* spin given: block_spin0, else release.omega (2D) / release.spin (terrain) */
    double block_spin0[3];      /* [rad/s] initial angular velocity in space */
    double block_time_step;     /* [s] the rigid-body time step */
    double block_max_time;      /* [s] a block still moving then ends as step_limit */
    double block_rest_time;     /* [s] at rest when the kinetic energy stays below m v_stop^2 / 2 that long */
} rf_traj_spec;

/* The shape of a rigid block (spec->block_kind). */
typedef enum { RF_TRAJ_BLOCK_NONE = 0, RF_TRAJ_BLOCK_ELLIPSOID, RF_TRAJ_BLOCK_BOX, RF_TRAJ_BLOCK_POLYHEDRON,
               RF_TRAJ_BLOCK_EOTA_CUBE, RF_TRAJ_BLOCK_EOTA_WHEEL } rf_traj_block_kind;

void rf_traj_spec_free(rf_traj_spec *spec);
/* Deep copy (for binding values without touching the original). */
rf_status rf_traj_spec_copy(const rf_traj_spec *src, rf_traj_spec *dst, rf_error *err);

/* Load a trajectory file (docs/trajectories.md); errors name file:line: field = value. */
rf_status rf_traj_load(const char *path, rf_traj_spec *spec, rf_error *err);
rf_status rf_traj_load_buffer(const char *name, const char *buf, size_t len, rf_traj_spec *spec, rf_error *err);
/* Read "x,y[,material]" lines (a header line is allowed) into the spec's profile. */
rf_status rf_traj_profile_read_csv(const char *path, rf_traj_spec *spec, rf_error *err);

/* Address of a numeric input by path: a row of the input tables below
 * (gravity, block.mass, release.vx, materials.NAME.R_n, collectors.NAME.x,
 * ...), profile.points.I.x|y, and for a random input P: P.lo / P.hi
 * (uniform), P.mean / P.sd (normal).  NULL if unknown.  The value there is as
 * stored: an angle in RADIANS; rf_traj_spec_set / _get take it as given. */
double *rf_traj_spec_field(rf_traj_spec *spec, const char *path);

/* ---- the trajectory inputs: one table per family (traj_fields.c) ----
 * Every numeric input of a trajectory file is one row: its key, place, unit
 * as given, default, check, whether it may be random or bound, and a help
 * line.  The file reader, the defaults, the validation messages, the paths a
 * study may bind (with its did-you-mean message), the model identity and the
 * key table of docs/trajectories.md come from these rows.  A row marked
 * `degrees` is given (file, binding, messages) in degrees and stored in
 * radians. */
typedef enum { RF_TRAJ_OWNER_SPEC = 0, RF_TRAJ_OWNER_MATERIAL, RF_TRAJ_OWNER_COLLECTOR } rf_traj_field_owner;
typedef enum {
    RF_TRAJ_CHECK_NONE = 0, RF_TRAJ_CHECK_FINITE, RF_TRAJ_CHECK_POSITIVE, RF_TRAJ_CHECK_NONNEGATIVE,
    RF_TRAJ_CHECK_UNIT,         /* in [0, 1] */
    RF_TRAJ_CHECK_ANGLE_90,     /* in [0, 90) deg */
    RF_TRAJ_CHECK_ANGLE_45,     /* in [0, 45] deg */
    RF_TRAJ_CHECK_ANGLE_180,    /* in [-180, 180] deg */
    RF_TRAJ_CHECK_HEIGHT        /* finite, |y| <= RF_TRAJ_MAX_COORD */
} rf_traj_check;
/* When a row is used (and checked): always, for a point block, a sphere, a
 * release given by vx/vy, by speed/angle, or at a point. */
typedef enum { RF_TRAJ_WHEN_ALWAYS = 0, RF_TRAJ_WHEN_POINT, RF_TRAJ_WHEN_SPHERE, RF_TRAJ_WHEN_VXVY,
               RF_TRAJ_WHEN_SPEED, RF_TRAJ_WHEN_AT_POINT,
               RF_TRAJ_WHEN_PROFILE,        /* a profile file (not terrain) */
               RF_TRAJ_WHEN_PROFILE_SPEED,  /* a profile file, release by speed and angle */
               RF_TRAJ_WHEN_TERRAIN,        /* a terrain file */
               RF_TRAJ_WHEN_TERRAIN_VXVY,   /* a terrain file, release by vx, vy, vz */
               RF_TRAJ_WHEN_TERRAIN_SPEED,  /* a terrain file, release by speed, azimuth, dip */
               RF_TRAJ_WHEN_BLOCK,          /* a rigid block (block_kind: ellipsoid, box, polyhedron, eota_*) */
               RF_TRAJ_WHEN_RIGID           /* a sphere or a rigid block (density) */
} rf_traj_when;
typedef struct {
    const char *key;            /* path below its table's prefix: "mass", "R_n", "bounce.scale_speed" */
    size_t offset;              /* in rf_traj_spec, rf_traj_material or rf_traj_collector (owner) */
    int degrees;                /* given in degrees, stored in radians */
    const char *unit;           /* as given ("deg" for angles; "" dimensionless) */
    double def;                 /* default; NaN: required (or from elsewhere, see help) */
    double probe;               /* an admissible value other than the default, as given (the tests) */
    rf_traj_check check;
    rf_traj_when when;
    int random;                 /* may be written {uniform: ..} / {normal: ..} */
    int bindable;               /* a study may bind a fuzzy parameter to it */
    const char *help;
} rf_traj_field;
typedef struct {
    const char *family;         /* "block", "release", "material", "run", "collector" */
    const char *prefix;         /* of the paths: "block.", "release.", "materials.NAME.", "", "collectors.NAME." */
    rf_traj_field_owner owner;
    const rf_traj_field *rows;
    size_t n_rows;
} rf_traj_field_table;
extern const rf_traj_field_table rf_traj_field_tables[];
extern const size_t rf_traj_n_field_tables;

/* The run settings that are not numbers a study binds or draws (traj_fields.c,
 * rf_traj_settings): counts with their exact range, names from a list, a
 * pair, a path, and the few numbers of the impact table.  One row each: its
 * full path, its member of rf_traj_spec, its kind, range or names, default, a
 * probe value as written in a file (the tests) and a help line.  The reader
 * checks each value at load (file:line: path = value: reason), and the
 * defaults, the model identity and the key table of docs/trajectories.md loop
 * over the rows. */
typedef enum {
    RF_TRAJ_SETTING_COUNT = 0,  /* an integer in [count_min, count_max]: a size_t or uint64_t (size) */
    RF_TRAJ_SETTING_NAME,       /* one of names(k), stored as its index k in an int (an enum) */
    RF_TRAJ_SETTING_WORD,       /* one of names(k), stored as the name in a char[size] */
    RF_TRAJ_SETTING_NUMBER,     /* a double in [lo, hi] (ends excluded: lo_open, hi_open; hi inf: finite) */
    RF_TRAJ_SETTING_PAIR,       /* [a, b] with lo < a < b: two doubles, at offset and offset + sizeof(double) */
    RF_TRAJ_SETTING_PATH        /* a file, relative to the trajectory file's folder: a char * (NULL: none) */
} rf_traj_setting_kind;
typedef struct {
    const char *key;            /* full path: "samples", "stop.max_steps", "bounce.impact.speeds" */
    rf_traj_setting_kind kind;
    size_t offset, size;        /* the member of rf_traj_spec and its size */
    const char *unit;           /* as given ("deg" for an angle; "" dimensionless) */
    long long count_min, count_max, count_def;  /* COUNT */
    const char *(*names)(size_t k);  /* NAME, WORD: the k-th allowed name, NULL past the last */
    const char *def_name;       /* NAME, WORD: the default */
    int degrees;                /* NUMBER: given in degrees, stored in radians */
    double lo, hi;              /* NUMBER: the range as given; PAIR: lo bounds a from below */
    int lo_open, hi_open;       /* NUMBER: an end excluded */
    double def, def2;           /* NUMBER (NaN: unset, see help), PAIR: the defaults as given */
    const char *note;           /* the rule's remark (NUMBER, NAME: "(note)"; PAIR: what the pair is) */
    const char *def_text;       /* the docs' default when it is no value ("min(samples, 200)") */
    const char *probe;          /* an admissible value other than the default, as written in a file */
    const char *help;
} rf_traj_setting;
extern const rf_traj_setting rf_traj_settings[];
extern const size_t rf_traj_n_settings;
/* The setting at a full path, or NULL. */
const rf_traj_setting *rf_traj_setting_named(const char *path);
/* The rule of a setting as text ("must lie in (0, 1)", "expected random or
 * lhs (Latin hypercube)", "an integer in [1, 100000000]") into buf. */
void rf_traj_setting_rule(const rf_traj_setting *g, char *buf, size_t size);

/* The row of a path and where it is stored (NULL if the path is no row, e.g.
 * a random input's lo/hi or a profile point). */
const rf_traj_field *rf_traj_field_at(rf_traj_spec *spec, const char *path, double **place);
/* Set / get an input by path in the units it is given in (degrees for
 * angles): rows, random parameters (P.lo|hi|mean|sd, as given), profile
 * points.  0 if the path is unknown. */
int rf_traj_spec_set(rf_traj_spec *spec, const char *path, double given);
int rf_traj_spec_get(const rf_traj_spec *spec, const char *path, double *given);
/* The check of a row on a value as given: NULL if admissible, else the rule
 * ("must lie in [0, 1]"). */
const char *rf_traj_field_rule(const rf_traj_field *f, double given);
/* Whether a study may bind `path` of this spec; if not, *why says why (with
 * the nearest bindable path when one is close: a typo). */
int rf_traj_path_bindable(const rf_traj_spec *spec, const char *path, char *why, size_t size);
/* The bindable paths of this spec, comma-separated, with their units. */
void rf_traj_bindable_list(const rf_traj_spec *spec, char *buf, size_t size);
/* The key table of docs/trajectories.md (markdown rows), from the tables. */
void rf_traj_fields_markdown(FILE *f);
/* FNV-1a over every row of every table (each material and collector), the
 * random inputs, the release geometry, the outputs asked for and every
 * setting (rf_traj_settings: counts, law, sampling, bounce.impact): the
 * values a run reads. */
uint64_t rf_traj_spec_values_hash(const rf_traj_spec *spec);

/* The bounce laws: a registry of {name, parameters, validate, apply}
 * (bounce.c); the names come from it. */
const char *rf_traj_bounce_law_parameters(rf_bounce_law law);

/* Material and collector names: 1 to RF_TRAJ_NAME_MAX letters, digits, '_'
 * or '-', because a name becomes part of output names, CSV fields, file names
 * (trajectory_hist_NAME.png) and binding paths (collectors.NAME.x); nothing
 * else can then break a CSV row, a page or a path. */
#define RF_TRAJ_NAME_MAX 64
#define RF_TRAJ_NAME_RULE "a name holds 1 to 64 letters, digits, '_' or '-' (it becomes part of output " \
                          "names, file names and binding paths)"
int rf_traj_name_valid(const char *name);

/* Check the spec (profile sorted and not self-intersecting, materials,
 * release above the ground, ...); the message names the field and value. */
rf_status rf_traj_spec_validate(const rf_traj_spec *spec, rf_error *err);

/* The impact_model law: each material whose impact model has a soil layer
 * (solver fem, layer_thickness > 0) and whose rolling_resistance the file
 * does not give gets the rolling resistance derived from the layer's
 * mechanics for the sphere's nominal radius and density (src/trajectory/
 * traj_rolling*.c, docs/soil-impacts.md "Rolling resistance from the
 * layer": an FE indentation per material, a few seconds); a value given in
 * the file (or bound by a study) wins.  Says each material's value and its
 * source on log (may be NULL).  Other laws and specs: nothing changes. */
rf_status rf_traj_rolling_resolve(rf_traj_spec *spec, FILE *log, rf_error *err);

/* ---- one trajectory ---- */

typedef enum { RF_TRAJ_STOPPED = 0, RF_TRAJ_EXITED, RF_TRAJ_STEP_LIMIT } rf_traj_state;
const char *rf_traj_state_name(rf_traj_state s);

typedef struct {
    double t, x, y;
    size_t segment;
    double vx_in, vy_in, vx_out, vy_out, omega_out;
    /* A rigid block (spec->block_kind): x, y are its lowest point, the
     * velocities its centre's; its orientation and rotational energy about
     * each body axis after the impact (else q = 0). */
    double q[4];                /* (w, x, y, z), body to space (the profile's x-y is the block's x-z) */
    double rot_energy[3];       /* [J] */
} rf_traj_impact;

/* Event kinds along a recorded trajectory (the motion between two events is
 * a parabola (flight) or uniformly accelerated along a segment (contact)). */
typedef enum { RF_EV_RELEASE = 0, RF_EV_IMPACT, RF_EV_LAUNCH, RF_EV_CONTACT, RF_EV_VERTEX, RF_EV_REST,
               RF_EV_EXIT, RF_EV_STEP_LIMIT,
               RF_EV_BARRIER    /* terrain: a barrier broken through slowed the block here */
} rf_traj_event_kind;

typedef struct {
    rf_traj_event_kind kind;
    int flying;                 /* the motion after this event is a flight */
    double t, x, y, vx, vy, omega;  /* state after the event */
    double ax, ay;              /* acceleration after the event [m/s^2] */
    double q[4];                /* a rigid block: its orientation (w, x, y, z); else 0 */
} rf_traj_event;

typedef struct {
    int reached;                /* crossed the collector line (first crossing recorded) */
    int stopped_by_barrier;
    double t;                   /* [s] */
    double height_lowest;       /* [m] the block's lowest point (the simulated point) above the ground, vertically */
    double height_centre;       /* [m] its centre: height_lowest + radius (sphere), height_lowest (point) */
    double normal_height;       /* [m] the simulated point's distance from the ground segment, along its normal */
    double speed;               /* [m/s] */
    double translational_energy, rotational_energy;  /* [J] m v^2 / 2, I omega^2 / 2 */
    double total_energy;        /* [J] translational_energy + rotational_energy */
    double x, y;                /* [m] where it crossed: on terrain the map point (2D: x, and the block's y) */
    double along;               /* [m] terrain: distance along the barrier line from its first vertex (2D: 0) */
    double energy_after;        /* [J] terrain: a barrier passed, the energy left (total_energy - capacity when
                                   it broke through; total_energy when it flew over; 2D: total_energy) */
} rf_traj_crossing;

typedef struct {
    rf_traj_state state;
    double t_end, x_end, y_end;    /* rest point, exit state or last state */
    double runout_x;               /* x of the rest point (stopped), else of the last state */
    double rebound_height;         /* largest apex of a flight starting at an impact, above that impact [m] */
    size_t n_impacts, n_steps;
    rf_traj_crossing *crossings;   /* n_collectors, caller-sized */
    /* Optional records (NULL = not recorded): */
    rf_traj_impact *impacts; size_t impacts_cap;
    rf_traj_event *events; size_t n_events, events_cap;
} rf_traj_result;

/* A prepared profile (segment geometry, collector grounds); read-only while
 * trajectories run, so any number of threads may share it. */
typedef struct rf_traj_world rf_traj_world;
rf_status rf_traj_world_create(const rf_traj_spec *spec, rf_traj_world **world, rf_error *err);
void rf_traj_world_free(rf_traj_world *world);

/* One trajectory with the spec's crisp values; roughness draws come from the
 * counter-based stream (seed, sample).  res->crossings must hold
 * n_collectors entries; impacts/events are filled if their arrays are set
 * (growing with realloc). */
rf_status rf_traj_simulate(const rf_traj_world *world, const rf_traj_spec *values, uint64_t seed,
                           uint64_t sample, rf_traj_result *res, rf_error *err);

/* ---- Monte Carlo ensembles ---- */

/* Percentiles of a sample: the fixed p50, p95, p99, and value[k] at the
 * chosen level[k] [%] (the spec's outputs.percentiles), max and mean. */
typedef struct {
    double p50, p95, p99, max, mean;
    size_t n;
    double level[RF_TRAJ_MAX_PERCENTILES];
    double value[RF_TRAJ_MAX_PERCENTILES];
} rf_traj_percentiles;

/* Envelopes along x (envelope.c), from ALL trajectories of a run: at the
 * edges x_k = x_first + k (x_last - x_first) / (n_edges - 1) of the profile,
 * each trajectory's state at its first passage of x_k, solved exactly for the
 * crossing time (a flight is a parabola, a contact stretch uniformly
 * accelerated).  A trajectory whose path never reaches x_k does not count
 * there; reached[k] says how many do.  p50 and p95 (Hyndman-Fan type 7 over
 * the trajectories reaching x_k) come from a streaming log histogram: each is
 * within RF_TRAJ_ENVELOPE_ACCURACY relative (or the floor below) of the exact
 * percentile; the max is exact.  NaN where no trajectory reaches x_k. */
#define RF_TRAJ_ENVELOPE_EDGES 161
#define RF_TRAJ_ENVELOPE_ACCURACY 0.005     /* relative, of p50 and p95 */
#define RF_TRAJ_ENVELOPE_HEIGHT_FLOOR 1e-4  /* [m] heights below it count as 0 in p50/p95 */
#define RF_TRAJ_ENVELOPE_ENERGY_FLOOR 1e-2  /* [J] energies below it count as 0 in p50/p95 */
typedef struct {
    size_t n_edges;
    double *x;                  /* [m] edges x_k */
    size_t *reached;            /* trajectories whose path reaches x_k */
    double *height[3];          /* p50, p95, max [m]: y of the block's point minus the ground's y at x_k */
    double *energy[3];          /* p50, p95, max [J]: translational + rotational kinetic energy */
} rf_traj_envelope;

typedef struct {
    size_t samples;
    size_t n_collectors;
    /* Per sample (index = sample number): */
    unsigned char *state;          /* rf_traj_state */
    double *runout_x, *rebound_height;
    rf_traj_crossing *crossings;   /* samples * n_collectors, sample-major */
    /* The first `record` trajectories with their impacts and events: */
    size_t n_recorded;
    rf_traj_result *recorded;
    double wall_seconds;
    /* impact_model law: the table built for this run */
    size_t impact_nodes_vn, impact_nodes_theta, impact_evaluations, impact_from_cache;
    double impact_error_estimate;   /* largest |table - model| of R_n, R_t at the cell centres [-] */
    rf_traj_envelope envelope;      /* from all samples */
    struct rf_terrain_samples *terrain;  /* a terrain run (terrain.h), NULL for a profile */
    const struct rf_terrain *terrain_dem;       /* a terrain run: its surface, for the outputs (CRS, grid, maps) */
    struct rf_terrain_world *terrain_world;     /* rf_terrain_run: its world, owned (freed with the ensemble);
                                                   NULL when a caller's world ran (terrain_run_world) */
} rf_traj_ensemble;

/* Run spec->samples trajectories on `threads` threads (0 = online cores).
 * Results do not depend on the thread count: sample k uses only its own
 * counter-based random stream. */
rf_status rf_traj_run(const rf_traj_spec *spec, int threads, rf_traj_ensemble *ens, rf_error *err);
/* rf_traj_run calling progress(ctx, done, samples) on the calling thread
 * after each sample it runs itself (done counts the samples of every thread):
 * a progress line (src/cli/progress.c). */
typedef void (*rf_traj_progress_fn)(void *ctx, size_t done, size_t samples);
rf_status rf_traj_run_progress(const rf_traj_spec *spec, int threads, rf_traj_progress_fn progress, void *ctx,
                               rf_traj_ensemble *ens, rf_error *err);
void rf_traj_ensemble_free(rf_traj_ensemble *ens);

/* Percentiles (linear interpolation between order statistics, Hyndman-Fan
 * type 7) of the finite values among v[0..n-1] (v is not modified); NaN if
 * none.  _of: at the levels 50, 95, 99; _at: at levels[0..n_levels-1] [%]. */
rf_traj_percentiles rf_traj_percentiles_of(const double *v, size_t n);
rf_traj_percentiles rf_traj_percentiles_at(const double *v, size_t n, const double *levels, size_t n_levels);
/* The name of a percentile level: "p50", "p99_9" (a '.' becomes '_'). */
void rf_traj_percentile_name(double level, char *buf, size_t size);

/* Counts of a sample in `bins` equal bins over [lo, hi] = [min, max] of its
 * finite values: bin k holds edge[k] <= v < edge[k + 1], the last one also
 * v = hi (all values equal: one bin). */
typedef struct {
    size_t bins, total;
    double edge[RF_TRAJ_MAX_BINS + 1];
    size_t count[RF_TRAJ_MAX_BINS];
} rf_traj_histogram;
void rf_traj_histogram_of(const double *v, size_t n, size_t bins, rf_traj_histogram *h);
/* The histogram of the end points runout_x of every sample. */
void rf_traj_runout_histogram(const rf_traj_ensemble *ens, size_t bins, rf_traj_histogram *h);

/* Per collector: percentiles over the samples that reach it; exceedance
 * probabilities over ALL samples (a block that does not reach the line does
 * not exceed), at the collector's thresholds. */
/* The exceedance thresholds of a collector: energy (height 0) [J] or height
 * (height 1) [m]: the barrier's own value when > 0 (*own = 1), then the
 * user's; returns how many were written to t[RF_TRAJ_MAX_THRESHOLDS]. */
size_t rf_traj_thresholds(const rf_traj_collector *c, int height, double *t, int *own);

typedef struct {
    double reach_probability;
    rf_traj_percentiles total_energy, translational_energy, rotational_energy;  /* [J] */
    rf_traj_percentiles height_lowest, height_centre;   /* [m] */
    rf_traj_percentiles speed;                          /* [m/s] */
    double p_energy_above[RF_TRAJ_MAX_THRESHOLDS];      /* P(total_energy > rf_traj_thresholds(.., 0, ..)[k]) */
    double p_height_above[RF_TRAJ_MAX_THRESHOLDS];      /* P(height_lowest > rf_traj_thresholds(.., 1, ..)[k]) */
} rf_traj_collector_stats;

typedef struct {
    size_t samples, stopped, exited, step_limit;
    rf_traj_percentiles runout_x, rebound_height;       /* [m], over all samples */
    rf_traj_percentiles reach_angle;                    /* [rad] a terrain run: the reach angle over the samples
                                                           with a runout (terrain.h); a profile: NaN */
    double p_runout_above[RF_TRAJ_MAX_THRESHOLDS];      /* P(runout_x > outputs.runout_thresholds[k]) */
    rf_traj_histogram runout_histogram;
    size_t n_collectors;
    rf_traj_collector_stats *collectors;                /* n_collectors */
} rf_traj_stats;

/* Statistics with the spec's outputs (percentiles, thresholds, bins); spec
 * NULL: the defaults (p50, p95, p99, 20 bins, no thresholds). */
rf_status rf_traj_stats_compute_spec(const rf_traj_spec *spec, const rf_traj_ensemble *ens, rf_traj_stats *st,
                                     rf_error *err);
rf_status rf_traj_stats_compute(const rf_traj_ensemble *ens, rf_traj_stats *st, rf_error *err);
void rf_traj_stats_free(rf_traj_stats *st);

/* ---- counter-based random numbers (rng.c) ---- */

/* Uniform in (0, 1): a pure function of (seed, stream, index) (SplitMix64
 * finaliser over a Weyl sequence), so any thread or rank computes the same
 * number for the same triple. */
double rf_traj_uniform(uint64_t seed, uint64_t stream, uint64_t index);
/* Standard normal quantile (Wichura 1988, AS 241, ~1e-16 relative). */
double rf_traj_normal_quantile(double p);

/* ---- outputs (traj_output.c) ---- */

/* The JSON document of `rockfuzz trajectory --json` (docs/trajectories.md):
 * samples, the recorded trajectories (at most max_trajectories), statistics. */
void rf_traj_write_json(FILE *f, const rf_traj_spec *spec, const rf_traj_ensemble *ens, const rf_traj_stats *st,
                        size_t max_trajectories);
/* traj_json_file.c: that document (a terrain run's, rf_terrain_write_json,
 * when spec->terrain) into the file at path, written as path.tmp and renamed
 * into place only when every byte was written and closed: a failed write
 * (full disk, file size limit) or close is an error naming the file and the
 * cause, path.tmp is removed and a previous file at path stays as it was. */
rf_status rf_traj_write_json_file(const char *path, const rf_traj_spec *spec, const rf_traj_ensemble *ens,
                                  const rf_traj_stats *st, size_t max_trajectories, rf_error *err);
/* A readable summary (states, runout, per collector reach/energy/height). */
void rf_traj_write_summary(FILE *f, const rf_traj_spec *spec, const rf_traj_ensemble *ens, const rf_traj_stats *st);
/* traj_csv.c: DIR/trajectories.csv (recorded paths: every event and 15
 * points inside each stretch), samples.csv (every sample's state, runout_x,
 * rebound height), crossings.csv (every sample's collector crossings),
 * statistics.csv (percentiles per quantity), exceedance.csv (P(quantity >
 * threshold)), runout_histogram.csv, envelopes.csv (per edge x_k,
 * envelope.c).  Every header names its unit. */
rf_status rf_traj_write_csv(const char *dir, const rf_traj_spec *spec, const rf_traj_ensemble *ens,
                            const rf_traj_stats *st, rf_error *err);
/* traj_plot.c: DIR/trajectory_profile.{png,svg} (profile, recorded paths,
 * envelopes of height and energy along x), DIR/trajectory_hist_NAME.{png,svg}
 * per collector, and DIR/report.html showing them with the statistics. */
rf_status rf_traj_write_plots(const char *dir, const rf_traj_spec *spec, const rf_traj_ensemble *ens,
                              const rf_traj_stats *st, rf_error *err);
/* Position and velocity at time t of the recorded trajectory res (events
 * interpolated exactly); 0 if t lies outside it. */
int rf_traj_state_at(const rf_traj_result *res, double t, double *x, double *y, double *vx, double *vy);

/* ---- the study model (traj_model.c) ---- */

/* Output names (pXX: each of the spec's outputs.percentiles, then max; see
 * rf_traj_percentile_name), per collector C: C_total_energy_pXX [J],
 * C_height_lowest_pXX, C_height_centre_pXX [m], C_speed_pXX [m/s],
 * C_reach_probability, C_p_total_energy_above_capacity (barrier) and
 * C_p_total_energy_above_<E>J, C_p_height_lowest_above_barrier and
 * C_p_height_lowest_above_<h>m [-]; then runout_x_pXX, rebound_height_pXX [m],
 * p_runout_x_above_<x>m [-] ('.' in a number becomes '_').  A terrain file
 * (spec->terrain): the collector outputs per barrier, then runout_pXX [m],
 * reach_angle_pXX [deg], rebound_height_pXX [m], p_runout_above_<x>m [-]
 * (the terrain Monte Carlo, no rasters: fuzzy hazard rasters are not model
 * outputs).  param_names[i] is
 * bound to the spec path bind_paths[i].  Every evaluation uses the same seed:
 * common random numbers across the TM's points. */
rf_status rf_traj_model_create(const rf_traj_spec *spec, size_t n_params, const char *const *param_names,
                               const char *const *bind_paths, rf_model *model, rf_error *err);
/* The ranges [lo[i], hi[i]] (as given: angles in degrees) the bound inputs of
 * a trajectory model take (a study: its parameters' supports).  With them,
 * bound inputs of a material's impact model (materials.NAME.impact.X) are
 * evaluated on a surrogate of the impact model over that box, built once in
 * the run (docs/soil-surrogate.md); without them each evaluation builds its
 * own impact table. */
rf_status rf_traj_model_set_ranges(rf_model *m, const double *lo, const double *hi, rf_error *err);

/* The Monte Carlo of a trajectory model (rf_traj_model_create) at the point x
 * of its parameters, written to the existing folder dir as `rockfuzz
 * trajectory --out` writes a run (result.json, CSV files, and with plots the
 * figures and report.html); 100 trajectories recorded (traj_run_at.c). */
rf_status rf_traj_model_write_run(const rf_model *m, const double *x, const char *dir, int threads, int plots,
                                  rf_error *err);

/* Figures of several runs drawn on the same axes (a fuzzy trajectory study's
 * nominal and bound reruns): the upper ends of the envelope axes and of the
 * end-point count axis, and per collector (the first RF_TRAJ_SCALE_COLLECTORS)
 * the ranges of its energy and height histograms.  A zero range or upper
 * end: the run's own.  rf_traj_plot_scales_add widens sc to cover a run. */
#define RF_TRAJ_SCALE_COLLECTORS 16
typedef struct {
    size_t runs;                     /* runs added (start from a zeroed struct) */
    double height_max, energy_max;   /* [m], [J]: envelope panels */
    double runout_count_max;         /* end points per bin */
    double energy_lo[RF_TRAJ_SCALE_COLLECTORS], energy_hi[RF_TRAJ_SCALE_COLLECTORS]; /* [J] histograms */
    double height_lo[RF_TRAJ_SCALE_COLLECTORS], height_hi[RF_TRAJ_SCALE_COLLECTORS]; /* [m] */
} rf_traj_plot_scales;

/* A trajectory model's Monte Carlo at one point x (100 trajectories recorded,
 * envelopes from all), kept to be written later (traj_run_at.c): y gets the
 * model's outputs there (n_outputs values, as an evaluation of the model
 * returns them: same seed, the same bits). */
typedef struct rf_traj_point_run rf_traj_point_run;
rf_status rf_traj_model_run_at(const rf_model *m, const double *x, int threads, double *y, rf_traj_point_run **out,
                               rf_error *err);
void rf_traj_plot_scales_add(rf_traj_plot_scales *sc, const rf_traj_point_run *r);
/* Written as rf_traj_model_write_run writes, the figures on the axes sc (NULL: their own). */
rf_status rf_traj_point_run_write(const rf_traj_point_run *r, const char *dir, int plots,
                                  const rf_traj_plot_scales *sc, rf_error *err);
void rf_traj_point_run_free(rf_traj_point_run *r);

#ifdef __cplusplus
}
#endif
#endif
