/* profile_csv.c - the strict reader of a slope profile CSV: one vertex per
 * line, "x,y" or "x,y,material" (metres; the material names one of the
 * spec's materials and applies to the segment starting at that vertex).
 * The file is read whole (the input-file guard of core/textfile.h: no FIFO
 * or device, a size limit), so no line is cut into pieces.  A UTF-8 byte
 * order mark is skipped; a NUL byte is an error; a line ends at LF (a CR
 * before it is dropped).  Blank lines and lines starting with '#' are
 * skipped.  The first other line may be a header naming the columns
 * (x, y[, material], e.g. "x_m,y_m,material"); any other line must hold two
 * numbers and at most a material, separated by single commas: an empty
 * field, a fourth column or a non-numeric value is an error naming
 * file:line, the field and the value.  When the material column is used,
 * every vertex but the last must name its segment's material. */
#include "trajectory/traj_internal.h"
#include "core/textfile.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define CSV_MAX_BYTES (256u << 20)
#define CSV_MAX_FIELD 256

typedef struct {
    const char *name;       /* file name in messages */
    size_t line;            /* 1-based */
    char field[3][CSV_MAX_FIELD];
    int nf;
} csv_line;

typedef struct {
    double *x, *y;
    size_t *mat;
    size_t n, cap;
    int named;              /* a row named a material */
    size_t unnamed_row;     /* line of the first row without one (0: none) */
    size_t unnamed_at;      /* its vertex index */
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

/* Split [s, e) at commas into L->field (trimmed); an error for too many or too long fields. */
static rf_status split(const char *s, const char *e, csv_line *L, rf_error *err)
{
    L->nf = 0;
    for (;;) {
        const char *c = memchr(s, ',', (size_t)(e - s)), *end = c ? c : e;
        if (L->nf == 3)
            return rf_fail(err, RF_EINVAL, "%s:%zu: more than 3 fields; expected x,y[,material]", L->name, L->line);
        while (s < end && isspace((unsigned char)*s))
            s++;
        const char *t = end;
        while (t > s && isspace((unsigned char)t[-1]))
            t--;
        if ((size_t)(t - s) >= CSV_MAX_FIELD)
            return rf_fail(err, RF_EINVAL, "%s:%zu: field %d is longer than %d characters", L->name, L->line, L->nf + 1,
                           CSV_MAX_FIELD - 1);
        memcpy(L->field[L->nf], s, (size_t)(t - s));
        L->field[L->nf++][t - s] = '\0';
        if (!c)
            return RF_OK;
        s = c + 1;
    }
}

static int is_number(const char *f, double *v)
{
    char *end;
    *v = strtod(f, &end);
    return *f && end != f && !*end && isfinite(*v);
}

/* A header line: x..., y...[, material...] (names with units, e.g. x_m). */
static int is_header(const csv_line *L)
{
    return L->nf >= 2 && tolower((unsigned char)L->field[0][0]) == 'x' && tolower((unsigned char)L->field[1][0]) == 'y' &&
           (L->nf == 2 || !strncasecmp(L->field[2], "material", 8));
}

static rf_status vertex(const rf_traj_spec *s, const csv_line *L, csv_rows *r, rf_error *err)
{
    static const char *const what[3] = {"x", "y", "material"};
    double xy[2];
    for (int k = 0; k < L->nf; k++)
        if (!L->field[k][0])
            return rf_fail(err, RF_EINVAL, "%s:%zu: %s is empty; expected x,y[,material]", L->name, L->line, what[k]);
    if (L->nf < 2)
        return rf_fail(err, RF_EINVAL, "%s:%zu: '%s': one field; expected x,y[,material]", L->name, L->line,
                       L->field[0]);
    for (int k = 0; k < 2; k++)
        if (!is_number(L->field[k], &xy[k]))
            return rf_fail(err, RF_EINVAL, "%s:%zu: %s = %s: expected a finite number [m]", L->name, L->line, what[k],
                           L->field[k]);
    size_t m = 0;
    if (L->nf == 3) {
        for (m = 0; m < s->n_materials && strcmp(s->materials[m].name, L->field[2]); m++)
            ;
        if (m == s->n_materials)
            return rf_fail(err, RF_EINVAL, "%s:%zu: material = %s: no such material", L->name, L->line, L->field[2]);
        r->named = 1;
    } else if (!r->unnamed_row) {
        r->unnamed_row = L->line, r->unnamed_at = r->n;
    }
    if (!push(r, xy[0], xy[1], m))
        return rf_fail(err, RF_ENOMEM, "out of memory");
    return RF_OK;
}

/* Every line of buf[0..len) into r. */
static rf_status parse(const char *name, const char *buf, size_t len, const rf_traj_spec *s, csv_rows *r,
                       rf_error *err)
{
    const char *p = buf, *end = buf + len, *nul = memchr(buf, '\0', len);
    if (len >= 3 && !memcmp(p, "\xEF\xBB\xBF", 3))
        p += 3; /* UTF-8 byte order mark */
    csv_line L = {name, 0, {{0}}, 0};
    int first = 1;
    rf_status st = RF_OK;
    while (st == RF_OK && p < end) {
        const char *e = memchr(p, '\n', (size_t)(end - p)), *next;
        next = e ? e + 1 : end;
        e = e ? e : end;
        L.line++;
        if (nul && nul < next)
            return rf_fail(err, RF_EINVAL, "%s:%zu: a NUL byte at column %zu: not a text file", name, L.line,
                           (size_t)(nul - p) + 1);
        if (e > p && e[-1] == '\r')
            e--;
        const char *t = p;
        while (t < e && isspace((unsigned char)*t))
            t++;
        p = next;
        if (t == e || *t == '#')
            continue;
        if ((st = split(t, e, &L, err)) != RF_OK)
            break;
        double v;
        if (first && !is_number(L.field[0], &v)) {
            first = 0;
            if (!is_header(&L))
                st = rf_fail(err, RF_EINVAL, "%s:%zu: x = %s: neither a number nor a header (x,y[,material])", name,
                             L.line, L.field[0]);
            continue;
        }
        first = 0;
        st = vertex(s, &L, r, err);
    }
    return st;
}

rf_status traj_csv_parse(const char *name, const char *buf, size_t len, rf_traj_spec *s, int *named, rf_error *err)
{
    csv_rows r = {0};
    rf_status st = parse(name, buf, len, s, &r, err);
    *named = r.named;
    if (st == RF_OK && r.n < 2)
        st = rf_fail(err, RF_EINVAL, "%s: %zu points; a profile needs at least 2", name, r.n);
    if (st == RF_OK && r.named && r.unnamed_row && r.unnamed_at + 1 != r.n)
        st = rf_fail(err, RF_EINVAL, "%s:%zu: no material while other lines name theirs; every vertex but the "
                     "last names the material of the segment it starts", name, r.unnamed_row);
    if (st != RF_OK) {
        free(r.x), free(r.y), free(r.mat);
        return st;
    }
    free(s->px), free(s->py), free(s->seg_material);
    s->px = r.x, s->py = r.y, s->seg_material = r.mat, s->n_points = r.n;
    return RF_OK;
}

rf_status traj_csv_read(const char *path, rf_traj_spec *s, int *named, rf_error *err)
{
    char *buf = NULL;
    size_t len = 0;
    *named = 0;
    rf_status st = rf_read_text_file(path, "profile CSV", CSV_MAX_BYTES, &buf, &len, err);
    if (st == RF_OK)
        st = traj_csv_parse(path, buf, len, s, named, err);
    free(buf);
    return st;
}

rf_status rf_traj_profile_read_csv(const char *path, rf_traj_spec *s, rf_error *err)
{
    int named;
    return traj_csv_read(path, s, &named, err);
}
