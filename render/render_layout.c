/* SPDX-License-Identifier: MIT */
/* render_layout.c: where a frame lands on the canvas, shared by the Cairo drawer (render_cairo.c)
 * and the GL drawer (render_gl.c) so both put grains, plot rectangle and margins on the same
 * pixels: the world window, the margins every annotation is given outside the plot rectangle
 * (title, time stamp, axes, scale bar, arrow key, colour bar or species legend, arch inset), the
 * plot rectangle at one scale, and the style's automatic values resolved for a frame. The
 * margins estimate text widths without a Cairo context (the tick labels are formatted as the
 * axes draw them, render_cairo_util.h). */
#include "render_cairo_util.h"

#include "render/internal.h"

#include <math.h>
#include <stdio.h>

int render_colorbar_kind(const RenderStyle *style)
{
    if (!style->colorbar)
        return 0;
    if (style->color_by == RENDER_COLOR_FORCE || style->color_by == RENDER_COLOR_SPEED)
        return 1; /* continuous bar */
    if (style->color_by == RENDER_COLOR_SPECIES)
        return 2; /* categorical legend */
    return 0;
}

static double font_size_of(const RenderStyle *style)
{
    if (style->font_size > 0)
        return style->font_size;
    return RENDER_FIGURE_FONT_PT * (style->dpi > 0 ? style->dpi : 96.0) / 72.0;
}

int render_grain_fixed(const SimFrame *frame, int i)
{
    return frame->flags && (frame->flags[i] & SIM_GRAIN_FIXED);
}

static double frame_mean_diameter(const SimFrame *frame)
{
    double sum = 0;
    int n = 0;
    for (int i = 0; i < frame->count; ++i) {
        if (render_grain_fixed(frame, i) && frame->mobile_count > 0)
            continue;
        sum += 2 * frame->radius[i];
        ++n;
    }
    return n ? sum / n : 0;
}

/* The world window a frame shows: the style's view, else every grain and wall with a 2 % margin
 * (a periodic frame: its domain across). */
static void world_window(const SimFrame *frame, const RenderStyle *style, double w[4])
{
    if (style->view_x1 > style->view_x0 && style->view_y1 > style->view_y0) {
        w[0] = style->view_x0;
        w[1] = style->view_y0;
        w[2] = style->view_x1;
        w[3] = style->view_y1;
        return;
    }
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int i = 0; i < frame->count; ++i) {
        double r = frame->radius[i];
        x0 = fmin(x0, frame->x[i] - r);
        x1 = fmax(x1, frame->x[i] + r);
        y0 = fmin(y0, frame->y[i] - r);
        y1 = fmax(y1, frame->y[i] + r);
    }
    for (int k = 0; k < frame->wall_count; ++k) {
        double wx0, wy0, wx1, wy1;
        sim_wall_bounds(&frame->walls[k], &wx0, &wy0, &wx1, &wy1);
        x0 = fmin(x0, wx0);
        x1 = fmax(x1, wx1);
        y0 = fmin(y0, wy0);
        y1 = fmax(y1, wy1);
    }
    if (!(x1 > x0) || !(y1 > y0)) {
        x0 = y0 = 0;
        x1 = y1 = 1;
    }
    double margin = 0.02 * fmax(x1 - x0, y1 - y0);
    y0 -= margin;
    y1 += margin;
    if (frame->periodic && frame->domain_x1 > frame->domain_x0) {
        x0 = frame->domain_x0;
        x1 = frame->domain_x1;
    } else {
        x0 -= margin;
        x1 += margin;
    }
    w[0] = x0;
    w[1] = y0;
    w[2] = x1;
    w[3] = y1;
}

/* Metres per axis unit: the mean diameter in reduced units, else 1. */
double render_axis_unit(const RenderStyle *style, double d)
{
    return style->reduced_units && d > 0 ? d : 1.0;
}

