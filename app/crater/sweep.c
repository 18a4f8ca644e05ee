/* SPDX-License-Identifier: MIT */
/* sweep.c: `sablier sweep`. Members are child processes (fork + exec of sablier itself), so a
 * member's outputs are those of the same `sablier run` command line whatever the job count. */
#include "sweep.h"

#include "base/config.h"
#include "base/util.h"
#include "driver/driver.h"
#include "driver/pool.h"
#include "run/run.h"
#include "scene/scene.h"
#include "sim/sim.h"

#include <errno.h>
#include <libconfig.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAX_MEMBERS  64
#define MAX_SETS     48
#define MAX_VARY     4
#define MAX_VALUES   32
#define SWEEP_PATH   2048
#define SWEEP_STRING 256
/* one --vary or `vary` list: a key and MAX_VALUES values of up to 64 characters */
#define VARY_STRING  (SWEEP_STRING + MAX_VALUES * 65)

typedef struct Member {
    char label[64];
    int line; /* of its group in the sweep file (0: from --vary) */
    double value;
    int set_count;
    char sets[MAX_SETS][SWEEP_STRING];
    char dir[SWEEP_PATH];
    int status; /* exit status; -1 not run, APP_POOL_INTERRUPTED */
    double started, wall_seconds;
} Member;

typedef struct Sweep {
    const AppCraterSweepOptions *o;
    char scene_path[SWEEP_PATH];
    char name[SCENE_NAME_MAX];
    char parameter[64];          /* the x label of crater_height.png with its unit */
    char vary_key[SWEEP_STRING]; /* the first varied key (the members' `value`) */
    char out_dir[SWEEP_PATH];
    int set_count; /* the definition's `set`, for members only */
    char sets[MAX_SETS][SWEEP_STRING];
    int member_count;
    Member *members;
    char bed_name[SCENE_NAME_MAX]; /* the definition's `bed_stage` */
    char stage_names[SCENE_MAX_STAGES][SCENE_NAME_MAX];
    int stage_count, bed_stage;
    char bed_state[SWEEP_PATH];
    SceneStyle print; /* the scene's `render` keys with --set: the comparison plots' print size
                       * and render.plot_format (docs/figures.md#plots) */
} Sweep;

AppCraterSweepOptions app_crater_sweep_options_default(void)
{
    AppCraterSweepOptions o;
    memset(&o, 0, sizeof o);
    o.jobs = 2;
    return o;
}

