/* raster_store.c - the per-point raster store of a study (fuzzy_raster.h,
 * docs/fuzzy-hazard.md "Store"): DIR/<key>.f32 per evaluated point.
 *
 * File layout (native byte order, the machine that wrote it reads it):
 *   "RFRAST01"                          8 bytes
 *   n_params, n_bands, nx, ny           4 x uint64
 *   x0, y0, cell                        3 x double (south-west corner, cell [m])
 *   crs_len                             uint64, then crs_len bytes of CRS WKT
 *   x[n_params]                         double (the point, checked on read)
 *   per band: name[48], unit[16]        NUL-padded
 *   data[n_bands][ny][nx]               float32, row 0 first
 * A raster is written to DIR/<key>.f32.tmp.<pid>.<n>, flushed to disk and
 * renamed over DIR/<key>.f32: a reader sees the old file, the new one, or
 * none, never a part.  The sink runs inside the evaluation, so the result
 * store commits a point only after its raster is in place. */
#define _POSIX_C_SOURCE 200809L
#include "study/fuzzy_raster.h"
#include "rockfuzz/model.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define MAGIC "RFRAST01"
#define NAME_BYTES 48
#define UNIT_BYTES 16

struct fr_store {
    char dir[PATH_MAX - 64];
    atomic_ulong serial; /* temporary names of concurrent writers */
};

rf_status fr_store_open(const char *dir, fr_store **out, rf_error *err)
{
    *out = NULL;
    if (strlen(dir) >= PATH_MAX - 64)
        return rf_fail(err, RF_EINVAL, "raster store folder name too long: %s", dir);
    /* a missing parent is not an error yet: an MPI worker rank may open the
     * store before rank 0 made the output folder; put creates DIR then */
    if (mkdir(dir, 0777) != 0 && errno != EEXIST && errno != ENOENT)
        return rf_fail(err, RF_EIO, "cannot create the raster store folder %s: %s", dir, strerror(errno));
    fr_store *s = calloc(1, sizeof *s);
    if (!s)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    snprintf(s->dir, sizeof s->dir, "%s", dir);
    atomic_init(&s->serial, 0);
    *out = s;
    return RF_OK;
}

void fr_store_close(fr_store *s) { free(s); }

void fr_store_key(const double *x, size_t n, char key[17])
{
    uint64_t h = 0xcbf29ce484222325ULL; /* FNV-1a 64 */
    for (size_t i = 0; i < n; i++) {
        uint64_t bits;
        memcpy(&bits, &x[i], sizeof bits);
        for (int b = 0; b < 8; b++) {
            h ^= (bits >> (8 * b)) & 0xff;
            h *= 0x100000001b3ULL;
        }
    }
    snprintf(key, 17, "%016llx", (unsigned long long)h);
}

static void raster_path(const fr_store *s, const double *x, size_t n, char *path, size_t size)
{
    char key[17];
    fr_store_key(x, n, key);
    snprintf(path, size, "%s/%s.f32", s->dir, key);
}

#define MAX_CRS 65536

static size_t header_bytes(size_t n, size_t nb, size_t crs_len)
{
    return 8 + 4 * 8 + 3 * 8 + 8 + crs_len + n * sizeof(double) + nb * (NAME_BYTES + UNIT_BYTES);
}

static int write_header(FILE *f, const double *x, size_t n, const terrain_band *bands, size_t nb,
                        const traj_raster_grid *g)
{
    const char *crs = g->crs_wkt ? g->crs_wkt : "";
    uint64_t dims[4] = {n, nb, g->nx, g->ny}, crs_len = strlen(crs);
    double geo[3] = {g->x0, g->y0, g->cell};
    int bad = crs_len > MAX_CRS || fwrite(MAGIC, 1, 8, f) != 8 || fwrite(dims, sizeof dims, 1, f) != 1 ||
              fwrite(geo, sizeof geo, 1, f) != 1 || fwrite(&crs_len, sizeof crs_len, 1, f) != 1 ||
              (crs_len && fwrite(crs, 1, crs_len, f) != crs_len) || (n && fwrite(x, sizeof(double), n, f) != n);
    for (size_t b = 0; !bad && b < nb; b++) {
        char name[NAME_BYTES] = {0}, unit[UNIT_BYTES] = {0};
        snprintf(name, sizeof name, "%s", bands[b].name);
        snprintf(unit, sizeof unit, "%s", bands[b].unit ? bands[b].unit : "");
        bad = fwrite(name, 1, sizeof name, f) != sizeof name || fwrite(unit, 1, sizeof unit, f) != sizeof unit;
    }
    return bad;
}