/* Highest species index among mobile grains (the legend's last entry), at most 15. */
int render_legend_top(const SimFrame *frame)
{
    int top = 0;
    for (int i = 0; i < frame->count; ++i)
        if (!render_grain_fixed(frame, i) && frame->species && frame->species[i] > top)
            top = frame->species[i];
    return top > 15 ? 15 : top;
}

void render_species_label(const RenderStyle *style, int k, char *buf, size_t size)
{
    const char *name =
        k < style->species_name_count && style->species_names ? style->species_names[k] : NULL;
    if (name && *name)
        snprintf(buf, size, "%s", name);
    else
        snprintf(buf, size, "species %d", k);
}

/* Width of text estimated without a Cairo context: DejaVu Sans averages 0.62 em per character
 * of labels and digits (layout only; drawing measures). UTF-8 continuation bytes do not count. */
static double text_estimate(const char *text, double fs)
{
    int n = 0;
    for (const unsigned char *c = (const unsigned char *)text; *c; ++c)
        n += (*c & 0xc0) != 0x80;
    return 0.62 * fs * n;
}

/* Width of the y axis's tick labels, pixels. */
static double y_label_width(const RenderStyle *style, const double w[4], double unit, double fs)
{
    double ticks[32];
    int n = render_axis_ticks(w[1] / unit, w[3] / unit, 0, 5, ticks, 32);
    int e = render_tick_exponent(ticks, n);
    double step = (n > 1 ? ticks[1] - ticks[0] : (w[3] - w[1]) / unit) / pow(10, e), widest = 0;
    for (int k = 0; k < n; ++k) {
        char text[40];
        render_format_tick(ticks[k] / pow(10, e), step, 0, text, sizeof text);
        widest = fmax(widest, text_estimate(text, fs));
    }
    (void)style;
    return widest;
}

static int has_inset(const SimFrame *frame, const RenderStyle *style)
{
    if (!style->arch_inset || !style->arch_ids)
        return 0;
    for (int i = 0; i < frame->count; ++i)
        if (style->arch_ids[i] >= 0)
            return 1;
    return 0;
}

/* Room under the plot: tick labels and axis label, then one row for the scale bar and the
 * reference arrow. */
double render_axes_room(const RenderStyle *s, double fs)
{
    return s->axes ? 3.1 * fs : 0.0;
}

static int has_arrow_key(const RenderStyle *s)
{
    return s->velocity_field || s->velocity_arrows || s->node_vx;
}

/* Rows under the plot: the scale bar's, then the arrow key's (each on its own row, so neither
 * label runs into the other on narrow figures). */
static double key_rows(const RenderStyle *s, double fs)
{
    return (s->scale_bar ? 2.0 * fs : 0.0) +
           (has_arrow_key(s) ? (s->scale_bar ? 1.6 : 2.0) * fs : 0.0);
}

/* The reserved margins (top, bottom, left, right), pixels, for window w. */
static void layout_margins(const SimFrame *frame, const RenderStyle *style, const double w[4],
                           double d, double fs, double m[4])
{
    double pad = 0.6 * fs;
    /* Reserved margins: every annotation sits outside the plot rectangle. */
    double top = pad + (style->title ? 1.8 * fs : 0) + (style->time_stamp ? 1.6 * fs : 0);
    double bottom = pad + render_axes_room(style, fs) + key_rows(style, fs);
    double left = pad, right = pad;
    if (style->axes) {
        double unit = render_axis_unit(style, d);
        left += y_label_width(style, w, unit, fs) + 2.7 * fs;
        right += 1.2 * fs; /* half the last x tick label */
    }
    int bar = render_colorbar_kind(style);
    if (bar == 1)
        right += 7.5 * fs;
    if (bar == 2) {
        double widest = text_estimate("species", fs);
        for (int k = 0, top_k = render_legend_top(frame); k <= top_k; ++k) {
            char text[96];
            render_species_label(style, k, text, sizeof text);
            widest = fmax(widest, text_estimate(text, fs) + 1.5 * fs);
        }
        right += 1.2 * fs + widest;
    }
    if (has_inset(frame, style))
        right += 0.3 * style->width;
    m[0] = top;
    m[1] = bottom;
    m[2] = left;
    m[3] = right;
}

