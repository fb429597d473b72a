/* traj_model_raster.c - the raster sink of trajectory models (see
 * terrain_internal.h): a small table from a model's ctx to the sink a study
 * set on it.  traj_model.c calls traj_model_raster_emit after a terrain
 * evaluation; nothing here knows what the sink does with the bands. */
#include "trajectory/terrain_internal.h"

#include <pthread.h>

#define MAX_SINKS 16

static struct {
    const void *model_ctx;
    traj_raster_sink sink;
    void *ctx;
} table[MAX_SINKS];
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

rf_status traj_model_raster_sink_set(const rf_model *m, traj_raster_sink sink, void *ctx, rf_error *err)
{
    rf_status st = RF_OK;
    pthread_mutex_lock(&lock);
    size_t k = 0, free_at = MAX_SINKS;
    for (; k < MAX_SINKS && table[k].model_ctx != m->ctx; k++)
        if (!table[k].model_ctx && free_at == MAX_SINKS)
            free_at = k;
    if (k == MAX_SINKS)
        k = free_at;
    if (k < MAX_SINKS) {
        table[k].model_ctx = sink ? m->ctx : NULL;
        table[k].sink = sink;
        table[k].ctx = sink ? ctx : NULL;
    } else if (sink) {
        st = rf_fail(err, RF_ECAP, "raster sinks: %d models have one already", MAX_SINKS);
    }
    pthread_mutex_unlock(&lock);
    return st;
}

int traj_model_raster_wanted(const void *model_ctx)
{
    int found = 0;
    pthread_mutex_lock(&lock);
    for (size_t k = 0; k < MAX_SINKS && !found; k++)
        found = model_ctx && table[k].model_ctx == model_ctx;
    pthread_mutex_unlock(&lock);
    return found;
}

rf_status traj_model_raster_emit(const void *model_ctx, const double *x, size_t n_params, const terrain_band *bands,
                                 size_t n_bands, const traj_raster_grid *grid, rf_error *err)
{
    traj_raster_sink sink = NULL;
    void *ctx = NULL;
    pthread_mutex_lock(&lock);
    for (size_t k = 0; k < MAX_SINKS && !sink; k++)
        if (model_ctx && table[k].model_ctx == model_ctx) {
            sink = table[k].sink;
            ctx = table[k].ctx;
        }
    pthread_mutex_unlock(&lock);
    return sink ? sink(ctx, x, n_params, bands, n_bands, grid, err) : RF_OK;
}
