/* fem_dispatch.c - rf_fem_solve: the one place that decides which FE model an
 * impact needs (rf_fem_needs_3d) and runs it, for the impact model and the
 * command line alike. */
#include "rockfuzz/fem3d.h"

#include <stddef.h>

rf_status rf_fem_solve(const rf_impact_input *in, const rf_fem_options *opt, rf_impact_output *out,
                       rf_fem_history *hist, double *friction_work, int *three_d, rf_error *err)
{
    return rf_fem_solve_ws(NULL, in, opt, out, hist, friction_work, three_d, err);
}

rf_status rf_fem_solve_ws(rf_fem_workspace *ws, const rf_impact_input *in, const rf_fem_options *opt,
                          rf_impact_output *out, rf_fem_history *hist, double *friction_work, int *three_d,
                          rf_error *err)
{
    if (!in)
        return rf_fail(err, RF_EINVAL, "fem: NULL input");
    int want_3d = rf_fem_needs_3d(in);
    if (three_d)
        *three_d = want_3d;
    if (friction_work)
        *friction_work = 0.0;
    /* the 3D model refuses what it cannot do (gravity, a spheroid on a slope, ...) with its own message */
    if (!want_3d) { /* the axisymmetric model: its friction work is in the history */
        rf_fem_history local, *h = hist ? hist : friction_work ? &local : NULL;
        rf_status st = ws ? rf_fem_impact_ws(ws, in, opt, out, h, err) : rf_fem_impact(in, opt, out, h, err);
        if (friction_work && st == RF_OK)
            *friction_work = h->friction_work;
        if (h == &local && st == RF_OK)
            rf_fem_history_free(&local);
        return st;
    }
    rf_fem_options o;
    if (opt)
        o = *opt;
    else
        rf_fem_options_default(&o);
    rf_fem3d_report rep = {0};
    rf_fem3d_report *r = friction_work ? &rep : NULL;
    rf_status st = ws ? rf_fem3d_impact_ws(ws, in, &o, NULL, out, hist, r, err)
                      : rf_fem3d_impact_ex(in, &o, NULL, out, hist, r, err);
    if (friction_work)
        *friction_work = rep.friction_work;
    rf_fem3d_report_free(&rep);
    return st;
}
