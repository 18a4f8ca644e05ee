/* SPDX-License-Identifier: MIT */
/* render.h: sablier's renderer, the public API of render/. Reads sim's frame view (sim/sim.h),
 * never the other way. Figures through Cairo (PNG via libpng, PDF, SVG); movie frames through
 * OSMesa or Cairo; MP4 through libavcodec; an image diff for CI. Installed: it declares what
 * programs outside render/ call; the helpers the back ends share are in render/internal.h.
 *
 *     RenderStyle style = render_style_default();
 *     style.color_by = RENDER_COLOR_FORCE;
 *     RenderMeta meta = {.scene = "crater", .seed = 1};
 *     render_figure_write(&frame, &style, &meta, "fig.png", err, sizeof err);
 */
#ifndef RENDER_H
#define RENDER_H

#include "render/render_image.h"
#include "render/render_style.h"
#include "sim/sim.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/// Provenance written into PNG text chunks and PDF/SVG metadata.
typedef struct RenderMeta {
    const char *scene; ///< scene name
    uint64_t seed;
    const char *comment; ///< free text (e.g. the command line); NULL = none
} RenderMeta;

/* ---- figures (Cairo; owned by render_cairo.c, render_png.c) ---- */

/// Draws one frame into a new BGRA image with Cairo (caller frees with render_image_free).
int render_cairo_draw(const SimFrame *frame, const RenderStyle *style, RenderImage *out);
/// Writes a figure of one frame; format from the extension: .png (libpng, with text chunks),
/// .pdf, .svg. Written to a temporary name, renamed when complete. 0 on success, else -1 and a
/// message in err.
int render_figure_write(const SimFrame *frame, const RenderStyle *style, const RenderMeta *meta,
                        const char *path, char *err, size_t err_size);
/// Writes an image as PNG through libpng with provenance text chunks (key/value pairs, NULL ended).
int render_png_write(const RenderImage *image, const char *path, const char *const *text, char *err,
                     size_t err_size);
/// Reads a PNG into an RGBA image; 0 on success.
int render_png_read(const char *path, RenderImage *out, char *err, size_t err_size);

/* ---- figures read back as pixels (owned by render_raster.c) ---- */

/// The resolution at which render_figure_read draws a PDF or SVG (dots per inch).
#define RENDER_RASTER_DPI 150.0
/// Reads a figure as pixels: a PNG as it is; the first page of a PDF (poppler-glib) or an SVG
/// (librsvg) drawn on white at `dpi` (0: RENDER_RASTER_DPI). 0 on success; 1 when this build
/// cannot draw that format (built without poppler-glib and librsvg; message in err); -1 when the
/// file cannot be read (message in err). The caller frees the image with render_image_free.
int render_figure_read(const char *path, double dpi, RenderImage *out, char *err, size_t err_size);
/// 1 when render_figure_read can draw a file of this name's format (.png; .pdf and .svg in a
/// build with poppler-glib and librsvg), else 0.
int render_figure_readable(const char *path);

/* ---- a frame's layout (render_layout.c, followed by the Cairo and OSMesa drawers) and colour
 * range (render_colormap.c) ---- */

/// Where the world lands on the canvas. Pixel coordinates have their origin at the top-left
/// corner, y down; world y is up.
typedef struct RenderView {
    double scale;              ///< pixels per metre
    double center_x, center_y; ///< world point at the centre of the plot rectangle, m
    double plot_x, plot_y;     ///< plot rectangle (grains are clipped to it), pixels
    double plot_w, plot_h;
    double font_size;     ///< pixels
    double mean_diameter; ///< of mobile grains (all grains if none), m
} RenderView;

