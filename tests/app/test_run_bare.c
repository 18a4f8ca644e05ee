/* SPDX-License-Identifier: MIT */
/* test_run_bare.c: AppRunOptions.bare and .world (docs/dev/architecture.md, "A family's protocol
 * may run its phases in process"): the resume test's scene (two stages, a source, a trace, no
 * family), reduced to a fraction of a second, run bare into
 * an empty folder writes nothing there and hands back its last world, the world a full run of
 * the same scene saves as its last stage's state (same time, steps and bytes); a failure comes
 * back in `err`, not on stderr. */
#include "test.h"

#include "run/run.h"
#include "scene/scene.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define SCENE "tests/cli/resume.scene"

static Scene *small(void)
{
    const char *sets[] = {"stages.fill.time.end=0.05", "stages.tilt.time.end=0.05",
                          "output.checkpoint_every=0.02"};
    char err[2048];
    Scene *scene = scene_load(SCENE, sets, 3, err, sizeof err);
    if (!scene)
        fprintf(stderr, "%s\n", err);
    return scene;
}

/* Entries of folder `dir` besides . and .., -1 when it cannot be read. */
static int entries(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    int n = 0;
    for (struct dirent *e; (e = readdir(d)) != NULL;)
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(d);
    return n;
}

static int bare_writes_nothing_and_hands_the_world(void)
{
    Scene *scene = small();
    TEST_ASSERT(scene != NULL);
    char bare_dir[256], full_dir[256], cmd[1600], err[512] = "x";
    snprintf(bare_dir, sizeof bare_dir, "/tmp/sablier_test_run_bare_%ld", (long)getpid());
    snprintf(full_dir, sizeof full_dir, "/tmp/sablier_test_run_full_%ld", (long)getpid());
    snprintf(cmd, sizeof cmd, "rm -rf '%s' '%s' && mkdir -p '%s'", bare_dir, full_dir, bare_dir);
    TEST_ASSERT(system(cmd) == 0);
    SimWorld *world = NULL;
    AppRunOptions options = app_run_options_default();
    options.out_dir = bare_dir;
    options.bare = 1;
    options.err = err;
    options.err_size = sizeof err;
    options.world = &world;
    TEST_ASSERT(app_run(scene, &options) == 0);
    TEST_ASSERT(err[0] == '\0');
    TEST_ASSERT(world != NULL);
    TEST_ASSERT(entries(bare_dir) == 0); /* no summary, energy, trace, states, checkpoints */
    /* the same scene run with its files: its last state is the bare run's world */
    AppRunOptions full = app_run_options_default();
    full.out_dir = full_dir;
    full.quiet = 1;
    full.render_off = 1;
    TEST_ASSERT(app_run(scene, &full) == 0);
    char path[700], saved[700];
    snprintf(path, sizeof path, "%s/%s.state", full_dir,
             scene->stages[scene->stage_count - 1].name);
    snprintf(saved, sizeof saved, "%s/bare.state", bare_dir);
    SimError error;
    TEST_ASSERT(sim_world_save(world, saved, &error) == SIM_OK);
    snprintf(cmd, sizeof cmd, "cmp -s '%s' '%s'", path, saved);
    TEST_ASSERT(system(cmd) == 0);
    sim_world_destroy(world);
    /* a failure: its message in err, no world */
    world = (SimWorld *)(void *)&options; /* any pointer: the run sets it to NULL */
    scene->stages[0].load = SCENE_LOAD_FILE;
    snprintf(scene->stages[0].load_path, sizeof scene->stages[0].load_path, "%s/none.state",
             bare_dir);
    TEST_ASSERT(app_run(scene, &options) == 2);
    TEST_ASSERT(world == NULL);
    TEST_ASSERT(strstr(err, "none.state") != NULL);
    scene_free(scene);
    snprintf(cmd, sizeof cmd, "rm -rf '%s' '%s'", bare_dir, full_dir);
    TEST_ASSERT(system(cmd) == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(bare_writes_nothing_and_hands_the_world))
