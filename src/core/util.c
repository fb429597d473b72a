/* util.c - small helpers shared by every module (see util.h). */
#include "core/util.h"

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
