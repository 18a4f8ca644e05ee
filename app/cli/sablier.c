/* SPDX-License-Identifier: MIT */
/* sablier.c: the `sablier` command (run, check, diff, render, export). The one translation unit
 * that sees both sim/ and render/: it maps the scene's plain style data onto RenderStyle and hands
 * the runner its figure and movie hooks. Built without render/ (SABLIER_WITH_RENDER=OFF), figures
 * and movies are skipped with a warning and `diff`/`render` exit 2. */
#include "base/experiments.h"
#include "base/util.h"
#include "cli/cli.h"
#include "driver/ensemble.h"
#include "driver/pool.h"
#include "output/diff_folders.h"
#include "output/dump.h"
#include "run/run.h"
#include "scene/advice.h"
#include "scene/scene.h"
#include "scene/sources.h"
#include "sim/sim.h"

#ifdef SABLIER_HAVE_RENDER
#include "cli/render_glue.h"
#endif

#include "revision.h" /* SABLIER_REVISION, made at build time (cmake/revision.cmake) */

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#ifndef SABLIER_VERSION
#define SABLIER_VERSION "0.0.0"
#endif

#define MAX_SETS APP_MAX_SETS

/* `sablier --help`: the core commands, then every family's from the registry. */
static const char USAGE_HEAD[] =
    "usage: sablier COMMAND [options]\n"
    "\n"
    "commands:\n"
    "  run SCENE      run a scene and write its outputs (summary.json, energy.csv, ...)\n"
    "  check SCENE    validate a scene and print what it would run\n"
    "  diff A B       compare two PNG images, or two folders of figures (exit 0 match, 1 differ)\n"
    "  render STATE   draw a saved checkpoint without simulating\n"
    "  export STATE   write a checkpoint as a LAMMPS dump, a VTK file or CSV\n"
    "  ensemble SCENE seeds x time steps: from which dt on a mean stays within its error\n";

static const char USAGE_TAIL[] =
    "\n"
    "  sablier COMMAND --help   options of one command\n"
    "  sablier --version        versions of sablier and its libraries\n"
    "\n"
    "exit status: 0 success, 1 the simulation failed, 2 bad usage or bad input (nothing\n"
    "written), 3 disk full, 130/143 interrupted by SIGINT/SIGTERM (docs/cli.md)\n";

static void print_usage(FILE *out)
{
    fputs(USAGE_HEAD, out);
    for (int f = 0; app_experiments[f]; ++f)
        for (int c = 0; c < app_experiments[f]->command_count; ++c) {
            const AppCommand *command = &app_experiments[f]->commands[c];
            fprintf(out, "  %s\n", command->help);
        }
    fputs(USAGE_TAIL, out);
}

static const char USAGE_RUN[] =
    "usage: sablier run SCENE [--out DIR] [--set KEY=VALUE]... [--unset KEY]...\n"
    "                   [--threads N|auto] [--quiet] [--progress-every SECONDS] [--force]\n"
    "                   [--resume] [--threads-switch-every STEPS]\n"
    "\n"
    "  --out DIR          output folder (default out/<scene name>/)\n"
    "  --set KEY=VALUE    override a scene key by its dotted path, e.g. time.dt=2e-5,\n"
    "                     species.0.k_n=1e6, stages.collapse.time.end=2 (see docs/scenes.md)\n"
    "  --unset KEY        remove a scene key (and the keys only it allows: --unset\n"
    "                     contact.tangential also removes k_t, gamma_t), in order with --set\n"
    "  --threads N|auto   threads for the physics step (results do not depend on N); auto,\n"
    "                     the default: the count that steps fastest now, measured while the\n"
    "                     run goes on (neighbouring counts tried from time to time, and again\n"
    "                     when the grains change or the steps slow down), within the CPUs this\n"
    "                     process may use; N: always N\n"
    "  --threads-switch-every STEPS\n"
    "                     a testing aid: cycle through 1, 2, 3 and 4 threads every STEPS steps\n"
    "                     (the outputs stay one thread's, to the bit)\n"
    "  --quiet, -q        one line per stage, no progress\n"
    "  --progress-every SECONDS\n"
    "                     when stderr is no terminal (a batch job's log): one progress line\n"
    "                     every SECONDS of wall time with the stage, the simulated time, the\n"
    "                     rate and the ETA (default 60; 0: none)\n"
    "  --force            run into a folder that holds another run's outputs without a\n"
    "                     manifest.txt (a previous sablier run's own files are replaced anyway)\n"
    "  --resume           continue the run in DIR from its newest checkpoint (DIR/checkpoint.txt:\n"
    "                     output.checkpoint_every, or an interruption), with the same scene and\n"
    "                     --set values; the outputs come out as an uninterrupted run's\n"
    "\n"
    "SIGINT or SIGTERM stops the run after the current step: the running stage's state goes to\n"
    "DIR/STAGE.interrupted.state, every output is committed, summary.json says \"interrupted\".\n"
    "\n"
    "exit status: 0 the run ended, 1 unstable (the last good state saved), 2 bad input (nothing\n"
    "written) or an output that cannot be written, 3 disk full, 130/143 SIGINT/SIGTERM\n";

static const char USAGE_CHECK[] =
    "usage: sablier check SCENE [--set KEY=VALUE]... [--unset KEY]... [--target-error E]\n"
    "\n"
    "Validates the scene (keys, types, values, overlaps, time step) and prints its stages,\n"
    "effects, grains, friction law (static friction or not), time step, contact time and steps\n"
    "per contact without running it. Warnings (stderr, file:line): motions that move nothing.\n"
    "  --target-error E   also print, for the stiffest pair and its damping, the steps per\n"
    "                     contact and dt that reach |e - e_n| <= E (measured convergence of the\n"
    "                     integrator and contact.onset) and the CPU time per simulated second\n"
    "                     that implies (an estimate)\n"
    "\n"
    "exit status: 0 the scene is good, 2 bad input (check writes nothing, ever)\n";

