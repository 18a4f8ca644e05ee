/* SPDX-License-Identifier: MIT */
/* render_colormap.c: colour maps as 256-entry tables built from knots, and the per-grain colour
 * rules shared by the Cairo and OSMesa drawers. Both drawers look colours up here and never
 * recompute a map, so their grains agree to the byte (anchors-render 1.8). */
#include "render/internal.h"

#include <math.h>

/* viridis (matplotlib, CC0, van der Walt, Smith & Firing 2015): every 4th entry of the
 * 256-entry table, plus the last; linear interpolation between them is within 1/255 of the full
 * table. */
static const double viridis_knots[][3] = {
    {0.267004, 0.004874, 0.329415}, {0.272594, 0.025563, 0.353093}, {0.277018, 0.050344, 0.375715},
    {0.280267, 0.073417, 0.397163}, {0.282327, 0.094955, 0.417331}, {0.283197, 0.115680, 0.436115},
    {0.282884, 0.135920, 0.453427}, {0.281412, 0.155834, 0.469201}, {0.278826, 0.175490, 0.483397},
    {0.275191, 0.194905, 0.496005}, {0.270595, 0.214069, 0.507052}, {0.265145, 0.232956, 0.516599},
    {0.258965, 0.251537, 0.524736}, {0.252194, 0.269783, 0.531579}, {0.244972, 0.287675, 0.537260},
    {0.237441, 0.305202, 0.541921}, {0.229739, 0.322361, 0.545706}, {0.221989, 0.339161, 0.548752},
    {0.214298, 0.355619, 0.551184}, {0.206756, 0.371758, 0.553117}, {0.199430, 0.387607, 0.554642},
    {0.192357, 0.403199, 0.555836}, {0.185556, 0.418570, 0.556753}, {0.179019, 0.433756, 0.557430},
    {0.172719, 0.448791, 0.557885}, {0.166617, 0.463708, 0.558119}, {0.160665, 0.478540, 0.558115},
    {0.154815, 0.493313, 0.557840}, {0.149039, 0.508051, 0.557250}, {0.143343, 0.522773, 0.556295},
    {0.137770, 0.537492, 0.554906}, {0.132444, 0.552216, 0.553018}, {0.127568, 0.566949, 0.550556},
    {0.123463, 0.581687, 0.547445}, {0.120565, 0.596422, 0.543611}, {0.119423, 0.611141, 0.538982},
    {0.120638, 0.625828, 0.533488}, {0.124780, 0.640461, 0.527068}, {0.132268, 0.655014, 0.519661},
    {0.143303, 0.669459, 0.511215}, {0.157851, 0.683765, 0.501686}, {0.175707, 0.697900, 0.491033},
    {0.196571, 0.711827, 0.479221}, {0.220124, 0.725509, 0.466226}, {0.246070, 0.738910, 0.452024},
    {0.274149, 0.751988, 0.436601}, {0.304148, 0.764704, 0.419943}, {0.335885, 0.777018, 0.402049},
    {0.369214, 0.788888, 0.382914}, {0.404001, 0.800275, 0.362552}, {0.440137, 0.811138, 0.340967},
    {0.477504, 0.821444, 0.318195}, {0.515992, 0.831158, 0.294279}, {0.555484, 0.840254, 0.269281},
    {0.595839, 0.848717, 0.243329}, {0.636902, 0.856542, 0.216620}, {0.678489, 0.863742, 0.189503},
    {0.720391, 0.870350, 0.162603}, {0.762373, 0.876424, 0.137064}, {0.804182, 0.882046, 0.114965},
    {0.845561, 0.887322, 0.099702}, {0.886271, 0.892374, 0.095374}, {0.926106, 0.897330, 0.104071},
    {0.964894, 0.902323, 0.123941}, {0.993248, 0.906157, 0.143936},
};

/* Light yellow to dark red (ColorBrewer YlOrRd hues, Brewer 2002), the look of the force maps of
 * thesis 000 figs. 6.16-7.2. Evenly spaced. */
static const double yellow_red_knots[][3] = {
    {1.000, 0.929, 0.627}, {0.996, 0.851, 0.463}, {0.996, 0.698, 0.298}, {0.992, 0.553, 0.235},
    {0.988, 0.306, 0.165}, {0.890, 0.102, 0.110}, {0.741, 0.000, 0.149}, {0.502, 0.000, 0.149},
};

