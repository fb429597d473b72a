/* fem3d_layer.c - the slope of a layered 3D impact as an extruded mesh: a
 * plane O-grid (the fine box's top face of uniform squares of size h,
 * surrounded by rings whose nodes lie on the rays from the contact point
 * through the box-edge nodes, spaced geometrically out to the domain radius
 * R) swept down through horizontal node planes (uniform h down to the fine
 * box's depth, geometric below, down to R).  The domain is a (half) cylinder
 * of radius and depth R.  Every node plane is horizontal, so the plane
 * nearest to the layer's bottom is moved to z = -layer_depth and no element
 * straddles the interface (the O-grid's curved layers cannot carry a
 * horizontal plane beyond its fine box).  The cost: the fine squares of the
 * top face are carried down every plane (docs/validation-plastic.md section
 * 9b gives the counts).  Element orientation is fixed by the sign of the
 * Jacobian. */
#include "fem3d_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The plane O-grid and the node planes of the extruded slope. */
typedef struct {
    int NX, NY, j0, K, nring, nseg, nl;
    long n2, q2; /* plane nodes and quads */
    double h, R;
} slab;

static int slab_rings(const f3_box *b, double R, double aspect)
{
    int nmin = b->nxm < b->ny ? b->nxm : b->ny;
    double c = nmin * b->h;
    int K = (int)ceil(log(R / c) / log(1 + aspect / nmin));
    return K < 1 ? 1 : K;
}

static void slab_init(slab *s, const f3_mesh_spec *sp)
{
    const f3_box *b = &sp->slope;
    memset(s, 0, sizeof *s);
    s->NX = b->nxm + b->nxp, s->NY = sp->full ? 2 * b->ny : b->ny, s->j0 = sp->full ? b->ny : 0;
    s->h = b->h, s->R = sp->domain;
    s->K = slab_rings(b, sp->domain, sp->layer_aspect);
    s->nring = sp->full ? 2 * s->NY + 2 * s->NX : 2 * s->NY + s->NX + 1; /* half: open chain (0,0) to (NX,0) */
    s->nseg = sp->full ? s->nring : s->nring - 1;
    s->n2 = (long)(s->NX + 1) * (s->NY + 1) + (long)s->K * s->nring;
    s->q2 = (long)s->NX * s->NY + (long)s->K * s->nseg;
    const double c = b->nz * b->h;
    const int Kz = (int)ceil(log(sp->domain / c) / log(1 + sp->layer_aspect / b->nz));
    s->nl = b->nz + (Kz < 1 ? 1 : Kz) + 1;
}

/* Core (i, j) of ring node r: up the side x = -, along y = max, down x = +, back along y = min (full). */
static void ring_ij(const slab *s, int r, int *i, int *j)
{
    if (r <= s->NY) {
        *i = 0, *j = r;
        return;
    }
    r -= s->NY;
    if (r <= s->NX) {
        *i = r, *j = s->NY;
        return;
    }
    r -= s->NX;
    if (r <= s->NY) {
        *i = s->NX, *j = s->NY - r;
        return;
    }
    r -= s->NY;
    *i = s->NX - r, *j = 0;
}

static long plane_id(const slab *s, int r, int l)
{
    if (l == 0) {
        int i, j;
        ring_ij(s, r % s->nring, &i, &j);
        return (long)i * (s->NY + 1) + j;
    }
    return (long)(s->NX + 1) * (s->NY + 1) + (long)(l - 1) * s->nring + r % s->nring;
}

/* Plane coordinates of plane node n. */
static void plane_point(const slab *s, const f3_box *b, long n, double p[2])
{
    const long ncore = (long)(s->NX + 1) * (s->NY + 1);
    if (n < ncore) {
        p[0] = ((int)(n / (s->NY + 1)) - b->nxm) * s->h, p[1] = ((int)(n % (s->NY + 1)) - s->j0) * s->h;
        return;
    }
    const int l = (int)((n - ncore) / s->nring) + 1, r = (int)((n - ncore) % s->nring);
    double q[2];
    plane_point(s, b, plane_id(s, r, 0), q);
    const double rb = hypot(q[0], q[1]), t = (double)l / s->K;
    const double rr = l == s->K ? s->R : pow(rb, 1 - t) * pow(s->R, t);
    p[0] = q[0] / rb * rr, p[1] = q[1] == 0 ? 0 : q[1] / rb * rr;
}

