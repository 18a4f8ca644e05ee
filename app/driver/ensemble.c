/* SPDX-License-Identifier: MIT */
/* ensemble.c: `sablier ensemble` (ensemble.h). Every (dt, seed) member is a child process of the
 * pool (app/driver/pool.h) that execs `sablier run SCENE --out DIR --quiet --set ...` (or the
 * command a family names for its members, AppExperiment.member: `sablier discharge`) and records
 * that process's CPU time; after the pool the observables are read from the members' folders and
 * reduced (stats.h) into members.csv, ensemble.csv, ensemble.json and ensemble.png/.pdf, and one
 * answer line per observable on stdout. */
#include "driver/ensemble.h"

#include "base/experiments.h"
#include "base/util.h"
#include "driver/driver.h"
#include "driver/pool.h"
#include "driver/run_value.h"
#include "driver/stats.h"
#include "output/provenance.h" /* app_json_string, app_json_number */
#include "run/run.h"
#include "scene/scene.h"
#include "sim/sim.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>

#define ENS_LEVELS 32   /* time steps */
#define ENS_KEYS   8    /* observables (one plot panel each) */
#define ENS_KEY    256  /* characters of one key */
#define ENS_LEVEL  0.95 /* confidence level */
#define ENS_PATH   (SCENE_PATH_MAX + 2 * SCENE_NAME_MAX)
#define ENS_ARGV   (2 * APP_MAX_SETS + 16)

const char app_ensemble_usage[] =
    "usage: sablier ensemble SCENE (--dt LIST | --steps-per-contact LIST) --observe KEY[,KEY...]\n"
    "                        [--seeds N] [--seed0 S] [--jobs N] [--out DIR] [--set KEY=VALUE]...\n"
    "                        [--resume] [--quiet]\n"
    "\n"
    "Runs SCENE for N seeds (default 5, at least 2) at each time step of the list and tells, per\n"
    "observable, from which dt on the ensemble mean stays within its statistical error of the\n"
    "finest dt's (the reference): shift of the mean with Welch's 95 % interval, against the CPU\n"
    "time per member (docs/accuracy.md#ensemble-accuracy). Members are `sablier run`; those of\n"
    "a discharge scene `sablier discharge` with discharge.dt_divisor=0 (summary.json:\n"
    "discharges.0.s, discharges.0.h).\n"
    "  --dt LIST                 time steps, s (comma list; sets time.dt)\n"
    "  --steps-per-contact LIST  or steps per shortest contact time (time.steps_per_contact)\n"
    "  --observe KEY,...         numbers in each member's folder, KEY = [FILE:]PATH: FILE "
    "(default\n"
    "                            summary.json) .json with a dotted PATH (crater.crater_height,\n"
    "                            bed.packing_fraction), or .csv: a key,value table's row PATH\n"
    "                            (observables.csv:crater_height_m) or column PATH of the last\n"
    "                            row (energy.csv:e_kin, trace.csv:y); at most 8 keys\n"
    "  --seeds N --seed0 S       seeds S .. S+N-1 (the scene's `seed` key; default S = 1)\n"
    "  --jobs N                  members at a time, 1-64 (default 2; results do not depend on N)\n"
    "  --set KEY=VALUE           override for every member\n"
    "  --out DIR                 default out/ensemble-<scene name>\n"
    "  --resume                  skip the members whose folder holds a completed run\n"
    "  --quiet, -q               no per-member lines\n"
    "Writes DIR/members.csv (every member's values and CPU s), DIR/ensemble.csv and\n"
    "DIR/ensemble.json (per observable and dt: n, mean, std, 95 % CI, shift against the\n"
    "reference with its Welch CI, mean CPU s per member), DIR/ensemble.png and .pdf; members'\n"
    "outputs in DIR/dt=X/seed-S/ (log.txt).\n"
    "\n"
    "exit status: 0 every member succeeded, 1 a member went unstable, 2 bad input (nothing\n"
    "runs), a member that failed otherwise or an observable that is missing, 130/143\n"
    "SIGINT/SIGTERM (the members stopped, the tables of the finished ones written, the others\n"
    "`interrupted` in members.csv)\n";

typedef struct Options {
    AppDriverArgs d; /* the common options: scene, --out, --set, --jobs, --quiet, --resume */
    const char *scene_path, *out_dir, *self;
    int by_steps; /* 1: the values are steps per contact */
    double values[ENS_LEVELS];
    int value_count;
    char keys[ENS_KEYS][ENS_KEY];
    int key_count;
    long seeds, seed0;
    const AppRender *render;
    char default_out[ENS_PATH];
} Options;

