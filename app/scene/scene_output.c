/* SPDX-License-Identifier: MIT */
/* scene_output.c: the scene's `output` group (movies, energy and trace rows, t*), its `render`
 * style and the `figures` drawn after a run, each with the render style under its own keys. */
#include "scene/scene_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const STYLE_KEYS[] = {"width",
                                         "height",
                                         "color_by",
                                         "colormap",
                                         "range",
                                         "band_height",
                                         "outline",
                                         "orientation_tick",
                                         "force_chains",
                                         "chain_threshold",
                                         "chain_width_max",
                                         "velocity_arrows",
                                         "velocity_field",
                                         "colorbar",
                                         "time_stamp",
                                         "scale_bar",
                                         "background",
                                         "fill",
                                         "fixed_color",
                                         "view",
                                         "title",
                                         "axes",
                                         "size",
                                         "size_unit",
                                         "dpi",
                                         "font_size",
                                         "style",
                                         "field_color",
                                         "plot_format",
                                         NULL};

SceneStyle scene_style_unset(void)
{
    SceneStyle s;
    memset(&s, 0, sizeof s);
    s.width = s.height = s.color_by = s.colormap = -1;
    s.outline = s.orientation_tick = s.force_chains = -1;
    s.velocity_arrows = s.velocity_field = s.colorbar = s.time_stamp = s.scale_bar = -1;
    const double unset = (double)NAN;
    s.range_min = s.range_max = s.band_height = unset;
    s.chain_threshold = s.chain_width_max = unset;
    s.view_x0 = s.view_y0 = s.view_x1 = s.view_y1 = unset;
    s.background_rgb = s.fill_rgb = s.fixed_rgb = -1;
    s.axes = s.size_inches = s.preset = s.field_color = s.plot_format = -1;
    s.size_w = s.size_h = s.dpi = s.font_pt = unset;
    return s;
}

static int get_color(Loader *L, const config_setting_t *g, const char *key, long *out)
{
    const char *text = NULL;
    int found = app_config_string(&L->p, g, key, &text);
    if (found <= 0)
        return found;
    char *end = NULL;
    long v = text && text[0] == '#' && strlen(text) == 7 ? strtol(text + 1, &end, 16) : -1;
    if (v < 0 || !end || *end != '\0')
        return app_config_fail(&L->p, app_config_member(g, key),
                               "`%s` must be a colour \"#rrggbb\"", key);
    *out = v;
    return 1;
}

static int get_pixels(Loader *L, const config_setting_t *g, const char *key, int *out)
{
    long long v;
    int found = app_config_int(&L->p, g, key, &v);
    if (found <= 0)
        return found;
    /* H.264 needs even sizes; figures accept any */
    if (v < 16 || v > 16384)
        return app_config_fail(&L->p, app_config_member(g, key),
                               "`%s` must be in [16, 16384] pixels", key);
    *out = (int)v;
    return 1;
}

/* Print keys (docs/figures.md#print-sizes): axes, size [w, h] in size_unit at dpi, font_size in
 * points, a journal-column style preset, field_color, the plots' extra format. */
static int parse_print(Loader *L, const config_setting_t *g, SceneStyle *s)
{
    static const char *const units[] = {"cm", "in", NULL};
    static const char *const presets[] = {"single_column", "double_column", NULL};
    static const char *const formats[] = {"png", "pdf", "svg", NULL};
    double size[2] = {0.0, 0.0};
    if (app_config_bool(&L->p, g, "axes", &s->axes) < 0 ||
        app_config_bool(&L->p, g, "field_color", &s->field_color) < 0 ||
        app_config_choice(&L->p, g, "size_unit", units, &s->size_inches) < 0 ||
        app_config_choice(&L->p, g, "style", presets, &s->preset) < 0 ||
        app_config_choice(&L->p, g, "plot_format", formats, &s->plot_format) < 0 ||
        app_config_number(&L->p, g, "dpi", &s->dpi) < 0 ||
        app_config_number(&L->p, g, "font_size", &s->font_pt) < 0)
        return -1;
    if (app_config_member(g, "dpi") && !(s->dpi >= 50.0 && s->dpi <= 2400.0))
        return app_config_fail(&L->p, app_config_member(g, "dpi"),
                               "`dpi` must be in [50, 2400] pixels per inch");
    if (app_config_member(g, "font_size") && !(s->font_pt >= 2.0 && s->font_pt <= 72.0))
        return app_config_fail(&L->p, app_config_member(g, "font_size"),
                               "`font_size` must be in [2, 72] points");
    int found = app_config_vector(&L->p, g, "size", size, 2);
    if (found < 0)
        return -1;
    if (found) {
        if (!(size[0] > 0.0 && size[1] > 0.0 && size[0] <= 200.0 && size[1] <= 200.0))
            return app_config_fail(&L->p, app_config_member(g, "size"),
                                   "`size` = [width, height] must be in (0, 200] (cm or in)");
        s->size_w = size[0];
        s->size_h = size[1];
    }
    return 0;
}

