/* test_study.c - study files: every parameter shape gives the cuts of the
 * same rf_fuzzy built directly; every class of bad input fails before any
 * evaluation with a message naming file, line, field and value. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "rockfuzz/study.h"
#include "test_util.h"

#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define M 4

static rf_status load(const char *text, rf_study *s, rf_error *err)
{
    memset(err, 0, sizeof *err);
    return rf_study_load_buffer("study.yaml", text, strlen(text), s, err);
}

static size_t find_param(const rf_study *s, const char *name)
{
    for (size_t i = 0; i < s->n_params; i++)
        if (!strcmp(s->param_names[i], name))
            return i;
    fail_msg("parameter %s not found", name);
    return 0;
}

static void assert_same_cuts(const rf_fuzzy *a, const rf_fuzzy *b)
{
    double alo[M + 1], ahi[M + 1], blo[M + 1], bhi[M + 1];
    assert_int_equal(rf_fuzzy_decompose(a, M, alo, ahi, NULL), RF_OK);
    assert_int_equal(rf_fuzzy_decompose(b, M, blo, bhi, NULL), RF_OK);
    for (int j = 0; j <= M; j++) {
        assert_true(alo[j] == blo[j]);
        assert_true(ahi[j] == bhi[j]);
    }
}

static const char *all_shapes =
    "name: shapes\n"
    "scheme: general\n"
    "levels: 4\n"
    "parameters:\n"
    "  x1: {tfn: [2, 1, 1]}\n"
    "  x2: {trapezoid: [0.05, 0.45, 0.55, 0.95], unit: \"m\"}\n"
    "  x3: {interval: [1, 2]}\n"
    "  x4: {gaussian: [10, 1, 2], cutoff: 3}\n"
    "  x5: {crisp: 1.5}\n"
    "  x6: {points: [[0, 0], [1, 1], [3, 0]]}\n"
    "  x7: {cuts: {mu: [0, 0.5, 1], lower: [1, 1.5, 2], upper: [3, 2.5, 2]}}\n"
    "  x8: 4.25\n"
    "  x9:\n"
    "    tfn: [0, 1, 2]\n"
    "    class: nonmonotonic\n"
    "model:\n"
    "  formula: {y: \"x1*x2 + x3\", z: \"x1 - x1\"}\n"
    "options:\n"
    "  max_evaluations: 1e6\n"
    "  left_right: false\n"
    "  jobs: 2\n";

static void test_every_shape(void **state)
{
    (void)state;
    rf_study s;
    rf_error err;
    rf_status st = load(all_shapes, &s, &err);
    if (st != RF_OK)
        fail_msg("%s", err.msg);
    assert_string_equal(s.name, "shapes");
    assert_int_equal(s.scheme, RF_TM_GENERAL);
    assert_int_equal(s.levels, M);
    assert_int_equal(s.n_params, 9);
    assert_int_equal(s.max_evaluations, 1000000);
    assert_int_equal(s.left_right, 0);
    assert_int_equal(s.jobs, 2);
    /* file order is the model's input order */
    const char *order[] = {"x1", "x2", "x3", "x4", "x5", "x6", "x7", "x8", "x9"};
    for (size_t i = 0; i < 9; i++)
        assert_string_equal(s.param_names[i], order[i]);
    assert_string_equal(s.param_units[1], "m");
    assert_string_equal(s.param_units[0], "");
    assert_int_equal(s.param_class[8], RF_MONO_NONMONOTONIC);
    assert_int_equal(s.param_class[0], RF_MONO_AUTO);
    assert_int_equal(s.param_line[0], 5);
    assert_int_equal(s.param_line[8], 13);

    rf_fuzzy f;
    rf_fuzzy_tfn(&f, 2, 1, 1, NULL);
    assert_same_cuts(&s.inputs[find_param(&s, "x1")], &f);
    rf_fuzzy_free(&f);
    rf_fuzzy_trapezoid(&f, 0.05, 0.45, 0.55, 0.95, NULL);
    assert_same_cuts(&s.inputs[find_param(&s, "x2")], &f);
    rf_fuzzy_free(&f);
    rf_fuzzy_interval(&f, 1, 2, NULL);
    assert_same_cuts(&s.inputs[find_param(&s, "x3")], &f);
    rf_fuzzy_free(&f);
    rf_fuzzy_gaussian(&f, 10, 1, 2, 3, NULL);
    assert_same_cuts(&s.inputs[find_param(&s, "x4")], &f);
    rf_fuzzy_free(&f);
    rf_fuzzy_crisp(&f, 1.5, NULL);
    assert_same_cuts(&s.inputs[find_param(&s, "x5")], &f);
    rf_fuzzy_free(&f);
    const double px[] = {0, 1, 3}, pm[] = {0, 1, 0};
    rf_fuzzy_points(&f, 3, px, pm, NULL);
    assert_same_cuts(&s.inputs[find_param(&s, "x6")], &f);
    rf_fuzzy_free(&f);
    const double cm[] = {0, 0.5, 1}, cl[] = {1, 1.5, 2}, cu[] = {3, 2.5, 2};
    rf_fuzzy_cuts(&f, 3, cm, cl, cu, NULL);
    assert_same_cuts(&s.inputs[find_param(&s, "x7")], &f);
    rf_fuzzy_free(&f);
    rf_fuzzy_crisp(&f, 4.25, NULL);
    assert_same_cuts(&s.inputs[find_param(&s, "x8")], &f);
    rf_fuzzy_free(&f);
    rf_fuzzy_tfn(&f, 0, 1, 2, NULL);
    assert_same_cuts(&s.inputs[find_param(&s, "x9")], &f);
    rf_fuzzy_free(&f);

    /* the model is built, in file order, and evaluates */
    assert_int_equal(s.model_kind, RF_STUDY_MODEL_FORMULA);
    assert_int_equal(s.model.n_inputs, 9);
    assert_int_equal(s.model.n_outputs, 2);
    assert_string_equal(s.model.output_names[0], "y");
    assert_string_equal(s.model.output_names[1], "z");
    double x[9] = {2, 3, 4, 0, 0, 0, 0, 0, 0}, y[2];
    assert_int_equal(rf_model_eval(&s.model, x, y, &err), RF_OK);
    assert_close(y[0], 10, 1e-15);
    assert_close(y[1], 0, 0);

    rf_tm_options opt;
    rf_study_tm_options(&s, &opt);
    assert_int_equal(opt.scheme, RF_TM_GENERAL);
    assert_int_equal(opt.levels, M);
    assert_int_equal(opt.left_right, 0);
    assert_ptr_equal(opt.force_class, s.param_class);
    rf_study_free(&s);
    rf_study_free(&s); /* idempotent */
}

