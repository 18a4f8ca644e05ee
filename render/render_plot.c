/* SPDX-License-Identifier: MIT */
/* render_plot.c: line and scatter plots for figures such as the 2x2 dimensionless energy panels of
 * thesis 000 fig. 6.15: ticks on 1, 2, 2.5, 5 x 10^k with one format per axis, log axes, error
 * bars, legends placed where they hide the fewest data, multi-panel grids, text in the markup of
 * render_markup.c; laid out from measured text (every placed text box is recorded:
 * render_plot_layout), drawn with Cairo, written as PNG, PDF or SVG like frame figures. */
#include "render_cairo_util.h"

#include "render/internal.h"

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

/* Smallest of 1, 2, 2.5, 5 x 10^k not below raw (matplotlib's MaxNLocator steps). */
static double nice_step(double raw)
{
    if (!(raw > 0) || !isfinite(raw))
        return 1;
    double p = pow(10, floor(log10(raw)));
    static const double m[] = {1, 2, 2.5, 5, 10};
    for (int k = 0; k < 5; ++k)
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

enum { MAX_TICKS = 32 };

/* An axis' ticks with their labels (one format for the axis) and measured sizes. */
typedef struct AxisTicks {
    int n, log;
    double v[MAX_TICKS], step;
    char label[MAX_TICKS][40];
    double w[MAX_TICKS], h[MAX_TICKS], wmax, hmax, amax, bmax; /* hmax = amax + bmax */
    char offset[40]; /* "x10^-3" at the axis end, "" = none */
    double ow, oa, ob;
} AxisTicks;

typedef struct Panel {
    double cx, cy, cw, ch; /* grid cell, pixels */
    double ax, ay, aw, ah; /* axes rectangle, pixels */
    double xlo, xhi, ylo, yhi;
    int xlog, ylog;
    AxisTicks xt, yt;
    double lw, lh, lfs;  /* legend frame (0 = none) and font size */
    RenderLegend legend; /* where it goes: a best legend too large for the axes goes outside */
    double ylfs, ylc;    /* the y label's font size and the height of its centre, pixels */
} Panel;

/* The text boxes placed (render_plot_layout); NULL boxes = not recorded. */
typedef struct Recorder {
    RenderPlotBox *boxes;
    int capacity, n;
} Recorder;

typedef struct PlotDraw {
    const RenderPlot *plot;
    Recorder *rec;
} PlotDraw;

static void record(Recorder *r, RenderPlotText kind, int panel, const double b[4], const char *text)
{
    if (!r)
        return;
    if (r->n < r->capacity) {
        RenderPlotBox *o = &r->boxes[r->n];
        *o = (RenderPlotBox){
            .x0 = b[0], .y0 = b[1], .x1 = b[2], .y1 = b[3], .kind = kind, .panel = panel};
        snprintf(o->text, sizeof o->text, "%s", text ? text : "");
    }
    ++r->n;
}

static double plot_font(const RenderPlot *p)
{
    if (p->font_size > 0)
        return p->font_size;
    return RENDER_PLOT_FONT_PT * (p->dpi > 0 ? p->dpi : 96.0) / 72.0;
}

/* No script below RENDER_TEXT_MIN_PT at the plot's print size (a legend's t_0 at 0.8 em). */
static void plot_min_script(cairo_t *cr, const RenderPlot *p)
{
    render_markup_min_script(cr, RENDER_TEXT_MIN_PT * (p->dpi > 0 ? p->dpi : 96.0) / 72.0);
}

static int valid(double v, int log)
{
    return isfinite(v) && (!log || v > 0);
}

/* Data bounds of a panel's axis (error bars included); 0 when there is no valid point. */
static int data_bounds(const RenderPanel *pn, int is_y, double *lo, double *hi)
{
    double a = INFINITY, b = -INFINITY;
    int log = is_y ? pn->y.log : pn->x.log;
    for (int s = 0; s < pn->series_count; ++s) {
        const RenderSeries *se = &pn->series[s];
        for (int k = 0; k < se->count; ++k) {
            double x = se->x[k], y = se->y[k];
            if (!valid(x, pn->x.log) || !valid(y, pn->y.log))
                continue;
            double v = is_y ? y : x;
            double e = is_y && se->y_err && isfinite(se->y_err[k]) ? fabs(se->y_err[k]) : 0;
            b = fmax(b, v + e);
            a = fmin(a, valid(v - e, log) ? v - e : v);
        }
    }
    *lo = a;
    *hi = b;
    return a <= b;
}

/* Axis limits: the declared ones, else the data plus 5 % of their span on each side (in
 * decades on a log axis), never beyond the declared domain. */
static void axis_range(const RenderPanel *pn, int is_y, double *lo, double *hi)
{
    const RenderAxis *axis = is_y ? &pn->y : &pn->x;
    int log = axis->log;
    if (axis->min < axis->max && (!log || axis->min > 0)) {
        *lo = axis->min;
        *hi = axis->max;
        return;
    }
    double a, b;
    if (!data_bounds(pn, is_y, &a, &b)) {
        a = log ? 1 : 0;
        b = log ? 10 : 1;
    }
    if (log) {
        a = log10(a);
        b = log10(b);
    }
    if (!(b > a)) {
        double w = a != 0 ? 0.1 * fabs(a) : 1;
        a -= 0.5 * w;
        b += 0.5 * w;
    }
    double margin = 0.05 * (b - a);
    a -= margin;
    b += margin;
    if (log) {
        a = pow(10, a);
        b = pow(10, b);
    }
    int domain = axis->domain_min < axis->domain_max && (!log || axis->domain_min > 0);
    if (domain) {
        a = fmax(a, axis->domain_min);
        b = fmin(b, axis->domain_max);
        if (!(b > a)) {
            a = axis->domain_min;
            b = axis->domain_max;
        }
    }
    *lo = a;
    *hi = b;
}

static double axis_pos(double v, double lo, double hi, int log)
{
    if (log)
        return (log10(v) - log10(lo)) / (log10(hi) - log10(lo));
    return (v - lo) / (hi - lo);
}

/* One format for all labels of an axis: the fewest decimals that show every tick exactly, and
 * a common factor "x10^e" (render_tick_exponent) written once at the axis end. Log axes: 10^e. */
static void format_ticks(AxisTicks *t)
{
    t->offset[0] = '\0';
    if (t->log) {
        for (int k = 0; k < t->n; ++k) {
            int e = (int)floor(log10(t->v[k]) + 0.5);
            if (e == 0 || e == 1)
                snprintf(t->label[k], sizeof t->label[k], "%d", e == 0 ? 1 : 10);
            else
                snprintf(t->label[k], sizeof t->label[k], "10^{%d}", e);
        }
        return;
    }
    int e = render_tick_exponent(t->v, t->n);
    double scale = pow(10, -e), step = t->step * scale;
    int d = 0;
    for (int ok = 0; !ok && d < 8; d += !ok) {
        ok = 1;
        for (int k = 0; k < t->n; ++k) {
            double x = t->v[k] * scale * pow(10, d);
            if (fabs(x - round(x)) > 1e-6 * fmax(1, fabs(x)))
                ok = 0;
        }
    }
    for (int k = 0; k < t->n; ++k) {
        double x = t->v[k] * scale;
        if (fabs(x) < 1e-9 * step)
            x = 0;
        char text[32];
        snprintf(text, sizeof text, "%.*f", d, x);
        /* a true minus sign (U+2212), as typeset */
        snprintf(t->label[k], sizeof t->label[k], "%s%s", text[0] == '-' ? "\xe2\x88\x92" : "",
                 text[0] == '-' ? text + 1 : text);
    }
    if (e != 0)
        render_exponent_text(e, t->offset, sizeof t->offset);
}

static void measure_ticks(cairo_t *cr, AxisTicks *t, double fs)
{
    t->wmax = t->amax = t->bmax = 0;
    for (int k = 0; k < t->n; ++k) {
        double a, b;
        render_markup_measure(cr, t->label[k], fs, &t->w[k], &a, &b);
        t->h[k] = a + b;
        t->wmax = fmax(t->wmax, t->w[k]);
        t->amax = fmax(t->amax, a);
        t->bmax = fmax(t->bmax, b);
    }
    t->hmax = t->amax + t->bmax;
    t->ow = t->oa = t->ob = 0;
    if (t->offset[0])
        render_markup_measure(cr, t->offset, fs, &t->ow, &t->oa, &t->ob);
}

/* Neighbouring labels keep a gap: 0.8 em across the x axis, 0.4 em up the y axis. */
static int ticks_fit(const AxisTicks *t, double lo, double hi, double length, int is_y, double fs)
{
    for (int k = 1; k < t->n; ++k) {
        double dist =
            (axis_pos(t->v[k], lo, hi, t->log) - axis_pos(t->v[k - 1], lo, hi, t->log)) * length;
        double need = is_y ? 0.5 * (t->h[k] + t->h[k - 1]) + 0.4 * fs
                           : 0.5 * (t->w[k] + t->w[k - 1]) + 0.8 * fs;
        if (dist < need)
            return 0;
    }
    return 1;
}

static void axis_ticks(cairo_t *cr, double lo, double hi, int log, int target, double fs,
                       AxisTicks *t)
{
    t->log = log;
    t->n = render_axis_ticks(lo, hi, log, target, t->v, MAX_TICKS);
    t->step = t->n > 1 ? t->v[1] - t->v[0] : hi - lo;
    format_ticks(t);
    measure_ticks(cr, t, fs);
}

/* Ticks for an axis `length` pixels long: about one per 3 em across, per 2 em up (matplotlib's
 * tick space), fewer until their labels do not touch. */
static void choose_ticks(cairo_t *cr, double lo, double hi, int log, double length, int is_y,
                         double fs, AxisTicks *t)
{
    int target = (int)floor(length / ((is_y ? 2.0 : 3.0) * fs));
    target = target < 2 ? 2 : target > 10 ? 10 : target;
    for (;; --target) {
        axis_ticks(cr, lo, hi, log, target, fs, t);
        if (target <= 2 || ticks_fit(t, lo, hi, length, is_y, fs))
            break;
    }
    /* A short axis with a single tick: take more ticks when their labels still fit. */
    AxisTicks more;
    for (int k = target + 1; t->n < 2 && k <= 6; ++k) {
        axis_ticks(cr, lo, hi, log, k, fs, &more);
        if (more.n >= 2 && ticks_fit(&more, lo, hi, length, is_y, fs))
            *t = more;
    }
}

static int legend_entries(const RenderPanel *pn)
{
    int n = 0;
    for (int s = 0; s < pn->series_count; ++s)
        n += pn->series[s].label != NULL;
    return pn->legend == RENDER_LEGEND_NONE ? 0 : n;
}

static void legend_size(cairo_t *cr, const RenderPanel *pn, double fs, double *w, double *h)
{
    int n = legend_entries(pn);
    double wmax = 0;
    for (int s = 0; s < pn->series_count && n > 0; ++s)
        if (pn->series[s].label) {
            double lw, a, b;
            render_markup_measure(cr, pn->series[s].label, fs, &lw, &a, &b);
            wmax = fmax(wmax, lw);
        }
    *w = n > 0 ? 0.5 * fs + 2.2 * fs + 0.5 * fs + wmax + 0.5 * fs : 0;
    *h = n > 0 ? n * 1.45 * fs + 0.5 * fs : 0;
}

/* Size of a markup text: width and ink height (above + below the baseline). */
static void text_size(cairo_t *cr, const char *text, double size, int bold, double *w, double *h,
                      double *below)
{
    *w = *h = *below = 0;
    if (!text)
        return;
    double a;
    render_text_font(cr, size, bold);
    render_markup_measure(cr, text, size, w, &a, below);
    *h = a + *below;
}

/* The figure title's font: 1.2 em, smaller (down to 0.7 em) when that is wider than the canvas. */
static double title_font(cairo_t *cr, const RenderPlot *p, double fs)
{
    double w, h, b, size = 1.2 * fs;
    text_size(cr, p->title, size, 0, &w, &h, &b);
    if (w > p->width - 0.8 * fs)
        size = fmax(0.7 * fs, size * (p->width - 0.8 * fs) / w);
    render_text_font(cr, fs, 0);
    return size;
}

static double figure_top(cairo_t *cr, const RenderPlot *p, double fs)
{
    double w, h, b;
    text_size(cr, p->title, title_font(cr, p, fs), 0, &w, &h, &b);
    render_text_font(cr, fs, 0);
    return p->title ? 0.4 * fs + h + 0.3 * fs : 0;
}

/* A legend wider than the axes is set smaller (down to 0.7 em); a best one that would hide a
 * fifth of the axes is set at 0.8 em, then goes outside if still that large and outside
 * leaves the axes over half the cell. */
static void legend_fit(cairo_t *cr, const RenderPanel *pn, double fs, Panel *g)
{
    double room = g->aw - fs;
    if (g->lw > room && room > 0) {
        g->lfs = fs * fmax(0.7, room / g->lw);
        legend_size(cr, pn, g->lfs, &g->lw, &g->lh);
    }
    if (g->legend != RENDER_LEGEND_BEST || g->lw * g->lh <= 0.2 * g->aw * g->ah)
        return;
    if (g->lfs > 0.8 * fs) { /* first a smaller font, as matplotlib's fontsize="small" */
        g->lfs = 0.8 * fs;
        legend_size(cr, pn, g->lfs, &g->lw, &g->lh);
    }
    if (g->lw * g->lh > 0.2 * g->aw * g->ah && g->lw + 0.5 * fs < 0.45 * g->cw)
        g->legend = RENDER_LEGEND_OUTSIDE;
}

/* The y label runs along the axes, centred on them; one longer than the axes may reach into
 * the cell's margins above and below them (its column left of the tick labels holds nothing
 * else), so it is shifted to stay inside the cell, and one longer than the cell is set smaller
 * (down to 0.7 em, as titles and legends) so that it never runs into the figure title or the
 * panel below. */
static void y_label_fit(cairo_t *cr, const RenderPanel *pn, double fs, Panel *g)
{
    double pad = 0.4 * fs, span = g->ch - 2 * pad, w = 0, h, b;
    g->ylfs = fs;
    g->ylc = g->ay + 0.5 * g->ah;
    if (!pn->y.label)
        return;
    text_size(cr, pn->y.label, fs, 0, &w, &h, &b);
    if (w > span && span > 0) {
        g->ylfs = fmax(0.7 * fs, fs * span / w);
        text_size(cr, pn->y.label, g->ylfs, 0, &w, &h, &b);
    }
    render_text_font(cr, fs, 0);
    if (w >= span) { /* still longer than the cell: centred on it */
        g->ylc = g->cy + 0.5 * g->ch;
        return;
    }
    g->ylc = fmax(g->ylc, g->cy + pad + 0.5 * w);
    g->ylc = fmin(g->ylc, g->cy + g->ch - pad - 0.5 * w);
}

/* Margins of the axes in their cell from the measured text around them. */
static void panel_margins(const RenderPanel *pn, const Panel *g, const double sizes[6], double fs,
                          double m[4])
{
    double gap = 0.3 * fs, tl = 0.35 * fs, pad = 0.4 * fs;
    const AxisTicks *xt = &g->xt, *yt = &g->yt;
    double y_label = sizes[0], x_label = sizes[1], title = sizes[2];
    double left = pad + (pn->y.label ? y_label + gap : 0) + yt->wmax + gap + tl;
    double right = pad, up = pad, bottom = pad + tl + gap + xt->hmax;
    if (xt->n > 0) { /* the first and last x labels are centred on their ticks */
        double p0 = axis_pos(xt->v[0], g->xlo, g->xhi, g->xlog) * g->aw;
        double p1 = (1 - axis_pos(xt->v[xt->n - 1], g->xlo, g->xhi, g->xlog)) * g->aw;
        left = fmax(left, pad + 0.5 * xt->w[0] - p0);
        right = fmax(right, pad + 0.5 * xt->w[xt->n - 1] - p1);
    }
    if (xt->offset[0])
        bottom += gap + xt->oa + xt->ob;
    if (pn->x.label)
        bottom += gap + x_label;
    up += fmax(0, yt->amax - 0.3645 * fs); /* the top y label: capitals centred on its tick */
    if (yt->offset[0])
        up = fmax(up, pad + yt->oa + yt->ob + gap);
    if (pn->title)
        up = fmax(up, pad + title + 0.5 * fs + (yt->offset[0] ? yt->oa + yt->ob + gap : 0));
    if (g->legend == RENDER_LEGEND_OUTSIDE && sizes[3] > 0)
        right += 0.5 * fs + sizes[3];
    m[0] = left;
    m[1] = right;
    m[2] = up;
    m[3] = bottom;
}

/* A panel's cell, limits, ticks and axes rectangle: the ticks follow the axes' length and the
 * margins the ticks' labels, so the two are iterated to agreement. */
static int panel_layout(cairo_t *cr, const RenderPlot *p, int index, Panel *g)
{
    int rows = p->rows > 0 ? p->rows : 1, cols = p->cols > 0 ? p->cols : 1;
    if (index < 0 || index >= rows * cols)
        return -1;
    const RenderPanel *pn = &p->panels[index];
    double fs = plot_font(p), edge = 0.2 * fs;
    plot_min_script(cr, p);
    double top = figure_top(cr, p, fs);
    g->cw = (p->width - 2 * edge) / cols;
    g->ch = (p->height - top - 2 * edge) / rows;
    g->cx = edge + (index % cols) * g->cw;
    g->cy = top + edge + (index / cols) * g->ch;
    g->xlog = pn->x.log;
    g->ylog = pn->y.log;
    axis_range(pn, 0, &g->xlo, &g->xhi);
    axis_range(pn, 1, &g->ylo, &g->yhi);
    double sizes[6] = {0}, w, b;
    text_size(cr, pn->y.label, fs, 0, &w, &sizes[0], &b);
    text_size(cr, pn->x.label, fs, 0, &w, &sizes[1], &b);
    text_size(cr, pn->title, 1.05 * fs, 1, &w, &sizes[2], &b);
    render_text_font(cr, fs, 0);
    g->lfs = fs;
    legend_size(cr, pn, fs, &g->lw, &g->lh);
    sizes[3] = g->lw;
    g->aw = fmax(1.0, g->cw - 6 * fs);
    g->ah = fmax(1.0, g->ch - 5 * fs);
    g->legend = pn->legend;
    for (int pass = 0; pass < 3; ++pass) {
        if (pass == 1) {
            legend_fit(cr, pn, fs, g);
            sizes[3] = g->lw;
        }
        choose_ticks(cr, g->xlo, g->xhi, g->xlog, g->aw, 0, fs, &g->xt);
        choose_ticks(cr, g->ylo, g->yhi, g->ylog, g->ah, 1, fs, &g->yt);
        double m[4];
        panel_margins(pn, g, sizes, fs, m);
        g->ax = g->cx + m[0];
        g->ay = g->cy + m[2];
        g->aw = fmax(1.0, g->cw - m[0] - m[1]);
        g->ah = fmax(1.0, g->ch - m[2] - m[3]);
    }
    y_label_fit(cr, pn, fs, g);
    return 0;
}

static void to_pixel(const Panel *g, double x, double y, double *px, double *py)
{
    *px = g->ax + axis_pos(x, g->xlo, g->xhi, g->xlog) * g->aw;
    *py = g->ay + g->ah - axis_pos(y, g->ylo, g->yhi, g->ylog) * g->ah;
}

/* A context on a 1x1 surface for measuring text (unhinted metrics: the same on any surface). */
static cairo_t *measure_context(void)
{
    cairo_surface_t *surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 1, 1);
    cairo_t *cr = cairo_create(surface);
    cairo_surface_destroy(surface);
    return cr;
}

