/* fem_vtk.c - ParaView output of the impact: one ASCII .vtu per frame
 * (points in the (r, z) plane as x, y; point data displacement and velocity;
 * cell data stress components, equivalent plastic strain and body id) and a
 * .pvd time index. */
#include "fem_internal.h"
#include "fem_kernel.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

rf_status fem_vtk_frame(const char *dir, int frame, double t, const fem_mesh *mesh, const double *u,
                        const double *v, const fem_material mat[2], const fem_kernel *kernel, rf_error *err)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/fem_%04d.vtu", dir, frame);
    FILE *fp = fopen(path, "w");
    if (!fp)
        return rf_fail(err, RF_EIO, "fem vtk: cannot write %s: %s", path, strerror(errno));
    fprintf(fp, "<?xml version=\"1.0\"?>\n<!-- t = %.9g s -->\n"
                "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                "<UnstructuredGrid>\n<Piece NumberOfPoints=\"%ld\" NumberOfCells=\"%ld\">\n",
            t, mesh->n_nodes, mesh->n_elems);
    fprintf(fp, "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for (long i = 0; i < mesh->n_nodes; i++)
        fprintf(fp, "%.9g %.9g 0\n", mesh->r[i], mesh->z[i]);
    fprintf(fp, "</DataArray>\n</Points>\n<Cells>\n"
                "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
    for (long e = 0; e < mesh->n_elems; e++) {
        const int *c = mesh->conn + 4 * e;
        fprintf(fp, "%d %d %d %d\n", c[0], c[1], c[2], c[3]);
    }
    fprintf(fp, "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n");
    for (long e = 0; e < mesh->n_elems; e++)
        fprintf(fp, "%ld\n", 4 * (e + 1));
    fprintf(fp, "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for (long e = 0; e < mesh->n_elems; e++)
        fprintf(fp, "9\n");
    fprintf(fp, "</DataArray>\n</Cells>\n<PointData Vectors=\"displacement\">\n");
    const double *arr[2] = {u, v};
    const char *names[2] = {"displacement", "velocity"};
    for (int k = 0; k < 2; k++) {
        fprintf(fp, "<DataArray type=\"Float64\" Name=\"%s\" NumberOfComponents=\"3\" format=\"ascii\">\n",
                names[k]);
        for (long i = 0; i < mesh->n_nodes; i++)
            fprintf(fp, "%.9g %.9g 0\n", arr[k][2 * i], arr[k][2 * i + 1]);
        fprintf(fp, "</DataArray>\n");
    }
    fprintf(fp, "</PointData>\n<CellData>\n");
    const char *sn[5] = {"sigma_rr", "sigma_zz", "sigma_tt", "sigma_rz", "equivalent_plastic_strain"};
    for (int k = 0; k < 5; k++) {
        fprintf(fp, "<DataArray type=\"Float64\" Name=\"%s\" format=\"ascii\">\n", sn[k]);
        for (long e = 0; e < mesh->n_elems; e++) {
            const int *c = mesh->conn + 4 * e;
            double r[4], z[4], ue[8], s[5] = {0, 0, 0, 0, 0};
            if (!kernel || !fem_kernel_cell_state(&kernel[mesh->ebody[e]], e, s, &s[4])) {
                for (int a = 0; a < 4; a++) {
                    r[a] = mesh->r[c[a]], z[a] = mesh->z[c[a]];
                    ue[2 * a] = u[2 * c[a]], ue[2 * a + 1] = u[2 * c[a] + 1];
                }
                fem_element_stress(r, z, &mat[mesh->ebody[e]], ue, s);
            }
            fprintf(fp, "%.7g\n", s[k]);
        }
        fprintf(fp, "</DataArray>\n");
    }
    fprintf(fp, "<DataArray type=\"UInt8\" Name=\"body\" format=\"ascii\">\n");
    for (long e = 0; e < mesh->n_elems; e++)
        fprintf(fp, "%d\n", mesh->ebody[e]);
    fprintf(fp, "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    if (fclose(fp) != 0)
        return rf_fail(err, RF_EIO, "fem vtk: error writing %s", path);
    return RF_OK;
}

rf_status fem_vtk_index(const char *dir, int frames, const double *times, rf_error *err)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/fem.pvd", dir);
    FILE *fp = fopen(path, "w");
    if (!fp)
        return rf_fail(err, RF_EIO, "fem vtk: cannot write %s: %s", path, strerror(errno));
    fprintf(fp, "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n");
    for (int i = 0; i < frames; i++)
        fprintf(fp, "<DataSet timestep=\"%.9g\" part=\"0\" file=\"fem_%04d.vtu\"/>\n", times[i], i);
    fprintf(fp, "</Collection>\n</VTKFile>\n");
    if (fclose(fp) != 0)
        return rf_fail(err, RF_EIO, "fem vtk: error writing %s", path);
    return RF_OK;
}
