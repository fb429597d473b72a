/* test_terrain_output.c - the outputs of a terrain run on a hand-made
 * ensemble (no simulator needed): the JSON document parses and holds per
 * trajectory state, impacts (t, x, y, z, v_in[3], v_out[3], omega_out[3],
 * class), rest or null, barrier crossings, and the statistics: runout and
 * reach angle percentiles (deg) against values worked out by hand
 * (Hyndman-Fan type 7 over the samples, the reach angle atan(drop / runout)
 * skipping the block that did not move), per barrier reach probability and
 * held count; the summary gives the answer first; the CSV headers name their
 * units and hold one row per sample. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <libfyaml.h>

#include "trajectory/terrain_internal.h"

/* |a - b| <= tol in double (cmocka's assert_float_equal compares floats). */
#define assert_near(a, b, tol)                                                                              \
    do {                                                                                                    \
        double a_ = (a), b_ = (b);                                                                          \
        if (!(fabs(a_ - b_) <= (tol)))                                                                      \
            fail_msg("%s = %.17g, expected %.17g (tol %g)", #a, a_, b_, (double)(tol));                     \
    } while (0)

#define N 5
#define DEGREES (180 / 3.14159265358979323846)

typedef struct {
    rf_traj_spec spec;
    rf_traj_material mat[2];
    rf_traj_collector col;
    rf_terrain_def def;
    rf_traj_ensemble ens;
    rf_traj_stats st;
} fixture;

/* Sample i ends at end[i] from (0, 0, 100); runouts 50, 100, 0, 5, 10 m and
 * drops 30, 50, 0, 5, 10 m. */
static const double END[N][3] = {{30, 40, 70}, {60, 80, 50}, {0, 0, 100}, {3, 4, 95}, {6, 8, 90}};
static const rf_traj_state STATE[N] = {RF_TRAJ_STOPPED, RF_TRAJ_EXITED, RF_TRAJ_STOPPED, RF_TRAJ_STOPPED,
                                       RF_TRAJ_STEP_LIMIT};

static void make_spec(fixture *f)
{
    memset(&f->spec, 0, sizeof f->spec);
    f->mat[0] = (rf_traj_material){"rock", 0.5, 0.8, 0.5, 0.1, 0, {0}};
    f->mat[1] = (rf_traj_material){"soil", 0.3, 0.6, 0.6, 0.4, 0, {0}};
    memset(&f->col, 0, sizeof f->col);
    f->col.name = "fence", f->col.capacity = 2e6, f->col.height = 4;
    memset(&f->def, 0, sizeof f->def);
    f->spec.name = "valley", f->spec.samples = N, f->spec.seed = 7, f->spec.record = 2;
    f->spec.n_materials = 2, f->spec.materials = f->mat;
    f->spec.n_collectors = 1, f->spec.collectors = &f->col;
    f->spec.terrain = &f->def;
    f->spec.release_kind = RF_TRAJ_RELEASE_MAP;
}

static rf_traj_crossing crossing(double t, double e, int stopped)
{
    rf_traj_crossing c = {0};
    c.reached = 1, c.t = t, c.x = 10, c.y = 20, c.along = 12.5, c.height_lowest = 1.5, c.height_centre = 2;
    c.speed = 20, c.translational_energy = 0.8 * e, c.rotational_energy = 0.2 * e, c.total_energy = e;
    c.energy_after = stopped ? 0 : e > 2e6 ? e - 2e6 : e, c.stopped_by_barrier = stopped;
    return c;
}

static void make_recorded(rf_terrain_samples *t)
{
    t->n_recorded = 2;
    t->recorded = calloc(2, sizeof *t->recorded);
    for (size_t i = 0; i < 2; i++) {
        rf_terrain_result *r = &t->recorded[i];
        r->state = STATE[i];
        memcpy(r->start, (double[3]){0, 0, 100}, sizeof r->start);
        memcpy(r->end, END[i], sizeof r->end);
        r->t_end = 4 + (double)i, r->runout = hypot(END[i][0], END[i][1]);
        r->reach_angle = atan((100 - END[i][2]) / r->runout);
        r->crossings = calloc(1, sizeof *r->crossings);
        r->impacts = calloc(2, sizeof *r->impacts), r->impacts_cap = 2;
        r->n_impacts = i == 0 ? 2 : 0;
    }
    rf_terrain_impact *m = t->recorded[0].impacts;
    m[0] = (rf_terrain_impact){1.0, 5, 6, 90, {1, -2, -9}, {0.5, -1, 4}, {0.1, 0.2, 0.3}, 0, {0}, {0}};
    m[1] = (rf_terrain_impact){2.5, 15, 20, 80, {2, 3, -8}, {1, 1.5, 3}, {0, 0, 0}, 1, {0}, {0}};
    t->recorded[0].crossings[0] = crossing(2, 1e6, 0);
}

static void make_ensemble(fixture *f)
{
    rf_traj_ensemble *e = &f->ens;
    memset(e, 0, sizeof *e);
    e->samples = N, e->n_collectors = 1;
    e->state = malloc(N), e->runout_x = malloc(N * sizeof(double)), e->rebound_height = calloc(N, sizeof(double));
    e->crossings = calloc(N, sizeof *e->crossings);
    rf_terrain_samples *t = e->terrain = calloc(1, sizeof *t);
    t->start = malloc(3 * N * sizeof(double)), t->end = malloc(3 * N * sizeof(double));
    t->runout = malloc(N * sizeof(double)), t->reach_angle = malloc(N * sizeof(double));
    for (size_t i = 0; i < N; i++) {
        memcpy(&t->start[3 * i], (double[3]){0, 0, 100}, 3 * sizeof(double));
        memcpy(&t->end[3 * i], END[i], 3 * sizeof(double));
        e->state[i] = (unsigned char)STATE[i];
        t->runout[i] = e->runout_x[i] = hypot(END[i][0], END[i][1]);
        t->reach_angle[i] = t->runout[i] > 0 ? atan((100 - END[i][2]) / t->runout[i]) : NAN;
    }
    e->crossings[0] = crossing(2, 1e6, 0);
    e->crossings[1] = crossing(3, 3e6, 0);
    e->crossings[3] = crossing(1, 1.5e6, 1);
    make_recorded(t);
}

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    make_spec(f);
    make_ensemble(f);
    rf_error err;
    assert_int_equal(rf_traj_stats_compute_spec(&f->spec, &f->ens, &f->st, &err), RF_OK);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    rf_traj_stats_free(&f->st);
    rf_traj_ensemble_free(&f->ens); /* frees ens->terrain: ASan sees a leak or a double free */
    assert_null(f->ens.terrain);
    free(f);
    return 0;
}

