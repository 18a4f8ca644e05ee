/* SPDX-License-Identifier: MIT */
/* render_glue.c: the app layer's AppRender (render_hooks.h) filled with render/ calls. The only
 * app file besides sablier.c that sees render/; it knows no experiment family: what a family adds
 * to a figure comes as AppFigureExtras (marks, side panels). */
#include "cli/render_glue.h"

#include "base/util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* the scene loader refuses exactly the frame rates the encoder refuses */
_Static_assert((long)SCENE_MAX_FPS == (long)RENDER_VIDEO_MAX_FPS, "SCENE_MAX_FPS");
/* scene.h and render_hooks.h mirror three render enums value for value; the casts below rely on it
 */
_Static_assert(SCENE_COLOR_FIXED == (int)RENDER_COLOR_FIXED &&
                   SCENE_COLOR_FORCE == (int)RENDER_COLOR_FORCE &&
                   SCENE_COLOR_SPEED == (int)RENDER_COLOR_SPEED &&
                   SCENE_COLOR_SPECIES == (int)RENDER_COLOR_SPECIES &&
                   SCENE_COLOR_HEIGHT == (int)RENDER_COLOR_HEIGHT,
               "SceneColorBy mirrors RenderColorBy");
_Static_assert(SCENE_CMAP_VIRIDIS == (int)RENDER_CMAP_VIRIDIS &&
                   SCENE_CMAP_YELLOW_RED == (int)RENDER_CMAP_YELLOW_RED &&
                   SCENE_CMAP_GREYS == (int)RENDER_CMAP_GREYS,
               "SceneColormap mirrors RenderColormap");
_Static_assert(APP_MARKER_NONE == (int)RENDER_MARKER_NONE &&
                   APP_MARKER_CIRCLE == (int)RENDER_MARKER_CIRCLE &&
                   APP_MARKER_SQUARE == (int)RENDER_MARKER_SQUARE &&
                   APP_MARKER_TRIANGLE == (int)RENDER_MARKER_TRIANGLE &&
                   APP_MARKER_CROSS == (int)RENDER_MARKER_CROSS,
               "AppMarker mirrors RenderMarker");

/* Journal column presets (docs/figures.md#print-sizes): width x height, cm. */
static const double preset_cm[][2] = {{8.5, 6.4}, {17.8, 8.9}};

/* A print size: width and height (inches, 0 = none), dpi (0 = unset) and font (pixels, 0 =
 * unset). */
typedef struct PrintSize {
    double w_in, h_in, dpi, font_px;
} PrintSize;

/* `size` (cm or in), else a `style` preset, else the preset `fallback` (-1 none), at `dpi` (300
 * when a size is known); `font_size` points (8 pt with a preset) at that dpi. */
static PrintSize print_resolve(const SceneStyle *s, int fallback)
{
    int preset = s->preset >= 0 && s->preset <= 1 ? s->preset : -1;
    int sized = preset >= 0 ? preset : fallback;
    PrintSize p = {0};
    if (!isnan(s->size_w)) {
        double per_unit = s->size_inches == 1 ? 1.0 : 1.0 / 2.54;
        p.w_in = s->size_w * per_unit;
        p.h_in = s->size_h * per_unit;
    } else if (sized >= 0) {
        p.w_in = preset_cm[sized][0] / 2.54;
        p.h_in = preset_cm[sized][1] / 2.54;
    }
    p.dpi = !isnan(s->dpi) ? s->dpi : p.w_in > 0.0 ? 300.0 : 0.0;
    double pt = !isnan(s->font_pt) ? s->font_pt : preset >= 0 ? 8.0 : 0.0;
    p.font_px = pt > 0.0 ? pt * (p.dpi > 0.0 ? p.dpi : 96.0) / 72.0 : 0.0;
    return p;
}

static int print_pixels(double inches, double dpi)
{
    return (int)fmin(16384.0, fmax(16.0, round(inches * dpi)));
}

/* Print size of a grain figure (docs/figures.md#print-sizes). */
static void print_size(const SceneStyle *s, RenderStyle *r)
{
    PrintSize p = print_resolve(s, -1);
    r->dpi = p.dpi;
    if (p.w_in > 0.0) {
        r->width = print_pixels(p.w_in, p.dpi);
        r->height = print_pixels(p.h_in, p.dpi);
    }
    if (p.font_px > 0.0)
        r->font_size = p.font_px;
}

/* Print size of a plot (docs/figures.md#plots): the print keys, else one column wide (two for
 * several columns of panels) at 300 dpi with the family's width:height. */
