/* test_report.c - the report files: every file is written, NaN becomes
 * JSON null / CSV nan, and result.json lands only when everything else did
 * (faults injected: an output path that cannot be created, a CSV path that
 * is a directory, a stale result.json from an earlier run). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <sys/stat.h>
#include <unistd.h>

#include "rockfuzz/analysis.h"
#include "rockfuzz/report.h"
#include "rockfuzz/study.h"
#include "study/report_internal.h"
#include "test_util.h"

/* Under -DROCKFUZZ_SANITIZE=ON: fontconfig (loaded by cairo for the plots)
 * keeps process-lifetime caches; they are not leaks of ours. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:libfontconfig.so\n"; }

typedef struct {
    rf_study study;
    rf_tm_result res;
    rf_analysis an;
    char dir[64];
} fixture;

static const char *study_text = "name: rep\n"
                                "levels: 4\n"
                                "parameters:\n"
                                "  x1: {tfn: [2, 1, 1]}\n"
                                "  x2: {tfn: [3, 1, 2], unit: \"kg\"}\n"
                                "  x3: 7\n"
                                "model:\n"
                                "  formula: {\"f\": \"x1*x2\", \"g/h\": \"x1 - x1\"}\n";

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    rf_error err;
    if (rf_study_load_buffer("rep.yaml", study_text, strlen(study_text), &f->study, &err) != RF_OK) {
        print_error("%s\n", err.msg);
        return -1;
    }
    rf_tm_options opt;
    rf_study_tm_options(&f->study, &opt);
    if (rf_tm_run(f->study.inputs, f->study.n_params, &f->study.model, &opt, &f->res, &err) != RF_OK ||
        rf_analysis_compute(&f->res, &f->an, &err) != RF_OK) {
        print_error("%s\n", err.msg);
        return -1;
    }
    snprintf(f->dir, sizeof f->dir, "/tmp/rockfuzz_report_XXXXXX");
    if (!mkdtemp(f->dir))
        return -1;
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", f->dir);
    if (system(cmd) != 0)
        return -1;
    rf_analysis_free(&f->an);
    rf_tm_result_free(&f->res);
    rf_study_free(&f->study);
    free(f);
    return 0;
}

static char *slurp(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return NULL;
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    char *buf = calloc((size_t)n + 1, 1);
    if (fread(buf, 1, (size_t)n, fp) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    fclose(fp);
    return buf;
}

static int exists_nonempty(const char *dir, const char *name)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    struct stat sb;
    return stat(path, &sb) == 0 && sb.st_size > 0;
}

static void test_all_files(void **state)
{
    fixture *f = *state;
    char out[128];
    snprintf(out, sizeof out, "%s/all", f->dir);
    rf_report_options ro;
    rf_report_options_default(&ro);
    ro.wall_seconds = 1.5;
    ro.jobs = 3;
    rf_error err;
    assert_int_equal(rf_report_write(out, &f->study, &f->res, &f->an, &ro, &err), RF_OK);
    const char *files[] = {"result.json",     "inputs.csv",         "cuts_f.csv",         "cuts_g_h.csv",
                           "influence_f.csv", "input_x1.png",       "input_x2.svg",       "input_x3.png",
                           "output_f.png",    "influence_f.png",    "influence_lr_f.svg"};
    for (size_t k = 0; k < sizeof files / sizeof files[0]; k++)
        if (!exists_nonempty(out, files[k]))
            fail_msg("%s missing or empty", files[k]);
    assert_false(exists_nonempty(out, "result.json.tmp"));

    char path[256];
    snprintf(path, sizeof path, "%s/result.json", out);
    char *json = slurp(path);
    assert_non_null(json);
    assert_non_null(strstr(json, "\"g/h\": {")); /* names kept verbatim in JSON */
    assert_non_null(strstr(json, "\"x3\": {\"rho\": null")); /* crisp input: NaN -> null */
    assert_non_null(strstr(json, "\"jobs\": 3"));
    assert_non_null(strstr(json, "\"wall_seconds\": 1.5"));
    assert_non_null(strstr(json, "\"unit\": \"kg\""));
    assert_non_null(strstr(json, "\"g/h\": {\n      \"unit\": \"\",\n      \"status\": \"zero\""));
    assert_non_null(strstr(json, "\"f\": {\n      \"unit\": \"\",\n      \"status\": \"shown\""));
    assert_null(strstr(json, "tm_spec")); /* a file that is not in the project */
    assert_non_null(strstr(json, "docs/user-guide.md section 3"));
    assert_null(strstr(json, "nan"));
    assert_null(strstr(json, ": inf"));
    assert_null(strstr(json, "-inf"));
    free(json);

    snprintf(path, sizeof path, "%s/influence_f.csv", out);
    char *csv = slurp(path);
    assert_non_null(strstr(csv, "\nx3,nan,"));
    free(csv);
    snprintf(path, sizeof path, "%s/cuts_f.csv", out);
    csv = slurp(path);
    assert_non_null(strstr(csv, "mu,lower,upper\n0,2,15\n0.25,2.8125,12.375\n"));
    free(csv);
}

