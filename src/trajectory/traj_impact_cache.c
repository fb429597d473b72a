/* traj_impact_cache.c - impacts of the `impact_model` table kept in a text
 * file (bounce.impact.cache), so that an expensive model (the FE) computes
 * each impact once across runs and processes.  One line per impact:
 *   KEY v_n theta R_n R_t spin
 * where KEY names the solver and the inputs that change the result
 * (radius, density, friction, FE refinement); only lines with the current
 * KEY are used.  Each new impact is appended as soon as it is computed, one
 * write per line (O_APPEND), so concurrent runs interleave whole lines and an
 * interrupted build keeps what it computed. */
#include "trajectory/traj_internal.h"
#include "trajectory/traj_impact.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void cache_key(const traj_impact_setup *s, char *key, size_t size)
{
    snprintf(key, size, "solver=%d,r=%.17g,rho=%.17g,mu=%.17g,ref=%.17g", s->solver, s->radius, s->density,
             s->friction, s->refinement);
}

size_t traj_impact_cache_load(const char *path, const traj_impact_setup *s, double **memo, size_t *n, size_t *cap)
{
    FILE *f = path ? fopen(path, "r") : NULL;
    if (!f)
        return 0;
    char key[256], line[512], k[256];
    cache_key(s, key, sizeof key);
    size_t loaded = 0;
    while (fgets(line, sizeof line, f)) {
        double r[5];
        if (sscanf(line, "%255s %lf %lf %lf %lf %lf", k, &r[0], &r[1], &r[2], &r[3], &r[4]) != 6 || strcmp(k, key))
            continue;
        if (*n == *cap) {
            size_t c = *cap ? 2 * *cap : 256;
            double *m = realloc(*memo, c * 5 * sizeof *m);
            if (!m)
                break;
            *memo = m, *cap = c;
        }
        memcpy(*memo + 5 * (*n)++, r, sizeof r);
        loaded++;
    }
    fclose(f);
    return loaded;
}

void traj_impact_cache_append(const char *path, const traj_impact_setup *s, const double *rows, size_t count)
{
    int fd = path && count ? open(path, O_WRONLY | O_APPEND | O_CREAT, 0666) : -1;
    if (fd < 0)
        return; /* a cache that cannot be written only costs time */
    char key[256], line[512];
    cache_key(s, key, sizeof key);
    for (size_t i = 0; i < count; i++) {
        const double *r = rows + 5 * i;
        int len = snprintf(line, sizeof line, "%s %.17g %.17g %.17g %.17g %.17g\n", key, r[0], r[1], r[2], r[3], r[4]);
        if (len > 0 && (size_t)len < sizeof line && write(fd, line, (size_t)len) != len)
            break;
    }
    close(fd);
}
