/* study_run.c - a whole study in one call (see study_run.h): load, folder
 * checks and lock, result store, TM through the runner, analysis, outputs.
 *
 * The steps, in this order, each refusing before the next one writes:
 *   load the study -> (MPI: every rank said hello) -> the folder is empty, or
 *   holds a rockfuzz run, or force -> lock it -> open the store (format,
 *   integrity, key) -> plan and cap -> the model's deferred work (a trajectory
 *   model's impact table: rf_model_prepare) -> TM -> analysis -> report,
 *   result.json last.  The lock is released only when everything is closed. */
#include "rockfuzz/study_run.h"
#include "core/outdir.h"
#include "study/study_internal.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/util.h"
#include "rockfuzz/analysis.h"
#include "rockfuzz/mpi.h"
#include "rockfuzz/report.h"
#include "rockfuzz/runner.h"
#include "rockfuzz/store.h"
#include "rockfuzz/study.h"
#include "rockfuzz/tm.h"

void rf_study_run_options_default(rf_study_run_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->max_evaluations = -1;
    opt->plots = 1;
    opt->mpi_ranks = 1;
}

/* ---- the output folder ------------------------------------------------ */


/* The folder must be missing, empty, a rockfuzz run folder (one of the files
 * only a study run leaves there), or accepted by force. */
static rf_status check_out_dir(const char *dir, int force, rf_error *err)
{
    const char *const markers[] = {RF_STORE_FILE, RF_RUN_LOCK_FILE, "result.json"};
    return rf_check_out_dir(dir, force, markers, 3, err);
}

/* Take DIR/rockfuzz.lock (exclusive flock, released when *fd is closed or
 * the process dies); a held lock names its holder.  *created: the file is new. */
static rf_status lock_dir(const char *dir, int *fd, int *created, rf_error *err)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", dir, RF_RUN_LOCK_FILE);
    *created = 0;
    *fd = open(path, O_RDWR | O_CLOEXEC);
    if (*fd < 0 && errno == ENOENT) {
        *fd = open(path, O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
        *created = *fd >= 0;
        if (*fd < 0 && errno == EEXIST)
            *fd = open(path, O_RDWR | O_CLOEXEC);
    }
    if (*fd < 0)
        return rf_fail(err, RF_EIO, "--out %s: cannot create the lock file %s: %s", dir, path, strerror(errno));
    if (flock(*fd, LOCK_EX | LOCK_NB) != 0) {
        int e = errno;
        char holder[512] = "";
        ssize_t n = pread(*fd, holder, sizeof holder - 1, 0);
        holder[n > 0 ? n : 0] = '\0';
        holder[strcspn(holder, "\n")] = '\0';
        close(*fd);
        *fd = -1;
        if (e != EWOULDBLOCK)
            return rf_fail(err, RF_EIO, "--out %s: cannot lock %s: %s", dir, path, strerror(e));
        return rf_fail(err, RF_EIO, "--out %s: the folder is in use by another rockfuzz run (%s); wait for it to "
                       "end or stop it, or choose another folder",
                       dir, holder[0] ? holder : "holder unknown");
    }
    return RF_OK;
}

/* Write who holds the lock (after the store was accepted: a refused run
 * leaves the folder as it was). */
static rf_status write_holder(const char *dir, const char *study_path, int fd, rf_error *err)
{
    char host[256] = "?", text[1024];
    gethostname(host, sizeof host - 1);
    time_t now = time(NULL);
    struct tm tmv;
    char when[64] = "?";
    if (localtime_r(&now, &tmv))
        strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S %z", &tmv);
    int len = snprintf(text, sizeof text, "pid %ld on %s since %s, study %s\n", (long)getpid(), host, when,
                       study_path);
    if (len < 0 || (size_t)len >= sizeof text)
        len = len < 0 ? 0 : (int)sizeof text - 1; /* a very long path is cut, never over-read */
    if (ftruncate(fd, 0) != 0 || pwrite(fd, text, (size_t)len, 0) != len)
        return rf_fail(err, RF_EIO, "--out %s: cannot write the lock file %s: %s", dir, RF_RUN_LOCK_FILE,
                       strerror(errno));
    return RF_OK;
}

/* ---- one run on rank 0 -------------------------------------------------- */

