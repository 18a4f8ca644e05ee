/* SPDX-License-Identifier: MIT */
/* Plots: nice ticks, tick labels, a 2x2 panel figure with a log axis, error bars and legends
 * (thesis 000 fig. 6.15 layout), data drawn where render_plot_map says; the layout's record of
 * placed text (no overlaps, all on the canvas, one format per axis), NaN gaps, the legend placed
 * off the data, declared domains, markup, print sizes. */
#include "fixture.h"
#include "test.h"

#include "render/render_cairo_util.h"

#define DIR "out/render-tests/plot"

static int ticks_equal(const double *got, int n, const double *want, int m)
{
    if (n != m) {
        fprintf(stderr, "%d ticks, expected %d\n", n, m);
        return 0;
    }
    for (int k = 0; k < n; ++k)
        if (fabs(got[k] - want[k]) > 1e-12 * fmax(1.0, fabs(want[k]))) {
            fprintf(stderr, "tick %d = %.17g, expected %.17g\n", k, got[k], want[k]);
            return 0;
        }
    return 1;
}

static int nice_ticks(void)
{
    double t[32];
    int n = render_axis_ticks(0, 1, 0, 5, t, 32);
    TEST_ASSERT(ticks_equal(t, n, (double[]){0, 0.2, 0.4, 0.6, 0.8, 1.0}, 6));
    n = render_axis_ticks(0, 7.3, 0, 5, t, 32);
    TEST_ASSERT(ticks_equal(t, n, (double[]){0, 2, 4, 6}, 4));
    n = render_axis_ticks(-1.5, 2.5, 0, 4, t, 32);
    TEST_ASSERT(ticks_equal(t, n, (double[]){-1, 0, 1, 2}, 4));
    n = render_axis_ticks(0.001, 0.0042, 0, 5, t, 32);
    TEST_ASSERT(ticks_equal(t, n, (double[]){0.001, 0.002, 0.003, 0.004}, 4));
    n = render_axis_ticks(1, 1000, 1, 5, t, 32);
    TEST_ASSERT(ticks_equal(t, n, (double[]){1, 10, 100, 1000}, 4));
    n = render_axis_ticks(2, 8, 1, 5, t, 32); /* under a decade: 1-2-5 steps */
    TEST_ASSERT(ticks_equal(t, n, (double[]){2, 5}, 2));
    n = render_axis_ticks(1e-12, 1e12, 1, 5, t, 32); /* 25 decades: every third */
    TEST_ASSERT(n <= 10 && n >= 5 && t[0] == 1e-12);
    TEST_ASSERT(render_axis_ticks(1, 1, 0, 5, t, 32) == 0);
    TEST_ASSERT(render_axis_ticks(-1, 10, 1, 5, t, 32) == 0);
    TEST_ASSERT(render_axis_ticks(0, 1, 0, 5, t, 3) == 3); /* capacity respected */
    n = render_axis_ticks(0, 10, 0, 4, t, 32);             /* 2.5 x 10^k steps, like MaxNLocator */
    TEST_ASSERT(ticks_equal(t, n, (double[]){0, 2.5, 5, 7.5, 10}, 5));
    n = render_axis_ticks(0, 0.002, 0, 4, t, 32);
    TEST_ASSERT(ticks_equal(t, n, (double[]){0, 0.0005, 0.001, 0.0015, 0.002}, 5));
    n = render_axis_ticks(0, 8.6, 0, 3, t, 32);
    TEST_ASSERT(ticks_equal(t, n, (double[]){0, 5}, 2) ||
                ticks_equal(t, n, (double[]){0, 2.5, 5, 7.5}, 4));
    n = render_axis_ticks(-3, 3, 0, 6, t, 32);
    TEST_ASSERT(ticks_equal(t, n, (double[]){-3, -2, -1, 0, 1, 2, 3}, 7));
    double lo = 0.13, hi = 9.7;
    render_axis_nice_range(&lo, &hi, 0, 5);
    TEST_ASSERT(lo == 0 && hi == 10);
    lo = 0.5;
    hi = 300;
    render_axis_nice_range(&lo, &hi, 1, 5);
    TEST_NEAR(lo, 0.1, 1e-15);
    TEST_NEAR(hi, 1000, 1e-12);
    lo = hi = 3;
    render_axis_nice_range(&lo, &hi, 0, 5);
    TEST_ASSERT(lo < 3 && hi > 3);
    return 0;
}

