/* SPDX-License-Identifier: MIT */
/* Image diff: what it must catch (a recoloured grain, a missing force-chain segment) and what it
 * must forgive (a one-pixel shift of the whole drawing), and bad input; PDF and SVG figures
 * compared by their drawn pixels, not by their bytes. */
#include "fixture.h"
#include "test.h"

#include "render/render_cairo_util.h"

#include <stdio.h>

#define DIR "out/render-tests/diff"

static RenderStyle diff_style(void)
{
    RenderStyle s = render_style_default();
    s.width = 320;
    s.height = 240;
    s.colorbar = 0;
    s.time_stamp = 0;
    s.scale_bar = 0;
    s.color_by = RENDER_COLOR_SPECIES;
    s.force_chains = 1;
    s.chain_threshold = 0; /* every contact drawn: removing one changes nothing else */
    s.chain_force_max = 6; /* fixed width scale */
    s.chain_width_max = 5;
    return s;
}

static int write_frame(const Fixture *f, const RenderStyle *s, const char *path)
{
    RenderImage image;
    char err[256];
    if (render_cairo_draw(&f->frame, s, &image) != 0)
        return -1;
    int rc = render_png_write(&image, path, NULL, err, sizeof err);
    render_image_free(&image);
    return rc;
}

static void make_dirs(void)
{
    fixture_mkdirs();
    mkdir(DIR, 0777);
}

static int identical(void)
{
    make_dirs();
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 21) == 0);
    RenderStyle s = diff_style();
    TEST_ASSERT(write_frame(&f, &s, DIR "/a.png") == 0);
    TEST_ASSERT(write_frame(&f, &s, DIR "/a2.png") == 0);
    RenderDiffResult r;
    char err[256];
    TEST_ASSERT(render_diff_files(DIR "/a.png", DIR "/a2.png", NULL, NULL, &r, err, sizeof err) ==
                0);
    TEST_ASSERT(r.differing_pixels == 0 && r.raw_pixels == 0 && r.max_channel_diff == 0);
    TEST_NEAR(r.rms, 0, 0);
    TEST_ASSERT(r.width == 320 && r.height == 240 && r.verdict == 0);
    char json[512];
    int n = render_diff_result_json(&r, json, sizeof json);
    TEST_ASSERT(n > 0 && (size_t)n < sizeof json);
    TEST_ASSERT(strstr(json, "\"verdict\":\"match\"") && strstr(json, "\"differing_pixels\":0"));
    TEST_ASSERT(json[0] == '{' && json[n - 1] == '}' && !strchr(json, '\n'));
    fixture_free(&f);
    return 0;
}

static int recoloured_grain(void)
{
    make_dirs();
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 22) == 0);
    RenderStyle s = diff_style();
    TEST_ASSERT(write_frame(&f, &s, DIR "/b.png") == 0);
    int g = 25;
    f.species[g] = f.species[g] == 0 ? 2 : 0;
    TEST_ASSERT(write_frame(&f, &s, DIR "/b_recoloured.png") == 0);
    RenderDiffResult r;
    char err[256];
    int rc = render_diff_files(DIR "/b.png", DIR "/b_recoloured.png", NULL, DIR "/b.diff.png", &r,
                               err, sizeof err);
    TEST_ASSERT(rc == 1 && r.verdict == 1);
    TEST_ASSERT(r.differing_pixels > 50);
    TEST_ASSERT(strstr(err, "pixels differ"));
    /* The diff image marks the grain's centre in red. */
    RenderImage d;
    TEST_ASSERT(render_png_read(DIR "/b.diff.png", &d, err, sizeof err) == 0);
    RenderView v;
    render_view_fit(&f.frame, &s, &v);
    double px, py;
    render_view_to_pixel(&v, f.x[g], f.y[g], &px, &py);
    TEST_ASSERT(fixture_pixel(&d, px, py) == 0xe60000);
    TEST_ASSERT(fixture_pixel(&d, 2, 2) != 0xe60000); /* background: grey */
    render_image_free(&d);
    fixture_free(&f);
    return 0;
}

static int missing_chain_segment(void)
{
    make_dirs();
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 23) == 0);
    RenderStyle s = diff_style();
    TEST_ASSERT(write_frame(&f, &s, DIR "/c.png") == 0);
    /* Drop one mid-strength contact between two mobile grains. */
    int drop = -1;
    for (int c = 0; c < f.frame.contact_count && drop < 0; ++c)
        if (f.contacts[c].normal_force > 1.0 && f.contacts[c].normal_force < 2.0 &&
            !f.flags[f.contacts[c].i] && !f.flags[f.contacts[c].j])
            drop = c;
    TEST_ASSERT(drop >= 0);
    f.contacts[drop] = f.contacts[--f.frame.contact_count];
    TEST_ASSERT(write_frame(&f, &s, DIR "/c_missing.png") == 0);
    RenderDiffResult r;
    char err[256];
    TEST_ASSERT(render_diff_files(DIR "/c.png", DIR "/c_missing.png", NULL, NULL, &r, err,
                                  sizeof err) == 1);
    TEST_ASSERT(r.differing_pixels > 0);
    /* RMS alone would not flag it (pytest-mpl's default tolerance is 2). */
    TEST_ASSERT(r.rms < 2.0);
    fixture_free(&f);
    return 0;
}