static void test_defaults_and_file(void **state)
{
    (void)state;
    char dir[] = "/tmp/rockfuzz_study_XXXXXX", path[64];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/my_study.yaml", dir);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs("parameters:\n  a: {tfn: [1, 0.5, 0.5]}\nmodel:\n  formula: \"2*a\"\n", f);
    fclose(f);
    rf_study s;
    rf_error err;
    assert_int_equal(rf_study_load(path, &s, &err), RF_OK);
    assert_int_equal(s.scheme, RF_TM_REDUCED);
    assert_int_equal(s.levels, 10);
    assert_int_equal(s.left_right, 1);
    assert_int_equal(s.max_evaluations, 100000);
    assert_string_equal(s.model.output_names[0], "y");
    assert_string_equal(s.dir, dir);
    assert_string_equal(s.name, "my_study"); /* name defaults to the file name */
    rf_study_free(&s);
    unlink(path);
    rmdir(dir);

    assert_int_equal(rf_study_load("/nonexistent/dir/study.yaml", &s, &err), RF_EIO);
    assert_non_null(strstr(err.msg, "/nonexistent/dir/study.yaml"));
    rf_study_free(&s);
}

/* ---- errors: each case names the line, the field and the value ---- */

typedef struct {
    const char *what;
    const char *text;
    int line;
    const char *field;   /* must appear in the message */
    const char *value;   /* must appear in the message */
} bad_case;

