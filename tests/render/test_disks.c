/* SPDX-License-Identifier: MIT */
/* The disk filler of PNG figures and movie frames (render/render_disks.c): its coverage adds up to
 * the disk's (and a force chain's capsule's) area, it stays within a few levels of Cairo's own
 * fill and stroke, a surface moved by whole
 * pixels gets the same bytes, and the frame drawer leaves a disk that the plot's edge cuts to
 * Cairo's clip. */
#include "fixture.h"
#include "test.h"

#include "render/render_cairo_util.h"

#include <cairo.h>

enum { SIDE = 64 };

static const double radii[] = {0.8, 1.5, 2.5, 4.0, 7.3, 20.0};
static const double offsets[][2] = {{0.0, 0.0}, {0.3, 0.7}, {0.5, 0.5}, {0.91, 0.13}};
#define COUNT(a) ((int)(sizeof(a) / sizeof((a)[0])))

static RenderDiskTarget target_of(cairo_surface_t *s)
{
    cairo_surface_flush(s);
    return (RenderDiskTarget){cairo_image_surface_get_data(s),
                              cairo_image_surface_get_width(s),
                              cairo_image_surface_get_height(s),
                              cairo_image_surface_get_stride(s),
                              0,
                              0};
}

/* Every pixel of the target opaque white. */
static void paint_white(const RenderDiskTarget *t)
{
    for (int y = 0; y < t->height; ++y)
        for (int x = 0; x < t->width; ++x)
            ((uint32_t *)(t->data + y * t->stride))[x] = 0xffffffffu;
}

/* The largest difference of a channel between Cairo's surface and the filler's target (the same
 * size and stride). */
static int channel_difference(cairo_surface_t *cairo, const RenderDiskTarget *t)
{
    cairo_surface_flush(cairo);
    const uint8_t *pa = cairo_image_surface_get_data(cairo);
    int worst = 0;
    for (int k = 0; k < t->height * t->stride; ++k) {
        const int d = abs((int)pa[k] - (int)t->data[k]);
        worst = d > worst ? d : worst;
    }
    return worst;
}

/* White over transparent black: each pixel's alpha is its coverage in 1/255. The sum is the
 * disk's area (to 0.3 % from a radius of 1.5 px, 1 % below), a pixel inside is whole and
 * nothing outside the disk's square is touched. */
static int coverage_is_area(void)
{
    cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, SIDE, SIDE);
    TEST_ASSERT(cairo_surface_status(s) == CAIRO_STATUS_SUCCESS);
    const RenderDiskTarget t = target_of(s);
    for (int i = 0; i < COUNT(radii); ++i)
        for (int o = 0; o < COUNT(offsets); ++o) {
            memset(t.data, 0, (size_t)t.stride * SIDE);
            const double r = radii[i], cx = 30 + offsets[o][0], cy = 31 + offsets[o][1];
            render_disk_fill(&t, cx, cy, r, 0xffffff);
            double sum = 0;
            int outside = 0;
            for (int y = 0; y < SIDE; ++y)
                for (int x = 0; x < SIDE; ++x) {
                    const uint32_t p = ((const uint32_t *)(t.data + y * t.stride))[x];
                    const int a = (int)(p >> 24);
                    sum += a / 255.0;
                    if (x + 1 < cx - r || x > cx + r || y + 1 < cy - r || y > cy + r)
                        outside |= p != 0;
                    /* a pixel whose far corner is inside the circle is covered whole */
                    const double fx = fmax(fabs(x - cx), fabs(x + 1 - cx));
                    const double fy = fmax(fabs(y - cy), fabs(y + 1 - cy));
                    if (fx * fx + fy * fy < r * r)
                        TEST_ASSERT(p == 0xffffffffu);
                    /* colour and alpha agree (premultiplied white) */
                    TEST_ASSERT((p & 0xff) == (uint32_t)a && ((p >> 16) & 0xff) == (uint32_t)a);
                }
            const double area = SIM_PI * r * r, error = fabs(sum - area) / area;
            if (error > 0.002)
                fprintf(stderr, "r %.1f at +(%.2f, %.2f): area %.4f, coverage %.4f (%.2f %%)\n", r,
                        offsets[o][0], offsets[o][1], area, sum, 100 * error);
            TEST_ASSERT(error < (r >= 1.5 ? 0.003 : 0.01));
            TEST_ASSERT(!outside);
        }
    cairo_surface_destroy(s);
    return 0;
}

