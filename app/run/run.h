/* SPDX-License-Identifier: MIT */
/* run.h: runs the stages of a loaded scene and writes its outputs (summary.json, energy.csv,
 * trace.csv, checkpoints) and calls the experiment families' hooks (app/base/experiment.h). Knows
 * nothing about rendering: figures and movies go through the AppRender that app/cli/render_glue.c
 * fills with render/ calls (NULL hooks: they are skipped).
 *
 *     AppRunOptions options = app_run_options_default();
 *     options.out_dir = "out/quick";
 *     int status = app_run(scene, &options);  // 0 ok, 1 simulation failed, 2 bad input / I/O
 */
#ifndef APP_RUN_H
#define APP_RUN_H

#include "base/render_hooks.h"
#include "output/provenance.h"
#include "run/thread_tuner.h"
#include "scene/scene.h"
#include "sim/sim.h"

#include <stddef.h>

/// Called between steps with the world of stage `stage` at its step `step` (app_run's hook).
typedef int (*AppRunHook)(void *context, SimWorld *world, int stage, long step);

typedef struct AppRunOptions {
    const char *out_dir; ///< created if missing
    int quiet;           ///< 1: one line per stage only
    /// Wall seconds between progress lines when stderr is no terminal (a batch job's log): one
    /// line each with the stage, the simulated time, the rate and the ETA; 0: none. Default
    /// APP_PROGRESS_EVERY; a terminal gets one line rewritten in place instead; quiet: neither.
    double progress_every;
    /// Threads of the physics step (the same results for any count): N, or APP_THREADS_AUTO
    /// (0): the count that steps fastest now, measured while the run goes on, within the CPUs
    /// this process may use (app/run/thread_tuner.h). Default 1 (the multi-run drivers run members
    /// side by side); `sablier run` defaults to APP_THREADS_AUTO.
    int threads;
    int grains_per_thread; ///< APP_THREADS_AUTO: mobile grains a thread of its first try; 0:
                           ///< default
    /// A testing aid: > 0 cycles the count through 1, 2, 3 and 4 threads every this many steps,
    /// whatever `threads` says (the results must be one thread's, to the bit).
    long threads_switch_every;
    double threads_block_seconds; ///< APP_THREADS_AUTO's measured blocks; 0: the default
    const AppRender *render;      ///< NULL: figures and movies skipped with one warning
    int render_off;               ///< 1: the caller chose no rendering (NULL render, no warning)
    const char *sablier_version;  ///< for summary.json
    const char *render_versions;  ///< render_library_versions(), or NULL
    AppProvenance provenance;     ///< the command line and --set overrides, for summary.json
    int force;  ///< 1: run into a folder that holds outputs of an unknown run (no manifest.txt)
    int resume; ///< 1: continue from the newest checkpoint in out_dir (DIR/checkpoint.txt)
    /// A caller's hook (the Python module's in-process runner, docs/python.md): called at step 0
    /// of every stage, every `hook_every` steps, and at its last step, after that step's
    /// outputs, with the stage's world, which it may read and change (sim_world_set_grains,
    /// sim_world_set_gravity, ...). Nonzero stops the run: exit status 2. NULL: none.
    AppRunHook hook;
    void *hook_context;
    long hook_every; ///< steps, >= 1
    /// 1: a phase of a family's protocol run in process, whose caller writes the outputs (its
    /// own files, in its own form): the runner writes no file (no summary.json, energy.csv,
    /// trace.csv, manifest, resolved scene, stage states or checkpoints; out_dir may be NULL),
    /// catches no signal, prints no line, and puts a failure's message in `err` rather than on
    /// stderr. The scene is then usually one the caller built in memory (its stages the phases).
    int bare;
    char *err; ///< bare: the message of a failure ("" when none); may be NULL
    size_t err_size;
    /// Not NULL: the world at the end of a successful run is handed over here (the caller
    /// destroys it) instead of destroyed; NULL after a failure.
    SimWorld **world;
} AppRunOptions;

AppRunOptions app_run_options_default(void);

/// Default of AppRunOptions.progress_every, s.
#define APP_PROGRESS_EVERY 60.0

/* APP_THREADS_AUTO and app_step_threads: thread_tuner.h; the CPUs: sim_cpu_count (sim.h) */

/// Exit statuses of app_run besides 0 (ok), 1 (simulation failed) and 2 (bad input, I/O):
/// 128 + the signal for a run interrupted by SIGINT (130) or SIGTERM (143), which finishes its
/// step, saves DIR/STAGE.interrupted.state, commits every output and writes summary.json with
/// "status": "interrupted".
#define APP_EXIT_SIGNAL 128
/* APP_EXIT_DISK_FULL, the exit status of a run whose outputs did not fit: base/util.h */

/// Runs every stage; returns the exit status after printing any message on stderr. SIGINT and
/// SIGTERM are caught while it runs (a second one kills at once); the caller's handlers are
/// restored on return.
int app_run(const Scene *scene, const AppRunOptions *options);

/// app_run for bindings (the Python module, libsablier-scene): runs `scene` into `out_dir`
/// without figures or movies, quiet or with progress lines, on `threads` (APP_THREADS_AUTO: 0),
/// with `hook` (may be NULL) every `every` steps. Returns app_run's exit status.
int scene_run(const Scene *scene, const char *out_dir, int quiet, int threads, AppRunHook hook,
              void *context, long every);

#endif
