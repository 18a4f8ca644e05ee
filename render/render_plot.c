/* SPDX-License-Identifier: MIT */
/* render_plot.c: line and scatter plots for figures such as the 2x2 dimensionless energy panels of
 * thesis 000 fig. 6.15: nice-number ticks, log axes, error bars, legends, multi-panel grids; drawn
 * with Cairo, written as PNG, PDF or SVG like frame figures. */
#include "render_cairo_util.h"

#include "render/render.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const uint32_t axis_rgb = 0x1a1a1a;
static const uint32_t grid_rgb = 0xe4e4e4;
/* Okabe & Ito (2008) order, colour-blind safe. */
static const uint32_t palette[8] = {0x0072b2, 0xd55e00, 0x009e73, 0xcc79a7,
                                    0xe69f00, 0x56b4e9, 0x000000, 0xf0e442};

/* ---------------------------------------------------------------- ticks */

/* Smallest of 1, 2, 5 x 10^k not below raw. */
static double nice_step(double raw)
{
    if (!(raw > 0) || !isfinite(raw))
        return 1;
    double p = pow(10, floor(log10(raw)));
    static const double m[] = {1, 2, 5, 10};
    for (int k = 0; k < 4; ++k)
        if (m[k] * p >= raw * (1 - 1e-9))
            return m[k] * p;
    return 10 * p;
}

int render_axis_ticks(double lo, double hi, int log, int target, double *ticks, int capacity)
{
    if (!(hi > lo) || !isfinite(lo) || !isfinite(hi) || capacity <= 0)
        return 0;
    if (target < 2)
        target = 2;
    int n = 0;
    if (log) {
        if (!(lo > 0))
            return 0;
        double a = log10(lo), b = log10(hi);
        int e0 = (int)ceil(a - 1e-9), e1 = (int)floor(b + 1e-9);
        if (e1 - e0 + 1 >= 2) {
            int every = 1;
            while ((e1 - e0) / every + 1 > 2 * target)
                ++every;
            for (int e = e0; e <= e1 && n < capacity; ++e)
                if ((e - e0) % every == 0)
                    ticks[n++] = pow(10, e);
            return n;
        }
        /* Less than two decades shown: 1, 2, 5 x 10^k. */
        static const double m[] = {1, 2, 5};
        for (int e = (int)floor(a) - 1; e <= (int)ceil(b) && n < capacity; ++e)
            for (int k = 0; k < 3 && n < capacity; ++k) {
                double v = m[k] * pow(10, e);
                if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9))
                    ticks[n++] = v;
            }
        return n;
    }
    double step = nice_step((hi - lo) / target);
    double k0 = ceil(lo / step - 1e-9), k1 = floor(hi / step + 1e-9);
    for (double k = k0; k <= k1 && n < capacity; k += 1) {
        double v = k * step;
        ticks[n++] = fabs(v) < 1e-12 * step ? 0.0 : v;
    }
    return n;
}

void render_axis_nice_range(double *lo, double *hi, int log, int target)
{
    if (target < 2)
        target = 2;
    if (log) {
        if (!(*lo > 0))
            *lo = *hi > 0 ? *hi / 10 : 1;
        if (!(*hi > *lo))
            *hi = *lo * 10;
        *lo = pow(10, floor(log10(*lo) + 1e-9));
        *hi = pow(10, ceil(log10(*hi) - 1e-9));
        if (!(*hi > *lo))
            *hi = *lo * 10;
        return;
    }
    if (!(*hi > *lo)) {
        double w = *lo != 0 ? 0.1 * fabs(*lo) : 1;
        *lo -= w;
        *hi += w;
    }
    double step = nice_step((*hi - *lo) / target);
    *lo = floor(*lo / step + 1e-9) * step;
    *hi = ceil(*hi / step - 1e-9) * step;
}

/* ---------------------------------------------------------------- layout */

typedef struct Panel {
    double cx, cy, cw, ch; /* grid cell, pixels */
    double ax, ay, aw, ah; /* axes rectangle, pixels */
    double xlo, xhi, ylo, yhi;
    int xlog, ylog;
} Panel;