static int tick_labels(void)
{
    char b[32];
    render_format_tick(0.30000000000000004, 0.1, 0, b, sizeof b);
    TEST_ASSERT(strcmp(b, "0.3") == 0);
    render_format_tick(-1e-17, 0.2, 0, b, sizeof b);
    TEST_ASSERT(strcmp(b, "0.0") == 0);
    render_format_tick(25000, 5000, 0, b, sizeof b);
    TEST_ASSERT(strcmp(b, "25000") == 0);
    render_format_tick(2e5, 1e5, 0, b, sizeof b);
    TEST_ASSERT(strcmp(b, "2e5") == 0);
    render_format_tick(2.5e-4, 5e-5, 0, b, sizeof b);
    TEST_ASSERT(strcmp(b, "2.5e-4") == 0);
    render_format_tick(1000, 0, 1, b, sizeof b);
    TEST_ASSERT(strcmp(b, "1000") == 0);
    render_format_tick(1e-6, 0, 1, b, sizeof b);
    TEST_ASSERT(strcmp(b, "1e-6") == 0);
    return 0;
}

/* Four panels of dimensionless energies against t*: a log y axis with error bars, markers,
 * dashed lines, legends. */
typedef struct EnergyData {
    double t[40], kin[40], pot[40], err[40], el[40], total[40];
} EnergyData;

static void energy_data(EnergyData *d)
{
    for (int k = 0; k < 40; ++k) {
        double t = 0.25 * k;
        d->t[k] = t;
        d->kin[k] = 50.0 * exp(-0.6 * t) + 0.05;
        d->err[k] = 0.5 * d->kin[k];
        d->pot[k] = 100.0 - 20.0 * (1 - exp(-0.4 * t));
        d->el[k] = 2.0 + 0.5 * sin(1.3 * t);
        d->total[k] = d->kin[k] + d->pot[k] + d->el[k];
    }
}

static void energy_plot(const EnergyData *d, RenderSeries series[5], RenderPanel panels[4],
                        RenderPlot *plot)
{
    memset(series, 0, 5 * sizeof *series);
    memset(panels, 0, 4 * sizeof *panels);
    series[0] = (RenderSeries){.label = "E^*_{kin}",
                               .count = 40,
                               .x = d->t,
                               .y = d->kin,
                               .y_err = d->err,
                               .rgb = RENDER_RGB_AUTO,
                               .line = 1,
                               .marker = RENDER_MARKER_CIRCLE};
    series[1] = (RenderSeries){.label = "E^*_{pot}",
                               .count = 40,
                               .x = d->t,
                               .y = d->pot,
                               .rgb = RENDER_RGB_AUTO,
                               .line = 1};
    series[2] = (RenderSeries){.label = "E^*_{el}",
                               .count = 40,
                               .x = d->t,
                               .y = d->el,
                               .rgb = 0xcc79a7,
                               .marker = RENDER_MARKER_SQUARE};
    series[3] = (RenderSeries){.label = "E^*_{total}",
                               .count = 40,
                               .x = d->t,
                               .y = d->total,
                               .rgb = 0x000000,
                               .line = 1,
                               .dashed = 1};
    series[4] = (RenderSeries){.label = "E^*_{pot}",
                               .count = 40,
                               .x = d->t,
                               .y = d->pot,
                               .rgb = 0x009e73,
                               .line = 1,
                               .marker = RENDER_MARKER_TRIANGLE};
    const char *xl = "t^* = t / \\sqrt{d/g}";
    panels[0] = (RenderPanel){.title = "(a) kinetic",
                              .x = {.label = xl},
                              .y = {.label = "E^*", .log = 1},
                              .series_count = 1,
                              .series = &series[0],
                              .legend = RENDER_LEGEND_UPPER_RIGHT};
    panels[1] = (RenderPanel){.title = "(b) potential",
                              .x = {.label = xl},
                              .y = {.label = "E^*"},
                              .series_count = 1,
                              .series = &series[4],
                              .legend = RENDER_LEGEND_UPPER_RIGHT};
    panels[2] = (RenderPanel){.title = "(c) elastic",
                              .x = {.label = xl},
                              .y = {.label = "E^*", .min = 0, .max = 4},
                              .series_count = 1,
                              .series = &series[2],
                              .legend = RENDER_LEGEND_LOWER_RIGHT};
    panels[3] = (RenderPanel){.title = "(d) all",
                              .x = {.label = xl},
                              .y = {.label = "E^*", .log = 1, .min = 0.1, .max = 1e4},
                              .series_count = 4,
                              .series = series,
                              .legend = RENDER_LEGEND_UPPER_RIGHT};
    *plot = (RenderPlot){.width = 800,
                         .height = 600,
                         .rows = 2,
                         .cols = 2,
                         .panels = panels,
                         .title = "Dimensionless energies",
                         .font_size = 15};
}

