/* SPDX-License-Identifier: MIT */
/* render_gl.c: the fast movie drawer. GL 3.3 core on llvmpipe through OSMesa; every disk is one
 * point sprite whose fragment shader keeps the pixels inside the circle and antialiases the rim
 * by the area of the pixel inside it (outline ring in the same fragment); orientation ticks and
 * walls are quads (two indexed triangles) and force chains wide lines (one primitive each), with
 * the same analytic coverage.
 *
 * Speed (1920x1080, 7284 grains and ~8k chains; bench/README.md): llvmpipe shades vertices and
 * sets up primitives in the calling thread and shades fragments in LP_NUM_THREADS threads on 4x4
 * blocks, executing both sides of every branch, so the drawer uses plain vertex arrays (no
 * instancing: per-instance overhead), one vertex per disk, branch-free coverage, separate round
 * and butt programs, the clip compiled in only when something reaches it, persistent buffers
 * (glBufferSubData) and draws straight into the caller's image (render_gl_frame_to).
 *
 * What is drawn follows the Cairo drawer (render_cairo.c, the reference) in order, colours and
 * sizes, so both agree within the image-diff tolerance: background; clipped to the plot
 * rectangle: disks in frame order (fill by RenderStyle.color_by through the shared colour
 * functions, fixed grains in fixed_rgb, dark outline ring), orientation ticks, walls, force
 * chains weakest first (width and colour by F_n); periodic copies across the seam. Layout,
 * colours and chain selection come from render.h's shared helpers; colours reach GL as the same
 * 8-bit values Cairo uses. The annotations (velocity arrows and field, arch highlights and inset,
 * colour bar, time stamp, scale bar, title) are Cairo's, drawn on the GL image by
 * render_cairo_overlay.
 *
 * The GL context is the one struct GlContext below (create, make current, finish, destroy);
 * GL entry points come through its proc-address function, so an EGL surfaceless back end
 * (eglGetProcAddress, an FBO and glReadPixels in finish) replaces OSMesa here alone. */
#include "render/render_gl.h"

#include "render/render.h"

#include <GL/osmesa.h>
#include <math.h>
#include <pthread.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ------------------------------------------------------------------ GL context (OSMesa) */

typedef void (*GlProc)(void);

typedef struct GlContext {
    OSMesaContext osmesa;
    uint8_t *pixels; ///< the drawer's own BGRA buffer, rows top-down, width * height * 4 bytes
    int width, height;
} GlContext;

/* llvmpipe reads LP_NUM_THREADS once, when the first context creates its screen; by default it
 * takes every online CPU. Set it explicitly (unless the user did) so the rasteriser uses the
 * cores the machine has (anchors-render: 16.3 ms with 1 thread, 10.9 ms with 2). */
static void set_rasteriser_threads(void)
{
    if (getenv("LP_NUM_THREADS"))
        return;
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    char value[16];
    snprintf(value, sizeof value, "%ld", cpus > 0 ? (cpus < 32 ? cpus : 32) : 1);
    setenv("LP_NUM_THREADS", value, 0);
}

static pthread_once_t threads_once = PTHREAD_ONCE_INIT;

static int context_create(GlContext *context, int width, int height, char *err, size_t err_size)
{
    /* Core 3.3 without depth or stencil: llvmpipe in Mesa 22.3 gives 4.5 core. BGRA bytes are
     * Cairo's ARGB32 on little-endian, so the overlay draws on GL frames in place. */
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
    context->width = width;
    context->height = height;
    context->pixels = malloc((size_t)width * (size_t)height * 4);
    if (!context->pixels) {
        snprintf(err, err_size, "GL: out of memory for %dx%d pixels", width, height);
        return -1;
    }
    context->osmesa = OSMesaCreateContextAttribs(attributes, NULL);
    if (!context->osmesa) {
        snprintf(err, err_size, "GL: OSMesa cannot create a GL 3.3 core context");
        free(context->pixels);
        context->pixels = NULL;
        return -1;
    }
    return 0;
}

/* Binds the context to `pixels` (the drawer's own buffer or a caller's image of the same size):
 * OSMesa copies the finished frame there, so a movie draws straight into its queue slots. */
static int context_make_current(GlContext *context, uint8_t *pixels)
{
    if (!OSMesaMakeCurrent(context->osmesa, pixels, GL_UNSIGNED_BYTE, context->width,
                           context->height))
        return -1;
    OSMesaPixelStore(OSMESA_Y_UP, 0); /* rows top-down, as RenderImage wants: no flip */
    return 0;
}

static GlProc context_proc(const char *name)
{
    return (GlProc)OSMesaGetProcAddress(name);
}

/* OSMesa renders into pixels; the caller's glFinish completes them. */
static void context_finish(GlContext *context)
{
    (void)context;
}

