/* SPDX-License-Identifier: MIT */
/* render_image.c: the RenderImage hand-off struct. */
#include "render/render_image.h"

#include <stdlib.h>

int render_image_alloc(RenderImage *image, int width, int height, RenderPixelFormat format)
{
    image->width = image->height = image->stride = 0;
    image->format = format;
    image->pixels = NULL;
    if (width <= 0 || height <= 0 || width > 32767 || height > 32767)
        return -1;
    image->pixels = calloc((size_t)width * (size_t)height, 4);
    if (!image->pixels)
        return -1;
    image->width = width;
    image->height = height;
    image->stride = 4 * width;
    return 0;
}

void render_image_free(RenderImage *image)
{
    if (!image)
        return;
    free(image->pixels);
    image->pixels = NULL;
    image->width = image->height = image->stride = 0;
}

void render_image_get_rgba(const RenderImage *image, int x, int y, uint8_t rgba[4])
{
    const uint8_t *p = image->pixels + (size_t)y * (size_t)image->stride + 4 * (size_t)x;
    if (image->format == RENDER_PIXEL_RGBA) {
        rgba[0] = p[0];
        rgba[1] = p[1];
        rgba[2] = p[2];
        rgba[3] = p[3];
        return;
    }
    /* Premultiplied B, G, R, A: divide back, rounding to nearest. */
    unsigned a = p[3];
    rgba[3] = (uint8_t)a;
    if (a == 255) {
        rgba[0] = p[2];
        rgba[1] = p[1];
        rgba[2] = p[0];
    } else if (a == 0) {
        rgba[0] = rgba[1] = rgba[2] = 0;
    } else {
        for (int c = 0; c < 3; ++c) {
            unsigned v = (p[2 - c] * 255u + a / 2) / a;
            rgba[c] = (uint8_t)(v > 255 ? 255 : v);
        }
    }
}
