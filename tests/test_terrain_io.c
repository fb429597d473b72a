/* test_terrain_io.c - the terrain's files through GDAL/OGR (terrain_io*.c),
 * on rasters and vectors made here in a temporary directory:
 * - a plane DEM (GeoTIFF, Float64) is read back exact at random points
 *   (bilinear interpolation reproduces a plane) with its CRS kept;
 * - a non-symmetric DEM (ESRI ASCII grid, dx != dy) proves the row order and
 *   the half-cell offset: each node holds the value gdallocationinfo reports
 *   at that map point, and the value the grid's text puts there;
 * - no-data cells (declared, and NaN) make the cells around them outside;
 *   a Float32 3.4e38 is refused unless it is the declared no-data;
 * - EPSG:4326, a US-foot CRS, a rotated geotransform and an absurd size are
 *   refused with messages naming the file and the cause; a broken file's
 *   GDAL message is in ours and nothing reaches stderr;
 * - classes on a 2x coarser, shifted grid give each cell the class of the
 *   pixel holding its centre (computed here by floor), no-data pixels make
 *   cells outside; on the DEM's own grid the centre (a pixel corner) takes the
 *   north-east pixel; an unknown class value and a CRS mismatch are refused;
 *   roughness in degrees is stored in radians, 50 deg refused;
 * - a GeoTIFF written and read back: values, NaN no-data on every band,
 *   geotransform, CRS, descriptions, DEFLATE and tiles; no temporary file left;
 * - release features from GeoJSON (points, lines, polygons, multi-parts with
 *   a count field, per area) and a shapefile, refusals (hole, mixed kinds,
 *   WGS 84, empty layer, missing field), and from a release raster;
 * - a GeoPackage of a hand-made ensemble read back with OGR, and as release
 *   points from its layer end_points. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <unistd.h>

#include "trajectory/terrain_internal.h"
#include "test_util.h"

#ifdef ROCKFUZZ_HAVE_GDAL
#include <cpl_string.h>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

static char dir[64];

static const char *at(const char *name)
{
    static char buf[8][256];
    static int k;
    k = (k + 1) % 8;
    snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
    return buf[k];
}

/* A reproducible uniform in [0, 1). */
static double uni(uint64_t *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* A GeoTIFF of one band: v holds h rows of w values, north first; epsg 0: no CRS. */
static void make_tif(const char *path, int w, int h, GDALDataType type, const double gt[6], int epsg, const double *nodata,
                     const double *v)
{
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path, w, h, 1, type, NULL);
    assert_non_null(ds);
    assert_int_equal(GDALSetGeoTransform(ds, (double *)gt), CE_None);
    if (epsg) {
        OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
        assert_int_equal(OSRImportFromEPSG(srs, epsg), OGRERR_NONE);
        GDALSetSpatialRef(ds, srs);
        OSRDestroySpatialReference(srs);
    }
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    if (nodata)
        GDALSetRasterNoDataValue(b, *nodata);
    assert_int_equal(GDALRasterIO(b, GF_Write, 0, 0, w, h, (void *)v, w, h, GDT_Float64, 0, 0), CE_None);
    GDALClose(ds);
}

static rf_terrain *read_ok(const char *path)
{
    rf_terrain *t;
    rf_error err;
    if (rf_terrain_read(path, 1, &t, &err) != RF_OK)
        fail_msg("%s", err.msg);
    return t;
}

static void read_fails(const char *path, const char *want1, const char *want2)
{
    rf_terrain *t = (rf_terrain *)1;
    rf_error err;
    assert_int_not_equal(rf_terrain_read(path, 1, &t, &err), RF_OK);
    assert_null(t);
    if (!strstr(err.msg, want1) || !strstr(err.msg, want2) || !strstr(err.msg, path))
        fail_msg("message '%s' lacks '%s' or '%s'", err.msg, want1, want2);
}

/* ---- DEM ---- */

static double plane(double x, double y) { return 1520.25 + 0.41 * (x - 600000) - 0.27 * (y - 5100000); }

static void test_dem_plane(void **state)
{
    (void)state;
    enum { W = 40, H = 30 };
    static double v[W * H];
    double gt[6] = {600000, 2, 0, 5100090, 0, -3};
    for (int r = 0; r < H; r++)
        for (int c = 0; c < W; c++)
            v[r * W + c] = plane(gt[0] + (c + 0.5) * gt[1], gt[3] + (r + 0.5) * gt[5]);
    make_tif(at("plane.tif"), W, H, GDT_Float64, gt, 32632, NULL, v);
    rf_terrain *t = read_ok(at("plane.tif"));
    double xmin, xmax, ymin, ymax, dx, dy, z;
    rf_terrain_extent(t, &xmin, &xmax, &ymin, &ymax, &dx, &dy);
    assert_true(xmin == 600001 && xmax == 600000 + 2 * (W - 0.5) && dx == 2 && dy == 3);
    assert_true(ymax == 5100090 - 1.5 && ymin == 5100090 - 3 * (H - 0.5));
    uint64_t s = 3;
    for (int k = 0; k < 1000; k++) {
        double x = xmin + uni(&s) * (xmax - xmin), y = ymin + uni(&s) * (ymax - ymin);
        assert_int_equal(rf_terrain_height(t, x, y, &z, NULL), 1);
        if (fabs(z - plane(x, y)) > 1e-9)
            fail_msg("z(%f, %f) = %.12f, plane %.12f", x, y, z, plane(x, y));
    }
    assert_non_null(strstr(rf_terrain_crs_wkt(t), "32632"));
    assert_int_equal(rf_terrain_height(t, xmin - 0.01, ymin, &z, NULL), 0);
    rf_terrain_free(t);
}