static void context_destroy(GlContext *context)
{
    if (context->osmesa)
        OSMesaDestroyContext(context->osmesa);
    free(context->pixels);
    context->osmesa = NULL;
    context->pixels = NULL;
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
    X(void, Finish, (void))                                                                        \
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
    X(void, BindAttribLocation, (GLuint, GLuint, const GLchar *))                                  \
    X(void, LinkProgram, (GLuint))                                                                 \
    X(void, GetProgramiv, (GLuint, GLenum, GLint *))                                               \
    X(void, GetProgramInfoLog, (GLuint, GLsizei, GLsizei *, GLchar *))                             \
    X(void, DeleteProgram, (GLuint))                                                               \
    X(void, UseProgram, (GLuint))                                                                  \
    X(GLint, GetUniformLocation, (GLuint, const GLchar *))                                         \
    X(void, Uniform1f, (GLint, GLfloat))                                                           \
    X(void, Uniform2f, (GLint, GLfloat, GLfloat))                                                  \
    X(void, Uniform4f, (GLint, GLfloat, GLfloat, GLfloat, GLfloat))                                \
    X(void, GenVertexArrays, (GLsizei, GLuint *))                                                  \
    X(void, BindVertexArray, (GLuint))                                                             \
    X(void, DeleteVertexArrays, (GLsizei, const GLuint *))                                         \
    X(void, GenBuffers, (GLsizei, GLuint *))                                                       \
    X(void, BindBuffer, (GLenum, GLuint))                                                          \
    X(void, BufferData, (GLenum, GLsizeiptr, const void *, GLenum))                                \
    X(void, BufferSubData, (GLenum, GLintptr, GLsizeiptr, const void *))                           \
    X(void, DeleteBuffers, (GLsizei, const GLuint *))                                              \
    X(void, EnableVertexAttribArray, (GLuint))                                                     \
    X(void, VertexAttribPointer, (GLuint, GLint, GLenum, GLboolean, GLsizei, const void *))        \
    X(void, VertexAttribDivisor, (GLuint, GLuint))                                                 \
    X(void, DrawArrays, (GLenum, GLint, GLsizei))                                                  \
    X(void, DrawElements, (GLenum, GLsizei, GLenum, const void *))                                 \
    X(void, DrawArraysInstanced, (GLenum, GLint, GLsizei, GLsizei))                                \
    X(void, LineWidth, (GLfloat))

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
 * the formula is branch-free, the footprint (a, b, 1 / 2ab) is computed once per fragment and
 * shared by both edges of a shape, b is kept above 1/64 (a trapezoid that narrow differs from
 * the box by under 0.002 of coverage, half a level), round and butt segments are separate
 * programs, and the plot-rectangle clip is compiled in (CLIP 1) only when a frame has
 * primitives that reach it. */
static const char common_source[] =
    "uniform vec2 viewport;\n" /* width, height, px */
    "uniform vec4 clip;\n"     /* x0, y0, x1, y1, px, y down */
    "uniform float margin;\n"  /* px the GL viewport reaches beyond each image edge */
    "vec4 clip_position(vec2 p) {\n"
    "    vec2 q = (p + margin) / (viewport + 2.0 * margin);\n"
    "    return vec4(2.0 * q.x - 1.0, 1.0 - 2.0 * q.y, 0.0, 1.0);\n"
    "}\n";

static const char fragment_common_source[] =
    "vec3 footprint(vec2 n) {\n" /* a, b, 1 / (2 a b) of a pixel seen along n */
    "    vec2 m = abs(n);\n"
    "    float a = max(max(m.x, m.y), 1.0 / 64.0), b = max(min(m.x, m.y), 1.0 / 64.0);\n"
    "    return vec3(a, b, 0.5 / (a * b));\n"
    "}\n"
    "float pixel_cdf(float t, vec3 p) {\n" /* share of the pixel at depth t inside an edge */
    "    float s = t + 0.5 * (p.x + p.y);\n"
    "    vec4 r = max(vec4(s, s - p.x, s - p.y, s - p.x - p.y), 0.0);\n"
    "    r *= r;\n"
    "    return clamp((r.x - r.y - r.z + r.w) * p.z, 0.0, 1.0);\n"
    "}\n"
    "float band(float s, float lo, float hi, vec3 p) {\n"
    "    return max(0.0, pixel_cdf(hi - s, p) - pixel_cdf(lo - s, p));\n"
    "}\n"
    "vec2 pixel_position() {\n" /* pixel centre, px, y down */
    "    return vec2(gl_FragCoord.x, viewport.y - gl_FragCoord.y);\n"
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
     * shares add up without a division, and one inverse square root gives the distance and the
     * edge normal. */
    "uniform vec4 outline_colour;\n"
    "vec4 shade_disk(vec2 local, vec2 size, vec4 colour) {\n"
    "    float d2 = dot(local, local);\n"
    "    float inv = inversesqrt(max(d2, 1e-12));\n"
    "    float d = d2 * inv;\n"
    "    vec3 p = footprint(d2 > 0.0 ? local * inv : vec2(1.0, 0.0));\n"
    "    float total = min(pixel_cdf(size.x - d, p), 3.14159265 * size.x * size.x);\n"
    "    float inner = size.y > 0.0 ? min(pixel_cdf(size.x - size.y - d, p), total) : total;\n"
    "    float alpha = total * clip_coverage(), fill = inner * clip_coverage();\n"
    "    return vec4(outline_colour.rgb * (alpha - fill) + colour.rgb * fill, alpha);\n"
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
 * gl_FragCoord, so coverage and colour are the quad shader's. */
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
    "    result = shade_disk(pixel_position() - shape.xy, shape.zw, colour);\n"
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
    "    vec2 v = vec2(local.x - clamp(local.x, 0.0, form.x), local.y);\n"
    "    float d = length(v);\n"
    "    vec2 n = d > 0.0 ? (direction * v.x + vec2(-direction.y, direction.x) * v.y) / d\n"
    "                     : vec2(-direction.y, direction.x);\n"
    "    float a = band(d, -form.y, form.y, footprint(n)) * clip_coverage() * colour.a;\n"
    "    if (a <= 0.0) discard;\n"
    "    result = vec4(colour.rgb, a);\n"
    "}\n";

/* Force chains as wide lines: one primitive per chain (llvmpipe rasterises a wide line as one
 * four-edged primitive; a quad's two long thin triangles both visit every 4x4 block along their
 * shared diagonal). The line runs along the chain, lengthened at both ends so the caps fit; its
 * width, a whole number of pixels shared by a run of chains (glLineWidth), covers the capsule at
 * any angle (draw_chain_lines). A line's attributes do not vary across it, so the fragment finds
 * its place along and across the chain from gl_FragCoord, as the point sprites do. */
static const char line_vertex_source[] =
    "layout(location = 0) in vec2 corner;\n" /* 0: start, 1: end */
    "layout(location = 1) in vec4 ends;\n"   /* x0, y0, x1, y1, px */
    "layout(location = 2) in vec2 shape;\n"  /* half width px, round caps */
    "layout(location = 3) in vec4 paint;\n"
    "flat out vec4 start;\n" /* x0, y0, unit direction */
    "flat out vec2 form;\n"  /* length, half width, px */
    "flat out vec4 colour;\n"
    "void main() {\n"
    "    vec2 axis = ends.zw - ends.xy;\n"
    "    float len = length(axis);\n"
    "    vec2 t = len > 0.0 ? axis / len : vec2(1.0, 0.0);\n"
    /* Along the major axis the line must reach a pixel beyond the cap, plus the one pixel
     * llvmpipe's diamond-exit rule may take off an end. */
    "    vec2 m = abs(t);\n"
    "    float reach = (shape.x + 2.0) / max(m.x, m.y);\n"
    "    gl_Position = clip_position(corner.x > 0.5 ? ends.zw + t * reach : ends.xy - t * reach);\n"
    "    start = vec4(ends.xy, t);\n"
    "    form = vec2(len, shape.x);\n"
    "    colour = paint;\n"
    "}\n";

static const char line_fragment_source[] =
    "flat in vec4 start;\n"
    "flat in vec2 form;\n"
    "flat in vec4 colour;\n"
    "out vec4 result;\n"
    "void main() {\n"
    "    vec2 q = pixel_position() - start.xy, across = vec2(-start.w, start.z);\n"
    "    float along = dot(q, start.zw);\n"
    "    vec2 v = vec2(along - clamp(along, 0.0, form.x), dot(q, across));\n"
    "    float d2 = dot(v, v);\n"
    "    float inv = inversesqrt(max(d2, 1e-12));\n"
    "    float d = d2 * inv;\n"
    "    vec2 n = d2 > 0.0 ? (start.zw * v.x + across * v.y) * inv : across;\n"
    "    float a = band(d, -form.y, form.y, footprint(n)) * clip_coverage() * colour.a;\n"
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
    "    vec3 p = footprint(direction);\n"
    "    float a = band(local.x, 0.0, form.x, p) * band(local.y, -form.y, form.y, p);\n"
    "    a = min(a, 1.0) * clip_coverage() * colour.a;\n"
    "    if (a <= 0.0) discard;\n"
    "    result = vec4(colour.rgb, a);\n"
    "}\n";

/* Programs: each shape with the clip compiled out (index 0) and in (index 1). */
enum {
    PROGRAM_QUAD_DISK,
    PROGRAM_POINT_DISK,
    PROGRAM_ROUND,
    PROGRAM_BUTT,
    PROGRAM_LINE,
    PROGRAM_KINDS
};

static const char *const program_sources[PROGRAM_KINDS][2] = {
    {disk_vertex_source, disk_fragment_source},     {point_vertex_source, point_fragment_source},
    {segment_vertex_source, round_fragment_source}, {segment_vertex_source, butt_fragment_source},
    {line_vertex_source, line_fragment_source},
};

/* ------------------------------------------------------------------ drawer */

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

typedef struct ChainOrder {
    double force; ///< N
    int index;    ///< contact
} ChainOrder;

/* Uniform locations of a program. */
typedef struct Uniforms {
    GLint viewport, clip, margin, outline_colour;
} Uniforms;

struct RenderGl {
    GlContext context;
    GlApi gl;
    int current;                       ///< 1 after the first make-current
    GLuint programs[PROGRAM_KINDS][2]; ///< [kind][clip]
    Uniforms uniforms[PROGRAM_KINDS][2];
    GLuint disk_vao, point_vao, segment_vao, line_vao;
    GLuint corner_buffer, disk_buffer, segment_buffer, index_buffer, line_index_buffer;
    GLsizeiptr disk_bytes, segment_bytes; ///< buffer capacities, bytes
    int index_segments;                   ///< segments the index buffer covers
    float margin;                         ///< px the viewport reaches beyond each image edge
    float point_limit;                    ///< largest point sprite, px
    float line_limit;                     ///< widest line, px (chains wider are quads)
    DiskInstance *disks;
    SegmentVertex *segments; ///< 4 vertices per segment
    uint32_t *indices;       ///< 6 per segment: two triangles
    uint32_t *line_indices;  ///< 2 per segment: its start and end vertices
    ChainOrder *chains;
    int disk_capacity, segment_capacity, chain_capacity, index_capacity, line_index_capacity;
    char renderer[128];
};

static GLuint compile(RenderGl *r, GLenum kind, const char *body, int clip, char *err,
                      size_t err_size)
{
    const char *parts[4] = {
        clip ? "#version 330 core\n#define CLIP 1\n" : "#version 330 core\n#define CLIP 0\n",
        common_source, kind == GL_FRAGMENT_SHADER ? fragment_common_source : "", body};
    GLuint shader = r->gl.CreateShader(kind);
    r->gl.ShaderSource(shader, 4, parts, NULL);
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

static GLuint link_program(RenderGl *r, const char *vertex, const char *fragment, int clip,
                           Uniforms *uniforms, char *err, size_t err_size)
{
    GLuint vs = compile(r, GL_VERTEX_SHADER, vertex, clip, err, err_size);
    if (!vs)
        return 0;
    GLuint fs = compile(r, GL_FRAGMENT_SHADER, fragment, clip, err, err_size);
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
    uniforms->viewport = r->gl.GetUniformLocation(program, "viewport");
    uniforms->clip = r->gl.GetUniformLocation(program, "clip");
    uniforms->margin = r->gl.GetUniformLocation(program, "margin");
    uniforms->outline_colour = r->gl.GetUniformLocation(program, "outline_colour");
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

static void setup_vaos(RenderGl *r)
{
    /* Instanced quads (disks too large for a point sprite): attribute 0 the corners (a
     * triangle strip), then per-instance attributes. */
    GLsizei stride = sizeof(DiskInstance);
    r->gl.BindVertexArray(r->disk_vao);
    r->gl.BindBuffer(GL_ARRAY_BUFFER, r->corner_buffer);
    attribute(r, 0, 2, GL_FLOAT, 2 * sizeof(float), 0, 0);
    r->gl.BindBuffer(GL_ARRAY_BUFFER, r->disk_buffer);
    attribute(r, 1, 4, GL_FLOAT, stride, offsetof(DiskInstance, x), 1);
    attribute(r, 2, 4, GL_UNSIGNED_BYTE, stride, offsetof(DiskInstance, rgba), 1);
    /* Point sprites: the same buffer, one vertex per disk. */
    r->gl.BindVertexArray(r->point_vao);
    attribute(r, 0, 4, GL_FLOAT, stride, offsetof(DiskInstance, x), 0);
    attribute(r, 1, 4, GL_UNSIGNED_BYTE, stride, offsetof(DiskInstance, rgba), 0);
    /* Segments: indexed triangles over four vertices each. */
    stride = sizeof(SegmentVertex);
    r->gl.BindVertexArray(r->segment_vao);
    r->gl.BindBuffer(GL_ARRAY_BUFFER, r->segment_buffer);
    attribute(r, 0, 2, GL_FLOAT, stride, offsetof(SegmentVertex, corner), 0);
    attribute(r, 1, 4, GL_FLOAT, stride, offsetof(SegmentVertex, x0), 0);
    attribute(r, 2, 2, GL_FLOAT, stride, offsetof(SegmentVertex, half_width), 0);
    attribute(r, 3, 4, GL_UNSIGNED_BYTE, stride, offsetof(SegmentVertex, rgba), 0);
    r->gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->index_buffer); /* part of the VAO's state */
    /* Chains as lines: the same vertices, two of each segment's four. */
    r->gl.BindVertexArray(r->line_vao);
    attribute(r, 0, 2, GL_FLOAT, stride, offsetof(SegmentVertex, corner), 0);
    attribute(r, 1, 4, GL_FLOAT, stride, offsetof(SegmentVertex, x0), 0);
    attribute(r, 2, 2, GL_FLOAT, stride, offsetof(SegmentVertex, half_width), 0);
    attribute(r, 3, 4, GL_UNSIGNED_BYTE, stride, offsetof(SegmentVertex, rgba), 0);
    r->gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->line_index_buffer);
    r->gl.BindVertexArray(0);
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
    if (context_create(&r->context, width, height, err, err_size) != 0) {
        free(r);
        return NULL;
    }
    if (context_make_current(&r->context, r->context.pixels) != 0) {
        snprintf(err, err_size, "GL: cannot make the OSMesa context current");
        goto fail;
    }
    r->current = 1;
    if (api_load(&r->gl, err, err_size) != 0)
        goto fail;
    const GLubyte *renderer = r->gl.GetString(GL_RENDERER);
    snprintf(r->renderer, sizeof r->renderer, "%s", renderer ? (const char *)renderer : "?");

    for (int kind = 0; kind < PROGRAM_KINDS; ++kind) {
        for (int clip = 0; clip < 2; ++clip) {
            r->programs[kind][clip] =
                link_program(r, program_sources[kind][0], program_sources[kind][1], clip,
                             &r->uniforms[kind][clip], err, err_size);
            if (!r->programs[kind][clip])
                goto fail;
        }
    }

    /* Points are clipped by their centre: the viewport reaches past the image by half the
     * largest sprite, so disks centred just outside the image still show their inner part. */
    GLfloat sizes[2] = {1.0f, 1.0f};
    GLint dims[2] = {width, height};
    r->gl.GetFloatv(GL_ALIASED_POINT_SIZE_RANGE, sizes);
    r->gl.GetIntegerv(GL_MAX_VIEWPORT_DIMS, dims);
    int room = (dims[0] - width < dims[1] - height ? dims[0] - width : dims[1] - height) / 2;
    int margin = (int)ceil(0.5 * (double)sizes[1]) + 1;
    r->margin = (float)(margin < room ? margin : room > 0 ? room : 0);
    r->point_limit = fminf(sizes[1], 2.0f * r->margin - 2.0f);
    r->gl.Enable(GL_PROGRAM_POINT_SIZE);
    GLfloat widths[2] = {1.0f, 1.0f};
    r->gl.GetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, widths);
    r->line_limit = widths[1];

    /* Quads as triangle strips: disks use (+-1, +-1). */
    static const float corners[8] = {-1, -1, 1, -1, -1, 1, 1, 1};
    GLuint buffers[5];
    r->gl.GenBuffers(5, buffers);
    r->corner_buffer = buffers[0];
    r->disk_buffer = buffers[1];
    r->segment_buffer = buffers[2];
    r->index_buffer = buffers[3];
    r->line_index_buffer = buffers[4];
    GLuint vaos[4];
    r->gl.GenVertexArrays(4, vaos);
    r->disk_vao = vaos[0];
    r->point_vao = vaos[1];
    r->segment_vao = vaos[2];
    r->line_vao = vaos[3];
    r->gl.BindBuffer(GL_ARRAY_BUFFER, r->corner_buffer);
    r->gl.BufferData(GL_ARRAY_BUFFER, sizeof corners, corners, GL_STATIC_DRAW);
    setup_vaos(r);
    if (r->gl.GetError() != GL_NO_ERROR) {
        snprintf(err, err_size, "GL: set-up failed on %s", r->renderer);
        goto fail;
    }
    return r;

fail:
    render_gl_destroy(r);
    return NULL;
}

