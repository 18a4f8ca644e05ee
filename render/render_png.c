/* SPDX-License-Identifier: MIT */
/* render_png.c: PNG through libpng (not cairo_surface_write_to_png: slower, and no text chunks),
 * and reading PNGs back for the image diff. */
#include "render_cairo_util.h"

#include "render/internal.h"
#include "sim/sim.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* libpng state lives in this struct, whose address libpng holds, so nothing changed after
 * setjmp sits in a register that longjmp could restore stale. */
typedef struct PngJob {
    png_structp png;
    png_infop info;
    FILE *file;
    uint8_t *row;
    png_text *texts;
    char message[200];
} PngJob;

static void png_error_fn(png_structp png, png_const_charp message)
{
    PngJob *job = png_get_error_ptr(png);
    snprintf(job->message, sizeof job->message, "%s", message);
    png_longjmp(png, 1);
}

static void png_warning_fn(png_structp png, png_const_charp message)
{
    (void)png;
    (void)message;
}

static int image_is_opaque(const RenderImage *image)
{
    for (int y = 0; y < image->height; ++y) {
        const uint8_t *p = image->pixels + (size_t)y * (size_t)image->stride;
        for (int x = 0; x < image->width; ++x)
            if (p[4 * x + 3] != 255)
                return 0;
    }
    return 1;
}

/* Row y as straight RGB or RGBA bytes; the opaque BGRA case (every figure) is a plain swizzle. */
static void convert_row(const RenderImage *image, int y, int channels, uint8_t *out)
{
    const uint8_t *p = image->pixels + (size_t)y * (size_t)image->stride;
    int w = image->width;
    if (image->format == RENDER_PIXEL_BGRA_PREMUL && channels == 3) {
        for (int x = 0; x < w; ++x, p += 4, out += 3) {
            out[0] = p[2];
            out[1] = p[1];
            out[2] = p[0];
        }
        return;
    }
    if (image->format == RENDER_PIXEL_RGBA) {
        for (int x = 0; x < w; ++x, p += 4, out += channels)
            memcpy(out, p, (size_t)channels);
        return;
    }
    for (int x = 0; x < w; ++x, out += channels) {
        uint8_t rgba[4];
        render_image_get_rgba(image, x, y, rgba);
        memcpy(out, rgba, (size_t)channels);
    }
}

static int ascii_only(const char *s)
{
    for (; *s; ++s)
        if ((unsigned char)*s >= 0x80)
            return 0;
    return 1;
}

int render_png_write(const RenderImage *image, const char *path, const char *const *text, char *err,
                     size_t err_size)
{
    return render_png_write_dpi(image, path, text, 0.0, err, err_size);
}