/* Light grey to near black: a white background stays distinguishable from the weakest grain. */
static const double greys_knots[][3] = {{0.949, 0.949, 0.949}, {0.098, 0.098, 0.098}};

/* Okabe & Ito (2008) colour-blind-safe categorical palette, black left out (outlines are dark). */
static const uint32_t species_palette[8] = {0x0072b2, 0xe69f00, 0x009e73, 0xcc79a7,
                                            0x56b4e9, 0xd55e00, 0xf0e442, 0x999999};

static uint8_t channel(double v)
{
    double c = floor(v * 255.0 + 0.5);
    return (uint8_t)(c < 0 ? 0 : c > 255 ? 255 : c);
}

/* Entry k of a table built by linear interpolation between knots at positions `pos` (in table
 * index units, increasing, first 0, last 255). */
static void lut_entry(const double (*knots)[3], const double *pos, int count, int k, uint8_t out[3])
{
    int s = 0;
    while (s + 2 < count && pos[s + 1] < (double)k)
        ++s;
    double f = ((double)k - pos[s]) / (pos[s + 1] - pos[s]);
    for (int c = 0; c < 3; ++c)
        out[c] = channel(knots[s][c] + f * (knots[s + 1][c] - knots[s][c]));
}

static void map_entry(RenderColormap map, int k, uint8_t out[3])
{
    enum { NV = sizeof viridis_knots / sizeof viridis_knots[0] };

    enum { NY = sizeof yellow_red_knots / sizeof yellow_red_knots[0] };

    double pos[NV];
    switch (map) {
    case RENDER_CMAP_YELLOW_RED:
        for (int s = 0; s < NY; ++s)
            pos[s] = 255.0 * s / (NY - 1);
        lut_entry(yellow_red_knots, pos, NY, k, out);
        return;
    case RENDER_CMAP_GREYS:
        pos[0] = 0;
        pos[1] = 255;
        lut_entry(greys_knots, pos, 2, k, out);
        return;
    case RENDER_CMAP_VIRIDIS:
    default:
        for (int s = 0; s < NV - 1; ++s)
            pos[s] = 4.0 * s;
        pos[NV - 1] = 255;
        lut_entry(viridis_knots, pos, NV, k, out);
        return;
    }
}

void render_colormap_lut(RenderColormap map, uint8_t lut[256][3])
{
    for (int k = 0; k < 256; ++k)
        map_entry(map, k, lut[k]);
}

uint32_t render_colormap_rgb(RenderColormap map, double t)
{
    if (!(t > 0))
        t = 0; /* also NaN */
    if (t > 1)
        t = 1;
    uint8_t c[3];
    map_entry(map, (int)floor(t * 255.0 + 0.5), c);
    return (uint32_t)c[0] << 16 | (uint32_t)c[1] << 8 | c[2];
}

uint32_t render_species_rgb(int species)
{
    unsigned u = species < 0 ? 0u - (unsigned)species : (unsigned)species; /* INT_MIN too */
    return species_palette[u % 8u];
}

static double mean_diameter(const SimFrame *frame)
{
    double sum = 0;
    int n = 0;
    for (int i = 0; i < frame->count; ++i) {
        if (frame->flags && (frame->flags[i] & SIM_GRAIN_FIXED) && frame->mobile_count > 0)
            continue;
        sum += 2 * frame->radius[i];
        ++n;
    }
    return n ? sum / n : 0;
}

double render_grain_value(const SimFrame *frame, const RenderStyle *style, int i)
{
    switch (style->color_by) {
    case RENDER_COLOR_FORCE:
        return frame->force ? frame->force[i] : 0;
    case RENDER_COLOR_SPEED:
        return frame->vx && frame->vy ? hypot(frame->vx[i], frame->vy[i]) : 0;
    case RENDER_COLOR_SPECIES:
        return frame->species ? frame->species[i] : 0;
    case RENDER_COLOR_HEIGHT: {
        double y = frame->y[i];
        if (style->initial_y && frame->id && frame->id[i] < (uint32_t)style->initial_y_count)
            y = style->initial_y[frame->id[i]];
        double band = style->band_height;
        if (!(band > 0))
            band = 5 * mean_diameter(frame);
        return band > 0 ? floor(y / band) : 0;
    }
    case RENDER_COLOR_FIXED:
    default:
        return 0;
    }
}