static double plot_font(const RenderPlot *p)
{
    if (p->font_size > 0)
        return p->font_size;
    return fmax(10.0, fmin(p->width, p->height) / 40.0);
}

static int valid(double v, int log)
{
    return isfinite(v) && (!log || v > 0);
}

static void axis_range(const RenderPanel *pn, int is_y, double *lo, double *hi)
{
    const RenderAxis *axis = is_y ? &pn->y : &pn->x;
    if (axis->min < axis->max && (!axis->log || axis->min > 0)) {
        *lo = axis->min;
        *hi = axis->max;
        return;
    }
    double a = INFINITY, b = -INFINITY;
    for (int s = 0; s < pn->series_count; ++s) {
        const RenderSeries *se = &pn->series[s];
        for (int k = 0; k < se->count; ++k) {
            double x = se->x[k], y = se->y[k];
            if (!valid(x, pn->x.log) || !valid(y, pn->y.log))
                continue;
            if (!is_y) {
                a = fmin(a, x);
                b = fmax(b, x);
                continue;
            }
            double e = se->y_err && isfinite(se->y_err[k]) ? fabs(se->y_err[k]) : 0;
            b = fmax(b, y + e);
            a = fmin(a, valid(y - e, axis->log) ? y - e : y);
        }
    }
    if (!(a <= b)) {
        a = axis->log ? 1 : 0;
        b = axis->log ? 10 : 1;
    }
    render_axis_nice_range(&a, &b, axis->log, 5);
    *lo = a;
    *hi = b;
}

static int panel_layout(const RenderPlot *p, int index, Panel *g)
{
    int rows = p->rows > 0 ? p->rows : 1, cols = p->cols > 0 ? p->cols : 1;
    if (index < 0 || index >= rows * cols)
        return -1;
    const RenderPanel *pn = &p->panels[index];
    double fs = plot_font(p), pad = 0.5 * fs;
    double top = p->title ? 2.2 * fs : 0;
    g->cw = (p->width - 2 * pad) / cols;
    g->ch = (p->height - top - 2 * pad) / rows;
    g->cx = pad + (index % cols) * g->cw;
    g->cy = top + pad + (index / cols) * g->ch;
    double left = (pn->y.label ? 2.0 * fs : 0.6 * fs) + 3.6 * fs;
    double bottom = (pn->x.label ? 1.9 * fs : 0.4 * fs) + 1.6 * fs;
    double up = pn->title ? 2.0 * fs : 0.8 * fs;
    g->ax = g->cx + left;
    g->ay = g->cy + up;
    g->aw = fmax(1.0, g->cw - left - 1.2 * fs);
    g->ah = fmax(1.0, g->ch - up - bottom);
    g->xlog = pn->x.log;
    g->ylog = pn->y.log;
    axis_range(pn, 0, &g->xlo, &g->xhi);
    axis_range(pn, 1, &g->ylo, &g->yhi);
    return 0;
}

static double axis_pos(double v, double lo, double hi, int log)
{
    if (log)
        return (log10(v) - log10(lo)) / (log10(hi) - log10(lo));
    return (v - lo) / (hi - lo);
}

static void to_pixel(const Panel *g, double x, double y, double *px, double *py)
{
    *px = g->ax + axis_pos(x, g->xlo, g->xhi, g->xlog) * g->aw;
    *py = g->ay + g->ah - axis_pos(y, g->ylo, g->yhi, g->ylog) * g->ah;
}

int render_plot_map(const RenderPlot *plot, int panel, double x, double y, double *px, double *py)
{
    Panel g;
    if (!plot || !plot->panels || panel_layout(plot, panel, &g) != 0)
        return -1;
    if (!valid(x, g.xlog) || !valid(y, g.ylog))
        return -1;
    to_pixel(&g, x, y, px, py);
    return 0;
}

/* ---------------------------------------------------------------- drawing */

