/* fem_options.c - the settings of the FE solvers: their one default (and the
 * 3D model's own defaults), their one validation (a table of rules, the few
 * that differ in 3D marked), the resolution of the automatic settings
 * (refinement, domain radius), and the choice between the axisymmetric and
 * the 3D model. */
#include "rockfuzz/fem3d.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "core/util.h"

void rf_fem_options_default(rf_fem_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->refinement = 0;     /* automatic: RF_FEM_REFINEMENT_AXI / _3D */
    opt->domain_factor = 0;  /* automatic: no reflection into the contact */
    opt->boundary = RF_FEM_BOUNDARY_AUTO; /* rf_fem_boundary_resolve */
    opt->end_time = 0;
    opt->threads = 1;
    opt->vtk_dir = NULL;
    opt->boulder_mesh_ratio = 1;
    opt->core_factor = 2.5;
    opt->grading = 1.15;
    opt->dt_safety = 0.9;
    opt->surface_mass_kappa = 0.1;
    opt->surface_mass_3d = 1;
    opt->sphere_contact_3d = 1;
    opt->vtk_frames = 60;
    opt->history_stride = 0;
    opt->max_elements = 2000000;
    opt->duration_threshold = 1e-6;
    opt->ale = RF_FEM_ALE_AUTO;
    opt->ale_trigger = 0.5;
    opt->ale_sweeps = 10;
}

void rf_fem3d_options_default(rf_fem3d_options *o3)
{
    memset(o3, 0, sizeof *o3);
    o3->full_model = 0;
    o3->core_factor = 1.3;
    o3->elongation = 1.0;
    o3->layer_aspect = 1.6;
    o3->boulder_inner = 4.0;
}

static const char *const boundary_names[] = {"fixed", "absorbing", "auto"};

const char *rf_fem_boundary_name(rf_fem_boundary b)
{
    return (unsigned)b < 3 ? boundary_names[b] : "unknown";
}

rf_status rf_fem_boundary_parse(const char *name, rf_fem_boundary *b, rf_error *err)
{
    const int k = rf_name_index(name, boundary_names, 3);
    if (k >= 0) {
        *b = (rf_fem_boundary)k;
        return RF_OK;
    }
    return rf_fail(err, RF_EINVAL, "boundary '%s' is unknown (accepted: auto, fixed, absorbing)",
                   name ? name : "(null)");
}

/* A layer or a plastic body makes the contact last many times the P wave's
 * round trip in the automatic domain (sized from the elastic Hertz duration of
 * boulder and bedrock: S5's soil contact 26 ms against 2.5 ms); only the
 * dashpots keep the reflections out of it.  Elastic bodies on the half-space
 * keep the fixed boundary of the seed paper (docs/validation-plastic.md
 * section 10b). */
rf_fem_boundary rf_fem_boundary_resolve(rf_fem_boundary b, const rf_impact_input *in)
{
    if (b != RF_FEM_BOUNDARY_AUTO)
        return b;
    return in->layer_thickness > 0 || rf_impact_has_plastic_body(in) ? RF_FEM_BOUNDARY_ABSORBING
                                                                      : RF_FEM_BOUNDARY_FIXED;
}

static const char *const kinematics_names[] = {"auto", "off", "on"};

const char *rf_fem_kinematics_name(rf_fem_kinematics k)
{
    return (unsigned)k < 3 ? kinematics_names[k] : "unknown";
}

rf_status rf_fem_kinematics_parse(const char *name, rf_fem_kinematics *k, rf_error *err)
{
    const int i = rf_name_index(name, kinematics_names, 3);
    if (i >= 0) {
        *k = (rf_fem_kinematics)i;
        return RF_OK;
    }
    return rf_fail(err, RF_EINVAL, "large_deformation '%s' is unknown (accepted: auto, off, on)",
                   name ? name : "(null)");
}

static const char *const ale_names[] = {"auto", "off", "on"};

const char *rf_fem_ale_name(rf_fem_ale a)
{
    return (unsigned)a < 3 ? ale_names[a] : "unknown";
}

rf_status rf_fem_ale_parse(const char *name, rf_fem_ale *a, rf_error *err)
{
    const int i = rf_name_index(name, ale_names, 3);
    if (i >= 0) {
        *a = (rf_fem_ale)i;
        return RF_OK;
    }
    return rf_fail(err, RF_EINVAL, "ale '%s' is unknown (accepted: auto, off, on)", name ? name : "(null)");
}

