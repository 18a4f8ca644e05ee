/* SPDX-License-Identifier: MIT */
/* test_long_bne.c: the Brazil nut effect itself on the reduced box (scenes/brazil_nut/small.scene:
 * 300 grains, 15 d wide, frictional walls, Gamma = 3, 30 periods of 3.953), three seeds, about
 * 3 s in Release (label slow). Bounds from the measured rises 8.4, 11.8 and 13.3 d: every seed
 * rises by more than 5 d and the mean by more than 8 d, while the same box at Gamma = 0.8 moves the
 * intruder by less than 0.2 d (test_bne.c).
 *
 * Frictionless walls (002 §3.4 item 3, fig. 25): the same box with wall mu = 0 (harmonic mixing
 * makes every grain-wall contact frictionless) rises much less. Over 16 seeds (docs/brazil_nut.md)
 * the rise (mean height over the last 20 time units minus the start) was 12.3 +- 1.6 d with
 * frictional walls and 3.7 +- 0.6 d with smooth ones (95 % intervals), ranges 7.8-19.8 and 1.8-5.7
 * d: no overlap. Seeds 1-3 gave 10.9, 9.9, 10.7 against 4.2, 3.2, 4.5. Bounds: every smooth-wall
 * seed below every frictional one, and the means at least 3 d apart.
 *
 * Fully frictionless box (002 fig. 26, scenes/brazil_nut/small_frictionless.scene): mu = 0
 * everywhere, intruder dropped on top, restitution 0.99, Gamma = 2, 50 periods. Measured (4
 * seeds): the intruder's mean height over the last 10 periods 3.6-4.1 d above the floor (2.5 =
 * resting on it), from a start near 14 d; with restitution 0.9 (same scene otherwise) it stays at
 * 13.7 d or higher over 6 seeds. Bounds: every seed starts above 12 and ends below 6 with e = 0.99,
 * and ends above 10 with e = 0.9.
 *
 * Intruder density (002 figs. 22-24, scenes/brazil_nut/small_density.scene: critical damping,
 * Gamma = 1.5, 30 periods): a lighter intruder rises faster, weakly. Measured over seeds 1-32:
 * rise 2.8 d for rho_I / rho = 1/3 against 2.0 d for 3, difference +0.86 d (95 % +0.43 .. +1.28;
 * 16 seeds do not resolve it). Bound: the mean difference over the 32 seeds > 0.3 d (2.5 standard
 * errors below the measured value). The run is deterministic; the bound guards against a change
 * of the physics that reverses the ordering (at Gamma >= 2 or restitution >= 0.9 it is reversed:
 * docs/brazil_nut.md). */
#include "test.h"

#include "run/run.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <unistd.h>

#include "bne/bne.h"

static int rises_with_frictional_walls(void)
{
    double sum = 0.0;
    for (int seed = 1; seed <= 3; ++seed) {
        char seed_set[32], dir[256], err[1024] = "";
        snprintf(seed_set, sizeof seed_set, "seed=%d", seed);
        const char *sets[] = {seed_set};
        Scene *scene = scene_load("scenes/brazil_nut/small.scene", sets, 1, err, sizeof err);
        TEST_ASSERT(scene);
        snprintf(dir, sizeof dir, "/tmp/sablier_test_long_bne_%ld_%d", (long)getpid(), seed);
        AppRunOptions o = app_run_options_default();
        o.out_dir = dir;
        o.quiet = 1;
        TEST_ASSERT(app_run(scene, &o) == 0);
        AppBneResult r = app_bne_result(app_bne_of(scene));
        double rise = r.end_height - r.start_height;
        printf("seed %d: rise %.2f d in %.1f (rise time %g)\n", seed, rise, r.shaking_time,
               r.rise_time);
        TEST_ASSERT(rise > 5.0);
        sum += rise;
        scene_free(scene);
    }
    TEST_ASSERT(sum / 3.0 > 8.0);
    return 0;
}

/* Runs `scene` with `seed` and the --set assignments `sets`, and gives the intruder's height at
 * the start of shaking and its mean height over the last `window` time units (box frame). */
