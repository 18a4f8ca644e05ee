/* SPDX-License-Identifier: MIT */
/* render_raster.c: a figure read back as pixels for the image diff: a PNG as it is, the first page
 * of a PDF (poppler-glib) and an SVG (librsvg) drawn by Cairo on white at a fixed resolution, so
 * that `sablier diff` compares what a reader sees, not bytes that also hold metadata. Without
 * poppler-glib or librsvg at build time those formats are not readable (render_figure_read says
 * so and the caller compares bytes). */
#include "render/internal.h"
#include "render/render_cairo_util.h"

#include <cairo.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#ifdef SABLIER_HAVE_RASTER
#include <librsvg/rsvg.h>
#include <poppler.h>
#endif

int render_figure_readable(const char *path)
{
    if (render_has_extension(path, "png"))
        return 1;
#ifdef SABLIER_HAVE_RASTER
    return render_has_extension(path, "pdf") || render_has_extension(path, "svg");
#else
    return 0;
#endif
}

#ifdef SABLIER_HAVE_RASTER
typedef struct Raster {
    PopplerPage *page; /* one of the two */
    RsvgHandle *svg;
    double w_pt, h_pt, dpi;
    GError *error;
} Raster;

static void raster_draw(cairo_t *cr, void *context)
{
    Raster *r = context;
    cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
    cairo_paint(cr);
    cairo_scale(cr, r->dpi / 72.0, r->dpi / 72.0);
    if (r->page) {
        poppler_page_render(r->page, cr);
        return;
    }
    RsvgRectangle viewport = {0.0, 0.0, r->w_pt, r->h_pt};
    rsvg_handle_render_document(r->svg, cr, &viewport, &r->error);
}

/* The PDF's first page or the SVG into r (sizes in points); 0, or -1 with a message. */
static int raster_open(const char *path, Raster *r, char *err, size_t err_size)
{
    if (render_has_extension(path, "svg")) {
        r->svg = rsvg_handle_new_from_file(path, &r->error);
        double w = 0.0, h = 0.0;
        if (r->svg) {
            rsvg_handle_set_dpi(r->svg, 72.0); /* sizes in points */
            if (!rsvg_handle_get_intrinsic_size_in_pixels(r->svg, &w, &h))
                w = h = 0.0;
        }
        r->w_pt = w;
        r->h_pt = h;
    } else {
        gchar *data = NULL;
        gsize size = 0;
        if (g_file_get_contents(path, &data, &size, &r->error)) {
            GBytes *bytes = g_bytes_new_take(data, size);
            PopplerDocument *doc = poppler_document_new_from_bytes(bytes, NULL, &r->error);
            g_bytes_unref(bytes);
            if (doc && poppler_document_get_n_pages(doc) > 0)
                r->page = poppler_document_get_page(doc, 0);
            if (doc)
                g_object_unref(doc);
        }
        if (r->page)
            poppler_page_get_size(r->page, &r->w_pt, &r->h_pt);
    }
    if ((r->page || r->svg) && r->w_pt > 0.0 && r->h_pt > 0.0 && r->w_pt < 1e5 && r->h_pt < 1e5)
        return 0;
    render_set_err(err, err_size, "%s: cannot read: %s", path,
                   r->error ? r->error->message : "no page of a known size");
    return -1;
}

static void raster_close(Raster *r)
{
    if (r->page)
        g_object_unref(r->page);
    if (r->svg)
        g_object_unref(r->svg);
    if (r->error)
        g_error_free(r->error);
}
#endif

int render_figure_read(const char *path, double dpi, RenderImage *out, char *err, size_t err_size)
{
    memset(out, 0, sizeof *out);
    if (render_has_extension(path, "png"))
        return render_png_read(path, out, err, err_size) == 0 ? 0 : -1;
    if (!render_figure_readable(path)) {
        render_set_err(err, err_size,
                       "%s: built without poppler-glib and librsvg: no pixels of a %s", path,
                       render_has_extension(path, "pdf")   ? "PDF"
                       : render_has_extension(path, "svg") ? "SVG"
                                                           : "file");
        return 1;
    }
#ifdef SABLIER_HAVE_RASTER
    Raster r = {.dpi = dpi > 0.0 ? dpi : RENDER_RASTER_DPI};
    int rc = raster_open(path, &r, err, err_size);
    if (rc == 0) {
        int w = (int)ceil(r.w_pt * r.dpi / 72.0 - 1e-9),
            h = (int)ceil(r.h_pt * r.dpi / 72.0 - 1e-9);
        rc = render_cairo_image(w, h, raster_draw, &r, out, err, err_size);
        if (rc == 0 && r.error) {
            render_set_err(err, err_size, "%s: cannot draw: %s", path, r.error->message);
            render_image_free(out);
            rc = -1;
        }
    }
    raster_close(&r);
    return rc;
#else
    (void)dpi;
    return -1;
#endif
}
