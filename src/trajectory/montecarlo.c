/* montecarlo.c - ensembles of trajectories over the random inputs.
 * Sample i draws input j from the counter-based uniform
 * U(seed, stream 2i, index j) (roughness: stream 2i + 1), optionally
 * stratified by a Latin hypercube (u = (perm_j[i] + U) / N, the permutations
 * also drawn from the seed; traj_draw.c, shared with terrain_montecarlo.c),
 * and writes its results at index i.  So the
 * ensemble is the same bits whatever the thread count or the split over MPI
 * ranks.  Threads take contiguous blocks of samples; each keeps its own deep
 * copy of the spec into which the draws are written, one events buffer
 * reused by the trajectories it does not record, and its envelope
 * accumulator (envelope.c), merged at the end (counts and maxima: the same
 * bits in any order). */
#include "trajectory/terrain_internal.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Samples done by all threads; the first job reports them. */
typedef struct {
    rf_traj_progress_fn fn;
    void *ctx;
    atomic_size_t done;
} mc_progress;

typedef struct {
    const rf_traj_spec *spec;
    const rf_traj_world *world;
    rf_traj_ensemble *ens;
    const size_t *perm;     /* n_random * samples (LHS), or NULL */
    size_t begin, end;
    traj_env_acc *env;
    rf_status status;
    rf_error err;
    mc_progress *progress;  /* NULL: none */
    int reports;            /* this job (the calling thread's) calls progress->fn */
} mc_job;

static void count_sample(const mc_job *job)
{
    if (!job->progress)
        return;
    size_t done = atomic_fetch_add(&job->progress->done, 1) + 1;
    if (job->reports)
        job->progress->fn(job->progress->ctx, done, job->spec->samples);
}

/* The uniform of input dimension j of sample i (traj_draw.c). */
static double sample_u(const mc_job *job, size_t i, size_t j)
{
    return traj_sample_u(job->spec, job->perm, i, j);
}

static void *mc_worker(void *arg)
{
    mc_job *job = arg;
    const rf_traj_spec *spec = job->spec;
    rf_traj_ensemble *ens = job->ens;
    rf_traj_spec local;
    double **field = calloc(spec->n_random ? spec->n_random : 1, sizeof *field);
    const rf_traj_field **row = calloc(spec->n_random ? spec->n_random : 1, sizeof *row);
    rf_traj_crossing *cross = calloc(ens->n_collectors ? ens->n_collectors : 1, sizeof *cross);
    rf_traj_result tmp = {0}; /* the unrecorded trajectories; events only for the envelopes */
    if (job->env)
        tmp.events = malloc(64 * sizeof *tmp.events), tmp.events_cap = 64;
    tmp.crossings = cross;
    int nomem = !field || !row || !cross;
    if (nomem || (job->env && !tmp.events) || (job->status = rf_traj_spec_copy(spec, &local, &job->err)) != RF_OK) {
        free(field);
        free(row);
        free(cross);
        free(tmp.events);
        job->status = rf_fail(&job->err, RF_ENOMEM, "out of memory");
        return NULL;
    }
    traj_draw_bind(&local, spec, row, field);
    for (size_t i = job->begin; i < job->end && job->status == RF_OK; i++) {
        traj_draw_inputs(spec, job->perm, i, row, field);
        if (job->world->release)
            traj_release_point(job->world, sample_u(job, i, spec->n_random), &local.x0, &local.y0);
        rf_traj_result *res = i < ens->n_recorded ? &ens->recorded[i] : &tmp; /* tmp.events grows, reused */
        job->status = rf_traj_simulate(job->world, &local, spec->seed, i, res, &job->err);
        if (job->env)
            traj_env_add(job->env, &local, res);
        ens->state[i] = (unsigned char)res->state;
        ens->runout_x[i] = res->runout_x;
        ens->rebound_height[i] = res->rebound_height;
        if (ens->n_collectors)
            memcpy(&ens->crossings[i * ens->n_collectors], res->crossings, ens->n_collectors * sizeof *cross);
        count_sample(job);
    }
    rf_traj_spec_free(&local);
    free(field);
    free(row);
    free(cross);
    free(tmp.events);
    return NULL;
}