static int parse_style(Loader *L, const config_setting_t *g, SceneStyle *s)
{
    static const char *const color_by[] = {"fixed", "force", "speed", "species", "height", NULL};
    static const char *const colormaps[] = {"viridis", "yellow_red", "greys", NULL};
    static const char *const flags[] = {"outline",         "orientation_tick", "force_chains",
                                        "velocity_arrows", "velocity_field",   "colorbar",
                                        "time_stamp",      "scale_bar"};
    int *flag_fields[] = {&s->outline,         &s->orientation_tick, &s->force_chains,
                          &s->velocity_arrows, &s->velocity_field,   &s->colorbar,
                          &s->time_stamp,      &s->scale_bar};
    double range[2] = {0.0, 0.0}, view[4] = {0.0, 0.0, 0.0, 0.0};
    const char *title = NULL;
    if (get_pixels(L, g, "width", &s->width) < 0 || get_pixels(L, g, "height", &s->height) < 0 ||
        app_config_choice(&L->p, g, "color_by", color_by, &s->color_by) < 0 ||
        app_config_choice(&L->p, g, "colormap", colormaps, &s->colormap) < 0)
        return -1;
    for (int k = 0; k < 8; ++k)
        if (app_config_bool(&L->p, g, flags[k], flag_fields[k]) < 0)
            return -1;
    int found = app_config_vector(&L->p, g, "range", range, 2);
    if (found < 0)
        return -1;
    if (found) {
        if (!(range[1] > range[0]))
            return app_config_fail(&L->p, app_config_member(g, "range"),
                                   "`range` = [min, max] needs max > min");
        s->range_min = range[0];
        s->range_max = range[1];
    }
    found = app_config_vector(&L->p, g, "view", view, 4);
    if (found < 0)
        return -1;
    if (found) {
        if (!(view[2] > view[0] && view[3] > view[1]))
            return app_config_fail(&L->p, app_config_member(g, "view"),
                                   "`view` = [x0, y0, x1, y1] needs x1 > x0, y1 > y0");
        s->view_x0 = view[0];
        s->view_y0 = view[1];
        s->view_x1 = view[2];
        s->view_y1 = view[3];
    }
    if (app_config_number(&L->p, g, "band_height", &s->band_height) < 0 ||
        (app_config_member(g, "band_height") &&
         app_config_positive(&L->p, g, "band_height", s->band_height) < 0) ||
        app_config_number(&L->p, g, "chain_threshold", &s->chain_threshold) < 0 ||
        (app_config_member(g, "chain_threshold") &&
         app_config_non_negative(&L->p, g, "chain_threshold", s->chain_threshold) < 0) ||
        app_config_number(&L->p, g, "chain_width_max", &s->chain_width_max) < 0 ||
        (app_config_member(g, "chain_width_max") &&
         app_config_positive(&L->p, g, "chain_width_max", s->chain_width_max) < 0) ||
        get_color(L, g, "background", &s->background_rgb) < 0 ||
        get_color(L, g, "fill", &s->fill_rgb) < 0 ||
        get_color(L, g, "fixed_color", &s->fixed_rgb) < 0)
        return -1;
    found = app_config_string(&L->p, g, "title", &title);
    if (found < 0)
        return -1;
    if (found)
        snprintf(s->title, sizeof s->title, "%s", title);
    return parse_print(L, g, s);
}

