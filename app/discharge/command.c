/* SPDX-License-Identifier: MIT */
/* discharge/command.c: `sablier discharge` (thesis 004): one open pile built (or loaded) and
 * discharged through a central orifice at each width, with figures and movies on request. */
#include "drivers.h"

#include "base/util.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_WIDTHS 128
#define PATH       2048

const char APP_DISCHARGE_USAGE[] =
    "usage: sablier discharge SCENE [--out DIR] [--width W]... [--pile STATE] [--seed N]\n"
    "                         [--set KEY=VALUE]... [--figures] [--movie] [--quiet]\n"
    "\n"
    "Builds an open pile (rows rained on the base, relaxed to static equilibrium; thesis 004)\n"
    "and discharges it through a central orifice of each width W (in grain diameters).\n"
    "  --out DIR      output folder (default out/<scene name>/)\n"
    "  --width W      orifice width, d (repeatable; default the scene's discharge.widths)\n"
    "  --pile STATE   discharge this saved pile instead of building one\n"
    "  --seed N       deposition seed (default the scene's seed)\n"
    "  --figures      pile.png and w<W>.png (species colours, arch highlighted with an inset)\n"
    "  --movie        deposition.mp4 and w<W>.mp4\n"
    "  --quiet, -q    no summary line per deposition and per width\n"
    "Writes pile.state, deposition.csv, discharge.csv (s, h, arch, composition) and\n"
    "w<W>.state.\n"
    "\n"
    "exit status: 0 every width was discharged, 1 a discharge went unstable, 2 bad input or an\n"
    "output that cannot be written (SIGINT and SIGTERM are not caught: they end it at once)\n";

/* ---------------------------------------------------------------- sablier discharge */

/* The command line of `sablier discharge`. */
typedef struct DischargeArgs {
    const char *scene_path, *out, *pile, *sets[APP_MAX_SETS];
    int set_count, figures, movies, quiet, width_count, seed_given;
    double widths[MAX_WIDTHS];
    unsigned long long seed;
} DischargeArgs;

/* 0, or the exit status of a bad command line (message on stderr). */
static int parse_args(int argc, char **argv, DischargeArgs *a)
{
    const char *value;
    memset(a, 0, sizeof *a);
    for (int i = 2; i < argc; ++i) {
        int m;
        if ((m = app_option(argc, argv, &i, "--out", &value)) != 0) {
            if (m < 0)
                return 2;
            a->out = value;
        } else if ((m = app_option(argc, argv, &i, "--pile", &value)) != 0) {
            if (m < 0)
                return 2;
            FILE *pile = fopen(value, "rb"); /* refused before anything runs */
            if (!pile)
                return app_usage_error(APP_DISCHARGE_USAGE, "--pile: cannot read", value);
            fclose(pile);
            a->pile = value;
        } else if ((m = app_set_option(argc, argv, &i, a->sets, &a->set_count, APP_MAX_SETS)) !=
                   0) {
            if (m < 0)
                return app_usage_error(APP_DISCHARGE_USAGE, "bad --set", NULL);
        } else if ((m = app_option(argc, argv, &i, "--width", &value)) != 0) {
            double w;
            if (m < 0 || app_discharge_parse_real(value, &w) != 0 || !(w >= 0.0) ||
                a->width_count >= MAX_WIDTHS)
                return app_usage_error(APP_DISCHARGE_USAGE, "--width needs a width (d), got",
                                       m < 0 ? "nothing" : value);
            a->widths[a->width_count++] = w;
        } else if ((m = app_option(argc, argv, &i, "--seed", &value)) != 0) {
            char *end;
            if (m < 0)
                return 2;
            a->seed = strtoull(value, &end, 10);
            if (end == value || *end)
                return app_usage_error(APP_DISCHARGE_USAGE, "--seed needs an integer, got", value);
            a->seed_given = 1;
        } else if (strcmp(argv[i], "--figures") == 0) {
            a->figures = 1;
        } else if (strcmp(argv[i], "--movie") == 0) {
            a->movies = 1;
        } else if (strcmp(argv[i], "--quiet") == 0 || strcmp(argv[i], "-q") == 0) {
            a->quiet = 1;
        } else if (app_scene_argument(APP_DISCHARGE_USAGE, argv[i], &a->scene_path) != 0) {
            return 2;
        }
    }
    if (!a->scene_path)
        return app_usage_error(APP_DISCHARGE_USAGE, "missing SCENE", NULL);
    return 0;
}

