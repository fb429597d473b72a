/* fem3d_vtk.c - ParaView output of the 3D impact (the half model as it is
 * meshed, slope frame: x down-slope, z the outward slope normal): one ASCII
 * .vtu per frame with 8-node hexahedra (VTK type 12, the same node order),
 * point data displacement and velocity, cell data the six stress components
 * (mean over the Gauss points: the committed stresses of an integration-point
 * kernel, else linear elasticity of the displacement, the boulder's in its
 * co-rotated frame), the equivalent plastic strain and the body id; the .pvd
 * time index is the axisymmetric writer's (fem_vtk_index). */
#include "fem3d_internal.h"
#include "fem_internal.h"

#include <errno.h>
#include <stdio.h>
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

static void write_points(FILE *fp, const f3_mesh *mesh)
{
    fprintf(fp, "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for (long i = 0; i < mesh->n_nodes; i++)
        fprintf(fp, "%.9g %.9g %.9g\n", mesh->x[3 * i], mesh->x[3 * i + 1], mesh->x[3 * i + 2]);
    fprintf(fp, "</DataArray>\n</Points>\n<Cells>\n"
                "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
    for (long e = 0; e < mesh->n_elems; e++) {
        const int *c = mesh->conn + 8 * e;
        fprintf(fp, "%d %d %d %d %d %d %d %d\n", c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]);
    }
    fprintf(fp, "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n");
    for (long e = 0; e < mesh->n_elems; e++)
        fprintf(fp, "%ld\n", 8 * (e + 1));
    fprintf(fp, "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for (long e = 0; e < mesh->n_elems; e++)
        fprintf(fp, "12\n");
    fprintf(fp, "</DataArray>\n</Cells>\n");
}

static void write_cells(FILE *fp, const f3_system *S, const double *u, const f3_material mat[2])
{
    const f3_mesh *mesh = S->mesh;
    static const char *const sn[7] = {"sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy", "sigma_yz", "sigma_zx",
                                      "equivalent_plastic_strain"};
    fprintf(fp, "<CellData>\n");
    for (int k = 0; k < 7; k++) {
        fprintf(fp, "<DataArray type=\"Float64\" Name=\"%s\" format=\"ascii\">\n", sn[k]);
        for (long e = 0; e < mesh->n_elems; e++) {
            const int b = e < mesh->boulder_elems ? F3_BOULDER : F3_SLOPE;
            double s[7] = {0, 0, 0, 0, 0, 0, 0};
            if (!fem_kernel_points_hex_cell(&S->kernel[b], e, s, &s[6]))
                elastic_cell_stress(mesh, e, b == F3_BOULDER ? S->ub : u, &mat[b], s);
            fprintf(fp, "%.7g\n", s[k]);
        }
        fprintf(fp, "</DataArray>\n");
    }
    fprintf(fp, "<DataArray type=\"UInt8\" Name=\"body\" format=\"ascii\">\n");
    for (long e = 0; e < mesh->n_elems; e++)
        fprintf(fp, "%d\n", e < mesh->boulder_elems ? F3_BOULDER : F3_SLOPE);
    fprintf(fp, "</DataArray>\n</CellData>\n");
}

rf_status f3_vtk_frame(const char *dir, int frame, double t, const f3_system *S, const double *u, const double *v,
                       const f3_material mat[2], rf_error *err)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/fem_%04d.vtu", dir, frame);
    FILE *fp = fopen(path, "w");
    if (!fp)
        return rf_fail(err, RF_EIO, "fem3d vtk: cannot write %s: %s", path, strerror(errno));
    const f3_mesh *mesh = S->mesh;
    fprintf(fp, "<?xml version=\"1.0\"?>\n<!-- t = %.9g s -->\n"
                "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                "<UnstructuredGrid>\n<Piece NumberOfPoints=\"%ld\" NumberOfCells=\"%ld\">\n",
            t, mesh->n_nodes, mesh->n_elems);
    write_points(fp, mesh);
    fprintf(fp, "<PointData Vectors=\"displacement\">\n");
    const double *arr[2] = {u, v};
    static const char *const names[2] = {"displacement", "velocity"};
    for (int k = 0; k < 2; k++) {
        fprintf(fp, "<DataArray type=\"Float64\" Name=\"%s\" NumberOfComponents=\"3\" format=\"ascii\">\n",
                names[k]);
        for (long i = 0; i < mesh->n_nodes; i++)
            fprintf(fp, "%.9g %.9g %.9g\n", arr[k][3 * i], arr[k][3 * i + 1], arr[k][3 * i + 2]);
        fprintf(fp, "</DataArray>\n");
    }
    fprintf(fp, "</PointData>\n");
    write_cells(fp, S, u, mat);
    fprintf(fp, "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    if (fclose(fp) != 0)
        return rf_fail(err, RF_EIO, "fem3d vtk: error writing %s", path);
    return RF_OK;
}