int render_plot_map(const RenderPlot *plot, int panel, double x, double y, double *px, double *py)
{
    if (!plot || !plot->panels)
        return -1;
    Panel g;
    cairo_t *cr = measure_context();
    render_text_font(cr, plot_font(plot), 0);
    int rc = panel_layout(cr, plot, panel, &g);
    cairo_destroy(cr);
    if (rc != 0 || !valid(x, g.xlog) || !valid(y, g.ylog))
        return -1;
    to_pixel(&g, x, y, px, py);
    return 0;
}

/* ---------------------------------------------------------------- drawing */

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

/* Pixel of point k of a series; 0 when it cannot be drawn (NaN, <= 0 on a log axis). */
static int series_point(const Panel *g, const RenderSeries *se, int k, double *px, double *py)
{
    if (!valid(se->x[k], g->xlog) || !valid(se->y[k], g->ylog))
        return 0;
    to_pixel(g, se->x[k], se->y[k], px, py);
    return 1;
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
    if (se->line) { /* a missing value (NaN, an empty bin) lifts the pen */
        line_style(cr, se, lw);
        int pen = 0;
        for (int k = 0; k < se->count; ++k) {
            double px, py;
            if (!series_point(g, se, k, &px, &py)) {
                pen = 0;
                continue;
            }
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
            double px, py;
            if (series_point(g, se, k, &px, &py))
                marker_path(cr, se->marker, px, py, ms);
        }
        finish_marker(cr, se->marker, lw);
    }
}