static const char *const switch_names[] = {"off", "on"};

rf_status rf_fem_switch_parse(const char *what, const char *name, int *on, rf_error *err)
{
    const int i = rf_name_index(name, switch_names, 2);
    if (i >= 0) {
        *on = i;
        return RF_OK;
    }
    return rf_fail(err, RF_EINVAL, "%s '%s' is unknown (accepted: off, on)", what, name ? name : "(null)");
}

/* auto: off (docs/validation-plastic.md section 8b). */
int rf_fem_ale_enabled(const rf_fem_options *opt, const rf_impact_input *in)
{
    if (!rf_fem_large_deformation(opt, in))
        return 0;
    return opt->ale == RF_FEM_ALE_ON;
}

int rf_fem_large_deformation(const rf_fem_options *opt, const rf_impact_input *in)
{
    if (opt->large_deformation != RF_FEM_KINEMATICS_AUTO)
        return opt->large_deformation == RF_FEM_LARGE_DEFORMATION;
    return rf_impact_has_plastic_body(in);
}

/* Closed ranges of the real-valued settings; lo3/hi3 are the 3D limits. */
static const struct {
    const char *name;
    size_t offset;
    double lo, hi, lo3, hi3;
    int zero_ok; /* 0 means "automatic" */
    const char *why;
} rules[] = {
    {"refinement", offsetof(rf_fem_options, refinement), 2, 400, 2, 100, 1,
     "(Hertz contact radius / element size; 0 = automatic, 10 or more for accuracy)"},
    {"domain_factor", offsetof(rf_fem_options, domain_factor), 3, 1e4, 3, 1e4, 1,
     "(slope hemisphere radius / r0; 0 = automatic)"},
    {"boulder_mesh_ratio", offsetof(rf_fem_options, boulder_mesh_ratio), 0.25, 1.25, 0.25, 4, 0,
     "(the boulder surface carries the contact nodes and must not be much coarser than the slope)"},
    {"core_factor", offsetof(rf_fem_options, core_factor), 1.5, 10, 1.5, 10, 0, "(fine zone / a)"},
    {"grading", offsetof(rf_fem_options, grading), 1, 2, 1, 2, 0, "(element-size growth)"},
    {"dt_safety", offsetof(rf_fem_options, dt_safety), 1e-6, 4, 1e-6, 1, 0, "(time step / eigenvalue bound)"},
    {"surface_mass_kappa", offsetof(rf_fem_options, surface_mass_kappa), 0, 1, 0, 1, 0,
     "(contact-face element eigenvalue / the mesh's largest after the mass redistribution; 0 = off)"},
    {"end_time", offsetof(rf_fem_options, end_time), 0, INFINITY, 0, INFINITY, 0, "[s] (0 = automatic)"},
    {"duration_threshold", offsetof(rf_fem_options, duration_threshold), 0, 0.4999999, 0, 0.4999999, 0,
     "(share of F_max)"},
};

