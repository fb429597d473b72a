/* traj_rolling.c - which rolling resistance each material of a run uses
 * (rf_traj_rolling_resolve, trajectory.h): the file's (or a study's bound)
 * value wins; else, with the impact_model law, a material whose impact
 * model has a soil layer (solver fem, layer_thickness > 0) gets the value
 * derived from the layer's mechanics for the nominal sphere
 * (traj_rolling_fe.c, traj_rolling_model.c); a rock-only impact model, an
 * analytic solver (no layer) or a block that is not a sphere keeps the
 * file's value (default 0) and says so.  Materials with the same impact
 * model share one calibration.  Also the report of the values (JSON member
 * "rolling_resistance" and the summary's lines). */
#include "trajectory/traj_internal.h"
#include "trajectory/traj_rolling.h"

#include "rockfuzz/impact_model.h"

#include <math.h>
#include <string.h>

const char *traj_rolling_source_name(int source)
{
    static const char *const names[] = {"file", "default", "derived from impact model",
                                        "rock impact model (no soil layer): the file's value"};
    return source >= 0 && source < 4 ? names[source] : "?";
}

/* Why material k's value cannot be derived (NULL: it can), into why[size]. */
static const char *not_derivable(const rf_traj_spec *s, const traj_impact_setup *setup, char *why, size_t size)
{
    if (setup->solver != (int)RF_IMPACT_FEM)
        snprintf(why, size, "solver %s has no soil layer", traj_impact_solver_name((size_t)setup->solver));
    else if (!(traj_impact_layer_thickness(&setup->ground) > 0))
        snprintf(why, size, "layer_thickness 0: rock only, which a rigid block does not plough");
    else if (!s->sphere || s->block_kind != RF_TRAJ_BLOCK_NONE)
        snprintf(why, size, "the block is not a sphere (the model needs its radius)");
    else
        return NULL;
    return why;
}

/* An earlier material j < k of the same impact model, already derived, or SIZE_MAX. */
static size_t same_ground(const rf_traj_spec *s, size_t k, const char *key)
{
    for (size_t j = 0; j < k; j++) {
        traj_impact_setup o;
        rf_error e;
        char other[512];
        if (s->materials[j].impact.rolling_source != TRAJ_ROLLING_DERIVED ||
            traj_impact_setup_material(&o, s, j, &e) != RF_OK)
            continue;
        traj_impact_setup_key(&o, other, sizeof other);
        if (!strcmp(other, key))
            return j;
    }
    return SIZE_MAX;
}

static rf_status derive(rf_traj_spec *s, size_t k, const traj_impact_setup *setup, FILE *log, rf_error *err)
{
    rf_traj_material *m = &s->materials[k];
    char key[512];
    traj_impact_setup_key(setup, key, sizeof key);
    size_t j = same_ground(s, k, key);
    if (j != SIZE_MAX) {
        m->rolling_resistance = s->materials[j].rolling_resistance;
        m->impact.rolling_sinkage = s->materials[j].impact.rolling_sinkage;
        m->impact.rolling_source = TRAJ_ROLLING_DERIVED;
        return RF_OK;
    }
    traj_rolling_calibration cal;
    rf_status st = traj_rolling_calibrate(setup, s->gravity, &cal, err);
    if (st != RF_OK)
        return rf_error_prefix(err, "materials.%s", m->name);
    m->rolling_resistance = cal.r.mu_r;
    m->impact.rolling_sinkage = cal.r.sinkage;
    m->impact.rolling_source = TRAJ_ROLLING_DERIVED;
    if (log)
        fprintf(log, "Rolling resistance of %s: %.4g (derived from impact model: rut depth %.4g m under the "
                     "%g m sphere, weight %.4g N, resistance %.4g N; FE indentation at %g m/s to %.4g m, "
                     "F = %.4g N d^%.3g (rms %.2g in log), %.1f s wall)\n",
                m->name, cal.r.mu_r, cal.r.sinkage, setup->radius, cal.r.weight, cal.r.force, cal.speed,
                cal.depth_max, cal.fit_A, cal.fit_m, cal.fit_rms, cal.wall);
    return RF_OK;
}

rf_status rf_traj_rolling_resolve(rf_traj_spec *s, FILE *log, rf_error *err)
{
    for (size_t k = 0; k < s->n_materials; k++) {
        rf_traj_material *m = &s->materials[k];
        m->impact.rolling_source = m->impact.rolling_given ? TRAJ_ROLLING_FILE : TRAJ_ROLLING_DEFAULT;
        if (m->impact.rolling_given || s->law != RF_BOUNCE_IMPACT_MODEL || !m->impact.given)
            continue;
        traj_impact_setup setup;
        rf_status st = traj_impact_setup_material(&setup, s, k, err);
        if (st != RF_OK)
            return st;
        char why[200];
        if (not_derivable(s, &setup, why, sizeof why)) {
            m->impact.rolling_source = TRAJ_ROLLING_ROCK;
            if (log)
                fprintf(log, "Rolling resistance of %s: %g, the file's (not derived from its impact model: %s)\n",
                        m->name, m->rolling_resistance, why);
            continue;
        }
        if ((st = derive(s, k, &setup, log, err)) != RF_OK)
            return st;
    }
    return RF_OK;
}

void traj_rolling_json(FILE *f, const rf_traj_spec *s)
{
    fputs(",\n \"rolling_resistance\": {", f);
    for (size_t k = 0; k < s->n_materials; k++) {
        const rf_traj_material *m = &s->materials[k];
        fputs(k ? ", " : "", f);
        fprintf(f, "\"%s\": {\"value\": %.6g, \"unit\": \"-\", \"source\": \"%s\"", m->name, m->rolling_resistance,
                traj_rolling_source_name(m->impact.rolling_source));
        if (m->impact.rolling_source == TRAJ_ROLLING_DERIVED)
            fprintf(f, ", \"rut_depth_m\": %.6g", m->impact.rolling_sinkage);
        fputc('}', f);
    }
    fputc('}', f);
}

void traj_rolling_summary(FILE *f, const rf_traj_spec *s)
{
    for (size_t k = 0; k < s->n_materials; k++) {
        const rf_traj_material *m = &s->materials[k];
        if (m->impact.rolling_source == TRAJ_ROLLING_DERIVED)
            fprintf(f, "  rolling resistance of %s: %.4g (derived from impact model; rut depth %.4g m)\n", m->name,
                    m->rolling_resistance, m->impact.rolling_sinkage);
        else if (m->impact.rolling_source == TRAJ_ROLLING_ROCK)
            fprintf(f, "  rolling resistance of %s: %.4g (%s)\n", m->name, m->rolling_resistance,
                    traj_rolling_source_name(m->impact.rolling_source));
    }
}