int render_png_write_dpi(const RenderImage *image, const char *path, const char *const *text,
                         double dpi, char *err, size_t err_size)
{
    if (!image || !image->pixels || image->width <= 0 || image->height <= 0) {
        render_set_err(err, err_size, "%s: empty image", path);
        return -1;
    }
    char *tmp = render_tmp_name(path, err, err_size);
    if (!tmp)
        return -1;

    PngJob job = {0};
    int opaque = image_is_opaque(image);
    int channels = opaque ? 3 : 4;
    int ntext = 0;
    while (text && text[2 * ntext] && text[2 * ntext + 1])
        ++ntext;
    job.row = malloc((size_t)image->width * 4);
    job.texts = ntext ? calloc((size_t)ntext, sizeof *job.texts) : NULL;
    job.file = fopen(tmp, "wb");
    if (!job.row || (ntext && !job.texts) || !job.file) {
        render_set_err(err, err_size, "%s: %s", tmp, job.file ? "out of memory" : strerror(errno));
        goto fail;
    }
    job.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &job, png_error_fn, png_warning_fn);
    if (!job.png || !(job.info = png_create_info_struct(job.png))) {
        render_set_err(err, err_size, "%s: cannot create libpng writer", path);
        goto fail;
    }
    errno = 0; /* a failed write leaves its reason (ENOSPC: disk full) for the message */
    if (setjmp(png_jmpbuf(job.png))) {
        int why = errno;
        render_set_err(err, err_size, "%s: libpng: %s%s%s", tmp, job.message, why ? ": " : "",
                       why ? strerror(why) : "");
        goto fail;
    }
    png_init_io(job.png, job.file);
    png_set_IHDR(job.png, job.info, (png_uint_32)image->width, (png_uint_32)image->height, 8,
                 opaque ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    /* Flat-colour drawings compress best and fastest unfiltered; zlib level 3 is as small as 6
     * on our figures and a third faster (anchors-render 2d; measured on the 1080p bench). */
    png_set_filter(job.png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
    png_set_compression_level(job.png, 3);
    png_set_sRGB_gAMA_and_cHRM(job.png, job.info, PNG_sRGB_INTENT_PERCEPTUAL);
    /* 96 pixels per inch (or the figure's dpi), the size PDF and SVG figures are written at. */
    png_uint_32 per_metre = dpi > 0 ? (png_uint_32)lround(dpi / 0.0254) : 3780;
    png_set_pHYs(job.png, job.info, per_metre, per_metre, PNG_RESOLUTION_METER);
    for (int k = 0; k < ntext; ++k) {
        png_text *t = &job.texts[k];
        t->key = (png_charp)(uintptr_t)text[2 * k];
        t->text = (png_charp)(uintptr_t)text[2 * k + 1];
        t->text_length = strlen(text[2 * k + 1]);
        /* tEXt is Latin-1; UTF-8 values (e.g. a scene named with mu) go to iTXt. */
        t->compression =
            ascii_only(text[2 * k + 1]) ? PNG_TEXT_COMPRESSION_NONE : PNG_ITXT_COMPRESSION_NONE;
    }
    if (ntext)
        png_set_text(job.png, job.info, job.texts, ntext);
    png_write_info(job.png, job.info);
    for (int y = 0; y < image->height; ++y) {
        convert_row(image, y, channels, job.row);
        png_write_row(job.png, job.row);
    }
    png_write_end(job.png, job.info);
    png_destroy_write_struct(&job.png, &job.info);
    free(job.row);
    free(job.texts);
    int closed = fclose(job.file) == 0;
    if (!closed)
        render_set_err(err, err_size, "%s: %s", tmp, strerror(errno));
    return render_tmp_commit(tmp, path, closed, err, err_size);
fail:
    if (job.png)
        png_destroy_write_struct(&job.png, job.info ? &job.info : NULL);
    free(job.row);
    free(job.texts);
    if (job.file) { /* created: remove it */
        fclose(job.file);
        return render_tmp_commit(tmp, path, 0, err, err_size);
    }
    free(tmp);
    return -1;
}

int render_png_read(const char *path, RenderImage *out, char *err, size_t err_size)
{
    out->pixels = NULL;
    out->width = out->height = out->stride = 0;
    PngJob job = {0};
    const char *why = NULL;
    job.file = sim_open_input(path, &why);
    if (!job.file) {
        render_set_err(err, err_size, "%s: %s", path, why);
        return -1;
    }
    uint8_t sig[8];
    if (fread(sig, 1, 8, job.file) != 8 || png_sig_cmp(sig, 0, 8) != 0) {
        render_set_err(err, err_size, "%s: not a PNG file", path);
        fclose(job.file);
        return -1;
    }
    job.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &job, png_error_fn, png_warning_fn);
    if (!job.png || !(job.info = png_create_info_struct(job.png))) {
        render_set_err(err, err_size, "%s: cannot create libpng reader", path);
        goto fail;
    }
    if (setjmp(png_jmpbuf(job.png))) {
        render_set_err(err, err_size, "%s: libpng: %s", path, job.message);
        goto fail;
    }
    png_init_io(job.png, job.file);
    png_set_sig_bytes(job.png, 8);
    png_read_info(job.png, job.info);
    png_uint_32 w = png_get_image_width(job.png, job.info);
    png_uint_32 h = png_get_image_height(job.png, job.info);
    if (w == 0 || h == 0 || w > 32767 || h > 32767) {
        snprintf(job.message, sizeof job.message, "unsupported size %ux%u", (unsigned)w,
                 (unsigned)h);
        png_error(job.png, job.message);
    }
    /* Whatever the stored type, deliver 8-bit straight RGBA. */
    png_set_expand(job.png);
    png_set_strip_16(job.png);
    png_set_gray_to_rgb(job.png);
    png_set_add_alpha(job.png, 0xff, PNG_FILLER_AFTER);
    png_set_interlace_handling(job.png);
    png_read_update_info(job.png, job.info);
    if (render_image_alloc(out, (int)w, (int)h, RENDER_PIXEL_RGBA) != 0) {
        snprintf(job.message, sizeof job.message, "out of memory");
        png_error(job.png, job.message);
    }
    /* The row pointers live in job.row so they survive a longjmp. */
    job.row = malloc(sizeof(png_bytep) * h);
    if (!job.row) {
        snprintf(job.message, sizeof job.message, "out of memory");
        png_error(job.png, job.message);
    }
    png_bytep *rows = (png_bytep *)(void *)job.row;
    for (png_uint_32 y = 0; y < h; ++y)
        rows[y] = out->pixels + (size_t)y * (size_t)out->stride;
    png_read_image(job.png, rows);
    png_read_end(job.png, NULL);
    png_destroy_read_struct(&job.png, &job.info, NULL);
    free(job.row);
    fclose(job.file);
    return 0;
fail:
    if (job.png)
        png_destroy_read_struct(&job.png, job.info ? &job.info : NULL, NULL);
    free(job.row);
    fclose(job.file);
    render_image_free(out);
    return -1;
}
