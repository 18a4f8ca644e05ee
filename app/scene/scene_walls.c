/* SPDX-License-Identifier: MIT */
/* scene_walls.c: the keys that make a wall respond to the grains (docs/scenes.md, "Walls that
 * respond"): walls.N.mass, axis, force, gravity, servo = {stress | force, gain, max_speed,
 * length | between}, rotation and inertia, into sim.h's SimWallBody (a `motion` of the wall moves
 * it across its axis); the same keys make a named group of fixed grains one rigid body (`bodies`,
 * a rough piston; the grains.rows and columns entries with that `group`). sim checks the rest
 * (the servo's stability rule, the motion's direction, the `between` walls' geometry) against
 * the stage's time step, with walls[N] and bodies[N] mapped back to their lines. */
#include "scene/scene_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The unit direction of `axis` for wall w: "normal" is the left normal of from -> to, (-ey, ex)
 * / |e| (a segment), "x" and "y" the coordinate axes; a leading '-' turns it round; "none" (0, 0)
 * for a body that only turns (rotation = true, no servo). w NULL: a grain body (no normal). */
static int parse_axis(Loader *L, const config_setting_t *g, const SimWall *w, SimWallBody *b)
{
    static const char *const names[] = {"normal", "-normal", "x", "-x", "y", "-y", "none", NULL};
    int which = 0;
    if (app_config_choice(&L->p, g, "axis", names, &which) < 0)
        return -1;
    if (which == 6) { /* no translation: a body hinged at its centre that only turns */
        b->axis_x = b->axis_y = 0.0;
        return 0;
    }
    const double sign = which % 2 ? -1.0 : 1.0;
    if (which < 2) {
        if (!w || w->shape == SIM_WALL_ARC)
            return app_config_fail(&L->p, app_config_member(g, "axis"),
                                   "`axis` = \"normal\" is for segments: give %s \"x\" or "
                                   "\"y\"",
                                   w ? "an arc" : "a grain body");
        const double ex = w->x1 - w->x0, ey = w->y1 - w->y0, len = hypot(ex, ey);
        b->axis_x = -sign * ey / len;
        b->axis_y = sign * ex / len;
    } else {
        b->axis_x = which < 4 ? sign : 0.0;
        b->axis_y = which < 4 ? 0.0 : sign;
    }
    return 0;
}

/* A stress servo's `length = L` (m) or `between = [i, j]` (two walls of the list, by index),
 * the length its target is taken over (sim.h SimWallBody length_kind; sim checks the walls'
 * geometry). */
static int parse_servo_length(Loader *L, const config_setting_t *servo, const char *name, int k,
                              SimWallBody *b)
{
    const config_setting_t *length = app_config_member(servo, "length");
    const config_setting_t *between = app_config_member(servo, "between");
    if (!length && !between)
        return 0;
    if (b->servo != 1 || (length && between))
        return app_config_fail(&L->p, length ? length : between,
                               "%s: `length` or `between` (one of them) is for a `stress` target",
                               name);
    if (length) {
        b->length_kind = 1;
        return app_config_number(&L->p, servo, "length", &b->length) < 0 ||
                       app_config_positive(&L->p, servo, "length", b->length) < 0
                   ? -1
                   : 0;
    }
    double pair[2];
    /* a wall's servo names the other walls of its list; a grain body's, the scene's walls */
    const int count =
        k >= 0 ? config_setting_length(config_setting_parent(config_setting_parent(servo)))
               : L->scene->def.wall_count;
    if (app_config_vector(&L->p, servo, "between", pair, 2) < 0)
        return -1;
    for (int j = 0; j < 2; ++j) {
        if (!(pair[j] >= 0.0 && pair[j] < count && pair[j] == floor(pair[j]) && pair[j] != k &&
              pair[j] != pair[1 - j]))
            return app_config_fail(&L->p, between,
                                   "%s.between: two other walls of the list, by index (0 to %d, "
                                   "not %d)",
                                   name, count - 1, k);
        b->between[j] = (int)pair[j];
    }
    b->length_kind = 2;
    return 0;
}

/* servo = {stress = S | force = F, gain = G, max_speed = V, length = L | between = [i, j],
 * damping = "implicit" | "explicit"}: implicit is a wall's default, explicit a grain body's
 * only law (sim.h SimWallBody servo_explicit; docs/scenes.md "Damping bound"). */
