/* test_terrain_report.c - the maps and report.html of a terrain run
 * (terrain_report.c, terrain_maps.c) on hand-made data: the hillshade
 * against its closed form on planes of any aspect (and against the normal
 * of rf_terrain_height on a curved cell), the maps' pages to scale (the
 * same metres per pixel on both axes, the PNG that size; hillshade, colour
 * scale and no-data white where they belong), and the report's
 * answer against counts and percentiles known from the construction; the
 * page rendered by headless Chromium has every image and none broken. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "trajectory/terrain_internal.h"
#include "test_util.h"

#include <sys/stat.h>
#include <unistd.h>

#define PI 3.14159265358979323846

/* Under -DROCKFUZZ_SANITIZE=ON: fontconfig (loaded by cairo for the plots)
 * keeps process-lifetime caches; they are not leaks of ours. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:libfontconfig.so\n"; }

/* max(0, n . l), n the upward normal of z = a x + b y, l from azimuth 315, altitude 45 deg. */
static double shade_plane(double a, double b)
{
    double l[3] = {-0.5, 0.5, sqrt(0.5)}, s = 1 / sqrt(1 + a * a + b * b);
    return fmax(0, (-a * l[0] - b * l[1] + l[2]) * s);
}

static rf_terrain *plane(size_t nx, size_t ny, double dx, double dy, double a, double b)
{
    double *z = malloc(nx * ny * sizeof *z);
    for (size_t j = 0; j < ny; j++)
        for (size_t i = 0; i < nx; i++)
            z[j * nx + i] = 100 + a * (double)i * dx + b * (double)j * dy;
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(nx, ny, 1000, 2000, dx, dy, z, &t, &err), RF_OK);
    free(z);
    return t;
}

/* Planes facing every direction: flat 1/sqrt(2); facing the light (NW) brighter; facing away dark, 0 when
 * steeper than 45 deg toward the south-east. */
static void test_hillshade_planes(void **state)
{
    (void)state;
    static const double ab[][2] = {{0, 0}, {0.5, -0.5}, {-0.3, 0.8}, {2, 0}, {0, -2}, {-1.5, 1.5}, {1e-3, 7}};
    for (size_t k = 0; k < sizeof ab / sizeof *ab; k++) {
        rf_terrain *t = plane(5, 4, 2, 3, ab[k][0], ab[k][1]);
        for (size_t j = 0; j < 3; j++)
            for (size_t i = 0; i < 4; i++)
                assert_true(fabs(terrain_hillshade_cell(t, i, j) - shade_plane(ab[k][0], ab[k][1])) < 1e-14);
        rf_terrain_free(t);
    }
    assert_true(fabs(shade_plane(0, 0) - sqrt(0.5)) < 1e-15);
    assert_true(shade_plane(-1.5, 1.5) == 0);           /* 64.8 deg slope facing the south-east */
    assert_true(shade_plane(1, -1) > shade_plane(0, 0)); /* facing the light */
}

/* A curved cell: the shade is that of rf_terrain_height's normal at the cell's centre; no data: NaN. */
static void test_hillshade_curved_and_nodata(void **state)
{
    (void)state;
    double z[9] = {0, 3, 1, 2, 7, 4, 5, 1, NAN};
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(3, 3, 0, 0, 2, 4, z, &t, &err), RF_OK);
    double h, n[3], l[3] = {-0.5, 0.5, sqrt(0.5)};
    assert_true(rf_terrain_height(t, 1, 2, &h, n));
    assert_true(fabs(terrain_hillshade_cell(t, 0, 0) - fmax(0, n[0] * l[0] + n[1] * l[1] + n[2] * l[2])) < 1e-14);
    assert_true(rf_terrain_height(t, 1, 6, &h, n));
    assert_true(fabs(terrain_hillshade_cell(t, 0, 1) - fmax(0, n[0] * l[0] + n[1] * l[1] + n[2] * l[2])) < 1e-14);
    assert_true(isnan(terrain_hillshade_cell(t, 1, 1)));
    rf_terrain_free(t);
}

