/* SPDX-License-Identifier: MIT */
/* render_gl.c: the fast movie drawer. GL 3.3 core on llvmpipe through OSMesa; every disk is one
 * point sprite whose fragment shader keeps the pixels inside the circle and antialiases the rim
 * by the area of the pixel inside it (outline ring in the same fragment); orientation ticks and
 * walls are quads (two indexed triangles) and force chains wide lines (one primitive each), with
 * the same analytic coverage.
 *
 * Speed (1920x1080, 7284 grains and ~8k chains; bench/README.md): llvmpipe shades vertices and
 * sets up primitives in the drawing thread and shades fragments in LP_NUM_THREADS threads on 4x4
 * blocks, executing both sides of every branch, so the drawer uses plain vertex arrays (no
 * instancing: per-instance overhead), one vertex per disk, branch-free coverage, separate round
 * and butt programs, the clip compiled in only when something reaches it, constants instead of
 * fragment-shader uniforms, persistent buffers (glBufferSubData), and reads the frame straight
 * into the caller's image (render_gl_frame_to). The image is drawn in two horizontal bands by two
 * threads with a context each (struct Band), which halves the serial part of a frame.
 *
 * What is drawn follows the Cairo drawer (render_cairo.c, the reference) in order, colours and
 * sizes, so both agree within the image-diff tolerance: background; clipped to the plot
 * rectangle: disks in frame order (fill by RenderStyle.color_by through the shared colour
 * functions, fixed grains in fixed_rgb, dark outline ring), orientation ticks, walls, force
 * chains weakest first (width and colour by F_n); periodic copies across the seam. Layout
 * (render_layout.c), colours and chain selection come from internal.h's shared helpers; colours
 * reach GL as the same 8-bit values Cairo uses. The annotations (velocity arrows and field, arch
 * highlights and inset, colour bar, time stamp, scale bar, title) are Cairo's, drawn on the GL
 * image by render_cairo_overlay.
 *
 * The GL context is the one struct GlContext below (create, make current, release, destroy);
 * GL entry points come through its proc-address function and each band draws into a framebuffer
 * object read back with glReadPixels, so an EGL surfaceless back end (eglGetProcAddress,
 * eglMakeCurrent without a surface) replaces OSMesa here alone. */
#include "render/internal.h"

#include <GL/osmesa.h>
#include <math.h>
#include <pthread.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------ GL context (OSMesa) */

typedef void (*GlProc)(void);

/* OSMesa's own colour buffer is 1 x 1 and never drawn: frames go to the drawer's framebuffer
 * object and come back with glReadPixels, as they would from an EGL surfaceless context. */
typedef struct GlContext {
    OSMesaContext osmesa;
    uint8_t surface[4];
} GlContext;

/* llvmpipe reads LP_NUM_THREADS once, when the first context creates its screen; by default it
 * takes every online CPU. Set it explicitly (unless the user did) so the rasteriser uses the
 * cores the machine has (anchors-render: 16.3 ms with 1 thread, 10.9 ms with 2). */
static void set_rasteriser_threads(void)
{
    if (getenv("LP_NUM_THREADS"))
        return;
    const int cpus = sim_cpu_count(); /* the affinity mask's: taskset, a batch system's CPU set */
    char value[16];
    snprintf(value, sizeof value, "%d", cpus < 32 ? cpus : 32);
    setenv("LP_NUM_THREADS", value, 0);
}

static pthread_once_t threads_once = PTHREAD_ONCE_INIT;

static int context_create(GlContext *context, char *err, size_t err_size)
{
    /* Core 3.3 without depth or stencil: llvmpipe in Mesa 22.3 gives 4.5 core. */
    static const int attributes[] = {OSMESA_FORMAT,
                                     OSMESA_BGRA,
                                     OSMESA_DEPTH_BITS,
                                     0,
                                     OSMESA_STENCIL_BITS,
                                     0,
                                     OSMESA_ACCUM_BITS,
                                     0,
                                     OSMESA_PROFILE,
                                     OSMESA_CORE_PROFILE,
                                     OSMESA_CONTEXT_MAJOR_VERSION,
                                     3,
                                     OSMESA_CONTEXT_MINOR_VERSION,
                                     3,
                                     0};
    pthread_once(&threads_once, set_rasteriser_threads);
    context->osmesa = OSMesaCreateContextAttribs(attributes, NULL);
    if (!context->osmesa) {
        snprintf(err, err_size, "GL: OSMesa cannot create a GL 3.3 core context");
        return -1;
    }
    return 0;
}

static int context_make_current(GlContext *context)
{
    return OSMesaMakeCurrent(context->osmesa, context->surface, GL_UNSIGNED_BYTE, 1, 1) ? 0 : -1;
}

static GlProc context_proc(const char *name)
{
    return (GlProc)OSMesaGetProcAddress(name);
}

/* Leaves the calling thread without a current context. */
static void context_release(void)
{
    OSMesaMakeCurrent(NULL, NULL, 0, 0, 0);
}

static void context_destroy(GlContext *context)
{
    if (context->osmesa)
        OSMesaDestroyContext(context->osmesa);
    context->osmesa = NULL;
}

/* ------------------------------------------------------------------ GL entry points */

/* Every GL function used: return type, name without the gl prefix, parameter list. */
#define GL_FUNCTIONS(X)                                                                            \
    X(void, Viewport, (GLint, GLint, GLsizei, GLsizei))                                            \
    X(void, ClearColor, (GLfloat, GLfloat, GLfloat, GLfloat))                                      \
    X(void, Clear, (GLbitfield))                                                                   \
    X(void, Enable, (GLenum))                                                                      \
    X(void, GetFloatv, (GLenum, GLfloat *))                                                        \
    X(void, GetIntegerv, (GLenum, GLint *))                                                        \
    X(void, BlendFuncSeparate, (GLenum, GLenum, GLenum, GLenum))                                   \
    X(GLenum, GetError, (void))                                                                    \
    X(const GLubyte *, GetString, (GLenum))                                                        \
    X(GLuint, CreateShader, (GLenum))                                                              \
    X(void, ShaderSource, (GLuint, GLsizei, const GLchar *const *, const GLint *))                 \
    X(void, CompileShader, (GLuint))                                                               \
    X(void, GetShaderiv, (GLuint, GLenum, GLint *))                                                \
    X(void, GetShaderInfoLog, (GLuint, GLsizei, GLsizei *, GLchar *))                              \
    X(void, DeleteShader, (GLuint))                                                                \
    X(GLuint, CreateProgram, (void))                                                               \
    X(void, AttachShader, (GLuint, GLuint))                                                        \
    X(void, LinkProgram, (GLuint))                                                                 \
    X(void, GetProgramiv, (GLuint, GLenum, GLint *))                                               \
    X(void, GetProgramInfoLog, (GLuint, GLsizei, GLsizei *, GLchar *))                             \
    X(void, DeleteProgram, (GLuint))                                                               \
    X(void, UseProgram, (GLuint))                                                                  \
    X(GLint, GetUniformLocation, (GLuint, const GLchar *))                                         \
    X(void, Uniform4f, (GLint, GLfloat, GLfloat, GLfloat, GLfloat))                                \
    X(void, GenVertexArrays, (GLsizei, GLuint *))                                                  \
    X(void, BindVertexArray, (GLuint))                                                             \
    X(void, GenBuffers, (GLsizei, GLuint *))                                                       \
    X(void, BindBuffer, (GLenum, GLuint))                                                          \
    X(void, BufferData, (GLenum, GLsizeiptr, const void *, GLenum))                                \
    X(void, BufferSubData, (GLenum, GLintptr, GLsizeiptr, const void *))                           \
    X(void, EnableVertexAttribArray, (GLuint))                                                     \
    X(void, VertexAttribPointer, (GLuint, GLint, GLenum, GLboolean, GLsizei, const void *))        \
    X(void, VertexAttribDivisor, (GLuint, GLuint))                                                 \
    X(void, DrawArrays, (GLenum, GLint, GLsizei))                                                  \
    X(void, DrawElements, (GLenum, GLsizei, GLenum, const void *))                                 \
    X(void, DrawArraysInstanced, (GLenum, GLint, GLsizei, GLsizei))                                \
    X(void, LineWidth, (GLfloat))                                                                  \
    X(void, GenTextures, (GLsizei, GLuint *))                                                      \
    X(void, BindTexture, (GLenum, GLuint))                                                         \
    X(void, TexImage2D,                                                                            \
      (GLenum, GLint, GLint, GLsizei, GLsizei, GLint, GLenum, GLenum, const void *))               \
    X(void, GenFramebuffers, (GLsizei, GLuint *))                                                  \
    X(void, BindFramebuffer, (GLenum, GLuint))                                                     \
    X(void, FramebufferTexture2D, (GLenum, GLenum, GLenum, GLuint, GLint))                         \
    X(GLenum, CheckFramebufferStatus, (GLenum))                                                    \
    X(void, ReadPixels, (GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, void *))

typedef struct GlApi {
#define API_MEMBER(type, name, parameters) type(GLAPIENTRY *name) parameters;
    GL_FUNCTIONS(API_MEMBER)
#undef API_MEMBER
} GlApi;