static int parse_servo(Loader *L, const config_setting_t *g, const char *what, int k,
                       SimWallBody *b)
{
    static const char *const keys[] = {"stress", "force",   "gain",    "max_speed",
                                       "length", "between", "damping", NULL};
    static const char *const laws[] = {"implicit", "explicit", NULL};
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
        app_config_positive(&L->p, servo, "max_speed", b->max_speed) < 0 ||
        parse_servo_length(L, servo, name, k, b) < 0)
        return -1;
    int law = k < 0; /* a grain body's contacts are grain pairs: no implicit law */
    if (app_config_member(servo, "damping") &&
        app_config_choice(&L->p, servo, "damping", laws, &law) < 0)
        return -1;
    if (k < 0 && law == 0)
        return app_config_fail(&L->p, app_config_member(servo, "damping"),
                               "%s: `damping` = \"implicit\" is for a wall's servo (a grain "
                               "body's load comes from grain pairs, whose dashpots it does not "
                               "sum): give \"explicit\" or leave it out",
                               name);
    b->servo_explicit = law;
    if (!(b->target >= 0.0))
        return app_config_fail(&L->p, app_config_member(servo, stress ? "stress" : "force"),
                               "%s: the target must be >= 0 (compressive)", name);
    return 0;
}

/* The body keys of group g (`what` names it) into b; w: the wall and k its index, NULL and -1 for
 * a grain body. */
static int parse_body(Loader *L, const config_setting_t *g, const char *what, const SimWall *w,
                      int k, SimWallBody *b)
{
    double force[2] = {0.0, 0.0};
    b->active = 1;
    b->gravity = 1;
    if (!app_config_member(g, "mass") && !app_config_member(g, "servo"))
        return app_config_fail(&L->p, g,
                               "%s: `axis`, `force`, `gravity` and `rotation` need a `mass` or a "
                               "`servo`",
                               what);
    if (app_config_need(&L->p, g, "axis", what) < 0 || parse_axis(L, g, w, b) < 0 ||
        app_config_number(&L->p, g, "mass", &b->mass) < 0 ||
        (app_config_member(g, "mass") && app_config_positive(&L->p, g, "mass", b->mass) < 0) ||
        app_config_vector(&L->p, g, "force", force, 2) < 0 ||
        app_config_bool(&L->p, g, "gravity", &b->gravity) < 0 ||
        app_config_bool(&L->p, g, "rotation", &b->rotation) < 0 ||
        app_config_number(&L->p, g, "inertia", &b->inertia) < 0 ||
        (app_config_member(g, "inertia") &&
         app_config_positive(&L->p, g, "inertia", b->inertia) < 0) ||
        (app_config_member(g, "servo") && parse_servo(L, g, what, k, b) < 0))
        return -1;
    if (app_config_member(g, "inertia") && !b->rotation)
        return app_config_fail(&L->p, app_config_member(g, "inertia"),
                               "%s: `inertia` is for a body that turns (rotation = true)", what);
    if (b->rotation && !app_config_member(g, "mass") && !app_config_member(g, "inertia"))
        return app_config_fail(&L->p, app_config_member(g, "rotation"),
                               "%s: a body that turns needs a `mass` or an `inertia`", what);
    if (b->axis_x == 0.0 && b->axis_y == 0.0 && (!b->rotation || b->servo))
        return app_config_fail(&L->p, app_config_member(g, "axis"),
                               "%s: `axis` = \"none\" is for a body that only turns: it needs "
                               "rotation = true and no servo",
                               what);
    b->force_x = force[0];
    b->force_y = force[1];
    return 0;
}

int loader_parse_wall_body(Loader *L, const config_setting_t *g, const char *what, int k)
{
    static const char *const body_keys[] = {"mass",  "axis",     "force",   "gravity",
                                            "servo", "rotation", "inertia", NULL};
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
    const SimWall *w = &scene->walls[k];
    if (parse_body(L, g, what, w, k, &scene->wall_bodies[k]) < 0)
        return -1;
    scene->def.wall_bodies = scene->wall_bodies;
    return 0;
}