/* Width and height of a PNG (its IHDR). */
static void png_size(const char *path, int *w, int *h)
{
    unsigned char b[24];
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fread(b, 1, 24, f), 24);
    fclose(f);
    assert_memory_equal(b + 1, "PNG", 3);
    *w = b[16] << 24 | b[17] << 16 | b[18] << 8 | b[19];
    *h = b[20] << 24 | b[21] << 16 | b[22] << 8 | b[23];
}

/* Wide, tall, square and thin extents: metres per pixel equal on both axes within half a pixel. */
static void test_layout_to_scale(void **state)
{
    (void)state;
    static const double ext[][2] = {{500, 300}, {300, 500}, {1000, 1000}, {2000, 120}, {50, 3000}, {1e4, 7e3}};
    for (size_t k = 0; k < sizeof ext / sizeof *ext; k++) {
        terrain_map_layout L = terrain_map_layout_of(2.6e6, 2.6e6 + ext[k][0], 1.1e6, 1.1e6 + ext[k][1]);
        double sx = ext[k][0] / L.map_w, sy = ext[k][1] / L.map_h;
        assert_true(fabs(sx - sy) <= sx * 0.5 / fmin(L.map_w, L.map_h) + 1e-12);
        assert_true(fabs(L.m_per_px - sx) < 1e-12 * sx);
        assert_true(L.map_w <= 780 && L.map_h <= 1000 && L.width > L.map_w && L.height > L.map_h);
    }
}

/* ---- a hand-made run on a valley 300 m x 200 m (DEM 4 m cells) ---- */

#define NX 76
#define NY 51
#define N 1000

typedef struct {
    rf_traj_spec s;
    rf_terrain_def td;
    rf_traj_material mat[3];
    rf_traj_collector col[1];
    size_t bstart[2];
    double bx[2], by[2];
    size_t rstart[2];
    double rx[4], ry[4], rw[1];
    rf_traj_ensemble e;
    rf_terrain_samples ts;
    rf_terrain_result rec[3];
    rf_terrain_event ev[3][4];
    unsigned char state[N];
    double runout_x[N], rebound[N], start[3 * N], end[3 * N], runout[N], reach[N];
    rf_traj_crossing cross[N];
    rf_terrain *dem;
} run;

/* Ground: z = 200 - 0.6 x (relative to x0) with a gully along y = 100; material by x: rock, talus, soil. */
static rf_terrain *valley(void)
{
    static double z[NX * NY];
    for (size_t j = 0; j < NY; j++)
        for (size_t i = 0; i < NX; i++) {
            double x = 4.0 * (double)i, y = 4.0 * (double)j;
            z[j * NX + i] = 200 - (x < 60 ? 1.5 * x : 90 + 0.4 * (x - 60)) + 0.002 * (y - 100) * (y - 100);
        }
    z[3 * NX + 70] = NAN; /* a no-data node: white on the maps */
    rf_terrain *t;
    rf_error err;
    assert_int_equal(rf_terrain_from_nodes(NX, NY, 2600000, 1100000, 4, 4, z, &t, &err), RF_OK);
    t->material = calloc((NX - 1) * (NY - 1), sizeof *t->material);
    for (size_t j = 0; j + 1 < NY; j++)
        for (size_t i = 0; i + 1 < NX; i++)
            t->material[j * (NX - 1) + i] = i < 15 ? 0 : i < 50 ? 1 : 2;
    return t;
}

/* Block i: i % 10 < 6 stops on talus (x 100..190 m), 6, 7 held by the fence at x 220 m, 8 breaks through it and
 * stops on soil at x 260 m, 9 exits at the east edge (x 300 m).  Runout = end x - start x (start x 20 m). */