static int api_load(GlApi *api, char *err, size_t err_size)
{
    GlProc proc;
#define LOAD_ENTRY(type, name, parameters)                                                         \
    proc = context_proc("gl" #name);                                                               \
    if (!proc) {                                                                                   \
        snprintf(err, err_size, "GL: no entry point gl%s", #name);                                 \
        return -1;                                                                                 \
    }                                                                                              \
    api->name = (type(GLAPIENTRY *) parameters)proc;
    GL_FUNCTIONS(LOAD_ENTRY)
#undef LOAD_ENTRY
    return 0;
}

/* ------------------------------------------------------------------ shaders */

/* Instance attributes are in pixels with y down (Cairo's device space); the vertex shaders map
 * them to clip space so that window row 0 is the image's top row.
 *
 * Antialiasing is the area of the pixel square inside the shape, as Cairo computes it, with the
 * shape's edge taken as straight across the pixel: the fraction of a pixel whose centre lies at
 * distance t inside an edge with unit normal n. The pixel projected onto n is a box of width
 * a = max(|n_x|, |n_y|) convolved with one of width b = min(...): a trapezoid, whose
 * distribution function at s = t + (a + b) / 2 is
 *     F(s) = [R(s)^2 - R(s - a)^2 - R(s - b)^2 + R(s - a - b)^2] / (2 a b),  R(x) = max(x, 0)
 * (0 below the trapezoid, 1 above it). A plain one-dimensional box (clamp(r - d + 1/2)) is off by
 * up to 0.15 of a pixel on diagonal edges, 30 levels on a dark outline against a light fill.
 *
 * Speed (llvmpipe runs fragment shaders on 4x4 blocks with every branch of an `if` executed):
 * the formula is branch-free, the footprint is computed once per fragment and shared by both
 * edges of a shape, b is kept above a / 64 (a trapezoid that narrow differs from the box by under
 * 0.002 of coverage, half a level), round and butt segments are separate programs, and the
 * plot-rectangle clip is compiled in (CLIP 1) only when a frame has primitives that reach it.
 * Per eight pixels the cost is counted in instructions of llvmpipe's code (bench/README.md,
 * render round 4): the normal is left unnormalised (depths are scaled by its length instead: one
 * square root and one division per fragment), the distribution function is a clamped ramp less
 * a signed parabolic bump (no clamp between two variables: llvmpipe's NaN handling makes each
 * such min or max three instructions), and the min and max of values >= 0 go through their
 * bits (one integer instruction). */
static const char common_source[] =
    "uniform vec4 clip;\n"  /* x0, y0, x1, y1, px, y down */
    "uniform vec4 frame;\n" /* image width, band height, viewport margin, band's first row, px */
    "vec4 clip_position(vec2 p) {\n"
    "    vec2 q = (p - vec2(0.0, frame.w) + frame.z) / (frame.xy + 2.0 * frame.z);\n"
    "    return vec4(2.0 * q.x - 1.0, 2.0 * q.y - 1.0, 0.0, 1.0);\n"
    "}\n";

static const char fragment_common_source[] =
    /* Minimum and maximum of two floats >= 0 by their bits: one integer instruction (a float
     * min or max between two variables costs three in llvmpipe, which handles NaN). */
    "float max_pos(float x, float y) {\n"
    "    return intBitsToFloat(max(floatBitsToInt(x), floatBitsToInt(y)));\n"
    "}\n"
    "float min_pos(float x, float y) {\n"
    "    return intBitsToFloat(min(floatBitsToInt(x), floatBitsToInt(y)));\n"
    "}\n"
    /* The footprint of a pixel seen along v, a normal of any length L, in units of L:
     * (a / 2, b / 2, 1 / a, 1 / (2 a b)) times (L, L, 1 / L, 1 / L^2), so that a depth t
     * given as t L needs no division by L. */
    "vec4 footprint(vec2 v) {\n"
    "    vec2 m = abs(v);\n"
    "    float a = max(max_pos(m.x, m.y), 1e-6);\n"
    "    float b = max_pos(min_pos(m.x, m.y), a * (1.0 / 64.0));\n"
    "    float inv = 1.0 / (a * b);\n"
    "    return vec4(0.5 * a, 0.5 * b, b * inv, 0.5 * inv);\n"
    "}\n"
    /* Share of the pixel whose centre lies at depth t inside an edge, from tl = t L: the ramp
     * 1/2 + t / a, clamped, less a parabolic bump of width b centred on t = +-a/2 (the
     * trapezoid's rounded corners), with the sign of t. Same values as F(s) above. */
    "float pixel_cdf(float tl, vec4 f) {\n"
    "    float ramp = clamp(0.5 + tl * f.z, 0.0, 1.0);\n"
    "    float g = max(f.y - abs(abs(tl) - f.x), 0.0);\n"
    "    g = uintBitsToFloat((floatBitsToUint(tl) & 0x80000000u) | floatBitsToUint(g * g));\n"
    "    return ramp - g * f.w;\n"
    "}\n"
    "float band(float s, float lo, float hi, vec4 f) {\n" /* depths times L */
    "    return max(0.0, pixel_cdf(hi - s, f) - pixel_cdf(lo - s, f));\n"
    "}\n"
    "vec2 pixel_position() {\n" /* pixel centre, px, y down */
    "    return gl_FragCoord.xy + vec2(0.0, band_y0);\n"
    "}\n"
    "float clip_coverage() {\n" /* the plot rectangle (Cairo's cairo_clip, fractional edges) */
    "#if CLIP\n"                /* axis-aligned edges: the one-dimensional box is exact */
    "    vec2 p = pixel_position();\n"
    "    vec2 lo = clamp(p - clip.xy + 0.5, 0.0, 1.0), hi = clamp(clip.zw - p + 0.5, 0.0, 1.0);\n"
    "    return lo.x * lo.y * hi.x * hi.y;\n"
    "#else\n"
    "    return 1.0;\n"
    "#endif\n"
    "}\n"
    /* Cairo draws an outlined disk as a dark disk of radius r under a coloured one of radius
     * r - w; here both coverages come from one fragment (the rim as a straight edge along the
     * radius). local: pixel centre minus disk centre; size: radius, outline width, px. The far
     * side of the rim matters only for disks under a pixel: their coverage is capped by their
     * area instead (one distribution lookup per edge instead of two). The colour is premultiplied
     * by the coverage (drawn with glBlendFunc(ONE, ONE_MINUS_SRC_ALPHA)): the outline and fill
     * shares add up without a division. The edge normal is `local` itself, of length d (at the
     * centre any direction will do: the depth, the radius, is beyond the footprint). */
    "vec4 shade_disk(vec2 local, vec2 size, vec4 colour) {\n"
    "    float d = sqrt(dot(local, local)), l = max(d, 1e-6);\n"
    "    vec4 f = footprint(local);\n"
    "    float total = min_pos(pixel_cdf((size.x - d) * l, f), 3.14159265 * size.x * size.x);\n"
    "#if OUTLINE\n" /* programs for disks without an outline skip the inner edge */
    "    float inner = size.y > 0.0 ? min_pos(pixel_cdf((size.x - size.y - d) * l, f), total)\n"
    "                               : total;\n"
    "    float alpha = total * clip_coverage(), fill = inner * clip_coverage();\n"
    "    return vec4(outline_rgb * (alpha - fill) + colour.rgb * fill, alpha);\n"
    "#else\n" /* alpha == fill: the outline term is exactly 0 */
    "    float alpha = total * clip_coverage();\n"
    "    return vec4(colour.rgb * alpha, alpha);\n"
    "#endif\n"
    "}\n";

/* Instanced quads: the fallback for disks larger than the largest point sprite. */
static const char disk_vertex_source[] =
    "layout(location = 0) in vec2 corner;\n" /* (+-1, +-1) */
    "layout(location = 1) in vec4 disk;\n"   /* centre x, y, radius, outline width, px */
    "layout(location = 2) in vec4 fill;\n"
    "out vec2 local;\n"
    "flat out vec2 size;\n"
    "flat out vec4 colour;\n"
    "void main() {\n"
    "    local = corner * (disk.z + 1.0);\n"
    "    gl_Position = clip_position(disk.xy + local);\n"
    "    size = disk.zw;\n"
    "    colour = fill;\n"
    "}\n";

static const char disk_fragment_source[] = "in vec2 local;\n"
                                           "flat in vec2 size;\n"
                                           "flat in vec4 colour;\n"
                                           "out vec4 result;\n"
                                           "void main() {\n"
                                           "    result = shade_disk(local, size, colour);\n"
                                           "    if (result.a <= 0.0) discard;\n"
                                           "}\n";

/* The fast path: one point sprite per disk (one vertex instead of an instanced quad). The sprite
 * is the square of side 2 r + 1: a pixel whose centre lies further than r + 1/2 from the centre
 * along x or y does not meet the disk. The fragment's offset from the centre comes from
 * gl_PointCoord (the sprite is centred on the disk), so coverage and colour are the quad
 * shader's. Not from gl_FragCoord: Mesa turns gl_FragCoord.y into y * k0 + k1 with (k0, k1) a
 * state constant that llvmpipe loads as a gather, about 25 instructions per eight pixels. */
static const char point_vertex_source[] =
    "layout(location = 0) in vec4 disk;\n" /* centre x, y, radius, outline width, px */
    "layout(location = 1) in vec4 fill;\n"
    "flat out vec4 shape;\n"
    "flat out vec4 colour;\n"
    "void main() {\n"
    "    gl_Position = clip_position(disk.xy);\n"
    "    gl_PointSize = 2.0 * disk.z + 1.0;\n"
    "    shape = disk;\n"
    "    colour = fill;\n"
    "}\n";

static const char point_fragment_source[] =
    "flat in vec4 shape;\n"
    "flat in vec4 colour;\n"
    "out vec4 result;\n"
    "void main() {\n"
    "    result = shade_disk((gl_PointCoord - 0.5) * (2.0 * shape.z + 1.0), shape.zw, colour);\n"
    "    if (result.a <= 0.0) discard;\n"
    "}\n";

static const char segment_vertex_source[] =
    "layout(location = 0) in vec2 corner;\n" /* along 0 or 1, across +-1 */
    "layout(location = 1) in vec4 ends;\n"   /* x0, y0, x1, y1, px */
    "layout(location = 2) in vec2 shape;\n"  /* half width px, 1 = round caps */
    "layout(location = 3) in vec4 paint;\n"
    "out vec2 local;\n" /* along from the start, across from the axis, px */
    "flat out vec3 form;\n"
    "flat out vec2 direction;\n"
    "flat out vec4 colour;\n"
    "void main() {\n"
    "    vec2 axis = ends.zw - ends.xy;\n"
    "    float len = length(axis);\n"
    "    vec2 t = len > 0.0 ? axis / len : vec2(1.0, 0.0);\n"
    "    vec2 n = vec2(-t.y, t.x);\n"
    "    float pad = shape.x + 1.0;\n"
    "    local = vec2(corner.x * (len + 2.0 * pad) - pad, corner.y * pad);\n"
    "    gl_Position = clip_position(ends.xy + t * local.x + n * local.y);\n"
    "    form = vec3(len, shape);\n"
    "    direction = t;\n"
    "    colour = paint;\n"
    "}\n";

/* Round caps: a capsule, by the distance to the axis segment (walls, force chains). */
static const char round_fragment_source[] =
    "in vec2 local;\n"
    "flat in vec3 form;\n" /* length, half width, round caps */
    "flat in vec2 direction;\n"
    "flat in vec4 colour;\n"
    "out vec4 result;\n"
    "void main() {\n"
    "    vec2 v = vec2(max(local.x - form.x, 0.0) + min(local.x, 0.0), local.y);\n"
    "    float d = sqrt(dot(v, v)), l = max(d, 1e-6);\n"
    "    vec2 across = vec2(-direction.y, direction.x);\n" /* the normal on the axis */
    "    vec4 f = footprint(d >= 1e-6 ? direction * v.x + across * v.y : across * 1e-6);\n"
    "    float a = band(d * l, -form.y * l, form.y * l, f) * clip_coverage() * colour.a;\n"
    "    if (a <= 0.0) discard;\n"
    "    result = vec4(colour.rgb, a);\n"
    "}\n";

/* Force chains as wide lines: one primitive per chain (llvmpipe rasterises a wide line as one
 * four-edged primitive; a quad's two long thin triangles both visit every 4x4 block along their
 * shared diagonal). The line runs along the chain, lengthened at both ends so the caps fit; its
 * width, a whole number of pixels shared by a run of chains (glLineWidth), covers the capsule at
 * any angle (draw_chain_lines). A line's attributes do not vary across it, so the fragment finds
 * its place along and across the chain from gl_FragCoord (and pays for its y transform: see
 * point_vertex_source). */
static const char line_vertex_source[] =
    "layout(location = 0) in vec4 ends;\n" /* x0, y0, x1, y1, px */
    "layout(location = 1) in float half_width;\n"
    "layout(location = 2) in vec3 paint;\n"
    "flat out vec4 start;\n" /* x0, y0, unit direction */
    "flat out vec2 form;\n"  /* length, half width, px */
    "flat out vec3 colour;\n"
    "void main() {\n"
    "    vec2 axis = ends.zw - ends.xy;\n"
    "    float len = length(axis);\n"
    "    vec2 t = len > 0.0 ? axis / len : vec2(1.0, 0.0);\n"
    /* Along the major axis the line must reach past the cap (half width) by the pixels its
     * antialiasing reaches (up to sqrt(2) / 2) and the one pixel llvmpipe's diamond-exit rule
     * may take off an end. */
    "    vec2 m = abs(t);\n"
    "    float reach = (half_width + 1.75) / max(m.x, m.y);\n"
    "    bool end = (gl_VertexID & 1) != 0;\n" /* a chain's two vertices: start, end */
    "    gl_Position = clip_position(end ? ends.zw + t * reach : ends.xy - t * reach);\n"
    "    start = vec4(ends.xy, t);\n"
    "    form = vec2(len, half_width);\n"
    "    colour = paint;\n"
    "}\n";

static const char line_fragment_source[] =
    "flat in vec4 start;\n"
    "flat in vec2 form;\n"
    "flat in vec3 colour;\n"
    "out vec4 result;\n"
    "void main() {\n"
    "    vec2 q = pixel_position() - start.xy, across = vec2(-start.w, start.z);\n"
    "    float along = dot(q, start.zw);\n"
    "    vec2 v = vec2(max(along - form.x, 0.0) + min(along, 0.0), dot(q, across));\n"
    "    float d = sqrt(dot(v, v)), l = max(d, 1e-6);\n" /* the normal v, of length d */
    "    vec4 f = footprint(d >= 1e-6 ? start.zw * v.x + across * v.y : across * 1e-6);\n"
    "#if ONE_EDGE\n" /* wide chains: the far edge is out of reach (band's lower term is 0) */
    "    float a = pixel_cdf((form.y - d) * l, f);\n"
    "#else\n"
    "    float a = band(d * l, -form.y * l, form.y * l, f);\n"
    "#endif\n"
    "    a *= clip_coverage();\n" /* chains are opaque */
    "    if (a <= 0.0) discard;\n"
    "    result = vec4(colour.rgb, a);\n"
    "}\n";

/* Butt ends: the pixel's footprint is the same along and across (orientation ticks). */
static const char butt_fragment_source[] =
    "in vec2 local;\n"
    "flat in vec3 form;\n"
    "flat in vec2 direction;\n"
    "flat in vec4 colour;\n"
    "out vec4 result;\n"
    "void main() {\n"
    "    vec4 p = footprint(direction);\n"
    "    float a = band(local.x, 0.0, form.x, p) * band(local.y, -form.y, form.y, p);\n"
    "    a = min(a, 1.0) * clip_coverage() * colour.a;\n"
    "    if (a <= 0.0) discard;\n"
    "    result = vec4(colour.rgb, a);\n"
    "}\n";

/* Programs: each shape with the clip compiled out (index 0) and in (index 1). */
enum {
    PROGRAM_QUAD_DISK,
    PROGRAM_POINT_DISK,
    PROGRAM_POINT_PLAIN, /* point sprites of disks without an outline */
    PROGRAM_ROUND,
    PROGRAM_BUTT,
    PROGRAM_LINE,
    PROGRAM_WIDE_LINE,
    PROGRAM_KINDS
};

/* Vertex source, fragment source, definitions for both. */
static const char *const program_sources[PROGRAM_KINDS][3] = {
    {disk_vertex_source, disk_fragment_source, "#define OUTLINE 1\n"},
    {point_vertex_source, point_fragment_source, "#define OUTLINE 1\n"},
    {point_vertex_source, point_fragment_source, "#define OUTLINE 0\n"},
    {segment_vertex_source, round_fragment_source, "#define OUTLINE 1\n"},
    {segment_vertex_source, butt_fragment_source, "#define OUTLINE 1\n"},
    {line_vertex_source, line_fragment_source, "#define OUTLINE 1\n#define ONE_EDGE 0\n"},
    {line_vertex_source, line_fragment_source, "#define OUTLINE 1\n#define ONE_EDGE 1\n"},
};

/* ------------------------------------------------------------------ drawer */

/* Colours and sizes of the Cairo drawer (render_cairo.c), which is the reference. */
#define OUTLINE_RGB 0x2a2a2au
#define WALL_RGB    0x3c3c3cu

typedef struct DiskInstance {
    float x, y, radius, outline; ///< px
    uint8_t rgba[4];
} DiskInstance;

/* A segment is drawn as two triangles over four vertices that each carry the whole segment
 * (plain vertices, not instances: see point_vertex_source). */
typedef struct SegmentVertex {
    float corner[2];      ///< along 0 or 1, across +-1
    float x0, y0, x1, y1; ///< px
    float half_width;     ///< px
    float round;          ///< 1: round caps, 0: butt
    uint8_t rgba[4];
} SegmentVertex;

/* A force chain drawn as a line: two vertices carrying the whole chain. */
typedef struct ChainVertex {
    float x0, y0, x1, y1; ///< px
    float half_width;     ///< px
    uint8_t rgba[4];
} ChainVertex;

typedef struct ChainOrder {
    uint64_t key; ///< bits of F_n (> 0), which order as the forces do
    int index;    ///< contact
} ChainOrder;

/* Uniform locations of a program. */
typedef struct Uniforms {
    GLint clip, frame;
} Uniforms;

/* One horizontal band of the image, rows [y0, y0 + height), with its own context, framebuffer
 * object, programs, buffers and primitives (those that reach its rows). llvmpipe sets up and bins
 * primitives in the thread that draws them and rasterises one scene at a time, waiting for the
 * rasteriser before the drawing thread goes on, so with one context a frame is serial work
 * (frame data, vertex set-up, binning, read-back: 4 of 31 CPU ms in the bench) followed by parallel
 * rasterisation. Two bands drawn in two threads halve the serial part; their scenes are
 * rasterised one after the other, each by all rasteriser threads. Every pixel still gets the
 * primitives that reach it, in the same order. */
typedef struct Band {
    GlContext context;
    int y0, height;                    ///< image rows, px
    GLuint framebuffer, target;        ///< the framebuffer object this band draws into, its texture
    GLuint programs[PROGRAM_KINDS][2]; ///< [kind][clip]
    Uniforms uniforms[PROGRAM_KINDS][2];
    GLuint disk_vao, point_vao, segment_vao, line_vao;
    GLuint corner_buffer, disk_buffer, segment_buffer, index_buffer, chain_buffer;
    GLsizeiptr disk_bytes, segment_bytes, chain_bytes; ///< buffer capacities, bytes
    int index_segments;                                ///< segments the index buffer covers
    DiskInstance *disks;
    SegmentVertex *segments;            ///< 4 vertices per segment
    uint32_t *indices;                  ///< 6 per segment: two triangles
    ChainVertex *lines;                 ///< 2 per force chain, drawn weakest first
    ChainOrder *chains, *chain_scratch; ///< chains to draw, sorted; the sort's second buffer
    int disk_capacity, segment_capacity, line_capacity, chain_capacity, scratch_capacity,
        index_capacity;
    int clip_disks, clip_butt, clip_round; ///< 1: some primitive of the kind reaches the clip
    char prelude[2][384]; ///< first lines of every shader, [clip]: version and constants
    int rc;               ///< the band's last result, 0 or -1 with a message in err
    char err[256];
} Band;

enum { MAX_BANDS = 2 };

typedef struct Layout Layout;

struct RenderGl {
    GlApi gl;           ///< entry points (the same in every context)
    int width, height;  ///< px
    uint8_t *pixels;    ///< the drawer's own BGRA image, rows top-down, stride 4 * width
    float margin;       ///< px the viewport reaches beyond each band edge
    float point_limit;  ///< largest point sprite, px
    float line_limit;   ///< widest line, px (chains wider are quads)
    char renderer[128]; ///< GL_RENDERER
    Band bands[MAX_BANDS];
    int band_count;
    /* The helper thread (render_helper.c) draws band 1 (its context is current there only). */
    RenderHelper *helper;
    const SimFrame *frame; ///< the job's frame, layout and image rows (band 1's start there)
    const Layout *layout;
    uint8_t *image;
};

/* One channel of a 0xRRGGBB colour as GL receives an 8-bit value. */
static double channel(uint32_t rgb, int shift)
{
    return (double)((float)((rgb >> shift) & 255u) / 255.0f);
}

/* The outline colour and the band's first row are shader constants, not uniforms: llvmpipe
 * loads a uniform in a fragment shader as a gather (eight scalar loads per eight pixels), a
 * constant costs nothing. The colour is printed with 9 digits, so the shader sees the float the
 * C expression gives. */
static void write_preludes(Band *b)
{
    for (int clip = 0; clip < 2; ++clip)
        snprintf(b->prelude[clip], sizeof b->prelude[clip],
                 "#version 330 core\n"
                 "#define CLIP %d\n"
                 "const float band_y0 = %d.0;\n"
                 "const vec3 outline_rgb = vec3(%.9g, %.9g, %.9g);\n",
                 clip, b->y0, channel(OUTLINE_RGB, 16), channel(OUTLINE_RGB, 8),
                 channel(OUTLINE_RGB, 0));
}

static GLuint compile(RenderGl *r, Band *b, GLenum kind, const char *body, const char *defines,
                      int clip, char *err, size_t err_size)
{
    const char *parts[5] = {b->prelude[clip != 0], defines, common_source,
                            kind == GL_FRAGMENT_SHADER ? fragment_common_source : "", body};
    GLuint shader = r->gl.CreateShader(kind);
    r->gl.ShaderSource(shader, 5, parts, NULL);
    r->gl.CompileShader(shader);
    GLint ok = 0;
    r->gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        r->gl.GetShaderInfoLog(shader, sizeof log, NULL, log);
        snprintf(err, err_size, "GL: shader does not compile: %s", log);
        r->gl.DeleteShader(shader);
        return 0;
    }
    return shader;
}

static GLuint link_program(RenderGl *r, Band *b, const char *const sources[3], int clip,
                           Uniforms *uniforms, char *err, size_t err_size)
{
    GLuint vs = compile(r, b, GL_VERTEX_SHADER, sources[0], sources[2], clip, err, err_size);
    if (!vs)
        return 0;
    GLuint fs = compile(r, b, GL_FRAGMENT_SHADER, sources[1], sources[2], clip, err, err_size);
    if (!fs) {
        r->gl.DeleteShader(vs);
        return 0;
    }
    GLuint program = r->gl.CreateProgram();
    r->gl.AttachShader(program, vs);
    r->gl.AttachShader(program, fs);
    r->gl.LinkProgram(program);
    r->gl.DeleteShader(vs);
    r->gl.DeleteShader(fs);
    GLint ok = 0;
    r->gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        r->gl.GetProgramInfoLog(program, sizeof log, NULL, log);
        snprintf(err, err_size, "GL: shaders do not link: %s", log);
        r->gl.DeleteProgram(program);
        return 0;
    }
    uniforms->clip = r->gl.GetUniformLocation(program, "clip");
    uniforms->frame = r->gl.GetUniformLocation(program, "frame");
    return program;
}

