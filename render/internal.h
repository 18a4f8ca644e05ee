/* SPDX-License-Identifier: MIT */
/* internal.h: render/'s private header, included by the render/ sources and render's own tests
 * (tests/render) and benchmarks, never installed. render.h is the public API (what app/, python/
 * and examples/ call); this adds the helpers the back ends share: the frame layout of
 * render_layout.c that the Cairo drawer (render_cairo.c) and the GL drawer (render_gl.c) both
 * follow, the colour and force-chain helpers of render_colormap.c, the velocity field, the plots'
 * layout record, the GL drawer and the temporary-file writes. Cairo-only helpers are in
 * render_cairo_util.h. */
#ifndef RENDER_INTERNAL_H
#define RENDER_INTERNAL_H

#include "render/render.h"
#include "sim/sim.h"

#include <stddef.h>
#include <stdint.h>

/* ---- the frame layout (render_layout.c), followed by both drawers ---- */

/// 1 when grain i of the frame is fixed (a wall or base grain).
int render_grain_fixed(const SimFrame *frame, int i);
/// What the style's colour bar is: 0 none, 1 a continuous bar (force, speed), 2 a categorical
/// species legend.
int render_colorbar_kind(const RenderStyle *style);
/// Metres per axis unit: the mean diameter d in reduced units, else 1.
double render_axis_unit(const RenderStyle *style, double d);
/// Highest species index among mobile grains (the species legend's last entry), at most 15.
int render_legend_top(const SimFrame *frame);
/// The species legend's text of species k: its name in the style, else "species k".
void render_species_label(const RenderStyle *style, int k, char *buf, size_t size);
/// Room under the plot for the axes' tick labels and axis label, pixels (0 without axes).
double render_axes_room(const RenderStyle *style, double font_size);
/// World (m) to pixel coordinates.
void render_view_to_pixel(const RenderView *view, double x, double y, double *px, double *py);

/* ---- labels (render_cairo.c) and colours (render_colormap.c) ---- */

/// The time stamp's text (style->time_stamp): "t = 0.1200 s    t* = 3.46" (t* with the frame's
/// time_scale), or with style->reduced_units "t = 3.46 √(d/g)" (UTF-8). Returns buf.
const char *render_time_label(const SimFrame *frame, const RenderStyle *style, char *buf,
                              size_t size);
/// The scale bar's text for a bar of `diameters` mean diameters of d metres: "5 d   (d = 2 mm)",
/// or with style->reduced_units "5 d". Returns buf.
const char *render_scale_label(double diameters, double d, const RenderStyle *style, char *buf,
                               size_t size);
/// 256-entry colour table of a map (the single source of colours: drawers look up, never compute).
void render_colormap_lut(RenderColormap map, uint8_t lut[256][3]);
/// Colour of t in [0, 1] (clamped; NaN = 0) as 0xRRGGBB: LUT entry round(255 t).
uint32_t render_colormap_rgb(RenderColormap map, double t);
/// Categorical colour of a species (colour-blind-safe palette, cycles after 8), 0xRRGGBB.
uint32_t render_species_rgb(int species);
/// Colour range of the style's quantity: the fixed range when range_min < range_max, else
/// [0, max over the frame's mobile grains] (1 when that is 0).
void render_color_range(const SimFrame *frame, const RenderStyle *style, double *lo, double *hi);

/* ---- the drawing helper (render_helper.c): a second thread for the lower band of a movie
 * frame, in both drawers ---- */

/// A thread that runs one job at a time for the thread that created it.
typedef struct RenderHelper RenderHelper;
typedef void RenderJobFn(void *context);
/// Starts the thread; NULL when the system gives none (the caller then draws alone).
RenderHelper *render_helper_create(void);
/// Gives the thread `job(context)`; the caller goes on and later waits (one job at a time).
void render_helper_start(RenderHelper *helper, RenderJobFn *job, void *context);
/// Returns once the job given last has finished (at once when none is running).
void render_helper_wait(RenderHelper *helper);
/// Waits for the job running, stops the thread and frees it; NULL is a no-op.
void render_helper_destroy(RenderHelper *helper);
/// How many bands a movie frame of `height` rows is drawn in: 2 (the lower one in a helper
/// thread) when `threads` is 2 or more (0: the CPUs of the affinity mask, sim_cpu_count) and the
/// frame has 128 rows or more, else 1; the environment variable SABLIER_BANDS=1 or 2 chooses
/// (tests and A/B timing). The pixels are the same either way.
int render_band_count(int height, int threads);

