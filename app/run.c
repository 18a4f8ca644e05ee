/* SPDX-License-Identifier: MIT */
/* run.c: the stage runner. For each stage: build or continue the world, dig and remove, then step
 * in chunks that end on output times (energy rows, movie frames, trace rows, settle test), and
 * save a checkpoint. Every output is written under path.tmp and renamed when complete, so an
 * interrupted run never leaves a truncated file under a final name. */
#include "run.h"

#include "experiments.h"
#include "sources.h"
#include "util.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define PATH_SIZE (SCENE_PATH_MAX + 2 * SCENE_NAME_MAX)

typedef struct StageReport {
    long steps;
    double start_time, end_time; /* s */
    double wall_seconds;
    int settled;
    int removed;
    int mobile;
} StageReport;

typedef struct Run {
    const Scene *scene;
    const AppRunOptions *options;
    SimWorld *world;
    FILE *energy, *trace;
    char energy_path[PATH_SIZE], trace_path[PATH_SIZE];
    double time_scale; /* sqrt(D/g), s; 0 = unknown */
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
    AppContext context;  /* what the experiment families' hooks see */
    char observed[2048]; /* their summary.json members */
    /* The motions' clocks by world time (sim_world_set_motion), from the stages' `motions`. */
    int motion_running[SIM_MAX_MOTIONS];
    double motion_on[SIM_MAX_MOTIONS], motion_off[SIM_MAX_MOTIONS];
    AppSources *sources; /* insertion sources, NULL without */
} Run;

AppRunOptions app_run_options_default(void)
{
    AppRunOptions o;
    memset(&o, 0, sizeof o);
    o.threads = 1;
    o.sablier_version = "unknown";
    return o;
}

int app_make_dirs(const char *path)
{
    char buffer[PATH_SIZE];
    if (strlen(path) >= sizeof buffer || !path[0])
        return -1;
    strcpy(buffer, path);
    for (char *p = buffer + 1; *p; ++p) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(buffer, 0777) != 0 && errno != EEXIST)
            return -1;
        *p = '/';
    }
    if (mkdir(buffer, 0777) != 0 && errno != EEXIST)
        return -1;
    struct stat st;
    return stat(buffer, &st) == 0 && S_ISDIR(st.st_mode) ? 0 : -1;
}

static void out_path(const Run *run, char *out, const char *name, const char *suffix)
{
    snprintf(out, PATH_SIZE, "%s/%s%s", run->options->out_dir, name, suffix);
}

/* ---------------------------------------------------------------- JSON */

static void json_string(char *out, size_t size, const char *text)
{
    size_t n = 0;
    if (size < 3)
        return;
    out[n++] = '"';
    for (const unsigned char *c = (const unsigned char *)(text ? text : ""); *c && n + 8 < size;
         ++c) {
        if (*c == '"' || *c == '\\') {
            out[n++] = '\\';
            out[n++] = (char)*c;
        } else if (*c < 0x20) {
            n += (size_t)snprintf(out + n, size - n, "\\u%04x", *c);
        } else {
            out[n++] = (char)*c;
        }
    }
    out[n++] = '"';
    out[n] = '\0';
}

/* A double as JSON (NaN and infinities have no JSON form: null). */
static void json_number(char *out, size_t size, double v)
{
    if (isfinite(v))
        snprintf(out, size, "%.10g", v);
    else
        snprintf(out, size, "null");
}

