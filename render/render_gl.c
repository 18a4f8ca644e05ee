/* SPDX-License-Identifier: MIT */
/* render_gl.c: the fast movie drawer. GL 3.3 core on llvmpipe through OSMesa; every disk is one
 * instanced quad whose fragment shader keeps the pixels inside the circle and antialiases the
 * rim by the area of the pixel inside it; orientation ticks, walls and force chains are
 * instanced quads too (anchors-render 2b: 6-8x faster than triangle fans, and antialiased).
 *
 * What is drawn follows the Cairo drawer (render_cairo.c, the reference) in order, colours and
 * sizes, so both agree within the image-diff tolerance: background; clipped to the plot
 * rectangle: disks in frame order (fill by RenderStyle.color_by through the shared colour
 * functions, fixed grains in fixed_rgb, dark outline ring), orientation ticks, walls, force
 * chains weakest first (width and colour by F_n); periodic copies across the seam. Layout,
 * colours and chain selection come from render.h's shared helpers; colours reach GL as the same
 * 8-bit values Cairo uses. Cairo-only: velocity arrows and field, arch highlights and inset,
 * colour bar, time stamp, scale bar, title.
 *
 * The GL context is the one struct GlContext below (create, make current, finish, destroy);
 * GL entry points come through its proc-address function, so an EGL surfaceless back end
 * (eglGetProcAddress, an FBO and glReadPixels in finish) replaces OSMesa here alone. */
#include "render/render_gl.h"

#include "render/render.h"

#include <GL/osmesa.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------ GL context (OSMesa) */

typedef void (*GlProc)(void);

typedef struct GlContext {
    OSMesaContext osmesa;
    uint8_t *pixels; ///< RGBA, rows top-down (OSMESA_Y_UP = 0), width * height * 4 bytes
    int width, height;
} GlContext;