/* The whole drawing moved by one pixel (view window shifted by 1 / scale): explained by the
 * shift test, so a match; without the shift tolerance it differs. */
static int one_pixel_shift(void)
{
    make_dirs();
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 24) == 0);
    RenderStyle s = diff_style();
    RenderView v;
    render_view_fit(&f.frame, &s, &v);
    s.view_x0 = v.center_x - 0.5 * v.plot_w / v.scale;
    s.view_x1 = v.center_x + 0.5 * v.plot_w / v.scale;
    s.view_y0 = v.center_y - 0.5 * v.plot_h / v.scale;
    s.view_y1 = v.center_y + 0.5 * v.plot_h / v.scale;
    TEST_ASSERT(write_frame(&f, &s, DIR "/d.png") == 0);
    RenderStyle t = s;
    t.view_x0 += 1.0 / v.scale;
    t.view_x1 += 1.0 / v.scale;
    t.view_y0 -= 1.0 / v.scale;
    t.view_y1 -= 1.0 / v.scale;
    TEST_ASSERT(write_frame(&f, &t, DIR "/d_shift.png") == 0);
    RenderDiffResult r;
    char err[256];
    TEST_ASSERT(
        render_diff_files(DIR "/d.png", DIR "/d_shift.png", NULL, NULL, &r, err, sizeof err) == 0);
    TEST_ASSERT(r.raw_pixels > 100 && r.differing_pixels == 0);
    RenderDiffOptions strict = render_diff_options_default();
    strict.shift_tolerance = 0;
    TEST_ASSERT(render_diff_files(DIR "/d.png", DIR "/d_shift.png", &strict, NULL, &r, err,
                                  sizeof err) == 1);
    fixture_free(&f);
    return 0;
}

static int bad_input(void)
{
    make_dirs();
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 6, 4, 0.01, 25) == 0);
    RenderStyle s = diff_style();
    TEST_ASSERT(write_frame(&f, &s, DIR "/e.png") == 0);
    s.width = 322;
    TEST_ASSERT(write_frame(&f, &s, DIR "/e_wide.png") == 0);
    RenderDiffResult r;
    char err[512];
    TEST_ASSERT(
        render_diff_files(DIR "/e.png", DIR "/e_wide.png", NULL, NULL, &r, err, sizeof err) == 2);
    TEST_ASSERT(r.verdict == 2 && strstr(err, "different sizes") && strstr(err, "322x240"));
    TEST_ASSERT(render_diff_files(DIR "/e.png", DIR "/nope.png", NULL, NULL, &r, err, sizeof err) ==
                2);
    TEST_ASSERT(strstr(err, "nope.png"));
    FILE *text = fopen(DIR "/text.png", "w");
    TEST_ASSERT(text);
    fputs("this is not an image\n", text);
    fclose(text);
    TEST_ASSERT(render_diff_files(DIR "/text.png", DIR "/e.png", NULL, NULL, &r, err, sizeof err) ==
                2);
    TEST_ASSERT(strstr(err, "not a PNG"));
    char json[512];
    render_diff_result_json(&r, json, sizeof json);
    TEST_ASSERT(strstr(json, "\"verdict\":\"error\""));
    fixture_free(&f);
    return 0;
}

/* In-memory comparison accepts mixed formats: a BGRA drawing equals its RGBA read-back. */
static int mixed_formats(void)
{
    make_dirs();
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 6, 4, 0.01, 26) == 0);
    RenderStyle s = diff_style();
    RenderImage a, b;
    char err[256];
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &a) == 0);
    TEST_ASSERT(render_png_write(&a, DIR "/g.png", NULL, err, sizeof err) == 0);
    TEST_ASSERT(render_png_read(DIR "/g.png", &b, err, sizeof err) == 0);
    TEST_ASSERT(b.format == RENDER_PIXEL_RGBA);
    RenderDiffResult r;
    TEST_ASSERT(render_diff_images(&a, &b, NULL, NULL, &r, err, sizeof err) == 0);
    TEST_ASSERT(r.max_channel_diff == 0);
    render_image_free(&a);
    render_image_free(&b);
    fixture_free(&f);
    return 0;
}

/* A grey square, and a red disc when the context says so. */
static void draw_shape(cairo_t *cr, void *context)
{
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    cairo_rectangle(cr, 40, 40, 120, 80);
    cairo_fill(cr);
    if (*(const int *)context) {
        cairo_set_source_rgb(cr, 0.9, 0.1, 0.1);
        cairo_arc(cr, 240, 160, 30, 0, 6.283185307179586);
        cairo_fill(cr);
    }
}

