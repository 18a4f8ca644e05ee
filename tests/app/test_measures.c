/* SPDX-License-Identifier: MIT */
/* test_measures.c: the measures layer (app/output/measures.c) through sablier run's runner: the
 * column scene's profile, grid, .vti and flux outputs; a scene without measures runs no measure;
 * every sink's count reaches summary.json. */
#include "test.h"

#include "output/measures.h"
#include "run/run.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define COLUMN "scenes/measure/column.scene"

static void fresh_dir(char *dir, size_t size, const char *tag)
{
    snprintf(dir, size, "/tmp/sablier_test_measures_%ld_%s", (long)getpid(), tag);
    char command[600];
    snprintf(command, sizeof command, "rm -rf '%s'", dir);
    if (system(command) != 0)
        dir[0] = '\0';
}

static void remove_dir(const char *dir)
{
    char command[600];
    snprintf(command, sizeof command, "rm -rf '%s'", dir);
    if (system(command) != 0)
        fprintf(stderr, "cannot remove %s\n", dir);
}

static int run_scene(const char *path, const char *dir, const char *const *sets, int set_count)
{
    char err[1024];
    Scene *scene = scene_load(path, sets, set_count, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    AppRunOptions o = app_run_options_default();
    o.out_dir = dir;
    o.quiet = 1;
    o.render_off = 1;
    int rc = app_run(scene, &o);
    scene_free(scene);
    return rc;
}

static char *read_text(const char *dir, const char *name)
{
    char path[600];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return test_read_file(path, NULL);
}

/* Mobile grains of a checkpoint below height y (centre not above it), with their weight. */
static long count_below(const char *dir, const char *state, double y, double *weight_above,
                        double *top)
{
    char path[600];
    snprintf(path, sizeof path, "%s/%s", dir, state);
    SimGrainSet g;
    SimWall *walls = NULL;
    int wall_count = 0;
    double time;
    SimError e;
    if (sim_state_load(path, &g, &walls, &wall_count, &time, &e) != SIM_OK)
        return -1;
    long below = 0;
    *weight_above = 0.0;
    *top = 0.0;
    for (int i = 0; i < g.count; ++i) {
        if (!(g.y[i] - y > 0.0))
            ++below;
        else /* the column's grains weigh m g = 1 (density 4/pi, d = 1, g = 1) */
            *weight_above += 1.0;
        *top = fmax(*top, g.y[i]);
    }
    sim_grain_set_free(&g);
    free(walls);
    return below;
}

/* The column scene: stress.csv holds t,y,<fields> with sigma_yy at mid-height within 5 % of the
 * weight above per unit width (20 d wide) in the final state, sigma_xy below 5 % of the base
 * stress (wall pressures differ a little from side to side at a given height); field.csv and one
 * .vti per sample; the flux through y = 10 in the rain stage equals the change of the count
 * below it exactly, and summary.json reports it. */
static int column_scene_outputs(void)
{
    char dir[256];
    fresh_dir(dir, sizeof dir, "column");
    TEST_ASSERT(dir[0] && run_scene(COLUMN, dir, NULL, 0) == 0);
    char *stress = read_text(dir, "stress.csv");
    TEST_ASSERT(stress && strncmp(stress, "t,y,syy,sxy,sxx,phi,z\n", 22) == 0);
    double weight, top;
    TEST_ASSERT(count_below(dir, "rest.state", 15.0, &weight, &top) > 0);
    int checked = 0;
    for (char *line = strchr(stress, '\n'); line && line[1]; line = strchr(line + 1, '\n')) {
        double t, y, syy, sxy, sxx, phi, z;
        TEST_ASSERT(sscanf(line + 1, "%lf,%lf,%lf,%lf,%lf,%lf,%lf", &t, &y, &syy, &sxy, &sxx, &phi,
                           &z) == 7);
        TEST_ASSERT(t > 38.0); /* the rest stage (after 37.2 s of rain): 2 s windows */
        if (fabs(y - 15.25) < 1e-9) {
            TEST_REL(syy, weight / 20.0, 0.05);
            TEST_NEAR(sxy, 0.0, 0.05 * 600.0 / 20.0); /* 5 % of the base stress */
            TEST_ASSERT(phi > 0.75 && phi < 0.92 && z > 3.0);
            ++checked;
        }
    }
    TEST_ASSERT(checked == 2); /* two windows of 2 s in the 4 s stage */
    free(stress);
    char *field = read_text(dir, "field.csv");
    TEST_ASSERT(field && strncmp(field, "t,x,y,phi,vx,vy,syy,p\n", 22) == 0);
    long rows = 0, empty = 0;
    for (const char *c = field; *c; ++c)
        rows += *c == '\n';
    TEST_ASSERT(rows - 1 == 5L * 20 * 36); /* samples at 0, 1, 2, 3, 4 s x nodes */
    /* bins above the column hold no grain: vx, vy are nan there (never 0), finite elsewhere */
    for (char *line = strchr(field, '\n'); line && line[1]; line = strchr(line + 1, '\n')) {
        double t, x, y, phi;
        char vx[32], vy[32];
        TEST_ASSERT(sscanf(line + 1, "%lf,%lf,%lf,%lf,%31[^,],%31[^,]", &t, &x, &y, &phi, vx, vy) ==
                    6);
        TEST_ASSERT((strcmp(vx, "nan") == 0) == (phi == 0.0));
        TEST_ASSERT((strcmp(vy, "nan") == 0) == (phi == 0.0));
        empty += phi == 0.0;
    }
    TEST_ASSERT(empty > 20); /* at least the top row */
    free(field);
    char *vti = read_text(dir, "field/field_00004.vti");
    TEST_ASSERT(vti && strstr(vti, "<ImageData WholeExtent=\"0 19 0 35 0 0\"") &&
                strstr(vti, "Name=\"syy\""));
    free(vti);
    /* the rain stage's flux through y = 10: scene grains below it at the start, rain.state after */
    char err[1024];
    Scene *scene = scene_load(COLUMN, NULL, 0, err, sizeof err);
    TEST_ASSERT(scene);
    long start = 0;
    for (int i = 0; i < scene->grains.count; ++i)
        start += !(scene->grains.y[i] - 10.0 > 0.0);
    scene_free(scene);
    long end = count_below(dir, "rain.state", 10.0, &weight, &top);
    char *fall = read_text(dir, "fall.csv");
    TEST_ASSERT(fall && strncmp(fall, "t,count,mass,rate,mass_rate\n", 28) == 0);
    char *last = fall + strlen(fall) - 2;
    while (last > fall && *last != '\n')
        --last;
    double t, mass;
    long count;
    TEST_ASSERT(sscanf(last + 1, "%lf,%ld,%lf", &t, &count, &mass) == 3);
    TEST_ASSERT(count == end - start && count > 50);
    free(fall);
    char *summary = read_text(dir, "summary.json");
    char expect[128];
    snprintf(expect, sizeof expect, "\"measures\": {\"fall\": {\"count\": %ld,", count);
    TEST_ASSERT(summary && strstr(summary, expect) && strstr(summary, "\"stage\": \"rain\""));
    free(summary);
    remove_dir(dir);
    return 0;
}

/* A small box scene written to `path`: grains rain onto a floor from x = `floor_x0` to 10, a
 * `below` sink under it (with removal) when `sink` is 1; `extra` is added at the top level. */
static int write_box_scene(const char *path, double floor_x0, int sink, const char *extra)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fprintf(f,
            "name = \"box\"; seed = 1; mass_model = \"disk\";\n"
            "effects = [%s]; gravity = [0.0, -1.0]; time = { dt = 1e-3; end = 8.0; };\n"
            "species = ( { name = \"grain\"; density = 1.27323954473516; k_n = 2000.0; "
            "critical_fraction = 0.9; } );\n"
            "walls = ( { from = [%.3f, 0.0]; to = [10.0, 0.0]; }, { from = [0.0, 0.0]; to = [0.0, "
            "40.0]; }, { from = [10.0, 0.0]; to = [10.0, 40.0]; } );\n"
            "grains = { rain = { x0 = 0.6; x1 = 9.4; y0 = 1.0; y1 = 30.0; radius_mean = 0.5; "
            "polydispersity = 0.08; max_count = 200; }; };\n%s%s\n"
            "stages = ( { name = \"fill\"; time = { end = 8.0; }; } );\n",
            sink ? "\"removal\"" : "", floor_x0, sink ? "sinks = ( { below = -2.0; } );\n" : "",
            extra);
    return fclose(f) == 0 ? 0 : -1;
}

