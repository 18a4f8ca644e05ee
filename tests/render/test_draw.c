/* SPDX-License-Identifier: MIT */
/* Cairo frame drawing: reference images for each drawing feature (compared with our own diff),
 * plus pixel probes that pin colours and positions numerically. */
#include "fixture.h"
#include "test.h"

#include "render/internal.h"

#include <pthread.h>

static RenderStyle quiet_style(int w, int h)
{
    RenderStyle s = render_style_default();
    s.width = w;
    s.height = h;
    s.colorbar = 0;
    s.time_stamp = 0;
    s.scale_bar = 0;
    return s;
}

static int draw_and_check(const char *name, const Fixture *f, const RenderStyle *s)
{
    RenderImage image;
    TEST_ASSERT(render_cairo_draw(&f->frame, s, &image) == 0);
    TEST_ASSERT(image.format == RENDER_PIXEL_BGRA_PREMUL);
    TEST_ASSERT(image.width == s->width && image.height == s->height);
    int rc = fixture_check_reference(name, &image);
    render_image_free(&image);
    return rc;
}

/* Flat disks with outlines and orientation ticks, fixed base grains, side walls. */
static int grains_fixed(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 1) == 0);
    RenderStyle s = quiet_style(320, 240);
    s.orientation_tick = 1;
    int rc = draw_and_check("grains_fixed", &f, &s);
    fixture_free(&f);
    return rc;
}

/* Grain fill = colour map of the per-grain force, fixed range, viridis. */
static int grains_force_viridis(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 2) == 0);
    RenderStyle s = quiet_style(320, 240);
    s.color_by = RENDER_COLOR_FORCE;
    s.range_min = 0;
    s.range_max = 8;
    int rc = draw_and_check("grains_force_viridis", &f, &s);
    fixture_free(&f);
    return rc;
}

/* Strong force network on grey grains, including wall contacts drawn to the contact point. */
static int force_chains(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 3) == 0);
    int top = 0;
    for (int i = 0; i < f.frame.mobile_count; ++i)
        if (f.y[i] < f.y[top] || (f.y[i] == f.y[top] && f.x[i] < f.x[top]))
            top = i;
    fixture_contact(&f, top, -1, 4.0, 0, f.y[top]); /* left wall */
    RenderStyle s = quiet_style(320, 240);
    s.color_by = RENDER_COLOR_FORCE;
    s.colormap = RENDER_CMAP_GREYS;
    s.range_min = 0;
    s.range_max = 12;
    s.force_chains = 1;
    int rc = draw_and_check("force_chains", &f, &s);
    fixture_free(&f);
    return rc;
}

/* Per-grain velocity arrows and the coarse-grained field. */
static int velocity_arrows(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 4) == 0);
    RenderStyle s = quiet_style(320, 240);
    s.velocity_arrows = 1;
    s.arrow_scale = 0; /* auto: the fastest grain gets an arrow of 2 mean diameters */
    int rc = draw_and_check("velocity_arrows", &f, &s);
    s.velocity_arrows = 0;
    s.velocity_field = 1;
    s.fill_rgb = 0xe8e0cc;
    rc |= draw_and_check("velocity_field", &f, &s);
    fixture_free(&f);
    return rc;
}

/* Two arches outlined, polylines through their centres, zoomed inset. */
static int arches(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 30, 10, 0.01, 5) == 0);
    int *ids = malloc((size_t)f.frame.count * sizeof *ids);
    TEST_ASSERT(ids);
    double h = 0.02 * sqrt(3.0) / 2;
    for (int i = 0; i < f.frame.count; ++i) {
        ids[i] = -1;
        if (f.flags[i])
            continue;
        int row = (int)((f.y[i] - 0.02) / h + 0.5);
        double x = f.x[i];
        if (row == 3 && x > 0.25 && x < 0.33)
            ids[i] = 0; /* a flat arch on two lower feet */
        if (row == 2 && ((x > 0.225 && x < 0.245) || (x > 0.325 && x < 0.345)))
            ids[i] = 0;
        if (row == 5 && x > 0.27 && x < 0.32)
            ids[i] = 1;
    }
    RenderStyle s = quiet_style(480, 200);
    s.arch_ids = ids;
    s.arch_inset = 1;
    s.fill_rgb = 0xcfcfcf;
    int rc = draw_and_check("arches", &f, &s);
    free(ids);
    fixture_free(&f);
    return rc;
}

