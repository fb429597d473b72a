/* traj_internal.h - what the trajectory files share: the prepared profile
 * (segments with tangent, normal, length, x-range), collector geometry, the
 * state of one running trajectory, and the functions of each phase
 * (flight.c, contact.c, bounce.c, simulate.c). */
#ifndef ROCKFUZZ_TRAJ_INTERNAL_H
#define ROCKFUZZ_TRAJ_INTERNAL_H

#include "rockfuzz/trajectory.h"
#include "core/util.h"

#include <stdatomic.h>
#include <math.h>
#include <stdint.h>

#define TRAJ_NONE ((size_t)-1)

typedef struct {
    double ax, ay, bx, by;   /* end points A (point i), B (point i+1) */
    double tx, ty, nx, ny;   /* unit tangent A->B, outward normal (-t_y, t_x) */
    double len, xmin, xmax;
    size_t material;
} traj_segment;

typedef struct {
    double x, ground_y;      /* ground under the line */
    size_t segment;          /* the segment carrying that ground */
} traj_collector_geo;

typedef struct traj_release_set traj_release_set;

struct rf_traj_world {
    size_t nseg;
    traj_segment *seg;
    size_t ncol;
    traj_collector_geo *col;
    void *impact_table;      /* impact_model law: traj_impact_table */
    int owns_table;          /* 0: shared by the caller (traj_world_create_shared) */
    traj_release_set *release;  /* release line or zone: the pieces a point is drawn on (release.c) */
};

/* spec.c: the mass of a point block (spec->mass) or of a homogeneous sphere
 * (4/3 pi r^3 rho) [kg]; a rigid block's comes from its shape (block_traj_setup.c). */
double traj_spec_mass(const rf_traj_spec *s);
/* release.c: the release velocity (vx, vy, or speed and angle); the pieces
 * of a release line or zone (w->release, NULL for a point; an empty zone is
 * an error); the point at u in (0, 1), uniform by length over the pieces. */
void traj_release_velocity(const rf_traj_spec *s, double *vx, double *vy);
rf_status traj_release_prepare(const rf_traj_spec *s, rf_traj_world *w, rf_error *err);
void traj_release_free(traj_release_set *r);
void traj_release_point(const rf_traj_world *w, double u, double *x, double *y);


/* traj_output.c: pieces of the JSON document and the summary that the
 * terrain outputs (terrain_output.c) share: {"pXX": .., "max": .., "mean": ..};
 * [{"threshold", "barrier", "probability"}]; {"edges", "counts"}; a
 * collector's "NAME": {statistics}; a summary line of percentiles (values
 * times scale) and of exceedance probabilities. */
void traj_json_percentiles(FILE *f, const rf_traj_percentiles *p);
void traj_json_exceed(FILE *f, const double *t, const double *p, size_t n, int own);
void traj_json_histogram(FILE *f, const rf_traj_histogram *h);
void traj_json_collector_stats(FILE *f, const rf_traj_collector *col, const rf_traj_collector_stats *cs);
void traj_summary_row(FILE *f, int indent, const char *what, const rf_traj_percentiles *p, double scale);
void traj_summary_exceed(FILE *f, const char *what, const char *unit, const double *t, const double *p, size_t n,
                         int own, const char *own_name, double scale);

/* traj_draw.c: the random inputs of sample i (montecarlo.c, terrain_montecarlo.c).
 * traj_draw_value: the value of random input r at the uniform u in (0, 1);
 * traj_sample_u: the uniform of input dimension j of sample i (dimensions
 * 0..n_random-1 the random inputs, then the release point's), from
 * U(seed, stream 2i, index j), stratified when perm (dims * samples, from
 * traj_lhs_permutations) is set; traj_draw_bind: where each random input of
 * the copy `local` lives (row NULL: not a row, never drawn);
 * traj_draw_inputs: write sample i's draws there. */
double traj_draw_value(const rf_traj_random *r, double u);
/* traj_draw.c: run worker on jobs[0..threads-1] (each job_size bytes), job 0
 * on this thread, the others on their own threads (a thread that cannot
 * start has its share done here), and wait for all. */