static void attribute(RenderGl *r, GLuint location, GLint size, GLenum type, GLsizei stride,
                      size_t offset, GLuint divisor)
{
    r->gl.EnableVertexAttribArray(location);
    r->gl.VertexAttribPointer(location, size, type, type == GL_UNSIGNED_BYTE ? GL_TRUE : GL_FALSE,
                              stride, (const void *)offset);
    r->gl.VertexAttribDivisor(location, divisor);
}

static void setup_vaos(RenderGl *r, Band *b)
{
    /* Instanced quads (disks too large for a point sprite): attribute 0 the corners (a
     * triangle strip), then per-instance attributes. */
    GLsizei stride = sizeof(DiskInstance);
    r->gl.BindVertexArray(b->disk_vao);
    r->gl.BindBuffer(GL_ARRAY_BUFFER, b->corner_buffer);
    attribute(r, 0, 2, GL_FLOAT, 2 * sizeof(float), 0, 0);
    r->gl.BindBuffer(GL_ARRAY_BUFFER, b->disk_buffer);
    attribute(r, 1, 4, GL_FLOAT, stride, offsetof(DiskInstance, x), 1);
    attribute(r, 2, 4, GL_UNSIGNED_BYTE, stride, offsetof(DiskInstance, rgba), 1);
    /* Point sprites: the same buffer, one vertex per disk. */
    r->gl.BindVertexArray(b->point_vao);
    attribute(r, 0, 4, GL_FLOAT, stride, offsetof(DiskInstance, x), 0);
    attribute(r, 1, 4, GL_UNSIGNED_BYTE, stride, offsetof(DiskInstance, rgba), 0);
    /* Segments: indexed triangles over four vertices each. */
    stride = sizeof(SegmentVertex);
    r->gl.BindVertexArray(b->segment_vao);
    r->gl.BindBuffer(GL_ARRAY_BUFFER, b->segment_buffer);
    attribute(r, 0, 2, GL_FLOAT, stride, offsetof(SegmentVertex, corner), 0);
    attribute(r, 1, 4, GL_FLOAT, stride, offsetof(SegmentVertex, x0), 0);
    attribute(r, 2, 2, GL_FLOAT, stride, offsetof(SegmentVertex, half_width), 0);
    attribute(r, 3, 4, GL_UNSIGNED_BYTE, stride, offsetof(SegmentVertex, rgba), 0);
    r->gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, b->index_buffer); /* part of the VAO's state */
    /* Chains as lines: two vertices each. */
    stride = sizeof(ChainVertex);
    r->gl.BindVertexArray(b->line_vao);
    r->gl.BindBuffer(GL_ARRAY_BUFFER, b->chain_buffer);
    attribute(r, 0, 4, GL_FLOAT, stride, offsetof(ChainVertex, x0), 0);
    attribute(r, 1, 1, GL_FLOAT, stride, offsetof(ChainVertex, half_width), 0);
    attribute(r, 2, 3, GL_UNSIGNED_BYTE, stride, offsetof(ChainVertex, rgba), 0);
    r->gl.BindVertexArray(0);
}