/* Grid lines at the major ticks of both axes. */
static void draw_grid(cairo_t *cr, const Panel *g, double fs)
{
    double lw = fmax(1.0, fs / 24.0);
    render_set_rgb(cr, grid_rgb);
    cairo_set_line_width(cr, lw);
    int crisp = lw < 1.5; /* one-pixel lines on pixel centres */
    for (int k = 0; k < g->yt.n; ++k) {
        double px, py;
        to_pixel(g, g->xlo, g->yt.v[k], &px, &py);
        py = crisp ? floor(py) + 0.5 : py;
        cairo_move_to(cr, g->ax, py);
        cairo_line_to(cr, g->ax + g->aw, py);
    }
    for (int k = 0; k < g->xt.n; ++k) {
        double px, py;
        to_pixel(g, g->xt.v[k], g->ylo, &px, &py);
        px = crisp ? floor(px) + 0.5 : px;
        cairo_move_to(cr, px, g->ay);
        cairo_line_to(cr, px, g->ay + g->ah);
    }
    cairo_stroke(cr);
}

/* Minor ticks at 2..9 x 10^k on a log axis showing few decades. */
static void draw_minor_log(cairo_t *cr, const Panel *g, int is_y, double tl)
{
    double lo = is_y ? g->ylo : g->xlo, hi = is_y ? g->yhi : g->xhi;
    double a = floor(log10(lo)), b = ceil(log10(hi));
    if (b - a > 8)
        return;
    for (double e = a; e < b; e += 1)
        for (int m = 2; m <= 9; ++m) {
            double v = m * pow(10, e), px, py;
            if (v < lo || v > hi)
                continue;
            to_pixel(g, is_y ? g->xlo : v, is_y ? v : g->ylo, &px, &py);
            if (is_y) {
                cairo_move_to(cr, g->ax, py);
                cairo_line_to(cr, g->ax - 0.55 * tl, py);
            } else {
                cairo_move_to(cr, px, g->ay + g->ah);
                cairo_line_to(cr, px, g->ay + g->ah + 0.55 * tl);
            }
        }
    cairo_stroke(cr);
}