int loader_parse_bodies(Loader *L, const config_setting_t *root)
{
    static const char *const keys[] = {"group", "mass",     "axis",    "force", "gravity",
                                       "servo", "rotation", "inertia", NULL};
    const config_setting_t *list;
    if (app_config_list(&L->p, root, "bodies", &list) <= 0)
        return L->p.failed ? -1 : 0;
    Scene *scene = L->scene;
    const int count = config_setting_length(list);
    scene->grain_bodies = calloc((size_t)(count > 0 ? count : 1), sizeof *scene->grain_bodies);
    scene->body_names = calloc((size_t)(count > 0 ? count : 1), sizeof *scene->body_names);
    if (!scene->grain_bodies || !scene->body_names)
        return app_config_fail(&L->p, list, "out of memory");
    for (int k = 0; k < count; ++k) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
        char what[32], field[32];
        const char *name = NULL;
        snprintf(what, sizeof what, "bodies.%d", k);
        if (app_config_keys(&L->p, g, what, keys, NULL) < 0 ||
            app_config_need(&L->p, g, "group", what) < 0 ||
            app_config_string(&L->p, g, "group", &name) < 0 ||
            parse_body(L, g, what, NULL, -1, &scene->grain_bodies[k]) < 0)
            return -1;
        for (int j = 0; j < k; ++j)
            if (strcmp(scene->body_names[j], name) == 0)
                return app_config_fail(&L->p, app_config_member(g, "group"),
                                       "%s: group `%s` already has a body (bodies.%d)", what, name,
                                       j);
        snprintf(scene->body_names[k], SCENE_NAME_MAX, "%s", name);
        snprintf(field, sizeof field, "bodies[%d]", k);
        loader_where_add(L, field, g);
    }
    scene->def.grain_bodies = scene->grain_bodies;
    scene->def.grain_body_count = count;
    return 0;
}

int loader_get_group(Loader *L, const config_setting_t *g, const char *what, int *motion)
{
    const char *name = NULL;
    if (app_config_string(&L->p, g, "group", &name) <= 0)
        return L->p.failed ? -1 : 0;
    const Scene *scene = L->scene;
    for (int b = 0; b < scene->def.grain_body_count; ++b)
        if (strcmp(scene->body_names[b], name) == 0) {
            if (*motion >= 0)
                return app_config_fail(&L->p, app_config_member(g, "group"),
                                       "%s: the grains of group `%s` move with their body and "
                                       "cannot also follow a motion",
                                       what, name);
            *motion = SIM_GRAIN_BODY(b);
            return 1;
        }
    return app_config_fail(&L->p, app_config_member(g, "group"),
                           "%s: unknown group `%s`: no entry of `bodies` has group = \"%s\"", what,
                           name, name);
}

/* The first added grain of group b at a stage after stage `after` (-1: any stage), with its
 * stage in *stage; NULL when none. */
static const SceneAdd *group_add(const Scene *scene, int b, int after, int *stage)
{
    for (int k = after + 1; k < scene->stage_count; ++k)
        for (int j = 0; j < scene->stages[k].add_count; ++j)
            if (scene->stages[k].adds[j].motion == SIM_GRAIN_BODY(b)) {
                *stage = k;
                return &scene->stages[k].adds[j];
            }
    return NULL;
}

int loader_check_bodies(Loader *L, const config_setting_t *root)
{
    const Scene *scene = L->scene;
    for (int b = 0; b < scene->def.grain_body_count; ++b) {
        const char *name = scene->body_names[b];
        int n = 0, first = -1, later = -1;
        for (int i = 0; i < scene->grains.count; ++i)
            n += scene->grains.motion[i] == SIM_GRAIN_BODY(b);
        const SceneAdd *added = group_add(scene, b, -1, &first);
        if (n == 0 && !added) {
            const config_setting_t *list = app_config_member(root, "bodies");
            return app_config_fail(&L->p, config_setting_get_elem(list, (unsigned)b),
                                   "bodies.%d: group `%s` is empty: no grains.rows, "
                                   "grains.columns or stage `add` entry has group = \"%s\"",
                                   b, name, name);
        }
        if (n > 0 && added)
            return app_config_fail_at(&L->p, added->where,
                                      "stage %s: add: group `%s` has its grains from grains.rows "
                                      "or grains.columns and its body moves from the start: a "
                                      "stage adds the grains of a group that is empty until then "
                                      "(its body dormant), all in one stage",
                                      scene->stages[first].name, name);
        const SceneAdd *again = added ? group_add(scene, b, first, &later) : NULL;
        if (again)
            return app_config_fail_at(&L->p, again->where,
                                      "stage %s: add: group `%s` got its grains at stage %s and "
                                      "its body moves from then on: a body takes no more grains "
                                      "(add them all in one stage)",
                                      scene->stages[later].name, name, scene->stages[first].name);
    }
    return 0;
}
