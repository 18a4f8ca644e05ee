/* SPDX-License-Identifier: MIT */
/* test_crater.c: the crater study of thesis 000 on reduced sizes (scenes/crater/small.scene,
 * 300 grains): settled-bed structure, energy during the collapse, time-step robustness, the crater
 * height trend of fig. 7.28, and the observables a run writes. No rendering. */
#include "test.h"

#include "run/run.h"
#include "scene/scene.h"
#include "sim/sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "crater/crater.h"

#define SMALL "scenes/crater/small.scene"

/* A world of a scene's first stage (with overrides). */
static SimWorld *scene_world(const char *const *sets, int set_count, Scene **out)
{
    char err[2048];
    Scene *scene = scene_load(SMALL, sets, set_count, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return NULL;
    }
    SimWorldDef def = scene_world_def(scene, 0);
    SimError error;
    SimWorld *world = sim_world_create(&def, &error);
    if (!world)
        fprintf(stderr, "%s: %s\n", error.field, error.message);
    *out = scene;
    return world;
}

/* Steps until E_kin + E_rot < tol (checked every 0.01 s, not before `after`) or `cap` s. */
static int settle(SimWorld *world, double tol, double after, double cap)
{
    double dt = sim_world_time_step(world), t0 = sim_world_time(world);
    long chunk = (long)llround(0.01 / dt);
    SimError error;
    while (sim_world_time(world) - t0 < cap - 0.5 * dt) {
        if (sim_world_step(world, chunk, &error) != SIM_OK) {
            fprintf(stderr, "unstable: %s\n", error.message);
            return -1;
        }
        SimEnergy e = sim_world_energy(world);
        if (sim_world_time(world) - t0 >= after && e.kinetic + e.rotational < tol)
            return 1;
    }
    return 0;
}

/* The settled small bed (deposit stage of small.scene). */
static SimWorld *small_bed(const char *const *sets, int set_count, Scene **scene)
{
    SimWorld *world = scene_world(sets, set_count, scene);
    if (world && settle(world, 0.02, 1.0, 3.0) < 0) {
        sim_world_destroy(world);
        return NULL;
    }
    return world;
}

/* A world continuing a saved state with another time step (contact history restarts). */
static SimWorld *world_from(const Scene *scene, const char *path, double dt, const char *set)
{
    (void)set;
    SimError error;
    SimWorldDef def = scene_world_def(scene, 2);
    def.time_step = dt;
    SimWorld *world = sim_world_load(path, &def, &error);
    if (!world)
        fprintf(stderr, "%s: %s: %s\n", path, error.field, error.message);
    return world;
}

/* Digs a cavity of width L and height H centred at cx below the free surface (000 §4.1). */
static int dig(SimWorld *world, double cx, double width, double height)
{
    SimFrame frame;
    sim_world_frame(world, &frame);
    double top = 0.0;
    if (app_crater_surface_height(&frame, cx, 0.5 * width, &top) != 0)
        return -1;
    return sim_world_remove_rect(world, cx - 0.5 * width, top - height, cx + 0.5 * width,
                                 top + height);
}

static void temp_path(char *out, size_t size, const char *name)
{
    snprintf(out, size, "/tmp/sablier_test_crater_%ld_%s", (long)getpid(), name);
}

/* 8 % uniform polydispersity (000 §4.2): a dense bed without crystals; monodisperse grains
 * order more (000 fig. 6.4). Bounds: coordination 3.4-4.6 and packing fraction 0.80-0.88 (2D
 * dense packings of frictional disks lie between 3 and 4.5 contacts and 0.80 and 0.86 in area;
 * the rain lattice packs slightly denser: 0.86 measured); mean local |psi_6| < 0.9 (a triangular
 * crystal gives 1; sim's measure counts neighbours within 1.1 (r_i + r_j), so grains with two or
 * three neighbours already score high: 0.82 measured here) and below the monodisperse bed's
 * (0.86 measured). */
