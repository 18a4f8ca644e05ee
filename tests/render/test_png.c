/* SPDX-License-Identifier: MIT */
/* Figure files: PNG provenance chunks, byte-identical PNG and PDF reruns, SVG, pixel formats,
 * atomic writes. */
#include "fixture.h"
#include "test.h"

#include <png.h>

#define DIR "out/render-tests/png"

static void make_dirs(void)
{
    fixture_mkdirs();
    mkdir(DIR, 0777);
}

static RenderStyle figure_style(void)
{
    RenderStyle s = render_style_default();
    s.width = 400;
    s.height = 260;
    s.color_by = RENDER_COLOR_FORCE;
    s.range_min = 0;
    s.range_max = 8;
    s.force_chains = 1;
    s.title = "figure test";
    return s;
}

/* strstr over binary data (PDF streams hold NUL bytes). */
static int contains(const unsigned char *buf, long n, const char *text)
{
    size_t m = strlen(text);
    for (long k = 0; k + (long)m <= n; ++k)
        if (memcmp(buf + k, text, m) == 0)
            return 1;
    return 0;
}

static int file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* Text chunk `key` of a PNG (read back with libpng directly), copied into value. */
static int png_text_value(const char *path, const char *key, char *value, size_t size,
                          int *color_type)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    int found = -1;
    if (setjmp(png_jmpbuf(png)) == 0) {
        png_init_io(png, f);
        png_read_info(png, info);
        *color_type = png_get_color_type(png, info);
        png_textp text;
        int n = 0;
        png_get_text(png, info, &text, &n);
        for (int k = 0; k < n; ++k)
            if (strcmp(text[k].key, key) == 0) {
                snprintf(value, size, "%s", text[k].text);
                found = 0;
            }
    }
    png_destroy_read_struct(&png, &info, NULL);
    fclose(f);
    return found;
}

static int png_metadata(void)
{
    make_dirs();
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 31) == 0);
    RenderStyle s = figure_style();
    RenderMeta meta = {.scene = "crater", .seed = 42, .comment = "sablier run crater.scene"};
    char err[256], value[256];
    int type = -1;
    TEST_ASSERT(render_figure_write(&f.frame, &s, &meta, DIR "/meta.png", err, sizeof err) == 0);
    TEST_ASSERT(!file_exists(DIR "/meta.png.tmp"));
    TEST_ASSERT(png_text_value(DIR "/meta.png", "Software", value, sizeof value, &type) == 0);
    TEST_ASSERT(strcmp(value, "sablier") == 0);
    TEST_ASSERT(type == PNG_COLOR_TYPE_RGB); /* opaque background: no alpha channel */
    TEST_ASSERT(png_text_value(DIR "/meta.png", "Sablier version", value, sizeof value, &type) ==
                0);
    TEST_ASSERT(strcmp(value, SIM_VERSION) == 0);
    TEST_ASSERT(png_text_value(DIR "/meta.png", "Scene", value, sizeof value, &type) == 0);
    TEST_ASSERT(strcmp(value, "crater") == 0);
    TEST_ASSERT(png_text_value(DIR "/meta.png", "Seed", value, sizeof value, &type) == 0);
    TEST_ASSERT(strcmp(value, "42") == 0);
    TEST_ASSERT(png_text_value(DIR "/meta.png", "Simulated time", value, sizeof value, &type) == 0);
    TEST_ASSERT(strcmp(value, "0.125 s") == 0);
    TEST_ASSERT(png_text_value(DIR "/meta.png", "Step", value, sizeof value, &type) == 0);
    TEST_ASSERT(strcmp(value, "12500") == 0);
    TEST_ASSERT(png_text_value(DIR "/meta.png", "Comment", value, sizeof value, &type) == 0);
    TEST_ASSERT(strcmp(value, "sablier run crater.scene") == 0);
    TEST_ASSERT(png_text_value(DIR "/meta.png", "Renderer", value, sizeof value, &type) == 0);
    TEST_ASSERT(strncmp(value, "cairo ", 6) == 0);
    /* The figure file holds the same pixels as render_cairo_draw. */
    RenderImage drawn, read;
    TEST_ASSERT(render_cairo_draw(&f.frame, &s, &drawn) == 0);
    TEST_ASSERT(render_png_read(DIR "/meta.png", &read, err, sizeof err) == 0);
    RenderDiffOptions exact = {.channel_threshold = 0, .shift_tolerance = 0, .max_pixels = 0};
    RenderDiffResult r;
    TEST_ASSERT(render_diff_images(&drawn, &read, &exact, NULL, &r, err, sizeof err) == 0);
    render_image_free(&drawn);
    render_image_free(&read);
    fixture_free(&f);
    return 0;
}

static int png_byte_identical(void)
{
    make_dirs();
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 32) == 0);
    RenderStyle s = figure_style();
    s.velocity_field = 1;
    RenderMeta meta = {.scene = "bed", .seed = 1};
    char err[256];
    TEST_ASSERT(render_figure_write(&f.frame, &s, &meta, DIR "/run1.png", err, sizeof err) == 0);
    TEST_ASSERT(render_figure_write(&f.frame, &s, &meta, DIR "/run2.png", err, sizeof err) == 0);
    TEST_ASSERT(test_same_bytes(DIR "/run1.png", DIR "/run2.png"));
    fixture_free(&f);
    return 0;
}

