/* terrain_parts.c - a terrain run in parts (terrain.h, "a run in parts"):
 * a part (rf_terrain_run_part: the samples [first, end)) as bytes, and such
 * bytes appended to the ensemble of the samples before them.  MPI ranks run
 * contiguous parts and rank 0 joins them in rank order (src/cli/traj_ranks.c);
 * as every sample's results depend only on the seed and its index, and the
 * rasters merge by adding counts, the joined ensemble is the one-process
 * run's, bit for bit.
 *
 * The bytes: a header of 64-bit words (magic, the sizes of the records so
 * that a rank of another build is refused, first, samples, collectors,
 * recorded trajectories, raster words), the per-sample arrays as the
 * ensemble holds them, each recorded trajectory (its scalars, crossings,
 * impacts, events), padding to 8 bytes and the rasters' words
 * (terrain_hazard_pack).  Same byte order on every rank (a cluster of one
 * architecture); the magic word catches another. */
#include "trajectory/terrain_internal.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define PART_MAGIC 0x3154524150544652ull /* "RFTPART1" read as a little-endian word */
enum { H_MAGIC, H_CROSSING, H_IMPACT, H_EVENT, H_FIRST, H_SAMPLES, H_COLLECTORS, H_RECORDED, H_RASTER, H_WORDS };
#define NO_RASTER UINT64_MAX

typedef struct {
    unsigned char *p;
    size_t n, cap;
    int nomem;
} part_out;

static void put(part_out *o, const void *src, size_t bytes)
{
    if (o->nomem || bytes == 0)
        return;
    if (o->n + bytes > o->cap) {
        size_t cap = o->cap ? o->cap : 4096;
        while (cap < o->n + bytes)
            cap *= 2;
        unsigned char *q = realloc(o->p, cap);
        if (!q) {
            o->nomem = 1;
            return;
        }
        o->p = q, o->cap = cap;
    }
    memcpy(o->p + o->n, src, bytes);
    o->n += bytes;
}

static void put_word(part_out *o, uint64_t w)
{
    put(o, &w, sizeof w);
}

static void put_pad8(part_out *o)
{
    static const unsigned char zero[8] = {0};
    put(o, zero, (8 - o->n % 8) % 8);
}

typedef struct {
    const unsigned char *p;
    size_t n, at;
} part_in;

/* 0 if the bytes are cut. */
static int get(part_in *in, void *dst, size_t bytes)
{
    if (bytes > in->n - in->at)
        return 0;
    if (bytes)
        memcpy(dst, in->p + in->at, bytes);
    in->at += bytes;
    return 1;
}

/* The bytes left hold count elements of elem bytes. */
static int fits(const part_in *in, uint64_t count, size_t elem)
{
    return count <= (in->n - in->at) / (elem ? elem : 1);
}

static void put_recorded(part_out *o, const rf_terrain_result *r, size_t nc)
{
    double d[10] = {r->start[0], r->start[1], r->start[2], r->end[0],    r->end[1],
                    r->end[2],   r->t_end,    r->runout,   r->reach_angle, r->rebound_height};
    put_word(o, (uint64_t)r->state);
    put(o, d, sizeof d);
    put_word(o, r->n_impacts), put_word(o, r->n_steps), put_word(o, r->n_events);
    put(o, r->crossings, nc * sizeof *r->crossings);
    put(o, r->impacts, r->n_impacts * sizeof *r->impacts);
    put(o, r->events, r->n_events * sizeof *r->events);
}

rf_status rf_terrain_part_pack(const rf_traj_ensemble *part, size_t first, void **buf, size_t *bytes, rf_error *err)
{
    *buf = NULL, *bytes = 0;
    const rf_terrain_samples *t = part->terrain;
    if (!t)
        return rf_fail(err, RF_EINVAL, "not a terrain run");
    uint64_t *hz = NULL;
    size_t hz_words = 0;
    if (t->hazard && terrain_hazard_pack(t->hazard, &hz, &hz_words, err) != RF_OK)
        return err ? err->code : RF_ENOMEM;
    size_t n = part->samples, nc = part->n_collectors;
    uint64_t h[H_WORDS] = {PART_MAGIC, sizeof(rf_traj_crossing), sizeof(rf_terrain_impact), sizeof(rf_terrain_event),
                           first, n, nc, t->n_recorded, t->hazard ? hz_words : NO_RASTER};
    part_out o = {0};
    put(&o, h, sizeof h);
    put(&o, part->state, n);
    put(&o, part->runout_x, n * sizeof(double));
    put(&o, part->rebound_height, n * sizeof(double));
    put(&o, part->crossings, n * nc * sizeof *part->crossings);
    put(&o, t->start, 3 * n * sizeof(double));
    put(&o, t->end, 3 * n * sizeof(double));
    put(&o, t->runout, n * sizeof(double));
    put(&o, t->reach_angle, n * sizeof(double));
    for (size_t i = 0; i < t->n_recorded; i++)
        put_recorded(&o, &t->recorded[i], nc);
    put_pad8(&o);
    put(&o, hz, hz_words * sizeof *hz);
    free(hz);
    if (o.nomem) {
        free(o.p);
        return rf_fail(err, RF_ENOMEM, "out of memory packing %zu samples", n);
    }
    *buf = o.p, *bytes = o.n;
    return RF_OK;
}

