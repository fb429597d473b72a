/* terrain_internal.h - what the terrain files share (terrain.h): the
 * surface's data and its cell evaluation, the prepared world, the state of
 * one running 3D trajectory, the "piece" of path each phase emits (for the
 * barriers, the hazard rasters and the records), and each file's functions:
 *   terrain_grid.c      the surface from nodes, height and normal
 *   terrain_io*.c       GDAL/OGR: DEM, classes, roughness (terrain_io.c), release vectors and
 *                       rasters (terrain_io_release.c), GeoTIFF and GeoPackage (terrain_io_write.c)
 *   terrain_flight.c    exact first impact of a parabola with the bilinear surface
 *   terrain_bounce.c    the bounce laws in the local frame of the normal (3D)
 *   terrain_contact*.c  sliding and rolling on the surface (terrain_contact_internal.h)
 *   terrain_barrier.c   barrier crossings of a piece (first crossing, capacity rule)
 *   terrain_fly.c       the flight phase: first impact, the flight's piece, the impact
 *   terrain_simulate.c  one trajectory: the state machine over those
 *   terrain_hazard.c    hazard raster accumulators (counts, log histograms), merge, percentiles
 *   terrain_release.c   release features: the point at given uniforms
 *   terrain_spec.c      rf_terrain_def free / copy / hash / checks
 *   terrain_world.c     the world: DEM, classes, barrier lines, release set, impact table
 *   traj_yaml_terrain.c the `terrain:` part of a trajectory file (release, barriers, rasters)
 *   terrain_montecarlo.c ensembles on terrain (threads; same bits at any thread count)
 *   terrain_parts.c     a run in parts (MPI ranks): a part packed, parts joined
 *   terrain_output.c    JSON, CSV, GeoPackage; terrain_report.c maps and report.html */
#ifndef ROCKFUZZ_TERRAIN_INTERNAL_H
#define ROCKFUZZ_TERRAIN_INTERNAL_H

#include "rockfuzz/terrain.h"
#include "trajectory/traj_internal.h"

#include <math.h>
#include <stdint.h>

/* ---- the surface ---- */

struct rf_terrain {
    size_t nx, ny;              /* nodes; cells (nx - 1) x (ny - 1) */
    double x0, y0, dx, dy;      /* node (i, j) at (x0 + i dx, y0 + j dy), j to the north */
    double *z;                  /* ny * nx, z[j nx + i]; NaN: no data */
    unsigned char *valid;       /* (nx - 1) * (ny - 1): the cell's four nodes hold data */
    uint16_t *material;         /* per cell, index in spec->materials; NULL: material 0 */
    float *roughness;           /* per cell roughness SD [rad]; NULL: the material's */
    char *crs_wkt;              /* "" if none */
};

/* The cell (i, j) holding (x, y) and the local coordinates u, v in [0, 1];
 * 0 if outside the surface.  On a shared edge the cell to the east / north
 * is taken, except at the last row or column. */
static inline int terrain_cell_of(const rf_terrain *t, double x, double y, size_t *i, size_t *j, double *u,
                                  double *v)
{
    double fx = (x - t->x0) / t->dx, fy = (y - t->y0) / t->dy;
    if (!(fx >= 0 && fy >= 0 && fx <= (double)(t->nx - 1) && fy <= (double)(t->ny - 1)))
        return 0;
    size_t ci = (size_t)fx, cj = (size_t)fy;
    if (ci >= t->nx - 1)
        ci = t->nx - 2;
    if (cj >= t->ny - 1)
        cj = t->ny - 2;
    *i = ci, *j = cj, *u = fx - (double)ci, *v = fy - (double)cj;
    return t->valid[cj * (t->nx - 1) + ci];
}

/* The bilinear patch of cell (i, j) as z = a + b X + c Y + d X Y in local
 * metres X = x - x_i, Y = y - y_j (0 <= X <= dx, 0 <= Y <= dy). */