/* "0.5 wide" -> "0.5-wide": safe in a folder name. */
static void slug(char *out, size_t size, const char *label)
{
    size_t n = 0;
    for (const char *c = label; *c && n + 1 < size; ++c) {
        int ok = (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') ||
                 *c == '.' || *c == '_' || *c == '-';
        out[n++] = ok ? *c : '-';
    }
    out[n] = '\0';
}

static int add_set(char sets[][SWEEP_STRING], int *count, const char *text)
{
    if (*count >= MAX_SETS || strlen(text) >= SWEEP_STRING)
        return -1;
    snprintf(sets[(*count)++], SWEEP_STRING, "%s", text);
    return 0;
}

/* ---------------------------------------------------------------- definition file */

static int read_string_array(AppConfig *p, const config_setting_t *a, char sets[][SWEEP_STRING],
                             int *count)
{
    if (!a)
        return 0;
    if (config_setting_type(a) != CONFIG_TYPE_ARRAY)
        return app_config_fail(p, a, "`set` must be an array of \"KEY=VALUE\" strings");
    for (int k = 0; k < config_setting_length(a); ++k) {
        const config_setting_t *e = config_setting_get_elem(a, (unsigned)k);
        const char *text = config_setting_get_string(e);
        if (!text || !strchr(text, '='))
            return app_config_fail(p, e, "`set` elements are \"KEY=VALUE\" strings");
        if (add_set(sets, count, text) != 0)
            return app_config_fail(p, e, "too many or too long `set` elements");
    }
    return 0;
}

/* The definition's `members` list (may be NULL): a member per group. 0, or -1 with the message
 * in p. */
static int read_members(AppConfig *p, const config_setting_t *members, Sweep *w)
{
    static const char *const member_keys[] = {"label", "value", "set", NULL};
    const char *text;
    int rc = 0;
    if (!members)
        return 0;
    if (config_setting_type(members) != CONFIG_TYPE_LIST)
        rc = app_config_fail(p, members, "`members` must be a list of groups ( {...}, ... )");
    for (int k = 0; rc == 0 && k < config_setting_length(members); ++k) {
        const config_setting_t *g = config_setting_get_elem(members, (unsigned)k);
        if (w->member_count >= MAX_MEMBERS) {
            rc = app_config_fail(p, g, "too many members");
            break;
        }
        Member *m = &w->members[w->member_count];
        memset(m, 0, sizeof *m);
        m->value = (double)k;
        const config_setting_t *value = config_setting_get_member(g, "value");
        if (config_setting_type(g) != CONFIG_TYPE_GROUP ||
            app_config_keys(p, g, NULL, member_keys, NULL) ||
            !config_setting_lookup_string(g, "label", &text)) {
            rc = app_config_fail(p, g, "a member is { label = \"...\"; value = x; set = [...]; }");
            break;
        }
        snprintf(m->label, sizeof m->label, "%s", text);
        m->line = config_setting_source_line(g);
        if (value && app_config_number_of(p, value, "value", &m->value) < 0)
            rc = -1;
        if (rc == 0)
            rc = read_string_array(p, config_setting_get_member(g, "set"), m->sets, &m->set_count);
        w->member_count++;
    }
    return rc;
}

/* The definition's `vary` list (may be NULL): a "KEY=v1,v2,..." line per element in vary. 0, or
 * -1 with the message in p. */
static int read_vary(AppConfig *p, const config_setting_t *v, char vary[][VARY_STRING],
                     int *vary_count)
{
    static const char *const vary_keys[] = {"key", "values", NULL};
    const char *text;
    int rc = 0;
    if (!v)
        return 0;
    if (config_setting_type(v) != CONFIG_TYPE_LIST)
        rc = app_config_fail(p, v, "`vary` must be a list ( { key = \"...\"; values = [...]; } )");
    for (int k = 0; rc == 0 && k < config_setting_length(v); ++k) {
        const config_setting_t *g = config_setting_get_elem(v, (unsigned)k);
        const config_setting_t *values = config_setting_get_member(g, "values");
        if (config_setting_type(g) != CONFIG_TYPE_GROUP ||
            app_config_keys(p, g, NULL, vary_keys, NULL) ||
            !config_setting_lookup_string(g, "key", &text) || !values ||
            config_setting_type(values) != CONFIG_TYPE_ARRAY || *vary_count >= MAX_VARY) {
            rc =
                app_config_fail(p, g, "a vary element is { key = \"...\"; values = [a, b, ...]; }");
            break;
        }
        char *out = vary[(*vary_count)++];
        size_t n = (size_t)snprintf(out, VARY_STRING, "%s=", text);
        if (config_setting_length(values) > MAX_VALUES || n >= SWEEP_STRING) {
            rc = app_config_fail(p, g, "at most %d values per key (got %d)", MAX_VALUES,
                                 config_setting_length(values));
            break;
        }
        for (int j = 0; j < config_setting_length(values); ++j) {
            double x;
            if (app_config_number_of(p, config_setting_get_elem(values, (unsigned)j), "values",
                                     &x) < 0) {
                rc = -1;
                break;
            }
            n += (size_t)snprintf(out + n, VARY_STRING - n, "%s%.10g", j ? "," : "", x);
        }
    }
    return rc;
}

static int read_definition(Sweep *w, const char *file, char vary[][VARY_STRING], int *vary_count)
{
    static const char *const keys[] = {"scene",   "bed_stage", "parameter", "set",
                                       "members", "vary",      NULL};
    char err[2048];
    AppConfig p = {.path = file, .err = err, .err_size = sizeof err};
    config_t config;
    config_init(&config);
    int rc = 0;
    const char *why = NULL;
    FILE *in = sim_open_input(file, &why);
    if (!in) {
        fprintf(stderr, "sablier: sweep: cannot read %s: %s\n", file, why);
        config_destroy(&config);
        return -1;
    }
    int read = config_read(&config, in);
    fclose(in);
    if (read != CONFIG_TRUE) {
        fprintf(stderr, "%s:%d: %s\n",
                config_error_file(&config) ? config_error_file(&config) : file,
                config_error_line(&config), config_error_text(&config));
        config_destroy(&config);
        return -1;
    }
    const config_setting_t *root = config_root_setting(&config);
    const char *text;
    rc = app_config_keys(&p, root, NULL, keys, NULL);
    if (rc == 0 && config_setting_lookup_string(root, "scene", &text) && !w->o->scene_path) {
        /* relative to the definition's folder */
        const char *slash = strrchr(file, '/');
        if (text[0] == '/' || !slash)
            snprintf(w->scene_path, sizeof w->scene_path, "%s", text);
        else
            snprintf(w->scene_path, sizeof w->scene_path, "%.*s/%s", (int)(slash - file), file,
                     text);
    }
    if (rc == 0 && config_setting_lookup_string(root, "parameter", &text))
        snprintf(w->parameter, sizeof w->parameter, "%s", text);
    if (rc == 0 && config_setting_lookup_string(root, "bed_stage", &text) && !w->o->bed_stage)
        snprintf(w->bed_name, sizeof w->bed_name, "%s", text);
    if (rc == 0)
        rc = read_string_array(&p, config_setting_get_member(root, "set"), w->sets, &w->set_count);
    if (rc == 0)
        rc = read_members(&p, config_setting_get_member(root, "members"), w);
    if (rc == 0)
        rc = read_vary(&p, config_setting_get_member(root, "vary"), vary, vary_count);
    if (rc != 0)
        fprintf(stderr, "%s\n", err);
    config_destroy(&config);
    return rc;
}

/* Members from "KEY=v1,v2" lists: one per combination (first key slowest). */
static int expand_vary(Sweep *w, char vary[][VARY_STRING], int vary_count)
{
    char keys[MAX_VARY][SWEEP_STRING], values[MAX_VARY][MAX_VALUES][64];
    int counts[MAX_VARY], total = 1;
    for (int v = 0; v < vary_count; ++v) {
        char *eq = strchr(vary[v], '=');
        if (!eq || eq == vary[v] || !eq[1]) {
            fprintf(stderr, "sablier: sweep: --vary needs KEY=v1,v2,..., got `%s`\n", vary[v]);
            return -1;
        }
        if (eq - vary[v] >= SWEEP_STRING) {
            fprintf(stderr, "sablier: sweep: --vary key longer than %d characters\n",
                    SWEEP_STRING - 1);
            return -1;
        }
        snprintf(keys[v], sizeof keys[v], "%.*s", (int)(eq - vary[v]), vary[v]);
        counts[v] = 0;
        const char *list = eq + 1, *item;
        size_t length;
        while ((item = app_list_item(&list, &length)) != NULL) {
            if (length == 0) { /* ",,", a leading or trailing comma: no value */
                fprintf(stderr, "sablier: sweep: --vary %s: an empty value in the list\n", vary[v]);
                return -1;
            }
            if (counts[v] >= MAX_VALUES) {
                fprintf(stderr, "sablier: sweep: at most %d values per key\n", MAX_VALUES);
                return -1;
            }
            if (length >= 64) {
                fprintf(stderr, "sablier: sweep: --vary value %.20s... longer than 63 characters\n",
                        item);
                return -1;
            }
            snprintf(values[v][counts[v]++], 64, "%.*s", (int)length, item);
        }
        total *= counts[v];
    }
    if (vary_count == 0)
        return 0;
    if (w->member_count + total > MAX_MEMBERS) {
        fprintf(stderr, "sablier: sweep: at most %d members\n", MAX_MEMBERS);
        return -1;
    }
    for (int k = 0; k < total; ++k) {
        Member *m = &w->members[w->member_count++];
        memset(m, 0, sizeof *m);
        int rest = k;
        size_t n = 0;
        int index[MAX_VARY];
        for (int v = vary_count - 1; v >= 0; --v) {
            index[v] = rest % counts[v];
            rest /= counts[v];
        }
        for (int v = 0; v < vary_count; ++v) {
            const char *short_key = strrchr(keys[v], '.');
            short_key = short_key ? short_key + 1 : keys[v];
            n += (size_t)snprintf(m->label + n, sizeof m->label - (n < sizeof m->label ? n : 0),
                                  "%s%s=%s", v ? " " : "", short_key, values[v][index[v]]);
            if (n >= sizeof m->label)
                n = sizeof m->label - 1;
            char set[2 * SWEEP_STRING + 2]; /* KEY=VALUE, both at most SWEEP_STRING */
            snprintf(set, sizeof set, "%s=%s", keys[v], values[v][index[v]]);
            add_set(m->sets, &m->set_count, set);
        }
        char *end;
        m->value = strtod(values[0][index[0]], &end);
        if (*end)
            m->value = (double)index[0];
    }
    snprintf(w->vary_key, sizeof w->vary_key, "%s", keys[0]);
    return 0;
}

/* ---------------------------------------------------------------- processes */

/* A malloc'd copy of a formatted string (argv entries). */
static char *format(const char *a, const char *b)
{
    size_t n = strlen(a) + strlen(b) + 1;
    char *out = malloc(n);
    if (out)
        snprintf(out, n, "%s%s", a, b);
    return out;
}

static void free_argv(char **argv)
{
    for (int k = 0; argv[k]; ++k)
        free(argv[k]);
}

/* argv of `sablier run SCENE --out DIR --quiet [--threads 1] --set ...` (malloc'd strings, NULL
 * ended). Members side by side (--jobs, or the MPI ranks) run on one thread each, one at a time on
 * the threads `auto` gives them (app_pool_member_threads); so does the bed, which runs alone. */
static int member_argv(const Sweep *w, const Member *m, int bed_run, char **argv, int capacity)
{
    int n = 0;
    const char *fixed[] = {"sablier", "run", w->scene_path, "--out", m->dir, "--quiet"};
    for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; ++k)
        argv[n++] = format(fixed[k], "");
    const char *threads = bed_run ? NULL : app_pool_member_threads(w->o->jobs);
    if (threads) {
        argv[n++] = format("--threads", "");
        argv[n++] = format(threads, "");
    }
    const char *sets[3 * MAX_SETS + SCENE_MAX_STAGES + 1];
    char buffers[SCENE_MAX_STAGES + 1][SWEEP_PATH + 2 * SCENE_NAME_MAX];
    int count = 0, b = 0;
    for (int k = 0; k < w->o->set_count; ++k)
        sets[count++] = w->o->sets[k];
    if (!bed_run) {
        for (int k = 0; k < w->set_count; ++k)
            sets[count++] = w->sets[k];
        for (int k = 0; k < m->set_count; ++k)
            sets[count++] = m->sets[k];
    }
    for (int k = 0; k < w->stage_count; ++k)
        if (bed_run ? k > w->bed_stage : k <= w->bed_stage) {
            snprintf(buffers[b], sizeof buffers[b], "stages.%s.skip=true", w->stage_names[k]);
            sets[count++] = buffers[b++];
        }
    if (!bed_run && w->bed_state[0]) {
        snprintf(buffers[b], sizeof buffers[b], "stages.%s.load=%s",
                 w->stage_names[w->bed_stage + 1], w->bed_state);
        sets[count++] = buffers[b++];
    }
    for (int k = 0; k < count && n + 3 <= capacity; ++k) {
        argv[n++] = format(app_set_option_name(sets[k]), "");
        argv[n++] = format(sets[k], "");
    }
    argv[n] = NULL;
    for (int k = 0; k < n; ++k)
        if (!argv[k]) {
            for (int j = 0; j < n; ++j)
                free(argv[j]);
            argv[0] = NULL;
            return -1;
        }
    return n;
}

