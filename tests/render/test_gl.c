/* SPDX-License-Identifier: MIT */
/* test_gl.c: the OSMesa drawer. Disk colours at centres and background at corners, rows top-down,
 * outlines and force chains, repeatability, size checks, agreement with the Cairo drawer on the
 * same frame (pixels over a threshold that a one-pixel shift does not explain), and the same
 * image from one band as from two (the drawer's two drawing threads). */
#include "test.h"

#include "render/internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

#define OUT_DIR "out/render-tests"

/* Up to 4096 grains on a jittered triangular lattice with contacts between touching neighbours;
 * the last row is fixed (a base). Deterministic (own LCG). */
typedef struct Pack {
    int n, contacts;
    double x[4096], y[4096], r[4096], angle[4096], vx[4096], vy[4096], omega[4096], force[4096];
    int species[4096];
    unsigned flags[4096];
    uint32_t id[4096];
    SimContact contact[3 * 4096];
    SimFrame frame;
} Pack;

static double lcg(uint64_t *state)
{
    *state = *state * 6364136223846793005u + 1442695040888963407u;
    return (double)(*state >> 11) / 9007199254740992.0;
}

static void pack_init(Pack *p, int cols, int rows, double radius)
{
    memset(p, 0, sizeof *p);
    uint64_t seed = 12345;
    int n = 0;
    /* Mobile grains first, then the fixed base row (frame order). */
    for (int pass = 0; pass < 2; ++pass) {
        for (int j = 0; j < rows; ++j) {
            int base = j == 0;
            if (base != pass)
                continue;
            for (int i = 0; i < cols && n < 4096; ++i) {
                p->x[n] = (2 * i + (j % 2)) * radius + radius;
                p->y[n] = j * sqrt(3.0) * radius + radius;
                p->r[n] = radius * (0.92 + 0.08 * lcg(&seed));
                p->angle[n] = 6.283185307179586 * lcg(&seed);
                p->vx[n] = lcg(&seed) - 0.5;
                p->vy[n] = lcg(&seed) - 0.5;
                p->species[n] = (i / 3 + j / 2) % 3;
                p->flags[n] = base ? SIM_GRAIN_FIXED : 0;
                p->id[n] = (uint32_t)n;
                ++n;
            }
        }
    }
    p->n = n;
    int c = 0;
    for (int a = 0; a < n; ++a) {
        for (int b = a + 1; b < n; ++b) {
            double dx = p->x[b] - p->x[a], dy = p->y[b] - p->y[a];
            if (dx * dx + dy * dy < 4.4 * radius * radius && c < 3 * 4096) {
                double f = 0.2 + 2.0 * lcg(&seed) * lcg(&seed);
                p->contact[c++] = (SimContact){.i = a,
                                               .j = b,
                                               .normal_force = f,
                                               .x = 0.5 * (p->x[a] + p->x[b]),
                                               .y = 0.5 * (p->y[a] + p->y[b])};
                p->force[a] += f;
                p->force[b] += f;
            }
        }
    }
    p->contacts = c;
    p->frame = (SimFrame){.count = n,
                          .mobile_count = n - cols,
                          .x = p->x,
                          .y = p->y,
                          .angle = p->angle,
                          .radius = p->r,
                          .vx = p->vx,
                          .vy = p->vy,
                          .omega = p->omega,
                          .species = p->species,
                          .flags = p->flags,
                          .id = p->id,
                          .force = p->force,
                          .contact_count = c,
                          .contacts = p->contact};
}

/* The grain layer only (no annotations), over a fixed world window. */
static RenderStyle plain_style(int width, int height, double x1, double y1)
{
    RenderStyle style = render_style_default();
    style.width = width;
    style.height = height;
    style.view_x0 = 0.0;
    style.view_y0 = 0.0;
    style.view_x1 = x1;
    style.view_y1 = y1;
    style.colorbar = 0;
    style.time_stamp = 0;
    style.scale_bar = 0;
    style.title = NULL;
    style.outline = 0;
    return style;
}