static void fill(run *r)
{
    memset(r, 0, sizeof *r);
    r->dem = valley();
    double X0 = 2600000, Y0 = 1100000;
    static char *names[3] = {"rock", "talus", "soil"};
    for (int m = 0; m < 3; m++)
        r->mat[m] = (rf_traj_material){names[m], 0.4, 0.8, 30 * PI / 180, 0.1, 5 * PI / 180, {0}};
    r->col[0] = (rf_traj_collector){.name = "fence", .capacity = 2e6, .height = 4};
    r->bstart[1] = 2, r->bx[0] = r->bx[1] = X0 + 220, r->by[0] = Y0 + 40, r->by[1] = Y0 + 160;
    r->rstart[1] = 4, r->rw[0] = 1;
    double rx[4] = {10, 30, 30, 10}, ry[4] = {80, 80, 120, 120};
    for (int k = 0; k < 4; k++)
        r->rx[k] = X0 + rx[k], r->ry[k] = Y0 + ry[k];
    r->td = (rf_terrain_def){.dem = "valley.asc", .raster_cell = 10, .statistics = 31, .barrier_start = r->bstart,
                             .barrier_x = r->bx, .barrier_y = r->by};
    r->td.release = (rf_terrain_release){RF_TERRAIN_POLYGONS, 1, r->rstart, r->rx, r->ry, r->rw, NULL};
    rf_traj_spec *s = &r->s;
    s->name = "valley", s->gravity = 9.81, s->n_materials = 3, s->materials = r->mat, s->sphere = 1;
    s->radius = 0.5, s->density = 2600, s->mass = 4.0 / 3.0 * PI * 0.125 * 2600, s->height0 = 1;
    s->n_collectors = 1, s->collectors = r->col, s->samples = N, s->seed = 1, s->terrain = &r->td;
    s->release_kind = RF_TRAJ_RELEASE_MAP;
    for (size_t i = 0; i < N; i++) {
        int k = (int)(i % 10);
        double xe = k < 6 ? 100 + 15 * k + 0.01 * (double)(i / 10) : k < 8 ? 220 : k == 8 ? 260 : 300;
        double ye = 60 + 0.08 * (double)i, xs = 20, ys = 100;
        r->state[i] = k == 9 ? RF_TRAJ_EXITED : RF_TRAJ_STOPPED;
        r->start[3 * i] = X0 + xs, r->start[3 * i + 1] = Y0 + ys, r->start[3 * i + 2] = 175;
        r->end[3 * i] = X0 + xe, r->end[3 * i + 1] = Y0 + ye, r->end[3 * i + 2] = 200 - 90 - 0.4 * (xe - 60);
        r->runout[i] = r->runout_x[i] = hypot(xe - xs, ye - ys);
        r->reach[i] = atan((r->start[3 * i + 2] - r->end[3 * i + 2]) / r->runout[i]);
        r->rebound[i] = 0.5 + 0.001 * (double)i;
        rf_traj_crossing *c = &r->cross[i];
        if (k >= 6) {
            c->reached = 1, c->stopped_by_barrier = k < 8, c->x = X0 + 220, c->y = Y0 + ye, c->along = ye - 40;
            c->total_energy = c->translational_energy = (k < 8 ? 1e6 : 3e6) + 100.0 * (double)i;
            c->energy_after = k == 8 ? c->total_energy - 2e6 : c->total_energy;
            c->height_lowest = k == 9 ? 5 : 1, c->height_centre = c->height_lowest + 0.5, c->speed = 20;
        }
    }
    for (int q = 0; q < 3; q++) {
        rf_terrain_result *res = &r->rec[q];
        res->events = r->ev[q], res->n_events = 4;
        for (int k = 0; k < 4; k++) {
            r->ev[q][k].p[0] = X0 + 20 + 60.0 * k + 5 * q, r->ev[q][k].p[1] = Y0 + 100 + 10.0 * k * (q - 1);
            r->ev[q][k].kind = k ? RF_EV_IMPACT : RF_EV_RELEASE;
        }
    }
    r->ts = (rf_terrain_samples){.start = r->start, .end = r->end, .runout = r->runout, .reach_angle = r->reach, .n_recorded = 3, .recorded = r->rec};
    rf_traj_ensemble *e = &r->e;
    e->samples = N, e->n_collectors = 1, e->state = r->state, e->runout_x = r->runout_x;
    e->rebound_height = r->rebound, e->crossings = r->cross, e->terrain = &r->ts, e->wall_seconds = 0.5;
}

