/* SPDX-License-Identifier: MIT */
/* test_forcing.c: per-stage forcing (docs/scenes.md, stages): a stage's own `gravity` and
 * `motions`. A settled pile tilted in a later stage starts moving only then; a box whose shaking
 * is enabled in stage two is at rest at the end of stage one. Runs small scenes written here. */
#include "app_test_run.h"
#include "test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A box 12 d wide of three walls, about 60 grains rained in; `stages` appended. */
static const char *const BOX =
    "name = \"forcing\"; seed = 3; mass_model = \"disk\";\n"
    "effects = [\"friction\", \"vibration\"]; gravity = [0.0, -1.0];\n"
    "time = { dt = 1e-3; end = 10.0; };\n"
    "contact = { normal = \"linear\"; tangential = \"spring\"; };\n"
    "species = ( { name = \"g\"; density = 1.27; k_n = 2000.0; k_t = 1500.0; mu = 0.5;\n"
    "              restitution = 0.2; } );\n"
    "motions = { shake = { amplitude = 0.3; frequency = 1.0; }; };\n"
    "walls = ( { from = [0.0, 0.0]; to = [12.0, 0.0]; motion = \"shake\"; },\n"
    "          { from = [0.0, 0.0]; to = [0.0, 20.0]; motion = \"shake\"; },\n"
    "          { from = [12.0, 0.0]; to = [12.0, 20.0]; motion = \"shake\"; } );\n"
    "grains = { rain = { x0 = 0.6; x1 = 11.4; y0 = 0.6; y1 = 6.0; radius_mean = 0.5;\n"
    "                    polydispersity = 0.1; }; };\n"
    "output = { energy_every = 1.0; };\n";

/* Writes BOX + stages into a scene file, runs it into a fresh folder (dir, 256 bytes). */
static int run_box(const char *stages, char *dir)
{
    char path[256];
    snprintf(path, sizeof path, "/tmp/sablier_test_forcing_%ld.scene", (long)getpid());
    snprintf(dir, 256, "/tmp/sablier_test_forcing_%ld", (long)getpid());
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fprintf(f, "%s%s\n", BOX, stages);
    fclose(f);
    int status = app_test_run(path, NULL, 0, dir);
    remove(path);
    return status;
}

/* Largest grain speed and mean x of the mobile grains of DIR/STAGE.state. */
static int state_motion(const char *dir, const char *stage, double *speed, double *mean_x)
{
    SimGrainSet g;
    if (app_test_state(dir, stage, &g) != 0)
        return -1;
    *speed = 0.0;
    *mean_x = 0.0;
    int n = 0;
    for (int i = 0; i < g.count; ++i)
        if (!(g.flags[i] & SIM_GRAIN_FIXED)) {
            *speed = fmax(*speed, hypot(g.vx[i], g.vy[i]));
            *mean_x += g.x[i];
            ++n;
        }
    *mean_x /= n > 0 ? n : 1;
    sim_grain_set_free(&g);
    return 0;
}

/* gravity [0, -1] while settling, then tilted to [0.6, -1]: at rest (speed < 0.02 sqrt(g d))
 * at the end of the first stage, then the pile slumps to +x. */
static int tilted_pile_moves_only_then(void)
{
    char dir[256];
    TEST_ASSERT(run_box("stages = ( { name = \"settle\"; time = { end = 25.0; }; motions = []; },\n"
                        "  { name = \"tilt\"; time = { end = 5.0; }; gravity = [0.6, -1.0]; } );",
                        dir) == 0);
    double v_settle, x_settle, v_tilt, x_tilt;
    TEST_ASSERT(state_motion(dir, "settle", &v_settle, &x_settle) == 0);
    TEST_ASSERT(state_motion(dir, "tilt", &v_tilt, &x_tilt) == 0);
    app_test_remove_dir(dir);
    TEST_ASSERT(v_settle < 0.02);
    TEST_ASSERT(x_tilt > x_settle + 0.2);
    return 0;
}

/* `motions = []` while settling, `motions = ["shake"]` in stage two: at rest at the end of
 * stage one, shaken (grains faster than the settle bound) in stage two. */
static int shaking_enabled_in_stage_two(void)
{
    char dir[256];
    TEST_ASSERT(run_box("stages = ( { name = \"settle\"; time = { end = 25.0; }; motions = []; },\n"
                        "  { name = \"shake\"; time = { end = 2.25; }; motions = [\"shake\"]; } );",
                        dir) == 0);
    double v_settle, x_settle, v_shake, x_shake;
    TEST_ASSERT(state_motion(dir, "settle", &v_settle, &x_settle) == 0);
    TEST_ASSERT(state_motion(dir, "shake", &v_shake, &x_shake) == 0);
    app_test_remove_dir(dir);
    TEST_ASSERT(v_settle < 0.02);
    TEST_ASSERT(v_shake > 0.5); /* the floor moves at up to 2 pi 0.3 = 1.9 d/s */
    return 0;
}

/* A stage's `effects` (a subset) is what its world is built from: friction off in stage two;
 * one outside the scene's list is refused at its line. */
static int stage_effects_subset(void)
{
    char path[256], err[2048];
    snprintf(path, sizeof path, "/tmp/sablier_test_forcing_fx_%ld.scene", (long)getpid());
    FILE *f = fopen(path, "w");
    TEST_ASSERT(f);
    fprintf(f, "%s%s\n", BOX,
            "stages = ( { name = \"a\"; }, { name = \"b\"; effects = [\"vibration\"]; } );");
    fclose(f);
    Scene *scene = scene_load(path, NULL, 0, err, sizeof err);
    TEST_ASSERT(scene);
    TEST_ASSERT(scene_world_def(scene, 0).effects & SIM_EFFECT_FRICTION);
    TEST_ASSERT(!(scene_world_def(scene, 1).effects & SIM_EFFECT_FRICTION));
    scene_free(scene);
    f = fopen(path, "w");
    TEST_ASSERT(f);
    fprintf(f, "%s%s\n", BOX,
            "stages = ( { name = \"a\"; },\n { name = \"b\"; effects = [\"removal\"]; } );");
    fclose(f);
    scene = scene_load(path, NULL, 0, err, sizeof err);
    remove(path);
    TEST_ASSERT(!scene);
    fprintf(stderr, "(expected) %s\n", err);
    TEST_ASSERT(strstr(err, ".scene:15:") && strstr(err, "removal"));
    return 0;
}

TEST_MAIN(TEST_CASE(tilted_pile_moves_only_then), TEST_CASE(shaking_enabled_in_stage_two),
          TEST_CASE(stage_effects_subset))
