/* impact_fem.c - see impact_fem.h. */
#include "impact/impact_fem.h"

#include <math.h>

int rf_impact_fem_needs_3d_(const rf_impact_input *in)
{
    if (in->slope_angle != 0.0)
        return 1;
    if (!(in->friction > 0.0))
        return 0;
    /* Dundurs' second parameter: zero when a normal contact causes no
     * tangential traction (identical elastic constants, among others). */
    double g1 = in->boulder_E / (2.0 * (1.0 + in->boulder_poisson));
    double g2 = in->slope_E / (2.0 * (1.0 + in->slope_poisson));
    double num = g1 * (1.0 - 2.0 * in->slope_poisson) - g2 * (1.0 - 2.0 * in->boulder_poisson);
    double den = 2.0 * g1 * (1.0 - in->slope_poisson) + 2.0 * g2 * (1.0 - in->boulder_poisson);
    return fabs(num / den) > 1e-12;
}

double rf_impact_fem_refinement_(const rf_impact_model_spec *spec, int three_d)
{
    if (spec->fem_refinement > 0.0)
        return spec->fem_refinement;
    return three_d ? RF_IMPACT_FEM_REFINEMENT_3D : RF_IMPACT_FEM_REFINEMENT_AXI;
}

#ifdef RF_HAVE_FEM
void rf_impact_fem_options_(const rf_impact_model_spec *spec, int three_d, rf_fem_options *opt)
{
    rf_fem_options_default(opt);
    opt->refinement = rf_impact_fem_refinement_(spec, three_d);
    opt->domain_factor = spec->fem_domain_factor;
    opt->boundary = spec->fem_boundary == RF_IMPACT_BOUNDARY_ABSORBING ? RF_FEM_BOUNDARY_ABSORBING
                                                                       : RF_FEM_BOUNDARY_FIXED;
    opt->threads = spec->fem_threads;
    opt->vtk_dir = three_d ? NULL : spec->fem_vtk_dir; /* the 3D model writes no VTK */
}

rf_status rf_impact_fem_run_(const rf_impact_model_spec *spec, const rf_impact_input *in, rf_impact_output *out,
                             rf_fem_history *hist, double *friction_work, int *three_d, rf_error *err)
{
    int want_3d = rf_impact_fem_needs_3d_(in);
    rf_fem_options opt;
    rf_impact_fem_options_(spec, want_3d, &opt);
    if (three_d)
        *three_d = want_3d;
    if (friction_work)
        *friction_work = 0.0;
    if (!want_3d)
        return rf_fem_impact(in, &opt, out, hist, err);
#ifdef RF_HAVE_FEM3D
    rf_fem3d_report rep = {0};
    rf_status st = rf_fem3d_impact_ex(in, &opt, NULL, out, hist, friction_work ? &rep : NULL, err);
    if (friction_work)
        *friction_work = rep.friction_work;
    rf_fem3d_report_free(&rep);
    return st;
#else
    return rf_fail(err, RF_EINVAL, "an inclined slope or friction needs the 3D FE solver, which is not built");
#endif
}
#endif
