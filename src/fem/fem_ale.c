/* fem_ale.c - ALE rezoning of the axisymmetric updated-Lagrangian slope
 * (fem_ale.h): the mesh topology the rezone needs (node neighbours, elements
 * around a node, the element across each face), the smoothing, the
 * donor-cell remap of the point state with the exact swept volumes, the
 * velocity remap, and the rezone that strings them together. */
#include "fem_ale.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void fem_ale_free(fem_ale *A)
{
    free(A->move), free(A->nb_ptr), free(A->nb), free(A->ne_ptr), free(A->ne), free(A->face), free(A->size0);
    free(A->zone_e), free(A->zone_n), free(A->slot), free(A->mean), free(A->swept), free(A->vol0), free(A->w1);
    free(A->hmin), free(A->vnew);
    memset(A, 0, sizeof *A);
}

/* Node coordinates of element e at X + u + delta (u, delta may be NULL). */
static void element_xy(const fem_mesh *mesh, long e, const double *u, const double *delta, double r[4], double z[4])
{
    const int *c = mesh->conn + 4 * e;
    for (int a = 0; a < 4; a++) {
        r[a] = mesh->r[c[a]] + (u ? u[2 * c[a]] : 0) + (delta ? delta[2 * c[a]] : 0);
        z[a] = mesh->z[c[a]] + (u ? u[2 * c[a] + 1] : 0) + (delta ? delta[2 * c[a] + 1] : 0);
    }
}

static double size_of(const double r[4], const double z[4])
{
    const double area = 0.5 * ((r[2] - r[0]) * (z[3] - z[1]) - (r[3] - r[1]) * (z[2] - z[0]));
    const double diag = fmax(hypot(r[2] - r[0], z[2] - z[0]), hypot(r[3] - r[1], z[3] - z[1]));
    return area > 0 ? area / diag : 0;
}

double fem_ale_element_size(const fem_mesh *mesh, long e, const double *u)
{
    double r[4], z[4];
    element_xy(mesh, e, u, NULL, r, z);
    return size_of(r, z);
}

/* Node -> elements of the block, and node -> edge neighbours (unique). */
static rf_status ale_topology(fem_ale *A, const fem_mesh *mesh, rf_error *err)
{
    const long nn = A->nn, nbe = A->e1 - A->e0;
    A->ne_ptr = calloc((size_t)nn + 1, sizeof *A->ne_ptr), A->nb_ptr = calloc((size_t)nn + 1, sizeof *A->nb_ptr);
    A->ne = malloc((size_t)(4 * nbe + 1) * sizeof *A->ne), A->nb = malloc((size_t)(8 * nbe + 1) * sizeof *A->nb);
    if (!A->ne_ptr || !A->nb_ptr || !A->ne || !A->nb)
        return rf_fail(err, RF_ENOMEM, "fem ale: out of memory");
    for (long e = A->e0; e < A->e1; e++)
        for (int a = 0; a < 4; a++)
            A->ne_ptr[mesh->conn[4 * e + a] + 1]++;
    for (long i = 0; i < nn; i++)
        A->ne_ptr[i + 1] += A->ne_ptr[i];
    long *fill = calloc((size_t)nn + 1, sizeof *fill);
    if (!fill)
        return rf_fail(err, RF_ENOMEM, "fem ale: out of memory");
    for (long e = A->e0; e < A->e1; e++)
        for (int a = 0; a < 4; a++) {
            const int n = mesh->conn[4 * e + a];
            if (a == 0 || n != mesh->conn[4 * e + a - 1]) /* a collapsed corner lists the element once */
                A->ne[A->ne_ptr[n] + fill[n]++] = e;
        }
    for (long i = 0; i < nn; i++) { /* neighbours: the other ends of the edges at i, once each */
        long k = 0;
        for (long p = A->ne_ptr[i]; p < A->ne_ptr[i] + fill[i]; p++) {
            const int *c = mesh->conn + 4 * A->ne[p];
            for (int a = 0; a < 4; a++) {
                if (c[a] != i)
                    continue;
                const long o[2] = {c[(a + 1) % 4], c[(a + 3) % 4]};
                for (int s = 0; s < 2; s++) {
                    int seen = o[s] == i;
                    for (long m = 0; m < k && !seen; m++)
                        seen = A->nb[2 * A->ne_ptr[i] + m] == o[s];
                    if (!seen)
                        A->nb[2 * A->ne_ptr[i] + k++] = o[s];
                }
            }
        }
        A->nb_ptr[i + 1] = k; /* count for now; compacted below */
    }
    long w = 0; /* compact: neighbours of i at [nb_ptr[i], nb_ptr[i + 1]) */
    for (long i = 0; i < nn; i++) {
        const long k = A->nb_ptr[i + 1], from = 2 * A->ne_ptr[i];
        memmove(A->nb + w, A->nb + from, (size_t)k * sizeof *A->nb);
        A->nb_ptr[i] = w, w += k;
    }
    A->nb_ptr[nn] = w;
    for (long i = 0; i < nn; i++) /* the element lists with their true lengths (collapsed corners) */
        for (long p = A->ne_ptr[i] + fill[i]; p < A->ne_ptr[i + 1]; p++)
            A->ne[p] = -1;
    free(fill);
    return RF_OK;
}