/* The pool of one run_members: the bed (bed_run = 1) or the members. */
typedef struct SweepRun {
    Sweep *w;
    Member *members;
    int bed_run;
    char *argv[3 * MAX_SETS * 2 + 32]; /* of the member being started; argv[0] NULL: none */
} SweepRun;

static void not_started(const SweepRun *run, Member *m)
{
    if (!run->bed_run)
        fprintf(stderr, "sablier: sweep: cannot start member %s in %s\n", m->label, m->dir);
    m->status = 2;
}

/* Parent, before member i's fork: its folder and command line. */
static int member_start(void *ctx, int i)
{
    SweepRun *run = ctx;
    Member *m = &run->members[i];
    if (run->argv[0])
        free_argv(run->argv);
    run->argv[0] = NULL;
    if (app_make_dirs(m->dir) != 0 ||
        member_argv(run->w, m, run->bed_run, run->argv,
                    (int)(sizeof run->argv / sizeof run->argv[0])) < 0) {
        not_started(run, m);
        return 1;
    }
    m->started = sim_clock_seconds(SIM_CLOCK_WALL);
    return 0;
}

/* Child: `sablier run` of member i, its output into DIR/log.txt. */
static int member_exec(void *ctx, int i)
{
    const SweepRun *run = ctx;
    app_driver_log_to(run->members[i].dir);
    execv(run->w->o->self, run->argv);
    fprintf(stderr, "sablier: sweep: cannot run %s: %s\n", run->w->o->self, strerror(errno));
    return 2;
}

