/* SPDX-License-Identifier: MIT */
/* experiment.h: the one interface of an experiment family (types only). A family (crater, Brazil
 * nut, sediment, discharge, ...) is a folder app/<family>/ that defines one AppExperiment and is
 * listed once in app/base/experiments.c. The scene loader, the stage runner and the CLI reach
 * families only through this table; every hook is optional (NULL: nothing to do).
 *
 * Lifecycle of one `sablier run` (app/run/run.c), for each family whose parse hook returned a
 * state:
 *
 *     parse                      scene_load: the family's top-level group (and its own stage or
 *                                output keys) -> state; adjust_def shapes each stage's world
 *     begin                      output folder ready: open the family's files
 *     for each stage:
 *       restart?                 1: the stage re-creates its world instead of continuing
 *       stage_edit               world ready, before the scene's removals (dig a cavity, ...)
 *       stage_begin              after every edit, at the stage's start time
 *       loop: sample             at every energy row (output.energy_every)
 *             next_step, step    at steps the family asks for (profiles, phase samples)
 *             stage_done         at every step boundary: 1 ends the stage there
 *       stage_end                checkpoint written (the world is the stage's end state)
 *     end                        every stage done or the run failed (ok = 0); world may be NULL
 *                                (ok = 0 with c->checkpointed: interrupted at a checkpoint, the
 *                                files appended to are committed as they are, for --resume)
 *     summary_json               members for summary.json
 *     figures                    after a successful run: figures drawn from the written files
 *
 * Checkpoints and --resume (docs/cli.md#periodic-checkpoints-and---resume):
 *
 *     checkpoint                 at a checkpoint of the running stage, at a step boundary after
 *                                that step's sample/step hooks: the family writes what it keeps
 *                                in memory (counters, sums, next-due steps, the lengths of the
 *                                files it appends to) as lines of its section of checkpoint.txt
 *                                (app/base/checkpoint.h)
 *     --resume: parse, begin     as in any run (begin opens the files afresh)
 *       resume                   the resumed stage's world loaded, before its loop (no
 *                                stage_edit, no stage_begin for it): the family restores its
 *                                section and reopens its append files at the recorded lengths
 *                                (the world is loaded again after it when a family has
 *                                adjust_def, which then sees the restored state)
 *       loop, stage_end, ...     as above; the later stages as in any run
 *
 * A family that keeps state across steps (any hook after begin) without a resume hook makes
 * --resume refuse the scene, naming the family, before anything runs.
 *
 * A family's multi-run drivers (sweeps, seed samples, scans, studies) are CLI commands listed in
 * `commands`; they sit above the runner (app_run) and use app/driver/pool.h for processes. */
#ifndef APP_EXPERIMENT_H
#define APP_EXPERIMENT_H

#include "base/render_hooks.h"
#include "sim/sim.h"

#include <libconfig.h>
#include <stddef.h>
#include <stdio.h>

struct Scene;

/// Where a run is, handed to every runtime hook. The runner owns it; hooks read it, add to
/// `removed` (stage_edit) and write messages to err.
typedef struct AppContext {
    const struct Scene *scene;
    const char *out_dir;
    const AppRender *render; ///< NULL: figures and movies are skipped
    int stage;               ///< current stage index (-1 before the first)
    SimWorld *world;         ///< current world; NULL before the first stage (and in end, at times)
    double stage_start;      ///< simulated time at the stage's start, s
    long stage_steps;        ///< steps the stage runs at most
    int removed;             ///< grains removed at the stage's start, by every edit
    int checkpointed;        ///< 1 once the run stopped at a checkpoint it can --resume from
    char *err;
    size_t err_size;
} AppContext;

/// What the CLI gives a family command.
typedef struct AppEnv {
    const AppRender *render;     ///< NULL when rendering is not built
    const char *sablier_version; ///< for summary.json
    const char *render_versions; ///< render_library_versions(), NULL when not built
    const char *self;            ///< the sablier executable, for drivers that exec members
} AppEnv;

/// One `sablier COMMAND`: argv[0] is "sablier", argv[1] the command. Returns the exit status.
typedef struct AppCommand {
    const char *name;
    const char *help;  ///< its line in `sablier --help`: "NAME ARGS  what it does" (no newline)
    const char *usage; ///< `sablier NAME --help`
    int (*run)(int argc, char **argv, const AppEnv *env);
    /// Checks the command line only, as `run` does first: 0 when it is good, else the exit status
    /// of the usage error (message on stderr). Reads no file, writes nothing, starts nothing
    /// (tests/fuzz/fuzz_cli.c calls it on any argument list).
    int (*parse)(int argc, char **argv);
} AppCommand;

