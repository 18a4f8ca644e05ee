/* SPDX-License-Identifier: MIT */
/* test_sources.c: insertion sources (app/scene/sources.h): the count over a stage is the rate times
 * the time, inserted grains never overlap, the same seed gives the same grains. */
#include "app_test_run.h"
#include "test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *const BOX =
    "name = \"sources\"; mass_model = \"disk\"; effects = [\"friction\"];\n"
    "gravity = [0.0, -1.0];\n"
    "contact = { normal = \"linear\"; tangential = \"regularised\"; };\n"
    "species = ( { name = \"a\"; density = 1.27; k_n = 2000.0; mu = 0.5; gamma_s = 1.0;\n"
    "              restitution = 0.3; },\n"
    "            { name = \"b\"; density = 1.27; k_n = 2000.0; mu = 0.5; gamma_s = 1.0;\n"
    "              restitution = 0.3; } );\n"
    "walls = ( { from = [0.0, 0.0]; to = [20.0, 0.0]; }, { from = [0.0, 0.0]; to = [0.0, 30.0]; "
    "},\n"
    "          { from = [20.0, 0.0]; to = [20.0, 30.0]; } );\n"
    "grains = { list = (); };\n";

/* Runs BOX + `more` with `seed` into dir (256 bytes); the number of grains inserted. */
static long run_box(const char *more, int seed, char *dir, int tag)
{
    char path[256];
    snprintf(path, sizeof path, "/tmp/sablier_test_sources_%ld.scene", (long)getpid());
    snprintf(dir, 256, "/tmp/sablier_test_sources_%ld_%d", (long)getpid(), tag);
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fprintf(f, "%sseed = %d;\n%s\n", BOX, seed, more);
    fclose(f);
    int status = app_test_run(path, NULL, 0, dir);
    remove(path);
    if (status != 0)
        return -1;
    SimGrainSet g;
    if (app_test_state(dir, "run", &g) != 0)
        return -1;
    long n = g.count;
    sim_grain_set_free(&g);
    return n;
}

/* 20 grains/s for 3 s into an empty box: 60 grains, within one. */
static int count_is_rate_times_time(void)
{
    char dir[256];
    long n = run_box("sources = ( { region = [1.0, 10.0, 19.0, 28.0]; rate = 20.0;\n"
                     "  radius = [0.4, 0.6]; } );\ntime = { dt = 1e-3; end = 3.0; };",
                     1, dir, 0);
    app_test_remove_dir(dir);
    TEST_ASSERT(n >= 59 && n <= 61);
    return 0;
}

/* 150 grains of two species at once into a crowded region: none overlaps another or a wall;
 * the same seed gives the same bytes, another seed other grains. */
static int no_overlap_same_seed_same_grains(void)
{
    const char *more =
        "sources = ( { region = [0.6, 0.6, 19.4, 12.0]; count = 150;\n"
        "  mixture = ( { species = \"a\"; fraction = 0.7; radius = 0.4; },\n"
        "              { species = \"b\"; fraction = 0.3; radius = [0.6, 0.7]; } );\n"
        "  attempts = 50; } );\ntime = { dt = 1e-3; end = 0.0; };";
    char dir[3][256];
    TEST_ASSERT(run_box(more, 1, dir[0], 1) > 100);
    TEST_ASSERT(run_box(more, 1, dir[1], 2) > 100);
    TEST_ASSERT(run_box(more, 2, dir[2], 3) > 100);
    char path[1024];
    snprintf(path, sizeof path, "%s/run.state", dir[0]);
    SimGrainSet g;
    SimWall *walls = NULL;
    int wall_count = 0;
    double time;
    SimError error;
    TEST_ASSERT(sim_state_load(path, &g, &walls, &wall_count, &time, &error) == SIM_OK);
    for (int i = 0; i < g.count; ++i) {
        for (int j = i + 1; j < g.count; ++j)
            TEST_ASSERT(hypot(g.x[i] - g.x[j], g.y[i] - g.y[j]) >= g.radius[i] + g.radius[j]);
        for (int k = 0; k < wall_count; ++k)
            TEST_ASSERT(sim_wall_contact_distance(&walls[k], g.x[i], g.y[i], g.radius[i]) >=
                        g.radius[i]);
    }
    sim_grain_set_free(&g);
    free(walls);
    SimGrainSet a, b, c;
    for (int r = 0; r < 3; ++r) {
        snprintf(path, sizeof path, "%s/run.state", dir[r]);
        TEST_ASSERT(sim_state_load(path,
                                   r == 0   ? &a
                                   : r == 1 ? &b
                                            : &c,
                                   &walls, &wall_count, &time, &error) == SIM_OK);
        free(walls);
    }
    TEST_ASSERT(a.count == b.count);
    TEST_ASSERT(memcmp(a.x, b.x, (size_t)a.count * sizeof(double)) == 0);
    TEST_ASSERT(memcmp(a.radius, b.radius, (size_t)a.count * sizeof(double)) == 0);
    TEST_ASSERT(a.count != c.count || memcmp(a.x, c.x, (size_t)a.count * sizeof(double)) != 0);
    sim_grain_set_free(&a);
    sim_grain_set_free(&b);
    sim_grain_set_free(&c);
    for (int r = 0; r < 3; ++r)
        app_test_remove_dir(dir[r]);
    return 0;
}

/* `rain` as a list of groups: a bidisperse bed of two species, each from its own region. */
static int rain_list_of_groups(void)
{
    char path[256], err[2048];
    snprintf(path, sizeof path, "/tmp/sablier_test_rain_%ld.scene", (long)getpid());
    FILE *f = fopen(path, "w");
    TEST_ASSERT(f);
    fprintf(f, "%s",
            "name = \"rain\"; seed = 1; mass_model = \"disk\"; time = { dt = 1e-3; end = 1.0; };\n"
            "species = ( { name = \"a\"; density = 1.0; k_n = 1e3; gamma_n = 1.0; },\n"
            "            { name = \"b\"; density = 1.0; k_n = 1e3; gamma_n = 1.0; } );\n"
            "grains = { rain = ( { x0 = 0.0; x1 = 10.0; y0 = 0.0; y1 = 5.0; radius_mean = 0.5;\n"
            "                      species = \"a\"; },\n"
            "                    { x0 = 0.0; x1 = 10.0; y0 = 6.0; y1 = 11.0; radius_mean = 0.3;\n"
            "                      species = \"b\"; } ); };\n");
    fclose(f);
    Scene *scene = scene_load(path, NULL, 0, err, sizeof err);
    remove(path);
    if (!scene)
        fprintf(stderr, "%s\n", err);
    TEST_ASSERT(scene);
    int count[2] = {0, 0};
    for (int i = 0; i < scene->grains.count; ++i)
        count[scene->grains.species[i]]++;
    scene_free(scene);
    TEST_ASSERT(count[0] > 10 && count[1] > count[0]);
    return 0;
}

TEST_MAIN(TEST_CASE(count_is_rate_times_time), TEST_CASE(no_overlap_same_seed_same_grains),
          TEST_CASE(rain_list_of_groups))
