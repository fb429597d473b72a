/* test_trajectory_input.c - bad trajectory files get one message naming the
 * file, line, field and value (issue 11 point 7), and the minimal file of the
 * issue loads with its defaults. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/trajectory.h"
#include "test_util.h"

static const char *base =
    "name: cliff\n"                                                          /* 1 */
    "gravity: 9.81\n"                                                        /* 2 */
    "profile:\n"                                                             /* 3 */
    "  points: [[-10, 20], [0, 20], [0, 0], [100, 0]]\n"                     /* 4 */
    "  materials: [rock, rock, rock]\n"                                      /* 5 */
    "materials:\n"                                                           /* 6 */
    "  rock: {R_n: 0.4, R_t: 0.7, friction_angle: 30, rolling_resistance: 0, roughness: 0}\n" /* 7 */
    "block: {shape: point, mass: 1000}\n"                                    /* 8 */
    "release: {x: -0.5, y: 20.5, vx: 5, vy: 2}\n"                            /* 9 */
    "bounce: {law: constant}\n"                                              /* 10 */
    "stop: {v_stop: 0.1}\n"                                                  /* 11 */
    "collectors: [{name: barrier, x: 6}]\n"                                  /* 12 */
    "samples: 1\n"                                                           /* 13 */
    "seed: 1\n";                                                             /* 14 */

/* base with the first occurrence of `from` replaced by `to`. */
static rf_status load_edit(const char *from, const char *to, rf_traj_spec *s, rf_error *err)
{
    char buf[4096];
    const char *p = strstr(base, from);
    if (!p)
        fail_msg("'%s' not in the base file", from);
    snprintf(buf, sizeof buf, "%.*s%s%s", (int)(p - base), base, to, p + strlen(from));
    return rf_traj_load_buffer("t.yaml", buf, strlen(buf), s, err);
}

static void expect_error(const char *from, const char *to, const char *want1, const char *want2)
{
    rf_traj_spec s;
    rf_error err;
    assert_int_not_equal(load_edit(from, to, &s, &err), RF_OK);
    if (!strstr(err.msg, want1) || !strstr(err.msg, want2))
        fail_msg("message '%s' lacks '%s' or '%s'", err.msg, want1, want2);
}