void traj_start_and_join(void *jobs, size_t job_size, int threads, void *(*worker)(void *));
double traj_sample_u(const rf_traj_spec *s, const size_t *perm, size_t i, size_t j);
size_t *traj_lhs_permutations(const rf_traj_spec *s, size_t dims);
void traj_draw_bind(rf_traj_spec *local, const rf_traj_spec *spec, const rf_traj_field **row, double **field);
void traj_draw_inputs(const rf_traj_spec *spec, const size_t *perm, size_t i, const rf_traj_field *const *row,
                      double *const *field);

/* A world that uses the given impact table (not owned; NULL: built if the law needs it). */
rf_status traj_world_create_shared(const rf_traj_spec *spec, void *table, rf_traj_world **world, rf_error *err);
/* montecarlo.c: rf_traj_run with a shared impact table (NULL: the run builds its own). */
rf_status traj_run_shared(const rf_traj_spec *spec, int threads, void *table, rf_traj_ensemble *ens,
                          rf_error *err);
/* The same, with the envelopes (ens->envelope) only if `envelopes` (they
 * about double the run time; the study model does not need them). */
rf_status traj_run_with(const rf_traj_spec *spec, int threads, void *table, int envelopes, rf_traj_ensemble *ens,
                        rf_error *err);

/* traj_fields.c: a row's value as stored (radians for an angle) from the
 * value as given (degrees), and back; whether the row is used by this spec
 * (e.g. block.mass only for a point block); every input path of the spec
 * (rows per material and collector, then the random inputs' parameters with
 * row NULL). */
double traj_field_store(const rf_traj_field *f, double given);
double traj_field_given(const rf_traj_field *f, double stored);
int traj_field_used(const rf_traj_spec *s, const rf_traj_field *f);
/* rf_traj_field_rule on the value as stored. */
const char *traj_field_rule_stored(const rf_traj_field *f, double stored);
/* Why a row is not used (f->when does not hold), for messages. */
const char *traj_field_unused_reason(const rf_traj_field *f);
void traj_each_path(const rf_traj_spec *s, void (*fn)(void *ctx, const char *path, const rf_traj_field *f),
                    void *ctx);

/* traj_fields.c: every setting of rf_traj_settings at its default (record:
 * its cap; the reader makes it min(samples, cap) when left out); the cache
 * none.  traj_bind.c: the hash of every setting's value (the identity). */
void traj_settings_default(rf_traj_spec *s);
uint64_t traj_settings_hash(uint64_t h, const rf_traj_spec *s);

/* Round-off allowance [m] of a geometric test near (x, y): relative to the
 * local coordinates, never to the profile's extent (a far vertex must not
 * change the motion here). */
static inline double traj_tol(double rel, double x, double y) { return rel * (1 + fabs(x) + fabs(y)); }

/* profile.c: x sorted, no repeated point, no self-intersection. */
rf_status traj_profile_check(const rf_traj_spec *s, rf_error *err);

/* Ground under x (the highest non-vertical segment covering x); segment
 * index in *seg (TRAJ_NONE and NaN outside the profile). */
double traj_ground_y(const rf_traj_world *w, double x, size_t *seg);

/* The state of one running trajectory: a small state machine whose phase
 * is a flight (from a point on segments on[0], on[1]) or a contact with
 * segment k at signed speed u along its tangent. */
typedef enum { TRAJ_FLY = 0, TRAJ_CONTACT, TRAJ_DONE } traj_phase;

typedef struct {
    const rf_traj_world *w;
    const rf_traj_spec *s;
    rf_traj_result *res;
    uint64_t seed, sample, n_rough;   /* roughness draws: stream 2 sample + 1, index n_rough */
    double g, mass, inertia, radius;
    double t, x, y, vx, vy, omega;
    traj_phase phase;
    size_t k, on[2];
    double u;
    int from_impact;                  /* the current flight starts at an impact (rebound height) */
    int nomem;                        /* recording an event or impact ran out of memory */
} traj_run;

/* flight.c: first impact of the parabola from (x, y) with velocity (vx, vy).
 * Segments on[0], on[1] contain the start point (TRAJ_NONE: none): their
 * t = 0 root is never taken unless the block moves into them.  Returns the
 * segment hit, or TRAJ_NONE (the block leaves the profile); *tau is the
 * flight time. */
size_t traj_first_impact(const rf_traj_world *w, double x, double y, double vx, double vy, double g,
                         const size_t on[2], double *tau);
