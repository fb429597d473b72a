/* test_terrain_release.c - release features on the map (terrain_release.c):
 * a polygon's ear-clipping triangles cover it exactly (their areas sum to the
 * shoelace area, concave polygons of few and many vertices, either
 * orientation) and every drawn point lies inside it; points are uniform by
 * area (Kolmogorov-Smirnov on x and y against the exact area fraction,
 * computed by clipping the polygon with a half-plane); features are chosen by
 * weight (chi-square at 0.1 %); points on a line are uniform by length (KS on
 * the distance along it); a self-intersecting polygon is refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "trajectory/terrain_internal.h"

/* A spec whose terrain holds the features: nv[f] vertices each from xy (x, y pairs). */
typedef struct {
    rf_traj_spec s;
    rf_terrain_def d;
} holder;

static void make(holder *h, rf_terrain_feature_kind kind, size_t nf, const size_t *nv, const double *xy,
                 const double *w)
{
    memset(h, 0, sizeof *h);
    rf_terrain_release *r = &h->d.release;
    r->kind = kind, r->n_features = nf;
    r->start = calloc(nf + 1, sizeof *r->start);
    r->weight = malloc(nf * sizeof *r->weight);
    size_t total = 0;
    for (size_t f = 0; f < nf; f++)
        total += nv[f], r->start[f + 1] = total, r->weight[f] = w ? w[f] : 1;
    r->x = malloc(total * sizeof *r->x);
    r->y = malloc(total * sizeof *r->y);
    for (size_t k = 0; k < total; k++)
        r->x[k] = xy[2 * k], r->y[k] = xy[2 * k + 1];
    h->s.terrain = &h->d;
}

static void unmake(holder *h) { rf_terrain_def_free(&h->d); }

static terrain_release_set *prepare(holder *h)
{
    terrain_release_set *set;
    rf_error err;
    if (terrain_release_prepare(&h->s, &set, &err) != RF_OK)
        fail_msg("%s", err.msg);
    return set;
}

static double shoelace(const double *x, const double *y, size_t n)
{
    double a = 0;
    for (size_t i = 0; i < n; i++)
        a += x[i] * y[(i + 1) % n] - x[(i + 1) % n] * y[i];
    return 0.5 * a;
}

/* Inside or on the boundary (within 1e-9) of the ring. */
static int inside(const double *x, const double *y, size_t n, double px, double py)
{
    int in = 0;
    for (size_t i = 0, j = n - 1; i < n; j = i++) {
        double ex = x[j] - x[i], ey = y[j] - y[i];
        double len = hypot(ex, ey), cr = fabs((px - x[i]) * ey - (py - y[i]) * ex) / len;
        double t = ((px - x[i]) * ex + (py - y[i]) * ey) / (len * len);
        if (cr < 1e-9 && t >= -1e-12 && t <= 1 + 1e-12)
            return 1;
        if ((y[i] > py) != (y[j] > py) && px < x[i] + (py - y[i]) / (y[j] - y[i]) * (x[j] - x[i]))
            in = !in;
    }
    return in;
}

/* Area of the ring's part with coordinate (axis 0: x, 1: y) <= c (Sutherland-Hodgman
 * against one half-plane: right for concave rings too, the doubled edges on the cut cancel). */
static double area_below(const double *x, const double *y, size_t n, int axis, double c)
{
    double *cx = malloc(2 * n * sizeof *cx), *cy = malloc(2 * n * sizeof *cy);
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        size_t j = (i + 1) % n;
        double a = axis ? y[i] : x[i], b = axis ? y[j] : x[j];
        if (a <= c)
            cx[m] = x[i], cy[m++] = y[i];
        if ((a <= c) != (b <= c)) {
            double t = (c - a) / (b - a);
            cx[m] = x[i] + t * (x[j] - x[i]), cy[m++] = y[i] + t * (y[j] - y[i]);
        }
    }
    double area = m >= 3 ? fabs(shoelace(cx, cy, m)) : 0;
    free(cx), free(cy);
    return area;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* KS distance of the sample v (sorted here) from the CDF F. */
