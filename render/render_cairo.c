/* SPDX-License-Identifier: MIT */
/* render_cairo.c: the reference drawer. One frame becomes flat antialiased disks coloured through
 * a LUT, fixed grains and walls, force chains (strong network), velocity arrows and the
 * coarse-grained field, arch highlights with an inset, and annotations (colour bar, time stamp,
 * scale bar, title). Everything is drawn in pixel units; PDF/SVG scale pixels to points.
 *
 * Speed (anchors-render 2a): one new_path/arc/fill per disk, outlines as a dark disk under a
 * smaller coloured one (a stroke per disk costs 3x), the source colour set only when it changes,
 * batched paths for same-style strokes (ticks, arrows). */
#include "render_cairo_util.h"

#include "render/internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const uint32_t outline_rgb = 0x2a2a2a;
static const uint32_t wall_rgb = 0x3c3c3c;
static const uint32_t arrow_rgb = 0x161616;
static const uint32_t field_rgb = 0x0b3d91;
static const uint32_t text_rgb = 0x111111;

/* ---------------------------------------------------------------- the drawn scene */

/* What one frame's drawing needs, resolved once (not `Scene`: app/scene/scene.h has its own). */
typedef struct DrawScene {
    const SimFrame *frame;
    RenderStyle style; /* resolved */
    RenderView view;
    double lo, hi; /* colour range */
    int extend;    /* the colour bar's end triangles, RENDER_EXTEND_* bits */
    double chain_cut, chain_fmax;
    int *chains; /* selected contacts, weakest first */
    int chain_count;
    RenderField field;
    int has_field;
    double field_arrow_scale;   /* s; auto: the fastest node gets an arrow of 0.9 cell */
    double key_vmax, key_scale; /* the arrow key: fastest arrow, m/s; arrow length per speed, s */
    double key_ref, key_unit;   /* the key's speed (in key_unit m/s) */
    double key_len, arrow_cut;  /* the key's length; arrows shorter than arrow_cut go, pixels */
    int *arch_order;            /* arch grains sorted by (arch id, x) */
    int arch_count;
    double period;
    double *heads; /* arrow heads, 6 doubles per arrow (grain arrows or field arrows) */
} DrawScene;

/* Merge sort (stable, deterministic) with a context argument, which qsort lacks; no global state,
 * so two threads may draw two frames at once. */
static void sort_indices(int *v, int n, int *tmp, const DrawScene *sc,
                         int (*cmp)(const DrawScene *, int, int))
{
    if (n < 2)
        return;
    int h = n / 2;
    sort_indices(v, h, tmp, sc, cmp);
    sort_indices(v + h, n - h, tmp, sc, cmp);
    int i = 0, j = h, k = 0;
    while (i < h && j < n)
        tmp[k++] = cmp(sc, v[j], v[i]) < 0 ? v[j++] : v[i++];
    while (i < h)
        tmp[k++] = v[i++];
    while (j < n)
        tmp[k++] = v[j++];
    memcpy(v, tmp, (size_t)n * sizeof *v);
}

static int cmp_chain(const DrawScene *sc, int a, int b)
{
    double fa = sc->frame->contacts[a].normal_force, fb = sc->frame->contacts[b].normal_force;
    if (fa != fb)
        return fa < fb ? -1 : 1;
    return a < b ? -1 : a > b;
}

static int cmp_arch(const DrawScene *sc, int a, int b)
{
    const int *ids = sc->style.arch_ids;
    const double *x = sc->frame->x;
    if (ids[a] != ids[b])
        return ids[a] < ids[b] ? -1 : 1;
    if (x[a] != x[b])
        return x[a] < x[b] ? -1 : 1;
    return a < b ? -1 : a > b;
}

/* A field given on its own nodes (style->node_vx, node_vy) as a RenderField: non-finite nodes
 * are masked (packing 0), the others drawn as they are (packing 1). */
static int node_field(const RenderStyle *s, RenderField *out)
{
    size_t n = (size_t)s->node_nx * (size_t)s->node_ny;
    memset(out, 0, sizeof *out);
    out->vx = calloc(n, sizeof *out->vx);
    out->vy = calloc(n, sizeof *out->vy);
    out->packing = calloc(n, sizeof *out->packing);
    if (!out->vx || !out->vy || !out->packing) {
        render_field_free(out);
        return -1;
    }
    out->nx = s->node_nx;
    out->ny = s->node_ny;
    out->x0 = s->node_x0;
    out->y0 = s->node_y0;
    out->cell = s->node_cell;
    for (size_t k = 0; k < n; ++k)
        if (isfinite(s->node_vx[k]) && isfinite(s->node_vy[k])) {
            out->vx[k] = s->node_vx[k];
            out->vy[k] = s->node_vy[k];
            out->packing[k] = 1;
        }
    return 0;
}

static void draw_scene_free(DrawScene *sc)
{
    free(sc->chains);
    free(sc->arch_order);
    free(sc->heads);
    render_field_free(&sc->field);
}

/* The next round speed above r (1, 2, 5 x 10^k). */
static double round_above(double r)
{
    double decade = pow(10.0, floor(log10(r) + 1e-12)), m = r / decade;
    return (m < 1.5 ? 2.0 : m < 3.5 ? 5.0 : 10.0) * decade;
}

/* The reference (key) arrow: a round speed (m/s, or sqrt(g d) in reduced units) at most the
 * fastest arrow and 6 em long, but at least 5 mm at the figure's print size (style dpi) so that it
 * reads with its head; the arrows shorter than style arrow_min of it are left out. */
static void arrow_key_size(DrawScene *sc)
{
    const RenderView *v = &sc->view;
    double fs = v->font_size, px_per_speed = sc->key_scale * v->scale;
    if (!(sc->key_vmax > 0) || !(px_per_speed > 0))
        return;
    int reduced = sc->style.reduced_units && sc->frame->time_scale > 0 && v->mean_diameter > 0;
    sc->key_unit = reduced ? v->mean_diameter / sc->frame->time_scale : 1.0; /* sqrt(g d) */
    double ref = render_arrow_reference(fmin(sc->key_vmax, 6 * fs / px_per_speed) / sc->key_unit);
    double dpi = sc->style.dpi > 0 ? sc->style.dpi : 96.0, shortest = 5.0 / 25.4 * dpi;
    for (int k = 0; k < 64 && ref > 0 && ref * sc->key_unit * px_per_speed < shortest; ++k)
        ref = round_above(ref);
    sc->key_ref = ref;
    sc->key_len = ref * sc->key_unit * px_per_speed;
    double fraction = sc->style.arrow_min == 0 ? 0.1 : fmax(0.0, sc->style.arrow_min);
    sc->arrow_cut = fraction * sc->key_len;
}

