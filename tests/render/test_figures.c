/* SPDX-License-Identifier: MIT */
/* Publication grain figures: framed axes in metres and in mean diameters, annotations
 * in reserved margins (never over the plot), colour-bar ticks with a x10^e offset, a node field
 * with its reference arrow, and print sizes (dpi in the PNG's pHYs chunk, PDF page in points,
 * fonts embedded). Reference images through our own diff (fixture_check_reference). */
#include "fixture.h"
#include "test.h"

static RenderStyle figure_style(int w, int h)
{
    RenderStyle s = render_style_default();
    s.width = w;
    s.height = h;
    s.axes = 1;
    return s;
}

static int draw_and_check(const char *name, const Fixture *f, const RenderStyle *s)
{
    RenderImage image;
    TEST_ASSERT(render_cairo_draw(&f->frame, s, &image) == 0);
    int rc = fixture_check_reference(name, &image);
    render_image_free(&image);
    return rc;
}

/* Axes in metres around the bed, force colours with their bar, time stamp and scale bar. */
static int axes_metres(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 12, 6, 0.01, 21) == 0);
    RenderStyle s = figure_style(560, 320);
    s.color_by = RENDER_COLOR_FORCE;
    s.range_min = 0;
    s.range_max = 6;
    int rc = draw_and_check("axes_metres", &f, &s);
    fixture_free(&f);
    return rc;
}

/* units = "reduced": axes in d, time in sqrt(d/g), scale bar in d only. */
static int axes_reduced(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 12, 6, 0.01, 22) == 0);
    RenderStyle s = figure_style(560, 320);
    s.reduced_units = 1;
    s.colorbar = 0;
    int rc = draw_and_check("axes_reduced", &f, &s);
    fixture_free(&f);
    return rc;
}

/* Every annotation on, over a window holding no grain (the one grain lies outside it, so the
 * mean diameter, the arrow key and the colour range exist): every pixel inside the plot frame
 * stays background, so no annotation covers data; and the margins do hold ink. */
static int margins_leave_plot_clear(void)
{
    Fixture f;
    TEST_ASSERT(fixture_init(&f, 4, 4, 23) == 0);
    int g = fixture_add(&f, 5.0, 5.0, 0.01, 0);
    f.vx[g] = 0.3;
    f.force[g] = 3e-5;
    f.frame.time = 0.5;
    f.frame.time_scale = 0.03;
    RenderStyle s = figure_style(480, 300);
    s.view_x0 = 0;
    s.view_y0 = 0;
    s.view_x1 = 0.4;
    s.view_y1 = 0.2;
    s.title = "margins";
    s.color_by = RENDER_COLOR_FORCE;
    s.velocity_arrows = 1;
    s.arrow_scale = 0.05;
    RenderImage image;
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &image) == 0);
    RenderView v;
    render_view_fit(&f.frame, &s, &v);
    TEST_ASSERT(v.plot_w > 100 && v.plot_h > 50);
    TEST_NEAR(v.plot_w / v.plot_h, 2.0, 0.02); /* the view's aspect kept */
    long inside = 0, ink_outside = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            int in = x > v.plot_x + 2 && x < v.plot_x + v.plot_w - 2 && y > v.plot_y + 2 &&
                     y < v.plot_y + v.plot_h - 2;
            uint32_t p = fixture_pixel(&image, x, y);
            if (in)
                inside += p != 0xffffff;
            else
                ink_outside += p != 0xffffff;
        }
    TEST_ASSERT(inside == 0);
    TEST_ASSERT(ink_outside > 2000);
    int rc = fixture_check_reference("margins", &image);
    render_image_free(&image);
    fixture_free(&f);
    return rc;
}

/* A colour bar over [0, 4e-5] N: ticks 0, 1, 2, 3, 4 and one "x10^-5" above the bar. */
static int colorbar_exponent(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 5, 0.01, 24) == 0);
    for (int i = 0; i < f.frame.count; ++i)
        f.force[i] *= 4e-6;
    RenderStyle s = figure_style(480, 280);
    s.axes = 0;
    s.time_stamp = 0;
    s.scale_bar = 0;
    s.color_by = RENDER_COLOR_FORCE;
    s.range_min = 0;
    s.range_max = 4e-5;
    int rc = draw_and_check("colorbar_exponent", &f, &s);
    fixture_free(&f);
    return rc;
}

/* A short colour bar (a 240 x 160 px frame, its font at 7.5 pt) has fewer ticks, at least two
 * em apart, so that their labels do not run into each other (the figure lint's overlap). */