static uint32_t pixel_rgb(const RenderImage *image, double x, double y)
{
    uint8_t c[4];
    render_image_get_rgba(image, (int)x, (int)y, c);
    return (uint32_t)c[0] << 16 | (uint32_t)c[1] << 8 | c[2];
}

static int close_rgb(uint32_t a, uint32_t b, int tolerance)
{
    for (int s = 0; s < 24; s += 8) {
        int d = (int)(a >> s & 255) - (int)(b >> s & 255);
        if (d > tolerance || d < -tolerance)
            return 0;
    }
    return 1;
}

/* Three separated disks: species colours at their centres, background in the corners. */
typedef struct Three {
    double x[3], y[3], r[3], force[3];
    int species[3];
    unsigned flags[3];
    uint32_t id[3];
    SimContact contact[1];
    SimFrame frame;
} Three;

static void three_init(Three *t)
{
    memset(t, 0, sizeof *t);
    /* World 4 x 3 m: disk 0 high on the left, disk 1 low on the right, disk 2 fixed. */
    double x[3] = {1.0, 3.0, 2.0}, y[3] = {2.2, 0.8, 1.5};
    for (int i = 0; i < 3; ++i) {
        t->x[i] = x[i];
        t->y[i] = y[i];
        t->r[i] = 0.4;
        t->species[i] = i;
        t->id[i] = (uint32_t)i;
        t->force[i] = 1.0;
    }
    t->flags[2] = SIM_GRAIN_FIXED;
    t->contact[0] = (SimContact){.i = 0, .j = 1, .normal_force = 3.0, .x = 2.0, .y = 1.5};
    t->frame = (SimFrame){.count = 3,
                          .mobile_count = 2,
                          .x = t->x,
                          .y = t->y,
                          .radius = t->r,
                          .species = t->species,
                          .flags = t->flags,
                          .id = t->id,
                          .force = t->force,
                          .contact_count = 1,
                          .contacts = t->contact};
}

static int gl_disk_colours(void)
{
    Three t;
    three_init(&t);
    RenderStyle style = plain_style(400, 300, 4.0, 3.0);
    style.color_by = RENDER_COLOR_SPECIES;
    style.background_rgb = 0xf0f0e0;
    style.fixed_rgb = 0x505050;
    RenderImage image = {0};
    TEST_ASSERT(render_gl_draw(&t.frame, &style, &image) == 0);
    TEST_ASSERT(image.width == 400 && image.height == 300 &&
                image.format == RENDER_PIXEL_BGRA_PREMUL);
    RenderStyle resolved = render_style_resolve(&t.frame, &style);
    RenderView view;
    render_view_fit(&t.frame, &resolved, &view);
    double px[3], py[3];
    for (int i = 0; i < 3; ++i)
        render_view_to_pixel(&view, t.x[i], t.y[i], &px[i], &py[i]);
    /* Rows are top-down: the higher disk 0 lies in the upper half of the image. */
    TEST_ASSERT(py[0] < 150.0 && py[1] > 150.0);
    TEST_ASSERT(close_rgb(pixel_rgb(&image, px[0], py[0]), render_species_rgb(0), 1));
    TEST_ASSERT(close_rgb(pixel_rgb(&image, px[1], py[1]), render_species_rgb(1), 1));
    TEST_ASSERT(close_rgb(pixel_rgb(&image, px[2], py[2]), 0x505050, 1)); /* fixed grain */
    TEST_ASSERT(pixel_rgb(&image, 0, 0) == 0xf0f0e0);
    TEST_ASSERT(pixel_rgb(&image, 399, 0) == 0xf0f0e0);
    TEST_ASSERT(pixel_rgb(&image, 0, 299) == 0xf0f0e0);
    TEST_ASSERT(pixel_rgb(&image, 399, 299) == 0xf0f0e0);
    /* Just outside a rim: background; the image is opaque everywhere. */
    double rim = view.scale * t.r[0];
    TEST_ASSERT(pixel_rgb(&image, px[0] + rim + 2.0, py[0]) == 0xf0f0e0);
    uint8_t rgba[4];
    render_image_get_rgba(&image, (int)(px[0] + rim), (int)py[0], rgba);
    TEST_ASSERT(rgba[3] == 255);
    render_image_free(&image);
    return 0;
}

