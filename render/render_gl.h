/* SPDX-License-Identifier: MIT */
/* render_gl.h: internal header of the GL movie drawer (render_gl.c). Draws the grain layer of a
 * frame (background, walls, force chains, disks with outlines and orientation ticks) with
 * shader-drawn disks on llvmpipe through OSMesa; the annotations (colour bar, text, scale bar,
 * arrows, velocity field, arches and inset) go on top with render_cairo_overlay. Images are BGRA
 * (Cairo's ARGB32 byte order), so the overlay draws on them in place. The GL context lives in
 * one struct in render_gl.c so that an EGL surfaceless back end can replace OSMesa (gone in
 * Mesa >= 25.1). */
#ifndef RENDER_GL_H
#define RENDER_GL_H

#include "render/render_image.h"
#include "render/render_style.h"
#include "sim/sim.h"

#include <stddef.h>

/// A persistent GL drawer of one size (contexts, shaders, buffers); one per thread. It draws the
/// lower half of each image in a helper thread of its own when the machine has two CPUs or more
/// (environment SABLIER_GL_BANDS=1 keeps all drawing in the calling thread, =2 forces the helper).
typedef struct RenderGl RenderGl;

/// Creates a drawer for width x height pixels. NULL on failure with a message in err.
RenderGl *render_gl_create(int width, int height, char *err, size_t err_size);
void render_gl_destroy(RenderGl *gl);
/// Draws one frame (style->width/height must equal the drawer's size). On success *out views the
/// drawer's own BGRA buffer (RENDER_PIXEL_BGRA_PREMUL, rows top-down, opaque), valid until the
/// next draw or destroy. 0 on success, else -1 and a message in err.
int render_gl_frame(RenderGl *gl, const SimFrame *frame, const RenderStyle *style, RenderImage *out,
                    char *err, size_t err_size);
/// Draws one frame into the caller's image (the drawer's size, stride 4 * width; its format is
/// set to RENDER_PIXEL_BGRA_PREMUL): no copy, so a movie draws straight into its frame queue.
int render_gl_frame_to(RenderGl *gl, const SimFrame *frame, const RenderStyle *style,
                       RenderImage *target, char *err, size_t err_size);
/// GL_RENDERER of the drawer's context, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
const char *render_gl_renderer(const RenderGl *gl);
/// One-shot drawing with the same signature as render_cairo_draw: a new BGRA image the caller
/// frees with render_image_free. 0 on success. Slow per call (creates a context): for movies keep
/// a RenderGl.
int render_gl_draw(const SimFrame *frame, const RenderStyle *style, RenderImage *out);

#endif
