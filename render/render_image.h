/* SPDX-License-Identifier: MIT */
/* render_image.h: the hand-off between drawers (Cairo, OSMesa) and writers (PNG, MP4).
 * Any drawer works with any writer through this one struct. */
#ifndef RENDER_IMAGE_H
#define RENDER_IMAGE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum RenderPixelFormat {
    RENDER_PIXEL_BGRA_PREMUL = 0, ///< Cairo ARGB32 on little-endian: bytes B,G,R,A, premultiplied
    RENDER_PIXEL_RGBA = 1,        ///< bytes R,G,B,A, straight alpha, rows top-down
} RenderPixelFormat;

/// An image owned by whoever produced it; rows are top-down, `stride` bytes apart.
typedef struct RenderImage {
    int width, height, stride; ///< pixels, pixels, bytes
    RenderPixelFormat format;
    uint8_t *pixels;
} RenderImage;

/// Allocates a zeroed image (stride = 4 * width); returns 0 on success.
int render_image_alloc(RenderImage *image, int width, int height, RenderPixelFormat format);
void render_image_free(RenderImage *image);
/// Reads pixel (x, y) as straight-alpha 8-bit R, G, B, A whatever the format.
void render_image_get_rgba(const RenderImage *image, int x, int y, uint8_t rgba[4]);

#ifdef __cplusplus
}
#endif

#endif
