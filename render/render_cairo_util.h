/* SPDX-License-Identifier: MIT */
/* render_cairo_util.h: Cairo helpers shared inside render/ by the frame drawer (render_cairo.c)
 * and the plots (render_plot.c): text, colours, writing a drawing to PNG, PDF or SVG. Not part
 * of the public API. */
#ifndef RENDER_CAIRO_UTIL_H
#define RENDER_CAIRO_UTIL_H

#include "render/internal.h"

#include <cairo.h>
#include <stddef.h>
#include <stdint.h>

/// Points per pixel of PDF and SVG output: 1 pixel = 1/96 inch (the CSS pixel).
#define RENDER_PT_PER_PX 0.75

/// Selects DejaVu Sans at `size` pixels, unhinted with grey antialiasing, so glyph positions
/// scale linearly and do not depend on the hinting defaults of the machine.
void render_text_font(cairo_t *cr, double size, int bold);
/// Draws text with its anchor at (x, y): halign 0 left, 0.5 centre, 1 right; valign 0 top of
/// the capitals, 0.5 middle of the capitals, 1 baseline. Returns the advance width.
double render_text_draw(cairo_t *cr, double x, double y, const char *text, double halign,
                        double valign);
/// Advance width of text in the current font, pixels.
double render_text_width(cairo_t *cr, const char *text);
/// Sets the source colour from 0xRRGGBB.
void render_set_rgb(cairo_t *cr, uint32_t rgb);
/// Formats a tick value given the tick spacing (no "-0", no trailing noise like 0.30000000004).
void render_format_tick(double value, double step, int log, char *buf, size_t size);

/// Exponent e of the common offset of tick labels (labels read value / 10^e, with "x10^e" once
/// beside the axis) when the ticks' magnitude is >= 10^4 or < 10^-2; 0 = plain labels.
int render_tick_exponent(const double *ticks, int n);
/// "\u00d710" followed by e in superscript digits (UTF-8), e.g. "x10^-5" as a label. Returns buf.
const char *render_exponent_text(int e, char *buf, size_t size);
/// Round value (1, 2 or 5 x 10^k) of a reference arrow: the largest not above `top`.
double render_arrow_reference(double top);
/// Draws one filled arrow from (x, y) by (dx, dy) pixels with the current source and line
/// width; the head is 0.3 of the length, at most head_max pixels.
void render_arrow(cairo_t *cr, double x, double y, double dx, double dy, double head_max);

/// Plot text markup (docs/figures.md#markup): x^2, x_i, x^{ab}, x_{ab} (raised or lowered at 0.7
/// size; a superscript and a subscript in a row are stacked, E^*_{kin}), \alpha...\omega and
/// \Gamma...\Omega, \sqrt, \times, \cdot, \pm, \langle, \rangle, \deg; \_ \^ \{ \} \\ literal.
/// Measures text in the current font (size `size` pixels): advance width, ink above and below the
/// baseline (both >= 0).
void render_markup_measure(cairo_t *cr, const char *text, double size, double *width, double *above,
                           double *below);
/// Draws markup anchored like render_text_draw (halign 0 left .. 1 right; valign 0 top of the
/// capitals, 0.5 middle, 1 baseline); box (optional) receives x0, y0, x1, y1 of its ink.
void render_markup_draw(cairo_t *cr, double x, double y, const char *text, double size,
                        double halign, double valign, double box[4]);

/// Sets the smallest font size of a script (pixels) for markup on this context: scripts are 0.7
/// of their base size, but not below `size` (nor above their base). The plots set
/// RENDER_TEXT_MIN_PT at their print size, so that a subscript of a small legend stays readable.
void render_markup_min_script(cairo_t *cr, double size);

typedef void (*RenderDrawFn)(cairo_t *cr, void *context);

/* Draws a valid plot (render_plot_layout >= 0) at the origin of cr on its own width x height,
 * white background included (render_plot.c). */
void render_plot_paint(cairo_t *cr, const RenderPlot *plot);

/// Draws with `draw` (in pixel units) into path: .png through libpng with text chunks
/// (key/value pairs, NULL ended), .pdf (fixed dates: byte-identical reruns) or .svg, at
/// width x height pixels. Temporary name, then rename. 0, or -1 with a message in err.
int render_cairo_write(const char *path, int width, int height, RenderDrawFn draw, void *context,
                       const char *const *text, char *err, size_t err_size);
/// render_cairo_write at `dpi` pixels per inch (0 = 96): the PNG's pHYs chunk, the PDF/SVG
/// page of width/dpi x height/dpi inches (print sizes: 8.5 cm at 300 dpi is 1004 pixels).
int render_cairo_write_dpi(const char *path, int width, int height, double dpi, RenderDrawFn draw,
                           void *context, const char *const *text, char *err, size_t err_size);
/// render_png_write with a pHYs chunk of `dpi` pixels per inch (0 = 96).
int render_png_write_dpi(const RenderImage *image, const char *path, const char *const *text,
                         double dpi, char *err, size_t err_size);
/// Appends the provenance chunks every written image carries (key, value pairs) to text from
/// *n: Software, Sablier version, Scene and Seed (Seed also without a scene when seed_always),
/// Title, Comment. `seed` (32 bytes) holds the seed's text and must outlive `text`.
void render_provenance(const RenderMeta *meta, const char *title, int seed_always, char *seed,
                       const char **text, int *n);
/// Draws with `draw` into a new BGRA image. 0, or -1 with a message in err.
int render_cairo_image(int width, int height, RenderDrawFn draw, void *context, RenderImage *out,
                       char *err, size_t err_size);

#endif
