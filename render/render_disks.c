/* SPDX-License-Identifier: MIT */
/* render_disks.c: opaque filled disks and capsules straight into the pixels of a Cairo image
 * surface, for the grains and force chains of PNG figures and movie frames (render_cairo.c
 * draw_disks, draw_chains). Cairo spends 4-9 us on a small disk (its arc becomes Bezier curves,
 * then a polygon, then a scan conversion through pixman) and as much on a chain's stroke; a frame
 * of the crater holds 7284 disks with outlines, 14 568 fills. Here a shape's coverage is computed
 * row by row from the shape itself: each pixel row is cut into
 * DISK_SUBROWS sub-rows (Cairo's own scan converter uses 15), each sub-row's chord covers the
 * pixels it spans exactly in x, and the pixel's coverage is the mean over its sub-rows. The
 * colour goes on with the OVER operator in 8 bits, rounded as pixman rounds, so a fully covered
 * pixel has the very bytes Cairo writes and an edge pixel differs from Cairo's by the two
 * scan conversions' difference (a few levels; the circle against Cairo's polygon of it).
 *
 * Positions are fixed point in 1/256 pixel, as Cairo's are: a surface moved by whole pixels
 * (render_cairo_draw_split's bands) then sees every shape at the same place relative to its
 * pixel grid, and each pixel gets the same bytes in a band as in the whole image. */
#include "render/internal.h"

#include <math.h>
#include <stdint.h>

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

/* The larger and the smaller of two (no NaN here): one instruction each, where fmax and fmin are
 * calls into libm (their NaN rules). */
static inline double larger(double a, double b)
{
    return a > b ? a : b;
}

static inline double smaller(double a, double b)
{
    return a < b ? a : b;
}

static inline float largerf(float a, float b)
{
    return a > b ? a : b;
}

static inline float smallerf(float a, float b)
{
    return a < b ? a : b;
}

/* A row's sub-rows as spans [lo_k, hi_k] in pixels from the shape's first column; a sub-row the
 * shape misses has lo_k > hi_k and adds nothing. */
typedef struct Spans {
    F4 lo[DISK_QUADS], hi[DISK_QUADS];
} Spans;

/* Coverage of pixel column [x, x + 1] by the row's spans, in sub-rows: 0..DISK_SUBROWS. */
static inline float column_cover(const Spans *s, float x)
{
    const F4 zero = {0, 0, 0, 0}, left = zero + x, right = zero + (x + 1);
    F4 cover = zero;
    for (int q = 0; q < DISK_QUADS; ++q)
        cover += larger4(zero, smaller4(right, s->hi[q]) - larger4(left, s->lo[q]));
    return (cover[0] + cover[1]) + (cover[2] + cover[3]);
}

/* Blends columns [from, to) of a row by their coverage. */
static void edge_run(uint32_t *row, int from, int to, const Spans *s, uint32_t rgb)
{
    for (int x = from; x < to; ++x) {
        const int level = (int)(column_cover(s, (float)x) * (255.0f / DISK_SUBROWS) + 0.5f);
        if (level > 0)
            blend(&row[x], rgb, (uint32_t)level);
    }
}

/* One pixel row of a convex shape: the columns that every sub-row covers whole get the colour,
 * those its spans reach in part are blended by their coverage. n: the row's columns from the
 * shape's first one (the target's edge clips). */
static void fill_row(uint32_t *row, int n, const Spans *s, uint32_t rgb)
{
    float outer_lo = HUGE_VALF, outer_hi = -HUGE_VALF, inner_lo = -HUGE_VALF, inner_hi = HUGE_VALF;
    for (int k = 0; k < DISK_SUBROWS; ++k) {
        const float lo = s->lo[k / 4][k % 4], hi = s->hi[k / 4][k % 4];
        if (lo > hi) { /* a missed sub-row: no column is whole */
            inner_lo = HUGE_VALF;
            continue;
        }
        outer_lo = smallerf(outer_lo, lo);
        outer_hi = largerf(outer_hi, hi);
        inner_lo = largerf(inner_lo, lo);
        inner_hi = smallerf(inner_hi, hi);
    }
    if (!(outer_lo < outer_hi))
        return;
    int from = (int)floorf(outer_lo), to = (int)ceilf(outer_hi);
    from = from < 0 ? 0 : from;
    to = to > n ? n : to;
    int inner_from = inner_lo < HUGE_VALF ? (int)ceilf(inner_lo) : to;
    int inner_to = inner_lo < HUGE_VALF ? (int)floorf(inner_hi) : to;
    inner_from = inner_from < from ? from : inner_from > to ? to : inner_from;
    inner_to = inner_to < inner_from ? inner_from : inner_to > to ? to : inner_to;
    edge_run(row, from, inner_from, s, rgb);
    const uint32_t opaque = 0xff000000u | rgb;
    for (int x = inner_from; x < inner_to; ++x)
        row[x] = opaque;
    edge_run(row, inner_to, to, s, rgb);
}

/* A point in 24.8 fixed point device coordinates, as Cairo's: exact under whole-pixel moves. */
static inline int64_t fixed(double v, int offset)
{
    return llround(v * 256.0) + (int64_t)offset * 256;
}

/* The sub-row k of pixel row y, 1/256 pixel. */
static inline int64_t subrow(int64_t y, int k)
{
    return y * 256 + (256 * k + 128) / DISK_SUBROWS;
}