/* A scene that declares no measure has no measures state, so no hook of the layer runs (nothing
 * is sampled, no step is forced), and it gets no measure file; one that declares one has it. */
static int undeclared_costs_nothing(void)
{
    char dir[256], path[300], err[1024];
    fresh_dir(dir, sizeof dir, "undeclared");
    TEST_ASSERT(dir[0]);
    char command[600];
    snprintf(command, sizeof command, "mkdir -p '%s'", dir);
    TEST_ASSERT(system(command) == 0);
    snprintf(path, sizeof path, "%s/box.scene", dir);
    TEST_ASSERT(write_box_scene(path, 0.0, 0, "") == 0);
    Scene *scene = scene_load(path, NULL, 0, err, sizeof err);
    TEST_ASSERT(scene);
    TEST_ASSERT(app_measures_of(scene) == NULL);
    scene_free(scene);
    TEST_ASSERT(write_box_scene(path, 0.0, 0,
                                "measures = ( { name = \"m\"; kind = \"profile_y\"; width = 1.0; "
                                "fields = [\"phi\"]; } );") == 0);
    scene = scene_load(path, NULL, 0, err, sizeof err);
    TEST_ASSERT(scene && app_measures_of(scene) != NULL);
    scene_free(scene);
    remove_dir(dir);
    return 0;
}

