/* SPDX-License-Identifier: MIT */
/* run.h: runs the stages of a loaded scene and writes its outputs (summary.json, energy.csv,
 * trace.csv, checkpoints) and calls the experiment families' hooks (app/experiment.h). Knows
 * nothing about rendering: figures and movies go through the AppRender that app/render_glue.c
 * fills with render/ calls (NULL hooks: they are skipped).
 *
 *     AppRunOptions options = app_run_options_default();
 *     options.out_dir = "out/quick";
 *     int status = app_run(scene, &options);  // 0 ok, 1 simulation failed, 2 bad input / I/O
 */
#ifndef APP_RUN_H
#define APP_RUN_H

#include "render_hooks.h"
#include "scene.h"

#include "sim/sim.h"

#include <stddef.h>

typedef struct AppRunOptions {
    const char *out_dir;         ///< created if missing
    int quiet;                   ///< 1: one line per stage only
    int threads;                 ///< physics step, encoding, rendering (same results for any)
    const AppRender *render;     ///< NULL: figures and movies skipped with one warning
    int render_off;              ///< 1: the caller chose no rendering (NULL render, no warning)
    const char *sablier_version; ///< for summary.json
    const char *render_versions; ///< render_library_versions(), or NULL
} AppRunOptions;

AppRunOptions app_run_options_default(void);

/// Runs every stage; returns the exit status (0, 1 or 2) after printing any message on stderr.
int app_run(const Scene *scene, const AppRunOptions *options);

/// mkdir -p; 0 on success.
int app_make_dirs(const char *path);

#endif