/* p50 of the reach angles {atan(30/50), atan(50/100), 45 deg, 45 deg}: half way between the 2nd and 3rd. */
static double reach_p50_deg(void) { return 0.5 * (atan(0.6) + atan(1.0)) * DEGREES; }

static void test_stats(void **state)
{
    fixture *f = *state;
    assert_int_equal(f->st.stopped, 3);
    assert_int_equal(f->st.exited, 1);
    assert_int_equal(f->st.step_limit, 1);
    /* runouts sorted 0 5 10 50 100: p50 = 10, p95 at h = 3.8: 50 + 0.8 * 50 */
    assert_near(f->st.runout_x.p50, 10, 1e-12);
    assert_near(f->st.runout_x.p95, 90, 1e-12);
    assert_near(f->st.reach_angle.p50 * DEGREES, reach_p50_deg(), 1e-12);
    assert_near(f->st.reach_angle.max * DEGREES, 45, 1e-12);
    assert_near(f->st.collectors[0].reach_probability, 0.6, 1e-15);
}

static char *json_of(const fixture *f, size_t max_traj)
{
    char *doc = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&doc, &len);
    assert_non_null(m);
    rf_terrain_write_json(m, &f->spec, &f->ens, &f->st, max_traj);
    fclose(m);
    return doc;
}

static const char *at(struct fy_document *d, const char *path)
{
    struct fy_node *n = fy_node_by_path(fy_document_root(d), path, -1, FYNWF_DONT_FOLLOW);
    if (!n)
        fail_msg("no %s in the JSON document", path);
    static char buf[256];
    size_t len = 0;
    const char *v = fy_node_is_scalar(n) ? fy_node_get_scalar(n, &len) : NULL;
    if (!v)
        return "<not a scalar>";
    snprintf(buf, sizeof buf, "%.*s", (int)len, v);
    return buf;
}

