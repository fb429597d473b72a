/* terrain_report.c - the maps (terrain_maps.c) and report.html of a terrain
 * run, the answer first: where the blocks stop (by material), what each
 * barrier holds and what passes it, the runout and reach angle; then the
 * maps, the per-barrier table, the runout / reach-angle statistics and the
 * inputs.  The maps are inlined as data: URIs (the page stands alone, like
 * the 2D and study reports). */
#include "trajectory/block_traj.h"
#include "trajectory/terrain_internal.h"
#include "core/html.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static const char *CSS =
    "body{font-family:sans-serif;max-width:1100px;margin:1em auto;color:#222}"
    "h1{font-size:1.5em}h2{border-bottom:1px solid #ccc;margin-top:1.6em}"
    "table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:2px 8px;text-align:right}"
    "th{background:#eee}td.l{text-align:left}.note{color:#666}img{max-width:100%;border:1px solid #ddd}"
    ".summary{background:#eef5ff;border:2px solid #36c;padding:.5em 1em;margin:1em 0}";

void terrain_report_grid(const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_terrain *dem, terrain_map_grid *g)
{
    memset(g, 0, sizeof *g);
    if (e->terrain && e->terrain->hazard)
        terrain_hazard_grid(e->terrain->hazard, &g->nx, &g->ny, &g->x0, &g->y0, &g->cell);
    if (g->nx && g->ny && g->cell > 0)
        return;
    double xmin, xmax, ymin, ymax, dx, dy;
    rf_terrain_extent(dem, &xmin, &xmax, &ymin, &ymax, &dx, &dy);
    g->cell = s->terrain && s->terrain->raster_cell > 0 ? s->terrain->raster_cell : dx;
    g->x0 = xmin, g->y0 = ymin;
    g->nx = (size_t)ceil((xmax - xmin) / g->cell - 1e-9);
    g->ny = (size_t)ceil((ymax - ymin) / g->cell - 1e-9);
    g->nx += !g->nx, g->ny += !g->ny;
}

/* <img> of dir/stem.png inlined as base64, in its paragraph. */
static void image(FILE *f, const char *dir, const char *stem)
{
    fputs("<p>", f);
    traj_html_image(f, dir, stem);
    fputs("</p>\n", f);
}

/* A count with thin-space thousands: 10 000. */
static void count_text(FILE *f, size_t n)
{
    char d[32];
    int len = snprintf(d, sizeof d, "%zu", n);
    for (int k = 0; k < len; k++) {
        if (k && (len - k) % 3 == 0)
            fputs("&#8201;", f);
        fputc(d[k], f);
    }
}

static double pct(size_t k, size_t n) { return n ? 100.0 * (double)k / (double)n : 0; }

/* What happened to each block: held by barrier c (0..nc-1), else stopped on
 * material m (nc + m), exited (nc + nm), step limit (nc + nm + 1). */
typedef struct {
    size_t nc, nm, *count;          /* nc + nm + 2 */
    size_t *broke, *flew;           /* per barrier: broke through it, flew over it */
} fates;

/* The material of the cell holding the end point (without a class raster the spec's one material). */
static size_t end_material(const rf_traj_spec *s, const rf_terrain *dem, const double *end)
{
    size_t i, j;
    double u, v;
    if (!dem->material)
        return s->terrain ? s->terrain->material : 0;
    if (!terrain_cell_of(dem, end[0], end[1], &i, &j, &u, &v))
        return SIZE_MAX;
    return terrain_material_of(dem, i, j);
}

static int fates_count(const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_terrain *dem, fates *F)
{
    size_t nc = e->n_collectors, nm = s->n_materials;
    F->nc = nc, F->nm = nm;
    F->count = calloc(nc + nm + 2, sizeof *F->count);
    F->broke = calloc(nc + 1, sizeof *F->broke), F->flew = calloc(nc + 1, sizeof *F->flew);
    if (!F->count || !F->broke || !F->flew)
        return 0;
    for (size_t i = 0; i < e->samples; i++) {
        size_t held = SIZE_MAX;
        for (size_t c = 0; c < nc; c++) {
            const rf_traj_crossing *x = &e->crossings[i * nc + c];
            if (!x->reached)
                continue;
            if (x->stopped_by_barrier)
                held = c;
            else if (x->energy_after < x->total_energy)
                F->broke[c]++;
            else if (s->collectors[c].height > 0 && x->height_lowest > s->collectors[c].height)
                F->flew[c]++;
        }
        if (held != SIZE_MAX && e->state[i] == RF_TRAJ_STOPPED)
            F->count[held]++;
        else if (e->state[i] == RF_TRAJ_STOPPED) {
            size_t m = e->terrain ? end_material(s, dem, e->terrain->end + 3 * i) : SIZE_MAX;
            F->count[nc + (m < nm ? m : 0)]++;
        } else
            F->count[nc + nm + (e->state[i] == RF_TRAJ_EXITED ? 0 : 1)]++;
    }
    return 1;
}

