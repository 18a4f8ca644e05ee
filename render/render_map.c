/* SPDX-License-Identifier: MIT */
/* render_map.c: heat maps of values on square cells (thesis 004 fig. 3.4: species fraction on
 * 5 d squares), drawn with Cairo: cells as filled rectangles at equal aspect ratio, axes with
 * ticks, a colour bar. Cell edges are snapped to whole pixels and drawn without antialiasing, so
 * the pixel at a cell's centre is exactly the colour-map entry of its value. */
#include "render_cairo_util.h"

#include "render/internal.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>

static const uint32_t axis_rgb = 0x202020, empty_rgb = 0xffffff;

typedef struct Layout {
    double fs;             /* font size, pixels */
    double ax, ay, aw, ah; /* cell area (axes rectangle), pixels */
    double scale;          /* pixels per data unit */
    double bx, by, bw, bh; /* colour bar rectangle */
    double ref_y;          /* the reference arrow's line (maps with arrows), pixels */
    double lo, hi;         /* colour range */
} Layout;

static void value_range(const RenderMap *m, double *lo, double *hi)
{
    if (m->min < m->max) {
        *lo = m->min;
        *hi = m->max;
        return;
    }
    double a = INFINITY, b = -INFINITY;
    for (long k = 0; k < (long)m->nx * m->ny; ++k)
        if (isfinite(m->values[k])) {
            a = fmin(a, m->values[k]);
            b = fmax(b, m->values[k]);
        }
    if (!(a <= b))
        a = 0.0, b = 1.0;
    render_axis_nice_range(&a, &b, 0, 5); /* also widens a single value */
    *lo = a;
    *hi = b;
}

static void layout(const RenderMap *m, Layout *g)
{
    g->fs = m->font_size > 0 ? m->font_size : RENDER_FIGURE_FONT_PT * 96.0 / 72.0; /* 96 dpi */
    double fs = g->fs;
    double left = (m->y_label ? 2.0 * fs : 0.6 * fs) + 3.6 * fs;
    /* gap, bar, tick labels, bar label */
    double right = 2.7 * fs + 3.8 * fs + (m->bar_label ? 1.5 * fs : 0.0);
    double top = (m->title ? 3.0 * fs : 0.8 * fs);
    double bottom = (m->x_label ? 1.9 * fs : 0.4 * fs) + 2.0 * fs;
    double ref_room = m->arrow_x && m->arrow_y ? 1.6 * fs : 0.0; /* a line for the reference */
    double room_w = fmax(1.0, m->width - left - right),
           room_h = fmax(1.0, m->height - top - bottom - ref_room);
    double data_w = m->nx * m->cell, data_h = m->ny * m->cell;
    g->scale = fmin(room_w / data_w, room_h / data_h);
    g->aw = data_w * g->scale;
    g->ah = data_h * g->scale;
    g->ax = floor(left + 0.5 * (room_w - g->aw));
    g->ay = floor(top + 0.5 * (room_h - g->ah));
    g->bw = 1.2 * fs;
    g->bx = floor(g->ax + g->aw + 1.5 * fs);
    g->by = g->ay;
    g->bh = g->ah;
    g->ref_y = g->ay + g->ah + bottom + 0.6 * fs;
    value_range(m, &g->lo, &g->hi);
}

static void to_pixel(const RenderMap *m, const Layout *g, double x, double y, double *px,
                     double *py)
{
    *px = g->ax + (x - m->x0) * g->scale;
    *py = g->ay + g->ah - (y - m->y0) * g->scale;
}

static void draw_ticks(cairo_t *cr, const RenderMap *m, const Layout *g, int is_y)
{
    double lo = is_y ? m->y0 : m->x0, hi = lo + (is_y ? m->ny : m->nx) * m->cell;
    double ticks[64];
    int n = render_axis_ticks(lo, hi, 0, 5, ticks, 64);
    double step = n > 1 ? ticks[1] - ticks[0] : hi - lo, tl = 0.35 * g->fs;
    char text[40];
    for (int k = 0; k < n; ++k) {
        double px, py;
        to_pixel(m, g, is_y ? m->x0 : ticks[k], is_y ? ticks[k] : m->y0, &px, &py);
        render_format_tick(ticks[k], step, 0, text, sizeof text);
        if (is_y) {
            cairo_move_to(cr, g->ax, py);
            cairo_line_to(cr, g->ax - tl, py);
            cairo_stroke(cr);
            render_text_draw(cr, g->ax - tl - 0.25 * g->fs, py, text, 1, 0.5);
        } else {
            cairo_move_to(cr, px, g->ay + g->ah);
            cairo_line_to(cr, px, g->ay + g->ah + tl);
            cairo_stroke(cr);
            render_text_draw(cr, px, g->ay + g->ah + tl + 0.35 * g->fs, text, 0.5, 0);
        }
    }
}

