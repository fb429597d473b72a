/* fem_vtk.c - ParaView output of the impact: one binary XML .vtu per frame
 * (UnstructuredGrid, every array in one appended raw block after the XML
 * header, each preceded by its byte count as UInt64: the layout VTK 9 and
 * ParaView read; no compression), and a .pvd time index.  The axisymmetric
 * frame: points in the (r, z) plane as x, y; point data displacement and
 * velocity; cell data stress components, equivalent plastic strain and body
 * id.  Points, displacement and velocity are Float64 (the solver's values,
 * bit for bit); the cell stresses and plastic strains Float32 (7 digits, as
 * the earlier ASCII files had them).  The 3D frame is fem3d_vtk.c's,
 * through the same writer. */
#include "fem_internal.h"
#include "fem_kernel.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

_Static_assert(sizeof(int) == 4, "the connectivity is written as Int32");

static const char *byte_order(void)
{
    const uint16_t one = 1;
    unsigned char b;
    memcpy(&b, &one, 1);
    return b ? "LittleEndian" : "BigEndian";
}

/* The XML of one array with its offset into the appended block (advanced). */
static void array_header(FILE *fp, const fem_vtk_array *a, uint64_t *offset)
{
    fprintf(fp, "<DataArray type=\"%s\" Name=\"%s\" NumberOfComponents=\"%d\" format=\"appended\" "
                "offset=\"%llu\"/>\n", a->type, a->name, a->ncomp, (unsigned long long)*offset);
    *offset += sizeof(uint64_t) + (uint64_t)a->count * a->size;
}

static void array_data(FILE *fp, const fem_vtk_array *a)
{
    const uint64_t bytes = (uint64_t)a->count * a->size;
    fwrite(&bytes, sizeof bytes, 1, fp);
    if (bytes)
        fwrite(a->data, a->size, a->count, fp);
}

rf_status fem_vtk_write(const char *path, double t, const fem_vtk_grid *g, rf_error *err)
{
    FILE *fp = fopen(path, "wb");
    if (!fp)
        return rf_fail(err, RF_EIO, "fem vtk: cannot write %s: %s", path, strerror(errno));
    fprintf(fp, "<?xml version=\"1.0\"?>\n<!-- t = %.17g s -->\n"
                "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"%s\" header_type=\"UInt64\">\n"
                "<UnstructuredGrid>\n<Piece NumberOfPoints=\"%ld\" NumberOfCells=\"%ld\">\n",
            t, byte_order(), g->n_points, g->n_cells);
    uint64_t off = 0;
    fputs("<Points>\n", fp);
    array_header(fp, &g->points, &off);
    fputs("</Points>\n<Cells>\n", fp);
    for (int k = 0; k < 3; k++)
        array_header(fp, &g->cells[k], &off);
    fprintf(fp, "</Cells>\n<PointData Vectors=\"%s\">\n", g->n_point_data ? g->point_data[0].name : "");
    for (int k = 0; k < g->n_point_data; k++)
        array_header(fp, &g->point_data[k], &off);
    fputs("</PointData>\n<CellData>\n", fp);
    for (int k = 0; k < g->n_cell_data; k++)
        array_header(fp, &g->cell_data[k], &off);
    fputs("</CellData>\n</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_", fp);
    array_data(fp, &g->points);
    for (int k = 0; k < 3; k++)
        array_data(fp, &g->cells[k]);
    for (int k = 0; k < g->n_point_data; k++)
        array_data(fp, &g->point_data[k]);
    for (int k = 0; k < g->n_cell_data; k++)
        array_data(fp, &g->cell_data[k]);
    fputs("\n</AppendedData>\n</VTKFile>\n", fp);
    const int bad = ferror(fp);
    if (fclose(fp) != 0 || bad)
        return rf_fail(err, RF_EIO, "fem vtk: error writing %s", path);
    return RF_OK;
}

/* Connectivity, offsets and cell types of n elements of k nodes (VTK type vtk_type). */
rf_status fem_vtk_cells(fem_vtk_grid *g, const int *conn, long n, int k, unsigned char vtk_type, rf_error *err)
{
    int32_t *off = malloc((size_t)(n > 0 ? n : 1) * sizeof *off);
    unsigned char *types = malloc((size_t)(n > 0 ? n : 1));
    if (!off || !types) {
        free(off), free(types);
        return rf_fail(err, RF_ENOMEM, "fem vtk: out of memory");
    }
    for (long e = 0; e < n; e++)
        off[e] = (int32_t)(k * (e + 1)), types[e] = vtk_type;
    g->cells[0] = (fem_vtk_array){"connectivity", "Int32", 1, conn, (size_t)(k * n), sizeof(int32_t)};
    g->cells[1] = (fem_vtk_array){"offsets", "Int32", 1, off, (size_t)n, sizeof(int32_t)};
    g->cells[2] = (fem_vtk_array){"types", "UInt8", 1, types, (size_t)n, 1};
    g->owned[0] = off, g->owned[1] = types;
    return RF_OK;
}

