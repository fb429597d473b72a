/* test_formula.c - the muParser formula model: values against C, error
 * messages at creation, NaN reporting, concurrent evaluation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "rockfuzz/model.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

static const char *const params3[] = {"x1", "x2", "x3"};

static void assert_close(double got, double want)
{
    double tol = 1e-14 * fmax(1.0, fabs(want));
    if (fabs(got - want) > tol)
        fail_msg("got %.17g, want %.17g", got, want);
}

static void test_values_against_c(void **state)
{
    (void)state;
    const char *names[] = {"sum", "power", "trig", "cond", "minmax", "logexp", "zero"};
    const char *exprs[] = {"x1*x2 + x3", "x1^2 - 3*x2^3", "sin(x1)*cos(x2) + tan(x3/10)", "x1 > x2 ? x1 : x2",
                           "min(x1, x2) + max(x2, x3)", "exp(x1/4) + ln(x2) + log10(x3) + sqrt(x3) + abs(-x1)",
                           "x1 - x1"};
    rf_model m;
    rf_error err = {0};
    assert_int_equal(rf_formula_model_create(3, params3, 7, names, exprs, &m, &err), RF_OK);
    assert_int_equal(m.n_inputs, 3);
    assert_int_equal(m.n_outputs, 7);
    assert_int_equal(m.threads_per_eval, 1);
    assert_string_equal(m.output_names[2], "trig");
    assert_string_equal(m.output_units[2], "");
    assert_non_null(strstr(m.identity, "x1*x2 + x3"));

    const double xs[][3] = {{1.5, 2.0, 3.0}, {-2.0, 0.5, 7.25}, {3.0, 3.0, 1e-3}};
    for (size_t t = 0; t < 3; t++) {
        const double *x = xs[t];
        double y[7];
        assert_int_equal(rf_model_eval(&m, x, y, &err), RF_OK);
        assert_close(y[0], x[0] * x[1] + x[2]);
        assert_close(y[1], x[0] * x[0] - 3 * x[1] * x[1] * x[1]);
        assert_close(y[2], sin(x[0]) * cos(x[1]) + tan(x[2] / 10));
        assert_close(y[3], x[0] > x[1] ? x[0] : x[1]);
        assert_close(y[4], fmin(x[0], x[1]) + fmax(x[1], x[2]));
        assert_close(y[5], exp(x[0] / 4) + log(x[1]) + log10(x[2]) + sqrt(x[2]) + fabs(x[0]));
        assert_true(y[6] == 0.0);
    }
    rf_model_free(&m);
}

static void test_identity_depends_on_parameter_order(void **state)
{
    (void)state;
    const char *out[] = {"y"};
    const char *expr[] = {"x1 - x2"};
    const char *swapped[] = {"x2", "x1"};
    rf_model a, b;
    rf_error err = {0};
    assert_int_equal(rf_formula_model_create(2, params3, 1, out, expr, &a, &err), RF_OK);
    assert_int_equal(rf_formula_model_create(2, swapped, 1, out, expr, &b, &err), RF_OK);
    assert_string_not_equal(a.identity, b.identity);
    double x[2] = {5, 3}, ya, yb;
    assert_int_equal(rf_model_eval(&a, x, &ya, &err), RF_OK);
    assert_int_equal(rf_model_eval(&b, x, &yb, &err), RF_OK);
    assert_true(ya == 2.0 && yb == -2.0);
    rf_model_free(&a);
    rf_model_free(&b);
}

static void test_unknown_identifier(void **state)
{
    (void)state;
    const char *out[] = {"ok", "y"};
    const char *expr[] = {"x1", "x1*x9"};
    rf_model m;
    rf_error err = {0};
    assert_int_equal(rf_formula_model_create(2, params3, 2, out, expr, &m, &err), RF_EINVAL);
    print_message("message: %s\n", err.msg);
    assert_string_equal(err.msg, "output 'y': unknown parameter 'x9' near \"x1*x9\" (known: x1, x2)");
    assert_null(m.ctx);
}

static void test_syntax_error(void **state)
{
    (void)state;
    const char *out[] = {"y"};
    const char *bad[][1] = {{"x1*/x2"}, {"(x1 + x2"}, {"x1 +"}, {"sin(x1, x2)"}, {"x1, x2"}};
    for (size_t t = 0; t < sizeof bad / sizeof bad[0]; t++) {
        rf_model m;
        rf_error err = {0};
        rf_status st = rf_formula_model_create(2, params3, 1, out, bad[t], &m, &err);
        print_message("%-12s -> %s\n", bad[t][0], err.msg);
        assert_true(st == RF_EPARSE);
        assert_non_null(strstr(err.msg, "output 'y'"));
        assert_non_null(strstr(err.msg, bad[t][0]));
    }
    rf_model m;
    rf_error err = {0};
    assert_int_equal(rf_formula_model_create(2, params3, 1, out, bad[0], &m, &err), RF_EPARSE);
    assert_non_null(strstr(err.msg, "syntax error at position 4: Unexpected operator \"/\" found, near \"x1*/x2\""));
}