/* "10" with a superscript exponent, anchored like render_text_draw; returns the width. */
static double draw_pow10(cairo_t *cr, double x, double y, double value, double halign,
                         double valign, double fs, int measure_only)
{
    int e = (int)floor(log10(value) + 0.5);
    char base[] = "10", exp[16];
    snprintf(exp, sizeof exp, "%d", e);
    if (e == 0 || e == 1) { /* 1 and 10 read better plain */
        snprintf(exp, sizeof exp, "%d", e == 0 ? 1 : 10);
        double w = render_text_width(cr, exp);
        if (!measure_only)
            render_text_draw(cr, x, y, exp, halign, valign);
        return w;
    }
    double wb = render_text_width(cr, base);
    render_text_font(cr, 0.7 * fs, 0);
    double we = render_text_width(cr, exp);
    render_text_font(cr, fs, 0);
    double w = wb + we;
    if (measure_only)
        return w;
    double x0 = x - halign * w;
    render_text_draw(cr, x0, y, base, 0, valign);
    render_text_font(cr, 0.7 * fs, 0);
    /* Raise the exponent by half a capital height. */
    render_text_draw(cr, x0 + wb, y - 0.45 * 0.729 * fs, exp, 0, valign);
    render_text_font(cr, fs, 0);
    return w;
}

static void marker_path(cairo_t *cr, RenderMarker m, double x, double y, double size)
{
    double r = 0.5 * size;
    switch (m) {
    case RENDER_MARKER_CIRCLE:
        cairo_new_sub_path(cr);
        cairo_arc(cr, x, y, r, 0, 2 * SIM_PI);
        break;
    case RENDER_MARKER_SQUARE:
        cairo_rectangle(cr, x - 0.85 * r, y - 0.85 * r, 1.7 * r, 1.7 * r);
        break;
    case RENDER_MARKER_TRIANGLE:
        cairo_move_to(cr, x, y - 1.1 * r);
        cairo_line_to(cr, x + 0.95 * r, y + 0.55 * r);
        cairo_line_to(cr, x - 0.95 * r, y + 0.55 * r);
        cairo_close_path(cr);
        break;
    case RENDER_MARKER_CROSS:
        cairo_move_to(cr, x - 0.8 * r, y - 0.8 * r);
        cairo_line_to(cr, x + 0.8 * r, y + 0.8 * r);
        cairo_move_to(cr, x - 0.8 * r, y + 0.8 * r);
        cairo_line_to(cr, x + 0.8 * r, y - 0.8 * r);
        break;
    case RENDER_MARKER_NONE:
    default:
        break;
    }
}

static void finish_marker(cairo_t *cr, RenderMarker m, double lw)
{
    if (m == RENDER_MARKER_CROSS) {
        cairo_set_line_width(cr, 1.3 * lw);
        cairo_stroke(cr);
    } else {
        cairo_fill(cr);
    }
}

static void line_style(cairo_t *cr, const RenderSeries *se, double lw)
{
    cairo_set_line_width(cr, lw);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_set_line_cap(cr, se->dashed ? CAIRO_LINE_CAP_BUTT : CAIRO_LINE_CAP_ROUND);
    if (se->dashed) {
        double dash[2] = {4 * lw, 2.5 * lw};
        cairo_set_dash(cr, dash, 2, 0);
    } else {
        cairo_set_dash(cr, NULL, 0, 0);
    }
}