static void plot_print(const AppPlot *plot, int cols, RenderPlot *r)
{
    SceneStyle none = scene_style_unset();
    const SceneStyle *s = plot->print ? plot->print : &none;
    double w = plot->width > 0 ? plot->width : 1000, h = plot->height > 0 ? plot->height : 700;
    PrintSize p = print_resolve(s, cols > 1 ? 1 : 0);
    if (isnan(s->size_w) && !(s->preset >= 0 && s->preset <= 1))
        p.h_in = p.w_in * h / w; /* the family's shape at a column's width */
    r->dpi = p.dpi;
    r->width = print_pixels(p.w_in, p.dpi);
    r->height = print_pixels(p.h_in, p.dpi);
    r->font_size = plot->font_size > 0 ? plot->font_size * p.dpi / 72.0 : p.font_px;
}

void app_render_names(const Scene *scene, const char *names[SIM_MAX_SPECIES], RenderStyle *style)
{
    for (int k = 0; k < SIM_MAX_SPECIES; ++k)
        names[k] = scene ? scene->species_names[k] : "";
    style->species_names = names;
    style->species_name_count = SIM_MAX_SPECIES;
}

void app_reduced_style(double force_unit, double speed_unit, RenderStyle *style)
{
    if (!(force_unit > 0.0 && speed_unit > 0.0))
        return;
    style->force_unit = force_unit;
    style->speed_unit = speed_unit;
    if (style->color_by == RENDER_COLOR_FORCE)
        style->colorbar_unit = "m g";
    else if (style->color_by == RENDER_COLOR_SPEED)
        style->colorbar_unit = "\xe2\x88\x9a(gd)"; /* sqrt(g d) */
}

RenderStyle app_render_style(const SceneStyle *s)
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
    r.reduced_units = s->reduced_units;
    r.normalised_units = s->normalised_units == SCENE_UNITS_NORMALISED_G ? RENDER_UNITS_NORMALISED_G
                         : s->normalised_units                           ? RENDER_UNITS_NORMALISED
                                                                         : 0;
    r.axes = s->axes > 0;
    r.field_color = s->field_color > 0;
    print_size(s, &r);
    /* colour-bar label and unit follow the quantity, the unit in the scene's units (scene
     * units table: N, m/s, m in SI; m g, sqrt(g d), d in a normalised scene with g = 1) */
    static const char *const labels[] = {"", "contact force", "speed", "species", "height"};
    static const SceneQuantity quantity[] = {SCENE_DIMENSIONLESS, SCENE_FORCE, SCENE_SPEED,
                                             SCENE_DIMENSIONLESS, SCENE_LENGTH};
    if (r.color_by >= RENDER_COLOR_FIXED && r.color_by <= RENDER_COLOR_HEIGHT) {
        r.colorbar_label = labels[r.color_by];
        r.colorbar_unit = scene_style_unit(s, quantity[r.color_by], 1);
    }
    return r;
}

typedef struct Renderer {
    RenderMovie *movie;
    const char *species[SIM_MAX_SPECIES]; /* the movie's legend names */
    int quiet;
    char comment[2048]; /* provenance of the figures (PNG Comment) */
    /* a movie that opens at its first frame (its view follows the grains) */
    int pending, failed;
    RenderMovieDef def;
    RenderStyle style;
    char path[SCENE_PATH_MAX + 64];
    char message[512];

    /* figure series: what their first figure fixed (series_fix) */
    struct FigureSeries {
        char scene[SCENE_NAME_MAX];
        uint64_t seed;
        int stage, color_by, field, fixed;
        double range[2], view[4], arrow_scale;
    } series[16];

    int series_count;
    double force_unit, speed_unit; /* reduced units: m g (N) and sqrt(g d) (m/s); 0 = SI */
    int threads;                   /* the movies' drawing threads (RenderMovieDef); 0 = the CPUs */
} Renderer;

static void hook_reduced_units(void *context, double force_unit, double speed_unit)
{
    Renderer *renderer = context;
    renderer->force_unit = force_unit;
    renderer->speed_unit = speed_unit;
}

static void hook_threads(void *context, int threads)
{
    Renderer *renderer = context;
    renderer->threads = threads > 0 ? threads : 0;
}

static void hook_provenance(void *context, const char *comment)
{
    Renderer *renderer = context;
    snprintf(renderer->comment, sizeof renderer->comment, "%s", comment ? comment : "");
}

static const char *renderer_comment(const void *context)
{
    const Renderer *renderer = context;
    return renderer && renderer->comment[0] ? renderer->comment : NULL;
}

/* The mobile grains' box in a frame (all grains when none is mobile; walls and fixed grains
 * such as containers built of grains do not count) widened by 2 mean diameters and 5 % of its
 * larger side on every side; a periodic frame spans its domain. 0, or -1 with no grains. */
