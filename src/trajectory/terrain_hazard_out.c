/* terrain_hazard_out.c - what is read from the hazard accumulators
 * (terrain_hazard_internal.h): merge, packed words (MPI), size, grid and
 * the raster bands. */
#include "trajectory/terrain_hazard_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void terrain_hazard_merge(rf_terrain_hazard *into, const rf_terrain_hazard *from)
{
    if (!into || !from)
        return;
    hz_pend_flush(into), hz_pend_flush_const(from);
    if (into->nx != from->nx || into->ny != from->ny || from->nomem) {
        into->nomem = 1; /* not the same grid (a bug) or an incomplete part: refuse the bands */
        return;
    }
    for (size_t k = 0; k < from->n_rec; k++) {
        const hz_rec *f = &from->rec[k];
        uint32_t m = hz_record_at(into, f->cell);
        if (m == NO_POS)
            return;
        hz_rec *r = &into->rec[m];
        r->passages += f->passages, r->deposits += f->deposits;
        r->e_max = max_of(r->e_max, f->e_max), r->h_max = max_of(r->h_max, f->h_max);
        into->nomem |= !hz_hist_merge(&r->e, &f->e) || !hz_hist_merge(&r->h, &f->h);
    }
}

/* ---- packed accumulators (MPI) ---- */

/* Layout, 64-bit words in the machine's byte order: magic, nx, ny, n_rec;
 * per record: cell | n_e << 32, n_h, passages, deposits, e_max, h_max (the
 * doubles' bits), then the n_e + n_h histogram words. */
#define PACK_MAGIC UINT64_C(0x31465a4852525446) /* "FTRRHZF1" */

static size_t pack_words(const rf_terrain_hazard *h)
{
    size_t n = 4;
    for (size_t k = 0; k < h->n_rec; k++)
        n += 6 + (size_t)h->rec[k].e.n + h->rec[k].h.n;
    return n;
}

rf_status terrain_hazard_pack(const rf_terrain_hazard *h, uint64_t **buf, size_t *words, rf_error *err)
{
    *buf = NULL, *words = 0;
    hz_pend_flush_const(h);
    if (h->nomem)
        return rf_fail(err, RF_ENOMEM, "out of memory while accumulating the hazard rasters");
    size_t n = pack_words(h), w = 0;
    uint64_t *b = malloc(n * sizeof *b);
    if (!b)
        return rf_fail(err, RF_ENOMEM, "out of memory packing the hazard rasters (%zu bytes)", n * sizeof *b);
    b[w++] = PACK_MAGIC, b[w++] = h->nx, b[w++] = h->ny, b[w++] = h->n_rec;
    for (size_t k = 0; k < h->n_rec; k++) {
        const hz_rec *r = &h->rec[k];
        b[w++] = r->cell | (uint64_t)r->e.n << 32, b[w++] = r->h.n;
        b[w++] = r->passages, b[w++] = r->deposits;
        memcpy(&b[w++], &r->e_max, sizeof r->e_max), memcpy(&b[w++], &r->h_max, sizeof r->h_max);
        for (uint32_t e = 0; e < r->e.n; e++)
            b[w++] = r->e.v[e];
        for (uint32_t e = 0; e < r->h.n; e++)
            b[w++] = r->h.v[e];
    }
    *buf = b, *words = n;
    return RF_OK;
}

rf_status terrain_hazard_merge_packed(rf_terrain_hazard *into, const uint64_t *b, size_t words, rf_error *err)
{
    if (words < 4 || b[0] != PACK_MAGIC || b[1] != into->nx || b[2] != into->ny)
        return rf_fail(err, RF_EINVAL, "packed hazard rasters: not a %zu x %zu grid's accumulator", into->nx,
                       into->ny);
    size_t w = 4;
    hz_pend_flush(into);
    rf_terrain_hazard one = *into; /* a one-record accumulator over the packed words */
    one.pend = one.pend_tmp = NULL, one.n_pend = 0;
    for (uint64_t k = 0; k < b[3]; k++) {
        if (words - w < 6 || (b[w] & 0xffffffffu) >= into->nx * into->ny ||
            (b[w] >> 32) + b[w + 1] > words - w - 6)
            return rf_fail(err, RF_EINVAL, "packed hazard rasters: record %llu is cut or out of the grid",
                           (unsigned long long)k);
        hz_rec r = {b[w + 2], b[w + 3], 0, 0, {NULL, 0, 0}, {NULL, 0, 0}, (uint32_t)(b[w] & 0xffffffffu), NO_POS};
        memcpy(&r.e_max, &b[w + 4], sizeof r.e_max), memcpy(&r.h_max, &b[w + 5], sizeof r.h_max);
        r.e.n = (uint32_t)(b[w] >> 32), r.h.n = (uint32_t)b[w + 1];
        r.e.v = (uint64_t *)(b + w + 6), r.h.v = (uint64_t *)(b + w + 6 + r.e.n);
        w += 6 + (size_t)r.e.n + r.h.n;
        one.rec = &r, one.n_rec = 1, one.nomem = 0;
        terrain_hazard_merge(into, &one);
    }
    if (into->nomem)
        return rf_fail(err, RF_ENOMEM, "out of memory merging packed hazard rasters");
    return RF_OK;
}

void terrain_hazard_free(rf_terrain_hazard *h)
{
    if (!h)
        return;
    for (size_t k = 0; k < h->n_rec; k++)
        free(h->rec[k].e.v), free(h->rec[k].h.v);
    free(h->rec), free(h->touch), free(h->slot), free(h->pend), free(h->pend_tmp), free(h);
}