typedef struct {
    const char *study_path;
    const rf_study_run_options *opt;
    rf_study study;
    rf_store *store;
    rf_runner runner;
    rf_tm_options tm;
    rf_tm_result res;
    rf_analysis an;
    rf_error plan_err;
    int plan_failed;
    char store_path[PATH_MAX];
    double t0;
    int lock_fd;
    rf_fuzzy_rasters *fuzzy; /* a terrain study's per-point raster store as the model's sink, or NULL */
    rf_model_side_store side; /* the store as the model's side store (its impact table) */
} run_state;

static int on_plan(void *user, size_t requested, size_t distinct)
{
    (void)requested;
    run_state *r = user;
    r->runner.planned_total = distinct;
    if (r->store && rf_store_begin_run(r->store, distinct, r->study.name, &r->plan_err) != RF_OK) {
        r->plan_failed = 1;
        return 1;
    }
    return 0;
}

static rf_status open_store(run_state *r, rf_error *err)
{
    const rf_study *s = &r->study;
    snprintf(r->store_path, sizeof r->store_path, "%s/%s", r->opt->out_dir, RF_STORE_FILE);
    rf_store_key key = {s->model.identity ? s->model.identity : "", ROCKFUZZ_VERSION, s->n_params,
                        s->model.n_outputs, (const char *const *)s->param_names,
                        (const char *const *)s->model.output_names};
    return rf_store_open(r->store_path, &key, r->opt->fresh, &r->store, err);
}

static void setup_runner(run_state *r)
{
    const rf_study_run_options *o = r->opt;
    rf_study_tm_options(&r->study, &r->tm);
    if (o->max_evaluations >= 0)
        r->tm.max_evaluations = (size_t)o->max_evaluations;
    r->tm.tolerate_failures = o->tolerate_failures;
    rf_runner_init(&r->runner);
    r->runner.jobs = o->jobs > 0            ? o->jobs
                     : o->mpi_ranks > 1     ? 1
                     : r->study.jobs > 0    ? r->study.jobs
                                            : rf_runner_default_jobs(&r->study.model);
    r->runner.progress = o->progress;
    r->runner.store = r->store;
    r->runner.tolerate_failures = o->tolerate_failures;
    r->runner.mpi_workers = o->mpi_ranks > 1 ? o->mpi_ranks - 1 : 0;
    r->runner.interrupt = o->interrupt;
    r->tm.interrupt = o->interrupt; /* counting a grid of millions of points (the cap off) answers it too */
    rf_model_set_interrupt(&r->study.model, o->interrupt);
    r->tm.on_plan = on_plan;
    r->tm.on_plan_user = r;
}

/* Append tail to the message, cutting the message (never the tail) to fit. */
static void append_tail(rf_error *err, const char *tail)
{
    size_t len = strlen(err->msg), add = strlen(tail);
    if (len + add >= sizeof err->msg)
        len = sizeof err->msg > add + 1 ? sizeof err->msg - add - 1 : 0;
    memcpy(err->msg + len, tail, add < sizeof err->msg ? add + 1 : 0);
    err->msg[sizeof err->msg - 1] = '\0';
}

/* Count the plan, show it, and refuse it above the cap. */
static rf_status plan(run_state *r, rf_error *err)
{
    const rf_study *s = &r->study;
    FILE *out = r->opt->out;
    size_t requested = 0, distinct = 0;
    rf_status st = rf_tm_count(s->inputs, s->n_params, &r->tm, &requested, &distinct, err);
    if (st == RF_EINTERRUPTED)
        append_tail(err, "; nothing was evaluated");
    if (st != RF_OK)
        return rf_error_prefix(err, "%s", r->study_path);
    if (out) {
        fprintf(out, "Study '%s': %s form, m = %zu, %zu parameter%s; model %s\n", s->name,
                rf_tm_scheme_name(s->scheme), s->levels, s->n_params, s->n_params == 1 ? "" : "s",
                s->model_description);
        fprintf(out, "Scheme: %s, %s\n", rf_tm_scheme_name(s->scheme), s->scheme_reason ? s->scheme_reason : "");
        fprintf(out, "Evaluations: %zu requested, %zu distinct%s%s; %d job%s", requested, distinct,
                s->scheme == RF_TM_EXTENDED ? " (at most; the probe decides)" : "",
                s->left_right ? ", including the left/right three-point grid" : "", r->runner.jobs,
                r->runner.jobs == 1 ? "" : "s");
        if (r->opt->mpi_ranks > 1)
            fprintf(out, " on rank 0 + %d MPI worker rank%s", r->opt->mpi_ranks - 1,
                    r->opt->mpi_ranks == 2 ? "" : "s");
        fprintf(out, "\n");
        fflush(out);
    }
    if (r->tm.max_evaluations > 0 && distinct > r->tm.max_evaluations && s->scheme != RF_TM_EXTENDED)
        return rf_fail(err, RF_ECAP,
                       "%s: the study needs %zu distinct model evaluations, more than the cap of %zu; raise "
                       "--max-evaluations (or options.max_evaluations) or lower levels%s",
                       r->study_path, distinct, r->tm.max_evaluations,
                       s->scheme == RF_TM_GENERAL ? ", or use scheme: reduced" : "");
    return RF_OK;
}