static int draw_scene_init(DrawScene *sc, const SimFrame *frame, const RenderStyle *style)
{
    memset(sc, 0, sizeof *sc);
    sc->frame = frame;
    sc->style = render_style_resolve(frame, style);
    render_view_fit(frame, &sc->style, &sc->view);
    render_color_range(frame, &sc->style, &sc->lo, &sc->hi);
    sc->extend = render_color_extend(frame, &sc->style, sc->lo, sc->hi);
    sc->period = frame->periodic ? frame->domain_x1 - frame->domain_x0 : 0;
    int n = frame->count > frame->contact_count ? frame->count : frame->contact_count;
    int *tmp = malloc((size_t)(n > 0 ? n : 1) * sizeof *tmp);
    if (!tmp)
        return -1;
    if (sc->style.force_chains && frame->contact_count > 0) {
        sc->chain_cut = render_chain_cut(frame, &sc->style, &sc->chain_fmax);
        sc->chains = malloc((size_t)frame->contact_count * sizeof *sc->chains);
        if (!sc->chains) {
            free(tmp);
            return -1;
        }
        for (int c = 0; c < frame->contact_count; ++c) {
            double f = frame->contacts[c].normal_force;
            if (f > 0 && f > sc->chain_cut)
                sc->chains[sc->chain_count++] = c;
        }
        /* Weakest first, so strong chains are drawn on top. */
        sort_indices(sc->chains, sc->chain_count, tmp, sc, cmp_chain);
    }
    if (sc->style.arch_ids && frame->count > 0) {
        sc->arch_order = malloc((size_t)frame->count * sizeof *sc->arch_order);
        if (!sc->arch_order) {
            free(tmp);
            return -1;
        }
        for (int i = 0; i < frame->count; ++i)
            if (sc->style.arch_ids[i] >= 0)
                sc->arch_order[sc->arch_count++] = i;
        sort_indices(sc->arch_order, sc->arch_count, tmp, sc, cmp_arch);
    }
    free(tmp);
    if (sc->style.node_vx && sc->style.node_vy && sc->style.node_nx > 0 && sc->style.node_ny > 0 &&
        sc->style.node_cell > 0) {
        if (node_field(&sc->style, &sc->field) != 0)
            return -1;
        sc->has_field = 1;
    } else if (sc->style.velocity_field) {
        const RenderView *v = &sc->view;
        RenderFieldDef def = {
            .x0 = v->center_x - 0.5 * v->plot_w / v->scale,
            .x1 = v->center_x + 0.5 * v->plot_w / v->scale,
            .y0 = v->center_y - 0.5 * v->plot_h / v->scale,
            .y1 = v->center_y + 0.5 * v->plot_h / v->scale,
            .cell = sc->style.field_cell,
            .width = sc->style.field_width,
            .kernel = (RenderKernel)sc->style.field_kernel,
            .mass_power = 2,
        };
        sc->has_field = render_velocity_field(frame, &def, &sc->field) == 0;
    }
    if (sc->has_field) {
        sc->field_arrow_scale = style->arrow_scale;
        size_t nodes = (size_t)sc->field.nx * (size_t)sc->field.ny;
        for (size_t k = 0; k < nodes; ++k)
            if (sc->field.packing[k] >= 0.1)
                sc->key_vmax = fmax(sc->key_vmax, hypot(sc->field.vx[k], sc->field.vy[k]));
        if (!(sc->field_arrow_scale > 0))
            sc->field_arrow_scale = sc->key_vmax > 0 ? 0.9 * sc->field.cell / sc->key_vmax : 0;
        sc->key_scale = sc->field_arrow_scale;
    } else if (sc->style.velocity_arrows && frame->vx && frame->vy) {
        for (int i = 0; i < frame->count; ++i)
            if (!render_grain_fixed(frame, i))
                sc->key_vmax = fmax(sc->key_vmax, hypot(frame->vx[i], frame->vy[i]));
        sc->key_scale = sc->style.arrow_scale;
    }
    arrow_key_size(sc);
    /* The drawers return nothing: what they need is allocated here, where failing is reported. */
    size_t arrows = 0;
    if (sc->style.velocity_arrows && frame->vx && frame->vy && sc->style.arrow_scale > 0)
        arrows = (size_t)(frame->count > 0 ? frame->count : 1);
    if (sc->has_field && sc->field_arrow_scale > 0) {
        size_t nodes = (size_t)sc->field.nx * (size_t)sc->field.ny;
        arrows = nodes > arrows ? nodes : arrows;
    }
    if (arrows > 0) {
        sc->heads = malloc(arrows * 6 * sizeof *sc->heads);
        if (!sc->heads)
            return -1;
    }
    return 0;
}

/* ---------------------------------------------------------------- world layer */

/* x offsets (m) of the copies of a shape spanning [x - r, x + r] that a periodic frame shows. */
static int periodic_copies(const DrawScene *sc, double x, double r, double offsets[3])
{
    int n = 0;
    offsets[n++] = 0;
    if (sc->period > 0) {
        if (x - r < sc->frame->domain_x0)
            offsets[n++] = sc->period;
        if (x + r > sc->frame->domain_x1)
            offsets[n++] = -sc->period;
    }
    return n;
}

static void clip_world(cairo_t *cr, const DrawScene *sc, const RenderView *v)
{
    double x0 = v->plot_x, x1 = v->plot_x + v->plot_w;
    if (sc->period > 0) {
        double px0, px1, py;
        render_view_to_pixel(v, sc->frame->domain_x0, 0, &px0, &py);
        render_view_to_pixel(v, sc->frame->domain_x1, 0, &px1, &py);
        x0 = fmax(x0, px0);
        x1 = fmin(x1, px1);
    }
    cairo_rectangle(cr, x0, v->plot_y, fmax(0, x1 - x0), v->plot_h);
    cairo_clip(cr);
}

/* The part of the plot the surface shows, a pixel wider on each side: a band of a movie frame
 * (render_cairo_draw_split) is a surface over some rows, and a shape wholly outside them leaves no
 * mark there (antialiasing reaches no further than the shape's own extent), so its path need not be
 * built. */
static void visible_box(cairo_t *cr, const RenderView *v, double box[4])
{
    double x0, y0, x1, y1;
    cairo_clip_extents(cr, &x0, &y0, &x1, &y1);
    if (!(x1 > x0 && y1 > y0)) { /* an unbounded surface without a clip */
        x0 = y0 = -INFINITY;
        x1 = y1 = INFINITY;
    }
    box[0] = fmax(v->plot_x, x0 - 1);
    box[1] = fmin(v->plot_x + v->plot_w, x1 + 1);
    box[2] = fmax(v->plot_y, y0 - 1);
    box[3] = fmin(v->plot_y + v->plot_h, y1 + 1);
}

/* How draw_disks fills a disk: with its own coverage straight into the pixels (render_disks.c,
 * several times faster than Cairo's path of a small disk) where the drawing goes to an image
 * surface without a group, under a whole-pixel translation, and the disk lies inside the clip,
 * one rectangle; else with Cairo (PDF, SVG, scaled layouts, disks cut by the plot's edge). */
typedef struct DiskPen {
    cairo_t *cr;
    RenderDiskTarget target;
    double clip[4];   /* x0, x1, y0, y1, user pixels; +-infinity where only the surface's edge is */
    int direct;       /* the target may be drawn to */
    int dirty;        /* pixels written since Cairo last drew */
    uint32_t current; /* Cairo's source colour */
} DiskPen;

/* The clip's rectangle, with the sides on the surface's own edges (whole pixels, which the disk
 * filler keeps to itself) opened: a band of a movie frame then decides as the whole image does. */
static int clip_rectangle(cairo_t *cr, const RenderDiskTarget *t, double clip[4])
{
    cairo_rectangle_list_t *list = cairo_copy_clip_rectangle_list(cr);
    const int ok = list->status == CAIRO_STATUS_SUCCESS && list->num_rectangles == 1;
    if (ok) {
        const cairo_rectangle_t *c = &list->rectangles[0];
        const double x0 = c->x + t->offset_x, y0 = c->y + t->offset_y;
        clip[0] = x0 <= 0 ? -HUGE_VAL : c->x;
        clip[1] = x0 + c->width >= t->width ? HUGE_VAL : c->x + c->width;
        clip[2] = y0 <= 0 ? -HUGE_VAL : c->y;
        clip[3] = y0 + c->height >= t->height ? HUGE_VAL : c->y + c->height;
    }
    cairo_rectangle_list_destroy(list);
    return ok;
}

