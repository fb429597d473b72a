/* test_study_bind.c - `bind:` in study files (docs/user-guide.md 1.5).
 * A parameter bound to a list of inputs, or as value * scale + offset, must
 * give bit for bit the outputs of a study whose parameters set those inputs
 * separately to the same values (trajectory, impact and program models).
 * Refused at load, with file:line: an input driven by two parameters, a
 * profile index written as an alias (01, +1, " 1"), a parameter bound to
 * nothing, and a corner of the parameter box the model does not admit
 * although every support end alone is admissible.  The default scheme:
 * general for program and trajectory models, reduced for impact and formula
 * models, and the scheme the file sets wherever it sets one. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/study.h"
#include "rockfuzz/trajectory.h"
#include "test_util.h"

static const char *two_yaml =
    "name: two\n"
    "profile:\n"
    "  points: [[0, 20], [10, 10], [20, 5], [40, 0]]\n"
    "  materials: [rock, talus, talus]\n"
    "materials:\n"
    "  rock: {R_n: 0.4, R_t: 0.8, friction_angle: 30}\n"
    "  talus: {R_n: 0.3, R_t: 0.75, friction_angle: 32, rolling_resistance: 0.2}\n"
    "block: {shape: point, mass: 100}\n"
    "release: {x: 1, y: 30, vx: {uniform: [2, 5]}}\n"
    "collectors: [{name: c, x: 15}]\n"
    "samples: 200\nseed: 5\n";

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static rf_status load(const char *text, rf_study *s, rf_error *err)
{
    write_file("bind_two.yaml", two_yaml);
    write_file("bind_study.yaml", text);
    return rf_study_load("bind_study.yaml", s, err);
}

static void load_ok(const char *text, rf_study *s)
{
    rf_error err;
    if (load(text, s, &err) != RF_OK)
        fail_msg("%s", err.msg);
}

/* The study fails to load and its message holds every one of want[]. */
static void load_fails(const char *text, const char *const *want, size_t n)
{
    rf_study s;
    rf_error err;
    assert_int_not_equal(load(text, &s, &err), RF_OK);
    for (size_t k = 0; k < n; k++)
        if (!strstr(err.msg, want[k]))
            fail_msg("'%s' not in: %s", want[k], err.msg);
}

/* a's model at xa and b's at xb give the same bytes. */
static void same_outputs(const char *a, const double *xa, const char *b, const double *xb)
{
    rf_study sa, sb;
    rf_error err;
    double ya[128], yb[128];
    load_ok(a, &sa);
    load_ok(b, &sb);
    assert_int_equal(sa.model.n_outputs, sb.model.n_outputs);
    assert_true(sa.model.n_outputs <= 128);
    if (rf_model_eval(&sa.model, xa, ya, &err) != RF_OK || rf_model_eval(&sb.model, xb, yb, &err) != RF_OK)
        fail_msg("%s", err.msg);
    for (size_t k = 0; k < sa.model.n_outputs; k++) {
        assert_string_equal(sa.model.output_names[k], sb.model.output_names[k]);
        if (memcmp(&ya[k], &yb[k], sizeof ya[k]))
            fail_msg("%s: %.17g bound, %.17g separately", sa.model.output_names[k], ya[k], yb[k]);
    }
    rf_study_free(&sa);
    rf_study_free(&sb);
}

