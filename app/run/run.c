/* SPDX-License-Identifier: MIT */
/* run.c: the stage runner. For each stage: build or continue the world, dig and remove, then step
 * in chunks that end on output times (energy rows, movie frames, trace rows, settle test), and
 * save a checkpoint. Every output is written under path.tmp and renamed when complete, so an
 * interrupted run never leaves a truncated file under a final name. */
#define _GNU_SOURCE /* struct sigaction */
#include "run/run.h"

#include "base/checkpoint.h"
#include "base/experiments.h"
#include "base/util.h"
#include "output/dump.h"
#include "run/run_internal.h"
#include "scene/sources.h"
#include "sim/sim.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* A stage steps at most this many steps between two looks at the signal flag (the chunks end on
 * output times anyway; their lengths do not change the bits). */
#define SIGNAL_CHECK_STEPS 2000

AppRunOptions app_run_options_default(void)
{
    AppRunOptions o;
    memset(&o, 0, sizeof o);
    o.threads = 1;
    o.progress_every = APP_PROGRESS_EVERY;
    o.sablier_version = "unknown";
    o.hook_every = 1;
    return o;
}

/* The step's threads for the world as it is now (AppRunOptions.threads, app/run/thread_tuner.h):
 * set when the count changes, or at once for a new world (`fresh`); the results do not depend on
 * it. */
static void apply_threads(Run *run, int fresh)
{
    const int want = app_threads_want(&run->threads, sim_world_mobile_count(run->world));
    if (fresh || want != run->threads_asked)
        sim_world_set_threads(run->world, want);
    run->threads_asked = want;
    const int have = sim_world_threads(run->world);
    run->threads_most = have > run->threads_most ? have : run->threads_most;
}

static void out_path(const Run *run, char *out, const char *name, const char *suffix)
{
    const char *dir = run->options->out_dir ? run->options->out_dir : "."; /* bare: may be NULL */
    snprintf(out, PATH_SIZE, "%s/%s%s", dir, name, suffix);
}

/* ---------------------------------------------------------------- outputs during a stage */

static void energy_row(Run *run, int stage)
{
    SimEnergy e = sim_world_energy(run->world);
    double t = sim_world_time(run->world);
    run->contacts_sum += e.contacts;
    run->contacts_samples++;
    for (int f = 0; app_experiments[f]; ++f) /* family measures ride on the energy rows */
        if (run->scene->experiments[f] && app_experiments[f]->sample)
            app_experiments[f]->sample(run->scene->experiments[f], &run->context);
    if (!run->energy)
        return;
    double t_star = run->time_scale > 0.0 ? t / run->time_scale : 0.0;
    if (run->unit_time > 0.0) /* reduced: t in sqrt(d/g), to the last bit */
        fprintf(run->energy, "%.17g,", t / run->unit_time);
    else
        fprintf(run->energy, "%.9g,", t);
    fprintf(run->energy, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d,%d,%s\n", t_star, e.kinetic, e.potential,
            e.rotational, e.elastic, e.total, e.mobile, e.contacts, run->scene->stages[stage].name);
}

static void trace_rows(Run *run, const SimFrame *frame)
{
    const SceneOutput *out = &run->scene->output;
    /* reduced units: lengths in d, times in tau = sqrt(d/g), speeds in d/tau = sqrt(g d), forces
     * in m g and torques in m g d (g = d / tau^2); all 1 in SI */
    double length = 1.0, time = 1.0, force = 1.0;
    if (run->unit_time > 0.0) {
        length = run->unit_length;
        time = run->unit_time;
        force = run->unit_mass * length / (time * time);
    }
    const double speed = length / time;
    for (int k = 0; k < out->trace_count; ++k)
        for (int i = 0; i < frame->count; ++i) {
            if (frame->id[i] != out->trace_ids[k])
                continue;
            fprintf(run->trace, "%.9g,%u,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n",
                    frame->time / time, frame->id[i], frame->x[i] / length, frame->y[i] / length,
                    frame->vx[i] / speed, frame->vy[i] / speed, frame->omega[i] * time,
                    frame->fx ? frame->fx[i] / force : 0.0, frame->fy ? frame->fy[i] / force : 0.0,
                    frame->torque ? frame->torque[i] / (force * length) : 0.0);
            break;
        }
}

/* Extras the scene's families add to a grain figure (the first family that has any). */
static const AppFigureExtras *figure_extras(Run *run, const SimFrame *frame, AppFigureExtras *out)
{
    for (int f = 0; app_experiments[f]; ++f)
        if (run->scene->experiments[f] && app_experiments[f]->figure_extras &&
            app_experiments[f]->figure_extras(run->scene->experiments[f], frame, out))
            return out;
    return NULL;
}

/* The figures of stage `stage` due now: at its start (when 0), its end (1) or, with `at` = a
 * time after the stage start (2), at step `done`. */
static int figures_due(Run *run, int stage, int when, long done, double dt)
{
    const Scene *scene = run->scene;
    const SceneOutput *out = &scene->output;
    const AppRender *render = run->options->render;
    SimFrame frame;
    int framed = 0;
    for (int k = 0; k < out->figure_count; ++k) {
        const SceneFigure *f = &out->figures[k];
        if (f->stage != stage || f->at_end != when || !render || !render->figure)
            continue;
        if (when == 2 && llround(f->at_time / dt) != done)
            continue;
        if (!framed) {
            sim_world_frame(run->world, &frame);
            framed = 1;
        }
        char path[PATH_SIZE], suffix[16], err[512] = "";
        snprintf(suffix, sizeof suffix, ".%s", f->format);
        out_path(run, path, f->name, suffix);
        AppFigureExtras extras = {0};
        if (render->figure(render->context, scene, f, &frame, figure_extras(run, &frame, &extras),
                           path, err, sizeof err) != 0) {
            snprintf(run->message, sizeof run->message, "figure %s: %s", path, err);
            return -1;
        }
    }
    return 0;
}

/* The next step after `done` at which a timed figure of the stage is due, else `total`. */
static long next_figure_step(const Run *run, int stage, long done, double dt, long total)
{
    const SceneOutput *out = &run->scene->output;
    long next = total;
    for (int k = 0; k < out->figure_count; ++k) {
        const SceneFigure *f = &out->figures[k];
        long step = llround(f->at_time / dt);
        if (f->stage == stage && f->at_end == 2 && step > done && step < next)
            next = step;
    }
    return next;
}

/* ---------------------------------------------------------------- world per stage */

static SimWorld *world_from_state(Run *run, int stage, const char *path)
{
    const Scene *scene = run->scene;
    SimWorldDef def = scene_world_def(scene, stage);
    SimWorld *world = sim_world_load(path, &def, &run->error);
    if (!world && run->error.status == SIM_ERROR_IO)
        snprintf(run->message, sizeof run->message, "%s: cannot load checkpoint %s: %s",
                 scene_where_field(scene, stage, "grains"), path, run->error.message);
    else if (!world)
        snprintf(run->message, sizeof run->message, "%s: checkpoint %s: %s",
                 scene_where_field(scene, stage, run->error.field), path, run->error.message);
    else if (sim_world_restore_contacts(world, path, &run->error) != SIM_OK) {
        /* springs and rolling torques as they were at the save */
        snprintf(run->message, sizeof run->message, "%s: checkpoint %s: %s",
                 scene_where_field(scene, stage, "grains"), path, run->error.message);
        sim_world_destroy(world);
        world = NULL;
    }
    return world;
}

/* 1 when a family needs stage k to re-create its world. */
static int family_restart(const Run *run, int k)
{
    for (int f = 0; app_experiments[f]; ++f)
        if (run->scene->experiments[f] && app_experiments[f]->restart &&
            app_experiments[f]->restart(run->scene->experiments[f], k))
            return 1;
    return 0;
}