static DiskPen disk_pen(cairo_t *cr)
{
    DiskPen pen = {.cr = cr, .current = 0xffffffffu};
    cairo_surface_t *s = cairo_get_group_target(cr);
    double dx, dy;
    cairo_surface_get_device_offset(s, &dx, &dy);
    cairo_matrix_t m;
    cairo_get_matrix(cr, &m);
    if (s != cairo_get_target(cr) || cairo_surface_get_type(s) != CAIRO_SURFACE_TYPE_IMAGE ||
        dx != 0 || dy != 0 || m.xx != 1 || m.yy != 1 || m.xy != 0 || m.yx != 0 ||
        m.x0 != floor(m.x0) || m.y0 != floor(m.y0) || fabs(m.x0) > 1e6 || fabs(m.y0) > 1e6)
        return pen;
    const cairo_format_t format = cairo_image_surface_get_format(s);
    if (format != CAIRO_FORMAT_ARGB32 && format != CAIRO_FORMAT_RGB24)
        return pen;
    cairo_surface_flush(s);
    pen.target = (RenderDiskTarget){cairo_image_surface_get_data(s),
                                    cairo_image_surface_get_width(s),
                                    cairo_image_surface_get_height(s),
                                    cairo_image_surface_get_stride(s),
                                    (int)m.x0,
                                    (int)m.y0};
    pen.direct = pen.target.data != NULL && clip_rectangle(cr, &pen.target, pen.clip) &&
                 !getenv("SABLIER_CAIRO_DISKS");
    return pen;
}

/* The shape with box [x0, x1] x [y0, y1] (user pixels) may go straight into the pixels. */
static int pen_inside(const DiskPen *pen, double x0, double x1, double y0, double y1)
{
    return pen->direct && x0 >= pen->clip[0] && x1 <= pen->clip[1] && y0 >= pen->clip[2] &&
           y1 <= pen->clip[3];
}

/* Before the filler writes pixels: Cairo's drawing so far is in them. */
static void pen_to_pixels(DiskPen *pen)
{
    if (!pen->dirty)
        cairo_surface_flush(cairo_get_target(pen->cr));
    pen->dirty = 1;
}

/* Before Cairo draws: it reads what the filler wrote. */
static void pen_to_cairo(DiskPen *pen)
{
    if (pen->dirty)
        cairo_surface_mark_dirty(cairo_get_target(pen->cr));
    pen->dirty = 0;
}

static void pen_fill(DiskPen *pen, double px, double py, double r, uint32_t rgb)
{
    if (pen_inside(pen, px - r, px + r, py - r, py + r)) {
        pen_to_pixels(pen);
        render_disk_fill(&pen->target, px, py, r, rgb);
        return;
    }
    pen_to_cairo(pen);
    if (pen->current != rgb)
        render_set_rgb(pen->cr, pen->current = rgb);
    cairo_new_path(pen->cr);
    cairo_arc(pen->cr, px, py, r, 0, 2 * SIM_PI);
    cairo_fill(pen->cr);
}

static void pen_done(DiskPen *pen)
{
    pen_to_cairo(pen);
}

static void draw_disks(cairo_t *cr, const DrawScene *sc, const RenderView *v)
{
    const SimFrame *f = sc->frame;
    const RenderStyle *s = &sc->style;
    DiskPen pen = disk_pen(cr);
    double box[4];
    visible_box(cr, v, box);
    const double xmin = box[0], xmax = box[1], ymin = box[2], ymax = box[3];
    for (int i = 0; i < f->count; ++i) {
        uint32_t rgb = render_grain_rgb(f, s, i, sc->lo, sc->hi);
        double r = f->radius[i] * v->scale;
        double offsets[3];
        int copies = periodic_copies(sc, f->x[i], f->radius[i], offsets);
        for (int k = 0; k < copies; ++k) {
            double px, py;
            render_view_to_pixel(v, f->x[i] + offsets[k], f->y[i], &px, &py);
            if (px + r < xmin || px - r > xmax || py + r < ymin || py - r > ymax)
                continue;
            double inner = r;
            if ((s->outline || render_grain_fixed(f, i)) && r >= 1.5) {
                pen_fill(&pen, px, py, r, outline_rgb);
                inner = r - fmin(1.5, fmax(0.6, 0.07 * r));
            }
            pen_fill(&pen, px, py, inner, rgb);
        }
    }
    pen_done(&pen);
}

static void draw_ticks(cairo_t *cr, const DrawScene *sc, const RenderView *v)
{
    const SimFrame *f = sc->frame;
    if (!sc->style.orientation_tick || !f->angle)
        return;
    double width = fmin(2.5, fmax(0.8, 0.12 * sc->view.mean_diameter * 0.5 * v->scale));
    cairo_new_path(cr);
    for (int i = 0; i < f->count; ++i) {
        double r = f->radius[i] * v->scale;
        if (r < 2)
            continue;
        double offsets[3];
        int copies = periodic_copies(sc, f->x[i], f->radius[i], offsets);
        for (int k = 0; k < copies; ++k) {
            double px, py;
            render_view_to_pixel(v, f->x[i] + offsets[k], f->y[i], &px, &py);
            double len = r - fmin(1.5, fmax(0.6, 0.07 * r));
            cairo_move_to(cr, px, py);
            /* Counter-clockwise angle in a y-down pixel frame. */
            cairo_line_to(cr, px + len * cos(f->angle[i]), py - len * sin(f->angle[i]));
        }
    }
    render_set_rgb(cr, outline_rgb);
    cairo_set_line_width(cr, width);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
    cairo_stroke(cr);
}

static void draw_walls(cairo_t *cr, const DrawScene *sc, const RenderView *v)
{
    const SimFrame *f = sc->frame;
    if (f->wall_count <= 0 || !f->walls)
        return;
    cairo_new_path(cr);
    for (int k = 0; k < f->wall_count; ++k) {
        double ax, ay, bx, by;
        const SimWall *w = &f->walls[k];
        if (w->shape == SIM_WALL_ARC) { /* y points down in pixels: angles turn the other way */
            render_view_to_pixel(v, w->center_x, w->center_y, &ax, &ay);
            cairo_new_sub_path(cr);
            cairo_arc_negative(cr, ax, ay, w->radius * v->scale, -w->angle0, -w->angle1);
            continue;
        }
        render_view_to_pixel(v, f->walls[k].x0, f->walls[k].y0, &ax, &ay);
        render_view_to_pixel(v, f->walls[k].x1, f->walls[k].y1, &bx, &by);
        cairo_move_to(cr, ax, ay);
        cairo_line_to(cr, bx, by);
    }
    render_set_rgb(cr, wall_rgb);
    cairo_set_line_width(cr, fmax(3.0, 0.3 * sc->view.mean_diameter * v->scale));
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    cairo_stroke(cr);
}

static void draw_chains(cairo_t *cr, const DrawScene *sc, const RenderView *v)
{
    const SimFrame *f = sc->frame;
    /* Widths are scaled with the view so the inset magnifies chains like the grains. */
    double zoom = v->scale / sc->view.scale;
    double box[4];
    visible_box(cr, v, box);
    DiskPen pen = disk_pen(cr);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    for (int k = 0; k < sc->chain_count; ++k) {
        const SimContact *c = &f->contacts[sc->chains[k]];
        if (c->i < 0 || c->i >= f->count || c->j >= f->count)
            continue;
        double t = sc->chain_fmax > 0 ? fmin(1.0, c->normal_force / sc->chain_fmax) : 1.0;
        double ax = f->x[c->i], ay = f->y[c->i], bx, by;
        if (c->j >= 0) {
            bx = f->x[c->j];
            by = f->y[c->j];
        } else { /* wall contact: to the contact point */
            bx = c->x;
            by = c->y;
        }
        double dx = bx - ax;
        if (sc->period > 0) /* minimum image across the seam */
            dx -= sc->period * floor(dx / sc->period + 0.5);
        const double width = fmax(0.8, sc->style.chain_width_max * t) * zoom;
        double px, py, qx, qy;
        render_view_to_pixel(v, ax, ay, &px, &py);
        render_view_to_pixel(v, ax + dx, by, &qx, &qy);
        const double reach = 0.5 * width; /* the round caps' and the sides' reach */
        const double x0 = fmin(px, qx) - reach, x1 = fmax(px, qx) + reach;
        const double y0 = fmin(py, qy) - reach, y1 = fmax(py, qy) + reach;
        if (sc->period <= 0 && (y1 < box[2] || y0 > box[3] || x1 < box[0] || x0 > box[1]))
            continue;
        /* Chains use the upper 65 % of the map: the pale end would vanish on light grains. */
        const uint32_t rgb = render_colormap_rgb(RENDER_CMAP_YELLOW_RED, 0.35 + 0.65 * t);
        const int seam = sc->period > 0 && (ax + dx < f->domain_x0 || ax + dx > f->domain_x1);
        if (!seam && pen_inside(&pen, x0, x1, y0, y1)) {
            pen_to_pixels(&pen);
            render_capsule_fill(&pen.target, px, py, qx, qy, reach, rgb);
            continue;
        }
        pen_to_cairo(&pen);
        render_set_rgb(cr, rgb);
        cairo_set_line_width(cr, width);
        cairo_move_to(cr, px, py);
        cairo_line_to(cr, qx, qy);
        if (seam) { /* the other half, seen from the partner's side of the seam */
            double rx, ry, sx, sy;
            render_view_to_pixel(v, bx, by, &rx, &ry);
            render_view_to_pixel(v, bx - dx, ay, &sx, &sy);
            cairo_move_to(cr, rx, ry);
            cairo_line_to(cr, sx, sy);
        }
        cairo_stroke(cr);
    }
    pen_done(&pen);
}

