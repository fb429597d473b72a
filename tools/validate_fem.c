/* validate_fem.c - command-line driver of rf_fem_impact for the validation
 * study (docs/validation.md).  One impact per invocation:
 *   validate_fem [key=value ...]
 * keys: v (m/s), r0 (m), c, d (spheroid axes, m), ref (a/h), dom (L/r0),
 *       bc (fixed|absorbing), ratio (boulder/slope element size), end (s),
 *       threads, dtsafety, grading, core, hist=file.csv, vtk=dir
 * Prints one line "key=value ..." with the FE outputs, the Hertz references
 * and diagnostics; hist=... writes the time series as CSV. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/util.h"
#include "rockfuzz/fem.h"
#include "fem/fem_tuning.h"

int main(int argc, char **argv)
{
    rf_impact_input in = {.radius = 1, .boulder_density = 2600, .slope_density = 2600, .boulder_E = 68.2e9,
                          .slope_E = 68.2e9, .boulder_poisson = 0.25, .slope_poisson = 0.25, .velocity = 10};
    rf_fem_options o;
    rf_fem_tuning tu; /* the numerics (fem_tune) */
    rf_fem_options_default(&o);
    o.domain_factor = 10; /* the documented runs use the seed paper's 10 r0; dom=0 = automatic */
    const char *histfile = NULL;
    for (int i = 1; i < argc; i++) {
        char key[64];
        const char *eq = strchr(argv[i], '=');
        if (!eq || eq - argv[i] >= (long)sizeof key) {
            fprintf(stderr, "bad argument %s\n", argv[i]);
            return 2;
        }
        memcpy(key, argv[i], (size_t)(eq - argv[i]));
        key[eq - argv[i]] = 0;
        const char *val = eq + 1;
        double x = atof(val);
        if (!strcmp(key, "v")) in.velocity = x;
        else if (!strcmp(key, "r0")) in.radius = x;
        else if (!strcmp(key, "c")) in.horizontal_axis = x;
        else if (!strcmp(key, "d")) in.vertical_axis = x;
        else if (!strcmp(key, "Es")) in.slope_E = x;
        else if (!strcmp(key, "angle")) in.slope_angle = x;
        else if (!strcmp(key, "ref")) o.refinement = x;
        else if (!strcmp(key, "dom")) o.domain_factor = x;
        else if (!strcmp(key, "bc")) o.boundary = !strcmp(val, "absorbing") ? RF_FEM_BOUNDARY_ABSORBING : RF_FEM_BOUNDARY_FIXED;
        else if (!strcmp(key, "ratio")) fem_tune(&o, &tu)->boulder_mesh_ratio = x;
        else if (!strcmp(key, "end")) o.end_time = x;
        else if (!strcmp(key, "threads")) o.threads = (int)x;
        else if (!strcmp(key, "dtsafety")) fem_tune(&o, &tu)->dt_safety = x;
        else if (!strcmp(key, "grading")) fem_tune(&o, &tu)->grading = x;
        else if (!strcmp(key, "core")) fem_tune(&o, &tu)->fine_zone_factor = x;
        else if (!strcmp(key, "hist")) histfile = val;
        else if (!strcmp(key, "vtk")) o.vtk_dir = val;
        else {
            fprintf(stderr, "unknown key %s\n", key);
            return 2;
        }
    }
    rf_impact_output out;
    rf_fem_history h;
    rf_error err = {0};
    if (rf_fem_impact(&in, &o, &out, &h, &err) != RF_OK) {
        fprintf(stderr, "error: %s\n", err.msg);
        return 1;
    }
    /* Hertz reference (impact_refs.md 1.1), computed independently of the solver */
    double c = in.radius, d = in.radius;
    if (in.horizontal_axis > 0) {
        c = in.horizontal_axis;
        d = in.vertical_axis > 0 ? in.vertical_axis : pow(in.radius, 3) / (c * c);
    }
    double R = c * c / d, m = 4.0 / 3.0 * RF_PI * c * c * d * in.boulder_density;
    double Es = 1 / ((1 - 0.0625) / in.boulder_E + (1 - 0.0625) / in.slope_E), V = in.velocity;
    double dH = pow(15 * m * V * V / (16 * Es * sqrt(R)), 0.4), FH = 1.25 * m * V * V / dH;
    double aH = sqrt(R * dH), tH = 2.94328 * dH / V; /* 2 (2/5) B(2/5, 1/2), to 6 digits */
    printf("v=%g ref=%g dom=%g auto=%d bc=%s ratio=%g c=%g d=%g r0=%g a_over_R=%.5f "
           "F=%.6e dF=%.5f delta=%.6e dd=%.5f tc=%.6e dt_c=%.5f a=%.6e da=%.5f "
           "Rn=%.7f Rke=%.7f eerr=%.3e pen_rel=%.3e slip_rel_h=%.3e vib=%.4e slope_E=%.4e lost=%.4e "
           "mesh_mass_rel=%.5f nodes=%.0f elems=%.0f steps=%.0f dt=%.4e dt_bound=%.4e dt_edge=%.4e wall=%.3f "
           "ns_per_es=%.2f warning=\"%s\"\n",
           V, rf_fem_refinement(&o, 0), rf_fem_domain_factor(&o, &in), o.domain_factor == 0, rf_fem_boundary_name(rf_fem_boundary_resolve(o.boundary, &in)), fem_tuning_of(&o)->boulder_mesh_ratio, c, d,
           in.radius, aH / R, out.contact_force_max, out.contact_force_max / FH - 1, out.compression_max,
           out.compression_max / dH - 1, out.contact_duration, out.contact_duration / tH - 1, out.contact_radius,
           out.contact_radius / aH - 1, out.R_n, out.R_ke, out.energy_error,
           h.penetration_max / out.compression_max, h.slip_max / h.h_contact, h.vibration_energy / h.ke0,
           h.slope_energy / h.ke0, (h.ke0 - 0.5 * h.boulder_mass * out.v_n_after * out.v_n_after) / h.ke0,
           h.boulder_mesh_mass / h.boulder_mass - 1, out.nodes, out.elements, out.steps, h.dt, h.dt_bound,
           h.dt_edge, out.wall_seconds, 1e9 * out.wall_seconds / (out.elements * out.steps), h.warning);
    if (histfile) {
        FILE *fp = fopen(histfile, "w");
        if (!fp) {
            perror(histfile);
            return 1;
        }
        fprintf(fp, "t,force,compression,contact_radius,ke_boulder,se_boulder,ke_slope,se_slope,contact_work,"
                    "absorbed,closure,v_boulder\n");
        for (size_t i = 0; i < h.n; i++)
            fprintf(fp, "%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e,%.9e\n", h.t[i],
                    h.contact_force[i], h.compression[i], h.contact_radius[i], h.kinetic_boulder[i],
                    h.strain_boulder[i], h.kinetic_slope[i], h.strain_slope[i], h.contact_work[i], h.absorbed[i],
                    h.closure[i], h.boulder_velocity[i]);
        fclose(fp);
    }
    rf_fem_history_free(&h);
    return 0;
}
