/* traj_impact_cache.c - impacts of the `impact_model` table kept in a text
 * file (bounce.impact.cache), so that an expensive model (the FE) computes
 * each impact once across runs and processes.  One line per impact:
 *   KEY v_n theta R_n R_t spin
 * where KEY names the solver, the block radius and the inputs that change
 * the result (density, friction, FE refinement, and a material's own impact
 * model as the hash of its inputs): "solver=S,r=R,rho=..,mu=..,ref=..[,ground=H]";
 * only lines whose KEY matches the current setup at any radius are used.
 * Each new impact is appended as soon as it is computed, one write per line
 * (O_APPEND), so concurrent runs interleave whole lines and an interrupted
 * build keeps what it computed.  A study keeps its impacts in its store
 * instead (traj_impact_store.c). */
#include "trajectory/traj_internal.h"
#include "trajectory/traj_impact.h"
#include "core/textfile.h"
#include "core/hash.h"

#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The setup's inputs after the radius: "rho=..,mu=..,ref=..[,ground=HASH[,rock_mass_scale=100][,fem_ground=stable]]"
 * (the layer preset: traj_impact_layer_preset; the FE's ground no steeper than the layer stands,
 * traj_impact_adapter.c, which changes the values of a ground's FE impacts at steep incidences). */
static void key_rest(const traj_impact_setup *s, char *key, size_t size)
{
    int n = snprintf(key, size, "rho=%.17g,mu=%.17g,ref=%.17g", s->density, s->friction, s->refinement);
    if (!s->has_ground || n < 0 || (size_t)n >= size)
        return;
    const rf_traj_impact_ground *g = &s->ground;
    uint64_t h = rf_fnv1a(RF_FNV1A_OFFSET, g->solver, sizeof g->solver);
    h = rf_fnv1a(h, g->boulder_material, sizeof g->boulder_material);
    h = rf_fnv1a(h, g->slope_material, sizeof g->slope_material);
    h = rf_fnv1a(h, g->layer_material, sizeof g->layer_material);
    h = rf_fnv1a(h, g->v, sizeof g->v);
    snprintf(key + n, size - (size_t)n, ",ground=%016llx%s%s", (unsigned long long)h,
             traj_impact_layer_preset(s) ? ",rock_mass_scale=100" : "",
             traj_impact_fem(s) ? ",fem_ground=stable" : "");
}

void traj_impact_setup_key(const traj_impact_setup *s, char *key, size_t size)
{
    char rest[200];
    key_rest(s, rest, sizeof rest);
    snprintf(key, size, "solver=%d,%s", s->solver, rest);
}

/* The file's key of the setup at radius r. */
static void cache_key(const traj_impact_setup *s, double r, char *key, size_t size)
{
    char rest[200];
    key_rest(s, rest, sizeof rest);
    snprintf(key, size, "solver=%d,r=%.17g,%s", s->solver, r, rest);
}

/* The radius of a file key of this setup (solver and rest equal), or NaN. */
static double key_radius(const traj_impact_setup *s, const char *rest, const char *k)
{
    int solver, at = 0;
    if (sscanf(k, "solver=%d,r=%n", &solver, &at) != 1 || at == 0 || solver != s->solver)
        return NAN;
    char *end;
    double r = strtod(k + at, &end);
    return end != k + at && *end == ',' && !strcmp(end + 1, rest) ? r : NAN;
}

/* Why a row (v_n, theta, radius, R_n, R_t, spin) cannot be an impact of a
 * sphere, or NULL.  The energy after the impact (translation and rotation,
 * I = 0.4 m r^2) may exceed the energy before by at most 1 %, the FE energy
 * closure's order; the bounce law caps what is left. */
const char *traj_impact_row_invalid(const double r[6])
{
    for (int q = 0; q < 6; q++)
        if (!isfinite(r[q]))
            return "a value is not a finite number";
    if (!(r[0] > 0))
        return "v_n must be > 0 [m/s]";
    if (!(r[1] >= 0 && r[1] < 0.5 * RF_PI))
        return "theta must lie in [0, pi/2) [rad]";
    if (!(r[2] > 0))
        return "the radius must be > 0 [m]";
    if (!(r[3] >= 0 && r[3] <= 1))
        return "R_n must lie in [0, 1]";
    if (!(fabs(r[4]) <= 1))
        return "R_t must lie in [-1, 1]";
    double c = cos(r[1]), s = sin(r[1]);
    if (r[3] * r[3] * c * c + r[4] * r[4] * s * s * (1 + 0.4 * r[5] * r[5]) > 1.01)
        return "the impact would gain kinetic energy (R_n, R_t and spin together)";
    return NULL;
}

/* Index of an earlier row of *memo with the same (v_n, theta, radius), or n. */
static size_t same_impact(const double *memo, size_t n, const double r[6])
{
    for (size_t k = 0; k < n; k++)
        if (memo[6 * k] == r[0] && memo[6 * k + 1] == r[1] && memo[6 * k + 2] == r[2])
            return k;
    return n;
}

/* Room for one more row in *memo (rows of 6) and in *lines (their line numbers). */
static rf_status grow(double **memo, size_t n, size_t *cap, size_t **lines, size_t *lcap, rf_error *err)
{
    if (n >= *cap) {
        size_t c = *cap ? 2 * *cap : 256;
        double *m = realloc(*memo, c * 6 * sizeof *m);
        if (!m)
            return rf_fail(err, RF_ENOMEM, "out of memory reading the impact cache");
        *memo = m, *cap = c;
    }
    if (n >= *lcap) {
        size_t c = *lcap ? 2 * *lcap : 256;
        while (c <= n)
            c *= 2;
        size_t *l = realloc(*lines, c * sizeof *l);
        if (!l)
            return rf_fail(err, RF_ENOMEM, "out of memory reading the impact cache");
        *lines = l, *lcap = c;
    }
    return RF_OK;
}

typedef struct {
    const char *path;
    double **memo;
    size_t *n, *cap;
    size_t *lines, lcap;      /* file line of each row (0: not from the file) */
    rf_error *err;
} cache_reader;

/* One row of the current setup: checked, and added unless an identical one is
 * there; a different result for the same impact is an error naming both lines. */
static rf_status add_row(cache_reader *c, size_t line, const double r[6])
{
    const char *why = traj_impact_row_invalid(r);
    if (why)
        return rf_fail(c->err, RF_EINVAL, "%s:%zu: impact cache row (v_n %g, theta %g, radius %g, R_n %g, R_t %g, "
                       "spin %g): %s", c->path, line, r[0], r[1], r[2], r[3], r[4], r[5], why);
    size_t k = same_impact(*c->memo, *c->n, r);
    if (k < *c->n && memcmp(*c->memo + 6 * k, r, 6 * sizeof *r) != 0)
        return rf_fail(c->err, RF_EINVAL, "%s:%zu: impact cache: the impact v_n %g m/s, theta %g rad, radius %g m "
                       "has other results than at line %zu; remove the wrong line", c->path, line, r[0], r[1], r[2],
                       c->lines[k]);
    if (k < *c->n)
        return RF_OK; /* the same impact twice (e.g. two runs computed it): kept once */
    rf_status st = grow(c->memo, *c->n, c->cap, &c->lines, &c->lcap, c->err);
    if (st == RF_OK) {
        memcpy(*c->memo + 6 * *c->n, r, 6 * sizeof *r);
        c->lines[(*c->n)++] = line;
    }
    return st;
}

rf_status traj_impact_cache_load(const char *path, const traj_impact_setup *s, double **memo, size_t *n,
                                 size_t *cap, rf_error *err)
{
    if (!path || access(path, F_OK) != 0)
        return RF_OK; /* no cache yet */
    rf_status fst = rf_require_regular_file(path, "impact cache", err); /* not a FIFO or /dev/zero */
    FILE *f = fst == RF_OK ? fopen(path, "r") : NULL;
    if (!f)
        return fst != RF_OK ? fst : rf_fail(err, RF_EIO, "%s: cannot read the impact cache", path);
    char rest[200], line[512], k[256];
    key_rest(s, rest, sizeof rest);
    cache_reader c = {path, memo, n, cap, NULL, 0, err};
    rf_status st = grow(memo, *n, cap, &c.lines, &c.lcap, err); /* rows already in the memo: line 0 */
    for (size_t q = 0; st == RF_OK && q < *n; q++)
        c.lines[q] = 0;
    for (size_t nl = 1; st == RF_OK && fgets(line, sizeof line, f); nl++) {
        double r[6];
        if (sscanf(line, "%255s %lf %lf %lf %lf %lf", k, &r[0], &r[1], &r[3], &r[4], &r[5]) != 6)
            continue;
        r[2] = key_radius(s, rest, k);
        if (!isnan(r[2]))
            st = add_row(&c, nl, r);
    }
    fclose(f);
    free(c.lines);
    return st;
}

void traj_impact_cache_append(const char *path, const traj_impact_setup *s, const double *rows, size_t count)
{
    int fd = path && count ? open(path, O_WRONLY | O_APPEND | O_CREAT, 0666) : -1;
    if (fd < 0)
        return; /* a cache that cannot be written only costs time */
    char key[300], line[600];
    for (size_t i = 0; i < count; i++) {
        const double *r = rows + 6 * i;
        cache_key(s, r[2], key, sizeof key);
        int len = snprintf(line, sizeof line, "%s %.17g %.17g %.17g %.17g %.17g\n", key, r[0], r[1], r[3], r[4], r[5]);
        if (len > 0 && (size_t)len < sizeof line && write(fd, line, (size_t)len) != len)
            break;
    }
    close(fd);
}