static void fates_free(fates *F) { free(F->count), free(F->broke), free(F->flew); }

/* Percentiles at levels of v * scale (NaN skipped). */
static rf_traj_percentiles scaled_percentiles(const double *v, size_t n, double scale, const double *lv, size_t nl)
{
    double *w = malloc((n ? n : 1) * sizeof *w);
    rf_traj_percentiles p;
    memset(&p, 0, sizeof p);
    p.p50 = p.p95 = p.max = NAN;
    if (!w)
        return p;
    for (size_t i = 0; i < n; i++)
        w[i] = v[i] * scale;
    p = rf_traj_percentiles_at(w, n, lv, nl);
    free(w);
    return p;
}

/* Where the blocks end, by fate, in one sentence. */
static void answer_fates(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e, const fates *F)
{
    size_t N = e->samples, nc = F->nc, nm = F->nm;
    const char *sep = "";
    fputs("Of ", f);
    count_text(f, N);
    fprintf(f, " block%s released, ", N == 1 ? "" : "s");
    for (size_t m = 0; m < nm; m++)
        if (F->count[nc + m]) {
            fprintf(f, "%s%.1f&nbsp;%% stop on %s", sep, pct(F->count[nc + m], N), s->materials[m].name);
            sep = ", ";
        }
    for (size_t c = 0; c < nc; c++)
        if (F->count[c]) {
            fprintf(f, "%s%.1f&nbsp;%% are held by %s", sep, pct(F->count[c], N), s->collectors[c].name);
            sep = ", ";
        }
    if (F->count[nc + nm]) {
        fprintf(f, "%s%.1f&nbsp;%% leave the DEM", sep, pct(F->count[nc + nm], N));
        sep = ", ";
    }
    if (F->count[nc + nm + 1])
        fprintf(f, "%s%.1f&nbsp;%% reach the step limit (unfinished)", sep, pct(F->count[nc + nm + 1], N));
    fputs(". ", f);
}

static void answer_runout(FILE *f, const rf_traj_ensemble *e)
{
    const rf_terrain_samples *ts = e->terrain;
    if (!ts)
        return;
    static const double lv[3] = {5, 50, 95};
    rf_traj_percentiles r = scaled_percentiles(ts->runout, e->samples, 1, lv, 3);
    rf_traj_percentiles a = scaled_percentiles(ts->reach_angle, e->samples, 180 / PI, lv, 3);
    fprintf(f, "The median runout is %.0f&nbsp;m, the 95th percentile %.0f&nbsp;m and the longest %.0f&nbsp;m "
               "(horizontal distance from the release). ", r.value[1], r.value[2], r.max);
    if (isfinite(a.value[0]))
        fprintf(f, "95&nbsp;%% of the blocks end at a reach angle (Fahrb&ouml;schung) of %.1f&deg; or more (the 5th "
                   "percentile; median %.1f&deg;). ", a.value[0], a.value[1]);
}

static void answer_barrier(FILE *f, const rf_traj_spec *s, const rf_traj_stats *st, const fates *F, size_t c,
                           size_t N)
{
    const rf_traj_collector *k = &s->collectors[c];
    const rf_traj_collector_stats *cs = &st->collectors[c];
    fprintf(f, "At %s, %.1f&nbsp;%% of the blocks arrive", k->name, 100 * cs->reach_probability);
    if (cs->reach_probability <= 0) {
        fputs(". ", f);
        return;
    }
    fprintf(f, ", with p95 energy %.0f&nbsp;kJ and p95 passing height %.2f&nbsp;m", cs->total_energy.p95 * 1e-3,
            cs->height_lowest.p95);
    double t[RF_TRAJ_MAX_THRESHOLDS];
    int own = 0;
    rf_traj_thresholds(k, 1, t, &own);
    if (own)
        fprintf(f, ", above its %g&nbsp;m height for %.1f&nbsp;%%", k->height, 100 * cs->p_height_above[0]);
    rf_traj_thresholds(k, 0, t, &own);
    if (own)
        fprintf(f, ", above its %g&nbsp;kJ capacity for %.1f&nbsp;%%", k->capacity * 1e-3, 100 * cs->p_energy_above[0]);
    if (k->capacity > 0 || k->height > 0)
        fprintf(f, "; it holds %.1f&nbsp;%%, %.1f&nbsp;%% break through and %.1f&nbsp;%% fly over",
                pct(F->count[c], N), pct(F->broke[c], N), pct(F->flew[c], N));
    fputs(". ", f);
}