void render_gl_destroy(RenderGl *r)
{
    if (!r)
        return;
    if (r->current && r->gl.DeleteBuffers &&
        context_make_current(&r->context, r->context.pixels) == 0) {
        GLuint buffers[5] = {r->corner_buffer, r->disk_buffer, r->segment_buffer, r->index_buffer,
                             r->line_index_buffer};
        GLuint vaos[4] = {r->disk_vao, r->point_vao, r->segment_vao, r->line_vao};
        r->gl.DeleteBuffers(5, buffers);
        r->gl.DeleteVertexArrays(4, vaos);
        for (int kind = 0; kind < PROGRAM_KINDS; ++kind)
            for (int clip = 0; clip < 2; ++clip)
                if (r->programs[kind][clip])
                    r->gl.DeleteProgram(r->programs[kind][clip]);
    }
    context_destroy(&r->context);
    free(r->disks);
    free(r->segments);
    free(r->indices);
    free(r->line_indices);
    free(r->chains);
    free(r);
}

const char *render_gl_renderer(const RenderGl *r)
{
    return r ? r->renderer : "";
}

/* ------------------------------------------------------------------ what to draw */

/* Colours and sizes of the Cairo drawer (render_cairo.c), which is the reference. */
#define OUTLINE_RGB 0x2a2a2au
#define WALL_RGB    0x3c3c3cu

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