typedef struct {
    double a, b, c, d;
    double xi, yj;              /* the cell's south-west node [m] */
} terrain_patch;

static inline terrain_patch terrain_patch_of(const rf_terrain *t, size_t i, size_t j)
{
    const double *z = t->z + j * t->nx + i;
    double z00 = z[0], z10 = z[1], z01 = z[t->nx], z11 = z[t->nx + 1];
    terrain_patch p;
    p.a = z00;
    p.b = (z10 - z00) / t->dx;
    p.c = (z01 - z00) / t->dy;
    p.d = (z11 - z10 - z01 + z00) / (t->dx * t->dy);
    p.xi = t->x0 + (double)i * t->dx, p.yj = t->y0 + (double)j * t->dy;
    return p;
}

/* terrain_grid.c: an empty surface of nx x ny nodes (z to fill, no CRS),
 * and the valid-cell mask once z is filled (for the readers). */
rf_status terrain_alloc(size_t nx, size_t ny, rf_terrain **t, rf_error *err);
void terrain_finish(rf_terrain *t);

/* Material index of cell (i, j). */
static inline size_t terrain_material_of(const rf_terrain *t, size_t i, size_t j)
{
    return t->material ? t->material[j * (t->nx - 1) + i] : 0;
}

/* ---- the prepared world ---- */

typedef struct terrain_release_set terrain_release_set;

typedef struct {
    size_t n;                   /* vertices */
    const double *x, *y;        /* spec->terrain->barrier_* (the spec outlives the world's use) */
    double *cum;                /* n: distance along the line to vertex k [m] */
    int has_box;                /* the box below is set (terrain_barrier_box; a world filled by hand may not) */
    double xmin, xmax, ymin, ymax; /* its bounding box widened by round-off [m] (the crossing test's quick reject) */
} terrain_barrier_geo;

struct rf_terrain_world {
    rf_terrain *dem;
    size_t ncol;
    terrain_barrier_geo *col;
    terrain_release_set *release;
    void *impact_table;         /* impact_model law: traj_impact_table (not yet on terrain) */
};

/* ---- the Monte Carlo and its outputs: terrain_montecarlo.c, terrain_samples.c
 * (freeing the per-sample part), terrain_output.c (JSON, summary),
 * terrain_files.c (the run folder) ---- */

/* terrain_montecarlo.c: rf_terrain_run on a prepared world (the caller's:
 * tests and the benchmark build one from a surface in memory; the study
 * model shares one over its evaluations), with the rasters only if
 * `rasters` (and the spec asks for some); the bytes a run keeps per sample
 * (its per-sample arrays: state, runout, rebound height, start, end, reach
 * angle, a crossing per barrier). */
rf_status terrain_run_world(const rf_traj_spec *spec, const rf_terrain_world *w, int threads, int rasters,
                            rf_traj_progress_fn progress, void *ctx, rf_traj_ensemble *ens, rf_error *err);
double terrain_bytes_per_sample(size_t n_collectors);
/* terrain_run_world for the samples [first, end) only (rf_terrain_run_part),
 * and how many of them are recorded (those below spec->record). */
rf_status terrain_run_world_part(const rf_traj_spec *spec, const rf_terrain_world *w, size_t first, size_t end,
                                 int threads, int rasters, rf_traj_progress_fn progress, void *ctx,
                                 rf_traj_ensemble *ens, rf_error *err);
size_t terrain_part_recorded(const rf_traj_spec *s, size_t first, size_t end);
/* terrain_files.c: the CSV files of rf_terrain_write_outputs alone
 * (samples.csv, crossings.csv, statistics.csv). */
rf_status terrain_write_tables(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                               const rf_traj_stats *st, rf_error *err);
/* terrain_samples.c: free ens->terrain (per-sample arrays, recorded
 * trajectories, rasters) and the struct itself; NULL is a no-op
 * (rf_traj_ensemble_free calls it). */
