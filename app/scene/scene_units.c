/* SPDX-License-Identifier: MIT */
/* scene_units.c: the names of the scene's units (docs/scenes.md#units), one table read by every
 * axis, colour bar, check line and summary that prints a unit. */
#include "scene/scene.h"

#include <stdio.h>
#include <string.h>

/* The unit systems' rows of the table. */
enum { UNITS_SI, UNITS_OWN_G, UNITS_OWN, UNITS_COUNT };

/* {ASCII, figure} per quantity and system; a NULL figure name is the ASCII one. The scene's own
 * units (units = "normalised", |g| = 1): length d, mass m (a grain's), time sqrt(d/g), so that a
 * force is m g, an energy m g d and a 2D stress (force per length) m g/d. With another g the time
 * unit is the scene's own and unnamed: times and what holds them are written bare. */
static const char *const names[SCENE_QUANTITY_COUNT][UNITS_COUNT][2] = {
    [SCENE_LENGTH] = {{"m", NULL}, {"d", NULL}, {"d", NULL}},
    [SCENE_TIME] = {{"s", NULL}, {"sqrt(d/g)", "\xe2\x88\x9a(d/g)"}, {"", NULL}},
    [SCENE_SPEED] = {{"m/s", NULL}, {"sqrt(g d)", "\xe2\x88\x9a(gd)"}, {"d per time unit", NULL}},
    [SCENE_ACCELERATION] = {{"m/s^2", "m/s\xc2\xb2"}, {"g", NULL}, {"", NULL}},
    [SCENE_MASS] = {{"kg", NULL}, {"m", NULL}, {"m", NULL}},
    [SCENE_FORCE] = {{"N", NULL}, {"m g", NULL}, {"", NULL}},
    [SCENE_ENERGY] = {{"J", NULL}, {"m g d", NULL}, {"", NULL}},
    [SCENE_STRESS] = {{"N/m", NULL}, {"m g/d", NULL}, {"", NULL}},
    [SCENE_AREAL_DENSITY] = {{"kg/m^2", "kg/m\xc2\xb2"},
                             {"m/d^2", "m/d\xc2\xb2"},
                             {"m/d^2", "m/d\xc2\xb2"}},
    [SCENE_MOMENTUM_DENSITY] = {{"kg/(m s)", NULL},
                                {"m sqrt(g d)/d^2", "m\xe2\x88\x9a(gd)/d\xc2\xb2"},
                                {"", NULL}},
    [SCENE_SPEED_SQUARED] = {{"m^2/s^2", "m\xc2\xb2/s\xc2\xb2"}, {"g d", NULL}, {"", NULL}},
    [SCENE_RATE] = {{"1/s", NULL}, {"sqrt(g/d)", "\xe2\x88\x9a(g/d)"}, {"", NULL}},
    [SCENE_MASS_RATE] = {{"kg/s", NULL}, {"m sqrt(g/d)", "m\xe2\x88\x9a(g/d)"}, {"", NULL}},
    [SCENE_DIMENSIONLESS] = {{"", NULL}, {"", NULL}, {"", NULL}},
    [SCENE_DENSITY] = {{"kg/m^3", "kg/m\xc2\xb3"},
                       {"m/d^3", "m/d\xc2\xb3"},
                       {"m/d^3", "m/d\xc2\xb3"}},
    [SCENE_HERTZ_STIFFNESS] = {{"N/m^1.5", "N/m^{1.5}"}, /* figure markup */
                               {"m g/d^1.5", "m g/d^{1.5}"},
                               {"", NULL}},
    [SCENE_ROLLING_STIFFNESS] = {{"N m/rad", NULL}, {"m g d/rad", NULL}, {"", NULL}},
};

static int system_of_style(const SceneStyle *style)
{
    const int own = style ? style->normalised_units : 0;
    return own == SCENE_UNITS_NORMALISED_G ? UNITS_OWN_G : own ? UNITS_OWN : UNITS_SI;
}

static int system_of(const Scene *scene)
{
    return system_of_style(scene ? &scene->style : NULL);
}

const char *scene_style_unit(const SceneStyle *style, SceneQuantity quantity, int figure)
{
    if ((int)quantity < 0 || quantity >= SCENE_QUANTITY_COUNT)
        return "";
    const char *const *name = names[quantity][system_of_style(style)];
    return figure && name[1] ? name[1] : name[0];
}

const char *scene_unit(const Scene *scene, SceneQuantity quantity, int figure)
{
    return scene_style_unit(scene ? &scene->style : NULL, quantity, figure);
}

const char *scene_axis_label(const Scene *scene, const char *name, SceneQuantity quantity,
                             char *buf, size_t size)
{
    const char *unit = scene_unit(scene, quantity, 1);
    if (quantity == SCENE_DIMENSIONLESS)
        snprintf(buf, size, "%s (1)", name); /* a pure number: "φ (1)" in every system */
    else if (!unit[0])
        snprintf(buf, size, "%s", name);
    else if (system_of(scene) == UNITS_SI)
        snprintf(buf, size, "%s (%s)", name, unit);
    else if (strchr(unit, ' ') || (strchr(unit, '/') && unit[0] != '\xe2'))
        snprintf(buf, size, "%s / (%s)", name, unit); /* a compound unit: "σ / (m g/d)" */
    else
        snprintf(buf, size, "%s / %s", name, unit);
    return buf;
}

const char *scene_unit_after(const Scene *scene, SceneQuantity quantity, char *buf, size_t size)
{
    const char *unit = scene_unit(scene, quantity, 0);
    snprintf(buf, size, "%s%s", unit[0] ? " " : "", unit);
    return buf;
}