/// Lays out a frame: plot rectangle (room for title and colour bar) and world window.
void render_view_fit(const SimFrame *frame, const RenderStyle *style, RenderView *view);
/// The image height at which the style's window, at style->width, fills the width exactly
/// with the style's margins (for movies sized to their view).
int render_fit_height(const SimFrame *frame, const RenderStyle *style);
/// Fixes a movie's or figure series' colour range for all its frames (docs/figures.md, "One colour
/// scale per series"): a declared range (range_min < range_max) is kept; else, at the first frame
/// whose mobile grains have a value above 0, [0, max] widened by a quarter for headroom and rounded
/// up to a round number (render_axis_nice_range). Sets RENDER_EXTEND_MAX (and RENDER_EXTEND_MIN for
/// a declared range above 0) so the colour bar shows the saturation on every frame. Returns 1
/// once the range is fixed (always for quantities without a colour bar), 0 while the frames
/// seen so far were all 0: call again with the next frame.
int render_color_lock(const SimFrame *frame, RenderStyle *style);
/// Copy of a style with its automatic values resolved for this frame (band_height 0 = 5 mean
/// diameters, chain_width_max 0 = half a mean diameter in pixels, font_size). Drawers call this
/// once per frame; the per-grain helpers below are then O(1).
RenderStyle render_style_resolve(const SimFrame *frame, const RenderStyle *style);

/* ---- plots (render_plot.c): line and scatter plots in multi-panel layouts ---- */

typedef enum RenderMarker {
    RENDER_MARKER_NONE = 0,
    RENDER_MARKER_CIRCLE = 1,
    RENDER_MARKER_SQUARE = 2,
    RENDER_MARKER_TRIANGLE = 3,
    RENDER_MARKER_CROSS = 4,
} RenderMarker;

/// RenderSeries.rgb value meaning "next colour of the panel's palette".
#define RENDER_RGB_AUTO     0xffffffffu
#define RENDER_RGB_PREVIOUS 0xfffffffeu /* the colour of the series before (a fit and its data) */

typedef struct RenderSeries {
    const char *label; ///< legend text; NULL = not in the legend
    int count;
    const double *x, *y; ///< data; non-finite points (and <= 0 on a log axis) break the line
    const double *y_err; ///< symmetric error bars; NULL = none
    uint32_t rgb;        ///< 0xRRGGBB, RENDER_RGB_AUTO or RENDER_RGB_PREVIOUS
    int line;            ///< 1: join points with a line
    int dashed;          ///< 1: dashed line
    RenderMarker marker;
    double line_width;  ///< pixels (0 = font size / 8)
    double marker_size; ///< diameter, pixels (0 = font size / 2)
} RenderSeries;

typedef struct RenderAxis {
    const char *label; ///< markup (render_markup_draw), e.g. "t^* = t / \sqrt{d/g}"; NULL = none
    int log;           ///< 1: base-10 logarithmic
    double min, max;   ///< min >= max = from the data plus a 5 % margin
    /// The physical domain of the quantity (a box's width): automatic limits never leave it.
    /// domain_min >= domain_max = none.
    double domain_min, domain_max;
} RenderAxis;

typedef enum RenderLegend {
    RENDER_LEGEND_NONE = 0,
    RENDER_LEGEND_UPPER_RIGHT = 1,
    RENDER_LEGEND_UPPER_LEFT = 2,
    RENDER_LEGEND_LOWER_LEFT = 3,
    RENDER_LEGEND_LOWER_RIGHT = 4,
    RENDER_LEGEND_BEST = 5,    ///< inside, where it covers the fewest data (matplotlib's "best")
    RENDER_LEGEND_OUTSIDE = 6, ///< right of the axes, outside them
} RenderLegend;

typedef struct RenderPanel {
    const char *title; ///< NULL = none; e.g. "(a) kinetic"
    RenderAxis x, y;
    int series_count;
    const RenderSeries *series;
    RenderLegend legend;
} RenderPanel;

