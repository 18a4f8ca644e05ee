/* SPDX-License-Identifier: MIT */
/* Heat maps (render_map.c, 004 fig. 3.4): the pixel at each cell's centre is the colour-map entry
 * of its value, empty cells are white, the range comes from the data or is fixed, the PNG is
 * written under its name only (no temporary left), and bad maps are refused. */
#include "fixture.h"
#include "test.h"

#include <unistd.h>

#define DIR "out/render-tests/map"

static int cell_colours(void)
{
    fixture_mkdirs();
    mkdir(DIR, 0777);
    /* 3 x 2 cells of 5 d, one empty; fixed range [0, 1] */
    double values[6] = {0.0, 0.25, 1.0, 0.5, NAN, 0.75};
    RenderMap map = {.width = 600,
                     .height = 400,
                     .nx = 3,
                     .ny = 2,
                     .x0 = -7.5,
                     .y0 = 0.0,
                     .cell = 5.0,
                     .values = values,
                     .min = 0.0,
                     .max = 1.0,
                     .colormap = RENDER_CMAP_VIRIDIS,
                     .title = "q_s",
                     .x_label = "x / d",
                     .y_label = "y / d",
                     .bar_label = "q_s"};
    char err[512] = "";
    remove(DIR "/map.png");
    TEST_ASSERT(render_map_write(&map, NULL, DIR "/map.png", err, sizeof err) == 0);
    TEST_ASSERT(access(DIR "/map.png.tmp", F_OK) != 0);
    RenderImage image = {0};
    TEST_ASSERT(render_png_read(DIR "/map.png", &image, err, sizeof err) == 0);
    TEST_ASSERT(image.width == 600 && image.height == 400);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i) {
            double px, py, v = values[j * 3 + i];
            TEST_ASSERT(render_map_pixel(&map, -5.0 + 5.0 * i, 2.5 + 5.0 * j, &px, &py) == 0);
            uint32_t want = isfinite(v) ? render_colormap_rgb(RENDER_CMAP_VIRIDIS, v) : 0xffffff;
            if (fixture_pixel(&image, px, py) != want) {
                fprintf(stderr, "cell (%d, %d) at (%g, %g): %06x, expected %06x\n", i, j, px, py,
                        fixture_pixel(&image, px, py), want);
                return 1;
            }
        }
    /* cell (0, 0) is below and left of (1, 1) on the image (y up) */
    double ax, ay, bx, by;
    render_map_pixel(&map, -5.0, 2.5, &ax, &ay);
    render_map_pixel(&map, 0.0, 7.5, &bx, &by);
    TEST_ASSERT(ax < bx && ay > by);
    /* automatic range: [0.25, 0.75] widened to nice numbers [0.2, 0.8] */
    map.min = map.max = 0.0;
    values[0] = 0.25;
    values[2] = 0.75;
    TEST_ASSERT(render_map_write(&map, NULL, DIR "/auto.png", err, sizeof err) == 0);
    render_image_free(&image);
    TEST_ASSERT(render_png_read(DIR "/auto.png", &image, err, sizeof err) == 0);
    double px, py;
    render_map_pixel(&map, 0.0, 2.5, &px, &py); /* value 0.25: (0.25 - 0.2) / 0.6 */
    TEST_ASSERT(fixture_pixel(&image, px, py) ==
                render_colormap_rgb(RENDER_CMAP_VIRIDIS, 0.05 / 0.6));
    render_image_free(&image);
    return 0;
}

/* Dark enough to be an arrow (black antialiased over any viridis entry). */
static int dark(uint32_t rgb)
{
    return ((rgb >> 16) & 255) + ((rgb >> 8) & 255) + (rgb & 255) < 200;
}

/* An arrow field on the cells' centres: a horizontal arrow through the centre of the cell that
 * has one (dark along it, its end beyond the half cell left as the cell's colour), the cell with a
 * zero vector keeps its colour at the centre, and the reference arrow sits under the colour bar. */
