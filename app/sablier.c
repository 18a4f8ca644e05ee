/* SPDX-License-Identifier: MIT */
/* sablier.c: the `sablier` command (run, check, diff, render). The one translation unit that sees
 * both sim/ and render/: it maps the scene's plain style data onto RenderStyle and hands the
 * runner its figure and movie hooks. Built without render/ (SABLIER_WITH_RENDER=OFF), figures
 * and movies are skipped with a warning and `diff`/`render` exit 2. */
#include "bne.h"
#include "observe.h"
#include "run.h"
#include "scene.h"
#include "sediment.h"
#include "study.h"
#include "sweep.h"
#include "util.h"

#include "sim/sim.h"

#ifdef SABLIER_HAVE_RENDER
#include "render/render.h"
#endif

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef SABLIER_VERSION
#define SABLIER_VERSION "0.0.0"
#endif

#define MAX_SETS 64

static const char USAGE[] =
    "usage: sablier COMMAND [options]\n"
    "\n"
    "commands:\n"
    "  run SCENE      run a scene and write its outputs (summary.json, energy.csv, ...)\n"
    "  check SCENE    validate a scene and print what it would run\n"
    "  diff A B       compare two PNG images (exit 0 match, 1 differ, 2 bad input)\n"
    "  render STATE   draw a saved checkpoint without simulating\n"
    "  sweep SWEEP    run sweep members from one settled bed (crater studies)\n"
    "  discharge SCENE  build an open pile and discharge it through an orifice (004)\n"
    "  study SCENE    jamming statistics over base lengths and widths (004)\n"
    "  bne SCENE      Brazil-nut samples over seeds and one varied key: rise curves, LDF (002)\n"
    "  sediment SCENE Shields scan of bed-load transport: flux against Shields, threshold (002)\n"
    "\n"
    "  sablier COMMAND --help   options of one command\n"
    "  sablier --version        versions of sablier and its libraries\n"
    "\n"
    "exit status: 0 success, 1 the simulation failed, 2 bad usage or bad input\n";

static const char USAGE_RUN[] =
    "usage: sablier run SCENE [--out DIR] [--set KEY=VALUE]... [--threads N] [--quiet]\n"
    "\n"
    "  --out DIR          output folder (default out/<scene name>/)\n"
    "  --set KEY=VALUE    override a scene key by its dotted path, e.g. time.dt=2e-5,\n"
    "                     species.0.k_n=1e6, stages.collapse.time.end=2 (see docs/scenes.md)\n"
    "  --threads N        threads for encoding and rendering (results do not depend on N)\n"
    "  --quiet            one line per stage, no progress\n";

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
    "  --quiet            no per-member lines\n";

static const char USAGE_CHECK[] =
    "usage: sablier check SCENE [--set KEY=VALUE]...\n"
    "\n"
    "Validates the scene (keys, types, values, overlaps, time step) and prints its stages,\n"
    "effects, grains, time step, contact time and steps per contact without running it.\n";

static const char USAGE_DIFF[] =
    "usage: sablier diff A.png B.png [--out DIFF.png] [--threshold N] [--shift N]\n"
    "                    [--max-pixels N]\n"
    "\n"
    "  --out DIFF.png     write an image of the differences\n"
    "  --threshold N      a pixel differs when a channel differs by more than N (0-255)\n"
    "  --shift N          ignore differences matched within N pixels\n"
    "  --max-pixels N     the images match when at most N pixels differ\n"
    "Prints one JSON line; exit 0 match, 1 differ, 2 bad input.\n";

static const char USAGE_RENDER[] =
    "usage: sablier render STATE -o FIG.png|pdf|svg [options]\n"
    "\n"
    "  --scene SCENE        materials and style from a scene (needed for contact forces)\n"
    "  --set KEY=VALUE      override a key of that scene\n"
    "  --color-by NAME      fixed, force, speed, species, height\n"
    "  --colormap NAME      viridis, yellow_red, greys\n"
    "  --force-chains       draw contact force chains (needs --scene)\n"
    "  --chain-threshold X  draw contacts above X times the mean normal force\n"
    "  --velocity-field     draw the coarse-grained velocity field\n"
    "  --velocity-arrows    draw per-grain velocity arrows\n"
    "  --width N --height N size in pixels\n"
    "  --colorbar --time-stamp --scale-bar   annotations\n"
    "  --title TEXT\n";

/* ---------------------------------------------------------------- argument helpers */

/* Matches "--name VALUE" or "--name=VALUE"; advances *i past the value. */

static int parse_count(const char *text, long min, long max, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (end == text || *end || errno || v < min || v > max)
        return -1;
    *out = v;
    return 0;
}

static int wants_help(int argc, char **argv)
{
    for (int i = 2; i < argc; ++i)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
            return 1;
    return 0;
}

/* ---------------------------------------------------------------- render glue */

#ifdef SABLIER_HAVE_RENDER
static RenderStyle render_style_from_scene(const SceneStyle *s)
{
    RenderStyle r = render_style_default();
    if (s->width > 0)
        r.width = s->width;
    if (s->height > 0)
        r.height = s->height;
    if (s->color_by >= 0)
        r.color_by = (RenderColorBy)s->color_by;
    if (s->colormap >= 0)
        r.colormap = (RenderColormap)s->colormap;
    if (!isnan(s->range_min)) {
        r.range_min = s->range_min;
        r.range_max = s->range_max;
    }
    if (!isnan(s->band_height))
        r.band_height = s->band_height;
    if (!isnan(s->chain_threshold))
        r.chain_threshold = s->chain_threshold;
    if (!isnan(s->chain_width_max))
        r.chain_width_max = s->chain_width_max;
    if (!isnan(s->view_x0)) {
        r.view_x0 = s->view_x0;
        r.view_y0 = s->view_y0;
        r.view_x1 = s->view_x1;
        r.view_y1 = s->view_y1;
    }
    int *flags[] = {&r.outline,        &r.orientation_tick, &r.force_chains, &r.velocity_arrows,
                    &r.velocity_field, &r.colorbar,         &r.time_stamp,   &r.scale_bar};
    const int values[] = {s->outline,         s->orientation_tick, s->force_chains,
                          s->velocity_arrows, s->velocity_field,   s->colorbar,
                          s->time_stamp,      s->scale_bar};
    for (size_t k = 0; k < sizeof values / sizeof values[0]; ++k)
        if (values[k] >= 0)
            *flags[k] = values[k];
    if (s->background_rgb >= 0)
        r.background_rgb = (uint32_t)s->background_rgb;
    if (s->fill_rgb >= 0)
        r.fill_rgb = (uint32_t)s->fill_rgb;
    if (s->fixed_rgb >= 0)
        r.fixed_rgb = (uint32_t)s->fixed_rgb;
    if (s->title[0])
        r.title = s->title;
    /* colour-bar label and unit follow the quantity */
    static const char *const labels[][2] = {
        {"", ""}, {"contact force", "N"}, {"speed", "m/s"}, {"species", ""}, {"height", "m"}};
    if (r.color_by >= RENDER_COLOR_FIXED && r.color_by <= RENDER_COLOR_HEIGHT) {
        r.colorbar_label = labels[r.color_by][0];
        r.colorbar_unit = labels[r.color_by][1];
    }
    return r;
}

