/* traj_rolling_fe.c - the calibration of the rolling model on the FE model
 * of the layer (traj_rolling.h): the static indentation curve F(d) of a
 * sphere of the block's radius is the loading branch of an axisymmetric FE
 * impact of a rigid sphere (the block's radius and density, normal, with
 * gravity and large deformation: the impact model's automatic settings) on
 * the material's ground, slow enough that the soil's inertia is negligible
 * against its strength (rho v^2 ~ 2 kPa at 1 m/s against a bearing pressure
 * of hundreds of kPa).  A rigid sphere's CM approach is the penetration, and
 * the contact force is the layer's resistance at that depth.  The speed
 * starts at 1 m/s and doubles (up to 8 m/s) until the branch reaches 2.5 W,
 * beyond the rolling block's 2 W.
 *
 * The curve kept: the samples up to the deepest point, each with a depth
 * beyond the last kept one, the force as the running maximum (the layer's
 * resistance does not drop while it is pushed deeper; the FE's contact
 * force oscillates about it by a few per cent).
 *
 * The ground is put into the impact input the way traj_impact_adapter.c
 * does (by the impact inputs' names: traj_impact_ground_field), but the FE is
 * called directly (rf_fem_impact) for its time series, which the impact
 * models' common interface does not return. */
#include "trajectory/traj_rolling.h"
#include "core/util.h"

#include "rockfuzz/fem.h"
#include "rockfuzz/impact.h"
#include "rockfuzz/material.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The impact input of the calibration: setup's ground, a rigid sphere at speed v. */
static rf_status calibration_input(const traj_impact_setup *s, double v, double gravity, rf_impact_input *in,
                                   rf_error *err)
{
    rf_impact_input_default(in);
    for (size_t k = 0; s->has_ground && traj_impact_ground_field(k); k++) {
        const rf_impact_field *f = rf_impact_field_find(traj_impact_ground_field(k));
        if (!f)
            return rf_fail(err, RF_EINVAL, "internal: impact input %s unknown", traj_impact_ground_field(k));
        rf_impact_field_store(in, f, s->ground.v[k]);
    }
    rf_status st = RF_OK;
    if (s->has_ground && s->ground.slope_material[0])
        st = rf_material_model_parse(s->ground.slope_material, &in->slope_material, err);
    if (st == RF_OK && s->has_ground && s->ground.layer_material[0])
        st = rf_material_model_parse(s->ground.layer_material, &in->layer_material, err);
    in->boulder_material = RF_MATERIAL_RIGID_BODY;
    in->radius = s->radius;
    in->boulder_density = s->density;
    in->friction = 0;
    in->velocity = v;
    in->slope_angle = 0;
    in->gravity = gravity;
    return st == RF_OK ? rf_impact_input_validate(in, err) : st;
}

/* The loading branch of hist as a non-decreasing curve into depth/force (n_out points). */
static size_t loading_branch(const rf_fem_history *h, double *depth, double *force)
{
    size_t deepest = 0, n = 0;
    for (size_t i = 0; i < h->n; i++)
        if (h->compression[i] > h->compression[deepest])
            deepest = i;
    double fmax = 0;
    for (size_t i = 0; i <= deepest && i < h->n; i++) {
        double d = h->compression[i], f = h->contact_force[i];
        if (f > fmax)
            fmax = f;
        if (d > 0 && (!n || d > depth[n - 1]))
            depth[n] = d, force[n] = fmax, n++;
    }
    return n;
}

/* One FE run at speed v: its loading curve (malloc'd arrays) into c. */
static rf_status run_at(const traj_impact_setup *s, double v, double gravity, traj_rolling_curve *c, rf_error *err)
{
    rf_impact_input in;
    rf_status st = calibration_input(s, v, gravity, &in, err);
    if (st != RF_OK)
        return rf_error_prefix(err, "rolling resistance: the impact model");
    rf_fem_options opt;
    rf_fem_options_default(&opt);
    opt.threads = 1;
    opt.refinement = s->refinement;
    opt.interrupt = s->stop;
    if (s->refinement == 0) /* the axisymmetric preset of a thick layer (docs/soil-impacts.md section 4) */
        rf_fem_soil_table_preset(&opt);
    rf_impact_output out;
    rf_fem_history h;
    memset(&h, 0, sizeof h);
    st = rf_fem_impact(&in, &opt, &out, &h, err);
    if (st != RF_OK) {
        rf_fem_history_free(&h);
        return rf_error_prefix(err, "rolling resistance: FE indentation at %g m/s", v);
    }
    double *d = malloc((h.n ? h.n : 1) * sizeof *d), *f = malloc((h.n ? h.n : 1) * sizeof *f);
    if (!d || !f) {
        free(d), free(f), rf_fem_history_free(&h);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    c->n = loading_branch(&h, d, f);
    c->depth = d, c->force = f;
    rf_fem_history_free(&h);
    return RF_OK;
}

static void curve_free(traj_rolling_curve *c)
{
    free((double *)c->depth);
    free((double *)c->force);
    c->depth = c->force = NULL, c->n = 0;
}

rf_status traj_rolling_calibrate(const traj_impact_setup *s, double gravity, traj_rolling_calibration *cal,
                                 rf_error *err)
{
    memset(cal, 0, sizeof *cal);
    double t0 = rf_monotonic_seconds();
    double W = 4.0 / 3.0 * RF_PI * s->radius * s->radius * s->radius * s->density * gravity;
    traj_rolling_curve c = {0, NULL, NULL};
    rf_status st = RF_OK;
    for (double v = 1; v <= 8 && st == RF_OK; v *= 2) {
        curve_free(&c);
        st = run_at(s, v, gravity, &c, err);
        cal->speed = v;
        if (st == RF_OK && c.n && c.force[c.n - 1] >= 2.5 * W)
            break;
    }
    if (st == RF_OK)
        st = traj_rolling_solve(&c, s->radius, W, &cal->r, err);
    if (st == RF_OK) {
        cal->depth_max = c.depth[c.n - 1];
        cal->fit_rms = traj_rolling_power_fit(&c, 0.2, &cal->fit_A, &cal->fit_m);
    }
    curve_free(&c);
    cal->wall = rf_monotonic_seconds() - t0;
    return st;
}
