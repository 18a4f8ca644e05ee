/* SPDX-License-Identifier: MIT */
/* run.h: runs the stages of a loaded scene and writes its outputs (summary.json, energy.csv,
 * trace.csv, checkpoints). Knows nothing about rendering: figures and movies go through the
 * hooks that app/sablier.c fills with render/ calls (NULL hooks: they are skipped).
 *
 *     AppRunOptions options = app_run_options_default();
 *     options.out_dir = "out/quick";
 *     int status = app_run(scene, &options);  // 0 ok, 1 simulation failed, 2 bad input / I/O
 */
#ifndef APP_RUN_H
#define APP_RUN_H

#include "scene.h"

#include "sim/sim.h"

#include <stddef.h>

/// What the runner needs from a renderer. Each returns 0 on success, else -1 with a message.
typedef struct AppRenderHooks {
    void *context;
    /// Opens the movie of one stage at `path` and fills `sink` with its frame consumer.
    int (*movie_open)(void *context, const Scene *scene, int stage, const char *path,
                      SimFrameSink *sink, char *err, size_t err_size);
    /// Finishes the movie opened last (flush, rename). Called once per successful open.
    int (*movie_close)(void *context, char *err, size_t err_size);
    /// Writes one figure of a frame to `path` (format from the extension).
    int (*figure)(void *context, const Scene *scene, const SceneFigure *figure,
                  const SimFrame *frame, const char *path, char *err, size_t err_size);
} AppRenderHooks;

typedef struct AppRunOptions {
    const char *out_dir;          ///< created if missing
    int quiet;                    ///< 1: one line per stage only
    int threads;                  ///< for encoding/rendering; the simulation is serial
    const AppRenderHooks *render; ///< NULL: figures and movies skipped with one warning
    const char *sablier_version;  ///< for summary.json
    const char *render_versions;  ///< render_library_versions(), or NULL
} AppRunOptions;

AppRunOptions app_run_options_default(void);

/// Runs every stage; returns the exit status (0, 1 or 2) after printing any message on stderr.
int app_run(const Scene *scene, const AppRunOptions *options);

/// Free-surface height near x: highest top (y + r) of mobile grains with |x_i - x| <= half_width,
/// m. Returns 0 and sets *top, or -1 when no mobile grain is in the band.
int app_surface_height(const SimFrame *frame, double x, double half_width, double *top);

/// mkdir -p; 0 on success.
int app_make_dirs(const char *path);

#endif
