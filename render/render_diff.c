/* SPDX-License-Identifier: MIT */
/* render_diff.c: image comparison for tests and CI. A pixel counts when a channel differs by more
 * than a threshold AND a shift of up to shift_tolerance pixels does not explain it, in both
 * directions (VTK's AllowShift idea, anchors-render 3.2): renderer noise and sub-pixel moves give
 * 0, a missing force-chain segment does not. RMS is reported but never decides. */
#include "render/internal.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

RenderDiffOptions render_diff_options_default(void)
{
    RenderDiffOptions o = {.channel_threshold = 32, .shift_tolerance = 1, .max_pixels = 0};
    return o;
}

static int max_channel_diff(const uint8_t *p, const uint8_t *q)
{
    int m = 0;
    for (int c = 0; c < 4; ++c) {
        int d = abs((int)p[c] - (int)q[c]);
        if (d > m)
            m = d;
    }
    return m;
}

/* 1 when pixel (x, y) of `from` matches some pixel of `to` within `shift` pixels. */
static int matched_nearby(const uint8_t *from, const uint8_t *to, int w, int h, int x, int y,
                          int shift, int threshold)
{
    const uint8_t *p = from + 4 * ((size_t)y * (size_t)w + (size_t)x);
    for (int dy = -shift; dy <= shift; ++dy) {
        int yy = y + dy;
        if (yy < 0 || yy >= h)
            continue;
        for (int dx = -shift; dx <= shift; ++dx) {
            int xx = x + dx;
            if (xx < 0 || xx >= w)
                continue;
            if (max_channel_diff(p, to + 4 * ((size_t)yy * (size_t)w + (size_t)xx)) <= threshold)
                return 1;
        }
    }
    return 0;
}

/* Straight RGBA copy of any image, rows packed. */
static uint8_t *to_rgba(const RenderImage *image)
{
    uint8_t *buf = malloc((size_t)image->width * (size_t)image->height * 4);
    if (!buf)
        return NULL;
    for (int y = 0; y < image->height; ++y)
        for (int x = 0; x < image->width; ++x)
            render_image_get_rgba(image, x, y, buf + 4 * ((size_t)y * (size_t)image->width + x));
    return buf;
}