/* Adds an arrow from (x, y) along (dx, dy) pixels: shaft into `cr`'s path, head into `heads`. */
static void arrow_path(cairo_t *cr, double x, double y, double dx, double dy, double lw,
                       double *heads, int *head_count)
{
    double len = hypot(dx, dy);
    double ux = dx / len, uy = dy / len;
    double h = fmin(0.4 * len, fmax(3.0, 3.0 * lw));
    cairo_move_to(cr, x, y);
    cairo_line_to(cr, x + dx - ux * h * 0.8, y + dy - uy * h * 0.8);
    double *p = heads + 6 * (*head_count)++;
    p[0] = x + dx;
    p[1] = y + dy;
    p[2] = x + dx - ux * h - uy * 0.45 * h;
    p[3] = y + dy - uy * h + ux * 0.45 * h;
    p[4] = x + dx - ux * h + uy * 0.45 * h;
    p[5] = y + dy - uy * h - ux * 0.45 * h;
}

static void stroke_arrows(cairo_t *cr, const double *heads, int n, double lw, uint32_t rgb,
                          int halo)
{
    /* The shafts are the current path. A white halo keeps arrows readable on dark grains. */
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_MITER);
    if (halo) {
        cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
        cairo_set_line_width(cr, lw + 2);
        cairo_stroke_preserve(cr);
    }
    render_set_rgb(cr, rgb);
    cairo_set_line_width(cr, lw);
    cairo_stroke(cr);
    for (int k = 0; k < n; ++k) {
        const double *p = heads + 6 * k;
        cairo_move_to(cr, p[0], p[1]);
        cairo_line_to(cr, p[2], p[3]);
        cairo_line_to(cr, p[4], p[5]);
        cairo_close_path(cr);
    }
    if (halo) {
        cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
        cairo_set_line_width(cr, 2);
        cairo_stroke_preserve(cr);
        render_set_rgb(cr, rgb);
    }
    cairo_fill(cr);
}

static void draw_grain_arrows(cairo_t *cr, const DrawScene *sc, const RenderView *v)
{
    const SimFrame *f = sc->frame;
    if (!sc->style.velocity_arrows || !f->vx || !f->vy || !(sc->style.arrow_scale > 0))
        return;
    double *heads = sc->heads;
    int n = 0;
    double lw = fmin(2.0, fmax(0.8, 0.08 * sc->view.mean_diameter * v->scale));
    cairo_new_path(cr);
    for (int i = 0; i < f->count; ++i) {
        if (render_grain_fixed(f, i))
            continue;
        double dx = sc->style.arrow_scale * f->vx[i] * v->scale;
        double dy = -sc->style.arrow_scale * f->vy[i] * v->scale;
        if (hypot(dx, dy) < fmax(1.0, sc->arrow_cut))
            continue;
        double px, py;
        render_view_to_pixel(v, f->x[i], f->y[i], &px, &py);
        arrow_path(cr, px, py, dx, dy, lw, heads, &n);
    }
    stroke_arrows(cr, heads, n, lw, arrow_rgb, 0);
}

static void draw_field(cairo_t *cr, const DrawScene *sc, const RenderView *v)
{
    const RenderField *fd = &sc->field;
    double scale = sc->field_arrow_scale;
    if (!sc->has_field || !(scale > 0))
        return;
    double *heads = sc->heads;
    int n = 0;
    double lw = fmin(2.5, fmax(1.0, 0.1 * sc->view.mean_diameter * v->scale));
    cairo_new_path(cr);
    for (int j = 0; j < fd->ny; ++j) {
        for (int i = 0; i < fd->nx; ++i) {
            size_t k = (size_t)j * (size_t)fd->nx + (size_t)i;
            /* Mask nearly empty nodes where V = j / rho is ill-defined (anchors-render 1.7). */
            if (fd->packing[k] < 0.1)
                continue;
            double dx = scale * fd->vx[k] * v->scale;
            double dy = -scale * fd->vy[k] * v->scale;
            if (hypot(dx, dy) < fmax(1.0, sc->arrow_cut))
                continue;
            double px, py;
            render_view_to_pixel(v, fd->x0 + (i + 0.5) * fd->cell, fd->y0 + (j + 0.5) * fd->cell,
                                 &px, &py);
            /* Centred on the node. */
            arrow_path(cr, px - 0.5 * dx, py - 0.5 * dy, dx, dy, lw, heads, &n);
            if (sc->style.field_color) { /* one colour per arrow: its speed on the colour map */
                double t = sc->key_vmax > 0 ? hypot(fd->vx[k], fd->vy[k]) / sc->key_vmax : 0;
                stroke_arrows(cr, heads, n, lw, render_colormap_rgb(sc->style.colormap, t), 1);
                n = 0;
            }
        }
    }
    stroke_arrows(cr, heads, n, lw, field_rgb, 1);
}

static void draw_arches(cairo_t *cr, const DrawScene *sc, const RenderView *v)
{
    const SimFrame *f = sc->frame;
    if (sc->arch_count == 0)
        return;
    double ring = fmin(5.0, fmax(2.0, 0.12 * sc->view.mean_diameter * v->scale));
    const int *ids = sc->style.arch_ids;
    for (int pass = 0; pass < 2; ++pass) {
        /* Pass 0: white halos under everything; pass 1: the highlight colour. */
        if (pass == 0)
            cairo_set_source_rgb(cr, 1, 1, 1);
        else
            render_set_rgb(cr, sc->style.arch_rgb);
        cairo_new_path(cr);
        for (int k = 0; k < sc->arch_count; ++k) {
            int i = sc->arch_order[k];
            double px, py, r = f->radius[i] * v->scale;
            render_view_to_pixel(v, f->x[i], f->y[i], &px, &py);
            cairo_new_sub_path(cr);
            cairo_arc(cr, px, py, fmax(1.0, r - 0.5 * ring), 0, 2 * SIM_PI);
        }
        cairo_set_line_width(cr, pass == 0 ? ring + 2 : ring);
        cairo_stroke(cr);
        /* Polyline through the centres of each arch, in x order. */
        cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
        cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
        for (int k = 0; k < sc->arch_count; ++k) {
            int i = sc->arch_order[k];
            double px, py;
            render_view_to_pixel(v, f->x[i], f->y[i], &px, &py);
            if (k == 0 || ids[sc->arch_order[k - 1]] != ids[i])
                cairo_move_to(cr, px, py);
            else
                cairo_line_to(cr, px, py);
        }
        cairo_set_line_width(cr, pass == 0 ? 0.6 * ring + 2 : 0.6 * ring);
        cairo_stroke(cr);
        for (int k = 0; k < sc->arch_count; ++k) {
            double px, py;
            render_view_to_pixel(v, f->x[sc->arch_order[k]], f->y[sc->arch_order[k]], &px, &py);
            cairo_new_sub_path(cr);
            cairo_arc(cr, px, py, pass == 0 ? 0.9 * ring + 1 : 0.9 * ring, 0, 2 * SIM_PI);
        }
        cairo_fill(cr);
    }
}

