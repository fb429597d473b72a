/* traj_csv.c - a slope profile from a CSV file: one vertex per line,
 * "x,y" or "x,y,material" (metres; the material names one of the spec's
 * materials and applies to the segment starting at that vertex).  Blank
 * lines and lines starting with '#' are skipped, and so is a first line that
 * is not numeric (a header).  Errors name the file, line and value. */
#include "trajectory/traj_internal.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double *x, *y;
    size_t *mat;
    size_t n, cap;
} csv_rows;

static int push(csv_rows *r, double x, double y, size_t m)
{
    if (r->n == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 64;
        double *px = realloc(r->x, cap * sizeof *px);
        if (px) r->x = px;
        double *py = realloc(r->y, cap * sizeof *py);
        if (py) r->y = py;
        size_t *pm = realloc(r->mat, cap * sizeof *pm);
        if (pm) r->mat = pm;
        if (!px || !py || !pm)
            return 0;
        r->cap = cap;
    }
    r->x[r->n] = x, r->y[r->n] = y, r->mat[r->n++] = m;
    return 1;
}

static char *trim(char *s)
{
    while (isspace((unsigned char)*s))
        s++;
    size_t n = strlen(s);
    while (n && isspace((unsigned char)s[n - 1]))
        s[--n] = '\0';
    return s;
}

/* Parse one data line; returns 1 ok, 0 not numeric, -1 unknown material. */
static int parse_line(const rf_traj_spec *s, char *line, double *x, double *y, size_t *m, int *named, char **bad)
{
    char *f[3] = {NULL, NULL, NULL};
    int nf = 0;
    for (char *tok = strtok(line, ",;\t"); tok && nf < 3; tok = strtok(NULL, ",;\t"))
        f[nf++] = trim(tok);
    if (nf < 2)
        return 0;
    char *end;
    *x = strtod(f[0], &end);
    if (end == f[0] || *end)
        return 0;
    *y = strtod(f[1], &end);
    if (end == f[1] || *end)
        return 0;
    *m = 0;
    if (nf == 3 && *f[2]) {
        *named = 1;
        for (*m = 0; *m < s->n_materials && strcmp(s->materials[*m].name, f[2]); (*m)++)
            ;
        if (*m == s->n_materials) {
            *bad = f[2];
            return -1;
        }
    }
    return 1;
}

rf_status traj_csv_read(const char *path, rf_traj_spec *s, int *named, rf_error *err)
{
    FILE *fp = fopen(path, "r");
    if (!fp)
        return rf_fail(err, RF_EIO, "cannot open the profile CSV '%s': %s", path, strerror(errno));
    csv_rows r = {0};
    char line[4096];
    int lineno = 0, data = 0;
    rf_status st = RF_OK;
    *named = 0;
    while (st == RF_OK && fgets(line, sizeof line, fp)) {
        lineno++;
        char *t = trim(line), *bad = NULL;
        if (!*t || *t == '#')
            continue;
        double x, y;
        size_t m;
        int ok = parse_line(s, t, &x, &y, &m, named, &bad);
        if (ok == 0 && data == 0 && lineno == 1)
            continue; /* header */
        if (ok == 0)
            st = rf_fail(err, RF_EINVAL, "%s:%d: expected x,y[,material] with numbers x, y [m]", path, lineno);
        else if (ok < 0)
            st = rf_fail(err, RF_EINVAL, "%s:%d: material = %s: no such material", path, lineno, bad);
        else if (!push(&r, x, y, m))
            st = rf_fail(err, RF_ENOMEM, "out of memory");
        data++;
    }
    fclose(fp);
    if (st == RF_OK && r.n < 2)
        st = rf_fail(err, RF_EINVAL, "%s: %zu points; a profile needs at least 2", path, r.n);
    if (st != RF_OK) {
        free(r.x), free(r.y), free(r.mat);
        return st;
    }
    free(s->px), free(s->py), free(s->seg_material);
    s->px = r.x, s->py = r.y, s->seg_material = r.mat, s->n_points = r.n;
    return RF_OK;
}

rf_status rf_traj_profile_read_csv(const char *path, rf_traj_spec *s, rf_error *err)
{
    int named;
    return traj_csv_read(path, s, &named, err);
}
