/* traj_rolling.h - the rolling resistance of a sphere on a soil layer from
 * the layer's mechanics (issue 29 item 5; docs/soil-impacts.md, "Rolling
 * resistance from the layer").
 *
 * The reduced model (traj_rolling_model.c): the layer is a bed of
 * independent columns (Winkler/Bekker: the pressure at a point depends only
 * on the sinkage there), loaded without rebound (the rut stays).  Its
 * pressure-sinkage relation comes from the static indentation curve F(d) of a
 * sphere of the block's radius R (paraboloid contact, F(d) = 2 pi R P(d) with
 * P(z) = integral of p over [0, z]).  In steady rolling only the front half
 * of the contact carries load:
 *   weight      W = pi R P(z0)          i.e. F(z0) = 2 W      (z0: rut depth)
 *   resistance  F_r = integral over the rut's width of P(z0 - y^2/(2R)) dy
 *             = (a / (pi R)) integral_0^1 F(z0 (1 - t^2)) dt,   a = sqrt(2 R z0)
 * (the work of making the rut per metre = the horizontal force: Bekker's
 * compaction resistance for a sphere), mu_r = F_r / W.
 *
 * The calibration (traj_rolling_fe.c): F(d) is the loading branch of an
 * axisymmetric FE impact of a rigid sphere of the block's radius and density
 * on the material's impact model, slow enough to be quasi-static. */
#ifndef ROCKFUZZ_TRAJ_ROLLING_H
#define ROCKFUZZ_TRAJ_ROLLING_H

#include "trajectory/traj_internal.h"
#include "trajectory/traj_impact.h"

/* A static indentation curve: n points (depth [m], force [N]), depths
 * increasing from > 0, forces non-decreasing; F(0) = 0, linear in between. */
typedef struct {
    size_t n;
    const double *depth, *force;
} traj_rolling_curve;

typedef struct {
    double sinkage;      /* z0: the rut depth under the rolling block [m] */
    double half_width;   /* a = sqrt(2 R z0): half the rut's width [m] */
    double force;        /* F_r: the horizontal resistance [N] */
    double weight;       /* W [N] */
    double mu_r;         /* F_r / W [-] */
} traj_rolling_result;

/* F(d) on the curve (linear between points, from (0, 0); past the last point: NaN). */
double traj_rolling_curve_force(const traj_rolling_curve *c, double d);
/* The reduced model for a sphere of radius R [m] and weight W [N]; fails
 * (naming both forces) when the curve does not reach 2 W. */
rf_status traj_rolling_solve(const traj_rolling_curve *c, double radius, double weight, traj_rolling_result *r,
                             rf_error *err);
/* The closed form of a power-law curve F = A d^m (Bekker's p = K z^(m-1)):
 * mu_r = B_m sqrt(2 z0 / R) / pi, z0 = (2 W / A)^(1/m),
 * B_m = integral_{-1}^{1} (1 - t^2)^m dt = sqrt(pi) Gamma(m + 1) / Gamma(m + 3/2). */
double traj_rolling_power_mu(double A, double m, double radius, double weight, double *sinkage);
/* Least-squares fit of log F = log A + m log d over the curve's points with
 * d >= from * d_max; returns the rms residual of log F. */
double traj_rolling_power_fit(const traj_rolling_curve *c, double from, double *A, double *m);

/* The FE calibration of one material (setup: traj_impact_setup_material)
 * for a sphere of radius R and density rho: the indentation curve and the
 * reduced model's result.  The fitted power law (exponent, rms) and the FE
 * runs' speeds are said in *why (a line for the report). */
typedef struct {
    traj_rolling_result r;
    double fit_A, fit_m, fit_rms;  /* F = A d^m over the upper 80 % of the loading branch */
    double speed;                  /* impact speed of the FE run used [m/s] */
    double depth_max;              /* deepest point of its loading branch [m] */
    double wall;                   /* wall time of the calibration [s] */
} traj_rolling_calibration;

rf_status traj_rolling_calibrate(const traj_impact_setup *s, double gravity, traj_rolling_calibration *cal,
                                 rf_error *err);

/* What a material's rolling resistance is and why (traj_rolling.c). */
typedef enum {
    TRAJ_ROLLING_FILE = 0,      /* as given in the file, or bound by a study: wins */
    TRAJ_ROLLING_DEFAULT,       /* the default (no impact model with a soil layer to derive it from) */
    TRAJ_ROLLING_DERIVED,       /* derived from the material's impact model (its soil layer) */
    TRAJ_ROLLING_ROCK           /* the impact model has no soil layer: the file's value (rock) */
} traj_rolling_source;

const char *traj_rolling_source_name(int source);
/* The run's report: ,"rolling_resistance": {NAME: {value, unit, source[, rut_depth_m]}} for the JSON
 * record, and a line per derived or rock material for the summary. */
void traj_rolling_json(FILE *f, const rf_traj_spec *s);
void traj_rolling_summary(FILE *f, const rf_traj_spec *s);

#endif