/* A long expression must not push muParser's reason out of the message
 * (issue 12): the reason comes first, then an excerpt around the position. */
static void test_long_expression_error(void **state)
{
    (void)state;
    static char expr[6000];
    size_t n = 0;
    for (; n + 3 < 5000; n += 3)
        memcpy(expr + n, "x1+", 3);
    memcpy(expr + n, "x2)", 4);
    const char *out[] = {"y"};
    const char *e[] = {expr};
    rf_model m;
    rf_error err = {0};
    assert_int_equal(rf_formula_model_create(2, params3, 1, out, e, &m, &err), RF_EPARSE);
    print_message("%s\n", err.msg);
    assert_true(strlen(err.msg) < 400);
    assert_non_null(strstr(err.msg, "Unexpected parenthesis"));
    assert_non_null(strstr(err.msg, "near \"..."));
    assert_non_null(strstr(err.msg, "x2)\""));
}

static void test_empty_and_duplicate(void **state)
{
    (void)state;
    rf_model m;
    rf_error err = {0};
    const char *out[] = {"y", "y"};
    const char *expr[] = {"  ", "x1"};
    assert_int_equal(rf_formula_model_create(1, params3, 1, out, expr, &m, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "empty formula"));
    const char *expr2[] = {"x1", "x1"};
    assert_int_equal(rf_formula_model_create(1, params3, 2, out, expr2, &m, &err), RF_EINVAL);
    assert_non_null(strstr(err.msg, "defined twice"));
}

static void test_nan_is_an_error(void **state)
{
    (void)state;
    const char *out[] = {"root"};
    const char *expr[] = {"sqrt(x1)"};
    rf_model m;
    rf_error err = {0};
    assert_int_equal(rf_formula_model_create(1, params3, 1, out, expr, &m, &err), RF_OK);
    double x = -4, y;
    assert_int_equal(rf_model_eval(&m, &x, &y, &err), RF_EMODEL);
    print_message("message: %s\n", err.msg);
    assert_non_null(strstr(err.msg, "output 'root'"));
    assert_non_null(strstr(err.msg, "x1=-4"));
    x = 16;
    assert_int_equal(rf_model_eval(&m, &x, &y, &err), RF_OK);
    assert_true(y == 4.0);
    rf_model_free(&m);

    const char *inv[] = {"1/(x1 - 2)"};
    assert_int_equal(rf_formula_model_create(1, params3, 1, out, inv, &m, &err), RF_OK);
    x = 2;
    assert_int_equal(rf_model_eval(&m, &x, &y, &err), RF_EMODEL);
    print_message("message: %s\n", err.msg);
    assert_string_equal(err.msg, "output 'root': \"1/(x1 - 2)\" is infinite at (x1=2)");
    rf_model_free(&m);
}