static int gl_outline_and_chains(void)
{
    Three t;
    three_init(&t);
    RenderStyle style = plain_style(400, 300, 4.0, 3.0);
    style.color_by = RENDER_COLOR_FIXED;
    style.fill_rgb = 0xe0c080;
    RenderImage plain = {0}, decorated = {0};
    TEST_ASSERT(render_gl_draw(&t.frame, &style, &plain) == 0);
    style.outline = 1;
    style.force_chains = 1;
    style.chain_threshold = 0.5;
    style.chain_width_max = 6.0;
    TEST_ASSERT(render_gl_draw(&t.frame, &style, &decorated) == 0);
    RenderStyle resolved = render_style_resolve(&t.frame, &style);
    RenderView view;
    render_view_fit(&t.frame, &resolved, &view);
    double x0, y0, x1, y1;
    render_view_to_pixel(&view, t.x[0], t.y[0], &x0, &y0);
    render_view_to_pixel(&view, t.x[1], t.y[1], &x1, &y1);
    /* Chain 0-1 passes over the background between the disks (a quarter of the way along,
     * clear of disk 2 in the middle). */
    double qx = x0 + 0.25 * (x1 - x0), qy = y0 + 0.25 * (y1 - y0);
    TEST_ASSERT(pixel_rgb(&plain, qx, qy) == resolved.background_rgb);
    /* The only contact is the strongest: the dark end of the yellow-red map (render_cairo.c). */
    uint32_t chain = pixel_rgb(&decorated, qx, qy);
    TEST_ASSERT(close_rgb(chain, render_colormap_rgb(RENDER_CMAP_YELLOW_RED, 1.0), 1));
    /* The outline darkens the rim; the middle of the disk keeps the fill. */
    double rim = view.scale * t.r[0];
    double top = y0 - rim + 1.0;
    uint32_t plain_rim = pixel_rgb(&plain, x0, top), outlined_rim = pixel_rgb(&decorated, x0, top);
    TEST_ASSERT((outlined_rim >> 8 & 255) + 60 < (plain_rim >> 8 & 255));
    TEST_ASSERT(pixel_rgb(&decorated, x0 - 0.5 * rim, y0) == 0xe0c080);
    render_image_free(&plain);
    render_image_free(&decorated);
    return 0;
}

/* 0 when the pixels centred on the axes from (px[0], py[0]) to (px[c], py[c]), c = 1..chains
 * (ends and seven pixels between them), are `rgb` within 2 levels; else 1, naming the first
 * pixel that is not. */
static int axes_in_colour(const RenderImage *image, const double *px, const double *py, int chains,
                          uint32_t rgb)
{
    for (int c = 1; c <= chains; ++c) {
        for (int k = 0; k <= 8; ++k) {
            double qx = px[0] + (px[c] - px[0]) * k / 8.0;
            double qy = py[0] + (py[c] - py[0]) * k / 8.0;
            if (!close_rgb(pixel_rgb(image, qx, qy), rgb, 2)) {
                printf("chain %d, pixel (%g, %g): %06x, not %06x\n", c, qx, qy,
                       (unsigned)pixel_rgb(image, qx, qy), (unsigned)rgb);
                return 1;
            }
        }
    }
    return 0;
}

/* Shapes whose centres and axes fall on pixel centres, where a pixel's offset from the centre or
 * axis is exactly zero: the disk's centre pixel keeps the fill, and every pixel centred on a
 * chain's axis (horizontal, vertical, diagonal; ends included; wide and 1 px chains) is the
 * chain's colour. */