/* Grow *p to hold n elements of elem bytes; 0 if out of memory (*p kept). */
static int grow(void *p, size_t n, size_t elem)
{
    void **pp = p;
    void *q = realloc(*pp, (n ? n : 1) * elem);
    if (!q)
        return 0;
    *pp = q;
    return 1;
}

static rf_status grow_samples(rf_traj_ensemble *e, size_t n, rf_error *err)
{
    rf_terrain_samples *t = e->terrain;
    size_t nc = e->n_collectors ? e->n_collectors : 1;
    if (!grow(&e->state, n, 1) || !grow(&e->runout_x, n, sizeof(double)) ||
        !grow(&e->rebound_height, n, sizeof(double)) || !grow(&e->crossings, n * nc, sizeof *e->crossings) ||
        !grow(&t->start, 3 * n, sizeof(double)) || !grow(&t->end, 3 * n, sizeof(double)) ||
        !grow(&t->runout, n, sizeof(double)) || !grow(&t->reach_angle, n, sizeof(double)))
        return rf_fail(err, RF_ENOMEM, "out of memory joining the parts of %zu samples", n);
    return RF_OK;
}

static rf_status get_samples(part_in *in, rf_traj_ensemble *e, size_t n, rf_error *err)
{
    size_t k = e->samples, nc = e->n_collectors;
    rf_terrain_samples *t = e->terrain;
    int ok = get(in, e->state + k, n) && get(in, e->runout_x + k, n * sizeof(double)) &&
             get(in, e->rebound_height + k, n * sizeof(double)) &&
             get(in, e->crossings + k * nc, n * nc * sizeof *e->crossings) &&
             get(in, t->start + 3 * k, 3 * n * sizeof(double)) && get(in, t->end + 3 * k, 3 * n * sizeof(double)) &&
             get(in, t->runout + k, n * sizeof(double)) && get(in, t->reach_angle + k, n * sizeof(double));
    return ok ? RF_OK : rf_fail(err, RF_EINVAL, "a packed terrain part is cut short (its samples)");
}

/* One recorded trajectory into *r (zeroed, its arrays allocated here). */
static rf_status get_recorded(part_in *in, rf_terrain_result *r, size_t nc, rf_error *err)
{
    uint64_t state, cnt[3];
    double d[10];
    if (!get(in, &state, sizeof state) || !get(in, d, sizeof d) || !get(in, cnt, sizeof cnt) ||
        !fits(in, cnt[0], sizeof *r->impacts) || !fits(in, cnt[2], sizeof *r->events))
        return rf_fail(err, RF_EINVAL, "a packed terrain part is cut short (a recorded trajectory)");
    r->state = (rf_traj_state)state;
    memcpy(r->start, d, sizeof r->start), memcpy(r->end, d + 3, sizeof r->end);
    r->t_end = d[6], r->runout = d[7], r->reach_angle = d[8], r->rebound_height = d[9];
    r->crossings = calloc(nc ? nc : 1, sizeof *r->crossings);
    r->impacts = malloc((cnt[0] ? cnt[0] : 1) * sizeof *r->impacts);
    r->events = malloc((cnt[2] ? cnt[2] : 1) * sizeof *r->events);
    if (!r->crossings || !r->impacts || !r->events)
        return rf_fail(err, RF_ENOMEM, "out of memory joining a recorded trajectory");
    r->impacts_cap = cnt[0] ? cnt[0] : 1, r->events_cap = cnt[2] ? cnt[2] : 1;
    r->n_impacts = cnt[0], r->n_steps = cnt[1], r->n_events = cnt[2];
    if (!get(in, r->crossings, nc * sizeof *r->crossings) || !get(in, r->impacts, r->n_impacts * sizeof *r->impacts) ||
        !get(in, r->events, r->n_events * sizeof *r->events))
        return rf_fail(err, RF_EINVAL, "a packed terrain part is cut short (a recorded trajectory)");
    return RF_OK;
}