rf_status rf_fem_options_validate(const rf_fem_options *o, int three_d, rf_error *err)
{
    if (!o)
        return rf_fail(err, RF_EINVAL, "fem: NULL options");
    for (size_t k = 0; k < sizeof rules / sizeof rules[0]; k++) {
        double x = *(const double *)((const char *)o + rules[k].offset);
        double lo = three_d ? rules[k].lo3 : rules[k].lo, hi = three_d ? rules[k].hi3 : rules[k].hi;
        if (rules[k].zero_ok && x == 0)
            continue;
        if (!(x >= lo && x <= hi) || isnan(x))
            return rf_fail(err, RF_EINVAL, "fem%s: %s = %g must lie in [%g, %g] %s", three_d ? "3d" : "",
                           rules[k].name, x, lo, hi, rules[k].why);
    }
    if (isinf(o->end_time))
        return rf_fail(err, RF_EINVAL, "fem: end_time = %g must be finite [s]", o->end_time);
    if ((unsigned)o->large_deformation > RF_FEM_LARGE_DEFORMATION)
        return rf_fail(err, RF_EINVAL, "fem%s: large_deformation = %d is unknown (accepted: auto, off, on)",
                       three_d ? "3d" : "", (int)o->large_deformation);
    if (o->surface_mass_3d != 0 && o->surface_mass_3d != 1)
        return rf_fail(err, RF_EINVAL, "fem%s: surface_mass_3d = %d must be 0 (off) or 1 (on)", three_d ? "3d" : "",
                       o->surface_mass_3d);
    if (o->sphere_contact_3d != 0 && o->sphere_contact_3d != 1)
        return rf_fail(err, RF_EINVAL, "fem%s: sphere_contact_3d = %d must be 0 (off) or 1 (on)", three_d ? "3d" : "",
                       o->sphere_contact_3d);
    if ((unsigned)o->ale > RF_FEM_ALE_ON)
        return rf_fail(err, RF_EINVAL, "fem: ale = %d is unknown (accepted: auto, off, on)", (int)o->ale);
    if (!(o->ale_trigger > 0 && o->ale_trigger < 1))
        return rf_fail(err, RF_EINVAL, "fem: ale_trigger = %g must lie in (0, 1) (share of the reference element size)",
                       o->ale_trigger);
    if (o->ale_sweeps < 0 || o->ale_sweeps > 1000)
        return rf_fail(err, RF_EINVAL, "fem: ale_sweeps = %d must lie in [0, 1000]", o->ale_sweeps);
    if ((unsigned)o->boundary > RF_FEM_BOUNDARY_AUTO)
        return rf_fail(err, RF_EINVAL, "fem: unknown boundary kind %d", (int)o->boundary);
    if (o->threads < 0)
        return rf_fail(err, RF_EINVAL, "fem: threads = %d must be >= 0", o->threads);
    if (o->contact_single_pivot != 0 && o->contact_single_pivot != 1)
        return rf_fail(err, RF_EINVAL, "fem: contact_single_pivot = %d must be 0 or 1", o->contact_single_pivot);
    if (o->max_elements < 1)
        return rf_fail(err, RF_EINVAL, "fem: max_elements = %ld must be >= 1", o->max_elements);
    for (int b = 0; b < 2; b++)
        if ((unsigned)o->kernel[b] > RF_FEM_KERNEL_POINTS)
            return rf_fail(err, RF_EINVAL, "fem%s: kernel[%d] = %d is not available (0 stiffness, 1 points)",
                           three_d ? "3d" : "", b, (int)o->kernel[b]);
    return RF_OK;
}

double rf_fem_refinement(const rf_fem_options *opt, int three_d)
{
    if (opt->refinement > 0)
        return opt->refinement;
    return three_d ? RF_FEM_REFINEMENT_3D : RF_FEM_REFINEMENT_AXI;
}

/* Automatic: the P wave reflected at distance L returns to the contact after
 * 2 L / c_p; it must not arrive before the contact ends (Hertz t_c with a
 * margin for the finite-body lengthening of the contact). */
double rf_fem_domain_factor(const rf_fem_options *opt, const rf_impact_input *in)
{
    if (opt->domain_factor > 0)
        return opt->domain_factor;
    rf_hertz_reference H;
    rf_wave_speeds w;
    rf_impact_hertz_reference(in, &H);
    rf_impact_wave_speeds(in, 1, &w);
    double L = 0.5 * RF_FEM_DOMAIN_MARGIN * w.p * H.duration;
    return fmax(RF_FEM_DOMAIN_MIN, ceil(L / in->radius));
}

int rf_fem_needs_3d(const rf_impact_input *in)
{
    if (in->slope_angle != 0.0)
        return 1;
    if (!(in->friction > 0.0))
        return 0;
    if (rf_impact_has_plastic_body(in))
        return 0; /* the axisymmetric model (large deformation, gravity), with Coulomb friction */
    const int layer = in->layer_thickness > 0;
    /* Dundurs' beta of the boulder (a rigid one: E -> infinity) and the
     * surface it meets, the layer's when there is one */
    const double Eb = in->boulder_material == RF_MATERIAL_RIGID_BODY ? INFINITY : in->boulder_E;
    const double Es = layer ? in->layer_E : in->slope_E, nus = layer ? in->layer_poisson : in->slope_poisson;
    return fabs(rf_dundurs_beta(Eb, in->boulder_poisson, Es, nus)) > 1e-12;
}
