/* SPDX-License-Identifier: MIT */
/* render_figure.c: writing Cairo drawings to PNG (libpng), PDF and SVG, text helpers, provenance
 * and library versions. */
#include "render_cairo_util.h"

#include "render/internal.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <ctype.h>
#include <libavcodec/version.h>
#include <libavformat/version.h>
#include <libavutil/version.h>
#include <libswscale/version.h>
#include <math.h>
#include <png.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Pinned PDF dates: cairo 1.16 ignores SOURCE_DATE_EPOCH and would write the wall clock
 * (anchors-render 2a), which breaks byte-identical reruns; so a PDF's date is SOURCE_DATE_EPOCH
 * when set (as newer cairo does), else this fixed one, never the clock. */
#define PDF_FIXED_DATE "2000-01-01T00:00:00Z"

static void pdf_date(char *out, size_t size)
{
    const char *epoch = getenv("SOURCE_DATE_EPOCH");
    char *end = NULL;
    long long seconds = epoch && *epoch ? strtoll(epoch, &end, 10) : -1;
    time_t t = (time_t)seconds;
    struct tm tm;
    if (!end || *end != '\0' || seconds < 0 || !gmtime_r(&t, &tm) ||
        strftime(out, size, "%Y-%m-%dT%H:%M:%SZ", &tm) == 0)
        snprintf(out, size, "%s", PDF_FIXED_DATE);
}

void render_text_font(cairo_t *cr, double size, int bold)
{
    cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                           bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
    cairo_font_options_t *options = cairo_font_options_create();
    cairo_font_options_set_antialias(options, CAIRO_ANTIALIAS_GRAY);
    cairo_font_options_set_hint_style(options, CAIRO_HINT_STYLE_NONE);
    cairo_font_options_set_hint_metrics(options, CAIRO_HINT_METRICS_OFF);
    cairo_set_font_options(cr, options);
    cairo_font_options_destroy(options);
}

double render_text_width(cairo_t *cr, const char *text)
{
    cairo_text_extents_t e;
    cairo_text_extents(cr, text, &e);
    return e.x_advance;
}

double render_text_draw(cairo_t *cr, double x, double y, const char *text, double halign,
                        double valign)
{
    /* Capital height of DejaVu Sans is 0.729 em: anchoring on it (not on ink extents) keeps
     * baselines steady whatever the string, so labels do not jitter between movie frames. */
    cairo_matrix_t m;
    cairo_get_font_matrix(cr, &m);
    double cap = 0.729 * m.yy;
    double w = render_text_width(cr, text);
    cairo_move_to(cr, x - halign * w, y + cap * (1.0 - valign));
    cairo_show_text(cr, text);
    cairo_new_path(cr);
    return w;
}

void render_set_rgb(cairo_t *cr, uint32_t rgb)
{
    cairo_set_source_rgb(cr, ((rgb >> 16) & 255) / 255.0, ((rgb >> 8) & 255) / 255.0,
                         (rgb & 255) / 255.0);
}

void render_format_tick(double value, double step, int log, char *buf, size_t size)
{
    if (log) {
        double e = floor(log10(value) + 0.5);
        if (e >= -3 && e <= 4)
            snprintf(buf, size, "%g", pow(10, e));
        else
            snprintf(buf, size, "1e%d", (int)e);
        return;
    }
    if (fabs(value) < 1e-9 * step)
        value = 0; /* no "-0" or 1e-17 */
    double mag = fmax(fabs(value), step);
    if (mag >= 1e5 || mag < 1e-3) {
        int digits = (int)fmax(0, floor(log10(mag)) - floor(log10(step)));
        snprintf(buf, size, "%.*e", digits > 6 ? 6 : digits, value);
        /* Tidy "1.0e+04" to "1e4" style only in the exponent: drop '+' and leading zeros. */
        char *e = strchr(buf, 'e');
        if (e) {
            char *q = e + 1, *w = e + 1;
            if (*q == '+')
                ++q;
            if (*q == '-')
                *w++ = *q++;
            while (*q == '0' && q[1])
                ++q;
            memmove(w, q, strlen(q) + 1);
        }
        return;
    }
    int decimals = (int)ceil(-log10(step) - 1e-9);
    if (decimals < 0)
        decimals = 0;
    snprintf(buf, size, "%.*f", decimals, value);
}

int render_tick_exponent(const double *ticks, int n)
{
    double big = 0;
    for (int k = 0; k < n; ++k)
        big = fmax(big, fabs(ticks[k]));
    if (!(big > 0) || (big >= 1e-2 && big < 1e4))
        return 0;
    return (int)floor(log10(big) + 1e-9);
}