void terrain_samples_free(struct rf_terrain_samples *t);

/* ---- one running trajectory ---- */

/* A piece of path: uniformly accelerated motion p(tau) = p + v tau + a tau^2 / 2
 * for tau in [0, T] from time t.  A flight has a = (0, 0, -g) (its map path a
 * straight line); a contact stretch is one step of the surface motion, its
 * map path taken as the chord from p(0) to p(T).  on_ground: the block's
 * lowest point is on the ground (passing height 0). */
typedef struct {
    double t, T;
    double p[3], v[3], a[3];
    double e_rot;               /* rotational energy, constant over the piece [J] */
    int on_ground;
} terrain_piece;

typedef enum { TERRAIN_FLY = 0, TERRAIN_CONTACT, TERRAIN_DONE } terrain_phase;

struct rf_terrain_hazard;

typedef struct {
    const rf_terrain_world *w;
    const rf_terrain *dem;
    const rf_traj_spec *s;
    rf_terrain_result *res;
    struct rf_terrain_hazard *hazard;   /* NULL: no rasters */
    uint64_t seed, sample, n_rough;     /* roughness draws: stream 2 sample + 1, index n_rough (as 2D) */
    double g, mass, inertia, radius;
    double t, p[3], v[3], omega[3];
    terrain_phase phase;
    int from_impact;                    /* the current flight starts at an impact (rebound height) */
    int nomem;
    int piece_in_cell;                  /* the piece being emitted lies in the DEM cell (piece_ci, piece_cj), */
    size_t piece_ci, piece_cj;          /* its closed square (set by the contact phase; 0: not known) */
} terrain_run;

/* Barrier outcome of a piece (terrain_barrier.c). */
typedef enum { TERRAIN_PIECE_FREE = 0,  /* nothing stops or slows the block over the piece */
               TERRAIN_PIECE_STOPPED,   /* a barrier holds the block at tau_cut */
               TERRAIN_PIECE_SLOWED     /* it broke through a barrier at tau_cut, losing the capacity */
} terrain_piece_outcome;

/* terrain_barrier.c: record the first crossing of each barrier by the piece
 * (in res->crossings); the first barrier (in time) that holds or is broken
 * through cuts the piece at *tau_cut, and for SLOWED *scale is the factor
 * of the velocity and spin after it (energy minus capacity).  Flights over
 * the barrier's height pass untouched. */
terrain_piece_outcome terrain_barrier_piece(terrain_run *r, const terrain_piece *pc, double *tau_cut,
                                            double *scale);

/* terrain_emit.c (below the phases, which all call it): emit a piece: barriers (above), the hazard rasters
 * (terrain_hazard_piece), the rebound height.  Returns the barrier outcome;
 * the caller moves the state to the cut and continues. */
terrain_piece_outcome terrain_emit(terrain_run *r, const terrain_piece *pc, double *tau_cut, double *scale);
void terrain_event(terrain_run *r, rf_traj_event_kind kind, int flying);
/* terrain_simulate.c: rf_terrain_simulate adding the trajectory to the
 * hazard rasters `hazard` (NULL: none): terrain_hazard_begin, its pieces,
 * terrain_hazard_end (stopped, end point) are called here. */
rf_status terrain_simulate_hazard(const rf_terrain_world *w, const rf_traj_spec *values, uint64_t seed,
                                  uint64_t sample, const double start[3], struct rf_terrain_hazard *hazard,
                                  rf_terrain_result *res, rf_error *err);
/* terrain_invariants.c: a recorded trajectory (res->events) run with the
 * spec's values on the surface t never lies below the ground (beyond a local
 * round-off tolerance) and never gains mechanical energy (kinetic +
 * rotational + potential) from one event to the next; the message names the
 * event.  For the tests. */
rf_status terrain_check_invariants(const rf_traj_spec *spec, const rf_terrain *t, const rf_terrain_result *res,
                                   rf_error *err);