/* One time step of the list, as the scene resolves it. */
typedef struct Level {
    double value;           /* as given: dt (s) or steps per contact */
    double dt, per_contact; /* the last stage's time step and steps per shortest contact */
    double cpu_mean;        /* CPU s per member that succeeded (NaN: none) */
    int ok, failed;         /* members */
    AppSample sample[ENS_KEYS];
    AppShift shift[ENS_KEYS];
} Level;

typedef struct Ensemble {
    Options *o;
    const AppExperiment *family; /* the family whose command runs the members; NULL: `run` */
    Level levels[ENS_LEVELS];    /* by dt, finest (the reference) first */
    int level_count;
    int member_count;
    int *status;   /* each member's exit status (-1: not run) */
    double *cpu;   /* CPU s of each member (NaN: unknown) */
    double *value; /* [member * key_count + key] (NaN: none) */
    int missing;   /* observables that could not be read */
    char *argv[ENS_ARGV];
    char argv_text[ENS_ARGV][ENS_PATH];
} Ensemble;

/* ---------------------------------------------------------------- the command line */

static int usage_error(const char *message, const char *arg)
{
    return app_usage_error(app_ensemble_usage, message, arg);
}

/* --observe KEY[,KEY...]: 0, or the exit status. */
static int parse_keys(Options *o, const char *list)
{
    size_t length;
    for (const char *item; (item = app_list_item(&list, &length)) != NULL;) {
        char err[512];
        if (length == 0)
            return usage_error("--observe: empty key in", item);
        if (o->key_count == ENS_KEYS)
            return usage_error("--observe: at most 8 keys, got more in", item);
        if (length >= ENS_KEY)
            return usage_error("--observe: key too long:", item);
        char *key = o->keys[o->key_count];
        snprintf(key, ENS_KEY, "%.*s", (int)length, item);
        if (app_run_value_check(key, err, sizeof err) != 0)
            return usage_error("--observe:", err);
        for (int k = 0; k < o->key_count; ++k)
            if (strcmp(o->keys[k], key) == 0)
                return usage_error("--observe: key given twice:", key);
        ++o->key_count;
    }
    return 0;
}

/* --dt or --steps-per-contact LIST: 0, or the exit status. */
static int parse_values(Options *o, const char *name, const char *list, int by_steps)
{
    static const AppNumberList how = {.min = 0.0, .strict = 1, .exact = 1};
    if (o->value_count > 0)
        return usage_error("give one list: --dt or --steps-per-contact, once; got", name);
    o->by_steps = by_steps;
    o->value_count = app_parse_numbers(list, &how, o->values, ENS_LEVELS);
    if (o->value_count < 2)
        return usage_error(o->value_count < 0 ? "bad list (at most 32 numbers > 0) after"
                                              : "at least two values (a reference and one "
                                                "more) after",
                           name);
    for (int k = 0; k < o->value_count; ++k) {
        if (!(o->values[k] > 0.0))
            return usage_error("every value must be > 0 after", name);
        for (int j = 0; j < k; ++j)
            if (o->values[j] == o->values[k])
                return usage_error("a value given twice after", name);
    }
    return 0;
}

static const AppDriverSpec ENSEMBLE_SPEC = {.usage = app_ensemble_usage,
                                            .jobs_max = 64,
                                            .sets_max = APP_MAX_SETS - 8,
                                            .missing = "missing SCENE"};

/* The options of `sablier ensemble` alone (app_driver_parse's `own`): 1 taken, 0 not its own,
 * else the exit status. */
static int parse_option(void *ctx, int argc, char **argv, int *i)
{
    Options *o = ctx;
    const char *value = NULL;
    int m, rc = 0;
    if ((m = app_option(argc, argv, i, "--dt", &value)) != 0) {
        if (m > 0)
            rc = parse_values(o, "--dt", value, 0);
    } else if ((m = app_option(argc, argv, i, "--steps-per-contact", &value)) != 0) {
        if (m > 0)
            rc = parse_values(o, "--steps-per-contact", value, 1);
    } else if ((m = app_option(argc, argv, i, "--observe", &value)) != 0) {
        if (m > 0)
            rc = parse_keys(o, value);
    } else if ((m = app_option(argc, argv, i, "--seeds", &value)) != 0) {
        if (m < 0 || app_parse_count(value, 2, 10000, &o->seeds) < 0)
            return usage_error("--seeds needs a count in [2, 10000], got",
                               m < 0 ? "nothing" : value);
    } else if ((m = app_option(argc, argv, i, "--seed0", &value)) != 0) {
        if (m < 0 || app_parse_count(value, 0, 1000000000, &o->seed0) < 0)
            return usage_error("--seed0 needs a seed in [0, 1e9], got", m < 0 ? "nothing" : value);
    } else {
        return 0;
    }
    return m < 0 ? 2 : rc != 0 ? rc : 1;
}