static void uniform_rgb(RenderGl *r, GLint location, uint32_t rgb)
{
    r->gl.Uniform4f(location, (float)((rgb >> 16) & 255) / 255.0f,
                    (float)((rgb >> 8) & 255) / 255.0f, (float)(rgb & 255) / 255.0f, 1.0f);
}

static int is_fixed(const SimFrame *frame, int i)
{
    return frame->flags && (frame->flags[i] & SIM_GRAIN_FIXED);
}

/* Cairo's outline ring width for a disk of r pixels (0 = no outline). */
static double outline_width(double r)
{
    return fmin(1.5, fmax(0.6, 0.07 * r));
}

/* Everything one frame needs, resolved once. */
typedef struct Layout {
    RenderStyle style; ///< resolved (render_style_resolve)
    RenderView view;
    double lo, hi;                         ///< colour range
    double period;                         ///< periodic x length, m (0 = not periodic)
    float clip[4];                         ///< x0, y0, x1, y1, px
    int clip_disks, clip_butt, clip_round; ///< 1: some primitive of the kind reaches the clip
} Layout;

/* 1 when the box (px) is far enough inside the clip rectangle that every pixel centre in it has
 * clip coverage 1, so the shaders may leave the clip out. */
static int reaches_clip(const Layout *l, double x0, double y0, double x1, double y1)
{
    return !(x0 >= (double)l->clip[0] + 0.5 && y0 >= (double)l->clip[1] + 0.5 &&
             x1 <= (double)l->clip[2] - 0.5 && y1 <= (double)l->clip[3] - 0.5);
}

