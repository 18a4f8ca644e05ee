/* SPDX-License-Identifier: MIT */
/* test_bne.c: Brazil-nut checks on reduced sizes (thesis 002 ch. 5; scenes/brazil_nut/small.scene,
 * 300 grains), without rendering: the box follows the prescribed sinusoid exactly, grains never
 * tunnel through the moving base, no rise below Gamma = 1, the periodic seam changes nothing, and
 * the rise-time and large-deviation helpers. Slow orderings are in test_long_bne.c. */
#include "test.h"

#include "run/run.h"
#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bne/bne.h"

#define SMALL "scenes/brazil_nut/small.scene"
#define TPI   3.14159265358979323846

static Scene *load_small(const char *const *extra, int extra_count)
{
    const char *sets[16];
    int n = 0;
    for (int k = 0; k < extra_count && n < 16; ++k)
        sets[n++] = extra[k];
    char err[1024] = "";
    Scene *scene = scene_load(SMALL, sets, n, err, sizeof err);
    if (!scene)
        fprintf(stderr, "%s\n", err);
    return scene;
}

/* Gamma and the period set A = Gamma g / w^2; the walls follow y = A sin(w (t - t0)) to round-off
 * and grains never cross the moving floor or the side walls. */
static int box_motion_and_no_tunnelling(void)
{
    const char *sets[] = {"bne.gamma=3.0"};
    Scene *scene = load_small(sets, 1);
    TEST_ASSERT(scene && app_bne_of(scene));
    AppBneResult r = app_bne_result(app_bne_of(scene));
    double omega = 2.0 * TPI / 3.953;
    TEST_REL(r.amplitude, 3.0 * 1.0 / (omega * omega), 1e-12);
    /* the shaking stage's definition (phase 0 at t = 0), grains raining from the start */
    SimWorldDef def = scene_world_def(scene, 1);
    TEST_REL(def.motions[0].amplitude, r.amplitude, 1e-15);
    SimWorldDef def0 = scene_world_def(scene, 0);
    TEST_NEAR(def0.motions[0].amplitude, 0.0, 0.0); /* preparation at rest */
    SimError err;
    SimWorld *w = sim_world_create(&def, &err);
    TEST_ASSERT(w);
    double worst_wall = 0.0, lowest = INFINITY;
    for (int chunk = 0; chunk < 400; ++chunk) { /* 40 time units, 10 periods */
        TEST_ASSERT(sim_world_step(w, 100, &err) == SIM_OK);
        SimFrame f;
        sim_world_frame(w, &f);
        double y = r.amplitude * sin(omega * f.time);
        for (int k = 0; k < f.wall_count; ++k)
            worst_wall = fmax(worst_wall, fabs(f.walls[k].y0 - (k == 0 ? 0.0 : 0.0) - y));
        for (int i = 0; i < f.mobile_count; ++i) {
            lowest = fmin(lowest, (f.y[i] - y) / f.radius[i]);
            TEST_ASSERT(f.x[i] > 0.0 && f.x[i] < 15.0);
        }
    }
    printf("largest wall deviation from A sin(w t): %.3g; lowest centre above the floor: %.3f r\n",
           worst_wall, lowest);
    TEST_ASSERT(worst_wall < 1e-12);
    /* never through the floor: grains raining from 58 d hit it at ~11 sqrt(g d), the deepest
     * overlap stays below half a radius */
    TEST_ASSERT(lowest > 0.5);
    sim_world_destroy(w);
    scene_free(scene);
    return 0;
}

static int run_small(const char *const *sets, int n, const char *tag, AppBneResult *out,
                     Scene **keep)
{
    Scene *scene = load_small(sets, n);
    if (!scene)
        return -1;
    char dir[256];
    snprintf(dir, sizeof dir, "/tmp/sablier_test_bne_%ld_%s", (long)getpid(), tag);
    AppRunOptions o = app_run_options_default();
    o.out_dir = dir;
    o.quiet = 1;
    int rc = app_run(scene, &o);
    if (rc == 0)
        *out = app_bne_result(app_bne_of(scene));
    *keep = scene;
    return rc;
}

/* Gamma = 0.8 < 1: the bed never leaves the floor and the intruder stays put (002 §3.4.7):
 * |rise| < 0.2 d over 10 periods. */