static int energy_panels(void)
{
    fixture_mkdirs();
    EnergyData d;
    RenderSeries series[5];
    RenderPanel panels[4];
    RenderPlot plot;
    energy_data(&d);
    energy_plot(&d, series, panels, &plot);
    RenderImage image;
    char err[256];
    TEST_ASSERT(render_plot_draw(&plot, &image, err, sizeof err) == 0);
    /* Markers sit where render_plot_map puts the data: the circle markers of panel (a) are the
     * first palette colour, the squares of panel (c) are 0xcc79a7. */
    for (int k = 2; k < 40; k += 6) { /* point 0 sits on the clipped axis edge */
        double px, py;
        TEST_ASSERT(render_plot_map(&plot, 0, d.t[k], d.kin[k], &px, &py) == 0);
        TEST_ASSERT(fixture_pixel(&image, px, py) == 0x0072b2);
        TEST_ASSERT(render_plot_map(&plot, 2, d.t[k], d.el[k], &px, &py) == 0);
        TEST_ASSERT(fixture_pixel(&image, px, py) == 0xcc79a7);
    }
    /* Log axis: a decade is the same height anywhere; x <= 0 or y <= 0 cannot be mapped. */
    double p1, q1, p2, q2, p3, q3;
    TEST_ASSERT(render_plot_map(&plot, 0, 1, 0.1, &p1, &q1) == 0);
    TEST_ASSERT(render_plot_map(&plot, 0, 1, 1, &p2, &q2) == 0);
    TEST_ASSERT(render_plot_map(&plot, 0, 1, 10, &p3, &q3) == 0);
    TEST_NEAR(q1 - q2, q2 - q3, 1e-9);
    TEST_ASSERT(q1 > q2);
    TEST_ASSERT(render_plot_map(&plot, 0, 1, -1, &p1, &q1) == -1);
    TEST_ASSERT(render_plot_map(&plot, 7, 1, 1, &p1, &q1) == -1);
    /* An error bar: above the marker of point 3 (outside the marker disk) the bar's colour. */
    double px, py, pe, qe;
    TEST_ASSERT(render_plot_map(&plot, 0, d.t[3], d.kin[3], &px, &py) == 0);
    TEST_ASSERT(render_plot_map(&plot, 0, d.t[3], d.kin[3] + 0.9 * d.err[3], &pe, &qe) == 0);
    TEST_ASSERT(py - qe > 7); /* farther than the marker radius */
    int bar = 0; /* the bar is ~1.4 px wide: one of three neighbours is close to its colour */
    for (int dx = -1; dx <= 1; ++dx) {
        uint32_t c = fixture_pixel(&image, pe + dx, qe);
        int r = (int)(c >> 16), g = (int)(c >> 8 & 255), b = (int)(c & 255);
        if (abs(r - 0x00) < 60 && abs(g - 0x72) < 60 && abs(b - 0xb2) < 60)
            bar = 1;
    }
    TEST_ASSERT(bar);
    /* Not blank: a good share of the canvas is neither white nor grid grey. */
    long ink = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            uint32_t c = fixture_pixel(&image, x, y);
            if (c != 0xffffff && c != 0xe4e4e4)
                ++ink;
        }
    TEST_ASSERT(ink > 10000);
    int rc = fixture_check_reference("plot_energy", &image);
    render_image_free(&image);
    return rc;
}

static int plot_files(void)
{
    fixture_mkdirs();
    mkdir(DIR, 0777);
    EnergyData d;
    RenderSeries series[5];
    RenderPanel panels[4];
    RenderPlot plot;
    energy_data(&d);
    energy_plot(&d, series, panels, &plot);
    RenderMeta meta = {.scene = "crater", .seed = 3};
    char err[256];
    TEST_ASSERT(render_plot_write(&plot, &meta, DIR "/energy.png", err, sizeof err) == 0);
    TEST_ASSERT(render_plot_write(&plot, &meta, DIR "/energy.pdf", err, sizeof err) == 0);
    TEST_ASSERT(render_plot_write(&plot, &meta, DIR "/energy.svg", err, sizeof err) == 0);
    /* byte-reproducible: a second PNG of the same plot is the same file */
    TEST_ASSERT(render_plot_write(&plot, &meta, DIR "/energy2.png", err, sizeof err) == 0);
    TEST_ASSERT(test_same_bytes(DIR "/energy.png", DIR "/energy2.png"));
    RenderImage image;
    TEST_ASSERT(render_png_read(DIR "/energy.png", &image, err, sizeof err) == 0);
    TEST_ASSERT(image.width == 800 && image.height == 600);
    render_image_free(&image);
    /* Bad input is refused with a message. */
    RenderSeries broken = {.count = 3};
    RenderPanel bad = {.series_count = 1, .series = &broken};
    RenderPlot p = {.width = 100, .height = 100, .panels = &bad};
    TEST_ASSERT(render_plot_draw(&p, &image, err, sizeof err) == -1);
    TEST_ASSERT(strstr(err, "missing data"));
    return 0;
}

