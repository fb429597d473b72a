/* terrain.h - rockfall on terrain: 3D trajectories on a digital elevation
 * model (DEM) with the laws and conventions of the 2D engine (trajectory.h),
 * hazard rasters, and the release areas and barriers of a map.  A trajectory
 * file with `terrain:` instead of `profile:` is a terrain file
 * (docs/terrain.md); it is read into the same rf_traj_spec (materials, block,
 * bounce law, random inputs, samples, seed, outputs, collectors = barriers),
 * whose `terrain` member then holds what only a terrain has.
 *
 * Axes: map coordinates x (east), y (north) in metres of a projected CRS, z
 * up; gravity (0, 0, -g).  The surface is the bilinear interpolation of the
 * DEM's nodes (the centres of its cells); a cell of the surface with a
 * no-data node is outside.  As in 2D the simulated point is the block's
 * contact point (lowest point on flat ground), a sphere's centre r above it.
 * Spin is a vector omega [rad/s] (right-handed about the axis).
 * Units SI: m, kg, s, m/s, rad/s, J; angles given in degrees in files. */
#ifndef ROCKFUZZ_TERRAIN_H
#define ROCKFUZZ_TERRAIN_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "rockfuzz/status.h"
#include "rockfuzz/trajectory.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- the terrain surface (terrain_grid.c, terrain_grid_io.c) ---- */

/* A DEM as a bilinear surface, read-only once made: any number of threads
 * may share it. */
typedef struct rf_terrain rf_terrain;

/* From nodes: node (i, j) at (x0 + i dx, y0 + j dy), z[j nx + i] (NaN: no
 * data), nx, ny >= 2, dx, dy > 0 (j grows to the north).  Material 0 on
 * every cell; no CRS. */
rf_status rf_terrain_from_nodes(size_t nx, size_t ny, double x0, double y0, double dx, double dy, const double *z,
                                rf_terrain **t, rf_error *err);
/* Read band `band` (1-based) of a raster GDAL reads (GeoTIFF, ESRI ASCII
 * grid, ...): north-up (no rotation), a projected CRS in metres (a
 * geographic or non-metre CRS is refused; no CRS at all is accepted and
 * said so by rf_terrain_crs_wkt returning ""), no-data cells as NaN. */
rf_status rf_terrain_read(const char *path, int band, rf_terrain **t, rf_error *err);
/* The same, of the nodes covering window = {xmin, ymin, xmax, ymax} [m]
 * (NULL: the whole DEM): the cell centres in it and the next one beyond each
 * side (clamped to the raster), so the surface covers the window; only those
 * rows and columns are read.  The memory the surface takes is estimated
 * before anything is allocated and refused beyond RF_TERRAIN_MAX_DEM_BYTES,
 * naming the file, its size and the window. */
#define RF_TERRAIN_MAX_DEM_BYTES (4.0 * 1024 * 1024 * 1024)
rf_status rf_terrain_read_window(const char *path, int band, const double *window, rf_terrain **t, rf_error *err);
/* Material per cell from an integer raster: each raster value class_value[k]
 * maps to material class_material[k]; the raster is sampled at the centre of
 * each surface cell (nearest value, so any grid in the same CRS works); a
 * value not in the list is an error naming it and where it is. */
rf_status rf_terrain_read_classes(rf_terrain *t, const char *path, int band, size_t n_classes,
                                  const long *class_value, const size_t *class_material, rf_error *err);
/* Roughness SD [deg] per cell from a raster (sampled as the classes),
 * overriding the material's roughness there. */
rf_status rf_terrain_read_roughness(rf_terrain *t, const char *path, int band, rf_error *err);
void rf_terrain_free(rf_terrain *t);

/* Height of the surface at (x, y) and its unit upward normal (NULL: not
 * wanted); 0 if (x, y) is outside the DEM or on a no-data cell. */
int rf_terrain_height(const rf_terrain *t, double x, double y, double *z, double normal[3]);
/* The extent covered by the surface [m] and the node spacing. */
void rf_terrain_extent(const rf_terrain *t, double *xmin, double *xmax, double *ymin, double *ymax, double *dx,
                       double *dy);
/* The CRS as WKT ("" if the DEM had none). */
const char *rf_terrain_crs_wkt(const rf_terrain *t);

/* ---- what a terrain file adds to rf_traj_spec (spec->terrain) ---- */

/* Release geometry: features in map coordinates [m].  Feature f has the
 * vertices start[f] .. start[f + 1] - 1 of x, y: one vertex (a point), a
 * polyline (a line), or a closed ring without the repeated first vertex (a
 * polygon).  weight[f]: the feature's share of the blocks (a count, or a
 * count per unit area times its area; the sum need not be 1).  A block
 * starts at a point drawn uniformly (by length on a line, by area in a
 * polygon) in a feature drawn by weight, spec->height0 above the ground. */
