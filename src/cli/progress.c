/* progress.c - the progress line of a long single run (`rockfuzz impact` FE):
 * on stderr, redrawn at most RF_CLI_PROGRESS_HZ times per second, first after
 * RF_CLI_PROGRESS_DELAY s (a short run draws nothing; the environment
 * variable ROCKFUZZ_PROGRESS_DELAY [s] sets another delay, as the tests do),
 * erased at the end.
 * Time left = wall time so far x (t_end - t) / t, from the simulated time t
 * and the solver's expected end t_end. */
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
    p->last_draw = now;
    const double share = t_end > 0 ? fmin(t / t_end, 1) : 0;
    char el[32], left[32];
    rf_format_duration(now - p->start, RF_DURATION_WHOLE, el, sizeof el);
    rf_format_duration(t > 0 ? (now - p->start) * (t_end - t) / t : -1, RF_DURATION_WHOLE, left, sizeof left);
    fprintf(stderr, "\r  %s: simulated %.3g of ~%.3g s (%.0f %%), elapsed %s, left ~%s\033[K", p->what, t, t_end,
            100 * share, el, left);
    fflush(stderr);
    p->drawn = 1;
}

void rf_cli_progress_end(rf_cli_progress *p)
{
    if (p->drawn) {
        fputs("\r\033[K", stderr);
        fflush(stderr);
    }
    p->drawn = 0;
}