/* Grains leaving through a sink (the floor open over 0 < x < 4): summary.json lists the sink's
 * total, each stage's `removed_by_sinks`, and the stage's `removed` counts them: removed +
 * mobile = the grains rained. */
static int sink_counts_in_summary(void)
{
    char dir[256], path[300], out[300];
    fresh_dir(dir, sizeof dir, "sinks");
    TEST_ASSERT(dir[0]);
    char command[600];
    snprintf(command, sizeof command, "mkdir -p '%s'", dir);
    TEST_ASSERT(system(command) == 0);
    snprintf(path, sizeof path, "%s/box.scene", dir);
    snprintf(out, sizeof out, "%s/out", dir);
    TEST_ASSERT(write_box_scene(path, 4.0, 1, "") == 0);
    char err[1024];
    Scene *scene = scene_load(path, NULL, 0, err, sizeof err);
    TEST_ASSERT(scene);
    long rained = scene->grains.count;
    scene_free(scene);
    TEST_ASSERT(run_scene(path, out, NULL, 0) == 0);
    char *summary = read_text(out, "summary.json");
    TEST_ASSERT(summary);
    const char *key = "\"sinks\": [{\"shape\": \"below\", \"removed\": ";
    const char *sinks = strstr(summary, key);
    TEST_ASSERT(sinks);
    long removed = atol(sinks + strlen(key));
    const char *stage = strstr(summary, "{\"name\": \"fill\"");
    TEST_ASSERT(stage);
    const char *mobile = strstr(stage, "\"mobile_grains\": "),
               *in_stage = strstr(stage, "\"removed\": ");
    TEST_ASSERT(mobile && in_stage);
    TEST_ASSERT(removed > 10);
    TEST_ASSERT(atol(in_stage + strlen("\"removed\": ")) == removed);
    TEST_ASSERT(removed + atol(mobile + strlen("\"mobile_grains\": ")) == rained);
    char expect[64];
    snprintf(expect, sizeof expect, "\"removed_by_sinks\": [%ld]", removed);
    TEST_ASSERT(strstr(stage, expect));
    free(summary);
    remove_dir(dir);
    return 0;
}

TEST_MAIN(TEST_CASE(column_scene_outputs), TEST_CASE(undeclared_costs_nothing),
          TEST_CASE(sink_counts_in_summary))