/* Creates the band's context and GL objects in the calling thread, where the context stays
 * current (band 0: every drawing thread makes it current again; band 1: the helper thread). */
static int band_init(RenderGl *r, Band *b, char *err, size_t err_size)
{
    if (!b->context.osmesa && context_create(&b->context, err, err_size) != 0)
        return -1;
    if (context_make_current(&b->context) != 0) {
        snprintf(err, err_size, "GL: cannot make the OSMesa context current");
        return -1;
    }
    /* The band's image: a texture stored as BGRA bytes (Cairo's ARGB32 on little-endian, so the
     * overlay draws on GL frames in place), which glReadPixels(GL_BGRA) copies row by row;
     * row 0 is the band's top row (clip_position), so the copy needs no flip. The unsized
     * internal format lets Mesa store the bytes as given. */
    r->gl.GenTextures(1, &b->target);
    r->gl.BindTexture(GL_TEXTURE_2D, b->target);
    r->gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, r->width, b->height, 0, GL_BGRA, GL_UNSIGNED_BYTE,
                     NULL);
    r->gl.GenFramebuffers(1, &b->framebuffer);
    r->gl.BindFramebuffer(GL_FRAMEBUFFER, b->framebuffer);
    r->gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, b->target, 0);
    if (r->gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        snprintf(err, err_size, "GL: no %dx%d BGRA framebuffer on %s", r->width, b->height,
                 r->renderer);
        return -1;
    }
    r->gl.Enable(GL_PROGRAM_POINT_SIZE);
    write_preludes(b);
    for (int kind = 0; kind < PROGRAM_KINDS; ++kind) {
        for (int clip = 0; clip < 2; ++clip) {
            b->programs[kind][clip] = link_program(r, b, program_sources[kind], clip,
                                                   &b->uniforms[kind][clip], err, err_size);
            if (!b->programs[kind][clip])
                return -1;
        }
    }
    /* Quads as triangle strips: disks use (+-1, +-1). */
    static const float corners[8] = {-1, -1, 1, -1, -1, 1, 1, 1};
    GLuint buffers[5];
    r->gl.GenBuffers(5, buffers);
    b->corner_buffer = buffers[0];
    b->disk_buffer = buffers[1];
    b->segment_buffer = buffers[2];
    b->index_buffer = buffers[3];
    b->chain_buffer = buffers[4];
    GLuint vaos[4];
    r->gl.GenVertexArrays(4, vaos);
    b->disk_vao = vaos[0];
    b->point_vao = vaos[1];
    b->segment_vao = vaos[2];
    b->line_vao = vaos[3];
    r->gl.BindBuffer(GL_ARRAY_BUFFER, b->corner_buffer);
    r->gl.BufferData(GL_ARRAY_BUFFER, sizeof corners, corners, GL_STATIC_DRAW);
    setup_vaos(r, b);
    if (r->gl.GetError() != GL_NO_ERROR) {
        snprintf(err, err_size, "GL: set-up failed on %s", r->renderer);
        return -1;
    }
    return 0;
}