static double ks(double *v, size_t n, double (*F)(void *, double), void *ctx)
{
    qsort(v, n, sizeof *v, cmp);
    double d = 0;
    for (size_t i = 0; i < n; i++) {
        double f = F(ctx, v[i]);
        d = fmax(d, fmax(fabs(f - (double)i / (double)n), fabs((double)(i + 1) / (double)n - f)));
    }
    return d;
}

/* Polygons: an L (concave, 6 vertices), a 60-point star, a comb (concave, many
 * teeth) written clockwise, a square with collinear vertices on its sides. */
static size_t star(double *xy, size_t points)
{
    for (size_t k = 0; k < 2 * points; k++) {
        double r = k % 2 ? 3.0 : 10.0, a = RF_PI * (double)k / (double)points;
        xy[2 * k] = 500 + r * cos(a), xy[2 * k + 1] = 200 + r * sin(a);
    }
    return 2 * points;
}

static size_t comb(double *xy, size_t teeth)
{
    size_t n = 0; /* clockwise: up the left side, along the top with its notches, down, back */
    xy[n++] = 0, xy[n++] = 0;
    xy[n++] = 0, xy[n++] = 5;
    for (size_t t = 0; t < teeth; t++) {
        double x0 = 2.0 * (double)t;
        xy[n++] = x0 + 1, xy[n++] = 5;
        xy[n++] = x0 + 1, xy[n++] = 1;
        xy[n++] = x0 + 2, xy[n++] = 1;
        xy[n++] = x0 + 2, xy[n++] = 5;
    }
    xy[n++] = 2.0 * (double)teeth + 1, xy[n++] = 5;
    xy[n++] = 2.0 * (double)teeth + 1, xy[n++] = 0;
    return n / 2;
}

typedef struct {
    size_t n;
    double xy[2000];
} ring;

static void rings(ring *r, size_t *count)
{
    static const double L[] = {0, 0, 4, 0, 4, 1, 1, 1, 1, 3, 0, 3};
    static const double sq[] = {0, 0, 1, 0, 2, 0, 2, 1, 2, 2, 1, 2, 0, 2, 0, 1};
    memcpy(r[0].xy, L, sizeof L), r[0].n = 6;
    r[1].n = star(r[1].xy, 30);
    r[2].n = comb(r[2].xy, 40);
    memcpy(r[3].xy, sq, sizeof sq), r[3].n = 8;
    *count = 4;
}

static void split(const ring *r, double *x, double *y)
{
    for (size_t k = 0; k < r->n; k++)
        x[k] = r->xy[2 * k], y[k] = r->xy[2 * k + 1];
}

static void test_triangles_cover_the_polygon(void **state)
{
    (void)state;
    ring r[4];
    size_t nr;
    rings(r, &nr);
    for (size_t p = 0; p < nr; p++) {
        holder h;
        make(&h, RF_TERRAIN_POLYGONS, 1, &r[p].n, r[p].xy, NULL);
        terrain_release_set *set = prepare(&h);
        const double(*t)[6];
        size_t nt = terrain_release_pieces(set, 0, &t);
        double x[1000], y[1000], sum = 0;
        split(&r[p], x, y);
        double area = fabs(shoelace(x, y, r[p].n));
        assert_true(nt >= 1 && nt <= r[p].n - 2);
        for (size_t k = 0; k < nt; k++) {
            double a = 0.5 * ((t[k][2] - t[k][0]) * (t[k][5] - t[k][1]) - (t[k][3] - t[k][1]) * (t[k][4] - t[k][0]));
            assert_true(a > 0); /* counter-clockwise, not degenerate */
            sum += a;
            double cx = (t[k][0] + t[k][2] + t[k][4]) / 3, cy = (t[k][1] + t[k][3] + t[k][5]) / 3;
            assert_true(inside(x, y, r[p].n, cx, cy));
        }
        if (fabs(sum - area) > 1e-12 * area)
            fail_msg("polygon %zu: triangles %.17g, shoelace %.17g", p, sum, area);
        terrain_release_free(set);
        unmake(&h);
    }
}

