/* SPDX-License-Identifier: MIT */
/* wall_loads.c: the forces on the walls as a measure (docs/measures.md, "Forces on walls"):
 * `output.walls = { window = [t0, t1]; }` writes DIR/walls.csv, one row per wall at every energy
 * row (output.energy_every): the force of the grains on it (x, y, normal, tangential), its torque,
 * the normal stress (force per length), its centre and, for a responding wall, its offset and
 * speed (sim.h SimWallLoad); the grain bodies (`bodies`, rough pistons) follow the walls, numbered
 * on from them. The rows whose time lies in the window are averaged into
 * summary.json's "walls" (the steady mean). Not a family: a core layer that rides on the
 * experiment hooks, as app/output/measures.c does. */
#include "base/checkpoint.h"
#include "base/experiment.h"
#include "base/util.h"
#include "scene/scene_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The averaged quantities of a wall: fx, fy, normal, tangential, torque, stress, offset. */
enum { MEAN_COUNT = 7 };

typedef struct WallLoads {
    const Scene *scene;
    double from, to; /* the averaging window, s of simulated time */
    int wall_count;
    char path[4096];
    FILE *csv;
    double samples; /* rows averaged (per wall) */
    double *sums;   /* MEAN_COUNT per wall */
    /* per wall, a servo's steps spent flipping between its caps (sim.h SimWallLoad servo_flips)
     * at the last look; -1 without a servo */
    double *flips;
} WallLoads;

/* Body k of the scene (its walls, then its grain bodies) has a servo. */
static int has_servo(const Scene *scene, int k)
{
    const int walls = scene->def.wall_count;
    if (k < walls)
        return scene->def.wall_bodies && scene->def.wall_bodies[k].active &&
               scene->def.wall_bodies[k].servo;
    return scene->def.grain_bodies[k - walls].servo;
}

/* The servos' flip counts from the world as it is now. */
static void look_at_flips(WallLoads *w, const SimWorld *world)
{
    for (int k = 0; world && k < w->wall_count; ++k) {
        SimWallLoad l;
        if (w->flips[k] >= 0.0 && sim_world_wall_load(world, k, &l) == 0)
            w->flips[k] = (double)l.servo_flips;
    }
}

static int wall_loads_parse(const config_setting_t *root, const config_setting_t *group,
                            Scene *scene, void **state, char *err, size_t err_size)
{
    (void)group;
    *state = NULL;
    AppConfig p = {.path = scene->path, .err = err, .err_size = err_size, .group = "output"};
    static const char *const keys[] = {"window", NULL};
    const config_setting_t *output = config_setting_get_member(root, "output"), *g = NULL;
    if (!output || !app_config_member(output, "walls"))
        return 0;
    if (app_config_group(&p, output, "walls", &g) < 0 ||
        app_config_keys(&p, g, "output.walls", keys, NULL) < 0)
        return -1;
    double window[2] = {0.0, INFINITY};
    if (app_config_vector(&p, g, "window", window, 2) < 0)
        return -1;
    if (!(window[0] >= 0.0) || !(window[1] > window[0]))
        return app_config_fail(&p, app_config_member(g, "window"),
                               "`window` = [t0, t1] needs 0 <= t0 < t1 (simulated time)");
    const int count = scene->def.wall_count + scene->def.grain_body_count;
    if (count == 0)
        return app_config_fail(&p, g, "`output.walls`: the scene has no walls");
    if (scene_claim_output(scene, &p, g, "output.walls", "walls.csv") < 0 ||
        scene_claim_output(scene, &p, g, "output.walls", "walls.png") < 0)
        return -1;
    WallLoads *w = calloc(1, sizeof *w);
    if (w) {
        w->sums = calloc((size_t)count * MEAN_COUNT, sizeof *w->sums);
        w->flips = calloc((size_t)count, sizeof *w->flips);
    }
    if (!w || !w->sums || !w->flips) {
        if (w) {
            free(w->sums);
            free(w->flips);
        }
        free(w);
        return app_config_fail(&p, g, "out of memory");
    }
    for (int k = 0; k < count; ++k)
        w->flips[k] = has_servo(scene, k) ? 0.0 : -1.0;
    w->scene = scene;
    w->from = window[0];
    w->to = window[1];
    w->wall_count = count;
    *state = w;
    return 0;
}

static void wall_loads_free(void *state)
{
    WallLoads *w = state;
    app_tmp_discard(&w->csv, w->path);
    free(w->sums);
    free(w->flips);
    free(w);
}