typedef struct Renderer {
    RenderMovie *movie;
    int quiet;
} Renderer;

static int hook_movie_open(void *context, const Scene *scene, int stage, const char *path,
                           SimFrameSink *sink, char *err, size_t err_size)
{
    (void)stage;
    Renderer *renderer = context;
    RenderStyle style = render_style_from_scene(&scene->style);
    style.width += style.width % 2; /* H.264 needs even sizes */
    style.height += style.height % 2;
    RenderMovieDef def = {
        .path = path,
        .drawer = scene->output.drawer == 1 ? RENDER_DRAWER_OSMESA : RENDER_DRAWER_CAIRO,
        .fps = scene->output.fps,
        .crf = scene->output.crf,
        .quiet = 1,
        .meta = {.scene = scene->name, .seed = scene->seed},
    };
    renderer->movie = render_movie_open(&def, &style, err, err_size);
    if (!renderer->movie)
        return -1;
    *sink = render_movie_sink(renderer->movie);
    return 0;
}

static int hook_movie_close(void *context, char *err, size_t err_size)
{
    Renderer *renderer = context;
    int rc = render_movie_close(renderer->movie, err, err_size);
    renderer->movie = NULL;
    return rc == 0 ? 0 : -1;
}

/* Thesis 002 fig. 31 analogue: the bed (render_cairo_draw) with the fluid column's velocity and
 * concentration profiles (render_plot_draw) beside it, on the same heights: the plot's y axis is
 * the bed view's y range and its height is adjusted until the two scales match to a pixel. */
static int sediment_figure(const Scene *scene, const SimFrame *frame, const RenderStyle *style,
                           const RenderMeta *meta, const char *path, char *err, size_t err_size)
{
    RenderView view;
    render_view_fit(frame, style, &view);
    double y_top = view.center_y + 0.5 * view.plot_h / view.scale;
    double y_bottom = view.center_y - 0.5 * view.plot_h / view.scale;
    SimFluidProfile p;
    sim_fluid_profile(app_sediment_fluid(scene->sediment), &p);
    double *u = malloc(3 * (size_t)p.cells * sizeof *u);
    if (!u) {
        snprintf(err, err_size, "out of memory");
        return -1;
    }
    double *phi = u + p.cells, *y = phi + p.cells, u_max = 0.0;
    int n = 0;
    for (int k = 0; k < p.cells; ++k)
        if (p.y[k] >= y_bottom && p.y[k] <= y_top) {
            y[n] = p.y[k];
            u[n] = p.u[k];
            phi[n++] = p.solid_fraction[k];
            u_max = fmax(u_max, fabs(p.u[k]));
        }
    RenderSeries series[2];
    memset(series, 0, sizeof series);
    series[0] =
        (RenderSeries){.label = "u(y)", .count = n, .x = u, .y = y, .rgb = 0x1f77b4, .line = 1};
    series[1] =
        (RenderSeries){.label = "phi(y)", .count = n, .x = phi, .y = y, .rgb = 0xd62728, .line = 1};
    RenderPanel panels[2];
    memset(panels, 0, sizeof panels);
    panels[0].title = "fluid velocity";
    panels[0].x.label = "u";
    panels[0].x.max = u_max > 0.0 ? 1.05 * u_max : 1.0;
    panels[1].title = "grain fraction";
    panels[1].x.label = "phi";
    panels[1].x.max = 1.0;
    for (int k = 0; k < 2; ++k) {
        panels[k].y.label = k == 0 ? "y" : NULL;
        panels[k].y.min = y_bottom;
        panels[k].y.max = y_top;
        panels[k].series_count = 1;
        panels[k].series = &series[k];
    }
    RenderImage bed = {0}, plot = {0}, out = {0};
    RenderPlot r = {.width = style->width > 0 ? style->width / 2 : 600,
                    .height = style->height,
                    .rows = 1,
                    .cols = 2,
                    .panels = panels,
                    .font_size = 14.0};
    if (r.width < 360)
        r.width = 360;
    int rc = render_cairo_draw(frame, style, &bed) == 0 ? 0 : -1;
    if (rc != 0)
        snprintf(err, err_size, "cannot draw the bed");
    double top_px = 0.0, bottom_px = 0.0, x_px;
    for (int pass = 0; pass < 3 && rc == 0; ++pass) { /* match the vertical scales */
        render_image_free(&plot);
        rc = render_plot_draw(&r, &plot, err, err_size);
        if (rc != 0 || render_plot_map(&r, 0, 0.0, y_top, &x_px, &top_px) != 0 ||
            render_plot_map(&r, 0, 0.0, y_bottom, &x_px, &bottom_px) != 0)
            break;
        int grow = (int)lround(view.plot_h - (bottom_px - top_px));
        if (grow == 0)
            break;
        r.height += grow;
    }
    if (rc == 0) {
        int shift = (int)lround(view.plot_y - top_px); /* plot rows move down by this */
        int top = shift < 0 ? -shift : 0;
        int height = bed.height + top > plot.height + shift + top ? bed.height + top
                                                                  : plot.height + shift + top;
        rc = render_image_alloc(&out, bed.width + plot.width, height, RENDER_PIXEL_RGBA);
        for (int row = 0; rc == 0 && row < height; ++row)
            for (int col = 0; col < out.width; ++col) {
                uint8_t rgba[4] = {255, 255, 255, 255};
                int br = row - top, pr = row - top - shift;
                if (col < bed.width && br >= 0 && br < bed.height)
                    render_image_get_rgba(&bed, col, br, rgba);
                else if (col >= bed.width && pr >= 0 && pr < plot.height)
                    render_image_get_rgba(&plot, col - bed.width, pr, rgba);
                memcpy(out.pixels + (size_t)row * (size_t)out.stride + 4 * (size_t)col, rgba, 4);
            }
        if (rc != 0)
            snprintf(err, err_size, "out of memory");
    }
    if (rc == 0) {
        char seed[32];
        snprintf(seed, sizeof seed, "%llu", (unsigned long long)meta->seed);
        const char *text[] = {"Software", "sablier", "Scene", meta->scene, "Seed", seed, NULL};
        rc = render_png_write(&out, path, text, err, err_size) == 0 ? 0 : -1;
    }
    render_image_free(&bed);
    render_image_free(&plot);
    render_image_free(&out);
    free(u);
    return rc;
}