/* terrain_flight.c: the first time tau in (0, tmax] at which the parabola
 * p + v tau + (0, 0, -g) tau^2 / 2 meets the surface from above, found cell
 * by cell along its straight map path (exact root of a quadratic per cell:
 * no time step, no missed ridge).  The start may lie on the surface (eps:
 * its roots at tau <= 0 and the touching start are not taken unless the path
 * enters the ground).  Returns 1 with *tau, the point and the cell; 0 if the
 * path leaves the surface (the DEM's border or a no-data cell) first, with
 * *tau the time it leaves (INFINITY if it never does within tmax). */
int terrain_first_impact(const rf_terrain *t, const double p[3], const double v[3], double g, double tmax,
                         double *tau, size_t *ci, size_t *cj);

/* terrain_bounce.c: velocity and spin after an impact at the current state on
 * cell (ci, cj) with the spec's law in the frame of the surface normal,
 * tilted by the roughness (never injecting energy, never into the ground);
 * returns 1 for a soft landing (normal rebound speed below contact_speed:
 * the velocity along the surface is kept, the block continues in contact). */
int terrain_bounce(terrain_run *r, size_t ci, size_t cj, double v[3], double omega[3]);
/* terrain_bounce.c: the exact unit upward normal of cell (ci, cj)'s patch at
 * (x, y) (clamped to the cell). */
void terrain_surface_normal(const rf_terrain *t, size_t ci, size_t cj, double x, double y, double n[3]);
/* The same from the cell's patch p (terrain_patch_of) when the caller has it;
 * and terrain_bounce with that normal n (the caller's, of the same point: no
 * second evaluation). */
void terrain_patch_normal(const rf_terrain *t, const terrain_patch *p, double x, double y, double n[3]);
int terrain_bounce_n(terrain_run *r, size_t ci, size_t cj, const double n[3], double v[3], double omega[3]);

/* terrain_barrier.c: set g's bounding box (from its n vertices x, y). */
void terrain_barrier_box(terrain_barrier_geo *g);

/* terrain_fly.c: one flight from the current state to its first impact (or
 * the DEM's border, or a barrier's cut), the piece emitted, and the impact:
 * r->phase after it is TERRAIN_CONTACT (a soft landing or a slow rebound),
 * TERRAIN_FLY (a rebound, or a barrier broken through) or TERRAIN_DONE.
 * (*ci, *cj): the cell of the impact (set only when there is one). */
void terrain_fly(terrain_run *r, size_t *ci, size_t *cj);
/* terrain_fly.c: continue in contact: the velocity along the surface of normal n. */
void terrain_to_contact(terrain_run *r, const double n[3]);

/* terrain_contact.c: move the block in contact with the surface (sliding or
 * rolling under gravity, friction and rolling resistance, the normal force
 * including the surface's curvature) until it stops, leaves the surface
 * (launch), exits the DEM, a barrier holds it, or max_steps; emits its
 * pieces with terrain_emit.  A launch at a convex cell edge is flown inside
 * the phase (terrain_fly) and a landing in contact goes on in it.  Sets
 * r->phase (TERRAIN_FLY after a launch from inside a cell or a rebound,
 * TERRAIN_DONE with res->state otherwise). */
void terrain_contact_run(terrain_run *r);

/* terrain_hazard.c: the rasters (see terrain.h RF_TERRAIN_*): per cell of the
 * output grid, passages, deposits, and per-trajectory maxima of energy and
 * passing height in log-spaced histograms (TERRAIN_HAZARD_BINS_PER_OCTAVE;
 * relative error of a percentile at most TERRAIN_HAZARD_REL_ERROR).  A
 * trajectory's pieces count a cell once; accumulators of threads merge by
 * adding counts: the same bits in any order.  create returns NULL when out
 * of memory or the grid would have 2^32 cells or more. */