static void draw_series(cairo_t *cr, const Panel *g, const RenderSeries *se, uint32_t rgb,
                        double fs)
{
    double lw = se->line_width > 0 ? se->line_width : fs / 8.0;
    double ms = se->marker_size > 0 ? se->marker_size : fs / 2.0;
    render_set_rgb(cr, rgb);
    if (se->y_err) {
        cairo_set_dash(cr, NULL, 0, 0);
        cairo_set_line_width(cr, fmax(1.0, 0.75 * lw));
        cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
        for (int k = 0; k < se->count; ++k) {
            double x = se->x[k], y = se->y[k], e = se->y_err[k];
            if (!valid(x, g->xlog) || !valid(y, g->ylog) || !isfinite(e))
                continue;
            e = fabs(e);
            double lo = y - e, hi = y + e;
            if (g->ylog && !(lo > 0))
                lo = g->ylo; /* the lower bar runs off a log axis */
            double px, p0, p1, dummy;
            to_pixel(g, x, lo, &px, &p0);
            to_pixel(g, x, hi, &dummy, &p1);
            cairo_move_to(cr, px, p0);
            cairo_line_to(cr, px, p1);
            double cap = 0.35 * ms + 1;
            cairo_move_to(cr, px - cap, p0);
            cairo_line_to(cr, px + cap, p0);
            cairo_move_to(cr, px - cap, p1);
            cairo_line_to(cr, px + cap, p1);
        }
        cairo_stroke(cr);
    }
    if (se->line) {
        line_style(cr, se, lw);
        int pen = 0;
        for (int k = 0; k < se->count; ++k) {
            if (!valid(se->x[k], g->xlog) || !valid(se->y[k], g->ylog)) {
                pen = 0;
                continue;
            }
            double px, py;
            to_pixel(g, se->x[k], se->y[k], &px, &py);
            if (pen)
                cairo_line_to(cr, px, py);
            else
                cairo_move_to(cr, px, py);
            pen = 1;
        }
        cairo_stroke(cr);
        cairo_set_dash(cr, NULL, 0, 0);
    }
    if (se->marker != RENDER_MARKER_NONE) {
        cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
        for (int k = 0; k < se->count; ++k) {
            if (!valid(se->x[k], g->xlog) || !valid(se->y[k], g->ylog))
                continue;
            double px, py;
            to_pixel(g, se->x[k], se->y[k], &px, &py);
            marker_path(cr, se->marker, px, py, ms);
        }
        finish_marker(cr, se->marker, lw);
    }
}

static void draw_axis_ticks(cairo_t *cr, const Panel *g, int is_y, double fs)
{
    double lo = is_y ? g->ylo : g->xlo, hi = is_y ? g->yhi : g->xhi;
    int log = is_y ? g->ylog : g->xlog;
    double ticks[64];
    int n = render_axis_ticks(lo, hi, log, 5, ticks, 64);
    double step = n > 1 ? ticks[1] - ticks[0] : hi - lo;
    double tl = 0.35 * fs;
    /* Grid lines first, then tick marks and labels. */
    render_set_rgb(cr, grid_rgb);
    cairo_set_line_width(cr, 1);
    for (int k = 0; k < n; ++k) {
        double px, py;
        to_pixel(g, is_y ? g->xlo : ticks[k], is_y ? ticks[k] : g->ylo, &px, &py);
        if (is_y) {
            py = floor(py) + 0.5; /* crisp one-pixel lines */
            cairo_move_to(cr, g->ax, py);
            cairo_line_to(cr, g->ax + g->aw, py);
        } else {
            px = floor(px) + 0.5;
            cairo_move_to(cr, px, g->ay);
            cairo_line_to(cr, px, g->ay + g->ah);
        }
    }
    cairo_stroke(cr);
    render_set_rgb(cr, axis_rgb);
    for (int k = 0; k < n; ++k) {
        double px, py;
        to_pixel(g, is_y ? g->xlo : ticks[k], is_y ? ticks[k] : g->ylo, &px, &py);
        char text[40];
        if (is_y) {
            cairo_move_to(cr, g->ax, py);
            cairo_line_to(cr, g->ax - tl, py);
            cairo_stroke(cr);
            if (log)
                draw_pow10(cr, g->ax - tl - 0.25 * fs, py, ticks[k], 1, 0.5, fs, 0);
            else {
                render_format_tick(ticks[k], step, 0, text, sizeof text);
                render_text_draw(cr, g->ax - tl - 0.25 * fs, py, text, 1, 0.5);
            }
        } else {
            cairo_move_to(cr, px, g->ay + g->ah);
            cairo_line_to(cr, px, g->ay + g->ah + tl);
            cairo_stroke(cr);
            if (log)
                draw_pow10(cr, px, g->ay + g->ah + tl + 0.35 * fs, ticks[k], 0.5, 0, fs, 0);
            else {
                render_format_tick(ticks[k], step, 0, text, sizeof text);
                render_text_draw(cr, px, g->ay + g->ah + tl + 0.35 * fs, text, 0.5, 0);
            }
        }
    }
    if (log) { /* minor ticks at 2..9 x 10^k when few decades are shown */
        double a = floor(log10(lo)), b = ceil(log10(hi));
        if (b - a <= 8) {
            for (double e = a; e < b; e += 1)
                for (int m = 2; m <= 9; ++m) {
                    double v = m * pow(10, e);
                    if (v < lo || v > hi)
                        continue;
                    double px, py;
                    to_pixel(g, is_y ? g->xlo : v, is_y ? v : g->ylo, &px, &py);
                    if (is_y) {
                        cairo_move_to(cr, g->ax, py);
                        cairo_line_to(cr, g->ax - 0.55 * tl, py);
                    } else {
                        cairo_move_to(cr, px, g->ay + g->ah);
                        cairo_line_to(cr, px, g->ay + g->ah + 0.55 * tl);
                    }
                }
            cairo_set_line_width(cr, 0.8);
            cairo_stroke(cr);
            cairo_set_line_width(cr, 1);
        }
    }
}