static int map_arrows(void)
{
    fixture_mkdirs();
    mkdir(DIR, 0777);
    double values[4] = {0.2, 0.4, 0.6, 0.8}, u[4] = {1.0, 0.0, 0.0, 0.0}, v[4] = {0};
    RenderMap map = {.width = 600,
                     .height = 400,
                     .nx = 2,
                     .ny = 2,
                     .cell = 1.0,
                     .values = values,
                     .min = 0.0,
                     .max = 1.0,
                     .colormap = RENDER_CMAP_VIRIDIS,
                     .bar_label = "speed",
                     .arrow_x = u,
                     .arrow_y = v,
                     .arrow_unit = "m/s"};
    char err[512] = "";
    TEST_ASSERT(render_map_write(&map, NULL, DIR "/arrows.png", err, sizeof err) == 0);
    RenderImage image = {0};
    TEST_ASSERT(render_png_read(DIR "/arrows.png", &image, err, sizeof err) == 0);
    double px, py, qx, qy, ex, ey;
    render_map_pixel(&map, 0.5, 0.5, &px, &py);  /* centre of cell (0, 0): the arrow */
    render_map_pixel(&map, 0.75, 0.5, &ex, &ey); /* on it, towards its head */
    render_map_pixel(&map, 1.5, 1.5, &qx, &qy);  /* centre of cell (1, 1): no arrow */
    TEST_ASSERT(dark(fixture_pixel(&image, px, py)) && dark(fixture_pixel(&image, ex, ey)));
    TEST_ASSERT(fixture_pixel(&image, qx, qy) == render_colormap_rgb(RENDER_CMAP_VIRIDIS, 0.8));
    render_map_pixel(&map, 0.5, 0.97, &qx, &qy); /* above the arrow, inside the cell */
    TEST_ASSERT(fixture_pixel(&image, qx, qy) == render_colormap_rgb(RENDER_CMAP_VIRIDIS, 0.2));
    int reference = 0; /* dark pixels under the colour bar, right of the cells */
    double right, bottom;
    render_map_pixel(&map, 2.0, 0.0, &right, &bottom);
    for (int y = (int)bottom + 2; y < image.height; ++y)
        for (int x = (int)right + 20; x < image.width; ++x)
            reference += dark(fixture_pixel(&image, x, y));
    TEST_ASSERT(reference > 20);
    render_image_free(&image);
    return 0;
}

static int bad_maps(void)
{
    double values[4] = {0.1, 0.2, 0.3, 0.4};
    RenderMap good = {.width = 200, .height = 150, .nx = 2, .ny = 2, .cell = 1.0, .values = values};
    char err[256] = "";
    RenderMap bad = good;
    bad.values = NULL;
    TEST_ASSERT(render_map_write(&bad, NULL, DIR "/bad.png", err, sizeof err) == -1 && err[0]);
    bad = good;
    bad.nx = 0;
    TEST_ASSERT(render_map_write(&bad, NULL, DIR "/bad.png", err, sizeof err) == -1);
    bad = good;
    bad.cell = -1.0;
    TEST_ASSERT(render_map_write(&bad, NULL, DIR "/bad.png", err, sizeof err) == -1);
    bad = good;
    bad.width = 0;
    TEST_ASSERT(render_map_write(&bad, NULL, DIR "/bad.png", err, sizeof err) == -1);
    TEST_ASSERT(render_map_write(NULL, NULL, DIR "/bad.png", err, sizeof err) == -1);
    double px, py;
    TEST_ASSERT(render_map_pixel(&bad, 0, 0, &px, &py) == -1);
    TEST_ASSERT(access(DIR "/bad.png", F_OK) != 0);
    /* an unwritable path fails with a message and leaves nothing */
    TEST_ASSERT(render_map_write(&good, NULL, DIR "/no/such/dir/m.png", err, sizeof err) == -1);
    TEST_ASSERT(err[0]);
    return 0;
}

TEST_MAIN(TEST_CASE(cell_colours), TEST_CASE(map_arrows), TEST_CASE(bad_maps))
