/* tm_internal.h - the data the TM keeps after a run, shared by tm.c (grids,
 * cache, retransformation) and analysis.c (influence measures).
 *
 * Every grid value of input i is stored once in values[i] (values closer
 * than cache_rtol are merged); a grid point is a tuple of value indices, and
 * every distinct tuple is one point id, evaluated once.  A grid is a
 * Cartesian product of per-input index lists, enumerated in mixed radix with
 * input 0 most significant (tm_spec s.2.2). */
#ifndef ROCKFUZZ_TM_INTERNAL_H
#define ROCKFUZZ_TM_INTERNAL_H

#include <stdint.h>

#include "rockfuzz/tm.h"

typedef struct {
    size_t *radix;     /* [n] number of values of input i */
    size_t *stride;    /* [n] mixed-radix stride of input i inside the grid */
    uint32_t **vidx;   /* [n][radix[i]] ascending value indices */
    size_t *nominal_pos; /* [n] position of the nominal value in vidx[i] (three-point grid only) */
    uint32_t *ids;     /* [count] point id of every grid point */
    size_t count;
} rf_grid;

struct rf_tm_data {
    size_t n, m, n_out;
    double **values;     /* [n][nvalues[i]] distinct grid values of input i */
    size_t *nvalues, *capvalues;
    double *scale;       /* [n] merge scale of input i (support width or |value|) */
    double rtol;

    /* point table */
    uint32_t *tuples;    /* [npoints * n] */
    size_t npoints, cappoints;
    uint64_t *stride64;  /* [n] perfect-hash strides, or NULL if the product overflows */
    struct rf_tm_slot {
        uint64_t key;
        uint32_t id;     /* UINT32_MAX = empty */
    } *slots;            /* open addressing, linear probing, load <= 1/2 */
    size_t nslots;

    double *y;           /* [npoints * n_out] outputs */

    rf_grid *main;       /* [m+1] grids of the chosen form, level j */
    rf_grid *lr;         /* [m+1] three-point grids (levels 0..m), or NULL */
    uint32_t nominal_id;
};

#endif