static uint32_t series_rgb(const RenderPanel *pn, int s)
{
    while (s > 0 && pn->series[s].rgb == RENDER_RGB_PREVIOUS)
        --s;
    if (pn->series[s].rgb == RENDER_RGB_PREVIOUS) /* the first series: nothing before it */
        return palette[0];
    if (pn->series[s].rgb != RENDER_RGB_AUTO)
        return pn->series[s].rgb;
    int k = 0;
    for (int t = 0; t < s; ++t)
        if (pn->series[t].rgb == RENDER_RGB_AUTO)
            ++k;
    return palette[k % 8];
}

static void draw_legend(cairo_t *cr, const Panel *g, const RenderPanel *pn, double fs)
{
    if (pn->legend == RENDER_LEGEND_NONE)
        return;
    int n = 0;
    double wmax = 0;
    for (int s = 0; s < pn->series_count; ++s)
        if (pn->series[s].label) {
            ++n;
            wmax = fmax(wmax, render_text_width(cr, pn->series[s].label));
        }
    if (n == 0)
        return;
    double row = 1.45 * fs, sample = 2.2 * fs, pad = 0.5 * fs;
    double w = pad + sample + 0.5 * fs + wmax + pad, h = n * row + pad;
    double m = 0.5 * fs;
    int right = pn->legend == RENDER_LEGEND_UPPER_RIGHT || pn->legend == RENDER_LEGEND_LOWER_RIGHT;
    int upper = pn->legend == RENDER_LEGEND_UPPER_RIGHT || pn->legend == RENDER_LEGEND_UPPER_LEFT;
    double x = right ? g->ax + g->aw - m - w : g->ax + m;
    double y = upper ? g->ay + m : g->ay + g->ah - m - h;
    cairo_set_source_rgba(cr, 1, 1, 1, 0.9);
    cairo_rectangle(cr, x, y, w, h);
    cairo_fill_preserve(cr);
    render_set_rgb(cr, 0xb0b0b0);
    cairo_set_line_width(cr, 1);
    cairo_stroke(cr);
    int k = 0;
    for (int s = 0; s < pn->series_count; ++s) {
        const RenderSeries *se = &pn->series[s];
        if (!se->label)
            continue;
        double cy = y + 0.5 * pad + (k + 0.5) * row;
        uint32_t rgb = series_rgb(pn, s);
        render_set_rgb(cr, rgb);
        double lw = se->line_width > 0 ? se->line_width : fs / 8.0;
        double ms = se->marker_size > 0 ? se->marker_size : fs / 2.0;
        if (se->line || se->marker == RENDER_MARKER_NONE) {
            line_style(cr, se, lw);
            cairo_move_to(cr, x + pad, cy);
            cairo_line_to(cr, x + pad + sample, cy);
            cairo_stroke(cr);
            cairo_set_dash(cr, NULL, 0, 0);
        }
        if (se->marker != RENDER_MARKER_NONE) {
            marker_path(cr, se->marker, x + pad + 0.5 * sample, cy, ms);
            finish_marker(cr, se->marker, lw);
        }
        render_set_rgb(cr, axis_rgb);
        render_text_draw(cr, x + pad + sample + 0.5 * fs, cy, se->label, 0, 0.5);
        ++k;
    }
}