/* Tick marks, their labels (one format per axis) and the axis' common factor. */
static void draw_axis_ticks(cairo_t *cr, const Panel *g, int is_y, double fs, Recorder *rec,
                            int panel)
{
    const AxisTicks *t = is_y ? &g->yt : &g->xt;
    double tl = 0.35 * fs, gap = 0.3 * fs, b[4];
    render_set_rgb(cr, axis_rgb);
    cairo_set_line_width(cr, fmax(1.0, fs / 14.0));
    for (int k = 0; k < t->n; ++k) {
        double px, py;
        to_pixel(g, is_y ? g->xlo : t->v[k], is_y ? t->v[k] : g->ylo, &px, &py);
        if (is_y) {
            cairo_move_to(cr, g->ax, py);
            cairo_line_to(cr, g->ax - tl, py);
            cairo_stroke(cr);
            render_markup_draw(cr, g->ax - tl - gap, py, t->label[k], fs, 1, 0.5, b);
        } else {
            cairo_move_to(cr, px, g->ay + g->ah);
            cairo_line_to(cr, px, g->ay + g->ah + tl);
            cairo_stroke(cr);
            double base = g->ay + g->ah + tl + gap + t->amax;
            render_markup_draw(cr, px, base, t->label[k], fs, 0.5, 1, b);
        }
        record(rec, is_y ? RENDER_TEXT_Y_TICK : RENDER_TEXT_X_TICK, panel, b, t->label[k]);
    }
    if ((is_y ? g->ylog : g->xlog))
        draw_minor_log(cr, g, is_y, tl);
    if (!t->offset[0])
        return;
    if (is_y)
        render_markup_draw(cr, g->ax, g->ay - gap - t->ob, t->offset, fs, 0, 1, b);
    else
        render_markup_draw(cr, g->ax + g->aw, g->ay + g->ah + tl + gap + t->hmax + gap + t->oa,
                           t->offset, fs, 1, 1, b);
    record(rec, is_y ? RENDER_TEXT_Y_OFFSET : RENDER_TEXT_X_OFFSET, panel, b, t->offset);
}

