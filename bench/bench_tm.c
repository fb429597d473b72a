/* bench_tm.c - cost of the TM itself (grid, cache, evaluation dispatch,
 * retransformation, analysis) on a model that costs almost nothing.
 *
 * Cases of the fuzzy-core issue: general form n = 4, m = 10 (39 974 grid
 * points) and reduced form n = 10, m = 10 (10 241).  Prints the wall time of
 * the TM run, of the analysis, the model's own time measured separately on
 * the same points, the overhead per requested evaluation (cache and
 * analysis on, serial path; goal of issue 9: <= 12 ns incl. analysis), the
 * runner's speed-up from 1 to 2 workers on a ~1 us model, and the peak RSS.
 * Wall times on a shared machine are noisy: compare within one run, and use
 * callgrind instruction counts for small changes (docs/tm-internals.md).
 * Each case line ends with a checksum (FNV-1a) of the bits of every cut,
 * bound input, monotonicity verdict and influence measure: a change to the
 * TM's code must leave it unchanged.
 * The general and reduced cases run again through the runner (1 and 2
 * threads): the path of `rockfuzz run`, whose runner times every evaluation.
 * Usage: bench_tm [repeats] [case: general|reduced|extended|lr|runner|threads|all]
 * (one case alone, e.g. under callgrind). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "core/util.h"
#include "rockfuzz/analysis.h"
#include "rockfuzz/runner.h"
#include "rockfuzz/tm.h"


typedef struct {
    size_t n;
} cheap_ctx;

static uint64_t fnv(uint64_t h, const void *p, size_t bytes)
{
    const unsigned char *b = p;
    for (size_t k = 0; k < bytes; k++)
        h = (h ^ b[k]) * UINT64_C(0x100000001b3);
    return h;
}

/* Bits of every result and influence measure (see the header). */
static uint64_t checksum(const rf_tm_result *r, const rf_analysis *a)
{
    size_t n = r->n_inputs, no = r->n_outputs, m = r->levels, c = no * (m + 1), nk = n * no;
    uint64_t h = UINT64_C(0xcbf29ce484222325);
    h = fnv(h, r->lo, c * sizeof(double));
    h = fnv(h, r->hi, c * sizeof(double));
    h = fnv(h, r->x_lo, c * n * sizeof(double));
    h = fnv(h, r->x_hi, c * n * sizeof(double));
    h = fnv(h, r->nominal, no * sizeof(double));
    h = fnv(h, r->monotonicity, nk * sizeof *r->monotonicity);
    h = fnv(h, r->input_class, n * sizeof *r->input_class);
    h = fnv(h, a->gain, nk * m * sizeof(double));
    const double *per_input[] = {a->mean_gain, a->std_gain, a->kappa, a->rho,
                                 a->kappa_left, a->kappa_right, a->rho_left, a->rho_right};
    for (size_t k = 0; k < sizeof per_input / sizeof *per_input; k++)
        h = fnv(h, per_input[k], nk * sizeof(double));
    h = fnv(h, a->degree_of_uncertainty, no * sizeof(double));
    return fnv(h, a->interaction, no * sizeof(double));
}

static rf_status cheap_eval(void *ctx, const double *x, double *y, rf_error *err)
{
    (void)err;
    const cheap_ctx *c = ctx;
    double s = 0, p = 1;
    for (size_t i = 0; i < c->n; i++) {
        s += x[i];
        p *= 1 + 0.01 * x[i];
    }
    y[0] = s;
    y[1] = p;
    return RF_OK;
}

/* jobs = 0: the serial path (no evaluator); otherwise through the runner
 * with that many threads, as `rockfuzz run` evaluates (it also times every
 * evaluation).  The model alone is always timed on one thread. */
static void bench_case(const char *label, rf_tm_scheme scheme, size_t n, size_t m, int lr, int jobs, int repeats)
{
    rf_fuzzy in[16];
    for (size_t i = 0; i < n; i++)
        rf_fuzzy_tfn(&in[i], 1.0 + (double)i, 0.1 + 0.01 * (double)i, 0.2, NULL);
    cheap_ctx ctx = {n};
    rf_model model = {0};
    const char *names[] = {"sum", "product"};
    rf_model_init_outputs(&model, 2, names, NULL, NULL);
    model.n_inputs = n;
    model.eval = cheap_eval;
    model.ctx = &ctx;
    rf_tm_options opt;
    rf_tm_options_default(&opt);
    opt.scheme = scheme;
    opt.levels = m;
    opt.left_right = lr;
    rf_runner runner;
    rf_runner_init(&runner);
    runner.jobs = jobs;
    rf_evaluator ev = rf_runner_evaluator(&runner);
    opt.evaluator = jobs ? &ev : NULL;
    double best_run = 1e30, best_an = 1e30, best_model = 1e30;
    size_t requested = 0, distinct = 0;
    uint64_t sum = 0;
    for (int r = 0; r < repeats; r++) {
        rf_tm_result res;
        rf_error err;
        double t0 = rf_monotonic_seconds();
        if (rf_tm_run(in, n, &model, &opt, &res, &err)) {
            fprintf(stderr, "%s\n", err.msg);
            exit(1);
        }
        double t1 = rf_monotonic_seconds();
        rf_analysis an;
        rf_analysis_compute(&res, &an, NULL);
        double t2 = rf_monotonic_seconds();
        sum = checksum(&res, &an);
        requested = res.requested;
        distinct = res.distinct;
        /* the model's own cost on the same number of points */
        double x[16], y[2], sink = 0;
        double t3 = rf_monotonic_seconds();
        for (size_t p = 0; p < distinct; p++) {
            for (size_t i = 0; i < n; i++)
                x[i] = 1.0 + (double)((p + i) % 7);
            cheap_eval(&ctx, x, y, NULL);
            sink += y[1];
        }
        double t4 = rf_monotonic_seconds();
        if (sink == 42.4242)
            puts("");
        best_run = t1 - t0 < best_run ? t1 - t0 : best_run;
        best_an = t2 - t1 < best_an ? t2 - t1 : best_an;
        best_model = t4 - t3 < best_model ? t4 - t3 : best_model;
        rf_analysis_free(&an);
        rf_tm_result_free(&res);
    }
    double overhead = (best_run - best_model) / (double)requested * 1e9;
    printf("%-28s requested %7zu distinct %7zu | TM run %8.3f ms  analysis %7.3f ms  model alone %7.3f ms | "
           "TM overhead %5.1f ns/requested evaluation (%5.1f ns incl. analysis) | checksum %016llx\n",
           label, requested, distinct, best_run * 1e3, best_an * 1e3, best_model * 1e3, overhead,
           (best_run + best_an - best_model) / (double)requested * 1e9, (unsigned long long)sum);
    rf_model_free(&model);
}

