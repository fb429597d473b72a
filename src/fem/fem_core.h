/* fem_core.h - the stages of the explicit-dynamics impact run that the
 * axisymmetric (fem_solver.c) and the 3D (fem3d_solver.c) solvers share:
 *
 *   sizing     rf_impact_hertz_reference, rf_fem_refinement, rf_fem_domain_factor (fem_options.c)
 *   workspace  fem_pool: reusable buffers of a solver, owned by rf_fem_workspace
 *   time step  fem_time_step: dt from the largest element eigenvalue
 *   run        fem_run: the time span and stop test, the contact-force record,
 *              the maxima, the energy-closure check, the sampled history
 *   outputs    fem_run_outputs (peak force, compression, duration, radius,
 *              energy error, counts), fem_run_history, fem_run_warnings
 *              (reflection check, re-contact, unfinished contact)
 *
 * Each solver keeps what its geometry needs (mesher, element, contact, the
 * rigid-body extraction) and calls these stages in the same order; the
 * material enters through fem_kernel.h. */
#ifndef ROCKFUZZ_FEM_CORE_H
#define ROCKFUZZ_FEM_CORE_H

#include <stddef.h>
#include <stdint.h>

#include "fem_tuning.h"
#include "rockfuzz/fem.h"

/* --- workspace: growable buffers addressed by a solver's slot number --- */

#define FEM_POOL_SLOTS 48
typedef struct {
    void *ptr[FEM_POOL_SLOTS];
    size_t cap[FEM_POOL_SLOTS];
} fem_pool;

/* A buffer of at least `bytes` for slot (kept across calls: a worker that
 * reuses its workspace allocates only when a mesh grows), zeroed if zero. */
void *fem_pool_get(fem_pool *p, int slot, size_t bytes, int zero);
void fem_pool_free(fem_pool *p);

struct rf_fem_workspace {
    fem_pool axi, solid; /* the axisymmetric and the 3D solver's buffers */
};

/* --- time step --- */

/* dt = safety * 2 / sqrt(lambda_max) (central differences, undamped). */
double fem_time_step(double lambda_max, double safety, double *dt_bound);

/* --- large deformation: a run made again with half the step --- */

/* Elements compressed under the contact lower their explicit step bound; a
 * run whose step outgrows it is made again from the start with half the step
 * (up to FEM_STEP_HALVINGS times), so that every result comes from a uniform
 * step that stayed stable throughout. */
#define FEM_STEP_HALVINGS 4
/* One run with the options o; *unstable >= 0 (an element) if the step outgrew a bound. */
typedef rf_status (*fem_attempt_fn)(void *ctx, const rf_fem_options *o, long *unstable, rf_error *err);
/* attempt() with *o, then with dt_safety halved while an attempt was unstable; the last attempt's status. */
rf_status fem_run_halving(fem_attempt_fn attempt, void *ctx, const rf_fem_options *o, rf_error *err);

/* --- the run account --- */

#define FEM_SERIES_MAX 13
typedef struct {
    size_t n, cap;
    int ncol;
    double *col[FEM_SERIES_MAX];
} fem_series;

typedef struct {
    const char *who;          /* "fem" or "fem3d", for messages */
    double dt, t_h, end_time; /* time step, Hertz duration, requested end (0 = automatic) */
    double t_min, t_max;      /* the run lasts at least t_min, at most t_max */
    int stride;               /* history sample every stride steps */
    int record;               /* keep the sampled history */
    long steps_estimate;
    /* contact force of every step */
    double *force;
    long force_cap;
    /* maxima and contact episodes */
    double F_max, a_at_Fmax, comp_max, closure_max, t_last_contact;
    int episodes, in_contact;
    /* the boulder's normal velocity (history column 11; < 0: toward the slope):
       at the start, now; t_bound: the automatic end's bound, set at t_max when
       the impact has not ended (0: not yet) */
    double v_start, v_now, t_bound;
    /* gravity > 0 (set after fem_run_begin; 0 keeps the gravity-free rules): the
       normal velocity when the contact last opened (R_n with gravity), the start
       of the current slow spell in contact (-1: none) and the rest flag */
    double gravity, v_sep, rest_since;
    int at_rest;
    /* the roll rule (below): the boulder's displacement along the slope [m] at this step (set by the
       geometry before the account; 0 where it has none) and the largest contact radius so far [m];
       out: the run ended by it (at_rest is then set too) */
    struct {
        double travel, a_max;
        int out;
    } roll;
    int early_end; /* the tuning's end_at_separation */
    fem_series series;
    void (*progress)(void *ctx, double t, double t_end); /* the options' progress callback, or NULL */
    void *progress_ctx;
} fem_run;