/* How many of the panel's data the legend frame at (x, y) would hide: points, and points every
 * 1/8 along each line segment. */
static long legend_cover(const Panel *g, const RenderPanel *pn, const double box[4])
{
    long hidden = 0;
    for (int s = 0; s < pn->series_count; ++s) {
        const RenderSeries *se = &pn->series[s];
        double qx = 0, qy = 0;
        int pen = 0;
        for (int k = 0; k < se->count; ++k) {
            double px, py;
            if (!series_point(g, se, k, &px, &py)) {
                pen = 0;
                continue;
            }
            int steps = pen && se->line ? 8 : 1;
            for (int j = 1; j <= steps; ++j) {
                double f = (double)j / steps, x = qx + f * (px - qx), y = qy + f * (py - qy);
                if (steps == 1) {
                    x = px;
                    y = py;
                }
                hidden += x >= box[0] && x <= box[2] && y >= box[1] && y <= box[3];
            }
            qx = px;
            qy = py;
            pen = 1;
        }
    }
    return hidden;
}

/* The legend's frame: a corner asked for, outside right of the axes, or (best) the place
 * inside that hides the fewest data, first of matplotlib's order on a tie. */
static void legend_place(const Panel *g, const RenderPanel *pn, double fs, double box[4])
{
    static const double spots[][2] = {{1, 0},   {0, 0},   {0, 1},   {1, 1},    {1, 0.5},
                                      {0, 0.5}, {0.5, 1}, {0.5, 0}, {0.5, 0.5}};
    double m = 0.5 * fs, w = g->lw, h = g->lh, fx = 1, fy = 0;
    switch (g->legend) {
    case RENDER_LEGEND_UPPER_LEFT:
        fx = 0;
        break;
    case RENDER_LEGEND_LOWER_LEFT:
        fx = 0;
        fy = 1;
        break;
    case RENDER_LEGEND_LOWER_RIGHT:
        fy = 1;
        break;
    case RENDER_LEGEND_OUTSIDE:
        box[0] = g->ax + g->aw + m;
        box[1] = g->ay;
        box[2] = box[0] + w;
        box[3] = box[1] + h;
        return;
    case RENDER_LEGEND_BEST: {
        long best = -1;
        for (size_t k = 0; k < sizeof spots / sizeof spots[0]; ++k) {
            double x = g->ax + m + spots[k][0] * (g->aw - w - 2 * m);
            double y = g->ay + m + spots[k][1] * (g->ah - h - 2 * m);
            double b[4] = {x, y, x + w, y + h};
            long hidden = legend_cover(g, pn, b);
            if (best < 0 || hidden < best) {
                best = hidden;
                fx = spots[k][0];
                fy = spots[k][1];
            }
        }
        break;
    }
    default:
        break;
    }
    box[0] = g->ax + m + fx * (g->aw - w - 2 * m);
    box[1] = g->ay + m + fy * (g->ah - h - 2 * m);
    box[2] = box[0] + w;
    box[3] = box[1] + h;
}