static void test_no_result_after_a_failure(void **state)
{
    fixture *f = *state;
    rf_report_options ro;
    rf_report_options_default(&ro);
    ro.plots = 0;
    rf_error err;
    char out[128], path[256];

    /* the output directory cannot be created: its parent is a regular file
     * (missing parents are created, like mkdir -p) */
    snprintf(path, sizeof path, "%s/a-file", f->dir);
    FILE *fp = fopen(path, "w");
    assert_non_null(fp);
    fclose(fp);
    snprintf(out, sizeof out, "%s/a-file/parent", f->dir);
    assert_int_equal(rf_report_write(out, &f->study, &f->res, &f->an, &ro, &err), RF_EIO);
    assert_non_null(strstr(err.msg, out));
    unlink(path);
    snprintf(out, sizeof out, "%s/missing/parent", f->dir);
    assert_int_equal(rf_report_write(out, &f->study, &f->res, &f->an, &ro, &err), RF_OK);
    assert_true(exists_nonempty(out, "result.json"));

    /* a complete earlier run, then a rerun whose CSV cannot be written */
    snprintf(out, sizeof out, "%s/rerun", f->dir);
    assert_int_equal(rf_report_write(out, &f->study, &f->res, &f->an, &ro, &err), RF_OK);
    assert_true(exists_nonempty(out, "result.json"));
    snprintf(path, sizeof path, "%s/cuts_f.csv", out);
    assert_int_equal(unlink(path), 0);
    assert_int_equal(mkdir(path, 0777), 0); /* fopen fails on a directory */
    assert_int_not_equal(rf_report_write(out, &f->study, &f->res, &f->an, &ro, &err), RF_OK);
    assert_non_null(strstr(err.msg, "cuts_f.csv"));
    assert_false(exists_nonempty(out, "result.json"));      /* the stale result is gone */
    assert_false(exists_nonempty(out, "result.json.tmp"));
    rmdir(path);
}

static void test_summary(void **state)
{
    fixture *f = *state;
    char *buf = NULL;
    size_t size = 0;
    FILE *fp = open_memstream(&buf, &size);
    rf_report_print_summary(fp, &f->study, &f->res, &f->an);
    fclose(fp);
    assert_non_null(strstr(buf, "Output f"));
    assert_non_null(strstr(buf, "n/a (input has zero width)"));
    assert_non_null(strstr(buf, "level-0 lower bound 2 at: x1=1 x2=2 x3=7"));
    assert_non_null(strstr(buf, "degree of uncertainty"));
    free(buf);
}

/* The console summary: no second study header, no "nan", the zero output in one
 * line, and the answer: f = x1*x2 on x1 in [1, 3], x2 in [2, 5] is [2, 15] at
 * membership 0 with nominal 2*3 = 6. */
static void test_summary_reads_right(void **state)
{
    fixture *f = *state;
    char *buf = NULL;
    size_t size = 0;
    FILE *fp = open_memstream(&buf, &size);
    rf_report_print_summary(fp, &f->study, &f->res, &f->an);
    fclose(fp);
    assert_null(strstr(buf, "Study '")); /* the run printed it once before evaluating */
    assert_null(strstr(buf, "nan"));
    assert_null(strstr(buf, "Output g/h"));
    assert_non_null(strstr(buf, "\ng/h: 0 at every point"));
    const char *answer = strstr(buf, "\nAnswer ");
    assert_non_null(answer);
    assert_non_null(strstr(answer, "\n  f: 2 to 15, nominal 6; x"));
    assert_null(strstr(answer, "g/h"));
    free(buf);
}