/* The element across edge (p, q) of element e: the block element with the edge (q, p); -1 if none. */
static long across(const fem_ale *A, const fem_mesh *mesh, long e, int p, int q)
{
    for (long k = A->ne_ptr[p]; k < A->ne_ptr[p + 1]; k++) {
        const long f = A->ne[k];
        if (f < 0 || f == e)
            continue;
        const int *c = mesh->conn + 4 * f;
        for (int a = 0; a < 4; a++)
            if (c[a] == q && c[(a + 1) % 4] == p)
                return f;
    }
    return -1;
}

/* Which nodes may move (fem_ale.h): interior nodes of one material with both dofs free; axis nodes along z. */
static void ale_movable(fem_ale *A, const fem_mesh *mesh, const unsigned char *emat, const double *invm)
{
    for (long i = 0; i < A->nn; i++) {
        if (A->ne_ptr[i] == A->ne_ptr[i + 1] || (mesh->flags[i] & (FEM_OUTER | FEM_SURFACE)) || !(invm[2 * i + 1] > 0))
            continue;
        int one = 1;
        for (long k = A->ne_ptr[i]; k < A->ne_ptr[i + 1] && emat; k++)
            one &= A->ne[k] < 0 || emat[A->ne[k]] == emat[A->ne[A->ne_ptr[i]]];
        if (!one)
            continue;
        if (invm[2 * i] > 0)
            A->move[i] = 1;
        else if (mesh->flags[i] & FEM_AXIS)
            A->move[i] = 2;
    }
}

rf_status fem_ale_setup(fem_ale *A, const fem_mesh *mesh, long e0, long e1, const unsigned char *emat,
                        const double *invm, const fem_ale_params *p, rf_error *err)
{
    memset(A, 0, sizeof *A);
    if (!(p->trigger > 0 && p->trigger < 1) || !(p->zone >= p->trigger && p->zone < 1) || p->sweeps < 0)
        return rf_fail(err, RF_EINVAL, "fem ale: trigger = %g must lie in (0, 1), zone = %g in [trigger, 1), "
                       "sweeps = %d >= 0", p->trigger, p->zone, p->sweeps);
    A->p = *p, A->nn = mesh->n_nodes, A->e0 = e0, A->e1 = e1;
    const size_t nn = (size_t)A->nn, nbe = (size_t)(e1 - e0);
    rf_status st = ale_topology(A, mesh, err);
    if (st != RF_OK)
        return st;
    A->move = calloc(nn + 1, 1), A->zone_n = calloc(nn + 1, 1), A->zone_e = calloc(nbe + 1, 1);
    A->face = malloc((4 * nbe + 1) * sizeof *A->face), A->size0 = malloc((nbe + 1) * sizeof *A->size0);
    A->slot = malloc((nbe + 1) * sizeof *A->slot), A->hmin = malloc((nn + 1) * sizeof *A->hmin);
    A->swept = malloc((4 * nbe + 1) * sizeof *A->swept), A->vol0 = malloc((nbe + 1) * sizeof *A->vol0);
    A->w1 = malloc((4 * nbe + 1) * sizeof *A->w1), A->vnew = malloc((2 * nn + 1) * sizeof *A->vnew);
    if (!A->move || !A->zone_n || !A->zone_e || !A->face || !A->size0 || !A->slot || !A->hmin || !A->swept ||
        !A->vol0 || !A->w1 || !A->vnew)
        return rf_fail(err, RF_ENOMEM, "fem ale: out of memory for %ld elements", (long)nbe);
    for (long e = e0; e < e1; e++) {
        const int *c = mesh->conn + 4 * e;
        for (int a = 0; a < 4; a++)
            A->face[4 * (e - e0) + a] = c[a] == c[(a + 1) % 4] ? -1 : across(A, mesh, e, c[a], c[(a + 1) % 4]);
        A->size0[e - e0] = fem_ale_element_size(mesh, e, NULL);
        A->slot[e - e0] = -1;
    }
    ale_movable(A, mesh, emat, invm);
    return RF_OK;
}