static int wall_loads_begin(void *state, AppContext *c)
{
    WallLoads *w = state;
    snprintf(w->path, sizeof w->path, "%s/walls.csv", c->out_dir);
    w->csv = app_tmp_open(w->path, "t,stage,wall,fx,fy,normal,tangential,torque,stress,x,y,"
                                   "offset,speed,contacts");
    if (!w->csv) {
        snprintf(c->err, c->err_size, "cannot write %s.tmp", w->path);
        return -1;
    }
    return 0;
}

static void wall_loads_sample(void *state, AppContext *c)
{
    WallLoads *w = state;
    if (!c->world || !w->csv)
        return;
    const double t = sim_world_time(c->world);
    const int in_window = t >= w->from && t <= w->to;
    const char *stage = c->stage >= 0 ? w->scene->stages[c->stage].name : "";
    for (int k = 0; k < w->wall_count; ++k) {
        SimWallLoad l;
        if (sim_world_wall_load(c->world, k, &l) != 0)
            continue;
        const double stress = l.length > 0.0 ? l.normal / l.length : 0.0;
        fprintf(w->csv, "%.9g,%s,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n", t,
                stage, k, l.fx, l.fy, l.normal, l.tangential, l.torque, stress, l.x, l.y, l.offset,
                l.speed, l.contacts);
        if (in_window) {
            const double v[MEAN_COUNT] = {l.fx,     l.fy,   l.normal, l.tangential,
                                          l.torque, stress, l.offset};
            for (int q = 0; q < MEAN_COUNT; ++q)
                w->sums[k * MEAN_COUNT + q] += v[q];
        }
    }
    w->samples += in_window;
    look_at_flips(w, c->world);
}

static int wall_loads_end(void *state, AppContext *c, int ok)
{
    (void)ok;
    WallLoads *w = state;
    look_at_flips(w, c->world);
    if (app_tmp_commit(&w->csv, w->path) != 0) {
        snprintf(c->err, c->err_size, "cannot write %s", w->path);
        return -1;
    }
    return 0;
}

/* A checkpoint: the sample count, the sums and the length of walls.csv. */
static int wall_loads_checkpoint(const void *state, const AppContext *c, FILE *out)
{
    (void)c;
    const WallLoads *w = state;
    app_checkpoint_put(out, "walls_samples", &w->samples, 1);
    app_checkpoint_put(out, "walls_sums", w->sums, (long)w->wall_count * MEAN_COUNT);
    app_checkpoint_file(out, w->path, w->csv);
    return 0;
}

static int wall_loads_resume(void *state, AppContext *c, const char *record)
{
    WallLoads *w = state;
    if (app_checkpoint_take(record, "walls_samples", &w->samples, 1) != 0 ||
        app_checkpoint_take(record, "walls_sums", w->sums, (long)w->wall_count * MEAN_COUNT) != 0 ||
        app_checkpoint_reopen(record, w->path, &w->csv) != 0) {
        snprintf(c->err, c->err_size,
                 "--resume: walls: the checkpoint's record is malformed, or %s is shorter than it "
                 "records",
                 w->path);
        return -1;
    }
    return 0;
}

/* "walls": {"window": [t0, t1], "samples": N, "mean": [{"wall": k, "fx": N, "fy": N, "normal": N,
 * "tangential": N, "torque": N m, "stress": N/m, "offset": m[, "servo_flips": n]}, ...]}. */
static void wall_loads_summary_json(const void *state, char *out, size_t size)
{
    static const char *const names[MEAN_COUNT] = {"fx",     "fy",     "normal", "tangential",
                                                  "torque", "stress", "offset"};
    const WallLoads *w = state;
    size_t n = (size_t)snprintf(out, size,
                                "  \"walls\": {\"window\": [%.10g, %.10g], "
                                "\"samples\": %.0f, \"mean\": [",
                                w->from, isfinite(w->to) ? w->to : -1.0, w->samples);
    for (int k = 0; k < w->wall_count && n < size; ++k) {
        n += (size_t)snprintf(out + n, size - n, "%s{\"wall\": %d", k ? ", " : "", k);
        for (int q = 0; q < MEAN_COUNT && n < size; ++q) {
            const double mean = w->samples > 0.0 ? w->sums[k * MEAN_COUNT + q] / w->samples : 0.0;
            n += (size_t)snprintf(out + n, size - n, ", \"%s\": %.10g", names[q], mean);
        }
        if (w->flips[k] >= 0.0 && n < size) /* a servo's: 0 unless its mean is biased */
            n += (size_t)snprintf(out + n, size - n, ", \"servo_flips\": %.0f", w->flips[k]);
        if (n < size)
            n += (size_t)snprintf(out + n, size - n, "}");
    }
    if (n < size)
        snprintf(out + n, size - n, "]},\n");
}