typedef enum { RF_TERRAIN_POINTS = 0, RF_TERRAIN_LINES, RF_TERRAIN_POLYGONS } rf_terrain_feature_kind;
typedef struct {
    rf_terrain_feature_kind kind;
    size_t n_features;
    size_t *start;              /* n_features + 1 */
    double *x, *y;              /* start[n_features] vertices [m] */
    double *weight;             /* n_features [-] */
    char *file;                 /* the vector file or release raster they were read from (messages), or NULL */
} rf_terrain_release;

/* Hazard raster statistics (bit mask, `rasters.statistics`). */
enum {
    RF_TERRAIN_PASSAGES = 1u << 0,          /* blocks whose path crosses the cell [-] */
    RF_TERRAIN_REACH_PROBABILITY = 1u << 1, /* passages / samples [-] */
    RF_TERRAIN_DEPOSITS = 1u << 2,          /* blocks that stop in the cell [-] */
    RF_TERRAIN_ENERGY = 1u << 3,            /* per cell: max and percentiles of the total kinetic energy [J] */
    RF_TERRAIN_HEIGHT = 1u << 4             /* per cell: max and percentiles of the passing height [m] */
};

typedef struct rf_terrain_def {
    char *dem;                  /* DEM file */
    int band;                   /* its band, default 1 */
    char *classes;              /* integer raster of material classes, or NULL: all cells `material` */
    int classes_band;
    size_t n_classes;
    long *class_value;          /* raster value -> */
    size_t *class_material;     /* index in spec->materials */
    size_t material;            /* without a class raster: the one material */
    char *roughness;            /* raster of roughness SD [deg] per cell, or NULL */
    int roughness_band;         /* its band, default 1 */
    int has_window;             /* terrain.window given: only the DEM's nodes it needs are read */
    double window[4];           /* xmin, ymin, xmax, ymax [m] */
    rf_terrain_release release;
    /* per collector (spec->collectors[c]): its line on the map */
    size_t n_barriers;          /* = spec->n_collectors (barrier_start holds n_barriers + 1) */
    size_t *barrier_start;      /* n_collectors + 1 offsets into barrier_x, barrier_y */
    double *barrier_x, *barrier_y;  /* [m] */
    /* rasters */
    double raster_cell;         /* [m] output cell, 0 = the DEM's node spacing */
    unsigned statistics;        /* RF_TERRAIN_* */
    size_t max_paths;           /* trajectories written to the GeoPackage, default 200 */
} rf_terrain_def;

void rf_terrain_def_free(rf_terrain_def *d);
rf_status rf_terrain_def_copy(const rf_terrain_def *src, rf_terrain_def *dst, rf_error *err);
/* FNV-1a of everything a run reads (the files' contents included). */
uint64_t rf_terrain_def_hash(const rf_terrain_def *d, uint64_t h);

/* ---- one 3D trajectory ---- */

typedef struct {
    double t, x, y, z;
    double v_in[3], v_out[3], omega_out[3];
    size_t material;
    /* A rigid block (spec->block_kind): x, y, z are its lowest point, the
     * velocities its centre's; orientation (w, x, y, z) and rotational energy
     * about each body axis [J] after the impact (not set for a point or sphere). */
    double q[4], rot_energy[3];
} rf_terrain_impact;

typedef struct {
    rf_traj_event_kind kind;
    int flying;                 /* the motion after this event is a flight (else contact) */
    double t, p[3], v[3], omega[3];  /* state after the event */
    double q[4];                /* a rigid block: orientation (w, x, y, z) (not set for a point or sphere) */
} rf_terrain_event;

typedef struct {
    rf_traj_state state;
    double start[3], end[3];    /* release point; rest, exit or last state [m] */
    double t_end;
    double runout;              /* horizontal distance from the release to the end [m] */
    double reach_angle;         /* atan(drop / runout) [rad] (the Fahrboeschung; NaN when runout = 0) */
    double rebound_height;      /* largest rise of a flight that starts at an impact [m] */
    size_t n_impacts, n_steps;
    rf_traj_crossing *crossings;    /* n_collectors, caller-sized */
    /* Optional records (NULL = not recorded), growing with realloc: */
    rf_terrain_impact *impacts; size_t impacts_cap;
    rf_terrain_event *events; size_t n_events, events_cap;
} rf_terrain_result;

