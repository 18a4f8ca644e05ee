/* SPDX-License-Identifier: MIT */
/* surface.c: the `surface` family (surface.h). `surface = { x0; x1; bins; stage; after; }` in a
 * scene: at every energy row of the stage, the free surface over [x0, x1] in `bins` columns
 * (sim_world_surface_profile: the highest grain top per column, 000 §5.4) is fitted by a
 * least-squares line; surface.csv holds t, the angle (degrees, counter-clockwise from +x), the
 * slope, the intercept and the columns used; summary.json the mean angle from `after` s into
 * the stage on. */
#include "surface.h"

#include "base/checkpoint.h"
#include "base/config.h"
#include "base/util.h"
#include "driver/stats.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SURFACE_MAX_BINS 512

typedef struct SurfaceState {
    double x0, x1, after; /* m, m, s */
    int bins, stage;
    FILE *csv;
    char path[SCENE_PATH_MAX + 32];
    double sum, last;
    long samples;
} SurfaceState;

static int surface_parse(const config_setting_t *root, const config_setting_t *group,
                         struct Scene *scene, void **state, char *err, size_t err_size)
{
    static const char *const keys[] = {"x0", "x1", "bins", "stage", "after", NULL};
    (void)root;
    *state = NULL;
    if (!group)
        return 0;
    AppConfig p = {.path = scene->path, .err = err, .err_size = err_size, .group = "surface"};
    SurfaceState *s = calloc(1, sizeof *s);
    if (!s)
        return app_config_fail(&p, group, "out of memory");
    *state = s;
    long long bins = 24;
    const char *stage = NULL;
    if (app_config_keys(&p, group, "surface", keys, NULL) < 0 ||
        app_config_need_number(&p, group, "x0", "surface", &s->x0) < 0 ||
        app_config_need_number(&p, group, "x1", "surface", &s->x1) < 0 ||
        app_config_int(&p, group, "bins", &bins) < 0 ||
        app_config_string(&p, group, "stage", &stage) < 0 ||
        app_config_number(&p, group, "after", &s->after) < 0 ||
        app_config_non_negative(&p, group, "after", s->after) < 0)
        return -1;
    if (!(s->x1 > s->x0))
        return app_config_fail(&p, group, "needs x1 > x0");
    if (bins < 2 || bins > SURFACE_MAX_BINS)
        return app_config_fail(&p, app_config_member(group, "bins"), "`bins` must be in [2, %d]",
                               SURFACE_MAX_BINS);
    s->bins = (int)bins;
    s->stage = stage ? scene_stage_index(scene, stage) : scene->stage_count - 1;
    if (s->stage < 0)
        return app_config_fail(&p, app_config_member(group, "stage"), "no stage named `%s`", stage);
    return 0;
}

static void surface_free(void *state)
{
    free(state);
}

static int surface_begin(void *state, AppContext *c)
{
    SurfaceState *s = state;
    snprintf(s->path, sizeof s->path, "%s/surface.csv", c->out_dir);
    s->csv = app_tmp_open(s->path, "t,angle_deg,slope,intercept,columns");
    if (!s->csv) {
        snprintf(c->err, c->err_size, "cannot write %s", s->path);
        return -1;
    }
    return 0;
}

static void surface_sample(void *state, AppContext *c)
{
    SurfaceState *s = state;
    if (c->stage != s->stage || !s->csv)
        return;
    double x[SURFACE_MAX_BINS], y[SURFACE_MAX_BINS], slope, intercept;
    const double w = (s->x1 - s->x0) / s->bins;
    sim_world_surface_profile(c->world, s->x0, s->x1, s->bins, y);
    int used = 0;
    for (int k = 0; k < s->bins; ++k) {
        x[k] = s->x0 + (k + 0.5) * w;
        used += isfinite(y[k]) != 0;
    }
    if (app_linear_fit(x, y, s->bins, &intercept, &slope, NULL) != 0)
        return;
    const double t = sim_world_time(c->world), angle = atan(slope) * 180.0 / SIM_PI;
    fprintf(s->csv, "%.10g,%.10g,%.10g,%.10g,%d\n", t, angle, slope, intercept, used);
    s->last = angle;
    if (t - c->stage_start >= s->after) {
        s->sum += angle;
        s->samples++;
    }
}

static int surface_end(void *state, AppContext *c, int ok)
{
    SurfaceState *s = state;
    if (!ok && !c->checkpointed) { /* interrupted at a checkpoint: kept for --resume */
        app_tmp_discard(&s->csv, s->path);
        return 0;
    }
    if (app_tmp_commit(&s->csv, s->path) != 0) {
        snprintf(c->err, c->err_size, "cannot write %s", s->path);
        return -1;
    }
    return 0;
}

/* A checkpoint: the mean's sum and count, the last angle and surface.csv's length. */
static int surface_checkpoint(const void *state, const AppContext *c, FILE *out)
{
    (void)c;
    const SurfaceState *s = state;
    const double v[3] = {s->sum, s->last, (double)s->samples};
    app_checkpoint_put(out, "surface", v, 3);
    app_checkpoint_file(out, s->path, s->csv);
    return 0;
}

static int surface_resume(void *state, AppContext *c, const char *record)
{
    SurfaceState *s = state;
    double v[3];
    if (app_checkpoint_take(record, "surface", v, 3) != 0 ||
        app_checkpoint_reopen(record, s->path, &s->csv) != 0) {
        snprintf(c->err, c->err_size,
                 "--resume: the surface section of the checkpoint is malformed, or %s is "
                 "shorter than it records",
                 s->path);
        return -1;
    }
    s->sum = v[0];
    s->last = v[1];
    s->samples = (long)v[2];
    return 0;
}

static void surface_summary_json(const void *state, char *out, size_t size)
{
    const SurfaceState *s = state;
    if (s->samples > 0)
        snprintf(out, size,
                 "  \"surface_angle_deg\": %.10g,\n  \"surface_angle_last_deg\": %.10g,\n"
                 "  \"surface_samples\": %ld,\n",
                 s->sum / (double)s->samples, s->last, s->samples);
    else
        snprintf(out, size, "  \"surface_angle_deg\": null,\n");
}

static const char *const OUTPUTS[] = {"surface.csv", NULL};
const AppExperiment app_surface_experiment = {
    .name = "surface",
    .outputs = OUTPUTS,
    .group = "surface",
    .parse = surface_parse,
    .free = surface_free,
    .begin = surface_begin,
    .sample = surface_sample,
    .end = surface_end,
    .checkpoint = surface_checkpoint,
    .resume = surface_resume,
    .summary_json = surface_summary_json,
};
