/* terrain_montecarlo.c - ensembles of 3D trajectories on terrain, as
 * montecarlo.c runs them on a profile.  Sample i draws its random inputs as
 * in 2D (traj_draw.c: dimensions 0..n_random-1, the same draws for the same
 * seed) and its release point from dimensions n_random, n_random + 1,
 * n_random + 2 (terrain_release_point: feature by weight, then the position
 * in it), all stratified by the Latin hypercube when lhs; its roughness
 * draws come from stream 2i + 1 inside the simulator.  Results go to index
 * i.  A run may be a part: the samples [first, end) only (MPI ranks,
 * terrain_parts.c joins the parts), sample i at index i - first, the
 * recorded trajectories those of its samples below spec->record, the
 * rasters its samples'.  Threads take contiguous blocks of samples; each has its own deep copy
 * of the spec into which the draws are written and its own hazard
 * accumulator, merged at the end in thread order (the merge adds counts:
 * the same bits in any order).  So a run is the same bits at any thread
 * count.  Memory: the per-sample arrays (terrain_bytes_per_sample: 65 B
 * and 104 B per barrier, on x86-64) plus, independent of the samples, the
 * recorded trajectories and one raster accumulator per thread. */
#include "trajectory/terrain_internal.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct {
    rf_traj_progress_fn fn;
    void *ctx;
    atomic_size_t done;
} tmc_progress;

typedef struct {
    const rf_traj_spec *spec;
    const rf_terrain_world *w;
    rf_traj_ensemble *ens;
    const size_t *perm;        /* (n_random + 3) * samples (LHS), or NULL */
    size_t first;              /* the part's first sample: sample i is at index i - first */
    size_t begin, end;
    rf_terrain_hazard *hazard; /* this job's rasters, or NULL */
    rf_status status;
    rf_error err;
    tmc_progress *progress;    /* NULL: none */
    int reports;               /* this job (the calling thread's) calls progress->fn */
} tmc_job;

double terrain_bytes_per_sample(size_t n_collectors)
{
    return 1.0 + 8 * sizeof(double) + (double)n_collectors * sizeof(rf_traj_crossing);
}

static void count_sample(const tmc_job *job)
{
    if (!job->progress)
        return;
    size_t done = atomic_fetch_add(&job->progress->done, 1) + 1;
    if (job->reports)
        job->progress->fn(job->progress->ctx, done, job->ens->samples);
}

/* Sample i's release point on the map (z: NaN = the ground + height0). */
static void release_start(const tmc_job *job, size_t i, double start[3])
{
    size_t j = job->spec->n_random;
    double u1 = traj_sample_u(job->spec, job->perm, i, j), u2 = traj_sample_u(job->spec, job->perm, i, j + 1),
           u3 = traj_sample_u(job->spec, job->perm, i, j + 2);
    terrain_release_point(job->w->release, u1, u2, u3, &start[0], &start[1]);
    start[2] = NAN;
}

/* Sample first + i's results into the per-sample arrays (index i). */
static void store_sample(rf_traj_ensemble *ens, size_t i, const rf_terrain_result *res)
{
    rf_terrain_samples *t = ens->terrain;
    ens->state[i] = (unsigned char)res->state;
    ens->runout_x[i] = res->runout;
    ens->rebound_height[i] = res->rebound_height;
    if (ens->n_collectors)
        memcpy(&ens->crossings[i * ens->n_collectors], res->crossings, ens->n_collectors * sizeof *res->crossings);
    memcpy(&t->start[3 * i], res->start, sizeof res->start);
    memcpy(&t->end[3 * i], res->end, sizeof res->end);
    t->runout[i] = res->runout;
    t->reach_angle[i] = res->reach_angle;
}

/* One sample: draws, release point, trajectory, results. */
static void run_sample(tmc_job *job, rf_traj_spec *local, const rf_traj_field **row, double **field, size_t i,
                       rf_terrain_result *tmp)
{
    rf_traj_ensemble *ens = job->ens;
    double start[3];
    traj_draw_inputs(job->spec, job->perm, i, row, field);
    release_start(job, i, start);
    size_t k = i - job->first;
    rf_terrain_result *res = k < ens->terrain->n_recorded ? &ens->terrain->recorded[k] : tmp;
    res->n_impacts = res->n_steps = res->n_events = 0; /* as 2D's simulator does; the buffers are kept */
    memset(res->crossings, 0, ens->n_collectors * sizeof *res->crossings);
    job->status = terrain_simulate_hazard(job->w, local, job->spec->seed, i, start, job->hazard, res, &job->err);
    if (job->status == RF_OK)
        store_sample(ens, k, res);
    count_sample(job);
}

