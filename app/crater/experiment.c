/* SPDX-License-Identifier: MIT */
/* crater/experiment.c: the crater-collapse family (thesis 000) behind app/experiment.h. Owns the
 * stages' `dig` keys (a cavity dug at the stage start, 000 §4.1 stage 2) and `output.profile_every`
 * / `output.profile_bin` (free-surface profiles), runs the observer of crater.c during a run and
 * draws the energy and profile figures after it; `sablier sweep` (sweep.c) is its driver. */
#include "checkpoint.h"
#include "config.h"
#include "crater.h"
#include "experiments.h"
#include "sweep.h"
#include "util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct AppCraterState {
    AppCraterDig dig[SCENE_MAX_STAGES];
    double profile_every; /* s between free-surface profiles (0 = stage ends only) */
    double profile_bin;   /* m, 0 = the mean diameter */
    int energy_stage;     /* the stage energy_panels.png draws, -1 = the last */
    AppObserver *observer;
    long every_profile; /* steps, in the current stage; > stage steps: off */
    long done;          /* steps of the current stage, as last seen */
    char json[1024];    /* summary.json members, taken before the observer closes */
};

const AppCraterState *app_crater_of(const Scene *scene)
{
    return scene_experiment_state(scene, &app_crater_experiment);
}

AppCraterDig app_crater_dig(const Scene *scene, int stage)
{
    const AppCraterState *c = app_crater_of(scene);
    AppCraterDig none = {0};
    return c && stage >= 0 && stage < SCENE_MAX_STAGES ? c->dig[stage] : none;
}

/* ---------------------------------------------------------------- parse */

/* dig = { center_x; width; height; top = "surface" | m; } (000 §4.1 stage 2), in stage g */
static int parse_dig(AppConfig *p, const config_setting_t *stage, AppCraterDig *dig)
{
    static const char *const keys[] = {"center_x", "width", "height", "top", NULL};
    const config_setting_t *g;
    int found = app_config_group(p, stage, "dig", &g);
    if (found <= 0)
        return found;
    if (app_config_keys(p, g, "dig", keys, NULL) < 0)
        return -1;
    dig->dig = 1;
    dig->top_surface = 1;
    if (app_config_need_number(p, g, "center_x", "dig", &dig->center_x) < 0 ||
        app_config_need_number(p, g, "width", "dig", &dig->width) < 0 ||
        app_config_positive(p, g, "width", dig->width) < 0 ||
        app_config_need_number(p, g, "height", "dig", &dig->height) < 0 ||
        app_config_positive(p, g, "height", dig->height) < 0)
        return -1;
    const config_setting_t *top = app_config_member(g, "top");
    if (top && config_setting_type(top) == CONFIG_TYPE_STRING) {
        if (strcmp(config_setting_get_string(top), "surface") != 0)
            return app_config_fail(p, top, "`top` must be \"surface\" or a height in m");
    } else if (top) {
        dig->top_surface = 0;
        if (app_config_number(p, g, "top", &dig->top) < 0)
            return -1;
    }
    return 0;
}

/* A dig whose cavity lies beside everything the scene defines (its grains and walls, x) can
 * only fail after the earlier stages ran: refused at load (a centre of 1e308). Scenes whose
 * grains all come from elsewhere (a loaded state, sources) are not checked. */
static int dig_within(AppConfig *p, const config_setting_t *stage, const Scene *scene,
                      const AppCraterDig *dig)
{
    if (!dig->dig)
        return 0;
    double x0 = INFINITY, x1 = -INFINITY;
    for (int i = 0; i < scene->grains.count; ++i) {
        x0 = fmin(x0, scene->grains.x[i] - scene->grains.radius[i]);
        x1 = fmax(x1, scene->grains.x[i] + scene->grains.radius[i]);
    }
    for (int k = 0; k < scene->def.wall_count; ++k) {
        double a, b, c, d;
        sim_wall_bounds(&scene->def.walls[k], &a, &b, &c, &d);
        x0 = fmin(x0, a);
        x1 = fmax(x1, c);
    }
    if (!(x1 >= x0) || scene->source_count > 0)
        return 0;
    const double left = dig->center_x - 0.5 * dig->width, right = dig->center_x + 0.5 * dig->width;
    if (right > x0 && left < x1)
        return 0;
    const config_setting_t *g = config_setting_get_member(stage, "dig");
    return app_config_fail(p, g ? config_setting_get_member(g, "center_x") : stage,
                           "dig: the cavity [%g, %g] m lies outside the scene's grains and walls "
                           "(x in [%g, %g] m)",
                           left, right, x0, x1);
}

/* energy_stage = "NAME": the stage whose energies energy_panels.png draws (000 fig. 6.15 shows
 * the deposit, figs. 7.1-7.8 the collapse); a stage that runs for some time */