static void draw_legend(cairo_t *cr, const Panel *g, const RenderPanel *pn, double fs,
                        Recorder *rec, int panel)
{
    if (g->lw <= 0)
        return;
    double box[4];
    legend_place(g, pn, fs, box);
    double x = box[0], y = box[1], w = g->lw, h = g->lh;
    double lfs = g->lfs, row = 1.45 * lfs, sample = 2.2 * lfs, pad = 0.5 * lfs;
    cairo_set_source_rgba(cr, 1, 1, 1, 0.9);
    cairo_rectangle(cr, x, y, w, h);
    cairo_fill_preserve(cr);
    render_set_rgb(cr, 0xb0b0b0);
    cairo_set_line_width(cr, fmax(1.0, fs / 24.0));
    cairo_stroke(cr);
    record(rec, RENDER_TEXT_LEGEND, panel, box, NULL);
    cairo_save(cr);
    render_text_font(cr, lfs, 0);
    int k = 0;
    for (int s = 0; s < pn->series_count; ++s) {
        const RenderSeries *se = &pn->series[s];
        if (!se->label)
            continue;
        double cy = y + 0.5 * pad + (k + 0.5) * row;
        render_set_rgb(cr, series_rgb(pn, s));
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
        render_markup_draw(cr, x + pad + sample + 0.5 * lfs, cy, se->label, lfs, 0, 0.5, NULL);
        ++k;
    }
    cairo_restore(cr);
}

