/* terrain_io.c - GDAL/OGR reading and writing of terrain files: DEM, class
 * and roughness rasters, release vectors and rasters, GeoTIFF rasters,
 * GeoPackage layers.  (Stub: to be written.) */
#include "trajectory/terrain_internal.h"

rf_status rf_terrain_read(const char *path, int band, rf_terrain **t, rf_error *err)
{
    (void)band;
    *t = NULL;
    return rf_fail(err, RF_EINVAL, "%s: reading a DEM is not written yet", path);
}

rf_status rf_terrain_read_classes(rf_terrain *t, const char *path, int band, size_t n_classes, const long *class_value,
                                  const size_t *class_material, rf_error *err)
{
    (void)t, (void)band, (void)n_classes, (void)class_value, (void)class_material;
    return rf_fail(err, RF_EINVAL, "%s: reading classes is not written yet", path);
}

rf_status rf_terrain_read_roughness(rf_terrain *t, const char *path, int band, rf_error *err)
{
    (void)t, (void)band;
    return rf_fail(err, RF_EINVAL, "%s: reading roughness is not written yet", path);
}

rf_status terrain_geotiff_write(const char *path, const char *crs_wkt, size_t nx, size_t ny, double x0, double y0,
                                double cell, const terrain_band *bands, size_t n, rf_error *err)
{
    (void)crs_wkt, (void)nx, (void)ny, (void)x0, (void)y0, (void)cell, (void)bands, (void)n;
    return rf_fail(err, RF_EINVAL, "%s: GeoTIFF writing is not written yet", path);
}

rf_status terrain_read_release_vector(const char *path, const char *layer, const char *count_field, int per_area,
                                      rf_terrain_release *out, rf_error *err)
{
    (void)layer, (void)count_field, (void)per_area, (void)out;
    return rf_fail(err, RF_EINVAL, "%s: reading release vectors is not written yet", path);
}

rf_status terrain_read_release_raster(const char *path, int band, rf_terrain_release *out, rf_error *err)
{
    (void)band, (void)out;
    return rf_fail(err, RF_EINVAL, "%s: reading a release raster is not written yet", path);
}

rf_status terrain_gpkg_write(const char *path, const char *crs_wkt, const rf_traj_ensemble *ens, rf_error *err)
{
    (void)crs_wkt, (void)ens;
    return rf_fail(err, RF_EINVAL, "%s: GeoPackage writing is not written yet", path);
}