/* Periodic in x: grains crossing the seam appear on both sides, clipped to the domain, and a
 * contact across the seam is drawn as two half segments. */
static int periodic_seam(void)
{
    Fixture f;
    TEST_ASSERT(fixture_init(&f, 16, 16, 6) == 0);
    f.frame.periodic = 1;
    f.frame.domain_x0 = 0;
    f.frame.domain_x1 = 0.2;
    int a = fixture_add(&f, 0.003, 0.05, 0.012, 0);  /* crosses the left edge */
    int b = fixture_add(&f, 0.1955, 0.06, 0.012, 0); /* crosses the right edge */
    int c = fixture_add(&f, 0.1, 0.05, 0.02, 0);
    fixture_add(&f, 0.1, 0.01, 0.01, SIM_GRAIN_FIXED);
    fixture_contact(&f, a, b, 5.0, 0.0, 0.055);
    fixture_contact(&f, a, c, 1.0, 0.05, 0.05);
    f.species[b] = 1;
    RenderStyle s = quiet_style(320, 160);
    s.color_by = RENDER_COLOR_SPECIES;
    s.force_chains = 1;
    s.chain_threshold = 0;
    s.chain_width_max = 4;
    s.view_x0 = -0.02;
    s.view_x1 = 0.22;
    s.view_y0 = 0;
    s.view_y1 = 0.1;
    RenderImage image;
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &image) == 0);
    RenderView v;
    render_view_fit(&f.frame, &s, &v);
    double px, py;
    /* The right grain's copy at x - L = -0.0045 shows inside the domain. */
    render_view_to_pixel(&v, 0.002, 0.066, &px, &py);
    TEST_ASSERT(fixture_pixel(&image, px, py) == render_species_rgb(1));
    /* Outside the domain (x < 0) nothing is drawn: background. */
    render_view_to_pixel(&v, -0.004, 0.05, &px, &py);
    TEST_ASSERT(fixture_pixel(&image, px, py) == 0xffffff);
    /* The left grain's copy shows near the right edge. */
    render_view_to_pixel(&v, 0.1995, 0.042, &px, &py);
    TEST_ASSERT(fixture_pixel(&image, px, py) == render_species_rgb(0));
    render_image_free(&image);
    int rc = draw_and_check("periodic_seam", &f, &s);
    fixture_free(&f);
    return rc;
}

/* Categorical species legend and height bands. */
static int species_and_bands(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 7) == 0);
    RenderStyle s = quiet_style(360, 240);
    s.color_by = RENDER_COLOR_SPECIES;
    s.colorbar = 1;
    int rc = draw_and_check("species_legend", &f, &s);
    s = quiet_style(320, 240);
    s.color_by = RENDER_COLOR_HEIGHT;
    s.band_height = 0.035;
    rc |= draw_and_check("height_bands", &f, &s);
    fixture_free(&f);
    return rc;
}

/* Colour bar with label and unit, time stamp with t*, scale bar, title, yellow-red map. */
static int annotations(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 16, 8, 0.01, 8) == 0);
    RenderStyle s = render_style_default();
    s.width = 640;
    s.height = 360;
    s.color_by = RENDER_COLOR_FORCE;
    s.colormap = RENDER_CMAP_YELLOW_RED;
    s.range_min = 0;
    s.range_max = 10;
    s.title = "Packed bed, contact forces";
    int rc = draw_and_check("annotations", &f, &s);
    fixture_free(&f);
    return rc;
}

/* Flat disks: the centre pixel of a grain is exactly its LUT colour; fixed grains use fixed_rgb;
 * the background is untouched; two renders are identical. */