/* Frees the band's arrays and its context, which holds all its GL objects. */
static void band_free(Band *b)
{
    context_destroy(&b->context);
    free(b->disks);
    free(b->segments);
    free(b->indices);
    free(b->lines);
    free(b->chains);
    free(b->chain_scratch);
}

static int band_draw(RenderGl *r, Band *b, const SimFrame *frame, const Layout *l, uint8_t *image);

/* The helper thread's jobs on band 1: set it up, draw it, let go of its context (which the
 * creating thread destroys). */
static void band1_init(void *context)
{
    RenderGl *r = context;
    Band *b = &r->bands[1];
    b->rc = band_init(r, b, b->err, sizeof b->err);
}

static void band1_draw(void *context)
{
    RenderGl *r = context;
    Band *b = &r->bands[1];
    b->rc = band_draw(r, b, r->frame, r->layout, r->image);
}

static void band1_release(void *context)
{
    (void)context;
    context_release();
}

RenderGl *render_gl_create(int width, int height, char *err, size_t err_size)
{
    if (width <= 0 || height <= 0 || width > 16384 || height > 16384) {
        snprintf(err, err_size, "GL: image size %dx%d outside 1..16384", width, height);
        return NULL;
    }
    RenderGl *r = calloc(1, sizeof *r);
    if (!r) {
        snprintf(err, err_size, "GL: out of memory");
        return NULL;
    }
    r->width = width;
    r->height = height;
    r->pixels = malloc((size_t)width * (size_t)height * 4);
    if (!r->pixels) {
        snprintf(err, err_size, "GL: out of memory for %dx%d pixels", width, height);
        free(r);
        return NULL;
    }
    r->band_count = render_band_count(height, 0);
    int rows = r->band_count == 2 ? height / 2 : height;
    r->bands[0].height = rows;
    r->bands[1].y0 = rows;
    r->bands[1].height = height - rows;

    /* Band 0's context first: the entry points and limits come from it. */
    Band *b0 = &r->bands[0];
    if (context_create(&b0->context, err, err_size) != 0)
        goto fail;
    if (context_make_current(&b0->context) != 0) {
        snprintf(err, err_size, "GL: cannot make the OSMesa context current");
        goto fail;
    }
    if (api_load(&r->gl, err, err_size) != 0)
        goto fail;
    const GLubyte *renderer = r->gl.GetString(GL_RENDERER);
    snprintf(r->renderer, sizeof r->renderer, "%s", renderer ? (const char *)renderer : "?");
    /* Points are clipped by their centre: the viewport reaches past the band by half the
     * largest sprite, so disks centred just outside it still show their inner part. */
    GLfloat sizes[2] = {1.0f, 1.0f};
    GLint dims[2] = {width, height};
    r->gl.GetFloatv(GL_ALIASED_POINT_SIZE_RANGE, sizes);
    r->gl.GetIntegerv(GL_MAX_VIEWPORT_DIMS, dims);
    int room = (dims[0] - width < dims[1] - height ? dims[0] - width : dims[1] - height) / 2;
    int margin = (int)ceil(0.5 * (double)sizes[1]) + 1;
    r->margin = (float)(margin < room ? margin : room > 0 ? room : 0);
    r->point_limit = fminf(sizes[1], 2.0f * r->margin - 2.0f);
    GLfloat widths[2] = {1.0f, 1.0f};
    r->gl.GetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, widths);
    r->line_limit = widths[1];
    if (band_init(r, b0, err, err_size) != 0)
        goto fail;

    if (r->band_count == 2) {
        r->helper = render_helper_create();
        if (!r->helper)
            goto no_thread;
        render_helper_start(r->helper, band1_init, r);
        render_helper_wait(r->helper);
        if (r->bands[1].rc != 0) {
            snprintf(err, err_size, "%s", r->bands[1].err);
            goto fail;
        }
    }
    return r;

no_thread:
    snprintf(err, err_size, "GL: cannot start the drawing thread");
fail:
    render_gl_destroy(r);
    return NULL;
}

void render_gl_destroy(RenderGl *r)
{
    if (!r)
        return;
    if (r->helper) {
        render_helper_start(r->helper, band1_release, NULL);
        render_helper_destroy(r->helper);
    }
    context_release();
    for (int k = 0; k < MAX_BANDS; ++k)
        band_free(&r->bands[k]);
    free(r->pixels);
    free(r);
}

const char *render_gl_renderer(const RenderGl *r)
{
    return r ? r->renderer : "";
}

/* ------------------------------------------------------------------ what to draw */

/* Grows an array to hold at least `count` elements of `size` bytes. */
static int reserve(void **array, int *capacity, int count, size_t size)
{
    if (count <= *capacity)
        return 0;
    int grown = *capacity > 0 ? *capacity : 256;
    while (grown < count)
        grown *= 2;
    void *bigger = realloc(*array, (size_t)grown * size);
    if (!bigger)
        return -1;
    *array = bigger;
    *capacity = grown;
    return 0;
}

static void set_rgba(uint8_t rgba[4], uint32_t rgb)
{
    rgba[0] = (uint8_t)(rgb >> 16);
    rgba[1] = (uint8_t)(rgb >> 8);
    rgba[2] = (uint8_t)rgb;
    rgba[3] = 255;
}

/* Cairo's outline ring width for a disk of r pixels (0 = no outline). */
static double outline_width(double r)
{
    return fmin(1.5, fmax(0.6, 0.07 * r));
}

/* Everything one frame needs, resolved once and shared by the bands. */
struct Layout {
    RenderStyle style; ///< resolved (render_style_resolve)
    RenderView view;
    double lo, hi;       ///< colour range
    double period;       ///< periodic x length, m (0 = not periodic)
    float clip[4];       ///< x0, y0, x1, y1, px
    double cut, f_max;   ///< chains: the force they must exceed, the force of the widest, N
    int as_points;       ///< 1: disks are point sprites (none larger than the largest sprite)
    int chains_as_lines; ///< 1: chains are lines (none wider than the widest line)
};

/* 1 when the box (px) is far enough inside the clip rectangle that every pixel centre in it has
 * clip coverage 1, so the shaders may leave the clip out. */
static int reaches_clip(const Layout *l, double x0, double y0, double x1, double y1)
{
    return !(x0 >= (double)l->clip[0] + 0.5 && y0 >= (double)l->clip[1] + 0.5 &&
             x1 <= (double)l->clip[2] - 0.5 && y1 <= (double)l->clip[3] - 0.5);
}

/* 1 when image rows [y_lo, y_hi] (px) may hold pixels of the band: a primitive outside them
 * gives its pixels no coverage. */