/* Figure keys override the scene's render keys. */
static void style_merge(SceneStyle *out, const SceneStyle *over)
{
    int *ints[] = {&out->width,        &out->height,          &out->color_by,
                   &out->colormap,     &out->outline,         &out->orientation_tick,
                   &out->force_chains, &out->velocity_arrows, &out->velocity_field,
                   &out->colorbar,     &out->time_stamp,      &out->scale_bar};
    const int *over_ints[] = {&over->width,        &over->height,          &over->color_by,
                              &over->colormap,     &over->outline,         &over->orientation_tick,
                              &over->force_chains, &over->velocity_arrows, &over->velocity_field,
                              &over->colorbar,     &over->time_stamp,      &over->scale_bar};
    for (size_t k = 0; k < sizeof ints / sizeof ints[0]; ++k)
        if (*over_ints[k] >= 0)
            *ints[k] = *over_ints[k];
    double *doubles[] = {&out->range_min, &out->range_max, &out->band_height, &out->chain_threshold,
                         &out->chain_width_max};
    const double *over_doubles[] = {&over->range_min, &over->range_max, &over->band_height,
                                    &over->chain_threshold, &over->chain_width_max};
    for (size_t k = 0; k < sizeof doubles / sizeof doubles[0]; ++k)
        if (!isnan(*over_doubles[k]))
            *doubles[k] = *over_doubles[k];
    if (!isnan(over->view_x0)) {
        out->view_x0 = over->view_x0;
        out->view_y0 = over->view_y0;
        out->view_x1 = over->view_x1;
        out->view_y1 = over->view_y1;
    }
    if (over->background_rgb >= 0)
        out->background_rgb = over->background_rgb;
    if (over->fill_rgb >= 0)
        out->fill_rgb = over->fill_rgb;
    if (over->fixed_rgb >= 0)
        out->fixed_rgb = over->fixed_rgb;
    if (over->title[0])
        snprintf(out->title, sizeof out->title, "%s", over->title);
    int *print_ints[] = {&out->axes, &out->size_inches, &out->preset, &out->field_color};
    const int over_print[] = {over->axes, over->size_inches, over->preset, over->field_color};
    for (size_t k = 0; k < sizeof over_print / sizeof over_print[0]; ++k)
        if (over_print[k] >= 0)
            *print_ints[k] = over_print[k];
    if (!isnan(over->size_w)) {
        out->size_w = over->size_w;
        out->size_h = over->size_h;
    }
    if (!isnan(over->dpi))
        out->dpi = over->dpi;
    if (!isnan(over->font_pt))
        out->font_pt = over->font_pt;
}

/* ---------------------------------------------------------------- output names */

typedef struct Claim {
    char name[SCENE_NAME_MAX + 32];
    char what[SCENE_NAME_MAX + 32];
    char where[WHERE_MAX]; /* "file:line", "" for the run's and the families' own files */
} Claim;

struct SceneClaims {
    Claim *items;
    int count, capacity;
};

static int claim_taken(AppConfig *p, const config_setting_t *s, const char *what, const char *name,
                       const Claim *c)
{
    if (s)
        return app_config_fail(p, s, "%s would write %s, which %s writes: choose another name",
                               what, name, c->what);
    if (c->where[0])
        return app_config_fail_at(p, c->where,
                                  "%s would write %s, which %s writes: choose another name",
                                  c->what, name, what);
    return 0;
}