/* Member i ended (or its fork failed): its status and wall time. */
static int member_ended(void *ctx, int i, int status)
{
    SweepRun *run = ctx;
    Member *m = &run->members[i];
    if (status == APP_POOL_NOT_STARTED) {
        not_started(run, m);
        return m->status;
    }
    m->wall_seconds =
        m->started > 0.0 ? sim_clock_seconds(SIM_CLOCK_WALL) - m->started : 0.0; /* 0: --resume */
    m->status = status;
    return status;
}

static void member_progress(void *ctx, int i, int status, char *line, size_t size)
{
    const SweepRun *run = ctx;
    const Member *m = &run->members[i];
    snprintf(line, size, "member %d/%d %s: %s (%.1f s), crater height %.4g m", i + 1,
             run->w->member_count, m->label,
             status == 0                      ? "ok"
             : status == 1                    ? "unstable"
             : status == APP_POOL_INTERRUPTED ? "interrupted"
                                              : "error",
             m->wall_seconds, app_crater_observable(m->dir, "crater_height_m"));
}

static int member_folder(void *ctx, int i, char *dir, size_t size)
{
    const SweepRun *run = ctx;
    return snprintf(dir, size, "%s", run->members[i].dir) < (int)size ? 0 : -1;
}

/* Runs `count` members (the bed: bed_run = 1), `jobs` at a time (app/driver/pool.h); --resume skips
 * those whose folder holds a completed run. The pool's status: 0, or 128 + a signal that
 * stopped it. */
static int run_members(Sweep *w, Member *members, int count, int bed_run)
{
    SweepRun run = {.w = w, .members = members, .bed_run = bed_run};
    AppDriverPool pool = {.command = "sweep",
                          .count = count,
                          .jobs = w->o->jobs,
                          .resume = w->o->resume,
                          .signal_status = 2,
                          .quiet = w->o->quiet,
                          .ctx = &run,
                          .start = member_start,
                          .run = member_exec,
                          .folder = member_folder,
                          .ended = member_ended,
                          .progress = bed_run ? NULL : member_progress};
    int rc = app_driver_pool_run(&pool);
    if (run.argv[0])
        free_argv(run.argv);
    return rc > APP_EXIT_SIGNAL ? rc : 0;
}

/* ---------------------------------------------------------------- outputs */

static void csv_text(FILE *f, const char *text)
{
    fputc('"', f);
    for (const char *c = text; *c; ++c) {
        if (*c == '"')
            fputc('"', f);
        fputc(*c, f);
    }
    fputc('"', f);
}

