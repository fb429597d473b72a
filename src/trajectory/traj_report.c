/* traj_report.c - report.html of `rockfuzz trajectory --out DIR`: the run's
 * settings, states, statistics per collector, and the figures of
 * traj_plot.c embedded as data: URIs (the file stands alone, like the study
 * report). */
#include "trajectory/block_traj.h"
#include "trajectory/traj_internal.h"
#include "core/html.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

void traj_html_image(FILE *f, const char *dir, const char *stem)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.png", dir, stem);
    if (!rf_html_png(f, path, stem))
        fprintf(f, "<p>(%s.png missing)</p>", stem);
}

static void row(FILE *f, const char *what, const char *unit, const rf_traj_percentiles *p, double scale)
{
    fprintf(f, "<tr><td>%s</td><td>%s</td><td>%.4g</td><td>%.4g</td><td>%.4g</td><td>%.4g</td></tr>\n", what, unit,
            p->p50 * scale, p->p95 * scale, p->p99 * scale, p->max * scale);
}

rf_status traj_write_report_html(const char *dir, const rf_traj_spec *s, const rf_traj_ensemble *e,
                                 const rf_traj_stats *st, rf_error *err)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/report.html", dir);
    FILE *f = fopen(path, "w");
    if (!f)
        return rf_fail(err, RF_EIO, "cannot write %s: %s", path, strerror(errno));
    fputs("<!DOCTYPE html><html><head><meta charset=utf-8><title>", f);
    rf_html_text(f, s->name);
    fputs("</title><style>body{font-family:sans-serif;max-width:960px;margin:auto}td,th{padding:2px 8px;"
          "text-align:right}img{max-width:100%}</style></head><body><h1>Trajectories: ", f);
    rf_html_text(f, s->name);
    char block[256];
    traj_block_describe(s, block, sizeof block);
    fprintf(f, "</h1><p>%zu trajector%s, %s sampling, seed %llu, bounce law %s; block: ", e->samples,
            e->samples == 1 ? "y" : "ies", s->lhs ? "Latin hypercube" : "random", (unsigned long long)s->seed,
            s->block_kind ? "(a rigid block: its own contact dynamics)" : rf_traj_bounce_law_names[s->law]);
    rf_html_text(f, block);
    fprintf(f, "; stopped %zu, exited %zu, step_limit %zu; %.3g s.</p>\n", st->stopped, st->exited, st->step_limit,
            e->wall_seconds);
    fputs("<h2>Statistics</h2><table><tr><th>quantity</th><th>unit</th><th>p50</th><th>p95</th><th>p99</th>"
          "<th>max</th></tr>\n", f);
    row(f, "runout x", "m", &st->runout_x, 1);
    row(f, "rebound height", "m", &st->rebound_height, 1);
    for (size_t c = 0; c < s->n_collectors; c++) {
        char what[300];
        fprintf(f, "<tr><td>%s (x = %g m): reach probability</td><td>-</td><td colspan=4>%.4g</td></tr>\n",
                s->collectors[c].name, s->collectors[c].x, st->collectors[c].reach_probability);
        snprintf(what, sizeof what, "%s: energy", s->collectors[c].name);
        row(f, what, "kJ", &st->collectors[c].total_energy, 1e-3);
        snprintf(what, sizeof what, "%s: passing height", s->collectors[c].name);
        row(f, what, "m", &st->collectors[c].height_lowest, 1);
    }
    fprintf(f, "</table><p>Collector statistics are over the trajectories that reach the line; energies include "
               "rotation.</p>\n<h2>Profile, trajectories, envelopes</h2>\n<p>The envelopes use all %zu "
               "trajectories: at each of %zu evenly spaced x, every trajectory's state where its path first "
               "reaches that x (solved exactly, not from stored points); one that never reaches it does not "
               "count there (the grey line gives the fraction that does). Heights are measured as at a collector "
               "(vertically, above the ground); energies include rotation. p50 and p95 are within %g %% of the exact "
               "percentiles (streaming histogram), the max is exact; numbers in envelopes.csv. The profile shows "
               "%zu recorded trajectories.</p>\n", e->samples, e->envelope.n_edges, 100 * RF_TRAJ_ENVELOPE_ACCURACY,
            e->n_recorded < 100 ? e->n_recorded : 100);
    traj_html_image(f, dir, "trajectory_profile");
    for (size_t c = 0; c < s->n_collectors; c++) {
        char stem[300];
        fputs("<h2>Collector ", f);
        rf_html_text(f, s->collectors[c].name);
        fputs("</h2>", f);
        snprintf(stem, sizeof stem, "trajectory_hist_%s", s->collectors[c].name);
        if (st->collectors[c].reach_probability > 0)
            traj_html_image(f, dir, stem);
        else
            fprintf(f, "<p>No trajectory of the %zu reached this line: no energy or height to show.</p>", e->samples);
    }
    fputs("</body></html>\n", f);
    if (fclose(f) != 0)
        return rf_fail(err, RF_EIO, "cannot write %s", path);
    return RF_OK;
}