/// A family's ensemble member (AppExperiment.member): `sablier <command> SCENE --out DIR --quiet
/// --set ...` with `sets` (NULL-ended, at most 4, or NULL) after the driver's own --set lines;
/// `timing` gives the time step and steps per contact such a member uses with the scene as
/// loaded (the last stage's world definition would give them for `sablier run`).
typedef struct AppMember {
    const char *command;
    const char *const *sets;
    SimTiming (*timing)(const void *state, const struct Scene *scene);
} AppMember;

typedef struct AppExperiment {
    const char *name;  ///< family name, also its folder: "crater"
    const char *group; ///< top-level scene key that declares it ("bne"), or NULL
    /// An older name of `group` the loader still accepts (documented in docs/scenes.md), or NULL.
    /// A scene gives one of the two; the family's messages name the one it gave.
    const char *group_alias;
    /// Effects the family's group stands for (SIM_EFFECT_*): the group needs them declared in
    /// `effects`, as a core group does (`drag` needs fluid_drag), and an effect that needs a core
    /// group (fluid_drag: `drag`) is content with the family's group instead.
    unsigned effects;
    /// 1: a scene with the family's group makes its mobile grains during the run, so its
    /// `grains` may hold fixed grains only (the loader refuses such a scene otherwise).
    int grains_from_run;
    /// Keys the family owns inside each stage group and inside `output` (NULL-ended lists, or
    /// NULL); the loader accepts them and leaves them to parse.
    const char *const *stage_keys;
    const char *const *output_keys;
    /// The files the family writes into a run's folder under fixed names (NULL-ended, or NULL),
    /// claimed for it when a scene uses it: no figure or measure may write one of them.
    const char *const *outputs;
    /// Parses the family's settings: `group` is the top-level group (NULL when absent), `root` the
    /// whole scene (for stage and output keys). The scene's physics, grains, stages and output
    /// are parsed. Sets *state (NULL: the scene does not use the family) and returns 0, or -1
    /// with "file:line: message" in err.
    int (*parse)(const config_setting_t *root, const config_setting_t *group, struct Scene *scene,
                 void **state, char *err, size_t err_size);
    void (*free)(void *state);
    /// Shapes stage `stage`'s world definition (scene_world_def).
    void (*adjust_def)(const void *state, int stage, SimWorldDef *def);
    /// 1 when stage `stage` must re-create its world rather than continue in memory.
    int (*restart)(const void *state, int stage);
    /// Prints the family's settings of one stage for `sablier check` (", dig ...", no newline).
    void (*describe_stage)(const void *state, int stage, FILE *out);

    int (*begin)(void *state, AppContext *c);
    int (*stage_edit)(void *state, AppContext *c);
    int (*stage_begin)(void *state, AppContext *c);
    void (*sample)(void *state, AppContext *c);
    /// The earliest step after `done` (counted from the stage start) at which step() is due, or
    /// `next` when that comes first.
    long (*next_step)(const void *state, const AppContext *c, long done, long next);
    /// Called at every step boundary the runner stops at (`done` steps into the stage).
    void (*step)(void *state, AppContext *c, long done);
    /// The family's stop criterion, at every step boundary after `step` (and after the stage's
    /// settle test): 1 ends the stage at `done` as its time.end would (a flow that stopped, a
    /// pile at rest, a target reached; next_step makes the runner stop at the steps it tests
    /// on), 0 goes on, -1 fails the run with err (exit status 2).
    int (*stage_done)(void *state, AppContext *c, long done);
    int (*stage_end)(void *state, AppContext *c);
    int (*end)(void *state, AppContext *c, int ok);
    /// Writes the family's section of a checkpoint record (app/base/checkpoint.h). 0, or -1 with
    /// err.
    int (*checkpoint)(const void *state, const AppContext *c, FILE *out);
    /// --resume: restores the section `record` (its lines; "" when the checkpoint has none)
    /// into the state begin made. 0, or -1 with err.
    int (*resume)(void *state, AppContext *c, const char *record);
    /// JSON members `"key": value, ` (each followed by ", ") for summary.json.
    void (*summary_json)(const void *state, char *out, size_t size);
    /// After a successful run: figures drawn from the run's files.
    int (*figures)(const void *state, const AppContext *c);
    /// Extras for a grain figure of this scene (side panels, marks). 1 when filled, else 0.
    /// The data pointed to stays valid until the next call or free.
    int (*figure_extras)(void *state, const SimFrame *frame, AppFigureExtras *extras);

    const AppCommand *commands;
    int command_count;

    /// How a driver that runs one scene many times at chosen time steps (`sablier ensemble`)
    /// runs a member of a scene of this family, when the family's protocol is a command of its
    /// own rather than `sablier run` (NULL: `sablier run`, with the last stage's timing).
    const AppMember *member;
} AppExperiment;

#endif