static int write_table(const Sweep *w)
{
    char path[SWEEP_PATH + 32];
    snprintf(path, sizeof path, "%s/sweep.csv", w->out_dir);
    FILE *f = app_tmp_open(path, NULL);
    if (!f)
        return -1;
    static const char *const keys[] = {
        "crater_height_m",  "surface_min_m", "crater_x_m",       "removed",
        "mobile_grains",    "final_time_s",  "e_kin_J",          "e_pot_J",
        "e_rot_J",          "e_el_J",        "bed_coordination", "bed_packing_fraction",
        "bed_hexatic_order"};
    fprintf(f, "member,label,value,status");
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; ++k)
        fprintf(f, ",%s", keys[k]);
    fprintf(f, ",wall_seconds,dir,sets\n");
    for (int i = 0; i < w->member_count; ++i) {
        const Member *m = &w->members[i];
        fprintf(f, "%d,", i + 1);
        csv_text(f, m->label);
        char status[16];
        fprintf(f, ",%.10g,%s", m->value, app_pool_status_text(m->status, status));
        for (size_t k = 0; k < sizeof keys / sizeof keys[0]; ++k)
            fprintf(f, ",%.10g", app_crater_observable(m->dir, keys[k]));
        fprintf(f, ",%.3f,", m->wall_seconds);
        csv_text(f, m->dir);
        fputc(',', f);
        char sets[MAX_SETS * SWEEP_STRING] = "";
        size_t n = 0;
        for (int k = 0; k < m->set_count && n < sizeof sets; ++k)
            n += (size_t)snprintf(sets + n, sizeof sets - n, "%s%s", k ? " " : "", m->sets[k]);
        csv_text(f, sets);
        fputc('\n', f);
    }
    return app_tmp_commit(&f, path);
}

static int write_plots(const Sweep *w)
{
    if (!w->o->render || !w->o->render->plot)
        return 0;
    char path[SWEEP_PATH + 32], title[160], err[512] = "";
    AppCraterChart plot;
    int rc = 0;
    snprintf(title, sizeof title, "%s: dimensionless energies (000 figs. 7.1-7.8, 7.20)", w->name);
    app_crater_chart_init(&plot, 2, 2, title);
    plot.print = &w->print;
    for (int i = 0; i < w->member_count; ++i)
        app_crater_chart_energy_run(&plot, w->members[i].dir, w->members[i].label, NULL);
    snprintf(path, sizeof path, "%s/energy_panels.png", w->out_dir);
    if (plot.panels[0].series_count > 0 &&
        app_crater_chart_write(&plot, w->o->render, path, err, sizeof err) != 0)
        rc = -1;
    app_crater_chart_free(&plot);

    snprintf(title, sizeof title, "%s: crater height (000 fig. 7.28)", w->name);
    app_crater_chart_init(&plot, 1, 1, title);
    plot.print = &w->print;
    double x[MAX_MEMBERS], y[MAX_MEMBERS];
    int n = 0;
    for (int i = 0; i < w->member_count; ++i) {
        double h = app_crater_observable(w->members[i].dir, "crater_height_m");
        if (isfinite(h)) {
            x[n] = w->members[i].value;
            y[n++] = h;
        }
    }
    snprintf(plot.panels[0].x_label, sizeof plot.panels[0].x_label, "%s",
             w->parameter[0] ? w->parameter : "member");
    snprintf(plot.panels[0].y_label, sizeof plot.panels[0].y_label,
             "crater height h = level - min y_s (m)");
    snprintf(path, sizeof path, "%s/crater_height.png", w->out_dir);
    if (n > 0 && app_crater_chart_add(&plot, 0, NULL, x, y, n, 0, 1) == 0 &&
        app_crater_chart_write(&plot, w->o->render, path, err, sizeof err) != 0)
        rc = -1;
    app_crater_chart_free(&plot);

    snprintf(title, sizeof title, "%s: final free-surface profiles (000 fig. 7.29)", w->name);
    app_crater_chart_init(&plot, 1, 1, title);
    plot.print = &w->print;
    plot.width = 1200;
    for (int i = 0; i < w->member_count; ++i)
        app_crater_chart_profiles_run(&plot, 0, w->members[i].dir, 1, w->members[i].label);
    snprintf(path, sizeof path, "%s/profiles.png", w->out_dir);
    if (plot.panels[0].series_count > 0 &&
        app_crater_chart_write(&plot, w->o->render, path, err, sizeof err) != 0)
        rc = -1;
    app_crater_chart_free(&plot);
    if (rc != 0)
        fprintf(stderr, "sablier: sweep: figures: %s\n", err);
    return rc;
}

/* ---------------------------------------------------------------- the sweep */

/* The scene's stage names and the bed stage (named, or the one before the first dig) into w:
 * 0, or -1 (message on stderr). */