static int hook_figure(void *context, const Scene *scene, const SceneFigure *figure,
                       const SimFrame *frame, const char *path, char *err, size_t err_size)
{
    (void)context;
    RenderStyle style = render_style_from_scene(&figure->style);
    RenderMeta meta = {.scene = scene->name, .seed = scene->seed};
    size_t len = strlen(path);
    if (scene->sediment && len > 4 && strcmp(path + len - 4, ".png") == 0)
        return sediment_figure(scene, frame, &style, &meta, path, err, err_size);
    return render_figure_write(frame, &style, &meta, path, err, err_size) == 0 ? 0 : -1;
}

/* AppChart (observe.h, plain data) onto RenderPlot. */
static int hook_chart(void *context, const AppChart *plot, const char *path, char *err,
                      size_t err_size)
{
    (void)context;
    RenderSeries series[APP_CHART_MAX_PANELS][APP_CHART_MAX_SERIES];
    RenderPanel panels[APP_CHART_MAX_PANELS];
    int count = plot->rows * plot->cols;
    memset(panels, 0, sizeof panels);
    for (int p = 0; p < count && p < APP_CHART_MAX_PANELS; ++p) {
        const AppChartPanel *a = &plot->panels[p];
        for (int s = 0; s < a->series_count; ++s) {
            const AppChartSeries *in = &a->series[s];
            RenderSeries *out = &series[p][s];
            memset(out, 0, sizeof *out);
            out->label = in->label[0] ? in->label : NULL;
            out->count = in->count;
            out->x = in->x;
            out->y = in->y;
            out->rgb = RENDER_RGB_AUTO;
            out->line = in->line;
            out->marker = in->marker ? RENDER_MARKER_CIRCLE : RENDER_MARKER_NONE;
        }
        panels[p].title = a->title[0] ? a->title : NULL;
        panels[p].x.label = a->x_label[0] ? a->x_label : NULL;
        panels[p].y.label = a->y_label[0] ? a->y_label : NULL;
        panels[p].series_count = a->series_count;
        panels[p].series = series[p];
        panels[p].legend = a->series_count > 1 ? RENDER_LEGEND_UPPER_RIGHT : RENDER_LEGEND_NONE;
    }
    RenderPlot r = {.width = plot->width,
                    .height = plot->height,
                    .rows = plot->rows,
                    .cols = plot->cols,
                    .panels = panels,
                    .title = plot->title[0] ? plot->title : NULL};
    RenderMeta meta = {.scene = "", .seed = 0};
    return render_plot_write(&r, &meta, path, err, err_size) == 0 ? 0 : -1;
}
#endif

#ifdef SABLIER_HAVE_RENDER
/* ---- thesis 004 (app/study.c): pile snapshots with the arch, and statistics plots ---- */
static int hook_discharge_figure(void *context, const Scene *scene, const SimFrame *frame,
                                 const int *arch_marks, const char *title, const char *path,
                                 char *err, size_t err_size)
{
    (void)context;
    RenderStyle style = render_style_from_scene(&scene->style);
    style.title = title;
    style.arch_ids = arch_marks;
    style.arch_inset = arch_marks != NULL;
    style.force_chains = arch_marks != NULL; /* force chains through the arch */
    RenderMeta meta = {.scene = scene->name, .seed = scene->seed};
    return render_figure_write(frame, &style, &meta, path, err, err_size) == 0 ? 0 : -1;
}

static int hook_discharge_plot(void *context, const Scene *scene, const AppPlot *plot,
                               const char *path, char *err, size_t err_size)
{
    (void)context;
    RenderSeries series[64];
    int n = plot->series_count < 64 ? plot->series_count : 64;
    for (int k = 0; k < n; ++k) {
        const AppPlotSeries *in = &plot->series[k];
        series[k] = (RenderSeries){.label = in->label,
                                   .count = in->count,
                                   .x = in->x,
                                   .y = in->y,
                                   .y_err = in->y_err,
                                   .rgb = in->same_colour ? RENDER_RGB_PREVIOUS : RENDER_RGB_AUTO,
                                   .line = in->line,
                                   .dashed = in->dashed,
                                   .marker = (RenderMarker)in->marker};
    }
    RenderPanel panel = {.x = {.label = plot->x_label},
                         .y = {.label = plot->y_label, .log = plot->y_log},
                         .series_count = n,
                         .series = series,
                         .legend = RENDER_LEGEND_UPPER_RIGHT};
    RenderPlot r = {.width = 1000, .height = 700, .panels = &panel, .title = plot->title};
    RenderMeta meta = {.scene = scene->name, .seed = scene->seed};
    return render_plot_write(&r, &meta, path, err, err_size) == 0 ? 0 : -1;
}

/* Species maps (004 fig. 3.4) as heat maps on their cells, viridis, range from the data. */
static int hook_discharge_map(void *context, const Scene *scene, const AppMap *map,
                              const char *path, char *err, size_t err_size)
{
    (void)context;
    RenderMap r = {.width = 1000,
                   .height = 700,
                   .nx = map->nx,
                   .ny = map->ny,
                   .x0 = map->x0,
                   .y0 = map->y0,
                   .cell = map->cell,
                   .values = map->values,
                   .colormap = RENDER_CMAP_VIRIDIS,
                   .title = map->title,
                   .x_label = map->x_label,
                   .y_label = map->y_label,
                   .bar_label = map->bar_label};
    RenderMeta meta = {.scene = scene->name, .seed = scene->seed};
    return render_map_write(&r, &meta, path, err, err_size) == 0 ? 0 : -1;
}
#endif