static int disk_colours_exact(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 8, 5, 0.01, 9) == 0);
    RenderStyle s = quiet_style(400, 300);
    s.color_by = RENDER_COLOR_FORCE;
    s.range_min = 0;
    s.range_max = 6;
    RenderImage a, b;
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &a) == 0);
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &b) == 0);
    TEST_ASSERT(memcmp(a.pixels, b.pixels, (size_t)a.stride * (size_t)a.height) == 0);
    RenderView v;
    render_view_fit(&f.frame, &s, &v);
    for (int i = 0; i < f.frame.count; i += 3) {
        double px, py;
        render_view_to_pixel(&v, f.x[i], f.y[i], &px, &py);
        uint32_t want =
            f.flags[i] ? s.fixed_rgb : render_colormap_rgb(s.colormap, f.force[i] / s.range_max);
        TEST_ASSERT(fixture_pixel(&a, px, py) == want);
    }
    TEST_ASSERT(fixture_pixel(&a, 1, 1) == 0xffffff);
    /* Every grain lies inside the plot rectangle of the fitted view. */
    for (int i = 0; i < f.frame.count; ++i) {
        double px, py;
        render_view_to_pixel(&v, f.x[i], f.y[i], &px, &py);
        TEST_ASSERT(px - f.radius[i] * v.scale >= v.plot_x);
        TEST_ASSERT(px + f.radius[i] * v.scale <= v.plot_x + v.plot_w);
        TEST_ASSERT(py - f.radius[i] * v.scale >= v.plot_y);
        TEST_ASSERT(py + f.radius[i] * v.scale <= v.plot_y + v.plot_h);
    }
    render_image_free(&a);
    render_image_free(&b);
    fixture_free(&f);
    return 0;
}

/* A strong chain is drawn (its midpoint pixel is chain-coloured, not the grain fill); a weak one
 * (below the mean) is not. */
static int chain_selection(void)
{
    Fixture f;
    TEST_ASSERT(fixture_init(&f, 8, 8, 10) == 0);
    int a = fixture_add(&f, 0.0, 0.0, 0.01, 0);
    int b = fixture_add(&f, 0.02, 0.0, 0.01, 0);
    int c = fixture_add(&f, 0.0, 0.02, 0.01, 0);
    fixture_contact(&f, a, b, 9.0, 0.01, 0.0);
    fixture_contact(&f, a, c, 1.0, 0.0, 0.01);
    RenderStyle s = quiet_style(300, 300);
    s.force_chains = 1;
    s.fill_rgb = 0xffffff;
    double fmax;
    TEST_NEAR(render_chain_cut(&f.frame, &s, &fmax), 5.0, 1e-12);
    TEST_NEAR(fmax, 9.0, 0);
    RenderImage image;
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &image) == 0);
    RenderView v;
    render_view_fit(&f.frame, &s, &v);
    double px, py;
    render_view_to_pixel(&v, 0.005, 0.0, &px, &py); /* on the strong a-b segment */
    TEST_ASSERT(fixture_pixel(&image, px, py) == render_colormap_rgb(RENDER_CMAP_YELLOW_RED, 1.0));
    /* On the weak a-c segment, past the strong chain's round cap (radius 0.25 d = 0.005). */
    render_view_to_pixel(&v, 0.0, 0.0075, &px, &py);
    TEST_ASSERT(fixture_pixel(&image, px, py) == 0xffffff);
    render_image_free(&image);
    fixture_free(&f);
    return 0;
}