/* One `sablier discharge`: its scene, folder, movie, and the texts of discharge.csv and
 * summary.json as they grow. */
typedef struct DischargeRun {
    const DischargeArgs *a;
    const AppRender *render;
    const Scene *scene;
    const AppDischargeDef *def;
    const char *pile; /* the pile discharged */
    char dir[PATH], pile_path[PATH + 64];
    AppDischargeGeometry geo;
    AppDischargeMovie movie;
    double frame_time;
    char *summary, *csv;
    size_t summary_size, used, csv_size, csv_used;
} DischargeRun;

/* The deposition summary's line on stderr, and its summary.json members. */
static void deposition_summary(DischargeRun *d, const AppDischargeDeposit *dep)
{
    const DischargeArgs *a = d->a;
    const Scene *scene = d->scene;
    if (!a->quiet)
        fprintf(stderr,
                "sablier: deposition L = %g d: %d rows, %d released, %d in the pile, %ld "
                "lost, %s at t = %.6g (%ld steps, %.3g s)\n",
                d->def->base_length, dep->rows, dep->released, dep->pile, dep->lost,
                dep->equilibrium ? "static equilibrium" : "NOT at equilibrium (cap)", dep->time,
                dep->steps, dep->wall_seconds);
    d->used += (size_t)snprintf(
        d->summary + d->used, d->summary_size - d->used,
        "{\n  \"scene\": \"%s\",\n  \"base_length\": %.10g,\n  \"seed\": %llu,\n"
        "  \"g\": %.10g,\n  \"dt\": %.10g,\n  \"row_period\": %.10g,\n  \"row_size\": %d,\n"
        "  \"deposition\": {\"rows\": %d, \"released\": %d, \"pile\": %d, \"lost\": %ld, "
        "\"equilibrium\": %s, \"height\": %.10g, \"time\": %.10g, \"steps\": %ld, "
        "\"wall_seconds\": %.4g},\n  \"discharges\": [",
        scene->name, d->def->base_length, a->seed_given ? a->seed : (unsigned long long)scene->seed,
        d->geo.g, d->geo.dt, d->geo.row_period, d->geo.row_size, dep->rows, dep->released,
        dep->pile, dep->lost, dep->equilibrium ? "true" : "false", dep->height, dep->time,
        dep->steps, dep->wall_seconds);
}

/* Builds the pile: deposition.csv (and .mp4), pile.state, pile.png. 0, or the exit status. */
static int deposit_pile(DischargeRun *d)
{
    const DischargeArgs *a = d->a;
    const Scene *scene = d->scene;
    char path[PATH + 64], err[4096] = "";
    int status = 0;
    AppDischargeFrames frames;
    snprintf(path, sizeof path, "%s/deposition.mp4", d->dir);
    if (app_discharge_movie_start(&d->movie, scene, path, &frames, d->frame_time, d->geo.dt) != 0)
        status = 2;
    snprintf(path, sizeof path, "%s/deposition.csv", d->dir);
    FILE *trace = app_tmp_open(path, "t,row,released,pile,mobile");
    AppDischargeDeposit dep;
    SimWorld *world = status ? NULL
                             : app_discharge_deposit(scene, a->seed_given ? a->seed : scene->seed,
                                                     &frames, trace, &dep, err, sizeof err);
    if (app_discharge_movie_finish(&d->movie) != 0)
        status = 2;
    if (app_tmp_commit(&trace, path) != 0)
        status = 2;
    if (!world) {
        if (!status)
            fprintf(stderr, "sablier: deposition: %s\n",
                    err[0] ? err : "the pile could not be built (no cause recorded)");
        return status ? status : 1;
    }
    snprintf(d->pile_path, sizeof d->pile_path, "%s/pile.state", d->dir);
    SimError error;
    if (sim_world_save(world, d->pile_path, &error) != SIM_OK) {
        fprintf(stderr, "sablier: %s\n", error.message);
        status = 2;
    }
    if (a->figures) {
        snprintf(path, sizeof path, "%s/pile.png", d->dir);
        char title[128];
        snprintf(title, sizeof title, "pile L = %g d, %d grains", d->def->base_length, dep.pile);
        if (app_discharge_figure(d->render, scene, world, NULL, title, path) != 0)
            status = 2;
    }
    deposition_summary(d, &dep);
    sim_world_destroy(world);
    return status;
}

