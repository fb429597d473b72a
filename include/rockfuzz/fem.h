/* fem.h - axisymmetric explicit finite-element model of the normal impact of
 * an elastic boulder (sphere or spheroid) on an elastic half-space.
 *
 * The half-space is a hemisphere of radius domain_factor * r0 centred on the
 * first-contact point; its curved surface is fixed or absorbing
 * (Lysmer-Kuhlemeyer dashpots).  By default (domain_factor = 0) the radius is
 * sized from the Hertz contact duration so that no P wave reflected by the
 * fixed surface returns into the contact before it ends:
 * 2 L / c_p >= RF_FEM_DOMAIN_MARGIN t_c, and L >= 10 r0.  Both bodies are meshed with 4-node
 * axisymmetric quads (full 2x2 integration, lumped mass) by a structured
 * mesher that puts a node exactly at the first-contact point and sizes the
 * fine zone from the Hertz contact radius.  Time integration: central
 * differences at the element eigenvalue bound; contact: forward-increment
 * Lagrange multipliers (Carpenter, Taylor & Katona 1991), node-to-segment,
 * frictionless; small sliding on the reference geometry, or, in large
 * deformation (rf_fem_options.large_deformation), on the current surfaces
 * with an updated-Lagrangian material kernel.  No artificial damping of any kind.
 * See docs/validation.md for the measured accuracy.
 *
 * Units: SI.  Thread safety: rf_fem_impact keeps all state in its own
 * allocations (or a caller's rf_fem_workspace) and may be called from several
 * threads at once; results do not depend on opt->threads (fixed-order
 * assembly). */
#ifndef ROCKFUZZ_FEM_H
#define ROCKFUZZ_FEM_H

#include <stdatomic.h>
#include <stdint.h>

#include "rockfuzz/impact.h"
#include "rockfuzz/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    RF_FEM_BOUNDARY_FIXED = 0,  /* fixed outer surface of the slope domain */
    RF_FEM_BOUNDARY_ABSORBING,  /* viscous (Lysmer-Kuhlemeyer) dashpots */
    RF_FEM_BOUNDARY_AUTO        /* default: rf_fem_boundary_resolve */
} rf_fem_boundary;

/* "fixed" | "absorbing" | "auto" <-> enum. */
const char *rf_fem_boundary_name(rf_fem_boundary b);
rf_status rf_fem_boundary_parse(const char *name, rf_fem_boundary *b, rf_error *err);

/* The boundary a run uses: b itself unless it is RF_FEM_BOUNDARY_AUTO, which
 * is absorbing when the impact has a layer or an elasto-plastic body (their
 * contact lasts many times the P wave's round trip 2 L / c_p in the automatic
 * domain, which is sized from the elastic Hertz duration: a fixed boundary
 * would reflect waves back into it), and fixed otherwise (elastic bodies on
 * the half-space: the seed paper's validated model, results unchanged).  The
 * 3D model takes the same rule; its dashpots are explicit and a run refuses
 * them where dt C / m >= 2 (docs/validation-plastic.md section 10b). */
rf_fem_boundary rf_fem_boundary_resolve(rf_fem_boundary b, const rf_impact_input *in);

/* Kinematics of the FE models (docs/validation-plastic.md sections 6e, 9c). */
typedef enum {
    RF_FEM_KINEMATICS_AUTO = 0, /* default: large deformation when a body is elasto-plastic, else small strain */
    RF_FEM_SMALL_STRAIN,        /* strains, B and weights on the reference geometry; contact pairs fixed
                                   in the reference configuration (vertical gaps, small sliding) */
    RF_FEM_LARGE_DEFORMATION    /* updated Lagrangian: every deformable body on the integration-point
                                   kernel with B, 1/r and 2 pi r det J of the current geometry, the strain
                                   increment on the mid-step geometry, the stress rotated objectively
                                   (Hughes-Winget) before the return map; contact on the current surfaces,
                                   normal gaps, pairs found again every step */
} rf_fem_kinematics;

/* ALE rezoning of the axisymmetric large-deformation slope (docs/validation-plastic.md
 * section 8b): where the updated-Lagrangian mesh has become distorted (an element's
 * stable size below half its reference size), its interior nodes are relocated by a
 * smoothing and the stresses, internal variables and velocities remapped (first-order
 * donor cell, conservative; the energy the remap changes is reported as its own term of
 * the closure).  Off by default: it changes the peak force of deep runs by a third to a
 * half, which no reference decides yet; switch it on where a run fails with a crushed
 * element.  Ignored in small strain and by the 3D model. */
