/* SPDX-License-Identifier: MIT */
/* stage_adds.c: grains a stage places at its start (docs/scenes.md#grains-added-by-a-stage):
 *
 *     stages = ( { name = "drop"; add = ( { name = "projectile"; x = 0.5; y = 1.2; vy = -3.0;
 *                                             radius = 0.02; species = "steel"; } ); } );
 *
 * Their ids are fixed when the scene loads, so that `trace`, `remove_ids` and the dumps can name
 * them before the run: the added grains of every stage, in stage order and list order, take the
 * ids that follow the largest id of the scene's own grains (max + 1, max + 2, ...); a source's
 * grains are inserted above them (app/scene/sources.c). A grain is placed exactly where the scene
 * says or not at all: any overlap with a wall, a grain of the world or another added grain refuses
 * it (at load where the loader knows the world: the first stage built from the scene; else as the
 * stage starts, exit 2 at the entry's file:line). */
#include "scene/scene_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Overlaps below this fraction of the smaller radius are contact: a grain placed touching another
 * (its centre computed from theirs) lands on it up to rounding. */
#define TOUCH_TOLERANCE 1e-9

/* One entry of `add`: name, position, velocity, radius, species. 0, or -1. */
static int parse_add(Loader *L, const config_setting_t *e, SceneAdd *a, const char *what)
{
    static const char *const keys[] = {"name",  "x",      "y",       "vx",    "vy",
                                       "omega", "radius", "species", "group", NULL};
    const char *name = NULL;
    a->motion = -1;
    if (app_config_keys(&L->p, e, what, keys, NULL) < 0 ||
        app_config_need_number(&L->p, e, "x", what, &a->x) < 0 ||
        app_config_need_number(&L->p, e, "y", what, &a->y) < 0 ||
        app_config_need_number(&L->p, e, "radius", what, &a->radius) < 0 ||
        app_config_positive(&L->p, e, "radius", a->radius) < 0 ||
        app_config_number(&L->p, e, "vx", &a->vx) < 0 ||
        app_config_number(&L->p, e, "vy", &a->vy) < 0 ||
        app_config_number(&L->p, e, "omega", &a->omega) < 0 ||
        loader_get_species(L, e, &a->species) < 0 ||
        app_config_string(&L->p, e, "name", &name) < 0 ||
        loader_get_group(L, e, what, &a->motion) < 0)
        return -1;
    static const char *const moving[] = {"vx", "vy", "omega"};
    for (int k = 0; a->motion < -1 && k < 3; ++k)
        if (app_config_member(e, moving[k]))
            return app_config_fail(&L->p, app_config_member(e, moving[k]),
                                   "%s: `%s`: a grain of a group moves with its body (it is put "
                                   "at rest; give the body a force or a servo)",
                                   what, moving[k]);
    if (name && (!name[0] || strlen(name) >= sizeof a->name))
        return app_config_fail(&L->p, app_config_member(e, "name"),
                               "%s: `name` must have 1 to %d characters", what,
                               (int)sizeof a->name - 1);
    if (name && loader_check_file_name(L, e, "name", name) < 0)
        return -1;
    snprintf(a->name, sizeof a->name, "%s", name ? name : "");
    app_config_where(&L->p, e, a->where, sizeof a->where);
    return 0;
}

int loader_parse_adds(Loader *L, const config_setting_t *g, int k)
{
    SceneStage *stage = &L->scene->stages[k];
    const config_setting_t *list = NULL;
    if (app_config_list(&L->p, g, "add", &list) < 0)
        return -1;
    if (!list)
        return 0;
    int n = config_setting_length(list);
    if (n > SCENE_MAX_ADDS)
        return app_config_fail(&L->p, list, "`add` lists %d grains: at most %d", n, SCENE_MAX_ADDS);
    stage->adds = calloc((size_t)(n > 0 ? n : 1), sizeof *stage->adds);
    if (!stage->adds)
        return app_config_fail(&L->p, list, "out of memory");
    char what[SCENE_NAME_MAX + 32];
    snprintf(what, sizeof what, "stage %s: add", stage->name);
    for (int j = 0; j < n; ++j) {
        if (parse_add(L, config_setting_get_elem(list, (unsigned)j), &stage->adds[j], what) < 0)
            return -1;
        stage->add_count = j + 1;
    }
    return 0;
}