static double line_length(const rf_traj_spec *s, size_t c)
{
    const rf_terrain_def *td = s->terrain;
    double L = 0;
    if (!td || !td->barrier_start)
        return NAN;
    for (size_t v = td->barrier_start[c] + 1; v < td->barrier_start[c + 1]; v++)
        L += hypot(td->barrier_x[v] - td->barrier_x[v - 1], td->barrier_y[v] - td->barrier_y[v - 1]);
    return L;
}

static void barrier_table(FILE *f, const char *dir, const rf_traj_spec *s, const rf_traj_stats *st, const fates *F,
                          size_t N)
{
    if (!s->n_collectors)
        return;
    fputs("<h2>Barriers</h2>\n<table><tr><th>barrier</th><th>length [m]</th><th>height [m]</th><th>capacity "
          "[kJ]</th><th>reached [%]</th><th>held [%]</th><th>broke through [%]</th><th>flew over [%]</th>"
          "<th>energy p50 / p95 / max [kJ]</th><th>passing height p50 / p95 / max [m]</th><th>centre height "
          "p95 [m]</th><th>speed p95 [m/s]</th></tr>\n", f);
    for (size_t c = 0; c < s->n_collectors; c++) {
        const rf_traj_collector *k = &s->collectors[c];
        const rf_traj_collector_stats *cs = &st->collectors[c];
        fputs("<tr><td class=l>", f);
        rf_html_text(f, k->name);
        char h[32], cap[32];
        snprintf(h, sizeof h, k->height > 0 ? "%g" : "unlimited", k->height);
        snprintf(cap, sizeof cap, k->capacity > 0 ? "%g" : "collector", k->capacity * 1e-3);
        fprintf(f, "</td><td>%.1f</td><td>%s</td><td>%s</td><td>%.2f</td><td>%.2f</td><td>%.2f</td><td>%.2f</td>",
                line_length(s, c), h, cap, 100 * cs->reach_probability, pct(F->count[c], N), pct(F->broke[c], N),
                pct(F->flew[c], N));
        fprintf(f, "<td>%.4g / %.4g / %.4g</td><td>%.3g / %.3g / %.3g</td><td>%.3g</td><td>%.3g</td></tr>\n",
                cs->total_energy.p50 * 1e-3, cs->total_energy.p95 * 1e-3, cs->total_energy.max * 1e-3,
                cs->height_lowest.p50, cs->height_lowest.p95, cs->height_lowest.max, cs->height_centre.p95,
                cs->speed.p95);
    }
    fputs("</table>\n", f);
    fputs("<p class=note>Over all blocks: reached, held (stopped by the barrier: energy within its capacity and "
          "passing below its top), broke through (passed on with its energy less the capacity), flew over (passed "
          "above its top). Energies, heights and speeds over the blocks that reach the line; energies include "
          "rotation; the passing height is the block's lowest point above the ground.</p>\n", f);
    for (size_t c = 0; c < s->n_collectors; c++) {
        char stem[120];
        if (st->collectors[c].reach_probability <= 0)
            continue;
        terrain_barrier_stem(s->collectors[c].name, stem, sizeof stem);
        image(f, dir, stem);
    }
}