static int colorbar_short_ticks(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 5, 0.01, 24) == 0);
    RenderStyle s = figure_style(240, 160);
    s.color_by = RENDER_COLOR_FORCE;
    s.range_min = 0;
    s.range_max = 8000;
    RenderImage image;
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &image) == 0);
    RenderView v;
    render_view_fit(&f.frame, &s, &v);
    double fs = v.font_size;
    /* the tick marks: dark pixels in the column just right of the bar */
    int x = (int)(round(v.plot_x + v.plot_w + 1.2 * fs) + round(1.1 * fs) + 0.2 * fs);
    int marks = 0, last = -1000, closest = 1000, dark = 0;
    for (int y = (int)v.plot_y; y < image.height; ++y) /* the time stamp is above */ {
        uint32_t p = fixture_pixel(&image, x, y);
        int now = ((p >> 16 & 255) + (p >> 8 & 255) + (p & 255)) < 600; /* antialiased */
        if (now && !dark) {
            ++marks;
            closest = y - last < closest ? y - last : closest;
            last = y;
        }
        dark = now;
    }
    render_image_free(&image);
    fixture_free(&f);
    TEST_ASSERT(marks >= 2);
    TEST_ASSERT(closest >= 1.3 * fs); /* labels 1.16 em tall keep a gap */
    return 0;
}

/* A field given on its nodes (a vortex on 10 x 5 nodes, one masked) drawn on the nodes, coloured
 * by speed, with its reference arrow in m/s under the plot. */
static int node_field_key(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 25) == 0);

    enum { NX = 10, NY = 5 };

    double vx[NX * NY], vy[NX * NY], cell = 0.02;
    for (int j = 0; j < NY; ++j)
        for (int i = 0; i < NX; ++i) {
            double x = (i + 0.5) * cell - 0.1, y = (j + 0.5) * cell - 0.05;
            vx[j * NX + i] = -y * 2.0;
            vy[j * NX + i] = x * 2.0;
        }
    vx[0] = NAN;
    RenderStyle s = figure_style(480, 300);
    s.fill_rgb = 0xe4e4e4;
    s.colorbar = 0;
    s.node_vx = vx;
    s.node_vy = vy;
    s.node_nx = NX;
    s.node_ny = NY;
    s.node_x0 = 0.005;
    s.node_y0 = 0.01;
    s.node_cell = cell;
    s.field_color = 1;
    int rc = draw_and_check("node_field_key", &f, &s);
    fixture_free(&f);
    return rc;
}

static const unsigned char *find_bytes(const unsigned char *buf, long n, const char *what)
{
    size_t len = strlen(what);
    for (long k = 0; k + (long)len <= n; ++k)
        if (memcmp(buf + k, what, len) == 0)
            return buf + k;
    return NULL;
}

/* A single-column figure (8.5 x 6.4 cm at 300 dpi, 8 pt fonts): 1004 x 756 pixels, a 300 dpi
 * pHYs chunk, a PDF page of 241 x 181 pt with its fonts embedded, SVG glyphs as outlines. */
static int print_size(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 12, 6, 0.01, 26) == 0);
    RenderStyle s = figure_style(1004, 756);
    s.dpi = 300;
    s.font_size = 8.0 * 300 / 72;
    s.color_by = RENDER_COLOR_SPECIES;
    const char *names[] = {"small", "large"};
    s.species_names = names;
    s.species_name_count = 2;
    int rc = draw_and_check("print_single_column", &f, &s);
    fixture_mkdirs();
    char err[256];
    RenderMeta meta = {.scene = "print", .seed = 1};
    TEST_ASSERT(render_figure_write(&f.frame, &s, &meta, "out/render-tests/print.png", err,
                                    sizeof err) == 0);
    TEST_ASSERT(render_figure_write(&f.frame, &s, &meta, "out/render-tests/print.pdf", err,
                                    sizeof err) == 0);
    TEST_ASSERT(render_figure_write(&f.frame, &s, &meta, "out/render-tests/print.svg", err,
                                    sizeof err) == 0);
    static unsigned char buf[1 << 20];
    long n = fixture_read("out/render-tests/print.png", buf, sizeof buf);
    const unsigned char *p = find_bytes(buf, n, "pHYs");
    TEST_ASSERT(p);
    unsigned long per_metre =
        (unsigned long)p[4] << 24 | (unsigned long)p[5] << 16 | (unsigned long)p[6] << 8 | p[7];
    TEST_ASSERT(per_metre == 11811); /* 300 / 0.0254 */
    n = fixture_read("out/render-tests/print.pdf", buf, sizeof buf);
    TEST_ASSERT(n > 0);
    p = find_bytes(buf, n, "/MediaBox [ 0 0 ");
    TEST_ASSERT(p);
    double w_pt = 0, h_pt = 0;
    TEST_ASSERT(sscanf((const char *)p + 16, "%lf %lf", &w_pt, &h_pt) == 2);
    TEST_NEAR(w_pt, 1004 * 72.0 / 300, 0.01);
    TEST_NEAR(h_pt, 756 * 72.0 / 300, 0.01);
    TEST_ASSERT(find_bytes(buf, n, "/FontFile")); /* fonts embedded */
    n = fixture_read("out/render-tests/print.svg", buf, sizeof buf);
    TEST_ASSERT(n > 0 && find_bytes(buf, n, "glyph")); /* text as glyph outlines */
    fixture_free(&f);
    return rc;
}

TEST_MAIN(TEST_CASE(axes_metres), TEST_CASE(axes_reduced), TEST_CASE(margins_leave_plot_clear),
          TEST_CASE(colorbar_exponent), TEST_CASE(colorbar_short_ticks), TEST_CASE(node_field_key),
          TEST_CASE(print_size))
