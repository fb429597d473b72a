/* traj_gdal.h - what every GDAL/OGR reader and writer of the trajectory
 * module shares (dem.c, terrain_io*.c): GDAL's messages kept off the console
 * and added to ours, and the check that a CRS is in metres.  Only with
 * ROCKFUZZ_HAVE_GDAL. */
#ifndef ROCKFUZZ_TRAJ_GDAL_H
#define ROCKFUZZ_TRAJ_GDAL_H

#ifdef ROCKFUZZ_HAVE_GDAL
#include "rockfuzz/status.h"

#include <gdal.h>
#include <math.h>
#include <ogr_srs_api.h>

/* GDAL's first failure message while a capture is active (this thread). */
typedef struct {
    char msg[256];              /* " (GDAL: ...)" or "" */
} traj_gdal_capture;

/* Register the drivers and route this thread's GDAL messages into c. */
void traj_gdal_begin(traj_gdal_capture *c);
/* Restore the previous handler. */
void traj_gdal_end(traj_gdal_capture *c);
/* Append GDAL's message (if any, and if it fits) to err's; returns err's code. */
rf_status traj_gdal_explain(rf_error *err, const traj_gdal_capture *c);

/* Map units must be metres: a geographic (degrees) or non-metre CRS of the
 * `what` file at path is refused, naming the CRS; srs NULL (none) passes. */
rf_status traj_gdal_check_metres(OGRSpatialReferenceH srs, const char *what, const char *path, rf_error *err);

/* One band of a raster opened for reading. */
typedef struct {
    GDALDatasetH ds;
    GDALRasterBandH band;
    double gt[6];               /* pixel (c, r) corner -> map (gt[0] + c gt[1], gt[3] + r gt[5]) */
    int w, h;                   /* columns, rows */
    int has_nodata;
    double nodata;              /* as the band's data type holds it */
} traj_gdal_raster;

/* Band band_no (1-based) of the `what` raster at path (a regular file GDAL
 * reads), north-up: a geotransform without rotation, columns west to east,
 * rows north to south; map units metres or no CRS.  Within a capture
 * (traj_gdal_begin); close with traj_gdal_raster_close. */
rf_status traj_gdal_raster_open(const char *path, int band_no, const char *what, traj_gdal_raster *r, rf_error *err);
void traj_gdal_raster_close(traj_gdal_raster *r);

/* v is the band's no-data value or NaN. */
static inline int traj_gdal_is_nodata(const traj_gdal_raster *r, double v)
{
    return isnan(v) || (r->has_nodata && v == r->nodata);
}
#endif

#endif