/* Runout and reach angle at the spec's percentiles (default 50, 95, 99), the 5th, max and mean. */
static void runout_table(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_traj_stats *st)
{
    const rf_terrain_samples *ts = e->terrain;
    double lv[RF_TRAJ_MAX_PERCENTILES + 1] = {5};
    size_t nl = 1;
    for (size_t k = 0; k < s->outputs.n_percentiles && nl < RF_TRAJ_MAX_PERCENTILES; k++)
        if (s->outputs.percentiles[k] != 5)
            lv[nl++] = s->outputs.percentiles[k];
    if (nl == 1)
        lv[1] = 50, lv[2] = 95, lv[3] = 99, nl = 4;
    fputs("<h2>Runout and reach angle</h2>\n<table><tr><th>quantity</th><th>unit</th>", f);
    for (size_t k = 0; k < nl; k++) {
        char name[32];
        rf_traj_percentile_name(lv[k], name, sizeof name);
        fprintf(f, "<th>%s</th>", name);
    }
    fputs("<th>max</th><th>mean</th></tr>\n", f);
    static const char *const what[3] = {"runout (horizontal distance release to end)",
                                        "reach angle (Fahrb&ouml;schung)", "rebound height"};
    static const char *const unit[3] = {"m", "deg", "m"};
    for (int q = 0; q < 3; q++) {
        const double *v = q == 2 ? e->rebound_height : !ts ? NULL : q == 0 ? ts->runout : ts->reach_angle;
        if (!v)
            continue;
        rf_traj_percentiles p = scaled_percentiles(v, e->samples, q == 1 ? 180 / PI : 1, lv, nl);
        fprintf(f, "<tr><td class=l>%s</td><td>%s</td>", what[q], unit[q]);
        for (size_t k = 0; k < nl; k++)
            fprintf(f, "<td>%.4g</td>", p.value[k]);
        fprintf(f, "<td>%.4g</td><td>%.4g</td></tr>\n", p.max, p.mean);
    }
    fprintf(f, "</table>\n<p class=note>Over all %zu blocks (stopped %zu, exited %zu, step limit %zu); the runout and "
               "reach angle of a block that left the DEM are those of its last point. The reach angle is atan(drop / "
               "runout) from the release to the end: a low angle means a long reach.</p>\n",
            e->samples, st->stopped, st->exited, st->step_limit);
}

static const char *const stat_names[5] = {"passages", "reach_probability", "deposits", "energy", "height"};

static void inputs_table(FILE *f, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_terrain *dem,
                         const terrain_map_grid *g)
{
    const rf_terrain_def *td = s->terrain;
    double xmin, xmax, ymin, ymax, dx, dy;
    rf_terrain_extent(dem, &xmin, &xmax, &ymin, &ymax, &dx, &dy);
    fputs("<h2>Inputs</h2>\n<table>\n<tr><th>DEM</th><td class=l>", f);
    rf_html_text(f, td && td->dem ? td->dem : "(in memory)");
    fprintf(f, ": %zu x %zu nodes, %g x %g m cells, x %.1f to %.1f m, y %.1f to %.1f m; CRS: %s</td></tr>\n",
            dem->nx, dem->ny, dx, dy, xmin, xmax, ymin, ymax, *rf_terrain_crs_wkt(dem) ? "" : "none (local metres)");
    if (*rf_terrain_crs_wkt(dem)) {
        fputs("<tr><th>CRS (WKT)</th><td class=l><small>", f);
        rf_html_text(f, rf_terrain_crs_wkt(dem));
        fputs("</small></td></tr>\n", f);
    }
    fputs("<tr><th>materials</th><td class=l>", f);
    for (size_t m = 0; m < s->n_materials; m++) {
        const rf_traj_material *mt = &s->materials[m];
        fprintf(f, "%s%s: R_n %g, R_t %g, friction angle %g&deg;, rolling resistance %g, roughness %g&deg;",
                m ? "<br>" : "", mt->name, mt->R_n, mt->R_t, mt->friction_angle * 180 / PI, mt->rolling_resistance,
                mt->roughness * 180 / PI);
    }
    if (td && td->classes) {
        fputs("<br>classes from ", f);
        rf_html_text(f, td->classes);
    }
    fputs("</td></tr>\n", f);
    char block[256];
    traj_block_describe(s, block, sizeof block);
    fputs("<tr><th>block</th><td class=l>", f);
    rf_html_text(f, block);
    fputs("</td></tr>\n", f);
    if (td) {
        static const char *const kinds[3] = {"point", "line", "polygon"};
        const rf_terrain_release *r = &td->release;
        fprintf(f, "<tr><th>release</th><td class=l>%zu %s feature%s%s", r->n_features, kinds[r->kind % 3],
                r->n_features == 1 ? "" : "s", r->file ? " from " : "");
        rf_html_text(f, r->file);
        fprintf(f, "; %g m above the ground</td></tr>\n", s->height0);
    }
    fprintf(f, "<tr><th>bounce law</th><td class=l>%s</td></tr>\n",
            s->block_kind ? "(a rigid block: its own contact dynamics)" : rf_traj_bounce_law_names[s->law]);
    fprintf(f, "<tr><th>Monte Carlo</th><td class=l>%zu samples, %s sampling, seed %llu, %.3g s</td></tr>\n",
            e->samples, s->lhs ? "Latin hypercube" : "random", (unsigned long long)s->seed, e->wall_seconds);
    for (size_t k = 0; k < s->n_random; k++) {
        const rf_traj_random *r = &s->random[k];
        fputs("<tr><th>random input</th><td class=l>", f);
        rf_html_text(f, r->path);
        if (r->dist == RF_DIST_UNIFORM)
            fprintf(f, ": uniform [%g, %g] (as stored)", r->a, r->b);
        else if (r->dist == RF_DIST_NORMAL)
            fprintf(f, ": normal, mean %g, SD %g (as stored)", r->a, r->b);
        fputs("</td></tr>\n", f);
    }
    fprintf(f, "<tr><th>rasters</th><td class=l>%zu x %zu cells of %g m from (%.1f, %.1f) m:", g->nx, g->ny, g->cell,
            g->x0, g->y0);
    for (int k = 0; td && k < 5; k++)
        if (td->statistics & (1u << k))
            fprintf(f, " %s", stat_names[k]);
    fputs("</td></tr>\n</table>\n", f);
}