/* The families' hooks of one kind, in registry order; the first failure stops (-1, message). */
typedef enum FamilyHook {
    HOOK_BEGIN,
    HOOK_STAGE_EDIT,
    HOOK_STAGE_BEGIN,
    HOOK_STAGE_END,
} FamilyHook;

static int family_hooks(Run *run, FamilyHook which)
{
    run->context.world = run->world;
    for (int f = 0; app_experiments[f]; ++f) {
        const AppExperiment *e = app_experiments[f];
        void *state = run->scene->experiments[f];
        int (*hook)(void *, AppContext *) = which == HOOK_BEGIN         ? e->begin
                                            : which == HOOK_STAGE_EDIT  ? e->stage_edit
                                            : which == HOOK_STAGE_BEGIN ? e->stage_begin
                                                                        : e->stage_end;
        if (state && hook && hook(state, &run->context) != 0)
            return -1;
    }
    return 0;
}

static long family_next_step(const Run *run, long done, long next)
{
    for (int f = 0; app_experiments[f]; ++f)
        if (run->scene->experiments[f] && app_experiments[f]->next_step)
            next = app_experiments[f]->next_step(run->scene->experiments[f], &run->context, done,
                                                 next);
    return next;
}

static void family_step(Run *run, long done)
{
    for (int f = 0; app_experiments[f]; ++f)
        if (run->scene->experiments[f] && app_experiments[f]->step)
            app_experiments[f]->step(run->scene->experiments[f], &run->context, done);
}

/* The families' stop criteria at step `done` (AppExperiment.stage_done): 1 when one ends the
 * stage here, -1 when one failed (message in run->message), else 0. */
static int family_done(Run *run, long done)
{
    run->context.world = run->world;
    for (int f = 0; app_experiments[f]; ++f) {
        const AppExperiment *e = app_experiments[f];
        int r = run->scene->experiments[f] && e->stage_done
                    ? e->stage_done(run->scene->experiments[f], &run->context, done)
                    : 0;
        if (r != 0)
            return r < 0 ? -1 : 1;
    }
    return 0;
}

static int stage_world(Run *run, int k)
{
    const Scene *scene = run->scene;
    const SceneStage *stage = &scene->stages[k];
    if (stage->load == SCENE_LOAD_PREVIOUS && run->world &&
        scene->stages[k - 1].time_step == stage->time_step &&
        scene->stages[k - 1].effects == stage->effects && !family_restart(run, k))
        return 0; /* continue in memory: contact history and exact state kept */
    SimWorld *world = NULL;
    if (stage->load == SCENE_LOAD_SCENE) {
        SimWorldDef def = scene_world_def(scene, k);
        world = sim_world_create(&def, &run->error);
        if (!world)
            snprintf(run->message, sizeof run->message, "%s: %s",
                     scene_where_field(scene, k, run->error.field), run->error.message);
    } else {
        char path[PATH_SIZE];
        if (stage->load == SCENE_LOAD_PREVIOUS)
            out_path(run, path, scene->stages[k - 1].name, ".state");
        else
            snprintf(path, sizeof path, "%s", stage->load_path);
        world = world_from_state(run, k, path);
    }
    if (!world)
        return -1;
    if (run->world)
        sim_world_destroy(run->world);
    run->world = world;
    apply_threads(run, 1); /* same bits for any count */
    return 0;
}

/* The stage's gravity and motions (docs/scenes.md, stages): a motion the stage enables starts
 * its clock now (at t = 0 when it runs from the first stage), or, stopped in an earlier stage,
 * continues it from where it stopped (its pose is continuous); `restart_motions` starts it from
 * 0 again. One it stops holds its pose. The schedules are set again on every stage's world,
 * fresh or continued. */
static void stage_forcing(Run *run, int k)
{
    const SceneStage *stage = &run->scene->stages[k];
    sim_world_set_gravity(run->world, stage->gravity_x, stage->gravity_y);
    if (!stage->declares_motions)
        return; /* motions run on world time, as defined */
    const double now = sim_world_time(run->world);
    for (int m = 0; m < run->scene->def.motion_count; ++m) {
        const int enabled = (stage->motions >> m) & 1u;
        const int restart = (stage->restart_motions >> m) & 1u;
        if (enabled && (restart || !run->motion_running[m])) {
            /* the clock it held when it stopped (never started, or restarted: 0) */
            const double held = !restart && isfinite(run->motion_on[m])
                                    ? run->motion_off[m] - run->motion_on[m]
                                    : 0.0;
            run->motion_on[m] = now - held;
            run->motion_off[m] = (double)INFINITY;
        } else if (!enabled && run->motion_running[m]) {
            run->motion_off[m] = now;
        }
        run->motion_running[m] = enabled;
        sim_world_set_motion(run->world, m, run->motion_on[m], run->motion_off[m]);
    }
}