static void draw_world(cairo_t *cr, const DrawScene *sc, const RenderView *v)
{
    cairo_save(cr);
    clip_world(cr, sc, v);
    draw_disks(cr, sc, v);
    draw_ticks(cr, sc, v);
    draw_walls(cr, sc, v);
    draw_chains(cr, sc, v);
    draw_field(cr, sc, v);
    draw_grain_arrows(cr, sc, v);
    draw_arches(cr, sc, v);
    cairo_restore(cr);
}

/* Zoomed copy of the arches' neighbourhood in the right margin, beside the plot. */
static void draw_inset(cairo_t *cr, const DrawScene *sc)
{
    const SimFrame *f = sc->frame;
    if (!sc->style.arch_inset || sc->arch_count == 0)
        return;
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (int k = 0; k < sc->arch_count; ++k) {
        int i = sc->arch_order[k];
        x0 = fmin(x0, f->x[i] - f->radius[i]);
        x1 = fmax(x1, f->x[i] + f->radius[i]);
        y0 = fmin(y0, f->y[i] - f->radius[i]);
        y1 = fmax(y1, f->y[i] + f->radius[i]);
    }
    double pad = sc->view.mean_diameter;
    x0 -= pad;
    x1 += pad;
    y0 -= pad;
    y1 += pad;
    const RenderView *mv = &sc->view;
    /* In its own column at the right edge (render_view_fit reserves it), never over the grains. */
    double gap = 0.6 * mv->font_size;
    double iw = 0.3 * sc->style.width - gap, ih = iw * (y1 - y0) / (x1 - x0);
    if (ih > mv->plot_h) {
        ih = mv->plot_h;
        iw = ih * (x1 - x0) / (y1 - y0);
    }
    RenderView inset = *mv;
    inset.plot_x = sc->style.width - gap - iw;
    inset.plot_y = mv->plot_y;
    inset.plot_w = iw;
    inset.plot_h = ih;
    inset.scale = iw / (x1 - x0);
    inset.center_x = 0.5 * (x0 + x1);
    inset.center_y = 0.5 * (y0 + y1);
    if (inset.scale <= mv->scale)
        return; /* no magnification to show */
    /* Mark the zoomed region in the main view. */
    double ax, ay, bx, by;
    render_view_to_pixel(mv, x0, y1, &ax, &ay);
    render_view_to_pixel(mv, x1, y0, &bx, &by);
    cairo_save(cr);
    cairo_rectangle(cr, mv->plot_x, mv->plot_y, mv->plot_w, mv->plot_h);
    cairo_clip(cr);
    render_set_rgb(cr, text_rgb);
    cairo_set_line_width(cr, 1.2);
    cairo_rectangle(cr, ax, ay, bx - ax, by - ay);
    cairo_stroke(cr);
    cairo_restore(cr);

    render_set_rgb(cr, sc->style.background_rgb);
    cairo_rectangle(cr, inset.plot_x, inset.plot_y, iw, ih);
    cairo_fill(cr);
    draw_world(cr, sc, &inset);
    render_set_rgb(cr, text_rgb);
    cairo_set_line_width(cr, 1.5);
    cairo_rectangle(cr, inset.plot_x, inset.plot_y, iw, ih);
    cairo_stroke(cr);
    char label[32];
    snprintf(label, sizeof label, "\xc3\x97%.3g", inset.scale / mv->scale);
    render_text_font(cr, 0.8 * mv->font_size, 0);
    render_text_draw(cr, inset.plot_x + 0.4 * mv->font_size,
                     inset.plot_y + ih - 0.4 * mv->font_size, label, 0, 1);
}

/* ---------------------------------------------------------------- annotations */

static void default_label(const RenderStyle *s, const char **label, const char **unit)
{
    *label = s->colorbar_label;
    *unit = s->colorbar_unit;
    if (!*label)
        *label = s->color_by == RENDER_COLOR_FORCE   ? "contact force"
                 : s->color_by == RENDER_COLOR_SPEED ? "speed"
                                                     : "species";
    if (!*unit)
        *unit = s->color_by == RENDER_COLOR_FORCE   ? "N"
                : s->color_by == RENDER_COLOR_SPEED ? "m/s"
                                                    : "";
}

/* Species legend: a disk of each species' colour and its name, right of the plot. */
static void draw_legend(cairo_t *cr, const DrawScene *sc, double x, const char *title)
{
    const RenderView *v = &sc->view;
    double fs = v->font_size;
    double y = v->plot_y + 0.5 * fs;
    render_set_rgb(cr, text_rgb);
    render_text_draw(cr, x, y, title, 0, 0);
    for (int k = 0, top = render_legend_top(sc->frame); k <= top; ++k) {
        double cy = y + (k + 1.6) * 1.6 * fs;
        render_set_rgb(cr, outline_rgb);
        cairo_arc(cr, x + 0.5 * fs, cy, 0.5 * fs, 0, 2 * SIM_PI);
        cairo_fill(cr);
        render_set_rgb(cr, render_species_rgb(k));
        cairo_arc(cr, x + 0.5 * fs, cy, 0.5 * fs - 1, 0, 2 * SIM_PI);
        cairo_fill(cr);
        char text[96];
        render_species_label(&sc->style, k, text, sizeof text);
        render_set_rgb(cr, text_rgb);
        render_text_draw(cr, x + 1.5 * fs, cy, text, 0, 0.5);
    }
}

/* At most five tick intervals on a colour bar `h` pixels long, and at least two em between
 * ticks, so that their labels (1.16 em tall) keep a gap on a short bar (a single-column frame). */
static int colorbar_intervals(double h, double fs)
{
    return (int)fmax(1.0, fmin(5.0, floor(h / (2.0 * fs))));
}

/* Continuous colour bar right of the plot: ticks at round values, one "x10^e" offset above
 * the bar when the values need it, the quantity and its unit along the bar. */