/* The run's memory is estimated before anything is allocated: per sample its state, runout,
 * rebound height and a crossing per collector; per recorded trajectory its crossings and
 * first buffers.  Beyond the machine's physical memory the run is refused with the figure. */
static rf_status check_memory(const rf_traj_spec *s, rf_error *err)
{
    double N = (double)s->samples, nc = (double)s->n_collectors, rec = (double)(s->record < s->samples ? s->record
                                                                                                      : s->samples);
    double bytes = N * (1 + 2 * sizeof(double) + nc * sizeof(rf_traj_crossing)) +
                   rec * (sizeof(rf_traj_result) + nc * sizeof(rf_traj_crossing) + 16 * (sizeof(rf_traj_impact) +
                                                                                      sizeof(rf_traj_event)));
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    double phys = pages > 0 && page > 0 ? (double)pages * (double)page : INFINITY;
    if (bytes > phys)
        return rf_fail(err, RF_ENOMEM, "samples = %zu with %zu collectors need %.3g GB for the per-sample results, "
                       "more than this machine's %.3g GB of memory; use fewer samples", s->samples, s->n_collectors,
                       bytes / 1e9, phys / 1e9);
    return RF_OK;
}

static rf_status ensemble_alloc(const rf_traj_spec *s, rf_traj_ensemble *e, rf_error *err)
{
    memset(e, 0, sizeof *e);
    if (check_memory(s, err) != RF_OK)
        return RF_ENOMEM;
    size_t N = s->samples, nc = s->n_collectors;
    e->samples = N;
    e->n_collectors = nc;
    e->state = malloc(N ? N : 1);
    e->runout_x = malloc((N ? N : 1) * sizeof(double));
    e->rebound_height = malloc((N ? N : 1) * sizeof(double));
    e->crossings = calloc(N * nc > 0 ? N * nc : 1, sizeof *e->crossings);
    e->n_recorded = s->record < N ? s->record : N;
    e->recorded = calloc(e->n_recorded ? e->n_recorded : 1, sizeof *e->recorded);
    if (!e->state || !e->runout_x || !e->rebound_height || !e->crossings || !e->recorded)
        return rf_fail(err, RF_ENOMEM, "out of memory for %zu samples", N);
    for (size_t i = 0; i < e->n_recorded; i++) {
        rf_traj_result *r = &e->recorded[i];
        r->crossings = calloc(nc ? nc : 1, sizeof *r->crossings);
        r->impacts = malloc(16 * sizeof *r->impacts);
        r->events = malloc(16 * sizeof *r->events);
        r->impacts_cap = r->events_cap = 16;
        if (!r->crossings || !r->impacts || !r->events)
            return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    return RF_OK;
}

void rf_traj_ensemble_free(rf_traj_ensemble *e)
{
    if (!e)
        return;
    for (size_t i = 0; e->recorded && i < e->n_recorded; i++) {
        free(e->recorded[i].crossings);
        free(e->recorded[i].impacts);
        free(e->recorded[i].events);
    }
    free(e->recorded);
    free(e->state);
    free(e->runout_x);
    free(e->rebound_height);
    free(e->crossings);
    traj_envelope_free(&e->envelope);
    terrain_samples_free(e->terrain);
    rf_terrain_world_free(e->terrain_world);
    memset(e, 0, sizeof *e);
}

/* The first failed job's status, else the merged envelopes into ens. */
static rf_status collect(mc_job *jobs, int threads, rf_traj_ensemble *ens, rf_error *err)
{
    for (int t = 0; t < threads; t++)
        if (jobs[t].status != RF_OK) {
            if (err)
                *err = jobs[t].err;
            return jobs[t].status;
        }
    if (!jobs[0].env)
        return RF_OK;
    for (int t = 1; t < threads; t++)
        traj_env_merge(jobs[0].env, jobs[t].env);
    return traj_env_finish(jobs[0].env, &ens->envelope, err);
}

static rf_status run_jobs(const rf_traj_spec *spec, const rf_traj_world *w, const size_t *perm, int threads,
                          int envelopes, mc_progress *progress, rf_traj_ensemble *ens, rf_error *err)
{
    size_t N = spec->samples;
    if ((size_t)threads > N)
        threads = N ? (int)N : 1;
    mc_job *jobs = calloc((size_t)threads, sizeof *jobs);
    rf_status st = jobs ? RF_OK : RF_ENOMEM;
    for (int t = 0; t < threads && st == RF_OK; t++) {
        jobs[t] = (mc_job){spec, w, ens, perm, N * (size_t)t / (size_t)threads, N * (size_t)(t + 1) / (size_t)threads,
                           envelopes ? traj_env_create(spec, RF_TRAJ_ENVELOPE_EDGES, w) : NULL, RF_OK, {RF_OK, ""},
                           progress, t == 0};
        if (envelopes && !jobs[t].env)
            st = RF_ENOMEM;
    }
    if (st == RF_OK) {
        traj_start_and_join(jobs, sizeof *jobs, threads, mc_worker);
        st = collect(jobs, threads, ens, err);
    } else {
        st = rf_fail(err, RF_ENOMEM, "out of memory for %d threads", threads);
    }
    for (int t = 0; jobs && t < threads; t++)
        traj_env_free(jobs[t].env);
    free(jobs);
    return st;
}

static rf_status traj_run_full(const rf_traj_spec *spec, int threads, void *table, int envelopes,
                               mc_progress *progress, rf_traj_ensemble *ens, rf_error *err);

rf_status rf_traj_run(const rf_traj_spec *spec, int threads, rf_traj_ensemble *ens, rf_error *err)
{
    return traj_run_shared(spec, threads, NULL, ens, err);
}

rf_status traj_run_shared(const rf_traj_spec *spec, int threads, void *table, rf_traj_ensemble *ens, rf_error *err)
{
    return traj_run_with(spec, threads, table, 1, ens, err);
}

rf_status rf_traj_run_progress(const rf_traj_spec *spec, int threads, rf_traj_progress_fn progress, void *ctx,
                               rf_traj_ensemble *ens, rf_error *err)
{
    mc_progress p = {progress, ctx, 0};
    return traj_run_full(spec, threads, NULL, 1, progress ? &p : NULL, ens, err);
}

rf_status traj_run_with(const rf_traj_spec *spec, int threads, void *table, int envelopes, rf_traj_ensemble *ens,
                        rf_error *err)
{
    return traj_run_full(spec, threads, table, envelopes, NULL, ens, err);
}

static rf_status traj_run_full(const rf_traj_spec *spec, int threads, void *table, int envelopes,
                               mc_progress *progress, rf_traj_ensemble *ens, rf_error *err)
{
    double t0 = rf_monotonic_seconds();
    rf_status st = rf_traj_spec_validate(spec, err);
    if (st != RF_OK)
        return st;
    if ((st = ensemble_alloc(spec, ens, err)) != RF_OK) {
        rf_traj_ensemble_free(ens);
        return st;
    }
    rf_traj_world *w = NULL;
    if ((st = traj_world_create_shared(spec, table, &w, err)) != RF_OK) {
        rf_traj_ensemble_free(ens);
        return st;
    }
    size_t *perm = NULL;
    size_t dims = spec->n_random + (spec->release_kind != RF_TRAJ_RELEASE_POINT);
    if (spec->lhs && dims && !(perm = traj_lhs_permutations(spec, dims))) {
        rf_traj_world_free(w);
        rf_traj_ensemble_free(ens);
        return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    if (threads <= 0) {
        long c = sysconf(_SC_NPROCESSORS_ONLN);
        threads = c > 0 ? (int)c : 1;
    }
    traj_impact_table_info(w->impact_table, &ens->impact_nodes_vn, &ens->impact_nodes_theta,
                           &ens->impact_evaluations, &ens->impact_from_cache, &ens->impact_error_estimate);
    st = run_jobs(spec, w, perm, threads, envelopes, progress, ens, err);
    free(perm);
    rf_traj_world_free(w);
    ens->wall_seconds = rf_monotonic_seconds() - t0;
    if (st != RF_OK)
        rf_traj_ensemble_free(ens);
    return st;
}
