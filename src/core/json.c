/* json.c - JSON values (core/json.h). */
#include "core/json.h"
#include "core/fmt.h"

#include <math.h>

void rf_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p == '"' || *p == '\\')
            fprintf(f, "\\%c", *p);
        else if (*p == '\n')
            fputs("\\n", f);
        else if (*p == '\t')
            fputs("\\t", f);
        else if (*p < 0x20)
            fprintf(f, "\\u%04x", *p);
        else
            fputc(*p, f);
    }
    fputc('"', f);
}

void rf_json_number(FILE *f, double v)
{
    char buf[RF_FMT_G_MAX];
    if (isfinite(v))
        fwrite(buf, 1, rf_fmt_g(buf, v, 17), f); /* "%.17g", byte for byte, at a fifth of its cost */
    else
        fputs("null", f);
}

void rf_json_array(FILE *f, const double *v, size_t count, size_t stride)
{
    fputc('[', f);
    for (size_t j = 0; j < count; j++) {
        if (j)
            fputs(", ", f);
        rf_json_number(f, v[j * stride]);
    }
    fputc(']', f);
}
