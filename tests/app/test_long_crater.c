/* SPDX-License-Identifier: MIT */
/* test_long_crater.c: the thesis's own time-step pair (000 §6.1.1: dt = 1e-5 and 1e-6 agree) on
 * the reduced crater (scenes/crater/small.scene, 300 grains, 0.6 s of collapse): 660 000 steps,
 * so label slow (skipped by the sanitizer run); test_crater.c checks 2e-5 against 5e-6. */
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

static SimWorld *world_at(const Scene *scene, const char *path, double dt)
{
    SimError error;
    SimWorldDef def = scene_world_def(scene, 2);
    def.time_step = dt;
    return sim_world_load(path, &def, &error);
}

static int final_profile(const Scene *scene, const char *bed, double dt, AppCraterProfile *profile)
{
    SimWorld *world = world_at(scene, bed, dt);
    if (!world)
        return -1;
    SimFrame frame;
    sim_world_frame(world, &frame);
    double top = 0.0;
    SimError error;
    int rc = app_crater_surface_height(&frame, 2.625, 0.525, &top);
    if (rc == 0)
        sim_world_remove_rect(world, 2.1, top - 1.05, 3.15, top + 1.05);
    if (rc == 0 && sim_world_step(world, llround(0.6 / dt), &error) != SIM_OK)
        rc = -1;
    if (rc == 0)
        rc = app_crater_profile_measure(world, 0.0, profile);
    sim_world_destroy(world);
    return rc;
}

/* dt = 1e-5 and 1e-6 give the same final free surface within one mean diameter in every bin. */
static int thesis_time_steps_agree(void)
{
    char err[2048], path[256];
    Scene *scene = scene_load(SMALL, NULL, 0, err, sizeof err);
    TEST_ASSERT(scene);
    SimWorldDef def = scene_world_def(scene, 0);
    SimError error;
    SimWorld *world = sim_world_create(&def, &error);
    TEST_ASSERT(world);
    TEST_ASSERT(sim_world_step(world, 60000, &error) == SIM_OK); /* 3 s of deposition */
    double d, m;
    sim_world_means(world, &d, &m);
    snprintf(path, sizeof path, "/tmp/sablier_test_long_crater_%ld.state", (long)getpid());
    TEST_ASSERT(sim_world_save(world, path, &error) == SIM_OK);
    sim_world_destroy(world);
    AppCraterProfile a, b;
    TEST_ASSERT(final_profile(scene, path, 1e-5, &a) == 0);
    TEST_ASSERT(final_profile(scene, path, 1e-6, &b) == 0);
    remove(path);
    TEST_ASSERT(a.bins == b.bins && a.bins > 10);
    double worst = 0.0;
    for (int k = 0; k < a.bins; ++k)
        worst = fmax(worst, fabs(a.y[k] - b.y[k]));
    printf("dt 1e-5 vs 1e-6: largest profile difference %.4f m (d = %.4f m)\n", worst, d);
    TEST_ASSERT(worst <= d);
    app_crater_profile_free(&a);
    app_crater_profile_free(&b);
    scene_free(scene);
    return 0;
}

TEST_MAIN(TEST_CASE(thesis_time_steps_agree))
