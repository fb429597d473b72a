/* terrain_io_write.c - the terrain's map outputs written with GDAL/OGR
 * (terrain_internal.h): the hazard rasters as one GeoTIFF (float32 bands,
 * NaN no-data on every band, each band described "name [unit]", DEFLATE
 * compressed, tiled 256 x 256) and the end points and recorded trajectories
 * as a GeoPackage.  Each file is written under a temporary name in the same
 * directory and renamed when complete: an interrupted run never leaves a
 * half-written file under the final name.
 *
 * GeoPackage: layer "end_points", one 3D point per sample at its end (rest,
 * exit or last state) with sample, state, runout_m, reach_angle_deg (null
 * when the runout is 0); layer "trajectories", one 3D line string per
 * recorded trajectory through its events (release, impacts, launches, ...,
 * end) with sample and state.  Between two events the line is straight: in
 * map view a flight's path is exactly that line; its height is not the
 * parabola's. */
#include "trajectory/terrain_internal.h"
#include "trajectory/traj_gdal.h"
#include "core/util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifdef ROCKFUZZ_HAVE_GDAL
#include <cpl_string.h>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

/* The temporary name of path: in its directory, with the same extension. */
static void temp_name(const char *path, const char *ext, char *buf, size_t size)
{
    snprintf(buf, size, "%s.%ld.part%s", path, (long)getpid(), ext);
}

/* The CRS of crs_wkt (NULL for ""); destroy with OSRDestroySpatialReference. */
static rf_status crs_of(const char *crs_wkt, const char *path, OGRSpatialReferenceH *srs, rf_error *err)
{
    *srs = NULL;
    if (!crs_wkt || !crs_wkt[0])
        return RF_OK;
    if (!(*srs = OSRNewSpatialReference(crs_wkt)))
        return rf_fail(err, RF_EINVAL, "%s: the CRS to write is not valid WKT", path);
    OSRSetAxisMappingStrategy(*srs, OAMS_TRADITIONAL_GIS_ORDER);
    return RF_OK;
}

/* Rename tmp to path once GDAL closed it without a failure; else remove it. */
static rf_status commit(const char *tmp, const char *path, const traj_gdal_capture *cap, rf_status st, rf_error *err)
{
    if (st == RF_OK && cap->msg[0])
        st = rf_fail(err, RF_EIO, "%s: writing failed", path);
    if (st == RF_OK && rename(tmp, path) != 0)
        st = rf_fail(err, RF_EIO, "%s: cannot rename the written file into place", path);
    if (st != RF_OK)
        remove(tmp);
    return st;
}

/* ---- GeoTIFF ---- */

static rf_status write_bands(GDALDatasetH ds, const char *path, size_t nx, size_t ny, const terrain_band *bands,
                             size_t n, rf_error *err)
{
    for (size_t b = 0; b < n; b++) {
        GDALRasterBandH h = GDALGetRasterBand(ds, (int)b + 1);
        char desc[128];
        snprintf(desc, sizeof desc, "%s [%s]", bands[b].name, bands[b].unit ? bands[b].unit : "-");
        GDALSetDescription(h, desc);
        GDALSetRasterUnitType(h, bands[b].unit ? bands[b].unit : "");
        if (GDALSetRasterNoDataValue(h, NAN) != CE_None)
            return rf_fail(err, RF_EIO, "%s: cannot set the no-data value", path);
        for (size_t r = 0; r < ny; r++) /* north first: row r holds grid row ny - 1 - r */
            if (GDALRasterIO(h, GF_Write, 0, (int)r, (int)nx, 1, bands[b].data + (ny - 1 - r) * nx, (int)nx, 1,
                             GDT_Float32, 0, 0) != CE_None)
                return rf_fail(err, RF_EIO, "%s: cannot write band %zu", path, b + 1);
    }
    return RF_OK;
}

static rf_status geotiff_create(const char *tmp, const char *path, const char *crs_wkt, size_t nx, size_t ny,
                                double x0, double y0, double cell, const terrain_band *bands, size_t n, rf_error *err)
{
    GDALDriverH drv = GDALGetDriverByName("GTiff");
    if (!drv)
        return rf_fail(err, RF_EIO, "%s: GDAL has no GeoTIFF driver", path);
    char **opt = NULL;
    opt = CSLSetNameValue(opt, "COMPRESS", "DEFLATE");
    opt = CSLSetNameValue(opt, "PREDICTOR", "3");
    opt = CSLSetNameValue(opt, "TILED", "YES");
    opt = CSLSetNameValue(opt, "BIGTIFF", "IF_SAFER");
    GDALDatasetH ds = GDALCreate(drv, tmp, (int)nx, (int)ny, (int)n, GDT_Float32, opt);
    CSLDestroy(opt);
    if (!ds)
        return rf_fail(err, RF_EIO, "%s: cannot create the GeoTIFF", path);
    double gt[6] = {x0, cell, 0, y0 + (double)ny * cell, 0, -cell};
    OGRSpatialReferenceH srs;
    rf_status st = crs_of(crs_wkt, path, &srs, err);
    if (st == RF_OK && GDALSetGeoTransform(ds, gt) != CE_None)
        st = rf_fail(err, RF_EIO, "%s: cannot set the geotransform", path);
    if (st == RF_OK && srs && GDALSetSpatialRef(ds, srs) != CE_None)
        st = rf_fail(err, RF_EIO, "%s: cannot set the CRS", path);
    if (st == RF_OK)
        st = write_bands(ds, path, nx, ny, bands, n, err);
    if (srs)
        OSRDestroySpatialReference(srs);
    GDALClose(ds);
    return st;
}