int scene_claim_output(Scene *scene, AppConfig *p, const config_setting_t *s, const char *what,
                       const char *name)
{
    if (!scene->claims && !(scene->claims = calloc(1, sizeof *scene->claims)))
        return app_config_fail(p, s, "out of memory");
    struct SceneClaims *c = scene->claims;
    for (int k = 0; k < c->count; ++k)
        if (strcmp(c->items[k].name, name) == 0)
            return claim_taken(p, s, what, name, &c->items[k]);
    if (c->count == c->capacity) {
        int capacity = c->capacity ? 2 * c->capacity : 64;
        Claim *grown = realloc(c->items, (size_t)capacity * sizeof *grown);
        if (!grown)
            return app_config_fail(p, s, "out of memory");
        c->items = grown;
        c->capacity = capacity;
    }
    Claim *claim = &c->items[c->count++];
    snprintf(claim->name, sizeof claim->name, "%s", name);
    snprintf(claim->what, sizeof claim->what, "%s", what);
    claim->where[0] = '\0';
    if (s)
        app_config_where(p, s, claim->where, sizeof claim->where);
    return 0;
}

void scene_claims_free(Scene *scene)
{
    if (scene->claims)
        free(scene->claims->items);
    free(scene->claims);
    scene->claims = NULL;
}

int loader_claim_run_outputs(Loader *L, const config_setting_t *root)
{
    /* run.c's files, the crater figures hook's (any scene), the ensemble driver's */
    static const char *const own[] = {"energy.csv",         "trace.csv",
                                      "summary.json",       "manifest.txt",
                                      "scene.resolved.cfg", "checkpoint.txt",
                                      "energy_panels.png",  "profiles.png",
                                      "cpu_seconds.txt",    NULL};
    /* each stage's: checkpoints (run.c), movie, dumps (dump.c) */
    static const char *const per_stage[] = {".state",
                                            ".last_good.state",
                                            ".checkpoint.state",
                                            ".interrupted.state",
                                            ".mp4",
                                            ".lammpstrj",
                                            "/",
                                            ".pvd",
                                            "_contacts.pvd",
                                            NULL};
    Scene *scene = L->scene;
    for (int k = 0; own[k]; ++k)
        if (scene_claim_output(scene, &L->p, NULL, "the run", own[k]) < 0)
            return -1;
    const config_setting_t *stages = app_config_member(root, "stages");
    for (int k = 0; k < scene->stage_count; ++k) {
        const config_setting_t *g = stages ? config_setting_get_elem(stages, (unsigned)k) : NULL;
        const config_setting_t *at = g ? app_config_member(g, "name") : NULL;
        char file[SCENE_NAME_MAX + 32], what[SCENE_NAME_MAX + 16];
        snprintf(what, sizeof what, "stage `%s`", scene->stages[k].name);
        for (int j = 0; per_stage[j]; ++j) {
            snprintf(file, sizeof file, "%s%s", scene->stages[k].name, per_stage[j]);
            if (scene_claim_output(scene, &L->p, at ? at : g, what, file) < 0)
                return -1;
        }
    }
    return 0;
}

