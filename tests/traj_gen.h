/* traj_gen.h - trajectory files generated from bytes, for the fuzzer
 * (tests/fuzz/fuzz_trajectory.c) and for the generated cases of
 * tests/test_traj_ground.c: profiles chained from slopes, flats, vertical
 * steps up and down, pits and V-notches (sides 30 to 85 deg), a point block
 * or a sphere, any bounce law but impact_model, a release on the ground or
 * above it.  traj_gen_run loads such a file, runs one trajectory with its
 * events recorded and checks the invariants (traj_invariants.c). */
#ifndef ROCKFUZZ_TRAJ_GEN_H
#define ROCKFUZZ_TRAJ_GEN_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rockfuzz/trajectory.h"
#include "trajectory/traj_internal.h"

#define TRAJ_GEN_MAX_POINTS 64

typedef struct {
    const uint8_t *p;
    size_t n, i;
} traj_gen_bytes;

static inline unsigned traj_gen_byte(traj_gen_bytes *b) { return b->i < b->n ? b->p[b->i++] : 0; }

typedef struct {
    double x[TRAJ_GEN_MAX_POINTS], y[TRAJ_GEN_MAX_POINTS];
    size_t n;
} traj_gen_profile;

static inline void traj_gen_add(traj_gen_profile *p, double dx, double dy)
{
    if (p->n < TRAJ_GEN_MAX_POINTS)
        p->x[p->n] = p->x[p->n - 1] + dx, p->y[p->n] = p->y[p->n - 1] + dy, p->n++;
}

/* One feature; never two vertical segments in a row (they could fold back). */
static inline void traj_gen_feature(traj_gen_profile *p, traj_gen_bytes *b)
{
    static const double angle[6] = {30, 45, 60, 75, 85, 45};
    unsigned kind = traj_gen_byte(b) % 6, v = traj_gen_byte(b);
    double w = 1 + v % 20, h = 0.5 + (v % 37) * 0.5;
    double t = tan(angle[traj_gen_byte(b) % 6] * (3.14159265358979323846 / 180));
    switch (kind) {
    case 0: traj_gen_add(p, w, ((int)(v % 41) - 20) * w / 10); break;              /* slope, -2 to 2 */
    case 1: traj_gen_add(p, 0, h), traj_gen_add(p, w, 0); break;                   /* step up, flat */
    case 2: traj_gen_add(p, 0, -h), traj_gen_add(p, w, 0); break;                  /* step down, flat */
    case 3: traj_gen_add(p, 0, -h), traj_gen_add(p, w, 0), traj_gen_add(p, 0, h),  /* pit */
            traj_gen_add(p, 1 + v % 3, 0); break;
    case 4: traj_gen_add(p, h / t, -h), traj_gen_add(p, h / t, h); break;           /* V-notch */
    default: traj_gen_add(p, w, 0); break;                                           /* flat */
    }
}

/* The ground at a fraction f of segment i (non-vertical). */
static inline void traj_gen_release_point(const traj_gen_profile *p, traj_gen_bytes *b, double *x, double *y)
{
    size_t cand[TRAJ_GEN_MAX_POINTS], nc = 0;
    for (size_t i = 0; i + 1 < p->n; i++)
        if (p->x[i + 1] > p->x[i])
            cand[nc++] = i;
    size_t i = cand[traj_gen_byte(b) % nc];
    double f = (1 + traj_gen_byte(b) % 254) / 256.0;
    *x = p->x[i] + f * (p->x[i + 1] - p->x[i]);
    *y = p->y[i] + f * (p->y[i + 1] - p->y[i]);
}