/* Two figures of one format: the same drawing with other metadata (another date and comment)
 * matches by pixels though the bytes differ; an added disc is a change. */
static int vector_pair(const char *ext)
{
    make_dirs();
    char a[128], b[128], c[128], err[256];
    snprintf(a, sizeof a, DIR "/meta_a.%s", ext);
    snprintf(b, sizeof b, DIR "/meta_b.%s", ext);
    snprintf(c, sizeof c, DIR "/shape.%s", ext);
    const char *text_a[] = {"Comment", "command: sablier run /home/a/x.scene", "Title", "a", NULL};
    const char *text_b[] = {"Comment", "command: sablier run x.scene", "Title", "b", NULL};
    int plain = 0, disc = 1;
    TEST_ASSERT(render_cairo_write(a, 320, 240, draw_shape, &plain, text_a, err, sizeof err) == 0);
    setenv("SOURCE_DATE_EPOCH", "86400", 1); /* another date in the PDF */
    TEST_ASSERT(render_cairo_write(b, 320, 240, draw_shape, &plain, text_b, err, sizeof err) == 0);
    unsetenv("SOURCE_DATE_EPOCH");
    TEST_ASSERT(render_cairo_write(c, 320, 240, draw_shape, &disc, text_a, err, sizeof err) == 0);
    static char bytes_a[1 << 16], bytes_b[1 << 16];
    long na = fixture_read(a, bytes_a, sizeof bytes_a),
         nb = fixture_read(b, bytes_b, sizeof bytes_b);
    TEST_ASSERT(na > 0 && nb > 0);
    if (strcmp(ext, "pdf") == 0) /* SVG has no metadata: its bytes are the same */
        TEST_ASSERT(na != nb || memcmp(bytes_a, bytes_b, (size_t)na) != 0);
    RenderDiffResult r;
    if (!render_figure_readable(a)) { /* built without poppler-glib and librsvg */
        RenderImage none;
        TEST_ASSERT(render_figure_read(a, 0.0, &none, err, sizeof err) == 1);
        TEST_ASSERT(strstr(err, "built without"));
        TEST_ASSERT(render_diff_files(a, b, NULL, NULL, &r, err, sizeof err) == 2);
        return 0;
    }
    TEST_ASSERT(render_diff_files(a, b, NULL, NULL, &r, err, sizeof err) == 0);
    TEST_ASSERT(r.differing_pixels == 0 && r.max_channel_diff == 0);
    /* drawn at RENDER_RASTER_DPI from a page of 320 x 240 px at RENDER_PT_PER_PX pt/px */
    TEST_ASSERT(r.width == (int)ceil(320 * RENDER_PT_PER_PX * RENDER_RASTER_DPI / 72.0 - 1e-9));
    TEST_ASSERT(r.height == (int)ceil(240 * RENDER_PT_PER_PX * RENDER_RASTER_DPI / 72.0 - 1e-9));
    char diff[128]; /* one per format: the two cases run side by side under ctest -j */
    snprintf(diff, sizeof diff, DIR "/shape_diff_%s.png", ext);
    TEST_ASSERT(render_diff_files(a, c, NULL, diff, &r, err, sizeof err) == 1);
    TEST_ASSERT(r.differing_pixels > 1000 && r.max_channel_diff > 100);
    RenderImage page;
    TEST_ASSERT(render_figure_read(c, 72.0, &page, err, sizeof err) == 0);
    uint8_t grey[4], red[4], white[4];
    render_image_get_rgba(&page, (int)(80 * RENDER_PT_PER_PX), (int)(60 * RENDER_PT_PER_PX), grey);
    render_image_get_rgba(&page, (int)(240 * RENDER_PT_PER_PX), (int)(160 * RENDER_PT_PER_PX), red);
    render_image_get_rgba(&page, 1, (int)(230 * RENDER_PT_PER_PX), white);
    TEST_ASSERT(grey[0] > 60 && grey[0] < 90 && grey[0] == grey[2]);
    TEST_ASSERT(red[0] > 200 && red[1] < 50);
    TEST_ASSERT(white[0] == 255 && white[1] == 255 && white[2] == 255 && white[3] == 255);
    render_image_free(&page);
    TEST_ASSERT(render_figure_read(DIR "/none.pdf", 0.0, &page, err, sizeof err) == -1);
    return 0;
}

static int pdf_by_pixels(void)
{
    return vector_pair("pdf");
}

static int svg_by_pixels(void)
{
    return vector_pair("svg");
}

TEST_MAIN(TEST_CASE(identical), TEST_CASE(recoloured_grain), TEST_CASE(missing_chain_segment),
          TEST_CASE(one_pixel_shift), TEST_CASE(bad_input), TEST_CASE(mixed_formats),
          TEST_CASE(pdf_by_pixels), TEST_CASE(svg_by_pixels))