static int grains_window(const SimFrame *f, double w[4])
{
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY, d = 0.0;
    int n = 0;
    for (int i = 0; i < f->count; ++i) {
        if (f->mobile_count > 0 && f->flags && (f->flags[i] & SIM_GRAIN_FIXED))
            continue;
        ++n;
        x0 = fmin(x0, f->x[i] - f->radius[i]);
        x1 = fmax(x1, f->x[i] + f->radius[i]);
        y0 = fmin(y0, f->y[i] - f->radius[i]);
        y1 = fmax(y1, f->y[i] + f->radius[i]);
        d += 2.0 * f->radius[i];
    }
    if (n == 0 || !(x1 > x0) || !(y1 > y0))
        return -1;
    double margin = 2.0 * d / n + 0.05 * fmax(x1 - x0, y1 - y0);
    w[0] = x0 - margin;
    w[1] = y0 - margin;
    w[2] = x1 + margin;
    w[3] = y1 + margin;
    if (f->periodic && f->domain_x1 > f->domain_x0) {
        w[0] = f->domain_x0;
        w[2] = f->domain_x1;
    }
    return 0;
}

/* First frame of a following movie: its window (the stage's `view`, else the grains' box now),
 * the height that fits that window at the movie's width (even, 64 to 4096 pixels), then the
 * encoder. 0, or -1 with the message kept for movie_close. */
static int movie_start(Renderer *renderer, const SimFrame *frame)
{
    RenderStyle *style = &renderer->style;
    double w[4];
    if (!(style->view_x1 > style->view_x0) && grains_window(frame, w) == 0) {
        style->view_x0 = w[0];
        style->view_y0 = w[1];
        style->view_x1 = w[2];
        style->view_y1 = w[3];
    }
    int height = render_fit_height(frame, style);
    height = height < 64 ? 64 : height > 4096 ? 4096 : height;
    style->height = height + height % 2;
    renderer->pending = 0;
    renderer->movie =
        render_movie_open(&renderer->def, style, renderer->message, sizeof renderer->message);
    renderer->failed = renderer->movie == NULL;
    return renderer->failed ? -1 : 0;
}

static int lazy_consume(void *context, const SimFrame *frame)
{
    Renderer *renderer = context;
    if (renderer->pending && movie_start(renderer, frame) != 0)
        return -1;
    if (!renderer->movie)
        return -1;
    return render_movie_frame(renderer->movie, frame) != 0;
}

/* A stage's movie: with a `view` of its own, or with output.movie_view = "grains" (the default)
 * and no `render.view`, it follows the material: its window and height are set at its first
 * frame (movie_start); else it opens now with the render style's fixed size and window. */
static int hook_movie_open(void *context, const Scene *scene, int stage, const char *path,
                           SimFrameSink *sink, char *err, size_t err_size)
{
    Renderer *renderer = context;
    RenderStyle style = app_render_style(&scene->style); /* axes off unless asked */
    app_render_names(scene, renderer->species, &style);
    app_reduced_style(renderer->force_unit, renderer->speed_unit, &style);
    style.width += style.width % 2; /* H.264 needs even sizes */
    style.height += style.height % 2;
    snprintf(renderer->path, sizeof renderer->path, "%s", path);
    RenderMovieDef def = {
        .path = renderer->path,
        .drawer = scene->output.drawer == 1 ? RENDER_DRAWER_OSMESA : RENDER_DRAWER_CAIRO,
        .fps = scene->output.fps,
        .crf = scene->output.crf,
        .quiet = 1,
        .meta = {.scene = scene->name, .seed = scene->seed},
        .threads = renderer->threads,
    };
    const double *own =
        stage >= 0 && stage < scene->stage_count ? scene->stages[stage].movie_view : NULL;
    int has_own = own && own[2] > own[0] && own[3] > own[1];
    int fixed_view = style.view_x1 > style.view_x0 && style.view_y1 > style.view_y0;
    if (has_own || (scene->output.movie_view == 0 && !fixed_view)) {
        if (has_own) {
            style.view_x0 = own[0];
            style.view_y0 = own[1];
            style.view_x1 = own[2];
            style.view_y1 = own[3];
        }
        renderer->def = def;
        renderer->style = style;
        renderer->pending = 1;
        renderer->failed = 0;
        renderer->movie = NULL;
        *sink = (SimFrameSink){.consume = lazy_consume, .context = renderer};
        return 0;
    }
    renderer->pending = 0;
    renderer->movie = render_movie_open(&def, &style, err, err_size);
    if (!renderer->movie)
        return -1;
    *sink = render_movie_sink(renderer->movie);
    return 0;
}

static double hook_movie_encode_left(void *context, long frames_to_come)
{
    Renderer *renderer = context;
    return renderer->movie ? render_movie_encode_left(renderer->movie, frames_to_come) : 0.0;
}