/* A trajectory file from the bytes into buf (always loads); its length. */
static inline size_t traj_gen_yaml(const uint8_t *data, size_t size, char *buf, size_t cap)
{
    traj_gen_bytes b = {data, size, 0};
    traj_gen_profile p = {{0}, {100}, 1};
    traj_gen_add(&p, 5 + traj_gen_byte(&b) % 10, -(double)(traj_gen_byte(&b) % 20));
    for (unsigned k = 0, nf = 1 + traj_gen_byte(&b) % 8; k < nf; k++)
        traj_gen_feature(&p, &b);
    traj_gen_add(&p, 1 + traj_gen_byte(&b) % 10, 0);
    size_t len = (size_t)snprintf(buf, cap, "profile: {points: [");
    for (size_t i = 0; i < p.n && len < cap; i++)
        len += (size_t)snprintf(buf + len, cap - len, "%s[%.17g, %.17g]", i ? ", " : "", p.x[i], p.y[i]);
    double x0, y0;
    traj_gen_release_point(&p, &b, &x0, &y0);
    unsigned u = traj_gen_byte(&b), sphere = u & 1, law = (u >> 1) % 3, above = (u >> 3) % 3;
    double Rn = traj_gen_byte(&b) / 255.0, Rt = traj_gen_byte(&b) / 255.0, phi = traj_gen_byte(&b) % 85;
    double rough = (u >> 5) == 0 ? traj_gen_byte(&b) % 20 : 0, mur = (traj_gen_byte(&b) % 4) * 0.05;
    double vx = ((int)traj_gen_byte(&b) - 128) / 8.0, vy = ((int)traj_gen_byte(&b) - 128) / 8.0;
    double w = ((int)traj_gen_byte(&b) - 128) / 16.0, lift = above ? (traj_gen_byte(&b) % 50) * 0.5 : 0;
    static const char *const laws[3] = {"constant", "velocity_scaled", "rigid_sphere"};
    if (len < cap)
        len += (size_t)snprintf(
            buf + len, cap - len,
            "], material: m}\n"
            "materials: {m: {R_n: %.17g, R_t: %.17g, friction_angle: %g, rolling_resistance: %g, roughness: %g}}\n"
            "block: %s\n"
            "release: {x: %.17g, y: %.17g, vx: %g, vy: %g, omega: %g}\n"
            "bounce: {law: %s, contact_speed: %g}\n"
            "stop: {v_stop: %g, max_steps: 2000}\n"
            "seed: %u\n",
            Rn, Rt, phi, mur, rough, sphere ? "{shape: sphere, radius: 0.5, density: 2700}" : "{shape: point, mass: 1000}",
            x0, y0 + lift, vx, above == 2 ? vy : 0.0, sphere ? w : 0.0, laws[sphere ? law : law % 2],
            traj_gen_byte(&b) % 4 ? 0.1 : 0.0, traj_gen_byte(&b) % 5 ? 0.1 : 0.01, traj_gen_byte(&b));
    return len < cap ? len : cap - 1;
}

/* Load, simulate with events and check the invariants; 0: fine, 1: an
 * invariant broken or the run failed (err says why), -1: the file does not load. */
static inline int traj_gen_run(const char *yaml, size_t len, uint64_t sample, rf_error *err)
{
    rf_traj_spec s;
    if (rf_traj_load_buffer("gen.yaml", yaml, len, &s, err) != RF_OK)
        return -1;
    rf_traj_world *w = NULL;
    rf_traj_crossing cross[1];
    rf_traj_result r;
    memset(&r, 0, sizeof r);
    r.crossings = cross;
    r.events = malloc(16 * sizeof *r.events), r.events_cap = 16;
    if (!r.events) {
        rf_traj_spec_free(&s);
        rf_fail(err, RF_ENOMEM, "out of memory");
        return 1;
    }
    int bad = rf_traj_world_create(&s, &w, err) != RF_OK ||
              rf_traj_simulate(w, &s, s.seed, sample, &r, err) != RF_OK || traj_check_invariants(&s, &r, err) != RF_OK;
    free(r.events);
    rf_traj_world_free(w);
    rf_traj_spec_free(&s);
    return bad;
}

#endif