/* The discharge at widths[k]'s row of discharge.csv, its summary.json element and its line. */
static void width_summary(DischargeRun *d, int k, const AppDischarge *r)
{
    double w = d->a->widths[k];
    char row[512];
    app_discharge_csv_row(r, 0, d->def->base_length, row, sizeof row);
    d->csv_used += (size_t)snprintf(d->csv + d->csv_used, d->csv_size - d->csv_used, "%s\n", row);
    d->used += (size_t)snprintf(
        d->summary + d->used, d->summary_size - d->used,
        "%s\n    {\"w\": %.10g, \"s\": %ld, \"edges\": %ld, \"h\": %.10g, \"pile\": %d, "
        "\"arch\": %d, \"arch_species\": [%d, %d], \"equilibrium\": %s, \"time\": %.10g, "
        "\"wall_seconds\": %.4g}",
        k ? "," : "", r->width, r->through, r->edges, r->height, r->pile, r->arch,
        r->arch_species[0], r->arch_species[1], r->equilibrium ? "true" : "false", r->time,
        r->wall_seconds);
    if (!d->a->quiet)
        fprintf(stderr,
                "sablier: discharge w = %g d: s = %ld through, %ld over the edges, h = %.4g d, "
                "arch %d grains, %s (%.3g s)\n",
                w, r->through, r->edges, r->height, r->arch,
                r->equilibrium ? "static equilibrium" : "NOT at equilibrium (cap)",
                r->wall_seconds);
}

/* Discharges the pile at widths[k]: w<W>.state (.mp4, .png). 0, or the exit status (*stop = 1:
 * no later width). */
static int discharge_width(DischargeRun *d, int k, int *stop)
{
    double w = d->a->widths[k];
    char wname[32], path[PATH + 64], err[4096] = "";
    app_discharge_width_name(w, wname, sizeof wname);
    AppDischargeFrames frames;
    snprintf(path, sizeof path, "%s/%s.mp4", d->dir, wname);
    *stop = 1;
    if (app_discharge_movie_start(&d->movie, d->scene, path, &frames, d->frame_time, d->geo.dt) !=
        0)
        return 2;
    int status = 0;
    AppDischarge r;
    SimWorld *world = app_discharge(d->scene, d->pile, w, &frames, &r, err, sizeof err);
    if (app_discharge_movie_finish(&d->movie) != 0)
        status = 2;
    if (!world) {
        fprintf(stderr, "sablier: discharge w = %g d: %s\n", w, err);
        return 1;
    }
    *stop = 0;
    snprintf(path, sizeof path, "%s/%s.state", d->dir, wname);
    SimError error;
    if (sim_world_save(world, path, &error) != SIM_OK)
        status = 2;
    if (d->a->figures) {
        char title[160];
        snprintf(title, sizeof title, "w = %g d: s = %ld, h = %.3g d, arch of %d grains", w,
                 r.through, r.height, r.arch);
        snprintf(path, sizeof path, "%s/%s.png", d->dir, wname);
        if (app_discharge_figure(d->render, d->scene, world, &r, title, path) != 0)
            status = 2;
    }
    sim_world_destroy(world);
    width_summary(d, k, &r);
    return status;
}

