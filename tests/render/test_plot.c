/* SPDX-License-Identifier: MIT */
/* Plots: nice ticks, tick labels, a 2x2 panel figure with a log axis, error bars and legends
 * (thesis 000 fig. 6.15 layout), data drawn where render_plot_map says. */
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
    series[0] = (RenderSeries){.label = "E*_kin",
                               .count = 40,
                               .x = d->t,
                               .y = d->kin,
                               .y_err = d->err,
                               .rgb = RENDER_RGB_AUTO,
                               .line = 1,
                               .marker = RENDER_MARKER_CIRCLE};
    series[1] = (RenderSeries){
        .label = "E*_pot", .count = 40, .x = d->t, .y = d->pot, .rgb = RENDER_RGB_AUTO, .line = 1};
    series[2] = (RenderSeries){.label = "E*_el",
                               .count = 40,
                               .x = d->t,
                               .y = d->el,
                               .rgb = 0xcc79a7,
                               .marker = RENDER_MARKER_SQUARE};
    series[3] = (RenderSeries){.label = "E*_total",
                               .count = 40,
                               .x = d->t,
                               .y = d->total,
                               .rgb = 0x000000,
                               .line = 1,
                               .dashed = 1};
    series[4] = (RenderSeries){.label = "E*_pot",
                               .count = 40,
                               .x = d->t,
                               .y = d->pot,
                               .rgb = 0x009e73,
                               .line = 1,
                               .marker = RENDER_MARKER_TRIANGLE};
    const char *xl = "t* = t / sqrt(d/g)";
    panels[0] = (RenderPanel){.title = "(a) kinetic",
                              .x = {.label = xl},
                              .y = {.label = "E*", .log = 1},
                              .series_count = 1,
                              .series = &series[0],
                              .legend = RENDER_LEGEND_UPPER_RIGHT};
    panels[1] = (RenderPanel){.title = "(b) potential",
                              .x = {.label = xl},
                              .y = {.label = "E*"},
                              .series_count = 1,
                              .series = &series[4],
                              .legend = RENDER_LEGEND_UPPER_RIGHT};
    panels[2] = (RenderPanel){.title = "(c) elastic",
                              .x = {.label = xl},
                              .y = {.label = "E*", .min = 0, .max = 4},
                              .series_count = 1,
                              .series = &series[2],
                              .legend = RENDER_LEGEND_LOWER_RIGHT};
    panels[3] = (RenderPanel){.title = "(d) all",
                              .x = {.label = xl},
                              .y = {.label = "E*", .log = 1, .min = 0.1, .max = 1e4},
                              .series_count = 4,
                              .series = series,
                              .legend = RENDER_LEGEND_UPPER_RIGHT};
    *plot = (RenderPlot){.width = 800,
                         .height = 600,
                         .rows = 2,
                         .cols = 2,
                         .panels = panels,
                         .title = "Dimensionless energies"};
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

TEST_MAIN(TEST_CASE(nice_ticks), TEST_CASE(tick_labels), TEST_CASE(energy_panels),
          TEST_CASE(plot_files))