static rf_status load(const char *text, rf_study *s)
{
    rf_error err;
    rf_status st = rf_study_load_buffer("t.yaml", text, strlen(text), s, &err);
    if (st != RF_OK)
        print_error("%s\n", err.msg);
    return st;
}

/* indentation_depth is reported only above 1 % of the smallest penetration_max
 * (here penetration_max = x1 >= 1, support [1, 3], so the floor is 0.01), and
 * never where plastic_work is 0 at every point (elastic bodies: no crater). */
static void test_indentation_floor(void **state)
{
    (void)state;
    const char *fmt = "levels: 2\nparameters:\n  x1: {tfn: [2, 1, 1]}\n  x2: {tfn: [3, 1, 2]}\n"
                      "model:\n  formula: {penetration_max: \"x1\", indentation_depth: \"%s\", plastic_work: \"%s\"}\n"
                      "options: {left_right: false}\n";
    /* |.| <= 0.004 < 0.01; 0.005 .. 0.0125 with plastic work; the same without */
    const char *expr[3][2] = {{"0.002*(x2 - 3)", "0.1"}, {"0.0025*x2", "0.1*x1"}, {"0.0025*x2", "x1 - x1"}};
    const rp_output_kind want[3] = {RP_OUTPUT_BELOW_FLOOR, RP_OUTPUT_SHOWN, RP_OUTPUT_BELOW_FLOOR};
    for (int c = 0; c < 3; c++) {
        char text[512];
        snprintf(text, sizeof text, fmt, expr[c][0], expr[c][1]);
        rf_study s;
        rf_tm_result res;
        rf_tm_options opt;
        rf_error err;
        assert_int_equal(load(text, &s), RF_OK);
        rf_study_tm_options(&s, &opt);
        assert_int_equal(rf_tm_run(s.inputs, s.n_params, &s.model, &opt, &res, &err), RF_OK);
        char why[512];
        assert_int_equal(rp_output_classify(&s, &res, 0, why, sizeof why), RP_OUTPUT_SHOWN);
        rp_output_kind k = rp_output_classify(&s, &res, 1, why, sizeof why);
        assert_int_equal(k, want[c]);
        if (c == 0)
            assert_non_null(strstr(why, "|value| <= 0.004 m, less than 1 % of the smallest penetration_max (1 m)"));
        if (c == 2)
            assert_non_null(strstr(why, "the bodies stay elastic (plastic_work 0 at every point)"));
        rf_tm_result_free(&res);
        rf_study_free(&s);
    }
}

/* The model settings: the impact model's that differ from its defaults, printed
 * %.6g; every setting of the other models. */
static void test_model_settings(void **state)
{
    (void)state;
    rf_study s;
    rp_setting set[128];
    int vs = -1;
    assert_int_equal(load("parameters:\n  radius: {tfn: [1, 0.05, 0.05]}\nmodel:\n  impact: {solver: fem, "
                          "refinement: 4, velocity: 12.3}\n",
                          &s),
                     RF_OK);
    size_t n = rp_model_settings(&s, set, 128, &vs);
    assert_int_equal(vs, 1);
    int refinement = 0, velocity = 0;
    for (size_t i = 0; i < n; i++) {
        refinement += !strcmp(set[i].key, "refinement_axi") && !strcmp(set[i].value, "4");
        velocity += !strcmp(set[i].key, "velocity") && !strcmp(set[i].value, "12.3");
        assert_true(strcmp(set[i].key, "grading") != 0); /* at its default 1.15: not listed */
        assert_null(strstr(set[i].value, "99999"));
    }
    assert_int_equal(refinement, 1);
    assert_int_equal(velocity, 1);
    assert_true(n <= 4); /* refinement_axi, refinement_3d, velocity (+ nothing else at a non-default) */
    rf_study_free(&s);

    assert_int_equal(load("parameters:\n  x: {tfn: [1, 0.5, 0.5]}\nmodel:\n  formula: {y: \"x*0.1\"}\n", &s),
                     RF_OK);
    n = rp_model_settings(&s, set, 128, &vs);
    assert_int_equal(vs, 0);
    assert_int_equal(n, 0); /* the formula is the model line: no half-parsed identity */
    rf_study_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_all_files),
        cmocka_unit_test(test_no_result_after_a_failure),
        cmocka_unit_test(test_summary),
        cmocka_unit_test(test_summary_reads_right),
        cmocka_unit_test(test_indentation_floor),
        cmocka_unit_test(test_model_settings),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