static void test_minimal_file(void **state)
{
    (void)state;
    rf_traj_spec s;
    rf_error err;
    if (load_edit("name", "name", &s, &err) != RF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(s.n_points, 4);
    assert_int_equal(s.n_materials, 1);
    assert_true(s.gravity == 9.81 && s.mass == 1000 && s.x0 == -0.5 && s.vy0 == 2);
    assert_int_equal(s.law, RF_BOUNCE_CONSTANT);
    assert_int_equal(s.n_collectors, 1);
    assert_true(s.collectors[0].x == 6);
    assert_int_equal(s.n_random, 0);
    rf_traj_spec_free(&s);
}

static void test_bad_inputs(void **state)
{
    (void)state;
    expect_error("[0, 0], [100, 0]", "[0, 0], [-5, 0]", "t.yaml:4:", "profile.points[3] = [-5, 0]");
    expect_error("[0, 0], [100, 0]]\n  materials: [rock, rock, rock]", "[0, 0], [0, 10], [100, 0]]\n  material: rock",
                 "t.yaml:4:", "fold back");
    expect_error("materials: [rock, rock, rock]", "materials: [rock, rock, rock, rock]", "t.yaml:5:", "3 segments");
    expect_error("y: 20.5", "y: 19", "t.yaml:9:", "release.y = 19: under the ground");
    expect_error("R_n: 0.4", "R_n: 1.4", "t.yaml:7:", "materials.rock.R_n = 1.4");
    expect_error("R_n: 0.4", "R_n: {uniform: [0.5, 1.2]}", "t.yaml:7:", "reaches 1.2");
    expect_error("[rock, rock, rock]", "[rock, granite, rock]", "t.yaml:5:", "profile.materials[1] = granite");
    expect_error("law: constant", "law: bouncy", "t.yaml:10:", "bounce.law = bouncy");
    expect_error("law: constant", "law: rigid_sphere", "t.yaml:", "needs block.shape: sphere");
    expect_error("x: 6", "x: 600", "t.yaml:12:", "collectors.barrier.x = 600");
    expect_error("seed: 1", "seed: 1\nsed: 2", "t.yaml:15:", "sed: unknown key");
    expect_error("x: -0.5, ", "x: -0.5, z: 1, ", "t.yaml:9:", "release.z");
    expect_error("mass: 1000", "mass: -1", "t.yaml:8:", "block.mass = -1");
}

/* A material or collector name becomes part of output names, CSV fields, file
 * names and binding paths: markup, separators, quotes and path characters are
 * refused where they are given (they reached report.html unescaped, broke
 * CSV rows and made PLplot abort on '/'). */
static void test_names(void **state)
{
    (void)state;
    const char *bad[] = {"\"<img src=x onerror=alert(1)>\"", "../x", "a/b", "\"a,b\"", "\"a b\"", "a.b",
                         "\"\"", "x23456789012345678901234567890123456789012345678901234567890123456"};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        char to[128];
        snprintf(to, sizeof to, "name: %s, x: 6", bad[k]);
        expect_error("name: barrier, x: 6", to, "t.yaml:12:", "collectors[0].name");
        snprintf(to, sizeof to, "  %s: {R_n", bad[k]);
        if (bad[k][0] != '"' || bad[k][1] != '"') /* an empty key is YAML's own error */
            expect_error("  rock: {R_n", to, "t.yaml:7:", "is not a name");
    }
    rf_traj_spec s;
    rf_error err;
    assert_int_equal(load_edit("name: barrier, x: 6", "name: Barrier-2_b, x: 6", &s, &err), RF_OK);
    free(s.collectors[0].name); /* a spec built in code is held to the same rule */
    s.collectors[0].name = strdup("a/b");
    assert_int_not_equal(rf_traj_spec_validate(&s, &err), RF_OK);
    assert_non_null(strstr(err.msg, "collectors[0].name = a/b"));
    rf_traj_spec_free(&s);
}

/* With x sorted, a profile can only cross itself by folding back along a vertical step. */
static void test_self_intersection(void **state)
{
    (void)state;
    expect_error("[0, 0], [100, 0]]\n  materials: [rock, rock, rock]", "[0, 0], [0, 25], [100, 0]]\n  material: rock",
                 "t.yaml:4:", "self-intersecting");
}

static void test_fields_and_copy(void **state)
{
    (void)state;
    rf_traj_spec s, d;
    rf_error err;
    assert_int_equal(load_edit("vx: 5", "vx: {normal: [5, 1], min: 3, max: 7}", &s, &err), RF_OK);
    assert_int_equal(s.n_random, 1);
    assert_true(*rf_traj_spec_field(&s, "release.vx.mean") == 5);
    assert_true(*rf_traj_spec_field(&s, "release.vx.sd") == 1);
    assert_true(*rf_traj_spec_field(&s, "materials.rock.R_t") == 0.7);
    assert_true(*rf_traj_spec_field(&s, "collectors.barrier.x") == 6);
    assert_true(*rf_traj_spec_field(&s, "profile.points.2.y") == 0);
    assert_null(rf_traj_spec_field(&s, "materials.rock.colour"));
    assert_null(rf_traj_spec_field(&s, "profile.points.9.y"));
    assert_int_equal(rf_traj_spec_copy(&s, &d, &err), RF_OK);
    *rf_traj_spec_field(&d, "materials.rock.R_n") = 0.1;
    assert_true(s.materials[0].R_n == 0.4);
    rf_traj_spec_free(&d);
    rf_traj_spec_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_minimal_file),
        cmocka_unit_test(test_bad_inputs),
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_self_intersection),
        cmocka_unit_test(test_fields_and_copy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
