/* SPDX-License-Identifier: MIT */
/* test_experiment_scenes.c: shortened runs of the shipped scenes of docs/experiments.md (drum,
 * chute, hopper, couette), each asserting what it shows; and a fast drum that no grain leaves. */
#include "app_test_run.h"
#include "test.h"

#include "driver/stats.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "surface/surface.h"

/* Runs `scene` with the sets into the folder `dir` (256 bytes) named after tag. */
static int run_scene(const char *scene_path, const char **sets, int set_count, const char *tag,
                     char *dir)
{
    snprintf(dir, 256, "/tmp/sablier_test_scenes_%ld_%s", (long)getpid(), tag);
    return app_test_run(scene_path, sets, set_count, dir);
}

/* The text of DIR/NAME (malloc'd), or NULL. */
static char *slurp(const char *dir, const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *text = calloc(1, 1 << 20);
    if (text)
        text[fread(text, 1, (1 << 20) - 1, f)] = '\0';
    fclose(f);
    return text;
}

/* The drum turns and its surface tilts: a positive angle in summary.json. */
static int drum_surface_tilts(void)
{
    const char *sets[] = {"stages.settle.time.end=15", "stages.rotate.time.end=30",
                          "surface.after=20"};
    char dir[256];
    TEST_ASSERT(run_scene("scenes/drum/drum.scene", sets, 3, "drum", dir) == 0);
    char *summary = slurp(dir, "summary.json");
    TEST_ASSERT(summary);
    const char *at = strstr(summary, "\"surface_angle_deg\": ");
    double angle = at ? atof(at + strlen("\"surface_angle_deg\": ")) : 0.0;
    free(summary);
    app_test_remove_dir(dir);
    TEST_ASSERT(angle > 5.0 && angle < 45.0);
    return 0;
}

/* The chute flows downhill (+x) only once tilted. */
static int chute_flows_when_tilted(void)
{
    const char *sets[] = {"stages.settle.time.end=10", "stages.flow.time.end=5",
                          "stages.flow.measures.0.window=2"};
    char dir[256];
    TEST_ASSERT(run_scene("scenes/chute/chute.scene", sets, 3, "chute", dir) == 0);
    SimGrainSet a, b;
    TEST_ASSERT(app_test_state(dir, "settle", &a) == 0 && app_test_state(dir, "flow", &b) == 0);
    double va = 0.0, vb = 0.0;
    int n = 0;
    for (int i = 0; i < b.count; ++i)
        if (!(b.flags[i] & SIM_GRAIN_FIXED)) {
            va += a.vx[i];
            vb += b.vx[i];
            ++n;
        }
    sim_grain_set_free(&a);
    sim_grain_set_free(&b);
    app_test_remove_dir(dir);
    TEST_ASSERT(n > 0 && fabs(va / n) < 0.05 && vb / n > 0.5);
    return 0;
}

/* The hopper is fed by its source and drains through its orifice. */
static int hopper_fills_and_drains(void)
{
    const char *sets[] = {"stages.fill.time.end=12", "walls.3.from=[8.0,0.0]"};
    char dir[256];
    TEST_ASSERT(run_scene("scenes/hopper/hopper.scene", sets, 2, "hopper", dir) == 0);
    char *summary = slurp(dir, "summary.json");
    TEST_ASSERT(summary);
    const char *at = strstr(summary, "\"inserted\": ");
    long inserted = at ? atol(at + strlen("\"inserted\": ")) : 0;
    at = strstr(summary, "\"mobile_grains\": ");
    long mobile = at ? atol(at + strlen("\"mobile_grains\": ")) : 0;
    free(summary);
    app_test_remove_dir(dir);
    TEST_ASSERT(inserted >= 440 && inserted <= 481); /* 40 grains/s, some skipped */
    TEST_ASSERT(mobile > 100 && mobile < inserted);  /* some went through the orifice */
    return 0;
}

/* The couette's sliding wall drags the top of the bed along +x; the bottom stays. */
static int couette_shears(void)
{
    const char *sets[] = {"stages.settle.time.end=8", "stages.shear.time.end=20"};
    char dir[256];
    TEST_ASSERT(run_scene("scenes/shear/couette.scene", sets, 2, "couette", dir) == 0);
    SimGrainSet g;
    TEST_ASSERT(app_test_state(dir, "shear", &g) == 0);
    double top = 0.0, bottom = 0.0;
    int nt = 0, nb = 0;
    for (int i = 0; i < g.count; ++i) {
        if (g.flags[i] & SIM_GRAIN_FIXED)
            continue;
        if (g.y[i] > 5.5) {
            top += g.vx[i];
            ++nt;
        } else if (g.y[i] < 2.0) {
            bottom += g.vx[i];
            ++nb;
        }
    }
    sim_grain_set_free(&g);
    app_test_remove_dir(dir);
    TEST_ASSERT(nt > 0 && nb > 0 && top / nt > 0.2 && top / nt > 5.0 * fabs(bottom / nb));
    return 0;
}

/* A fast drum (omega = 1 rad/s: the wall at 15 d/s, cataracting): no grain leaves the arc. */
static int fast_drum_no_tunnelling(void)
{
    const char *sets[] = {"stages.settle.time.end=5", "stages.rotate.time.end=40",
                          "motions.spin.angular_velocity=1.0", "motions.spin.ramp=2.0"};
    char dir[256];
    TEST_ASSERT(run_scene("scenes/drum/drum.scene", sets, 4, "fast_drum", dir) == 0);
    SimGrainSet g;
    TEST_ASSERT(app_test_state(dir, "rotate", &g) == 0);
    double worst = 0.0;
    for (int i = 0; i < g.count; ++i)
        worst = fmax(worst, hypot(g.x[i], g.y[i]) + g.radius[i]);
    sim_grain_set_free(&g);
    app_test_remove_dir(dir);
    TEST_ASSERT(worst < 15.0 + 0.2); /* inside the R = 15 d drum, to the contact overlap */
    return 0;
}

/* The surface fit: an exact line through finite points, NAN columns skipped. */
static int surface_fit_is_least_squares(void)
{
    const double x[5] = {0.0, 1.0, 2.0, 3.0, 4.0};
    const double y[5] = {1.0, 1.5, NAN, 2.5, 3.0};
    double slope, intercept;
    TEST_ASSERT(app_linear_fit(x, y, 5, &intercept, &slope, NULL) == 0);
    TEST_NEAR(slope, 0.5, 1e-14);
    TEST_NEAR(intercept, 1.0, 1e-14);
    const double one[2] = {1.0, NAN};
    TEST_ASSERT(app_linear_fit(x, one, 2, &intercept, &slope, NULL) != 0);
    return 0;
}

TEST_MAIN(TEST_CASE(surface_fit_is_least_squares), TEST_CASE(drum_surface_tilts),
          TEST_CASE(chute_flows_when_tilted), TEST_CASE(hopper_fills_and_drains),
          TEST_CASE(couette_shears), TEST_CASE(fast_drum_no_tunnelling))