/* value of raster cell (column c, row r), north row first */
static int cell_value(int c, int r) { return 100 * r + c; }

static void test_dem_row_order(void **state)
{
    (void)state;
    enum { W = 5, H = 4 };
    const double xll = 1000, yll = 2000, dx = 2, dy = 3;
    FILE *f = fopen(at("asym.asc"), "w");
    assert_non_null(f);
    fprintf(f, "ncols %d\nnrows %d\nxllcorner %g\nyllcorner %g\ndx %g\ndy %g\nNODATA_value -9999\n", W, H, xll, yll, dx,
            dy);
    for (int r = 0; r < H; r++) {
        for (int c = 0; c < W; c++)
            fprintf(f, "%d ", cell_value(c, r));
        fputc('\n', f);
    }
    fclose(f);
    rf_terrain *t = read_ok(at("asym.asc"));
    assert_int_equal(t->nx, W);
    assert_int_equal(t->ny, H);
    assert_string_equal(rf_terrain_crs_wkt(t), "");
    FILE *pts = fopen(at("asym.xy"), "w");
    assert_non_null(pts);
    double want[W * H];
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            double x = xll + (i + 0.5) * dx, y = yll + (j + 0.5) * dy, z;
            assert_int_equal(rf_terrain_height(t, x, y, &z, NULL), 1);
            assert_true(z == cell_value(i, H - 1 - j)); /* the text's row H - 1 - j is j rows up from the south */
            fprintf(pts, "%.10g %.10g\n", x, y);
            want[j * W + i] = z;
        }
    fclose(pts);
    /* gdallocationinfo: the value of the pixel holding each map point, read from stdin */
    char cmd[512], out[64];
    snprintf(cmd, sizeof cmd, "gdallocationinfo -valonly -geoloc %s < %s 2>/dev/null", at("asym.asc"), at("asym.xy"));
    FILE *p = popen(cmd, "r");
    int checked = 0;
    while (p && checked < W * H && fgets(out, sizeof out, p)) {
        assert_true(atof(out) == want[checked]);
        checked++;
    }
    if (p)
        pclose(p);
    assert_true(checked == 0 || checked == W * H);
    if (!checked)
        print_message("gdallocationinfo not available: checked against the grid text only\n");
    rf_terrain_free(t);
}

static void test_dem_nodata(void **state)
{
    (void)state;
    enum { W = 6, H = 5 };
    double v[W * H], gt[6] = {0, 1, 0, 5, 0, -1}, nd = -9999;
    for (int k = 0; k < W * H; k++)
        v[k] = 50 + k;
    v[2 * W + 3] = nd;  /* raster (3, 2): node (3, 2) */
    v[4 * W + 0] = NAN; /* raster (0, 4): node (0, 0), south-west corner */
    make_tif(at("nd.tif"), W, H, GDT_Float32, gt, 0, &nd, v);
    rf_terrain *t = read_ok(at("nd.tif"));
    for (int j = 0; j + 1 < H; j++)
        for (int i = 0; i + 1 < W; i++) {
            int out = (i == 0 && j == 0) || ((i == 2 || i == 3) && (j == 1 || j == 2));
            double z, x = 0.5 + i + 0.5, y = 0.5 + j + 0.5;
            assert_int_equal(rf_terrain_height(t, x, y, &z, NULL), !out);
        }
    assert_true(isnan(t->z[2 * W + 3]) && isnan(t->z[0]));
    rf_terrain_free(t);
}