typedef enum {
    RF_FEM_ALE_OFF = 0, /* default: Lagrangian */
    RF_FEM_ALE_ON
} rf_fem_ale;
/* "off" | "on" <-> enum. */
const char *rf_fem_ale_name(rf_fem_ale a);
rf_status rf_fem_ale_parse(const char *name, rf_fem_ale *a, rf_error *err);

/* How the axisymmetric model sizes the mesh of a thick soil layer (docs/soil-impacts.md
 * sections 2 and 4).  hertz (default): from the finer of the rock's and the layer's elastic
 * Hertz contact radii, as every other impact; soil: from the layer's own contact estimate
 * (the 3D model's f3_layer_contact_estimate: a/h across the soil contact, the uniform zone
 * over it), the sizing an impact table of a soil layer takes.  Only a thick layer (the
 * estimated depth <= t/2, contact radius <= t) is sized by it; the 3D model always sizes a
 * thick layer from its contact estimate. */
typedef enum {
    RF_FEM_SIZING_HERTZ = 0,
    RF_FEM_SIZING_SOIL
} rf_fem_sizing;

/* 3D model with gravity: how the ground is inclined under an impact at slope angle
 * theta (the incidence from the normal).  incidence: at theta (the boulder falls
 * vertically onto a slope of theta).  stable: at theta, but at most the steepest
 * angle at which every elasto-plastic body (a layer at its base, the slope at the
 * model's depth) stands with an infinite-slope factor of safety of
 * RF_FEM_GROUND_SAFETY; steeper, the ground stays at that angle and the boulder
 * comes at theta from its normal (gravity then not vertical in the impact's plane).
 * The impact tables' setting for a soil layer: a layer that cannot stand at a
 * grazing incidence still has an impact there (docs/soil-impacts.md section 4b). */
typedef enum {
    RF_FEM_GROUND_INCIDENCE = 0,
    RF_FEM_GROUND_STABLE
} rf_fem_ground;

#define RF_FEM_GROUND_SAFETY 1.25

/* "auto" | "off" | "on" <-> enum. */
const char *rf_fem_kinematics_name(rf_fem_kinematics k);
rf_status rf_fem_kinematics_parse(const char *name, rf_fem_kinematics *k, rf_error *err);

/* Refinement (a/h) used when the options leave it at 0: the axisymmetric
 * model is converged to < 0.1 % at 10; the 3D one costs ~50x more per a/h and
 * at 3 is within 1.7e-4 / 4.8e-4 / 9.8e-5 of the converged R_n / R_t / R_ke of
 * the 10 m/s, 45 degree, f = 0.6 impact (below 3 its mesh family is not
 * reliable; docs/fem-speed.md section 5, docs/validation*.md). */
#define RF_FEM_REFINEMENT_AXI 10.0
#define RF_FEM_REFINEMENT_3D 3.0
/* Automatic domain: 2 L / c_p >= RF_FEM_DOMAIN_MARGIN * Hertz t_c, L >= RF_FEM_DOMAIN_MIN r0. */
#define RF_FEM_DOMAIN_MARGIN 1.25
#define RF_FEM_DOMAIN_MIN 10.0

/* The numerical settings that no user chooses (mesh grading, time-step safety, material
 * kernels, the second methods the validation compares against, ...): src/fem/fem_tuning.h,
 * for the tests and benchmarks only. */
typedef struct rf_fem_tuning rf_fem_tuning;

/* The default step budget of one FE run (rf_fem_options.max_steps): a run at
 * the finest admissible refinement takes a few 10^5 steps. */
#define RF_FEM_DEFAULT_MAX_STEPS 1e6
/* A run estimated to take longer than this [s] says so (rf_fem_options.say). */
#define RF_FEM_SAY_SECONDS 30.0

/* The options a user chooses.  Every member up to threads is a row of
 * rf_fem_option_fields (name, unit, default, range, help); see there. */