/* Bands on the report's grid: passages (0 west of x = 100 m), reach_probability, energy_p95 (NaN there). */
static terrain_band *bands_of(const terrain_map_grid *g, size_t *n)
{
    terrain_band *b = calloc(3, sizeof *b);
    static const char *names[3] = {"passages", "reach_probability", "energy_p95"}, *units[3] = {"", "", "J"};
    for (int k = 0; k < 3; k++) {
        snprintf(b[k].name, sizeof b[k].name, "%s", names[k]);
        b[k].unit = units[k];
        b[k].data = malloc(g->nx * g->ny * sizeof *b[k].data);
        for (size_t j = 0; j < g->ny; j++)
            for (size_t i = 0; i < g->nx; i++) {
                double x = ((double)i + 0.5) * g->cell, y = ((double)j + 0.5) * g->cell;
                double p = x < 100 ? 0 : exp(-(y - 100) * (y - 100) / 800) * (1 - x / 400);
                b[k].data[j * g->nx + i] = (float)(k == 0 ? floor(N * p) : k == 1 ? p : p > 0 ? 2e6 * p : NAN);
            }
    }
    *n = 3;
    return b;
}

/* The colour of the map point (x, y) [m] of a map PNG (tests/png_pixels.py decodes it). */
static void map_colour(const char *png, const terrain_map_layout *L, double x, double y, int rgb[3])
{
    char cmd[1024];
    int px = L->map_left + (int)((x - L->xmin) / L->m_per_px), py = L->map_top + (int)((L->ymax - y) / L->m_per_px);
    snprintf(cmd, sizeof cmd, "python3 %s/tests/png_pixels.py %s %d %d", ROCKFUZZ_SOURCE_DIR, png, px, py);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    assert_int_equal(fscanf(p, "%d %d %d", &rgb[0], &rgb[1], &rgb[2]), 3);
    assert_int_equal(pclose(p), 0);
}

/* On the passages map: the hillshade (grey) where no block passed, the colour scale where blocks did, white on
 * the no-data cells (a node of the DEM at (280, 12) m is NaN). */
static void check_map_colours(const char *dir, const terrain_map_layout *L)
{
    char png[256];
    int c[3];
    snprintf(png, sizeof png, "%s/terrain_map_passages.png", dir);
    map_colour(png, L, 2600000 + 50, 1100000 + 150, c);
    assert_true(c[0] == c[1] && c[1] == c[2] && c[0] > 20 && c[0] < 250); /* grey: the hillshade */
    map_colour(png, L, 2600000 + 150, 1100000 + 100, c);
    assert_true(c[0] - c[2] > 60);                                           /* yellow to red */
    map_colour(png, L, 2600000 + 280, 1100000 + 12, c);
    assert_true(c[0] == 255 && c[1] == 255 && c[2] == 255);                  /* no data */
    map_colour(png, L, 2600000 + 250, 1100000 + 12, c);
    assert_true(c[0] == c[1] && c[1] == c[2] && c[0] < 250);                 /* 0 passages: hillshade */
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    rewind(f);
    char *s = malloc((size_t)n + 1);
    assert_int_equal(fread(s, 1, (size_t)n, f), (size_t)n);
    s[n] = 0;
    fclose(f);
    return s;
}

static void contains(const char *html, const char *what)
{
    if (!strstr(html, what))
        fail_msg("report.html lacks \"%s\"", what);
}

/* Type 7 percentile of v (sorted copy). */
static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}
static double type7(const double *v, size_t n, double p)
{
    double *w = malloc(n * sizeof *w);
    memcpy(w, v, n * sizeof *w);
    qsort(w, n, sizeof *w, cmp);
    double h = (double)(n - 1) * p / 100, lo = floor(h);
    size_t k = (size_t)lo;
    double r = k + 1 < n ? w[k] + (h - lo) * (w[k + 1] - w[k]) : w[k];
    free(w);
    return r;
}

