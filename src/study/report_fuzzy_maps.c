/* report_fuzzy_maps.c - the fuzzy hazard maps of a terrain study in its
 * report.html (docs/fuzzy-hazard.md): the first chosen statistic's nominal
 * map (the alpha = 1 cut) next to its alpha = 0 upper bound, on one colour
 * scale, then the blame map; each image embedded, with a link to its PNG
 * file and to fuzzy_rasters.tif (all bands, for GIS). */
#include "core/html.h"
#include "study/report_internal.h"

#include <stdio.h>
#include <unistd.h>

static void figure(FILE *f, const char *dir, const char *stem, const char *caption)
{
    fputs("<div>", f);
    rp_embed_png(f, dir, stem, caption);
    fprintf(f, "<p class=note><a href=\"%s.png\">%s.png</a>: ", stem, stem);
    rf_html_text(f, caption);
    fputs("</p></div>\n", f);
}

void rp_fuzzy_maps_html(FILE *f, const char *dir)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/fuzzy_map_upper.png", dir);
    if (access(path, R_OK) != 0)
        return;
    fputs("<h2 id=fuzzy-maps>Fuzzy hazard maps</h2>\n"
          "<p>The first fuzzy raster of the study, cell by cell: at the left with every fuzzy input at its "
          "nominal value (alpha = 1), at the right the upper bound of its alpha = 0 cut, the worst case the "
          "fuzzy inputs allow, on the same colour scale; below, per cell the fuzzy input of largest relative "
          "influence rho on it (the blame map). Every alpha level's bounds of every chosen statistic are bands of "
          "<a href=\"fuzzy_rasters.tif\">fuzzy_rasters.tif</a> (GeoTIFF, opened by QGIS as it is).</p>\n"
          "<div class=fuzzymaps>\n",
          f);
    figure(f, dir, "fuzzy_map_nominal", "nominal map (alpha = 1)");
    figure(f, dir, "fuzzy_map_upper", "alpha = 0 upper bound (worst case)");
    fputs("</div>\n", f);
    figure(f, dir, "fuzzy_map_blame", "blame map: the fuzzy input of largest influence per cell");
}