typedef struct {
    const double *x, *y;
    size_t n;
    int axis;
    double area;
} frac_ctx;

static double area_fraction(void *ctx, double c)
{
    frac_ctx *f = ctx;
    return area_below(f->x, f->y, f->n, f->axis, c) / f->area;
}

/* Every point inside; x and y distributed as the area fraction (KS, 0.1 %). */
static void test_points_inside_and_uniform_by_area(void **state)
{
    (void)state;
    ring r[4];
    size_t nr, n = 20000;
    rings(r, &nr);
    double *vx = malloc(n * sizeof *vx), *vy = malloc(n * sizeof *vy);
    for (size_t p = 0; p < nr; p++) {
        holder h;
        make(&h, RF_TERRAIN_POLYGONS, 1, &r[p].n, r[p].xy, NULL);
        terrain_release_set *set = prepare(&h);
        double x[1000], y[1000];
        split(&r[p], x, y);
        for (size_t i = 0; i < n; i++) {
            double u1 = rf_traj_uniform(7, 3 * i, p), u2 = rf_traj_uniform(7, 3 * i + 1, p);
            terrain_release_point(set, u1, u2, rf_traj_uniform(7, 3 * i + 2, p), &vx[i], &vy[i]);
            if (!inside(x, y, r[p].n, vx[i], vy[i]))
                fail_msg("polygon %zu: point %zu (%.17g, %.17g) outside", p, i, vx[i], vy[i]);
        }
        frac_ctx fx = {x, y, r[p].n, 0, fabs(shoelace(x, y, r[p].n))}, fy = fx;
        fy.axis = 1;
        double dx = ks(vx, n, area_fraction, &fx), dy = ks(vy, n, area_fraction, &fy), crit = 1.949 / sqrt((double)n);
        if (dx > crit || dy > crit)
            fail_msg("polygon %zu: KS D_x = %g, D_y = %g > %g (0.1 %%)", p, dx, dy, crit);
        terrain_release_free(set);
        unmake(&h);
    }
    free(vx), free(vy);
}

/* Features by weight: chi-square with 4 degrees of freedom at 0.1 % (18.467);
 * a feature of weight 0 is never drawn. */
static void test_features_by_weight(void **state)
{
    (void)state;
    const double xy[] = {0, 0, 1, 0, 2, 0, 3, 0, 4, 0, 5, 0}, w[] = {1, 2, 0, 3, 4, 10};
    const size_t nv[] = {1, 1, 1, 1, 1, 1};
    holder h;
    make(&h, RF_TERRAIN_POINTS, 6, nv, xy, w);
    terrain_release_set *set = prepare(&h);
    size_t n = 50000, count[6] = {0};
    for (size_t i = 0; i < n; i++) {
        double x, y;
        terrain_release_point(set, rf_traj_uniform(3, i, 0), 0.5, 0.5, &x, &y);
        assert_true(x == floor(x) && x >= 0 && x <= 5 && y == 0);
        count[(size_t)x]++;
    }
    assert_int_equal(count[2], 0);
    double chi = 0;
    for (int f = 0; f < 6; f++) {
        double e = (double)n * w[f] / 20;
        if (e > 0)
            chi += (count[f] - e) * (count[f] - e) / e;
    }
    if (chi > 18.467)
        fail_msg("chi-square %g > 18.467 (4 dof, 0.1 %%)", chi);
    double x, y; /* u1 at the ends picks the first and last features of weight > 0 */
    terrain_release_point(set, 0, 0.5, 0.5, &x, &y);
    assert_true(x == 0);
    terrain_release_point(set, 1, 0.5, 0.5, &x, &y);
    assert_true(x == 5);
    terrain_release_free(set);
    unmake(&h);
}

typedef struct {
    const double *cum;
    size_t n;
} len_ctx;

static double uniform01(void *ctx, double c)
{
    (void)ctx;
    return fmin(fmax(c, 0), 1);
}

/* Two lines (weights 1, 3) of segments 1, 3, 6 m and 2, 2 m: the distance
 * along each, over its length, uniform (KS 0.1 %); the share of the second
 * line 3/4 (binomial, 4 sd). */