typedef struct {
    double refinement;                   /* elements across the Hertz contact radius a (a/h); 0 = automatic */
    double domain_factor;                /* hemisphere radius / r0; 0 = automatic (see above) */
    rf_fem_boundary boundary;            /* outer curved surface of the half-space (rf_fem_boundary_resolve) */
    rf_fem_kinematics large_deformation; /* see rf_fem_kinematics; in the 3D model `on` puts every deformable
                                            body on the updated-Lagrangian hexahedron kernel, auto the
                                            elasto-plastic ones, an elastic one keeps its small-strain kernel */
    rf_fem_ale ale;                      /* axisymmetric large deformation: ALE rezoning of the slope */
    double end_time;                     /* [s]; 0 = automatic: >= 1.3 Hertz durations and until the
                                            contact has stayed open for 0.1 of one while the boulder
                                            moves away; past 3 durations up to a bound scaled by the
                                            contact's progress (with gravity: 100 durations; the block
                                            may come to rest, R_n = 0), where the run fails (RF_EMODEL) */
    rf_fem_sizing mesh_sizing;           /* axisymmetric, a thick layer: hertz (default) or soil (see above) */
    double rock_mass_scale;              /* a layer's bedrock: its inertia (mass density in the mass matrix and the
                                            dashpots, not its weight) times this, >= 1; 1 (default) = the rock
                                            itself.  > 1 lengthens the explicit step the rock sets under a soft
                                            layer, up to the bound of the layer's contact face
                                            (docs/soil-impacts.md section 3) */
    rf_fem_ground ground;                /* 3D, gravity: the ground's inclination, incidence (default) or stable */
    int threads;                         /* OpenMP threads for one impact (0 = 1); results do not depend on it */
    /* --- not model settings (neither in the table nor in a model's identity) --- */
    const char *vtk_dir;       /* NULL = none; else write fem.pvd + fem_NNNN.vtu (an existing dir:
                                  the CLI's --vtk creates it) */
    /* NULL (default) or called after every time step with the simulated time t [s] and the
       expected end t_end [s] of the run: end_time when given, else an estimate from the
       contact's progress (fem_core.c) that is revised as the impact goes on; for a progress
       line (rockfuzz impact).  No result depends on it. */
    void (*progress)(void *ctx, double t, double t_end);
    void *progress_ctx;
    /* The step budget (fem_driver.c): a run whose estimated step count (its
       least simulated time / the time step, known after assembly) exceeds it
       is refused before it runs, naming the count and the time it would take,
       and no run takes more steps; 0 = RF_FEM_DEFAULT_MAX_STEPS, < 0 = none. */
    double max_steps;
    /* NULL or called once when a run will take long (over RF_FEM_SAY_SECONDS by
       the time its first steps took): one line saying the steps and the time. */
    void (*say)(void *ctx, const char *text);
    void *say_ctx;
    /* NULL or a flag: non-zero stops the run between two steps (RF_EINTERRUPTED). */
    const atomic_int *interrupt;
    const rf_fem_tuning *tuning; /* NULL (default): the validated numerics; tests and benchmarks only */
} rf_fem_options;

/* The one table of the public FE options: the options and usage of `rockfuzz
 * impact` (--name, '-' for '_'), the keys of a study's model.impact block, the
 * defaults, the validation and the impact model's identity all loop over it. */
typedef enum {
    RF_FEM_OPTION_REAL = 0, /* a double */
    RF_FEM_OPTION_COUNT,    /* an int */
    RF_FEM_OPTION_CHOICE    /* an enum, named by the row's choices (indexed by its value) */
} rf_fem_option_kind;

typedef struct {
    const char *name;           /* member of rf_fem_options, study key, CLI option */
    size_t offset;              /* of the member in rf_fem_options */
    rf_fem_option_kind kind;
    const char *unit;           /* SI unit of a REAL row, "" for a ratio or count */
    const char *value_name;     /* the value's placeholder in the usage */
    double def;                 /* default (a CHOICE: its enum value) */
    double lo, hi, lo3, hi3;    /* closed range of a REAL or COUNT, axisymmetric and 3D model */
    int zero_auto;              /* 1: 0 means automatic and lies outside the range */
    const char *const *choices; /* a CHOICE's names, NULL-terminated */
    const char *help;           /* one paragraph: what it does, its default */
} rf_fem_option_field;

extern const rf_fem_option_field rf_fem_option_fields[];
extern const size_t rf_fem_n_option_fields;

/* The row named name, or NULL. */
const rf_fem_option_field *rf_fem_option_find(const char *name);
/* Stores text (a number, or a choice's name) in f's member of o and checks it
 * against the row (axisymmetric limits; a 3D run checks its own); on failure o
 * is unchanged and err names the option and value. */