/* Record the collector crossings of the current flight over [0, tau_end]
 * (tau_end may be INFINITY); returns 1 if a barrier stopped the block. */
int traj_flight_collectors(traj_run *r, double tau_end);
/* Record the first crossing of collector c; *stopped = 1 if its barrier holds the block. */
/* The collector not yet reached that the block crosses first, at *tf = when(r, c, ctx) (INFINITY: never);
   TRAJ_NONE if none: the one search of the flight and the contact phase. */
size_t traj_next_crossing(const traj_run *r, double (*when)(const traj_run *r, size_t c, const void *ctx),
                          const void *ctx, double *tf);
void traj_record_crossing(traj_run *r, size_t c, double t, double x, double y, double vx, double vy,
                          double omega, int *stopped);

/* bounce.c: velocity and spin after an impact on segment k; returns 1 for a
 * soft landing (normal speed below contact_speed: only the velocity along the
 * segment is kept, no bounce law applied), else 0. */
int traj_bounce(traj_run *r, size_t k, double *vx, double *vy, double *omega);
/* bounce.c: the law's own check of the spec (e.g. needs a sphere); law in range. */
rf_status traj_bounce_law_validate(const rf_traj_spec *s, rf_error *err);

/* contact.c: one stretch of contact motion on segment r->k until the block
 * stops, reaches a vertex (then: launch, next segment, or impact) or a barrier. */
void traj_contact_step(traj_run *r);

/* contact.c: whether contact on segment k rolls (else it slides) and the
 * resisting deceleration there [m/s^2] (rolling resistance or friction). */
int traj_contact_rolls(const traj_run *r, size_t k, double *resist);

/* envelope.c: per-thread accumulators of the envelopes along x (rf_traj_envelope).
 * Counts and maxima only, so merging them in any order gives the same bits. */
typedef struct traj_env_acc traj_env_acc;
traj_env_acc *traj_env_create(const rf_traj_spec *spec, size_t n_edges, const rf_traj_world *w);
/* Add one trajectory (its events) run with the values `values`. */
void traj_env_add(traj_env_acc *a, const rf_traj_spec *values, const rf_traj_result *res);
void traj_env_merge(traj_env_acc *into, const traj_env_acc *from);
rf_status traj_env_finish(const traj_env_acc *a, rf_traj_envelope *env, rf_error *err);
void traj_env_free(traj_env_acc *a);
void traj_envelope_free(rf_traj_envelope *env);
/* DIR/envelopes.csv: one row per edge x_k (units in the header). */
rf_status traj_write_envelopes_csv(const char *dir, const rf_traj_ensemble *e, rf_error *err);

/* traj_model.c: the spec (a copy to free) that model m's evaluation at x
 * runs, and its shared impact table (or NULL); RF_EINVAL if m is not a
 * trajectory model.  For a run at one point (traj_run_at.c). */
rf_status traj_model_spec_at(const rf_model *m, const double *x, rf_traj_spec *spec, void **table, rf_error *err);
/* The outputs of trajectory model m (n_outputs values into y) from the
 * statistics t of a run of spec s, as its evaluation computes them. */
void traj_model_outputs(const rf_model *m, const rf_traj_spec *s, const rf_traj_stats *t, double *y);

/* traj_plot.c: rf_traj_write_plots on the axes sc (NULL: each figure its own),
 * and the axes a run's figures would take on their own, widening sc. */
rf_status traj_write_plots_scaled(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                                  const rf_traj_stats *st, const rf_traj_plot_scales *sc, rf_error *err);
void traj_plot_extent(const rf_traj_spec *s, const rf_traj_ensemble *e, rf_traj_plot_scales *sc);

/* traj_csv.c: statistics.csv, shared by profile and terrain runs: the header
 * (quantity, unit, the percentile levels, max, mean), one row of percentiles
 * (times scale, e.g. radians to degrees), and the rows of every collector. */
void traj_stats_header(FILE *f, const rf_traj_stats *st);
void traj_stats_row(FILE *f, const char *c, const char *what, const char *unit, const rf_traj_percentiles *p,
                    double scale);
void traj_stats_collectors(FILE *f, const rf_traj_spec *s, const rf_traj_stats *st);

/* traj_report.c: an <img> of the PNG dir/stem.png inlined as base64 (a note
 * when it is missing): both run reports' (text escaping: core/html.h). */