/* The thing added grain `a` overlaps among n grains (x, y, radius, id; NULL x: none), walls and
 * the stage's added grains before it (adds[0..before)): 1 with its description in what, else 0.
 * periodic: x wraps over [x0, x1]. */
typedef struct AddWorld {
    int count;
    const double *x, *y, *radius;
    const uint32_t *id;
    int wall_count;
    const SimWall *walls;
    int periodic;
    double x0, x1;
} AddWorld;

static int pair_overlap(const AddWorld *w, double xa, double ya, double ra, double xb, double yb,
                        double rb)
{
    double dx = xa - xb;
    if (w->periodic && w->x1 > w->x0)
        dx -= (w->x1 - w->x0) * floor(dx / (w->x1 - w->x0) + 0.5);
    return ra + rb - hypot(dx, ya - yb) > TOUCH_TOLERANCE * fmin(ra, rb);
}

static int add_overlaps(const AddWorld *w, const SceneAdd *adds, int index, char *what, size_t size)
{
    const SceneAdd *a = &adds[index];
    for (int i = 0; i < w->count; ++i)
        if (pair_overlap(w, a->x, a->y, a->radius, w->x[i], w->y[i], w->radius[i])) {
            snprintf(what, size, "grain %u at (%g, %g), radius %g", w->id[i], w->x[i], w->y[i],
                     w->radius[i]);
            return 1;
        }
    for (int k = 0; k < w->wall_count; ++k)
        if (a->radius - sim_wall_contact_distance(&w->walls[k], a->x, a->y, a->radius) >
            TOUCH_TOLERANCE * a->radius) {
            snprintf(what, size, "wall %d", k);
            return 1;
        }
    for (int j = 0; j < index; ++j)
        if (pair_overlap(w, a->x, a->y, a->radius, adds[j].x, adds[j].y, adds[j].radius)) {
            snprintf(what, size, "the added grain %u at (%g, %g) (%s)", adds[j].id, adds[j].x,
                     adds[j].y, adds[j].where);
            return 1;
        }
    return 0;
}

static const char *add_label(const SceneAdd *a, char *buf, size_t size)
{
    if (a->name[0])
        snprintf(buf, size, "`%s` (id %u)", a->name, a->id);
    else
        snprintf(buf, size, "%u", a->id);
    return buf;
}

/* The stage's added grains against a world w: 0, or -1 with "file:line: ..." in err. */
static int check_adds(const Scene *scene, int k, const AddWorld *w, char *err, size_t size)
{
    const SceneStage *stage = &scene->stages[k];
    char what[SCENE_PATH_MAX + 160], label[SCENE_NAME_MAX + 32];
    for (int j = 0; j < stage->add_count; ++j) {
        const SceneAdd *a = &stage->adds[j];
        for (int i = 0; i < w->count; ++i)
            if (w->id[i] == a->id) {
                snprintf(err, size,
                         "%s: stage %s: added grain %s: the id is taken by a grain of the world "
                         "(a state loaded by `load` holds it)",
                         a->where, stage->name, add_label(a, label, sizeof label));
                return -1;
            }
        if (add_overlaps(w, stage->adds, j, what, sizeof what)) {
            snprintf(err, size,
                     "%s: stage %s: added grain %s at (%g, %g), radius %g, overlaps %s: an added "
                     "grain is placed exactly where it is given, or not at all",
                     a->where, stage->name, add_label(a, label, sizeof label), a->x, a->y,
                     a->radius, what);
            return -1;
        }
    }
    return 0;
}

/* The largest id of the scene's own grains plus one (0 without grains). */
static uint64_t scene_id_end(const Scene *scene)
{
    const SimGrainBuffer *b = &scene->grains;
    uint64_t end = 0;
    for (int i = 0; i < b->count; ++i) {
        uint64_t id = b->id ? b->id[i] : (uint32_t)i;
        end = id + 1 > end ? id + 1 : end;
    }
    return end;
}

