/* progress.c - the progress line of a long single run (`rockfuzz impact` FE,
 * `rockfuzz trajectory` Monte Carlo):
 * on stderr, redrawn at most RF_CLI_PROGRESS_HZ times per second, first after
 * RF_CLI_PROGRESS_DELAY s (a short run draws nothing; the environment
 * variable ROCKFUZZ_PROGRESS_DELAY [s] sets another delay, as the tests do),
 * erased at the end.
 * Time left = wall time so far x (t_end - t) / t, from the simulated time t
 * and the solver's expected end t_end, or from the samples done of all. */
#include "cli/cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/util.h"

void rf_cli_progress_begin(rf_cli_progress *p, int on, const char *what)
{
    memset(p, 0, sizeof *p);
    p->on = on;
    p->what = what;
    p->start = rf_monotonic_seconds();
    const char *d = getenv("ROCKFUZZ_PROGRESS_DELAY");
    char *end = NULL;
    p->delay = d ? strtod(d, &end) : RF_CLI_PROGRESS_DELAY;
    if (!d || end == d || !(p->delay >= 0 && p->delay <= 3600))
        p->delay = RF_CLI_PROGRESS_DELAY;
}

/* The line: WHAT: DONE (share), elapsed, time left from the share done so far. */
static void draw(rf_cli_progress *p, double now, double done, double total, const char *text)
{
    p->last_draw = now;
    const double share = total > 0 ? fmin(done / total, 1) : 0;
    char el[32], left[32];
    rf_format_duration(now - p->start, RF_DURATION_WHOLE, el, sizeof el);
    rf_format_duration(done > 0 ? (now - p->start) * (total - done) / done : -1, RF_DURATION_WHOLE, left, sizeof left);
    fprintf(stderr, "\r  %s: %s (%.0f %%), elapsed %s, left ~%s\033[K", p->what, text, 100 * share, el, left);
    fflush(stderr);
    p->drawn = 1;
}

void rf_cli_progress_fem(void *ctx, double t, double t_end)
{
    rf_cli_progress *p = ctx;
    if (!p->on)
        return;
    const double now = rf_monotonic_seconds();
    if (t < p->t_last) /* the solver restarted (a halved time step): measure the rate again */
        p->start = now;
    p->t_last = t;
    if (now - p->start < p->delay || now - p->last_draw < 1.0 / RF_CLI_PROGRESS_HZ)
        return;
    char done[96];
    snprintf(done, sizeof done, "simulated %.3g of ~%.3g s", t, t_end);
    draw(p, now, t, t_end, done);
}

void rf_cli_progress_count(void *ctx, size_t done, size_t total)
{
    rf_cli_progress *p = ctx;
    if (!p->on)
        return;
    const double now = rf_monotonic_seconds();
    if (now - p->start < p->delay || now - p->last_draw < 1.0 / RF_CLI_PROGRESS_HZ)
        return;
    char text[96];
    snprintf(text, sizeof text, "%zu of %zu", done, total);
    draw(p, now, (double)done, (double)total, text);
}

void rf_cli_progress_end(rf_cli_progress *p)
{
    if (p->drawn) {
        fputs("\r\033[K", stderr);
        fflush(stderr);
    }
    p->drawn = 0;
}
