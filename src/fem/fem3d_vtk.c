/* fem3d_vtk.c - ParaView output of the 3D impact (the half model as it is
 * meshed, slope frame: x down-slope, z the outward slope normal): one binary
 * .vtu per frame (fem_vtk_write: appended raw arrays) with 8-node hexahedra
 * (VTK type 12, the same node order), point data displacement and velocity, cell data the six stress components
 * (mean over the Gauss points: the committed stresses of an integration-point
 * kernel, else linear elasticity of the displacement, the boulder's in its
 * co-rotated frame), the equivalent plastic strain and the body id; the .pvd
 * time index is the axisymmetric writer's (fem_vtk_index). */
#include "fem3d_internal.h"
#include "fem_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Mean linear-elastic stress over the element's Gauss points (xx yy zz xy yz zx). */
static void elastic_cell_stress(const f3_mesh *mesh, long e, const double *u, const f3_material *m, double s[6])
{
    const int *cn = mesh->conn + 8 * e;
    double xe[24], dN[8][8][3], w[8], W = 0, H[3][3] = {{0}};
    for (int a = 0; a < 8; a++)
        for (int c = 0; c < 3; c++)
            xe[3 * a + c] = mesh->x[3 * (long)cn[a] + c];
    f3_hex_gradients(xe, dN, w);
    for (int q = 0; q < 8; q++) { /* the mean gradient: the stress is linear in it */
        W += w[q];
        for (int a = 0; a < 8; a++)
            for (int c = 0; c < 3; c++)
                for (int j = 0; j < 3; j++)
                    H[c][j] += w[q] * u[3 * (long)cn[a] + c] * dN[q][a][j];
    }
    const double lam = m->E * m->nu / ((1 + m->nu) * (1 - 2 * m->nu)), mu = m->E / (2 * (1 + m->nu));
    const double tr = (H[0][0] + H[1][1] + H[2][2]) / W;
    for (int i = 0; i < 3; i++)
        s[i] = lam * tr + 2 * mu * H[i][i] / W;
    s[3] = mu * (H[0][1] + H[1][0]) / W, s[4] = mu * (H[1][2] + H[2][1]) / W, s[5] = mu * (H[2][0] + H[0][2]) / W;
}

/* Cell data: the six stresses and the plastic strain (7 x n_elems, Float32 as in fem_vtk.c), and the body ids. */
static void cell_state(const f3_system *S, const double *u, const f3_material mat[2], float *s, unsigned char *body)
{
    const f3_mesh *mesh = S->mesh;
    const long n = mesh->n_elems;
    for (long e = 0; e < n; e++) {
        const int b = e < mesh->boulder_elems ? F3_BOULDER : F3_SLOPE;
        double se[7] = {0, 0, 0, 0, 0, 0, 0};
        if (!fem_kernel_points_hex_cell(&S->kernel[b], e, se, &se[6]))
            elastic_cell_stress(mesh, e, b == F3_BOULDER ? S->ub : u, &mat[b], se);
        for (int k = 0; k < 7; k++)
            s[k * n + e] = (float)se[k];
        body[e] = (unsigned char)b;
    }
}

rf_status f3_vtk_frame(const char *dir, int frame, double t, const f3_system *S, const double *u, const double *v,
                       const f3_material mat[2], rf_error *err)
{
    static const char *const sn[7] = {"sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy", "sigma_yz", "sigma_zx",
                                      "equivalent_plastic_strain"};
    char path[4096];
    snprintf(path, sizeof path, "%s/fem_%04d.vtu", dir, frame);
    const f3_mesh *mesh = S->mesh;
    const long nn = mesh->n_nodes, ne = mesh->n_elems;
    fem_vtk_grid g = {0};
    float *s = g.owned[2] = malloc((size_t)(ne > 0 ? ne : 1) * 7 * sizeof *s);
    unsigned char *body = g.owned[3] = malloc((size_t)(ne > 0 ? ne : 1));
    rf_status st = s && body ? fem_vtk_cells(&g, mesh->conn, ne, 8, 12, err)
                             : rf_fail(err, RF_ENOMEM, "fem3d vtk: out of memory");
    if (st == RF_OK) {
        cell_state(S, u, mat, s, body);
        g.n_points = nn, g.n_cells = ne;
        g.points = (fem_vtk_array){"Points", "Float64", 3, mesh->x, (size_t)(3 * nn), sizeof(double)};
        g.point_data[0] = (fem_vtk_array){"displacement", "Float64", 3, u, (size_t)(3 * nn), sizeof(double)};
        g.point_data[1] = (fem_vtk_array){"velocity", "Float64", 3, v, (size_t)(3 * nn), sizeof(double)};
        g.n_point_data = 2;
        for (int k = 0; k < 7; k++)
            g.cell_data[k] = (fem_vtk_array){sn[k], "Float32", 1, s + k * ne, (size_t)ne, sizeof(float)};
        g.cell_data[7] = (fem_vtk_array){"body", "UInt8", 1, body, (size_t)ne, 1};
        g.n_cell_data = 8;
        st = fem_vtk_write(path, t, &g, err);
    }
    fem_vtk_grid_free(&g);
    return st;
}
