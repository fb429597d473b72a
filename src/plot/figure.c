/* figure.c - one PLplot figure to PNG and SVG (see figure.h). */
#include "plot/figure.h"

#include <math.h>
#include <plplot.h>
#include <stdio.h>
#include <sys/stat.h>

/* One device: dir/stem.ext. */
static rf_status figure_to(const char *dir, const char *stem, const char *device, const char *ext, int width,
                           int height, rf_plot_draw_fn draw, const void *data, rf_error *err)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.%s", dir, stem, ext);
    PLINT strm = 0;
    plmkstrm(&strm);
    if (strm < 0)
        return rf_fail(err, RF_EIO, "%s: PLplot has no free plot stream", path);
    plsdev(device);
    plsfnam(path);
    plspage(0, 0, width, height, 0, 0);
    plscolbg(255, 255, 255);
    plscol0(1, 0, 0, 0);        /* axes and text: black */
    plscol0(2, 31, 119, 180);   /* blue */
    plscol0(3, 214, 39, 40);    /* red */
    plscol0(4, 44, 160, 44);    /* green */
    plscol0(5, 150, 150, 150);  /* grey */
    plinit();
    draw(data);
    plend1();
    struct stat sb;
    if (stat(path, &sb) != 0 || sb.st_size == 0)
        return rf_fail(err, RF_EIO, "%s: the plot was not written (PLplot device %s)", path, device);
    return RF_OK;
}

rf_status rf_plot_figure(const char *dir, const char *stem, int width, int height, rf_plot_draw_fn draw,
                         const void *data, rf_error *err)
{
    rf_status rc = figure_to(dir, stem, "pngcairo", "png", width, height, draw, data, err);
    return rc == RF_OK ? figure_to(dir, stem, "svg", "svg", width, height, draw, data, err) : rc;
}

rf_status rf_plot_figure_png(const char *dir, const char *stem, int width, int height, rf_plot_draw_fn draw,
                             const void *data, rf_error *err)
{
    return figure_to(dir, stem, "pngcairo", "png", width, height, draw, data, err);
}

void rf_plot_axis_range(double *lo, double *hi)
{
    if (!isfinite(*lo) || !isfinite(*hi) || *hi < *lo) {
        *lo = 0;
        *hi = 1;
        return;
    }
    const double mag = fmax(fabs(*lo), fabs(*hi)), width = mag > 0 ? 1e-3 * mag : 1;
    if (*hi - *lo < width) {
        const double c = 0.5 * *lo + 0.5 * *hi;
        *lo = c - 0.5 * width;
        *hi = c + 0.5 * width;
    }
}
