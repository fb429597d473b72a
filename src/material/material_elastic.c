/* material_elastic.c - isotropic linear elasticity: the law with no return
 * (the elastic predictor of rf_material_update is the answer) and no
 * parameters besides E and poisson. */
#include "material/material_internal.h"

#include <math.h>
#include <string.h>

static void elastic_return(const rf_material *m, const rf_material_state *st, const double s_tr[6],
                           double p_tr, mat_return *r)
{
    (void)m, (void)st;
    memcpy(r->s, s_tr, sizeof r->s);
    r->p = p_tr;
}

static double elastic_yield(const rf_material *m, double sj2, double p, const rf_material_state *st)
{
    (void)m, (void)sj2, (void)p, (void)st;
    return -HUGE_VAL;
}

static int elastic_admissible(const rf_material *m, double sj2, double p, const rf_material_state *st,
                              double tol)
{
    (void)m, (void)sj2, (void)p, (void)st, (void)tol;
    return 1;
}

const mat_law mat_law_elastic = {
    {"elastic", "isotropic linear elasticity", NULL, 0},
    NULL, NULL, elastic_return, NULL, elastic_yield, elastic_admissible,
};