const char *render_exponent_text(int e, char *buf, size_t size)
{
    /* U+00D7 then superscript minus U+207B and digits U+2070, U+00B9, U+00B2, U+00B3, U+2074.. */
    static const char *const digits[] = {
        "\xe2\x81\xb0", "\xc2\xb9",     "\xc2\xb2",     "\xc2\xb3",     "\xe2\x81\xb4",
        "\xe2\x81\xb5", "\xe2\x81\xb6", "\xe2\x81\xb7", "\xe2\x81\xb8", "\xe2\x81\xb9"};
    char number[16];
    snprintf(number, sizeof number, "%d", e < 0 ? -e : e);
    size_t used = (size_t)snprintf(buf, size,
                                   "\xc3\x97"
                                   "10%s",
                                   e < 0 ? "\xe2\x81\xbb" : "");
    for (const char *c = number; *c && used < size; ++c)
        used += (size_t)snprintf(buf + used, size - used, "%s", digits[*c - '0']);
    return buf;
}

double render_arrow_reference(double top)
{
    if (!(top > 0) || !isfinite(top))
        return 0;
    double decade = pow(10.0, floor(log10(top) + 1e-12));
    if (5.0 * decade <= top * (1 + 1e-12))
        return 5.0 * decade;
    if (2.0 * decade <= top * (1 + 1e-12))
        return 2.0 * decade;
    return decade;
}

void render_arrow(cairo_t *cr, double x, double y, double dx, double dy, double head_max)
{
    double len = hypot(dx, dy);
    if (!(len > 0.5))
        return;
    double ux = dx / len, uy = dy / len, head = fmin(0.3 * len, head_max);
    cairo_move_to(cr, x, y);
    cairo_line_to(cr, x + dx, y + dy);
    cairo_stroke(cr);
    cairo_move_to(cr, x + dx, y + dy);
    cairo_line_to(cr, x + dx - head * (ux + 0.5 * uy), y + dy - head * (uy - 0.5 * ux));
    cairo_line_to(cr, x + dx - head * (ux - 0.5 * uy), y + dy - head * (uy + 0.5 * ux));
    cairo_close_path(cr);
    cairo_fill(cr);
}

int render_cairo_image(int width, int height, RenderDrawFn draw, void *context, RenderImage *out,
                       char *err, size_t err_size)
{
    if (render_image_alloc(out, width, height, RENDER_PIXEL_BGRA_PREMUL) != 0) {
        render_set_err(err, err_size, "cannot allocate a %dx%d image", width, height);
        return -1;
    }
    if (cairo_format_stride_for_width(CAIRO_FORMAT_ARGB32, width) != out->stride) {
        render_set_err(err, err_size, "unexpected Cairo stride");
        render_image_free(out);
        return -1;
    }
    cairo_surface_t *surface = cairo_image_surface_create_for_data(out->pixels, CAIRO_FORMAT_ARGB32,
                                                                   width, height, out->stride);
    cairo_t *cr = cairo_create(surface);
    draw(cr, context);
    cairo_status_t status = cairo_status(cr);
    cairo_destroy(cr);
    cairo_surface_flush(surface);
    cairo_surface_destroy(surface);
    if (status != CAIRO_STATUS_SUCCESS) {
        render_set_err(err, err_size, "cairo: %s", cairo_status_to_string(status));
        render_image_free(out);
        return -1;
    }
    return 0;
}

/* PDF metadata value from the text chunks: "key: value; key: value". */
static void join_text(const char *const *text, char *buf, size_t size)
{
    buf[0] = 0;
    size_t used = 0;
    for (int k = 0; text && text[2 * k] && text[2 * k + 1]; ++k) {
        int n = snprintf(buf + used, size - used, "%s%s: %s", k ? "; " : "", text[2 * k],
                         text[2 * k + 1]);
        if (n < 0 || (size_t)n >= size - used)
            break;
        used += (size_t)n;
    }
}

static const char *text_value(const char *const *text, const char *key)
{
    for (int k = 0; text && text[2 * k] && text[2 * k + 1]; ++k)
        if (strcmp(text[2 * k], key) == 0)
            return text[2 * k + 1];
    return NULL;
}

void render_provenance(const RenderMeta *meta, const char *title, int seed_always, char *seed,
                       const char **text, int *n)
{
    snprintf(seed, 32, "%llu", (unsigned long long)(meta ? meta->seed : 0));
    text[(*n)++] = "Software";
    text[(*n)++] = "sablier";
    text[(*n)++] = "Sablier version";
    text[(*n)++] = SIM_VERSION;
    if (meta && meta->scene) {
        text[(*n)++] = "Scene";
        text[(*n)++] = meta->scene;
    }
    if (seed_always || (meta && meta->scene)) {
        text[(*n)++] = "Seed";
        text[(*n)++] = seed;
    }
    if (title) {
        text[(*n)++] = "Title";
        text[(*n)++] = title;
    }
    if (meta && meta->comment) {
        text[(*n)++] = "Comment";
        text[(*n)++] = meta->comment;
    }
}