/* The arrow field on the cells' centres (the field's own nodes) and a reference arrow of a
 * round value under the colour bar, labelled with its unit. */
static void draw_arrows(cairo_t *cr, const RenderMap *m, const Layout *g)
{
    double big = 0.0;
    long cells = (long)m->nx * m->ny;
    for (long k = 0; k < cells; ++k)
        if (isfinite(m->arrow_x[k]) && isfinite(m->arrow_y[k]))
            big = fmax(big, hypot(m->arrow_x[k], m->arrow_y[k]));
    if (!(big > 0.0))
        return;
    double per_unit = 0.9 * m->cell * g->scale / big; /* pixels per arrow unit */
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, fmax(1.0, 0.08 * g->fs));
    for (int j = 0; j < m->ny; ++j)
        for (int i = 0; i < m->nx; ++i) {
            long k = (long)j * m->nx + i;
            if (!isfinite(m->arrow_x[k]) || !isfinite(m->arrow_y[k]))
                continue;
            double px, py, dx = m->arrow_x[k] * per_unit, dy = -m->arrow_y[k] * per_unit;
            to_pixel(m, g, m->x0 + (i + 0.5) * m->cell, m->y0 + (j + 0.5) * m->cell, &px, &py);
            render_arrow(cr, px - 0.5 * dx, py - 0.5 * dy, dx, dy, 0.6 * g->fs);
        }
    /* reference: the largest 1, 2 or 5 times a power of ten not above the longest arrow nor
     * longer than 6 font sizes, under the colour bar at the figure's right edge */
    double ref = render_arrow_reference(fmin(big, 6.0 * g->fs / per_unit));
    double y = g->ref_y, x = m->width - 0.8 * g->fs, len = ref * per_unit;
    render_arrow(cr, x - len, y, len, 0.0, 0.6 * g->fs);
    char text[64];
    snprintf(text, sizeof text, "%g %s", ref, m->arrow_unit ? m->arrow_unit : "");
    render_set_rgb(cr, axis_rgb);
    render_text_font(cr, g->fs, 0);
    render_text_draw(cr, x - len - 0.4 * g->fs, y, text, 1, 0.5);
}

