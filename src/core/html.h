/* html.h - the one HTML text escaper and PNG embedder of every report
 * (the study report, the trajectory and terrain run reports). */
#ifndef ROCKFUZZ_CORE_HTML_H
#define ROCKFUZZ_CORE_HTML_H

#include <stdio.h>

/* s with <, >, & and " escaped (NULL: nothing). */
void rf_html_text(FILE *f, const char *s);

/* <img alt="alt" src="data:image/png;base64,..."> and a newline, the PNG file
   at path embedded; 0 (nothing written) if it cannot be read. */
int rf_html_png(FILE *f, const char *path, const char *alt);

#endif