static void draw_colorbar(cairo_t *cr, const DrawScene *sc)
{
    const RenderView *v = &sc->view;
    const RenderStyle *s = &sc->style;
    int kind = render_colorbar_kind(s);
    if (!kind)
        return;
    double fs = v->font_size;
    const char *label, *unit;
    default_label(s, &label, &unit);
    char title[160];
    if (unit && *unit)
        snprintf(title, sizeof title, "%s (%s)", label, unit);
    else
        snprintf(title, sizeof title, "%s", label);
    double x = round(v->plot_x + v->plot_w + 1.2 * fs);
    render_text_font(cr, fs, 0);
    if (kind == 2) {
        draw_legend(cr, sc, x, title);
        return;
    }
    double w = round(1.1 * fs);
    double h = round(fmax(2 * fs, v->plot_h - 2.4 * fs));
    double top = round(v->plot_y + v->plot_h - h), outer = top;
    /* End triangles (matplotlib's extend = "max"/"min"): the range's end colour beyond it. */
    double up = sc->extend & RENDER_EXTEND_MAX ? w : 0,
           down = sc->extend & RENDER_EXTEND_MIN ? w : 0;
    top += up;
    h -= up + down;
    uint8_t lut[256][3];
    render_colormap_lut(s->colormap, lut);
    for (int row = 0; row < (int)h; ++row) {
        double t = 1.0 - (row + 0.5) / h;
        const uint8_t *c = lut[(int)floor(t * 255.0 + 0.5)];
        cairo_set_source_rgb(cr, c[0] / 255.0, c[1] / 255.0, c[2] / 255.0);
        cairo_rectangle(cr, x, top + row, w, 1);
        cairo_fill(cr);
    }
    render_set_rgb(cr, text_rgb);
    cairo_set_line_width(cr, 1);
    cairo_rectangle(cr, x + 0.5, top + 0.5, w - 1, h - 1);
    cairo_stroke(cr);
    for (int end = 0; end < 2; ++end) {
        double len = end ? down : up, base = end ? top + h - 0.5 : top + 0.5;
        if (!(len > 0))
            continue;
        const uint8_t *c = lut[end ? 0 : 255];
        cairo_move_to(cr, x + 0.5, base);
        cairo_line_to(cr, x + 0.5 * w, end ? base + len : base - len);
        cairo_line_to(cr, x + w - 0.5, base);
        cairo_close_path(cr);
        cairo_set_source_rgb(cr, c[0] / 255.0, c[1] / 255.0, c[2] / 255.0);
        cairo_fill_preserve(cr);
        render_set_rgb(cr, text_rgb);
        cairo_stroke(cr);
    }
    /* the ticks at round values of the bar's unit (reduced units: m g or sqrt(g d)) */
    double scale = s->color_by == RENDER_COLOR_FORCE   ? s->force_unit
                   : s->color_by == RENDER_COLOR_SPEED ? s->speed_unit
                                                       : 0.0;
    if (!(scale > 0.0) || !isfinite(scale))
        scale = 1.0;
    double ticks[16], lo = sc->lo / scale, hi = sc->hi / scale;
    int n = render_axis_ticks(lo, hi, 0, colorbar_intervals(h, fs), ticks, 16);
    int e = render_tick_exponent(ticks, n);
    double factor = pow(10, -e);
    double step = (n > 1 ? ticks[1] - ticks[0] : hi - lo) * factor;
    double widest = 0;
    for (int k = 0; k < n; ++k) {
        double y = top + h - (ticks[k] - lo) / (hi - lo) * h;
        cairo_move_to(cr, x + w, y);
        cairo_line_to(cr, x + w + 0.35 * fs, y);
        cairo_stroke(cr);
        char text[32];
        render_format_tick(ticks[k] * factor, step, 0, text, sizeof text);
        widest = fmax(widest, render_text_draw(cr, x + w + 0.55 * fs, y, text, 0, 0.5));
    }
    if (e != 0) {
        char offset[48];
        render_exponent_text(e, offset, sizeof offset);
        render_text_draw(cr, x, outer - 1.0 * fs, offset, 0, 1);
    }
    /* Rotated label along the bar. */
    cairo_save(cr);
    cairo_translate(cr, x + w + 0.9 * fs + widest, top + 0.5 * h);
    cairo_rotate(cr, -0.5 * SIM_PI);
    render_text_draw(cr, 0, 0, title, 0.5, 0);
    cairo_restore(cr);
}

/* One axis of the frame: ticks outward at round values of the axis unit (m, or d in reduced
 * units), labels, and the axis title with the unit (and a x10^e offset when needed). */
static void draw_axis(cairo_t *cr, const DrawScene *sc, int is_y)
{
    const RenderView *v = &sc->view;
    double fs = v->font_size, unit = render_axis_unit(&sc->style, v->mean_diameter);
    double half = 0.5 * (is_y ? v->plot_h : v->plot_w) / v->scale;
    double mid = is_y ? v->center_y : v->center_x;
    double lo = (mid - half) / unit, hi = (mid + half) / unit;
    int target = is_y ? 5 : (int)fmin(8, fmax(2, v->plot_w / (6 * fs)));
    double ticks[32];
    int n = render_axis_ticks(lo, hi, 0, target, ticks, 32);
    int e = render_tick_exponent(ticks, n);
    double factor = pow(10, -e), step = (n > 1 ? ticks[1] - ticks[0] : hi - lo) * factor;
    double tl = 0.35 * fs, widest = 0;
    double x0 = v->plot_x, y1 = v->plot_y + v->plot_h;
    for (int k = 0; k < n; ++k) {
        double px, py;
        render_view_to_pixel(v, is_y ? mid : ticks[k] * unit, is_y ? ticks[k] * unit : mid, &px,
                             &py);
        char text[40];
        render_format_tick(ticks[k] * factor, step, 0, text, sizeof text);
        if (is_y) {
            cairo_move_to(cr, x0, py);
            cairo_line_to(cr, x0 - tl, py);
            widest = fmax(widest, render_text_draw(cr, x0 - tl - 0.3 * fs, py, text, 1, 0.5));
        } else {
            cairo_move_to(cr, px, y1);
            cairo_line_to(cr, px, y1 + tl);
            render_text_draw(cr, px, y1 + tl + 0.3 * fs, text, 0.5, 0);
        }
        cairo_stroke(cr);
    }
    char offset[48] = "", label[96];
    if (e != 0)
        render_exponent_text(e, offset, sizeof offset);
    if ((sc->style.reduced_units && unit != 1.0) || sc->style.normalised_units)
        snprintf(label, sizeof label, "%s / %sd", is_y ? "y" : "x", offset);
    else
        snprintf(label, sizeof label, "%s (%s%sm)", is_y ? "y" : "x", offset, e ? " " : "");
    if (!is_y) {
        render_text_draw(cr, v->plot_x + 0.5 * v->plot_w, y1 + tl + 1.6 * fs, label, 0.5, 0);
        return;
    }
    cairo_save(cr);
    cairo_translate(cr, x0 - tl - 1.0 * fs - widest, v->plot_y + 0.5 * v->plot_h);
    cairo_rotate(cr, -0.5 * SIM_PI);
    render_text_draw(cr, 0, 0, label, 0.5, 1);
    cairo_restore(cr);
}

static void draw_axes(cairo_t *cr, const DrawScene *sc)
{
    if (!sc->style.axes)
        return;
    const RenderView *v = &sc->view;
    render_set_rgb(cr, text_rgb);
    cairo_set_line_width(cr, fmax(1.0, 0.08 * v->font_size));
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
    cairo_rectangle(cr, v->plot_x, v->plot_y, v->plot_w, v->plot_h);
    cairo_stroke(cr);
    render_text_font(cr, v->font_size, 0);
    draw_axis(cr, sc, 0);
    draw_axis(cr, sc, 1);
}

static void format_time(double t, char *buf, size_t size)
{
    if (t == 0 || fabs(t) >= 0.01)
        snprintf(buf, size, "%.4f", t);
    else
        snprintf(buf, size, "%.3e", t);
}

const char *render_time_label(const SimFrame *frame, const RenderStyle *style, char *buf,
                              size_t size)
{
    char t[32];
    if (style->normalised_units) { /* the scene's own time unit */
        snprintf(buf, size,
                 style->normalised_units == RENDER_UNITS_NORMALISED_G ? "t = %.2f \xe2\x88\x9a(d/g)"
                                                                      : "t = %.2f",
                 frame->time);
        return buf;
    }
    if (style->reduced_units && frame->time_scale > 0) {
        snprintf(buf, size, "t = %.2f \xe2\x88\x9a(d/g)", frame->time / frame->time_scale);
        return buf;
    }
    format_time(frame->time, t, sizeof t);
    if (frame->time_scale > 0)
        snprintf(buf, size, "t = %s s    t* = %.2f", t, frame->time / frame->time_scale);
    else
        snprintf(buf, size, "t = %s s", t);
    return buf;
}

/* Above the plot, left-aligned with it: in the top margin, never over grains. */
static void draw_time_stamp(cairo_t *cr, const DrawScene *sc)
{
    if (!sc->style.time_stamp)
        return;
    const RenderView *v = &sc->view;
    double fs = v->font_size;
    char text[96];
    render_time_label(sc->frame, &sc->style, text, sizeof text);
    render_text_font(cr, fs, 0);
    render_set_rgb(cr, text_rgb);
    render_text_draw(cr, v->plot_x, v->plot_y - 0.8 * fs, text, 0, 0.5);
}