static void add_disk(RenderGl *r, int *n, Layout *l, const SimFrame *frame, int i, double offset,
                     uint32_t rgb)
{
    DiskInstance *d = &r->disks[(*n)++];
    double px, py, radius = l->view.scale * frame->radius[i];
    render_view_to_pixel(&l->view, frame->x[i] + offset, frame->y[i], &px, &py);
    d->x = (float)px;
    d->y = (float)py;
    d->radius = (float)radius;
    d->outline = (l->style.outline || is_fixed(frame, i)) && radius >= 1.5
                     ? (float)outline_width(radius)
                     : 0.0f;
    set_rgba(d->rgba, rgb);
    double pad = radius + 1.0;
    if (!l->clip_disks)
        l->clip_disks = reaches_clip(l, px - pad, py - pad, px + pad, py + pad);
}

/* Disks in frame order, with the copies a periodic frame shows across the seam. */
static int collect_disks(RenderGl *r, const SimFrame *frame, Layout *l)
{
    if (reserve((void **)&r->disks, &r->disk_capacity, 3 * frame->count, sizeof(DiskInstance)))
        return -1;
    int n = 0;
    for (int i = 0; i < frame->count; ++i) {
        uint32_t rgb = render_grain_rgb(frame, &l->style, i, l->lo, l->hi);
        add_disk(r, &n, l, frame, i, 0.0, rgb);
        if (l->period > 0.0) {
            if (frame->x[i] - frame->radius[i] < frame->domain_x0)
                add_disk(r, &n, l, frame, i, l->period, rgb);
            if (frame->x[i] + frame->radius[i] > frame->domain_x1)
                add_disk(r, &n, l, frame, i, -l->period, rgb);
        }
    }
    return n;
}