static void test_dem_refused(void **state)
{
    (void)state;
    double v[16], gt[6] = {600000, 10, 0, 5100040, 0, -10};
    for (int k = 0; k < 16; k++)
        v[k] = 100 + k;
    make_tif(at("wgs84.tif"), 4, 4, GDT_Float64, (double[6]){7, 0.001, 0, 46, 0, -0.001}, 4326, NULL, v);
    read_fails(at("wgs84.tif"), "geographic coordinates (degrees)", "WGS 84");
    make_tif(at("usft.tif"), 4, 4, GDT_Float64, gt, 2229, NULL, v); /* NAD83 / California zone 5 (ftUS) */
    read_fails(at("usft.tif"), "map units of 0.3048006", "ftUS");
    double rot[6] = {600000, 10, 0.5, 5100040, 0.5, -10};
    make_tif(at("rot.tif"), 4, 4, GDT_Float64, rot, 32632, NULL, v);
    read_fails(at("rot.tif"), "rotated", "north-up");
    double up[6] = {600000, 10, 0, 5100000, 0, 10};
    make_tif(at("up.tif"), 4, 4, GDT_Float64, up, 32632, NULL, v);
    read_fails(at("up.tif"), "north to south", "10 x 10");
    /* 3.4e38: Float32's no-data of some tools, here undeclared, at raster (column 1, row 2) */
    v[2 * 4 + 1] = 3.4e38;
    make_tif(at("huge.tif"), 4, 4, GDT_Float32, gt, 32632, NULL, v);
    read_fails(at("huge.tif"), "cell (column 1, row 2) at map point (600015, 5100015)", "none is declared");
    double nd = 3.4e38; /* declared: a hole */
    make_tif(at("huge_nd.tif"), 4, 4, GDT_Float32, gt, 32632, &nd, v);
    rf_terrain *t = read_ok(at("huge_nd.tif"));
    assert_true(isnan(t->z[(4 - 1 - 2) * 4 + 1]));
    rf_terrain_free(t);
    /* an ASCII grid with decimals is read as Float32: its cells hold (float)3.4e38, its
     * declared no-data the double 3.4e38; they are the same no-data */
    FILE *f = fopen(at("huge_nd.asc"), "w");
    assert_non_null(f);
    fprintf(f, "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value 3.4e38\n"
               "1.5 2.5 3.5\n4.5 3.4e38 6.5\n");
    fclose(f);
    unsetenv("AAIGRID_DATATYPE");
    t = read_ok(at("huge_nd.asc"));
    assert_true(isnan(t->z[1]) && t->z[0] == 4.5 && t->z[5] == 3.5);
    rf_terrain_free(t);
    read_fails(at("missing.tif"), "cannot open the DEM", "No such file");
    /* absurd size: 2^21 columns (sparse, a few kB on disk) */
    char **opt = CSLSetNameValue(NULL, "SPARSE_OK", "TRUE");
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), at("wide.tif"), 1 << 21, 4, 1, GDT_Byte, opt);
    CSLDestroy(opt);
    assert_non_null(ds);
    GDALSetGeoTransform(ds, gt);
    GDALClose(ds);
    read_fails(at("wide.tif"), "2097152 x 4 cells, which would take 0.07 GB", "per side");
    /* a missing band */
    rf_error err;
    assert_int_equal(rf_terrain_read(at("huge_nd.tif"), 2, &t, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "no band 2 (it has 1)"));
}

/* A broken GeoTIFF: GDAL's message is in ours, and nothing reaches stderr. */
static void test_gdal_message_kept(void **state)
{
    (void)state;
    FILE *f = fopen(at("broken.tif"), "wb");
    assert_non_null(f);
    static const char bytes[] = "II*\0\xff\xff\xff\x7f garbage"; /* a TIFF header pointing nowhere */
    fwrite(bytes, 1, sizeof bytes - 1, f);
    fclose(f);
    fflush(stderr);
    int saved = dup(2);
    FILE *cap = fopen(at("stderr.txt"), "w");
    assert_non_null(cap);
    dup2(fileno(cap), 2);
    CPLSetErrorHandler(CPLDefaultErrorHandler); /* GDAL's own: prints to stderr */
    rf_terrain *t;
    rf_error err;
    rf_status st = rf_terrain_read(at("broken.tif"), 1, &t, &err);
    CPLSetErrorHandler(CPLQuietErrorHandler);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    fseek(cap, 0, SEEK_END);
    long printed = ftell(cap);
    fclose(cap);
    assert_int_equal(st, RF_EIO);
    if (!strstr(err.msg, "cannot read the DEM") || !strstr(err.msg, "(GDAL: "))
        fail_msg("%s", err.msg);
    assert_int_equal(printed, 0);
}

/* ---- classes and roughness ---- */

/* DEM: 12 x 9 nodes at 1 m from (0.5, 0.5), EPSG:32632. */
enum { DW = 12, DH = 9 };
static rf_terrain *class_dem(void)
{
    double v[DW * DH], gt[6] = {0, 1, 0, DH, 0, -1};
    for (int k = 0; k < DW * DH; k++)
        v[k] = 10;
    make_tif(at("cdem.tif"), DW, DH, GDT_Float64, gt, 32632, NULL, v);
    return read_ok(at("cdem.tif"));
}

static int class_at(int c, int r) { return 1 + (c + 2 * r) % 3; }

