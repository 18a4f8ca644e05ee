/* SPDX-License-Identifier: MIT */
/* run_internal.h: the stage runner's state, shared by its files (private to app/run/): run.c
 * runs the stages, run_summary.c writes summary.json from what they report. */
#ifndef APP_RUN_INTERNAL_H
#define APP_RUN_INTERNAL_H

#include "run/run.h"
#include "scene/sources.h"

#include <stdio.h>

#define PATH_SIZE     (SCENE_PATH_MAX + 2 * SCENE_NAME_MAX)
#define RESOLVED_NAME "scene.resolved.cfg" /* the scene as run, beside its outputs */

typedef struct StageReport {
    long steps;
    double start_time, end_time; /* s */
    double wall_seconds;
    int settled;
    int removed;  /* grains removed at the start (edits) and by the sinks during the stage */
    int at_start; /* of which at the start */
    long sinks[SIM_MAX_SINKS]; /* sink counters at the start, then grains through each sink */
    int mobile;
} StageReport;

typedef struct Run {
    const Scene *scene;
    const AppRunOptions *options;
    SimWorld *world;
    FILE *energy, *trace;
    char energy_path[PATH_SIZE], trace_path[PATH_SIZE];
    double time_scale; /* sqrt(D/g), s; 0 = unknown */
    /* units = "reduced" (docs/scenes.md#units): d, m and sqrt(d/g) of the mobile grains at the
     * start of the first stage, fixed for the run; 0 in SI */
    double unit_length, unit_mass, unit_time;
    long steps;
    double simulated, particle_steps, step_seconds;
    double contacts_sum;
    long contacts_samples;
    StageReport stages[SCENE_MAX_STAGES];
    int stages_done;
    int status; /* exit status */
    char message[4 * PATH_SIZE];
    SimError error;
    int render_warned;
    int progress_tty;
    double progress_every, last_progress; /* wall s between progress lines (0: none); the last */
    AppThreads threads;  /* fixed, tuned (APP_THREADS_AUTO) or switched: thread_tuner.h */
    int threads_asked;   /* the count last given to the world (sim_world_set_threads) */
    int threads_most;    /* the most threads the step ran on: summary.json's "threads" */
    AppContext context;  /* what the experiment families' hooks see */
    char observed[2048]; /* their summary.json members */
    /* The motions' clocks by world time (sim_world_set_motion), from the stages' `motions`. */
    int motion_running[SIM_MAX_MOTIONS];
    double motion_on[SIM_MAX_MOTIONS], motion_off[SIM_MAX_MOTIONS];
    double settle_since; /* the stage time since which the settle test holds; < 0: it does not */
    AppSources *sources; /* insertion sources, NULL without */
    /* Checkpoints (docs/cli.md): the wall clock of the last one; with --resume, the point
     * the run continues from (stage, steps done in it, state file) and the original start. */
    double checkpoint_wall;
    int resume_stage;
    long resume_done;
    char resume_state[PATH_SIZE];
    long long started;
    long energy_bytes, trace_bytes; /* of the files at the resumed checkpoint */
    char *resume_record;            /* its checkpoint.txt, whole (sections included) */
} Run;

/// summary.json of the run, written atomically into its folder: 0, or -1.
int app_run_summary_write(const Run *run, double wall_seconds);

#endif