static int parse_figures(Loader *L, const config_setting_t *output)
{
    static const char *const keys[] = {"name", "stage", "at", "format", NULL};
    static const char *const at_names[] = {"start", "end", NULL};
    static const char *const formats[] = {"png", "pdf", "svg", NULL};
    Scene *scene = L->scene;
    const config_setting_t *list;
    if (app_config_list(&L->p, output, "figures", &list) <= 0)
        return L->p.failed ? -1 : 0;
    int count = config_setting_length(list);
    if (count > SCENE_MAX_FIGURES)
        return app_config_fail(&L->p, list, "at most %d figures", SCENE_MAX_FIGURES);
    for (int k = 0; k < count; ++k) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
        SceneFigure *f = &scene->output.figures[k];
        char what[48];
        snprintf(what, sizeof what, "figure %d", k);
        const char *name = NULL, *stage = NULL;
        int at = 1, format = 0;
        SceneStyle own = scene_style_unset();
        if (app_config_keys(&L->p, g, what, keys, STYLE_KEYS) < 0 ||
            app_config_need(&L->p, g, "name", what) < 0 ||
            app_config_string(&L->p, g, "name", &name) < 0 ||
            loader_check_file_name(L, g, "name", name) < 0 ||
            app_config_string(&L->p, g, "stage", &stage) < 0 ||
            app_config_choice(&L->p, g, "format", formats, &format) < 0 ||
            parse_style(L, g, &own) < 0)
            return -1;
        /* at = "start" | "end" | seconds after the stage start (000 figs. 7.2, 7.9-7.23) */
        const config_setting_t *at_setting = app_config_member(g, "at");
        double at_time = 0.0;
        if (at_setting && config_setting_type(at_setting) != CONFIG_TYPE_STRING) {
            if (app_config_number_of(&L->p, at_setting, "at", &at_time) < 0)
                return -1;
            if (!(at_time >= 0.0))
                return app_config_fail(&L->p, at_setting,
                                       "`at` must be \"start\", \"end\" or a time >= 0 s");
            at = 2;
        } else if (app_config_choice(&L->p, g, "at", at_names, &at) < 0) {
            return -1;
        }
        /* its file may be no other output's (the run's own files, a stage's, a measure's) */
        char file[SCENE_NAME_MAX + 8], writer[SCENE_NAME_MAX + 16];
        snprintf(file, sizeof file, "%s.%s", name, formats[format]);
        snprintf(writer, sizeof writer, "figure `%s`", name);
        if (scene_claim_output(scene, &L->p, app_config_member(g, "name"), writer, file) < 0)
            return -1;
        snprintf(f->name, sizeof f->name, "%s", name);
        f->stage = scene->stage_count - 1;
        if (stage) {
            f->stage = scene_stage_index(scene, stage);
            if (f->stage < 0)
                return app_config_fail(&L->p, app_config_member(g, "stage"), "no stage named `%s`",
                                       stage);
        }
        if (at == 2 && at_time > scene->stages[f->stage].duration)
            return app_config_fail(
                &L->p, at_setting, "figure `%s` at %g s is after the end of stage %s (%g s long)",
                name, at_time, scene->stages[f->stage].name, scene->stages[f->stage].duration);
        f->at_end = at;
        f->at_time = at_time;
        snprintf(f->format, sizeof f->format, "%s", formats[format]);
        f->style = scene->style;
        style_merge(&f->style, &own);
        scene->output.figure_count = k + 1;
    }
    return 0;
}

/* movie = true | false | ["stage", ...]; a stage's own `movie` wins */
static int parse_movie(Loader *L, const config_setting_t *output)
{
    Scene *scene = L->scene;
    const config_setting_t *movie = app_config_member(output, "movie");
    int own[SCENE_MAX_STAGES]; /* 1: the stage sets its own `movie` */
    for (int k = 0; k < scene->stage_count; ++k) {
        int wanted = 0;
        own[k] = scene->stages[k].movie >= 0;
        if (movie && config_setting_type(movie) == CONFIG_TYPE_BOOL)
            wanted = config_setting_get_bool(movie);
        if (scene->stages[k].movie < 0)
            scene->stages[k].movie = wanted;
    }
    if (!movie || config_setting_type(movie) == CONFIG_TYPE_BOOL)
        return 0;
    if (config_setting_type(movie) != CONFIG_TYPE_ARRAY)
        return app_config_fail(&L->p, movie,
                               "`movie` must be true, false or an array of stage names");
    for (int j = 0; j < config_setting_length(movie); ++j) {
        const config_setting_t *e = config_setting_get_elem(movie, (unsigned)j);
        int stage = config_setting_type(e) == CONFIG_TYPE_STRING
                        ? scene_stage_index(scene, config_setting_get_string(e))
                        : -1;
        if (stage < 0)
            return app_config_fail(
                &L->p, e, "`movie` names no stage `%s`",
                config_setting_type(e) == CONFIG_TYPE_STRING ? config_setting_get_string(e) : "?");
        if (!own[stage])
            scene->stages[stage].movie = 1;
    }
    return 0;
}

/* trace = [id or name, ...]: grains whose paths go to trace.csv; a name is that of a grain a
 * stage adds (its id fixed at load, app/scene/stage_adds.c). An array holds one type, so a list
 * ( 3, "projectile" ) mixes ids and names. */