rf_status rf_fem_option_parse(rf_fem_options *o, const rf_fem_option_field *f, const char *text, rf_error *err);
/* The same for a number (REAL and COUNT rows; a COUNT must be an integer). */
rf_status rf_fem_option_set(rf_fem_options *o, const rf_fem_option_field *f, double x, rf_error *err);
/* f's value in o as text: %.17g, the count, or the choice's name. */
void rf_fem_option_format(const rf_fem_options *o, const rf_fem_option_field *f, char *buf, size_t size);
/* The choices of a CHOICE row as "a | b | c" into buf. */
void rf_fem_option_choices(const rf_fem_option_field *f, char *buf, size_t size);

void rf_fem_options_default(rf_fem_options *opt);

/* The axisymmetric preset of a thick soil layer's impact for a table
 * (docs/soil-impacts.md section 4): mesh_sizing soil, refinement
 * RF_FEM_SOIL_PRESET_REFINEMENT, rock_mass_scale RF_FEM_SOIL_PRESET_ROCK_SCALE;
 * the other options are left as they are.  The one place these numbers are
 * written (the rolling calibration and bench_soil_impact use it). */
#define RF_FEM_SOIL_PRESET_REFINEMENT 6.0
#define RF_FEM_SOIL_PRESET_ROCK_SCALE 100.0
void rf_fem_soil_table_preset(rf_fem_options *opt);

/* 1 if the FE models run in large deformation for this impact:
 * opt->large_deformation on, or auto with an elasto-plastic body (the boulder,
 * the slope or a layer); the one rule the solver and the model identity use. */
int rf_fem_large_deformation(const rf_fem_options *opt, const rf_impact_input *in);
/* 1 if the axisymmetric model rezones its slope (ALE): opt->ale on, and
 * only in large deformation. */
int rf_fem_ale_enabled(const rf_fem_options *opt, const rf_impact_input *in);


/* The one check of the options (three_d: for the 3D model, whose limits
 * differ where the table says so; and of opt->tuning when set); messages name
 * the setting and value. */
rf_status rf_fem_options_validate(const rf_fem_options *opt, int three_d, rf_error *err);

/* The refinement and the domain radius / r0 actually used for an impact. */
double rf_fem_refinement(const rf_fem_options *opt, int three_d);
double rf_fem_domain_factor(const rf_fem_options *opt, const rf_impact_input *in);

/* 1 if the impact needs the 3D model: an inclined slope, or a normal impact
 * with friction between elastically dissimilar bodies (Dundurs beta != 0 of
 * the boulder and the surface it meets, the layer's if any; a rigid boulder
 * is the limit of an infinitely stiff one: the two surfaces would slip
 * radially against each other); else the axisymmetric model is exact.  A
 * normal impact with any elasto-plastic body runs the axisymmetric model
 * (large deformation, gravity) without interface friction: the radial slip
 * of a yielding crater is not modelled (docs/impact.md). */
int rf_fem_needs_3d(const rf_impact_input *in);