static int hook_movie_close(void *context, char *err, size_t err_size)
{
    Renderer *renderer = context;
    if (!renderer->movie) { /* a following movie that never opened */
        snprintf(err, err_size, "%s",
                 renderer->failed ? renderer->message : "no frames: the movie was not written");
        renderer->pending = renderer->failed = 0;
        return -1;
    }
    int rc = render_movie_close(renderer->movie, err, err_size);
    renderer->movie = NULL;
    if (rc == 0)
        app_output_note(renderer->path);
    return rc == 0 ? 0 : -1;
}

/* The grains' image and the plot side by side, the plot's rows moved down by `shift`, on white. */
static int side_by_side(const RenderImage *bed, const RenderImage *plot, int shift,
                        RenderImage *out)
{
    int top = shift < 0 ? -shift : 0;
    int height = bed->height + top > plot->height + shift + top ? bed->height + top
                                                                : plot->height + shift + top;
    if (render_image_alloc(out, bed->width + plot->width, height, RENDER_PIXEL_RGBA) != 0)
        return -1;
    for (int row = 0; row < height; ++row)
        for (int col = 0; col < out->width; ++col) {
            uint8_t rgba[4] = {255, 255, 255, 255};
            int br = row - top, pr = row - top - shift;
            if (col < bed->width && br >= 0 && br < bed->height)
                render_image_get_rgba(bed, col, br, rgba);
            else if (col >= bed->width && pr >= 0 && pr < plot->height)
                render_image_get_rgba(plot, col - bed->width, pr, rgba);
            memcpy(out->pixels + (size_t)row * (size_t)out->stride + 4 * (size_t)col, rgba, 4);
        }
    return 0;
}

/* The panels beside a grain figure and the series of each, at most. */
enum { SIDE_MAX_PANELS = 4, SIDE_MAX_SERIES = 4 };

/* The side panels of a grain figure in render's form, each series clipped to the grain view's
 * y range [y_bottom, y_top] (a NaN point where it leaves it: the pen lifts) into `buffer` (two
 * doubles a point); an x range left unset runs from 0 to 1.05 max |x|. */
static void side_panels(const AppFigureExtras *extras, int panel_count, double y_bottom,
                        double y_top, double *buffer, RenderSeries series[][SIDE_MAX_SERIES],
                        RenderPanel *panels)
{
    double *next = buffer;
    for (int k = 0; k < panel_count; ++k) {
        const AppPlotPanel *in = &extras->side_panels[k];
        double x_max = 0.0;
        int n_series = in->series_count < SIDE_MAX_SERIES ? in->series_count : SIDE_MAX_SERIES;
        for (int j = 0; j < n_series; ++j) {
            const AppPlotSeries *s = &in->series[j];
            double *x = next, *y = next + s->count;
            int n = 0;
            for (int i = 0; i < s->count; ++i)
                if (s->y[i] >= y_bottom && s->y[i] <= y_top) {
                    x[n] = s->x[i];
                    y[n++] = s->y[i];
                    if (isfinite(s->x[i]))
                        x_max = fmax(x_max, fabs(s->x[i]));
                } else if (n > 0 && !isnan(y[n - 1])) { /* a gap: the pen lifts */
                    x[n] = y[n] = (double)NAN;
                    ++n;
                }
            next += 2 * (size_t)s->count;
            series[k][j] = (RenderSeries){.label = s->label,
                                          .count = n,
                                          .x = x,
                                          .y = y,
                                          .rgb = s->rgb < 0 ? RENDER_RGB_AUTO : (uint32_t)s->rgb,
                                          .line = s->line,
                                          .dashed = s->dashed,
                                          .marker = (RenderMarker)s->marker};
        }
        panels[k].title = in->title;
        panels[k].x.label = in->x_label;
        panels[k].x.min = in->x_min;
        panels[k].x.max = in->x_max > in->x_min ? in->x_max : x_max > 0.0 ? 1.05 * x_max : 1.0;
        panels[k].y.label = in->y_label;
        panels[k].y.min = y_bottom;
        panels[k].y.max = y_top;
        panels[k].series_count = n_series;
        panels[k].series = series[k];
    }
}

/* Draws the panels, changing their height until their y axis spans the grain view's height to a
 * pixel (three tries at most); *top_px gets the pixel row of y_top in the plot. 0, or -1 with a
 * message. */