/* Colour maps: known viridis entries, monotone lightness, clamping, categorical palette. */
static int colormaps(void)
{
    TEST_ASSERT(render_colormap_rgb(RENDER_CMAP_VIRIDIS, 0) == 0x440154);
    TEST_ASSERT(render_colormap_rgb(RENDER_CMAP_VIRIDIS, 1) == 0xfde725);
    /* matplotlib viridis(128/255) = (0.127568, 0.566949, 0.550556) = #21918c */
    TEST_ASSERT(render_colormap_rgb(RENDER_CMAP_VIRIDIS, 128.0 / 255.0) == 0x21918c);
    TEST_ASSERT(render_colormap_rgb(RENDER_CMAP_VIRIDIS, -3) == 0x440154);
    TEST_ASSERT(render_colormap_rgb(RENDER_CMAP_VIRIDIS, 7) == 0xfde725);
    TEST_ASSERT(render_colormap_rgb(RENDER_CMAP_VIRIDIS, NAN) == 0x440154);
    for (int m = 0; m < 3; ++m) {
        uint8_t lut[256][3];
        render_colormap_lut((RenderColormap)m, lut);
        double last = m == 0 ? -1 : 1e9;
        for (int k = 0; k < 256; ++k) {
            double lum = 0.2126 * lut[k][0] + 0.7152 * lut[k][1] + 0.0722 * lut[k][2];
            /* viridis brightens, yellow-red and greys darken with force */
            if (m == 0)
                TEST_ASSERT(lum >= last - 0.5);
            else
                TEST_ASSERT(lum <= last + 0.5);
            last = lum;
            uint32_t rgb = (uint32_t)lut[k][0] << 16 | (uint32_t)lut[k][1] << 8 | lut[k][2];
            TEST_ASSERT(render_colormap_rgb((RenderColormap)m, k / 255.0) == rgb);
        }
    }
    TEST_ASSERT(render_species_rgb(0) != render_species_rgb(1));
    TEST_ASSERT(render_species_rgb(8) == render_species_rgb(0));
    return 0;
}

/* Automatic colour range: [0, max over mobile grains]; a fixed range is kept. */
static int color_range(void)
{
    Fixture f;
    TEST_ASSERT(fixture_init(&f, 4, 4, 11) == 0);
    fixture_add(&f, 0, 0, 0.01, 0);
    fixture_add(&f, 0.02, 0, 0.01, 0);
    fixture_add(&f, 0.04, 0, 0.01, SIM_GRAIN_FIXED);
    f.vx[0] = 3;
    f.vy[0] = 4;
    f.vx[2] = 100; /* fixed grains do not set the range */
    RenderStyle s = render_style_default();
    s.color_by = RENDER_COLOR_SPEED;
    double lo, hi;
    render_color_range(&f.frame, &s, &lo, &hi);
    TEST_NEAR(lo, 0, 0);
    TEST_NEAR(hi, 5, 1e-15);
    s.range_min = 1;
    s.range_max = 2;
    render_color_range(&f.frame, &s, &lo, &hi);
    TEST_ASSERT(lo == 1 && hi == 2);
    TEST_ASSERT(render_grain_rgb(&f.frame, &s, 2, lo, hi) == s.fixed_rgb);
    fixture_free(&f);
    return 0;
}

/* The default font is RENDER_FIGURE_FONT_PT points at the print size, not a share of the
 * pixel height: 10 px on a tall 96-dpi figure (300 x 1200 px), 31.25 px at 300 dpi. */
static int default_font_in_points(void)
{
    Fixture f;
    TEST_ASSERT(fixture_init(&f, 4, 4, 0) == 0);
    fixture_add(&f, 0.1, 0.05, 0.01, 0);
    RenderStyle s = render_style_default();
    s.width = 300;
    s.height = 1200;
    RenderView v;
    render_view_fit(&f.frame, &s, &v);
    TEST_ASSERT(RENDER_FIGURE_FONT_PT == 7.5);
    TEST_ASSERT(fabs(v.font_size - 7.5 * 96.0 / 72.0) < 1e-12);
    s.dpi = 300.0;
    render_view_fit(&f.frame, &s, &v);
    TEST_ASSERT(fabs(v.font_size - 7.5 * 300.0 / 72.0) < 1e-12);
    fixture_free(&f);
    return 0;
}

/* A fixed range that the values exceed saturates: the colour bar gets an end triangle of the
 * top colour above its top (matplotlib's extend = "max"); a range the values fit has none. */