static void add_segment(RenderGl *r, int *n, Layout *l, double ax, double ay, double bx, double by,
                        double width, int round, uint32_t rgb)
{
    static const float corners[4][2] = {{0, -1}, {1, -1}, {0, 1}, {1, 1}};
    SegmentVertex *s = &r->segments[4 * (*n)++];
    double x0, y0, x1, y1;
    render_view_to_pixel(&l->view, ax, ay, &x0, &y0);
    render_view_to_pixel(&l->view, bx, by, &x1, &y1);
    s->x0 = (float)x0;
    s->y0 = (float)y0;
    s->x1 = (float)x1;
    s->y1 = (float)y1;
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
    double pad = 0.5 * width + 1.0;
    int *flag = round ? &l->clip_round : &l->clip_butt;
    if (!*flag)
        *flag = reaches_clip(l, fmin(x0, x1) - pad, fmin(y0, y1) - pad, fmax(x0, x1) + pad,
                             fmax(y0, y1) + pad);
}

static int compare_chains(const void *a, const void *b)
{
    const ChainOrder *p = a, *q = b;
    if (p->force != q->force)
        return p->force < q->force ? -1 : 1;
    return (p->index > q->index) - (p->index < q->index);
}

/* Orientation ticks, walls, force chains as segment instances, in Cairo's drawing order. */
static int collect_segments(RenderGl *r, const SimFrame *frame, Layout *l, int counts[3])
{
    const RenderStyle *s = &l->style;
    const RenderView *v = &l->view;
    int ticks = s->orientation_tick && frame->angle ? 3 * frame->count : 0;
    int chains = s->force_chains ? 2 * frame->contact_count : 0;
    if (reserve((void **)&r->segments, &r->segment_capacity, ticks + frame->wall_count + chains,
                4 * sizeof(SegmentVertex)) ||
        reserve((void **)&r->chains, &r->chain_capacity, frame->contact_count, sizeof(ChainOrder)))
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
                add_segment(r, &n, l, x, y, x + len * cos(frame->angle[i]),
                            y + len * sin(frame->angle[i]), width, 0, OUTLINE_RGB);
            }
        }
    }
    counts[0] = n;
    if (frame->walls) {
        double width = fmax(3.0, 0.3 * v->mean_diameter * v->scale);
        for (int w = 0; w < frame->wall_count; ++w) {
            const SimWall *wall = &frame->walls[w];
            add_segment(r, &n, l, wall->x0, wall->y0, wall->x1, wall->y1, width, 1, WALL_RGB);
        }
    }
    counts[1] = n - counts[0];
    if (chains && frame->contact_count > 0) {
        double f_max = 0.0;
        double cut = render_chain_cut(frame, s, &f_max);
        int m = 0;
        for (int c = 0; c < frame->contact_count; ++c) {
            double f = frame->contacts[c].normal_force;
            if (f > 0.0 && f > cut)
                r->chains[m++] = (ChainOrder){f, c};
        }
        /* Weakest first so strong chains lie on top; ties by index (a total order, so the
         * same sequence as Cairo's stable sort). */
        qsort(r->chains, (size_t)m, sizeof *r->chains, compare_chains);
        for (int k = 0; k < m; ++k) {
            const SimContact *c = &frame->contacts[r->chains[k].index];
            if (c->i < 0 || c->i >= frame->count || c->j >= frame->count)
                continue;
            double t = f_max > 0.0 ? fmin(1.0, c->normal_force / f_max) : 1.0;
            double ax = frame->x[c->i], ay = frame->y[c->i];
            double bx = c->j >= 0 ? frame->x[c->j] : c->x; /* wall contact: to the contact */
            double by = c->j >= 0 ? frame->y[c->j] : c->y;
            double dx = bx - ax;
            if (l->period > 0.0) /* minimum image across the seam */
                dx -= l->period * floor(dx / l->period + 0.5);
            /* Upper 65 % of the yellow-red map, width proportional to F_n (render_cairo.c). */
            uint32_t rgb = render_colormap_rgb(RENDER_CMAP_YELLOW_RED, 0.35 + 0.65 * t);
            double width = fmax(0.8, s->chain_width_max * t);
            add_segment(r, &n, l, ax, ay, ax + dx, by, width, 1, rgb);
            if (l->period > 0.0 && (ax + dx < frame->domain_x0 || ax + dx > frame->domain_x1))
                add_segment(r, &n, l, bx, by, bx - dx, ay, width, 1, rgb);
        }
    }
    counts[2] = n - counts[0] - counts[1];
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