static void test_lines_by_length(void **state)
{
    (void)state;
    const double xy[] = {0, 0, 1, 0, 1, 3, 7, 3, /* second line */ 100, 0, 100, 2, 102, 2};
    const size_t nv[] = {4, 3};
    const double w[] = {1, 3};
    holder h;
    make(&h, RF_TERRAIN_LINES, 2, nv, xy, w);
    terrain_release_set *set = prepare(&h);
    size_t n = 40000, n2 = 0, n1 = 0;
    double *s1 = malloc(n * sizeof *s1), *s2 = malloc(n * sizeof *s2);
    for (size_t i = 0; i < n; i++) {
        double x, y;
        terrain_release_point(set, rf_traj_uniform(5, 2 * i, 1), rf_traj_uniform(5, 2 * i + 1, 1), 0.3, &x, &y);
        if (x >= 100) { /* along: up 2, then right 2 */
            assert_true((x == 100 && y >= 0 && y <= 2) || (y == 2 && x <= 102));
            s2[n2++] = (x == 100 ? y : 2 + (x - 100)) / 4;
        } else {
            double along = y == 0 ? x : x == 1 ? 1 + y : 4 + (x - 1);
            assert_true((y == 0 && x <= 1) || (x == 1 && y <= 3) || (y == 3 && x <= 7));
            s1[n1++] = along / 10;
        }
    }
    double crit1 = 1.949 / sqrt((double)n1), crit2 = 1.949 / sqrt((double)n2);
    double d1 = ks(s1, n1, uniform01, NULL), d2 = ks(s2, n2, uniform01, NULL);
    if (d1 > crit1 || d2 > crit2)
        fail_msg("KS along the lines: %g (> %g?), %g (> %g?)", d1, crit1, d2, crit2);
    double p = 0.75, sd = sqrt(n * p * (1 - p));
    assert_true(fabs((double)n2 - n * p) < 4 * sd);
    free(s1), free(s2);
    terrain_release_free(set);
    unmake(&h);
}

static void test_self_intersecting_refused(void **state)
{
    (void)state;
    const double bowtie[] = {0, 0, 2, 2, 2, 0, 0, 2};
    const double touch[] = {0, 0, 4, 0, 4, 4, 2, 0.0, 0, 4}; /* a vertex on another edge */
    const double *polys[2] = {bowtie, touch};
    const size_t nv[2] = {4, 5};
    for (int k = 0; k < 2; k++) {
        holder h;
        make(&h, RF_TERRAIN_POLYGONS, 1, &nv[k], polys[k], NULL);
        terrain_release_set *set;
        rf_error err;
        assert_int_equal(terrain_release_prepare(&h.s, &set, &err), RF_EINVAL);
        assert_null(set);
        if (!strstr(err.msg, "release.polygons[0]") || !strstr(err.msg, "intersects itself"))
            fail_msg("message: %s", err.msg);
        unmake(&h);
    }
}

/* Weights that sum to 0, and a polygon of no area, are refused. */
static void test_bad_weights_and_flat_polygon(void **state)
{
    (void)state;
    const double xy[] = {0, 0, 1, 1}, w0[] = {0, 0}, flat[] = {0, 0, 1, 1, 2, 2};
    const size_t nv[] = {1, 1}, nf = 3;
    holder h;
    terrain_release_set *set;
    rf_error err;
    make(&h, RF_TERRAIN_POINTS, 2, nv, xy, w0);
    assert_int_equal(terrain_release_prepare(&h.s, &set, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "release.blocks"));
    unmake(&h);
    make(&h, RF_TERRAIN_POLYGONS, 1, &nf, flat, NULL);
    assert_int_equal(terrain_release_prepare(&h.s, &set, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "release.polygons[0]"));
    unmake(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_triangles_cover_the_polygon),
        cmocka_unit_test(test_points_inside_and_uniform_by_area),
        cmocka_unit_test(test_features_by_weight),
        cmocka_unit_test(test_lines_by_length),
        cmocka_unit_test(test_self_intersecting_refused),
        cmocka_unit_test(test_bad_weights_and_flat_polygon),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