static int context_create(GlContext *context, int width, int height, char *err, size_t err_size)
{
    /* Core 3.3 without depth or stencil: llvmpipe in Mesa 22.3 gives 4.5 core. */
    static const int attributes[] = {OSMESA_FORMAT,
                                     OSMESA_RGBA,
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

static int context_make_current(GlContext *context)
{
    if (!OSMesaMakeCurrent(context->osmesa, context->pixels, GL_UNSIGNED_BYTE, context->width,
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
    X(void, Uniform2f, (GLint, GLfloat, GLfloat))                                                  \
    X(void, Uniform4f, (GLint, GLfloat, GLfloat, GLfloat, GLfloat))                                \
    X(void, GenVertexArrays, (GLsizei, GLuint *))                                                  \
    X(void, BindVertexArray, (GLuint))                                                             \
    X(void, DeleteVertexArrays, (GLsizei, const GLuint *))                                         \
    X(void, GenBuffers, (GLsizei, GLuint *))                                                       \
    X(void, BindBuffer, (GLenum, GLuint))                                                          \
    X(void, BufferData, (GLenum, GLsizeiptr, const void *, GLenum))                                \
    X(void, DeleteBuffers, (GLsizei, const GLuint *))                                              \
    X(void, EnableVertexAttribArray, (GLuint))                                                     \
    X(void, VertexAttribPointer, (GLuint, GLint, GLenum, GLboolean, GLsizei, const void *))        \
    X(void, VertexAttribDivisor, (GLuint, GLuint))                                                 \
    X(void, DrawArraysInstanced, (GLenum, GLint, GLsizei, GLsizei))

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
 * shape's edge taken as straight across the pixel: band(s, lo, hi, n) is the fraction of a pixel
 * whose centre lies at s along the unit direction n that falls in lo <= s' <= hi. The pixel
 * projected onto n is a box of width a = max(|n_x|, |n_y|) convolved with one of width
 * b = min(...): a trapezoid, whose distribution function is below. A plain one-dimensional box
 * (clamp(r - d + 1/2)) is off by up to 0.15 of a pixel on diagonal edges, 30 levels on a
 * dark outline against a light fill. */
static const char common_source[] =
    "#version 330 core\n"
    "uniform vec2 viewport;\n" /* width, height, px */
    "uniform vec4 clip;\n"     /* x0, y0, x1, y1, px, y down */
    "float pixel_cdf(float t, vec2 n) {\n"
    "    vec2 m = abs(n);\n"
    "    float a = max(m.x, m.y), b = min(m.x, m.y);\n"
    "    float h = 0.5 * (a + b), flat_half = 0.5 * (a - b);\n"
    "    if (t <= -h) return 0.0;\n"
    "    if (t >= h) return 1.0;\n"
    "    if (t < -flat_half) { float u = t + h; return u * u / (2.0 * a * b); }\n"
    "    if (t > flat_half) { float u = h - t; return 1.0 - u * u / (2.0 * a * b); }\n"
    "    return 0.5 + t / a;\n"
    "}\n"
    "float band(float s, float lo, float hi, vec2 n) {\n"
    "    return max(0.0, pixel_cdf(hi - s, n) - pixel_cdf(lo - s, n));\n"
    "}\n"
    "vec4 clip_position(vec2 p) {\n"
    "    return vec4(2.0 * p.x / viewport.x - 1.0, 1.0 - 2.0 * p.y / viewport.y, 0.0, 1.0);\n"
    "}\n";

/* The plot rectangle clip (Cairo's cairo_clip, fractional edges). */
static const char fragment_common_source[] =
    "float clip_coverage() {\n" /* axis-aligned edges: the one-dimensional box is exact */
    "    vec2 p = vec2(gl_FragCoord.x, viewport.y - gl_FragCoord.y);\n"
    "    vec2 lo = clamp(p - clip.xy + 0.5, 0.0, 1.0), hi = clamp(clip.zw - p + 0.5, 0.0, 1.0);\n"
    "    return lo.x * lo.y * hi.x * hi.y;\n"
    "}\n";

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

/* Cairo draws an outlined disk as a dark disk of radius r under a coloured one of radius r - w;
 * here both coverages come from one fragment (the rim as a straight edge along the radius). */
static const char disk_fragment_source[] =
    "uniform vec4 outline_colour;\n"
    "in vec2 local;\n"
    "flat in vec2 size;\n"
    "flat in vec4 colour;\n"
    "out vec4 result;\n"
    "void main() {\n"
    "    float d = length(local);\n"
    "    vec2 n = d > 0.0 ? local / d : vec2(1.0, 0.0);\n"
    /* The far side of the rim matters only for disks under a pixel: their coverage is capped
     * by their area instead (one distribution lookup per edge instead of two). */
    "    float total = min(pixel_cdf(size.x - d, n), 3.14159265 * size.x * size.x);\n"
    "    if (total <= 0.0) discard;\n"
    "    vec3 c = colour.rgb;\n"
    "    if (size.y > 0.0) {\n"
    "        float inner = min(pixel_cdf(size.x - size.y - d, n), total);\n"
    "        c = (inner * colour.rgb + (total - inner) * outline_colour.rgb) / total;\n"
    "    }\n"
    "    float a = total * clip_coverage();\n"
    "    if (a <= 0.0) discard;\n"
    "    result = vec4(c, a);\n"
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

static const char segment_fragment_source[] =
    "in vec2 local;\n"
    "flat in vec3 form;\n" /* length, half width, round caps */
    "flat in vec2 direction;\n"
    "flat in vec4 colour;\n"
    "out vec4 result;\n"
    "void main() {\n"
    "    float a;\n"
    "    if (form.z > 0.5) {\n" /* round caps: a capsule, by the distance to the axis segment */
    "        vec2 v = vec2(local.x - clamp(local.x, 0.0, form.x), local.y);\n"
    "        float d = length(v);\n"
    "        vec2 n = d > 0.0 ? (direction * v.x + vec2(-direction.y, direction.x) * v.y) / d\n"
    "                         : vec2(-direction.y, direction.x);\n"
    "        a = band(d, -form.y, form.y, n);\n"
    "    } else {\n" /* butt ends: the pixel's footprint is the same along and across */
    "        a = band(local.x, 0.0, form.x, direction) * band(local.y, -form.y, form.y, "
    "direction);\n"
    "    }\n"
    "    a = min(a, 1.0) * clip_coverage() * colour.a;\n"
    "    if (a <= 0.0) discard;\n"
    "    result = vec4(colour.rgb, a);\n"
    "}\n";

/* ------------------------------------------------------------------ drawer */

typedef struct DiskInstance {
    float x, y, radius, outline; ///< px
    uint8_t rgba[4];
} DiskInstance;

typedef struct SegmentInstance {
    float x0, y0, x1, y1; ///< px
    float half_width;     ///< px
    float round;          ///< 1: round caps, 0: butt
    uint8_t rgba[4];
} SegmentInstance;

typedef struct ChainOrder {
    double force; ///< N
    int index;    ///< contact
} ChainOrder;

struct RenderGl {
    GlContext context;
    GlApi gl;
    int current; ///< 1 after the first make-current
    GLuint disk_program, segment_program;
    GLint disk_viewport, disk_clip, disk_outline_colour, segment_viewport, segment_clip;
    GLuint disk_vao, segment_vao;
    GLuint corner_buffer, disk_buffer, segment_buffer;
    DiskInstance *disks;
    SegmentInstance *segments;
    ChainOrder *chains;
    int disk_capacity, segment_capacity, chain_capacity;
    char renderer[128];
};

static GLuint compile(RenderGl *r, GLenum kind, const char *body, char *err, size_t err_size)
{
    const char *parts[3] = {common_source, kind == GL_FRAGMENT_SHADER ? fragment_common_source : "",
                            body};
    GLuint shader = r->gl.CreateShader(kind);
    r->gl.ShaderSource(shader, 3, parts, NULL);
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

static GLuint link_program(RenderGl *r, const char *vertex, const char *fragment, char *err,
                           size_t err_size)
{
    GLuint vs = compile(r, GL_VERTEX_SHADER, vertex, err, err_size);
    if (!vs)
        return 0;
    GLuint fs = compile(r, GL_FRAGMENT_SHADER, fragment, err, err_size);
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
    return program;
}

static void instance_attribute(RenderGl *r, GLuint location, GLint size, GLenum type,
                               GLsizei stride, size_t offset)
{
    r->gl.EnableVertexAttribArray(location);
    r->gl.VertexAttribPointer(location, size, type, type == GL_UNSIGNED_BYTE ? GL_TRUE : GL_FALSE,
                              stride, (const void *)offset);
    r->gl.VertexAttribDivisor(location, 1);
}

/* Attribute 0: quad corners (a triangle strip) from the shared buffer at corner_offset bytes;
 * then the per-instance attributes. */
static void setup_vao(RenderGl *r, GLuint vao, GLuint instance_buffer, size_t corner_offset,
                      int segment)
{
    r->gl.BindVertexArray(vao);
    r->gl.BindBuffer(GL_ARRAY_BUFFER, r->corner_buffer);
    r->gl.EnableVertexAttribArray(0);
    r->gl.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float),
                              (const void *)corner_offset);
    r->gl.BindBuffer(GL_ARRAY_BUFFER, instance_buffer);
    if (!segment) {
        GLsizei stride = sizeof(DiskInstance);
        instance_attribute(r, 1, 4, GL_FLOAT, stride, offsetof(DiskInstance, x));
        instance_attribute(r, 2, 4, GL_UNSIGNED_BYTE, stride, offsetof(DiskInstance, rgba));
    } else {
        GLsizei stride = sizeof(SegmentInstance);
        instance_attribute(r, 1, 4, GL_FLOAT, stride, offsetof(SegmentInstance, x0));
        instance_attribute(r, 2, 2, GL_FLOAT, stride, offsetof(SegmentInstance, half_width));
        instance_attribute(r, 3, 4, GL_UNSIGNED_BYTE, stride, offsetof(SegmentInstance, rgba));
    }
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
    if (context_make_current(&r->context) != 0) {
        snprintf(err, err_size, "GL: cannot make the OSMesa context current");
        goto fail;
    }
    r->current = 1;
    if (api_load(&r->gl, err, err_size) != 0)
        goto fail;
    const GLubyte *renderer = r->gl.GetString(GL_RENDERER);
    snprintf(r->renderer, sizeof r->renderer, "%s", renderer ? (const char *)renderer : "?");

    r->disk_program = link_program(r, disk_vertex_source, disk_fragment_source, err, err_size);
    if (!r->disk_program)
        goto fail;
    r->segment_program =
        link_program(r, segment_vertex_source, segment_fragment_source, err, err_size);
    if (!r->segment_program)
        goto fail;
    r->disk_viewport = r->gl.GetUniformLocation(r->disk_program, "viewport");
    r->disk_clip = r->gl.GetUniformLocation(r->disk_program, "clip");
    r->disk_outline_colour = r->gl.GetUniformLocation(r->disk_program, "outline_colour");
    r->segment_viewport = r->gl.GetUniformLocation(r->segment_program, "viewport");
    r->segment_clip = r->gl.GetUniformLocation(r->segment_program, "clip");

    /* Quads as triangle strips: disks use (+-1, +-1), segments (0 or 1, +-1). */
    static const float corners[16] = {-1, -1, 1, -1, -1, 1, 1, 1, 0, -1, 1, -1, 0, 1, 1, 1};
    GLuint buffers[3];
    r->gl.GenBuffers(3, buffers);
    r->corner_buffer = buffers[0];
    r->disk_buffer = buffers[1];
    r->segment_buffer = buffers[2];
    GLuint vaos[2];
    r->gl.GenVertexArrays(2, vaos);
    r->disk_vao = vaos[0];
    r->segment_vao = vaos[1];
    r->gl.BindBuffer(GL_ARRAY_BUFFER, r->corner_buffer);
    r->gl.BufferData(GL_ARRAY_BUFFER, sizeof corners, corners, GL_STATIC_DRAW);
    setup_vao(r, r->disk_vao, r->disk_buffer, 0, 0);
    setup_vao(r, r->segment_vao, r->segment_buffer, 8 * sizeof(float), 1);
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
    if (r->current && r->gl.DeleteBuffers && context_make_current(&r->context) == 0) {
        GLuint buffers[3] = {r->corner_buffer, r->disk_buffer, r->segment_buffer};
        GLuint vaos[2] = {r->disk_vao, r->segment_vao};
        r->gl.DeleteBuffers(3, buffers);
        r->gl.DeleteVertexArrays(2, vaos);
        r->gl.DeleteProgram(r->disk_program);
        r->gl.DeleteProgram(r->segment_program);
    }
    context_destroy(&r->context);
    free(r->disks);
    free(r->segments);
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
    double lo, hi; ///< colour range
    double period; ///< periodic x length, m (0 = not periodic)
    float clip[4]; ///< x0, y0, x1, y1, px
} Layout;

static void add_disk(RenderGl *r, int *n, const Layout *l, const SimFrame *frame, int i,
                     double offset, uint32_t rgb)
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
}

/* Disks in frame order, with the copies a periodic frame shows across the seam. */
static int collect_disks(RenderGl *r, const SimFrame *frame, const Layout *l)
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

static SegmentInstance *add_segment(RenderGl *r, int *n, const Layout *l, double ax, double ay,
                                    double bx, double by, double width, int round, uint32_t rgb)
{
    SegmentInstance *s = &r->segments[(*n)++];
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
    return s;
}

static int compare_chains(const void *a, const void *b)
{
    const ChainOrder *p = a, *q = b;
    if (p->force != q->force)
        return p->force < q->force ? -1 : 1;
    return (p->index > q->index) - (p->index < q->index);
}

/* Orientation ticks, walls, force chains as segment instances, in Cairo's drawing order. */
static int collect_segments(RenderGl *r, const SimFrame *frame, const Layout *l, int counts[3])
{
    const RenderStyle *s = &l->style;
    const RenderView *v = &l->view;
    int ticks = s->orientation_tick && frame->angle ? 3 * frame->count : 0;
    int chains = s->force_chains ? 2 * frame->contact_count : 0;
    if (reserve((void **)&r->segments, &r->segment_capacity, ticks + frame->wall_count + chains,
                sizeof(SegmentInstance)) ||
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

static void draw_segments(RenderGl *r, const Layout *l, int first, int count)
{
    if (count <= 0)
        return;
    r->gl.UseProgram(r->segment_program);
    r->gl.Uniform2f(r->segment_viewport, (float)r->context.width, (float)r->context.height);
    r->gl.Uniform4f(r->segment_clip, l->clip[0], l->clip[1], l->clip[2], l->clip[3]);
    r->gl.BindVertexArray(r->segment_vao);
    r->gl.BindBuffer(GL_ARRAY_BUFFER, r->segment_buffer);
    r->gl.BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)count * (GLsizeiptr)sizeof(SegmentInstance),
                     r->segments + first, GL_STREAM_DRAW);
    r->gl.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, count);
}

int render_gl_frame(RenderGl *r, const SimFrame *frame, const RenderStyle *style, RenderImage *out,
                    char *err, size_t err_size)
{
    if (!r || !frame || !style || !out) {
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
    int disks = collect_disks(r, frame, &l);
    int counts[3] = {0, 0, 0};
    if (disks < 0 || collect_segments(r, frame, &l, counts) != 0) {
        snprintf(err, err_size, "GL: out of memory for %d grains", frame->count);
        return -1;
    }

    if (context_make_current(&r->context) != 0) {
        snprintf(err, err_size, "GL: cannot make the OSMesa context current");
        return -1;
    }
    r->gl.Viewport(0, 0, r->context.width, r->context.height);
    uint32_t bg = l.style.background_rgb;
    r->gl.ClearColor((float)((bg >> 16) & 255) / 255.0f, (float)((bg >> 8) & 255) / 255.0f,
                     (float)(bg & 255) / 255.0f, 1.0f);
    r->gl.Clear(GL_COLOR_BUFFER_BIT);
    /* Straight-alpha "over"; the destination stays opaque. */
    r->gl.Enable(GL_BLEND);
    r->gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    if (disks > 0) {
        r->gl.UseProgram(r->disk_program);
        r->gl.Uniform2f(r->disk_viewport, (float)r->context.width, (float)r->context.height);
        r->gl.Uniform4f(r->disk_clip, l.clip[0], l.clip[1], l.clip[2], l.clip[3]);
        uniform_rgb(r, r->disk_outline_colour, OUTLINE_RGB);
        r->gl.BindVertexArray(r->disk_vao);
        r->gl.BindBuffer(GL_ARRAY_BUFFER, r->disk_buffer);
        r->gl.BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)disks * (GLsizeiptr)sizeof(DiskInstance),
                         r->disks, GL_STREAM_DRAW);
        r->gl.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, disks);
    }
    draw_segments(r, &l, 0, counts[0]);                     /* orientation ticks */
    draw_segments(r, &l, counts[0], counts[1]);             /* walls */
    draw_segments(r, &l, counts[0] + counts[1], counts[2]); /* force chains */
    r->gl.BindVertexArray(0);
    r->gl.Finish();
    context_finish(&r->context);
    GLenum error = r->gl.GetError();
    if (error != GL_NO_ERROR) {
        snprintf(err, err_size, "GL: drawing failed (GL error 0x%x on %s)", (unsigned)error,
                 r->renderer);
        return -1;
    }
    out->width = r->context.width;
    out->height = r->context.height;
    out->stride = 4 * r->context.width;
    out->format = RENDER_PIXEL_RGBA;
    out->pixels = r->context.pixels;
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
        rc = render_image_alloc(out, view.width, view.height, RENDER_PIXEL_RGBA);
    if (rc == 0)
        memcpy(out->pixels, view.pixels, (size_t)view.stride * (size_t)view.height);
    render_gl_destroy(r);
    return rc;
}
