/* SPDX-License-Identifier: MIT */
/* scene_walls.c: the keys that make a wall respond to the grains (docs/scenes.md, "Walls that
 * respond"): walls.N.mass, axis, force, gravity and servo = {stress | force, gain, max_speed},
 * into sim.h's SimWallBody. sim checks the rest (the servo's stability rule) against the stage's
 * time step, with walls[N] mapped back to the wall's line. */
#include "scene_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The unit direction of `axis` for wall w: "normal" is the left normal of from -> to, (-ey, ex)
 * / |e| (a segment), "x" and "y" the coordinate axes; a leading '-' turns it round. */
static int parse_axis(Loader *L, const config_setting_t *g, const SimWall *w, SimWallBody *b)
{
    static const char *const names[] = {"normal", "-normal", "x", "-x", "y", "-y", NULL};
    int which = 0;
    if (app_config_choice(&L->p, g, "axis", names, &which) < 0)
        return -1;
    const double sign = which % 2 ? -1.0 : 1.0;
    if (which < 2) {
        if (w->shape == SIM_WALL_ARC)
            return app_config_fail(&L->p, app_config_member(g, "axis"),
                                   "`axis` = \"normal\" is for segments: give an arc \"x\" or "
                                   "\"y\"");
        const double ex = w->x1 - w->x0, ey = w->y1 - w->y0, len = hypot(ex, ey);
        b->axis_x = -sign * ey / len;
        b->axis_y = sign * ex / len;
    } else {
        b->axis_x = which < 4 ? sign : 0.0;
        b->axis_y = which < 4 ? 0.0 : sign;
    }
    return 0;
}

/* servo = {stress = S | force = F, gain = G, max_speed = V}. */
static int parse_servo(Loader *L, const config_setting_t *g, const char *what, SimWallBody *b)
{
    static const char *const keys[] = {"stress", "force", "gain", "max_speed", NULL};
    const config_setting_t *servo;
    char name[48];
    snprintf(name, sizeof name, "%s.servo", what);
    if (app_config_group(&L->p, g, "servo", &servo) < 0 ||
        app_config_keys(&L->p, servo, name, keys, NULL) < 0)
        return -1;
    const int stress = app_config_member(servo, "stress") != NULL;
    if (stress == (app_config_member(servo, "force") != NULL))
        return app_config_fail(&L->p, servo,
                               "%s: give one of `stress` (force per length) or "
                               "`force`",
                               name);
    b->servo = stress ? 1 : 2;
    if (app_config_number(&L->p, servo, stress ? "stress" : "force", &b->target) < 0 ||
        app_config_need_number(&L->p, servo, "gain", name, &b->gain) < 0 ||
        app_config_positive(&L->p, servo, "gain", b->gain) < 0 ||
        app_config_need_number(&L->p, servo, "max_speed", name, &b->max_speed) < 0 ||
        app_config_positive(&L->p, servo, "max_speed", b->max_speed) < 0)
        return -1;
    if (!(b->target >= 0.0))
        return app_config_fail(&L->p, app_config_member(servo, stress ? "stress" : "force"),
                               "%s: the target must be >= 0 (compressive)", name);
    return 0;
}

int loader_parse_wall_body(Loader *L, const config_setting_t *g, const char *what, int k)
{
    static const char *const body_keys[] = {"mass", "axis", "force", "gravity", "servo", NULL};
    int any = 0;
    for (int j = 0; body_keys[j]; ++j)
        any |= app_config_member(g, body_keys[j]) != NULL;
    if (!any)
        return 0;
    Scene *scene = L->scene;
    if (!scene->wall_bodies) {
        int n = config_setting_length(config_setting_parent(g));
        scene->wall_bodies = calloc((size_t)(n > 0 ? n : 1), sizeof *scene->wall_bodies);
        if (!scene->wall_bodies)
            return app_config_fail(&L->p, g, "out of memory");
    }
    SimWallBody *b = &scene->wall_bodies[k];
    const SimWall *w = &scene->walls[k];
    double force[2] = {0.0, 0.0};
    b->active = 1;
    b->gravity = 1;
    if (!app_config_member(g, "mass") && !app_config_member(g, "servo"))
        return app_config_fail(&L->p, g,
                               "%s: `axis`, `force` and `gravity` need a `mass` or a "
                               "`servo`",
                               what);
    if (app_config_need(&L->p, g, "axis", what) < 0 || parse_axis(L, g, w, b) < 0 ||
        app_config_number(&L->p, g, "mass", &b->mass) < 0 ||
        (app_config_member(g, "mass") && app_config_positive(&L->p, g, "mass", b->mass) < 0) ||
        app_config_vector(&L->p, g, "force", force, 2) < 0 ||
        app_config_bool(&L->p, g, "gravity", &b->gravity) < 0 ||
        (app_config_member(g, "servo") && parse_servo(L, g, what, b) < 0))
        return -1;
    if (w->motion >= 0)
        return app_config_fail(&L->p, app_config_member(g, "motion"),
                               "%s: a wall with a mass or a servo cannot also follow a motion",
                               what);
    if (!b->servo && !app_config_member(g, "mass"))
        return app_config_fail(&L->p, g, "%s: a responding wall needs a `mass` or a `servo`", what);
    b->force_x = force[0];
    b->force_y = force[1];
    scene->def.wall_bodies = scene->wall_bodies;
    return 0;
}