static int gl_pixel_aligned_shapes(void)
{
    static double x[5], y[5], r[5], force[5];
    static int species[5];
    static unsigned flags[5];
    static uint32_t id[5];
    static SimContact contact[4];
    /* Pixel centres of the grains: a middle one with neighbours right, below, and on both
     * diagonals (image rows down). */
    static const double px[5] = {100.5, 140.5, 100.5, 128.5, 72.5};
    static const double py[5] = {100.5, 100.5, 140.5, 128.5, 128.5};
    RenderStyle style = plain_style(200, 200, 2.0, 2.0);
    style.color_by = RENDER_COLOR_FIXED;
    style.fill_rgb = 0xe0c080;
    style.force_chains = 1;
    style.chain_threshold = 0.5;
    style.chain_width_max = 3.0;
    SimFrame frame = {.count = 5,
                      .mobile_count = 5,
                      .x = x,
                      .y = y,
                      .radius = r,
                      .species = species,
                      .flags = flags,
                      .id = id,
                      .force = force,
                      .contact_count = 4,
                      .contacts = contact};
    for (int i = 0; i < 5; ++i) { /* any positions, to read the view's mapping */
        x[i] = 0.4 * i;
        y[i] = 0.4 * i;
        r[i] = 0.1;
        id[i] = (uint32_t)i;
    }
    RenderView view;
    render_view_fit(&frame, &style, &view);
    double ox, oy, ux, uy; /* pixel of world (0, 0) and of (1, 1) */
    render_view_to_pixel(&view, 0.0, 0.0, &ox, &oy);
    render_view_to_pixel(&view, 1.0, 1.0, &ux, &uy);
    for (int i = 0; i < 5; ++i) {
        x[i] = (px[i] - ox) / (ux - ox);
        y[i] = (py[i] - oy) / (uy - oy);
        r[i] = 9.0 / (ux - ox); /* 9 px */
    }
    for (int c = 0; c < 4; ++c)
        contact[c] = (SimContact){.i = 0,
                                  .j = c + 1,
                                  .normal_force = 2.0,
                                  .x = 0.5 * (x[0] + x[c + 1]),
                                  .y = 0.5 * (y[0] + y[c + 1])};
    RenderImage image = {0};
    TEST_ASSERT(render_gl_draw(&frame, &style, &image) == 0);
    uint32_t chain = render_colormap_rgb(RENDER_CMAP_YELLOW_RED, 1.0);
    TEST_ASSERT(axes_in_colour(&image, px, py, 4, chain) == 0);
    render_image_free(&image);
    /* Chains 1 px wide (the two-edge program): a pixel centred on a horizontal or vertical axis
     * is covered whole. */
    style.chain_width_max = 1.0;
    TEST_ASSERT(render_gl_draw(&frame, &style, &image) == 0);
    TEST_ASSERT(axes_in_colour(&image, px, py, 2, chain) == 0);
    render_image_free(&image);
    /* Without chains the centre pixel is the fill, its neighbours too. */
    style.force_chains = 0;
    TEST_ASSERT(render_gl_draw(&frame, &style, &image) == 0);
    for (int i = 0; i < 5; ++i) {
        TEST_ASSERT(pixel_rgb(&image, px[i], py[i]) == 0xe0c080);
        TEST_ASSERT(pixel_rgb(&image, px[i] + 1.0, py[i]) == 0xe0c080);
    }
    render_image_free(&image);
    return 0;
}

/* A persistent drawer gives the same pixels twice; a style of another size is refused. */
static int gl_repeatable_and_sized(void)
{
    static Pack pack;
    pack_init(&pack, 60, 40, 0.01);
    char err[256];
    RenderGl *gl = render_gl_create(640, 360, err, sizeof err);
    TEST_ASSERT(gl != NULL);
    printf("GL renderer: %s\n", render_gl_renderer(gl));
    RenderStyle style = plain_style(640, 360, 0.0, 0.0); /* fit all grains */
    style.color_by = RENDER_COLOR_FORCE;
    style.force_chains = 1;
    style.outline = 1;
    RenderImage a, b;
    TEST_ASSERT(render_gl_frame(gl, &pack.frame, &style, &a, err, sizeof err) == 0);
    size_t bytes = (size_t)a.stride * (size_t)a.height;
    uint8_t *copy = malloc(bytes);
    TEST_ASSERT(copy != NULL);
    memcpy(copy, a.pixels, bytes);
    TEST_ASSERT(render_gl_frame(gl, &pack.frame, &style, &b, err, sizeof err) == 0);
    TEST_ASSERT(memcmp(copy, b.pixels, bytes) == 0);
    /* Grains cover much of the canvas. */
    long covered = 0;
    for (int y = 0; y < b.height; ++y)
        for (int x = 0; x < b.width; ++x)
            covered += pixel_rgb(&b, x, y) != style.background_rgb;
    TEST_ASSERT(covered > (long)b.width * b.height / 4);
    free(copy);
    style.width = 320;
    TEST_ASSERT(render_gl_frame(gl, &pack.frame, &style, &b, err, sizeof err) != 0);
    TEST_ASSERT(strstr(err, "320x360") != NULL);
    render_gl_destroy(gl);
    TEST_ASSERT(render_gl_create(0, 10, err, sizeof err) == NULL);
    return 0;
}