static void format_length(double d, char *buf, size_t size)
{
    if (d >= 0.1)
        snprintf(buf, size, "%.3g m", d);
    else if (d >= 1e-4)
        snprintf(buf, size, "%.3g mm", d * 1e3);
    else
        snprintf(buf, size, "%.3g \xc2\xb5m", d * 1e6);
}

const char *render_scale_label(double diameters, double d, const RenderStyle *style, char *buf,
                               size_t size)
{
    char dtext[32];
    if (style->reduced_units || style->normalised_units) {
        snprintf(buf, size, "%g d", diameters);
        return buf;
    }
    format_length(d, dtext, sizeof dtext);
    snprintf(buf, size, "%g d   (d = %s)", diameters, dtext);
    return buf;
}

/* The row under the plot (below the axes' labels) that holds the scale bar and the arrow key. */
static double key_row_y(const DrawScene *sc)
{
    const RenderView *v = &sc->view;
    return v->plot_y + v->plot_h + render_axes_room(&sc->style, v->font_size) + 1.2 * v->font_size;
}

static void draw_scale_bar(cairo_t *cr, const DrawScene *sc)
{
    const RenderView *v = &sc->view;
    double d = v->mean_diameter;
    if (!sc->style.scale_bar || !(d > 0))
        return;
    static const double steps[] = {1, 2, 5, 10, 20, 50, 100, 200, 500, 1000};
    double k = 0;
    for (size_t s = 0; s < sizeof steps / sizeof steps[0]; ++s)
        if (steps[s] * d * v->scale <= 0.2 * v->plot_w)
            k = steps[s];
    if (k == 0)
        return;
    double fs = v->font_size, len = k * d * v->scale, y = key_row_y(sc);
    char text[96];
    render_scale_label(k, d, &sc->style, text, sizeof text);
    render_text_font(cr, fs, 0);
    render_set_rgb(cr, text_rgb);
    cairo_rectangle(cr, v->plot_x, y - 0.2 * fs, len, 0.4 * fs);
    cairo_fill(cr);
    render_text_draw(cr, v->plot_x + len + 0.6 * fs, y, text, 0, 0.5);
}

/* Reference arrow of the velocity field or arrows, right-aligned under the scale bar's row, at the
 * arrows' own scale (arrow_key_size). */
static void draw_arrow_key(cairo_t *cr, const DrawScene *sc)
{
    const RenderView *v = &sc->view;
    double fs = v->font_size, ref = sc->key_ref, len = sc->key_len, x1 = v->plot_x + v->plot_w;
    int reduced = sc->style.reduced_units && sc->frame->time_scale > 0 && v->mean_diameter > 0;
    const int normalised = sc->style.normalised_units; /* speeds as given */
    double y = key_row_y(sc) + (sc->style.scale_bar ? 1.6 * fs : 0.0);
    if (!(len > 1))
        return;
    render_set_rgb(cr, sc->has_field ? field_rgb : arrow_rgb);
    cairo_set_line_width(cr, fmax(1.0, 0.1 * fs));
    render_arrow(cr, x1 - len, y, len, 0, 0.6 * fs);
    char text[64];
    snprintf(text, sizeof text, "%g %s", ref,
             reduced || normalised == RENDER_UNITS_NORMALISED_G ? "\xe2\x88\x9a(gd)"
             : normalised                                       ? "d per time unit"
                                                                : "m/s");
    render_text_font(cr, fs, 0);
    render_set_rgb(cr, text_rgb);
    render_text_draw(cr, x1 - len - 0.5 * fs, y, text, 1, 0.5);
}

static void draw_title(cairo_t *cr, const DrawScene *sc)
{
    if (!sc->style.title)
        return;
    double fs = sc->view.font_size;
    render_text_font(cr, 1.15 * fs, 0);
    render_set_rgb(cr, text_rgb);
    render_text_draw(cr, 0.5 * sc->style.width, 0.6 * fs + 0.5 * fs, sc->style.title, 0.5, 0.5);
}

static void draw_scene(cairo_t *cr, void *context)
{
    const DrawScene *sc = context;
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_GOOD);
    render_set_rgb(cr, sc->style.background_rgb);
    cairo_rectangle(cr, 0, 0, sc->style.width, sc->style.height);
    cairo_fill(cr);
    draw_world(cr, sc, &sc->view);
    draw_inset(cr, sc);
    draw_axes(cr, sc);
    draw_time_stamp(cr, sc);
    draw_scale_bar(cr, sc);
    draw_arrow_key(cr, sc);
    draw_colorbar(cr, sc);
    draw_title(cr, sc);
}

/* Everything render_cairo_draw puts over the grain layer, in its order: velocity field, arrows
 * and arches (clipped to the plot), then the inset, time stamp, scale bar, colour bar, title. */
static void draw_overlay(cairo_t *cr, const DrawScene *sc)
{
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_GOOD);
    cairo_save(cr);
    clip_world(cr, sc, &sc->view);
    draw_field(cr, sc, &sc->view);
    draw_grain_arrows(cr, sc, &sc->view);
    draw_arches(cr, sc, &sc->view);
    cairo_restore(cr);
    draw_inset(cr, sc);
    draw_axes(cr, sc);
    draw_time_stamp(cr, sc);
    draw_scale_bar(cr, sc);
    draw_arrow_key(cr, sc);
    draw_colorbar(cr, sc);
    draw_title(cr, sc);
}

/* ---------------------------------------------------------------- public entry points */

/* Rows [y0, y1) of the scene into `out` (the whole style's size, BGRA): a surface over those rows
 * of its pixels, the scene moved up by y0 whole pixels. Cairo's coordinates are fixed point in
 * device space, so a whole-pixel move shifts every edge exactly and each pixel gets what the
 * whole-image drawing gives it (render.cairo.split_same_pixels). */
typedef struct Rows {
    const DrawScene *scene;
    RenderImage *out;
    int y0, y1;
    int rc; /* 0, or -1 when Cairo failed */
} Rows;

static void draw_rows(void *context)
{
    Rows *r = context;
    RenderImage *out = r->out;
    cairo_surface_t *surface = cairo_image_surface_create_for_data(
        out->pixels + (size_t)r->y0 * (size_t)out->stride, CAIRO_FORMAT_ARGB32, out->width,
        r->y1 - r->y0, out->stride);
    r->rc = -1;
    if (cairo_surface_status(surface) == CAIRO_STATUS_SUCCESS) {
        cairo_t *cr = cairo_create(surface);
        cairo_translate(cr, 0, -r->y0);
        draw_scene(cr, (void *)(uintptr_t)r->scene); /* RenderDrawFn's context is not const */
        r->rc = cairo_status(cr) == CAIRO_STATUS_SUCCESS ? 0 : -1;
        cairo_destroy(cr);
        cairo_surface_flush(surface);
    }
    cairo_surface_destroy(surface);
}

/* A disk's cost grows with its area on top of a fixed part, in Cairo's fill (about 0.3 (r^2 + 1)
 * us, docs/dev/scaling.md, "Frames") as in render_disk_fill, hence the weights; the chains lie
 * among the grains and follow them. Any row gives the same pixels
 * (render.draw.split_same_pixels). */
int render_cairo_split_row(const SimFrame *f, const RenderView *v, int height)
{
    if (height < 2)
        return height;
    double *rows = calloc((size_t)height, sizeof *rows);
    if (!rows)
        return height / 2;
    double total = 0;
    for (int i = 0; i < f->count; ++i) {
        double px, py, r = f->radius[i] * v->scale;
        render_view_to_pixel(v, f->x[i], f->y[i], &px, &py);
        if (!(py + r >= v->plot_y && py - r <= v->plot_y + v->plot_h && px + r >= v->plot_x &&
              px - r <= v->plot_x + v->plot_w))
            continue;
        const int row = py < 0 ? 0 : py >= height ? height - 1 : (int)py;
        rows[row] += r * r + 1;
        total += r * r + 1;
    }
    int split = height / 2;
    if (total > 0) {
        double sum = 0;
        for (split = 0; split < height - 1 && sum + rows[split] < 0.5 * total; ++split)
            sum += rows[split];
    }
    free(rows);
    return split < 1 ? 1 : split;
}