static int parse_options(Options *o, int argc, char **argv)
{
    o->seeds = 5;
    o->seed0 = 1;
    int rc = app_driver_parse(&ENSEMBLE_SPEC, argc, argv, &o->d, parse_option, o);
    if (rc != 0)
        return rc;
    o->scene_path = o->d.scene;
    o->out_dir = o->d.out;
    if (o->value_count == 0)
        return usage_error("missing --dt LIST or --steps-per-contact LIST", NULL);
    if (o->key_count == 0)
        return usage_error("missing --observe KEY[,KEY...]", NULL);
    if (!o->out_dir) {
        app_driver_default_out("ensemble", o->scene_path, o->default_out, sizeof o->default_out);
        o->out_dir = o->default_out;
    }
    return 0;
}

/* ---------------------------------------------------------------- members */

static double level_value(const Ensemble *E, int member)
{
    return E->levels[member / E->o->seeds].value;
}

static long member_seed(const Ensemble *E, int member)
{
    return E->o->seed0 + member % E->o->seeds;
}

static void member_dir(const Ensemble *E, int member, char *dir, size_t size)
{
    snprintf(dir, size, "%s/%s=%.10g/seed-%ld", E->o->out_dir,
             E->o->by_steps ? "steps_per_contact" : "dt", level_value(E, member),
             member_seed(E, member));
}

/* The --set values of the member at `value` with `seed`, after the command line's and the
 * family's (AppExperiment.member): in buffers[3][80], pointers appended to sets. Returns
 * the new count. */
static int member_sets(const Options *o, const AppExperiment *family, double value, long seed,
                       const char **sets, char buffers[3][80])
{
    int n = 0;
    for (int k = 0; k < o->d.set_count; ++k)
        sets[n++] = o->d.sets[k];
    for (int k = 0; family && family->member->sets && family->member->sets[k]; ++k)
        sets[n++] = family->member->sets[k];
    snprintf(buffers[0], 80, "seed=%ld", seed);
    sets[n++] = buffers[0];
    if (o->by_steps) {
        snprintf(buffers[1], 80, "time.dt=0");
        snprintf(buffers[2], 80, "time.steps_per_contact=%.17g", value);
        sets[n++] = buffers[1];
        sets[n++] = buffers[2];
    } else {
        snprintf(buffers[1], 80, "time.dt=%.17g", value);
        sets[n++] = buffers[1];
    }
    return n;
}

/* The family of the scene that names a member command (AppExperiment.member), or NULL
 * (members are `sablier run`). 0, or the exit status when the scene does not load. */