/* The same disks filled by Cairo and by the filler, a dark grey on white: every channel within
 * 20 levels (the circle against Cairo's polygon of it, two scan conversions). */
static int close_to_cairo(void)
{
    cairo_surface_t *a = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, SIDE, SIDE);
    cairo_surface_t *b = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, SIDE, SIDE);
    cairo_t *cr = cairo_create(a);
    int worst = 0;
    for (int i = 0; i < COUNT(radii); ++i)
        for (int o = 0; o < COUNT(offsets); ++o) {
            const double r = radii[i], cx = 30 + offsets[o][0], cy = 31 + offsets[o][1];
            cairo_set_source_rgb(cr, 1, 1, 1);
            cairo_paint(cr);
            render_set_rgb(cr, 0x2a2a2a);
            cairo_new_path(cr);
            cairo_arc(cr, cx, cy, r, 0, 2 * SIM_PI);
            cairo_fill(cr);
            const RenderDiskTarget t = target_of(b);
            paint_white(&t);
            render_disk_fill(&t, cx, cy, r, 0x2a2a2a);
            const int d = channel_difference(a, &t);
            worst = d > worst ? d : worst;
            TEST_ASSERT(d <= 20);
        }
    fprintf(stderr, "largest channel difference from Cairo: %d\n", worst);
    cairo_destroy(cr);
    cairo_surface_destroy(a);
    cairo_surface_destroy(b);
    return 0;
}

/* Force chains: capsules (a segment of width 2 r with round caps, as Cairo strokes it) of every
 * slope and length, a point among them: white over transparent black covers 2 r L + pi r^2 (to
 * 0.5 % from r = 0.75 px; 7 % below, where the 16 sub-rows are coarse across the line), and a dark
 * red over white stays within 24 levels of Cairo's stroke of the same line. */
static int capsule_area_and_cairo(void)
{
    static const double segments[][4] = {{20, 30, 44, 30},         {30.3, 18.7, 30.3, 44.2},
                                         {18.2, 21.9, 41.6, 40.1}, {40.5, 20.25, 22.75, 37.5},
                                         {31.4, 29.6, 31.4, 29.6}, {25.1, 33.3, 38.9, 31.2}};
    static const double widths[] = {0.8, 1.5, 3.0, 6.4};
    cairo_surface_t *a = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, SIDE, SIDE);
    cairo_surface_t *b = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, SIDE, SIDE);
    cairo_t *cr = cairo_create(a);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    const RenderDiskTarget t = target_of(b);
    int worst = 0;
    for (int i = 0; i < COUNT(segments); ++i)
        for (int w = 0; w < COUNT(widths); ++w) {
            const double *g = segments[i], r = 0.5 * widths[w];
            memset(t.data, 0, (size_t)t.stride * SIDE);
            render_capsule_fill(&t, g[0], g[1], g[2], g[3], r, 0xffffff);
            double sum = 0;
            for (int y = 0; y < SIDE; ++y)
                for (int x = 0; x < SIDE; ++x)
                    sum += (((const uint32_t *)(t.data + y * t.stride))[x] >> 24) / 255.0;
            const double area = 2 * r * hypot(g[2] - g[0], g[3] - g[1]) + SIM_PI * r * r;
            /* a line 0.8 px wide along a row meets 12 of its 16 sub-rows, not 12.8 */
            TEST_ASSERT(fabs(sum - area) / area < (r >= 0.75 ? 0.005 : 0.07));
            cairo_set_source_rgb(cr, 1, 1, 1);
            cairo_paint(cr);
            render_set_rgb(cr, 0xb2182b);
            cairo_set_line_width(cr, widths[w]);
            cairo_move_to(cr, g[0], g[1]);
            cairo_line_to(cr, g[2], g[3]);
            cairo_stroke(cr);
            paint_white(&t);
            render_capsule_fill(&t, g[0], g[1], g[2], g[3], r, 0xb2182b);
            const int d = channel_difference(a, &t);
            worst = d > worst ? d : worst;
            TEST_ASSERT(d <= 24);
        }
    fprintf(stderr, "largest channel difference from Cairo's stroke: %d\n", worst);
    cairo_destroy(cr);
    cairo_surface_destroy(a);
    cairo_surface_destroy(b);
    return 0;
}