/* The target's columns [x0, x1) and rows [y0, y1) that the box [left, right] x [top, bottom]
 * (1/256 pixel) touches; 0 when none. */
static int clip_box(const RenderDiskTarget *t, int64_t left, int64_t right, int64_t top,
                    int64_t bottom, int64_t box[4])
{
    left >>= 8;
    top >>= 8;
    right = (right + 255) >> 8;
    bottom = (bottom + 255) >> 8;
    box[0] = left < 0 ? 0 : left;
    box[1] = right > t->width ? t->width : right;
    box[2] = top < 0 ? 0 : top;
    box[3] = bottom > t->height ? t->height : bottom;
    return box[0] < box[1] && box[2] < box[3];
}

static inline uint32_t *row_at(const RenderDiskTarget *t, int64_t y, int64_t x0)
{
    return (uint32_t *)(t->data + (size_t)y * (size_t)t->stride) + x0;
}

void render_disk_fill(const RenderDiskTarget *t, double cx, double cy, double r, uint32_t rgb)
{
    const int64_t fx = fixed(cx, t->offset_x), fy = fixed(cy, t->offset_y), fr = llround(r * 256.0);
    int64_t box[4];
    if (fr <= 0 || !clip_box(t, fx - fr, fx + fr, fy - fr, fy + fr, box))
        return;
    const double rr = (double)fr * (double)fr;
    const float c = (float)(fx - box[0] * 256) / 256.0f; /* the centre, from column x0 */
    for (int64_t y = box[2]; y < box[3]; ++y) {
        Spans s;
        for (int k = 0; k < DISK_SUBROWS; ++k) {
            const double dy = (double)(subrow(y, k) - fy), dd = dy * dy;
            const float h = dd < rr ? (float)(sqrt(rr - dd) / 256.0) : -1.0f;
            s.lo[k / 4][k % 4] = c - h;
            s.hi[k / 4][k % 4] = c + h;
        }
        fill_row(row_at(t, y, box[0]), (int)(box[1] - box[0]), &s, rgb);
    }
}

/* Where the line y = sy (pixels from the first point) meets the capsule of the segment from the
 * origin to (dx, dy) with radius r: [*lo, *hi] in x from the first point, or lo > hi. */
static void capsule_span(double sy, double dx, double dy, double r, double *lo, double *hi)
{
    *lo = HUGE_VAL;
    *hi = -HUGE_VAL;
    const double ends[2][2] = {{0, 0}, {dx, dy}};
    for (int e = 0; e < 2; ++e) { /* the two round caps */
        const double v = sy - ends[e][1], dd = r * r - v * v;
        if (dd > 0) {
            const double h = sqrt(dd);
            *lo = smaller(*lo, ends[e][0] - h);
            *hi = larger(*hi, ends[e][0] + h);
        }
    }
    /* the band between them: 0 <= (x dx + sy dy) <= L^2 and |x dy - sy dx| <= r L */
    const double ll = dx * dx + dy * dy, l = sqrt(ll);
    if (!(ll > 0))
        return;
    double a = -HUGE_VAL, b = HUGE_VAL;
    const double limits[2][3] = {{dx, -sy * dy, ll - sy * dy},
                                 {dy, sy * dx - r * l, sy * dx + r * l}};
    for (int c = 0; c < 2; ++c) {
        const double k = limits[c][0], m1 = limits[c][1], m2 = limits[c][2];
        if (k > 0) {
            a = larger(a, m1 / k);
            b = smaller(b, m2 / k);
        } else if (k < 0) {
            a = larger(a, m2 / k);
            b = smaller(b, m1 / k);
        } else if (m1 > 0 || m2 < 0) {
            return; /* the line runs beside the band */
        }
    }
    if (a <= b) {
        *lo = smaller(*lo, a);
        *hi = larger(*hi, b);
    }
}

void render_capsule_fill(const RenderDiskTarget *t, double px, double py, double qx, double qy,
                         double r, uint32_t rgb)
{
    const int64_t fpx = fixed(px, t->offset_x), fpy = fixed(py, t->offset_y);
    const int64_t fqx = fixed(qx, t->offset_x), fqy = fixed(qy, t->offset_y);
    const int64_t fr = llround(r * 256.0);
    int64_t box[4];
    if (fr <= 0 || !clip_box(t, (fpx < fqx ? fpx : fqx) - fr, (fpx > fqx ? fpx : fqx) + fr,
                             (fpy < fqy ? fpy : fqy) - fr, (fpy > fqy ? fpy : fqy) + fr, box))
        return;
    const double dx = (double)(fqx - fpx) / 256.0, dy = (double)(fqy - fpy) / 256.0;
    const double from = (double)(fpx - box[0] * 256) / 256.0; /* the first point, from column x0 */
    const double radius = (double)fr / 256.0;
    for (int64_t y = box[2]; y < box[3]; ++y) {
        Spans s;
        for (int k = 0; k < DISK_SUBROWS; ++k) {
            double lo, hi;
            capsule_span((double)(subrow(y, k) - fpy) / 256.0, dx, dy, radius, &lo, &hi);
            s.lo[k / 4][k % 4] = lo <= hi ? (float)(from + lo) : 1.0f;
            s.hi[k / 4][k % 4] = lo <= hi ? (float)(from + hi) : -1.0f;
        }
        fill_row(row_at(t, y, box[0]), (int)(box[1] - box[0]), &s, rgb);
    }
}
