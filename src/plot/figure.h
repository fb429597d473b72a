/* figure.h - one PLplot figure rendered to PNG (pngcairo) and SVG, with the
 * project's colour map (1 black, 2 blue, 3 red, 4 green, 5 grey).  Used by
 * the study reports and the trajectory figures.  PLplot keeps global stream
 * state (plmkstrm/plsstrm are not thread-safe): call from one thread only.
 * Each figure gets its own stream, created and ended here. */
#ifndef ROCKFUZZ_PLOT_FIGURE_H
#define ROCKFUZZ_PLOT_FIGURE_H

#include "rockfuzz/status.h"

typedef void (*rf_plot_draw_fn)(const void *data);

/* Render draw(data) into dir/stem.png and dir/stem.svg, width x height pixels. */
rf_status rf_plot_figure(const char *dir, const char *stem, int width, int height, rf_plot_draw_fn draw,
                         const void *data, rf_error *err);
/* Only dir/stem.png: for rasters (a map of 10^5 cells is no vector figure). */
rf_status rf_plot_figure_png(const char *dir, const char *stem, int width, int height, rf_plot_draw_fn draw,
                             const void *data, rf_error *err);

/* Make [*lo, *hi] an axis PLplot can draw: a non-finite end gives [0, 1], and
 * a range narrower than 1e-3 of its magnitude (a crisp result, or values
 * that differ in the last bits) is widened about its centre to that width
 * (to 1 about 0).  PLplot's tick search does not end on a range of a few
 * units in the last place (40 to 40 + 7e-15 hung a report for ever). */
void rf_plot_axis_range(double *lo, double *hi);

#endif