/* Many outputs, many parameters: y_k = sum_i (k+1) * p_i^(1 + (i+k)%3). */
#define N_PARAMS 12
#define N_OUTPUTS 40
static void test_many_outputs(void **state)
{
    (void)state;
    char pnames[N_PARAMS][16], onames[N_OUTPUTS][16], exprs[N_OUTPUTS][512];
    const char *pp[N_PARAMS], *op[N_OUTPUTS], *ep[N_OUTPUTS];
    for (int i = 0; i < N_PARAMS; i++) {
        snprintf(pnames[i], sizeof pnames[i], "p_%d", i);
        pp[i] = pnames[i];
    }
    for (int k = 0; k < N_OUTPUTS; k++) {
        snprintf(onames[k], sizeof onames[k], "out%d", k);
        size_t used = 0;
        for (int i = 0; i < N_PARAMS; i++)
            used += (size_t)snprintf(exprs[k] + used, sizeof exprs[k] - used, "%s%d*p_%d^%d", i ? " + " : "", k + 1,
                                     i, 1 + (i + k) % 3);
        op[k] = onames[k];
        ep[k] = exprs[k];
    }
    rf_model m;
    rf_error err = {0};
    assert_int_equal(rf_formula_model_create(N_PARAMS, pp, N_OUTPUTS, op, ep, &m, &err), RF_OK);
    double x[N_PARAMS], y[N_OUTPUTS];
    for (int i = 0; i < N_PARAMS; i++)
        x[i] = 0.5 + 0.25 * i;
    assert_int_equal(rf_model_eval(&m, x, y, &err), RF_OK);
    for (int k = 0; k < N_OUTPUTS; k++) {
        double want = 0;
        for (int i = 0; i < N_PARAMS; i++)
            want += (k + 1) * pow(x[i], 1 + (i + k) % 3);
        assert_true(fabs(y[k] - want) <= 1e-13 * want);
    }
    rf_model_free(&m);
}

/* Several threads evaluate the same model at different points; any shared
 * parser would mix their variables up. */
typedef struct {
    const rf_model *m;
    int id;
    int failures;
} thread_arg;

static void *evaluate_many(void *p)
{
    thread_arg *a = p;
    rf_error err = {0};
    for (int it = 0; it < 20000; it++) {
        double x[3] = {a->id + 1.0, it * 0.001, 2.0 + a->id};
        double y[2];
        if (rf_model_eval(a->m, x, y, &err) != RF_OK || y[0] != x[0] * x[1] + x[2] ||
            fabs(y[1] - sin(x[0]) * x[2]) > 1e-15 * fabs(x[2]))
            a->failures++;
    }
    return NULL;
}

static void test_concurrent_evaluation(void **state)
{
    (void)state;
    const char *out[] = {"y", "z"};
    const char *expr[] = {"x1*x2 + x3", "sin(x1)*x3"};
    rf_model m;
    rf_error err = {0};
    assert_int_equal(rf_formula_model_create(3, params3, 2, out, expr, &m, &err), RF_OK);
    enum { N_THREADS = 4 };
    pthread_t th[N_THREADS];
    thread_arg args[N_THREADS];
    for (int t = 0; t < N_THREADS; t++) {
        args[t] = (thread_arg){&m, t, 0};
        assert_int_equal(pthread_create(&th[t], NULL, evaluate_many, &args[t]), 0);
    }
    for (int t = 0; t < N_THREADS; t++) {
        pthread_join(th[t], NULL);
        assert_int_equal(args[t].failures, 0);
    }
    rf_model_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_values_against_c),
        cmocka_unit_test(test_identity_depends_on_parameter_order),
        cmocka_unit_test(test_unknown_identifier),
        cmocka_unit_test(test_syntax_error),
        cmocka_unit_test(test_long_expression_error),
        cmocka_unit_test(test_empty_and_duplicate),
        cmocka_unit_test(test_nan_is_an_error),
        cmocka_unit_test(test_many_outputs),
        cmocka_unit_test(test_concurrent_evaluation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