static int meets_band(const Band *b, double y_lo, double y_hi)
{
    return y_hi >= (double)b->y0 - 1.0 && y_lo <= (double)(b->y0 + b->height) + 1.0;
}

static void add_disk(Band *b, int *n, const Layout *l, const SimFrame *frame, int i, double offset,
                     uint32_t rgb)
{
    DiskInstance *d = &b->disks[(*n)++];
    double px, py, radius = l->view.scale * frame->radius[i];
    render_view_to_pixel(&l->view, frame->x[i] + offset, frame->y[i], &px, &py);
    d->x = (float)px;
    d->y = (float)py;
    d->radius = (float)radius;
    d->outline = (l->style.outline || render_grain_fixed(frame, i)) && radius >= 1.5
                     ? (float)outline_width(radius)
                     : 0.0f;
    set_rgba(d->rgba, rgb);
    double pad = radius + 1.0;
    if (!b->clip_disks)
        b->clip_disks = reaches_clip(l, px - pad, py - pad, px + pad, py + pad);
}

/* The band's disks in frame order, with the copies a periodic frame shows across the seam. */
static int collect_disks(Band *b, const SimFrame *frame, const Layout *l)
{
    if (reserve((void **)&b->disks, &b->disk_capacity, 3 * frame->count, sizeof(DiskInstance)))
        return -1;
    int n = 0;
    for (int i = 0; i < frame->count; ++i) {
        double px, py, pad = l->view.scale * frame->radius[i] + 1.0;
        render_view_to_pixel(&l->view, frame->x[i], frame->y[i], &px, &py);
        if (!meets_band(b, py - pad, py + pad)) /* periodic copies share the row */
            continue;
        uint32_t rgb = render_grain_rgb(frame, &l->style, i, l->lo, l->hi);
        add_disk(b, &n, l, frame, i, 0.0, rgb);
        if (l->period > 0.0) {
            if (frame->x[i] - frame->radius[i] < frame->domain_x0)
                add_disk(b, &n, l, frame, i, l->period, rgb);
            if (frame->x[i] + frame->radius[i] > frame->domain_x1)
                add_disk(b, &n, l, frame, i, -l->period, rgb);
        }
    }
    return n;
}

/* The ends of a segment from (ax, ay) to (bx, by), m, of the given width in pixels: 0 when it
 * misses the band, else 1 with the ends (px) and *clip set when it reaches the plot clip. */
static int project_segment(const Band *b, const Layout *l, double ax, double ay, double bx,
                           double by, double width, double p[4], int *clip)
{
    double pad = 0.5 * width + 1.0;
    render_view_to_pixel(&l->view, ax, ay, &p[0], &p[1]);
    render_view_to_pixel(&l->view, bx, by, &p[2], &p[3]);
    if (!meets_band(b, fmin(p[1], p[3]) - pad, fmax(p[1], p[3]) + pad))
        return 0;
    if (!*clip)
        *clip = reaches_clip(l, fmin(p[0], p[2]) - pad, fmin(p[1], p[3]) - pad,
                             fmax(p[0], p[2]) + pad, fmax(p[1], p[3]) + pad);
    return 1;
}

/* A segment from (ax, ay) to (bx, by), m, unless it misses the band. */
/* Chords drawn for one wall: ARC_PIECES for an arc (a chord of 1/128 turn is within 0.03 % of
 * the radius), 1 for a segment. */
enum { ARC_PIECES = 128 };

static int wall_pieces(const SimWall *wall)
{
    return wall->shape == SIM_WALL_ARC ? ARC_PIECES : 1;
}

static void add_segment(Band *b, int *n, const Layout *l, double ax, double ay, double bx,
                        double by, double width, int round, uint32_t rgb)
{
    static const float corners[4][2] = {{0, -1}, {1, -1}, {0, 1}, {1, 1}};
    double p[4];
    if (!project_segment(b, l, ax, ay, bx, by, width, p, round ? &b->clip_round : &b->clip_butt))
        return;
    SegmentVertex *s = &b->segments[4 * (*n)++];
    s->x0 = (float)p[0];
    s->y0 = (float)p[1];
    s->x1 = (float)p[2];
    s->y1 = (float)p[3];
    s->half_width = (float)(0.5 * width);
    s->round = round ? 1.0f : 0.0f;
    set_rgba(s->rgba, rgb);
    s->corner[0] = corners[0][0];
    s->corner[1] = corners[0][1];
    for (int k = 1; k < 4; ++k) {
        s[k] = s[0];
        s[k].corner[0] = corners[k][0];
        s[k].corner[1] = corners[k][1];
    }
}

/* A force chain from (ax, ay) to (bx, by), m, as the two vertices of a line, unless it misses
 * the band. */
static void add_chain(Band *b, int *n, const Layout *l, double ax, double ay, double bx, double by,
                      double width, uint32_t rgb)
{
    double p[4];
    if (!project_segment(b, l, ax, ay, bx, by, width, p, &b->clip_round))
        return;
    ChainVertex *c = &b->lines[2 * (*n)++];
    c->x0 = (float)p[0];
    c->y0 = (float)p[1];
    c->x1 = (float)p[2];
    c->y1 = (float)p[3];
    c->half_width = (float)(0.5 * width);
    set_rgba(c->rgba, rgb);
    c[1] = c[0];
}

/* Chains [0, count) as round-capped quads after the segments [0, n): for a frame whose widest
 * chain is wider than the widest line. */
static void chains_as_quads(Band *b, int n, int count)
{
    static const float corners[4][2] = {{0, -1}, {1, -1}, {0, 1}, {1, 1}};
    for (int k = 0; k < count; ++k) {
        const ChainVertex *c = &b->lines[2 * k];
        SegmentVertex *q = &b->segments[4 * (n + k)];
        for (int v = 0; v < 4; ++v)
            q[v] = (SegmentVertex){{corners[v][0], corners[v][1]},
                                   c->x0,
                                   c->y0,
                                   c->x1,
                                   c->y1,
                                   c->half_width,
                                   1.0f,
                                   {c->rgba[0], c->rgba[1], c->rgba[2], c->rgba[3]}};
    }
}

/* Chains by force, weakest first, ties by contact index (a total order: the sequence of Cairo's
 * stable sort). A stable least-significant-digit radix sort on the bits of F_n, 8 bits a pass,
 * skipping digits that all chains share; the chains come in index order. It runs in the serial
 * part of a frame, where qsort's comparison calls cost about 0.7 ms for 8k chains. */
static void sort_chains(ChainOrder *chains, ChainOrder *scratch, int count)
{
    ChainOrder *from = chains, *to = scratch;
    for (int shift = 0; shift < 64; shift += 8) {
        int start[257] = {0};
        for (int k = 0; k < count; ++k)
            ++start[(from[k].key >> shift & 255u) + 1];
        int shared = 0;
        for (int d = 1; d <= 256 && !shared; ++d)
            shared = start[d] == count;
        if (shared)
            continue;
        for (int d = 1; d <= 256; ++d)
            start[d] += start[d - 1];
        for (int k = 0; k < count; ++k)
            to[start[from[k].key >> shift & 255u]++] = from[k];
        ChainOrder *swap = from;
        from = to;
        to = swap;
    }
    if (from != chains)
        memcpy(chains, from, (size_t)count * sizeof *chains);
}

/* Width of a chain of normal force f, px: upper 65 % of the yellow-red map, width proportional
 * to F_n (render_cairo.c). */
static double chain_width(const Layout *l, double f)
{
    double t = l->f_max > 0.0 ? fmin(1.0, f / l->f_max) : 1.0;
    return fmax(0.8, l->style.chain_width_max * t);
}

/* Orientation ticks and walls as segments, force chains as lines, in Cairo's drawing order:
 * those that reach the band. Room is kept for the chains as segments too (chains_as_quads). */
