/* json.h - the one JSON value writer of rockfuzz (result.json, the
 * evaluation log, trajectory and impact documents).  Core layer. */
#ifndef ROCKFUZZ_CORE_JSON_H
#define ROCKFUZZ_CORE_JSON_H

#include <stddef.h>
#include <stdio.h>

/* s as a JSON string: quotes and backslashes escaped, \n and \t as such,
   other control characters as \u00XX; bytes >= 0x80 pass (UTF-8 text). */
void rf_json_string(FILE *f, const char *s);
/* v with %.17g (round-trips a double); null when v is not finite, so the
   document stays valid JSON (the reader says what null means there). */
void rf_json_number(FILE *f, double v);
/* [v[0], v[stride], ...] of count numbers, each as rf_json_number. */
void rf_json_array(FILE *f, const double *v, size_t count, size_t stride);

#endif