double fem_ale_ratio_min(const fem_ale *A, const fem_mesh *mesh, const double *u)
{
    double m = INFINITY;
    for (long e = A->e0; e < A->e1; e++)
        if (A->size0[e - A->e0] > 0)
            m = fmin(m, fem_ale_element_size(mesh, e, u) / A->size0[e - A->e0]);
    return m;
}

/* The zone: elements below the zone ratio and two rings of elements around them; its movable nodes. */
static void ale_zone(fem_ale *A, const fem_mesh *mesh, const double *u)
{
    const long nbe = A->e1 - A->e0;
    memset(A->zone_n, 0, (size_t)A->nn);
    for (long e = A->e0; e < A->e1; e++)
        A->zone_e[e - A->e0] = A->size0[e - A->e0] > 0 &&
                               fem_ale_element_size(mesh, e, u) < A->p.zone * A->size0[e - A->e0];
    for (int ring = 0; ring < 3; ring++) {
        for (long le = 0; le < nbe; le++)
            for (int a = 0; a < 4 && A->zone_e[le]; a++)
                A->zone_n[mesh->conn[4 * (A->e0 + le) + a]] = 1;
        if (ring == 2)
            break;
        for (long i = 0; i < A->nn; i++)
            for (long k = A->ne_ptr[i]; k < A->ne_ptr[i + 1] && A->zone_n[i]; k++)
                if (A->ne[k] >= 0)
                    A->zone_e[A->ne[k] - A->e0] = 1;
    }
    for (long i = 0; i < A->nn; i++)
        A->zone_n[i] = A->zone_n[i] && A->move[i];
}

/* The affine fit of node i's neighbours' displacements d = u + delta from
 * the reference positions, at node i's reference position: target[2]. */
static void affine_target(const fem_ale *A, const fem_mesh *mesh, long i, const double *u, const double *delta,
                          double target[2])
{
    const long k0 = A->nb_ptr[i], k1 = A->nb_ptr[i + 1];
    double Xm = 0, Zm = 0, dm[2] = {0, 0};
    for (long k = k0; k < k1; k++) {
        const long j = A->nb[k];
        Xm += mesh->r[j], Zm += mesh->z[j];
        for (int c = 0; c < 2; c++)
            dm[c] += u[2 * j + c] + delta[2 * j + c];
    }
    const double n = (double)(k1 - k0);
    Xm /= n, Zm /= n, dm[0] /= n, dm[1] /= n;
    double mrr = 0, mrz = 0, mzz = 0, br[2] = {0, 0}, bz[2] = {0, 0};
    for (long k = k0; k < k1; k++) {
        const long j = A->nb[k];
        const double x = mesh->r[j] - Xm, y = mesh->z[j] - Zm;
        mrr += x * x, mrz += x * y, mzz += y * y;
        for (int c = 0; c < 2; c++) {
            const double d = u[2 * j + c] + delta[2 * j + c] - dm[c];
            br[c] += x * d, bz[c] += y * d;
        }
    }
    const double det = mrr * mzz - mrz * mrz, x = mesh->r[i] - Xm, y = mesh->z[i] - Zm;
    for (int c = 0; c < 2; c++) {
        target[c] = dm[c];
        if (det > 1e-12 * (mrr + mzz) * (mrr + mzz)) /* else the neighbours' mean */
            target[c] += x * (mzz * br[c] - mrz * bz[c]) / det + y * (mrr * bz[c] - mrz * br[c]) / det;
    }
}