/* The 4 plane nodes of plane quad q (counter-clockwise or not: fixed later). */
static void plane_quad(const slab *s, long q, long c[4])
{
    const long ncq = (long)s->NX * s->NY;
    if (q < ncq) {
        const int i = (int)(q / s->NY), j = (int)(q % s->NY);
        c[0] = (long)i * (s->NY + 1) + j, c[1] = (long)(i + 1) * (s->NY + 1) + j;
        c[2] = (long)(i + 1) * (s->NY + 1) + j + 1, c[3] = (long)i * (s->NY + 1) + j + 1;
        return;
    }
    q -= ncq;
    const int l = (int)(q / s->nseg), r = (int)(q % s->nseg);
    c[0] = plane_id(s, r, l), c[1] = plane_id(s, r + 1, l), c[2] = plane_id(s, r + 1, l + 1), c[3] = plane_id(s, r, l + 1);
}

/* Depths of the node planes (z_0 = 0 > z_1 > ...), the one nearest to -depth moved there. */
static void slab_levels(const slab *s, const f3_box *b, double depth, double *z)
{
    const int Kz = s->nl - 1 - b->nz;
    const double c = b->nz * b->h;
    for (int k = 0; k <= b->nz; k++)
        z[k] = -k * b->h;
    for (int l = 1; l <= Kz; l++)
        z[b->nz + l] = l == Kz ? -s->R : -pow(c, 1 - (double)l / Kz) * pow(s->R, (double)l / Kz);
    if (!(depth > 0))
        return;
    int best = 1;
    for (int k = 1; k < s->nl - 1; k++)
        if (fabs(z[k] + depth) < fabs(z[best] + depth))
            best = k;
    z[best] = -depth;
}

void f3_slab_counts(const f3_mesh_spec *sp, long *nodes, long *elems, long *outer_quads)
{
    slab s;
    slab_init(&s, sp);
    *nodes = s.n2 * s.nl;
    *elems = s.q2 * (s.nl - 1);
    *outer_quads = (long)s.nseg * (s.nl - 1) + s.q2;
}

rf_status f3_slab_fill(const f3_mesh_spec *sp, f3_mesh *m, long n0, long e0, rf_error *err)
{
    slab s;
    slab_init(&s, sp);
    double *z = malloc((size_t)s.nl * sizeof *z);
    if (!z)
        return rf_fail(err, RF_ENOMEM, "fem3d mesh: out of memory");
    slab_levels(&s, &sp->slope, sp->layer_depth, z);
    const long ncore = (long)(s.NX + 1) * (s.NY + 1);
    for (long n = 0; n < s.n2; n++) {
        double p[2];
        plane_point(&s, &sp->slope, n, p);
        const int outer = n >= ncore + (long)(s.K - 1) * s.nring;
        for (int k = 0; k < s.nl; k++) {
            const long id = n0 + (long)k * s.n2 + n;
            m->x[3 * id] = p[0], m->x[3 * id + 1] = p[1], m->x[3 * id + 2] = z[k];
            unsigned char f = 0;
            if (k == 0)
                f |= F3_SURFACE;
            if (!sp->full && p[1] == 0)
                f |= F3_SYM;
            if (outer || k == s.nl - 1)
                f |= F3_OUTER;
            m->flags[id] = f;
        }
    }
    free(z);
    for (int k = 0; k < s.nl - 1; k++)
        for (long q = 0; q < s.q2; q++) {
            long c[4];
            plane_quad(&s, q, c);
            int *cn = m->conn + 8 * (e0 + (long)k * s.q2 + q);
            for (int a = 0; a < 4; a++)
                cn[a] = (int)(n0 + (long)k * s.n2 + c[a]), cn[4 + a] = (int)(n0 + (long)(k + 1) * s.n2 + c[a]);
            f3_hex_orient(m->x, cn);
        }
    for (int i = 0; i <= s.NX; i++)
        for (int j = 0; j <= s.NY; j++)
            m->top_s[i * (s.NY + 1) + j] = (int)(n0 + (long)i * (s.NY + 1) + j);
    long oq = 0;
    for (int k = 0; k < s.nl - 1; k++) /* the cylinder's side */
        for (int r = 0; r < s.nseg; r++, oq++) {
            const long a = plane_id(&s, r, s.K), b = plane_id(&s, r + 1, s.K);
            int *o = m->outer_quads + 4 * oq;
            o[0] = (int)(n0 + (long)k * s.n2 + a), o[1] = (int)(n0 + (long)k * s.n2 + b);
            o[2] = (int)(n0 + (long)(k + 1) * s.n2 + b), o[3] = (int)(n0 + (long)(k + 1) * s.n2 + a);
        }
    for (long q = 0; q < s.q2; q++, oq++) { /* the bottom */
        long c[4];
        plane_quad(&s, q, c);
        for (int a = 0; a < 4; a++)
            m->outer_quads[4 * oq + a] = (int)(n0 + (long)(s.nl - 1) * s.n2 + c[a]);
    }
    m->nxt_s = s.NX + 1, m->nyt_s = s.NY + 1;
    m->extruded = 1;
    return RF_OK;
}