/* Axis labels and the panel title, placed as panel_margins reserved them. */
static void draw_labels(cairo_t *cr, const Panel *g, const RenderPanel *pn, double fs,
                        Recorder *rec, int panel)
{
    double gap = 0.3 * fs, tl = 0.35 * fs, b[4], w, a, below;
    render_set_rgb(cr, axis_rgb);
    if (pn->x.label) {
        double top = g->ay + g->ah + tl + gap + g->xt.hmax + gap;
        if (g->xt.offset[0])
            top += g->xt.oa + g->xt.ob + gap;
        render_markup_measure(cr, pn->x.label, fs, &w, &a, &below);
        render_markup_draw(cr, g->ax + 0.5 * g->aw, top + a, pn->x.label, fs, 0.5, 1, b);
        record(rec, RENDER_TEXT_X_LABEL, panel, b, NULL);
    }
    if (pn->y.label) { /* turned a quarter anticlockwise: its ink above the baseline is left */
        render_text_font(cr, g->ylfs, 0);
        render_markup_measure(cr, pn->y.label, g->ylfs, &w, &a, &below);
        double xb = g->ax - tl - gap - g->yt.wmax - gap - below, yc = g->ylc;
        cairo_save(cr);
        cairo_translate(cr, xb, yc);
        cairo_rotate(cr, -0.5 * SIM_PI);
        render_markup_draw(cr, 0, 0, pn->y.label, g->ylfs, 0.5, 1, b);
        cairo_restore(cr);
        render_text_font(cr, fs, 0);
        double r[4] = {xb + b[1], yc - b[2], xb + b[3], yc - b[0]};
        record(rec, RENDER_TEXT_Y_LABEL, panel, r, NULL);
    }
    if (pn->title) {
        render_text_font(cr, 1.05 * fs, 1);
        render_markup_measure(cr, pn->title, 1.05 * fs, &w, &a, &below);
        double bottom = g->ay - 0.5 * fs - (g->yt.offset[0] ? g->yt.oa + g->yt.ob + gap : 0);
        double x = g->ax + 0.5 * g->aw; /* centred on the axes, kept inside the cell */
        x = fmin(x, g->cx + g->cw - 0.4 * fs - 0.5 * w);
        x = fmax(x, g->cx + 0.4 * fs + 0.5 * w);
        render_markup_draw(cr, x, bottom - below, pn->title, 1.05 * fs, 0.5, 1, b);
        record(rec, RENDER_TEXT_PANEL_TITLE, panel, b, NULL);
        render_text_font(cr, fs, 0);
    }
}