static int write_summary(const Run *run, double wall_seconds)
{
    const Scene *scene = run->scene;
    size_t size = 16384 + 512 * SCENE_MAX_STAGES;
    char *text = malloc(size);
    if (!text)
        return -1;
    char name[256], file[2 * SCENE_PATH_MAX], message[2200], render[600], effects[256],
        effects_json[300], n1[40], n2[40], n3[40], n4[40];
    json_string(name, sizeof name, scene->name);
    json_string(file, sizeof file, scene->path);
    json_string(message, sizeof message, run->message);
    json_string(render, sizeof render,
                run->options->render_versions ? run->options->render_versions : "not built");
    scene_effect_names(scene->def.effects, effects, sizeof effects);
    json_string(effects_json, sizeof effects_json, effects);
    int grains = run->world ? sim_world_grain_count(run->world) : scene->grains.count;
    int mobile =
        run->world ? sim_world_mobile_count(run->world) : scene->grains.count - scene->fixed_count;
    json_number(n1, sizeof n1, run->simulated);
    json_number(n2, sizeof n2, wall_seconds);
    json_number(n3, sizeof n3,
                run->step_seconds > 0.0 ? run->particle_steps / run->step_seconds : 0.0);
    json_number(n4, sizeof n4,
                run->contacts_samples ? run->contacts_sum / (double)run->contacts_samples : 0.0);
    const char *status = run->status == 0 ? "ok" : run->status == 1 ? "unstable" : "error";
    size_t n = (size_t)snprintf(
        text, size,
        "{\n  \"scene\": %s,\n  \"scene_file\": %s,\n  \"seed\": %llu,\n  \"grains\": %d,\n"
        "  \"mobile_grains\": %d,\n  \"steps\": %ld,\n  \"simulated_seconds\": %s,\n"
        "  \"wall_seconds\": %s,\n  \"particle_steps_per_second\": %s,\n"
        "  \"contacts_mean\": %s,\n  \"status\": \"%s\",\n  \"message\": %s,\n"
        "  \"effects\": %s,\n  \"threads\": %d,\n",
        name, file, (unsigned long long)scene->seed, grains, mobile, run->steps, n1, n2, n3, n4,
        status, message, effects_json, run->options->threads);
    char sources[2048];
    app_sources_json(run->sources, sources, sizeof sources);
    n += (size_t)snprintf(text + n, size - n, "%s%s  \"stages\": [", sources, run->observed);
    for (int k = 0; k < run->stages_done && n < size; ++k) {
        const StageReport *s = &run->stages[k];
        char stage_name[160], a[40], b[40], c[40];
        json_string(stage_name, sizeof stage_name, scene->stages[k].name);
        json_number(a, sizeof a, s->start_time);
        json_number(b, sizeof b, s->end_time);
        json_number(c, sizeof c, s->wall_seconds);
        n += (size_t)snprintf(text + n, size - n,
                              "%s\n    {\"name\": %s, \"steps\": %ld, \"start_time\": %s, "
                              "\"end_time\": %s, \"wall_seconds\": %s, \"settled\": %s, "
                              "\"removed\": %d, \"mobile_grains\": %d}",
                              k ? "," : "", stage_name, s->steps, a, b, c,
                              s->settled ? "true" : "false", s->removed, s->mobile);
    }
    if (n < size) {
        char sablier[80];
        json_string(sablier, sizeof sablier, run->options->sablier_version);
        n += (size_t)snprintf(text + n, size - n,
                              "\n  ],\n  \"versions\": {\"sablier\": %s, \"sim\": \"%s\", "
                              "\"libconfig\": \"%s\", \"render\": %s}\n}\n",
                              sablier, SIM_VERSION,
                              scene_libconfig_version() + strlen("libconfig "), render);
    }
    char path[PATH_SIZE];
    out_path(run, path, "summary", ".json");
    int rc = n < size ? app_write_atomic(path, text) : -1;
    free(text);
    return rc;
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
    fprintf(run->energy, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d,%d,%s\n", t, t_star, e.kinetic,
            e.potential, e.rotational, e.elastic, e.total, e.mobile, e.contacts,
            run->scene->stages[stage].name);
}

