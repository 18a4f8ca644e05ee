/* SPDX-License-Identifier: MIT */
/* driver.h: what every multi-run command (`sablier sweep`, `bne`, `sediment`, `study`,
 * `ensemble`; docs/cli.md) shares: its common options (--out, --set, --vary, --jobs, --quiet,
 * --resume and the scene), the default output folder, a member's --set list, loading a member
 * with its sets and its family checked, and running it into its folder through the stage runner.
 * The members run through the process pool (pool.h: in-process children, local or under MPI;
 * signals, --resume); a command keeps only its levels, its member folders and its reduction.
 * docs/dev/architecture.md says how a sixth command plugs in. App core: names no family. */
#ifndef APP_DRIVER_H
#define APP_DRIVER_H

#include "base/experiment.h"
#include "base/util.h"
#include "driver/pool.h"
#include "run/run.h"
#include "scene/scene.h"

#include <stddef.h>

/// Most --vary options a command takes.
#define APP_DRIVER_VARY_MAX 8

/// What a command accepts of the common options.
typedef struct AppDriverSpec {
    const char *usage; ///< the command's usage text, printed after a usage error
    long jobs_max;     ///< --jobs N in [1, jobs_max]
    int sets_max;      ///< at most this many --set (0: APP_MAX_SETS)
    /// --vary: 0 not an option; 1 one key (the last given counts); else at most this many
    /// (up to APP_DRIVER_VARY_MAX)
    int vary_max;
    const char *set_error;   ///< the message of a bad --set (NULL: app_collect_set's own)
    const char *extra_error; ///< a second scene (NULL: "one scene at a time; extra argument")
    int no_quiet;            ///< 1: --quiet and -q are not options of the command
    const char *missing;     ///< the message when no scene is given ("missing SCENE")
} AppDriverSpec;

/// The common options of a command line.
typedef struct AppDriverArgs {
    const char *scene; ///< the one positional argument (NULL: none yet)
    const char *out;   ///< --out DIR (NULL: the command's default)
    const char *sets[APP_MAX_SETS];
    int set_count;
    const char *vary[APP_DRIVER_VARY_MAX];
    int vary_count;
    long jobs;  ///< --jobs, 2 unless given
    int quiet;  ///< --quiet or -q
    int resume; ///< --resume
} AppDriverArgs;

/// Every argument from argv[2] on: the common ones into *a (emptied first: no scene, no --out,
/// no sets, --jobs 2),
/// each other one handed to `own` (ctx, argc, argv, &i: 1 when it took argv[*i], 0 when it is not
/// its own, else the exit status of a usage error); then a usage error when no scene was given.
/// 0, or the exit status of a usage error.
int app_driver_parse(const AppDriverSpec *s, int argc, char **argv, AppDriverArgs *a,
                     int (*own)(void *ctx, int argc, char **argv, int *i), void *ctx);

/// The default output folder "out/PREFIX-BASE" of a scene path (BASE: its file name up to the
/// first dot) into out[size].
void app_driver_default_out(const char *prefix, const char *scene_path, char *out, size_t size);

/// A member's --set list: the command line's, then the family's or the level's, then the
/// member's own (seed, the varied key), in that order (the last of one key wins).
typedef struct AppDriverSets {
    const char *sets[3 * APP_MAX_SETS];
    int count;
    char text[4][200]; ///< the formatted ones
    int text_count;
} AppDriverSets;

/// sets[0 .. n-1] appended (NULL-ended when n < 0). 0, or -1 when they do not fit.
int app_driver_sets_add(AppDriverSets *s, const char *const *sets, int n);

/// One formatted set ("seed=%ld") appended. 0, or -1 when it does not fit.
int app_driver_sets_printf(AppDriverSets *s, const char *format, ...)
    __attribute__((format(printf, 2, 3)));

/// The scene at `path` with the sets: NULL with the loader's file:line message on stderr when it
/// does not load, or (with `family` not NULL) when it has no group of the family (its file:1).
Scene *app_driver_load(const char *path, const AppDriverSets *sets, const AppExperiment *family);

/// Runs a loaded member through the stage runner into `dir`, quietly; `render` NULL: no movies,
/// figures or "not built" warning. Its exit status (app_run).
int app_driver_run(Scene *scene, const char *dir, const AppRender *render);

/// The member at `path` with the sets, loaded (app_driver_load), run (app_driver_run) and freed:
/// its exit status, 2 when it does not load.
int app_driver_member(const char *path, const AppDriverSets *sets, const AppExperiment *family,
                      const char *dir, const AppRender *render);

/// A command's members through the process pool (pool.h). The driver keeps their statuses, says
/// when a fork failed and prints the command's progress line as each member ends.
typedef struct AppDriverPool {
    const char *command; ///< the messages' prefix: "sablier: COMMAND: ..."
    /// The message of a failed fork, followed by the reason ("cannot start a member"); NULL:
    /// `ended` is called with APP_POOL_NOT_STARTED and reports it.
    const char *not_started;
    int count;         ///< members 0 .. count-1
    long jobs;         ///< at most this many at a time (--jobs)
    int resume;        ///< --resume: skip the members whose folder holds a completed run
    int signal_status; ///< the status of a member a signal ended
    int quiet;         ///< --quiet: no progress lines
    void *ctx;         ///< handed to every hook
    /// Member k's status as it ends (NULL: none kept): -1 until then (app_driver_pool_run sets
    /// them), 2 when its fork failed.
    int *status;
    int (*start)(void *ctx, int k); ///< optional: pool.h's start
    int (*run)(void *ctx, int k);   ///< pool.h's run: the member, in its child
    /// Optional: member k's folder (pool.h's folder; --resume); 0, or -1 when it has none.
    int (*folder)(void *ctx, int k, char *dir, size_t size);
    /// Optional: member k ended with `status`; returns the status it keeps (a member whose results
    /// cannot be read: 2).
    int (*ended)(void *ctx, int k, int status);
    /// Optional: the progress line of member k that ended with `status`, without the prefix and
    /// the newline, into line[size] (left empty: no line).
    void (*progress)(void *ctx, int k, int status, char *line, size_t size);
    int finished;    ///< members that ended, not counting those interrupted (for an ETA)
    int failed;      ///< 1 once a member ended otherwise than with 0, or its fork failed
    double start_at; ///< sim_clock_seconds(SIM_CLOCK_WALL) when the pool started
} AppDriverPool;

/// Runs the members: app_pool_run's status (0, -1 when a fork or a wait failed, 128 + the
/// signal that stopped it).
int app_driver_pool_run(AppDriverPool *p);

/// In a member's child: its stdout and stderr into DIR/log.txt (left as they are when the file
/// cannot be opened).
void app_driver_log_to(const char *dir);

#endif