static int parse_energy_stage(AppConfig *p, const config_setting_t *output, const Scene *scene,
                              int *stage)
{
    const char *name = NULL;
    *stage = -1;
    if (app_config_string(p, output, "energy_stage", &name) < 0)
        return -1;
    if (!name)
        return 0;
    const config_setting_t *at = config_setting_get_member(output, "energy_stage");
    *stage = scene_stage_index(scene, name);
    if (*stage < 0)
        return app_config_fail(p, at, "`energy_stage`: no stage named `%s`", name);
    if (!(scene->stages[*stage].duration > 0.0))
        return app_config_fail(p, at, "`energy_stage`: stage `%s` runs no time (time.end = 0)",
                               name);
    return 0;
}

static int crater_parse(const config_setting_t *root, const config_setting_t *group, Scene *scene,
                        void **state, char *err, size_t err_size)
{
    (void)group;
    AppConfig p = {.path = scene->path, .err = err, .err_size = err_size, .group = NULL};
    AppCraterState c;
    memset(&c, 0, sizeof c);
    c.energy_stage = -1;
    const config_setting_t *output = config_setting_get_member(root, "output");
    if (output && (app_config_number(&p, output, "profile_every", &c.profile_every) < 0 ||
                   app_config_non_negative(&p, output, "profile_every", c.profile_every) < 0 ||
                   app_config_number(&p, output, "profile_bin", &c.profile_bin) < 0 ||
                   app_config_non_negative(&p, output, "profile_bin", c.profile_bin) < 0))
        return -1;
    if (output && parse_energy_stage(&p, output, scene, &c.energy_stage) < 0)
        return -1;
    /* a bin far below a grain measures nothing but memory (profile_bin = 1e-12 took 7.5 GB) */
    double r_min = INFINITY;
    for (int i = 0; i < scene->grains.count; ++i)
        r_min = fmin(r_min, scene->grains.radius[i]);
    if (c.profile_bin > 0.0 && c.profile_bin < 0.1 * r_min)
        return app_config_fail(&p, config_setting_get_member(output, "profile_bin"),
                               "`profile_bin` = %g m is below a tenth of the smallest grain "
                               "radius (%g m); use 0 (the mean diameter) or a larger bin",
                               c.profile_bin, r_min);
    const config_setting_t *stages = config_setting_get_member(root, "stages");
    int used = c.profile_every > 0.0;
    for (int k = 0; stages && k < scene->stage_count && k < config_setting_length(stages); ++k) {
        const config_setting_t *g = config_setting_get_elem(stages, (unsigned)k);
        if (parse_dig(&p, g, &c.dig[k]) < 0 || dig_within(&p, g, scene, &c.dig[k]) < 0)
            return -1;
        used |= c.dig[k].dig;
    }
    *state = NULL;
    if (!used)
        return 0;
    AppCraterState *out = malloc(sizeof *out);
    if (!out) {
        snprintf(err, err_size, "%s: out of memory", scene->path);
        return -1;
    }
    *out = c;
    *state = out;
    return 0;
}

static void crater_free(void *state)
{
    free(state);
}

static void crater_describe_stage(const void *state, int stage, FILE *out)
{
    const AppCraterDig *d = &((const AppCraterState *)state)->dig[stage];
    if (!d->dig)
        return;
    fprintf(out, ", dig center_x %g m width %g m height %g m top ", d->center_x, d->width,
            d->height);
    if (d->top_surface)
        fprintf(out, "surface");
    else
        fprintf(out, "%g m", d->top);
}

/* ---------------------------------------------------------------- run hooks */

static int crater_begin(void *state, AppContext *ctx)
{
    AppCraterState *c = state;
    const Scene *scene = ctx->scene;
    int observe = c->profile_every > 0.0;
    for (int k = 0; k < scene->stage_count; ++k)
        observe |= c->dig[k].dig && !scene->stages[k].skip;
    c->json[0] = '\0';
    if (!observe)
        return 0;
    c->observer = app_observer_open(scene, c->profile_bin, ctx->out_dir, ctx->err, ctx->err_size);
    return c->observer ? 0 : -1;
}

/* The bed measured, then the cavity dug (000 §4.1 stage 2). */
static int crater_stage_edit(void *state, AppContext *ctx)
{
    AppCraterState *c = state;
    const AppCraterDig *d = &c->dig[ctx->stage];
    if (!d->dig)
        return 0;
    double x0 = d->center_x - 0.5 * d->width, x1 = d->center_x + 0.5 * d->width;
    app_observer_before_dig(c->observer, ctx->world, x0, x1);
    SimFrame frame;
    sim_world_frame(ctx->world, &frame);
    double top = d->top;
    if (d->top_surface && app_surface_height(&frame, d->center_x, 0.5 * d->width, &top) != 0) {
        snprintf(ctx->err, ctx->err_size,
                 "stage %s: dig: no mobile grain within width/2 of center_x = %g m",
                 ctx->scene->stages[ctx->stage].name, d->center_x);
        return -1;
    }
    ctx->removed += sim_world_remove_rect(ctx->world, x0, top - d->height, x1, top + d->height);
    return 0;
}