static rf_status side_put(void *user, const char *key, const double *row, size_t width, rf_error *err)
{
    return rf_store_side_put(user, key, row, width, err);
}

static rf_status side_each(void *user, const char *key, size_t width, rf_status (*fn)(void *u, const double *row),
                           void *u, rf_error *err)
{
    return rf_store_side_each(user, key, width, fn, u, err);
}

/* The model's deferred work (a trajectory model's impact table), inside the
 * run: after the lock and the plan, answering the stop flag, saying progress;
 * what it computes is kept in the store (side rows). */
static rf_status prepare_model(run_state *r, rf_error *err)
{
    if (r->store) {
        r->side = (rf_model_side_store){r->store, side_put, side_each};
        rf_model_set_side_store(&r->study.model, &r->side);
    }
    if (r->opt->interrupt && atomic_load(r->opt->interrupt))
        return rf_fail(err, RF_EINTERRUPTED, "interrupted before the first evaluation; nothing was evaluated");
    rf_status st = rf_model_prepare(&r->study.model, r->opt->out, err);
    if (st == RF_EINTERRUPTED) {
        rf_error_prefix(err, "%s", r->study_path);
        append_tail(err, "; nothing was evaluated yet: rerun to resume");
        return st;
    }
    if (st != RF_OK)
        return rf_error_prefix(err, "%s: model", r->study_path);
    return RF_OK;
}

/* The TM through the runner; on failure the message says what is kept. */
static rf_status evaluate(run_state *r, rf_error *err)
{
    rf_evaluator ev = rf_runner_evaluator(&r->runner);
    r->tm.evaluator = &ev;
    rf_status st = rf_tm_run(r->study.inputs, r->study.n_params, &r->study.model, &r->tm, &r->res, err);
    r->tm.evaluator = NULL;
    if (st == RF_OK)
        return RF_OK;
    if (r->plan_failed) {
        *err = r->plan_err; /* the store could not record the plan: that is the error, not the TM's */
        st = err->code != RF_OK ? err->code : RF_EIO;
    }
    size_t n = r->runner.evaluated + r->runner.failed;
    rf_error_prefix(err, "%s", r->study_path);
    char tail[PATH_MAX + 128];
    snprintf(tail, sizeof tail, ". %zu evaluation%s of this run committed to %s (%zu found there before); "
             "rerun to resume", n, n == 1 ? "" : "s", r->store_path, r->runner.resumed);
    append_tail(err, tail);
    return st;
}

/* The model's warnings as data: this run's, else those a run before it stored
 * (its points were taken from the store, so the model did not see them again). */
static void model_warnings(run_state *r, char *buf, size_t size)
{
    buf[0] = '\0';
    const rf_model *m = &r->study.model;
    rf_error ignored;
    if (m->warnings && m->warnings(m->ctx, buf, size) > 0) {
        rf_store_note_set(r->store, "model_warnings", buf, &ignored);
        return;
    }
    if (r->runner.resumed > 0 && rf_store_note_get(r->store, "model_warnings", buf, size, &ignored) == RF_OK &&
        buf[0]) {
        char note[] = " (reported by an earlier run into this folder whose results were reused)";
        size_t len = strlen(buf);
        if (len + sizeof note < size)
            memcpy(buf + len, note, sizeof note);
    }
}

/* The error of the surrogate the model ran on: this run's, else the one a run
 * before it stored (a resumed run whose model built nothing). */
static void model_surrogate_error(run_state *r, char *buf, size_t size)
{
    buf[0] = '\0';
    const rf_model *m = &r->study.model;
    rf_error ignored;
    if (m->surrogate_error && m->surrogate_error(m->ctx, buf, size) > 0)
        rf_store_note_set(r->store, "surrogate_error", buf, &ignored);
    else if (m->surrogate_error && rf_store_note_get(r->store, "surrogate_error", buf, size, &ignored) != RF_OK)
        buf[0] = '\0';
}