static void test_classes_coarse(void **state)
{
    (void)state;
    rf_terrain *t = class_dem();
    /* 2 m pixels shifted by 0.25 m: no cell centre (at whole metres) on a pixel edge; the
     * raster covers x in [0.25, 12.25], y in [-0.75, 9.25]: the DEM's cells entirely */
    enum { W = 6, H = 5 };
    double v[W * H], gt[6] = {0.25, 2, 0, 9.25, 0, -2}, nd = 0;
    for (int r = 0; r < H; r++)
        for (int c = 0; c < W; c++)
            v[r * W + c] = class_at(c, r);
    v[1 * W + 2] = nd; /* pixel x in [4.25, 6.25], y in [5.25, 7.25]: cell centres x = 5, 6; y = 6, 7 */
    make_tif(at("classes.tif"), W, H, GDT_Int16, gt, 32632, &nd, v);
    long values[3] = {1, 2, 3};
    size_t mats[3] = {4, 0, 7};
    rf_error err;
    if (rf_terrain_read_classes(t, at("classes.tif"), 1, 3, values, mats, &err) != RF_OK)
        fail_msg("%s", err.msg);
    int outside = 0;
    for (size_t j = 0; j + 1 < t->ny; j++)
        for (size_t i = 0; i + 1 < t->nx; i++) {
            double x = t->x0 + (i + 0.5) * t->dx, y = t->y0 + (j + 0.5) * t->dy;
            int c = (int)floor((x - gt[0]) / gt[1]), r = (int)floor((y - gt[3]) / gt[5]);
            int hole = c == 2 && r == 1;
            assert_int_equal(t->valid[j * (t->nx - 1) + i], !hole);
            outside += hole;
            if (!hole)
                assert_int_equal(terrain_material_of(t, i, j), mats[class_at(c, r) - 1]);
        }
    assert_int_equal(outside, 4);
    rf_terrain_free(t);
}

static void test_classes_same_grid(void **state)
{
    (void)state;
    rf_terrain *t = class_dem();
    double v[DW * DH], gt[6] = {0, 1, 0, DH, 0, -1};
    for (int r = 0; r < DH; r++)
        for (int c = 0; c < DW; c++)
            v[r * DW + c] = class_at(c, r);
    make_tif(at("same.asc.tif"), DW, DH, GDT_Byte, gt, 0, NULL, v); /* no CRS: taken as the DEM's */
    long values[3] = {3, 2, 1};
    size_t mats[3] = {3, 2, 1};
    rf_error err;
    if (rf_terrain_read_classes(t, at("same.asc.tif"), 1, 3, values, mats, &err) != RF_OK)
        fail_msg("%s", err.msg);
    /* cell (i, j) has its centre on the corner of raster columns i, i + 1 and rows
     * DH - 1 - j, DH - 2 - j: the north-east pixel is (i + 1, DH - 2 - j) */
    for (size_t j = 0; j + 1 < t->ny; j++)
        for (size_t i = 0; i + 1 < t->nx; i++)
            assert_int_equal(terrain_material_of(t, i, j), class_at((int)i + 1, DH - 2 - (int)j));
    /* unknown value: class 3 missing from the list */
    long two[2] = {1, 2};
    uint16_t *before = t->material;
    assert_int_equal(rf_terrain_read_classes(t, at("same.asc.tif"), 1, 2, two, mats, &err), RF_EINVAL);
    if (!strstr(err.msg, "holds 3 at map point (") || !strstr(err.msg, "(1, 2)") || !strstr(err.msg, "same.asc.tif"))
        fail_msg("%s", err.msg);
    assert_ptr_equal(t->material, before); /* unchanged */
    rf_terrain_free(t);
}

static void test_classes_refused(void **state)
{
    (void)state;
    rf_terrain *t = class_dem();
    double v[DW * DH], gt[6] = {0, 1, 0, DH, 0, -1};
    for (int k = 0; k < DW * DH; k++)
        v[k] = 1;
    make_tif(at("utm33.tif"), DW, DH, GDT_Byte, gt, 32633, NULL, v);
    long values[1] = {1};
    size_t mats[1] = {0};
    rf_error err;
    assert_int_equal(rf_terrain_read_classes(t, at("utm33.tif"), 1, 1, values, mats, &err), RF_EINVAL);
    if (!strstr(err.msg, "zone 33N") || !strstr(err.msg, "zone 32N"))
        fail_msg("%s", err.msg);
    double far[6] = {1000, 1, 0, 1000, 0, -1};
    make_tif(at("far.tif"), DW, DH, GDT_Byte, far, 32632, NULL, v);
    assert_int_equal(rf_terrain_read_classes(t, at("far.tif"), 1, 1, values, mats, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "holds data at no cell of the DEM"));
    assert_null(t->material);
    rf_terrain_free(t);
}

static void test_roughness(void **state)
{
    (void)state;
    rf_terrain *t = class_dem();
    double v[DW * DH], gt[6] = {0, 1, 0, DH, 0, -1};
    for (int r = 0; r < DH; r++)
        for (int c = 0; c < DW; c++)
            v[r * DW + c] = 0.5 * c + r;
    make_tif(at("rough.tif"), DW, DH, GDT_Float32, gt, 32632, NULL, v);
    rf_error err;
    if (rf_terrain_read_roughness(t, at("rough.tif"), 1, &err) != RF_OK)
        fail_msg("%s", err.msg);
    for (size_t j = 0; j + 1 < t->ny; j++)
        for (size_t i = 0; i + 1 < t->nx; i++) {
            double deg = 0.5 * (double)(i + 1) + (double)(DH - 2 - (int)j);
            assert_true(fabs(t->roughness[j * (t->nx - 1) + i] - deg * 3.14159265358979323846 / 180) < 1e-7);
        }
    v[3 * DW + 4] = 50;
    make_tif(at("rough50.tif"), DW, DH, GDT_Float32, gt, 32632, NULL, v);
    assert_int_equal(rf_terrain_read_roughness(t, at("rough50.tif"), 1, &err), RF_EINVAL);
    if (!strstr(err.msg, "holds 50 deg at map point (4, 5)") || !strstr(err.msg, "[0, 45]"))
        fail_msg("%s", err.msg);
    rf_terrain_free(t);
}

