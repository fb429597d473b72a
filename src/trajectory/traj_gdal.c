/* traj_gdal.c - GDAL's messages captured for ours, and the metre check of a
 * CRS (traj_gdal.h), shared by the DEM profile reader and the terrain files. */
#include "trajectory/traj_gdal.h"

#ifdef ROCKFUZZ_HAVE_GDAL
#include <gdal.h>

#include <cpl_error.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* GDAL's messages go here, not to the console: the first failure is kept. */
static void CPL_STDCALL keep_error(CPLErr cls, CPLErrorNum no, const char *msg)
{
    (void)no;
    traj_gdal_capture *c = CPLGetErrorHandlerUserData();
    if (cls >= CE_Failure && c && !c->msg[0] && msg)
        snprintf(c->msg, sizeof c->msg, " (GDAL: %s)", msg);
}

void traj_gdal_begin(traj_gdal_capture *c)
{
    c->msg[0] = '\0';
    GDALAllRegister();
    CPLPushErrorHandlerEx(keep_error, c);
}

void traj_gdal_end(traj_gdal_capture *c)
{
    (void)c;
    CPLPopErrorHandler();
}

rf_status traj_gdal_explain(rf_error *err, const traj_gdal_capture *c)
{
    if (!err)
        return RF_EINTERNAL;
    if (c->msg[0] && !strstr(err->msg, c->msg) && strlen(err->msg) + strlen(c->msg) < sizeof err->msg)
        strcat(err->msg, c->msg);
    return err->code;
}

rf_status traj_gdal_check_metres(OGRSpatialReferenceH srs, const char *what, const char *path, rf_error *err)
{
    if (!srs)
        return RF_OK; /* no CRS given (e.g. an ASCII grid): taken as metres, as documented */
    const char *name = OSRGetName(srs);
    if (!name)
        name = "unnamed";
    if (OSRIsGeographic(srs))
        return rf_fail(err, RF_EINVAL, "the %s '%s' is in geographic coordinates (degrees), CRS \"%s\", not metres; "
                       "reproject it to a projected CRS in metres (e.g. gdalwarp -t_srs EPSG:32632)", what, path, name);
    char *unit = NULL;
    double m = OSRGetLinearUnits(srs, &unit);
    if (fabs(m - 1) > 1e-9)
        return rf_fail(err, RF_EINVAL, "the %s '%s' has map units of %.10g m (%s), CRS \"%s\", not metres; reproject "
                       "it to a CRS in metres", what, path, m, unit ? unit : "unnamed", name);
    return RF_OK;
}
#endif

#ifdef ROCKFUZZ_HAVE_GDAL
#include "core/textfile.h"

/* The geotransform: present, north-up and not rotated. */
static rf_status check_north_up(const traj_gdal_raster *r, const char *what, const char *path, rf_error *err)
{
    const double *gt = r->gt;
    if (gt[2] != 0 || gt[4] != 0)
        return rf_fail(err, RF_EINVAL, "the %s '%s' is rotated (geotransform rotation terms %g, %g); only north-up "
                       "rasters are read: warp it to a north-up grid (gdalwarp)", what, path, gt[2], gt[4]);
    if (!(gt[1] > 0 && gt[5] < 0 && isfinite(gt[0]) && isfinite(gt[3]) && isfinite(gt[1]) && isfinite(gt[5])))
        return rf_fail(err, RF_EINVAL, "the %s '%s' has pixel size %g x %g: columns must run west to east and rows "
                       "north to south (a positive width and a negative height); warp it to a north-up grid "
                       "(gdalwarp)", what, path, gt[1], gt[5]);
    return RF_OK;
}

/* No-data as the band stores it: a Float32 band's value compared as a float. */
static void read_nodata(traj_gdal_raster *r)
{
    r->nodata = GDALGetRasterNoDataValue(r->band, &r->has_nodata);
    if (r->has_nodata && GDALGetRasterDataType(r->band) == GDT_Float32 && fabs(r->nodata) <= 3.4028234663852886e38)
        r->nodata = (float)r->nodata;
}

static rf_status open_band(const char *path, int band_no, const char *what, traj_gdal_raster *r, rf_error *err)
{
    r->ds = GDALOpenEx(path, GDAL_OF_RASTER | GDAL_OF_READONLY, NULL, NULL, NULL);
    if (!r->ds)
        return rf_fail(err, RF_EIO, "cannot read the %s '%s' as a raster with GDAL", what, path);
    if (band_no < 1 || band_no > GDALGetRasterCount(r->ds))
        return rf_fail(err, RF_EINVAL, "the %s '%s' has no band %d (it has %d)", what, path, band_no,
                       GDALGetRasterCount(r->ds));
    r->band = GDALGetRasterBand(r->ds, band_no);
    r->w = GDALGetRasterXSize(r->ds), r->h = GDALGetRasterYSize(r->ds);
    if (GDALGetGeoTransform(r->ds, r->gt) != CE_None)
        return rf_fail(err, RF_EINVAL, "the %s '%s' has no georeferencing (geotransform)", what, path);
    rf_status st = check_north_up(r, what, path, err);
    if (st == RF_OK)
        st = traj_gdal_check_metres(GDALGetSpatialRef(r->ds), what, path, err);
    read_nodata(r);
    return st;
}

rf_status traj_gdal_raster_open(const char *path, int band_no, const char *what, traj_gdal_raster *r, rf_error *err)
{
    memset(r, 0, sizeof *r);
    rf_status st = rf_require_regular_file(path, what, err);
    if (st == RF_OK)
        st = open_band(path, band_no, what, r, err);
    if (st != RF_OK)
        traj_gdal_raster_close(r);
    return st;
}

void traj_gdal_raster_close(traj_gdal_raster *r)
{
    if (r->ds)
        GDALClose(r->ds);
    r->ds = NULL, r->band = NULL;
}
#endif
