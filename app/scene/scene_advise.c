/* SPDX-License-Identifier: MIT */
/* scene_advise.c: what `sablier check` says about a scene that loads but may not do what its
 * author meant (docs/scenes.md): the tangential law in use (the regularised law has no static
 * friction), and warnings on stderr, "file:line: warning: ...", for motions that move nothing
 * (declared but followed by no wall and no fixed grain) and for stages that enable such a
 * motion (a part of a composition, which runs on the composition's clock; a wall that responds
 * to the grains follows no motion). */
#include "scene/scene_internal.h"

#include <stdio.h>
#include <string.h>

void scene_describe_friction(const Scene *scene, FILE *out)
{
    if (!(scene->def.effects & SIM_EFFECT_FRICTION)) {
        fprintf(out, "friction none (effect \"friction\" not declared: frictionless contacts)\n");
        return;
    }
    switch (scene->def.contact.tangential) {
    case SIM_TANGENTIAL_REGULARISED:
        fprintf(out, "friction regularised Coulomb, F_t = min(gamma_s |v_s|, mu F_n): no static "
                     "friction (a contact at rest carries no tangential force; piles creep, "
                     "silo walls carry no weight); contact.tangential = \"spring\" has it\n");
        break;
    case SIM_TANGENTIAL_SPRING: {
        int damped = 0;
        for (int k = 0; k < scene->def.species_count; ++k)
            damped |= scene->def.materials[k].spring_damping > 0.0;
        fprintf(out,
                "friction spring (Cundall-Strack), |F_t| <= mu F_n: static friction; tangential "
                "dashpot gamma_t %s\n",
                damped ? "set" : "0 (none)");
        break;
    }
    case SIM_TANGENTIAL_NONE:
    default:
        fprintf(out, "friction none (contact.tangential = \"none\")\n");
        break;
    }
}

/* Bit m: motion m is followed by a wall or a fixed grain. */
static unsigned followed_motions(const Scene *scene)
{
    unsigned direct = 0;
    for (int k = 0; k < scene->def.wall_count; ++k)
        if (scene->walls[k].motion >= 0)
            direct |= 1u << scene->walls[k].motion;
    for (int i = 0; scene->grains.motion && i < scene->grains.count; ++i)
        if (scene->grains.motion[i] >= 0)
            direct |= 1u << scene->grains.motion[i];
    return direct;
}

/* The followed composition (the last defined) that has motion m among its parts, or -1. */
static int holder(const Scene *scene, unsigned used, int m)
{
    for (int c = scene->def.motion_count - 1; c > m; --c) {
        const SimMotion *mo = &scene->def.motions[c];
        for (int p = 0; mo->kind == SIM_MOTION_COMPOSE && (used >> c) & 1u && p < mo->part_count;
             ++p)
            if (mo->parts[p] == m)
                return c;
    }
    return -1;
}

/* The walls that respond to the grains (a mass or a servo) and follow no motion, as "walls 1, 3",
 * into text. */
static void responding_walls(const Scene *scene, char *text, size_t size)
{
    size_t n = 0;
    text[0] = '\0';
    for (int k = 0; scene->wall_bodies && k < scene->def.wall_count && n < size; ++k)
        if (scene->wall_bodies[k].active && scene->walls[k].motion < 0)
            n += (size_t)snprintf(text + n, size - n, "%s%d", n ? ", " : "; walls ", k);
    if (n && n < size)
        snprintf(text + n, size - n,
                 " respond to the grains (a mass or a servo) and follow no "
                 "motion");
}

int scene_warn(const Scene *scene, FILE *out)
{
    const SceneWhere *w = scene->where;
    const unsigned direct = followed_motions(scene);
    unsigned used = direct; /* compositions name motions defined before them */
    for (int c = scene->def.motion_count - 1; c >= 0; --c)
        for (int p = 0; scene->def.motions[c].kind == SIM_MOTION_COMPOSE && (used >> c) & 1u &&
                        p < scene->def.motions[c].part_count;
             ++p)
            used |= 1u << scene->def.motions[c].parts[p];
    int warnings = 0;
    for (int m = 0; m < scene->def.motion_count; ++m)
        if (!((used >> m) & 1u)) {
            fprintf(out,
                    "%s: warning: motion `%s` moves nothing: no wall or fixed grain follows it, "
                    "nor a composition that one follows\n",
                    w->motion[m], scene->motion_names[m]);
            ++warnings;
        }
    char bodies[256];
    responding_walls(scene, bodies, sizeof bodies);
    for (int k = 0; k < scene->stage_count; ++k) {
        const SceneStage *s = &scene->stages[k];
        if (!s->declares_motions)
            break;
        for (int m = 0; m < scene->def.motion_count; ++m) {
            if (!((s->motions >> m) & 1u) || ((direct >> m) & 1u))
                continue;
            const int c = holder(scene, used, m);
            char held[256] = "";
            if (c >= 0)
                snprintf(held, sizeof held,
                         ": what it moves follows motion `%s`, which runs its parts on its own "
                         "clock (enable `%s`)",
                         scene->motion_names[c], scene->motion_names[c]);
            fprintf(out, "%s: warning: stage `%s` enables motion `%s`, which moves nothing%s%s\n",
                    w->stage_motions[k][0] ? w->stage_motions[k] : w->stage_load[k], s->name,
                    scene->motion_names[m], held, bodies);
            ++warnings;
        }
    }
    return warnings;
}