/* ---- the layout's record of placed text */

static int boxes_overlap(const RenderPlotBox *a, const RenderPlotBox *b)
{
    return a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1;
}

/* No two text boxes overlap, every box is on the canvas; returns the box count. */
static int layout_clean(const RenderPlot *plot, RenderPlotBox *boxes, int capacity)
{
    int n = render_plot_layout(plot, boxes, capacity);
    TEST_ASSERT(n > 0 && n <= capacity);
    for (int i = 0; i < n; ++i) {
        const RenderPlotBox *a = &boxes[i];
        if (!(a->x0 >= 0 && a->y0 >= 0 && a->x1 <= plot->width && a->y1 <= plot->height)) {
            fprintf(stderr, "box %d (kind %d, '%s') [%g %g %g %g] leaves the %dx%d canvas\n", i,
                    a->kind, a->text, a->x0, a->y0, a->x1, a->y1, plot->width, plot->height);
            return -1;
        }
        for (int j = 0; j < i; ++j)
            if (boxes_overlap(a, &boxes[j])) {
                fprintf(stderr, "boxes %d (kind %d, '%s') and %d (kind %d, '%s') overlap\n", i,
                        a->kind, a->text, j, boxes[j].kind, boxes[j].text);
                return -1;
            }
    }
    return n;
}

/* Decimals of a tick label ("-" = not a plain number: an exponent or letters). */
static int decimals(const char *text)
{
    if (strchr(text, 'e') || strchr(text, 'E'))
        return -2;
    const char *dot = strchr(text, '.');
    return dot ? (int)strlen(dot + 1) : 0;
}

/* All tick labels of each axis of each panel share one format. */
static int one_format(const RenderPlotBox *boxes, int n)
{
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < i; ++j) {
            const RenderPlotBox *a = &boxes[i], *b = &boxes[j];
            int tick = a->kind == RENDER_TEXT_X_TICK || a->kind == RENDER_TEXT_Y_TICK;
            if (!tick || a->kind != b->kind || a->panel != b->panel)
                continue;
            if (decimals(a->text) != decimals(b->text) || decimals(a->text) < 0) {
                fprintf(stderr, "'%s' and '%s' on one axis\n", a->text, b->text);
                return 0;
            }
        }
    return 1;
}

static int count_kind(const RenderPlotBox *boxes, int n, RenderPlotText kind, int panel)
{
    int c = 0;
    for (int k = 0; k < n; ++k)
        c += boxes[k].kind == kind && boxes[k].panel == panel;
    return c;
}

/* The energy panel of the review (energy_panels.png (a)): a kinetic energy peaking at 0.002
 * labelled E^*_{kin}, at single-column size (8.5 x 6.4 cm, 300 dpi) and at 1000 x 700 px. */