static int member_family(Ensemble *E)
{
    const Options *o = E->o;
    char err[4096] = "";
    Scene *scene = scene_load(o->scene_path, o->d.sets, o->d.set_count, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    E->family = NULL;
    for (int k = 0; app_experiments[k]; ++k)
        if (app_experiments[k]->member && scene_experiment_state(scene, app_experiments[k]) &&
            !E->family)
            E->family = app_experiments[k];
    scene_free(scene);
    return 0;
}

/* The scene at each value, loaded as its first member would see it: a bad --set, a time step
 * the scene refuses or a stage with its own dt is an error before anything runs. Fills the
 * levels, sorted by dt. 0, or the exit status. */
static int resolve_levels(Ensemble *E)
{
    const Options *o = E->o;
    int rc = member_family(E);
    if (rc != 0)
        return rc;
    for (int v = 0; v < o->value_count; ++v) {
        const char *sets[APP_MAX_SETS];
        char buffers[3][80], err[4096] = "";
        int n = member_sets(o, E->family, o->values[v], o->seed0, sets, buffers);
        Scene *scene = scene_load(o->scene_path, sets, n, err, sizeof err);
        if (!scene) { /* a time step the scene (or its family, at parse) refuses */
            fprintf(stderr, "sablier: ensemble: %s %g: %s\n",
                    o->by_steps ? "--steps-per-contact" : "--dt", o->values[v], err);
            return 2;
        }
        for (int k = 0; !E->family && k < scene->stage_count; ++k)
            if (scene->stages[k].time_step != scene->def.time_step) {
                fprintf(stderr,
                        "sablier: ensemble: %s: stage `%s` sets its own time.dt (%g s), which "
                        "%s does not reach; remove it or pass --set stages.%s.time.dt=...\n",
                        o->scene_path, scene->stages[k].name, scene->stages[k].time_step,
                        o->by_steps ? "--steps-per-contact" : "--dt", scene->stages[k].name);
                scene_free(scene);
                return 2;
            }
        SimTiming t;
        if (E->family && E->family->member->timing) {
            t = E->family->member->timing(scene_experiment_state(scene, E->family), scene);
        } else {
            SimWorldDef def = scene_world_def(scene, scene->stage_count - 1);
            t = sim_world_def_timing(&def);
        }
        scene_free(scene);
        for (int k = 0; k < v; ++k)
            if (E->levels[k].dt == t.time_step) {
                fprintf(stderr,
                        "sablier: ensemble: --steps-per-contact %g and %g give the same time step "
                        "%g s: it is capped at half the stability limit (%g s); list fewer, or "
                        "use --dt (up to the stability limit)\n",
                        E->levels[k].value, o->values[v], t.time_step, t.stability_limit);
                return 2;
            }
        Level level = {
            .value = o->values[v], .dt = t.time_step, .per_contact = t.steps_per_contact};
        int at = v; /* insertion: by dt, finest first */
        while (at > 0 && E->levels[at - 1].dt > level.dt) {
            E->levels[at] = E->levels[at - 1];
            --at;
        }
        E->levels[at] = level;
    }
    E->level_count = o->value_count;
    return 0;
}

/* argv of member `member` in E->argv (the strings in E->argv_text). 0, or -1 when too long. */
static int member_argv(Ensemble *E, int member)
{
    const Options *o = E->o;
    char dir[ENS_PATH], buffers[3][80];
    const char *sets[APP_MAX_SETS];
    member_dir(E, member, dir, sizeof dir);
    int set_count =
        member_sets(o, E->family, level_value(E, member), member_seed(E, member), sets, buffers);
    const char *words[ENS_ARGV];
    int n = 0;
    const char *command = E->family ? E->family->member->command : "run";
    const char *head[] = {"sablier", command, o->scene_path, "--out", dir, "--quiet"};
    for (size_t k = 0; k < sizeof head / sizeof head[0]; ++k)
        words[n++] = head[k];
    const char *threads = app_pool_member_threads((int)o->d.jobs);
    if (strcmp(command, "run") == 0 && threads) { /* side by side: one thread each */
        words[n++] = "--threads";
        words[n++] = threads;
    }
    for (int k = 0; k < set_count; ++k) {
        words[n++] = app_set_option_name(sets[k]);
        words[n++] = sets[k];
    }
    for (int k = 0; k < n; ++k) {
        if (strlen(words[k]) >= ENS_PATH)
            return -1;
        snprintf(E->argv_text[k], ENS_PATH, "%s", words[k]);
        E->argv[k] = E->argv_text[k];
    }
    E->argv[n] = NULL;
    return 0;
}

/* Parent, before member k's fork: its folder and command line (a failure skips it). */
static int member_start(void *ctx, int k)
{
    Ensemble *E = ctx;
    char dir[ENS_PATH];
    member_dir(E, k, dir, sizeof dir);
    if (app_make_dirs(dir) != 0 || member_argv(E, k) != 0) {
        fprintf(stderr, "sablier: ensemble: cannot start the member in %s\n", dir);
        E->status[k] = 2;
        return 1;
    }
    return 0;
}

/* Child: runs the member as a process of its own (output to DIR/log.txt), waits for it and
 * writes its CPU time (user + system) to DIR/cpu_seconds.txt. Returns its exit status. */
static int member_run(void *ctx, int k)
{
    Ensemble *E = ctx;
    char dir[ENS_PATH], path[ENS_PATH + 32];
    member_dir(E, k, dir, sizeof dir);
    app_driver_log_to(dir);
    struct rusage usage;
    int status = app_pool_exec_wait(E->o->self, E->argv, &usage);
    if (status < 0) {
        fprintf(stderr, "sablier: ensemble: cannot run %s: %s\n", E->o->self, strerror(errno));
        return 2;
    }
    double cpu = (double)usage.ru_utime.tv_sec + 1e-6 * (double)usage.ru_utime.tv_usec +
                 (double)usage.ru_stime.tv_sec + 1e-6 * (double)usage.ru_stime.tv_usec;
    char text[64];
    snprintf(text, sizeof text, "%.6f\n", cpu);
    snprintf(path, sizeof path, "%s/cpu_seconds.txt", dir);
    if (app_write_atomic(path, text) != 0)
        fprintf(stderr, "sablier: ensemble: cannot write %s\n", path);
    return status;
}

static void member_progress(void *ctx, int k, int status, char *line, size_t size)
{
    char dir[ENS_PATH];
    member_dir(ctx, k, dir, sizeof dir);
    snprintf(line, size, "%s: %s", dir,
             status == 0                      ? "ok"
             : status == 1                    ? "unstable"
             : status == APP_POOL_INTERRUPTED ? "interrupted"
                                              : "failed (see its log.txt)");
}

static int member_folder(void *ctx, int k, char *dir, size_t size)
{
    member_dir(ctx, k, dir, size);
    return 0;
}

/* The members through the pool: 0, 2 when a fork failed, or 128 + the signal that stopped it. */
static int run_members(Ensemble *E)
{
    if (!E->o->d.quiet)
        fprintf(stderr, "sablier: ensemble: %d members (%d time steps x %ld seeds), %d at a time\n",
                E->member_count, E->level_count, E->o->seeds, app_pool_width((int)E->o->d.jobs));
    AppDriverPool pool = {.command = "ensemble",
                          .not_started = "cannot start a member",
                          .count = E->member_count,
                          .jobs = E->o->d.jobs,
                          .resume = E->o->d.resume,
                          .signal_status = 1,
                          .quiet = E->o->d.quiet,
                          .ctx = E,
                          .status = E->status,
                          .start = member_start,
                          .run = member_run,
                          .folder = member_folder,
                          .progress = member_progress};
    int rc = app_driver_pool_run(&pool);
    return rc == 0 || rc > APP_EXIT_SIGNAL ? rc : 2;
}

/* ---------------------------------------------------------------- reduction */

/* Reads every successful member's CPU time and observables. */
static void read_members(Ensemble *E)
{
    const Options *o = E->o;
    for (int k = 0; k < E->member_count; ++k) {
        char dir[ENS_PATH], path[ENS_PATH + 32], err[ENS_PATH + 256];
        member_dir(E, k, dir, sizeof dir);
        E->cpu[k] = NAN;
        for (int j = 0; j < o->key_count; ++j)
            E->value[k * o->key_count + j] = NAN;
        if (E->status[k] != 0)
            continue;
        snprintf(path, sizeof path, "%s/cpu_seconds.txt", dir);
        FILE *f = sim_open_input(path, NULL);
        if (!f || fscanf(f, "%lf", &E->cpu[k]) != 1)
            E->cpu[k] = NAN;
        if (f)
            fclose(f);
        for (int j = 0; j < o->key_count; ++j)
            if (app_run_value(dir, o->keys[j], &E->value[k * o->key_count + j], err, sizeof err) <
                0) {
                fprintf(stderr, "sablier: ensemble: --observe %s: %s\n", o->keys[j], err);
                ++E->missing;
            }
    }
}

/* Each level's samples, shifts against level 0 and mean CPU time. */
static void reduce(Ensemble *E)
{
    const Options *o = E->o;
    int seeds = (int)o->seeds;
    double *x = malloc((size_t)seeds * sizeof *x);
    if (!x)
        return;
    for (int v = 0; v < E->level_count; ++v) {
        Level *L = &E->levels[v];
        double cpu = 0.0;
        int timed = 0;
        L->ok = L->failed = 0;
        for (int s = 0; s < seeds; ++s) {
            int k = v * seeds + s;
            L->ok += E->status[k] == 0;
            L->failed += E->status[k] != 0;
            if (E->status[k] == 0 && isfinite(E->cpu[k])) {
                cpu += E->cpu[k];
                ++timed;
            }
        }
        L->cpu_mean = timed ? cpu / timed : (double)NAN;
        for (int j = 0; j < o->key_count; ++j) {
            for (int s = 0; s < seeds; ++s)
                x[s] = E->value[(v * seeds + s) * o->key_count + j];
            L->sample[j] = app_sample_stats(x, seeds, ENS_LEVEL);
        }
    }
    for (int v = 0; v < E->level_count; ++v)
        for (int j = 0; j < o->key_count; ++j)
            E->levels[v].shift[j] =
                v == 0
                    ? (AppShift){.shift = 0.0, .half = 0.0, .dof = NAN, .significant = 0}
                    : app_welch_shift(&E->levels[v].sample[j], &E->levels[0].sample[j], ENS_LEVEL);
    free(x);
}

/* ---------------------------------------------------------------- outputs */

static void csv_number(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, ",%.9g", v);
    else
        fprintf(f, ",nan");
}