static int match_plot_height(RenderPlot *r, const RenderView *view, double y_top, double y_bottom,
                             RenderImage *plot, double *top_px, char *err, size_t err_size)
{
    double bottom_px = 0.0, x_px;
    *top_px = 0.0;
    int rc = 0;
    for (int pass = 0; pass < 3 && rc == 0; ++pass) { /* match the vertical scales */
        render_image_free(plot);
        rc = render_plot_draw(r, plot, err, err_size);
        if (rc != 0 || render_plot_map(r, 0, 0.0, y_top, &x_px, top_px) != 0 ||
            render_plot_map(r, 0, 0.0, y_bottom, &x_px, &bottom_px) != 0)
            break;
        int grow = (int)lround(view->plot_h - (bottom_px - *top_px));
        if (grow == 0)
            break;
        r->height += grow;
    }
    return rc;
}

/* Writes the side-by-side image as PNG at `path` and, when `other` is set, the same page as
 * vector PDF or SVG (render.plot_format). 0, or -1 with a message. */
static int write_side_figure(const SimFrame *frame, const RenderStyle *style,
                             const RenderMeta *meta, const RenderPlot *r, int shift,
                             const RenderImage *out, const char *path, const char *other, char *err,
                             size_t err_size)
{
    char seed[32];
    snprintf(seed, sizeof seed, "%llu", (unsigned long long)meta->seed);
    const char *text[] = {"Software", "sablier", "Scene", meta->scene, "Seed", seed, NULL};
    int rc = render_png_write(out, path, text, err, err_size) == 0 ? 0 : -1;
    if (rc == 0 && other) { /* the same page as vector PDF or SVG (render.plot_format) */
        rc = render_figure_beside_write(frame, style, meta, r, shift, other, err, err_size);
        if (rc == 0)
            app_output_note(other);
    }
    return rc;
}

/* Panels beside a grain figure on the same heights (thesis 002 fig. 31 for the sediment bed):
 * the grains (render_cairo_draw) and the plot (render_plot_draw) side by side, the plot's y axis
 * the grain view's y range, its height adjusted until the two scales match to a pixel. Each
 * series is clipped to that range (a gap where it leaves it); an x range left unset runs from 0
 * to 1.05 max |x|. Text at the grain figure's font size. `print`: the figure has a print size
 * (`size` or `style`), which the whole is to fill: the grains take two thirds of its width and
 * the panels the rest; else the grains take the figure's width and the panels half as much more
 * (at least 360 pixels). */
static int side_figure(const SimFrame *frame, const RenderStyle *figure_style, int print,
                       const RenderMeta *meta, const AppFigureExtras *extras, const char *path,
                       const char *other, char *err, size_t err_size)
{
    RenderStyle grains = *figure_style;
    if (print && figure_style->width > 0)
        grains.width = figure_style->width * 2 / 3;
    const RenderStyle *style = &grains;
    RenderView view;
    render_view_fit(frame, style, &view);
    double y_top = view.center_y + 0.5 * view.plot_h / view.scale;
    double y_bottom = view.center_y - 0.5 * view.plot_h / view.scale;
    int panel_count =
        extras->side_panel_count < SIDE_MAX_PANELS ? extras->side_panel_count : SIDE_MAX_PANELS;
    size_t points = 0;
    for (int k = 0; k < panel_count; ++k)
        for (int j = 0; j < extras->side_panels[k].series_count && j < SIDE_MAX_SERIES; ++j)
            points += (size_t)extras->side_panels[k].series[j].count;
    double *buffer = malloc(2 * (points + 1) * sizeof *buffer);
    if (!buffer) {
        snprintf(err, err_size, "out of memory");
        return -1;
    }
    RenderSeries series[SIDE_MAX_PANELS][SIDE_MAX_SERIES];
    RenderPanel panels[SIDE_MAX_PANELS];
    memset(series, 0, sizeof series);
    memset(panels, 0, sizeof panels);
    side_panels(extras, panel_count, y_bottom, y_top, buffer, series, panels);
    RenderImage bed = {0}, plot = {0}, out = {0};
    RenderPlot r = {.width = print && figure_style->width > 0 ? figure_style->width - style->width
                             : style->width > 0               ? style->width / 2
                                                              : 600,
                    .height = style->height,
                    .rows = 1,
                    .cols = panel_count,
                    .panels = panels,
                    .font_size = render_style_resolve(frame, style).font_size,
                    .dpi = style->dpi};
    if (r.width < 360 && !print)
        r.width = 360;
    int rc = render_cairo_draw(frame, style, &bed) == 0 ? 0 : -1;
    if (rc != 0)
        snprintf(err, err_size, "cannot draw the bed");
    double top_px = 0.0;
    if (rc == 0)
        rc = match_plot_height(&r, &view, y_top, y_bottom, &plot, &top_px, err, err_size);
    int shift = (int)lround(view.plot_y - top_px);
    if (rc == 0 && side_by_side(&bed, &plot, shift, &out) != 0) {
        snprintf(err, err_size, "out of memory");
        rc = -1;
    }
    if (rc == 0)
        rc = write_side_figure(frame, style, meta, &r, shift, &out, path, other, err, err_size);
    render_image_free(&bed);
    render_image_free(&plot);
    render_image_free(&out);
    free(buffer);
    return rc;
}