/* ---- opaque disks straight into an image's pixels (render_disks.c) ---- */

/// Premultiplied 32-bit pixels (Cairo's ARGB32 or RGB24) and where user coordinates land in them:
/// device = user + offset, whole pixels.
typedef struct RenderDiskTarget {
    uint8_t *data;
    int width, height, stride;
    int offset_x, offset_y;
} RenderDiskTarget;

/// Fills the disk of centre (cx, cy) and radius r (user pixels) with the opaque colour 0xRRGGBB
/// over the target, antialiased by its exact coverage of each pixel along 16 sub-rows (Cairo's
/// OVER in 8 bits; positions in 1/256 pixel, as Cairo's), clipped to the target's pixels only: the
/// caller keeps Cairo for a disk that a clip cuts.
void render_disk_fill(const RenderDiskTarget *t, double cx, double cy, double r, uint32_t rgb);
/// Fills the capsule of the segment from (px, py) to (qx, qy) with radius r (a line of width 2 r
/// with round caps, as Cairo strokes it) in the same way.
void render_capsule_fill(const RenderDiskTarget *t, double px, double py, double qx, double qy,
                         double r, uint32_t rgb);

/* ---- the Cairo drawer and the annotations (render_cairo.c) ---- */

/// render_cairo_draw with the rows from render_cairo_split_row on drawn by `helper`
/// (render_helper.c) while the calling thread draws those above: the same pixels as
/// render_cairo_draw (each band is the whole scene on a surface over its rows, moved by whole
/// pixels), in about half the time on two cores. NULL helper: drawn in one band by the calling
/// thread.
/// The first row of the lower band: the row that halves the grains' drawing cost (each grain
/// weighs r^2 + 1, r its radius in pixels, at its centre's row), so that neither band waits on
/// the other when the grains fill part of the image; in [1, height - 1], the middle when no grain
/// is in view. `view` is the frame's fitted view (render_view_fit).
int render_cairo_split_row(const SimFrame *frame, const RenderView *view, int height);
int render_cairo_draw_split(const SimFrame *frame, const RenderStyle *style, RenderImage *out,
                            RenderHelper *helper);
/// Draws the annotations of render_cairo_draw (velocity field and arrows, arch highlights and
/// inset, time stamp, scale bar, colour bar, title: whatever the style asks for) over an image
/// that already holds the grain layer of the same frame and style (e.g. an OSMesa frame), with
/// the same layout (render_view_fit). The image is opaque, style->width x style->height, BGRA
/// (premultiplied) or RGBA, and keeps its format. 0 on success, -1 on bad input or failure.
int render_cairo_overlay(const SimFrame *frame, const RenderStyle *style, RenderImage *inout);

/* ---- colours and force chains (render_colormap.c) ---- */

/// The colour bar's end triangles for this frame: style->color_extend plus the ends that the
/// frame's mobile grains leave [lo, hi] by (RENDER_EXTEND_* bits).
int render_color_extend(const SimFrame *frame, const RenderStyle *style, double lo, double hi);
/// The style's quantity for grain i (force N, speed m/s, species, height band index).
double render_grain_value(const SimFrame *frame, const RenderStyle *style, int i);
/// Fill colour of grain i, 0xRRGGBB (fixed grains get style->fixed_rgb).
uint32_t render_grain_rgb(const SimFrame *frame, const RenderStyle *style, int i, double lo,
                          double hi);
/// Force-chain selection: returns the normal force above which a contact is drawn
/// (chain_threshold * mean F_n over contacts with F_n > 0) and sets *f_max to the force drawn at
/// full width (style->chain_force_max, or the frame's largest F_n).
double render_chain_cut(const SimFrame *frame, const RenderStyle *style, double *f_max);

