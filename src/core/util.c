/* util.c - small helpers shared by every module (see util.h). */
#include "core/util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

double rf_monotonic_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

char *rf_strdup(const char *s)
{
    if (!s)
        return NULL;
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d)
        memcpy(d, s, n);
    return d;
}

int rf_grow(void **p, size_t n, size_t *cap, size_t elem)
{
    if (n < *cap)
        return 1;
    size_t c = *cap ? 2 * *cap : 16;
    void *q = realloc(*p, c * elem);
    if (!q)
        return 0;
    *p = q;
    *cap = c;
    return 1;
}

int rf_name_index(const char *name, const char *const *names, int n)
{
    for (int k = 0; name && k < n; k++)
        if (!strcmp(name, names[k]))
            return k;
    return -1;
}

size_t rf_name_distance(const char *a, const char *b)
{
    size_t la = strlen(a) < 256 ? strlen(a) : 256, lb = strlen(b) < 256 ? strlen(b) : 256, row[257];
    for (size_t j = 0; j <= lb; j++)
        row[j] = j;
    for (size_t i = 1; i <= la; i++) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= lb; j++) {
            size_t up = row[j], best = diag + (a[i - 1] != b[j - 1]);
            best = up + 1 < best ? up + 1 : best;
            best = row[j - 1] + 1 < best ? row[j - 1] + 1 : best;
            diag = up, row[j] = best;
        }
    }
    return row[lb];
}

rf_status rf_name_parse(const char *what, const char *name, const char *(*names)(size_t k), size_t n,
                        int *index, rf_error *err)
{
    for (size_t k = 0; name && k < n; k++)
        if (!strcmp(name, names(k))) {
            *index = (int)k;
            return RF_OK;
        }
    char list[512] = "";
    for (size_t k = 0, len = 0; k < n && len < sizeof list; k++)
        len += (size_t)snprintf(list + len, sizeof list - len, "%s%s", k ? ", " : "", names(k));
    return rf_fail(err, RF_EINVAL, "%s '%s' is not one of %s", what, name ? name : "(null)", list);
}

int rf_format_duration(double s, int style, char *buf, size_t size)
{
    const int compact = style & RF_DURATION_COMPACT;
    if (!(s >= 0) || s > 1e8) {
        snprintf(buf, size, "?");
        return 0;
    }
    if (s < 60)
        snprintf(buf, size, "%.*f%s", style & RF_DURATION_WHOLE ? 0 : 1, s, compact ? "s" : " s");
    else if (s < 3600)
        snprintf(buf, size, compact ? "%dm%02ds" : "%d min %02d s", (int)(s / 60), (int)s % 60);
    else
        snprintf(buf, size, compact ? "%dh%02dm" : "%d h %02d min", (int)(s / 3600), ((int)s % 3600) / 60);
    return 1;
}