typedef struct rf_terrain_hazard rf_terrain_hazard;
#define TERRAIN_HAZARD_BINS_PER_OCTAVE 64   /* octave [2^e, 2^(e+1)) cut in 64 equal bins */
#define TERRAIN_HAZARD_FLOOR 0x1.0p-20      /* [J] or [m]: smaller values count in a zero bin (estimated 0) */
#define TERRAIN_HAZARD_REL_ERROR (1.0 / 64) /* bound of a percentile's relative error (plus at most FLOOR
                                               absolute; proof in terrain_hazard.c) */
rf_terrain_hazard *terrain_hazard_create(const rf_traj_spec *s, const rf_terrain *dem);
/* Every piece walked over the grid, no shortcut for a piece known to lie in
 * one DEM cell (terrain_hazard_piece_in): the tests' reference. */
void terrain_hazard_walk_only(rf_terrain_hazard *h);
void terrain_hazard_begin(rf_terrain_hazard *h);
void terrain_hazard_piece(rf_terrain_hazard *h, const rf_terrain *dem, double mass, const terrain_piece *pc);
/* The same for a piece whose path lies in the closed square of DEM cell (ci, cj): when the grid is the
 * DEM's, that cell alone, without the walk (slivers of round-off past its edges are not touched). */
void terrain_hazard_piece_in(rf_terrain_hazard *h, const rf_terrain *dem, double mass, const terrain_piece *pc,
                             size_t ci, size_t cj);
void terrain_hazard_end(rf_terrain_hazard *h, int stopped, const double end[3]);
void terrain_hazard_merge(rf_terrain_hazard *into, const rf_terrain_hazard *from);
void terrain_hazard_free(rf_terrain_hazard *h);
/* The bytes an accumulator holds (capacities included): it grows with the
 * cells touched and the histogram bins hit, not with the trajectories. */
size_t terrain_hazard_bytes(const rf_terrain_hazard *h);
/* For MPI: an accumulator as words (malloc'd; same byte order on every
 * rank), and such words added into an accumulator of the same grid exactly
 * as terrain_hazard_merge would (the same bits in any order); words that
 * are cut or of another grid are refused (into may then hold a part). */
rf_status terrain_hazard_pack(const rf_terrain_hazard *h, uint64_t **buf, size_t *words, rf_error *err);
rf_status terrain_hazard_merge_packed(rf_terrain_hazard *into, const uint64_t *buf, size_t words, rf_error *err);

/* The bands of the rasters (terrain_hazard.c) for GeoTIFF and maps: per
 * statistic a name ("passages", "reach_probability", "deposits",
 * "energy_max", "energy_p95", "height_max", "height_p95", ...) with its unit
 * and ny * nx values (row j = south to north, NaN where no block passed for
 * the per-cell energy and height statistics), on the grid of the hazard. */
typedef struct {
    char name[48];
    const char *unit;
    float *data;
} terrain_band;
void terrain_hazard_grid(const rf_terrain_hazard *h, size_t *nx, size_t *ny, double *x0, double *y0, double *cell);
/* The bands the spec's `rasters.statistics` ask for, the percentiles at the
 * spec's outputs.percentiles (default 50, 95, 99) (free with terrain_bands_free). */
rf_status terrain_hazard_bands(const rf_terrain_hazard *h, const rf_traj_spec *s, size_t samples, terrain_band **bands,
                               size_t *n, rf_error *err);
void terrain_bands_free(terrain_band *b, size_t n);

/* traj_model.c: the raster sink of a trajectory model (fuzzy hazard rasters,
 * docs/fuzzy-hazard.md).  A study sets it on the trajectory model (the model
 * behind any binding wrapper); the model's evaluation of a terrain file then
 * makes its hazard bands and hands them, with its own inputs x, to the sink.
 * The sink must be thread-safe (evaluations run in parallel) and must have
 * stored the bands when it returns: the result store commits the point after
 * the evaluation. */