static int no_rise_below_one(void)
{
    const char *sets[] = {"bne.gamma=0.8", "stages.shake.time.end=39.53"};
    AppBneResult r;
    Scene *scene = NULL;
    TEST_ASSERT(run_small(sets, 2, "gamma08", &r, &scene) == 0);
    printf("Gamma 0.8: rise %.4f d over %.1f\n", r.end_height - r.start_height, r.shaking_time);
    TEST_ASSERT(fabs(r.end_height - r.start_height) < 0.2);
    TEST_ASSERT(isnan(r.rise_time));
    double low = INFINITY, high = -INFINITY;
    for (int k = 0; k < r.count; ++k) {
        low = fmin(low, r.height[k]);
        high = fmax(high, r.height[k]);
    }
    TEST_ASSERT(high - low < 0.2);
    scene_free(scene);
    return 0;
}

/* A periodic bed shaken by its floor: translating everything by half the period across the seam
 * gives the same intruder trajectory (to the round-off of a different summation order). */
static SimWorld *periodic_world(double shift, SimGrainBuffer *b)
{
    const double L = 20.0;
    SimWorldDef def = sim_world_def_default();
    def.effects = SIM_EFFECT_FRICTION | SIM_EFFECT_PERIODIC_X | SIM_EFFECT_VIBRATION;
    def.domain_x0 = 0.0;
    def.domain_x1 = L;
    def.gravity_y = -1.0;
    def.time_step = 1e-3;
    def.species_count = 1;
    def.materials[0] = sim_material_default();
    def.materials[0].density = 1.0 / TPI;
    def.materials[0].normal_stiffness = 1000.0;
    def.materials[0].damping_mode = SIM_DAMPING_CRITICAL;
    def.materials[0].critical_fraction = 1.0;
    def.materials[0].friction = 0.5;
    def.materials[0].tangential_stiffness = 750.0;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.motion_count = 1;
    double omega = 2.0 * TPI / 3.953;
    def.motions[0] = (SimMotion){
        .amplitude = 3.0 / (omega * omega), .frequency = 1.0 / 3.953, .direction_y = 1.0};
    static SimWall floor_wall[1];
    floor_wall[0] =
        (SimWall){.x0 = -100.0, .y0 = 0.0, .x1 = 100.0, .y1 = 0.0, .species = 0, .motion = 0};
    def.walls = floor_wall;
    def.wall_count = 1;
    sim_grain_buffer_init(b);
    SimRng rng;
    sim_rng_seed(&rng, 5);
    /* the intruder straddles the seam */
    sim_grain_buffer_add(b, fmod(0.5 + shift, L), 2.6, 2.5, 0, 0, -1);
    for (int row = 0; row < 8; ++row)
        for (int col = 0; col < 17; ++col) {
            double x = 3.5 + col * 1.05 + (row % 2) * 0.3, y = 0.6 + 1.1 * row;
            if (y < 5.4 && (x < 3.3 || x > L - 2.3))
                continue; /* keep clear of the intruder (centre at x = 0.5) */
            double r = 0.5 * (1.0 + 0.025 * (2.0 * sim_rng_uniform(&rng) - 1.0));
            sim_grain_buffer_add(b, fmod(x + shift, L), y + 3.0, r, 0, 0, -1);
        }
    def.grains = sim_grain_buffer_view(b);
    SimError err;
    SimWorld *w = sim_world_create(&def, &err);
    if (!w)
        fprintf(stderr, "%s: %s\n", err.field, err.message);
    return w;
}

static int periodic_seam(void)
{
    SimGrainBuffer a, b;
    SimWorld *wa = periodic_world(0.0, &a), *wb = periodic_world(10.0, &b);
    TEST_ASSERT(wa && wb);
    SimError err;
    double worst = 0.0, early = 0.0;
    for (int chunk = 0; chunk < 80; ++chunk) { /* 2 periods at Gamma = 3 */
        TEST_ASSERT(sim_world_step(wa, 100, &err) == SIM_OK);
        TEST_ASSERT(sim_world_step(wb, 100, &err) == SIM_OK);
        SimFrame fa, fb;
        sim_world_frame(wa, &fa);
        int ia = -1;
        for (int i = 0; i < fa.mobile_count; ++i)
            if (fa.id[i] == 0)
                ia = i;
        double xa = fa.x[ia], ya = fa.y[ia];
        sim_world_frame(wb, &fb);
        int ib = -1;
        for (int i = 0; i < fb.mobile_count; ++i)
            if (fb.id[i] == 0)
                ib = i;
        double dx = fb.x[ib] - xa - 10.0;
        dx -= 20.0 * floor(dx / 20.0 + 0.5);
        worst = fmax(worst, fmax(fabs(dx), fabs(fb.y[ib] - ya)));
        if (chunk == 9)
            early = worst;
    }
    /* the summation order differs across the seam, and the granular dynamics amplifies that
     * round-off: identical to 1e-9 d over the first time unit, within 1e-3 d after two periods */
    printf("intruder: largest difference between the two framings %.3g d after 1 time unit, "
           "%.3g d after 2 periods\n",
           early, worst);
    TEST_ASSERT(early < 1e-9);
    TEST_ASSERT(worst < 1e-3);
    sim_world_destroy(wa);
    sim_world_destroy(wb);
    sim_grain_buffer_free(&a);
    sim_grain_buffer_free(&b);
    return 0;
}