/* ---- GeoTIFF writer ---- */

static int leftovers(void)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int n = 0;
    while ((e = readdir(d)))
        n += strstr(e->d_name, ".part") != NULL;
    closedir(d);
    return n;
}

static void test_geotiff_round_trip(void **state)
{
    (void)state;
    enum { NXX = 300, NYY = 7 }; /* wider than a 256 tile */
    static float a[NXX * NYY], b[NXX * NYY];
    for (int k = 0; k < NXX * NYY; k++)
        a[k] = (float)k, b[k] = k % 5 ? (float)(0.5 * k) : NAN;
    terrain_band bands[2] = {{"passages", "-", a}, {"energy_p95", "J", b}};
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    OSRImportFromEPSG(srs, 2056);
    char *wkt;
    OSRExportToWkt(srs, &wkt);
    rf_error err;
    const char *path = at("hazard.tif");
    if (terrain_geotiff_write(path, wkt, NXX, NYY, 2600000, 1200000, 2.5, bands, 2, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(leftovers(), 0);
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    assert_non_null(ds);
    assert_int_equal(GDALGetRasterCount(ds), 2);
    double gt[6];
    GDALGetGeoTransform(ds, gt);
    assert_true(gt[0] == 2600000 && gt[1] == 2.5 && gt[2] == 0 && gt[3] == 1200000 + NYY * 2.5 && gt[4] == 0 &&
                gt[5] == -2.5);
    assert_true(OSRIsSame(GDALGetSpatialRef(ds), srs));
    const char *comp = GDALGetMetadataItem(ds, "COMPRESSION", "IMAGE_STRUCTURE");
    assert_non_null(comp);
    assert_string_equal(comp, "DEFLATE");
    const char *names[2] = {"passages [-]", "energy_p95 [J]"};
    static float back[NXX * NYY];
    for (int k = 0; k < 2; k++) {
        GDALRasterBandH h = GDALGetRasterBand(ds, k + 1);
        assert_string_equal(GDALGetDescription(h), names[k]);
        int has, bx, by;
        assert_true(isnan(GDALGetRasterNoDataValue(h, &has)) && has);
        assert_int_equal(GDALGetRasterDataType(h), GDT_Float32);
        GDALGetBlockSize(h, &bx, &by);
        assert_true(bx == 256 && by == 256);
        assert_int_equal(GDALRasterIO(h, GF_Read, 0, 0, NXX, NYY, back, NXX, NYY, GDT_Float32, 0, 0), CE_None);
        const float *src = k ? b : a;
        for (int r = 0; r < NYY; r++) /* raster row r = grid row NYY - 1 - r */
            for (int c = 0; c < NXX; c++) {
                float want = src[(NYY - 1 - r) * NXX + c], got = back[r * NXX + c];
                assert_true(isnan(want) ? isnan(got) : got == want);
            }
    }
    GDALClose(ds);
    char cmd[512];
    snprintf(cmd, sizeof cmd, "gdalinfo -stats %s > %s 2>&1", path, at("gdalinfo.txt"));
    if (system(cmd) == 0) {
        FILE *f = fopen(at("gdalinfo.txt"), "r");
        char line[512];
        int found = 0;
        while (fgets(line, sizeof line, f))
            found += strstr(line, "NoData Value=nan") != NULL;
        fclose(f);
        assert_int_equal(found, 2);
    }
    /* written again: the stale statistics of gdalinfo -stats go */
    assert_int_equal(terrain_geotiff_write(path, "", NXX, NYY, 0, 0, 1, bands, 1, &err), RF_OK);
    snprintf(cmd, sizeof cmd, "%s.aux.xml", path);
    assert_int_not_equal(access(cmd, F_OK), 0);
    assert_int_equal(terrain_geotiff_write(at("no/such/dir/x.tif"), "", 2, 2, 0, 0, 1, bands, 1, &err), RF_EIO);
    CPLFree(wkt);
    OSRDestroySpatialReference(srs);
}

/* ---- release ---- */

static const char *crs32632 = "\"crs\": {\"type\": \"name\", \"properties\": {\"name\": \"urn:ogc:def:crs:EPSG::32632\"}},";

static void write_geojson(const char *path, const char *crs, const char *features)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "{\"type\": \"FeatureCollection\", %s \"features\": [%s]}\n", crs, features);
    fclose(f);
}

#define FEAT(geom, props) "{\"type\": \"Feature\", \"properties\": {" props "}, \"geometry\": " geom "}"