/* A model that costs about a microsecond: the speed-up with a second worker. */
static rf_status busy_eval(void *ctx, const double *x, double *y, rf_error *err)
{
    (void)ctx;
    (void)err;
    double s = x[0];
    for (int k = 0; k < 400; k++)
        s = s * 0.999 + x[k % 4] * 1e-3;
    y[0] = s;
    y[1] = x[1];
    return RF_OK;
}

static void bench_threads(int repeats)
{
    rf_fuzzy in[4];
    for (size_t i = 0; i < 4; i++)
        rf_fuzzy_tfn(&in[i], 1.0 + (double)i, 0.1, 0.2, NULL);
    rf_model model = {0};
    const char *names[] = {"a", "b"};
    rf_model_init_outputs(&model, 2, names, NULL, NULL);
    model.n_inputs = 4;
    model.eval = busy_eval;
    double t1 = 0;
    for (int jobs = 1; jobs <= 2; jobs++) {
        rf_runner runner;
        rf_runner_init(&runner);
        runner.jobs = jobs;
        rf_evaluator ev = rf_runner_evaluator(&runner);
        rf_tm_options opt;
        rf_tm_options_default(&opt);
        opt.scheme = RF_TM_GENERAL;
        opt.levels = 10;
        opt.left_right = 0;
        opt.evaluator = &ev;
        double best = 1e30;
        size_t distinct = 0;
        for (int r = 0; r < repeats; r++) {
            rf_tm_result res;
            rf_error err;
            double t0 = rf_monotonic_seconds();
            if (rf_tm_run(in, 4, &model, &opt, &res, &err)) {
                fprintf(stderr, "%s\n", err.msg);
                exit(1);
            }
            double t = rf_monotonic_seconds() - t0;
            best = t < best ? t : best;
            distinct = res.distinct;
            rf_tm_result_free(&res);
        }
        if (jobs == 1)
            t1 = best;
        printf("general n=4 m=10, ~1 us model  jobs %d: %7.2f ms for %zu evaluations (%.2f us each), speed-up %.2f\n",
               jobs, best * 1e3, distinct, best / (double)distinct * 1e6, t1 / best);
    }
    rf_model_free(&model);
}

int main(int argc, char **argv)
{
    int repeats = argc > 1 ? atoi(argv[1]) : 5;
    const char *only = argc > 2 ? argv[2] : "all";
    int all = !strcmp(only, "all");
    if (all || !strcmp(only, "general"))
        bench_case("general n=4 m=10", RF_TM_GENERAL, 4, 10, 0, 0, repeats);
    if (all || !strcmp(only, "reduced"))
        bench_case("reduced n=10 m=10", RF_TM_REDUCED, 10, 10, 0, 0, repeats);
    if (all || !strcmp(only, "extended"))
        bench_case("extended n=4 m=10 (probe)", RF_TM_EXTENDED, 4, 10, 0, 0, repeats);
    if (all || !strcmp(only, "lr"))
        bench_case("reduced n=6 m=10 + LR grid", RF_TM_REDUCED, 6, 10, 1, 0, repeats);
    for (int jobs = 1; jobs <= 2 && (all || !strcmp(only, "runner")); jobs++) {
        bench_case(jobs == 1 ? "general, runner 1 thread" : "general, runner 2 threads", RF_TM_GENERAL, 4, 10, 0,
                   jobs, repeats);
        bench_case(jobs == 1 ? "reduced, runner 1 thread" : "reduced, runner 2 threads", RF_TM_REDUCED, 10, 10, 0,
                   jobs, repeats);
    }
    if (all || !strcmp(only, "threads"))
        bench_threads(repeats);
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    printf("peak RSS %.1f MiB\n", (double)ru.ru_maxrss / 1024.0);
    return 0;
}