static int layout_energy(void)
{
    enum { N = 120 };

    double t[N], e[N];
    for (int k = 0; k < N; ++k) {
        t[k] = 2.75 * k / (N - 1);
        e[k] = 0.00195 * t[k] / 0.45 * exp(1 - t[k] / 0.45);
    }
    RenderSeries s = {.count = N, .x = t, .y = e, .rgb = RENDER_RGB_AUTO, .line = 1};
    RenderPanel panels[4];
    for (int k = 0; k < 4; ++k)
        panels[k] = (RenderPanel){.title = "(a) kinetic",
                                  .x = {.label = "t^* = (t \xe2\x88\x92 t_0) / \\sqrt{D/g}"},
                                  .y = {.label = "E^*_{kin}"},
                                  .series_count = 1,
                                  .series = &s};
    RenderPlot sizes[] = {
        {.width = 1004,
         .height = 756,
         .rows = 1,
         .cols = 1,
         .dpi = 300,
         .title = "crater_quick: dimensionless energies of the last stage"}, /* shrunk to fit */
        {.width = 2102, .height = 1051, .rows = 2, .cols = 2, .dpi = 300, .title = "energies"},
        {.width = 1000, .height = 700, .rows = 2, .cols = 2},
        {.width = 1000, .height = 700, .rows = 2, .cols = 2, .font_size = 17.5},
    };
    RenderPlotBox boxes[256];
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; ++k) {
        sizes[k].panels = panels;
        int n = layout_clean(&sizes[k], boxes, 256);
        TEST_ASSERT(n > 0);
        TEST_ASSERT(one_format(boxes, n));
        /* a single "x10^-3" at the y axis' end; a y label, an x label, a title */
        TEST_ASSERT(count_kind(boxes, n, RENDER_TEXT_Y_OFFSET, 0) == 1);
        TEST_ASSERT(count_kind(boxes, n, RENDER_TEXT_X_OFFSET, 0) == 0);
        TEST_ASSERT(count_kind(boxes, n, RENDER_TEXT_Y_LABEL, 0) == 1);
        TEST_ASSERT(count_kind(boxes, n, RENDER_TEXT_PANEL_TITLE, 0) == 1);
        TEST_ASSERT(count_kind(boxes, n, RENDER_TEXT_Y_TICK, 0) >= 3);
        TEST_ASSERT(count_kind(boxes, n, RENDER_TEXT_X_TICK, 0) >= 3);
        for (int b = 0; b < n; ++b)
            if (boxes[b].kind == RENDER_TEXT_Y_OFFSET)
                TEST_ASSERT(strcmp(boxes[b].text, "\xc3\x97"
                                                  "10\xe2\x81\xbb\xc2\xb3") == 0);
    }
    return 0;
}

/* The sediment side panels of the review (002_sediment_profiles.png): two narrow panels, x
 * from 0 to 0.42 and 0 to 1, whose x tick labels ran together ("0.00.10.2..."). */
static int layout_sediment(void)
{
    enum { N = 60 };

    double y[N], u[N], phi[N];
    for (int k = 0; k < N; ++k) {
        y[k] = 15.0 * k / (N - 1);
        u[k] = 0.42 * pow(y[k] / 15.0, 0.3);
        phi[k] = y[k] < 10 ? 0.6 + 0.2 * sin(y[k]) : 0.1;
    }
    RenderSeries s[2] = {
        {.label = "u(y)", .count = N, .x = u, .y = y, .rgb = RENDER_RGB_AUTO, .line = 1},
        {.label = "\\phi(y)", .count = N, .x = phi, .y = y, .rgb = 0xd62728, .line = 1}};
    RenderPanel panels[2] = {{.title = "fluid velocity",
                              .x = {.label = "u / \\sqrt{gd}", .min = 0, .max = 0.441},
                              .y = {.label = "y / d", .min = -1, .max = 15.2},
                              .series_count = 1,
                              .series = &s[0]},
                             {.title = "grain fraction",
                              .x = {.label = "\\phi", .min = 0, .max = 1},
                              .y = {.label = "y / d", .min = -1, .max = 15.2},
                              .series_count = 1,
                              .series = &s[1]}};
    RenderPlot sizes[] = {
        {.width = 640, .height = 360, .rows = 1, .cols = 2, .font_size = 14},
        {.width = 400, .height = 300, .rows = 1, .cols = 2, .font_size = 14},
        {.width = 1004, .height = 756, .rows = 1, .cols = 2, .dpi = 300},
    };
    RenderPlotBox boxes[128];
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; ++k) {
        sizes[k].panels = panels;
        int n = layout_clean(&sizes[k], boxes, 128);
        TEST_ASSERT(n > 0);
        TEST_ASSERT(one_format(boxes, n));
        TEST_ASSERT(count_kind(boxes, n, RENDER_TEXT_X_TICK, 1) >= 2);
    }
    return 0;
}

/* A y label longer than its axes (the crater sweep's crater_height.png, one column wide at
 * 300 dpi, 9 pt): it stays inside the plot's cell, clear of the figure title above, and is set
 * smaller, down to 0.7 of the font size, when it is longer than the cell (4.7 cm high). */