static int settled_bed_structure(void)
{
    Scene *scene = NULL;
    SimWorld *world = small_bed(NULL, 0, &scene);
    TEST_ASSERT(world);
    AppCraterProfile profile;
    TEST_ASSERT(app_crater_profile_measure(world, 0.0, &profile) == 0);
    AppCraterBed bed = app_crater_bed_measure(world, &profile);
    printf("8%%: coordination %.3f packing %.4f hexatic %.4f level %.3f m\n", bed.coordination,
           bed.packing_fraction, bed.hexatic_order, bed.level);
    TEST_ASSERT(bed.coordination > 3.4 && bed.coordination < 4.6);
    TEST_ASSERT(bed.packing_fraction > 0.80 && bed.packing_fraction < 0.88);
    TEST_ASSERT(bed.hexatic_order < 0.9);
    app_crater_profile_free(&profile);
    sim_world_destroy(world);
    scene_free(scene);

    const char *mono[] = {"grains.rain.polydispersity=0.0"};
    world = small_bed(mono, 1, &scene);
    TEST_ASSERT(world);
    TEST_ASSERT(app_crater_profile_measure(world, 0.0, &profile) == 0);
    AppCraterBed ordered = app_crater_bed_measure(world, &profile);
    printf("0%%: coordination %.3f packing %.4f hexatic %.4f\n", ordered.coordination,
           ordered.packing_fraction, ordered.hexatic_order);
    TEST_ASSERT(ordered.hexatic_order > bed.hexatic_order);
    app_crater_profile_free(&profile);
    sim_world_destroy(world);
    scene_free(scene);
    return 0;
}

/* During the collapse, E_kin + E_pot + E_rot + E_el never grows by more than 1e-4 N m g d (one
 * ten-thousandth of lifting every grain by a diameter): every force but gravity and the springs
 * dissipates (000 §5.1: the thesis's total omits E_el, which is why its total rose). */
static int collapse_energy_never_increases(void)
{
    Scene *scene = NULL;
    SimWorld *world = small_bed(NULL, 0, &scene);
    TEST_ASSERT(world);
    TEST_ASSERT(dig(world, 2.625, 1.05, 1.05) > 10);
    double d, m;
    sim_world_means(world, &d, &m);
    double tol = 1e-4 * sim_world_mobile_count(world) * m * 9.806 * d;
    SimEnergy e = sim_world_energy(world);
    double previous = e.total, rise = 0.0, start = e.total;
    SimError error;
    for (int k = 0; k < 1000; ++k) { /* 1 s in steps of 1 ms */
        TEST_ASSERT(sim_world_step(world, 20, &error) == SIM_OK);
        e = sim_world_energy(world);
        TEST_NEAR(e.total, e.kinetic + e.potential + e.rotational + e.elastic,
                  1e-9 * fabs(e.total));
        rise = fmax(rise, e.total - previous);
        previous = e.total;
    }
    printf("largest rise %.3g J (tolerance %.3g J), dissipated %.4g J\n", rise, tol,
           start - e.total);
    TEST_ASSERT(rise <= tol);
    TEST_ASSERT(start - e.total > 100.0 * tol); /* the collapse happened */
    sim_world_destroy(world);
    scene_free(scene);
    return 0;
}

/* Final free surface of a collapse from the saved bed at time step dt. */
static int collapse_profile(const Scene *scene, const char *bed, double dt, double duration,
                            AppCraterProfile *profile)
{
    SimWorld *world = world_from(scene, bed, dt, NULL);
    if (!world)
        return -1;
    SimError error;
    int rc = dig(world, 2.625, 1.05, 1.05) > 10 ? 0 : -1;
    if (rc == 0 && sim_world_step(world, llround(duration / dt), &error) != SIM_OK)
        rc = -1;
    if (rc == 0)
        rc = app_crater_profile_measure(world, 0.0, profile);
    sim_world_destroy(world);
    return rc;
}

/* Two time steps give the same final free surface within one mean diameter in every bin, and
 * within a fifth of one on average (000 §6.1.1: dt = 1e-5 and 1e-6 agree). */