/* Zero the motion of the nodes of elements that it would make worse than
 * the trigger allows (or invert); repeated until none is left. */
static int ale_reject(const fem_ale *A, const fem_mesh *mesh, long e, const double *u, double *delta)
{
    const long le = e - A->e0;
    double r[4], z[4];
    element_xy(mesh, e, u, delta, r, z);
    const double s1 = size_of(r, z) / A->size0[le], s0 = fem_ale_element_size(mesh, e, u) / A->size0[le];
    if (s1 > 0 && (s1 >= s0 || s1 >= A->p.trigger))
        return 0;
    int bad = 0;
    for (int a = 0; a < 4; a++) {
        const int n = mesh->conn[4 * e + a];
        bad |= delta[2 * n] != 0 || delta[2 * n + 1] != 0;
        delta[2 * n] = delta[2 * n + 1] = 0;
    }
    return bad;
}

static void ale_guard(fem_ale *A, const fem_mesh *mesh, const double *u, double *delta)
{
    for (int pass = 0; pass < 100; pass++) {
        int bad = 0;
        for (long i = 0; i < A->nn; i++)
            for (long k = A->ne_ptr[i]; A->zone_n[i] && k < A->ne_ptr[i + 1]; k++)
                if (A->ne[k] >= 0 && (delta[2 * i] != 0 || delta[2 * i + 1] != 0))
                    bad |= ale_reject(A, mesh, A->ne[k], u, delta);
        if (!bad)
            return;
    }
}

long fem_ale_smooth(fem_ale *A, const fem_mesh *mesh, const double *u, double *delta)
{
    memset(delta, 0, (size_t)(2 * A->nn) * sizeof *delta);
    ale_zone(A, mesh, u);
    for (long i = 0; i < A->nn; i++) { /* the shortest current edge at each zone node */
        A->hmin[i] = INFINITY;
        for (long k = A->nb_ptr[i]; k < A->nb_ptr[i + 1] && A->zone_n[i]; k++) {
            const long j = A->nb[k];
            A->hmin[i] = fmin(A->hmin[i], hypot(mesh->r[j] + u[2 * j] - mesh->r[i] - u[2 * i],
                                                mesh->z[j] + u[2 * j + 1] - mesh->z[i] - u[2 * i + 1]));
        }
    }
    const double omega = 0.8;
    for (int s = 0; s < A->p.sweeps; s++)
        for (long i = 0; i < A->nn; i++) {
            if (!A->zone_n[i])
                continue;
            double t[2];
            affine_target(A, mesh, i, u, delta, t);
            for (int c = A->move[i] == 2 ? 1 : 0; c < 2; c++)
                delta[2 * i + c] += omega * (t[c] - u[2 * i + c] - delta[2 * i + c]);
        }
    for (long i = 0; i < A->nn; i++) { /* at most 0.3 of the shortest edge per rezone */
        const double m = hypot(delta[2 * i], delta[2 * i + 1]), cap = 0.3 * A->hmin[i];
        if (A->zone_n[i] && m > cap)
            delta[2 * i] *= cap / m, delta[2 * i + 1] *= cap / m;
    }
    ale_guard(A, mesh, u, delta);
    long moved = 0;
    for (long i = 0; i < A->nn; i++)
        moved += delta[2 * i] != 0 || delta[2 * i + 1] != 0;
    return moved;
}

/* pi * integral of r^2 dz along the straight segment a -> b: the axisymmetric
 * volume enclosed by a counter-clockwise loop is the sum over its segments. */
static double seg(double ra, double za, double rb, double zb)
{
    return RF_PI * (zb - za) * (ra * ra + ra * rb + rb * rb) / 3;
}

static int moved_node(const double *delta, int n)
{
    return delta[2 * n] != 0 || delta[2 * n + 1] != 0;
}

