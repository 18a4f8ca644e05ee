/* SPDX-License-Identifier: MIT */
/* test_arc_walls.c: arc walls (sim.h SimWall, shape SIM_WALL_ARC) are drawn by Cairo and by the
 * GL drawer: pixels on the arc have the wall colour, pixels off it (the inside, the missing part
 * of a half arc) the background, and the view holds the whole circle. */
#include "fixture.h"
#include "test.h"

#include "render/internal.h"

typedef int DrawFn(const SimFrame *frame, const RenderStyle *style, RenderImage *out);

/* |a - b| <= tol in each channel. */
static int close_rgb(uint32_t a, uint32_t b, int tol)
{
    for (int s = 0; s < 24; s += 8) {
        int d = (int)((a >> s) & 0xff) - (int)((b >> s) & 0xff);
        if (d > tol || d < -tol)
            return 0;
    }
    return 1;
}

/* One grain at the bottom of a drum of radius 1 about the origin; `half`: only its upper half
 * (angles 0 to pi). Checks the drawing of `draw`. */
static int check_drum(DrawFn *draw, int half)
{
    double x = 0.0, y = -0.85, r = 0.1, zero = 0.0;
    int species = 0;
    unsigned flags = 0;
    uint32_t id = 0;
    SimWall wall = {.shape = SIM_WALL_ARC,
                    .side = SIM_WALL_INSIDE,
                    .radius = 1.0,
                    .angle0 = 0.0,
                    .angle1 = half ? SIM_PI : 2.0 * SIM_PI,
                    .motion = -1};
    SimFrame frame = {.count = 1,
                      .mobile_count = 1,
                      .x = &x,
                      .y = &y,
                      .radius = &r,
                      .angle = &zero,
                      .vx = &zero,
                      .vy = &zero,
                      .omega = &zero,
                      .species = &species,
                      .flags = &flags,
                      .id = &id,
                      .force = &zero,
                      .wall_count = 1,
                      .walls = &wall};
    RenderStyle s = render_style_default();
    s.width = 300;
    s.height = 300;
    s.colorbar = s.time_stamp = s.scale_bar = 0;
    s.background_rgb = 0xffffff;
    RenderImage image = {0};
    TEST_ASSERT(draw(&frame, &s, &image) == 0);
    RenderStyle resolved = render_style_resolve(&frame, &s);
    RenderView v;
    render_view_fit(&frame, &resolved, &v);
    double px, py;
    render_view_to_pixel(&v, 0.0, 1.0, &px, &py); /* the top of the circle: on the arc */
    TEST_ASSERT(py > 0.0 && close_rgb(fixture_pixel(&image, px, py), 0x3c3c3c, 40));
    render_view_to_pixel(&v, cos(0.3), sin(0.3), &px, &py);
    TEST_ASSERT(close_rgb(fixture_pixel(&image, px, py), 0x3c3c3c, 40));
    render_view_to_pixel(&v, 0.0, 0.4, &px, &py); /* inside, empty */
    TEST_ASSERT(fixture_pixel(&image, px, py) == 0xffffff);
    render_view_to_pixel(&v, 0.6, -0.8, &px, &py); /* the lower half: drawn unless `half` */
    TEST_ASSERT(py < 300.0);
    uint32_t low = fixture_pixel(&image, px, py);
    TEST_ASSERT(half ? low == 0xffffff : close_rgb(low, 0x3c3c3c, 40));
    render_image_free(&image);
    return 0;
}

static int cairo_draws_arcs(void)
{
    TEST_ASSERT(check_drum(render_cairo_draw, 0) == 0);
    TEST_ASSERT(check_drum(render_cairo_draw, 1) == 0);
    return 0;
}

static int gl_draws_arcs(void)
{
    TEST_ASSERT(check_drum(render_gl_draw, 0) == 0);
    TEST_ASSERT(check_drum(render_gl_draw, 1) == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(cairo_draws_arcs), TEST_CASE(gl_draws_arcs))