static void draw_panel(cairo_t *cr, const RenderPlot *p, int index, Recorder *rec)
{
    Panel g;
    double fs = plot_font(p);
    render_text_font(cr, fs, 0);
    if (panel_layout(cr, p, index, &g) != 0)
        return;
    const RenderPanel *pn = &p->panels[index];
    draw_grid(cr, &g, fs);
    cairo_save(cr);
    cairo_rectangle(cr, g.ax, g.ay, g.aw, g.ah);
    cairo_clip(cr);
    for (int s = 0; s < pn->series_count; ++s)
        draw_series(cr, &g, &pn->series[s], series_rgb(pn, s), fs);
    cairo_restore(cr);
    render_set_rgb(cr, axis_rgb);
    cairo_set_line_width(cr, fmax(1.2, fs / 14.0));
    cairo_rectangle(cr, g.ax, g.ay, g.aw, g.ah);
    cairo_stroke(cr);
    draw_axis_ticks(cr, &g, 0, fs, rec, index);
    draw_axis_ticks(cr, &g, 1, fs, rec, index);
    draw_legend(cr, &g, pn, fs, rec, index);
    draw_labels(cr, &g, pn, fs, rec, index);
}

static void draw_plot(cairo_t *cr, void *context)
{
    const PlotDraw *d = context;
    const RenderPlot *p = d->plot;
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_GOOD);
    plot_min_script(cr, p);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    int rows = p->rows > 0 ? p->rows : 1, cols = p->cols > 0 ? p->cols : 1;
    for (int k = 0; k < rows * cols; ++k)
        draw_panel(cr, p, k, d->rec);
    if (p->title) {
        double fs = plot_font(p), b[4], size = title_font(cr, p, fs);
        render_text_font(cr, size, 0);
        render_set_rgb(cr, axis_rgb);
        render_markup_draw(cr, 0.5 * p->width, 0.4 * fs, p->title, size, 0.5, 0, b);
        record(d->rec, RENDER_TEXT_TITLE, -1, b, NULL);
    }
}

void render_plot_paint(cairo_t *cr, const RenderPlot *plot)
{
    PlotDraw d = {.plot = plot};
    draw_plot(cr, &d);
}

int render_plot_limits(const RenderPlot *plot, int panel, double lim[4])
{
    char err[128];
    if (check_plot(plot, err, sizeof err) != 0)
        return -1;
    const int rows = plot->rows > 0 ? plot->rows : 1, cols = plot->cols > 0 ? plot->cols : 1;
    if (panel < 0 || panel >= rows * cols)
        return -1;
    axis_range(&plot->panels[panel], 0, &lim[0], &lim[1]);
    axis_range(&plot->panels[panel], 1, &lim[2], &lim[3]);
    return 0;
}

int render_plot_draw(const RenderPlot *plot, RenderImage *out, char *err, size_t err_size)
{
    out->pixels = NULL;
    if (check_plot(plot, err, err_size) != 0)
        return -1;
    PlotDraw d = {.plot = plot};
    return render_cairo_image(plot->width, plot->height, draw_plot, &d, out, err, err_size);
}

int render_plot_layout(const RenderPlot *plot, RenderPlotBox *boxes, int capacity)
{
    char err[128];
    if (check_plot(plot, err, sizeof err) != 0)
        return -1;
    Recorder rec = {.boxes = boxes, .capacity = capacity > 0 ? capacity : 0};
    PlotDraw d = {.plot = plot, .rec = &rec};
    cairo_t *cr = measure_context();
    draw_plot(cr, &d);
    cairo_destroy(cr);
    return rec.n;
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
    PlotDraw d = {.plot = plot};
    return render_cairo_write_dpi(path, plot->width, plot->height, plot->dpi, draw_plot, &d, text,
                                  err, err_size);
}