static const char USAGE_DIFF[] =
    "usage: sablier diff A.png B.png [--out DIFF.png] [--threshold N] [--shift N]\n"
    "                    [--max-pixels N]\n"
    "       sablier diff BASELINE_DIR FRESH_DIR [--report DIR] [--update] [--threshold N]\n"
    "                    [--shift N] [--max-pixels N]\n"
    "\n"
    "  --out DIFF.png     write an image of the differences\n"
    "  --threshold N      a pixel differs when a channel differs by more than N (0-255)\n"
    "  --shift N          ignore differences matched within N pixels (0-32)\n"
    "  --max-pixels N     the images match when at most N pixels differ\n"
    "  --report DIR       folders: write DIR/index.html (baseline, fresh and difference side by\n"
    "                     side) and DIR/report.json\n"
    "  --update           folders: then copy the changed and extra figures over the baseline and\n"
    "                     remove the missing ones (exit 0)\n"
    "Two images: prints one JSON line. Two folders: pairs their figures (.png, and .pdf and .svg\n"
    "drawn at 150 dpi, by the image diff) by relative path and prints one line per changed,\n"
    "missing or extra figure.\n"
    "\n"
    "exit status: 0 match (--update: the baseline was updated), 1 differ, 2 bad input, an\n"
    "unreadable figure or a report or copy that cannot be written\n";

static const char USAGE_RENDER[] =
    "usage: sablier render STATE -o FIG.png|pdf|svg [options]\n"
    "\n"
    "  -o, --out FIG        the figure; its extension gives the format (png, pdf, svg)\n"
    "  --scene SCENE        materials and style from a scene (needed for contact forces)\n"
    "  --set KEY=VALUE      override a key of that scene (needs --scene)\n"
    "  --unset KEY          remove a key of that scene (needs --scene)\n"
    "  --color-by NAME      fixed, force, speed, species, height\n"
    "  --colormap NAME      viridis, yellow_red, greys\n"
    "  --force-chains       draw contact force chains (needs --scene)\n"
    "  --no-force-chains    do not, whatever the scene's style says\n"
    "  --chain-threshold X  draw contacts above X times the mean normal force\n"
    "  --velocity-field     draw the coarse-grained velocity field\n"
    "  --velocity-arrows    draw per-grain velocity arrows\n"
    "  --width N            width in pixels, 16-16384\n"
    "  --height N           height in pixels, 16-16384\n"
    "  --colorbar           the colour bar\n"
    "  --time-stamp         the state's time above the plot\n"
    "  --scale-bar          a bar of a few grain diameters\n"
    "  --title TEXT         a title above the plot\n"
    "\n"
    "exit status: 0 the figure was written, 2 bad input or a state that does not fit --scene,\n"
    "3 disk full\n";

/* ---------------------------------------------------------------- argument helpers */

/* Matches "--name VALUE" or "--name=VALUE"; advances *i past the value. */

static int wants_help(int argc, char **argv)
{
    for (int i = 2; i < argc; ++i)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            return 1;
    return 0;
}

static const char *render_versions(void)
{
#ifdef SABLIER_HAVE_RENDER
    return render_library_versions();
#else
    return NULL;
#endif
}

/* ---------------------------------------------------------------- commands */

/* `sablier run`'s command line. */
typedef struct RunArgs {
    const char *scene_path, *out, *sets[MAX_SETS];
    int set_count, quiet, force, resume;
    long threads, switch_every;
    double progress_every;
} RunArgs;

/* The command line into *a: 0, or the exit status of a usage error (message on stderr). */
static int run_arguments(int argc, char **argv, RunArgs *a)
{
    const char *value;
    *a = (RunArgs){.threads = APP_THREADS_AUTO, .progress_every = APP_PROGRESS_EVERY};
    for (int i = 2; i < argc; ++i) {
        int m;
        if ((m = app_option(argc, argv, &i, "--out", &value)) != 0) {
            if (m < 0)
                return 2;
            a->out = value;
        } else if ((m = app_set_option(argc, argv, &i, a->sets, &a->set_count, MAX_SETS)) != 0) {
            if (m < 0)
                return 2;
        } else if ((m = app_option(argc, argv, &i, "--threads", &value)) != 0) {
            if (m > 0 && strcmp(value, "auto") == 0)
                a->threads = APP_THREADS_AUTO;
            else if (m < 0 || app_parse_count(value, 1, 1024, &a->threads) < 0)
                return app_usage_error(USAGE_RUN,
                                       "--threads needs a count in [1, 1024] or auto, got",
                                       m < 0 ? "nothing" : value);
        } else if ((m = app_option(argc, argv, &i, "--threads-switch-every", &value)) != 0) {
            if (m < 0 || app_parse_count(value, 1, 1000000000L, &a->switch_every) < 0)
                return app_usage_error(USAGE_RUN,
                                       "--threads-switch-every needs a step count >= 1, got",
                                       m < 0 ? "nothing" : value);
        } else if ((m = app_option(argc, argv, &i, "--progress-every", &value)) != 0) {
            const AppNumberList how = {.min = 0.0, .strict = 1, .exact = 1};
            if (m < 0 || app_parse_numbers(value, &how, &a->progress_every, 1) != 1)
                return app_usage_error(USAGE_RUN, "--progress-every needs seconds >= 0, got",
                                       m < 0 ? "nothing" : value);
        } else if (strcmp(argv[i], "--quiet") == 0 || strcmp(argv[i], "-q") == 0) {
            a->quiet = 1;
        } else if (strcmp(argv[i], "--force") == 0) {
            a->force = 1;
        } else if (strcmp(argv[i], "--resume") == 0) {
            a->resume = 1;
        } else if (app_scene_argument(USAGE_RUN, argv[i], &a->scene_path) != 0) {
            return 2;
        }
    }
    if (!a->scene_path)
        return app_usage_error(USAGE_RUN, "missing SCENE", NULL);
    return 0;
}

static int parse_run(int argc, char **argv)
{
    RunArgs a;
    return run_arguments(argc, argv, &a);
}