static void *tmc_worker(void *arg)
{
    tmc_job *job = arg;
    const rf_traj_spec *spec = job->spec;
    size_t nr = spec->n_random ? spec->n_random : 1, nc = job->ens->n_collectors ? job->ens->n_collectors : 1;
    double **field = calloc(nr, sizeof *field);
    const rf_traj_field **row = calloc(nr, sizeof *row);
    rf_terrain_result tmp = {0}; /* the unrecorded trajectories: no impacts, no events */
    tmp.crossings = calloc(nc, sizeof *tmp.crossings);
    rf_traj_spec local;
    if (!field || !row || !tmp.crossings) {
        job->status = rf_fail(&job->err, RF_ENOMEM, "out of memory");
    } else if ((job->status = rf_traj_spec_copy(spec, &local, &job->err)) == RF_OK) {
        traj_draw_bind(&local, spec, row, field);
        for (size_t i = job->begin; i < job->end && job->status == RF_OK; i++)
            run_sample(job, &local, row, field, i, &tmp);
        rf_traj_spec_free(&local);
    }
    free(field);
    free(row);
    free(tmp.crossings);
    return NULL;
}

/* The per-sample arrays are estimated before anything is allocated; beyond
 * the machine's physical memory the run is refused with the figure. */
static rf_status check_memory(const rf_traj_spec *s, size_t n, size_t rec, rf_error *err)
{
    double bytes = (double)n * terrain_bytes_per_sample(s->n_collectors) +
                   (double)rec * (sizeof(rf_terrain_result) + (double)s->n_collectors * sizeof(rf_traj_crossing) +
                                  16.0 * (sizeof(rf_terrain_impact) + sizeof(rf_terrain_event)));
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    double phys = pages > 0 && page > 0 ? (double)pages * (double)page : INFINITY;
    if (bytes > phys)
        return rf_fail(err, RF_ENOMEM, "samples = %zu with %zu barriers need %.3g GB for the per-sample results "
                       "(%.0f bytes each), more than this machine's %.3g GB of memory; use fewer samples",
                       n, s->n_collectors, bytes / 1e9, terrain_bytes_per_sample(s->n_collectors),
                       phys / 1e9);
    return RF_OK;
}

static rf_status alloc_recorded(rf_terrain_samples *t, size_t n, size_t nc, rf_error *err)
{
    t->n_recorded = n;
    t->recorded = calloc(n ? n : 1, sizeof *t->recorded);
    if (!t->recorded)
        return t->n_recorded = 0, rf_fail(err, RF_ENOMEM, "out of memory");
    for (size_t i = 0; i < n; i++) {
        rf_terrain_result *r = &t->recorded[i];
        r->crossings = calloc(nc ? nc : 1, sizeof *r->crossings);
        r->impacts = malloc(16 * sizeof *r->impacts);
        r->events = malloc(16 * sizeof *r->events);
        r->impacts_cap = r->events_cap = 16;
        if (!r->crossings || !r->impacts || !r->events)
            return rf_fail(err, RF_ENOMEM, "out of memory");
    }
    return RF_OK;
}

/* The recorded trajectories of the part [first, end): its samples below spec->record. */
size_t terrain_part_recorded(const rf_traj_spec *s, size_t first, size_t end)
{
    size_t rec_end = s->record < end ? s->record : end;
    return rec_end > first ? rec_end - first : 0;
}

/* An ensemble for the samples [first, end) (arrays of end - first). */
static rf_status ensemble_alloc(const rf_traj_spec *s, size_t first, size_t end, rf_traj_ensemble *e, rf_error *err)
{
    memset(e, 0, sizeof *e);
    size_t n = end - first, rec = terrain_part_recorded(s, first, end);
    if (check_memory(s, n, rec, err) != RF_OK)
        return RF_ENOMEM;
    size_t N = n ? n : 1, nc = s->n_collectors;
    e->samples = n;
    e->n_collectors = nc;
    e->state = malloc(N);
    e->runout_x = malloc(N * sizeof(double));
    e->rebound_height = malloc(N * sizeof(double));
    e->crossings = calloc(N * (nc ? nc : 1), sizeof *e->crossings);
    e->recorded = calloc(1, sizeof *e->recorded); /* the 2D records stay empty: n_recorded 0 */
    rf_terrain_samples *t = e->terrain = calloc(1, sizeof *t);
    if (!e->state || !e->runout_x || !e->rebound_height || !e->crossings || !e->recorded || !t)
        return rf_fail(err, RF_ENOMEM, "out of memory for %zu samples", n);
    t->start = malloc(3 * N * sizeof(double));
    t->end = malloc(3 * N * sizeof(double));
    t->runout = malloc(N * sizeof(double));
    t->reach_angle = malloc(N * sizeof(double));
    if (!t->start || !t->end || !t->runout || !t->reach_angle)
        return rf_fail(err, RF_ENOMEM, "out of memory for %zu samples", n);
    return alloc_recorded(t, rec, nc, err);
}