/* The largest value of the style's quantity over the frame's mobile grains (0 if none). */
static double mobile_max(const SimFrame *frame, const RenderStyle *style)
{
    double m = 0;
    for (int i = 0; i < frame->count; ++i) {
        if (frame->flags && (frame->flags[i] & SIM_GRAIN_FIXED))
            continue;
        double v = render_grain_value(frame, style, i);
        if (v > m)
            m = v;
    }
    return m;
}

void render_color_range(const SimFrame *frame, const RenderStyle *style, double *lo, double *hi)
{
    if (style->range_min < style->range_max) {
        *lo = style->range_min;
        *hi = style->range_max;
        return;
    }
    double m = mobile_max(frame, style);
    *lo = 0;
    *hi = m > 0 ? m : 1;
}

static int continuous(const RenderStyle *style)
{
    return style->color_by == RENDER_COLOR_FORCE || style->color_by == RENDER_COLOR_SPEED;
}

/* One colour scale per movie or figure series: a scale that follows each frame's maximum makes
 * frames incomparable (the same colour means 1 N in one frame and 6000 N in the next). Frames
 * come one at a time while the simulation runs, so the range cannot come from a pass over all of
 * them: it is fixed at the first frame with a non-zero value, with a quarter of headroom for the
 * growth that follows, and what still exceeds it saturates, as the bar's end triangle says. */
int render_color_lock(const SimFrame *frame, RenderStyle *style)
{
    if (!continuous(style))
        return 1;
    if (style->range_min < style->range_max) {
        style->color_extend |= RENDER_EXTEND_MAX | (style->range_min > 0 ? RENDER_EXTEND_MIN : 0);
        return 1;
    }
    double m = frame ? mobile_max(frame, style) : 0;
    if (!(m > 0) || !isfinite(m))
        return 0;
    double lo = 0, hi = 1.25 * m;
    render_axis_nice_range(&lo, &hi, 0, 5);
    style->range_min = 0;
    style->range_max = hi;
    style->color_extend |= RENDER_EXTEND_MAX;
    return 1;
}

int render_color_extend(const SimFrame *frame, const RenderStyle *style, double lo, double hi)
{
    int bits = style->color_extend & (RENDER_EXTEND_MAX | RENDER_EXTEND_MIN);
    if (!continuous(style) || !(style->range_min < style->range_max))
        return bits;
    for (int i = 0; i < frame->count; ++i) {
        if (frame->flags && (frame->flags[i] & SIM_GRAIN_FIXED))
            continue;
        double v = render_grain_value(frame, style, i);
        bits |= v > hi ? RENDER_EXTEND_MAX : v < lo ? RENDER_EXTEND_MIN : 0;
    }
    return bits;
}

uint32_t render_grain_rgb(const SimFrame *frame, const RenderStyle *style, int i, double lo,
                          double hi)
{
    if (frame->flags && (frame->flags[i] & SIM_GRAIN_FIXED))
        return style->fixed_rgb;
    switch (style->color_by) {
    case RENDER_COLOR_FORCE:
    case RENDER_COLOR_SPEED: {
        double v = render_grain_value(frame, style, i);
        return render_colormap_rgb(style->colormap, hi > lo ? (v - lo) / (hi - lo) : 0);
    }
    case RENDER_COLOR_SPECIES:
        return render_species_rgb(frame->species ? frame->species[i] : 0);
    case RENDER_COLOR_HEIGHT: {
        double band = render_grain_value(frame, style, i);
        return fmod(fabs(band), 2.0) == 1.0 ? style->band_rgb : style->fill_rgb;
    }
    case RENDER_COLOR_FIXED:
    default:
        return style->fill_rgb;
    }
}

double render_chain_cut(const SimFrame *frame, const RenderStyle *style, double *f_max)
{
    double sum = 0, top = 0;
    int n = 0;
    for (int c = 0; c < frame->contact_count; ++c) {
        double f = frame->contacts[c].normal_force;
        if (f > 0) {
            sum += f;
            ++n;
            if (f > top)
                top = f;
        }
    }
    *f_max = style->chain_force_max > 0 ? style->chain_force_max : top;
    return n ? style->chain_threshold * sum / n : 0;
}