/* The grid without a hazard: rasters.cell from the DEM's south-west node, covering it. */
static void test_report_grid(void **state)
{
    (void)state;
    run *r = malloc(sizeof *r);
    fill(r);
    terrain_map_grid g;
    terrain_report_grid(&r->s, &r->e, r->dem, &g);
    assert_int_equal(g.nx, 30), assert_int_equal(g.ny, 20);
    assert_true(g.cell == 10 && g.x0 == 2600000 && g.y0 == 1100000);
    r->td.raster_cell = 0;
    terrain_report_grid(&r->s, &r->e, r->dem, &g);
    assert_int_equal(g.nx, NX - 1), assert_int_equal(g.ny, NY - 1);
    assert_true(g.cell == 4);
    rf_terrain_free(r->dem);
    free(r);
}

static void render_check(const char *html, size_t images)
{
    if (system("command -v chromium > /dev/null 2>&1 || command -v chromium-browser > /dev/null 2>&1") != 0) {
        printf("render check SKIPPED: chromium not found\n");
        return;
    }
    char cmd[2048];
    snprintf(cmd, sizeof cmd,
             "bash -c '. \"$1/tests/cli_lib.sh\" none \"$1\"; cli_render_check terrain_report \"$2\" %zu; "
             "exit $fails' check %s %s",
             images, ROCKFUZZ_SOURCE_DIR, html);
    assert_int_equal(system(cmd), 0);
}

static void test_report(void **state)
{
    (void)state;
    run *r = malloc(sizeof *r);
    fill(r);
    rf_traj_stats st;
    rf_error err;
    assert_int_equal(rf_traj_stats_compute_spec(&r->s, &r->e, &st, &err), RF_OK);
    terrain_map_grid g;
    terrain_report_grid(&r->s, &r->e, r->dem, &g);
    size_t nb;
    terrain_band *b = bands_of(&g, &nb);
    char dir[] = "/tmp/terrain_report_XXXXXX", path[256];
    assert_non_null(mkdtemp(dir));
    if (terrain_write_maps(dir, &r->s, &r->e, &st, r->dem, b, nb, &err) != RF_OK)
        fail_msg("%s", err.msg);
    /* every map to scale: the page of the layout */
    terrain_map_layout L = terrain_map_layout_of(2600000, 2600300, 1100000, 1100200);
    static const char *stems[4] = {"terrain_endpoints", "terrain_map_passages", "terrain_map_reach_probability",
                                   "terrain_map_energy_p95"};
    struct stat sb;
    snprintf(path, sizeof path, "%s/terrain_barrier_fence.png", dir);
    assert_int_equal(stat(path, &sb), 0);
    for (int k = 0; k < 4; k++) {
        int w, h;
        snprintf(path, sizeof path, "%s/%s.png", dir, stems[k]);
        png_size(path, &w, &h);
        assert_int_equal(w, L.width), assert_int_equal(h, L.height);
    }
    check_map_colours(dir, &L);
    snprintf(path, sizeof path, "%s/report.html", dir);
    char *html = slurp(path);
    /* the answer, from the construction: 60 % on talus, 20 % held, 10 % on soil, 10 % exit */
    contains(html, "Of 1&#8201;000 blocks released, 60.0&nbsp;% stop on talus, 10.0&nbsp;% stop on soil, "
                   "20.0&nbsp;% are held by fence, 10.0&nbsp;% leave the DEM.");
    char want[300];
    snprintf(want, sizeof want, "the 95th percentile %.0f&nbsp;m", type7(r->runout, N, 95));
    contains(html, want);
    double deg[N];
    for (size_t i = 0; i < N; i++)
        deg[i] = r->reach[i] * 180 / PI;
    snprintf(want, sizeof want, "reach angle (Fahrb&ouml;schung) of %.1f&deg; or more", type7(deg, N, 5));
    contains(html, want);
    /* at the fence 40 % arrive; 10 % pass above 4 m; energy above 2 MJ for blocks 8 and 9: 20 % */
    contains(html, "At fence, 40.0&nbsp;% of the blocks arrive");
    contains(html, "above its 4&nbsp;m height for 10.0&nbsp;%");
    contains(html, "above its 2000&nbsp;kJ capacity for 20.0&nbsp;%");
    contains(html, "it holds 20.0&nbsp;%, 10.0&nbsp;% break through and 10.0&nbsp;% fly over");
    contains(html, "<td class=l>fence</td><td>120.0</td><td>4</td><td>2000</td><td>40.00</td><td>20.00</td>"
                   "<td>10.00</td><td>10.00</td>");
    contains(html, "30 x 20 cells of 10 m");
    assert_int_equal(strstr(html, "missing") == NULL, 1);
    free(html);
    render_check(path, 5);
    terrain_bands_free(b, nb);
    rf_traj_stats_free(&st);
    rf_terrain_free(r->dem);
    free(r);
    if (getenv("TERRAIN_REPORT_KEEP")) { /* to look at it */
        printf("kept %s\n", dir);
        return;
    }
    snprintf(path, sizeof path, "rm -rf %s", dir);
    assert_int_equal(system(path), 0);
}

