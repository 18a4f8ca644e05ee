/* SPDX-License-Identifier: MIT */
/* discharge/command.c: `sablier discharge` (thesis 004): one open pile built (or loaded) and
 * discharged through a central orifice at each width, with figures and movies on request. */
#include "drivers.h"
#include "util.h"

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
    "Writes pile.state, deposition.csv, discharge.csv (s, h, arch, composition) and\n"
    "w<W>.state.\n";

/* ---------------------------------------------------------------- sablier discharge */

static int discharge_command(int argc, char **argv, const AppEnv *env)
{
    const AppRender *render = env->render;
    const char *scene_path = NULL, *out = NULL, *pile = NULL, *value, *sets[APP_MAX_SETS];
    int set_count = 0, figures = 0, movies = 0, quiet = 0, width_count = 0, seed_given = 0;
    double widths[MAX_WIDTHS];
    unsigned long long seed = 0;
    for (int i = 2; i < argc; ++i) {
        int m;
        if ((m = app_option(argc, argv, &i, "--out", &value)) != 0) {
            if (m < 0)
                return 2;
            out = value;
        } else if ((m = app_option(argc, argv, &i, "--pile", &value)) != 0) {
            if (m < 0)
                return 2;
            pile = value;
        } else if ((m = app_option(argc, argv, &i, "--set", &value)) != 0) {
            if (m < 0 || set_count >= APP_MAX_SETS)
                return app_usage_error(APP_DISCHARGE_USAGE, "bad --set", NULL);
            sets[set_count++] = value;
        } else if ((m = app_option(argc, argv, &i, "--width", &value)) != 0) {
            double w;
            if (m < 0 || app_discharge_parse_real(value, &w) != 0 || !(w >= 0.0) ||
                width_count >= MAX_WIDTHS)
                return app_usage_error(APP_DISCHARGE_USAGE, "--width needs a width >= 0 (d), got",
                                       m < 0 ? "nothing" : value);
            widths[width_count++] = w;
        } else if ((m = app_option(argc, argv, &i, "--seed", &value)) != 0) {
            char *end;
            if (m < 0)
                return 2;
            seed = strtoull(value, &end, 10);
            if (end == value || *end)
                return app_usage_error(APP_DISCHARGE_USAGE, "--seed needs an integer, got", value);
            seed_given = 1;
        } else if (strcmp(argv[i], "--figures") == 0) {
            figures = 1;
        } else if (strcmp(argv[i], "--movie") == 0) {
            movies = 1;
        } else if (strcmp(argv[i], "--quiet") == 0 || strcmp(argv[i], "-q") == 0) {
            quiet = 1;
        } else if (app_scene_argument(APP_DISCHARGE_USAGE, argv[i], &scene_path) != 0) {
            return 2;
        }
    }
    if (!scene_path)
        return app_usage_error(APP_DISCHARGE_USAGE, "missing SCENE", NULL);
    char err[4096] = "";
    Scene *scene = app_discharge_load_scene(scene_path, sets, set_count, 0.0, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    const AppDischargeDef *def = app_discharge_of(scene);
    if (width_count == 0)
        for (int k = 0; k < def->width_count; ++k)
            widths[width_count++] = def->widths[k];
    char dir[PATH], path[PATH + 64];
    snprintf(dir, sizeof dir, "%s%s", out ? "" : "out/", out ? out : scene->name);
    if (app_make_dirs(dir) != 0) {
        fprintf(stderr, "sablier: cannot create output folder %s: %s\n", dir, strerror(errno));
        scene_free(scene);
        return 2;
    }
    AppDischargeGeometry geo;
    app_discharge_geometry(scene, &geo);
    AppDischargeMovie movie = {movies ? render : NULL, 0};
    const double frame_time = geo.row_period / 4.0;
    int status = 0;
    char pile_path[PATH + 64];
    size_t summary_size = 4096 + 512 * (size_t)width_count;
    char *summary = malloc(summary_size);
    if (!summary)
        abort();
    size_t used = 0;
    if (!pile) {
        AppFrames frames;
        snprintf(path, sizeof path, "%s/deposition.mp4", dir);
        if (app_discharge_movie_start(&movie, scene, path, &frames, frame_time, geo.dt) != 0)
            status = 2;
        snprintf(path, sizeof path, "%s/deposition.csv", dir);
        char tmp[PATH + 80];
        snprintf(tmp, sizeof tmp, "%s.tmp", path);
        FILE *trace = fopen(tmp, "w");
        if (trace)
            fprintf(trace, "t,row,released,pile,mobile\n");
        AppDeposit dep;
        SimWorld *world = status ? NULL
                                 : app_deposit(scene, seed_given ? seed : scene->seed, &frames,
                                               trace, &dep, err, sizeof err);
        if (app_discharge_movie_finish(&movie) != 0)
            status = 2;
        if (trace && (fclose(trace) != 0 || rename(tmp, path) != 0))
            status = 2;
        if (!world) {
            if (!status)
                fprintf(stderr, "sablier: deposition: %s\n", err);
            status = status ? status : 1;
        } else {
            snprintf(pile_path, sizeof pile_path, "%s/pile.state", dir);
            SimError error;
            if (sim_world_save(world, pile_path, &error) != SIM_OK) {
                fprintf(stderr, "sablier: %s\n", error.message);
                status = 2;
            }
            if (figures) {
                snprintf(path, sizeof path, "%s/pile.png", dir);
                char title[128];
                snprintf(title, sizeof title, "pile L = %g d, %d grains", def->base_length,
                         dep.pile);
                if (app_discharge_figure(render, scene, world, NULL, title, path) != 0)
                    status = 2;
            }
            if (!quiet)
                fprintf(stderr,
                        "sablier: deposition L = %g d: %d rows, %d released, %d in the pile, %ld "
                        "lost, %s at t = %.6g (%ld steps, %.3g s)\n",
                        def->base_length, dep.rows, dep.released, dep.pile, dep.lost,
                        dep.equilibrium ? "static equilibrium" : "NOT at equilibrium (cap)",
                        dep.time, dep.steps, dep.wall_seconds);
            used += (size_t)snprintf(
                summary + used, summary_size - used,
                "{\n  \"scene\": \"%s\",\n  \"base_length\": %.10g,\n  \"seed\": %llu,\n"
                "  \"g\": %.10g,\n  \"dt\": %.10g,\n  \"row_period\": %.10g,\n  \"row_size\": %d,\n"
                "  \"deposition\": {\"rows\": %d, \"released\": %d, \"pile\": %d, \"lost\": %ld, "
                "\"equilibrium\": %s, \"height\": %.10g, \"time\": %.10g, \"steps\": %ld, "
                "\"wall_seconds\": %.4g},\n  \"discharges\": [",
                scene->name, def->base_length, seed_given ? seed : (unsigned long long)scene->seed,
                geo.g, geo.dt, geo.row_period, geo.row_size, dep.rows, dep.released, dep.pile,
                dep.lost, dep.equilibrium ? "true" : "false", dep.height, dep.time, dep.steps,
                dep.wall_seconds);
            sim_world_destroy(world);
        }
        pile = pile_path;
    } else {
        used += (size_t)snprintf(
            summary + used, summary_size - used,
            "{\n  \"scene\": \"%s\",\n  \"pile\": \"%s\",\n  \"discharges\": [", scene->name, pile);
    }
    size_t csv_size = 512 + 256 * (size_t)width_count;
    char *csv = malloc(csv_size);
    if (!csv)
        abort();
    size_t csv_used = (size_t)snprintf(csv, csv_size, "%s\n", app_discharge_csv_header());
    for (int k = 0; status == 0 && k < width_count; ++k) {
        char wname[32];
        app_discharge_width_name(widths[k], wname, sizeof wname);
        AppFrames frames;
        snprintf(path, sizeof path, "%s/%s.mp4", dir, wname);
        if (app_discharge_movie_start(&movie, scene, path, &frames, frame_time, geo.dt) != 0) {
            status = 2;
            break;
        }
        AppDischarge r;
        SimWorld *world = app_discharge(scene, pile, widths[k], &frames, &r, err, sizeof err);
        if (app_discharge_movie_finish(&movie) != 0)
            status = 2;
        if (!world) {
            fprintf(stderr, "sablier: discharge w = %g d: %s\n", widths[k], err);
            status = 1;
            break;
        }
        snprintf(path, sizeof path, "%s/%s.state", dir, wname);
        SimError error;
        if (sim_world_save(world, path, &error) != SIM_OK)
            status = 2;
        if (figures) {
            char title[160];
            snprintf(title, sizeof title, "w = %g d: s = %ld, h = %.3g d, arch of %d grains",
                     widths[k], r.through, r.height, r.arch);
            snprintf(path, sizeof path, "%s/%s.png", dir, wname);
            if (app_discharge_figure(render, scene, world, &r, title, path) != 0)
                status = 2;
        }
        sim_world_destroy(world);
        char row[512];
        app_discharge_csv_row(&r, 0, def->base_length, row, sizeof row);
        csv_used += (size_t)snprintf(csv + csv_used, csv_size - csv_used, "%s\n", row);
        used += (size_t)snprintf(
            summary + used, summary_size - used,
            "%s\n    {\"w\": %.10g, \"s\": %ld, \"edges\": %ld, \"h\": %.10g, \"pile\": %d, "
            "\"arch\": %d, \"arch_species\": [%d, %d], \"equilibrium\": %s, \"time\": %.10g, "
            "\"wall_seconds\": %.4g}",
            k ? "," : "", r.width, r.through, r.edges, r.height, r.pile, r.arch, r.arch_species[0],
            r.arch_species[1], r.equilibrium ? "true" : "false", r.time, r.wall_seconds);
        if (!quiet)
            fprintf(stderr,
                    "sablier: discharge w = %g d: s = %ld through, %ld over the edges, h = %.4g d, "
                    "arch %d grains, %s (%.3g s)\n",
                    widths[k], r.through, r.edges, r.height, r.arch,
                    r.equilibrium ? "static equilibrium" : "NOT at equilibrium (cap)",
                    r.wall_seconds);
    }
    snprintf(path, sizeof path, "%s/discharge.csv", dir);
    if (width_count > 0 && status == 0 && app_write_atomic(path, csv) != 0)
        status = 2;
    if (used > 0) {
        snprintf(summary + used, summary_size - used, "\n  ],\n  \"status\": \"%s\"\n}\n",
                 status == 0 ? "ok" : "error");
        snprintf(path, sizeof path, "%s/summary.json", dir);
        if (app_write_atomic(path, summary) != 0 && status == 0)
            status = 2;
    }
    free(csv);
    free(summary);
    scene_free(scene);
    return status;
}

const AppCommand app_discharge_commands[] = {
    {"discharge", "discharge SCENE  build an open pile and discharge it through an orifice (004)",
     APP_DISCHARGE_USAGE, discharge_command},
    {"study", "study SCENE    jamming statistics over base lengths and widths (004)",
     APP_STUDY_USAGE, app_study_command},
};