static double num(struct fy_document *d, const char *path) { return strtod(at(d, path), NULL); }

static int seq_len(struct fy_document *d, const char *path)
{
    struct fy_node *n = fy_node_by_path(fy_document_root(d), path, -1, FYNWF_DONT_FOLLOW);
    return n && fy_node_is_sequence(n) ? fy_node_sequence_item_count(n) : -1;
}

static struct fy_document *parse(const char *doc)
{
    struct fy_parse_cfg cfg = {.flags = FYPCF_QUIET | FYPCF_JSON_FORCE};
    struct fy_document *d = fy_document_build_from_string(&cfg, doc, FY_NT);
    if (!d)
        fail_msg("the JSON document does not parse:\n%s", doc);
    return d;
}

static void test_json_trajectories(void **state)
{
    fixture *f = *state;
    char *doc = json_of(f, 100);
    struct fy_document *d = parse(doc);
    assert_string_equal(at(d, "/kind"), "terrain");
    assert_string_equal(at(d, "/units/angle"), "deg");
    assert_string_equal(at(d, "/units/energy"), "J");
    assert_int_equal(seq_len(d, "/trajectories"), 2);
    assert_string_equal(at(d, "/trajectories/0/state"), "stopped");
    assert_int_equal(seq_len(d, "/trajectories/0/impacts"), 2);
    assert_int_equal(seq_len(d, "/trajectories/0/impacts/0/v_in"), 3);
    assert_near(num(d, "/trajectories/0/impacts/0/v_in/2"), -9, 0);
    assert_near(num(d, "/trajectories/0/impacts/1/v_out/1"), 1.5, 0);
    assert_near(num(d, "/trajectories/0/impacts/0/omega_out/2"), 0.3, 0);
    assert_near(num(d, "/trajectories/0/impacts/1/z"), 80, 0);
    assert_string_equal(at(d, "/trajectories/0/impacts/1/class"), "soil");
    assert_near(num(d, "/trajectories/0/rest/z"), 70, 0);
    assert_near(num(d, "/trajectories/0/reach_angle"), atan(0.6) * DEGREES, 1e-12);
    assert_near(num(d, "/trajectories/0/barriers/fence/along"), 12.5, 0);
    assert_near(num(d, "/trajectories/0/barriers/fence/total_energy"), 1e6, 0);
    assert_string_equal(at(d, "/trajectories/1/state"), "exited");
    assert_string_equal(at(d, "/trajectories/1/rest"), "null");
    assert_string_equal(at(d, "/trajectories/1/barriers/fence"), "null");
    fy_document_destroy(d);
    free(doc);
    d = parse(doc = json_of(f, 1)); /* --max-trajectories 1 */
    assert_int_equal(seq_len(d, "/trajectories"), 1);
    assert_near(num(d, "/trajectories_shown"), 1, 0);
    fy_document_destroy(d);
    free(doc);
}

static void test_json_statistics(void **state)
{
    fixture *f = *state;
    char *doc = json_of(f, 100);
    struct fy_document *d = parse(doc);
    assert_near(num(d, "/statistics/runout/p50"), 10, 1e-12);
    assert_near(num(d, "/statistics/runout/p95"), 90, 1e-12);
    assert_near(num(d, "/statistics/reach_angle/p50"), reach_p50_deg(), 1e-12);
    assert_near(num(d, "/statistics/reach_angle/max"), 45, 1e-12);
    assert_near(num(d, "/statistics/barriers/fence/reach_probability"), 0.6, 1e-15);
    /* the energies of the three that reach it: 1, 1.5, 3 MJ; P(E > capacity 2 MJ) = 1 / 5 */
    assert_near(num(d, "/statistics/barriers/fence/total_energy/p50"), 1.5e6, 1e-6);
    assert_near(num(d, "/statistics/barriers/fence/p_total_energy_above/0/probability"), 0.2, 1e-15);
    assert_near(num(d, "/statistics/held_by_barrier/fence"), 1, 0);
    assert_near(num(d, "/states/step_limit"), 1, 0);
    fy_document_destroy(d);
    free(doc);
}