/* Start the account: time span from the options and the Hertz duration. */
rf_status fem_run_begin(fem_run *r, const char *who, const rf_fem_options *o, double dt, double t_h, int record,
                        int ncol, rf_error *err);
/* Step n (time t = n dt) done: total contact force Fc, contact radius rad,
 * boulder compression comp, energy closure error (absolute, J) against ke0;
 * row (ncol values, row[11] the boulder's normal velocity) is sampled into
 * the history.  Fails on divergence, and (automatic end) when the impact has
 * not ended by the bound of fem_run_stop. */
rf_status fem_run_account(fem_run *r, long n, double Fc, double rad, double comp, double closure, double ke0,
                          const double *row, rf_error *err);
/* 1 when the run ends after step n (with gravity the impact has ended when
 * the contact opened with the boulder moving away at v_sep > FEM_REST_SPEED V;
 * else it ends by the rest rule).  end_time > 0: at end_time.  Automatic:
 * the impact has ended (the contact open for 0.1 t_h and the boulder not
 * moving toward the slope) after t_min = 1.3 t_h; past t_max = 3 t_h it must
 * also have ended, else the run goes on up to a bound scaled by the contact's
 * progress at t_max (fem_run_account fails there; with gravity the bound is
 * FEM_RUN_BOUND_MAX t_h: a block settles by small bounces and oscillations,
 * and the rest rule below ends it). */
int fem_run_stop(const fem_run *r, long n);
/* The rest rule (gravity > 0, automatic end): the boulder has come to rest in
 * its crater when, for FEM_REST_WINDOW Hertz durations, it has been in contact
 * (closed within the last 0.1 t_h) with a normal speed below FEM_REST_SPEED
 * times the incoming one; the run then ends (R_n = 0), without failing. */
#define FEM_REST_SPEED 0.02
/* The roll rule (gravity > 0, automatic end): past t_max a boulder still in contact whose centre has
 * moved along the slope by more than its crater's diameter (twice the largest contact radius) has
 * rolled or slid out of its crater: the impact is over, the run ends as at rest (R_n = 0, the
 * tangential velocity and spin of that moment), without failing.  Without it a block that neither
 * rebounds nor rests (rolling down a slope steeper than its crater holds it) ran off the mesh and
 * failed at the automatic end's bound (docs/soil-impacts.md section 6). */
/* The mass redistribution at the contact face (docs/validation-plastic.md 9e) leaves every face
 * node at least this share of its element masses.  Any share keeps the step; the floor keeps the
 * face elements from being crushed: with a share of 0.006 (soft soil over granite) the boulder
 * drove nearly massless face nodes into the heavy ones below, and a 3D ploughing run at a/h 5
 * failed with a face element compressed below the step bound, which ends with 0.1. */
#define FEM_MASS_KEPT_MIN 0.1

/* The share of its face nodes' element masses that a contact-face element with eigenvalue bound
 * lam_e keeps, max(FEM_MASS_KEPT_MIN, lam_e / (kappa lam_max)) (>= 1: the element is left alone);
 * the rule of both solvers' mass redistribution. */
static inline double fem_mass_kept(double lam_e, double kappa, double lam_max)
{
    const double a = lam_e / (kappa * lam_max);
    return a > FEM_MASS_KEPT_MIN ? a : FEM_MASS_KEPT_MIN;
}
#define FEM_REST_WINDOW 2.0
/* Fill the outputs every FE model defines; nsteps steps were made. */
void fem_run_outputs(const fem_run *r, long nsteps, double duration_threshold, double ke0, double force_factor,
                     long nodes, long elements, rf_impact_output *out);
/* Move the first 12 sampled columns into hist (the series keeps the rest). */
void fem_run_history(fem_run *r, rf_fem_history *hist);
/* The warnings: reflection (fixed boundary and 2 L / c_p < t_c), re-contact,
 * contact at end_time; extra (may be NULL) is appended. */
void fem_run_warnings(const fem_run *r, int fixed_outer, double L, double c_p, double r0, char *buf, size_t size,
                      const char *extra);
void fem_run_free(fem_run *r);

/* First to last step whose force exceeds threshold, ends interpolated
 * linearly within the neighbouring step; *t_first = 0, *t_last = -1 if none. */
void fem_contact_window(const double *force, long nsteps, double dt, double threshold, double *t_first,
                        double *t_last);

/* FNV-1a (core/hash.h) over n bytes, continuing from h (start with FEM_HASH_SEED, a
   seed of its own that the regression hashes were recorded with). */
#define FEM_HASH_SEED 1469598103934665603ULL
uint64_t fem_hash(uint64_t h, const void *data, size_t n);

#endif