static int rise_time_and_ldf(void)
{
    double t[5] = {0, 1, 2, 3, 4}, h[5] = {2, 3, 5, 8, 9};
    TEST_NEAR(app_bne_rise_time(t, h, 5, 1.0, 10.0, 1.0), 3.0, 0.0); /* top 9 >= 10 - 1 */
    TEST_ASSERT(isnan(app_bne_rise_time(t, h, 5, 0.5, 20.0, 1.0)));
    /* a record rising at constant rate 1: every window of tau = 2 has v = 1 */
    double tt[11], hh[11];
    for (int k = 0; k <= 10; ++k) {
        tt[k] = k;
        hh[k] = k;
    }
    const double *ts[1] = {tt}, *hs[1] = {hh};
    int counts[1] = {11};
    double c[4], p[4], rf[4];
    int windows = app_bne_ldf(ts, hs, counts, 1, 2.0, 4, 0.0, 2.0, c, p, rf);
    TEST_ASSERT(windows == 5);
    TEST_NEAR(p[2], 1.0, 1e-12); /* bin [1, 1.5) */
    TEST_NEAR(rf[2], 0.0, 0.0);
    TEST_ASSERT(isnan(rf[0]));
    /* tau = inf once never advanced a window and wrote past the rate array (a heap
     * overflow); a tau below the samples' spacing gives one window per sample pair */
    TEST_ASSERT(app_bne_ldf(ts, hs, counts, 1, INFINITY, 4, 0.0, 2.0, c, p, rf) == 0);
    TEST_ASSERT(app_bne_ldf(ts, hs, counts, 1, NAN, 4, 0.0, 2.0, c, p, rf) == 0);
    TEST_ASSERT(app_bne_ldf(ts, hs, counts, 1, 1e-300, 4, 0.0, 2.0, c, p, rf) == 10);
    return 0;
}

/* The rise chart's and the LDF's axes carry the scene's units: the rise rate is a speed,
 * sqrt(g d) in a normalised scene, m/s in an SI one (the figure lint wants a unit on every axis).
 */
static int axis_units(void)
{
    char err[2048], time[64], rise[64], rate[64];
    Scene *scene = scene_load(SMALL, NULL, 0, err, sizeof err);
    TEST_ASSERT(scene != NULL);
    app_bne_axis_labels(scene, time, rise, rate);
    TEST_ASSERT(strcmp(time, "time since shaking starts / \xe2\x88\x9a(d/g)") == 0);
    TEST_ASSERT(strcmp(rise, "intruder height rise / d") == 0);
    TEST_ASSERT(strcmp(rate, "windowed rise rate v / \xe2\x88\x9a(gd)") == 0);
    scene_free(scene);
    const char *si[] = {"units=\"SI\""};
    scene = scene_load(SMALL, si, 1, err, sizeof err);
    TEST_ASSERT(scene != NULL);
    app_bne_axis_labels(scene, time, rise, rate);
    TEST_ASSERT(strcmp(rate, "windowed rise rate v (m/s)") == 0);
    scene_free(scene);
    app_bne_axis_labels(NULL, time, rise, rate); /* units unknown: bare */
    TEST_ASSERT(strcmp(rate, "windowed rise rate v") == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(box_motion_and_no_tunnelling), TEST_CASE(no_rise_below_one),
          TEST_CASE(periodic_seam), TEST_CASE(rise_time_and_ldf), TEST_CASE(axis_units))