static int parse_trace(Loader *L, const config_setting_t *output)
{
    SceneOutput *out = &L->scene->output;
    const config_setting_t *trace = app_config_member(output, "trace");
    if (!trace)
        return 0;
    int type = config_setting_type(trace);
    int n =
        type == CONFIG_TYPE_ARRAY || type == CONFIG_TYPE_LIST ? config_setting_length(trace) : -1;
    if (n < 0 || n > SCENE_MAX_TRACE)
        return app_config_fail(&L->p, trace,
                               "`trace` must be an array of at most %d grain ids or names",
                               SCENE_MAX_TRACE);
    for (int j = 0; j < n; ++j) {
        const config_setting_t *e = config_setting_get_elem(trace, (unsigned)j);
        if (config_setting_type(e) == CONFIG_TYPE_STRING) {
            const SceneAdd *a = scene_added_grain(L->scene, config_setting_get_string(e), 0);
            if (!a)
                return app_config_fail(&L->p, e, "`trace`: no stage adds a grain named `%s`",
                                       config_setting_get_string(e));
            out->trace_ids[j] = a->id;
            continue;
        }
        if (config_setting_type(e) != CONFIG_TYPE_INT || config_setting_get_int(e) < 0)
            return app_config_fail(&L->p, e,
                                   "`trace` must list grain ids (integers >= 0) or the names of "
                                   "added grains");
        out->trace_ids[j] = (uint32_t)config_setting_get_int(e);
    }
    out->trace_count = n;
    return 0;
}

/* frame_rate, movie_speed and movie_duration each set the simulated time between movie frames:
 * at most one of them (refused at the later one in the file). Then every stage's interval at
 * least its time step (a frame per step at the most), when the step is known now. */
static int check_movie_pace(Loader *L, const config_setting_t *output)
{
    static const char *const keys[] = {"frame_rate", "movie_speed", "movie_duration"};
    const config_setting_t *first = NULL, *later = NULL; /* in file order */
    for (int k = 0; k < 3; ++k) {
        const config_setting_t *s = app_config_member(output, keys[k]);
        if (!s)
            continue;
        if (!first || config_setting_source_line(s) < config_setting_source_line(first)) {
            later = later ? later : first;
            first = s;
        } else if (!later || config_setting_source_line(s) > config_setting_source_line(later)) {
            later = s;
        }
    }
    if (later)
        return app_config_fail(&L->p, later,
                               "`%s` contradicts `%s` (line %u): each sets the simulated time "
                               "between movie frames (frame_rate = fps / movie_speed, movie_speed "
                               "= time.end / movie_duration); give one",
                               config_setting_name(later), config_setting_name(first),
                               config_setting_source_line(first));
    const SceneOutput *out = &L->scene->output;
    const config_setting_t *pace = app_config_member(output, "movie_speed");
    if (!pace)
        pace = app_config_member(output, "movie_duration");
    for (int k = 0; pace && k < L->scene->stage_count; ++k) {
        const SceneStage *stage = &L->scene->stages[k];
        double dt = stage->time_step, every = scene_frame_interval(L->scene, k);
        if (stage->duration > 0.0 && dt > 0.0 && every < dt)
            return app_config_fail(
                &L->p, pace,
                "`%s` asks a frame every %g s in stage %s, less than its time step dt = %g s "
                "(at fps = %g the slowest movie_speed is %g)",
                config_setting_name(pace), every, stage->name, dt, out->fps, out->fps * dt);
    }
    return 0;
}

double scene_frame_interval(const Scene *scene, int k)
{
    const SceneOutput *out = &scene->output;
    if (out->movie_speed > 0.0)
        return out->movie_speed / out->fps;
    double end = k >= 0 && k < scene->stage_count ? scene->stages[k].duration : 0.0;
    if (out->movie_duration > 0.0 && end > 0.0)
        return end / (out->movie_duration * out->fps);
    return 1.0 / out->frame_rate;
}