/* A band of an image, the surface over rows [y0, SIDE) with the drawing moved up by y0, gets the
 * bytes of those rows of the whole image, for disks and capsules its top edge cuts. */
static int whole_pixel_moves(void)
{
    uint32_t whole[SIDE * SIDE], band[SIDE * SIDE];
    for (int y0 = 20; y0 <= 40; y0 += 7)
        for (int i = 0; i < COUNT(radii); ++i) {
            for (int k = 0; k < SIDE * SIDE; ++k)
                whole[k] = band[k] = 0xff808080u;
            const RenderDiskTarget all = {(uint8_t *)whole, SIDE, SIDE, 4 * SIDE, 0, 0};
            const RenderDiskTarget part = {(uint8_t *)band, SIDE, SIDE - y0, 4 * SIDE, 0, -y0};
            const double cx = 30.37, cy = y0 + 0.61;
            render_disk_fill(&all, cx, cy, radii[i], 0x1f77b4);
            render_disk_fill(&part, cx, cy, radii[i], 0x1f77b4);
            render_capsule_fill(&all, cx - 9.3, cy - 7.1, cx + 4.2, cy + 3.9, 0.3 * radii[i],
                                0xd6604d);
            render_capsule_fill(&part, cx - 9.3, cy - 7.1, cx + 4.2, cy + 3.9, 0.3 * radii[i],
                                0xd6604d);
            TEST_ASSERT(memcmp(whole + y0 * SIDE, band, (size_t)(SIDE - y0) * 4 * SIDE) == 0);
        }
    return 0;
}

/* A bed that the view cuts on the right: the grains across the plot's edge go to Cairo and its
 * clip, so outside the plot the figure has the bytes of the all-Cairo drawing
 * (SABLIER_CAIRO_DISKS=1), and inside every pixel is within render_diff's tolerance of it. */
static int clip_cuts_with_cairo(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 24, 10, 0.01, 3) == 0);
    RenderStyle s = render_style_default();
    s.width = 480;
    s.height = 300;
    s.color_by = RENDER_COLOR_FORCE;
    s.view_x0 = 0.05;
    s.view_x1 = 0.3333; /* through a column of grains */
    s.view_y0 = 0;
    s.view_y1 = 0.2;
    RenderImage own, cairo;
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &own) == 0);
    setenv("SABLIER_CAIRO_DISKS", "1", 1);
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &cairo) == 0);
    unsetenv("SABLIER_CAIRO_DISKS");
    RenderView v;
    render_view_fit(&f.frame, &s, &v);
    int inside_differs = 0;
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            const size_t at = (size_t)y * (size_t)own.stride + 4 * (size_t)x;
            const int in = x >= v.plot_x + 1 && x + 1 <= v.plot_x + v.plot_w - 1 &&
                           y >= v.plot_y + 1 && y + 1 <= v.plot_y + v.plot_h - 1;
            if (!in && x + 2 >= v.plot_x + v.plot_w) /* right of the cut, and its edge pixels */
                TEST_ASSERT(memcmp(own.pixels + at, cairo.pixels + at, 4) == 0);
            inside_differs |= in && memcmp(own.pixels + at, cairo.pixels + at, 4) != 0;
        }
    TEST_ASSERT(inside_differs); /* the filler drew the grains inside */
    RenderDiffOptions o = render_diff_options_default();
    RenderDiffResult d;
    char err[256];
    TEST_ASSERT(render_diff_images(&own, &cairo, &o, NULL, &d, err, sizeof err) == 0);
    TEST_ASSERT(d.differing_pixels == 0);
    render_image_free(&own);
    render_image_free(&cairo);
    fixture_free(&f);
    return 0;
}

TEST_MAIN(TEST_CASE(coverage_is_area), TEST_CASE(close_to_cairo), TEST_CASE(capsule_area_and_cairo),
          TEST_CASE(whole_pixel_moves), TEST_CASE(clip_cuts_with_cairo))
