/* test_util.h - helpers shared by the unit tests: a model made from a plain
 * C function, and relative comparison. */
#ifndef ROCKFUZZ_TEST_UTIL_H
#define ROCKFUZZ_TEST_UTIL_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/model.h"

typedef void (*test_fn)(const double *x, double *y);

typedef struct {
    test_fn fn;
    size_t calls; /* not thread-safe: only for serial tests */
} test_model_ctx;

static rf_status test_model_eval(void *ctx, const double *x, double *y, rf_error *err)
{
    (void)err;
    test_model_ctx *c = ctx;
    c->calls++;
    c->fn(x, y);
    return RF_OK;
}

static void test_model_destroy(void *ctx) { free(ctx); }

/* A model with n inputs and outputs named y0, y1, ... */
static inline rf_model test_model(size_t n, size_t n_out, test_fn fn)
{
    rf_model m;
    memset(&m, 0, sizeof m);
    m.n_inputs = n;
    const char *names[8] = {"y0", "y1", "y2", "y3", "y4", "y5", "y6", "y7"};
    rf_model_init_outputs(&m, n_out, names, NULL, NULL);
    test_model_ctx *c = calloc(1, sizeof *c);
    c->fn = fn;
    m.ctx = c;
    m.eval = test_model_eval;
    m.destroy = test_model_destroy;
    return m;
}

static inline size_t test_model_calls(const rf_model *m) { return ((test_model_ctx *)m->ctx)->calls; }

/* |a - b| <= rtol * max(|a|, |b|) (or <= rtol when both are tiny) */
static inline int close_rel(double a, double b, double rtol)
{
    double s = fmax(fabs(a), fabs(b));
    return fabs(a - b) <= rtol * (s > 1e-300 ? s : 1.0);
}

#define assert_close(a, b, rtol)                                                                            \
    do {                                                                                                    \
        double a_ = (a), b_ = (b);                                                                          \
        if (!close_rel(a_, b_, (rtol)))                                                                     \
            fail_msg("%s = %.17g, expected %.17g (rtol %g)", #a, a_, b_, (double)(rtol));                   \
    } while (0)

#endif