static int collect_segments(Band *b, const SimFrame *frame, const Layout *l, int counts[3])
{
    const RenderStyle *s = &l->style;
    const RenderView *v = &l->view;
    int ticks = s->orientation_tick && frame->angle ? 3 * frame->count : 0;
    int chains = s->force_chains ? 2 * frame->contact_count : 0;
    int wall_segments = 0;
    for (int w = 0; frame->walls && w < frame->wall_count; ++w)
        wall_segments += wall_pieces(&frame->walls[w]);
    if (reserve((void **)&b->segments, &b->segment_capacity, ticks + wall_segments + chains,
                4 * sizeof(SegmentVertex)) ||
        reserve((void **)&b->lines, &b->line_capacity, chains, 2 * sizeof(ChainVertex)) ||
        reserve((void **)&b->chains, &b->chain_capacity, frame->contact_count,
                sizeof(ChainOrder)) ||
        reserve((void **)&b->chain_scratch, &b->scratch_capacity, frame->contact_count,
                sizeof(ChainOrder)))
        return -1;
    int n = 0;
    if (ticks) {
        /* Butt-ended radius lines in the outline colour, as long as the disk's inner radius. */
        double width = fmin(2.5, fmax(0.8, 0.12 * v->mean_diameter * 0.5 * v->scale));
        for (int i = 0; i < frame->count; ++i) {
            double rp = frame->radius[i] * v->scale;
            if (rp < 2.0)
                continue;
            double len = (rp - outline_width(rp)) / v->scale; /* m */
            double offsets[3] = {0.0, 0.0, 0.0};
            int copies = 1;
            if (l->period > 0.0) {
                if (frame->x[i] - frame->radius[i] < frame->domain_x0)
                    offsets[copies++] = l->period;
                if (frame->x[i] + frame->radius[i] > frame->domain_x1)
                    offsets[copies++] = -l->period;
            }
            for (int k = 0; k < copies; ++k) {
                double x = frame->x[i] + offsets[k], y = frame->y[i];
                add_segment(b, &n, l, x, y, x + len * cos(frame->angle[i]),
                            y + len * sin(frame->angle[i]), width, 0, OUTLINE_RGB);
            }
        }
    }
    counts[0] = n;
    if (frame->walls) {
        double width = fmax(3.0, 0.3 * v->mean_diameter * v->scale);
        for (int w = 0; w < frame->wall_count; ++w) {
            const SimWall *wall = &frame->walls[w];
            const int pieces = wall_pieces(wall);
            for (int p = 0; p < pieces; ++p) { /* an arc as ARC_PIECES chords */
                double ax, ay, bx, by;
                sim_wall_point(wall, (double)p / pieces, &ax, &ay);
                sim_wall_point(wall, (double)(p + 1) / pieces, &bx, &by);
                add_segment(b, &n, l, ax, ay, bx, by, width, 1, WALL_RGB);
            }
        }
    }
    counts[1] = n - counts[0];
    n = 0;
    if (chains && frame->contact_count > 0) {
        /* The chains that reach the band (a chain's rows lie between its ends' rows), in index
         * order; the rest are left out before the sort. */
        int m = 0;
        for (int c = 0; c < frame->contact_count; ++c) {
            const SimContact *k = &frame->contacts[c];
            double f = k->normal_force;
            if (!(f > 0.0 && f > l->cut) || k->i < 0 || k->i >= frame->count ||
                k->j >= frame->count)
                continue;
            double ya = frame->y[k->i], yb = k->j >= 0 ? frame->y[k->j] : k->y, x, pa, pb;
            render_view_to_pixel(v, 0.0, ya, &x, &pa);
            render_view_to_pixel(v, 0.0, yb, &x, &pb);
            double pad = 0.5 * chain_width(l, f) + 1.0;
            if (!meets_band(b, fmin(pa, pb) - pad, fmax(pa, pb) + pad))
                continue;
            b->chains[m].index = c;
            memcpy(&b->chains[m++].key, &f, sizeof f);
        }
        /* Weakest first so strong chains lie on top. */
        sort_chains(b->chains, b->chain_scratch, m);
        for (int k = 0; k < m; ++k) {
            const SimContact *c = &frame->contacts[b->chains[k].index];
            double t = l->f_max > 0.0 ? fmin(1.0, c->normal_force / l->f_max) : 1.0;
            double ax = frame->x[c->i], ay = frame->y[c->i];
            double bx = c->j >= 0 ? frame->x[c->j] : c->x; /* wall contact: to the contact */
            double by = c->j >= 0 ? frame->y[c->j] : c->y;
            double dx = bx - ax;
            if (l->period > 0.0) /* minimum image across the seam */
                dx -= l->period * floor(dx / l->period + 0.5);
            uint32_t rgb = render_colormap_rgb(RENDER_CMAP_YELLOW_RED, 0.35 + 0.65 * t);
            double width = chain_width(l, c->normal_force);
            add_chain(b, &n, l, ax, ay, ax + dx, by, width, rgb);
            if (l->period > 0.0 && (ax + dx < frame->domain_x0 || ax + dx > frame->domain_x1))
                add_chain(b, &n, l, bx, by, bx - dx, ay, width, rgb);
        }
    }
    counts[2] = n;
    return 0;
}

/* Uploads `bytes` into a buffer, growing it (never shrinking) so frames of a movie reuse it. */
static void upload(RenderGl *r, GLenum target, GLuint buffer, GLsizeiptr *capacity,
                   const void *data, GLsizeiptr bytes)
{
    r->gl.BindBuffer(target, buffer);
    if (bytes > *capacity) {
        GLsizeiptr grown = *capacity > 0 ? *capacity : 4096;
        while (grown < bytes)
            grown *= 2;
        r->gl.BufferData(target, grown, NULL, GL_DYNAMIC_DRAW);
        *capacity = grown;
    }
    r->gl.BufferSubData(target, 0, bytes, data);
}

static void use_program(RenderGl *r, Band *b, int kind, int clip, const Layout *l)
{
    const Uniforms *u = &b->uniforms[kind][clip != 0];
    r->gl.UseProgram(b->programs[kind][clip != 0]);
    if (u->clip >= 0)
        r->gl.Uniform4f(u->clip, l->clip[0], l->clip[1], l->clip[2], l->clip[3]);
    r->gl.Uniform4f(u->frame, (float)r->width, (float)b->height, r->margin, (float)b->y0);
    /* Disks give premultiplied colour (shade_disk), segments straight colour; "over" either way,
     * and the destination stays opaque. */
    if (kind == PROGRAM_QUAD_DISK || kind == PROGRAM_POINT_DISK || kind == PROGRAM_POINT_PLAIN)
        r->gl.BlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    else
        r->gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE,
                                GL_ONE_MINUS_SRC_ALPHA);
}

/* Index buffer: triangles (0, 1, 2) and (2, 1, 3) of each segment's four vertices, the two
 * triangles of the former triangle strip. Built once for the largest count seen. */
static int segment_indices(RenderGl *r, Band *b, int segments)
{
    if (segments <= b->index_segments)
        return 0;
    if (reserve((void **)&b->indices, &b->index_capacity, 6 * segments, sizeof(uint32_t)))
        return -1;
    int count = b->index_capacity / 6;
    for (int k = 0; k < count; ++k) {
        uint32_t *i = b->indices + 6 * k, v = 4u * (uint32_t)k;
        i[0] = v;
        i[1] = v + 1;
        i[2] = v + 2;
        i[3] = v + 2;
        i[4] = v + 1;
        i[5] = v + 3;
    }
    GLsizeiptr capacity = 0; /* reallocated to the exact size */
    r->gl.BindVertexArray(b->segment_vao);
    upload(r, GL_ELEMENT_ARRAY_BUFFER, b->index_buffer, &capacity, b->indices,
           (GLsizeiptr)count * 6 * (GLsizeiptr)sizeof(uint32_t));
    r->gl.BindVertexArray(0);
    b->index_segments = count;
    return 0;
}

/* Line width (a whole number of px, as llvmpipe rounds it) that covers a capsule of half width h
 * and the pixels its antialiasing reaches, at any angle: llvmpipe widens a line along its minor
 * axis, where the capsule needs h / cos + (1 + tan) / 2 <= h sqrt(2) + 1 either side (the 0.01
 * covers llvmpipe's snapping of the ends to 1/256 px). */
static float line_width(double h)
{
    return (float)ceil(2.0 * (h * 1.4142135623730951 + 1.0) + 0.01);
}

static float chain_line_width(const Band *b, int k)
{
    return line_width((double)b->lines[2 * k].half_width);
}

/* 1 when chain k is so wide that a pixel reaching one of its long edges cannot reach the other:
 * a pixel's footprint across any edge is at most sqrt(2) wide, so with half width h >= 0.75 the
 * far edge's term of band() is exactly 0 and the one-edge line program draws the same pixels. */
static int one_edge(const Band *b, int k)
{
    return b->lines[2 * k].half_width >= 0.75f;
}

/* Chains [first, end) as lines, one draw per run of equal line widths (chains come weakest, so
 * narrowest, first: a handful of runs). */
static void draw_chain_lines(RenderGl *r, Band *b, const Layout *l, int first, int end)
{
    r->gl.BindVertexArray(b->line_vao);
    int program = -1;
    while (first < end) {
        float width = chain_line_width(b, first);
        int wide = one_edge(b, first), last = first + 1;
        while (last < end && chain_line_width(b, last) == width && one_edge(b, last) == wide)
            ++last;
        if (program != (wide ? PROGRAM_WIDE_LINE : PROGRAM_LINE)) {
            program = wide ? PROGRAM_WIDE_LINE : PROGRAM_LINE;
            use_program(r, b, program, b->clip_round, l);
        }
        r->gl.LineWidth(width);
        r->gl.DrawArrays(GL_LINES, 2 * first, 2 * (last - first));
        first = last;
    }
}

/* Draws the band's rows of a frame into image (the whole image, rows top-down). 0 or -1 with a
 * message in b->err. Runs in the thread where the band's context is current. */