/* The volume element e gains across its edge a as the mesh moves from x = X + u
 * to x + delta: minus the loop p -> q -> q' -> p' (exact, and the gains of an
 * element sum to its change of volume exactly: the node paths cancel). */
static double swept(const fem_mesh *mesh, long e, int a, const double *u, const double *delta)
{
    double r0[4], z0[4], r1[4], z1[4];
    element_xy(mesh, e, u, NULL, r0, z0);
    element_xy(mesh, e, u, delta, r1, z1);
    const int p = a, q = (a + 1) % 4;
    return seg(r1[p], z1[p], r1[q], z1[q]) - seg(r0[p], z0[p], r0[q], z0[q]) + seg(r0[p], z0[p], r1[p], z1[p]) -
           seg(r0[q], z0[q], r1[q], z1[q]);
}

/* Swept volumes of the faces of every element with a moved node; the
 * largest outflow of an element over its volume (donor-cell bound). */
static double ale_swept(fem_ale *A, const fem_mesh *mesh, const double *u, const double *delta)
{
    double worst = 0;
    for (long le = 0; le < A->e1 - A->e0; le++) {
        const long e = A->e0 + le;
        const int *c = mesh->conn + 4 * e;
        A->slot[le] = -1;
        if (!(moved_node(delta, c[0]) || moved_node(delta, c[1]) || moved_node(delta, c[2]) || moved_node(delta, c[3])))
            continue;
        A->slot[le] = 0;
        double r[4], z[4], out = 0, vol = 0;
        element_xy(mesh, e, u, NULL, r, z);
        for (int a = 0; a < 4; a++) {
            A->swept[4 * le + a] = c[a] == c[(a + 1) % 4] ? 0 : swept(mesh, e, a, u, delta);
            out += fmax(-A->swept[4 * le + a], 0);
            vol += seg(r[a], z[a], r[(a + 1) % 4], z[(a + 1) % 4]);
        }
        worst = fmax(worst, vol > 0 ? out / vol : INFINITY);
    }
    return worst;
}

/* The fields of point p: the committed stress, strain, then state. */
static double *field(const fem_points_view *v, size_t p, int k)
{
    const int nc = v->nc;
    return k < nc ? v->sig + (size_t)nc * p + k : k < 2 * nc ? v->eps + (size_t)nc * p + (k - nc)
                                                             : v->var + (size_t)v->law->nstate * p + (k - 2 * nc);
}

static double points_energy(const fem_points_view *v, long le, const double *w)
{
    const fem_point_law *L = v->use2 && v->use2[le] ? v->law2 : v->law;
    double E = 0;
    for (int q = 0; q < v->nq && L->energy; q++)
        E += w[q] * L->energy(L->params, v->sig + (size_t)v->nc * ((size_t)v->nq * (size_t)le + (size_t)q));
    return E;
}

/* Element means of the fields (old weights) of the elements with a slot. */
static rf_status ale_means(fem_ale *A, const fem_points_view *v, int nf, rf_error *err)
{
    long n = 0;
    for (long le = 0; le < A->e1 - A->e0; le++)
        if (A->slot[le] >= 0)
            A->slot[le] = n++;
    if (n > A->nmean) {
        free(A->mean);
        if (!(A->mean = malloc((size_t)n * (size_t)(nf + 1) * sizeof *A->mean)))
            return A->nmean = 0, rf_fail(err, RF_ENOMEM, "fem ale: out of memory");
        A->nmean = n;
    }
    for (long le = 0; le < A->e1 - A->e0; le++) {
        if (A->slot[le] < 0)
            continue;
        double *m = A->mean + (size_t)A->slot[le] * (size_t)(nf + 1), V = 0;
        for (int q = 0; q < v->nq; q++)
            V += v->w[v->nq * le + q];
        for (int k = 0; k < nf; k++) {
            double s = 0;
            for (int q = 0; q < v->nq; q++)
                s += v->w[v->nq * le + q] * *field(v, (size_t)(v->nq * le + q), k);
            m[k] = s / V;
        }
        m[nf] = V;
    }
    return RF_OK;
}