static void maps_section(FILE *f, const char *dir, const rf_traj_ensemble *e, const terrain_band *bands, size_t n)
{
    fputs("<h2>Maps</h2>\n<p class=note>Every map is drawn to scale (the same metres per pixel on both axes, map "
          "coordinates in metres) over a hillshade of the DEM (from the exact normal of its bilinear surface, light "
          "from the north-west at 45&deg;). The band maps show a cell only where a block passed (a count of 0 or "
          "no value is transparent). The same values are in hazard.tif, one band per statistic, for GIS.</p>\n", f);
    if (e->terrain)
        image(f, dir, "terrain_endpoints");
    for (size_t k = 0; k < n; k++) {
        char stem[120];
        terrain_map_stem(bands[k].name, stem, sizeof stem);
        const char *unit = bands[k].unit && *bands[k].unit ? bands[k].unit : "-";
        fputs("<h3>", f);
        rf_html_text(f, bands[k].name);
        fprintf(f, " [%s]</h3>\n", strcmp(unit, "J") ? unit : "kJ"); /* as on the map */
        image(f, dir, stem);
    }
#ifdef TERRAIN_HAZARD_REL_ERROR
    fprintf(f, "<p class=note>The per-cell percentiles come from log-spaced histograms: each is within %g %% "
               "(relative) of the exact percentile of the blocks that passed the cell; the max is exact.</p>\n",
            100 * TERRAIN_HAZARD_REL_ERROR);
#endif
}

static rf_status write_html(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e, const rf_traj_stats *st,
                            const rf_terrain *dem, const terrain_map_grid *g, const terrain_band *bands, size_t n,
                            rf_error *err)
{
    fates F;
    memset(&F, 0, sizeof F);
    if (!fates_count(s, e, dem, &F)) {
        fates_free(&F);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    char path[4096];
    snprintf(path, sizeof path, "%s/report.html", dir);
    FILE *f = fopen(path, "w");
    if (!f) {
        fates_free(&F);
        return rf_fail(err, RF_EIO, "cannot write %s: %s", path, strerror(errno));
    }
    fprintf(f, "<!DOCTYPE html><html><head><meta charset=utf-8><title>");
    rf_html_text(f, s->name);
    fprintf(f, "</title><style>%s</style></head><body>\n<h1>Rockfall on terrain: ", CSS);
    rf_html_text(f, s->name);
    fputs("</h1>\n<div class=summary id=summary><b>The answer.</b> ", f);
    answer_fates(f, s, e, &F);
    answer_runout(f, e);
    for (size_t c = 0; c < s->n_collectors; c++)
        answer_barrier(f, s, st, &F, c, e->samples);
    fputs("</div>\n", f);
    maps_section(f, dir, e, bands, n);
    barrier_table(f, dir, s, st, &F, e->samples);
    runout_table(f, s, e, st);
    inputs_table(f, s, e, dem, g);
    fputs("</body></html>\n", f);
    fates_free(&F);
    if (fclose(f) != 0)
        return rf_fail(err, RF_EIO, "cannot write %s", path);
    return RF_OK;
}

rf_status terrain_write_maps(const char *dir, const rf_traj_spec *spec, const rf_traj_ensemble *ens,
                             const rf_traj_stats *st, const rf_terrain *dem, const terrain_band *bands, size_t n,
                             rf_error *err)
{
    terrain_map_grid g;
    terrain_report_grid(spec, ens, dem, &g);
    rf_status rc = terrain_draw_maps(dir, spec, ens, dem, &g, bands, n, err);
    if (rc == RF_OK)
        rc = terrain_draw_barrier_figures(dir, spec, ens, err);
    return rc == RF_OK ? write_html(dir, spec, ens, st, dem, &g, bands, n, err) : rc;
}
