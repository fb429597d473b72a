/* fem_deep_inputs.h - the deep-penetration case shared by tests/test_fem_deep.c
 * (logic, coarse) and tests/test_fem_deep_accuracy.c (energy closure at the
 * mesh that needs): a heavy rigid sphere (r0 = 1 m) at 4 m/s into a soft,
 * gravity-free Drucker-Prager + cap soil; it sinks about 0.6 r0, beyond the
 * 0.5 r0 where the paired boulder surface used to end (section 6e of
 * docs/validation-plastic.md), and the soil climbs its steep sides.  The
 * final VTK frame is read back and every slope node is checked against the
 * sphere. */
#ifndef ROCKFUZZ_FEM_DEEP_INPUTS_H
#define ROCKFUZZ_FEM_DEEP_INPUTS_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fem_tune.h"
#include "rockfuzz/fem.h"
#include "fem/fem_tuning.h"
#include "vtu_reader.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define DEEP_END_TIME 0.36 /* [s] the contact lasts ~0.31 s */

static inline rf_impact_input deep_input(void)
{
    rf_impact_input in;
    rf_impact_input_default(&in);
    in.radius = 1, in.velocity = 4, in.boulder_material = RF_MATERIAL_RIGID_BODY;
    in.boulder_density = 8000; /* heavy: deep at a low speed */
    in.slope_density = 1800, in.slope_E = 200e6, in.slope_poisson = 0.3;
    in.slope_material = RF_MATERIAL_DRUCKER_PRAGER, in.slope_cohesion = 5e3;
    in.slope_friction_angle = 30 * M_PI / 180, in.slope_dilatancy_angle = 0;
    in.slope_cap_pressure = 1e6, in.slope_cap_hardening = 50e6;
    in.gravity = 0;
    return in;
}

/* What the last VTK frame in dir says of the slope nodes against the rigid
 * sphere (centre on the axis, r0 above the origin, where the boulder's
 * lowest point rests in the reference mesh):
 * *overlap the deepest a slope node is inside the sphere [m], *sag the
 * largest sag of a chord of the boulder's lower surface polygon (the
 * inscribed polygon that the contact enforces) [m], *t the frame's time,
 * *sink the boulder's displacement down [m].  Removes the frames. */
static inline int deep_last_frame(const char *dir, long nb, double r0, double *overlap, double *sag, double *t,
                                  double *sink)
{
    char path[512];
    int last = -1;
    for (int i = 0;; i++) {
        snprintf(path, sizeof path, "%s/fem_%04d.vtu", dir, i);
        if (access(path, R_OK) != 0)
            break;
        last = i;
    }
    if (last < 0)
        return -1;
    snprintf(path, sizeof path, "%s/fem_%04d.vtu", dir, last);
    vtu_file f;
    long n = 0;
    int st = -1;
    size_t np = 0, nu = 0;
    int nc = 0;
    double *x = NULL, *du = NULL;
    if (vtu_open(path, &f)) {
        n = f.points;
        sscanf(strstr(f.bytes, "<!-- t = ") ? strstr(f.bytes, "<!-- t = ") + 9 : "0", "%lf", t);
        x = vtu_array(&f, "Points", &np, &nc), du = vtu_array(&f, "displacement", &nu, &nc);
    }
    vtu_close(&f);
    if (n > nb && x && du && np == 3 * (size_t)n && nu == np) {
        const double *u = du;
        double zc = r0 + u[1]; /* the boulder rests on the origin; rigid: one displacement */
        *sink = -u[1];
        *overlap = -HUGE_VAL, *sag = 0;
        for (long i = nb; i < n; i++)
            *overlap = fmax(*overlap, r0 - hypot(x[3 * i] + u[3 * i], x[3 * i + 1] + u[3 * i + 1] - zc));
        /* lower-half surface nodes of the boulder, by angle from the lowest point */
        double ang[4096];
        int k = 0;
        for (long i = 0; i < nb && k < 4096; i++) {
            double dr = x[3 * i], dz = x[3 * i + 1] - r0;
            if (fabs(hypot(dr, dz) - r0) < 1e-6 * r0 && dz <= 0)
                ang[k++] = atan2(dr, -dz);
        }
        for (int a = 1; a < k; a++) /* insertion sort */
            for (int b = a; b > 0 && ang[b] < ang[b - 1]; b--) {
                double tmp = ang[b];
                ang[b] = ang[b - 1], ang[b - 1] = tmp;
            }
        for (int a = 1; a < k; a++)
            *sag = fmax(*sag, r0 * (1 - cos(0.5 * (ang[a] - ang[a - 1]))));
        st = k > 2 ? 0 : -1;
    }
    free(x), free(du);
    for (int i = 0; i <= last; i++) {
        snprintf(path, sizeof path, "%s/fem_%04d.vtu", dir, i);
        unlink(path);
    }
    snprintf(path, sizeof path, "%s/fem.pvd", dir);
    unlink(path);
    rmdir(dir);
    return st;
}

/* The deep case at a refinement (cmocka asserts: include after <cmocka.h>): outputs, and the last frame against the sphere. */
static inline void deep_run(double refinement, rf_impact_output *out, double *overlap, double *sag)
{
    char dir[] = "/tmp/rockfuzz_fem_deepXXXXXX";
    assert_non_null(mkdtemp(dir));
    rf_impact_input in = deep_input();
    rf_fem_options o;
    rf_fem_options_default(&o);
    o.refinement = refinement, o.boundary = RF_FEM_BOUNDARY_FIXED;
    o.end_time = DEEP_END_TIME, o.vtk_dir = dir, TUNE(o).vtk_frames = 12;
    rf_fem_history hist;
    rf_error err = {0};
    if (rf_fem_impact(&in, &o, out, &hist, &err) != RF_OK)
        fail_msg("%s", err.msg);
    double t = 0, sink = 0;
    assert_int_equal(deep_last_frame(dir, hist.boulder_nodes, in.radius, overlap, sag, &t, &sink), 0);
    printf("deep, a/h = %g: penetration %.4f r0 (last frame t = %.3f s: %.4f r0), R_n %.4f, energy error %.2e KE0, "
           "deepest slope node inside the sphere %.2e r0 (polygon sag %.2e r0)\n",
           refinement, out->penetration_max / in.radius, t, sink / in.radius, out->R_n, out->energy_error,
           *overlap / in.radius, *sag / in.radius);
    assert_true(t > 0.85 * DEEP_END_TIME); /* after the contact (~0.31 s) */
    rf_fem_history_free(&hist);
}

#endif