typedef struct RenderPlot {
    int width, height;         ///< pixels
    int rows, cols;            ///< panel grid (0 = 1)
    const RenderPanel *panels; ///< rows * cols panels, row-major
    const char *title;         ///< figure title (markup); NULL = none
    double font_size;          ///< pixels (0 = RENDER_PLOT_FONT_PT points at dpi)
    double dpi;                ///< pixels per inch of the written file (0 = 96)
} RenderPlot;

/// Default plot font size, points at the plot's print size (width / dpi).
#define RENDER_PLOT_FONT_PT 9.0
/// Smallest text of a plot, points at print size (sub- and superscripts are not set smaller).
#define RENDER_TEXT_MIN_PT  6.0

/// Draws a plot into a new BGRA image (white background). 0, or -1 with a message in err.
int render_plot_draw(const RenderPlot *plot, RenderImage *out, char *err, size_t err_size);
/// Writes a plot: .png (libpng, text chunks), .pdf or .svg; temporary name then rename.
int render_plot_write(const RenderPlot *plot, const RenderMeta *meta, const char *path, char *err,
                      size_t err_size);
/// Writes a grain figure with a plot beside it (the sediment bed's profile panels) as one .pdf or
/// .svg page, vector and text kept as text: the grains at `style`'s size on the left, the plot
/// (its width x height) right of them with its rows moved down by `shift` pixels (a negative
/// shift moves the grains down instead), white elsewhere, at `style->dpi`. The page is the PNG
/// composite's size. 0 on success, else -1 and a message in err.
int render_figure_beside_write(const SimFrame *frame, const RenderStyle *style,
                               const RenderMeta *meta, const RenderPlot *plot, int shift,
                               const char *path, char *err, size_t err_size);
/// Pixel position of data point (x, y) in a panel, as drawn. 0, or -1 if outside the axes'
/// domain (e.g. x <= 0 on a log axis).
int render_plot_map(const RenderPlot *plot, int panel, double x, double y, double *px, double *py);

/* ---- heat maps on square cells (render_map.c; 004 fig. 3.4) ---- */

typedef struct RenderMap {
    int width, height;    ///< pixels
    int nx, ny;           ///< cells; values row-major, index j * nx + i, row j = 0 at the bottom
    double x0, y0, cell;  ///< lower-left corner of cell (0, 0) and cell side, data units
    const double *values; ///< non-finite = empty cell, drawn white
    double min, max;      ///< colour range; min >= max = from the data, widened to nice numbers
    RenderColormap colormap;
    const char *title, *x_label, *y_label, *bar_label; ///< NULL = none
    double font_size; ///< pixels (0 = RENDER_FIGURE_FONT_PT points at 96 dpi)
    /// Optional arrow field on the cells' centres (same indexing; NULL = none, non-finite = no
    /// arrow): the longest arrow spans 0.9 cell, and a reference arrow under the colour bar is
    /// labelled with its value (a round number) and `arrow_unit`.
    const double *arrow_x, *arrow_y;
    const char *arrow_unit;
} RenderMap;

/// Writes a heat map (cells at equal aspect ratio, axes, colour bar): .png (libpng, text chunks),
/// .pdf or .svg; temporary name then rename. The pixel at a cell's centre is exactly
/// render_colormap_rgb of its value in the range. 0, or -1 with a message in err.
int render_map_write(const RenderMap *map, const RenderMeta *meta, const char *path, char *err,
                     size_t err_size);

/* ---- movies (owned by render_video.c; drawer OSMesa or Cairo) ---- */

typedef enum RenderDrawer {
    RENDER_DRAWER_CAIRO = 0,
    RENDER_DRAWER_OSMESA = 1,
} RenderDrawer;

/// libx264 preset of movies: the fastest giving H.264 High profile (render_video.c).
#define RENDER_MOVIE_PRESET  "superfast"
/// Encoder threads of every movie, fixed so that a movie's bytes do not depend on the machine.
#define RENDER_MOVIE_THREADS 4
/// The highest movie frame rate the encoder takes, frames/s.
#define RENDER_VIDEO_MAX_FPS 1000.0