/* The pile (built, or --pile) discharged at every width, then discharge.csv and summary.json:
 * the exit status. */
static int run_discharge(DischargeRun *d)
{
    const DischargeArgs *a = d->a;
    int status = 0;
    if (!a->pile) {
        status = deposit_pile(d);
        d->pile = d->pile_path;
    } else {
        d->pile = a->pile;
        d->used +=
            (size_t)snprintf(d->summary + d->used, d->summary_size - d->used,
                             "{\n  \"scene\": \"%s\",\n  \"pile\": \"%s\",\n  \"discharges\": [",
                             d->scene->name, a->pile);
    }
    d->csv_used = (size_t)snprintf(d->csv, d->csv_size, "%s\n", app_discharge_csv_header());
    for (int k = 0; status == 0 && k < a->width_count; ++k) {
        int stop;
        status = discharge_width(d, k, &stop);
        if (stop)
            break;
    }
    char path[PATH + 64];
    snprintf(path, sizeof path, "%s/discharge.csv", d->dir);
    if (a->width_count > 0 && status == 0 && app_write_atomic(path, d->csv) != 0)
        status = 2;
    if (d->used > 0) {
        snprintf(d->summary + d->used, d->summary_size - d->used,
                 "\n  ],\n  \"status\": \"%s\"\n}\n", status == 0 ? "ok" : "error");
        snprintf(path, sizeof path, "%s/summary.json", d->dir);
        if (app_write_atomic(path, d->summary) != 0 && status == 0)
            status = 2;
    }
    return status;
}

static int discharge_parse(int argc, char **argv)
{
    DischargeArgs a;
    return parse_args(argc, argv, &a);
}

static int discharge_command(int argc, char **argv, const AppEnv *env)
{
    DischargeArgs a;
    int status = parse_args(argc, argv, &a);
    if (status != 0)
        return status;
    char err[4096] = "";
    Scene *scene =
        app_discharge_load_scene(a.scene_path, a.sets, a.set_count, 0.0, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    DischargeRun d = {.a = &a, .render = env->render, .scene = scene};
    d.def = app_discharge_of(scene);
    if (a.width_count == 0)
        for (int k = 0; k < d.def->width_count; ++k)
            a.widths[a.width_count++] = d.def->widths[k];
    if (app_discharge_check_widths(scene, a.widths, a.width_count, "--width", err, sizeof err)) {
        fprintf(stderr, "%s\n", err);
        scene_free(scene);
        return 2;
    }
    snprintf(d.dir, sizeof d.dir, "%s%s", a.out ? "" : "out/", a.out ? a.out : scene->name);
    if (app_make_dirs(d.dir) != 0) {
        fprintf(stderr, "sablier: cannot create output folder %s: %s\n", d.dir, strerror(errno));
        scene_free(scene);
        return 2;
    }
    app_discharge_geometry(scene, &d.geo);
    d.movie = (AppDischargeMovie){a.movies ? env->render : NULL, 0};
    d.frame_time = d.geo.row_period / 4.0;
    d.summary_size = 4096 + 512 * (size_t)a.width_count;
    d.csv_size = 512 + 256 * (size_t)a.width_count;
    d.summary = malloc(d.summary_size);
    d.csv = malloc(d.csv_size);
    if (d.summary && d.csv) {
        status = run_discharge(&d);
    } else {
        fprintf(stderr, "sablier: out of memory\n");
        status = 2;
    }
    free(d.csv);
    free(d.summary);
    scene_free(scene);
    return status;
}

const AppCommand app_discharge_commands[] = {
    {"discharge", "discharge SCENE  build an open pile and discharge it through an orifice (004)",
     APP_DISCHARGE_USAGE, discharge_command, discharge_parse},
    {"study", "study SCENE    jamming statistics over base lengths and widths (004)",
     APP_STUDY_USAGE, app_study_command, app_study_parse},
};