static int colorbar_extend(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 2) == 0);
    RenderStyle s = quiet_style(320, 240);
    s.color_by = RENDER_COLOR_FORCE;
    s.colorbar = 1;
    s.range_min = 0;
    s.range_max = 1e9;
    TEST_ASSERT(render_color_extend(&f.frame, &s, 0, 1e9) == 0);
    s.range_max = 0.5; /* the bed's forces go up to about 8 */
    TEST_ASSERT(render_color_extend(&f.frame, &s, 0, 0.5) == RENDER_EXTEND_MAX);
    RenderView v;
    render_view_fit(&f.frame, &s, &v);
    /* the bar's outer box as draw_colorbar lays it out */
    double fs = v.font_size, x = round(v.plot_x + v.plot_w + 1.2 * fs), w = round(1.1 * fs);
    double top = round(v.plot_y + v.plot_h - round(fmax(2 * fs, v.plot_h - 2.4 * fs)));
    uint32_t yellow = render_colormap_rgb(s.colormap, 1.0);
    for (int extend = 0; extend < 2; ++extend) {
        s.range_max = extend ? 0.5 : 1e9;
        RenderImage image;
        TEST_ASSERT(render_cairo_draw(&f.frame, &s, &image) == 0);
        /* the triangle's middle is the top colour, its corner beside the tip is background */
        uint32_t mid = fixture_pixel(&image, x + 0.5 * w, top + 0.8 * w);
        uint32_t corner = fixture_pixel(&image, x + 0.2 * w, top + 0.2 * w);
        if (extend)
            TEST_ASSERT(mid == yellow && corner == s.background_rgb);
        else
            TEST_ASSERT(corner != s.background_rgb);
        render_image_free(&image);
    }
    fixture_free(&f);
    return 0;
}

/* One colour scale per series: the range fixed by the first frame with values (a quarter of
 * headroom, rounded up) stays while the values grow; a declared range is kept. */
static int color_lock(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 2) == 0);
    RenderStyle s = render_style_default();
    s.color_by = RENDER_COLOR_FORCE;
    double top = 0;
    for (int i = 0; i < f.frame.count; ++i)
        if (!f.flags[i])
            top = fmax(top, f.force[i]);
    const double *force = f.frame.force;
    f.frame.force = NULL; /* a frame without forces: nothing to scale by yet */
    TEST_ASSERT(render_color_lock(&f.frame, &s) == 0);
    TEST_ASSERT(!(s.range_min < s.range_max));
    f.frame.force = force;
    TEST_ASSERT(render_color_lock(&f.frame, &s) == 1);
    double lo = s.range_min, hi = s.range_max;
    TEST_ASSERT(lo == 0 && hi >= 1.25 * top && hi <= 2.5 * top);
    TEST_ASSERT(s.color_extend == RENDER_EXTEND_MAX);
    for (int i = 0; i < f.frame.count; ++i)
        f.force[i] *= 100;
    TEST_ASSERT(render_color_lock(&f.frame, &s) == 1);
    TEST_ASSERT(s.range_min == lo && s.range_max == hi);
    RenderStyle declared = render_style_default();
    declared.color_by = RENDER_COLOR_FORCE;
    declared.range_min = 1;
    declared.range_max = 3;
    TEST_ASSERT(render_color_lock(&f.frame, &declared) == 1);
    TEST_ASSERT(declared.range_min == 1 && declared.range_max == 3);
    TEST_ASSERT(declared.color_extend == (RENDER_EXTEND_MAX | RENDER_EXTEND_MIN));
    fixture_free(&f);
    return 0;
}