rf_status terrain_geotiff_write(const char *path, const char *crs_wkt, size_t nx, size_t ny, double x0, double y0,
                                double cell, const terrain_band *bands, size_t n, rf_error *err)
{
    if (nx < 1 || ny < 1 || n < 1 || nx > INT32_MAX || ny > INT32_MAX || n > 65535 || !(cell > 0) ||
        !isfinite(x0) || !isfinite(y0))
        return rf_fail(err, RF_EINVAL, "%s: a raster of %zu x %zu cells of %g m with %zu bands cannot be written",
                       path, nx, ny, cell, n);
    char tmp[4200];
    temp_name(path, ".tif", tmp, sizeof tmp);
    traj_gdal_capture cap;
    traj_gdal_begin(&cap);
    rf_status st = geotiff_create(tmp, path, crs_wkt, nx, ny, x0, y0, cell, bands, n, err);
    st = commit(tmp, path, &cap, st, err);
    if (st == RF_OK) { /* statistics of an earlier file (gdalinfo -stats, QGIS) would be stale */
        snprintf(tmp, sizeof tmp, "%s.aux.xml", path);
        remove(tmp);
    }
    if (st != RF_OK)
        traj_gdal_explain(err, &cap);
    traj_gdal_end(&cap);
    return st;
}

/* ---- GeoPackage ---- */

static rf_status add_fields(OGRLayerH lay, const char *const *names, const OGRFieldType *types, int n,
                            const char *path, rf_error *err)
{
    for (int k = 0; k < n; k++) {
        OGRFieldDefnH fd = OGR_Fld_Create(names[k], types[k]);
        OGRErr e = OGR_L_CreateField(lay, fd, TRUE);
        OGR_Fld_Destroy(fd);
        if (e != OGRERR_NONE)
            return rf_fail(err, RF_EIO, "%s: cannot create the field '%s'", path, names[k]);
    }
    return RF_OK;
}

/* Create the feature f (its geometry and fields set) in lay. */
static rf_status put_feature(OGRLayerH lay, OGRFeatureH f, OGRGeometryH g, const char *path, rf_error *err)
{
    OGR_F_SetGeometryDirectly(f, g);
    OGRErr e = OGR_L_CreateFeature(lay, f);
    OGR_F_Destroy(f);
    return e == OGRERR_NONE ? RF_OK : rf_fail(err, RF_EIO, "%s: cannot write a feature", path);
}

static rf_status write_end_points(GDALDatasetH ds, OGRSpatialReferenceH srs, const char *path,
                                  const rf_traj_ensemble *ens, rf_error *err)
{
    OGRLayerH lay = GDALDatasetCreateLayer(ds, "end_points", srs, wkbPoint25D, NULL);
    const char *names[] = {"sample", "state", "runout_m", "reach_angle_deg"};
    const OGRFieldType types[] = {OFTInteger64, OFTString, OFTReal, OFTReal};
    rf_status st = lay ? add_fields(lay, names, types, 4, path, err)
                       : rf_fail(err, RF_EIO, "%s: cannot create the layer end_points", path);
    const rf_terrain_samples *ts = ens->terrain;
    for (size_t k = 0; k < ens->samples && st == RF_OK; k++) {
        OGRFeatureH f = OGR_F_Create(OGR_L_GetLayerDefn(lay));
        OGRGeometryH g = OGR_G_CreateGeometry(wkbPoint25D);
        OGR_G_SetPoint(g, 0, ts->end[3 * k], ts->end[3 * k + 1], ts->end[3 * k + 2]);
        OGR_F_SetFieldInteger64(f, 0, (GIntBig)k);
        OGR_F_SetFieldString(f, 1, rf_traj_state_name((rf_traj_state)ens->state[k]));
        OGR_F_SetFieldDouble(f, 2, ts->runout[k]);
        if (isfinite(ts->reach_angle[k]))
            OGR_F_SetFieldDouble(f, 3, ts->reach_angle[k] * 180 / RF_PI);
        else
            OGR_F_SetFieldNull(f, 3);
        st = put_feature(lay, f, g, path, err);
    }
    return st;
}