void traj_html_image(FILE *f, const char *dir, const char *stem);

/* roots.c: the smallest tau in [0, tmax] with c2 tau^2 + c1 tau + c0 = 0; INFINITY if none. */
double traj_first_root(double c2, double c1, double c0, double tmax);

/* transitions.c */
void traj_event(traj_run *r, rf_traj_event_kind kind, int flying, double ax, double ay);
void traj_finish(traj_run *r, rf_traj_state state, rf_traj_event_kind kind);
/* Launch a flight from the current state (point on segments a, b); a velocity
 * along one of them, into it, continues in contact on it instead. */
void traj_launch(traj_run *r, size_t a, size_t b, rf_traj_event_kind kind);
/* The block at the current state hits segment k: bounce, stop, or contact. */
void traj_impact(traj_run *r, size_t k);

/* traj_invariants.c: a recorded trajectory (res->events) run with the spec's values never
 * lies inside the ground and never gains mechanical energy between events;
 * the message names the event. */
rf_status traj_check_invariants(const rf_traj_spec *spec, const rf_traj_result *res, rf_error *err);

/* profile_csv.c: read the profile CSV file (the input-file guard of core/textfile.h, then
 * traj_csv_parse); *named = 1 if a line named a material. */
rf_status traj_csv_read(const char *path, rf_traj_spec *spec, int *named, rf_error *err);
/* profile_csv.c: the profile CSV text buf[0..len) (messages name `name`) into the spec's
 * vertices and segment materials; *named: a line named a material. */
rf_status traj_csv_parse(const char *name, const char *buf, size_t len, rf_traj_spec *spec, int *named,
                         rf_error *err);

/* impact adapter (traj_impact_adapter.c + traj_impact_table.c) */
typedef struct traj_impact_table traj_impact_table;
rf_status traj_impact_table_build(const rf_traj_spec *spec, traj_impact_table **table, rf_error *err);
/* The same, watched: before each impact it computes, a non-zero *stop ends the
 * build with RF_EINTERRUPTED (the impacts computed so far stay in the cache
 * file); after each, progress(user, impacts computed, taken from the cache,
 * nodes in v_n, nodes in theta).  Every member may be NULL. */
struct traj_impact_setup_s; /* traj_impact.h: traj_impact_setup */
typedef struct traj_impact_store traj_impact_store; /* traj_impact.h: where impacts are kept (a study's store) */
typedef struct {
    const atomic_int *stop;
    void (*progress)(void *user, size_t computed, size_t from_cache, size_t nv, size_t nt);
    void *user;
    const traj_impact_store *store; /* NULL: bounce.impact.cache (a file) or nothing */
    /* the model tabulated instead of the impact model (tests: a known function); NULL: the impact model */
    rf_status (*model)(const struct traj_impact_setup_s *s, double vn, double theta, double c[3], rf_error *err);
} traj_table_watch;
rf_status traj_impact_table_build_watched(const rf_traj_spec *spec, const traj_table_watch *watch,
                                          traj_impact_table **table, rf_error *err);
void traj_impact_table_free(traj_impact_table *t);
/* R_n, R_t and omega*r/v_t after an impact of normal speed vn (>0), incidence
 * angle theta [rad] from the normal. */
void traj_impact_table_eval(const traj_impact_table *t, double vn, double theta, double *R_n, double *R_t,
                            double *spin_ratio);
void traj_impact_table_info(const traj_impact_table *t, size_t *nv, size_t *nt, size_t *evaluations,
                            size_t *from_cache, double *error_estimate);
/* The table of the contact's material (its own impact model, or bounce.impact)
 * at the block radius [m] (clamped to the run's range): R_n, R_t and
 * omega*r/v_t.  traj_impact_table_eval is material 0 at the smallest radius. */
void traj_impact_table_lookup(const traj_impact_table *t, size_t material, double radius, double vn, double theta,
                              double *R_n, double *R_t, double *spin_ratio);
/* The grids of the table (one per material with its own impact model, one for
 * the others) and grid k's nodes (v_n, theta, radius) and figures. */
size_t traj_impact_table_grids(const traj_impact_table *t);
void traj_impact_table_grid_info(const traj_impact_table *t, size_t k, size_t nodes[3], size_t *evaluations,
                                 size_t *from_cache, double *error_estimate);

#endif