/* Pixels of a differing by more than `threshold` (max channel) from b at the same place and at
 * every neighbour within one pixel: differences a one-pixel shift does not explain. */
static long unexplained_pixels(const RenderImage *a, const RenderImage *b, int threshold,
                               int *max_diff)
{
    long count = 0;
    *max_diff = 0;
    for (int y = 0; y < a->height; ++y) {
        for (int x = 0; x < a->width; ++x) {
            uint8_t pa[4], pb[4];
            render_image_get_rgba(a, x, y, pa);
            int best = 256;
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    int u = x + dx, v = y + dy;
                    if (u < 0 || v < 0 || u >= b->width || v >= b->height)
                        continue;
                    render_image_get_rgba(b, u, v, pb);
                    int d = 0;
                    for (int c = 0; c < 4; ++c) {
                        int e = abs(pa[c] - pb[c]);
                        d = e > d ? e : d;
                    }
                    if (dx == 0 && dy == 0 && d > *max_diff)
                        *max_diff = d;
                    best = d < best ? d : best;
                }
            }
            count += best > threshold;
        }
    }
    return count;
}

/* The two drawers agree on the same frame within the image-diff tolerance (T = 32, one-pixel
 * shift; anchors-render 3.2 measured 0 such pixels for a renderer swap). */
static int gl_matches_cairo(void)
{
    static Pack pack;
    pack_init(&pack, 40, 30, 0.01);
    mkdir("out", 0755);
    mkdir(OUT_DIR, 0755);
    static const RenderColorBy modes[] = {RENDER_COLOR_FORCE, RENDER_COLOR_SPECIES};
    for (int m = 0; m < 2; ++m) {
        RenderStyle style = plain_style(480, 360, 0.0, 0.0);
        style.color_by = modes[m];
        style.force_chains = 1;
        style.outline = 1;
        style.orientation_tick = m == 1;
        RenderImage gl = {0}, cairo = {0};
        TEST_ASSERT(render_gl_draw(&pack.frame, &style, &gl) == 0);
        TEST_ASSERT(render_cairo_draw(&pack.frame, &style, &cairo) == 0);
        TEST_ASSERT(gl.width == cairo.width && gl.height == cairo.height);
        char err[256], path[128];
        snprintf(path, sizeof path, OUT_DIR "/gl_vs_cairo_%d_gl.png", m);
        render_png_write(&gl, path, NULL, err, sizeof err);
        snprintf(path, sizeof path, OUT_DIR "/gl_vs_cairo_%d_cairo.png", m);
        render_png_write(&cairo, path, NULL, err, sizeof err);
        int max_ab = 0, max_ba = 0;
        long ab = unexplained_pixels(&gl, &cairo, 32, &max_ab);
        long ba = unexplained_pixels(&cairo, &gl, 32, &max_ba);
        printf("mode %d: unexplained %ld / %ld pixels, max channel difference %d\n", m, ab, ba,
               max_ab);
        TEST_ASSERT(ab == 0 && ba == 0);
        render_image_free(&gl);
        render_image_free(&cairo);
    }
    return 0;
}