/* Arrows shorter than a tenth of the key are left out: grains that barely move carry no dot. */
static int arrows_below_key(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 4) == 0);
    RenderStyle s = quiet_style(320, 240);
    s.velocity_arrows = 1;
    int fast = -1;
    for (int i = 0; i < f.frame.count; ++i) {
        f.vx[i] = f.vy[i] = 0;
        if (!f.flags[i] && fast < 0)
            fast = i;
    }
    f.vx[fast] = 1.0;
    RenderImage still, slow;
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &still) == 0);
    for (int i = 0; i < f.frame.count; ++i)
        if (i != fast && !f.flags[i])
            f.vx[i] = 0.03; /* 3 % of the fastest: a few pixels, under a tenth of the key */
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &slow) == 0);
    TEST_ASSERT(memcmp(still.pixels, slow.pixels, (size_t)still.stride * still.height) == 0);
    s.arrow_min = -1; /* every arrow */
    render_image_free(&slow);
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &slow) == 0);
    TEST_ASSERT(memcmp(still.pixels, slow.pixels, (size_t)still.stride * still.height) != 0);
    render_image_free(&still);
    render_image_free(&slow);
    fixture_free(&f);
    return 0;
}

/* The reference arrow is at least 5 mm long at the figure's print size (600 dpi here), where
 * the 6 em rule alone would give 2.5 mm at most. */
static int arrow_key_length(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 4) == 0);
    RenderStyle s = quiet_style(320, 240);
    s.velocity_arrows = 1;
    s.dpi = 600;
    s.font_size = 10;
    RenderImage image;
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &image) == 0);
    RenderView v;
    render_view_fit(&f.frame, &s, &v);
    /* the longest dark run in a row under the plot: the key's shaft (text runs are shorter) */
    int longest = 0;
    for (int y = (int)ceil(v.plot_y + v.plot_h) + 1; y < image.height; ++y)
        for (int x = 0, run = 0; x < image.width; ++x) {
            run = (fixture_pixel(&image, x, y) & 0xff) < 0xa0 ? run + 1 : 0;
            longest = run > longest ? run : longest;
        }
    fprintf(stderr, "arrow key: %d pixels, %.2f mm at 600 dpi\n", longest, longest / 600.0 * 25.4);
    TEST_ASSERT(longest >= 5.0 / 25.4 * 600 - 1);
    render_image_free(&image);
    fixture_free(&f);
    return 0;
}

/* The view of a bed of `rows` rows of grains of radius r in a square box twice its height. */
static void view_box(RenderStyle *s, int rows, double r)
{
    s->view_x0 = s->view_y0 = 0;
    s->view_x1 = s->view_y1 = 2 * (2 * r + rows * r * sqrt(3.0));
}

/* A frame drawn in two bands, the lower one by the helper thread (render_cairo_draw_split), has
 * every pixel of the one-band drawing: force chains, outlines, arrows and the field, colour bar,
 * time stamp, scale bar and title, at an even and an odd height (the bands' edge cuts disks,
 * chains and text), and with the grains in the lower half of the image, where the bands meet
 * below the middle. */
static int split_same_pixels(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 24, 14, 0.01, 9) == 0);
    fixture_find_contacts(&f, 0.2 * 0.01, 1.0);
    RenderHelper *helper = render_helper_create();
    TEST_ASSERT(helper != NULL);
    for (int odd = 0; odd < 3; ++odd) {
        RenderStyle s = render_style_default();
        s.width = 480;
        s.height = 360 + odd;
        s.color_by = RENDER_COLOR_FORCE;
        s.force_chains = 1;
        s.velocity_arrows = odd;
        s.velocity_field = !odd;
        s.title = "bands";
        if (odd == 2)
            view_box(&s, 14, 0.01);
        RenderImage one, two;
        TEST_ASSERT(render_cairo_draw(&f.frame, &s, &one) == 0);
        TEST_ASSERT(render_cairo_draw_split(&f.frame, &s, &two, helper) == 0);
        TEST_ASSERT(two.width == one.width && two.height == one.height &&
                    two.stride == one.stride && two.format == one.format);
        TEST_ASSERT(memcmp(one.pixels, two.pixels, (size_t)one.stride * (size_t)one.height) == 0);
        /* the drawing reaches both bands: neither half is plain background */
        const size_t half = (size_t)one.stride * (size_t)(one.height / 2);
        int upper = 0, lower = 0;
        for (size_t k = 4; k < half; k += 4) {
            upper |= memcmp(one.pixels + k, one.pixels, 4) != 0;
            lower |= memcmp(one.pixels + half + k, one.pixels + half, 4) != 0;
        }
        TEST_ASSERT(upper && lower);
        render_image_free(&one);
        render_image_free(&two);
    }
    render_helper_destroy(helper);
    fixture_free(&f);
    return 0;
}

