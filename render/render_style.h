/* SPDX-License-Identifier: MIT */
/* render_style.h: what a frame drawing shows and how; shared by the Cairo and OSMesa drawers so
 * the two agree on the same frame. Start from render_style_default() and override. */
#ifndef RENDER_STYLE_H
#define RENDER_STYLE_H

#include "sim/sim.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum RenderColorBy {
    RENDER_COLOR_FIXED = 0,   ///< one fill colour
    RENDER_COLOR_FORCE = 1,   ///< per-grain contact-force magnitude (SimFrame.force), N
    RENDER_COLOR_SPEED = 2,   ///< |v|, m/s
    RENDER_COLOR_SPECIES = 3, ///< categorical, species index
    RENDER_COLOR_HEIGHT = 4,  ///< height bands of initial y (band width in style), m
} RenderColorBy;

typedef enum RenderColormap {
    RENDER_CMAP_VIRIDIS = 0,    ///< perceptually uniform (default)
    RENDER_CMAP_YELLOW_RED = 1, ///< thesis 000 figs. 6.16-7.2 force map
    RENDER_CMAP_GREYS = 2,      ///< black and white (thesis 004 snapshots)
} RenderColormap;

typedef enum RenderKernel {
    RENDER_KERNEL_LUCY = 0,     ///< Lucy polynomial, compact support (MercuryCG default)
    RENDER_KERNEL_GAUSSIAN = 1, ///< Gaussian, standard deviation width / 3, cut at width
} RenderKernel;

typedef struct RenderStyle {
    int width, height;       ///< pixels (1 pixel = 1/96 inch = 0.75 pt in PDF and SVG)
    double view_x0, view_y0; ///< world window, m; view_x1 <= view_x0 = fit all grains
    double view_x1, view_y1;
    RenderColorBy color_by;
    RenderColormap colormap;
    double range_min, range_max; ///< colour range in the quantity's unit; min >= max = auto
    double band_height;          ///< RENDER_COLOR_HEIGHT band width, m (0 = 5 mean diameters)
    uint32_t fill_rgb;           ///< RENDER_COLOR_FIXED fill (and even height bands), 0xRRGGBB
    uint32_t fixed_rgb;          ///< fill of fixed grains (walls, base), 0xRRGGBB
    uint32_t background_rgb;     ///< 0xRRGGBB
    int outline;                 ///< 1: thin dark outline around each disk
    int orientation_tick;        ///< 1: radius line showing the grain angle (000 fig. 5.26)
    int force_chains;            ///< 1: draw contact segments (strong network)
    double chain_threshold;      ///< draw contacts with F_n > threshold * mean F_n (default 1)
    double chain_width_max;      ///< width of the strongest chain, pixels (0 = 0.5 mean d)
    int velocity_arrows;         ///< 1: per-grain velocity arrows
    int velocity_field;          ///< 1: coarse-grained mean velocity field on a grid
    double field_cell;           ///< grid spacing of the velocity field, m (0 = 2 mean d)
    double field_width;          ///< kernel cutoff radius, m (0 = 1.5 mean diameters)
    int field_kernel;            ///< RenderKernel: 0 Lucy, 1 Gaussian
    double arrow_scale;          ///< arrow length per speed, s (0 = auto: fastest = 2 mean d)
    int colorbar;                ///< 1: colour bar with label and unit (species: a legend)
    const char *colorbar_label;  ///< e.g. "contact force"; NULL = from color_by
    const char *colorbar_unit;   ///< e.g. "N"; NULL = from color_by
    int time_stamp;              ///< 1: "t = ... s, t* = ..."
    int scale_bar;               ///< 1: scale bar in mean diameters
    const char *title;           ///< NULL = none
    const int *arch_ids;         ///< per-grain arch id (frame order), -1 none; NULL = no arches
    int arch_inset;              ///< 1: zoomed inset around the arches
    /* Later additions; always start from render_style_default(). */
    uint32_t band_rgb;       ///< fill of odd height bands, 0xRRGGBB
    const double *initial_y; ///< initial y per stable grain id, m; NULL = current y
    int initial_y_count;     ///< entries in initial_y
    double chain_force_max;  ///< F_n drawn at chain_width_max, N (0 = per-frame maximum)
    uint32_t arch_rgb;       ///< arch highlight colour, 0xRRGGBB
    double font_size;        ///< pixels (0 = RENDER_FIGURE_FONT_PT points at dpi)
    int reduced_units;       ///< 1: time stamp in sqrt(d/g), scale bar in d only (no metres)
    /* Publication figures. */
    int axes;                         ///< 1: framed x/y axes with ticks, in m (or d if reduced)
    const char *const *species_names; ///< legend names by species index; NULL/"" = "species N"
    int species_name_count;           ///< entries in species_names
    double dpi;                       ///< pixels per inch of the written file (0 = 96)
    int field_color;                  ///< 1: field arrows coloured by speed (colormap)
    /// Node field drawn instead of the coarse-grained one (velocity_field): nodes at
    /// (node_x0 + (i + 1/2) node_cell, node_y0 + (j + 1/2) node_cell), row-major j * nx + i,
    /// m/s; non-finite = no arrow. NULL = none.
    const double *node_vx, *node_vy;
    int node_nx, node_ny;
    double node_x0, node_y0, node_cell; ///< m
    /// A scene written in its own units (units = "normalised"): lengths already in d, so axes and
    /// scale bar say d at the numbers as given; RENDER_UNITS_NORMALISED_G also labels times in
    /// sqrt(d/g) and speeds in sqrt(g d) (|g| = 1), RENDER_UNITS_NORMALISED writes times bare.
    /// 0 = not declared.
    int normalised_units;
    /// Ends of the colour bar drawn as triangles (RENDER_EXTEND_* bits), as matplotlib's
    /// `extend`: values beyond a fixed range saturate at the end colour. A frame whose own values
    /// leave a fixed range adds that end; 0 = only those. Movies and figure series set
    /// RENDER_EXTEND_MAX when they fix their range (render_color_lock), so every frame's bar is
    /// the same.
    int color_extend;
    /// Grain and field arrows shorter than this fraction of the reference (key) arrow are not
    /// drawn, so grains at rest carry no dot (0 = 0.1; negative = draw every arrow).
    double arrow_min;
    /// Reduced units (a scene's units = "reduced"): the colour bar of force shows F / force_unit
    /// (m g, N) and that of speed v / speed_unit (sqrt(g d), m/s), in the scene's scales; the
    /// colours and `range_min`/`range_max` stay SI. 0 = SI.
    double force_unit, speed_unit;
} RenderStyle;

/// Default font size of grain figures, movies and heat maps: points at the print size (pixels /
/// dpi, 96 dpi when none is set): 10 px on a 96-dpi screen figure, 31 px at 300 dpi; never a
/// fraction of the pixel height, so a tall figure keeps its width for the grains.
#define RENDER_FIGURE_FONT_PT 7.5

/// RenderStyle.normalised_units
enum { RENDER_UNITS_NORMALISED = 1, RENDER_UNITS_NORMALISED_G = 2 };

/// RenderStyle.color_extend bits
enum { RENDER_EXTEND_MAX = 1, RENDER_EXTEND_MIN = 2 };

/// Defaults: 1280x720, sand-coloured outlined disks on white, fit view, colour bar, time stamp
/// and scale bar on; colour map viridis, chains off.
RenderStyle render_style_default(void);

#ifdef __cplusplus
}
#endif

#endif
