/* traj_draw.c - the random inputs of one Monte Carlo sample, shared by the
 * profile (montecarlo.c) and terrain (terrain_montecarlo.c) ensembles.
 * Sample i draws its input dimension j from the counter-based uniform
 * U(seed, stream 2i, index j) (its roughness draws take stream 2i + 1),
 * optionally stratified by a Latin hypercube: u = (perm_j[i] + U) / N with
 * perm_j a random permutation of 0..N-1 drawn from (seed, LHS stream + j).
 * Dimensions 0..n_random-1 are the random inputs; the release point takes
 * the next ones (one on a profile line or zone, three on a terrain map).
 * Everything is a pure function of (seed, i, j): the same bits on any thread
 * or rank. */
#include "trajectory/traj_internal.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>

#define LHS_STREAM 0x4000000000000000ULL

static double normal_cdf(double z) { return 0.5 * erfc(-z / sqrt(2.0)); }

double traj_draw_value(const rf_traj_random *r, double u)
{
    if (r->dist == RF_DIST_UNIFORM)
        return r->a + u * (r->b - r->a);
    if (r->dist == RF_DIST_NORMAL) {
        if (!(r->b > 0))
            return r->a;
        double plo = isfinite(r->lo) ? normal_cdf((r->lo - r->a) / r->b) : 0;
        double phi = isfinite(r->hi) ? normal_cdf((r->hi - r->a) / r->b) : 1;
        double x = r->a + r->b * rf_traj_normal_quantile(plo + u * (phi - plo));
        return fmin(fmax(x, r->lo), r->hi);
    }
    return r->a;
}

double traj_sample_u(const rf_traj_spec *s, const size_t *perm, size_t i, size_t j)
{
    double u = rf_traj_uniform(s->seed, 2 * (uint64_t)i, j);
    size_t N = s->samples;
    return perm ? ((double)perm[j * N + i] + u) / (double)N : u;
}

size_t *traj_lhs_permutations(const rf_traj_spec *s, size_t dims)
{
    size_t N = s->samples;
    size_t *p = malloc((dims * N > 0 ? dims * N : 1) * sizeof *p);
    if (!p)
        return NULL;
    for (size_t j = 0; j < dims; j++) {
        size_t *q = p + j * N;
        for (size_t i = 0; i < N; i++)
            q[i] = i;
        for (size_t i = N; i > 1; i--) { /* Fisher-Yates */
            size_t k = (size_t)(rf_traj_uniform(s->seed, LHS_STREAM + j, i) * (double)i);
            size_t t = q[i - 1];
            q[i - 1] = q[k < i ? k : i - 1];
            q[k < i ? k : i - 1] = t;
        }
    }
    return p;
}

void traj_draw_bind(rf_traj_spec *local, const rf_traj_spec *spec, const rf_traj_field **row, double **field)
{
    for (size_t j = 0; j < spec->n_random; j++)
        row[j] = rf_traj_field_at(local, spec->random[j].path, &field[j]);
}

void traj_draw_inputs(const rf_traj_spec *spec, const size_t *perm, size_t i, const rf_traj_field *const *row,
                      double *const *field)
{
    for (size_t j = 0; j < spec->n_random; j++)
        if (row[j]) /* in the row's units: an angle drawn in degrees, stored in radians */
            *field[j] = traj_field_store(row[j], traj_draw_value(&spec->random[j], traj_sample_u(spec, perm, i, j)));
}

void traj_start_and_join(void *jobs, size_t job_size, int threads, void *(*worker)(void *))
{
    char *job = jobs;
    pthread_t *tid = calloc((size_t)threads, sizeof *tid);
    char *started = calloc((size_t)threads, 1);
    for (int t = 1; tid && started && t < threads; t++)
        started[t] = pthread_create(&tid[t], NULL, worker, job + (size_t)t * job_size) == 0;
    worker(job);
    for (int t = 1; t < threads; t++) {
        if (started && started[t])
            pthread_join(tid[t], NULL);
        else
            worker(job + (size_t)t * job_size); /* could not start a thread: do its share here */
    }
    free(tid);
    free(started);
}
