/* SPDX-License-Identifier: MIT */
/* render_disks.c: opaque filled disks straight into the pixels of a Cairo image surface, for the
 * grain layer of PNG figures and movie frames (render_cairo.c draw_disks). Cairo spends 2-5 us on
 * a small disk (its arc becomes Bezier curves, then a polygon, then a scan conversion through
 * pixman); a frame of the crater holds 7284 disks with outlines, 14 568 fills. Here a disk's
 * coverage is computed row by row from the circle itself: each pixel row is cut into
 * DISK_SUBROWS sub-rows (Cairo's own scan converter uses 15), each sub-row's chord covers the
 * pixels it spans exactly in x, and the pixel's coverage is the mean over its sub-rows. The
 * colour goes on with the OVER operator in 8 bits, rounded as pixman rounds, so a fully covered
 * pixel has the very bytes Cairo writes and an edge pixel differs from Cairo's by the two
 * scan conversions' difference (a few levels; the circle against Cairo's polygon of it).
 *
 * Positions are fixed point in 1/256 pixel, as Cairo's are: a surface moved by whole pixels
 * (render_cairo_draw_split's bands) then sees every disk at the same place relative to its
 * pixel grid, and each pixel gets the same bytes in a band as in the whole image. */
#include "render/internal.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

enum { DISK_SUBROWS = 16 };

/* x * y / 255 rounded, for x, y in 0..255 (pixman's MUL_UN8). */
static inline uint32_t mul_un8(uint32_t x, uint32_t y)
{
    uint32_t t = x * y + 0x80;
    return (t + (t >> 8)) >> 8;
}

/* Colour `rgb` (0xRRGGBB, opaque) over the premultiplied pixel *p at coverage c (1..255). */
static inline void blend(uint32_t *p, uint32_t rgb, uint32_t c)
{
    if (c >= 255) {
        *p = 0xff000000u | rgb;
        return;
    }
    const uint32_t d = *p, keep = 255 - c;
    uint32_t out = 0;
    for (int shift = 0; shift < 32; shift += 8) {
        const uint32_t s = shift == 24 ? 255 : (rgb >> shift) & 0xff;
        const uint32_t v = mul_un8(s, c) + mul_un8((d >> shift) & 0xff, keep);
        out |= (v > 255 ? 255 : v) << shift;
    }
    *p = out;
}

/* Four sub-rows at a time, in single precision: a coverage goes to 8 bits, and the positions are
 * relative to the disk's first column, below 2^16 pixels, exact in a float's 24 bits. */
typedef float F4 __attribute__((vector_size(4 * sizeof(float))));
typedef int32_t M4 __attribute__((vector_size(4 * sizeof(int32_t))));

enum { DISK_QUADS = DISK_SUBROWS / 4 };

static inline F4 select4(M4 m, F4 a, F4 b)
{
    return (F4)((m & (M4)a) | (~m & (M4)b));
}

static inline F4 larger4(F4 a, F4 b)
{
    return select4(a > b, a, b);
}

static inline F4 smaller4(F4 a, F4 b)
{
    return select4(a < b, a, b);
}

/* Coverage of pixel column [x, x + 1] by the chords [c - h_k, c + h_k] of the row's sub-rows (a
 * sub-row the disk misses has h_k < 0 and adds nothing), in sub-rows: 0..DISK_SUBROWS. */
static inline float column_cover(const F4 *h, float c, float x)
{
    const F4 zero = {0, 0, 0, 0}, left = zero + x, right = zero + (x + 1), centre = zero + c;
    F4 cover = zero;
    for (int q = 0; q < DISK_QUADS; ++q)
        cover += larger4(zero, smaller4(right, centre + h[q]) - larger4(left, centre - h[q]));
    return (cover[0] + cover[1]) + (cover[2] + cover[3]);
}

/* Blends columns [from, to) of a row by their coverage. */
static void edge_run(uint32_t *row, int from, int to, const F4 *h, float c, uint32_t rgb)
{
    for (int x = from; x < to; ++x) {
        const int level = (int)(column_cover(h, c, (float)x) * (255.0f / DISK_SUBROWS) + 0.5f);
        if (level > 0)
            blend(&row[x], rgb, (uint32_t)level);
    }
}

void render_disk_fill(const RenderDiskTarget *t, double cx, double cy, double r, uint32_t rgb)
{
    /* 24.8 fixed point, as Cairo's device coordinates: exact under whole-pixel moves */
    const int64_t fx = llround(cx * 256.0) + t->offset_x * 256;
    const int64_t fy = llround(cy * 256.0) + t->offset_y * 256;
    const int64_t fr = llround(r * 256.0);
    if (fr <= 0)
        return;
    const int64_t left = (fx - fr) >> 8, right = (fx + fr + 255) >> 8;
    const int64_t top = (fy - fr) >> 8, bottom = (fy + fr + 255) >> 8;
    const int64_t x0 = left < 0 ? 0 : left, x1 = right > t->width ? t->width : right;
    const int64_t y0 = top < 0 ? 0 : top, y1 = bottom > t->height ? t->height : bottom;
    if (x0 >= x1 || y0 >= y1)
        return;
    const int n = (int)(x1 - x0);
    const double rr = (double)fr * (double)fr;
    const float c = (float)(fx - x0 * 256) / 256.0f; /* the centre, relative to column x0 */
    const uint32_t opaque = 0xff000000u | rgb;
    for (int64_t y = y0; y < y1; ++y) {
        /* the sub-rows' half chords, pixels (-1: missed); the shortest and the longest */
        F4 h[DISK_QUADS];
        float shortest = HUGE_VALF, longest = -1;
        for (int k = 0; k < DISK_SUBROWS; ++k) {
            const int64_t dy = y * 256 + (256 * k + 128) / DISK_SUBROWS - fy; /* 1/256 pixel */
            const double dd = (double)dy * (double)dy;
            const float hk = dd < rr ? (float)(sqrt(rr - dd) / 256.0) : -1.0f;
            h[k / 4][k % 4] = hk;
            shortest = hk < shortest ? (hk > 0 ? hk : 0) : shortest;
            longest = hk > longest ? hk : longest;
        }
        if (longest <= 0)
            continue;
        /* columns the longest chord touches, and those every sub-row covers whole */
        int from = (int)floorf(c - longest), to = (int)ceilf(c + longest);
        from = from < 0 ? 0 : from;
        to = to > n ? n : to;
        int inner_from = (int)ceilf(c - shortest), inner_to = (int)floorf(c + shortest);
        inner_from = inner_from < from ? from : inner_from;
        inner_to = inner_to > to ? to : inner_to;
        uint32_t *row = (uint32_t *)(t->data + (size_t)y * (size_t)t->stride) + x0;
        if (shortest <= 0 || inner_from >= inner_to) {
            edge_run(row, from, to, h, c, rgb);
            continue;
        }
        edge_run(row, from, inner_from, h, c, rgb);
        for (int x = inner_from; x < inner_to; ++x)
            row[x] = opaque;
        edge_run(row, inner_to, to, h, c, rgb);
    }
}