rf_status fr_store_put(void *store, const double *x, size_t n, const terrain_band *bands, size_t n_bands,
                       const traj_raster_grid *grid, rf_error *err)
{
    size_t nx = grid->nx, ny = grid->ny;
    fr_store *s = store;
    char path[PATH_MAX], tmp[PATH_MAX + 64];
    raster_path(s, x, n, path, sizeof path);
    snprintf(tmp, sizeof tmp, "%s.tmp.%ld.%lu", path, (long)getpid(), atomic_fetch_add(&s->serial, 1));
    FILE *f = fopen(tmp, "wb");
    if (!f && errno == ENOENT && (mkdir(s->dir, 0777) == 0 || errno == EEXIST))
        f = fopen(tmp, "wb");
    if (!f)
        return rf_fail(err, RF_EIO, "cannot write the raster %s: %s", tmp, strerror(errno));
    int bad = write_header(f, x, n, bands, n_bands, grid);
    for (size_t b = 0; !bad && b < n_bands; b++)
        bad = nx * ny > 0 && fwrite(bands[b].data, sizeof(float), nx * ny, f) != nx * ny;
    bad |= fflush(f) != 0 || fsync(fileno(f)) != 0;
    bad |= fclose(f) != 0;
    if (bad || rename(tmp, path) != 0) {
        int e = errno;
        remove(tmp);
        return rf_fail(err, RF_EIO, "cannot write the raster %s: %s", path, strerror(e));
    }
    return RF_OK;
}

/* Open the raster of x and read its header; NULL if missing or not this x's. */
typedef struct {
    FILE *f;
    size_t nb, nx, ny, header;
    double geo[3];
    char *crs;
    char (*names)[NAME_BYTES];
    char (*units)[UNIT_BYTES];
} raster_file;

static void raster_close(raster_file *r)
{
    if (r->f)
        fclose(r->f);
    free(r->names);
    free(r->units);
    free(r->crs);
    memset(r, 0, sizeof *r);
}

static int raster_open(const fr_store *s, const double *x, size_t n, raster_file *r)
{
    memset(r, 0, sizeof *r);
    char path[PATH_MAX], magic[8];
    raster_path(s, x, n, path, sizeof path);
    uint64_t dims[4], crs_len = 0;
    double xs[64];
    struct stat sb;
    if (n > 64 || !(r->f = fopen(path, "rb")) || fstat(fileno(r->f), &sb) != 0 || fread(magic, 1, 8, r->f) != 8 ||
        memcmp(magic, MAGIC, 8) || fread(dims, sizeof dims, 1, r->f) != 1 || dims[0] != n || dims[1] > 4096 ||
        fread(r->geo, sizeof r->geo, 1, r->f) != 1 || fread(&crs_len, sizeof crs_len, 1, r->f) != 1 ||
        crs_len > MAX_CRS || !(r->crs = calloc(crs_len + 1, 1)) ||
        (crs_len && fread(r->crs, 1, crs_len, r->f) != crs_len) || (n && fread(xs, sizeof(double), n, r->f) != n) ||
        memcmp(xs, x, n * sizeof(double)))
        goto bad;
    r->nb = dims[1], r->nx = dims[2], r->ny = dims[3];
    r->header = header_bytes(n, r->nb, crs_len);
    if ((r->nx && r->ny > SIZE_MAX / r->nx / 4 / (r->nb ? r->nb : 1)) ||
        (uint64_t)sb.st_size != r->header + (uint64_t)r->nb * r->nx * r->ny * sizeof(float))
        goto bad;
    if (!(r->names = malloc((r->nb ? r->nb : 1) * sizeof *r->names)) ||
        !(r->units = malloc((r->nb ? r->nb : 1) * sizeof *r->units)))
        goto bad;
    for (size_t b = 0; b < r->nb; b++) {
        if (fread(r->names[b], 1, NAME_BYTES, r->f) != NAME_BYTES ||
            fread(r->units[b], 1, UNIT_BYTES, r->f) != UNIT_BYTES)
            goto bad;
        r->names[b][NAME_BYTES - 1] = '\0';
        r->units[b][UNIT_BYTES - 1] = '\0';
    }
    return 1;
bad:
    raster_close(r);
    return 0;
}

int fr_store_has(fr_store *s, const double *x, size_t n)
{
    raster_file r;
    int ok = raster_open(s, x, n, &r);
    raster_close(&r);
    return ok;
}

static rf_status missing(const fr_store *s, const double *x, size_t n, rf_error *err)
{
    char path[PATH_MAX];
    raster_path(s, x, n, path, sizeof path);
    return rf_fail(err, RF_EIO, "the raster %s of a TM point is missing or damaged", path);
}

