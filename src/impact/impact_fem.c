/* impact_fem.c - see impact_fem.h. */
#include "impact/impact_fem.h"

#ifdef RF_HAVE_FEM
void rf_impact_fem_options_(const rf_impact_model_spec *spec, rf_fem_options *opt)
{
    rf_fem_options_default(opt);
    opt->refinement = spec->fem_refinement;
    opt->domain_factor = spec->fem_domain_factor;
    opt->boundary = spec->fem_boundary == RF_IMPACT_BOUNDARY_ABSORBING ? RF_FEM_BOUNDARY_ABSORBING
                                                                       : RF_FEM_BOUNDARY_FIXED;
    opt->threads = spec->fem_threads;
    opt->vtk_dir = spec->fem_vtk_dir;
}
#else
typedef int rf_impact_fem_unused_; /* ISO C forbids an empty translation unit */
#endif