static const bad_case bad_cases[] = {
    {"unknown top-level key",
     "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel: {formula: {y: \"x1\"}}\ncolour: red\n", 5, "colour",
     "unknown key"},
    {"unknown parameter key",
     "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1], colour: red}\nmodel: {formula: {y: \"x1\"}}\n", 3,
     "parameters.x1.colour", "unknown key"},
    {"string where a number is expected",
     "levels: 4\nparameters:\n  x1: {tfn: [2, abc, 1]}\nmodel: {formula: {y: \"x1\"}}\n", 3,
     "parameters.x1.tfn[1]", "abc"},
    {"quoted number",
     "levels: \"4\"\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel: {formula: {y: \"x1\"}}\n", 1, "levels",
     "\"4\""},
    {"list where a number is expected",
     "levels: 4\nparameters:\n  x1: {crisp: [1, 2]}\nmodel: {formula: {y: \"x1\"}}\n", 3, "parameters.x1.crisp",
     "[1, 2]"},
    {"non-nesting cuts",
     "levels: 4\nparameters:\n  x1:\n    cuts:\n      mu: [0, 0.5, 1]\n      lower: [1, 0.5, 2]\n"
     "      upper: [3, 2.5, 2]\nmodel: {formula: {y: \"x1\"}}\n",
     6, "parameters.x1.cuts.lower[1]", "0.5"},
    {"negative deviation",
     "levels: 4\nparameters:\n  x0: 1\n  x1: {tfn: [2, -1, 1]}\nmodel: {formula: {y: \"x1\"}}\n", 4,
     "parameters.x1.tfn[1] = -1", "left deviation must be >= 0"},
    {"levels 0", "levels: 0\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel: {formula: {y: \"x1\"}}\n", 1,
     "levels = 0", ">= 1"},
    {"levels not an integer", "levels: 2.5\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel: {formula: {y: \"x1\"}}\n",
     1, "levels = 2.5", "integer"},
    {"unknown scheme",
     "scheme: fancy\nlevels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel: {formula: {y: \"x1\"}}\n", 1,
     "scheme = fancy", "general, reduced or extended"},
    {"formula with an unknown parameter",
     "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel:\n  formula:\n    y: \"x1\"\n    z: \"x1 + q\"\n", 7,
     "model.formula.z", "q"},
    {"duplicate parameter name",
     "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\n  x1: {crisp: 2}\nmodel: {formula: {y: \"x1\"}}\n", 4,
     "parameters.x1", "duplicate key 'x1' (first given at line 3)"},
    {"decreasing trapezoid",
     "levels: 4\nparameters:\n  x1: {trapezoid: [1, 3, 2, 4]}\nmodel: {formula: {y: \"x1\"}}\n", 3,
     "parameters.x1.trapezoid[2] = 2", "previous value 3"},
    {"reversed interval", "levels: 4\nparameters:\n  x1: {interval: [2, 1]}\nmodel: {formula: {y: \"x1\"}}\n", 3,
     "parameters.x1.interval[1] = 1", "must be >="},
    {"membership above 1",
     "levels: 4\nparameters:\n  x1: {points: [[0, 0], [1, 1.5], [2, 0]]}\nmodel: {formula: {y: \"x1\"}}\n", 3,
     "parameters.x1.points[1][1] = 1.5", "[0, 1]"},
    {"two shapes", "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1], crisp: 2}\nmodel: {formula: {y: \"x1\"}}\n", 3,
     "parameters.x1.crisp", "already"},
    {"no shape", "levels: 4\nparameters:\n  x1: {unit: m}\nmodel: {formula: {y: \"x1\"}}\n", 3, "parameters.x1",
     "no shape"},
    {"cutoff on a tfn", "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1], cutoff: 3}\nmodel: {formula: {y: \"x1\"}}\n",
     3, "parameters.x1.cutoff", "gaussian"},
    {"non-positive sigma",
     "levels: 4\nparameters:\n  x1: {gaussian: [2, 0, 1]}\nmodel: {formula: {y: \"x1\"}}\n", 3,
     "parameters.x1.gaussian[1] = 0", "sigma"},
    {"infinite value", "levels: 4\nparameters:\n  x1: {tfn: [.inf, 1, 1]}\nmodel: {formula: {y: \"x1\"}}\n", 3,
     "parameters.x1.tfn[0]", "number"},
    {"support end overflows",
     "levels: 4\nparameters:\n  x1: {tfn: [1e307, 1, 1.79e308]}\nmodel: {formula: {y: \"x1\"}}\n", 3,
     "parameters.x1.tfn", "peak + right deviation = inf"},
    {"spread below the resolution",
     "levels: 4\nparameters:\n  x1: {tfn: [1e16, 1e-5, 1e-5]}\nmodel: {formula: {y: \"x1\"}}\n", 3,
     "parameters.x1.tfn", "left deviation = 1e-05 vanishes"},
    {"support too narrow for the levels",
     "levels: 10\nparameters:\n  x1: {trapezoid: [1e16, 1e16, 1e16, 1.0000000000000008e16]}\n"
     "model: {formula: {y: \"x1\"}}\n",
     3, "parameters.x1", "too narrow for doubles"},
    {"bad class", "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1], class: wobbly}\nmodel: {formula: {y: \"x1\"}}\n",
     3, "parameters.x1.class = wobbly", "monotonic"},
    {"parameter name not an identifier",
     "levels: 4\nparameters:\n  1x: {tfn: [2, 1, 1]}\nmodel: {formula: {y: \"x\"}}\n", 3, "parameters.1x",
     "identifier"},
    {"unknown option",
     "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel: {formula: {y: \"x1\"}}\noptions: {speed: 2}\n", 5,
     "options.speed", "unknown option"},
    {"negative max_evaluations",
     "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel: {formula: {y: \"x1\"}}\noptions:\n"
     "  max_evaluations: -5\n",
     6, "options.max_evaluations = -5", "[0,"},
    {"left_right not a boolean",
     "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel: {formula: {y: \"x1\"}}\noptions: {left_right: maybe}\n",
     5, "options.left_right = maybe", "true or false"},
    {"unknown model", "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel:\n  spline: {y: 1}\n", 5,
     "model.spline", "unknown model"},
    {"program without argv",
     "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel:\n  program:\n    outputs: {y: {}}\n", 6,
     "model.program", "missing argv"},
    {"program template missing",
     "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel:\n  program:\n    argv: [cat, in.txt]\n"
     "    templates: {in.txt: no_such_template.tpl}\n    outputs: {y: {}}\n",
     7, "model.program.templates.in.txt", "no_such_template.tpl"},
    {"regex that makes regcomp explode",
     "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel:\n  program:\n    argv: [cat]\n"
     "    outputs: {y: {pattern: \"z=(.*++++++++)\"}}\n",
     7, "model.program.outputs.y.pattern", "adjacent repetition"},
    {"regex with nested repetitions",
     "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel:\n  program:\n    argv: [cat]\n"
     "    outputs: {y: {pattern: \"((((((((((((((a+)+)+)+)+)+)+)+)+)+)+)+)+)+)\"}}\n",
     7, "model.program.outputs.y.pattern", "too many repetitions"},
    {"impact input bound to an unknown name",
     "levels: 4\nparameters:\n  velocity: {tfn: [10, 1, 1]}\n  colour: {tfn: [1, 0.1, 0.1]}\nmodel:\n"
     "  impact: {solver: hunter}\n",
     4, "parameters.colour", "not an input of the impact model"},
    {"unknown impact solver",
     "levels: 4\nparameters:\n  velocity: {tfn: [10, 1, 1]}\nmodel:\n  impact: {solver: magic}\n", 5,
     "model.impact.solver = magic", "hertz"},
    {"ale auto is no longer a value (it meant off)",
     "levels: 4\nparameters:\n  velocity: {tfn: [10, 1, 1]}\nmodel:\n  impact: {solver: fem, ale: auto}\n", 5,
     "model.impact.ale = auto", "expected off | on"},
    {"an internal FE setting is not a key",
     "levels: 4\nparameters:\n  velocity: {tfn: [10, 1, 1]}\nmodel:\n  impact: {solver: fem, sphere_contact_3d: on}\n", 5,
     "model.impact.sphere_contact_3d", "unknown key"},
    {"threads not an integer",
     "levels: 4\nparameters:\n  velocity: {tfn: [10, 1, 1]}\nmodel:\n  impact: {solver: fem, threads: 1.5}\n", 5,
     "model.impact.threads = 1.5", "must be an integer"},
    {"impact input both fuzzy and crisp",
     "levels: 4\nparameters:\n  velocity: {tfn: [10, 1, 1]}\nmodel:\n  impact:\n    solver: hertz\n"
     "    velocity: 3\n",
     7, "model.impact.velocity = 3", "line 3"},
    {"impact support inadmissible",
     "levels: 4\nparameters:\n  boulder_poisson: {tfn: [0.25, 0.1, 0.3]}\nmodel:\n  impact: {solver: hertz}\n", 3,
     "parameters.boulder_poisson", "0.55"},
    {"unknown slope material",
     "levels: 4\nparameters:\n  velocity: {tfn: [10, 1, 1]}\nmodel:\n  impact: {slope_material: clay}\n", 5,
     "model.impact.slope_material = clay", "drucker_prager"},
    {"slope friction angle support inadmissible (degrees)",
     "levels: 4\nparameters:\n  slope_friction_angle: {tfn: [30, 10, 70]}\nmodel:\n"
     "  impact: {slope_material: drucker_prager, slope_cohesion: 1e4}\n",
     3, "parameters.slope_friction_angle", "100 deg"},
    {"negative FE end time",
     "levels: 4\nparameters:\n  velocity: {tfn: [10, 1, 1]}\nmodel:\n  impact: {solver: fem, end_time: -0.01}\n", 5,
     "model.impact.end_time = -0.01", "end_time = -0.01 must lie in [0, inf] [s]"},
    {"gravity given as a signed vector component",
     "levels: 4\nparameters:\n  velocity: {tfn: [10, 1, 1]}\nmodel:\n  impact: {solver: fem, gravity: -9.81}\n", 5,
     "model.impact.gravity = -9.81", "auto or a magnitude >= 0"},
    {"not YAML", "levels: 4\nparameters: [1, 2\n", 3, "not valid YAML", "column"},
    {"missing model", "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\n", 1, "model", "missing"},
    {"top level is a list", "- 1\n- 2\n", 1, "(top level)", "expected a mapping"},
    {"alias", "levels: 4\nparameters:\n  x1: &t {tfn: [2, 1, 1]}\n  x2: *t\nmodel: {formula: {y: \"x1\"}}\n", 4,
     "parameters.x2", "alias"},
    /* issue 12 point 9 */
    {"second document", "levels: 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel: {formula: {y: \"x1\"}}\n---\nlevels: 5\n",
     6, "second YAML document", "exactly one"},
    {"!!str number", "levels: !!str 4\nparameters:\n  x1: {tfn: [2, 1, 1]}\nmodel: {formula: {y: \"x1\"}}\n", 1,
     "levels = 4", "got a string"},
    {"!!str in a shape", "levels: 4\nparameters:\n  x1: {tfn: [2, !!str 1, 1]}\nmodel: {formula: {y: \"x1\"}}\n", 3,
     "parameters.x1.tfn[1]", "expected a number"},
};

