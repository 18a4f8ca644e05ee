/* SPDX-License-Identifier: MIT */
/* depth.c: the depth of a projectile in a bed followed in time (docs/measures.md, "Penetration
 * depth"): `output.depth = { species = "projectile"; width = 1.0; }` writes DIR/depth.csv at
 * every energy row (output.energy_every) once a mobile grain of that species exists: the depth of
 * its lowest point below the bed's initial surface, d = h_0 - min (y - r) over the species'
 * grains, with h_0 taken at the first such row as the mean over `columns` equal columns of
 * [x_p - width / 2, x_p + width / 2] (x_p: the projectile's centre then) of the highest top
 * y + r of the other mobile grains (the surface of scripts/experiments/impact.py). The largest
 * depth and its time go to summary.json ("depth"), the curve to depth.png. The penetration of
 * an impactor into a granular bed: Uehara et al. (2003), Phys. Rev. Lett. 90, 194301. Not a
 * family: a core layer on the experiment hooks, as app/output/wall_loads.c. */
#include "base/checkpoint.h"
#include "base/experiment.h"
#include "base/util.h"
#include "scene/scene_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEPTH_MAX_COLUMNS 64

typedef struct Depth {
    const Scene *scene;
    int species;
    double width;
    int columns;
    char path[4096];
    FILE *csv;
    /* kept across a checkpoint: found (0/1), h_0, the largest depth and its time, rows */
    double found, surface, max, t_max, rows;
} Depth;

static int depth_parse(const config_setting_t *root, const config_setting_t *group, Scene *scene,
                       void **state, char *err, size_t err_size)
{
    (void)group;
    *state = NULL;
    AppConfig p = {.path = scene->path, .err = err, .err_size = err_size, .group = "output"};
    static const char *const keys[] = {"species", "width", "columns", NULL};
    const config_setting_t *output = config_setting_get_member(root, "output"), *g = NULL;
    if (!output || !app_config_member(output, "depth"))
        return 0;
    const char *name = NULL;
    double width = 0.0;
    long long columns = 5;
    if (app_config_group(&p, output, "depth", &g) < 0 ||
        app_config_keys(&p, g, "output.depth", keys, NULL) < 0 ||
        app_config_need(&p, g, "species", "output.depth") < 0 ||
        app_config_string(&p, g, "species", &name) < 0 ||
        app_config_need_number(&p, g, "width", "output.depth", &width) < 0 ||
        app_config_positive(&p, g, "width", width) < 0 ||
        app_config_int(&p, g, "columns", &columns) < 0)
        return -1;
    if (columns < 1 || columns > DEPTH_MAX_COLUMNS)
        return app_config_fail(&p, app_config_member(g, "columns"), "`columns` must be 1 to %d",
                               DEPTH_MAX_COLUMNS);
    int species = -1;
    for (int k = 0; k < scene->def.species_count; ++k)
        if (strcmp(scene->species_names[k], name) == 0)
            species = k;
    if (species < 0)
        return app_config_fail(&p, app_config_member(g, "species"), "no species named `%s`", name);
    if (scene_claim_output(scene, &p, g, "output.depth", "depth.csv") < 0 ||
        scene_claim_output(scene, &p, g, "output.depth", "depth.png") < 0)
        return -1;
    Depth *d = calloc(1, sizeof *d);
    if (!d)
        return app_config_fail(&p, g, "out of memory");
    d->scene = scene;
    d->species = species;
    d->width = width;
    d->columns = (int)columns;
    *state = d;
    return 0;
}

static void depth_free(void *state)
{
    Depth *d = state;
    app_tmp_discard(&d->csv, d->path);
    free(d);
}

static int depth_begin(void *state, AppContext *c)
{
    Depth *d = state;
    snprintf(d->path, sizeof d->path, "%s/depth.csv", c->out_dir);
    d->csv = app_tmp_open(d->path, "t (s),stage,depth (m),bottom (m),x (m),surface (m)"); /* SI */
    if (!d->csv) {
        snprintf(c->err, c->err_size, "cannot write %s.tmp", d->path);
        return -1;
    }
    return 0;
}

/* h_0: the mean over d->columns columns around x_p of the highest top of the other mobile grains
 * (columns without one left out); NAN when none has one. */
static double bed_surface(const Depth *d, const SimFrame *f, double x_p)
{
    double top[DEPTH_MAX_COLUMNS];
    const double x0 = x_p - 0.5 * d->width, cell = d->width / d->columns;
    for (int k = 0; k < d->columns; ++k)
        top[k] = -INFINITY;
    for (int i = 0; i < f->mobile_count; ++i) {
        const int k = (int)floor((f->x[i] - x0) / cell);
        if (f->species[i] != d->species && k >= 0 && k < d->columns)
            top[k] = fmax(top[k], f->y[i] + f->radius[i]);
    }
    double sum = 0.0;
    int n = 0;
    for (int k = 0; k < d->columns; ++k)
        if (isfinite(top[k])) {
            sum += top[k];
            ++n;
        }
    return n ? sum / n : (double)NAN;
}

static void depth_sample(void *state, AppContext *c)
{
    Depth *d = state;
    if (!c->world || !d->csv)
        return;
    SimFrame f;
    sim_world_frame(c->world, &f);
    int lowest = -1;
    for (int i = 0; i < f.mobile_count; ++i)
        if (f.species[i] == d->species &&
            (lowest < 0 || f.y[i] - f.radius[i] < f.y[lowest] - f.radius[lowest]))
            lowest = i;
    if (lowest < 0)
        return; /* no projectile yet (or any more) */
    const double bottom = f.y[lowest] - f.radius[lowest], t = f.time;
    if (!d->found) {
        d->surface = bed_surface(d, &f, f.x[lowest]);
        d->found = 1.0;
        d->max = -INFINITY;
    }
    const double depth = d->surface - bottom;
    if (depth > d->max) {
        d->max = depth;
        d->t_max = t;
    }
    ++d->rows;
    fprintf(d->csv, "%.9g,%s,%.9g,%.9g,%.9g,%.9g\n", t,
            c->stage >= 0 ? d->scene->stages[c->stage].name : "", depth, bottom, f.x[lowest],
            d->surface);
}