rf_status fr_store_band(fr_store *s, const double *x, size_t n, const char *name, size_t *band, char unit[16],
                        fr_grid *g, rf_error *err)
{
    raster_file r;
    if (!raster_open(s, x, n, &r))
        return missing(s, x, n, err);
    g->nx = r.nx, g->ny = r.ny, g->x0 = r.geo[0], g->y0 = r.geo[1], g->cell = r.geo[2];
    snprintf(g->crs_wkt, sizeof g->crs_wkt, "%s", r.crs);
    size_t b = 0;
    while (b < r.nb && strcmp(r.names[b], name))
        b++;
    rf_status st = RF_OK;
    if (b == r.nb) {
        char have[512] = "";
        for (size_t k = 0, used = 0; k < r.nb && used < sizeof have; k++)
            used += (size_t)snprintf(have + used, sizeof have - used, "%s%s", k ? ", " : "", r.names[k]);
        st = rf_fail(err, RF_EINVAL, "the per-point rasters have no band '%s' (they have: %s)", name, have);
    }
    else
        memcpy(unit, r.units[b], UNIT_BYTES);
    *band = b;
    raster_close(&r);
    return st;
}

rf_status fr_store_read(fr_store *s, const double *x, size_t n, size_t band, size_t nx, size_t row0, size_t nrows,
                        float *out, rf_error *err)
{
    raster_file r;
    if (!raster_open(s, x, n, &r))
        return missing(s, x, n, err);
    rf_status st = RF_OK;
    size_t cells = nrows * r.nx;
    if (r.nx != nx)
        st = rf_fail(err, RF_EINVAL, "the per-point rasters differ in shape (%zu and %zu columns)", nx, r.nx);
    else if (band >= r.nb || row0 + nrows > r.ny)
        st = rf_fail(err, RF_EINVAL, "raster read out of range (band %zu of %zu, rows %zu..%zu of %zu)", band, r.nb,
                     row0, row0 + nrows, r.ny);
    else if (fseeko(r.f, (off_t)(r.header + ((band * r.ny + row0) * r.nx) * sizeof(float)), SEEK_SET) != 0 ||
             fread(out, sizeof(float), cells, r.f) != cells)
        st = missing(s, x, n, err);
    raster_close(&r);
    return st;
}

/* ---- reading the store for the retransformation */

rf_status fr_store_reader_init(fr_store_reader *r, fr_store *s, const rf_tm_result *res, size_t n_key, fr_map_fn map,
                               void *map_ctx, const char *const *names, size_t n_names, rf_error *err)
{
    memset(r, 0, sizeof *r);
    r->store = s, r->res = res, r->n_key = n_key, r->map = map, r->map_ctx = map_ctx;
    if (n_names > FR_MAX_BANDS || n_key > 64)
        return rf_fail(err, RF_EINVAL, "fuzzy rasters: at most %d bands and 64 inputs", FR_MAX_BANDS);
    double x[64], xi[64];
    rf_status st = rf_tm_point_inputs(res, 0, x, err);
    if (!st)
        fr_point_key(r, x, xi);
    for (size_t b = 0; !st && b < n_names; b++)
        st = fr_store_band(s, xi, n_key, names[b], &r->band[b], r->unit_text[b], &r->grid, err);
    for (size_t b = 0; b < n_names; b++)
        r->units[b] = r->unit_text[b];
    r->nx = r->grid.nx;
    return st;
}

void fr_point_key(const fr_store_reader *r, const double *x, double *xi)
{
    if (r->map)
        r->map(r->map_ctx, x, xi);
    else
        memcpy(xi, x, r->n_key * sizeof *x);
}

rf_status fr_store_read_point(void *reader, size_t id, size_t b, size_t row0, size_t nrows, float *out, rf_error *err)
{
    const fr_store_reader *r = reader;
    double x[64], xi[64];
    rf_status st = rf_tm_point_inputs(r->res, id, x, err);
    if (st)
        return st;
    fr_point_key(r, x, xi);
    if (rf_tm_point_failed(r->res, id) && !fr_store_has(r->store, xi, r->n_key)) {
        for (size_t c = 0; c < nrows * r->nx; c++) /* a failed point (tolerate_failures) has no raster */
            out[c] = NAN;
        return RF_OK;
    }
    return fr_store_read(r->store, xi, r->n_key, r->band[b], r->nx, row0, nrows, out, err);
}

rf_status fr_store_rebuild(const fr_store_reader *r, const rf_model *model, size_t *rebuilt, rf_error *err)
{
    *rebuilt = 0;
    size_t np = rf_tm_point_count(r->res), no = model->n_outputs;
    double x[64], xi[64], *y = malloc((no ? no : 1) * sizeof(double));
    rf_status st = y ? RF_OK : rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t id = 0; !st && id < np; id++) {
        st = rf_tm_point_inputs(r->res, id, x, err);
        if (st)
            break;
        fr_point_key(r, x, xi);
        if (rf_tm_point_failed(r->res, id) || fr_store_has(r->store, xi, r->n_key))
            continue; /* a failed point is left out of the bounds, its raster too */
        st = rf_model_eval(model, x, y, err); /* the model's sink writes the raster */
        if (!st && !fr_store_has(r->store, xi, r->n_key))
            st = missing(r->store, xi, r->n_key, err);
        if (st)
            rf_error_prefix(err, "rebuilding the raster of TM point %zu", id);
        else
            (*rebuilt)++;
    }
    free(y);
    return st;
}