static int write_members_csv(const Ensemble *E, const char *path)
{
    const Options *o = E->o;
    FILE *f = app_tmp_open(path, NULL);
    if (!f)
        return -1;
    fprintf(f, "dt_s,steps_per_contact,seed,status,cpu_s");
    for (int j = 0; j < o->key_count; ++j)
        fprintf(f, ",%s", o->keys[j]);
    fprintf(f, "\n");
    for (int k = 0; k < E->member_count; ++k) {
        const Level *L = &E->levels[k / o->seeds];
        char status[16];
        fprintf(f, "%.9g,%.9g,%ld,%s", L->dt, L->per_contact, member_seed(E, k),
                app_pool_status_text(E->status[k], status));
        csv_number(f, E->cpu[k]);
        for (int j = 0; j < o->key_count; ++j)
            csv_number(f, E->value[k * o->key_count + j]);
        fprintf(f, "\n");
    }
    return app_tmp_commit(&f, path);
}

static int write_ensemble_csv(const Ensemble *E, const char *path)
{
    FILE *f = app_tmp_open(path, "observable,dt_s,steps_per_contact,n,mean,std,ci95,shift,"
                                 "shift_ci95,welch_dof,within,cpu_s_mean");
    if (!f)
        return -1;
    for (int j = 0; j < E->o->key_count; ++j)
        for (int v = 0; v < E->level_count; ++v) {
            const Level *L = &E->levels[v];
            const AppSample *s = &L->sample[j];
            const AppShift *d = &L->shift[j];
            fprintf(f, "%s,%.9g,%.9g,%d", E->o->keys[j], L->dt, L->per_contact, s->n);
            csv_number(f, s->mean);
            csv_number(f, s->std);
            csv_number(f, s->half);
            csv_number(f, d->shift);
            csv_number(f, d->half);
            csv_number(f, d->dof);
            fprintf(f, d->significant < 0 ? "," : ",%d", !d->significant);
            csv_number(f, L->cpu_mean);
            fprintf(f, "\n");
        }
    return app_tmp_commit(&f, path);
}