static void trace_rows(Run *run, const SimFrame *frame)
{
    const SceneOutput *out = &run->scene->output;
    for (int k = 0; k < out->trace_count; ++k)
        for (int i = 0; i < frame->count; ++i) {
            if (frame->id[i] != out->trace_ids[k])
                continue;
            fprintf(run->trace, "%.9g,%u,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", frame->time,
                    frame->id[i], frame->x[i], frame->y[i], frame->vx[i], frame->vy[i],
                    frame->omega[i], frame->fx ? frame->fx[i] : 0.0, frame->fy ? frame->fy[i] : 0.0,
                    frame->torque ? frame->torque[i] : 0.0);
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
    sim_world_set_threads(world, run->options->threads); /* same bits for any count */
    if (run->world)
        sim_world_destroy(run->world);
    run->world = world;
    return 0;
}

/* The stage's gravity and motions (docs/scenes.md, stages): a motion the stage enables starts
 * its clock now (at t = 0 when it runs from the first stage); one it stops holds its pose. The
 * schedules are set again on every stage's world, fresh or continued. */
static void stage_forcing(Run *run, int k)
{
    const SceneStage *stage = &run->scene->stages[k];
    sim_world_set_gravity(run->world, stage->gravity_x, stage->gravity_y);
    if (!stage->declares_motions)
        return; /* motions run on world time, as defined */
    const double now = sim_world_time(run->world);
    for (int m = 0; m < run->scene->def.motion_count; ++m) {
        const int enabled = (stage->motions >> m) & 1u;
        if (enabled && !run->motion_running[m]) {
            run->motion_on[m] = now;
            run->motion_off[m] = (double)INFINITY;
        } else if (!enabled && run->motion_running[m]) {
            run->motion_off[m] = now;
        }
        run->motion_running[m] = enabled;
        sim_world_set_motion(run->world, m, run->motion_on[m], run->motion_off[m]);
    }
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
    if (stage->remove_count > 0)
        report->removed += sim_world_remove_ids(run->world, stage->remove_ids, stage->remove_count);
    return 0;
}

static void progress(Run *run, int k, double elapsed, double duration, double rate, int final)
{
    const SceneStage *stage = &run->scene->stages[k];
    if (final) {
        const StageReport *r = &run->stages[k];
        if (run->progress_tty)
            fputs("\r\033[K", stderr);
        fprintf(stderr,
                "sablier: stage %s: %.4g s simulated (t = %.4g s) in %.3g s, %ld steps, %d "
                "mobile grains%s%s\n",
                stage->name, r->end_time - r->start_time, r->end_time, r->wall_seconds, r->steps,
                r->mobile, r->settled ? ", settled" : "",
                r->removed ? ", grains removed at start" : "");
        return;
    }
    if (!run->progress_tty)
        return;
    double left = duration > elapsed && rate > 0.0 ? (duration - elapsed) / rate : 0.0;
    fprintf(stderr, "\r\033[Ksablier: %s  t = %.3f / %.3f s  %.3g steps/s  ETA %.0f s", stage->name,
            elapsed, duration, rate / sim_world_time_step(run->world), left);
    fflush(stderr);
}

static void unstable_message(Run *run, int k)
{
    const SceneStage *stage = &run->scene->stages[k];
    char path[PATH_SIZE];
    out_path(run, path, stage->name, ".last_good.state");
    SimError save_error;
    int saved = sim_world_save(run->world, path, &save_error) == SIM_OK;
    SimTiming timing = sim_world_timing(run->world);
    const char *cause =
        timing.steps_per_contact < 20.0
            ? "the time step is too large for the contacts (fewer than 20 steps per contact): "
              "lower time.dt"
            : "a contact blew up (overlap or speed beyond the guard): check k_n against the "
              "loads, the damping, and overlaps at the start";
    /* sim's message may already name the cause */
    int named = strstr(run->error.message, "likely cause") != NULL;
    snprintf(run->message, sizeof run->message,
             "stage %s: simulation failed at step %ld (t = %.6g s), grain %ld: %s%s%s "
             "(dt = %g s, %.1f steps per contact); last good state %s %s",
             stage->name, run->error.step, sim_world_time(run->world), run->error.grain,
             run->error.message, named ? "" : "; likely cause: ", named ? "" : cause,
             timing.time_step, timing.steps_per_contact,
             saved ? "saved to" : "could not be saved to", path);
}

/* The stage's cadences, in steps from its start: chunks of sim_world_step end on output times. */
typedef struct StageClock {
    double dt; /* s */
    long total, every_energy, every_frame, every_trace;
    int movie; /* 1: a movie is open (sink) */
    SimFrameSink sink;
} StageClock;

/* World, edits, the families' stage_begin, t*, the start figures and the movie. 0, or the exit
 * status. */
static int stage_start(Run *run, int k, StageClock *clock)
{
    const Scene *scene = run->scene;
    const SceneStage *stage = &scene->stages[k];
    const SceneOutput *out = &scene->output;
    const AppRender *render = run->options->render;
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
    if (figures_due(run, k, 0, 0, dt) != 0)
        return 2;
    if ((stage->movie || out->figure_count > 0) && !render && !run->options->render_off &&
        !run->render_warned) {
        fprintf(stderr, "sablier: warning: rendering is not built: figures and movies are "
                        "skipped\n");
        run->render_warned = 1;
    }
    *clock = (StageClock){
        .dt = dt,
        .total = (long)llround(stage->duration / dt),
        .every_energy = (long)fmax(1.0, (double)llround(out->energy_every / dt)),
        .every_frame = (long)fmax(1.0, (double)llround(1.0 / (out->frame_rate * dt))),
        .every_trace = (long)fmax(1.0, (double)llround(out->trace_every / dt)),
        .movie = stage->movie && render && render->movie_open,
    };
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
    if (done % clock->every_energy == 0 || done == clock->total)
        energy_row(run, k);
    if (frame_due || trace_due) {
        SimFrame frame;
        sim_world_frame(run->world, &frame);
        if (frame_due && clock->sink.consume(clock->sink.context, &frame) != 0)
            clock->sink.consume = NULL; /* the movie's sticky error is reported at close */
        if (trace_due)
            trace_rows(run, &frame);
    }
    family_step(run, done); /* profiles, phase samples, ... */
    return figures_due(run, k, 2, done, clock->dt) != 0 ? 2 : 0;
}

/* The next step after `done` at which anything is due. */
static long next_due(const Run *run, int k, const StageClock *clock, long done)
{
    long next = clock->total;
    long marks[3] = {clock->every_energy, clock->movie ? clock->every_frame : clock->total,
                     run->trace ? clock->every_trace : clock->total};
    for (int m = 0; m < 3; ++m) {
        long candidate = (done / marks[m] + 1) * marks[m];
        if (candidate < next)
            next = candidate;
    }
    next = next_figure_step(run, k, done, clock->dt, next);
    next = app_sources_next_step(run->sources, done, clock->dt, next);
    return family_next_step(run, done, next);
}

/* 1 when the stage's settle test passes at step `done`. */
static int settled(Run *run, const SceneStage *stage, const StageClock *clock, long done)
{
    double elapsed = (double)done * clock->dt;
    if (!(stage->settle_kinetic > 0.0) || done % clock->every_energy != 0 || done == 0 ||
        elapsed < stage->settle_after - 0.5 * clock->dt)
        return 0;
    SimEnergy e = sim_world_energy(run->world);
    return e.kinetic + e.rotational < stage->settle_kinetic;
}

/* Steps the stage in chunks that end on output times, until its end or the settle test. 0, or
 * the exit status. */
static int stage_loop(Run *run, int k, StageClock *clock)
{
    const SceneStage *stage = &run->scene->stages[k];
    StageReport *report = &run->stages[k];
    long done = 0;
    int status = 0;
    double last_progress = app_now_seconds(), step_wall = 0.0;
    for (;;) {
        if ((status = outputs_due(run, k, clock, done)) != 0 || done >= clock->total)
            break;
        if (settled(run, stage, clock, done)) {
            report->settled = 1;
            break;
        }
        long next = next_due(run, k, clock, done);
        double t0 = app_now_seconds();
        SimStatus s = sim_world_step(run->world, next - done, &run->error);
        double t1 = app_now_seconds();
        step_wall += t1 - t0;
        run->particle_steps += (double)sim_world_mobile_count(run->world) * (double)(next - done);
        report->steps += next - done;
        done = next;
        if (s != SIM_OK) {
            unstable_message(run, k);
            status = s == SIM_ERROR_UNSTABLE ? 1 : 2;
            break;
        }
        if (t1 - last_progress > 0.25) {
            progress(run, k, (double)done * clock->dt, stage->duration,
                     (double)done * clock->dt / step_wall, 0);
            last_progress = t1;
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
    report->end_time = sim_world_time(run->world);
    report->mobile = sim_world_mobile_count(run->world);
    run->simulated += report->end_time - report->start_time;
    if (clock->movie) {
        char err[512] = "";
        if (render->movie_close(render->context, err, sizeof err) != 0 && status == 0) {
            snprintf(run->message, sizeof run->message, "movie of stage %s: %s", stage->name, err);
            status = 2;
        }
    }
    if (status != 0)
        return status;
    char path[PATH_SIZE];
    out_path(run, path, stage->name, ".state");
    if (sim_world_save(run->world, path, &run->error) != SIM_OK) {
        snprintf(run->message, sizeof run->message, "checkpoint %s: %s", path, run->error.message);
        return 2;
    }
    if (family_hooks(run, HOOK_STAGE_END) != 0 || figures_due(run, k, 1, 0, clock->dt) != 0)
        return 2;
    return 0;
}

static int run_stage(Run *run, int k)
{
    double wall_start = app_now_seconds();
    StageClock clock;
    memset(&clock, 0, sizeof clock);
    int status = stage_start(run, k, &clock);
    if (status != 0)
        return status;
    status = stage_finish(run, k, &clock, stage_loop(run, k, &clock));
    if (status != 0)
        return status;
    run->stages[k].wall_seconds = app_now_seconds() - wall_start;
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

int app_run(const Scene *scene, const AppRunOptions *options)
{
    Run *run = calloc(1, sizeof *run);
    if (!run) {
        fprintf(stderr, "sablier: out of memory\n");
        return 2;
    }
    run->scene = scene;
    run->options = options;
    run->context = (AppContext){.scene = scene,
                                .out_dir = options->out_dir,
                                .render = options->render,
                                .stage = -1,
                                .err = run->message,
                                .err_size = sizeof run->message};
    run->progress_tty = !options->quiet && isatty(STDERR_FILENO);
    double wall_start = app_now_seconds();
    if (app_make_dirs(options->out_dir) != 0) {
        fprintf(stderr, "sablier: cannot create output folder %s: %s\n", options->out_dir,
                strerror(errno));
        free(run);
        return 2;
    }
    out_path(run, run->energy_path, "energy", ".csv");
    run->energy = app_tmp_open(run->energy_path,
                               "t,t_star,e_kin,e_pot,e_rot,e_el,e_total,grains,contacts,stage");
    if (scene->output.trace_count > 0) {
        out_path(run, run->trace_path, "trace", ".csv");
        run->trace = app_tmp_open(run->trace_path, "t,id,x,y,vx,vy,omega,fx,fy,torque");
    }
    if (!run->energy || (scene->output.trace_count > 0 && !run->trace)) {
        snprintf(run->message, sizeof run->message, "cannot write in %s: %s", options->out_dir,
                 strerror(errno));
        run->status = 2;
    }
    if (run->status == 0 && family_hooks(run, HOOK_BEGIN) != 0)
        run->status = 2;
    int sources_failed = 0;
    run->sources = app_sources_create(scene, &sources_failed);
    if (sources_failed) {
        snprintf(run->message, sizeof run->message, "out of memory");
        run->status = 2;
    }
    for (int m = 0; m < SIM_MAX_MOTIONS; ++m) { /* the first stage's motions run from t = 0 */
        run->motion_running[m] = (scene->stages[0].motions >> m) & 1u;
        run->motion_on[m] = run->motion_running[m] ? 0.0 : (double)INFINITY;
        run->motion_off[m] = (double)INFINITY;
    }
    for (int k = 0; run->status == 0 && k < scene->stage_count; ++k) {
        run->stages_done = k + 1;
        if (scene->stages[k].skip)
            continue; /* e.g. a sweep member that starts from a saved bed */
        run->status = run_stage(run, k);
    }
    families_end(run);
    /* The CSV files are complete records up to here, failure included. */
    if (app_tmp_commit(&run->energy, run->energy_path) != 0 ||
        app_tmp_commit(&run->trace, run->trace_path) != 0) {
        if (run->status == 0) {
            snprintf(run->message, sizeof run->message, "cannot finish the CSV files in %s",
                     options->out_dir);
            run->status = 2;
        }
    }
    if (write_summary(run, app_now_seconds() - wall_start) != 0 && run->status == 0) {
        snprintf(run->message, sizeof run->message, "cannot write %s/summary.json",
                 options->out_dir);
        run->status = 2;
    }
    families_figures(run); /* after summary.json, as before: a figure failure exits 2 */
    if (run->status != 0)
        fprintf(stderr, "sablier: %s\n", run->message);
    int status = run->status;
    if (run->world)
        sim_world_destroy(run->world);
    app_sources_free(run->sources);
    free(run);
    return status;
}