static rf_status write_outputs(run_state *r, rf_error *err)
{
    const rf_study_run_options *o = r->opt;
    char warnings[RF_ERROR_MAX], surrogate[RF_ERROR_MAX];
    model_warnings(r, warnings, sizeof warnings);
    model_surrogate_error(r, surrogate, sizeof surrogate);
    rf_report_options ropt;
    rf_report_options_default(&ropt);
    ropt.plots = o->plots;
    ropt.wall_seconds = rf_monotonic_seconds() - r->t0;
    ropt.jobs = r->runner.jobs;
    ropt.cap = r->tm.max_evaluations;
    ropt.evaluated = r->runner.evaluated;
    ropt.failed = r->runner.failed;
    ropt.resumed = r->runner.resumed;
    ropt.mpi_ranks = o->mpi_ranks;
    ropt.remote = r->runner.remote;
    ropt.eval_seconds = r->runner.eval_seconds;
    ropt.model_warnings = warnings;
    ropt.surrogate_error = surrogate;
    ropt.interrupt = o->interrupt;
    /* From here on the files are rewritten: the old result.json goes first, so
     * that its presence keeps meaning "every file belongs to one complete run". */
    char old[PATH_MAX];
    snprintf(old, sizeof old, "%s/result.json", o->out_dir);
    if (unlink(old) != 0 && errno != ENOENT)
        return rf_fail(err, RF_EIO, "%s: cannot replace the old result: %s", old, strerror(errno));
    rf_status st = rf_report_stopped(o->interrupt, "the fuzzy rasters", err);
    if (st == RF_OK)
        st = rf_study_fuzzy_rasters_write(o->out_dir, &r->study, r->fuzzy, &r->res, o->plots, err);
    if (st == RF_OK)
        st = rf_report_write(o->out_dir, &r->study, &r->res, &r->an, &ropt, err);
    if (st == RF_OK) /* a trajectory study: its trajectories at the nominal point and the bounds, for the report */
        st = rf_traj_study_reruns(o->out_dir, &r->study, &r->res, r->runner.jobs, o->plots, o->interrupt, err);
    if (st == RF_OK)
        st = rf_report_stopped(o->interrupt, "report.html", err);
    if (st == RF_OK)
        st = rf_report_write_html(o->out_dir, err);
    if (st == RF_EINTERRUPTED) {
        unlink(old); /* written before the stop: without report.html the run is not complete */
        char tail[PATH_MAX + 128];
        snprintf(tail, sizeof tail, "; every evaluation is in %s: rerun to write the report", r->store_path);
        append_tail(err, tail);
        rf_error_prefix(err, "%s", r->study_path);
    }
    return st;
}

static void print_results(run_state *r)
{
    const rf_study_run_options *o = r->opt;
    if (o->out) {
        rf_report_print_summary(o->out, &r->study, &r->res, &r->an);
        fflush(o->out);
    }
    if (o->log && (r->res.failed_points > 0 || r->runner.failed > 0))
        fprintf(o->log,
                "rockfuzz run: WARNING: %zu evaluation%s failed and %s left out of the bounds: the fuzzy outputs "
                "may be too narrow. The failures (parameters, message) are in %s; `rockfuzz status %s` lists "
                "them.\n",
                r->runner.failed, r->runner.failed == 1 ? "" : "s", r->runner.failed == 1 ? "was" : "were",
                r->store_path, o->out_dir);
}

static rf_status run_steps(run_state *r, rf_error *err)
{
    rf_status st;
    if ((st = open_store(r, err)) != RF_OK)
        return st;
    if ((st = write_holder(r->opt->out_dir, r->study_path, r->lock_fd, err)) != RF_OK)
        return st;
    setup_runner(r);
    if ((st = plan(r, err)) != RF_OK)
        return st;
    if ((st = rf_study_fuzzy_rasters_begin(r->opt->out_dir, &r->study, &r->fuzzy, err)) != RF_OK)
        return rf_error_prefix(err, "%s", r->study_path);
    if ((st = prepare_model(r, err)) != RF_OK)
        return st;
    if (r->opt->interrupt && atomic_load(r->opt->interrupt))
        return rf_fail(err, RF_EINTERRUPTED, "interrupted before the first evaluation; nothing was evaluated");
    r->t0 = rf_monotonic_seconds();
    if ((st = evaluate(r, err)) != RF_OK)
        return st;
    if ((st = rf_analysis_compute(&r->res, &r->an, err)) != RF_OK)
        return rf_error_prefix(err, "%s: analysis", r->study_path);
    print_results(r);
    if ((st = write_outputs(r, err)) != RF_OK)
        return st;
    if (r->opt->out)
        fprintf(r->opt->out,
                "Wall time %.3f s (%zu evaluated, %zu failed, %zu from the store; %.3f s in the model). Results: "
                "%s/result.json, %s/report.html\n",
                rf_monotonic_seconds() - r->t0, r->runner.evaluated, r->runner.failed, r->runner.resumed,
                r->runner.eval_seconds, r->opt->out_dir, r->opt->out_dir);
    return RF_OK;
}