static void test_trajectory_list_and_affine(void **state)
{
    (void)state;
    /* one restitution for both materials, and R_t of the talus derived from that of the rock */
    double x[2] = {0.35, 0.82}, sep[4] = {0.35, 0.35, 0.82, 0.82 * 0.9 + 0.02};
    same_outputs("levels: 2\nparameters:\n  Rn: {tfn: [0.35, 0.05, 0.05]}\n  Rt: {tfn: [0.82, 0.05, 0.05]}\n"
                 "model:\n  trajectory:\n    file: bind_two.yaml\n    bind:\n"
                 "      Rn: [materials.rock.R_n, materials.talus.R_n]\n"
                 "      Rt: [materials.rock.R_t, {to: materials.talus.R_t, scale: 0.9, offset: 0.02}]\n",
                 x,
                 "levels: 2\nparameters:\n  a: {tfn: [0.35, 0.05, 0.05]}\n  b: {tfn: [0.35, 0.05, 0.05]}\n"
                 "  c: {tfn: [0.82, 0.05, 0.05]}\n  d: {tfn: [0.758, 0.05, 0.05]}\n"
                 "model:\n  trajectory:\n    file: bind_two.yaml\n    bind: {a: materials.rock.R_n, "
                 "b: materials.talus.R_n, c: materials.rock.R_t, d: materials.talus.R_t}\n",
                 sep);
    /* the outputs really depend on the bound inputs: another value changes them */
    rf_study s;
    rf_error err;
    double y1[128], y2[128], x2[2] = {0.45, 0.82};
    load_ok("parameters:\n  Rn: {tfn: [0.35, 0.05, 0.1]}\n  Rt: {tfn: [0.82, 0.05, 0.05]}\nmodel:\n  trajectory:\n"
            "    file: bind_two.yaml\n    bind: {Rn: [materials.rock.R_n, materials.talus.R_n], Rt: materials.rock.R_t}\n",
            &s);
    assert_int_equal(rf_model_eval(&s.model, x, y1, &err), RF_OK);
    assert_int_equal(rf_model_eval(&s.model, x2, y2, &err), RF_OK);
    assert_true(memcmp(y1, y2, s.model.n_outputs * sizeof *y1) != 0);
    rf_study_free(&s);
}

/* The store's identity of a bound model names the inner model and every binding. */
static void test_bound_identity(void **state)
{
    (void)state;
    rf_study s;
    load_ok("parameters:\n  Rn: {tfn: [0.35, 0.05, 0.05]}\nmodel:\n  trajectory:\n    file: bind_two.yaml\n"
            "    bind: {Rn: [materials.rock.R_n, {to: materials.talus.R_n, scale: 0.5}]}\n",
            &s);
    assert_non_null(strstr(s.model.identity, "trajectory v3"));
    assert_non_null(strstr(s.model.identity, "x0->materials.talus.R_n*0.5+0"));
    rf_study_free(&s);
}

static void test_impact_list_and_affine(void **state)
{
    (void)state;
    double x[2] = {50e9, 2650}, sep[4] = {50e9, 50e9, 2650, 2650 * 0.75 - 100};
    same_outputs("parameters:\n  E: {tfn: [50e9, 5e9, 5e9]}\n  rho: {tfn: [2650, 100, 100]}\n"
                 "model:\n  impact:\n    solver: hunter\n"
                 "    bind: {E: [boulder_E, slope_E], rho: [boulder_density, {to: slope_density, scale: 0.75, "
                 "offset: -100}]}\n",
                 x,
                 "parameters:\n  boulder_E: {tfn: [50e9, 5e9, 5e9]}\n  slope_E: {tfn: [50e9, 5e9, 5e9]}\n"
                 "  boulder_density: {tfn: [2650, 100, 100]}\n  slope_density: {tfn: [1887.5, 100, 100]}\n"
                 "model:\n  impact: {solver: hunter}\n",
                 sep);
}

static void test_program_list_and_affine(void **state)
{
    (void)state;
    double x[1] = {1.25}, sep[3] = {1.25, 1.25, 1.25 * 2 + 1};
    same_outputs("parameters:\n  p: {tfn: [1.25, 0.5, 0.5]}\nmodel:\n  program:\n"
                 "    argv: [printf, \"y = %s\\nz = %s\\nw = %s\\n\", \"{A}\", \"{B}\", \"{C}\"]\n"
                 "    outputs: {y: {}, z: {}, w: {}}\n"
                 "    bind: {p: [A, B, {to: C, scale: 2, offset: 1}]}\n",
                 x,
                 "parameters:\n  A: {tfn: [1.25, 0.5, 0.5]}\n  B: {tfn: [1.25, 0.5, 0.5]}\n  C: {tfn: [3.5, 1, 1]}\n"
                 "model:\n  program:\n    argv: [printf, \"y = %s\\nz = %s\\nw = %s\\n\", \"{A}\", \"{B}\", \"{C}\"]\n"
                 "    outputs: {y: {}, z: {}, w: {}}\n",
                 sep);
    /* and the values are those written: y = z = p, w = 2 p + 1 */
    rf_study s;
    rf_error err;
    double y[3];
    load_ok("parameters:\n  p: {tfn: [1.25, 0.5, 0.5]}\nmodel:\n  program:\n"
            "    argv: [printf, \"y = %s\\nz = %s\\nw = %s\\n\", \"{A}\", \"{B}\", \"{C}\"]\n"
            "    outputs: {y: {}, z: {}, w: {}}\n    bind: {p: [A, B, {to: C, scale: 2, offset: 1}]}\n", &s);
    assert_int_equal(rf_model_eval(&s.model, x, y, &err), RF_OK);
    assert_true(y[0] == 1.25 && y[1] == 1.25 && y[2] == 3.5);
    rf_study_free(&s);
}