int render_cairo_write(const char *path, int width, int height, RenderDrawFn draw, void *context,
                       const char *const *text, char *err, size_t err_size)
{
    return render_cairo_write_dpi(path, width, height, 0.0, draw, context, text, err, err_size);
}

int render_cairo_write_dpi(const char *path, int width, int height, double dpi, RenderDrawFn draw,
                           void *context, const char *const *text, char *err, size_t err_size)
{
    int png = render_has_extension(path, "png"), pdf = render_has_extension(path, "pdf"),
        svg = render_has_extension(path, "svg");
    if (!png && !pdf && !svg) {
        render_set_err(err, err_size, "%s: unknown figure format (use .png, .pdf or .svg)", path);
        return -1;
    }
    if (width <= 0 || height <= 0) {
        render_set_err(err, err_size, "%s: bad size %dx%d", path, width, height);
        return -1;
    }
    if (png) {
        RenderImage image;
        if (render_cairo_image(width, height, draw, context, &image, err, err_size) != 0)
            return -1;
        int rc = render_png_write_dpi(&image, path, text, dpi, err, err_size);
        render_image_free(&image);
        return rc;
    }
    char *tmp = render_tmp_name(path, err, err_size);
    if (!tmp)
        return -1;
    /* 72 points per inch: a figure of `dpi` is printed at its physical size */
    double pt_per_px = dpi > 0 ? 72.0 / dpi : RENDER_PT_PER_PX;
    double w_pt = width * pt_per_px, h_pt = height * pt_per_px;
    cairo_surface_t *surface =
        pdf ? cairo_pdf_surface_create(tmp, w_pt, h_pt) : cairo_svg_surface_create(tmp, w_pt, h_pt);
    if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
        render_set_err(err, err_size, "%s: %s", tmp,
                       cairo_status_to_string(cairo_surface_status(surface)));
        cairo_surface_destroy(surface);
        return render_tmp_commit(tmp, path, 0, err, err_size);
    }
    if (pdf) {
        char subject[1024];
        join_text(text, subject, sizeof subject);
        const char *title = text_value(text, "Title");
        if (!title)
            title = text_value(text, "Scene");
        if (title)
            cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_TITLE, title);
        cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_SUBJECT, subject);
        cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATOR, "sablier " SIM_VERSION);
        char date[40];
        pdf_date(date, sizeof date);
        cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATE_DATE, date);
        cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_MOD_DATE, date);
    } else {
        cairo_svg_surface_restrict_to_version(surface, CAIRO_SVG_VERSION_1_1);
        cairo_svg_surface_set_document_unit(surface, CAIRO_SVG_UNIT_PT);
    }
    cairo_t *cr = cairo_create(surface);
    cairo_scale(cr, pt_per_px, pt_per_px);
    draw(cr, context);
    cairo_show_page(cr);
    cairo_status_t status = cairo_status(cr);
    cairo_destroy(cr);
    cairo_surface_finish(surface);
    if (status == CAIRO_STATUS_SUCCESS)
        status = cairo_surface_status(surface);
    cairo_surface_destroy(surface);
    if (status != CAIRO_STATUS_SUCCESS)
        render_set_err(err, err_size, "%s: cairo: %s", tmp, cairo_status_to_string(status));
    return render_tmp_commit(tmp, path, status == CAIRO_STATUS_SUCCESS, err, err_size);
}

const char *render_library_versions(void)
{
    static char buf[256];
    /* Rebuilt on every call from constants: same text each time, no first-call race. */
    char local[256];
    snprintf(local, sizeof local,
             "cairo %s, libpng %s, libavcodec %d.%d.%d, libavformat %d.%d.%d, libavutil %d.%d.%d, "
             "libswscale %d.%d.%d",
             cairo_version_string(), PNG_LIBPNG_VER_STRING, LIBAVCODEC_VERSION_MAJOR,
             LIBAVCODEC_VERSION_MINOR, LIBAVCODEC_VERSION_MICRO, LIBAVFORMAT_VERSION_MAJOR,
             LIBAVFORMAT_VERSION_MINOR, LIBAVFORMAT_VERSION_MICRO, LIBAVUTIL_VERSION_MAJOR,
             LIBAVUTIL_VERSION_MINOR, LIBAVUTIL_VERSION_MICRO, LIBSWSCALE_VERSION_MAJOR,
             LIBSWSCALE_VERSION_MINOR, LIBSWSCALE_VERSION_MICRO);
    memcpy(buf, local, sizeof buf);
    return buf;
}
