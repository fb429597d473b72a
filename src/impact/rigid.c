/* rigid.c - the rigid-body solver's registry entry (rf_impact_law, impact.h):
 * the oblique impact of rigid_kinematics.c with the normal COR given, or
 * Hunter's e_n of the input (hertz.c) when it is not.  A file of its own so
 * that rigid_kinematics.c, which hertz.c uses, does not use hertz.c back. */
#include "impact/impact_internal.h"

#include <math.h>

/* e_n = NaN: Hunter's e_n of the input. */
static rf_status rigid_solve(const rf_impact_input *in, const rf_impact_law_settings *s, rf_impact_output *out,
                             rf_error *err)
{
    double e_n = s->e_n;
    if (isnan(e_n)) {
        rf_impact_output h;
        rf_status st = rf_impact_hunter_A(in, s->hunter_coefficient, &h, err);
        if (st != RF_OK) {
            rf_impact_output_clear(out);
            return st;
        }
        e_n = h.R_n;
    }
    return rf_impact_rigid(in, e_n, out, err);
}

const rf_impact_law rf_impact_law_rigid = {"rigid", "rigid-body impact with Coulomb friction",
                                           rf_impact_analytic_validate, rigid_solve,
                                           rf_impact_en_identity};
