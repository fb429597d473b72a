/* report.h - what a finished study run leaves behind: a readable summary,
 * result.json, CSV tables and membership/influence plots (PNG and SVG).
 *
 * result.json is written last and atomically (result.json.tmp, then
 * rename), so its presence means every other file was written too.
 * result.json also carries "warnings": every message a reader must see
 * (failed evaluations left out of the bounds, non-monotonic outputs under the
 * reduced form, the model's own warnings as the run collected them), which
 * report.html shows at the top.  The report is written from these data only:
 * it neither parses the model's identity nor recomputes any physics. */
#ifndef ROCKFUZZ_REPORT_H
#define ROCKFUZZ_REPORT_H

#include <stdio.h>

#include "rockfuzz/analysis.h"
#include "rockfuzz/study.h"
#include "rockfuzz/tm.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    int plots;             /* write PNG and SVG plots (default 1) */
    double wall_seconds;   /* wall time of the run, stored in result.json */
    int jobs;              /* worker threads used, stored in result.json */
    size_t cap;            /* evaluation cap used (0 = none) */
    size_t evaluated;      /* evaluated in this run (successfully) */
    size_t failed;         /* failed in this run (tolerate_failures) */
    size_t resumed;        /* found in the result store */
    int mpi_ranks;         /* MPI ranks (1 = none) */
    size_t remote;         /* of the evaluated, how many ran on MPI worker ranks */
    double eval_seconds;   /* time spent in the model in this run [s] */
    const char *model_warnings; /* what the model reported while evaluating (rf_model.warnings), NULL = none */
    const char *surrogate_error; /* the error of the surrogate the model ran on (rf_model.surrogate_error: result.json
                                  * "impact_surrogate_error", report.html, summary), NULL or "" = none */
    /* Non-zero *interrupt stops the writing between two files (RF_EINTERRUPTED,
     * no result.json: the folder is then an incomplete run); NULL = never. */
    const atomic_int *interrupt;
} rf_report_options;

void rf_report_options_default(rf_report_options *opt);

/* Human-readable summary: per output the cut table (mu | lower | upper), the
 * nominal value, the inputs giving the level-0 bounds, the influence table
 * and the degree of uncertainty; monotonicity warnings and the extended-form
 * classification. */
void rf_report_print_summary(FILE *f, const rf_study *study, const rf_tm_result *res, const rf_analysis *an);

/* Write every output file into dir (created if missing); result.json last. */
/* Create the output directory and any missing parents (mkdir -p). */
rf_status rf_report_make_dir(const char *dir, rf_error *err);

rf_status rf_report_write(const char *dir, const rf_study *study, const rf_tm_result *res, const rf_analysis *an,
                          const rf_report_options *opt, rf_error *err);

/* DIR/report.html from DIR/result.json and the SVG figures written next to it
 * (embedded inline, so the page is self-contained); nothing is re-run.  The
 * page is written to report.html.tmp and renamed. */
rf_status rf_report_write_html(const char *dir, rf_error *err);

/* The pieces, for tests and other front ends. */
rf_status rf_report_write_json(const char *path, const rf_study *study, const rf_tm_result *res,
                               const rf_analysis *an, const rf_report_options *opt, rf_error *err);
rf_status rf_report_write_csv(const char *dir, const rf_study *study, const rf_tm_result *res,
                              const rf_analysis *an, rf_error *err);
rf_status rf_report_write_plots(const char *dir, const rf_study *study, const rf_tm_result *res,
                                const rf_analysis *an, rf_error *err);
/* The same, stopping between two figures when *interrupt (may be NULL) is non-zero. */
rf_status rf_report_write_plots_until(const char *dir, const rf_study *study, const rf_tm_result *res,
                                      const rf_analysis *an, const atomic_int *interrupt, rf_error *err);
/* RF_EINTERRUPTED naming what was being written when *interrupt (may be NULL) is non-zero, else RF_OK. */
rf_status rf_report_stopped(const atomic_int *interrupt, const char *writing, rf_error *err);

#ifdef __cplusplus
}
#endif
#endif