static void test_summary(void **state)
{
    fixture *f = *state;
    char *doc = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&doc, &len);
    rf_terrain_write_summary(m, &f->spec, &f->ens, &f->st);
    fclose(m);
    /* the answer first: the second line says how many stop */
    const char *l2 = strchr(doc, '\n') + 1;
    assert_true(!strncmp(l2, "  60 % stop (3), 20 % leave the DEM (1), 20 % reach the step limit (1)", 70));
    assert_non_null(strstr(doc, "runout (horizontal, release to end) [m]: p50 10, p95 90, max 100"));
    assert_non_null(strstr(doc, "barrier fence: reached by 60 % of the blocks, held 20 %; energy p95 "));
    assert_non_null(strstr(doc, "P(total energy > 2000 kJ, the capacity) = 0.2"));
    free(doc);
}

/* The lines of dir/name; *header gets the first. */
static int read_lines(const char *dir, const char *name, char *header, size_t size, char *row1, size_t size1)
{
    char path[512], line[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *fp = fopen(path, "r");
    assert_non_null(fp);
    int n = 0;
    while (fgets(line, sizeof line, fp)) {
        if (n == 0)
            snprintf(header, size, "%s", line);
        if (n == 1)
            snprintf(row1, size1, "%s", line);
        n++;
    }
    fclose(fp);
    unlink(path);
    return n;
}

static void test_csv(void **state)
{
    fixture *f = *state;
    char dir[] = "/tmp/rf_terrain_out_XXXXXX", header[4096], row[4096];
    assert_non_null(mkdtemp(dir));
    rf_error err;
    assert_int_equal(terrain_write_tables(dir, &f->spec, &f->ens, &f->st, &err), RF_OK);
    assert_int_equal(read_lines(dir, "samples.csv", header, sizeof header, row, sizeof row), N + 1);
    assert_string_equal(header, "sample,state,start_x_m,start_y_m,start_z_m,end_x_m,end_y_m,end_z_m,runout_m,"
                                "reach_angle_deg,rebound_height_m\n");
    double v[9];
    assert_int_equal(sscanf(row, "0,stopped,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4],
                            &v[5], &v[6], &v[7], &v[8]), 9);
    assert_near(v[5], 70, 0);
    assert_near(v[6], 50, 0);
    assert_near(v[7], atan(0.6) * DEGREES, 1e-12);
    assert_int_equal(read_lines(dir, "crossings.csv", header, sizeof header, row, sizeof row), N + 1);
    assert_non_null(strstr(header, ",x_m,y_m,along_m,"));
    assert_non_null(strstr(header, ",total_energy_J,energy_after_J,stopped_by_barrier\n"));
    assert_int_equal(strncmp(row, "0,stopped,50,fence,1,2,10,20,12.5,", 34), 0);
    int n = read_lines(dir, "statistics.csv", header, sizeof header, row, sizeof row);
    assert_int_equal(n, 1 + 3 + 7);
    assert_string_equal(header, "quantity,unit,p50,p95,p99,max,mean\n");
    assert_int_equal(strncmp(row, "runout,m,10,90,", 15), 0);
    assert_int_equal(rmdir(dir), 0);
}

static void test_refuses_profile(void **state)
{
    (void)state;
    rf_traj_spec s;
    memset(&s, 0, sizeof s);
    s.samples = 1, s.file = "slope.yaml";
    rf_traj_ensemble e;
    rf_error err;
    assert_int_equal(terrain_run_world(&s, NULL, 1, 1, NULL, NULL, &e, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "slope.yaml: not a terrain file"));
    /* the per-sample arrays of a run: 8 doubles and a state, and a crossing per barrier */
    assert_near(terrain_bytes_per_sample(2), 65 + 2.0 * sizeof(rf_traj_crossing), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_stats, setup, teardown),
        cmocka_unit_test_setup_teardown(test_json_trajectories, setup, teardown),
        cmocka_unit_test_setup_teardown(test_json_statistics, setup, teardown),
        cmocka_unit_test_setup_teardown(test_summary, setup, teardown),
        cmocka_unit_test_setup_teardown(test_csv, setup, teardown),
        cmocka_unit_test(test_refuses_profile),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