/* ---- coarse-grained velocity field (render_field.c) ---- */

typedef struct RenderFieldDef {
    double x0, y0, x1, y1; ///< region, m; nodes at cell centres, x0 + (i + 1/2) cell
    double cell;           ///< node spacing, m
    double width;          ///< kernel cutoff radius, m
    RenderKernel kernel;
    int mass_power; ///< grain mass taken proportional to r^mass_power (2 disk, 3 sphere)
} RenderFieldDef;

/// Fields on a node grid, row-major, index j * nx + i, node (i, j) at (x0 + (i + 1/2) cell,
/// y0 + (j + 1/2) cell).
typedef struct RenderField {
    int nx, ny;
    double x0, y0, cell; ///< m
    double *vx, *vy; ///< momentum-weighted mean velocity sum m v W / sum m W, m/s (0 where empty)
    double *packing; ///< solid fraction sum pi r^2 W (kernel normalised over the plane)
} RenderField;

/// Coarse-grained velocity (MercuryCG: V = j / rho, j = sum m_i v_i W, rho = sum m_i W) over
/// mobile grains; periodic frames wrap in x. 0 on success, -1 on bad definition or no memory.
int render_velocity_field(const SimFrame *frame, const RenderFieldDef *def, RenderField *out);
void render_field_free(RenderField *field);
/// Kernel value W(r) for a cutoff radius `width`, normalised so its integral over the plane is 1.
double render_kernel(RenderKernel kernel, double r, double width);

/* ---- plots (render_plot.c) and heat maps (render_map.c) ---- */

/// What a text box of a plot holds (render_plot_layout).
typedef enum RenderPlotText {
    RENDER_TEXT_TITLE = 0,       ///< the figure's title
    RENDER_TEXT_PANEL_TITLE = 1, ///< a panel's title ("(a) kinetic")
    RENDER_TEXT_X_TICK = 2,
    RENDER_TEXT_Y_TICK = 3,
    RENDER_TEXT_X_LABEL = 4,
    RENDER_TEXT_Y_LABEL = 5,
    RENDER_TEXT_X_OFFSET = 6, ///< the axis' common factor "x10^-3"
    RENDER_TEXT_Y_OFFSET = 7,
    RENDER_TEXT_LEGEND = 8, ///< the legend's frame (all its entries)
} RenderPlotText;

/// A text box the layout placed: pixels, y down, x0 < x1, y0 < y1 (ink of the glyphs, advance
/// width); `text` is the string drawn (tick labels, offsets; "" for others).
typedef struct RenderPlotBox {
    double x0, y0, x1, y1;
    RenderPlotText kind;
    int panel; ///< -1 for the figure title
    char text[40];
} RenderPlotBox;

/// The layout's record of the text it placed (tick labels, axis labels, offsets, titles, legend
/// frames), as drawn by render_plot_draw: writes at most `capacity` boxes, returns how many there
/// are (or -1 on a bad plot). Nothing overlaps, and all lies inside the canvas.
int render_plot_layout(const RenderPlot *plot, RenderPlotBox *boxes, int capacity);
/// A panel's axis limits as drawn: lim = {x_lo, x_hi, y_lo, y_hi}. 0, or -1 on a bad plot or panel.
int render_plot_limits(const RenderPlot *plot, int panel, double lim[4]);
/// Nice axis ticks (1, 2, 2.5, 5 x 10^k steps; decades on a log axis) covering [lo, hi] with at
/// most about `target` intervals; writes at most `capacity` values inside [lo, hi], returns how
/// many.
int render_axis_ticks(double lo, double hi, int log, int target, double *ticks, int capacity);
/// Widens [*lo, *hi] outward to tick multiples (linear) or whole decades (log).
void render_axis_nice_range(double *lo, double *hi, int log, int target);
/// Pixel position of data point (x, y) in the map as drawn. 0, or -1 on a bad map.
int render_map_pixel(const RenderMap *map, double x, double y, double *px, double *py);

/* ---- image diff (render_diff.c) ---- */