int loader_assign_add_ids(Loader *L)
{
    Scene *scene = L->scene;
    uint64_t next = scene_id_end(scene);
    int total = 0;
    for (int k = 0; k < scene->stage_count; ++k)
        for (int j = 0; j < scene->stages[k].add_count; ++j, ++next, ++total) {
            SceneAdd *a = &scene->stages[k].adds[j];
            if (next >= UINT32_MAX)
                return app_config_fail_at(&L->p, a->where, "no grain id left for this grain");
            a->id = (uint32_t)next;
            for (int m = 0; a->name[0] && m <= k; ++m)
                for (int i = 0; i < (m < k ? scene->stages[m].add_count : j); ++i)
                    if (strcmp(scene->stages[m].adds[i].name, a->name) == 0)
                        return app_config_fail_at(&L->p, a->where,
                                                  "added grain name `%s` is used twice (%s)",
                                                  a->name, scene->stages[m].adds[i].where);
        }
    scene->added_id_end = total > 0 ? (uint32_t)next : 0;
    /* the first stage built from the scene: its world is known now */
    const SceneStage *first = &scene->stages[0];
    AddWorld w = {.count = first->load == SCENE_LOAD_SCENE ? scene->grains.count : 0,
                  .x = scene->grains.x,
                  .y = scene->grains.y,
                  .radius = scene->grains.radius,
                  .id = scene->grains.id,
                  .wall_count = scene->def.wall_count,
                  .walls = scene->walls,
                  .periodic = (scene->def.effects & SIM_EFFECT_PERIODIC_X) != 0,
                  .x0 = scene->def.domain_x0,
                  .x1 = scene->def.domain_x1};
    if (first->load == SCENE_LOAD_SCENE && check_adds(scene, 0, &w, L->p.err, L->p.err_size) != 0)
        return -1;
    for (int k = 1; k < scene->stage_count; ++k) { /* among themselves, whatever the world */
        AddWorld none = {.periodic = w.periodic, .x0 = w.x0, .x1 = w.x1};
        if (check_adds(scene, k, &none, L->p.err, L->p.err_size) != 0)
            return -1;
    }
    return 0;
}

const SceneAdd *scene_added_grain(const Scene *scene, const char *name, uint32_t id)
{
    for (int k = 0; k < scene->stage_count; ++k)
        for (int j = 0; j < scene->stages[k].add_count; ++j) {
            const SceneAdd *a = &scene->stages[k].adds[j];
            if (name ? a->name[0] && strcmp(a->name, name) == 0 : a->id == id)
                return a;
        }
    return NULL;
}

int scene_stage_add(const Scene *scene, int k, SimWorld *world, char *err, size_t err_size)
{
    const SceneStage *stage = &scene->stages[k];
    if (stage->add_count == 0)
        return 0;
    SimFrame f;
    sim_world_frame(world, &f);
    AddWorld w = {.count = f.count,
                  .x = f.x,
                  .y = f.y,
                  .radius = f.radius,
                  .id = f.id,
                  .wall_count = f.wall_count,
                  .walls = f.walls,
                  .periodic = f.periodic,
                  .x0 = f.domain_x0,
                  .x1 = f.domain_x1};
    if (check_adds(scene, k, &w, err, err_size) != 0)
        return -1;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    for (int j = 0; j < stage->add_count; ++j) {
        const SceneAdd *a = &stage->adds[j];
        const unsigned fixed = a->motion < -1 ? SIM_GRAIN_FIXED : 0u; /* a body's grain */
        int i = sim_grain_buffer_add(&b, a->x, a->y, a->radius, a->species, fixed, a->motion);
        b.vx[i] = a->vx;
        b.vy[i] = a->vy;
        b.omega[i] = a->omega;
        b.id[i] = a->id;
    }
    SimGrainSet set = sim_grain_buffer_view(&b);
    SimError error;
    int rc = sim_world_add_grains(world, &set, &error) == SIM_OK ? 0 : -1;
    if (rc != 0) {
        int j = 0, body = -1;
        sscanf(error.field, "grains[%d]", &j);
        if (sscanf(error.field, "bodies[%d]", &body) == 1) /* the group's first grain */
            for (j = 0; j < stage->add_count && stage->adds[j].motion != SIM_GRAIN_BODY(body);)
                ++j;
        snprintf(err, err_size, "%s: stage %s: added grain: %s",
                 stage->adds[j >= 0 && j < stage->add_count ? j : 0].where, stage->name,
                 error.message);
    }
    sim_grain_buffer_free(&b);
    return rc;
}