static rf_terrain_release release_ok(const char *name, const char *count, int per_area)
{
    rf_terrain_release r;
    rf_error err;
    if (terrain_read_release_vector(at(name), NULL, count, per_area, &r, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_string_equal(r.file, at(name));
    return r;
}

static void release_free(rf_terrain_release *r)
{
    free(r->start), free(r->x), free(r->y), free(r->weight), free(r->file);
}

static void test_release_points_lines(void **state)
{
    (void)state;
    write_geojson(at("pts.geojson"), crs32632,
                  FEAT("{\"type\": \"Point\", \"coordinates\": [100, 200]}", "\"n\": 3") ","
                  FEAT("{\"type\": \"MultiPoint\", \"coordinates\": [[110, 210], [120, 220]]}", "\"n\": 4"));
    rf_terrain_release r = release_ok("pts.geojson", "n", 0);
    assert_int_equal(r.kind, RF_TERRAIN_POINTS);
    assert_int_equal(r.n_features, 3);
    const double px[3] = {100, 110, 120}, py[3] = {200, 210, 220}, pw[3] = {3, 2, 2};
    for (int k = 0; k < 3; k++) {
        assert_int_equal(r.start[k], k);
        assert_true(r.x[k] == px[k] && r.y[k] == py[k] && r.weight[k] == pw[k]);
    }
    assert_int_equal(r.start[3], 3);
    release_free(&r);
    r = release_ok("pts.geojson", NULL, 0); /* no count field: 1 per feature */
    assert_true(r.weight[0] == 1 && r.weight[1] == 0.5 && r.weight[2] == 0.5);
    release_free(&r);
    write_geojson(at("lines.geojson"), crs32632,
                  FEAT("{\"type\": \"LineString\", \"coordinates\": [[0, 0], [3, 4]]}", "\"n\": 2") ","
                  FEAT("{\"type\": \"MultiLineString\", \"coordinates\": [[[10, 0], [13, 4]], [[20, 0], [29, 12], [29, 12]]]}",
                       "\"n\": 8"));
    r = release_ok("lines.geojson", "n", 0);
    assert_int_equal(r.kind, RF_TERRAIN_LINES);
    assert_int_equal(r.n_features, 3);
    assert_true(r.start[0] == 0 && r.start[1] == 2 && r.start[2] == 4 && r.start[3] == 7);
    assert_true(r.weight[0] == 2 && r.weight[1] == 2 && r.weight[2] == 6); /* lengths 5, 5 and 15 */
    assert_true(r.x[5] == 29 && r.y[5] == 12);
    release_free(&r);
    /* the same lines as a shapefile */
    char cmd[512];
    snprintf(cmd, sizeof cmd, "ogr2ogr -f 'ESRI Shapefile' %s %s > /dev/null 2>&1", at("lines.shp"), at("lines.geojson"));
    if (system(cmd) != 0) {
        print_message("ogr2ogr not available: shapefile not checked\n");
        return;
    }
    r = release_ok("lines.shp", "n", 0);
    assert_int_equal(r.n_features, 3);
    assert_true(r.start[3] == 7 && r.weight[0] == 2 && r.weight[1] == 2 && r.weight[2] == 6);
    assert_true(r.x[5] == 29 && r.y[5] == 12);
    release_free(&r);
}

static void test_release_polygons(void **state)
{
    (void)state;
    write_geojson(at("poly.geojson"), crs32632,
                  FEAT("{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]]]}",
                       "\"d\": 0.02") ","
                  FEAT("{\"type\": \"MultiPolygon\", \"coordinates\": [[[[20, 0], [30, 0], [30, 10], [20, 0]]], "
                       "[[[40, 0], [40, 30], [50, 0], [40, 0]]]]}", "\"d\": 0.5"));
    rf_terrain_release r = release_ok("poly.geojson", "d", 1);
    assert_int_equal(r.kind, RF_TERRAIN_POLYGONS);
    assert_int_equal(r.n_features, 3);
    assert_true(r.start[1] == 4 && r.start[2] == 7 && r.start[3] == 10); /* rings without the repeated vertex */
    /* areas 100, 50, 150 */
    assert_close(r.weight[0], 2, 1e-15);
    assert_close(r.weight[1], 25, 1e-15);
    assert_close(r.weight[2], 75, 1e-15);
    assert_true(r.x[3] == 0 && r.y[3] == 10);
    release_free(&r);
    r = release_ok("poly.geojson", "d", 0); /* a count per feature: shared by area */
    assert_close(r.weight[0], 0.02, 1e-15);
    assert_close(r.weight[1], 0.125, 1e-15);
    assert_close(r.weight[2], 0.375, 1e-15);
    release_free(&r);
}

static void release_fails(const char *name, const char *count, int per_area, const char *want)
{
    rf_terrain_release r;
    rf_error err;
    assert_int_not_equal(terrain_read_release_vector(at(name), NULL, count, per_area, &r, &err), RF_OK);
    assert_null(r.x);
    if (!strstr(err.msg, want) || !strstr(err.msg, name))
        fail_msg("message '%s' lacks '%s'", err.msg, want);
}

static void test_release_refused(void **state)
{
    (void)state;
    write_geojson(at("hole.geojson"), crs32632,
                  FEAT("{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [10, 0], [10, 10], [0, 0]], "
                       "[[5, 1], [6, 1], [6, 2], [5, 1]]]}", "\"n\": 1"));
    release_fails("hole.geojson", NULL, 0, "a polygon with a hole");
    write_geojson(at("mixed.geojson"), crs32632,
                  FEAT("{\"type\": \"Point\", \"coordinates\": [0, 0]}", "\"n\": 1") ","
                  FEAT("{\"type\": \"LineString\", \"coordinates\": [[0, 0], [1, 1]]}", "\"n\": 1"));
    release_fails("mixed.geojson", NULL, 0, "holds one kind");
    write_geojson(at("wgs.geojson"), "", FEAT("{\"type\": \"Point\", \"coordinates\": [7.1, 46.2]}", "\"n\": 1"));
    release_fails("wgs.geojson", NULL, 0, "geographic coordinates");
    write_geojson(at("empty.geojson"), crs32632, "");
    release_fails("empty.geojson", NULL, 0, "holds no feature");
    release_fails("pts.geojson", "count", 0, "has no field 'count'");
    release_fails("pts.geojson", "n", 1, "a count per area needs polygons");
    write_geojson(at("zero.geojson"), crs32632, FEAT("{\"type\": \"Point\", \"coordinates\": [0, 0]}", "\"n\": 0"));
    release_fails("zero.geojson", "n", 0, "has a positive count");
}

static void test_release_raster(void **state)
{
    (void)state;
    enum { W = 4, H = 3 };
    double v[W * H] = {0, 2, 0, 255, /* north row */
                       0, 0, 0, 0,
                       1.5, 0, -1, 3};
    double gt[6] = {500, 5, 0, 800, 0, -5}, nd = 255;
    make_tif(at("rel.tif"), W, H, GDT_Float32, gt, 32632, &nd, v);
    rf_terrain_release r;
    rf_error err;
    if (terrain_read_release_raster(at("rel.tif"), 1, &r, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(r.kind, RF_TERRAIN_POLYGONS);
    assert_int_equal(r.n_features, 3);
    /* (col 1, row 0) w 2; (col 0, row 2) w 1.5; (col 3, row 2) w 3 */
    const double w[3] = {2, 1.5, 3}, xw[3] = {505, 500, 515}, ys[3] = {795, 785, 785};
    for (int k = 0; k < 3; k++) {
        assert_int_equal(r.start[k], 4 * k);
        assert_true(r.weight[k] == w[k]);
        const double *x = r.x + 4 * k, *y = r.y + 4 * k;
        assert_true(x[0] == xw[k] && y[0] == ys[k] && x[1] == xw[k] + 5 && y[1] == ys[k]);
        assert_true(x[2] == xw[k] + 5 && y[2] == ys[k] + 5 && x[3] == xw[k] && y[3] == ys[k] + 5);
    }
    release_free(&r);
    for (int k = 0; k < W * H; k++)
        v[k] = 0;
    make_tif(at("rel0.tif"), W, H, GDT_Float32, gt, 32632, &nd, v);
    assert_int_equal(terrain_read_release_raster(at("rel0.tif"), 1, &r, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "no cell with a positive count"));
}

/* ---- GeoPackage ---- */

static void test_gpkg(void **state)
{
    (void)state;
    double start[9] = {0}, end[9] = {10, 20, 30, 11, 21, 31, 12, 22, 32};
    double runout[3] = {5, 0, 7.5}, reach[3] = {0.5, NAN, 0.25};
    unsigned char st[3] = {RF_TRAJ_STOPPED, RF_TRAJ_EXITED, RF_TRAJ_STEP_LIMIT};
    rf_terrain_event ev[3];
    memset(ev, 0, sizeof ev);
    for (int e = 0; e < 3; e++)
        ev[e].p[0] = 100 + e, ev[e].p[1] = 200 - e, ev[e].p[2] = 50 - 10 * e;
    rf_terrain_result rec[2];
    memset(rec, 0, sizeof rec);
    rec[0].state = RF_TRAJ_STOPPED, rec[0].events = ev, rec[0].n_events = 3;
    rec[1].state = RF_TRAJ_EXITED, rec[1].events = ev + 1, rec[1].n_events = 2;
    rf_terrain_samples ts = {.start = start, .end = end, .runout = runout, .reach_angle = reach, .n_recorded = 2, .recorded = rec};
    rf_traj_ensemble ens;
    memset(&ens, 0, sizeof ens);
    ens.samples = 3, ens.state = st, ens.terrain = &ts;
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    OSRImportFromEPSG(srs, 32632);
    char *wkt;
    OSRExportToWkt(srs, &wkt);
    rf_error err;
    const char *path = at("paths.gpkg");
    if (terrain_gpkg_write(path, wkt, &ens, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(terrain_gpkg_write(path, wkt, &ens, &err), RF_OK); /* over an existing file */
    assert_int_equal(leftovers(), 0);
    GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_VECTOR, NULL, NULL, NULL);
    assert_non_null(ds);
    OGRLayerH ep = GDALDatasetGetLayerByName(ds, "end_points"), tr = GDALDatasetGetLayerByName(ds, "trajectories");
    assert_non_null(ep);
    assert_non_null(tr);
    assert_true(OSRIsSame(OGR_L_GetSpatialRef(ep), srs) && OSRIsSame(OGR_L_GetSpatialRef(tr), srs));
    assert_int_equal(OGR_L_GetFeatureCount(ep, TRUE), 3);
    assert_int_equal(OGR_L_GetFeatureCount(tr, TRUE), 2);
    OGRFeatureDefnH d = OGR_L_GetLayerDefn(ep);
    int fs = OGR_FD_GetFieldIndex(d, "sample"), fst = OGR_FD_GetFieldIndex(d, "state");
    int fr = OGR_FD_GetFieldIndex(d, "runout_m"), fa = OGR_FD_GetFieldIndex(d, "reach_angle_deg");
    assert_true(fs >= 0 && fst >= 0 && fr >= 0 && fa >= 0);
    OGRFeatureH f;
    int k = 0;
    OGR_L_ResetReading(ep);
    while ((f = OGR_L_GetNextFeature(ep))) {
        OGRGeometryH g = OGR_F_GetGeometryRef(f);
        assert_int_equal(OGR_F_GetFieldAsInteger64(f, fs), k);
        assert_true(OGR_G_GetX(g, 0) == end[3 * k] && OGR_G_GetY(g, 0) == end[3 * k + 1] &&
                    OGR_G_GetZ(g, 0) == end[3 * k + 2]);
        assert_string_equal(OGR_F_GetFieldAsString(f, fst), rf_traj_state_name((rf_traj_state)st[k]));
        assert_true(OGR_F_GetFieldAsDouble(f, fr) == runout[k]);
        if (k == 1)
            assert_false(OGR_F_IsFieldSetAndNotNull(f, fa));
        else
            assert_close(OGR_F_GetFieldAsDouble(f, fa), reach[k] * 180 / 3.14159265358979323846, 1e-15);
        OGR_F_Destroy(f);
        k++;
    }
    k = 0;
    OGR_L_ResetReading(tr);
    while ((f = OGR_L_GetNextFeature(tr))) {
        OGRGeometryH g = OGR_F_GetGeometryRef(f);
        assert_int_equal(OGR_F_GetFieldAsInteger(f, OGR_FD_GetFieldIndex(OGR_L_GetLayerDefn(tr), "sample")), k);
        assert_int_equal(OGR_G_GetPointCount(g), (int)rec[k].n_events);
        for (int e = 0; e < OGR_G_GetPointCount(g); e++)
            assert_true(OGR_G_GetX(g, e) == rec[k].events[e].p[0] && OGR_G_GetY(g, e) == rec[k].events[e].p[1] &&
                        OGR_G_GetZ(g, e) == rec[k].events[e].p[2]);
        OGR_F_Destroy(f);
        k++;
    }
    assert_int_equal(k, 2);
    GDALClose(ds);
    /* read back as release points from its layer end_points */
    rf_terrain_release r;
    if (terrain_read_release_vector(path, "end_points", NULL, 0, &r, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(r.kind, RF_TERRAIN_POINTS);
    assert_int_equal(r.n_features, 3);
    for (k = 0; k < 3; k++)
        assert_true(r.x[k] == end[3 * k] && r.y[k] == end[3 * k + 1] && r.weight[k] == 1);
    release_free(&r);
    assert_int_equal(terrain_read_release_vector(path, "nope", NULL, 0, &r, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "has no layer named nope"));
    CPLFree(wkt);
    OSRDestroySpatialReference(srs);
    ens.terrain = NULL;
    assert_int_equal(terrain_gpkg_write(path, "", &ens, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "not a complete terrain run"));
}

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/rf_terrain_io_XXXXXX");
    if (!mkdtemp(dir))
        return -1;
    GDALAllRegister();
    CPLSetErrorHandler(CPLQuietErrorHandler); /* the test's own GDAL calls */
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd) == 0 ? 0 : -1;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dem_plane),          cmocka_unit_test(test_dem_row_order),
        cmocka_unit_test(test_dem_nodata),         cmocka_unit_test(test_dem_refused),
        cmocka_unit_test(test_gdal_message_kept),
        cmocka_unit_test(test_classes_coarse),     cmocka_unit_test(test_classes_same_grid),
        cmocka_unit_test(test_classes_refused),    cmocka_unit_test(test_roughness),
        cmocka_unit_test(test_geotiff_round_trip), cmocka_unit_test(test_release_points_lines),
        cmocka_unit_test(test_release_polygons),   cmocka_unit_test(test_release_refused),
        cmocka_unit_test(test_release_raster),     cmocka_unit_test(test_gpkg),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

#else

static void test_without_gdal(void **state)
{
    (void)state;
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_read("dem.tif", 1, &t, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "without GDAL"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_without_gdal)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}

#endif