typedef struct {
    size_t nx, ny;           /* columns, rows (row 0 south, as terrain_band) */
    double x0, y0, cell;     /* south-west corner and cell size [m] */
    const char *crs_wkt;     /* "" or NULL: none */
} traj_raster_grid;
typedef rf_status (*traj_raster_sink)(void *ctx, const double *x, size_t n_params, const terrain_band *bands,
                                      size_t n_bands, const traj_raster_grid *grid, rf_error *err);
/* Set (sink != NULL) or clear (NULL) the sink of trajectory model m (set or
 * cleared while no evaluation runs); RF_EINVAL if m is no trajectory model. */
rf_status traj_model_raster_sink_set(const rf_model *m, traj_raster_sink sink, void *ctx, rf_error *err);

/* terrain_io.c (GDAL): a GeoTIFF of n float32 bands on the grid nx x ny with
 * south-west corner (x0, y0) and square cells `cell` (rows written north
 * first), CRS crs_wkt ("" none), no-data value NaN, each band's description
 * its name and unit; PNG-independent, opened by QGIS as it is. */
rf_status terrain_geotiff_write(const char *path, const char *crs_wkt, size_t nx, size_t ny, double x0, double y0,
                                double cell, const terrain_band *bands, size_t n, rf_error *err);
/* terrain_io.c (OGR): release features from a vector file (GeoPackage,
 * shapefile, GeoJSON; layer NULL = the first): points, lines or polygons
 * (one kind per file; multi-geometries split into parts), each feature's
 * weight its field `count_field` (NULL: 1 per feature; per_area: the field
 * is blocks per m^2, the weight that times the polygon's area in m^2; only
 * for polygons); a multi-geometry's parts share their feature's weight in
 * proportion to length / area (points: equally).  A polygon with holes, an
 * empty layer, no positive weight and a geographic or non-metre CRS are
 * refused.  out->file = path. */
rf_status terrain_read_release_vector(const char *path, const char *layer, const char *count_field, int per_area,
                                      rf_terrain_release *out, rf_error *err);
/* terrain_io.c (GDAL): release cells of a raster: every cell holding a
 * positive count becomes a square polygon feature of that weight. */
rf_status terrain_read_release_raster(const char *path, int band, rf_terrain_release *out, rf_error *err);
/* terrain_io.c (OGR): a GeoPackage with layer "end_points" (3D points:
 * sample, state, runout [m], reach_angle [deg]) and layer "trajectories"
 * (3D line strings of the recorded trajectories' events, attributes sample,
 * state), CRS crs_wkt; written to a temporary name and renamed. */
rf_status terrain_gpkg_write(const char *path, const char *crs_wkt, const rf_traj_ensemble *ens, rf_error *err);

/* terrain_report.c: the maps of a terrain run into dir (PNG, drawn to
 * scale over a hillshade of the DEM: each band, the end points, the
 * recorded trajectories and the barriers) and report.html showing them with
 * the statistics, the answer first. */
rf_status terrain_write_maps(const char *dir, const rf_traj_spec *spec, const rf_traj_ensemble *ens,
                             const rf_traj_stats *st, const rf_terrain *dem, const terrain_band *bands, size_t n,
                             rf_error *err);
/* The bands' grid: nx x ny square cells `cell` [m] from the south-west
 * corner (x0, y0), row j to the north (terrain_hazard_grid's). */
typedef struct {
    size_t nx, ny;
    double x0, y0, cell;
} terrain_map_grid;
/* terrain_report.c: the grid of the hazard of ens->terrain; without one,
 * the grid the spec asks for: cells of rasters.cell (0: the DEM's dx) from
 * the DEM's south-west node, covering its extent. */
void terrain_report_grid(const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_terrain *dem,
                         terrain_map_grid *g);
/* terrain_maps.c: a map's page (same metres per pixel both ways), the
 * hillshade of a cell (max(0, n . l) at its centre, light from azimuth 315
 * deg, altitude 45 deg; NaN on no data), the PNG stem of a band's map, and
 * the maps: DIR/terrain_endpoints.png and DIR/terrain_map_NAME.png per band. */