static int layout_long_y_label(void)
{
    double x[3] = {0.1, 0.5, 1.0}, y[3] = {0.82, 0.61, 0.55};
    RenderSeries s = {.count = 3, .x = x, .y = y, .rgb = RENDER_RGB_AUTO, .line = 1};
    RenderPanel pn = {.x = {.label = "\\mu (1)"},
                      .y = {.label = "crater height h = level - min y_s (m)"},
                      .series_count = 1,
                      .series = &s};
    RenderPlot sizes[] = {
        {.width = 1004, .height = 703, .dpi = 300, .title = "crater_standard: crater height"},
        {.width = 1004, .height = 560, .dpi = 300, .title = "crater_standard: crater height"},
    };
    RenderPlotBox boxes[64];
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; ++k) {
        sizes[k].rows = sizes[k].cols = 1;
        sizes[k].panels = &pn;
        int n = layout_clean(&sizes[k], boxes, 64);
        TEST_ASSERT(n > 0);
        TEST_ASSERT(count_kind(boxes, n, RENDER_TEXT_Y_LABEL, 0) == 1);
    }
    return 0;
}

/* A missing value lifts the pen: no line is drawn across it. */
static int nan_gap(void)
{
    double x[6] = {0, 1, 2, 3, 4, 5}, y[6] = {1, 1, 1, NAN, 1, 1};
    RenderSeries s = {.count = 6, .x = x, .y = y, .rgb = 0xd55e00, .line = 1, .line_width = 4};
    RenderPanel pn = {.series_count = 1, .series = &s, .y = {.min = 0, .max = 2}};
    RenderPlot plot = {.width = 600, .height = 400, .panels = &pn};
    RenderImage image;
    char err[256];
    TEST_ASSERT(render_plot_draw(&plot, &image, err, sizeof err) == 0);
    double px, py;
    TEST_ASSERT(render_plot_map(&plot, 0, 0.5, 1, &px, &py) == 0);
    TEST_ASSERT(fixture_pixel(&image, px, py) == 0xd55e00); /* drawn between valid points */
    TEST_ASSERT(render_plot_map(&plot, 0, 3.0, 1, &px, &py) == 0);
    TEST_ASSERT(fixture_pixel(&image, px, py) != 0xd55e00); /* the gap */
    TEST_ASSERT(render_plot_map(&plot, 0, 4.5, 1, &px, &py) == 0);
    TEST_ASSERT(fixture_pixel(&image, px, py) == 0xd55e00);
    render_image_free(&image);
    return 0;
}

/* legend = best: the frame sits where no data are; pinned upper right it hides some. */
static int legend_best(void)
{
    enum { N = 50 };

    double x[N], a[N], b[N];
    for (int k = 0; k < N; ++k) { /* two rising curves fill the upper right */
        x[k] = k;
        a[k] = k * k;
        b[k] = 0.8 * k * k;
    }
    RenderSeries s[2] = {
        {.label = "first", .count = N, .x = x, .y = a, .rgb = RENDER_RGB_AUTO, .line = 1},
        {.label = "second", .count = N, .x = x, .y = b, .rgb = RENDER_RGB_AUTO, .line = 1}};
    RenderPanel pn = {.series_count = 2, .series = s, .legend = RENDER_LEGEND_BEST};
    RenderPlot plot = {.width = 800, .height = 600, .panels = &pn};
    RenderPlotBox boxes[64];
    for (int pass = 0; pass < 2; ++pass) {
        int n = layout_clean(&plot, boxes, 64), hidden = 0, found = 0;
        TEST_ASSERT(n > 0);
        for (int k = 0; k < n; ++k) {
            if (boxes[k].kind != RENDER_TEXT_LEGEND)
                continue;
            found = 1;
            for (int i = 0; i < N; ++i)
                for (int j = 0; j < 2; ++j) {
                    double px, py;
                    TEST_ASSERT(render_plot_map(&plot, 0, x[i], j ? b[i] : a[i], &px, &py) == 0);
                    hidden += px >= boxes[k].x0 && px <= boxes[k].x1 && py >= boxes[k].y0 &&
                              py <= boxes[k].y1;
                }
            /* best: upper left, clear of the data */
            TEST_ASSERT(pass == 1 || boxes[k].x1 < plot.width / 2);
        }
        TEST_ASSERT(found);
        if (pass == 0 ? hidden != 0 : hidden == 0)
            fprintf(stderr, "pass %d: the legend hides %d points\n", pass, hidden);
        TEST_ASSERT(pass == 0 ? hidden == 0 : hidden > 0);
        pn.legend = RENDER_LEGEND_UPPER_RIGHT;
    }
    /* outside: right of the axes, still on the canvas (layout_clean) */
    pn.legend = RENDER_LEGEND_OUTSIDE;
    int n = layout_clean(&plot, boxes, 64);
    double px, py;
    TEST_ASSERT(render_plot_map(&plot, 0, x[N - 1], a[N - 1], &px, &py) == 0);
    for (int k = 0; k < n; ++k)
        if (boxes[k].kind == RENDER_TEXT_LEGEND)
            TEST_ASSERT(boxes[k].x0 > px);
    return 0;
}