/* Unexplained pixels both ways between a GL image and Cairo's drawing of the same frame. */
static long disagreement(const RenderImage *gl, const RenderImage *cairo, const char *name)
{
    char err[256], path[160];
    snprintf(path, sizeof path, OUT_DIR "/%s_gl.png", name);
    render_png_write(gl, path, NULL, err, sizeof err);
    snprintf(path, sizeof path, OUT_DIR "/%s_cairo.png", name);
    render_png_write(cairo, path, NULL, err, sizeof err);
    int max_ab = 0, max_ba = 0;
    long ab = unexplained_pixels(gl, cairo, 32, &max_ab);
    long ba = unexplained_pixels(cairo, gl, 32, &max_ba);
    printf("%s: unexplained %ld / %ld pixels, max channel difference %d\n", name, ab, ba, max_ab);
    return ab + ba;
}

/* An OSMesa frame with render_cairo_overlay (colour bar, time stamp, scale bar, title, velocity
 * arrows and field, arches) agrees with Cairo's full drawing; the overlay keeps an RGBA image
 * RGBA with the same pixels. */
static int gl_overlay_matches_cairo(void)
{
    static Pack pack;
    pack_init(&pack, 40, 30, 0.01);
    mkdir("out", 0755);
    mkdir(OUT_DIR, 0755);
    static int arch[4096];
    for (int i = 0; i < pack.n; ++i)
        arch[i] = i >= 100 && i < 106 ? 0 : i >= 300 && i < 304 ? 1 : -1;
    pack.frame.time = 0.125;
    pack.frame.time_scale = 0.01;
    for (int m = 0; m < 2; ++m) {
        RenderStyle style = render_style_default();
        style.width = 640;
        style.height = 400;
        style.color_by = m == 0 ? RENDER_COLOR_FORCE : RENDER_COLOR_SPECIES;
        style.force_chains = 1;
        style.outline = 1;
        style.title = "overlay on an OSMesa frame";
        style.velocity_arrows = m == 0;
        style.velocity_field = m == 1;
        style.arch_ids = arch;
        RenderImage gl = {0}, cairo = {0};
        TEST_ASSERT(render_gl_draw(&pack.frame, &style, &gl) == 0);
        TEST_ASSERT(render_cairo_overlay(&pack.frame, &style, &gl) == 0);
        TEST_ASSERT(gl.format == RENDER_PIXEL_BGRA_PREMUL);
        TEST_ASSERT(render_cairo_draw(&pack.frame, &style, &cairo) == 0);
        TEST_ASSERT(disagreement(&gl, &cairo, m == 0 ? "overlay_force" : "overlay_species") == 0);
        /* The same overlay on an RGBA copy of the grain layer. */
        RenderImage layer = {0}, rgba = {0};
        TEST_ASSERT(render_gl_draw(&pack.frame, &style, &layer) == 0);
        TEST_ASSERT(render_image_alloc(&rgba, layer.width, layer.height, RENDER_PIXEL_RGBA) == 0);
        for (int y = 0; y < layer.height; ++y)
            for (int x = 0; x < layer.width; ++x)
                render_image_get_rgba(&layer, x, y,
                                      rgba.pixels + (size_t)y * (size_t)rgba.stride + 4 * x);
        TEST_ASSERT(render_cairo_overlay(&pack.frame, &style, &rgba) == 0);
        TEST_ASSERT(rgba.format == RENDER_PIXEL_RGBA);
        long same = 0;
        for (int y = 0; y < gl.height; ++y)
            for (int x = 0; x < gl.width; ++x)
                same += pixel_rgb(&gl, x, y) == pixel_rgb(&rgba, x, y);
        TEST_ASSERT(same == (long)gl.width * gl.height);
        /* Without annotations asked for, the overlay leaves the image alone. */
        RenderStyle bare = plain_style(640, 400, 0.0, 0.0);
        TEST_ASSERT(render_cairo_overlay(&pack.frame, &bare, &rgba) == 0);
        TEST_ASSERT(pixel_rgb(&rgba, 320, 200) == pixel_rgb(&gl, 320, 200));
        bare.width = 320; /* wrong size */
        TEST_ASSERT(render_cairo_overlay(&pack.frame, &bare, &rgba) != 0);
        render_image_free(&layer);
        render_image_free(&rgba);
        render_image_free(&gl);
        render_image_free(&cairo);
    }
    return 0;
}