static int compare_time_steps(double dt_a, double dt_b, double duration)
{
    Scene *scene = NULL;
    SimWorld *world = small_bed(NULL, 0, &scene);
    TEST_ASSERT(world);
    double d, m;
    sim_world_means(world, &d, &m);
    char path[256];
    temp_path(path, sizeof path, "bed.state");
    SimError error;
    TEST_ASSERT(sim_world_save(world, path, &error) == SIM_OK);
    sim_world_destroy(world);
    AppCraterProfile a, b;
    TEST_ASSERT(collapse_profile(scene, path, dt_a, duration, &a) == 0);
    TEST_ASSERT(collapse_profile(scene, path, dt_b, duration, &b) == 0);
    remove(path);
    TEST_ASSERT(a.bins == b.bins && a.bins > 10);
    double worst = 0.0, mean = 0.0;
    for (int k = 0; k < a.bins; ++k) {
        worst = fmax(worst, fabs(a.y[k] - b.y[k]));
        mean += fabs(a.y[k] - b.y[k]) / a.bins;
    }
    printf("dt %g vs %g: largest profile difference %.4f m, mean %.4f m, d = %.4f m\n", dt_a, dt_b,
           worst, mean, d);
    TEST_ASSERT(worst <= d);
    TEST_ASSERT(mean <= 0.2 * d);
    app_crater_profile_free(&a);
    app_crater_profile_free(&b);
    scene_free(scene);
    return 0;
}

static int time_steps_agree(void)
{
    return compare_time_steps(2e-5, 5e-6, 0.6);
}

/* dt = 1e-4 with the thesis parameters (000 §6.1.1) is refused at set-up with a message naming
 * the time step, its line and the contact time. */
static int large_time_step_refused(void)
{
    const char *sets[] = {"time.dt=1e-4"};
    char err[2048] = "";
    Scene *scene = scene_load(SMALL, sets, 1, err, sizeof err);
    TEST_ASSERT(!scene);
    printf("%s\n", err);
    TEST_ASSERT(strstr(err, "time step 0.0001 s"));
    TEST_ASSERT(strstr(err, "contact time"));
    scene = scene_load("scenes/crater/standard.scene", sets, 1, err, sizeof err);
    TEST_ASSERT(!scene);
    TEST_ASSERT(strstr(err, "max_dt_fraction"));
    return 0;
}

/* Fig. 7.28: at fixed cavity height H, the crater height (depth below the settled surface)
 * decreases with H/L and levels off: narrow pits are filled. H = 6 diameters; H/L = 1, 2, 3. */
static int crater_height_trend(void)
{
    Scene *scene = NULL;
    SimWorld *world = small_bed(NULL, 0, &scene);
    TEST_ASSERT(world);
    char path[256];
    temp_path(path, sizeof path, "trend.state");
    SimError error;
    TEST_ASSERT(sim_world_save(world, path, &error) == SIM_OK);
    AppCraterProfile profile;
    TEST_ASSERT(app_crater_profile_measure(world, 0.0, &profile) == 0);
    double level = app_crater_profile_level(&profile, 2);
    app_crater_profile_free(&profile);
    sim_world_destroy(world);
    const double height = 0.96, ratios[3] = {1.0, 2.0, 3.0};
    double h[3];
    for (int k = 0; k < 3; ++k) {
        double width = height / ratios[k];
        world = world_from(scene, path, 5e-5, NULL);
        TEST_ASSERT(world);
        TEST_ASSERT(dig(world, 2.625, width, height) > 0);
        TEST_ASSERT(settle(world, 0.02, 0.5, 1.5) >= 0);
        TEST_ASSERT(app_crater_profile_measure(world, 0.0, &profile) == 0);
        AppCrater c = app_crater_measure(&profile, 2.625 - 0.5 * width, 2.625 + 0.5 * width, level);
        h[k] = c.height;
        printf("H/L = %.0f: crater height %.4f m (surface min %.4f m at x = %.3f m)\n", ratios[k],
               c.height, c.surface_min, c.x_min);
        app_crater_profile_free(&profile);
        sim_world_destroy(world);
    }
    remove(path);
    TEST_ASSERT(h[0] > h[1] && h[0] > h[2]);
    TEST_ASSERT(h[0] - h[1] > fabs(h[1] - h[2])); /* levels off */
    scene_free(scene);
    return 0;
}