/* A declared domain bounds the automatic limits: a profile across an 8.6 m box stops at 8.6. */
static int declared_domain(void)
{
    double x[44], y[44];
    for (int k = 0; k < 44; ++k) {
        x[k] = 0.1 + 0.2 * k; /* bin centres 0.1 .. 8.7 */
        y[k] = 1.0 + 0.1 * sin(x[k]);
    }
    RenderSeries s = {.count = 43, .x = x, .y = y, .rgb = RENDER_RGB_AUTO, .line = 1};
    RenderPanel pn = {.series_count = 1, .series = &s};
    RenderPlot plot = {.width = 800, .height = 500, .panels = &pn};
    double lim[4];
    TEST_ASSERT(render_plot_limits(&plot, 0, lim) == 0);
    TEST_ASSERT(lim[1] > 8.6 && lim[0] < 0.1); /* data plus a margin */
    TEST_NEAR(lim[1] - 8.5, 0.05 * 8.4, 1e-12);
    pn.x.domain_min = 0;
    pn.x.domain_max = 8.6;
    TEST_ASSERT(render_plot_limits(&plot, 0, lim) == 0);
    TEST_NEAR(lim[0], 0, 0);
    TEST_NEAR(lim[1], 8.6, 0);
    RenderPlotBox boxes[64];
    int n = layout_clean(&plot, boxes, 64);
    TEST_ASSERT(n > 0 && one_format(boxes, n));
    return 0;
}

/* Markup: scripts smaller and raised or lowered, Greek letters as UTF-8, braces not drawn. */
static int markup(void)
{
    cairo_surface_t *surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 1, 1);
    cairo_t *cr = cairo_create(surface);
    render_text_font(cr, 20, 0);
    double w0, a0, b0, w1, a1, b1, w2, a2, b2;
    render_markup_measure(cr, "x", 20, &w0, &a0, &b0);
    render_markup_measure(cr, "x^2", 20, &w1, &a1, &b1);
    render_markup_measure(cr, "x_2", 20, &w2, &a2, &b2);
    TEST_ASSERT(a1 > a0 + 3 && b2 > b0 + 3);
    TEST_NEAR(w1, w2, 1e-9);
    TEST_ASSERT(w1 < w0 + render_text_width(cr, "2")); /* the script is smaller */
    render_markup_measure(cr, "\\phi", 20, &w1, &a1, &b1);
    TEST_NEAR(w1, render_text_width(cr, "\xcf\x86"), 1e-9);
    render_markup_measure(cr, "\\Gamma", 20, &w1, &a1, &b1);
    TEST_NEAR(w1, render_text_width(cr, "\xce\x93"), 1e-9);
    render_markup_measure(cr, "{ab}", 20, &w1, &a1, &b1);
    TEST_NEAR(w1, render_text_width(cr, "ab"), 1e-9);
    /* E^*_{kin}: the star and "kin" stacked, as wide as the wider of the two */
    render_markup_measure(cr, "E^*_{kin}", 20, &w1, &a1, &b1);
    render_markup_measure(cr, "E_{kin}", 20, &w2, &a2, &b2);
    TEST_NEAR(w1, w2, 1e-9);
    render_markup_measure(cr, "a\\_b", 20, &w1, &a1, &b1);
    TEST_NEAR(w1, render_text_width(cr, "a_b"), 1e-9);
    /* a space after a command is kept */
    render_markup_measure(cr, "\\phi (y)", 20, &w1, &a1, &b1);
    TEST_NEAR(w1, render_text_width(cr, "\xcf\x86 (y)"), 1e-9);
    /* a name with an underscore inside a word stays as written */
    render_markup_measure(cr, "crater_quick", 20, &w1, &a1, &b1);
    TEST_NEAR(w1, render_text_width(cr, "crater_quick"), 1e-9);
    render_markup_measure(cr, "\\rho_I/\\rho", 20, &w1, &a1, &b1);
    TEST_ASSERT(w1 < render_text_width(cr, "\xcf\x81I/\xcf\x81") - 1); /* rho_I: a smaller I */
    cairo_destroy(cr);
    cairo_surface_destroy(surface);
    return 0;
}

/* Fonts are points at print size: the same 8.5 cm plot at 96 and at 300 dpi has text 300/96
 * times as tall in pixels, the same on paper. */
