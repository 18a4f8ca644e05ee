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

#include "provenance.h"
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
    AppProvenance provenance;    ///< the command line and --set overrides, for summary.json
    int force;  ///< 1: run into a folder that holds outputs of an unknown run (no manifest.txt)
    int resume; ///< 1: continue from the newest checkpoint in out_dir (DIR/checkpoint.txt)
} AppRunOptions;

AppRunOptions app_run_options_default(void);

/// Exit statuses of app_run besides 0 (ok), 1 (simulation failed) and 2 (bad input, I/O):
/// 128 + the signal for a run interrupted by SIGINT (130) or SIGTERM (143), which finishes its
/// step, saves DIR/STAGE.interrupted.state, commits every output and writes summary.json with
/// "status": "interrupted".
#define APP_EXIT_SIGNAL    128
/// Exit status of a run whose outputs could not be written because the disk or the quota was
/// full: no truncated file is left under a final name, and the message names the first one.
#define APP_EXIT_DISK_FULL 3

/// Runs every stage; returns the exit status after printing any message on stderr. SIGINT and
/// SIGTERM are caught while it runs (a second one kills at once); the caller's handlers are
/// restored on return.
int app_run(const Scene *scene, const AppRunOptions *options);

#endif