int render_diff_images(const RenderImage *a, const RenderImage *b, const RenderDiffOptions *options,
                       RenderImage *diff, RenderDiffResult *result, char *err, size_t err_size)
{
    RenderDiffOptions opt = options ? *options : render_diff_options_default();
    RenderDiffResult r = {0};
    r.options = opt;
    r.verdict = 2;
    r.width = a->width;
    r.height = a->height;
    if (diff)
        diff->pixels = NULL;
    if (a->width != b->width || a->height != b->height) {
        render_set_err(err, err_size, "different sizes: %dx%d and %dx%d", a->width, a->height,
                       b->width, b->height);
        if (result)
            *result = r;
        return 2;
    }
    int w = a->width, h = a->height;
    uint8_t *pa = to_rgba(a), *pb = to_rgba(b);
    if (!pa || !pb || (diff && render_image_alloc(diff, w, h, RENDER_PIXEL_RGBA) != 0)) {
        free(pa);
        free(pb);
        render_set_err(err, err_size, "out of memory");
        if (result)
            *result = r;
        return 2;
    }
    double sum2 = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            size_t k = 4 * ((size_t)y * (size_t)w + (size_t)x);
            int d = max_channel_diff(pa + k, pb + k);
            for (int c = 0; c < 4; ++c) {
                double e = (double)pa[k + c] - (double)pb[k + c];
                sum2 += e * e;
            }
            if (d > r.max_channel_diff)
                r.max_channel_diff = d;
            int kind = 0; /* 0 same, 1 within threshold, 2 explained by a shift, 3 unexplained */
            if (d > opt.channel_threshold) {
                ++r.raw_pixels;
                kind = 3;
                if (opt.shift_tolerance > 0 &&
                    matched_nearby(pa, pb, w, h, x, y, opt.shift_tolerance,
                                   opt.channel_threshold) &&
                    matched_nearby(pb, pa, w, h, x, y, opt.shift_tolerance, opt.channel_threshold))
                    kind = 2;
                if (kind == 3)
                    ++r.differing_pixels;
            } else if (d > 0) {
                kind = 1;
            }
            if (diff) {
                /* Faded grey copy of A; red unexplained, orange shift-explained, yellow small. */
                static const uint8_t marks[4][3] = {
                    {0, 0, 0}, {255, 220, 0}, {255, 140, 0}, {230, 0, 0}};
                uint8_t *o = diff->pixels + (size_t)y * (size_t)diff->stride + 4 * (size_t)x;
                if (kind == 0) {
                    double lum = 0.2126 * pa[k] + 0.7152 * pa[k + 1] + 0.0722 * pa[k + 2];
                    uint8_t g = (uint8_t)(170.0 + lum * (85.0 / 255.0) + 0.5);
                    o[0] = o[1] = o[2] = g;
                } else {
                    memcpy(o, marks[kind], 3);
                }
                o[3] = 255;
            }
        }
    }
    free(pa);
    free(pb);
    r.rms = sqrt(sum2 / ((double)w * (double)h * 4.0));
    r.verdict = r.differing_pixels > opt.max_pixels ? 1 : 0;
    if (result)
        *result = r;
    if (r.verdict == 1)
        render_set_err(err, err_size, "%ld pixels differ (threshold %d, shift %d, allowed %ld)",
                       r.differing_pixels, opt.channel_threshold, opt.shift_tolerance,
                       opt.max_pixels);
    return r.verdict;
}

int render_diff_files(const char *a, const char *b, const RenderDiffOptions *options,
                      const char *diff_path, RenderDiffResult *result, char *err, size_t err_size)
{
    RenderImage ia, ib, id;
    RenderDiffResult r = {0};
    r.options = options ? *options : render_diff_options_default();
    r.verdict = 2;
    if (result)
        *result = r;
    if (render_figure_read(a, 0.0, &ia, err, err_size) != 0)
        return 2;
    if (render_figure_read(b, 0.0, &ib, err, err_size) != 0) {
        render_image_free(&ia);
        return 2;
    }
    int rc = render_diff_images(&ia, &ib, options, diff_path ? &id : NULL, result, err, err_size);
    if (rc == 2 && (ia.width != ib.width || ia.height != ib.height))
        render_set_err(err, err_size, "different sizes: %s is %dx%d, %s is %dx%d", a, ia.width,
                       ia.height, b, ib.width, ib.height);
    if (diff_path && rc != 2) {
        char werr[300];
        if (render_png_write(&id, diff_path, NULL, werr, sizeof werr) != 0) {
            render_set_err(err, err_size, "%s", werr);
            rc = 2;
            if (result)
                result->verdict = 2;
        }
        render_image_free(&id);
    }
    render_image_free(&ia);
    render_image_free(&ib);
    return rc;
}

int render_diff_result_json(const RenderDiffResult *r, char *buf, size_t size)
{
    static const char *const verdicts[3] = {"match", "differ", "error"};
    int v = r->verdict >= 0 && r->verdict <= 2 ? r->verdict : 2;
    return snprintf(buf, size,
                    "{\"verdict\":\"%s\",\"width\":%d,\"height\":%d,\"differing_pixels\":%ld,"
                    "\"raw_pixels\":%ld,\"max_channel_diff\":%d,\"rms\":%.4f,"
                    "\"channel_threshold\":%d,\"shift_tolerance\":%d,\"max_pixels\":%ld}",
                    verdicts[v], r->width, r->height, r->differing_pixels, r->raw_pixels,
                    r->max_channel_diff, r->rms, r->options.channel_threshold,
                    r->options.shift_tolerance, r->options.max_pixels);
}