/* A band with no value anywhere still gets its map (said in its title), a run without barriers its report, and
 * a terrain of one material (no class raster) names it. */
static void test_report_empty_band(void **state)
{
    (void)state;
    run *r = malloc(sizeof *r);
    fill(r);
    r->s.n_collectors = 0, r->e.n_collectors = 0;
    rf_traj_stats st;
    rf_error err;
    assert_int_equal(rf_traj_stats_compute_spec(&r->s, &r->e, &st, &err), RF_OK);
    terrain_map_grid g;
    terrain_report_grid(&r->s, &r->e, r->dem, &g);
    terrain_band b = {"height_p95", "m", malloc(g.nx * g.ny * sizeof(float))};
    for (size_t k = 0; k < g.nx * g.ny; k++)
        b.data[k] = NAN;
    char dir[] = "/tmp/terrain_report_XXXXXX", path[256];
    assert_non_null(mkdtemp(dir));
    if (terrain_write_maps(dir, &r->s, &r->e, &st, r->dem, &b, 1, &err) != RF_OK)
        fail_msg("%s", err.msg);
    snprintf(path, sizeof path, "%s/terrain_map_height_p95.png", dir);
    struct stat sb;
    assert_int_equal(stat(path, &sb), 0);
    snprintf(path, sizeof path, "%s/report.html", dir);
    char *html = slurp(path);
    contains(html, "Of 1&#8201;000 blocks released, 60.0&nbsp;% stop on talus, 30.0&nbsp;% stop on soil, "
                   "10.0&nbsp;% leave the DEM.");
    assert_null(strstr(html, "<h2>Barriers</h2>"));
    free(html);
    /* without a class raster every block stops on the spec's one material */
    free(r->dem->material);
    r->dem->material = NULL, r->td.material = 1;
    if (terrain_write_maps(dir, &r->s, &r->e, &st, r->dem, &b, 1, &err) != RF_OK)
        fail_msg("%s", err.msg);
    html = slurp(path);
    contains(html, "Of 1&#8201;000 blocks released, 90.0&nbsp;% stop on talus, 10.0&nbsp;% leave the DEM.");
    free(html);
    free(b.data);
    rf_traj_stats_free(&st);
    rf_terrain_free(r->dem);
    free(r);
    snprintf(path, sizeof path, "rm -rf %s", dir);
    assert_int_equal(system(path), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hillshade_planes),     cmocka_unit_test(test_hillshade_curved_and_nodata),
        cmocka_unit_test(test_layout_to_scale),      cmocka_unit_test(test_report_grid),
        cmocka_unit_test(test_report),               cmocka_unit_test(test_report_empty_band),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