typedef struct RenderMovieDef {
    const char *path; ///< .mp4
    RenderDrawer drawer;
    double fps; ///< frames per second of video, in (0, RENDER_VIDEO_MAX_FPS]
    int crf;    ///< quality (libx264 CRF, default 20)
    int quiet;  ///< 1: no progress on stderr
    RenderMeta meta;
    /* Added by the movie side (render_video.c); zero keeps the default. */
    long frames_expected; ///< frames the run will give, for the progress ETA (0 = unknown)
    const char *preset;   ///< libx264 preset, NULL = RENDER_MOVIE_PRESET
    const char *encoder;  ///< libavcodec encoder; NULL = "libx264" ("mpeg4" + warning if absent)
    /// Threads the Cairo drawer's frames may use: 1 draws each frame on the calling thread alone,
    /// 2 or more in two bands (the lower one on a helper thread; the same pixels either way); 0 =
    /// the CPUs of the affinity mask (sim_cpu_count). The OSMesa drawer's bands follow the
    /// affinity mask alone (they agree with one band only up to rounding, and a movie's bytes
    /// must not depend on the run's threads); the encoder keeps RENDER_MOVIE_THREADS whatever
    /// this is (x264's bytes depend on its thread count).
    int threads;
} RenderMovieDef;

typedef struct RenderMovie RenderMovie;

/// Opens a movie (encoder, muxer, drawer). NULL on failure with a message in err.
RenderMovie *render_movie_open(const RenderMovieDef *def, const RenderStyle *style, char *err,
                               size_t err_size);
/// Draws and encodes one frame (OSMesa: the grain layer by GL, the style's annotations by
/// Cairo over it). Errors are sticky: returned again by render_movie_close.
int render_movie_frame(RenderMovie *movie, const SimFrame *frame);
/// Flushes the encoder, writes the trailer, renames the temporary file. 0 on success.
int render_movie_close(RenderMovie *movie, char *err, size_t err_size);
/// Encoding time still owed, s: the frames queued, `frames_to_come` more and the ~1 s of frames
/// the encoder holds until the flush at close, at the mean encoding time per frame so far (0
/// before the first frame is encoded). Progress ETAs add it.
double render_movie_encode_left(RenderMovie *movie, long frames_to_come);
/// A SimFrameSink that feeds render_movie_frame.
SimFrameSink render_movie_sink(RenderMovie *movie);

/* ---- image diff (owned by render_diff.c) ---- */

typedef struct RenderDiffOptions {
    int channel_threshold; ///< a pixel differs when a channel differs by more than this (0-255)
    int shift_tolerance;   ///< pixels; a difference matched within this shift is ignored (1)
    long max_pixels;       ///< images match when at most this many pixels differ (0)
} RenderDiffOptions;

typedef struct RenderDiffResult {
    long differing_pixels; ///< after the shift test
    long raw_pixels;       ///< before the shift test
    int max_channel_diff;
    double rms;
    int width, height;
    int verdict;               ///< 0 match, 1 differ, 2 bad input (the return value)
    RenderDiffOptions options; ///< the options used
} RenderDiffResult;

RenderDiffOptions render_diff_options_default(void);
/// Compares two figure files (PNG, or PDF and SVG drawn by render_figure_read) by their pixels.
/// Returns 0 match, 1 differ, 2 bad input (message in err). Writes a diff image (PNG) to
/// diff_path when not NULL.
int render_diff_files(const char *a, const char *b, const RenderDiffOptions *options,
                      const char *diff_path, RenderDiffResult *result, char *err, size_t err_size);

/// Versions of the linked libraries, e.g. "cairo 1.16.0, libpng 1.6.39, libavcodec 59.37.100".
const char *render_library_versions(void);

#ifdef __cplusplus
}
#endif

#endif
