/* fem_tune.h - TUNE(o): the internal numerics (src/fem/fem_tuning.h) of the
 * options o for a test or benchmark, TUNE(o).dt_safety = 0.5.  Each options
 * struct gets its own tuning (a slot keyed by its address, filled with the
 * defaults whenever o has none: rf_fem_options_default clears it). */
#ifndef ROCKFUZZ_TEST_FEM_TUNE_H
#define ROCKFUZZ_TEST_FEM_TUNE_H

#include "fem/fem_tuning.h"

static inline rf_fem_tuning *fem_tune_slot(rf_fem_options *o)
{
    static struct {
        const rf_fem_options *o;
        rf_fem_tuning t;
    } slot[8];
    static unsigned next;
    unsigned k = 0;
    while (k < 8 && slot[k].o != o)
        k++;
    if (k == 8) {
        k = next++ % 8;
        slot[k].o = o;
        if (o->tuning == &slot[k].t)
            o->tuning = NULL;
    }
    return fem_tune(o, &slot[k].t);
}
#define TUNE(o) (*fem_tune_slot(&(o)))

#endif