int loader_parse_output(Loader *L, const config_setting_t *root)
{
    static const char *const keys[] = {"frame_rate",
                                       "fps",
                                       "crf",
                                       "movie_speed",
                                       "movie_duration",
                                       "movie",
                                       "drawer",
                                       "energy_every",
                                       "trace",
                                       "trace_every",
                                       "t_star_length",
                                       "figures",
                                       "dump",
                                       "movie_view",
                                       "checkpoint_every",
                                       "checkpoint_every_minutes",
                                       NULL};
    static const char *const drawers[] = {"cairo", "osmesa", NULL};
    static const char *const movie_views[] = {"grains", "container", NULL};
    Scene *scene = L->scene;
    SceneOutput *out = &scene->output;
    const config_setting_t *render, *output;
    out->frame_rate = 25.0;
    out->fps = 25.0;
    out->crf = 20;
    out->energy_every = 0.01;
    out->trace_every = -1.0;
    scene->style = scene_style_unset();
    if (app_config_group(&L->p, root, "render", &render) < 0 ||
        app_config_keys(&L->p, render, "render", STYLE_KEYS, NULL) < 0 ||
        (render && parse_style(L, render, &scene->style) < 0))
        return -1;
    if (app_config_group(&L->p, root, "output", &output) < 0 ||
        app_config_keys(&L->p, output, "output", keys, loader_family_keys(2)) < 0)
        return -1;
    long long crf = out->crf;
    if (app_config_number(&L->p, output, "frame_rate", &out->frame_rate) < 0 ||
        app_config_positive(&L->p, output, "frame_rate", out->frame_rate) < 0 ||
        app_config_number(&L->p, output, "fps", &out->fps) < 0 ||
        app_config_positive(&L->p, output, "fps", out->fps) < 0 ||
        app_config_int(&L->p, output, "crf", &crf) < 0 ||
        app_config_number(&L->p, output, "movie_speed", &out->movie_speed) < 0 ||
        (app_config_member(output, "movie_speed") &&
         app_config_positive(&L->p, output, "movie_speed", out->movie_speed) < 0) ||
        app_config_number(&L->p, output, "movie_duration", &out->movie_duration) < 0 ||
        (app_config_member(output, "movie_duration") &&
         app_config_positive(&L->p, output, "movie_duration", out->movie_duration) < 0) ||
        app_config_choice(&L->p, output, "drawer", drawers, &out->drawer) < 0 ||
        app_config_choice(&L->p, output, "movie_view", movie_views, &out->movie_view) < 0 ||
        app_config_number(&L->p, output, "energy_every", &out->energy_every) < 0 ||
        app_config_positive(&L->p, output, "energy_every", out->energy_every) < 0 ||
        app_config_number(&L->p, output, "trace_every", &out->trace_every) < 0 ||
        (app_config_member(output, "trace_every") &&
         app_config_positive(&L->p, output, "trace_every", out->trace_every) < 0) ||
        app_config_number(&L->p, output, "t_star_length", &out->t_star_length) < 0 ||
        app_config_non_negative(&L->p, output, "t_star_length", out->t_star_length) < 0 ||
        app_config_number(&L->p, output, "checkpoint_every", &out->checkpoint_every) < 0 ||
        app_config_non_negative(&L->p, output, "checkpoint_every", out->checkpoint_every) < 0 ||
        app_config_number(&L->p, output, "checkpoint_every_minutes", &out->checkpoint_minutes) <
            0 ||
        app_config_non_negative(&L->p, output, "checkpoint_every_minutes",
                                out->checkpoint_minutes) < 0)
        return -1;
    if (crf < 0 || crf > 51)
        return app_config_fail(&L->p, app_config_member(output, "crf"), "`crf` must be in [0, 51]");
    out->crf = (int)crf;
    if (out->fps > SCENE_MAX_FPS) /* the encoder's bound, checked here before anything runs */
        return app_config_fail(&L->p, app_config_member(output, "fps"),
                               "`fps` must be at most %g frames/s (got %g)", SCENE_MAX_FPS,
                               out->fps);
    if (out->trace_every < 0.0)
        out->trace_every = out->energy_every;
    if (check_movie_pace(L, output) < 0 || parse_movie(L, output) < 0 ||
        parse_trace(L, output) < 0 || app_dump_parse(&L->p, root, scene) < 0)
        return -1;
    return parse_figures(L, output);
}