static int late_height(const char *scene_path, int seed, const char *const *sets, int set_count,
                       double window, double *start, double *late)
{
    char seed_set[32], dir[256], err[1024] = "";
    snprintf(seed_set, sizeof seed_set, "seed=%d", seed);
    const char *all[8] = {seed_set};
    for (int k = 0; k < set_count && k < 7; ++k)
        all[k + 1] = sets[k];
    Scene *scene = scene_load(scene_path, all, set_count + 1, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    static int run_index = 0;
    snprintf(dir, sizeof dir, "/tmp/sablier_test_long_bne_%ld_%d", (long)getpid(), ++run_index);
    AppRunOptions o = app_run_options_default();
    o.out_dir = dir;
    o.quiet = 1;
    int rc = app_run(scene, &o);
    if (rc == 0) {
        AppBneResult r = app_bne_result(app_bne_of(scene));
        double sum = 0.0;
        int n = 0;
        for (int k = 0; k < r.count; ++k)
            if (r.t[k] >= r.shaking_time - window) {
                sum += r.height[k];
                ++n;
            }
        *start = r.start_height;
        *late = n ? sum / n : (double)NAN;
    }
    scene_free(scene);
    return rc;
}

/* Rise of one seed: the intruder's mean height over the last 20 time units (the bed flies at
 * Gamma = 3: one sample is at an arbitrary phase) minus its start height. */
static int late_rise(const char *wall_mu, int seed, double *rise)
{
    char mu_set[64];
    snprintf(mu_set, sizeof mu_set, "species.wall.mu=%s", wall_mu);
    const char *sets[] = {mu_set};
    double start, late;
    int rc = late_height("scenes/brazil_nut/small.scene", seed, sets, 1, 20.0, &start, &late);
    *rise = late - start;
    return rc;
}

static int smooth_walls_rise_slower(void)
{
    double rough[3], smooth[3], mean_rough = 0.0, mean_smooth = 0.0;
    for (int s = 0; s < 3; ++s) {
        TEST_ASSERT(late_rise("0.5", s + 1, &rough[s]) == 0);
        TEST_ASSERT(late_rise("0.0", s + 1, &smooth[s]) == 0);
        printf("seed %d: rise %.2f d with frictional walls, %.2f d with smooth walls\n", s + 1,
               rough[s], smooth[s]);
        mean_rough += rough[s] / 3.0;
        mean_smooth += smooth[s] / 3.0;
    }
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            TEST_ASSERT(smooth[a] < rough[b]);
    TEST_ASSERT(mean_rough - mean_smooth > 3.0);
    return 0;
}

/* Mean intruder height over the last 10 periods of small_frictionless.scene at restitution e. */
static int frictionless_late_height(const char *restitution, int seed, double *start, double *late)
{
    char e[3][64];
    const char *species[3] = {"grain", "intruder", "wall"};
    for (int k = 0; k < 3; ++k)
        snprintf(e[k], sizeof e[k], "species.%s.restitution=%s", species[k], restitution);
    const char *sets[] = {e[0], e[1], e[2]};
    return late_height("scenes/brazil_nut/small_frictionless.scene", seed, sets, 3, 10.0 * 3.953,
                       start, late);
}

static int frictionless_intruder_sinks(void)
{
    for (int seed = 1; seed <= 3; ++seed) {
        double start, elastic, damped, unused;
        TEST_ASSERT(frictionless_late_height("0.99", seed, &start, &elastic) == 0);
        TEST_ASSERT(frictionless_late_height("0.9", seed, &unused, &damped) == 0);
        printf("seed %d: start %.2f d; last 10 periods %.2f d (e = 0.99), %.2f d (e = 0.9)\n", seed,
               start, elastic, damped);
        TEST_ASSERT(start > 12.0);
        TEST_ASSERT(elastic < 6.0);
        TEST_ASSERT(damped > 10.0);
    }
    return 0;
}

static int lighter_intruder_rises_faster(void)
{
    const char *densities[2] = {"species.intruder.density=0.106103295394597",  /* 1/3 */
                                "species.intruder.density=0.954929658551372"}; /* 3 */
    double mean[2] = {0.0, 0.0};
    for (int seed = 1; seed <= 32; ++seed)
        for (int k = 0; k < 2; ++k) {
            double start, late;
            TEST_ASSERT(late_height("scenes/brazil_nut/small_density.scene", seed, &densities[k], 1,
                                    20.0, &start, &late) == 0);
            mean[k] += (late - start) / 32.0;
        }
    printf("rise over 32 seeds: %.2f d (rho_I / rho = 1/3), %.2f d (3)\n", mean[0], mean[1]);
    TEST_ASSERT(mean[0] - mean[1] > 0.3);
    return 0;
}

TEST_MAIN(TEST_CASE(rises_with_frictional_walls), TEST_CASE(smooth_walls_rise_slower),
          TEST_CASE(frictionless_intruder_sinks), TEST_CASE(lighter_intruder_rises_faster))
