/* validate_fem3d.c - command-line driver of rf_fem3d_impact_ex (and, for
 * comparison, rf_fem_impact) for docs/validation-3d.md.  One impact per call:
 *   validate_fem3d [key=value ...]
 * keys: v (m/s), angle (deg), f (friction), r0 (m), c, d (spheroid axes, m),
 *       ref (a/h), dom (L/r0), bc (fixed|absorbing), ratio (boulder/slope
 *       element size), end (s), threads, full (0|1), core, elong, aspect,
 *       inner, dtsafety, axi (1 = run the axisymmetric solver instead),
 *       hist=file.csv
 * Prints one line "key=value ..." with outputs and diagnostics. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/util.h"
#include "rockfuzz/fem3d.h"
#include "fem/fem_tuning.h"


int main(int argc, char **argv)
{
    rf_impact_input in = {.radius = 1, .boulder_density = 2600, .slope_density = 2600, .boulder_E = 68.2e9,
                          .slope_E = 68.2e9, .boulder_poisson = 0.25, .slope_poisson = 0.25, .velocity = 10};
    rf_fem_options o;
    rf_fem_tuning tu; /* the numerics (fem_tune) */
    rf_fem_options_default(&o);
    o.domain_factor = 10; /* the documented runs use the seed paper's 10 r0; dom=0 = automatic */
    o.refinement = 6;
    rf_fem3d_options o3;
    rf_fem3d_options_default(&o3);
    const char *histfile = NULL;
    int axi = 0;
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
        if (!strcmp(key, "v"))
            in.velocity = x;
        else if (!strcmp(key, "angle"))
            in.slope_angle = x * RF_PI / 180;
        else if (!strcmp(key, "f"))
            in.friction = x;
        else if (!strcmp(key, "r0"))
            in.radius = x;
        else if (!strcmp(key, "c"))
            in.horizontal_axis = x;
        else if (!strcmp(key, "d"))
            in.vertical_axis = x;
        else if (!strcmp(key, "ref"))
            o.refinement = x;
        else if (!strcmp(key, "dom"))
            o.domain_factor = x;
        else if (!strcmp(key, "bc"))
            o.boundary = !strcmp(val, "absorbing") ? RF_FEM_BOUNDARY_ABSORBING : RF_FEM_BOUNDARY_FIXED;
        else if (!strcmp(key, "ratio"))
            fem_tune(&o, &tu)->boulder_mesh_ratio = x;
        else if (!strcmp(key, "end"))
            o.end_time = x;
        else if (!strcmp(key, "threads"))
            o.threads = (int)x;
        else if (!strcmp(key, "dtsafety"))
            fem_tune(&o, &tu)->dt_safety = x;
        else if (!strcmp(key, "full"))
            o3.full_model = (int)x;
        else if (!strcmp(key, "core"))
            o3.fine_box_factor = x;
        else if (!strcmp(key, "elong"))
            o3.elongation = x;
        else if (!strcmp(key, "aspect"))
            o3.layer_aspect = x;
        else if (!strcmp(key, "inner"))
            o3.boulder_inner = x;
        else if (!strcmp(key, "axi"))
            axi = (int)x;
        else if (!strcmp(key, "hist"))
            histfile = val;
        else {
            fprintf(stderr, "unknown key %s\n", key);
            return 2;
        }
    }
    rf_impact_output out;
    rf_fem_history h;
    rf_fem3d_report rep;
    memset(&rep, 0, sizeof rep);
    rf_error err = {0};
    rf_status st = axi ? rf_fem_impact(&in, &o, &out, &h, &err) : rf_fem3d_impact_ex(&in, &o, &o3, &out, &h, &rep, &err);
    if (st != RF_OK) {
        printf("error=%s msg=\"%s\"\n", rf_status_name(st), err.msg);
        return 1;
    }
    rf_impact_output rig;
    double e_n = out.R_n;
    int have_rigid = rf_impact_rigid(&in, e_n, &rig, &err) == RF_OK;
    printf("F=%.6e comp=%.6e tc=%.6e a=%.6e Rn=%.6f Rt=%.6f Rke=%.6f vn=%.5f vt=%.5f w=%.5f "
           "err=%.3e steps=%.0f elems=%.0f nodes=%.0f wall=%.2f dt=%.4e dtedge=%.4e h=%.4e aH=%.5e tH=%.5e pen=%.3e "
           "slip=%.3e fric=%.5e Wn=%.3e cpv=%.4f Ilump=%.5e Iexact=%.5e stick=%.3f sweeps=%d res=%.2e hash=%016llx "
           "vib=%.4e slopeE=%.4e ke0=%.5e",
           out.contact_force_max, out.compression_max, out.contact_duration, out.contact_radius, out.R_n, out.R_t,
           out.R_ke, out.v_n_after, out.v_t_after, out.omega_after, out.energy_error, out.steps, out.elements,
           out.nodes, out.wall_seconds, h.dt, h.dt_edge, h.h_contact, h.hertz_radius, h.hertz_duration,
           h.penetration_max, h.slip_max, rep.friction_work, rep.normal_work, rep.contact_point_velocity,
           rep.inertia_lumped, rep.inertia_exact, rep.stick_fraction, rep.pgs_sweeps_max, rep.pgs_residual_max,
           (unsigned long long)rep.state_hash, h.vibration_energy, h.slope_energy, h.ke0);
    if (have_rigid)
        printf(" rigid_Rt=%.6f rigid_w=%.5f rigid_Rke=%.6f", rig.R_t, rig.omega_after, rig.R_ke);
    printf("\n");
    if (h.warning[0])
        fprintf(stderr, "warning: %s\n", h.warning);
    if (histfile) {
        FILE *fp = fopen(histfile, "w");
        if (fp) {
            fprintf(fp, "t,force,compression,radius,ke_b,se_b,ke_s,se_s,contact_work,absorbed,closure,vn,friction\n");
            for (size_t k = 0; k < h.n; k++)
                fprintf(fp, "%.8e,%.8e,%.8e,%.8e,%.8e,%.8e,%.8e,%.8e,%.8e,%.8e,%.8e,%.8e,%.8e\n", h.t[k],
                        h.contact_force[k], h.compression[k], h.contact_radius[k], h.kinetic_boulder[k],
                        h.strain_boulder[k], h.kinetic_slope[k], h.strain_slope[k], h.contact_work[k], h.absorbed[k],
                        h.closure[k], h.boulder_velocity[k], k < rep.n ? rep.friction_series[k] : 0.0);
            fclose(fp);
        }
    }
    rf_fem_history_free(&h);
    rf_fem3d_report_free(&rep);
    return 0;
}