static int band_draw(RenderGl *r, Band *b, const SimFrame *frame, const Layout *l, uint8_t *image)
{
    b->clip_disks = b->clip_butt = b->clip_round = 0;
    int disks = collect_disks(b, frame, l);
    int counts[3] = {0, 0, 0};
    if (disks < 0 || collect_segments(b, frame, l, counts) != 0) {
        snprintf(b->err, sizeof b->err, "GL: out of memory for %d grains", frame->count);
        return -1;
    }
    int chains = counts[2], segments = counts[0] + counts[1];
    if (!l->chains_as_lines) { /* chains as quads, after the walls */
        chains_as_quads(b, segments, chains);
        segments += chains;
        chains = 0;
    }
    if (context_make_current(&b->context) != 0) {
        snprintf(b->err, sizeof b->err, "GL: cannot make the OSMesa context current");
        return -1;
    }
    r->gl.BindFramebuffer(GL_FRAMEBUFFER, b->framebuffer);
    if (segment_indices(r, b, segments) != 0) {
        snprintf(b->err, sizeof b->err, "GL: out of memory for %d segments", segments);
        return -1;
    }
    GLint m = (GLint)r->margin;
    r->gl.Viewport(-m, -m, r->width + 2 * m, b->height + 2 * m);
    uint32_t bg = l->style.background_rgb;
    r->gl.ClearColor((float)((bg >> 16) & 255) / 255.0f, (float)((bg >> 8) & 255) / 255.0f,
                     (float)(bg & 255) / 255.0f, 1.0f);
    r->gl.Clear(GL_COLOR_BUFFER_BIT);
    r->gl.Enable(GL_BLEND); /* the function goes with the program (use_program) */
    if (disks > 0) {
        upload(r, GL_ARRAY_BUFFER, b->disk_buffer, &b->disk_bytes, b->disks,
               (GLsizeiptr)disks * (GLsizeiptr)sizeof(DiskInstance));
        if (l->as_points) { /* one draw per run of disks with or without an outline */
            r->gl.BindVertexArray(b->point_vao);
            for (int first = 0, last; first < disks; first = last) {
                const int outlined = b->disks[first].outline > 0.0f;
                for (last = first + 1; last < disks && (b->disks[last].outline > 0.0f) == outlined;)
                    ++last;
                use_program(r, b, outlined ? PROGRAM_POINT_DISK : PROGRAM_POINT_PLAIN,
                            b->clip_disks, l);
                r->gl.DrawArrays(GL_POINTS, first, last - first);
            }
        } else {
            use_program(r, b, PROGRAM_QUAD_DISK, b->clip_disks, l);
            r->gl.BindVertexArray(b->disk_vao);
            r->gl.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, disks);
        }
    }
    if (segments > 0) { /* orientation ticks (butt ends), then walls (round) */
        upload(r, GL_ARRAY_BUFFER, b->segment_buffer, &b->segment_bytes, b->segments,
               (GLsizeiptr)segments * 4 * (GLsizeiptr)sizeof(SegmentVertex));
        r->gl.BindVertexArray(b->segment_vao);
        if (counts[0] > 0) {
            use_program(r, b, PROGRAM_BUTT, b->clip_butt, l);
            r->gl.DrawElements(GL_TRIANGLES, 6 * counts[0], GL_UNSIGNED_INT, NULL);
        }
        if (segments > counts[0]) {
            use_program(r, b, PROGRAM_ROUND, b->clip_round, l);
            r->gl.DrawElements(GL_TRIANGLES, 6 * (segments - counts[0]), GL_UNSIGNED_INT,
                               (const void *)((size_t)counts[0] * 6 * sizeof(uint32_t)));
        }
    }
    if (chains > 0) { /* force chains, weakest first */
        upload(r, GL_ARRAY_BUFFER, b->chain_buffer, &b->chain_bytes, b->lines,
               (GLsizeiptr)chains * 2 * (GLsizeiptr)sizeof(ChainVertex));
        draw_chain_lines(r, b, l, 0, chains);
    }
    r->gl.BindVertexArray(0);
    /* Waits for the rasteriser, then copies the rows (same byte order, no conversion). */
    r->gl.ReadPixels(0, 0, r->width, b->height, GL_BGRA, GL_UNSIGNED_BYTE,
                     image + (size_t)b->y0 * 4 * (size_t)r->width);
    GLenum error = r->gl.GetError();
    if (error != GL_NO_ERROR) {
        snprintf(b->err, sizeof b->err, "GL: drawing failed (GL error 0x%x on %s)", (unsigned)error,
                 r->renderer);
        return -1;
    }
    return 0;
}

/* The frame's layout, colours and chain selection: the Cairo drawer's own functions. */
static void layout_frame(const RenderGl *r, const SimFrame *frame, const RenderStyle *style,
                         Layout *l)
{
    l->style = render_style_resolve(frame, style);
    render_view_fit(frame, &l->style, &l->view);
    render_color_range(frame, &l->style, &l->lo, &l->hi);
    l->period = frame->periodic && frame->domain_x1 > frame->domain_x0
                    ? frame->domain_x1 - frame->domain_x0
                    : 0.0;
    double x0 = l->view.plot_x, x1 = l->view.plot_x + l->view.plot_w, y;
    if (l->period > 0.0) { /* Cairo clips a periodic frame to its domain as well */
        double px0, px1;
        render_view_to_pixel(&l->view, frame->domain_x0, 0.0, &px0, &y);
        render_view_to_pixel(&l->view, frame->domain_x1, 0.0, &px1, &y);
        x0 = fmax(x0, px0);
        x1 = fmin(x1, px1);
    }
    l->clip[0] = (float)x0;
    l->clip[1] = (float)l->view.plot_y;
    l->clip[2] = (float)fmax(x0, x1);
    l->clip[3] = (float)(l->view.plot_y + l->view.plot_h);
    /* Point sprites unless a disk is larger than the largest sprite: then every disk is a quad
     * that frame, in every band (such frames have few, large disks). */
    l->as_points = 1;
    for (int i = 0; i < frame->count && l->as_points; ++i)
        l->as_points = (float)(l->view.scale * frame->radius[i]) + 1.0f <= 0.5f * r->point_limit;
    /* Chains are lines unless one is wider than the widest line: then all are quads. */
    l->cut = 0.0;
    l->f_max = 0.0;
    l->chains_as_lines = 1;
    if (l->style.force_chains && frame->contact_count > 0) {
        l->cut = render_chain_cut(frame, &l->style, &l->f_max);
        double f_top = 0.0;
        for (int c = 0; c < frame->contact_count; ++c)
            f_top = fmax(f_top, frame->contacts[c].normal_force);
        if (f_top > l->cut)
            l->chains_as_lines = line_width(0.5 * chain_width(l, f_top)) <= r->line_limit;
    }
}

/* Draws a frame into `pixels` (the drawer's own buffer or a caller's of the same size): band 1
 * in the helper thread while the calling thread draws band 0. */
static int draw_frame(RenderGl *r, const SimFrame *frame, const RenderStyle *style, uint8_t *pixels,
                      char *err, size_t err_size)
{
    if (!r || !frame || !style || !pixels) {
        snprintf(err, err_size, "GL: no drawer, frame, style or image");
        return -1;
    }
    if (style->width != r->width || style->height != r->height) {
        snprintf(err, err_size, "GL: style size %dx%d differs from the drawer's %dx%d",
                 style->width, style->height, r->width, r->height);
        return -1;
    }
    Layout l;
    layout_frame(r, frame, style, &l);
    if (r->band_count == 2) {
        r->frame = frame;
        r->layout = &l;
        r->image = pixels;
        render_helper_start(r->helper, band1_draw, r);
    }
    Band *b0 = &r->bands[0];
    b0->rc = band_draw(r, b0, frame, &l, pixels);
    if (r->band_count == 2)
        render_helper_wait(r->helper);
    for (int k = 0; k < r->band_count; ++k) {
        if (r->bands[k].rc != 0) {
            snprintf(err, err_size, "%s", r->bands[k].err);
            return -1;
        }
    }
    return 0;
}

int render_gl_frame(RenderGl *r, const SimFrame *frame, const RenderStyle *style, RenderImage *out,
                    char *err, size_t err_size)
{
    if (!out) {
        snprintf(err, err_size, "GL: no image");
        return -1;
    }
    if (draw_frame(r, frame, style, r ? r->pixels : NULL, err, err_size) != 0)
        return -1;
    out->width = r->width;
    out->height = r->height;
    out->stride = 4 * r->width;
    out->format = RENDER_PIXEL_BGRA_PREMUL;
    out->pixels = r->pixels;
    return 0;
}

int render_gl_frame_to(RenderGl *r, const SimFrame *frame, const RenderStyle *style,
                       RenderImage *target, char *err, size_t err_size)
{
    if (!r || !target || !target->pixels || target->width != r->width ||
        target->height != r->height || target->stride != 4 * target->width) {
        snprintf(err, err_size, "GL: target image does not fit the drawer");
        return -1;
    }
    if (draw_frame(r, frame, style, target->pixels, err, err_size) != 0)
        return -1;
    target->format = RENDER_PIXEL_BGRA_PREMUL;
    return 0;
}

int render_gl_draw(const SimFrame *frame, const RenderStyle *style, RenderImage *out)
{
    char err[256];
    if (!style || !out)
        return -1;
    out->pixels = NULL;
    RenderGl *r = render_gl_create(style->width, style->height, err, sizeof err);
    if (!r)
        return -1;
    RenderImage view;
    int rc = render_gl_frame(r, frame, style, &view, err, sizeof err);
    if (rc == 0)
        rc = render_image_alloc(out, view.width, view.height, view.format);
    if (rc == 0)
        memcpy(out->pixels, view.pixels, (size_t)view.stride * (size_t)view.height);
    render_gl_destroy(r);
    return rc;
}
