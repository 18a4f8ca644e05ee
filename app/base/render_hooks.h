/* SPDX-License-Identifier: MIT */
/* render_hooks.h: what the app layer asks of a renderer, as plain data (types only). The runner,
 * the experiment families and their multi-run drivers describe movies, figures, plots and maps
 * with these types; app/cli/render_glue.c (the one app file that sees render/) fills an AppRender
 * with render/ calls. A NULL AppRender, or a NULL hook in it, means "not built": the caller skips
 * that output.
 *
 *     AppPlotSeries s = {.label = "q*", .count = n, .x = theta, .y = q, .line = 1};
 *     AppPlotPanel p = {.x_label = "Shields", .y_label = "q*", .series_count = 1, .series = &s};
 *     AppPlot plot = {.title = "flux", .panel_count = 1, .panels = &p};
 *     if (render && render->plot) render->plot(render->context, &plot, "flux.png", err, size);
 */
#ifndef APP_RENDER_HOOKS_H
#define APP_RENDER_HOOKS_H

#include "sim/sim.h"

#include <stddef.h>
#include <stdint.h>

struct Scene;
struct SceneStyle;
struct SceneFigure;

/// Marker shapes; the values of RenderMarker (render_glue.c asserts it).
typedef enum AppMarker {
    APP_MARKER_NONE = 0,
    APP_MARKER_CIRCLE = 1,
    APP_MARKER_SQUARE = 2,
    APP_MARKER_TRIANGLE = 3,
    APP_MARKER_CROSS = 4,
} AppMarker;

/// Where a panel's legend goes. AUTO: where it hides the fewest data (matplotlib's "best") when
/// the panel has more than one series; OUTSIDE: right of the axes.
typedef enum AppLegend {
    APP_LEGEND_AUTO = 0,
    APP_LEGEND_NONE = 1,
    APP_LEGEND_UPPER_RIGHT = 2,
    APP_LEGEND_UPPER_LEFT = 3,
    APP_LEGEND_OUTSIDE = 4,
} AppLegend;

/// Colour of a series: automatic (the next of the palette), or the previous series' colour (a
/// fit drawn with its data); any other value is 0xRRGGBB.
#define APP_RGB_AUTO     (-1L)
#define APP_RGB_PREVIOUS (-2L)

/// Text of plots (titles, axis labels, legends) is markup (docs/figures.md#markup): E^*_{kin},
/// \sigma_{yy}, \phi, \rho_I/\rho.
typedef struct AppPlotSeries {
    const char *label; ///< legend text, NULL = none
    int count;
    const double *x, *y, *y_err; ///< y_err may be NULL
    int line, dashed;            ///< 1 = on
    AppMarker marker;
    long rgb; ///< APP_RGB_AUTO (use 0 only for black: designated initialisers set rgb explicitly)
} AppPlotSeries;

typedef struct AppPlotPanel {
    const char *title, *x_label, *y_label; ///< NULL = none
    int x_log, y_log;                      ///< 1: base-10 logarithmic axis
    AppLegend legend;
    /// Axis ranges; min >= max: from the data plus a 5 % margin.
    double x_min, x_max, y_min, y_max;
    /// Physical domains (a box's width) that automatic ranges never leave; min >= max: none.
    double x_domain_min, x_domain_max, y_domain_min, y_domain_max;
    int series_count;
    const AppPlotSeries *series;
} AppPlotPanel;

/// One figure of panels on a rows x cols grid (row-major). Its print size (docs/figures.md#plots):
/// the `size`, `size_unit`, `dpi`, `font_size` and `style` of `print` (the scene's `render` keys)
/// when set; else one column (8.5 cm; 17.8 cm for several columns of panels) wide at 300 dpi,
/// width:height as width and height say.
typedef struct AppPlot {
    const char *title; ///< NULL = none
    int width, height; ///< aspect ratio only; 0 = 1000 x 700
    int rows, cols;    ///< 0 = 1 x panel_count
    double font_size;  ///< points at print size; 0 = `print`'s, else the renderer's default
    int panel_count;
    const AppPlotPanel *panels;
    const char *scene; ///< PNG metadata (NULL = "")
    uint64_t seed;
    const struct SceneStyle *print; ///< print keys (size, dpi, font_size, style); NULL = none
    /// 0: the renderer writes the plot's data beside it (the path with .csv,
    /// docs/figures.md#plot-data); 1: the caller writes that file itself (its own columns, with
    /// units in its header).
    int data_beside;
} AppPlot;