int render_cairo_draw_split(const SimFrame *frame, const RenderStyle *style, RenderImage *out,
                            RenderHelper *helper)
{
    out->pixels = NULL;
    if (!frame || !style || style->width <= 0 || style->height <= 0)
        return -1;
    DrawScene sc;
    int rc = draw_scene_init(&sc, frame, style);
    if (rc == 0)
        rc = render_image_alloc(out, style->width, style->height, RENDER_PIXEL_BGRA_PREMUL);
    if (rc == 0 && cairo_format_stride_for_width(CAIRO_FORMAT_ARGB32, out->width) != out->stride)
        rc = -1;
    if (rc == 0) { /* no helper: one band, the whole image */
        const int middle =
            helper ? render_cairo_split_row(frame, &sc.view, style->height) : style->height;
        Rows lower = {&sc, out, middle, style->height, 0}, upper = {&sc, out, 0, middle, 0};
        if (helper)
            render_helper_start(helper, draw_rows, &lower);
        draw_rows(&upper);
        if (helper)
            render_helper_wait(helper);
        rc = upper.rc != 0 || lower.rc != 0 ? -1 : 0;
    }
    if (rc != 0)
        render_image_free(out);
    draw_scene_free(&sc);
    return rc;
}

int render_cairo_draw(const SimFrame *frame, const RenderStyle *style, RenderImage *out)
{
    return render_cairo_draw_split(frame, style, out, NULL);
}

/* Swaps bytes 0 and 2 of every pixel: RGBA <-> BGRA. */
static void swap_red_blue(RenderImage *image)
{
    for (int y = 0; y < image->height; ++y) {
        uint8_t *p = image->pixels + (size_t)y * (size_t)image->stride;
        for (int x = 0; x < image->width; ++x, p += 4) {
            uint8_t t = p[0];
            p[0] = p[2];
            p[2] = t;
        }
    }
}

int render_cairo_overlay(const SimFrame *frame, const RenderStyle *style, RenderImage *inout)
{
    if (!frame || !style || !inout || !inout->pixels || inout->width != style->width ||
        inout->height != style->height || inout->stride % 4 != 0 ||
        inout->stride < 4 * inout->width)
        return -1;
    /* The grain layer is already drawn: skip sorting the chains unless the inset redraws them. */
    RenderStyle s = *style;
    if (!(s.arch_inset && s.arch_ids))
        s.force_chains = 0;
    DrawScene sc;
    if (draw_scene_init(&sc, frame, &s) != 0) {
        draw_scene_free(&sc);
        return -1;
    }
    /* Opaque RGBA becomes Cairo's ARGB32 (BGRA bytes) for the drawing and is swapped back;
     * straight and premultiplied alpha agree on opaque pixels. */
    int rgba = inout->format == RENDER_PIXEL_RGBA;
    if (rgba)
        swap_red_blue(inout);
    cairo_surface_t *surface = cairo_image_surface_create_for_data(
        inout->pixels, CAIRO_FORMAT_ARGB32, inout->width, inout->height, inout->stride);
    int rc = -1;
    if (cairo_surface_status(surface) == CAIRO_STATUS_SUCCESS) {
        cairo_t *cr = cairo_create(surface);
        draw_overlay(cr, &sc);
        rc = cairo_status(cr) == CAIRO_STATUS_SUCCESS ? 0 : -1;
        cairo_destroy(cr);
        cairo_surface_flush(surface);
    }
    cairo_surface_destroy(surface);
    if (rgba)
        swap_red_blue(inout);
    draw_scene_free(&sc);
    return rc;
}

/* A grain figure and a plot side by side (render_figure_beside_write): each clipped to its own
 * rectangle on a white page, the grains `top` pixels down, the plot `top + shift`. */
typedef struct Beside {
    DrawScene *scene;
    const RenderPlot *plot;
    int top, shift, width, height;
} Beside;

static void draw_beside(cairo_t *cr, void *context)
{
    const Beside *b = context;
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_save(cr);
    cairo_translate(cr, 0, b->top);
    cairo_rectangle(cr, 0, 0, b->scene->style.width, b->scene->style.height);
    cairo_clip(cr);
    draw_scene(cr, b->scene);
    cairo_restore(cr);
    cairo_save(cr);
    cairo_translate(cr, b->scene->style.width, b->top + b->shift);
    cairo_rectangle(cr, 0, 0, b->plot->width, b->plot->height);
    cairo_clip(cr);
    render_plot_paint(cr, b->plot);
    cairo_restore(cr);
}

/* A figure of `frame` as one page with its provenance (render_provenance, the frame's time,
 * step and renderer): the scene alone at its size, or with `b` (its scene filled in here) the
 * grains and plot side by side on b's width x height. */
static int figure_page(const SimFrame *frame, const RenderStyle *style, const RenderMeta *meta,
                       Beside *b, const char *path, char *err, size_t err_size)
{
    DrawScene sc;
    if (draw_scene_init(&sc, frame, style) != 0) {
        draw_scene_free(&sc);
        snprintf(err, err_size, "%s: out of memory", path);
        return -1;
    }
    char seed[32], time[48], step[32], renderer[64];
    snprintf(time, sizeof time, "%.9g s", frame->time);
    snprintf(step, sizeof step, "%ld", frame->step);
    snprintf(renderer, sizeof renderer, "cairo %s", cairo_version_string());
    const char *text[20];
    int n = 0;
    render_provenance(meta, style->title, 1, seed, text, &n);
    text[n++] = "Simulated time";
    text[n++] = time;
    text[n++] = "Step";
    text[n++] = step;
    text[n++] = "Renderer";
    text[n++] = renderer;
    text[n++] = NULL;
    text[n++] = NULL;
    int rc;
    if (b) {
        b->scene = &sc;
        rc = render_cairo_write_dpi(path, b->width, b->height, style->dpi, draw_beside, b, text,
                                    err, err_size);
    } else {
        rc = render_cairo_write_dpi(path, style->width, style->height, style->dpi, draw_scene, &sc,
                                    text, err, err_size);
    }
    draw_scene_free(&sc);
    return rc;
}

int render_figure_beside_write(const SimFrame *frame, const RenderStyle *style,
                               const RenderMeta *meta, const RenderPlot *plot, int shift,
                               const char *path, char *err, size_t err_size)
{
    if (!frame || !style || style->width <= 0 || style->height <= 0 || !plot ||
        render_plot_layout(plot, NULL, 0) < 0) {
        snprintf(err, err_size, "%s: bad frame, style or plot", path);
        return -1;
    }
    if (render_has_extension(path, "png")) {
        snprintf(err, err_size, "%s: a figure with a plot beside it is .pdf or .svg", path);
        return -1;
    }
    /* the PNG composite's geometry (app/cli/render_glue.c side_by_side) */
    Beside b = {.plot = plot, .top = shift < 0 ? -shift : 0, .shift = shift};
    b.width = style->width + plot->width;
    b.height = style->height + b.top > plot->height + shift + b.top ? style->height + b.top
                                                                    : plot->height + shift + b.top;
    return figure_page(frame, style, meta, &b, path, err, err_size);
}

int render_figure_write(const SimFrame *frame, const RenderStyle *style, const RenderMeta *meta,
                        const char *path, char *err, size_t err_size)
{
    if (!frame || !style || style->width <= 0 || style->height <= 0) {
        snprintf(err, err_size, "%s: bad frame or style", path);
        return -1;
    }
    return figure_page(frame, style, meta, NULL, path, err, err_size);
}