int render_fit_height(const SimFrame *frame, const RenderStyle *style)
{
    double w[4], m[4], fs = font_size_of(style);
    world_window(frame, style, w);
    layout_margins(frame, style, w, frame_mean_diameter(frame), fs, m);
    double room_w = fmax(1.0, style->width - m[2] - m[3]);
    return (int)ceil(m[0] + m[1] + room_w * (w[3] - w[1]) / (w[2] - w[0]));
}

void render_view_fit(const SimFrame *frame, const RenderStyle *style, RenderView *view)
{
    double fs = font_size_of(style), w[4], m[4];
    world_window(frame, style, w);
    view->font_size = fs;
    view->mean_diameter = frame_mean_diameter(frame);
    layout_margins(frame, style, w, view->mean_diameter, fs, m);
    double top = m[0], bottom = m[1], left = m[2], right = m[3];
    double room_w = fmax(1.0, style->width - left - right);
    double room_h = fmax(1.0, style->height - top - bottom);
    /* The plot rectangle is the world window at one scale (the aspect kept), centred in the room
     * the margins leave. */
    view->scale = fmin(room_w / (w[2] - w[0]), room_h / (w[3] - w[1]));
    /* The window's middle lands at the room's middle; the rectangle is widened to whole pixels
     * (so the Cairo and OSMesa drawers clip the same pixels) and the centre moved to match. */
    double cx = left + 0.5 * room_w, cy = top + 0.5 * room_h;
    double half_w = 0.5 * (w[2] - w[0]) * view->scale, half_h = 0.5 * (w[3] - w[1]) * view->scale;
    view->plot_x = floor(cx - half_w + 1e-6);
    view->plot_y = floor(cy - half_h + 1e-6);
    view->plot_w = fmax(1.0, ceil(cx + half_w - 1e-6) - view->plot_x);
    view->plot_h = fmax(1.0, ceil(cy + half_h - 1e-6) - view->plot_y);
    view->center_x = 0.5 * (w[0] + w[2]) + (view->plot_x + 0.5 * view->plot_w - cx) / view->scale;
    view->center_y = 0.5 * (w[1] + w[3]) - (view->plot_y + 0.5 * view->plot_h - cy) / view->scale;
}

void render_view_to_pixel(const RenderView *view, double x, double y, double *px, double *py)
{
    *px = view->plot_x + 0.5 * view->plot_w + (x - view->center_x) * view->scale;
    *py = view->plot_y + 0.5 * view->plot_h - (y - view->center_y) * view->scale;
}

RenderStyle render_style_resolve(const SimFrame *frame, const RenderStyle *style)
{
    RenderStyle s = *style;
    RenderView view;
    render_view_fit(frame, style, &view);
    double d = view.mean_diameter;
    s.font_size = view.font_size;
    if (!(s.band_height > 0))
        s.band_height = d > 0 ? 5 * d : 1;
    if (!(s.chain_width_max > 0))
        s.chain_width_max = fmax(1.5, 0.5 * d * view.scale);
    if (!(s.field_cell > 0))
        s.field_cell = d > 0 ? 2 * d : 1;
    if (!(s.field_width > 0))
        s.field_width = d > 0 ? 1.5 * d : 1;
    if (!(s.arrow_scale > 0) && s.velocity_arrows) { /* only the arrows use it */
        double vmax = 0;
        for (int i = 0; i < frame->count; ++i)
            if (!render_grain_fixed(frame, i) && frame->vx && frame->vy)
                vmax = fmax(vmax, hypot(frame->vx[i], frame->vy[i]));
        s.arrow_scale = vmax > 0 ? 2 * d / vmax : 0;
    }
    return s;
}