void fem_vtk_grid_free(fem_vtk_grid *g)
{
    for (size_t k = 0; k < sizeof g->owned / sizeof g->owned[0]; k++)
        free(g->owned[k]);
    memset(g, 0, sizeof *g);
}

/* Nodal (r, z) pairs as 3-vectors (r, z, 0). */
static double *planar_to_3d(const double *a, const double *b, long n)
{
    double *p = malloc((size_t)(n > 0 ? n : 1) * 3 * sizeof *p);
    for (long i = 0; p && i < n; i++)
        p[3 * i] = b ? a[i] : a[2 * i], p[3 * i + 1] = b ? b[i] : a[2 * i + 1], p[3 * i + 2] = 0;
    return p;
}

/* Cell data of the axisymmetric frame: sigma_rr, sigma_zz, sigma_tt, sigma_rz, plastic strain (5 x n),
 * as Float32. */
static float *axi_cell_stress(const fem_mesh *mesh, const double *u, const fem_material mat[2],
                              const fem_kernel *kernel)
{
    const long n = mesh->n_elems;
    float *s = malloc((size_t)(n > 0 ? n : 1) * 5 * sizeof *s);
    for (long e = 0; s && e < n; e++) {
        const int *c = mesh->conn + 4 * e;
        double r[4], z[4], ue[8], se[5] = {0, 0, 0, 0, 0};
        if (!kernel || !fem_kernel_cell_state(&kernel[mesh->ebody[e]], e, se, &se[4])) {
            for (int a = 0; a < 4; a++) {
                r[a] = mesh->r[c[a]], z[a] = mesh->z[c[a]];
                ue[2 * a] = u[2 * c[a]], ue[2 * a + 1] = u[2 * c[a] + 1];
            }
            fem_element_stress(r, z, &mat[mesh->ebody[e]], ue, se);
        }
        for (int k = 0; k < 5; k++)
            s[k * n + e] = (float)se[k];
    }
    return s;
}

rf_status fem_vtk_frame(const char *dir, int frame, double t, const fem_mesh *mesh, const double *u,
                        const double *v, const fem_material mat[2], const fem_kernel *kernel, rf_error *err)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/fem_%04d.vtu", dir, frame);
    fem_vtk_grid g = {0};
    const long nn = mesh->n_nodes, ne = mesh->n_elems;
    double *pts = g.owned[2] = planar_to_3d(mesh->r, mesh->z, nn);
    double *u3 = g.owned[3] = planar_to_3d(u, NULL, nn), *v3 = g.owned[4] = planar_to_3d(v, NULL, nn);
    float *s = g.owned[5] = axi_cell_stress(mesh, u, mat, kernel);
    unsigned char *body = g.owned[6] = malloc((size_t)(ne > 0 ? ne : 1));
    rf_status st = pts && u3 && v3 && s && body ? fem_vtk_cells(&g, mesh->conn, ne, 4, 9, err)
                                                : rf_fail(err, RF_ENOMEM, "fem vtk: out of memory");
    if (st == RF_OK) {
        static const char *const sn[5] = {"sigma_rr", "sigma_zz", "sigma_tt", "sigma_rz", "equivalent_plastic_strain"};
        for (long e = 0; e < ne; e++)
            body[e] = (unsigned char)mesh->ebody[e];
        g.n_points = nn, g.n_cells = ne;
        g.points = (fem_vtk_array){"Points", "Float64", 3, pts, (size_t)(3 * nn), sizeof(double)};
        g.point_data[0] = (fem_vtk_array){"displacement", "Float64", 3, u3, (size_t)(3 * nn), sizeof(double)};
        g.point_data[1] = (fem_vtk_array){"velocity", "Float64", 3, v3, (size_t)(3 * nn), sizeof(double)};
        g.n_point_data = 2;
        for (int k = 0; k < 5; k++)
            g.cell_data[k] = (fem_vtk_array){sn[k], "Float32", 1, s + k * ne, (size_t)ne, sizeof(float)};
        g.cell_data[5] = (fem_vtk_array){"body", "UInt8", 1, body, (size_t)ne, 1};
        g.n_cell_data = 6;
        st = fem_vtk_write(path, t, &g, err);
    }
    fem_vtk_grid_free(&g);
    return st;
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