static int command_discharge_or_study(int argc, char **argv, int study)
{
#ifdef SABLIER_HAVE_RENDER
    Renderer renderer = {.quiet = 1};
    AppRenderHooks movie = {&renderer, hook_movie_open, hook_movie_close, hook_figure};
    AppDischargeRender render = {NULL, hook_discharge_figure, hook_discharge_plot, &movie,
                                 hook_discharge_map};
    const AppDischargeRender *hooks = &render;
#else
    const AppDischargeRender *hooks = NULL;
#endif
    return study ? app_study_command(argc, argv, hooks) : app_discharge_command(argc, argv, hooks);
}

static int command_discharge(int argc, char **argv)
{
    return command_discharge_or_study(argc, argv, 0);
}

static int command_study(int argc, char **argv)
{
    return command_discharge_or_study(argc, argv, 1);
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

static int collect_set(const char **sets, int *count, const char *value)
{
    if (*count >= MAX_SETS) {
        fprintf(stderr, "sablier: at most %d --set options\n", MAX_SETS);
        return -1;
    }
    sets[(*count)++] = value;
    return 0;
}

static int command_run(int argc, char **argv)
{
    const char *scene_path = NULL, *out = NULL, *value, *sets[MAX_SETS];
    int set_count = 0, quiet = 0;
    long threads = 1;
    for (int i = 2; i < argc; ++i) {
        int m;
        if ((m = app_option(argc, argv, &i, "--out", &value)) != 0) {
            if (m < 0)
                return 2;
            out = value;
        } else if ((m = app_option(argc, argv, &i, "--set", &value)) != 0) {
            if (m < 0 || collect_set(sets, &set_count, value) < 0)
                return 2;
        } else if ((m = app_option(argc, argv, &i, "--threads", &value)) != 0) {
            if (m < 0 || parse_count(value, 1, 1024, &threads) < 0)
                return app_usage_error(USAGE_RUN, "--threads needs a count in [1, 1024], got",
                                       m < 0 ? "nothing" : value);
        } else if (strcmp(argv[i], "--quiet") == 0 || strcmp(argv[i], "-q") == 0) {
            quiet = 1;
        } else if (app_scene_argument(USAGE_RUN, argv[i], &scene_path) != 0) {
            return 2;
        }
    }
    if (!scene_path)
        return app_usage_error(USAGE_RUN, "missing SCENE", NULL);
    char err[4096];
    Scene *scene = scene_load(scene_path, sets, set_count, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    char default_out[SCENE_NAME_MAX + 8];
    snprintf(default_out, sizeof default_out, "out/%s", scene->name);
    AppRunOptions options = app_run_options_default();
    options.out_dir = out ? out : default_out;
    options.quiet = quiet;
    options.threads = (int)threads;
    options.sablier_version = SABLIER_VERSION;
    options.render_versions = render_versions();
#ifdef SABLIER_HAVE_RENDER
    Renderer renderer = {.quiet = quiet};
    AppRenderHooks hooks = {&renderer, hook_movie_open, hook_movie_close, hook_figure};
    options.render = &hooks;
#endif
    int status = app_run(scene, &options);
#ifdef SABLIER_HAVE_RENDER
    if (status == 0) { /* crater figures from the run's CSV files (energy panels, profiles) */
        char plot_err[512] = "";
        if (app_crater_plots(scene, options.out_dir, hook_chart, NULL, plot_err, sizeof plot_err) !=
            0) {
            fprintf(stderr, "sablier: figures: %s\n", plot_err);
            status = 2;
        }
    }
#endif
    scene_free(scene);
    return status;
}

static int command_sweep(int argc, char **argv)
{
    const char *path = NULL, *value, *sets[MAX_SETS], *vary[8];
    int set_count = 0, vary_count = 0;
    long jobs = 2;
    AppSweepOptions o = app_sweep_options_default();
    for (int i = 2; i < argc; ++i) {
        int m;
        if ((m = app_option(argc, argv, &i, "--out", &value)) != 0) {
            if (m < 0)
                return 2;
            o.out_dir = value;
        } else if ((m = app_option(argc, argv, &i, "--from", &value)) != 0) {
            if (m < 0)
                return 2;
            o.from = value;
        } else if ((m = app_option(argc, argv, &i, "--bed-stage", &value)) != 0) {
            if (m < 0)
                return 2;
            o.bed_stage = value;
        } else if ((m = app_option(argc, argv, &i, "--set", &value)) != 0) {
            if (m < 0 || collect_set(sets, &set_count, value) < 0)
                return 2;
        } else if ((m = app_option(argc, argv, &i, "--vary", &value)) != 0) {
            if (m < 0)
                return 2;
            if (vary_count >= 8)
                return app_usage_error(USAGE_SWEEP, "too many --vary options", NULL);
            vary[vary_count++] = value;
        } else if ((m = app_option(argc, argv, &i, "--jobs", &value)) != 0) {
            if (m < 0 || parse_count(value, 1, 64, &jobs) < 0)
                return app_usage_error(USAGE_SWEEP, "--jobs needs a count in [1, 64], got",
                                       m < 0 ? "nothing" : value);
        } else if (strcmp(argv[i], "--quiet") == 0 || strcmp(argv[i], "-q") == 0) {
            o.quiet = 1;
        } else if (strcmp(argv[i], "--dry-run") == 0) {
            o.dry_run = 1;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return app_usage_error(USAGE_SWEEP, "unknown option", argv[i]);
        } else if (!path) {
            path = argv[i];
        } else {
            return app_usage_error(USAGE_SWEEP, "one sweep at a time; extra argument", argv[i]);
        }
    }
    if (!path)
        return app_usage_error(USAGE_SWEEP, "missing FILE.sweep or SCENE", NULL);
    size_t n = strlen(path);
    if (n > 6 && strcmp(path + n - 6, ".sweep") == 0)
        o.definition = path;
    else
        o.scene_path = path;
    o.self = "/proc/self/exe";
    o.jobs = (int)jobs;
    o.sets = sets;
    o.set_count = set_count;
    o.vary = vary;
    o.vary_count = vary_count;
#ifdef SABLIER_HAVE_RENDER
    o.plot = hook_chart;
#endif
    return app_sweep(&o);
}

/* ---------------------------------------------------------------- sediment (thesis 002) */

#ifdef SABLIER_HAVE_RENDER
static int hook_sediment_plot(void *context, const char *path, const char *title,
                              const char *x_label, const char *y_label,
                              const AppSedimentCurve *curves, int curve_count, char *err,
                              size_t err_size)
{
    (void)context;
    RenderSeries series[8];
    int n = curve_count < 8 ? curve_count : 8;
    memset(series, 0, sizeof series);
    for (int k = 0; k < n; ++k) {
        series[k].label = curves[k].label;
        series[k].count = curves[k].count;
        series[k].x = curves[k].x;
        series[k].y = curves[k].y;
        series[k].rgb = RENDER_RGB_AUTO;
        series[k].line = curves[k].line;
        series[k].dashed = curves[k].dashed;
        series[k].marker = curves[k].marker ? RENDER_MARKER_CIRCLE : RENDER_MARKER_NONE;
    }
    RenderPanel panel;
    memset(&panel, 0, sizeof panel);
    panel.x.label = x_label;
    panel.y.label = y_label;
    panel.series_count = n;
    panel.series = series;
    panel.legend = RENDER_LEGEND_UPPER_LEFT;
    RenderPlot plot = {
        .width = 1000, .height = 700, .rows = 1, .cols = 1, .panels = &panel, .title = title};
    RenderMeta meta = {.scene = "sediment", .seed = 0};
    return render_plot_write(&plot, &meta, path, err, err_size) == 0 ? 0 : -1;
}
#endif

static int command_sediment(int argc, char **argv)
{
#ifdef SABLIER_HAVE_RENDER
    Renderer renderer = {.quiet = 1};
    AppRenderHooks hooks = {&renderer, hook_movie_open, hook_movie_close, hook_figure};
    AppSedimentRender render = {NULL, hook_sediment_plot, &hooks};
    return app_sediment_command(argc, argv, &render);
#else
    return app_sediment_command(argc, argv, NULL);
#endif
}

/* ---------------------------------------------------------------- bne (thesis 002) */

static const char USAGE_BNE[] =
    "usage: sablier bne SCENE [--seeds N] [--seed0 S] [--vary KEY=v1,v2,...] [--ldf PERIODS]\n"
    "                   [--out DIR] [--set KEY=VALUE]... [--movies] [--quiet]\n"
    "Runs a scene with a `bne` group for N seeds (default 5) and each value of KEY; writes\n"
    "DIR/samples.csv (rise time and rate per run), rise.csv and rise.png (mean +- std of the\n"
    "intruder's rise against time), ldf.csv and ldf.png (large-deviation function of the rise\n"
    "rate over windows of PERIODS shaking periods, default 5; docs/brazil_nut.md). Each run's own\n"
    "outputs go to DIR/KEY=value/seed-S/ (movies and figures only with --movies).\n";

#ifdef SABLIER_HAVE_RENDER
static int hook_bne_plot(void *context, const char *path, const char *title, const char *x_label,
                         const char *y_label, const AppBneCurve *curves, int curve_count, char *err,
                         size_t err_size)
{
    (void)context;
    RenderSeries series[64];
    int n = curve_count < 64 ? curve_count : 64;
    memset(series, 0, sizeof series);
    for (int k = 0; k < n; ++k) {
        series[k].label = curves[k].label;
        series[k].count = curves[k].count;
        series[k].x = curves[k].x;
        series[k].y = curves[k].y;
        series[k].y_err = curves[k].y_err;
        series[k].rgb = RENDER_RGB_AUTO;
        series[k].line = 1;
    }
    RenderPanel panel;
    memset(&panel, 0, sizeof panel);
    panel.x.label = x_label;
    panel.y.label = y_label;
    panel.series_count = n;
    panel.series = series;
    panel.legend = RENDER_LEGEND_UPPER_LEFT;
    RenderPlot plot = {
        .width = 1000, .height = 700, .rows = 1, .cols = 1, .panels = &panel, .title = title};
    RenderMeta meta = {.scene = "bne", .seed = 0};
    return render_plot_write(&plot, &meta, path, err, err_size) == 0 ? 0 : -1;
}
#endif

static int command_bne(int argc, char **argv)
{
    const char *path = NULL, *value, *sets[MAX_SETS], *out = NULL;
    int set_count = 0, movies = 0;
    long seeds = 5, seed0 = 1;
    AppBneSamplesOptions o;
    memset(&o, 0, sizeof o);
    o.ldf_periods = 5.0;
    for (int i = 2; i < argc; ++i) {
        int m;
        if ((m = app_option(argc, argv, &i, "--out", &value)) != 0) {
            if (m < 0)
                return 2;
            out = value;
        } else if ((m = app_option(argc, argv, &i, "--set", &value)) != 0) {
            if (m < 0 || collect_set(sets, &set_count, value) < 0)
                return 2;
        } else if ((m = app_option(argc, argv, &i, "--vary", &value)) != 0) {
            if (m < 0)
                return 2;
            o.vary = value;
        } else if ((m = app_option(argc, argv, &i, "--seeds", &value)) != 0) {
            if (m < 0 || parse_count(value, 1, 10000, &seeds) < 0)
                return app_usage_error(USAGE_BNE, "--seeds needs a count in [1, 10000], got",
                                       m < 0 ? "nothing" : value);
        } else if ((m = app_option(argc, argv, &i, "--seed0", &value)) != 0) {
            if (m < 0 || parse_count(value, 0, 1000000000, &seed0) < 0)
                return app_usage_error(USAGE_BNE, "--seed0 needs a seed >= 0, got",
                                       m < 0 ? "nothing" : value);
        } else if ((m = app_option(argc, argv, &i, "--ldf", &value)) != 0) {
            char *end = NULL;
            o.ldf_periods = m < 0 ? -1.0 : strtod(value, &end);
            if (m < 0 || !end || *end || !(o.ldf_periods >= 0.0))
                return app_usage_error(USAGE_BNE, "--ldf needs a number of periods >= 0, got",
                                       m < 0 ? "nothing" : value);
        } else if (strcmp(argv[i], "--movies") == 0) {
            movies = 1;
        } else if (strcmp(argv[i], "--quiet") == 0 || strcmp(argv[i], "-q") == 0) {
            o.quiet = 1;
        } else if (app_scene_argument(USAGE_BNE, argv[i], &path) != 0) {
            return 2;
        }
    }
    if (!path)
        return app_usage_error(USAGE_BNE, "missing SCENE", NULL);
    char default_out[SCENE_PATH_MAX];
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    snprintf(default_out, sizeof default_out, "out/bne-%.*s", (int)strcspn(base, "."), base);
    o.scene_path = path;
    o.out_dir = out ? out : default_out;
    o.sets = sets;
    o.set_count = set_count;
    o.seeds = (int)seeds;
    o.seed0 = seed0;
#ifdef SABLIER_HAVE_RENDER
    Renderer renderer = {.quiet = 1};
    AppRenderHooks hooks = {&renderer, hook_movie_open, hook_movie_close, hook_figure};
    if (movies)
        o.render = &hooks;
    o.plot = hook_bne_plot;
#else
    (void)movies;
#endif
    return app_bne_samples(&o);
}

static void print_timing(const Scene *scene, int k)
{
    SimWorldDef def = scene_world_def(scene, k);
    SimTiming t = sim_world_def_timing(&def);
    printf("  time step        %g s%s\n", t.time_step,
           scene->stages[k].time_step > 0.0 ? "" : " (chosen from steps_per_contact)");
    printf("  contact time     %g s (shortest pair)\n", t.contact_time_min);
    printf("  stability limit  %g s\n", t.stability_limit);
    printf("  steps per contact %.1f\n", t.steps_per_contact);
}

static int command_check(int argc, char **argv)
{
    const char *scene_path = NULL, *value, *sets[MAX_SETS];
    int set_count = 0;
    for (int i = 2; i < argc; ++i) {
        int m = app_option(argc, argv, &i, "--set", &value);
        if (m < 0)
            return 2;
        if (m > 0) {
            if (collect_set(sets, &set_count, value) < 0)
                return 2;
        } else if (app_scene_argument(USAGE_CHECK, argv[i], &scene_path) != 0) {
            return 2;
        }
    }
    if (!scene_path)
        return app_usage_error(USAGE_CHECK, "missing SCENE", NULL);
    char err[4096];
    Scene *scene = scene_load(scene_path, sets, set_count, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    static const char *const mass[] = {"disk", "sphere"};
    char effects[256];
    scene_effect_names(scene->def.effects, effects, sizeof effects);
    printf("scene    %s (%s)\n", scene->name, scene->path);
    printf("seed     %llu\n", (unsigned long long)scene->seed);
    printf("effects  %s\n", effects);
    printf("mass     %s, integrator %s, gravity (%g, %g) m/s^2\n", mass[scene->def.mass_model],
           sim_integrator_name(scene->def.integrator), scene->def.gravity_x, scene->def.gravity_y);
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
    if (scene->def.skin > 0.0)
        printf("lists    Verlet skin %g m (fixed)\n", scene->def.skin);
    else
        printf("lists    Verlet skin automatic, 0.01-0.2 mean diameter (the cheapest for the "
               "grains' motion)\n");
    printf("stages   %d\n", scene->stage_count);
    static const char *const loads[] = {"scene grains", "previous stage", "file"};
    for (int k = 0; k < scene->stage_count; ++k) {
        const SceneStage *s = &scene->stages[k];
        printf("stage %s: from %s%s%s, time.end %g s", s->name, loads[s->load],
               s->load == SCENE_LOAD_FILE ? " " : "",
               s->load == SCENE_LOAD_FILE ? s->load_path : "", s->duration);
        if (s->settle_kinetic > 0.0)
            printf(", settle when E_kin + E_rot < %g J (after %g s)", s->settle_kinetic,
                   s->settle_after);
        if (s->dig) {
            printf(", dig center_x %g m width %g m height %g m top ", s->dig_center_x, s->dig_width,
                   s->dig_height);
            if (s->dig_top_surface)
                printf("surface");
            else
                printf("%g m", s->dig_top);
        }
        if (s->remove_count)
            printf(", remove %d ids", s->remove_count);
        printf("%s\n", s->movie ? ", movie" : "");
        print_timing(scene, k);
    }
    const SceneOutput *o = &scene->output;
    printf("output   energy every %g s, %g frames per simulated second, %d figures, %d traced "
           "grains\n",
           o->energy_every, o->frame_rate, o->figure_count, o->trace_count);
    for (int k = 0; k < o->figure_count; ++k)
        if (o->figures[k].at_end == 2)
            printf("figure %s.%s: stage %s, at %g s after its start\n", o->figures[k].name,
                   o->figures[k].format, scene->stages[o->figures[k].stage].name,
                   o->figures[k].at_time);
        else
            printf("figure %s.%s: stage %s, at %s\n", o->figures[k].name, o->figures[k].format,
                   scene->stages[o->figures[k].stage].name, o->figures[k].at_end ? "end" : "start");
    printf("ok\n");
    scene_free(scene);
    return 0;
}

static int command_diff(int argc, char **argv)
{
    const char *files[2] = {NULL, NULL}, *out = NULL, *value;
    long threshold = -1, shift = -1, max_pixels = -1;
    int file_count = 0;
    for (int i = 2; i < argc; ++i) {
        int m;
        long *target = NULL;
        if ((m = app_option(argc, argv, &i, "--out", &value)) != 0) {
            if (m < 0)
                return 2;
            out = value;
            continue;
        }
        if ((m = app_option(argc, argv, &i, "--threshold", &value)) != 0)
            target = &threshold;
        else if ((m = app_option(argc, argv, &i, "--shift", &value)) != 0)
            target = &shift;
        else if ((m = app_option(argc, argv, &i, "--max-pixels", &value)) != 0)
            target = &max_pixels;
        if (target) {
            if (m < 0 || parse_count(value, 0, 1000000000L, target) < 0)
                return app_usage_error(USAGE_DIFF, "expected a count >= 0, got",
                                       m < 0 ? "nothing" : value);
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return app_usage_error(USAGE_DIFF, "unknown option", argv[i]);
        } else if (file_count < 2) {
            files[file_count++] = argv[i];
        } else {
            return app_usage_error(USAGE_DIFF, "two images at a time; extra argument", argv[i]);
        }
    }
    if (file_count != 2)
        return app_usage_error(USAGE_DIFF, "needs two images", NULL);
#ifdef SABLIER_HAVE_RENDER
    RenderDiffOptions options = render_diff_options_default();
    if (threshold >= 0)
        options.channel_threshold = (int)(threshold > 255 ? 255 : threshold);
    if (shift >= 0)
        options.shift_tolerance = (int)shift;
    if (max_pixels >= 0)
        options.max_pixels = max_pixels;
    RenderDiffResult r;
    memset(&r, 0, sizeof r);
    char err[512] = "";
    int rc = render_diff_files(files[0], files[1], &options, out, &r, err, sizeof err);
    if (rc == 2)
        fprintf(stderr, "sablier: diff: %s\n", err);
    printf("{\"result\": \"%s\", \"differing_pixels\": %ld, \"raw_pixels\": %ld, "
           "\"max_channel_diff\": %d, \"rms\": %.6g, \"width\": %d, \"height\": %d, "
           "\"threshold\": %d, \"shift\": %d, \"max_pixels\": %ld}\n",
           rc == 0   ? "match"
           : rc == 1 ? "differ"
                     : "error",
           r.differing_pixels, r.raw_pixels, r.max_channel_diff, isfinite(r.rms) ? r.rms : 0.0,
           r.width, r.height, options.channel_threshold, options.shift_tolerance,
           options.max_pixels);
    return rc == 0 || rc == 1 ? rc : 2;
#else
    (void)out;
    (void)files;
    fprintf(stderr, "sablier: diff: rendering is not built (SABLIER_WITH_RENDER=OFF)\n");
    return 2;
#endif
}

#ifdef SABLIER_HAVE_RENDER
/* A frame straight from saved grains (no world): mobile first, no forces or contacts. */
typedef struct StateFrame {
    double *x, *y, *angle, *radius, *vx, *vy, *omega, *zero;
    int *species;
    unsigned *flags;
    uint32_t *id;
} StateFrame;

static int state_frame(const SimGrainSet *g, const SimWall *walls, int wall_count, double time,
                       StateFrame *s, SimFrame *frame)
{
    size_t n = (size_t)(g->count > 0 ? g->count : 1);
    double **columns[] = {&s->x, &s->y, &s->angle, &s->radius, &s->vx, &s->vy, &s->omega, &s->zero};
    for (size_t c = 0; c < sizeof columns / sizeof columns[0]; ++c)
        *columns[c] = calloc(n, sizeof(double));
    s->species = calloc(n, sizeof(int));
    s->flags = calloc(n, sizeof(unsigned));
    s->id = calloc(n, sizeof(uint32_t));
    for (size_t c = 0; c < sizeof columns / sizeof columns[0]; ++c)
        if (!*columns[c])
            return -1;
    if (!s->species || !s->flags || !s->id)
        return -1;
    int k = 0, mobile = 0;
    for (int pass = 0; pass < 2; ++pass)
        for (int i = 0; i < g->count; ++i) {
            unsigned flags = g->flags ? g->flags[i] : 0u;
            if ((pass == 0) == ((flags & SIM_GRAIN_FIXED) != 0))
                continue;
            s->x[k] = g->x[i];
            s->y[k] = g->y[i];
            s->radius[k] = g->radius[i];
            s->angle[k] = g->angle ? g->angle[i] : 0.0;
            s->vx[k] = g->vx ? g->vx[i] : 0.0;
            s->vy[k] = g->vy ? g->vy[i] : 0.0;
            s->omega[k] = g->omega ? g->omega[i] : 0.0;
            s->species[k] = g->species ? g->species[i] : 0;
            s->flags[k] = flags;
            s->id[k] = g->id ? g->id[i] : (uint32_t)i;
            mobile += pass == 0;
            ++k;
        }
    memset(frame, 0, sizeof *frame);
    frame->count = g->count;
    frame->mobile_count = mobile;
    frame->time = time;
    frame->x = s->x;
    frame->y = s->y;
    frame->angle = s->angle;
    frame->radius = s->radius;
    frame->vx = s->vx;
    frame->vy = s->vy;
    frame->omega = s->omega;
    frame->species = s->species;
    frame->flags = s->flags;
    frame->id = s->id;
    frame->force = frame->fx = frame->fy = frame->torque = s->zero;
    frame->walls = walls;
    frame->wall_count = wall_count;
    return 0;
}

static void state_frame_free(StateFrame *s)
{
    free(s->x);
    free(s->y);
    free(s->angle);
    free(s->radius);
    free(s->vx);
    free(s->vy);
    free(s->omega);
    free(s->zero);
    free(s->species);
    free(s->flags);
    free(s->id);
}

static int name_index(const char *value, const char *const *names)
{
    for (int k = 0; names[k]; ++k)
        if (strcmp(value, names[k]) == 0)
            return k;
    return -1;
}
#endif

static int command_render(int argc, char **argv)
{
#ifdef SABLIER_HAVE_RENDER
    static const char *const color_names[] = {"fixed", "force", "speed", "species", "height", NULL};
    static const char *const cmap_names[] = {"viridis", "yellow_red", "greys", NULL};
    const char *state = NULL, *out = NULL, *scene_path = NULL, *value, *sets[MAX_SETS];
    int set_count = 0;
    SceneStyle over = scene_style_unset();
    for (int i = 2; i < argc; ++i) {
        int m;
        long count;
        if ((m = app_option(argc, argv, &i, "-o", &value)) != 0 ||
            (m = app_option(argc, argv, &i, "--out", &value)) != 0) {
            if (m < 0)
                return 2;
            out = value;
        } else if ((m = app_option(argc, argv, &i, "--scene", &value)) != 0) {
            if (m < 0)
                return 2;
            scene_path = value;
        } else if ((m = app_option(argc, argv, &i, "--set", &value)) != 0) {
            if (m < 0 || collect_set(sets, &set_count, value) < 0)
                return 2;
        } else if ((m = app_option(argc, argv, &i, "--color-by", &value)) != 0) {
            if (m < 0 || (over.color_by = name_index(value, color_names)) < 0)
                return app_usage_error(USAGE_RENDER, "unknown --color-by", m < 0 ? "" : value);
        } else if ((m = app_option(argc, argv, &i, "--colormap", &value)) != 0) {
            if (m < 0 || (over.colormap = name_index(value, cmap_names)) < 0)
                return app_usage_error(USAGE_RENDER, "unknown --colormap", m < 0 ? "" : value);
        } else if ((m = app_option(argc, argv, &i, "--width", &value)) != 0) {
            if (m < 0 || parse_count(value, 16, 16384, &count) < 0)
                return app_usage_error(USAGE_RENDER, "--width must be in [16, 16384], got",
                                       m < 0 ? "" : value);
            over.width = (int)count;
        } else if ((m = app_option(argc, argv, &i, "--height", &value)) != 0) {
            if (m < 0 || parse_count(value, 16, 16384, &count) < 0)
                return app_usage_error(USAGE_RENDER, "--height must be in [16, 16384], got",
                                       m < 0 ? "" : value);
            over.height = (int)count;
        } else if ((m = app_option(argc, argv, &i, "--chain-threshold", &value)) != 0) {
            char *end;
            over.chain_threshold = m > 0 ? strtod(value, &end) : -1.0;
            if (m < 0 || *end || !(over.chain_threshold >= 0.0))
                return app_usage_error(USAGE_RENDER, "bad --chain-threshold", m < 0 ? "" : value);
        } else if ((m = app_option(argc, argv, &i, "--title", &value)) != 0) {
            if (m < 0)
                return 2;
            snprintf(over.title, sizeof over.title, "%s", value);
        } else if (strcmp(argv[i], "--force-chains") == 0) {
            over.force_chains = 1;
        } else if (strcmp(argv[i], "--no-force-chains") == 0) {
            over.force_chains = 0;
        } else if (strcmp(argv[i], "--velocity-field") == 0) {
            over.velocity_field = 1;
        } else if (strcmp(argv[i], "--velocity-arrows") == 0) {
            over.velocity_arrows = 1;
        } else if (strcmp(argv[i], "--colorbar") == 0) {
            over.colorbar = 1;
        } else if (strcmp(argv[i], "--time-stamp") == 0) {
            over.time_stamp = 1;
        } else if (strcmp(argv[i], "--scale-bar") == 0) {
            over.scale_bar = 1;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return app_usage_error(USAGE_RENDER, "unknown option", argv[i]);
        } else if (!state) {
            state = argv[i];
        } else {
            return app_usage_error(USAGE_RENDER, "one state at a time; extra argument", argv[i]);
        }
    }
    if (!state || !out)
        return app_usage_error(USAGE_RENDER, state ? "missing -o FIG" : "missing STATE", NULL);
    if (set_count && !scene_path)
        return app_usage_error(USAGE_RENDER, "--set needs --scene", NULL);
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
    /* figure-style overlay: only what the command line set */
    SceneFigure figure;
    memset(&figure, 0, sizeof figure);
    figure.style = style;
    {
        int *dst[] = {&figure.style.width,           &figure.style.height,
                      &figure.style.color_by,        &figure.style.colormap,
                      &figure.style.force_chains,    &figure.style.velocity_field,
                      &figure.style.velocity_arrows, &figure.style.colorbar,
                      &figure.style.time_stamp,      &figure.style.scale_bar};
        const int src[] = {over.width,           over.height,       over.color_by,
                           over.colormap,        over.force_chains, over.velocity_field,
                           over.velocity_arrows, over.colorbar,     over.time_stamp,
                           over.scale_bar};
        for (size_t k = 0; k < sizeof src / sizeof src[0]; ++k)
            if (src[k] >= 0)
                *dst[k] = src[k];
        if (!isnan(over.chain_threshold))
            figure.style.chain_threshold = over.chain_threshold;
        if (over.title[0])
            snprintf(figure.style.title, sizeof figure.style.title, "%s", over.title);
    }
    RenderStyle render_style = render_style_from_scene(&figure.style);
    RenderMeta meta = {.scene = scene ? scene->name : "", .seed = scene ? scene->seed : 0};
    SimFrame frame;
    StateFrame columns;
    memset(&columns, 0, sizeof columns);
    SimWorld *world = NULL;
    if (scene) {
        SimWorldDef def = scene_world_def(scene, scene->stage_count - 1);
        def.grains = grains;
        def.walls = walls;
        def.wall_count = wall_count;
        def.start_time = time;
        world = sim_world_create(&def, &error);
        if (!world) {
            fprintf(stderr, "sablier: render: %s does not fit scene %s: %s: %s\n", state,
                    scene->path, error.field, error.message);
            status = 2;
        } else {
            sim_world_frame(world, &frame);
        }
    } else if (state_frame(&grains, walls, wall_count, time, &columns, &frame) != 0) {
        fprintf(stderr, "sablier: render: out of memory\n");
        status = 2;
    }
    if (status == 0 &&
        render_figure_write(&frame, &render_style, &meta, out, err, sizeof err) != 0) {
        fprintf(stderr, "sablier: render: %s: %s\n", out, err);
        status = 2;
    }
    if (world)
        sim_world_destroy(world);
    state_frame_free(&columns);
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

static int command_version(void)
{
    const char *render = render_versions();
    printf("sablier %s\nsim %s\n%s\nrender: %s\n", SABLIER_VERSION, SIM_VERSION,
           scene_libconfig_version(), render ? render : "not built");
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fputs(USAGE, stderr);
        return 2;
    }
    const char *command = argv[1];
    if (strcmp(command, "--help") == 0 || strcmp(command, "-h") == 0 ||
        strcmp(command, "help") == 0) {
        fputs(USAGE, stdout);
        return 0;
    }
    if (strcmp(command, "--version") == 0 || strcmp(command, "version") == 0)
        return command_version();

    static const struct {
        const char *name;
        int (*run)(int, char **);
        const char *usage;
    } commands[] = {
        {"run", command_run, USAGE_RUN},
        {"check", command_check, USAGE_CHECK},
        {"diff", command_diff, USAGE_DIFF},
        {"render", command_render, USAGE_RENDER},
        {"sweep", command_sweep, USAGE_SWEEP},
        {"discharge", command_discharge, APP_DISCHARGE_USAGE},
        {"study", command_study, APP_STUDY_USAGE},
        {"bne", command_bne, USAGE_BNE},
        {"sediment", command_sediment, APP_SEDIMENT_USAGE},
    };

    for (size_t k = 0; k < sizeof commands / sizeof commands[0]; ++k) {
        if (strcmp(command, commands[k].name) != 0)
            continue;
        if (wants_help(argc, argv)) {
            fputs(commands[k].usage, stdout);
            return 0;
        }
        return commands[k].run(argc, argv);
    }
    fprintf(stderr, "sablier: unknown command `%s`\n\n%s", command, USAGE);
    return 2;
}