/* The paths beside the point sprites: disks too large for a sprite (instanced quads), disks
 * whose centres lie outside the image (the viewport margin), primitives crossing the plot
 * clip (the CLIP shader variants), a caller's target image; all agree with Cairo. */
static int gl_large_edge_and_clipped(void)
{
    Three t;
    three_init(&t);
    mkdir("out", 0755);
    mkdir(OUT_DIR, 0755);
    /* A window over the left part: disk 0 (centre x = 1) is cut by the left edge of the plot,
     * its centre is outside the image; the chain is cut too. */
    RenderStyle style = plain_style(400, 300, 3.3, 2.6);
    style.view_x0 = 1.3;
    style.view_y0 = 1.4;
    style.color_by = RENDER_COLOR_SPECIES;
    style.force_chains = 1;
    style.chain_threshold = 0.5;
    style.chain_width_max = 4.0;
    style.outline = 1;
    RenderStyle resolved = render_style_resolve(&t.frame, &style);
    RenderView view;
    render_view_fit(&t.frame, &resolved, &view);
    double px, py;
    render_view_to_pixel(&view, t.x[0], t.y[0], &px, &py);
    TEST_ASSERT(px < 0.0 && px + view.scale * t.r[0] > view.plot_x + 5.0); /* partly visible */
    TEST_ASSERT(view.scale * t.r[0] * 2.0 < 255.0);                        /* still sprites */
    char err[256];
    RenderGl *gl = render_gl_create(400, 300, err, sizeof err);
    TEST_ASSERT(gl != NULL);
    RenderImage target = {0}, cairo = {0};
    TEST_ASSERT(render_image_alloc(&target, 400, 300, RENDER_PIXEL_RGBA) == 0);
    TEST_ASSERT(render_gl_frame_to(gl, &t.frame, &style, &target, err, sizeof err) == 0);
    TEST_ASSERT(target.format == RENDER_PIXEL_BGRA_PREMUL);
    TEST_ASSERT(render_cairo_draw(&t.frame, &style, &cairo) == 0);
    TEST_ASSERT(disagreement(&target, &cairo, "edge_clipped") == 0);
    /* Disk 0 is drawn: its visible part at the plot's left edge has its species colour. */
    TEST_ASSERT(close_rgb(pixel_rgb(&target, view.plot_x + 2.0, py), render_species_rgb(0), 1));
    render_image_free(&cairo);
    /* Huge disks: a close-up where radii exceed the largest sprite. */
    RenderStyle zoom = plain_style(400, 300, 1.4, 2.6);
    zoom.view_x0 = 0.6;
    zoom.view_y0 = 1.8;
    zoom.outline = 1;
    resolved = render_style_resolve(&t.frame, &zoom);
    render_view_fit(&t.frame, &resolved, &view);
    TEST_ASSERT(view.scale * t.r[0] * 2.0 > 256.0);
    TEST_ASSERT(render_gl_frame_to(gl, &t.frame, &zoom, &target, err, sizeof err) == 0);
    TEST_ASSERT(render_cairo_draw(&t.frame, &zoom, &cairo) == 0);
    TEST_ASSERT(disagreement(&target, &cairo, "huge_disks") == 0);
    render_view_to_pixel(&view, t.x[0], t.y[0], &px, &py);
    TEST_ASSERT(close_rgb(pixel_rgb(&target, px, py), resolved.fill_rgb, 1));
    /* A target of another size is refused. */
    RenderImage small = {0};
    TEST_ASSERT(render_image_alloc(&small, 200, 300, RENDER_PIXEL_RGBA) == 0);
    TEST_ASSERT(render_gl_frame_to(gl, &t.frame, &zoom, &small, err, sizeof err) != 0);
    render_image_free(&small);
    render_image_free(&cairo);
    render_image_free(&target);
    render_gl_destroy(gl);
    return 0;
}