static int depth_end(void *state, AppContext *c, int ok)
{
    (void)ok;
    Depth *d = state;
    if (app_tmp_commit(&d->csv, d->path) != 0) {
        snprintf(c->err, c->err_size, "cannot write %s", d->path);
        return -1;
    }
    return 0;
}

static int depth_checkpoint(const void *state, const AppContext *c, FILE *out)
{
    (void)c;
    const Depth *d = state;
    const double kept[5] = {d->found, d->surface, d->max, d->t_max, d->rows};
    app_checkpoint_put(out, "depth", kept, 5);
    app_checkpoint_file(out, d->path, d->csv);
    return 0;
}

static int depth_resume(void *state, AppContext *c, const char *record)
{
    Depth *d = state;
    double kept[5];
    if (app_checkpoint_take(record, "depth", kept, 5) != 0 ||
        app_checkpoint_reopen(record, d->path, &d->csv) != 0) {
        snprintf(c->err, c->err_size,
                 "--resume: depth: the checkpoint's record is malformed, or %s is shorter than it "
                 "records",
                 d->path);
        return -1;
    }
    d->found = kept[0];
    d->surface = kept[1];
    d->max = kept[2];
    d->t_max = kept[3];
    d->rows = kept[4];
    return 0;
}

/* "depth": {"species": S, "surface": m, "rows": N, "max": m, "t_max": s} (max and t_max null
 * when no grain of the species appeared). */
static void depth_summary_json(const void *state, char *out, size_t size)
{
    const Depth *d = state;
    if (!d->found) {
        snprintf(out, size,
                 "  \"depth\": {\"species\": \"%s\", \"surface\": null, \"rows\": 0, \"max\": "
                 "null, \"t_max\": null},\n",
                 d->scene->species_names[d->species]);
        return;
    }
    snprintf(out, size,
             "  \"depth\": {\"species\": \"%s\", \"surface\": %.10g, \"rows\": %.0f, \"max\": "
             "%.10g, \"t_max\": %.10g},\n",
             d->scene->species_names[d->species], d->surface, d->rows, d->max, d->t_max);
}

/* The (t, depth) rows of depth.csv (a resumed run's too). 0, or -1. */
static int read_curve(const Depth *d, double **t, double **depth, int *count)
{
    FILE *f = sim_open_input(d->path, NULL);
    if (!f)
        return -1;
    char line[512];
    int capacity = 0, rc = fgets(line, sizeof line, f) ? 0 : -1; /* the header */
    while (rc == 0 && fgets(line, sizeof line, f)) {
        const char *stage_end = strchr(line, ',');
        const char *depth_at = stage_end ? strchr(stage_end + 1, ',') : NULL;
        if (!depth_at)
            continue;
        if (*count == capacity && app_series_grow(t, depth, &capacity, 256) != 0)
            rc = -1;
        else {
            (*t)[*count] = strtod(line, NULL);
            (*depth)[(*count)++] = strtod(depth_at + 1, NULL);
        }
    }
    fclose(f);
    return rc;
}

/* depth.png: the depth against time, in the scene's units; depth.csv is its data. */
static int depth_figures(const void *state, const AppContext *c)
{
    const Depth *d = state;
    if (!c->render || !c->render->plot || !d->found)
        return 0;
    double *t = NULL, *depth = NULL;
    int count = 0, rc = read_curve(d, &t, &depth, &count);
    AppPlotSeries series = {.label = d->scene->species_names[d->species],
                            .count = count,
                            .x = t,
                            .y = depth,
                            .line = 1,
                            .rgb = APP_RGB_AUTO};
    char x_label[64], y_label[64], title[SCENE_NAME_MAX + 48], path[sizeof d->path], err[512] = "";
    AppPlotPanel panel = {
        .x_label = scene_axis_label(d->scene, "t", SCENE_TIME, x_label, sizeof x_label),
        .y_label = scene_axis_label(d->scene, "depth", SCENE_LENGTH, y_label, sizeof y_label),
        .legend = APP_LEGEND_NONE,
        .series_count = 1,
        .series = &series};
    snprintf(title, sizeof title, "%s: depth below the bed's surface", d->scene->name);
    AppPlot plot = {.title = title,
                    .width = 1000,
                    .height = 600,
                    .panel_count = 1,
                    .panels = &panel,
                    .scene = d->scene->name,
                    .seed = d->scene->seed,
                    .print = &d->scene->style,
                    .data_beside = 1}; /* depth.csv */
    snprintf(path, sizeof path, "%s/depth.png", c->out_dir);
    if (rc != 0)
        snprintf(c->err, c->err_size, "depth.png: cannot read %s", d->path);
    else if ((rc = c->render->plot(c->render->context, &plot, path, err, sizeof err)) != 0)
        snprintf(c->err, c->err_size, "figure %s: %s", path, err);
    free(t);
    free(depth);
    return rc;
}

static const char *const output_keys[] = {"depth", NULL};

const AppExperiment app_depth_experiment = {
    .name = "depth",
    .output_keys = output_keys,
    .parse = depth_parse,
    .free = depth_free,
    .begin = depth_begin,
    .sample = depth_sample,
    .end = depth_end,
    .checkpoint = depth_checkpoint,
    .resume = depth_resume,
    .summary_json = depth_summary_json,
    .figures = depth_figures,
};