/* Time series and diagnostics of one impact.  Energies in J. */
typedef struct {
    size_t n;                     /* samples */
    double *t;                    /* [s] */
    double *contact_force;        /* sum of contact multipliers [N] */
    double *compression;          /* approach of the boulder CM [m] */
    double *contact_radius;       /* outermost contact, interpolated [m] */
    double *kinetic_boulder, *strain_boulder;
    double *kinetic_slope, *strain_slope;
    double *contact_work;         /* work of the contact forces (ideally 0) */
    double *absorbed;             /* energy taken out by the dashpots */
    double *closure;              /* total + absorbed - KE0 (energy error) */
    double *boulder_velocity;     /* rigid (CM) vertical velocity [m/s] */
    double *remap;                /* axisymmetric with ALE: energy the remaps added so far [J] (kinetic +
                                     elastic + potential; NULL without ALE); the closure is net of it */

    /* diagnostics */
    double dt;                    /* time step used [s] */
    double dt_bound;              /* element eigenvalue bound 2/sqrt(max lambda) [s] */
    double dt_edge;               /* smallest edge / c_p, for comparison only [s] */
    double h_contact;             /* slope element size in the fine zone [m] */
    double hertz_radius;          /* Hertz contact radius a used to size the mesh [m] */
    double hertz_duration;        /* Hertz contact duration [s] */
    double boulder_mass;          /* exact (analytic) boulder mass [kg] */
    double boulder_mesh_mass;     /* mass of the boulder mesh before the density correction [kg] */
    double penetration_max;       /* largest penetration of any contact pair [m] */
    double slip_max;              /* largest radial slip of a contact pair while in contact [m] */
    double reflection_time;       /* 2 L / c_p of the slope [s] */
    double vibration_energy;      /* boulder KE + strain energy - rigid KE at the end [J] */
    double slope_energy;          /* slope KE + strain energy at the end [J] */
    double ke0;                   /* initial kinetic energy [J] */
    /* plasticity (both models; the 3D model's as full-body values, r = distance from the impact axis) */
    double plastic_work_boulder, plastic_work_slope; /* plastic dissipation of each body at the end [J] */
    double elastic_energy_stress; /* plastic bodies: elastic energy of the committed stresses [J] ... */
    double elastic_energy_work;   /* ... and their internal work less the plastic work (should agree) [J] */
    int plastic_strain_max_in;    /* where the largest equivalent plastic strain is: 0 nowhere, 1 boulder, 2 slope */
    double plastic_strain_max_r, plastic_strain_max_z; /* centre of its element (reference coordinates,
                                                            z = 0 on the slope surface) [m] */
    long boulder_nodes, boulder_elements, slope_nodes, slope_elements;
    /* gravity (rf_impact_gravity; docs/validation-plastic.md "Gravity") */
    double gravity;               /* [m/s^2] the run used */
    double gravity_work;          /* work of gravity on both bodies at the end (the loss of potential energy) [J] */
    long geostatic_outside;       /* integration points whose geostatic state the law does not admit (0 expected) */
    int at_rest;                  /* 1: the run ended by the rest rule (the boulder at rest in contact: R_n = 0) */
    /* ALE rezoning (axisymmetric large deformation, option ale; zeros without) */
    long ale_rezones, ale_nodes_moved; /* rezones that moved nodes; node relocations summed */
    double ale_kinetic, ale_elastic, ale_potential; /* energy the remaps added [J], by kind */
    double ale_move_max;          /* largest relocation of a node in one rezone [m] */
    double ale_ratio_min;         /* smallest element size / reference size that triggered a rezone */
    /* Coulomb friction of the axisymmetric contact (friction > 0; zeros without) */
    double friction_work;         /* work dissipated by friction at the end [J], a term of the closure */
    double stick_fraction;        /* closed pair-steps that stuck (|F_t| < mu F_n) / all closed pair-steps */
    int friction_sweeps_max;      /* most Gauss-Seidel sweeps one step needed */
    double stick_residual_max;    /* largest slip per step left on a sticking pair [m] */
    uint64_t state_hash;          /* FNV-1a over the bytes of the final u and v (determinism checks) */
    char warning[512];            /* "" or a human-readable warning */
} rf_fem_history;

void rf_fem_history_free(rf_fem_history *hist);

/* The state of the FE solvers between evaluations (GSL style): growable
 * buffers that a worker thread reuses, so that a study's evaluations do not
 * reallocate the solver's arrays.  One workspace per thread. */
typedef struct rf_fem_workspace rf_fem_workspace;
rf_fem_workspace *rf_fem_workspace_alloc(void);
void rf_fem_workspace_free(rf_fem_workspace *ws);

/* Run one normal impact.  out is filled on success; hist (may be NULL) gets
 * time series and diagnostics and must be released with rf_fem_history_free.
 * Returns RF_EINVAL for an inclined slope (slope_angle != 0), bad inputs, or
 * a mesh too coarse for the contact radius. */
rf_status rf_fem_impact(const rf_impact_input *in, const rf_fem_options *opt,
                        rf_impact_output *out, rf_fem_history *hist, rf_error *err);
/* The same in a caller's workspace (rf_fem_impact allocates a fresh one). */
rf_status rf_fem_impact_ws(rf_fem_workspace *ws, const rf_impact_input *in, const rf_fem_options *opt,
                           rf_impact_output *out, rf_fem_history *hist, rf_error *err);

/* Run the FE model the impact needs (rf_fem_needs_3d): the axisymmetric one
 * or the 3D half model with default 3D settings.  hist may be NULL;
 * friction_work (may be NULL) receives the Coulomb dissipation [J] (0 for the
 * axisymmetric model); *three_d (may be NULL) says which model ran.  VTK
 * frames (opt->vtk_dir) in both models (the 3D model's half model). */
rf_status rf_fem_solve(const rf_impact_input *in, const rf_fem_options *opt, rf_impact_output *out,
                       rf_fem_history *hist, double *friction_work, int *three_d, rf_error *err);
/* The same in a caller's workspace (NULL = a fresh one). */
rf_status rf_fem_solve_ws(rf_fem_workspace *ws, const rf_impact_input *in, const rf_fem_options *opt,
                          rf_impact_output *out, rf_fem_history *hist, double *friction_work, int *three_d,
                          rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