/* JSON members "name": number, for the numbers of one row. */
static void json_pair(FILE *f, const char *name, double v, const char *tail)
{
    char text[40];
    app_json_number(text, sizeof text, v);
    fprintf(f, "\"%s\": %s%s", name, text, tail);
}

static void json_observable(const Ensemble *E, FILE *f, int j)
{
    char key[2 * ENS_KEY];
    app_json_string(key, sizeof key, E->o->keys[j]);
    AppShift shifts[ENS_LEVELS];
    for (int v = 0; v < E->level_count; ++v)
        shifts[v] = E->levels[v].shift[j];
    int until = app_shift_within_until(shifts, E->level_count);
    fprintf(f, "    {\"key\": %s, ", key);
    json_pair(f, "within_from_dt_s", until > 0 ? E->levels[until].dt : (double)NAN, ", ");
    json_pair(f, "within_from_steps_per_contact",
              until > 0 ? E->levels[until].per_contact : (double)NAN, ",\n     \"rows\": [");
    for (int v = 0; v < E->level_count; ++v) {
        const Level *L = &E->levels[v];
        const AppSample *s = &L->sample[j];
        const AppShift *d = &L->shift[j];
        fprintf(f, "%s\n       {", v ? "," : "");
        json_pair(f, "dt_s", L->dt, ", ");
        fprintf(f, "\"n\": %d, ", s->n);
        json_pair(f, "mean", s->mean, ", ");
        json_pair(f, "std", s->std, ", ");
        json_pair(f, "ci95", s->half, ", ");
        json_pair(f, "shift", d->shift, ", ");
        json_pair(f, "shift_ci95", d->half, ", ");
        json_pair(f, "welch_dof", d->dof, ", ");
        fprintf(f, "\"within\": %s}",
                d->significant < 0 ? "null"
                : d->significant   ? "false"
                                   : "true");
    }
    fprintf(f, "\n     ]}");
}

static int write_ensemble_json(const Ensemble *E, const char *path)
{
    const Options *o = E->o;
    FILE *f = app_tmp_open(path, NULL);
    if (!f)
        return -1;
    char scene[2 * SCENE_PATH_MAX];
    app_json_string(scene, sizeof scene, o->scene_path);
    fprintf(f,
            "{\n  \"scene\": %s,\n  \"by\": \"%s\",\n  \"seeds\": %ld,\n"
            "  \"seed0\": %ld,\n  \"confidence\": %.2f,\n  \"reference\": {",
            scene, o->by_steps ? "steps_per_contact" : "dt", o->seeds, o->seed0, ENS_LEVEL);
    json_pair(f, "dt_s", E->levels[0].dt, ", ");
    json_pair(f, "steps_per_contact", E->levels[0].per_contact, "},\n  \"levels\": [");
    for (int v = 0; v < E->level_count; ++v) {
        const Level *L = &E->levels[v];
        fprintf(f, "%s\n    {", v ? "," : "");
        json_pair(f, "value", L->value, ", ");
        json_pair(f, "dt_s", L->dt, ", ");
        json_pair(f, "steps_per_contact", L->per_contact, ", ");
        fprintf(f, "\"members_ok\": %d, \"members_failed\": %d, ", L->ok, L->failed);
        json_pair(f, "cpu_s_mean", L->cpu_mean, "}");
    }
    fprintf(f, "\n  ],\n  \"observables\": [\n");
    for (int j = 0; j < o->key_count; ++j) {
        json_observable(E, f, j);
        fprintf(f, j + 1 < o->key_count ? ",\n" : "\n");
    }
    fprintf(f, "  ]\n}\n");
    return app_tmp_commit(&f, path);
}