/* The bands meet where the grains' drawing cost is halved: with a bed in the lower half of a
 * square box, below the middle, with as many grains (of one size, give or take 4 %) above the
 * edge as below it; with no grain in view, at the middle. */
static int split_row_halves_grains(void)
{
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 40, 20, 0.01, 5) == 0);
    RenderStyle s = render_style_default();
    s.width = s.height = 400;
    view_box(&s, 20, 0.01);
    RenderView v;
    render_view_fit(&f.frame, &s, &v);
    const int row = render_cairo_split_row(&f.frame, &v, s.height);
    int above = 0, below = 0;
    for (int i = 0; i < f.frame.count; ++i) {
        double px, py;
        render_view_to_pixel(&v, f.frame.x[i], f.frame.y[i], &px, &py);
        above += py < row;
        below += py >= row;
    }
    fprintf(stderr, "bands meet at row %d of %d: %d grains above, %d below\n", row, s.height, above,
            below);
    TEST_ASSERT(row > 0.6 * s.height);
    TEST_ASSERT(abs(above - below) <= 0.04 * f.frame.count + 30); /* a row of grains: 40 */
    s.view_y0 = 10;
    s.view_y1 = s.view_y0 + s.view_x1;
    render_view_fit(&f.frame, &s, &v);
    TEST_ASSERT(render_cairo_split_row(&f.frame, &v, s.height) == s.height / 2);
    fixture_free(&f);
    return 0;
}

/* The helper runs each job in one thread of its own (the same for every job: a GL context stays
 * current there), the jobs one after the other; waiting with no job given returns at once, and
 * destroying it waits for the job given last. */
typedef struct Job {
    pthread_t ran_on;
    int count;
} Job;

static void record_job(void *context)
{
    Job *j = context;
    j->ran_on = pthread_self();
    j->count += 1;
}

static int helper_runs_jobs_in_one_thread(void)
{
    RenderHelper *helper = render_helper_create();
    TEST_ASSERT(helper != NULL);
    render_helper_wait(helper); /* nothing given */
    Job job = {.count = 0};
    render_helper_start(helper, record_job, &job);
    render_helper_wait(helper);
    const pthread_t first = job.ran_on;
    TEST_ASSERT(job.count == 1 && !pthread_equal(first, pthread_self()));
    for (int k = 1; k < 3; ++k) {
        render_helper_start(helper, record_job, &job);
        render_helper_wait(helper);
        TEST_ASSERT(pthread_equal(job.ran_on, first));
    }
    TEST_ASSERT(job.count == 3);
    render_helper_start(helper, record_job, &job);
    render_helper_destroy(helper); /* waits for the job given */
    TEST_ASSERT(job.count == 4);
    render_helper_destroy(NULL);
    return 0;
}

TEST_MAIN(TEST_CASE(grains_fixed), TEST_CASE(grains_force_viridis), TEST_CASE(force_chains),
          TEST_CASE(velocity_arrows), TEST_CASE(arches), TEST_CASE(periodic_seam),
          TEST_CASE(species_and_bands), TEST_CASE(annotations), TEST_CASE(disk_colours_exact),
          TEST_CASE(chain_selection), TEST_CASE(colormaps), TEST_CASE(color_range),
          TEST_CASE(default_font_in_points), TEST_CASE(colorbar_extend), TEST_CASE(color_lock),
          TEST_CASE(arrows_below_key), TEST_CASE(arrow_key_length), TEST_CASE(split_same_pixels),
          TEST_CASE(split_row_halves_grains), TEST_CASE(helper_runs_jobs_in_one_thread))