static int id_order(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

/* The stage's remove_ids must each name a grain of the world as the stage starts (the ids of
 * rained grains are known only then): 0, or -1 with the first missing id in run->message. */
static int check_remove_ids(Run *run, const SceneStage *stage)
{
    SimFrame f;
    sim_world_frame(run->world, &f);
    uint32_t *ids = malloc((size_t)(f.count > 0 ? f.count : 1) * sizeof *ids);
    if (!ids) {
        snprintf(run->message, sizeof run->message, "out of memory");
        return -1;
    }
    memcpy(ids, f.id, (size_t)f.count * sizeof *ids);
    qsort(ids, (size_t)f.count, sizeof *ids, id_order);
    int missing = 0;
    uint32_t first = 0;
    for (int j = 0; j < stage->remove_count; ++j)
        if (!bsearch(&stage->remove_ids[j], ids, (size_t)f.count, sizeof *ids, id_order)) {
            if (missing++ == 0)
                first = stage->remove_ids[j];
        }
    free(ids);
    if (missing == 0)
        return 0;
    snprintf(run->message, sizeof run->message,
             "stage %s: remove_ids: %d of its %d ids name no grain of the world (first: %u; the "
             "world holds %d grains)",
             stage->name, missing, stage->remove_count, first, f.count);
    return -1;
}

/* The families' edits (a crater dig, ...) and the stage's explicit removals, at its start. */
static int stage_edit(Run *run, int k)
{
    const SceneStage *stage = &run->scene->stages[k];
    StageReport *report = &run->stages[k];
    run->context.removed = 0;
    if (family_hooks(run, HOOK_STAGE_EDIT) != 0)
        return -1;
    report->removed += run->context.removed;
    if (stage->remove_count > 0) {
        if (check_remove_ids(run, stage) != 0)
            return -1;
        report->removed += sim_world_remove_ids(run->world, stage->remove_ids, stage->remove_count);
    }
    /* the stage's listed grains, placed after its removals (app/scene/stage_adds.c) */
    if (scene_stage_add(run->scene, k, run->world, run->message, sizeof run->message) != 0)
        return -1;
    report->at_start = report->removed;
    for (int s = 0; s < SIM_MAX_SINKS; ++s) /* the sinks' counters as the stage starts */
        report->sinks[s] = sim_world_removed_count(run->world, s);
    return 0;
}

static void progress(Run *run, int k, double elapsed, double duration, double rate, int final)
{
    const SceneStage *stage = &run->scene->stages[k];
    if (final) {
        const StageReport *r = &run->stages[k];
        if (run->progress_tty)
            fputs("\r\033[K", stderr);
        char u[32]; /* simulated time in its units; the scene's own, unnamed: "time units" */
        if (!scene_unit_after(run->scene, SCENE_TIME, u, sizeof u)[0])
            snprintf(u, sizeof u, " time units");
        fprintf(stderr,
                "sablier: stage %s: %.4g%s simulated (t = %.4g%s) in %.3g s, %ld steps, %d "
                "mobile grains%s%s\n",
                stage->name, r->end_time - r->start_time, u, r->end_time, u, r->wall_seconds,
                r->steps, r->mobile, r->settled ? ", settled" : "",
                r->at_start ? ", grains removed at start" : "");
        return;
    }
    if (!(run->progress_every > 0.0))
        return;
    double left = duration > elapsed && rate > 0.0 ? (duration - elapsed) / rate : 0.0;
    double encode = 0.0;
    const AppRender *render = run->options->render;
    if (stage->movie && render && render->movie_encode_left) { /* encoding runs alongside */
        long to_come = (long)fmax(0.0, (duration - elapsed) / scene_frame_interval(run->scene, k));
        encode = render->movie_encode_left(render->context, to_come);
        left = fmax(left, encode);
    }
    if (run->progress_tty)
        fprintf(stderr, "\r\033[Ksablier: %s  t = %.3f / %.3f s  %.3g steps/s  ETA %.0f s",
                stage->name, elapsed, duration, rate / sim_world_time_step(run->world), left);
    else /* a log: one whole line each time, the stage's number and the rate in both units */
        fprintf(stderr,
                "sablier: progress: stage %s (%d/%d)  t = %.4g / %.4g s  %.3g steps/s, %.3g s "
                "simulated per s  ETA %.0f s",
                stage->name, k + 1, run->scene->stage_count, elapsed, duration,
                rate / sim_world_time_step(run->world), rate, left);
    if (encode > 0.0) /* the movie encoder's share: what it still owes */
        fprintf(stderr, " (movie encoding %.0f s)", encode);
    if (!run->progress_tty)
        fputc('\n', stderr);
    fflush(stderr);
}

static void unstable_message(Run *run, int k)
{
    const SceneStage *stage = &run->scene->stages[k];
    char path[PATH_SIZE];
    out_path(run, path, stage->name, ".last_good.state");
    SimError save_error;
    int saved = !run->options->bare && app_state_save(run->world, path, &save_error) == 0;
    SimTiming timing = sim_world_timing(run->world);
    const char *cause =
        timing.steps_per_contact < 20.0
            ? "the time step is too large for the contacts (fewer than 20 steps per contact): "
              "lower time.dt"
            : "a contact blew up (overlap or speed beyond the guard): check k_n against the "
              "loads, the damping, and overlaps at the start";
    /* sim's message may already name the cause */
    int named = strstr(run->error.message, "likely cause") != NULL;
    /* the world is back at its last good check: the failure's own time is error.step's */
    const double t_fail =
        sim_world_time(run->world) + (double)(run->error.step - sim_world_step_count(run->world)) *
                                         sim_world_time_step(run->world);
    snprintf(run->message, sizeof run->message,
             "stage %s: simulation failed at step %ld (t = %.6g s), grain %ld: %s%s%s "
             "(dt = %g s, %.1f steps per contact); last good state %s %s",
             stage->name, run->error.step,
             run->error.step >= 0 ? t_fail : sim_world_time(run->world), run->error.grain,
             run->error.message, named ? "" : "; likely cause: ", named ? "" : cause,
             timing.time_step, timing.steps_per_contact,
             saved                ? "saved to"
             : run->options->bare ? "not saved (a bare run writes no file), as"
                                  : "could not be saved to",
             path);
}

/* The stage's cadences, in steps from its start: chunks of sim_world_step end on output times. */
typedef struct StageClock {
    double dt; /* s */
    long total, every_energy, every_frame, every_trace, every_dump;
    long every_checkpoint; /* periodic checkpoints (output.checkpoint_every); total: none */
    int movie;             /* 1: a movie is open (sink) */
    SimFrameSink sink;
    AppDump *dump; /* NULL: no per-grain dump declared for the stage */
} StageClock;

/* A cadence of `steps` (a number of steps, maybe huge or not finite) as a count in [1, 1e15]:
 * at least every step, at most once in any stage (a stage has at most SCENE_MAX_STEPS), never
 * an overflowed conversion (energy_every = 1e308 means the first and last rows only). */
static long cadence_steps(double steps)
{
    if (!(steps >= 1.0))
        return 1;
    return steps < 1e15 ? (long)llround(steps) : (long)1e15;
}

static int stage_clock(Run *run, int k, StageClock *clock);

/* World, edits, the families' stage_begin, t*, the start figures and the movie. 0, or the exit
 * status. */
static int stage_start(Run *run, int k, StageClock *clock)
{
    const Scene *scene = run->scene;
    const SceneStage *stage = &scene->stages[k];
    const SceneOutput *out = &scene->output;
    run->context.stage = k;
    if (stage_world(run, k) != 0)
        return 2;
    stage_forcing(run, k);
    app_sources_stage_begin(run->sources, k);
    double dt = sim_world_time_step(run->world);
    run->context.stage_steps = (long)llround(stage->duration / dt);
    if (stage_edit(run, k) != 0)
        return 2;
    run->stages[k].start_time = sim_world_time(run->world);
    run->context.stage_start = run->stages[k].start_time;
    if (family_hooks(run, HOOK_STAGE_BEGIN) != 0)
        return 2;
    /* t* = t / sqrt(D/g) (000 eq. 6.1) */
    double g = hypot(scene->def.gravity_x, scene->def.gravity_y);
    SimFrame frame;
    sim_world_frame(run->world, &frame);
    run->time_scale =
        out->t_star_length > 0.0 && g > 0.0 ? sqrt(out->t_star_length / g) : frame.time_scale;
    if (scene->units_reduced && run->unit_time == 0.0 && g > 0.0) {
        sim_world_means(run->world, &run->unit_length, &run->unit_mass);
        run->unit_time = sqrt(run->unit_length / g);
        const AppRender *render = run->options->render;
        if (render && render->reduced_units) /* colour bars in m g and sqrt(g d) */
            render->reduced_units(render->context, run->unit_mass * g, sqrt(g * run->unit_length));
    }
    if (run->unit_time > 0.0)
        run->time_scale = run->unit_time; /* t* in the run's fixed sqrt(d/g) */
    if (figures_due(run, k, 0, 0, dt) != 0)
        return 2;
    return stage_clock(run, k, clock);
}

/* The stage's cadences, its dump and its movie opened. 0, or the exit status. */
static int stage_clock(Run *run, int k, StageClock *clock)
{
    const Scene *scene = run->scene;
    const SceneStage *stage = &scene->stages[k];
    const SceneOutput *out = &scene->output;
    const AppRender *render = run->options->render;
    const double dt = sim_world_time_step(run->world);
    if ((stage->movie || out->figure_count > 0) && !render && !run->options->render_off &&
        !run->render_warned) {
        fprintf(stderr, "sablier: warning: rendering is not built: figures and movies are "
                        "skipped\n");
        run->render_warned = 1;
    }
    *clock = (StageClock){
        .dt = dt,
        .total = (long)llround(stage->duration / dt), /* <= SCENE_MAX_STEPS (scene_load) */
        .every_energy = cadence_steps(out->energy_every / dt),
        .every_frame = cadence_steps(scene_frame_interval(scene, k) / dt),
        .every_trace = cadence_steps(out->trace_every / dt),
        .movie = stage->movie && render && render->movie_open,
        .every_dump = app_dump_every_steps(&out->dump[k], dt),
        .every_checkpoint = out->checkpoint_every > 0.0 ? cadence_steps(out->checkpoint_every / dt)
                                                        : (long)llround(stage->duration / dt),
    };
    if (app_dump_open(&clock->dump, scene, k, run->options->out_dir, run->message,
                      sizeof run->message) != 0)
        return 2;
    if (clock->movie) {
        char path[PATH_SIZE], err[512] = "";
        out_path(run, path, stage->name, ".mp4");
        if (render->movie_open(render->context, scene, k, path, &clock->sink, err, sizeof err) !=
            0) {
            snprintf(run->message, sizeof run->message, "movie %s: %s", path, err);
            clock->movie = 0;
            return 2;
        }
    }
    return 0;
}

/* What is due at step `done`: energy row, movie frame, trace rows, the families' steps, timed
 * figures. 0, or the exit status. */
static int outputs_due(Run *run, int k, StageClock *clock, long done)
{
    if (app_sources_insert(run->sources, run->world, done, clock->dt, run->message,
                           sizeof run->message) != 0)
        return 2;
    int frame_due = clock->movie && clock->sink.consume && done % clock->every_frame == 0;
    int trace_due = run->trace && done % clock->every_trace == 0;
    int dump_due = clock->dump && done % clock->every_dump == 0;
    if (done % clock->every_energy == 0 || done == clock->total)
        energy_row(run, k);
    if (frame_due || trace_due || dump_due) {
        SimFrame frame;
        sim_world_frame(run->world, &frame);
        if (frame_due && clock->sink.consume(clock->sink.context, &frame) != 0)
            clock->sink.consume = NULL; /* the movie's sticky error is reported at close */
        if (trace_due)
            trace_rows(run, &frame);
        if (dump_due)
            app_dump_frame(clock->dump, &frame);
    }
    family_step(run, done); /* profiles, phase samples, ... */
    if (figures_due(run, k, 2, done, clock->dt) != 0)
        return 2;
    const AppRunOptions *o = run->options;
    if (o->hook && (done % o->hook_every == 0 || done == clock->total) &&
        o->hook(o->hook_context, run->world, k, done) != 0) {
        snprintf(run->message, sizeof run->message,
                 "stopped by the caller's hook in stage %s at "
                 "step %ld",
                 run->scene->stages[k].name, done);
        return 2;
    }
    return 0;
}

/* The next step after `done` at which anything is due. */
static long next_due(const Run *run, int k, const StageClock *clock, long done)
{
    long next = clock->total;
    long marks[6] = {clock->every_energy,
                     clock->movie ? clock->every_frame : clock->total,
                     run->trace ? clock->every_trace : clock->total,
                     clock->dump ? clock->every_dump : clock->total,
                     clock->every_checkpoint,
                     run->options->hook ? run->options->hook_every : clock->total};
    for (int m = 0; m < 6; ++m) {
        long candidate = (done / marks[m] + 1) * marks[m];
        if (candidate < next)
            next = candidate;
    }
    next = next_figure_step(run, k, done, clock->dt, next);
    next = app_sources_next_step(run->sources, done, clock->dt, next);
    return family_next_step(run, done, next);
}

/* 1 when the stage's settle test passes at step `done`: E_kin + E_rot (per mobile grain with
 * kinetic_per_grain_below) below the level at this energy row and at every row of the last
 * `hold` seconds (run->settle_since: the first of them). */
static int settled(Run *run, const SceneStage *stage, const StageClock *clock, long done)
{
    double elapsed = (double)done * clock->dt;
    const int total = stage->settle_kinetic > 0.0;
    const double level = total ? stage->settle_kinetic : stage->settle_per_grain;
    if (!(level > 0.0) || done % clock->every_energy != 0 || done == 0 ||
        elapsed < stage->settle_after - 0.5 * clock->dt)
        return 0;
    SimEnergy e = sim_world_energy(run->world);
    const int mobile = sim_world_mobile_count(run->world);
    const double kinetic = e.kinetic + e.rotational;
    if (!(total ? kinetic < level : kinetic < level * (mobile > 0 ? mobile : 1))) {
        run->settle_since = -1.0;
        return 0;
    }
    if (run->settle_since < 0.0)
        run->settle_since = elapsed;
    return elapsed - run->settle_since >= stage->settle_hold - 0.5 * clock->dt;
}

/* ---------------------------------------------------------------- checkpoints and resume */

#define CHECKPOINT_NAME "checkpoint.txt" /* the newest checkpoint's record (docs/cli.md) */

/* 1 when a periodic checkpoint is due at step `done` (simulated or wall-clock cadence). */
static int checkpoint_due(Run *run, const StageClock *clock, long done)
{
    const double minutes = run->scene->output.checkpoint_minutes;
    if (done <= 0 || done >= clock->total || run->options->bare)
        return 0;
    if (done % clock->every_checkpoint == 0)
        return 1;
    return minutes > 0.0 &&
           sim_clock_seconds(SIM_CLOCK_WALL) - run->checkpoint_wall >= 60.0 * minutes;
}

/* The record of a checkpoint at step `done` of stage k: what the run needs to continue from its
 * state file exactly (the run's totals and scales, the motions' clocks, the stages' reports, the
 * lengths of energy.csv and trace.csv), doubles in hexadecimal so that they come back to the
 * bit. */
static size_t checkpoint_record(const Run *run, int k, long done, const char *state, char *text,
                                size_t size, int interrupted)
{
    /* the run's steps before this stage (an interrupted stage's loop added its own already) */
    const long steps = interrupted ? run->steps - run->stages[k].steps : run->steps;
    size_t n = (size_t)snprintf(
        text, size,
        "sablier-checkpoint 1\nscene_sha256 %s\nstarted %lld\nstage %d\ndone %ld\nstate %s\n"
        "energy_bytes %ld\ntrace_bytes %ld\nscales %a %a %a %a\ntotals %ld %a %a %a %a %ld\n"
        "settle %a\n",
        run->scene->sha256, run->started, k, done, state, app_checkpoint_bytes(run->energy),
        app_checkpoint_bytes(run->trace), run->time_scale, run->unit_length, run->unit_mass,
        run->unit_time, steps, run->simulated, run->particle_steps, run->step_seconds,
        run->contacts_sum, run->contacts_samples, run->settle_since);
    for (int m = 0; m < SIM_MAX_MOTIONS && n < size; ++m)
        n += (size_t)snprintf(text + n, size - n, "motion %d %d %a %a\n", m, run->motion_running[m],
                              run->motion_on[m], run->motion_off[m]);
    for (int j = 0; j <= k && n < size; ++j) {
        const StageReport *r = &run->stages[j];
        n += (size_t)snprintf(text + n, size - n, "report %d %ld %a %a %a %d %d %d %d", j, r->steps,
                              r->start_time, r->end_time, r->wall_seconds, r->settled, r->removed,
                              r->at_start, r->mobile);
        for (int q = 0; q < SIM_MAX_SINKS && n < size; ++q)
            n += (size_t)snprintf(text + n, size - n, " %ld", r->sinks[q]);
        if (n < size)
            n += (size_t)snprintf(text + n, size - n, "\n");
    }
    if (n < size)
        app_sources_checkpoint(run->sources, text + n, size - n);
    return n < size ? n + strlen(text + n) : n;
}

/* The sections of a record after the runner's own lines (app/base/checkpoint.h): the stage's dump,
 * then each family's, in registry order. 0, or -1 (a family's message in run->message). */
static int checkpoint_sections(Run *run, const AppDump *dump, FILE *f)
{
    if (dump) {
        fputs("begin dump\n", f);
        app_dump_checkpoint(dump, f);
        fputs("end dump\n", f);
    }
    run->context.world = run->world;
    for (int m = 0; app_experiments[m]; ++m) {
        const AppExperiment *e = app_experiments[m];
        void *state = run->scene->experiments[m];
        if (!state || !e->checkpoint)
            continue;
        fprintf(f, "begin %s\n", e->name);
        if (e->checkpoint(state, &run->context, f) != 0)
            return -1;
        fprintf(f, "end %s\n", e->name);
    }
    return 0;
}

/* A checkpoint at step `done` of stage k: the world's state (DIR/STAGE.checkpoint.state; an
 * interrupted stage's DIR/STAGE.interrupted.state is written by stage_finish) and its record
 * DIR/checkpoint.txt, with the sections of the stage's dump and of the families, in one file
 * renamed into place. 0, or -1 with the message. */
static int checkpoint_write(Run *run, int k, long done, int interrupted, const AppDump *dump)
{
    const SceneStage *stage = &run->scene->stages[k];
    char name[SCENE_NAME_MAX + 32], path[PATH_SIZE];
    snprintf(name, sizeof name, "%s%s", stage->name,
             interrupted ? ".interrupted.state" : ".checkpoint.state");
    out_path(run, path, name, "");
    if (!interrupted && app_state_save(run->world, path, &run->error) != 0) {
        snprintf(run->message, sizeof run->message, "checkpoint %s: %s", path, run->error.message);
        return -1;
    }
    size_t size = 4096 + 400 * (size_t)SCENE_MAX_STAGES;
    char *text = malloc(size);
    int rc = -1, family_failed = 0;
    FILE *f = NULL;
    out_path(run, path, CHECKPOINT_NAME, "");
    if (text && checkpoint_record(run, k, done, name, text, size, interrupted) < size)
        f = app_tmp_open(path, NULL);
    if (f) {
        fputs(text, f);
        family_failed = checkpoint_sections(run, dump, f) != 0;
        if (family_failed)
            app_tmp_discard(&f, path);
        else
            rc = app_tmp_commit(&f, path);
    }
    free(text);
    if (rc != 0 && !family_failed)
        snprintf(run->message, sizeof run->message, "cannot write %s/%s: %s", run->options->out_dir,
                 CHECKPOINT_NAME, strerror(errno));
    run->checkpoint_wall = sim_clock_seconds(SIM_CLOCK_WALL);
    return rc;
}

/* One `report` line of a record into run->stages. 0, or -1. */
static int resume_report(Run *run, const char *line)
{
    int j, used = 0;
    StageReport r;
    memset(&r, 0, sizeof r);
    if (sscanf(line, "report %d %ld %la %la %la %d %d %d %d%n", &j, &r.steps, &r.start_time,
               &r.end_time, &r.wall_seconds, &r.settled, &r.removed, &r.at_start, &r.mobile,
               &used) != 9 ||
        j < 0 || j >= SCENE_MAX_STAGES)
        return -1;
    for (int q = 0; q < SIM_MAX_SINKS; ++q) {
        int more = 0;
        if (sscanf(line + used, " %ld%n", &r.sinks[q], &more) != 1)
            return -1;
        used += more;
    }
    run->stages[j] = r;
    return 0;
}

/* One line of a record. 0, or -1 when it is malformed. */
static int resume_line(Run *run, const char *line, char *sha, int *seen)
{
    int m, running;
    double on, off;
    if (sscanf(line, "scene_sha256 %64s", sha) == 1 ||
        sscanf(line, "started %lld", &run->started) == 1 ||
        sscanf(line, "energy_bytes %ld", &run->energy_bytes) == 1 ||
        sscanf(line, "trace_bytes %ld", &run->trace_bytes) == 1 ||
        strcmp(line, "sablier-checkpoint 1\n") == 0)
        return 0;
    if (sscanf(line, "stage %d", &run->resume_stage) == 1 ||
        sscanf(line, "done %ld", &run->resume_done) == 1) {
        *seen |= line[0] == 's' ? 1 : 2;
        return 0;
    }
    if (strncmp(line, "state ", 6) == 0) {
        char name[160]; /* %159s: the buffer must hold 159 characters and the NUL */
        if (sscanf(line, "state %159s", name) != 1 || strchr(name, '/'))
            return -1;
        out_path(run, run->resume_state, name, "");
        *seen |= 4;
        return 0;
    }
    if (sscanf(line, "scales %la %la %la %la", &run->time_scale, &run->unit_length, &run->unit_mass,
               &run->unit_time) == 4)
        return 0;
    if (sscanf(line, "totals %ld %la %la %la %la %ld", &run->steps, &run->simulated,
               &run->particle_steps, &run->step_seconds, &run->contacts_sum,
               &run->contacts_samples) == 6)
        return 0;
    if (sscanf(line, "settle %la", &run->settle_since) == 1)
        return 0;
    if (sscanf(line, "motion %d %d %la %la", &m, &running, &on, &off) == 4) {
        if (m < 0 || m >= SIM_MAX_MOTIONS)
            return -1;
        run->motion_running[m] = running;
        run->motion_on[m] = on;
        run->motion_off[m] = off;
        return 0;
    }
    if (strncmp(line, "source ", 7) == 0)
        return 0; /* resume_sources, once the sources exist */
    return strncmp(line, "report ", 7) == 0 ? resume_report(run, line) : -1;
}

/* The next line of a record outside its sections, from *at, into line[size] (with its newline):
 * 1, 0 at the end, or -1 (a line too long, a section without its end). */
static int record_next(const char **at, char *line, size_t size)
{
    while (**at) {
        const char *p = *at, *newline = strchr(p, '\n');
        size_t n = newline ? (size_t)(newline - p) + 1 : strlen(p);
        *at = p + n;
        if (strncmp(p, "begin ", 6) == 0) { /* a section (its owner reads it): to its end */
            char end[SCENE_NAME_MAX + 16];
            snprintf(end, sizeof end, "\nend %.*s", (int)(n - 6), p + 6);
            const char *e = newline ? strstr(newline, end) : NULL;
            if (!e || n - 6 > SCENE_NAME_MAX)
                return -1;
            *at = e + strlen(end);
            continue;
        }
        if (n >= size)
            return -1;
        memcpy(line, p, n);
        line[n] = '\0';
        return 1;
    }
    return 0;
}

/* The lines of section `name` of a record (malloc'd), or NULL when it has none. */
static char *record_section(const char *record, const char *name)
{
    char begin[SCENE_NAME_MAX + 16], end[SCENE_NAME_MAX + 16];
    snprintf(begin, sizeof begin, "\nbegin %s\n", name);
    snprintf(end, sizeof end, "\nend %s\n", name);
    const char *b = record ? strstr(record, begin) : NULL;
    const char *e = b ? strstr(b + strlen(begin) - 1, end) : NULL;
    if (!e)
        return NULL;
    const char *from = b + strlen(begin);
    size_t n = e + 1 > from ? (size_t)(e + 1 - from) : 0;
    char *text = malloc(n + 1);
    if (text) {
        memcpy(text, from, n);
        text[n] = '\0';
    }
    return text;
}

/* --resume: the newest checkpoint's record read, and checked against this scene. 0, or -1 with
 * a message on stderr (exit status 2). */
static int resume_read(Run *run)
{
    const char *dir = run->options->out_dir;
    char path[PATH_SIZE], line[1024] = "", sha[80] = "";
    out_path(run, path, CHECKPOINT_NAME, "");
    run->resume_record = app_checkpoint_read(path);
    if (!run->resume_record) {
        fprintf(stderr, "sablier: --resume: no checkpoint in %s (%s: %s)\n", dir, path,
                strerror(errno));
        return -1;
    }
    int seen = 0, bad = 0, more;
    const char *at = run->resume_record;
    while (!bad && (more = record_next(&at, line, sizeof line)) != 0)
        bad = more < 0 || resume_line(run, line, sha, &seen) != 0;
    if (!bad && sha[0] && strcmp(sha, run->scene->sha256) != 0) {
        fprintf(stderr,
                "sablier: --resume: the checkpoint in %s was written by another scene file "
                "(SHA-256 %s, %s has %s)\n",
                dir, sha, run->scene->path, run->scene->sha256);
        return -1;
    }
    if (bad || seen != 7 || !sha[0] || run->resume_stage < 0 ||
        run->resume_stage >= run->scene->stage_count || run->resume_done < 0) {
        fprintf(stderr, "sablier: --resume: %s is malformed%s%s\n", path, bad ? " at: " : "",
                bad ? line : "");
        return -1;
    }
    return 0;
}

/* --resume: the sources' state from the checkpoint's record (after app_sources_create). 0, or
 * -1 with the message. */
static int resume_sources(Run *run)
{
    char path[PATH_SIZE], line[1024];
    out_path(run, path, CHECKPOINT_NAME, "");
    const char *at = run->resume_record;
    int bad = 0;
    while (!bad && record_next(&at, line, sizeof line) > 0)
        bad = strncmp(line, "source ", 7) == 0 && app_sources_restore(run->sources, line) != 0;
    if (bad)
        snprintf(run->message, sizeof run->message, "--resume: %s: bad source state", path);
    return bad ? -1 : 0;
}

/* The scene as resolved (--set overrides applied) must be the one the checkpoint's run ran. */
static int resume_same_scene(const Run *run)
{
    char path[PATH_SIZE];
    out_path(run, path, RESOLVED_NAME, "");
    FILE *f = sim_open_input(path, NULL);
    const char *want = run->scene->resolved ? run->scene->resolved : "";
    size_t length = strlen(want);
    char *text = malloc(length + 2);
    size_t got = f && text ? fread(text, 1, length + 1, f) : 0;
    int same = f && text && got == length && memcmp(text, want, length) == 0;
    if (f)
        fclose(f);
    free(text);
    if (!same)
        fprintf(stderr,
                "sablier: --resume: the scene differs from the one the checkpoint's run ran "
                "(%s: other --set values or includes)\n",
                path);
    return same ? 0 : -1;
}

/* A servo found flipping between its caps in the steps since time `before` (sim.h SimWallLoad
 * servo_flips: the first run longer than SIM_SERVO_FLIP_STEPS, found once per run and saved in
 * checkpoints, so a resumed run does not tell it again), told on stderr. */
static void servo_flip_report(const Run *run, int stage, double before)
{
    const Scene *scene = run->scene;
    const int walls = scene->def.wall_count;
    for (int b = 0; b < walls + scene->def.grain_body_count; ++b) {
        SimWallLoad l;
        if (sim_world_wall_load(run->world, b, &l) != 0 || !(l.servo_flip_time > before))
            continue;
        char who[SCENE_NAME_MAX + 16];
        if (b < walls)
            snprintf(who, sizeof who, "wall %d", b);
        else
            snprintf(who, sizeof who, "body %s", scene->body_names[b - walls]);
        fprintf(stderr,
                "sablier: warning: %s's servo flips its speed between +max_speed and -max_speed "
                "every step since t = %.9g s (stage %s; more than %d steps in a row): its load "
                "alternates between two values, so rows taken an even number of steps apart "
                "(walls.csv, summary.json's walls mean, which counts them as servo_flips) catch "
                "one of them; docs/scenes.md \"Damping bound\"\n",
                who, l.servo_flip_time, scene->stages[stage].name, SIM_SERVO_FLIP_STEPS);
    }
}

/* Steps the stage in chunks that end on output times, until its end, the settle test or a
 * family's stop criterion (AppExperiment.stage_done), from step `done` (resumed: a checkpoint's,
 * whose outputs were written). 0, or the exit status. */
static int stage_loop(Run *run, int k, StageClock *clock, long done, int resumed)
{
    const SceneStage *stage = &run->scene->stages[k];
    StageReport *report = &run->stages[k];
    int status = 0;
    double step_wall = 0.0;
    for (;; resumed = 0) {
        if (!resumed && ((status = outputs_due(run, k, clock, done)) != 0 || done >= clock->total))
            break;
        if (!resumed && settled(run, stage, clock, done)) {
            report->settled = 1;
            break;
        }
        int family_stop = resumed ? 0 : family_done(run, done);
        if (family_stop != 0) {
            status = family_stop < 0 ? 2 : 0;
            break;
        }
        /* A periodic checkpoint due here is written before a signal is heeded: a run resumed
         * from this step writes no outputs for it, so the periodic one would be missing. */
        if (!resumed && checkpoint_due(run, clock, done) &&
            checkpoint_write(run, k, done, 0, clock->dump) != 0) {
            status = 2;
            break;
        }
        if (!run->options->bare && app_run_signal()) { /* bare: catches none */
            status = APP_EXIT_SIGNAL + app_run_signal();
            break;
        }
        long next = next_due(run, k, clock, done);
        if (next - done > SIGNAL_CHECK_STEPS)
            next = done + SIGNAL_CHECK_STEPS;
        apply_threads(run, 0); /* APP_THREADS_AUTO follows the rates and the grains */
        next = done + app_threads_chunk(&run->threads, next - done);
        const double before = sim_world_time(run->world);
        double t0 = sim_clock_seconds(SIM_CLOCK_WALL);
        SimStatus s = sim_world_step(run->world, next - done, &run->error);
        double t1 = sim_clock_seconds(SIM_CLOCK_WALL);
        servo_flip_report(run, k, before);
        step_wall += t1 - t0;
        const int mobile = sim_world_mobile_count(run->world);
        app_threads_done(&run->threads, next - done, mobile,
                         app_threads_work(mobile, sim_world_list_entries(run->world)), t1 - t0);
        run->particle_steps += (double)mobile * (double)(next - done);
        report->steps += next - done;
        done = next;
        if (s != SIM_OK) {
            unstable_message(run, k);
            status = s == SIM_ERROR_UNSTABLE ? 1 : 2;
            break;
        }
        if (run->progress_every > 0.0 && t1 - run->last_progress >= run->progress_every) {
            progress(run, k, (double)done * clock->dt, stage->duration,
                     (double)done * clock->dt / step_wall, 0);
            run->last_progress = t1;
        }
    }
    run->step_seconds += step_wall;
    run->steps += report->steps;
    return status;
}

/* The movie closed, the checkpoint written, the families' stage_end and the end figures. */
static int stage_finish(Run *run, int k, StageClock *clock, int status)
{
    const SceneStage *stage = &run->scene->stages[k];
    const AppRender *render = run->options->render;
    StageReport *report = &run->stages[k];
    char path[PATH_SIZE];
    out_path(run, path, stage->name, ".interrupted.state");
    if (status > APP_EXIT_SIGNAL) { /* the checkpoint first: the dump, the families and the
                                       report as the loop left them */
        report->end_time = sim_world_time(run->world);
        if (app_state_save(run->world, path, &run->error) != 0) {
            snprintf(run->message, sizeof run->message, "checkpoint %s: %s", path,
                     run->error.message);
            status = 2;
        } else if (checkpoint_write(run, k, report->steps, 1, clock->dump) != 0) {
            status = 2;
        } else {
            run->context.checkpointed = 1; /* the families commit what they appended */
        }
    }
    report->end_time = sim_world_time(run->world);
    report->mobile = sim_world_mobile_count(run->world);
    for (int s = 0; s < SIM_MAX_SINKS; ++s) { /* grains that left through each sink */
        report->sinks[s] = sim_world_removed_count(run->world, s) - report->sinks[s];
        report->removed += (int)report->sinks[s];
    }
    run->simulated += report->end_time - report->start_time;
    if (clock->movie) {
        char err[512] = "";
        if (render->movie_close(render->context, err, sizeof err) != 0 && status == 0) {
            snprintf(run->message, sizeof run->message, "movie of stage %s: %s", stage->name, err);
            status = 2;
        }
    }
    int interrupted = status > APP_EXIT_SIGNAL; /* an interrupted stage keeps its frames */
    if (app_dump_close(&clock->dump, run->world, status == 0 || interrupted, run->message,
                       sizeof run->message) != 0 &&
        (status == 0 || interrupted))
        status = 2;
    if (status > APP_EXIT_SIGNAL) {
        snprintf(run->message, sizeof run->message,
                 "interrupted by %s in stage %s at t = %.9g s; its state is saved to %s",
                 status == APP_EXIT_SIGNAL + SIGINT ? "SIGINT" : "SIGTERM", stage->name,
                 report->end_time, path);
        return status;
    }
    if (status != 0)
        return status;
    out_path(run, path, stage->name, ".state");
    if (!run->options->bare && app_state_save(run->world, path, &run->error) != 0) {
        snprintf(run->message, sizeof run->message, "checkpoint %s: %s", path, run->error.message);
        return 2;
    }
    if (k == run->resume_stage && strstr(run->resume_state, ".interrupted.state"))
        remove(run->resume_state); /* the interrupted stage is complete now */
    if (family_hooks(run, HOOK_STAGE_END) != 0 || figures_due(run, k, 1, 0, clock->dt) != 0)
        return 2;
    return 0;
}

/* --resume: the stage's dump and every family continue from their sections of the record (the
 * dump just opened, the families' files opened by begin). 0, or 2 with the message. */
static int resume_sections(Run *run, StageClock *clock)
{
    int rc = 0;
    char *section = NULL;
    if (clock->dump) {
        section = record_section(run->resume_record, "dump");
        rc =
            app_dump_resume(clock->dump, section ? section : "", run->message, sizeof run->message);
        free(section);
    }
    run->context.world = run->world;
    for (int f = 0; rc == 0 && app_experiments[f]; ++f) {
        const AppExperiment *e = app_experiments[f];
        void *state = run->scene->experiments[f];
        if (!state || !e->resume)
            continue;
        section = record_section(run->resume_record, e->name);
        rc = e->resume(state, &run->context, section ? section : "");
        free(section);
    }
    return rc != 0 ? 2 : 0;
}

/* The world of a resumed stage k from the checkpoint's state, with the stage's gravity and the
 * motions' clocks of the record. 0, or -1 with the message. */
static int resume_world(Run *run, int k)
{
    const Scene *scene = run->scene;
    SimWorld *world = world_from_state(run, k, run->resume_state);
    if (!world)
        return -1;
    if (run->world)
        sim_world_destroy(run->world);
    run->world = world;
    run->context.world = world;
    apply_threads(run, 1);
    const SceneStage *stage = &scene->stages[k];
    sim_world_set_gravity(world, stage->gravity_x, stage->gravity_y);
    int motions_declared = 0;
    for (int j = 0; j <= k; ++j)
        motions_declared |= scene->stages[j].declares_motions;
    for (int m = 0; motions_declared && m < scene->def.motion_count; ++m)
        sim_world_set_motion(world, m, run->motion_on[m], run->motion_off[m]);
    return 0;
}

/* The stage a checkpoint interrupted, continued from its state: no edits, no stage_begin hooks,
 * no start figures (they ran before the checkpoint); the dump and the families continue from the
 * record; the movie starts again at the checkpoint's frame. A family that shapes the world's
 * definition (adjust_def: a motion's phase) does so from its restored state, so the world is
 * loaded again after the resume hooks when one does. 0, or the exit status. */
static int stage_resume(Run *run, int k, StageClock *clock)
{
    const SceneStage *stage = &run->scene->stages[k];
    run->context.stage = k;
    if (resume_world(run, k) != 0)
        return 2;
    run->context.stage_steps = (long)llround(stage->duration / sim_world_time_step(run->world));
    run->context.stage_start = run->stages[k].start_time;
    int status = stage_clock(run, k, clock);
    if (status == 0)
        status = resume_sections(run, clock);
    int shaped = 0;
    for (int f = 0; app_experiments[f]; ++f)
        shaped |= run->scene->experiments[f] && app_experiments[f]->adjust_def;
    if (status == 0 && shaped && resume_world(run, k) != 0)
        status = 2;
    return status;
}

static int run_stage(Run *run, int k)
{
    double wall_start = sim_clock_seconds(SIM_CLOCK_WALL);
    StageClock clock;
    memset(&clock, 0, sizeof clock);
    const int resumed = k == run->resume_stage && run->resume_state[0];
    if (!resumed)
        run->settle_since = -1.0;
    int status = resumed ? stage_resume(run, k, &clock) : stage_start(run, k, &clock);
    if (status != 0) {
        app_dump_close(&clock.dump, NULL, 0, NULL, 0); /* no half dump */
        return status;
    }
    status = stage_finish(run, k, &clock,
                          stage_loop(run, k, &clock, resumed ? run->resume_done : 0, resumed));
    run->stages[k].wall_seconds = sim_clock_seconds(SIM_CLOCK_WALL) - wall_start;
    if (status != 0)
        return status;
    if (!run->options->bare)
        progress(run, k, 0.0, 0.0, 0.0, 1);
    return 0;
}

/* Every family's end hook (files closed, results written), then its summary.json members. A
 * failure is reported when the run had none. */
static void families_end(Run *run)
{
    char err[512] = "";
    run->context.world = run->world;
    run->context.err = err;
    run->context.err_size = sizeof err;
    size_t used = 0;
    for (int f = 0; app_experiments[f]; ++f) {
        const AppExperiment *e = app_experiments[f];
        void *state = run->scene->experiments[f];
        if (!state)
            continue;
        err[0] = '\0';
        if (e->end && e->end(state, &run->context, run->status == 0) != 0 && run->status == 0) {
            snprintf(run->message, sizeof run->message, "%s", err);
            run->status = 2;
        }
        if (e->summary_json && used < sizeof run->observed) {
            e->summary_json(state, run->observed + used, sizeof run->observed - used);
            used += strlen(run->observed + used);
        }
    }
    run->context.err = run->message;
    run->context.err_size = sizeof run->message;
}

/* After a successful run: each family's figures drawn from the run's files. */
static void families_figures(Run *run)
{
    for (int f = 0; run->status == 0 && app_experiments[f]; ++f) {
        const AppExperiment *e = app_experiments[f];
        void *state = run->scene->experiments[f];
        if (state && e->figures && e->figures(state, &run->context) != 0) {
            char text[sizeof run->message];
            snprintf(text, sizeof text, "%s", run->message);
            snprintf(run->message, sizeof run->message, "figures: %.*s",
                     (int)(sizeof run->message - 16), text);
            run->status = 2;
        }
    }
}

/* --resume continues what the runner keeps (insertion sources and dumps included) and what each
 * family keeps through its checkpoint and resume hooks. A family that keeps state during a run
 * (hooks after begin) without them is refused, naming it. 0, or -1 with a message on stderr. */
static int resume_supported(const Run *run)
{
    const Scene *scene = run->scene;
    for (int f = 0; app_experiments[f]; ++f) {
        const AppExperiment *e = app_experiments[f];
        int keeps = e->begin || e->stage_begin || e->sample || e->step || e->stage_done ||
                    e->stage_end || e->end;
        if (!scene->experiments[f] || e->resume || !keeps)
            continue;
        fprintf(stderr,
                "sablier: --resume: scenes with %s cannot resume: its state during a run is not "
                "in the checkpoint (the family has no resume hook)\n",
                e->name);
        return -1;
    }
    return 0;
}

/* The output folder made ready: created; the files a previous run listed in its manifest removed
 * (but the states this scene loads); a folder with another run's summary.json and no manifest
 * refused without `force`; the resolved scene copied in. 0, or -1 with a message on stderr. */
static int prepare_folder(Run *run)
{
    const Scene *scene = run->scene;
    const char *dir = run->options->out_dir;
    if (run->options->resume && access(dir, F_OK) != 0) {
        fprintf(stderr, "sablier: --resume: no output folder %s\n", dir);
        return -1;
    }
    if (app_make_dirs(dir) != 0) {
        fprintf(stderr, "sablier: cannot create output folder %s: %s\n", dir, strerror(errno));
        return -1;
    }
    char path[PATH_SIZE], err[PATH_SIZE + 200];
    if (run->options->resume) /* every output so far stays: the run continues them */
        return resume_read(run) != 0 || resume_same_scene(run) != 0 || resume_supported(run) != 0
                   ? -1
                   : 0;
    out_path(run, path, "manifest", ".txt");
    int has_manifest = access(path, F_OK) == 0;
    out_path(run, path, "summary", ".json");
    if (!has_manifest && !run->options->force && access(path, F_OK) == 0) {
        fprintf(stderr,
                "sablier: %s holds the outputs of another run (summary.json without a "
                "manifest.txt): choose another --out, remove them, or use --force\n",
                dir);
        return -1;
    }
    const char *keep[SCENE_MAX_STAGES + 1];
    int keep_count = 0;
    keep[keep_count++] = scene->path; /* the scene, should it sit in the folder */
    for (int k = 0; k < scene->stage_count; ++k)
        if (scene->stages[k].load == SCENE_LOAD_FILE)
            keep[keep_count++] = scene->stages[k].load_path;
    if (app_manifest_remove_stale(dir, keep, keep_count, err, sizeof err) < 0) {
        fprintf(stderr, "sablier: %s\n", err);
        return -1;
    }
    out_path(run, path, "scene.resolved", ".cfg");
    if (scene->resolved && app_write_atomic(path, scene->resolved) != 0) {
        fprintf(stderr, "sablier: cannot write %s: %s\n", path, strerror(errno));
        return -1;
    }
    return 0;
}

/* A failed output (status 2) that failed for want of space becomes APP_EXIT_DISK_FULL. */
static void disk_full_status(Run *run)
{
    if (run->status != 2 || !app_failed_for_space(run->message))
        return;
    run->status = APP_EXIT_DISK_FULL;
    char text[sizeof run->message];
    snprintf(text, sizeof text, "%s", run->message);
    snprintf(run->message, sizeof run->message, "disk full: %.*s", (int)(sizeof run->message - 16),
             text);
}

/* A CSV output opened under PATH.tmp: with its header, or (--resume, bytes >= 0) with the part a
 * checkpoint recorded. NULL on failure. */
static FILE *csv_open(const char *path, const char *header, long bytes)
{
    return bytes < 0 ? app_tmp_open(path, header) : app_tmp_reopen(path, bytes);
}

/* The energy and trace CSV files opened. 0, or 2. */
static int open_csv(Run *run)
{
    const int resume = run->resume_state[0] != '\0';
    out_path(run, run->energy_path, "energy", ".csv");
    run->energy =
        csv_open(run->energy_path, "t,t_star,e_kin,e_pot,e_rot,e_el,e_total,grains,contacts,stage",
                 resume ? run->energy_bytes : -1);
    if (run->scene->output.trace_count > 0) {
        out_path(run, run->trace_path, "trace", ".csv");
        run->trace = csv_open(run->trace_path, "t,id,x,y,vx,vy,omega,fx,fy,torque",
                              resume ? run->trace_bytes : -1);
    }
    if (!run->energy || (run->scene->output.trace_count > 0 && !run->trace)) {
        snprintf(run->message, sizeof run->message, "cannot write in %s: %s", run->options->out_dir,
                 strerror(errno));
        return 2;
    }
    return 0;
}

/* The stages, in order, until one fails or a signal stops the run. */
static void run_stages(Run *run)
{
    const Scene *scene = run->scene;
    if (run->resume_record) /* before begin opens the families' files afresh */
        app_checkpoint_keep_files(run->resume_record, run->options->out_dir);
    if (run->status == 0 && family_hooks(run, HOOK_BEGIN) != 0)
        run->status = 2;
    int sources_failed = 0;
    run->sources = app_sources_create(scene, &sources_failed);
    if (sources_failed) {
        snprintf(run->message, sizeof run->message, "out of memory");
        run->status = 2;
    } else if (run->resume_state[0] && resume_sources(run) != 0) {
        run->status = 2;
    }
    for (int m = 0; !run->resume_state[0] && m < SIM_MAX_MOTIONS; ++m) {
        /* the first stage's motions run from t = 0 (a resumed run: as its record says) */
        run->motion_running[m] = (scene->stages[0].motions >> m) & 1u;
        run->motion_on[m] = run->motion_running[m] ? 0.0 : (double)INFINITY;
        run->motion_off[m] = (double)INFINITY;
    }
    for (int k = 0; run->status == 0 && k < scene->stage_count; ++k) {
        run->stages_done = k + 1;
        if (scene->stages[k].skip || (run->resume_state[0] && k < run->resume_stage))
            continue; /* e.g. a sweep member that starts from a saved bed; a resumed run's
                         stages before its checkpoint (their reports from its record) */
        run->status = run_stage(run, k);
    }
}

/* A bare run (AppRunOptions.bare): the stages and the families' hooks, no file, no signal. */
static void run_bare(Run *run)
{
    run_stages(run);
    families_end(run);
    const AppRunOptions *o = run->options;
    if (o->err && o->err_size > 0)
        snprintf(o->err, o->err_size, "%s", run->status != 0 ? run->message : "");
}

/* The run with its files: the folder, the stages, energy.csv, trace.csv, summary.json, the
 * families' figures and the manifest, under the caught signals. run->status set; 0, or -1
 * when the folder could not be made ready (nothing ran). */
static int run_files(Run *run, double wall_start)
{
    const Scene *scene = run->scene;
    const AppRunOptions *options = run->options;
    if (prepare_folder(run) != 0)
        return -1;
    if (options->render && options->render->provenance) {
        char comment[2048];
        app_provenance_comment(&options->provenance, scene->sha256, comment, sizeof comment);
        options->render->provenance(options->render->context, comment);
    }
    if (options->render && options->render->threads)
        options->render->threads(options->render->context, options->threads);
    struct sigaction saved[2];
    app_run_signal_catch(saved, 0);
    run->status = open_csv(run);
    run_stages(run);
    families_end(run);
    /* The CSV files are complete records up to here, failure included. */
    int energy_failed = app_tmp_commit(&run->energy, run->energy_path) != 0;
    int trace_failed = app_tmp_commit(&run->trace, run->trace_path) != 0; /* both, always */
    if ((energy_failed || trace_failed) && run->status == 0) {
        snprintf(run->message, sizeof run->message, "cannot write %s",
                 energy_failed ? run->energy_path : run->trace_path);
        run->status = 2;
    }
    disk_full_status(run);
    if (app_run_summary_write(run, sim_clock_seconds(SIM_CLOCK_WALL) - wall_start) != 0 &&
        run->status == 0) {
        snprintf(run->message, sizeof run->message, "cannot write %s/summary.json",
                 options->out_dir);
        run->status = 2;
    }
    families_figures(run); /* after summary.json, as before: a figure failure exits 2 */
    /* what this run wrote; a resumed run lists the files of the run it continues too */
    if (app_manifest_write(options->out_dir, options->resume) != 0 && run->status == 0) {
        snprintf(run->message, sizeof run->message, "cannot write %s/manifest.txt",
                 options->out_dir);
        run->status = 2;
    }
    app_run_signal_catch(saved, 1);
    disk_full_status(run);
    if (run->status != 0)
        fprintf(stderr, "sablier: %s\n", run->message);
    return 0;
}

int app_run(const Scene *scene, const AppRunOptions *options)
{
    Run *run = calloc(1, sizeof *run);
    if (!run) {
        fprintf(stderr, "sablier: out of memory\n");
        return 2;
    }
    run->scene = scene;
    run->options = options;
    run->settle_since = -1.0; /* a checkpoint from before `hold`: no window under way */
    run->context = (AppContext){.scene = scene,
                                .out_dir = options->out_dir,
                                .render = options->render,
                                .stage = -1,
                                .err = run->message,
                                .err_size = sizeof run->message};
    const int quiet = options->quiet || options->bare;
    run->progress_tty = !quiet && isatty(STDERR_FILENO);
    run->progress_every = quiet ? 0.0 : run->progress_tty ? 0.25 : options->progress_every;
    double wall_start = sim_clock_seconds(SIM_CLOCK_WALL);
    run->last_progress = wall_start;
    time_t started = time(NULL);
    run->started = (long long)started;
    run->resume_stage = -1;
    run->checkpoint_wall = wall_start;
    app_threads_init(&run->threads, options->threads, options->threads_switch_every,
                     sim_cpu_count(), options->grains_per_thread, options->threads_block_seconds);
    if (options->world)
        *options->world = NULL;
    int status = 2;
    if (options->bare)
        run_bare(run);
    if (options->bare || run_files(run, wall_start) == 0)
        status = run->status;
    if (run->world && options->world && status == 0)
        *options->world = run->world; /* handed over: the caller destroys it */
    else if (run->world)
        sim_world_destroy(run->world);
    app_sources_free(run->sources);
    free(run->resume_record);
    free(run);
    return status;
}