/* The answer line of observable j on stdout. */
static void print_answer(const Ensemble *E, int j)
{
    AppShift shifts[ENS_LEVELS];
    for (int v = 0; v < E->level_count; ++v)
        shifts[v] = E->levels[v].shift[j];
    int until = app_shift_within_until(shifts, E->level_count);
    const Level *ref = &E->levels[0];
    const char *key = E->o->keys[j];
    if (until > 0)
        printf("%s: from dt = %.6g s on (steps per contact >= %.4g), the mean stays within its "
               "statistical error of the reference (dt = %.6g s, mean %.6g +- %.3g)",
               key, E->levels[until].dt, E->levels[until].per_contact, ref->dt, ref->sample[j].mean,
               ref->sample[j].half);
    else
        printf("%s: no dt of the list but the reference (dt = %.6g s) keeps the mean within its "
               "statistical error",
               key, ref->dt);
    if (until + 1 < E->level_count) {
        const Level *L = &E->levels[until + 1];
        if (shifts[until + 1].significant < 0)
            printf("; at dt = %.6g s fewer than 2 members gave a value\n", L->dt);
        else
            printf("; dt = %.6g s moves it by %.4g +- %.3g (95 %%)\n", L->dt,
                   shifts[until + 1].shift, shifts[until + 1].half);
    } else {
        printf(" (every dt of the list)\n");
    }
}

/* ---------------------------------------------------------------- the figure */

typedef struct Figure {
    AppPlotPanel panels[ENS_KEYS];
    AppPlotSeries series[ENS_KEYS][ENS_LEVELS + 1];
    double x[ENS_LEVELS], y[ENS_KEYS][ENS_LEVELS], err[ENS_KEYS][ENS_LEVELS];
    double zero_x[2], zero_y[2];
    char labels[ENS_LEVELS][96];
} Figure;

/* Panel j of the figure: the zero line, then one point with its interval per dt (the legend, in
 * panel 0, gets room above the points). */
static void figure_panel(const Ensemble *E, Figure *F, int j)
{
    static const AppMarker markers[] = {APP_MARKER_CIRCLE, APP_MARKER_SQUARE, APP_MARKER_TRIANGLE,
                                        APP_MARKER_CROSS};
    AppPlotSeries *s = F->series[j];
    s[0] = (AppPlotSeries){
        .count = 2, .x = F->zero_x, .y = F->zero_y, .line = 1, .dashed = 1, .rgb = 0x808080};
    double lo = 0.0, hi = 0.0;
    for (int v = 0; v < E->level_count; ++v) {
        F->y[j][v] = E->levels[v].shift[j].shift;
        F->err[j][v] = v == 0 ? E->levels[0].sample[j].half : E->levels[v].shift[j].half;
        double e = isfinite(F->err[j][v]) ? F->err[j][v] : 0.0;
        if (isfinite(F->y[j][v])) {
            lo = fmin(lo, F->y[j][v] - e);
            hi = fmax(hi, F->y[j][v] + e);
        }
        s[v + 1] = (AppPlotSeries){.label = j == 0 ? F->labels[v] : NULL,
                                   .count = 1,
                                   .x = &F->x[v],
                                   .y = &F->y[j][v],
                                   .y_err = &F->err[j][v],
                                   .marker = markers[v % 4],
                                   .rgb = APP_RGB_AUTO};
    }
    double span = hi > lo ? hi - lo : fmax(fabs(hi), 1e-12);
    F->panels[j] = (AppPlotPanel){.title = E->o->keys[j],
                                  .x_label = "CPU time per member (s)",
                                  .y_label = "shift of the mean (the observable's unit)",
                                  .x_log = 1,
                                  .legend = j == 0 ? APP_LEGEND_UPPER_LEFT : APP_LEGEND_NONE,
                                  .x_min = pow(10.0, floor(log10(F->zero_x[0] / 1.3))),
                                  .x_max = pow(10.0, ceil(log10(F->zero_x[1] * 1.3))),
                                  .y_min = lo - 0.05 * span,
                                  .y_max = hi + (j == 0 ? 0.1 + 0.2 * E->level_count : 0.05) * span,
                                  .series_count = E->level_count + 1,
                                  .series = s};
}

/* ensemble.png and ensemble.pdf: per observable, the shift of the mean at each dt with its
 * interval (the reference: 0 with its own interval) against the CPU time per member, log x. */