/* A prepared terrain (the DEM with its classes, barrier geometry, release
 * features); read-only while trajectories run. */
typedef struct rf_terrain_world rf_terrain_world;
rf_status rf_terrain_world_create(const rf_traj_spec *spec, rf_terrain_world **w, rf_error *err);
void rf_terrain_world_free(rf_terrain_world *w);
const rf_terrain *rf_terrain_world_surface(const rf_terrain_world *w);

/* One trajectory from start (x, y on the map; z = the ground there plus the
 * release height when z is NaN) with the spec's crisp values. */
rf_status rf_terrain_simulate(const rf_terrain_world *w, const rf_traj_spec *values, uint64_t seed, uint64_t sample,
                              const double start[3], rf_terrain_result *res, rf_error *err);

/* ---- Monte Carlo on terrain (terrain_montecarlo.c) ---- */

/* Per sample, in rf_traj_ensemble.terrain (NULL for a profile): where each
 * block started and ended, its runout and reach angle. */
typedef struct rf_terrain_samples {
    double *start;              /* samples * 3 [m] */
    double *end;                /* samples * 3 [m] */
    double *runout;             /* [m] */
    double *reach_angle;        /* [rad] */
    size_t n_recorded;
    rf_terrain_result *recorded;
    struct rf_terrain_hazard *hazard;   /* the rasters (terrain_hazard.c) */
} rf_terrain_samples;

/* Run spec->samples trajectories of a terrain spec on `threads` threads (0 =
 * online cores), the same bits at any thread count (sample i draws from its
 * own counter-based streams, as in 2D; the release point takes three more
 * uniforms).  ens gets, per sample, state, runout_x = the runout [m],
 * rebound height and the barrier crossings, and ens->terrain the 3D part
 * and the merged hazard rasters.  progress may be NULL. */
rf_status rf_terrain_run(const rf_traj_spec *spec, int threads, rf_traj_progress_fn progress, void *ctx,
                         rf_traj_ensemble *ens, rf_error *err);

/* ---- a run in parts (MPI ranks; terrain_montecarlo.c, terrain_parts.c) ---- */

/* rf_terrain_run for the samples [first, end) of spec only (first <= end <=
 * spec->samples): ens->samples = end - first, sample i at index i - first
 * (each the same bits as in the whole run), the recorded trajectories of
 * its samples below spec->record, and its samples' rasters.  progress counts
 * the part's samples. */
rf_status rf_terrain_run_part(const rf_traj_spec *spec, size_t first, size_t end, int threads,
                              rf_traj_progress_fn progress, void *ctx, rf_traj_ensemble *ens, rf_error *err);
/* A part (rf_terrain_run_part from `first`) as bytes (*buf malloc'd): its
 * per-sample results, recorded trajectories and packed rasters; the layout
 * of this build and machine (another is refused by the join). */
rf_status rf_terrain_part_pack(const rf_traj_ensemble *part, size_t first, void **buf, size_t *bytes, rf_error *err);
/* Append a packed part to ens, a run of the samples [0, ens->samples) (the
 * first part, from rf_terrain_run_part(spec, 0, ...)): the part must start
 * at ens->samples and come from the same spec.  Joined in order up to
 * spec->samples, ens is what rf_terrain_run gives, bit for bit (the wall
 * time aside).  A part out of order, of another build or cut short in its
 * header or samples is refused (RF_EINVAL, the reason) leaving ens as it
 * was; one cut later leaves ens to be freed (rf_traj_ensemble_free) only. */
rf_status rf_terrain_part_join(rf_traj_ensemble *ens, const void *buf, size_t bytes, rf_error *err);

/* ---- outputs (terrain_output.c, terrain_report.c) ---- */

/* The JSON document of `rockfuzz trajectory --json` for a terrain file
 * (docs/terrain.md): per recorded trajectory (at most max_trajectories)
 * state, impacts, rest, crossings; statistics (runout, reach angle, per
 * barrier as in 2D). */
void rf_terrain_write_json(FILE *f, const rf_traj_spec *spec, const rf_traj_ensemble *ens, const rf_traj_stats *st,
                           size_t max_trajectories);
void rf_terrain_write_summary(FILE *f, const rf_traj_spec *spec, const rf_traj_ensemble *ens, const rf_traj_stats *st);
/* DIR/hazard.tif (one band per statistic), DIR/paths.gpkg (end points,
 * trajectories), samples.csv, crossings.csv, statistics.csv; with plots the
 * maps and report.html. */
rf_status rf_terrain_write_outputs(const char *dir, const rf_traj_spec *spec, const rf_traj_ensemble *ens,
                                   const rf_traj_stats *st, int plots, rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