static void test_refused_bindings(void **state)
{
    (void)state;
    const char *head = "parameters:\n  a: {tfn: [0.4, 0.05, 0.05]}\n  b: {tfn: [0.3, 0.05, 0.05]}\n"
                       "model:\n  trajectory:\n    file: bind_two.yaml\n    bind:\n";
    char text[1024];
    /* two parameters, one input (31.7): the second is refused where it is written */
    snprintf(text, sizeof text, "%s      a: materials.rock.R_n\n      b: [materials.talus.R_n, materials.rock.R_n]\n",
             head);
    load_fails(text, (const char *[]){"bind_study.yaml:9: model.trajectory.bind.b[1] = materials.rock.R_n",
                                      "already driven by parameter a (line 8)"}, 2);
    /* the same input twice in one list */
    snprintf(text, sizeof text, "%s      a: [materials.rock.R_n, materials.rock.R_n]\n      b: materials.talus.R_n\n",
             head);
    load_fails(text, (const char *[]){"bind_study.yaml:8:", "listed twice"}, 2);
    /* impact: a parameter named after an input and another bound to it */
    load_fails("parameters:\n  velocity: {tfn: [10, 1, 1]}\n  v2: {tfn: [10, 1, 1]}\n"
               "model:\n  impact: {solver: hunter, bind: {v2: velocity}}\n",
               (const char *[]){"bind_study.yaml:5: model.impact.bind.v2 = velocity",
                                "already driven by parameter velocity (line 2)"}, 2);
    /* a crisp value for an input a parameter drives */
    load_fails("parameters:\n  E: {tfn: [50e9, 5e9, 5e9]}\n"
               "model:\n  impact: {solver: hunter, slope_E: 3e10, bind: {E: [boulder_E, slope_E]}}\n",
               (const char *[]){"bind_study.yaml:4: model.impact.slope_E = 3e10",
                                "already driven by the fuzzy parameter E"}, 2);
    /* index aliases of profile.points.1.y */
    const char *alias[] = {"profile.points.01.y", "profile.points.+1.y", "\"profile.points. 1.y\""};
    for (int k = 0; k < 3; k++) {
        snprintf(text, sizeof text, "%s      a: %s\n      b: materials.talus.R_n\n", head, alias[k]);
        load_fails(text, (const char *[]){"bind_study.yaml:8: model.trajectory.bind.a", "profile.points.1.y",
                                          "no sign, space or leading zero"}, 3);
    }
    /* bound to nothing: an empty list, or no entry */
    snprintf(text, sizeof text, "%s      a: []\n      b: materials.talus.R_n\n", head);
    load_fails(text, (const char *[]){"bind_study.yaml:8: model.trajectory.bind.a", "bound to nothing"}, 2);
    snprintf(text, sizeof text, "%s      b: materials.talus.R_n\n", head);
    load_fails(text, (const char *[]){"bind_study.yaml:2: parameters.a: not bound"}, 1);
    /* a binding of no parameter, a scale of 0, a missing or unknown key of an affine form */
    snprintf(text, sizeof text, "%s      a: materials.rock.R_n\n      b: materials.talus.R_n\n      c: release.x\n",
             head);
    load_fails(text, (const char *[]){"bind_study.yaml:10: model.trajectory.bind.c", "not a parameter"}, 2);
    snprintf(text, sizeof text, "%s      a: {to: materials.rock.R_n, scale: 0}\n      b: materials.talus.R_n\n",
             head);
    load_fails(text, (const char *[]){"bind_study.yaml:8: model.trajectory.bind.a.scale = 0", "constant"}, 2);
    snprintf(text, sizeof text, "%s      a: {scale: 2}\n      b: materials.talus.R_n\n", head);
    load_fails(text, (const char *[]){"bind_study.yaml:8: model.trajectory.bind.a", "missing to"}, 2);
    snprintf(text, sizeof text, "%s      a: {to: materials.rock.R_n, factor: 2}\n      b: materials.talus.R_n\n",
             head);
    load_fails(text, (const char *[]){"bind_study.yaml:8: model.trajectory.bind.a.factor", "scale and offset"}, 2);
    /* an affine image outside the input's range is that input's value */
    snprintf(text, sizeof text, "%s      a: [materials.rock.R_n, {to: materials.talus.R_n, scale: 2.4}]\n"
                                "      b: materials.talus.R_t\n", head);
    load_fails(text, (const char *[]){"bind_study.yaml:2: parameters.a: the value 0.45",
                                      "materials.talus.R_n = 1.08", "must lie in [0, 1]"}, 3);
}