/// One JSON line (no newline) describing a comparison, e.g. {"verdict":"differ",
/// "differing_pixels":22,...}. Returns the length snprintf would write.
int render_diff_result_json(const RenderDiffResult *result, char *buf, size_t size);
/// Compares two images in memory (any formats, same size required); same metric as
/// render_diff_files. diff (optional) receives a new RGBA image.
int render_diff_images(const RenderImage *a, const RenderImage *b, const RenderDiffOptions *options,
                       RenderImage *diff, RenderDiffResult *result, char *err, size_t err_size);

/* ---- figures and images written to PATH.tmp and renamed when complete (render_file.c), so a
 * failed write never leaves a half-written PATH or a stray PATH.tmp; a file name's format; the
 * error messages ---- */

/// PATH.tmp in a new buffer, made anew as an empty regular file (sim_open_output: PATH refused
/// unless it is a regular file or absent), or NULL with "PATH: reason" in err.
char *render_tmp_name(const char *path, char *err, size_t err_size);
/// Finishes a write through `tmp` (from render_tmp_name, freed here): `ok` renames it to PATH,
/// else it is removed (the caller has written the message). A failed rename removes it too and
/// writes "TMP: cannot rename to PATH: reason" in err. 0, or -1.
int render_tmp_commit(char *tmp, const char *path, int ok, char *err, size_t err_size);
/// 1 when path ends in "." ext (ext without its dot, compared without case), else 0.
int render_has_extension(const char *path, const char *ext);
/// printf-style message into err[size] (nothing when err is NULL or size 0).
void render_set_err(char *err, size_t size, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* ---- the GL movie drawer (render_gl.c): the grain layer of a frame (background, walls, force
 * chains, disks with outlines and orientation ticks) as shader-drawn disks on llvmpipe through
 * OSMesa; the annotations go on top with render_cairo_overlay. Images are BGRA (Cairo's ARGB32
 * byte order), so the overlay draws on them in place. The GL context lives in one struct in
 * render_gl.c so that an EGL surfaceless back end can replace OSMesa (gone in Mesa >= 25.1) ---- */

/// A persistent GL drawer of one size (contexts, shaders, buffers); one per thread. It draws the
/// lower half of each image in a helper thread of its own (render_band_count: two CPUs or more;
/// SABLIER_BANDS=1 keeps all drawing in the calling thread, =2 forces the helper).
typedef struct RenderGl RenderGl;

/// Creates a drawer for width x height pixels, in two bands on two CPUs or more of the affinity
/// mask (render_band_count(height, 0); not the run's --threads: its bands agree with one band
/// only up to the rounding of the segment quads' vertices, and a movie's bytes must not depend
/// on --threads). NULL on failure with a message in err.
RenderGl *render_gl_create(int width, int height, char *err, size_t err_size);
void render_gl_destroy(RenderGl *gl);
/// Draws one frame (style->width/height must equal the drawer's size). On success *out views the
/// drawer's own BGRA buffer (RENDER_PIXEL_BGRA_PREMUL, rows top-down, opaque), valid until the
/// next draw or destroy. 0 on success, else -1 and a message in err.
int render_gl_frame(RenderGl *gl, const SimFrame *frame, const RenderStyle *style, RenderImage *out,
                    char *err, size_t err_size);
/// Draws one frame into the caller's image (the drawer's size, stride 4 * width; its format is
/// set to RENDER_PIXEL_BGRA_PREMUL): no copy, so a movie draws straight into its frame queue.
int render_gl_frame_to(RenderGl *gl, const SimFrame *frame, const RenderStyle *style,
                       RenderImage *target, char *err, size_t err_size);
/// GL_RENDERER of the drawer's context, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
const char *render_gl_renderer(const RenderGl *gl);
/// One-shot drawing with the same signature as render_cairo_draw: a new BGRA image the caller
/// frees with render_image_free. 0 on success. Slow per call (creates a context): for movies keep
/// a RenderGl.
int render_gl_draw(const SimFrame *frame, const RenderStyle *style, RenderImage *out);

#endif