static void draw_map(cairo_t *cr, void *context)
{
    const RenderMap *m = context;
    Layout g;
    layout(m, &g);
    render_markup_min_script(cr, RENDER_TEXT_MIN_PT * 96.0 / 72.0); /* maps are 96 dpi */
    uint8_t lut[256][3];
    render_colormap_lut(m->colormap, lut);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    /* cells: whole-pixel edges, no antialiasing, so neighbours neither overlap nor leave seams */
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
    for (int j = 0; j < m->ny; ++j)
        for (int i = 0; i < m->nx; ++i) {
            double v = m->values[(long)j * m->nx + i];
            double x0 = round(g.ax + i * m->cell * g.scale);
            double x1 = round(g.ax + (i + 1) * m->cell * g.scale);
            double y1 = round(g.ay + g.ah - j * m->cell * g.scale);
            double y0 = round(g.ay + g.ah - (j + 1) * m->cell * g.scale);
            render_set_rgb(cr, isfinite(v)
                                   ? render_colormap_rgb(m->colormap, (v - g.lo) / (g.hi - g.lo))
                                   : empty_rgb);
            cairo_rectangle(cr, x0, y0, x1 - x0, y1 - y0);
            cairo_fill(cr);
        }
    /* colour bar: one strip per pixel row, from the same table */
    int rows = (int)round(g.bh);
    for (int r = 0; r < rows; ++r) {
        int e = (int)lround(255.0 * (rows - 1 - r) / fmax(1.0, rows - 1.0));
        cairo_set_source_rgb(cr, lut[e][0] / 255.0, lut[e][1] / 255.0, lut[e][2] / 255.0);
        cairo_rectangle(cr, g.bx, g.by + r, g.bw, 1);
        cairo_fill(cr);
    }
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_GOOD);
    if (m->arrow_x && m->arrow_y)
        draw_arrows(cr, m, &g);
    render_set_rgb(cr, axis_rgb);
    cairo_set_line_width(cr, 1);
    cairo_rectangle(cr, g.ax + 0.5, g.ay + 0.5, g.aw, g.ah);
    cairo_stroke(cr);
    cairo_rectangle(cr, g.bx + 0.5, g.by + 0.5, g.bw, g.bh);
    cairo_stroke(cr);
    render_text_font(cr, g.fs, 0);
    draw_ticks(cr, m, &g, 0);
    draw_ticks(cr, m, &g, 1);
    double ticks[32];
    int n = render_axis_ticks(g.lo, g.hi, 0, 5, ticks, 32);
    double step = n > 1 ? ticks[1] - ticks[0] : g.hi - g.lo;
    for (int k = 0; k < n; ++k) {
        double py = g.by + g.bh - (ticks[k] - g.lo) / (g.hi - g.lo) * g.bh;
        char text[40];
        cairo_move_to(cr, g.bx + g.bw, py);
        cairo_line_to(cr, g.bx + g.bw + 0.35 * g.fs, py);
        cairo_stroke(cr);
        render_format_tick(ticks[k], step, 0, text, sizeof text);
        render_text_draw(cr, g.bx + g.bw + 0.6 * g.fs, py, text, 0, 0.5);
    }
    if (m->x_label)
        render_markup_draw(cr, g.ax + 0.5 * g.aw, g.ay + g.ah + 2.3 * g.fs, m->x_label, g.fs, 0.5,
                           0, NULL);
    if (m->y_label) {
        cairo_save(cr);
        cairo_translate(cr, g.ax - 4.6 * g.fs, g.ay + 0.5 * g.ah);
        cairo_rotate(cr, -SIM_PI / 2);
        render_markup_draw(cr, 0, 0, m->y_label, g.fs, 0.5, 0.5, NULL);
        cairo_restore(cr);
    }
    if (m->bar_label) {
        cairo_save(cr);
        cairo_translate(cr, g.bx + g.bw + 4.3 * g.fs, g.by + 0.5 * g.bh);
        cairo_rotate(cr, -SIM_PI / 2);
        render_markup_draw(cr, 0, 0, m->bar_label, g.fs, 0.5, 0.5, NULL);
        cairo_restore(cr);
    }
    if (m->title) {
        render_text_font(cr, 1.2 * g.fs, 0);
        render_markup_draw(cr, 0.5 * m->width, 1.2 * g.fs, m->title, 1.2 * g.fs, 0.5, 0.5, NULL);
    }
}

static int check_map(const RenderMap *m, char *err, size_t err_size)
{
    if (!m || m->width <= 0 || m->height <= 0 || m->nx <= 0 || m->ny <= 0 || !m->values ||
        !(m->cell > 0.0) || !isfinite(m->cell) || !isfinite(m->x0) || !isfinite(m->y0)) {
        snprintf(err, err_size, "map: bad size, cells or values");
        return -1;
    }
    return 0;
}

int render_map_pixel(const RenderMap *map, double x, double y, double *px, double *py)
{
    char err[64];
    if (check_map(map, err, sizeof err) != 0)
        return -1;
    Layout g;
    layout(map, &g);
    to_pixel(map, &g, x, y, px, py);
    return 0;
}

int render_map_write(const RenderMap *map, const RenderMeta *meta, const char *path, char *err,
                     size_t err_size)
{
    if (check_map(map, err, err_size) != 0)
        return -1;
    char seed[32];
    const char *text[14];
    int n = 0;
    render_provenance(meta, map->title, 0, seed, text, &n);
    text[n++] = NULL;
    text[n++] = NULL;
    /* The context is only read. */
    return render_cairo_write(path, map->width, map->height, draw_map, (void *)(uintptr_t)map, text,
                              err, err_size);
}