static void use_program(RenderGl *r, int kind, int clip, const Layout *l)
{
    const Uniforms *u = &r->uniforms[kind][clip != 0];
    r->gl.UseProgram(r->programs[kind][clip != 0]);
    r->gl.Uniform2f(u->viewport, (float)r->context.width, (float)r->context.height);
    r->gl.Uniform4f(u->clip, l->clip[0], l->clip[1], l->clip[2], l->clip[3]);
    r->gl.Uniform1f(u->margin, r->margin);
    if (u->outline_colour >= 0)
        uniform_rgb(r, u->outline_colour, OUTLINE_RGB);
    /* Disks give premultiplied colour (shade_disk), segments straight colour; "over" either way,
     * and the destination stays opaque. */
    if (kind == PROGRAM_QUAD_DISK || kind == PROGRAM_POINT_DISK)
        r->gl.BlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    else
        r->gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE,
                                GL_ONE_MINUS_SRC_ALPHA);
}

/* Index buffer: triangles (0, 1, 2) and (2, 1, 3) of each segment's four vertices, the two
 * triangles of the former triangle strip. Built once for the largest count seen. */
static int segment_indices(RenderGl *r, int segments)
{
    if (segments <= r->index_segments)
        return 0;
    if (reserve((void **)&r->indices, &r->index_capacity, 6 * segments, sizeof(uint32_t)))
        return -1;
    int count = r->index_capacity / 6;
    for (int k = 0; k < count; ++k) {
        uint32_t *i = r->indices + 6 * k, v = 4u * (uint32_t)k;
        i[0] = v;
        i[1] = v + 1;
        i[2] = v + 2;
        i[3] = v + 2;
        i[4] = v + 1;
        i[5] = v + 3;
    }
    if (reserve((void **)&r->line_indices, &r->line_index_capacity, 2 * count, sizeof(uint32_t)))
        return -1;
    for (int k = 0; k < count; ++k) {
        r->line_indices[2 * k] = 4u * (uint32_t)k;
        r->line_indices[2 * k + 1] = 4u * (uint32_t)k + 1u; /* corners (0, -1) and (1, -1) */
    }
    GLsizeiptr capacity = 0; /* reallocated to the exact size */
    r->gl.BindVertexArray(r->segment_vao);
    upload(r, GL_ELEMENT_ARRAY_BUFFER, r->index_buffer, &capacity, r->indices,
           (GLsizeiptr)count * 6 * (GLsizeiptr)sizeof(uint32_t));
    capacity = 0;
    r->gl.BindVertexArray(r->line_vao);
    upload(r, GL_ELEMENT_ARRAY_BUFFER, r->line_index_buffer, &capacity, r->line_indices,
           (GLsizeiptr)count * 2 * (GLsizeiptr)sizeof(uint32_t));
    r->gl.BindVertexArray(0);
    r->index_segments = count;
    return 0;
}

/* Line width (a whole number of px, as llvmpipe rounds it) that covers segment k's capsule and
 * the pixels its antialiasing reaches, at any angle: llvmpipe widens a line along its minor axis,
 * where a capsule of half width h needs h / cos + (1 + tan) / 2 <= h sqrt(2) + 1 either side. */
static float chain_line_width(const RenderGl *r, int k)
{
    double h = (double)r->segments[4 * k].half_width;
    return (float)ceil(2.0 * (h * 1.4142135623730951 + 1.25));
}

/* Chains [first, end) as lines, one draw per run of equal line widths (chains come weakest, so
 * narrowest, first: a handful of runs). */
static void draw_chain_lines(RenderGl *r, const Layout *l, int first, int end)
{
    use_program(r, PROGRAM_LINE, l->clip_round, l);
    r->gl.BindVertexArray(r->line_vao);
    while (first < end) {
        float width = chain_line_width(r, first);
        int last = first + 1;
        while (last < end && chain_line_width(r, last) == width)
            ++last;
        r->gl.LineWidth(width);
        r->gl.DrawElements(GL_LINES, 2 * (last - first), GL_UNSIGNED_INT,
                           (const void *)((size_t)first * 2 * sizeof(uint32_t)));
        first = last;
    }
}