/* Rank 0 with the study loaded: folder, lock, then the steps. */
static rf_status run_rank0(run_state *r, rf_error *err)
{
    const char *dir = r->opt->out_dir;
    rf_status st = check_out_dir(dir, r->opt->force, err);
    if (st == RF_OK)
        st = rf_report_make_dir(dir, err);
    int created = 0;
    r->lock_fd = -1;
    if (st == RF_OK)
        st = lock_dir(dir, &r->lock_fd, &created, err);
    if (st == RF_OK)
        st = run_steps(r, err);
    int opened = r->store != NULL;
    rf_study_fuzzy_rasters_end(r->fuzzy);
    r->fuzzy = NULL;
    rf_store_close(r->store);
    r->store = NULL;
    if (r->lock_fd >= 0) {
        if (created && !opened) {
            char path[PATH_MAX];
            snprintf(path, sizeof path, "%s/%s", dir, RF_RUN_LOCK_FILE);
            unlink(path); /* refused before anything was written: leave no trace */
        }
        close(r->lock_fd); /* the text stays: it names the last holder; the lock is the flock */
    }
    return st;
}

static void fill_stats(const run_state *r, rf_study_run_stats *stats)
{
    if (!stats)
        return;
    stats->evaluated = r->runner.evaluated;
    stats->failed = r->runner.failed;
    stats->resumed = r->runner.resumed;
    stats->wall_seconds = r->t0 > 0 ? rf_monotonic_seconds() - r->t0 : 0;
    stats->jobs = r->runner.jobs;
}

rf_status rf_study_run(const char *study_path, const rf_study_run_options *opt, rf_study_run_stats *stats,
                       rf_error *err)
{
    rf_error local;
    if (!err)
        err = &local;
    memset(err, 0, sizeof *err);
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (!study_path || !opt || !opt->out_dir)
        return rf_fail(err, RF_EINTERNAL, "rf_study_run: NULL study path, options or output folder");
    run_state *r = calloc(1, sizeof *r);
    if (!r)
        return rf_fail(err, RF_ENOMEM, "out of memory");
    r->study_path = study_path;
    r->opt = opt;
    rf_status st = rf_study_load(study_path, &r->study, err);
    if (opt->mpi_rank > 0) {
        /* A worker rank: evaluate what rank 0 sends; rank 0 reports every message.  With
         * the flag a stopped program comes back as RF_EINTERRUPTED, which rank 0 does not store. */
        rf_fuzzy_rasters *fuzzy = NULL; /* its points' rasters into OUT/rasters too (else rank 0 rebuilds them) */
        rf_error ferr;
        if (st == RF_OK) {
            rf_model_set_interrupt(&r->study.model, opt->interrupt);
            if (rf_study_fuzzy_rasters_begin(opt->out_dir, &r->study, &fuzzy, &ferr) != RF_OK)
                fuzzy = NULL;
        }
        int wrc = rf_mpi_worker(st == RF_OK ? &r->study.model : NULL, err->msg);
        rf_study_fuzzy_rasters_end(fuzzy);
        st = wrc == 0 ? RF_OK : rf_fail(err, RF_EIO, "MPI worker rank %d stopped with status %d", opt->mpi_rank, wrc);
    } else {
        if (opt->mpi_ranks > 1) {
            rf_error herr;
            memset(&herr, 0, sizeof herr);
            if (rf_mpi_gather_hello(st == RF_OK ? &r->study.model : NULL, &herr) != RF_OK && st == RF_OK)
                st = rf_fail(err, herr.code ? herr.code : RF_EIO, "%s", herr.msg);
        }
        if (st == RF_OK)
            st = run_rank0(r, err);
        rf_mpi_release_workers();
    }
    fill_stats(r, stats);
    rf_analysis_free(&r->an);
    rf_tm_result_free(&r->res);
    rf_study_free(&r->study);
    free(r);
    return st;
}