static int crater_stage_begin(void *state, AppContext *ctx)
{
    AppCraterState *c = state;
    c->done = 0;
    c->every_profile = ctx->stage_steps + 1;
    if (!c->observer)
        return 0;
    if (c->profile_every > 0.0) {
        double dt = sim_world_time_step(ctx->world);
        c->every_profile = (long)fmax(1.0, (double)llround(c->profile_every / dt));
    }
    app_observer_stage_start(c->observer, ctx->world, ctx->stage);
    app_observer_sample(c->observer, ctx->world, ctx->stage, ctx->stage_start);
    return 0;
}

static long crater_next_step(const void *state, const AppContext *ctx, long done, long next)
{
    const AppCraterState *c = state;
    long every = c->every_profile;
    if (every <= ctx->stage_steps && (done / every + 1) * every < next)
        next = (done / every + 1) * every;
    return next;
}

static void crater_step(void *state, AppContext *ctx, long done)
{
    AppCraterState *c = state;
    c->done = done;
    if (c->observer && done > 0 && done < ctx->stage_steps && done % c->every_profile == 0)
        app_observer_sample(c->observer, ctx->world, ctx->stage, ctx->stage_start);
}

static int crater_stage_end(void *state, AppContext *ctx)
{
    AppCraterState *c = state;
    if (c->observer && c->done > 0)
        app_observer_sample(c->observer, ctx->world, ctx->stage, ctx->stage_start);
    return 0;
}

static int crater_end(void *state, AppContext *ctx, int ok)
{
    (void)ok;
    AppCraterState *c = state;
    if (!c->observer)
        return 0;
    app_observer_json(c->observer, c->json, sizeof c->json);
    int rc = app_observer_close(c->observer, ctx->world, ctx->err, ctx->err_size);
    c->observer = NULL;
    return rc;
}

/* A checkpoint: the profile cadence and the step last seen, then the observer's measures. */
static int crater_checkpoint(const void *state, const AppContext *ctx, FILE *out)
{
    (void)ctx;
    const AppCraterState *c = state;
    const double v[2] = {(double)c->every_profile, (double)c->done};
    app_checkpoint_put(out, "crater", v, 2);
    if (c->observer)
        app_observer_checkpoint(c->observer, out);
    return 0;
}

static int crater_resume(void *state, AppContext *ctx, const char *record)
{
    AppCraterState *c = state;
    double v[2];
    if (app_checkpoint_take(record, "crater", v, 2) != 0) {
        snprintf(ctx->err, ctx->err_size,
                 "--resume: the crater section of the checkpoint is "
                 "malformed");
        return -1;
    }
    c->every_profile = (long)v[0];
    c->done = (long)v[1];
    return c->observer ? app_observer_resume(c->observer, record, ctx->err, ctx->err_size) : 0;
}

static void crater_summary_json(const void *state, char *out, size_t size)
{
    snprintf(out, size, "%s", ((const AppCraterState *)state)->json);
}

static int crater_figures(const void *state, const AppContext *ctx)
{
    const AppCraterState *c = state;
    if (!(c->profile_every > 0.0))
        return 0;
    return app_crater_plots(ctx->scene, c->energy_stage, ctx->out_dir, ctx->render, ctx->err,
                            ctx->err_size);
}

static const char *const STAGE_KEYS[] = {"dig", NULL};
static const char *const OUTPUT_KEYS[] = {"profile_every", "profile_bin", "energy_stage", NULL};

static const char *const OUTPUTS[] = {"profile.csv", "crater.csv", "observables.csv", NULL};
const AppExperiment app_crater_experiment = {
    .name = "crater",
    .outputs = OUTPUTS,
    .group = NULL,
    .stage_keys = STAGE_KEYS,
    .output_keys = OUTPUT_KEYS,
    .parse = crater_parse,
    .free = crater_free,
    .describe_stage = crater_describe_stage,
    .begin = crater_begin,
    .stage_edit = crater_stage_edit,
    .stage_begin = crater_stage_begin,
    .next_step = crater_next_step,
    .step = crater_step,
    .stage_end = crater_stage_end,
    .end = crater_end,
    .checkpoint = crater_checkpoint,
    .resume = crater_resume,
    .summary_json = crater_summary_json,
    .figures = crater_figures,
    .commands = app_sweep_commands,
    .command_count = 1,
};