static rf_status get_all_recorded(part_in *in, rf_terrain_samples *t, size_t count, size_t nc, rf_error *err)
{
    if (!grow(&t->recorded, t->n_recorded + count, sizeof *t->recorded))
        return rf_fail(err, RF_ENOMEM, "out of memory joining %zu recorded trajectories", count);
    for (size_t i = 0; i < count; i++) {
        rf_terrain_result *r = &t->recorded[t->n_recorded];
        memset(r, 0, sizeof *r);
        t->n_recorded++; /* counted at once: freed with the ensemble whatever happens next */
        rf_status st = get_recorded(in, r, nc, err);
        if (st != RF_OK)
            return st;
    }
    return RF_OK;
}

static rf_status get_rasters(part_in *in, rf_terrain_samples *t, uint64_t words, rf_error *err)
{
    if ((words == NO_RASTER) != (t->hazard == NULL))
        return rf_fail(err, RF_EINVAL, "a packed terrain part %s rasters and the run %s",
                       words == NO_RASTER ? "has no" : "has", t->hazard ? "has" : "has none");
    if (words == NO_RASTER)
        return RF_OK;
    size_t pad = (8 - in->at % 8) % 8;
    if (pad > in->n - in->at)
        return rf_fail(err, RF_EINVAL, "a packed terrain part's rasters are cut short");
    in->at += pad;
    if (!fits(in, words, sizeof(uint64_t)) || in->n - in->at != words * sizeof(uint64_t))
        return rf_fail(err, RF_EINVAL, "a packed terrain part's rasters are cut short or followed by other bytes");
    uint64_t *w = malloc((words ? words : 1) * sizeof *w);
    if (!w)
        return rf_fail(err, RF_ENOMEM, "out of memory joining the rasters");
    get(in, w, words * sizeof *w);
    rf_status st = terrain_hazard_merge_packed(t->hazard, w, words, err);
    free(w);
    return st;
}

static rf_status check_header(const uint64_t h[H_WORDS], const rf_traj_ensemble *e, rf_error *err)
{
    if (h[H_MAGIC] != PART_MAGIC || h[H_CROSSING] != sizeof(rf_traj_crossing) ||
        h[H_IMPACT] != sizeof(rf_terrain_impact) || h[H_EVENT] != sizeof(rf_terrain_event))
        return rf_fail(err, RF_EINVAL, "a packed terrain part of another rockfuzz build or machine (magic or record "
                                       "sizes differ): run every rank with the same binary on one architecture");
    if (h[H_FIRST] != e->samples)
        return rf_fail(err, RF_EINVAL, "a packed terrain part starts at sample %llu, the run holds samples [0, %zu): "
                       "the parts must be joined in order", (unsigned long long)h[H_FIRST], e->samples);
    if (h[H_COLLECTORS] != e->n_collectors)
        return rf_fail(err, RF_EINVAL, "a packed terrain part has %llu barriers, the run %zu",
                       (unsigned long long)h[H_COLLECTORS], e->n_collectors);
    if (h[H_RECORDED] > 0 && e->terrain->n_recorded != e->samples)
        return rf_fail(err, RF_EINVAL, "a packed terrain part records trajectories after unrecorded ones");
    if (h[H_RECORDED] > h[H_SAMPLES] || h[H_SAMPLES] > SIZE_MAX / 64 - e->samples)
        return rf_fail(err, RF_EINVAL, "a packed terrain part's counts are not possible");
    return RF_OK;
}

rf_status rf_terrain_part_join(rf_traj_ensemble *ens, const void *buf, size_t bytes, rf_error *err)
{
    if (!ens->terrain)
        return rf_fail(err, RF_EINVAL, "not a terrain run");
    part_in in = {buf, bytes, 0};
    uint64_t h[H_WORDS];
    if (!get(&in, h, sizeof h))
        return rf_fail(err, RF_EINVAL, "a packed terrain part is cut short (%zu bytes)", bytes);
    rf_status st = check_header(h, ens, err);
    size_t n = (size_t)h[H_SAMPLES];
    if (st == RF_OK && !fits(&in, n, 1 + 10 * sizeof(double) + ens->n_collectors * sizeof(rf_traj_crossing)))
        st = rf_fail(err, RF_EINVAL, "a packed terrain part is cut short (%llu samples in %zu bytes)",
                     (unsigned long long)n, bytes);
    if (st == RF_OK)
        st = grow_samples(ens, ens->samples + n, err);
    if (st == RF_OK)
        st = get_samples(&in, ens, n, err);
    if (st == RF_OK)
        st = get_all_recorded(&in, ens->terrain, (size_t)h[H_RECORDED], ens->n_collectors, err);
    if (st == RF_OK)
        st = get_rasters(&in, ens->terrain, h[H_RASTER], err);
    if (st == RF_OK)
        ens->samples += n;
    return st;
}