static rf_status write_trajectories(GDALDatasetH ds, OGRSpatialReferenceH srs, const char *path,
                                    const rf_traj_ensemble *ens, rf_error *err)
{
    OGRLayerH lay = GDALDatasetCreateLayer(ds, "trajectories", srs, wkbLineString25D, NULL);
    const char *names[] = {"sample", "state"};
    const OGRFieldType types[] = {OFTInteger64, OFTString};
    rf_status st = lay ? add_fields(lay, names, types, 2, path, err)
                       : rf_fail(err, RF_EIO, "%s: cannot create the layer trajectories", path);
    const rf_terrain_samples *ts = ens->terrain;
    for (size_t k = 0; k < ts->n_recorded && st == RF_OK; k++) {
        const rf_terrain_result *r = &ts->recorded[k];
        if (r->n_events < 2 || !r->events)
            continue; /* nothing to draw */
        OGRFeatureH f = OGR_F_Create(OGR_L_GetLayerDefn(lay));
        OGRGeometryH g = OGR_G_CreateGeometry(wkbLineString25D);
        for (size_t e = 0; e < r->n_events; e++)
            OGR_G_AddPoint(g, r->events[e].p[0], r->events[e].p[1], r->events[e].p[2]);
        OGR_F_SetFieldInteger64(f, 0, (GIntBig)k);
        OGR_F_SetFieldString(f, 1, rf_traj_state_name(r->state));
        st = put_feature(lay, f, g, path, err);
    }
    return st;
}

static rf_status gpkg_create(const char *tmp, const char *path, const char *crs_wkt, const rf_traj_ensemble *ens,
                             rf_error *err)
{
    GDALDriverH drv = GDALGetDriverByName("GPKG");
    if (!drv)
        return rf_fail(err, RF_EIO, "%s: GDAL has no GeoPackage driver", path);
    GDALDatasetH ds = GDALCreate(drv, tmp, 0, 0, 0, GDT_Unknown, NULL);
    if (!ds)
        return rf_fail(err, RF_EIO, "%s: cannot create the GeoPackage", path);
    OGRSpatialReferenceH srs;
    rf_status st = crs_of(crs_wkt, path, &srs, err);
    if (st == RF_OK && GDALDatasetStartTransaction(ds, FALSE) != OGRERR_NONE)
        st = rf_fail(err, RF_EIO, "%s: cannot start a transaction", path);
    if (st == RF_OK)
        st = write_end_points(ds, srs, path, ens, err);
    if (st == RF_OK)
        st = write_trajectories(ds, srs, path, ens, err);
    if (st == RF_OK && GDALDatasetCommitTransaction(ds) != OGRERR_NONE)
        st = rf_fail(err, RF_EIO, "%s: cannot commit the features", path);
    if (srs)
        OSRDestroySpatialReference(srs);
    GDALClose(ds);
    return st;
}

rf_status terrain_gpkg_write(const char *path, const char *crs_wkt, const rf_traj_ensemble *ens, rf_error *err)
{
    const rf_terrain_samples *ts = ens->terrain;
    if (!ts || (ens->samples && (!ts->end || !ts->runout || !ts->reach_angle || !ens->state)) ||
        (ts->n_recorded && !ts->recorded))
        return rf_fail(err, RF_EINVAL, "%s: the ensemble is not a complete terrain run", path);
    char tmp[4200];
    temp_name(path, ".gpkg", tmp, sizeof tmp);
    traj_gdal_capture cap;
    traj_gdal_begin(&cap);
    remove(tmp); /* GDALCreate of a GeoPackage refuses an existing file */
    rf_status st = gpkg_create(tmp, path, crs_wkt, ens, err);
    st = commit(tmp, path, &cap, st, err);
    if (st != RF_OK)
        traj_gdal_explain(err, &cap);
    traj_gdal_end(&cap);
    return st;
}

#else

rf_status terrain_geotiff_write(const char *path, const char *crs_wkt, size_t nx, size_t ny, double x0, double y0,
                                double cell, const terrain_band *bands, size_t n, rf_error *err)
{
    (void)crs_wkt, (void)nx, (void)ny, (void)x0, (void)y0, (void)cell, (void)bands, (void)n;
    return rf_fail(err, RF_EINVAL, "%s: cannot write the GeoTIFF: this rockfuzz was built without GDAL (install "
                   "libgdal-dev and rebuild)", path);
}

rf_status terrain_gpkg_write(const char *path, const char *crs_wkt, const rf_traj_ensemble *ens, rf_error *err)
{
    (void)crs_wkt, (void)ens;
    return rf_fail(err, RF_EINVAL, "%s: cannot write the GeoPackage: this rockfuzz was built without GDAL (install "
                   "libgdal-dev and rebuild)", path);
}

#endif