rf_status fem_ale_remap_points(fem_ale *A, const fem_mesh *mesh, const double *u, const double *delta, fem_kernel *k,
                               double *elastic, rf_error *err)
{
    fem_points_view v;
    double *ue_c;
    *elastic = 0;
    if (!fem_kernel_points_axi_ale(k, &v, &ue_c) || k->first != A->e0 || k->count != A->e1 - A->e0 || v.nq != 4)
        return rf_fail(err, RF_EINVAL, "fem ale: the remap needs the slope's updated Lagrangian point kernel");
    ale_swept(A, mesh, u, delta);
    const int nf = 2 * v.nc + v.law->nstate;
    rf_status st = ale_means(A, &v, nf, err);
    if (st != RF_OK)
        return st;
    for (long le = 0; le < A->e1 - A->e0; le++) {
        if (A->slot[le] < 0)
            continue;
        const long e = A->e0 + le;
        double r[4], z[4], B[4][32], *w1 = A->w1 + 4 * le, V1 = 0;
        element_xy(mesh, e, u, delta, r, z);
        fem_element_points(r, z, B, w1);
        for (int q = 0; q < 4; q++)
            V1 += w1[q];
        const double *m = A->mean + (size_t)A->slot[le] * (size_t)(nf + 1);
        *elastic -= points_energy(&v, le, v.w + 4 * le);
        for (int f = 0; f < nf; f++) {
            double total = m[f] * m[nf], now = 0;
            for (int a = 0; a < 4; a++) {
                const double s = A->swept[4 * le + a];
                const long o = A->face[4 * le + a];
                const double *donor = s > 0 && o >= 0 && A->slot[o - A->e0] >= 0
                                          ? A->mean + (size_t)A->slot[o - A->e0] * (size_t)(nf + 1)
                                          : m;
                total += s * donor[f];
            }
            for (int q = 0; q < 4; q++)
                now += w1[q] * *field(&v, (size_t)(4 * le + q), f);
            const double shift = (total - now) / V1;
            for (int q = 0; q < 4; q++)
                *field(&v, (size_t)(4 * le + q), f) += shift;
        }
        *elastic += points_energy(&v, le, w1);
        const int *c = mesh->conn + 4 * e;
        for (int a = 0; a < 4; a++)
            ue_c[8 * le + 2 * a] += delta[2 * c[a]], ue_c[8 * le + 2 * a + 1] += delta[2 * c[a] + 1];
    }
    return RF_OK;
}

/* Bilinear coordinates (xi, eta) of the point (pr, pz) in the quad (r, z) by
 * Newton; returns how far outside [-1, 1]^2 they lie (0 inside). */
static double inverse_bilinear(const double r[4], const double z[4], double pr, double pz, double N[4])
{
    static const double XI[4] = {-1, 1, 1, -1}, ETA[4] = {-1, -1, 1, 1};
    double xi = 0, eta = 0;
    for (int it = 0; it < 30; it++) {
        double fr = -pr, fz = -pz, a = 0, b = 0, c = 0, d = 0;
        for (int k = 0; k < 4; k++) {
            const double n = 0.25 * (1 + XI[k] * xi) * (1 + ETA[k] * eta);
            const double nx = 0.25 * XI[k] * (1 + ETA[k] * eta), ne = 0.25 * ETA[k] * (1 + XI[k] * xi);
            fr += n * r[k], fz += n * z[k];
            a += nx * r[k], b += ne * r[k], c += nx * z[k], d += ne * z[k];
        }
        const double det = a * d - b * c;
        if (!(fabs(det) > 0))
            break;
        const double dx = (d * fr - b * fz) / det, de = (a * fz - c * fr) / det;
        xi -= dx, eta -= de;
        if (fabs(dx) + fabs(de) < 1e-14)
            break;
    }
    for (int k = 0; k < 4; k++)
        N[k] = 0.25 * (1 + XI[k] * xi) * (1 + ETA[k] * eta);
    const double out = fmax(fabs(xi), fabs(eta)) - 1;
    return isfinite(out) ? fmax(out, 0) : INFINITY;
}