/* The first failed job's status, else the jobs' rasters merged in thread order into ens. */
static rf_status collect(tmc_job *jobs, int threads, rf_traj_ensemble *ens, rf_error *err)
{
    for (int t = 0; t < threads; t++)
        if (jobs[t].status != RF_OK) {
            if (err)
                *err = jobs[t].err;
            return jobs[t].status;
        }
    for (int t = 1; t < threads && jobs[0].hazard; t++)
        terrain_hazard_merge(jobs[0].hazard, jobs[t].hazard);
    ens->terrain->hazard = jobs[0].hazard;
    jobs[0].hazard = NULL;
    return RF_OK;
}

static rf_status run_jobs(const rf_traj_spec *spec, const rf_terrain_world *w, const size_t *perm, size_t first,
                          int threads, int rasters, tmc_progress *progress, rf_traj_ensemble *ens, rf_error *err)
{
    size_t N = ens->samples;
    if ((size_t)threads > N)
        threads = N ? (int)N : 1;
    tmc_job *jobs = calloc((size_t)threads, sizeof *jobs);
    rf_status st = jobs ? RF_OK : RF_ENOMEM;
    for (int t = 0; t < threads && st == RF_OK; t++) {
        jobs[t] = (tmc_job){spec, w, ens, perm, first, first + N * (size_t)t / (size_t)threads,
                            first + N * (size_t)(t + 1) / (size_t)threads,
                            rasters ? terrain_hazard_create(spec, w->dem) : NULL, RF_OK, {RF_OK, ""}, progress, t == 0};
        if (rasters && !jobs[t].hazard)
            st = RF_ENOMEM;
    }
    if (st == RF_OK) {
        traj_start_and_join(jobs, sizeof *jobs, threads, tmc_worker);
        st = collect(jobs, threads, ens, err);
    } else {
        st = rf_fail(err, RF_ENOMEM, "out of memory for the rasters of %d threads", threads);
    }
    for (int t = 0; jobs && t < threads; t++)
        terrain_hazard_free(jobs[t].hazard);
    free(jobs);
    return st;
}

rf_status terrain_run_world_part(const rf_traj_spec *spec, const rf_terrain_world *w, size_t first, size_t end,
                                 int threads, int rasters, rf_traj_progress_fn progress, void *ctx,
                                 rf_traj_ensemble *ens, rf_error *err)
{
    double t0 = rf_monotonic_seconds();
    if (!spec->terrain)
        return rf_fail(err, RF_EINVAL, "%s: not a terrain file (it has no `terrain:`)",
                       spec->file ? spec->file : "spec");
    if (first > end || end > spec->samples)
        return rf_fail(err, RF_EINVAL, "samples [%zu, %zu) are not a part of the %zu samples", first, end,
                       spec->samples);
    rf_status st = ensemble_alloc(spec, first, end, ens, err);
    size_t *perm = NULL;
    if (st == RF_OK && spec->lhs && !(perm = traj_lhs_permutations(spec, spec->n_random + 3)))
        st = rf_fail(err, RF_ENOMEM, "out of memory");
    if (threads <= 0) {
        long c = sysconf(_SC_NPROCESSORS_ONLN);
        threads = c > 0 ? (int)c : 1;
    }
    tmc_progress p = {progress, ctx, 0};
    if (st == RF_OK)
        st = run_jobs(spec, w, perm, first, threads, rasters && spec->terrain->statistics, progress ? &p : NULL,
                      ens, err);
    if (st == RF_OK)
        ens->terrain_dem = w->dem;
    free(perm);
    ens->wall_seconds = rf_monotonic_seconds() - t0;
    if (st != RF_OK)
        rf_traj_ensemble_free(ens);
    return st;
}

rf_status terrain_run_world(const rf_traj_spec *spec, const rf_terrain_world *w, int threads, int rasters,
                            rf_traj_progress_fn progress, void *ctx, rf_traj_ensemble *ens, rf_error *err)
{
    return terrain_run_world_part(spec, w, 0, spec->samples, threads, rasters, progress, ctx, ens, err);
}

rf_status rf_terrain_run_part(const rf_traj_spec *spec, size_t first, size_t end, int threads,
                              rf_traj_progress_fn progress, void *ctx, rf_traj_ensemble *ens, rf_error *err)
{
    memset(ens, 0, sizeof *ens);
    rf_status st = rf_traj_spec_validate(spec, err);
    if (st != RF_OK)
        return st;
    rf_terrain_world *w = NULL;
    if ((st = rf_terrain_world_create(spec, &w, err)) != RF_OK)
        return st;
    st = terrain_run_world_part(spec, w, first, end, threads, 1, progress, ctx, ens, err);
    if (st == RF_OK)
        ens->terrain_world = w; /* the outputs draw on its surface */
    else
        rf_terrain_world_free(w);
    return st;
}

rf_status rf_terrain_run(const rf_traj_spec *spec, int threads, rf_traj_progress_fn progress, void *ctx,
                         rf_traj_ensemble *ens, rf_error *err)
{
    return rf_terrain_run_part(spec, 0, spec->samples, threads, progress, ctx, ens, err);
}