size_t terrain_hazard_bytes(const rf_terrain_hazard *h)
{
    hz_pend_flush_const(h);
    size_t n = sizeof *h + h->nx * h->ny * sizeof *h->slot + h->cap_rec * sizeof *h->rec +
               h->cap_touch * sizeof *h->touch + (h->pend ? 2 * PEND_MAX * sizeof *h->pend : 0);
    for (size_t k = 0; k < h->n_rec; k++)
        n += ((size_t)h->rec[k].e.cap + h->rec[k].h.cap) * sizeof(uint64_t);
    return n;
}

void terrain_hazard_grid(const rf_terrain_hazard *h, size_t *nx, size_t *ny, double *x0, double *y0, double *cell)
{
    *nx = h->nx, *ny = h->ny, *x0 = h->x0, *y0 = h->y0, *cell = h->cell;
}

/* ---- bands ---- */

enum { B_PASSAGES, B_REACH, B_DEPOSITS, B_MAX, B_PERCENTILE };

typedef struct {
    int kind;                   /* B_* */
    int height;                 /* energy (0) or height (1) statistics */
    double level;               /* [%] for B_PERCENTILE */
} hz_band_def;

static float band_value(const hz_rec *r, const hz_band_def *b, size_t samples)
{
    const hz_hist *hh = b->height ? &r->h : &r->e;
    double vmax = b->height ? r->h_max : r->e_max;
    switch (b->kind) {
    case B_PASSAGES:
        return (float)r->passages;
    case B_REACH:
        return samples ? (float)((double)r->passages / (double)samples) : 0.0f;
    case B_DEPOSITS:
        return (float)r->deposits;
    case B_MAX:
        return hh->n ? (float)vmax : NAN;
    default:
        return hh->n ? (float)hz_hist_quantile(hh, vmax, b->level / 100) : NAN;
    }
}

/* The list of bands the spec asks for, with their names. */
static size_t band_defs(unsigned stats, const rf_traj_spec *s, hz_band_def *def, char (*name)[48])
{
    static const double dflt[3] = {50, 95, 99};
    size_t nl = s && s->outputs.n_percentiles ? s->outputs.n_percentiles : 3;
    const double *lv = s && s->outputs.n_percentiles ? s->outputs.percentiles : dflt;
    size_t n = 0;
    static const char *simple[3] = {"passages", "reach_probability", "deposits"};
    static const unsigned bit[3] = {RF_TERRAIN_PASSAGES, RF_TERRAIN_REACH_PROBABILITY, RF_TERRAIN_DEPOSITS};
    for (int k = 0; k < 3; k++)
        if (stats & bit[k]) {
            def[n] = (hz_band_def){k, 0, 0};
            snprintf(name[n++], 48, "%s", simple[k]);
        }
    for (int ht = 0; ht < 2; ht++) {
        if (!(stats & (ht ? RF_TERRAIN_HEIGHT : RF_TERRAIN_ENERGY)))
            continue;
        const char *what = ht ? "height" : "energy";
        def[n] = (hz_band_def){B_MAX, ht, 0};
        snprintf(name[n++], 48, "%s_max", what);
        for (size_t l = 0; l < nl; l++) {
            char p[24];
            rf_traj_percentile_name(lv[l], p, sizeof p);
            def[n] = (hz_band_def){B_PERCENTILE, ht, lv[l]};
            snprintf(name[n++], 48, "%s_%s", what, p);
        }
    }
    return n;
}

rf_status terrain_hazard_bands(const rf_terrain_hazard *h, const rf_traj_spec *s, size_t samples, terrain_band **bands,
                               size_t *n, rf_error *err)
{
    *bands = NULL, *n = 0;
    hz_pend_flush_const(h);
    if (h->nomem)
        return rf_fail(err, RF_ENOMEM, "out of memory while accumulating the hazard rasters");
    hz_band_def def[3 + 2 * (1 + RF_TRAJ_MAX_PERCENTILES)];
    char name[3 + 2 * (1 + RF_TRAJ_MAX_PERCENTILES)][48];
    size_t nb = band_defs(h->stats, s, def, name), cells = h->nx * h->ny;
    terrain_band *b = calloc(nb ? nb : 1, sizeof *b);
    if (!b)
        return rf_fail(err, RF_ENOMEM, "out of memory for the hazard raster bands");
    for (size_t k = 0; k < nb; k++) {
        memcpy(b[k].name, name[k], sizeof b[k].name);
        b[k].unit = def[k].kind < B_MAX ? "" : def[k].height ? "m" : "J";
        b[k].data = malloc(cells * sizeof *b[k].data);
        if (!b[k].data) {
            terrain_bands_free(b, nb);
            return rf_fail(err, RF_ENOMEM, "out of memory for the hazard raster bands (%zu cells)", cells);
        }
        float none = def[k].kind < B_MAX ? 0.0f : NAN;
        for (size_t c = 0; c < cells; c++)
            b[k].data[c] = none;
        for (size_t r = 0; r < h->n_rec; r++)
            b[k].data[h->rec[r].cell] = band_value(&h->rec[r], &def[k], samples);
    }
    *bands = b, *n = nb;
    return RF_OK;
}

void terrain_bands_free(terrain_band *b, size_t n)
{
    for (size_t k = 0; b && k < n; k++)
        free(b[k].data);
    free(b);
}