/* A release point under a raised vertex, only at one corner of the box (31.7):
 * P (the cliff top) alone up to 22 and H (the release height) alone down to
 * 20.5 are admissible; together the ground at x = 1 is 0.9 * 22 + 1 = 20.8 m. */
static void test_corner_admissibility(void **state)
{
    (void)state;
    load_fails("parameters:\n  P: {tfn: [20, 2, 2]}\n  H: {tfn: [21.5, 1, 1.5]}\n"
               "model: {trajectory: {file: bind_two.yaml, bind: {P: profile.points.0.y, H: release.y}}}\n",
               (const char *[]){"bind_study.yaml:4: model.trajectory.bind", "P = 22 (high end), H = 20.5 (low end)",
                                "release.y = 20.5: under the ground"}, 3);
    /* a narrower cliff-top support clears every corner */
    rf_study s;
    load_ok("parameters:\n  P: {tfn: [20, 2, 0.5]}\n  H: {tfn: [21.5, 1, 1.5]}\n"
            "model: {trajectory: {file: bind_two.yaml, bind: {P: profile.points.0.y, H: release.y}}}\n", &s);
    rf_study_free(&s);
}

static void scheme_is(const char *text, rf_tm_scheme want, const char *reason)
{
    rf_study s;
    load_ok(text, &s);
    assert_int_equal(s.scheme, want);
    assert_non_null(s.scheme_reason);
    if (!strstr(s.scheme_reason, reason))
        fail_msg("'%s' not in '%s'", reason, s.scheme_reason);
    rf_study_free(&s);
}

static void test_default_scheme(void **state)
{
    (void)state;
    const char *program = "parameters: {p: {tfn: [1, 0.5, 0.5]}}\nmodel:\n  program:\n"
                          "    argv: [printf, \"y = %s\\n\", \"{p}\"]\n    outputs: {y: {}}\n";
    char text[512];
    scheme_is(program, RF_TM_GENERAL, "default for a program model");
    snprintf(text, sizeof text, "scheme: reduced\n%s", program);
    scheme_is(text, RF_TM_REDUCED, "set in the study file");
    scheme_is("parameters: {Rn: {tfn: [0.35, 0.05, 0.05]}}\n"
              "model: {trajectory: {file: bind_two.yaml, bind: {Rn: materials.rock.R_n}}}\n",
              RF_TM_GENERAL, "default for a trajectory model");
    scheme_is("scheme: reduced\nparameters: {Rn: {tfn: [0.35, 0.05, 0.05]}}\n"
              "model: {trajectory: {file: bind_two.yaml, bind: {Rn: materials.rock.R_n}}}\n",
              RF_TM_REDUCED, "set in the study file");
    scheme_is("parameters: {velocity: {tfn: [10, 1, 1]}}\nmodel: {impact: {solver: hunter}}\n", RF_TM_REDUCED,
              "default for formula and impact models");
    scheme_is("parameters: {x: {tfn: [1, 0.5, 0.5]}}\nmodel: {formula: {y: \"x*x\"}}\noptions: {left_right: false}\n",
              RF_TM_REDUCED, "unchecked here");
    scheme_is("scheme: extended\nparameters: {x: {tfn: [1, 0.5, 0.5]}}\nmodel: {formula: {y: \"x*x\"}}\n",
              RF_TM_EXTENDED, "set in the study file");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_trajectory_list_and_affine),
        cmocka_unit_test(test_bound_identity),
        cmocka_unit_test(test_impact_list_and_affine),
        cmocka_unit_test(test_program_list_and_affine),
        cmocka_unit_test(test_refused_bindings),
        cmocka_unit_test(test_corner_admissibility),
        cmocka_unit_test(test_default_scheme),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