static int find_bed_stage(Sweep *w, const Scene *scene, const char *bed_name)
{
    snprintf(w->name, sizeof w->name, "%s", scene->name);
    w->stage_count = scene->stage_count;
    for (int k = 0; k < scene->stage_count; ++k)
        snprintf(w->stage_names[k], SCENE_NAME_MAX, "%s", scene->stages[k].name);
    w->bed_stage = -1;
    if (bed_name[0]) {
        w->bed_stage = scene_stage_index(scene, bed_name);
        if (w->bed_stage < 0)
            fprintf(stderr, "sablier: sweep: the scene has no stage `%s`\n", bed_name);
    } else {
        for (int k = 1; k < scene->stage_count && w->bed_stage < 0; ++k)
            if (app_crater_dig(scene, k).dig)
                w->bed_stage = k - 1;
        if (w->bed_stage < 0)
            fprintf(stderr, "sablier: sweep: no stage digs; name the bed stage (--bed-stage)\n");
    }
    if (w->bed_stage < 0)
        return -1;
    if (w->bed_stage + 1 >= w->stage_count) {
        fprintf(stderr, "sablier: sweep: no stage after the bed stage `%s`\n",
                w->stage_names[w->bed_stage]);
        return -1;
    }
    return 0;
}

/* Every member's folder, and its scene must load (the bed checkpoint is not there yet: not
 * checked). 0, or 2 (message on stderr). */
static int check_members(Sweep *w)
{
    const AppCraterSweepOptions *o = w->o;
    char err[4096];
    for (int i = 0; i < w->member_count; ++i) {
        Member *m = &w->members[i];
        char name[80];
        slug(name, sizeof name, m->label);
        if (snprintf(m->dir, sizeof m->dir, "%s/%02d-%s", w->out_dir, i + 1, name) >=
            (int)sizeof m->dir) {
            fprintf(stderr, "sablier: sweep: output folder name too long\n");
            return 2;
        }
        m->status = -1;
        const char *sets[3 * MAX_SETS + SCENE_MAX_STAGES];
        int n = 0;
        for (int k = 0; k < o->set_count; ++k)
            sets[n++] = o->sets[k];
        for (int k = 0; k < w->set_count; ++k)
            sets[n++] = w->sets[k];
        for (int k = 0; k < m->set_count; ++k)
            sets[n++] = m->sets[k];
        Scene *member = scene_load(w->scene_path, sets, n, err, sizeof err);
        if (!member) {
            if (m->line > 0) /* a member of the sweep file: point at its group */
                fprintf(stderr, "%s:%d: member %s: %s\n", o->definition, m->line, m->label, err);
            else
                fprintf(stderr, "sablier: sweep: member %s: %s\n", m->label, err);
            return 2;
        }
        scene_free(member);
    }
    return 0;
}

/* Without a sweep file's `parameter`: the first varied key with its unit in the scene's units
 * ("species.0.k_n (N/m)", "species.0.mu (1)"), or bare with a warning where the scene keys record
 * none (scene_key_quantity). */
static void parameter_of_key(Sweep *w, const Scene *scene)
{
    SceneQuantity quantity = scene_key_quantity(scene, w->vary_key);
    if (quantity < SCENE_QUANTITY_COUNT) {
        scene_axis_label(scene, w->vary_key, quantity, w->parameter, sizeof w->parameter);
        return;
    }
    snprintf(w->parameter, sizeof w->parameter, "%.63s", w->vary_key);
    fprintf(stderr,
            "sablier: sweep: warning: no unit is recorded for `%s`; crater_height's x axis "
            "names it bare (a sweep file's `parameter` gives its label)\n",
            w->vary_key);
}

