/* SPDX-License-Identifier: MIT */
/* app_test_run.h: runs of scenes for the app tests (tests/app/test_*.c): a scene file (with
 * --set overrides) run quietly without rendering into a folder, the grains of a stage's
 * checkpoint, and the folder removed. Static inline, so a test using part of it compiles
 * warning-free. */
#ifndef APP_TEST_RUN_H
#define APP_TEST_RUN_H

#include "run/run.h"
#include "scene/scene.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

/// Loads `path` with the sets and runs it into `dir`: the exit status, -1 when it does not load.
static inline int app_test_run(const char *path, const char *const *sets, int set_count,
                               const char *dir)
{
    char err[2048];
    Scene *scene = scene_load(path, sets, set_count, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    AppRunOptions options = app_run_options_default();
    options.out_dir = dir;
    options.quiet = 1;
    options.render_off = 1;
    int status = app_run(scene, &options);
    scene_free(scene);
    return status;
}

/// The grains of DIR/STAGE.state (free with sim_grain_set_free; walls dropped). 0, or -1.
static inline int app_test_state(const char *dir, const char *stage, SimGrainSet *grains)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s.state", dir, stage);
    SimWall *walls = NULL;
    int wall_count = 0;
    double time;
    SimError err;
    if (sim_state_load(path, grains, &walls, &wall_count, &time, &err) != SIM_OK) {
        fprintf(stderr, "%s\n", err.message);
        return -1;
    }
    free(walls);
    return 0;
}

/// Removes a run folder and the files in it.
static inline void app_test_remove_dir(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    char path[1024];
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        int n = snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (n > 0 && (size_t)n < sizeof path) /* a longer path is not this folder's file */
            remove(path);
    }
    closedir(d);
    rmdir(dir);
}

#endif