/* A directory or a FIFO nobody writes to as the study file: refused, never
 * read as empty or waited on forever (issue 12 point 9). */
static void test_not_a_regular_file(void **state)
{
    (void)state;
    char dir[] = "/tmp/rockfuzz-test-study-XXXXXX";
    assert_non_null(mkdtemp(dir));
    rf_study s;
    rf_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(rf_study_load(dir, &s, &err), RF_EIO);
    assert_non_null(strstr(err.msg, "it is a directory"));
    rf_study_free(&s);
    char fifo[sizeof dir + 8];
    snprintf(fifo, sizeof fifo, "%s/fifo", dir);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    double t0 = (double)time(NULL);
    assert_int_equal(rf_study_load(fifo, &s, &err), RF_EIO);
    assert_true((double)time(NULL) - t0 < 30);
    assert_non_null(strstr(err.msg, "pipe or FIFO"));
    rf_study_free(&s);
    unlink(fifo);
    rmdir(dir);
}

static void test_bad_inputs(void **state)
{
    (void)state;
    int failures = 0;
    for (size_t k = 0; k < sizeof bad_cases / sizeof bad_cases[0]; k++) {
        const bad_case *b = &bad_cases[k];
        rf_study s;
        rf_error err;
        rf_status st = load(b->text, &s, &err);
        char where[64];
        snprintf(where, sizeof where, "study.yaml:%d:", b->line);
        if (st == RF_OK) {
            print_error("case '%s': accepted\n", b->what);
            failures++;
            rf_study_free(&s);
            continue;
        }
        if (!strstr(err.msg, where) || !strstr(err.msg, b->field) || !strstr(err.msg, b->value)) {
            print_error("case '%s': message \"%s\" lacks \"%s\", \"%s\" or \"%s\"\n", b->what, err.msg, where,
                        b->field, b->value);
            failures++;
        }
        /* a failed load leaves an empty study that is safe to free */
        assert_int_equal(s.n_params, 0);
        assert_null(s.model.eval);
        rf_study_free(&s);
    }
    assert_int_equal(failures, 0);
}

static void test_truncations_never_crash(void **state)
{
    (void)state; /* every prefix of a valid file loads or fails with a located message */
    size_t len = strlen(all_shapes);
    for (size_t n = 0; n < len; n++) {
        rf_study s;
        rf_error err;
        memset(&err, 0, sizeof err);
        if (rf_study_load_buffer("study.yaml", all_shapes, n, &s, &err) != RF_OK)
            assert_true(!strncmp(err.msg, "study.yaml:", 11));
        rf_study_free(&s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_shape),
        cmocka_unit_test(test_defaults_and_file),
        cmocka_unit_test(test_bad_inputs),
        cmocka_unit_test(test_truncations_never_crash),
        cmocka_unit_test(test_not_a_regular_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