static int setup(Sweep *w)
{
    const AppCraterSweepOptions *o = w->o;
    char vary[MAX_VARY * 2][VARY_STRING];
    int vary_count = 0;
    char bed_name[SCENE_NAME_MAX] = "";
    if (o->scene_path)
        snprintf(w->scene_path, sizeof w->scene_path, "%s", o->scene_path);
    if (o->definition) {
        if (read_definition(w, o->definition, vary, &vary_count) != 0)
            return 2;
        snprintf(bed_name, sizeof bed_name, "%s", w->bed_name);
    }
    for (int k = 0; k < o->vary_count; ++k) {
        if (vary_count >= MAX_VARY) {
            fprintf(stderr, "sablier: sweep: at most %d varied keys\n", MAX_VARY);
            return 2;
        }
        if (snprintf(vary[vary_count++], VARY_STRING, "%s", o->vary[k]) >= VARY_STRING) {
            fprintf(stderr,
                    "sablier: sweep: --vary %.40s...: longer than %d characters (at most %d "
                    "values per key)\n",
                    o->vary[k], VARY_STRING - 1, MAX_VALUES);
            return 2;
        }
    }
    if (o->bed_stage)
        snprintf(bed_name, sizeof bed_name, "%s", o->bed_stage);
    if (!w->scene_path[0]) {
        fprintf(stderr, "sablier: sweep: no scene (give SCENE or `scene` in the sweep file)\n");
        return 2;
    }
    if (expand_vary(w, vary, vary_count) != 0)
        return 2;
    if (w->member_count == 0) {
        fprintf(stderr, "sablier: sweep: no members (use --vary KEY=v1,v2 or `members`)\n");
        return 2;
    }
    char err[4096];
    Scene *scene = scene_load(w->scene_path, o->sets, o->set_count, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    char why[1200];
    if (o->from && app_state_check(o->from, &scene->def, why, sizeof why) != 0) {
        fprintf(stderr, "sablier: sweep: --from: %s\n", why);
        scene_free(scene);
        return 2;
    }
    int bed = find_bed_stage(w, scene, bed_name);
    w->print = scene->style;
    if (!w->parameter[0] && w->vary_key[0])
        parameter_of_key(w, scene);
    scene_free(scene);
    if (bed != 0)
        return 2;
    if (o->out_dir) {
        snprintf(w->out_dir, sizeof w->out_dir, "%s", o->out_dir);
    } else if (o->definition) {
        app_driver_default_out("sweep", o->definition, w->out_dir, sizeof w->out_dir);
    } else {
        snprintf(w->out_dir, sizeof w->out_dir, "out/%s-sweep", w->name);
    }
    return check_members(w);
}

/* The sweep's last line on stderr. */
static void report_done(const char *out_dir, int interrupted, double seconds)
{
    fprintf(stderr, "sablier: sweep: %s in %.1f s: %s/sweep.csv\n",
            interrupted ? "interrupted" : "done", seconds, out_dir);
}

int app_crater_sweep(const AppCraterSweepOptions *o)
{
    Sweep *w = calloc(1, sizeof *w);
    Member *members = calloc(MAX_MEMBERS, sizeof *members);
    if (!w || !members) {
        free(w);
        free(members);
        fprintf(stderr, "sablier: out of memory\n");
        return 2;
    }
    w->o = o;
    w->members = members;
    int status = setup(w);
    if (status == 0 && app_make_dirs(w->out_dir) != 0) {
        fprintf(stderr, "sablier: sweep: cannot create %s: %s\n", w->out_dir, strerror(errno));
        status = 2;
    }
    double start = sim_clock_seconds(SIM_CLOCK_WALL);
    int interrupted = 0, tables = 0; /* interrupted: 128 + the signal that stopped a pool */
    /* the bed: given, or the scene's stages up to the bed stage, run once */
    if (status == 0) {
        if (o->from) {
            snprintf(w->bed_state, sizeof w->bed_state, "%s", o->from);
        } else {
            Member bed;
            memset(&bed, 0, sizeof bed);
            snprintf(bed.label, sizeof bed.label, "bed");
            if (snprintf(bed.dir, sizeof bed.dir, "%s/bed", w->out_dir) >= (int)sizeof bed.dir)
                status = 2;
            if (snprintf(w->bed_state, sizeof w->bed_state, "%s/%s.state", bed.dir,
                         w->stage_names[w->bed_stage]) >= (int)sizeof w->bed_state)
                status = 2;
            if (!o->quiet)
                fprintf(stderr, "sablier: sweep: settling the bed (stages up to %s) in %s\n",
                        w->stage_names[w->bed_stage], bed.dir);
            if (!o->dry_run && status == 0) {
                bed.status = 2; /* until it ends */
                interrupted = run_members(w, &bed, 1, 1);
                if (interrupted) {
                    status = interrupted; /* no member starts; each one is "interrupted" */
                    for (int i = 0; i < w->member_count; ++i)
                        w->members[i].status = APP_POOL_INTERRUPTED;
                } else if (bed.status != 0) {
                    fprintf(stderr,
                            "sablier: sweep: the bed run failed (status %d): see %s/log.txt\n",
                            bed.status, bed.dir);
                    status = bed.status;
                }
            }
        }
        char resolved[PATH_MAX];
        if (status == 0 && !o->dry_run) {
            if (!realpath(w->bed_state, resolved)) {
                fprintf(stderr, "sablier: sweep: cannot read the bed checkpoint %s: %s\n",
                        w->bed_state, strerror(errno));
                status = 2;
            } else {
                if (snprintf(w->bed_state, sizeof w->bed_state, "%s", resolved) >=
                    (int)sizeof w->bed_state)
                    status = 2;
            }
        }
    }
    if (status == 0 && o->dry_run) {
        for (int i = 0; i < w->member_count; ++i) {
            char *argv[3 * MAX_SETS * 2 + 32];
            int n = member_argv(w, &w->members[i], 0, argv, (int)(sizeof argv / sizeof argv[0]));
            printf("%s:", w->members[i].label);
            for (int k = 0; k < n; ++k)
                printf(" %s", argv[k]);
            printf("\n");
            if (n > 0)
                free_argv(argv);
        }
    } else if (status == 0) {
        if (!o->quiet)
            fprintf(stderr, "sablier: sweep: %d members from %s, %d at a time, into %s\n",
                    w->member_count, w->bed_state, app_pool_width(o->jobs), w->out_dir);
        interrupted = run_members(w, w->members, w->member_count, 0);
        for (int i = 0; i < w->member_count; ++i)
            if (w->members[i].status != 0 && status != 2)
                status = w->members[i].status == 1 ? 1 : 2;
        tables = 1;
    }
    if (tables || interrupted) { /* the finished members, the others "interrupted" */
        if (write_table(w) != 0) {
            fprintf(stderr, "sablier: sweep: cannot write %s/sweep.csv\n", w->out_dir);
            status = 2;
        }
        if (write_plots(w) != 0 && status == 0)
            status = 2;
        if (!o->quiet)
            report_done(w->out_dir, interrupted, sim_clock_seconds(SIM_CLOCK_WALL) - start);
    }
    if (interrupted)
        status = interrupted;
    free(members);
    free(w);
    return status;
}

/* ---------------------------------------------------------------- the command */

static const char USAGE_SWEEP[] =
    "usage: sablier sweep FILE.sweep [options]\n"
    "       sablier sweep SCENE --vary KEY=v1,v2,... [--vary KEY2=...] [options]\n"
    "\n"
    "Runs one member per value (or combination) from one settled bed: the scene's stages up to\n"
    "the bed stage run once (or --from gives the bed), then each member runs the later stages\n"
    "with its --set overrides, as a separate `sablier run` process; then sweep.csv and the\n"
    "comparison figures energy_panels.png, crater_height.png and profiles.png.\n"
    "\n"
    "  --vary KEY=v1,v2   one member per value (several --vary: every combination)\n"
    "  --from STATE       the bed checkpoint (default: run the bed stages into DIR/bed)\n"
    "  --bed-stage NAME   the stage whose checkpoint is the bed (default: the one before a dig)\n"
    "  --set KEY=VALUE    override a key for the bed and every member\n"
    "  --jobs N           members at a time (default 2; results do not depend on N)\n"
    "  --out DIR          output folder (default out/sweep-<file name> or out/<scene>-sweep)\n"
    "  --dry-run          print the member commands, run nothing\n"
    "  --resume           skip the bed and the members whose folder holds a completed run\n"
    "  --quiet, -q        no per-member lines\n"
    "\n"
    "SIGINT or SIGTERM stops the members (each saves its state), writes sweep.csv with status\n"
    "`interrupted` for the members not finished, and exits 130 or 143.\n"
    "\n"
    "exit status: 0 every member succeeded, 1 a member went unstable, 2 bad input (nothing\n"
    "runs), a member that failed otherwise or a table that cannot be written, 130/143\n"
    "SIGINT/SIGTERM\n";

static const AppDriverSpec SWEEP_SPEC = {.usage = USAGE_SWEEP,
                                         .jobs_max = 64,
                                         .vary_max = 8,
                                         .extra_error = "one sweep at a time; extra argument",
                                         .missing = "missing FILE.sweep or SCENE"};

/* The command line of `sablier sweep`: the common options (driver.h) and its own. */
typedef struct SweepArgs {
    AppCraterSweepOptions o;
    AppDriverArgs d;
} SweepArgs;

/* The options of `sablier sweep` alone (app_driver_parse's `own`). */
static int sweep_option(void *ctx, int argc, char **argv, int *i)
{
    AppCraterSweepOptions *o = ctx;
    const char *value;
    int m;
    if ((m = app_option(argc, argv, i, "--from", &value)) != 0)
        o->from = value;
    else if ((m = app_option(argc, argv, i, "--bed-stage", &value)) != 0)
        o->bed_stage = value;
    else if (strcmp(argv[*i], "--dry-run") == 0)
        o->dry_run = m = 1;
    return m < 0 ? 2 : m;
}

/* The command line into *a: 0, or the exit status of a usage error (message on stderr). */
static int sweep_arguments(int argc, char **argv, SweepArgs *a)
{
    a->o = app_crater_sweep_options_default();
    int rc = app_driver_parse(&SWEEP_SPEC, argc, argv, &a->d, sweep_option, &a->o);
    if (rc != 0)
        return rc;
    const char *path = a->d.scene;
    size_t n = strlen(path);
    if (n > 6 && strcmp(path + n - 6, ".sweep") == 0)
        a->o.definition = path;
    else
        a->o.scene_path = path;
    a->o.out_dir = a->d.out;
    a->o.quiet = a->d.quiet;
    a->o.resume = a->d.resume;
    a->o.jobs = (int)a->d.jobs;
    a->o.sets = a->d.sets;
    a->o.set_count = a->d.set_count;
    a->o.vary = a->d.vary;
    a->o.vary_count = a->d.vary_count;
    return 0;
}

static int sweep_parse(int argc, char **argv)
{
    SweepArgs a;
    return sweep_arguments(argc, argv, &a);
}

static int sweep_command(int argc, char **argv, const AppEnv *env)
{
    SweepArgs a;
    int status = sweep_arguments(argc, argv, &a);
    if (status != 0)
        return status;
    a.o.self = env->self;
    a.o.render = env->render;
    return app_crater_sweep(&a.o);
}

const AppCommand app_crater_commands[] = {
    {"sweep", "sweep SWEEP    run sweep members from one settled bed (crater studies)", USAGE_SWEEP,
     sweep_command, sweep_parse},
};