/* Each wall's stress (t, sigma) read back from walls.csv (the whole run, a resumed one too):
 * column 0 the time, 2 the wall, 8 the stress. 0, or -1. */
typedef struct WallSeries {
    int count, capacity;
    double *t, *stress;
} WallSeries;

static int read_series(const WallLoads *w, WallSeries *series)
{
    FILE *f = sim_open_input(w->path, NULL);
    if (!f)
        return -1;
    char line[1024];
    int rc = fgets(line, sizeof line, f) ? 0 : -1; /* the header */
    while (rc == 0 && fgets(line, sizeof line, f)) {
        double v[9];
        char *p = line;
        int n = 0;
        for (; n < 9 && p; ++n, p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL)
            v[n] = n == 1 ? 0.0 : strtod(p, NULL); /* column 1: the stage's name */
        int k = n == 9 ? (int)v[2] : -1;
        if (k < 0 || k >= w->wall_count)
            continue;
        WallSeries *s = &series[k];
        if (s->count == s->capacity && app_series_grow(&s->t, &s->stress, &s->capacity, 256) != 0)
            rc = -1;
        else {
            s->t[s->count] = v[0];
            s->stress[s->count++] = v[8];
        }
    }
    fclose(f);
    return rc;
}

/* walls.png (and render.plot_format's copy): each wall's normal stress against time, in the
 * scene's units; walls.csv is its data. */
static int wall_loads_figures(const void *state, const AppContext *c)
{
    const WallLoads *w = state;
    if (!c->render || !c->render->plot)
        return 0;
    WallSeries *series = calloc((size_t)w->wall_count, sizeof *series);
    AppPlotSeries *plotted = calloc((size_t)w->wall_count, sizeof *plotted);
    char(*labels)[32] = calloc((size_t)w->wall_count, sizeof *labels);
    int rc = series && plotted && labels ? read_series(w, series) : -1;
    for (int k = 0; rc == 0 && k < w->wall_count; ++k) {
        snprintf(labels[k], sizeof labels[k], "wall %d", k);
        plotted[k] = (AppPlotSeries){.label = labels[k],
                                     .count = series[k].count,
                                     .x = series[k].t,
                                     .y = series[k].stress,
                                     .line = 1,
                                     .rgb = APP_RGB_AUTO};
    }
    char x_label[64], y_label[64], title[SCENE_NAME_MAX + 48], path[sizeof w->path], err[512] = "";
    AppPlotPanel panel = {
        .x_label = scene_axis_label(w->scene, "t", SCENE_TIME, x_label, sizeof x_label),
        .y_label = scene_axis_label(w->scene, "\\sigma_n", SCENE_STRESS, y_label, sizeof y_label),
        .legend = w->wall_count > 1 ? APP_LEGEND_AUTO : APP_LEGEND_NONE,
        .series_count = w->wall_count,
        .series = plotted};
    snprintf(title, sizeof title, "%s: normal stress on the walls", w->scene->name);
    AppPlot plot = {.title = title,
                    .width = 1000,
                    .height = 600,
                    .panel_count = 1,
                    .panels = &panel,
                    .scene = w->scene->name,
                    .seed = w->scene->seed,
                    .print = &w->scene->style,
                    .data_beside = 1}; /* walls.csv */
    snprintf(path, sizeof path, "%s/walls.png", c->out_dir);
    if (rc != 0)
        snprintf(c->err, c->err_size, "walls.png: cannot read %s", w->path);
    else if ((rc = c->render->plot(c->render->context, &plot, path, err, sizeof err)) != 0)
        snprintf(c->err, c->err_size, "figure %s: %s", path, err);
    for (int k = 0; series && k < w->wall_count; ++k) {
        free(series[k].t);
        free(series[k].stress);
    }
    free(series);
    free(plotted);
    free(labels);
    return rc;
}

static const char *const output_keys[] = {"walls", NULL};

const AppExperiment app_wall_loads_experiment = {
    .name = "wall_loads",
    .output_keys = output_keys,
    .parse = wall_loads_parse,
    .free = wall_loads_free,
    .begin = wall_loads_begin,
    .sample = wall_loads_sample,
    .end = wall_loads_end,
    .checkpoint = wall_loads_checkpoint,
    .resume = wall_loads_resume,
    .summary_json = wall_loads_summary_json,
    .figures = wall_loads_figures,
};