static void write_figure(const Ensemble *E)
{
    const Options *o = E->o;
    if (!o->render || !o->render->plot)
        return;
    Figure *F = calloc(1, sizeof *F);
    if (!F)
        return;
    double lo = INFINITY, hi = -INFINITY;
    for (int v = 0; v < E->level_count; ++v) {
        const Level *L = &E->levels[v];
        F->x[v] = isfinite(L->cpu_mean) ? fmax(L->cpu_mean, 1e-6) : (double)NAN;
        lo = fmin(lo, F->x[v]);
        hi = fmax(hi, F->x[v]);
        snprintf(F->labels[v], sizeof F->labels[v], "dt = %.3g s, %.3g steps/contact%s", L->dt,
                 L->per_contact, v == 0 ? " (reference)" : "");
    }
    F->zero_x[0] = isfinite(lo) ? lo : 1e-3;
    F->zero_x[1] = isfinite(hi) ? hi : 1.0;
    for (int j = 0; j < o->key_count; ++j)
        figure_panel(E, F, j);
    int cols = o->key_count <= 3 ? o->key_count : 2, rows = (o->key_count + cols - 1) / cols;
    char title[256];
    snprintf(title, sizeof title,
             "Ensemble of %ld seeds: shift of the mean against dt = %.3g s, 95 %% intervals",
             o->seeds, E->levels[0].dt);
    AppPlot plot = {.title = title,
                    .width = cols == 1 ? 1000 : 160 + 620 * cols,
                    .height = 100 + 540 * rows,
                    .rows = rows,
                    .cols = cols,
                    .panel_count = o->key_count,
                    .panels = F->panels,
                    .scene = o->scene_path,
                    .data_beside = 1}; /* ensemble.csv */
    static const char *const names[] = {"ensemble.png", "ensemble.pdf"};
    for (int k = 0; k < 2; ++k) {
        char path[ENS_PATH + 16], err[512] = "";
        snprintf(path, sizeof path, "%s/%s", o->out_dir, names[k]);
        if (o->render->plot(o->render->context, &plot, path, err, sizeof err) != 0)
            fprintf(stderr, "sablier: ensemble: %s: %s\n", path, err);
    }
    free(F);
}

/* ---------------------------------------------------------------- the command */

/* Tables, figure and answers of the members that ran. 0, or 2 when a table cannot be written. */
static int write_outputs(Ensemble *E)
{
    static const char *const names[] = {"members.csv", "ensemble.csv", "ensemble.json"};
    int (*const writers[])(const Ensemble *, const char *) = {write_members_csv, write_ensemble_csv,
                                                              write_ensemble_json};
    int rc = 0;
    for (int k = 0; k < 3; ++k) {
        char path[ENS_PATH + 16];
        snprintf(path, sizeof path, "%s/%s", E->o->out_dir, names[k]);
        if (writers[k](E, path) != 0) {
            fprintf(stderr, "sablier: ensemble: cannot write %s\n", path);
            rc = 2;
        }
    }
    write_figure(E);
    for (int j = 0; j < E->o->key_count; ++j)
        print_answer(E, j);
    return rc;
}

/* The exit status of the members: 0, 1 when one went unstable, else 2 when one failed. */
static int members_status(const Ensemble *E)
{
    int rc = 0;
    for (int k = 0; k < E->member_count; ++k)
        if (E->status[k] == 1)
            return 1;
        else if (E->status[k] != 0)
            rc = 2;
    return rc;
}

int app_ensemble_parse(int argc, char **argv)
{
    Options *o = calloc(1, sizeof *o);
    int rc = o ? parse_options(o, argc, argv) : 2;
    free(o);
    return rc;
}

int app_ensemble_command(int argc, char **argv, const AppEnv *env)
{
    Options *o = calloc(1, sizeof *o);
    Ensemble *E = calloc(1, sizeof *E);
    int rc = o && E ? parse_options(o, argc, argv) : 2;
    if (rc == 0) {
        o->self = env->self;
        o->render = env->render;
        E->o = o;
        rc = resolve_levels(E);
    }
    if (rc == 0 && app_make_dirs(o->out_dir) != 0) {
        fprintf(stderr, "sablier: ensemble: cannot create %s\n", o->out_dir);
        rc = 2;
    }
    if (rc == 0) {
        E->member_count = E->level_count * (int)o->seeds;
        E->status = calloc((size_t)E->member_count, sizeof *E->status);
        E->cpu = calloc((size_t)E->member_count, sizeof *E->cpu);
        E->value = calloc((size_t)E->member_count * (size_t)o->key_count, sizeof *E->value);
        rc = E->status && E->cpu && E->value ? run_members(E) : 2;
    }
    if (rc == 0 || rc > APP_EXIT_SIGNAL) { /* interrupted: the finished members' tables */
        int interrupted = rc;
        read_members(E);
        reduce(E);
        rc = write_outputs(E);
        int members = members_status(E);
        rc = interrupted ? interrupted : members ? members : rc ? rc : E->missing ? 2 : 0;
    }
    if (E) {
        free(E->status);
        free(E->cpu);
        free(E->value);
    }
    free(E);
    free(o);
    return rc;
}