/* A figure series: the figures of one scene's stage that colour grains by one quantity (and
 * draw a velocity field or not), e.g. collapse frames at several times, or the discharge's
 * panels. They share one colour range (render_color_lock: the figure's `range` when it has one,
 * else the first figure's with headroom), one window (the first figure's when they declare no
 * `view`) and one arrow length per speed, so their panels compare (docs/figures.md). */
static void series_fix(Renderer *renderer, const Scene *scene, const SceneFigure *figure,
                       const SimFrame *frame, RenderStyle *style)
{
    if (!renderer || !scene)
        return;
    struct FigureSeries *sr = NULL;
    for (int k = 0; k < renderer->series_count && !sr; ++k) {
        struct FigureSeries *c = &renderer->series[k];
        if (strcmp(c->scene, scene->name) == 0 && c->seed == scene->seed &&
            c->stage == figure->stage && c->color_by == (int)style->color_by &&
            c->field == style->velocity_field)
            sr = c;
    }
    if (!sr) {
        if (renderer->series_count == (int)(sizeof renderer->series / sizeof *renderer->series))
            return; /* more series than slots: each figure on its own */
        sr = &renderer->series[renderer->series_count++];
        memset(sr, 0, sizeof *sr);
        snprintf(sr->scene, sizeof sr->scene, "%s", scene->name);
        sr->seed = scene->seed;
        sr->stage = figure->stage;
        sr->color_by = (int)style->color_by;
        sr->field = style->velocity_field;
    }
    if (sr->fixed) {
        if (!(style->range_min < style->range_max) && sr->range[0] < sr->range[1]) {
            style->range_min = sr->range[0];
            style->range_max = sr->range[1];
        }
        render_color_lock(frame, style);
        if (!(style->view_x1 > style->view_x0)) {
            style->view_x0 = sr->view[0];
            style->view_y0 = sr->view[1];
            style->view_x1 = sr->view[2];
            style->view_y1 = sr->view[3];
        }
        if (!(style->arrow_scale > 0))
            style->arrow_scale = sr->arrow_scale;
        return;
    }
    if (!render_color_lock(frame, style))
        return; /* nothing to colour yet: the next figure fixes the series */
    RenderView v;
    render_view_fit(frame, style, &v);
    sr->view[0] = v.center_x - 0.5 * v.plot_w / v.scale;
    sr->view[1] = v.center_y - 0.5 * v.plot_h / v.scale;
    sr->view[2] = v.center_x + 0.5 * v.plot_w / v.scale;
    sr->view[3] = v.center_y + 0.5 * v.plot_h / v.scale;
    sr->arrow_scale = style->velocity_arrows ? render_style_resolve(frame, style).arrow_scale : 0;
    sr->range[0] = style->range_min;
    sr->range[1] = style->range_max;
    sr->fixed = 1;
}

/* render.plot_format = 1 (pdf) or 2 (svg) beside a PNG at `path`: 1 and that file's path in
 * `other` (4096 bytes), else 0 (another format, not a PNG, a path too long). */
static int beside_path(const char *path, int format, char other[4096])
{
    static const char *const extensions[] = {"png", "pdf", "svg"};
    size_t len = strlen(path);
    if (!(format >= 1 && format <= 2) || len <= 4 || len >= 4096 ||
        strcmp(path + len - 4, ".png") != 0)
        return 0;
    memcpy(other, path, len - 3);
    memcpy(other + len - 3, extensions[format], 4);
    return 1;
}

/* 1 when a figure of the scene named `name` is written in `format` ("pdf"): its own file wins
 * over a PNG figure's copy beside (render.plot_format) */
static int figure_written_as(const Scene *scene, const char *name, const char *format)
{
    for (int k = 0; k < scene->output.figure_count; ++k)
        if (strcmp(scene->output.figures[k].name, name) == 0 &&
            strcmp(scene->output.figures[k].format, format) == 0)
            return 1;
    return 0;
}