/* Draws a frame with a new drawer of `bands` bands (SABLIER_BANDS); 0 on success. */
static int draw_banded(const SimFrame *frame, const RenderStyle *style, const char *bands,
                       RenderImage *out)
{
    setenv("SABLIER_BANDS", bands, 1);
    int rc = render_gl_draw(frame, style, out);
    unsetenv("SABLIER_BANDS");
    return rc;
}

/* Largest channel difference between two images of one size. */
static int max_difference(const RenderImage *a, const RenderImage *b)
{
    int most = 0;
    for (int y = 0; y < a->height; ++y) {
        for (int x = 0; x < a->width; ++x) {
            uint8_t pa[4], pb[4];
            render_image_get_rgba(a, x, y, pa);
            render_image_get_rgba(b, x, y, pb);
            for (int c = 0; c < 4; ++c)
                most = abs(pa[c] - pb[c]) > most ? abs(pa[c] - pb[c]) : most;
        }
    }
    return most;
}

/* The drawer splits the image into two bands drawn by two threads: the split is invisible (the
 * same pixels as one band, up to rounding of the segment quads' vertices), on a periodic frame
 * with ticks, walls and chains crossing the band edge; chains too wide for a line (quads) still
 * agree with Cairo. */
static int gl_bands_agree(void)
{
    static Pack pack;
    pack_init(&pack, 40, 30, 0.01);
    mkdir("out", 0755);
    mkdir(OUT_DIR, 0755);
    /* Walls inside the domain, one across the band edge (where a wall's end meets the plot clip
     * the GL coverage, a product of two coverages, is darker than Cairo's at the corner). */
    SimWall walls[2] = {{.x0 = 0.1, .y0 = 0.26, .x1 = 0.7, .y1 = 0.26},
                        {.x0 = 0.1, .y0 = 0.1, .x1 = 0.7, .y1 = 0.45}};
    pack.frame.walls = walls;
    pack.frame.wall_count = 2;
    pack.frame.periodic = 1;
    pack.frame.domain_x0 = 0.0;
    pack.frame.domain_x1 = 0.8;
    RenderStyle style = plain_style(480, 360, 0.0, 0.0);
    style.color_by = RENDER_COLOR_FORCE;
    style.force_chains = 1;
    style.outline = 1;
    style.orientation_tick = 1;
    RenderImage one = {0}, two = {0}, cairo = {0};
    TEST_ASSERT(draw_banded(&pack.frame, &style, "1", &one) == 0);
    TEST_ASSERT(draw_banded(&pack.frame, &style, "2", &two) == 0);
    int most = max_difference(&one, &two);
    printf("one band vs two: max channel difference %d\n", most);
    TEST_ASSERT(most <= 2);
    TEST_ASSERT(render_cairo_draw(&pack.frame, &style, &cairo) == 0);
    TEST_ASSERT(disagreement(&two, &cairo, "bands_periodic") == 0);
    render_image_free(&one);
    render_image_free(&two);
    render_image_free(&cairo);
    /* Chains wider than llvmpipe's widest line (255 px) are drawn as quads. */
    pack.frame.walls = NULL;
    pack.frame.wall_count = 0;
    pack.frame.periodic = 0;
    style = plain_style(480, 360, 0.0, 0.0);
    style.force_chains = 1;
    style.chain_threshold = 1.5;
    style.chain_width_max = 300.0;
    TEST_ASSERT(draw_banded(&pack.frame, &style, "2", &two) == 0);
    TEST_ASSERT(render_cairo_draw(&pack.frame, &style, &cairo) == 0);
    TEST_ASSERT(disagreement(&two, &cairo, "bands_wide_chains") == 0);
    render_image_free(&two);
    render_image_free(&cairo);
    return 0;
}

TEST_MAIN(TEST_CASE(gl_disk_colours), TEST_CASE(gl_outline_and_chains),
          TEST_CASE(gl_pixel_aligned_shapes), TEST_CASE(gl_repeatable_and_sized),
          TEST_CASE(gl_matches_cairo), TEST_CASE(gl_overlay_matches_cairo),
          TEST_CASE(gl_large_edge_and_clipped), TEST_CASE(gl_bands_agree))