double fem_ale_remap_velocity(fem_ale *A, const fem_mesh *mesh, const double *u, const double *delta,
                              const double *mass, const double *invm, double *v)
{
    double *vn = A->vnew, dpz = 0, msum = 0, dke = 0;
    for (long i = 0; i < A->nn; i++) { /* the old field at the new place (all read before any is written) */
        if (!moved_node(delta, (int)i))
            continue;
        const double pr = mesh->r[i] + u[2 * i] + delta[2 * i], pz = mesh->z[i] + u[2 * i + 1] + delta[2 * i + 1];
        double best = INFINITY;
        vn[2 * i] = v[2 * i], vn[2 * i + 1] = v[2 * i + 1];
        for (long p = A->ne_ptr[i]; p < A->ne_ptr[i + 1]; p++) { /* the element around i that holds it */
            if (A->ne[p] < 0)
                continue;
            double r[4], z[4], N[4];
            element_xy(mesh, A->ne[p], u, NULL, r, z);
            const double out = inverse_bilinear(r, z, pr, pz, N);
            if (!(out < best))
                continue;
            best = out, vn[2 * i] = vn[2 * i + 1] = 0;
            const int *c = mesh->conn + 4 * A->ne[p];
            for (int a = 0; a < 4; a++)
                vn[2 * i] += N[a] * v[2 * c[a]], vn[2 * i + 1] += N[a] * v[2 * c[a] + 1];
        }
        if (!(invm[2 * i] > 0)) /* on the axis: v_r = 0 */
            vn[2 * i] = v[2 * i];
    }
    for (long i = 0; i < A->nn; i++) { /* write back; the z momentum change */
        if (!moved_node(delta, (int)i))
            continue;
        const double m = mass[2 * i + 1];
        dke -= 0.5 * m * (v[2 * i] * v[2 * i] + v[2 * i + 1] * v[2 * i + 1]);
        dpz += m * (vn[2 * i + 1] - v[2 * i + 1]), msum += m;
        v[2 * i] = vn[2 * i], v[2 * i + 1] = vn[2 * i + 1];
    }
    for (long i = 0; i < A->nn; i++) { /* the z momentum restored: one shift of the moved nodes' v_z */
        if (!moved_node(delta, (int)i))
            continue;
        v[2 * i + 1] -= dpz / msum;
        dke += 0.5 * mass[2 * i + 1] * (v[2 * i] * v[2 * i] + v[2 * i + 1] * v[2 * i + 1]);
    }
    return dke;
}

long fem_ale_rezone(fem_ale *A, const fem_mesh *mesh, double *u, double *v, const double *mass,
                    const double *invm, const double *fgrav, fem_kernel *k, double *delta, fem_ale_account *acc,
                    rf_error *err)
{
    const double ratio = fem_ale_ratio_min(A, mesh, u);
    if (!(ratio < A->p.trigger))
        return 0;
    acc->ratio_min = acc->rezones == 0 ? ratio : fmin(acc->ratio_min, ratio);
    long moved = fem_ale_smooth(A, mesh, u, delta);
    if (moved == 0)
        return 0;
    for (int h = 0; h < 20 && ale_swept(A, mesh, u, delta) > 0.5; h++) /* donor cell: outflow < half the volume */
        for (long d = 0; d < 2 * A->nn; d++)
            delta[d] *= 0.5;
    double elastic, dpot = 0;
    if (fem_ale_remap_points(A, mesh, u, delta, k, &elastic, err) != RF_OK)
        return -1;
    const double dke = fem_ale_remap_velocity(A, mesh, u, delta, mass, invm, v);
    for (long i = 0; i < A->nn; i++) {
        if (!moved_node(delta, (int)i))
            continue;
        if (fgrav) /* the potential energy of the moved masses: - (gravity load) . delta */
            dpot -= fgrav[2 * i] * delta[2 * i] + fgrav[2 * i + 1] * delta[2 * i + 1];
        acc->move_max = fmax(acc->move_max, hypot(delta[2 * i], delta[2 * i + 1]));
        u[2 * i] += delta[2 * i], u[2 * i + 1] += delta[2 * i + 1];
    }
    acc->rezones++, acc->nodes_moved += moved;
    acc->kinetic += dke, acc->elastic += elastic, acc->potential += dpot;
    return moved;
}
