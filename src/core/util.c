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