static int print_size(void)
{
    double x[3] = {0, 1, 2}, y[3] = {0, 1, 4};
    RenderSeries s = {.count = 3, .x = x, .y = y, .rgb = RENDER_RGB_AUTO, .line = 1};
    RenderPanel pn = {.series_count = 1, .series = &s, .x = {.label = "x"}};
    RenderPlot low = {.width = 321, .height = 242, .panels = &pn, .dpi = 96};
    RenderPlot high = {.width = 1004, .height = 756, .panels = &pn, .dpi = 300};
    RenderPlotBox a[32], b[32];
    int na = layout_clean(&low, a, 32), nb = layout_clean(&high, b, 32);
    TEST_ASSERT(na > 0 && nb > 0);
    double ha = 0, hb = 0;
    for (int k = 0; k < na; ++k)
        if (a[k].kind == RENDER_TEXT_X_LABEL)
            ha = a[k].y1 - a[k].y0;
    for (int k = 0; k < nb; ++k)
        if (b[k].kind == RENDER_TEXT_X_LABEL)
            hb = b[k].y1 - b[k].y0;
    TEST_NEAR(hb / ha, 300.0 / 96.0, 1e-6);
    /* 9 pt: the x-height of "x" is 0.547 em of DejaVu Sans */
    TEST_NEAR(hb, 0.547 * RENDER_PLOT_FONT_PT * 300 / 72, 0.6);
    return 0;
}

/* Scripts are 0.7 of their base but never below 6 pt at print size: a legend's "t_0" at a
 * 7.2 pt font (9.6 px at 96 dpi) has its "0" at 6 pt (8 px), not 5 pt (the figure lint's
 * smallest text). */
static int script_floor(void)
{
    cairo_surface_t *surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 1, 1);
    cairo_t *cr = cairo_create(surface);
    double fs = 9.6, floor_px = RENDER_TEXT_MIN_PT * 96.0 / 72.0, w, a, b;
    render_text_font(cr, fs, 0);
    double t = render_text_width(cr, "t");
    render_text_font(cr, floor_px, 0);
    double zero = render_text_width(cr, "0");
    render_text_font(cr, 0.7 * fs, 0);
    double small = render_text_width(cr, "0");
    render_text_font(cr, fs, 0);
    render_markup_measure(cr, "t_0", fs, &w, &a, &b);
    TEST_NEAR(w, t + small, 1e-9); /* no floor set: 0.7 em */
    render_markup_min_script(cr, floor_px);
    render_markup_measure(cr, "t_0", fs, &w, &a, &b);
    TEST_NEAR(w, t + zero, 1e-9);
    render_markup_measure(cr, "t_0", 0.5 * floor_px, &w, &a, &b); /* never above its base */
    render_text_font(cr, 0.5 * floor_px, 0);
    TEST_NEAR(w, render_text_width(cr, "t0"), 1e-9);
    cairo_destroy(cr);
    cairo_surface_destroy(surface);
    /* the plots set the floor: the legend of "t_0" is wider than that of "t" by a 6 pt "0" */
    double x[3] = {0, 1, 2}, y[3] = {0, 1, 4}, width[2] = {0, 0};
    const char *labels[2] = {"t", "t_0"};
    int found = 0;
    for (int k = 0; k < 2; ++k) {
        RenderSeries s = {
            .count = 3, .x = x, .y = y, .rgb = RENDER_RGB_AUTO, .line = 1, .label = labels[k]};
        RenderPanel pn = {.series_count = 1,
                          .series = &s,
                          .x = {.label = "x (m)"},
                          .y = {.label = "y (m)"},
                          .legend = RENDER_LEGEND_OUTSIDE};
        RenderPlot plot = {.width = 480, .height = 320, .panels = &pn, .dpi = 96, .font_size = fs};
        RenderPlotBox boxes[32];
        int n = layout_clean(&plot, boxes, 32);
        for (int j = 0; j < n; ++j)
            if (boxes[j].kind == RENDER_TEXT_LEGEND) {
                width[k] = boxes[j].x1 - boxes[j].x0;
                ++found;
            }
    }
    TEST_NEAR(width[1] - width[0], zero, 1e-6);
    TEST_ASSERT(found == 2);
    return 0;
}

TEST_MAIN(TEST_CASE(nice_ticks), TEST_CASE(tick_labels), TEST_CASE(energy_panels),
          TEST_CASE(plot_files), TEST_CASE(layout_energy), TEST_CASE(layout_sediment),
          TEST_CASE(layout_long_y_label), TEST_CASE(nan_gap), TEST_CASE(legend_best),
          TEST_CASE(declared_domain), TEST_CASE(markup), TEST_CASE(print_size),
          TEST_CASE(script_floor))