static int command_run(int argc, char **argv)
{
    RunArgs a;
    int bad = run_arguments(argc, argv, &a);
    if (bad)
        return bad;
    const char *const *sets = a.sets;
    int set_count = a.set_count;
    char err[4096];
    Scene *scene = scene_load(a.scene_path, sets, set_count, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    char default_out[SCENE_NAME_MAX + 8];
    snprintf(default_out, sizeof default_out, "out/%s", scene->name);
    AppRunOptions options = app_run_options_default();
    options.out_dir = a.out ? a.out : default_out;
    options.quiet = a.quiet;
    options.progress_every = a.progress_every;
    options.threads = (int)a.threads;
    options.threads_switch_every = a.switch_every;
    options.sablier_version = SABLIER_VERSION;
    options.render_versions = render_versions();
    options.force = a.force;
    options.resume = a.resume;
    options.provenance = (AppProvenance){.argc = argc,
                                         .argv = argv,
                                         .sets = a.sets,
                                         .set_count = set_count,
                                         .revision = SABLIER_REVISION,
                                         .out_dir = options.out_dir};
#ifdef SABLIER_HAVE_RENDER
    options.render = app_render_glue();
#endif
    int status = app_run(scene, &options);
    scene_free(scene);
    return status;
}

/* A stage's own gravity, effects and motions, where they differ from the scene's. */
static void print_stage_forcing(const Scene *scene, int k)
{
    const SceneStage *s = &scene->stages[k];
    char u[32];
    if (s->gravity_x != scene->def.gravity_x || s->gravity_y != scene->def.gravity_y)
        printf(", gravity (%g, %g)%s", s->gravity_x, s->gravity_y,
               scene_unit_after(scene, SCENE_ACCELERATION, u, sizeof u));
    if (s->effects != scene->def.effects) {
        char names[256];
        scene_effect_names(s->effects, names, sizeof names);
        printf(", effects %s", names);
    }
    if (!s->declares_motions)
        return;
    printf(", motions");
    int any = 0;
    for (int m = 0; m < scene->def.motion_count; ++m)
        if ((s->motions >> m) & 1u)
            printf("%s %s", any++ ? "," : "", scene->motion_names[m]);
    printf("%s", any ? "" : " none");
}

/* Responding body k of def, stage `stage`'s (a wall, then the grain bodies): a free body's mass
 * and axis, or its servo's time scale and damping feedback (sim.h sim_wall_servo_time,
 * sim_wall_servo_damping), warned about on stderr at its `file:line` when a row of grains along
 * it would flip an explicit servo. `s`: the time unit after a number. */
static void print_body(const Scene *scene, int stage, int k, const SimWorldDef *def, double dt,
                       const char *s)
{
    const int walls = def->wall_count;
    const SimWallBody *b =
        k < walls ? (def->wall_bodies && def->wall_bodies[k].active ? &def->wall_bodies[k] : NULL)
                  : &def->grain_bodies[k - walls];
    if (!b)
        return;
    char who[SCENE_NAME_MAX + 16], field[32];
    if (k < walls) {
        snprintf(who, sizeof who, "wall %d", k);
        snprintf(field, sizeof field, "walls[%d]", k);
    } else {
        snprintf(who, sizeof who, "body %s", scene->body_names[k - walls]);
        snprintf(field, sizeof field, "bodies[%d]", k - walls);
    }
    if (!b->servo) {
        printf("  %-16s free body, mass %g, axis (%g, %g)\n", who, b->mass, b->axis_x, b->axis_y);
        return;
    }
    const double tau = sim_wall_servo_time(def, k);
    double row;
    const double per_contact = sim_wall_servo_damping(def, k, &row);
    char damping[64] = "damping implicit";
    if (!sim_wall_servo_implicit(def, k))
        snprintf(damping, sizeof damping, "damping feedback %.3g per contact", per_contact);
    printf("  %s servo%*s target %s %g, time scale tau %g%s, dt / tau %.3g (refused above 1; "
           "the gain's bound: tau = dt at gain %g), %s\n",
           who, (int)(strlen(who) < 10 ? 10 - strlen(who) : 0), "",
           b->servo == 1 ? "stress" : "force", b->target, tau, s, dt / tau, b->gain * tau / dt,
           damping);
    if (per_contact * row >= 1.0)
        fprintf(stderr,
                "%s: warning: %s's servo flips its speed every step once %.0f grains touch it "
                "(damping feedback %.3g per contact; a row of the smallest grains along it makes "
                "%.0f): its walls.csv rows then catch one phase; a gain below %g keeps a full row "
                "stable\n",
                scene_where_field(scene, stage, field), who, ceil(1.0 / per_contact), per_contact,
                row, b->gain / (per_contact * row));
}

static void print_timing(const Scene *scene, int k)
{
    SimWorldDef def = scene_world_def(scene, k);
    SimTiming t = app_sources_timing(scene, &def); /* the sources' grains' contacts too */
    char s[32];
    scene_unit_after(scene, SCENE_TIME, s, sizeof s);
    printf("  time step        %g%s%s\n", t.time_step, s,
           scene->stages[k].time_step > 0.0 ? "" : " (chosen from steps_per_contact)");
    printf("  contact time     %g%s (shortest pair)\n", t.contact_time_min, s);
    printf("  stability limit  %g%s\n", t.stability_limit, s);
    printf("  steps per contact %.1f\n", t.steps_per_contact);
    for (int b = 0; b < def.wall_count + def.grain_body_count; ++b)
        print_body(scene, k, b, &def, t.time_step, s);
}

/* `sablier check`'s command line. */
typedef struct CheckArgs {
    const char *scene_path, *sets[MAX_SETS];
    int set_count;
    double target; /* --target-error, 0 when not given */
} CheckArgs;

/* The command line into *a: 0, or the exit status of a usage error (message on stderr). */
static int check_arguments(int argc, char **argv, CheckArgs *a)
{
    const char *value;
    *a = (CheckArgs){.scene_path = NULL};
    for (int i = 2; i < argc; ++i) {
        int m = app_option(argc, argv, &i, "--target-error", &value);
        if (m != 0) {
            const AppNumberList how = {.min = 0.0, .strict = 1, .exact = 1};
            if (m < 0 || app_parse_numbers(value, &how, &a->target, 1) != 1 ||
                !(a->target > 0.0 && a->target < 0.5))
                return app_usage_error(USAGE_CHECK, "--target-error must be in (0, 0.5), got",
                                       m < 0 ? "" : value);
            continue;
        }
        m = app_set_option(argc, argv, &i, a->sets, &a->set_count, MAX_SETS);
        if (m < 0)
            return 2;
        if (m == 0 && app_scene_argument(USAGE_CHECK, argv[i], &a->scene_path) != 0)
            return 2;
    }
    if (!a->scene_path)
        return app_usage_error(USAGE_CHECK, "missing SCENE", NULL);
    return 0;
}

static int parse_check(int argc, char **argv)
{
    CheckArgs a;
    return check_arguments(argc, argv, &a);
}

/* The units `sablier check` prints after its numbers (docs/scenes.md#units): acceleration,
 * length, time, energy and mass rate. */
static void check_units(const Scene *scene, char u[5][32])
{
    scene_unit_after(scene, SCENE_ACCELERATION, u[0], sizeof u[0]);
    scene_unit_after(scene, SCENE_LENGTH, u[1], sizeof u[1]);
    scene_unit_after(scene, SCENE_TIME, u[2], sizeof u[2]);
    scene_unit_after(scene, SCENE_ENERGY, u[3], sizeof u[3]);
    scene_unit_after(scene, SCENE_MASS_RATE, u[4], sizeof u[4]);
}

/* `sablier check`: the scene, its physics, grains, species and neighbour lists. */
static void print_check_grains(const Scene *scene, char u[5][32])
{
    static const char *const mass[] = {"disk", "sphere"};
    char effects[256];
    scene_effect_names(scene->def.effects, effects, sizeof effects);
    printf("scene    %s (%s)\n", scene->name, scene->path);
    printf("seed     %llu\n", (unsigned long long)scene->seed);
    printf("effects  %s\n", effects);
    printf("mass     %s, integrator %s, gravity (%g, %g)%s\n", mass[scene->def.mass_model],
           sim_integrator_name(scene->def.integrator), scene->def.gravity_x, scene->def.gravity_y,
           u[0]);
    printf("grains   %d (%d mobile, %d fixed), %d walls, %d species:", scene->grains.count,
           scene->grains.count - scene->fixed_count, scene->fixed_count, scene->def.wall_count,
           scene->def.species_count);
    for (int k = 0; k < scene->def.species_count; ++k) {
        const SimMaterial *m = &scene->def.materials[k];
        printf("%s %s (density %g, k_n %g", k ? ";" : "",
               scene->species_names[k][0] ? scene->species_names[k] : "-", m->density,
               m->normal_stiffness);
        if (scene->def.effects & SIM_EFFECT_FRICTION)
            printf(", mu %g", m->friction);
        printf(")");
    }
    printf("\n");
    scene_describe_friction(scene, stdout);
    scene_warn(scene, stderr);
    if (scene->def.skin > 0.0)
        printf("lists    Verlet skin %g%s (fixed)\n", scene->def.skin, u[1]);
    else
        printf("lists    Verlet skin automatic, 0.01-0.2 mean diameter (the cheapest for the "
               "grains' motion)\n");
}

/* `sablier check`: each grain source and its rate. */
static void print_check_sources(const Scene *scene, char u[5][32])
{
    for (int k = 0; k < scene->source_count; ++k) {
        const SceneSource *src = &scene->sources[k];
        printf("source   %s: [%g, %g, %g, %g], ", src->name, src->x0, src->y0, src->x1, src->y1);
        if (src->rate > 0.0)
            printf("%g grains per%s", src->rate, u[2][0] ? u[2] : " time unit");
        else if (src->mass_rate > 0.0)
            printf("%g%s", src->mass_rate, u[4]);
        else
            printf("%ld grains at the stage start", src->count);
        printf("%s\n", src->rate > 0.0 && src->count > 0 ? " (capped)" : "");
    }
}

/* `sablier check`: each stage, its settings, its families' settings, adds, timing and dumps. */
static void print_check_stages(const Scene *scene, char u[5][32])
{
    printf("stages   %d\n", scene->stage_count);
    static const char *const loads[] = {"scene grains", "previous stage", "file"};
    for (int k = 0; k < scene->stage_count; ++k) {
        const SceneStage *s = &scene->stages[k];
        printf("stage %s: from %s%s%s, time.end %g%s", s->name, loads[s->load],
               s->load == SCENE_LOAD_FILE ? " " : "",
               s->load == SCENE_LOAD_FILE ? s->load_path : "", s->duration, u[2]);
        if (s->settle_kinetic > 0.0)
            printf(", settle when E_kin + E_rot < %g%s (after %g%s)", s->settle_kinetic, u[3],
                   s->settle_after, u[2]);
        for (int f = 0; app_experiments[f]; ++f) /* the families' own stage settings */
            if (scene->experiments[f] && app_experiments[f]->describe_stage)
                app_experiments[f]->describe_stage(scene->experiments[f], k, stdout);
        if (s->remove_count)
            printf(", remove %d ids", s->remove_count);
        print_stage_forcing(scene, k);
        if (s->movie) /* the pace: frame interval and speed (docs/scenes.md#output) */
            printf(", movie: a frame every %g%s, %g%s simulated per s of video",
                   scene_frame_interval(scene, k), u[2],
                   scene_frame_interval(scene, k) * scene->output.fps, u[2]);
        printf("\n");
        for (int j = 0; j < s->add_count; ++j) /* names and ids for trace, dumps, remove_ids */
            printf("  add grain %u%s%s%s at (%g, %g), radius %g, species %s\n", s->adds[j].id,
                   s->adds[j].name[0] ? " `" : "", s->adds[j].name, s->adds[j].name[0] ? "`" : "",
                   s->adds[j].x, s->adds[j].y, s->adds[j].radius,
                   scene->species_names[s->adds[j].species]);
        print_timing(scene, k);
        app_dump_describe(&scene->output.dump[k], s->duration, s->time_step, stdout);
    }
}

/* `sablier check`: the energy rows, figures and traced grains. */
static void print_check_output(const Scene *scene, char u[5][32])
{
    const SceneOutput *o = &scene->output;
    printf("output   energy every %g%s, %d figures, %d traced grains\n", o->energy_every, u[2],
           o->figure_count, o->trace_count);
    for (int k = 0; k < o->figure_count; ++k)
        if (o->figures[k].at_end == 2)
            printf("figure %s.%s: stage %s, at %g%s after its start\n", o->figures[k].name,
                   o->figures[k].format, scene->stages[o->figures[k].stage].name,
                   o->figures[k].at_time, u[2]);
        else
            printf("figure %s.%s: stage %s, at %s\n", o->figures[k].name, o->figures[k].format,
                   scene->stages[o->figures[k].stage].name, o->figures[k].at_end ? "end" : "start");
}

static int command_check(int argc, char **argv)
{
    CheckArgs a;
    int bad = check_arguments(argc, argv, &a);
    if (bad)
        return bad;
    double target = a.target;
    char err[4096];
    Scene *scene = scene_load(a.scene_path, a.sets, a.set_count, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    char u[5][32]; /* the scene's units (docs/scenes.md#units) */
    check_units(scene, u);
    print_check_grains(scene, u);
    print_check_sources(scene, u);
    print_check_stages(scene, u);
    print_check_output(scene, u);
    if (target > 0.0) {
        SimWorldDef def = scene_world_def(scene, 0);
        AppAdvice advice;
        if (app_dt_advice(&def, scene->grains.count - scene->fixed_count, target, &advice, err,
                          sizeof err) != 0) {
            fprintf(stderr, "%s: --target-error: %s\n", scene->path, err);
            scene_free(scene);
            return 2;
        }
        app_dt_advice_print(&advice, &def, stdout);
    }
    printf("ok\n");
    scene_free(scene);
    return 0;
}

/* `sablier diff`'s command line: two paths and the options of both forms. */
typedef struct DiffArgs {
    const char *paths[2], *out, *report;
    long threshold, shift, max_pixels; /* -1: the image diff's default */
    int update;
} DiffArgs;

static int diff_arguments(int argc, char **argv, DiffArgs *d)
{
    const char *value;
    int count = 0;
    for (int i = 2; i < argc; ++i) {
        int m;
        long *target = NULL;
        if ((m = app_option(argc, argv, &i, "--out", &value)) != 0) {
            if (m < 0)
                return 2;
            d->out = value;
            continue;
        }
        if ((m = app_option(argc, argv, &i, "--report", &value)) != 0) {
            if (m < 0)
                return 2;
            d->report = value;
            continue;
        }
        if ((m = app_option(argc, argv, &i, "--threshold", &value)) != 0)
            target = &d->threshold;
        else if ((m = app_option(argc, argv, &i, "--shift", &value)) != 0)
            target = &d->shift;
        else if ((m = app_option(argc, argv, &i, "--max-pixels", &value)) != 0)
            target = &d->max_pixels;
        if (target) {
            /* a shift is searched in a (2N+1)^2 window per differing pixel: at most 32; a
             * channel differs by at most 255; any count of pixels is a bound */
            long max = target == &d->shift ? 32 : target == &d->threshold ? 255 : LONG_MAX;
            if (m < 0 || app_parse_count(value, 0, max, target) < 0)
                return app_usage_error(USAGE_DIFF,
                                       target == &d->shift ? "--shift needs a count in [0, 32], got"
                                       : target == &d->threshold
                                           ? "--threshold needs a count in [0, 255], got"
                                           : "--max-pixels needs a count >= 0, got",
                                       m < 0 ? "nothing" : value);
        } else if (strcmp(argv[i], "--update") == 0) {
            d->update = 1;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return app_usage_error(USAGE_DIFF, "unknown option", argv[i]);
        } else if (count < 2) {
            d->paths[count++] = argv[i];
        } else {
            return app_usage_error(USAGE_DIFF, "two images or two folders; extra argument",
                                   argv[i]);
        }
    }
    if (count != 2)
        return app_usage_error(USAGE_DIFF, "needs two images or two folders", NULL);
    return 0;
}

/* 1 folder, 0 something else, -1 nothing there. */
static int path_kind(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return -1;
    return S_ISDIR(st.st_mode) ? 1 : 0;
}

/* Two folders, or a new baseline for --update; a folder against a file is bad input. */
static int diff_is_folders(const DiffArgs *d)
{
    int a = path_kind(d->paths[0]), b = path_kind(d->paths[1]);
    if (a == 1 || b == 1 || d->report || d->update) {
        if (d->out)
            return app_usage_error(USAGE_DIFF, "--out is for two images; for folders use",
                                   "--report DIR");
        const char *bad = b != 1                            ? d->paths[1]
                          : a == 0 || (a < 0 && !d->update) ? d->paths[0]
                                                            : NULL;
        if (bad) {
            fprintf(stderr, "sablier: diff: %s: %s\n", bad,
                    path_kind(bad) < 0 ? "no such folder" : "not a folder (compare two folders)");
            return 2;
        }
        return 1;
    }
    return 0;
}

#ifdef SABLIER_HAVE_RENDER
static RenderDiffOptions diff_options(const DiffArgs *d)
{
    RenderDiffOptions options = render_diff_options_default();
    if (d->threshold >= 0)
        options.channel_threshold = (int)d->threshold;
    if (d->shift >= 0)
        options.shift_tolerance = (int)d->shift;
    if (d->max_pixels >= 0)
        options.max_pixels = d->max_pixels;
    return options;
}

/* The image diff of a folder pair (AppImageCompare): a size change is a difference; -1 for a
 * format this build cannot draw. */
static int diff_pair(void *context, const char *a, const char *b, const char *diff_png,
                     AppImageDiff *result, char *err, size_t err_size)
{
    RenderDiffResult r;
    memset(&r, 0, sizeof r);
    memset(result, 0, sizeof *result);
    if (!render_figure_readable(a)) { /* a PDF or SVG without poppler and librsvg */
        RenderImage none;
        render_figure_read(a, 0.0, &none, err, err_size);
        return -1;
    }
    int rc = render_diff_files(a, b, context, diff_png, &r, err, err_size);
    int compared = rc != 2; /* else no pixel counts and no difference image */
    if (rc == 2 && strncmp(err, "different sizes", 15) == 0)
        rc = 1;
    *result = (AppImageDiff){.verdict = rc,
                             .differing_pixels = r.differing_pixels,
                             .raw_pixels = r.raw_pixels,
                             .max_channel_diff = r.max_channel_diff,
                             .rms = isfinite(r.rms) ? r.rms : 0.0,
                             .width = compared ? r.width : 0,
                             .height = compared ? r.height : 0};
    return rc;
}

/* A PDF or SVG drawn as the PNG that the report page shows (AppFigureImage). */
static int diff_image(void *context, const char *figure, const char *png, char *err,
                      size_t err_size)
{
    (void)context;
    RenderImage image;
    if (render_figure_read(figure, 0.0, &image, err, err_size) != 0)
        return 1;
    int rc = render_png_write(&image, png, NULL, err, err_size);
    render_image_free(&image);
    return rc == 0 ? 0 : -1;
}

static int diff_files(const DiffArgs *d, const RenderDiffOptions *options)
{
    RenderDiffResult r;
    memset(&r, 0, sizeof r);
    char err[512] = "";
    int rc = render_diff_files(d->paths[0], d->paths[1], options, d->out, &r, err, sizeof err);
    if (rc == 2)
        fprintf(stderr, "sablier: diff: %s\n", err);
    printf("{\"result\": \"%s\", \"differing_pixels\": %ld, \"raw_pixels\": %ld, "
           "\"max_channel_diff\": %d, \"rms\": %.6g, \"width\": %d, \"height\": %d, "
           "\"threshold\": %d, \"shift\": %d, \"max_pixels\": %ld}\n",
           rc == 0   ? "match"
           : rc == 1 ? "differ"
                     : "error",
           r.differing_pixels, r.raw_pixels, r.max_channel_diff, isfinite(r.rms) ? r.rms : 0.0,
           r.width, r.height, options->channel_threshold, options->shift_tolerance,
           options->max_pixels);
    return rc == 0 || rc == 1 ? rc : 2;
}
#endif

static int parse_diff(int argc, char **argv)
{
    DiffArgs d = {.threshold = -1, .shift = -1, .max_pixels = -1};
    return diff_arguments(argc, argv, &d);
}

static int command_diff(int argc, char **argv)
{
    DiffArgs d = {.threshold = -1, .shift = -1, .max_pixels = -1};
    int rc = diff_arguments(argc, argv, &d);
    if (rc != 0)
        return rc;
    int folders = diff_is_folders(&d);
    if (folders == 2)
        return 2;
#ifdef SABLIER_HAVE_RENDER
    RenderDiffOptions options = diff_options(&d);
    if (!folders)
        return diff_files(&d, &options);
    AppFolderDiff o = {.compare = diff_pair,
                       .image = diff_image,
                       .context = &options,
                       .threshold = options.channel_threshold,
                       .shift = options.shift_tolerance,
                       .max_pixels = options.max_pixels,
                       .report_dir = d.report,
                       .update = d.update};
#else
    if (!folders) {
        fprintf(stderr, "sablier: diff: rendering is not built (SABLIER_WITH_RENDER=OFF)\n");
        return 2;
    }
    /* without the image diff, figures are compared by their bytes */
    AppFolderDiff o = {.report_dir = d.report, .update = d.update};
#endif
    return app_diff_folders(d.paths[0], d.paths[1], &o);
}

#ifdef SABLIER_HAVE_RENDER
static int name_index(const char *value, const char *const *names)
{
    for (int k = 0; names[k]; ++k)
        if (strcmp(value, names[k]) == 0)
            return k;
    return -1;
}
#endif

#ifdef SABLIER_HAVE_RENDER
/* The style with what the command line set (fields of `over` that are set) on top. */
static SceneStyle style_overlay(SceneStyle style, const SceneStyle *over)
{
    int *dst[] = {&style.width,           &style.height,       &style.color_by,
                  &style.colormap,        &style.force_chains, &style.velocity_field,
                  &style.velocity_arrows, &style.colorbar,     &style.time_stamp,
                  &style.scale_bar};
    const int src[] = {over->width,           over->height,       over->color_by,
                       over->colormap,        over->force_chains, over->velocity_field,
                       over->velocity_arrows, over->colorbar,     over->time_stamp,
                       over->scale_bar};
    for (size_t k = 0; k < sizeof src / sizeof src[0]; ++k)
        if (src[k] >= 0)
            *dst[k] = src[k];
    if (!isnan(over->chain_threshold))
        style.chain_threshold = over->chain_threshold;
    if (over->title[0])
        snprintf(style.title, sizeof style.title, "%s", over->title);
    return style;
}

#endif

#ifdef SABLIER_HAVE_RENDER
typedef struct RenderArgs {
    const char *state, *out, *scene_path, *sets[MAX_SETS];
    int set_count;
    SceneStyle over; /* only what the command line set */
} RenderArgs;

/* The options of `sablier render`: 0, or the exit status of a usage error. */
static int render_args(int argc, char **argv, RenderArgs *a)
{
    static const char *const color_names[] = {"fixed", "force", "speed", "species", "height", NULL};
    static const char *const cmap_names[] = {"viridis", "yellow_red", "greys", NULL};
    const char *value;
    for (int i = 2; i < argc; ++i) {
        int m;
        long count;
        if ((m = app_option(argc, argv, &i, "-o", &value)) != 0 ||
            (m = app_option(argc, argv, &i, "--out", &value)) != 0) {
            if (m < 0)
                return 2;
            a->out = value;
        } else if ((m = app_option(argc, argv, &i, "--scene", &value)) != 0) {
            if (m < 0)
                return 2;
            a->scene_path = value;
        } else if ((m = app_set_option(argc, argv, &i, a->sets, &a->set_count, MAX_SETS)) != 0) {
            if (m < 0)
                return 2;
        } else if ((m = app_option(argc, argv, &i, "--color-by", &value)) != 0) {
            if (m < 0 || (a->over.color_by = name_index(value, color_names)) < 0)
                return app_usage_error(USAGE_RENDER, "unknown --color-by", m < 0 ? "" : value);
        } else if ((m = app_option(argc, argv, &i, "--colormap", &value)) != 0) {
            if (m < 0 || (a->over.colormap = name_index(value, cmap_names)) < 0)
                return app_usage_error(USAGE_RENDER, "unknown --colormap", m < 0 ? "" : value);
        } else if ((m = app_option(argc, argv, &i, "--width", &value)) != 0) {
            if (m < 0 || app_parse_count(value, 16, 16384, &count) < 0)
                return app_usage_error(USAGE_RENDER, "--width must be in [16, 16384], got",
                                       m < 0 ? "" : value);
            a->over.width = (int)count;
        } else if ((m = app_option(argc, argv, &i, "--height", &value)) != 0) {
            if (m < 0 || app_parse_count(value, 16, 16384, &count) < 0)
                return app_usage_error(USAGE_RENDER, "--height must be in [16, 16384], got",
                                       m < 0 ? "" : value);
            a->over.height = (int)count;
        } else if ((m = app_option(argc, argv, &i, "--chain-threshold", &value)) != 0) {
            char *end;
            a->over.chain_threshold = m > 0 ? strtod(value, &end) : -1.0;
            if (m < 0 || *end || !(a->over.chain_threshold >= 0.0))
                return app_usage_error(USAGE_RENDER, "bad --chain-threshold", m < 0 ? "" : value);
        } else if ((m = app_option(argc, argv, &i, "--title", &value)) != 0) {
            if (m < 0)
                return 2;
            snprintf(a->over.title, sizeof a->over.title, "%s", value);
        } else if (strcmp(argv[i], "--force-chains") == 0) {
            a->over.force_chains = 1;
        } else if (strcmp(argv[i], "--no-force-chains") == 0) {
            a->over.force_chains = 0;
        } else if (strcmp(argv[i], "--velocity-field") == 0) {
            a->over.velocity_field = 1;
        } else if (strcmp(argv[i], "--velocity-arrows") == 0) {
            a->over.velocity_arrows = 1;
        } else if (strcmp(argv[i], "--colorbar") == 0) {
            a->over.colorbar = 1;
        } else if (strcmp(argv[i], "--time-stamp") == 0) {
            a->over.time_stamp = 1;
        } else if (strcmp(argv[i], "--scale-bar") == 0) {
            a->over.scale_bar = 1;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return app_usage_error(USAGE_RENDER, "unknown option", argv[i]);
        } else if (!a->state) {
            a->state = argv[i];
        } else {
            return app_usage_error(USAGE_RENDER, "one state at a time; extra argument", argv[i]);
        }
    }
    if (!a->state || !a->out)
        return app_usage_error(USAGE_RENDER, a->state ? "missing -o FIG" : "missing STATE", NULL);
    if (a->set_count && !a->scene_path)
        return app_usage_error(USAGE_RENDER, "--set needs --scene", NULL);
    return 0;
}
#endif

static int command_render(int argc, char **argv)
{
#ifdef SABLIER_HAVE_RENDER
    RenderArgs args = {.over = scene_style_unset()};
    int bad = render_args(argc, argv, &args);
    if (bad)
        return bad;
    const char *state = args.state, *out = args.out, *scene_path = args.scene_path;
    const char *const *sets = args.sets;
    int set_count = args.set_count;
    SceneStyle over = args.over;
    const char *why = NULL;
    if (sim_output_target(out, &why) != 0) { /* a device or a link is never replaced */
        fprintf(stderr, "sablier: render: cannot write %s: %s\n", out, why);
        return 2;
    }
    char err[4096] = "";
    Scene *scene = NULL;
    if (scene_path && !(scene = scene_load(scene_path, sets, set_count, err, sizeof err))) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    SimGrainSet grains;
    SimWall *walls = NULL;
    int wall_count = 0, status = 0;
    double time = 0.0;
    SimError error;
    memset(&grains, 0, sizeof grains);
    if (sim_state_load(state, &grains, &walls, &wall_count, &time, &error) != SIM_OK) {
        fprintf(stderr, "sablier: render: cannot load %s: %s\n", state, error.message);
        scene_free(scene);
        return 2;
    }
    SceneStyle style = scene ? scene->style : scene_style_unset();
    if (!scene && over.force_chains == 1) {
        fprintf(stderr, "sablier: render: warning: force chains need contact forces: pass --scene "
                        "SCENE; drawing grains only\n");
        over.force_chains = 0;
    }
    if (!scene && style.color_by < 0 && over.color_by < 0)
        over.color_by = SCENE_COLOR_SPECIES;
    SceneFigure figure;
    memset(&figure, 0, sizeof figure);
    figure.style = style_overlay(style, &over);
    RenderStyle render_style = app_render_style(&figure.style);
    const char *species[SIM_MAX_SPECIES];
    app_render_names(scene, species, &render_style);
    if (figure.style.axes < 0)
        render_style.axes = 1; /* a figure: axes unless `axes = false` */
    RenderMeta meta = {.scene = scene ? scene->name : "", .seed = scene ? scene->seed : 0};
    SimFrame frame;
    AppStateFrame columns;
    memset(&columns, 0, sizeof columns);
    SimWorld *world = NULL;
    if (scene) {
        /* sim_world_load: the state's grains are restored ones, exempt from the start-overlap
         * bound (sim.h) */
        SimWorldDef def = scene_world_def(scene, scene->stage_count - 1);
        world = sim_world_load(state, &def, &error);
        if (!world) {
            fprintf(stderr, "sablier: render: %s does not fit scene %s: %s: %s\n", state,
                    scene->path, error.field, error.message);
            status = 2;
        } else {
            sim_world_frame(world, &frame);
            /* units = "reduced": colour bars in m g and sqrt(g d) of this state's grains */
            double g = hypot(scene->def.gravity_x, scene->def.gravity_y), d, m;
            if (scene->units_reduced && g > 0.0) {
                sim_world_means(world, &d, &m);
                app_reduced_style(m * g, sqrt(g * d), &render_style);
            }
        }
    } else if (app_state_frame(&grains, walls, wall_count, time, &columns, &frame) != 0) {
        fprintf(stderr, "sablier: render: out of memory\n");
        status = 2;
    }
    if (status == 0 &&
        render_figure_write(&frame, &render_style, &meta, out, err, sizeof err) != 0) {
        int full = app_failed_for_space(err);
        fprintf(stderr, "sablier: render: %s%s: %s\n", full ? "disk full: " : "", out, err);
        status = full ? APP_EXIT_DISK_FULL : 2;
    }
    if (world)
        sim_world_destroy(world);
    app_state_frame_free(&columns);
    sim_grain_set_free(&grains);
    free(walls);
    scene_free(scene);
    return status;
#else
    (void)argc;
    (void)argv;
    fprintf(stderr, "sablier: render: rendering is not built (SABLIER_WITH_RENDER=OFF)\n");
    return 2;
#endif
}

static int parse_render(int argc, char **argv)
{
#ifdef SABLIER_HAVE_RENDER
    RenderArgs args = {.over = scene_style_unset()};
    return render_args(argc, argv, &args);
#else
    return command_render(argc, argv); /* a message and 2, nothing else */
#endif
}

/* What a multi-run command (a family's, or `ensemble`) is given; under mpirun a worker rank
 * starts serving the command's pools here. */
static AppEnv driver_env(void)
{
    AppEnv env = {.sablier_version = SABLIER_VERSION,
                  .render_versions = render_versions(),
                  .self = "/proc/self/exe"};
#ifdef SABLIER_HAVE_RENDER
    env.render = app_render_glue();
#endif
    app_pool_begin();
    return env;
}

/* `sablier ensemble`: a generic multi-run driver (app/driver/ensemble.c). */
static int command_ensemble(int argc, char **argv)
{
    AppEnv env = driver_env();
    return app_ensemble_command(argc, argv, &env);
}

static int command_version(void)
{
    const char *render = render_versions();
    printf("sablier %s\nsim %s\n%s\nrender: %s\n", SABLIER_VERSION, SIM_VERSION,
           scene_libconfig_version(), render ? render : "not built");
    /* the hot loops' instruction set (sim_isa; SABLIER_ISA forces one) and those this CPU runs */
    printf("kernels: %s (this CPU:", sim_isa_name(sim_isa()));
    for (int k = 0; k < SIM_ISA_COUNT; ++k)
        if (sim_isa_supported((SimIsa)k))
            printf(" %s", sim_isa_name((SimIsa)k));
    printf(")\n");
    return 0;
}

/* The commands of this file and `ensemble`; the families' come from the registry. */
static const struct {
    const char *name;
    int (*run)(int, char **);
    int (*parse)(int, char **); /* the command line only, as AppCommand.parse */
    const char *usage;
} CORE[] = {
    {"run", command_run, parse_run, USAGE_RUN},
    {"check", command_check, parse_check, USAGE_CHECK},
    {"diff", command_diff, parse_diff, USAGE_DIFF},
    {"render", command_render, parse_render, USAGE_RENDER},
    {"export", app_dump_export, app_dump_export_parse, app_dump_export_usage},
    {"ensemble", command_ensemble, app_ensemble_parse, app_ensemble_usage},
};

/* `sablier ARGS`: runs the command, or with parse_only checks its command line only (nothing
 * printed on stdout, nothing read, written or started): the exit status either way. */
static int dispatch(int argc, char **argv, int parse_only)
{
    if (argc < 2) {
        print_usage(stderr);
        return 2;
    }
    const char *command = argv[1];
    if (strcmp(command, "--help") == 0 || strcmp(command, "-h") == 0 ||
        strcmp(command, "help") == 0) {
        if (!parse_only)
            print_usage(stdout);
        return 0;
    }
    if (strcmp(command, "--version") == 0 || strcmp(command, "version") == 0)
        return parse_only ? 0 : command_version();
    for (size_t k = 0; k < sizeof CORE / sizeof CORE[0]; ++k) {
        if (strcmp(command, CORE[k].name) != 0)
            continue;
        if (wants_help(argc, argv)) {
            if (!parse_only)
                fputs(CORE[k].usage, stdout);
            return 0;
        }
        return parse_only ? CORE[k].parse(argc, argv) : CORE[k].run(argc, argv);
    }
    const AppCommand *family = app_experiment_command(command);
    if (family) {
        if (wants_help(argc, argv)) {
            if (!parse_only)
                fputs(family->usage, stdout);
            return 0;
        }
        if (parse_only)
            return family->parse ? family->parse(argc, argv) : 0;
        AppEnv env = driver_env();
        return family->run(argc, argv, &env);
    }
    fprintf(stderr, "sablier: unknown command `%s`\n\n", command);
    print_usage(stderr);
    return 2;
}

int sablier_parse_arguments(int argc, char **argv)
{
    return dispatch(argc, argv, 1);
}

#ifndef SABLIER_NO_MAIN /* tests/fuzz/fuzz_cli.c links this file for sablier_parse_arguments */
int main(int argc, char **argv)
{
    app_pool_launcher_exec(argv);
    return dispatch(argc, argv, 0);
}
#endif