typedef struct {
    int width, height;          /* the page [px] */
    int map_w, map_h;           /* the map inside it [px] */
    int map_left, map_top;      /* the map's top-left corner on the page [px] */
    double xmin, xmax, ymin, ymax;  /* [m] */
    double m_per_px;            /* [m] per pixel on both axes */
} terrain_map_layout;
terrain_map_layout terrain_map_layout_of(double xmin, double xmax, double ymin, double ymax);
double terrain_hillshade_cell(const rf_terrain *t, size_t i, size_t j);
void terrain_map_stem(const char *band, char *buf, size_t size);
rf_status terrain_draw_maps(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_terrain *dem,
                            const terrain_map_grid *g, const terrain_band *bands, size_t n, rf_error *err);
/* terrain_maps.c: one band's map as DIR/STEM.png, drawn as a run's maps (to
 * scale over the hillshade of dem, with the barriers of s), for other
 * rasters on the same grid (a study's fuzzy hazard maps).  style NULL: as a
 * run's band map.  range: the colour scale spans that band's values (maps
 * side by side on one scale); labels: a categorical map, value k = 1 ..
 * n_labels is category labels[k - 1] in its own colour, named in a legend
 * (other values transparent); title: the first title line (NULL: the
 * band's name and unit). */
typedef struct {
    const terrain_band *range;
    const char *const *labels;
    size_t n_labels;
    const char *title;
} terrain_map_style;
rf_status terrain_draw_band_map(const char *dir, const char *stem, const rf_traj_spec *s, const rf_terrain *dem,
                                const terrain_map_grid *g, const terrain_band *band, const terrain_map_style *style,
                                rf_error *err);
/* terrain_report_barrier.c: per barrier, DIR/terrain_barrier_NAME.png: energy
 * and passing height of each crossing against the distance along the line. */
void terrain_barrier_stem(const char *name, char *buf, size_t size);
rf_status terrain_draw_barrier_figures(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                                       rf_error *err);

/* terrain_release.c: the release set of spec->terrain->release; the map point
 * at uniforms u1 (feature, by weight), u2, u3 (position in it). */
rf_status terrain_release_prepare(const rf_traj_spec *s, terrain_release_set **set, rf_error *err);
void terrain_release_free(terrain_release_set *set);
void terrain_release_point(const terrain_release_set *set, double u1, double u2, double u3, double *x, double *y);
/* The pieces of feature f (segments A, B of a line; triangles A, B, C of a
 * polygon's triangulation; a point's A) as v[k][0..5] = Ax, Ay, Bx, By, Cx,
 * Cy; returns their count (for tests). */
size_t terrain_release_pieces(const terrain_release_set *set, size_t f, const double (**v)[6]);

/* terrain_spec.c: the terrain checks of the validation (spec.c): materials
 * (classes name existing ones, every one used), barrier lines (>= 2 finite
 * vertices), rasters, release features (finite, weights, simple polygons). */
rf_status terrain_spec_check(const rf_traj_spec *s, rf_error *err);

/* terrain_world.c: rf_terrain_world_create without the reading: the world on
 * the surface dem (made in memory, e.g. by rf_terrain_from_nodes, its
 * material per cell set or NULL), which it takes over (freed on failure too);
 * without a class raster every cell gets spec->terrain->material. */
rf_status terrain_world_from_surface(const rf_traj_spec *s, rf_terrain *dem, rf_terrain_world **w, rf_error *err);
/* rf_terrain_world_create without the impact table (impact_model law): the
 * caller builds it into w->impact_table inside its run (a study: after the
 * folder lock, answering the stop flag; traj_model.c). */
rf_status terrain_world_create_deferred(const rf_traj_spec *s, rf_terrain_world **w, rf_error *err);

#endif