static void draw_panel(cairo_t *cr, const RenderPlot *p, int index)
{
    Panel g;
    if (panel_layout(p, index, &g) != 0)
        return;
    const RenderPanel *pn = &p->panels[index];
    double fs = plot_font(p);
    render_text_font(cr, fs, 0);
    draw_axis_ticks(cr, &g, 0, fs);
    draw_axis_ticks(cr, &g, 1, fs);
    cairo_save(cr);
    cairo_rectangle(cr, g.ax, g.ay, g.aw, g.ah);
    cairo_clip(cr);
    for (int s = 0; s < pn->series_count; ++s)
        draw_series(cr, &g, &pn->series[s], series_rgb(pn, s), fs);
    cairo_restore(cr);
    render_set_rgb(cr, axis_rgb);
    cairo_set_line_width(cr, 1.2);
    cairo_rectangle(cr, g.ax, g.ay, g.aw, g.ah);
    cairo_stroke(cr);
    draw_legend(cr, &g, pn, fs);
    render_set_rgb(cr, axis_rgb);
    if (pn->x.label)
        render_text_draw(cr, g.ax + 0.5 * g.aw, g.ay + g.ah + 2.3 * fs, pn->x.label, 0.5, 0);
    if (pn->y.label) {
        cairo_save(cr);
        cairo_translate(cr, g.cx + 0.4 * fs, g.ay + 0.5 * g.ah);
        cairo_rotate(cr, -0.5 * SIM_PI);
        render_text_draw(cr, 0, 0, pn->y.label, 0.5, 0);
        cairo_restore(cr);
    }
    if (pn->title) {
        render_text_font(cr, 1.05 * fs, 1);
        render_text_draw(cr, g.ax + 0.5 * g.aw, g.ay - 0.6 * fs, pn->title, 0.5, 1);
        render_text_font(cr, fs, 0);
    }
}

static void draw_plot(cairo_t *cr, void *context)
{
    const RenderPlot *p = context;
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_GOOD);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    int rows = p->rows > 0 ? p->rows : 1, cols = p->cols > 0 ? p->cols : 1;
    for (int k = 0; k < rows * cols; ++k)
        draw_panel(cr, p, k);
    if (p->title) {
        double fs = plot_font(p);
        render_text_font(cr, 1.2 * fs, 0);
        render_set_rgb(cr, axis_rgb);
        render_text_draw(cr, 0.5 * p->width, 0.5 * fs + 1.1 * fs, p->title, 0.5, 0.5);
    }
}

static int check_plot(const RenderPlot *p, char *err, size_t err_size)
{
    if (!p || p->width <= 0 || p->height <= 0 || !p->panels) {
        snprintf(err, err_size, "plot: bad size or no panels");
        return -1;
    }
    int rows = p->rows > 0 ? p->rows : 1, cols = p->cols > 0 ? p->cols : 1;
    for (int k = 0; k < rows * cols; ++k) {
        const RenderPanel *pn = &p->panels[k];
        if (pn->series_count < 0 || (pn->series_count > 0 && !pn->series)) {
            snprintf(err, err_size, "plot: panel %d: bad series list", k);
            return -1;
        }
        for (int s = 0; s < pn->series_count; ++s) {
            const RenderSeries *se = &pn->series[s];
            if (se->count < 0 || (se->count > 0 && (!se->x || !se->y))) {
                snprintf(err, err_size, "plot: panel %d series %d: missing data", k, s);
                return -1;
            }
        }
    }
    return 0;
}

int render_plot_draw(const RenderPlot *plot, RenderImage *out, char *err, size_t err_size)
{
    out->pixels = NULL;
    if (check_plot(plot, err, err_size) != 0)
        return -1;
    /* The context is only read. */
    return render_cairo_image(plot->width, plot->height, draw_plot, (void *)(uintptr_t)plot, out,
                              err, err_size);
}

int render_plot_write(const RenderPlot *plot, const RenderMeta *meta, const char *path, char *err,
                      size_t err_size)
{
    if (check_plot(plot, err, err_size) != 0)
        return -1;
    char seed[32];
    const char *text[16];
    int n = 0;
    render_provenance(meta, plot->title, 0, seed, text, &n);
    text[n++] = NULL;
    text[n++] = NULL;
    return render_cairo_write(path, plot->width, plot->height, draw_plot, (void *)(uintptr_t)plot,
                              text, err, err_size);
}