static int pdf_byte_identical(void)
{
    make_dirs();
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 33) == 0);
    RenderStyle s = figure_style();
    RenderMeta meta = {.scene = "bed", .seed = 1};
    char err[256];
    TEST_ASSERT(render_figure_write(&f.frame, &s, &meta, DIR "/run1.pdf", err, sizeof err) == 0);
    TEST_ASSERT(render_figure_write(&f.frame, &s, &meta, DIR "/run2.PDF", err, sizeof err) == 0);
    TEST_ASSERT(!file_exists(DIR "/run1.pdf.tmp"));
    TEST_ASSERT(test_same_bytes(DIR "/run1.pdf", DIR "/run2.PDF"));
    long n = 0;
    unsigned char *pdf = (unsigned char *)test_read_file(DIR "/run1.pdf", &n);
    TEST_ASSERT(pdf && n > 1000);
    TEST_ASSERT(memcmp(pdf, "%PDF-", 5) == 0);
    /* Pinned dates and our creator string; page size 400 x 260 px = 300 x 195 pt. */
    TEST_ASSERT(contains(pdf, n, "/CreationDate (20000101000000Z)"));
    TEST_ASSERT(contains(pdf, n, "/Creator (sablier " SIM_VERSION ")"));
    TEST_ASSERT(contains(pdf, n, "/MediaBox [ 0 0 300 195 ]"));
    free(pdf);
    fixture_free(&f);
    return 0;
}

static int svg_written(void)
{
    make_dirs();
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 10, 6, 0.01, 34) == 0);
    RenderStyle s = figure_style();
    char err[256];
    TEST_ASSERT(render_figure_write(&f.frame, &s, NULL, DIR "/fig.svg", err, sizeof err) == 0);
    long n = 0;
    unsigned char *svg = (unsigned char *)test_read_file(DIR "/fig.svg", &n);
    TEST_ASSERT(svg && n > 1000);
    TEST_ASSERT(strstr((char *)svg, "<svg") && strstr((char *)svg, "width=\"300pt\""));
    TEST_ASSERT(strstr((char *)svg, "</svg>"));
    TEST_ASSERT(!file_exists(DIR "/fig.svg.tmp"));
    /* Text is embedded as glyph outlines: no font needed to view it. */
    TEST_ASSERT(strstr((char *)svg, "<symbol overflow=\"visible\" id=\"glyph"));
    free(svg);
    /* Not compared byte for byte here: cairo numbers SVG surfaces with a process-wide counter, so
     * two writes in one process differ in one id (separate runs are identical). */
    fixture_free(&f);
    return 0;
}

static int write_errors(void)
{
    make_dirs();
    Fixture f;
    TEST_ASSERT(fixture_bed(&f, 4, 3, 0.01, 35) == 0);
    RenderStyle s = figure_style();
    char err[256] = "";
    TEST_ASSERT(render_figure_write(&f.frame, &s, NULL, DIR "/fig.bmp", err, sizeof err) == -1);
    TEST_ASSERT(strstr(err, "unknown figure format"));
    TEST_ASSERT(
        render_figure_write(&f.frame, &s, NULL, DIR "/no/such/dir/fig.png", err, sizeof err) == -1);
    TEST_ASSERT(strstr(err, "fig.png: "));
    TEST_ASSERT(
        render_figure_write(&f.frame, &s, NULL, DIR "/no/such/dir/fig.pdf", err, sizeof err) == -1);
    fixture_free(&f);
    return 0;
}

/* A translucent premultiplied image is written as straight RGBA and reads back within rounding;
 * opaque images are written as RGB. */
static int alpha_round_trip(void)
{
    make_dirs();
    RenderImage a;
    TEST_ASSERT(render_image_alloc(&a, 4, 2, RENDER_PIXEL_BGRA_PREMUL) == 0);
    /* Premultiplied B, G, R, A: straight (200, 100, 50) at alpha 128 */
    for (int x = 0; x < 4; ++x) {
        uint8_t *p = a.pixels + 4 * x;
        p[0] = 25;  /* 50 * 128 / 255 */
        p[1] = 50;  /* 100 * 128 / 255 */
        p[2] = 100; /* 200 * 128 / 255 */
        p[3] = 128;
    }
    char err[256];
    TEST_ASSERT(render_png_write(&a, DIR "/alpha.png", NULL, err, sizeof err) == 0);
    RenderImage b;
    TEST_ASSERT(render_png_read(DIR "/alpha.png", &b, err, sizeof err) == 0);
    uint8_t c[4];
    render_image_get_rgba(&b, 1, 0, c);
    TEST_ASSERT(c[3] == 128);
    TEST_NEAR(c[0], 200, 2);
    TEST_NEAR(c[1], 100, 2);
    TEST_NEAR(c[2], 50, 2);
    render_image_get_rgba(&b, 1, 1, c); /* untouched: transparent */
    TEST_ASSERT(c[3] == 0);
    char value[8];
    int type = -1;
    png_text_value(DIR "/alpha.png", "none", value, sizeof value, &type);
    TEST_ASSERT(type == PNG_COLOR_TYPE_RGB_ALPHA);
    render_image_free(&a);
    render_image_free(&b);
    return 0;
}

static int library_versions(void)
{
    const char *v = render_library_versions();
    TEST_ASSERT(strstr(v, "cairo 1.") && strstr(v, "libpng 1.") && strstr(v, "libavcodec "));
    TEST_ASSERT(strcmp(v, render_library_versions()) == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(png_metadata), TEST_CASE(png_byte_identical), TEST_CASE(pdf_byte_identical),
          TEST_CASE(svg_written), TEST_CASE(write_errors), TEST_CASE(alpha_round_trip),
          TEST_CASE(library_versions))