/* A run of the small scene writes profile.csv, crater.csv and observables.csv with the bed and
 * crater measures, and the crater is shallower than the cavity. */
static int run_writes_observables(void)
{
    const char *sets[] = {"stages.deposit.time.end=1.5", "stages.collapse.time.end=0.8"};
    char err[2048], dir[256], path[320];
    Scene *scene = scene_load(SMALL, sets, 2, err, sizeof err);
    TEST_ASSERT(scene);
    temp_path(dir, sizeof dir, "run");
    AppRunOptions options = app_run_options_default();
    options.out_dir = dir;
    options.quiet = 1;
    TEST_ASSERT(app_run(scene, &options) == 0);
    const char *files[] = {"profile.csv", "crater.csv", "observables.csv", "summary.json"};
    for (int k = 0; k < 4; ++k) {
        snprintf(path, sizeof path, "%s/%s", dir, files[k]);
        TEST_ASSERT(access(path, R_OK) == 0);
    }
    double h = app_crater_observable(dir, "crater_height_m");
    double z = app_crater_observable(dir, "bed_coordination");
    printf("crater height %.4f m, coordination %.3f\n", h, z);
    TEST_ASSERT(h > 0.0 && h < 1.05 + 0.2);
    TEST_ASSERT(z > 3.0 && z < 5.0);
    TEST_ASSERT(app_crater_observable(dir, "removed") > 10);
    AppCraterChart chart;
    app_crater_chart_init(&chart, 2, 2, "test");
    TEST_ASSERT(app_crater_chart_energy_run(&chart, dir, "small", NULL) == 0);
    TEST_ASSERT(chart.panels[0].series_count == 1 && chart.panels[0].series[0].count > 50);
    TEST_ASSERT(chart.panels[1].series[0].y[0] == 0.0); /* potential relative to the start */
    double collapse_t0 = chart.panels[0].series[0].x[0];
    app_crater_chart_free(&chart);
    /* the deposit's energies (000 fig. 6.15): from t* = 0 at rest, the grains falling gain
     * kinetic energy (E*_kin up to a peak well above the collapse's start) and lose potential */
    app_crater_chart_init(&chart, 2, 2, "test");
    TEST_ASSERT(app_crater_chart_energy_run(&chart, dir, "small", "deposit") == 0);
    const AppCraterChartSeries *kin = &chart.panels[0].series[0], *pot = &chart.panels[1].series[0];
    TEST_ASSERT(kin->count > 50 && kin->x[0] == 0.0 && collapse_t0 == 0.0);
    double peak = 0.0;
    for (int i = 0; i < kin->count; ++i)
        peak = fmax(peak, kin->y[i]);
    TEST_ASSERT(kin->y[0] == 0.0 && peak > 1e-3);
    TEST_ASSERT(pot->y[pot->count - 1] < -1e-2); /* the bed ends lower than the lattice */
    TEST_ASSERT(app_crater_chart_energy_run(&chart, dir, "small", "nowhere") == -1);
    app_crater_chart_free(&chart);
    app_crater_chart_init(&chart, 1, 1, "test");
    TEST_ASSERT(app_crater_chart_profiles_run(&chart, 0, dir, 4, NULL) == 0);
    TEST_ASSERT(chart.panels[0].series_count == 4);
    app_crater_chart_free(&chart);
    for (int k = 0; k < 4; ++k) {
        snprintf(path, sizeof path, "%s/%s", dir, files[k]);
        remove(path);
    }
    const char *more[] = {"energy.csv", "deposit.state", "dig.state", "collapse.state"};
    for (int k = 0; k < 4; ++k) {
        snprintf(path, sizeof path, "%s/%s", dir, more[k]);
        remove(path);
    }
    rmdir(dir);
    scene_free(scene);
    return 0;
}

TEST_MAIN(TEST_CASE(settled_bed_structure), TEST_CASE(collapse_energy_never_increases),
          TEST_CASE(time_steps_agree), TEST_CASE(large_time_step_refused),
          TEST_CASE(crater_height_trend), TEST_CASE(run_writes_observables))