/// A heat map on square cells: values row-major, index j * nx + i, row 0 at the bottom; NaN =
/// empty cell.
typedef struct AppMap {
    const char *title, *x_label, *y_label, *bar_label;
    int nx, ny;
    double x0, y0, cell; ///< lower-left corner of cell (0, 0) and side
    const double *values;
    /// Arrows on the cells' centres (NULL = none) with a reference arrow labelled in arrow_unit.
    const double *arrow_x, *arrow_y;
    const char *arrow_unit;
} AppMap;

/// What an experiment adds to a grain figure. Zero-initialised: nothing.
typedef struct AppFigureExtras {
    const char *title; ///< replaces the style's title when not NULL
    /// Per-grain marks in frame order (1 marked, -1 not; NULL = none): drawn highlighted with a
    /// zoomed inset and the force chains through them (thesis 004 arches).
    const int *marks;
    /// Profile panels drawn beside the grains on the same heights (PNG only): each series is x(y)
    /// and is clipped to the figure's vertical range; an x range left unset runs from 0 to 1.05
    /// max |x| of the clipped data (1 when that is 0).
    const AppPlotPanel *side_panels;
    int side_panel_count;
    /// A velocity field on its own grid nodes, drawn as arrows on the nodes with a reference
    /// arrow (m/s): node (i, j) at (field_x0 + (i + 1/2) field_cell, field_y0 + (j + 1/2)
    /// field_cell), row-major j * field_nx + i; non-finite = no arrow. NULL = none.
    const double *field_vx, *field_vy;
    int field_nx, field_ny;
    double field_x0, field_y0, field_cell; ///< m
} AppFigureExtras;

/// The renderer's services. Each returns 0, or -1 with a message in err.
typedef struct AppRender {
    void *context;
    /// Opens the movie of one stage at `path` and fills `sink` with its frame consumer.
    int (*movie_open)(void *context, const struct Scene *scene, int stage, const char *path,
                      SimFrameSink *sink, char *err, size_t err_size);
    /// Seconds of encoding the open movie still owes once `frames_to_come` more frames are given
    /// (0 when none is open); the runner's ETA counts it. NULL = not known.
    double (*movie_encode_left)(void *context, long frames_to_come);
    /// Finishes the movie opened last (flush, rename). Called once per successful open.
    int (*movie_close)(void *context, char *err, size_t err_size);
    /// Writes one grain figure of a frame to `path` (format from the extension); extras may be
    /// NULL.
    int (*figure)(void *context, const struct Scene *scene, const struct SceneFigure *figure,
                  const SimFrame *frame, const AppFigureExtras *extras, const char *path, char *err,
                  size_t err_size);
    /// Draws and writes a plot (format from the extension).
    int (*plot)(void *context, const AppPlot *plot, const char *path, char *err, size_t err_size);
    /// Draws and writes a heat map; `scene` gives the PNG metadata (may be NULL).
    int (*map)(void *context, const struct Scene *scene, const AppMap *map, const char *path,
               char *err, size_t err_size);
    /// Sets the provenance line (command, scene SHA-256, revision, date) that every figure
    /// written from now on carries as its PNG Comment text chunk; NULL or "" for none.
    void (*provenance)(void *context, const char *comment);
    /// Reduced units (units = "reduced"): the scales that force and speed colour bars are drawn
    /// in from now on, m g in N and sqrt(g d) in m/s (0, 0: SI). NULL = not drawn in them.
    void (*reduced_units)(void *context, double force_unit, double speed_unit);
    /// The run's thread count (`--threads N`; 0 = auto, the CPUs of the affinity mask): the
    /// movies opened from now on draw their frames within it (one band on one thread). NULL =
    /// the CPUs of the affinity mask.
    void (*threads)(void *context, int threads);
} AppRender;

#endif