/* Draws a frame into `pixels` (the drawer's own buffer or a caller's of the same size). */
static int draw_frame(RenderGl *r, const SimFrame *frame, const RenderStyle *style, uint8_t *pixels,
                      char *err, size_t err_size)
{
    if (!r || !frame || !style || !pixels) {
        snprintf(err, err_size, "GL: no drawer, frame, style or image");
        return -1;
    }
    if (style->width != r->context.width || style->height != r->context.height) {
        snprintf(err, err_size, "GL: style size %dx%d differs from the drawer's %dx%d",
                 style->width, style->height, r->context.width, r->context.height);
        return -1;
    }
    /* Layout, colours and chain selection are the Cairo drawer's own functions. */
    Layout l;
    l.style = render_style_resolve(frame, style);
    render_view_fit(frame, &l.style, &l.view);
    render_color_range(frame, &l.style, &l.lo, &l.hi);
    l.period = frame->periodic && frame->domain_x1 > frame->domain_x0
                   ? frame->domain_x1 - frame->domain_x0
                   : 0.0;
    double x0 = l.view.plot_x, x1 = l.view.plot_x + l.view.plot_w, y;
    if (l.period > 0.0) { /* Cairo clips a periodic frame to its domain as well */
        double px0, px1;
        render_view_to_pixel(&l.view, frame->domain_x0, 0.0, &px0, &y);
        render_view_to_pixel(&l.view, frame->domain_x1, 0.0, &px1, &y);
        x0 = fmax(x0, px0);
        x1 = fmin(x1, px1);
    }
    l.clip[0] = (float)x0;
    l.clip[1] = (float)l.view.plot_y;
    l.clip[2] = (float)fmax(x0, x1);
    l.clip[3] = (float)(l.view.plot_y + l.view.plot_h);
    l.clip_disks = l.clip_butt = l.clip_round = 0;
    int disks = collect_disks(r, frame, &l);
    int counts[3] = {0, 0, 0};
    if (disks < 0 || collect_segments(r, frame, &l, counts) != 0) {
        snprintf(err, err_size, "GL: out of memory for %d grains", frame->count);
        return -1;
    }
    int segments = counts[0] + counts[1] + counts[2];
    /* Point sprites unless a disk is larger than the largest sprite: then every disk is a quad
     * that frame, keeping frame order (such frames have few, large disks). */
    int as_points = 1;
    for (int i = 0; i < disks && as_points; ++i)
        as_points = 2.0f * (r->disks[i].radius + 1.0f) <= r->point_limit;

    if (context_make_current(&r->context, pixels) != 0) {
        snprintf(err, err_size, "GL: cannot make the OSMesa context current");
        return -1;
    }
    if (segment_indices(r, segments) != 0) {
        snprintf(err, err_size, "GL: out of memory for %d segments", segments);
        return -1;
    }
    GLint m = (GLint)r->margin;
    r->gl.Viewport(-m, -m, r->context.width + 2 * m, r->context.height + 2 * m);
    uint32_t bg = l.style.background_rgb;
    r->gl.ClearColor((float)((bg >> 16) & 255) / 255.0f, (float)((bg >> 8) & 255) / 255.0f,
                     (float)(bg & 255) / 255.0f, 1.0f);
    r->gl.Clear(GL_COLOR_BUFFER_BIT);
    r->gl.Enable(GL_BLEND); /* the function goes with the program (use_program) */
    if (disks > 0) {
        upload(r, GL_ARRAY_BUFFER, r->disk_buffer, &r->disk_bytes, r->disks,
               (GLsizeiptr)disks * (GLsizeiptr)sizeof(DiskInstance));
        if (as_points) {
            use_program(r, PROGRAM_POINT_DISK, l.clip_disks, &l);
            r->gl.BindVertexArray(r->point_vao);
            r->gl.DrawArrays(GL_POINTS, 0, disks);
        } else {
            use_program(r, PROGRAM_QUAD_DISK, l.clip_disks, &l);
            r->gl.BindVertexArray(r->disk_vao);
            r->gl.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, disks);
        }
    }
    if (segments > 0) { /* orientation ticks (butt ends), then walls and force chains (round) */
        upload(r, GL_ARRAY_BUFFER, r->segment_buffer, &r->segment_bytes, r->segments,
               (GLsizeiptr)segments * 4 * (GLsizeiptr)sizeof(SegmentVertex));
        r->gl.BindVertexArray(r->segment_vao);
        if (counts[0] > 0) {
            use_program(r, PROGRAM_BUTT, l.clip_butt, &l);
            r->gl.DrawElements(GL_TRIANGLES, 6 * counts[0], GL_UNSIGNED_INT, NULL);
        }
        int first_chain = counts[0] + counts[1];
        int lines = counts[2] > 0; /* unless a chain is wider than the widest line */
        for (int k = first_chain; k < segments && lines; ++k)
            lines = chain_line_width(r, k) <= r->line_limit;
        int quads_end = lines ? first_chain : segments;
        if (quads_end > counts[0]) {
            use_program(r, PROGRAM_ROUND, l.clip_round, &l);
            r->gl.DrawElements(GL_TRIANGLES, 6 * (quads_end - counts[0]), GL_UNSIGNED_INT,
                               (const void *)((size_t)counts[0] * 6 * sizeof(uint32_t)));
        }
        if (lines)
            draw_chain_lines(r, &l, first_chain, segments);
    }
    r->gl.BindVertexArray(0);
    r->gl.Finish();
    context_finish(&r->context);
    GLenum error = r->gl.GetError();
    if (error != GL_NO_ERROR) {
        snprintf(err, err_size, "GL: drawing failed (GL error 0x%x on %s)", (unsigned)error,
                 r->renderer);
        return -1;
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
    if (draw_frame(r, frame, style, r ? r->context.pixels : NULL, err, err_size) != 0)
        return -1;
    out->width = r->context.width;
    out->height = r->context.height;
    out->stride = 4 * r->context.width;
    out->format = RENDER_PIXEL_BGRA_PREMUL;
    out->pixels = r->context.pixels;
    return 0;
}

int render_gl_frame_to(RenderGl *r, const SimFrame *frame, const RenderStyle *style,
                       RenderImage *target, char *err, size_t err_size)
{
    if (!r || !target || !target->pixels || target->width != r->context.width ||
        target->height != r->context.height || target->stride != 4 * target->width) {
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