static int hook_figure(void *context, const Scene *scene, const SceneFigure *figure,
                       const SimFrame *frame, const AppFigureExtras *extras, const char *path,
                       char *err, size_t err_size)
{
    RenderStyle style = app_render_style(&figure->style);
    const char *species[SIM_MAX_SPECIES];
    app_render_names(scene, species, &style);
    const Renderer *renderer = context;
    app_reduced_style(renderer->force_unit, renderer->speed_unit, &style);
    if (figure->style.axes < 0)
        style.axes = 1; /* figures have axes unless they say `axes = false` */
    RenderMeta meta = {
        .scene = scene->name, .seed = scene->seed, .comment = renderer_comment(context)};
    if (extras && extras->title)
        style.title = extras->title;
    if (extras && extras->field_vx && extras->field_vy) { /* a field on its own nodes */
        style.node_vx = extras->field_vx;
        style.node_vy = extras->field_vy;
        style.node_nx = extras->field_nx;
        style.node_ny = extras->field_ny;
        style.node_x0 = extras->field_x0;
        style.node_y0 = extras->field_y0;
        style.node_cell = extras->field_cell;
    }
    series_fix(context, scene, figure, frame, &style);
    if (extras && extras->marks) { /* an arch: highlighted, zoomed inset, force chains */
        style.arch_ids = extras->marks;
        style.arch_inset = 1;
        style.force_chains = 1;
    }
    size_t len = strlen(path);
    int side =
        extras && extras->side_panel_count > 0 && len > 4 && strcmp(path + len - 4, ".png") == 0;
    int print =
        !isnan(figure->style.size_w) || (figure->style.preset >= 0 && figure->style.preset <= 1);
    /* render.plot_format = "pdf" or "svg": a PNG figure also in that format beside it */
    char other[4096];
    int also = beside_path(path, figure->style.plot_format, other) &&
               !figure_written_as(scene, figure->name, other + strlen(other) - 3);
    int rc = side ? side_figure(frame, &style, print, &meta, extras, path, also ? other : NULL, err,
                                err_size)
                  : render_figure_write(frame, &style, &meta, path, err, err_size);
    if (rc == 0)
        app_output_note(path);
    if (rc == 0 && !side && also) {
        rc = render_figure_write(frame, &style, &meta, other, err, err_size);
        if (rc == 0)
            app_output_note(other);
    }
    return rc == 0 ? 0 : -1;
}

static RenderLegend legend_of(const AppPlotPanel *p)
{
    switch (p->legend) {
    case APP_LEGEND_NONE:
        return RENDER_LEGEND_NONE;
    case APP_LEGEND_UPPER_RIGHT:
        return RENDER_LEGEND_UPPER_RIGHT;
    case APP_LEGEND_UPPER_LEFT:
        return RENDER_LEGEND_UPPER_LEFT;
    case APP_LEGEND_OUTSIDE:
        return RENDER_LEGEND_OUTSIDE;
    default:
        return p->series_count > 1 ? RENDER_LEGEND_BEST : RENDER_LEGEND_NONE;
    }
}

static uint32_t rgb_of(long rgb)
{
    return rgb == APP_RGB_AUTO       ? RENDER_RGB_AUTO
           : rgb == APP_RGB_PREVIOUS ? RENDER_RGB_PREVIOUS
                                     : (uint32_t)rgb;
}

/* A CSV field: the text between double quotes, a quote doubled (RFC 4180). */
static void csv_text(FILE *f, const char *text)
{
    fputc('"', f);
    for (const char *c = text ? text : ""; *c; ++c) {
        if (*c == '"')
            fputc('"', f);
        fputc(*c, f);
    }
    fputc('"', f);
}

/* A plot's data beside it (docs/figures.md#plot-data): PATH with .csv for its extension, one row
 * per point, `panel,series,label,x,y,y_err` (from 1; missing values and error bars empty), after
 * comment lines that name each panel's axes with their units, as the plot labels them. */
static int plot_data_write(const AppPlot *plot, const char *path)
{
    size_t len = strlen(path);
    char *csv = malloc(len + 5);
    if (!csv)
        return -1;
    memcpy(csv, path, len + 1);
    char *dot = strrchr(csv, '.');
    strcpy(dot && !strchr(dot, '/') ? dot : csv + len, ".csv");
    const char *base = strrchr(path, '/');
    FILE *f = app_tmp_open(csv, NULL);
    if (f) {
        fprintf(f, "# sablier plot data: %s (docs/figures.md#plot-data)\n", base ? base + 1 : path);
        for (int p = 0; p < plot->panel_count; ++p) {
            const AppPlotPanel *in = &plot->panels[p];
            fprintf(f, "# panel %d: x = %s; y = %s\n", p + 1, in->x_label ? in->x_label : "",
                    in->y_label ? in->y_label : "");
        }
        fputs("panel,series,label,x,y,y_err\n", f);
        for (int p = 0; p < plot->panel_count; ++p)
            for (int k = 0; k < plot->panels[p].series_count; ++k) {
                const AppPlotSeries *s = &plot->panels[p].series[k];
                for (int i = 0; i < s->count; ++i) {
                    fprintf(f, "%d,%d,", p + 1, k + 1);
                    csv_text(f, s->label);
                    const double v[3] = {s->x[i], s->y[i], s->y_err ? s->y_err[i] : (double)NAN};
                    for (int q = 0; q < 3; ++q) {
                        fputc(',', f);
                        if (isfinite(v[q]))
                            fprintf(f, "%.9g", v[q]);
                    }
                    fputc('\n', f);
                }
            }
    }
    int rc = f ? app_tmp_commit(&f, csv) : -1;
    free(csv);
    return rc;
}

static int hook_plot(void *context, const AppPlot *plot, const char *path, char *err,
                     size_t err_size)
{
    (void)context;

    enum { MAX_PANELS = 8, MAX_SERIES = 64 };

    int count = plot->panel_count < MAX_PANELS ? plot->panel_count : MAX_PANELS;
    RenderPanel panels[MAX_PANELS];
    RenderSeries *series = calloc((size_t)(count > 0 ? count : 1) * MAX_SERIES, sizeof *series);
    if (!series) {
        snprintf(err, err_size, "out of memory");
        return -1;
    }
    memset(panels, 0, sizeof panels);
    for (int p = 0; p < count; ++p) {
        const AppPlotPanel *in = &plot->panels[p];
        int n = in->series_count < MAX_SERIES ? in->series_count : MAX_SERIES;
        RenderSeries *out = series + (size_t)p * MAX_SERIES;
        for (int k = 0; k < n; ++k) {
            const AppPlotSeries *s = &in->series[k];
            out[k] = (RenderSeries){.label = s->label,
                                    .count = s->count,
                                    .x = s->x,
                                    .y = s->y,
                                    .y_err = s->y_err,
                                    .rgb = rgb_of(s->rgb),
                                    .line = s->line,
                                    .dashed = s->dashed,
                                    .marker = (RenderMarker)s->marker};
        }
        panels[p] = (RenderPanel){.title = in->title,
                                  .x = {.label = in->x_label,
                                        .log = in->x_log,
                                        .min = in->x_min,
                                        .max = in->x_max,
                                        .domain_min = in->x_domain_min,
                                        .domain_max = in->x_domain_max},
                                  .y = {.label = in->y_label,
                                        .log = in->y_log,
                                        .min = in->y_min,
                                        .max = in->y_max,
                                        .domain_min = in->y_domain_min,
                                        .domain_max = in->y_domain_max},
                                  .series_count = n,
                                  .series = out,
                                  .legend = legend_of(in)};
    }
    RenderPlot r = {.rows = plot->rows, .cols = plot->cols, .panels = panels, .title = plot->title};
    plot_print(plot, plot->cols, &r);
    RenderMeta meta = {.scene = plot->scene ? plot->scene : "",
                       .seed = plot->seed,
                       .comment = renderer_comment(context)};
    int rc = render_plot_write(&r, &meta, path, err, err_size) == 0 ? 0 : -1;
    if (rc == 0)
        app_output_note(path);
    if (rc == 0 && !plot->data_beside && plot_data_write(plot, path) != 0) {
        snprintf(err, err_size, "cannot write the data of %s", path);
        rc = -1;
    }
    /* render.plot_format = "pdf" or "svg": the same plot beside the PNG in that format */
    char other[4096];
    if (rc == 0 && beside_path(path, plot->print ? plot->print->plot_format : -1, other)) {
        rc = render_plot_write(&r, &meta, other, err, err_size) == 0 ? 0 : -1;
        if (rc == 0)
            app_output_note(other);
    }
    free(series);
    return rc;
}

/* Heat maps (the species maps, 004 fig. 3.4) on their cells, viridis, range from the data. */
static int hook_map(void *context, const Scene *scene, const AppMap *map, const char *path,
                    char *err, size_t err_size)
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
                   .bar_label = map->bar_label,
                   .arrow_x = map->arrow_x,
                   .arrow_y = map->arrow_y,
                   .arrow_unit = map->arrow_unit};
    RenderMeta meta = {.scene = scene ? scene->name : "",
                       .seed = scene ? scene->seed : 0,
                       .comment = renderer_comment(context)};
    if (render_map_write(&r, &meta, path, err, err_size) != 0)
        return -1;
    app_output_note(path);
    return 0;
}

const AppRender *app_render_glue(void)
{
    static Renderer renderer = {.quiet = 1};
    static const AppRender render = {
        .context = &renderer,
        .movie_open = hook_movie_open,
        .movie_close = hook_movie_close,
        .movie_encode_left = hook_movie_encode_left,
        .figure = hook_figure,
        .plot = hook_plot,
        .map = hook_map,
        .provenance = hook_provenance,
        .reduced_units = hook_reduced_units,
        .threads = hook_threads,
    };
    return &render;
}
