/* SPDX-License-Identifier: MIT */
/* scene_check.c: where every definition field came from (SimError field -> "file:line"), the
 * start-configuration checks (grains overlapping grains or walls) and scene_validate_def (the
 * time step against the contacts, then sim_world_def_validate with the field mapped back). */
#include "scene/scene_internal.h"
#include "scene/sources.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Start overlaps smaller than this fraction of the smaller radius are tolerated: lattices of
 * touching grains (fixed rows) land on exact contact up to rounding. */
#define OVERLAP_TOLERANCE 0.01

/* ---------------------------------------------------------------- where-mapping */

void loader_where_add(Loader *L, const char *field, const config_setting_t *s)
{
    SceneWhere *w = L->scene->where;
    if (w->count == w->capacity) {
        int capacity = w->capacity ? 2 * w->capacity : 64;
        WhereItem *items = realloc(w->items, (size_t)capacity * sizeof *items);
        if (!items)
            return;
        w->items = items;
        w->capacity = capacity;
    }
    WhereItem *item = &w->items[w->count++];
    snprintf(item->field, sizeof item->field, "%s", field);
    app_config_where(&L->p, s, item->where, sizeof item->where);
}

void loader_where_grains(Loader *L, int first, const config_setting_t *s, const char *field)
{
    SceneWhere *w = L->scene->where;
    int count = L->scene->grains.count;
    if (count > w->grain_capacity) {
        int capacity = count > 2 * w->grain_capacity ? count : 2 * w->grain_capacity;
        int *grow = realloc(w->grain_item, (size_t)capacity * sizeof *grow);
        if (!grow)
            return;
        w->grain_item = grow;
        w->grain_capacity = capacity;
    }
    loader_where_add(L, field, s);
    for (int i = first; i < count; ++i)
        w->grain_item[i] = w->count - 1;
}

/* ---------------------------------------------------------------- start-configuration checks */

typedef struct SortKey {
    double x;
    int i;
} SortKey;

static int compare_keys(const void *a, const void *b)
{
    double xa = ((const SortKey *)a)->x, xb = ((const SortKey *)b)->x;
    return (xa > xb) - (xa < xb);
}

static const char *grain_where(const Scene *scene, int i)
{
    const SceneWhere *w = scene->where;
    if (i >= 0 && i < scene->grains.count && i < w->grain_capacity && w->grain_item)
        return w->items[w->grain_item[i]].where;
    return w->fallback;
}

/* Grains overlapping grains: a sweep over x. */
int loader_check_overlaps(Loader *L)
{
    const Scene *scene = L->scene;
    const SimGrainBuffer *b = &scene->grains;
    int n = b->count;
    SortKey *keys = malloc((size_t)(n > 0 ? n : 1) * sizeof *keys);
    if (!keys)
        return app_config_fail(&L->p, NULL, "out of memory");
    double r_max = 0.0;
    for (int i = 0; i < n; ++i) {
        keys[i] = (SortKey){b->x[i], i};
        r_max = fmax(r_max, b->radius[i]);
    }
    qsort(keys, (size_t)n, sizeof *keys, compare_keys);
    char message[WHERE_MAX + 400];
    for (int a = 0; a < n; ++a) {
        int i = keys[a].i;
        for (int c = a + 1; c < n && keys[c].x - keys[a].x < b->radius[i] + r_max; ++c) {
            int j = keys[c].i;
            if ((b->flags[i] & SIM_GRAIN_FIXED) && (b->flags[j] & SIM_GRAIN_FIXED))
                continue;
            double d = hypot(b->x[j] - b->x[i], b->y[j] - b->y[i]);
            double overlap = b->radius[i] + b->radius[j] - d;
            if (overlap > OVERLAP_TOLERANCE * fmin(b->radius[i], b->radius[j])) {
                int late = i > j ? i : j, early = i > j ? j : i;
                snprintf(message, sizeof message,
                         "grain %d at (%g, %g) overlaps grain %d at (%g, %g) by %g m at the start "
                         "(%s)",
                         late, b->x[late], b->y[late], early, b->x[early], b->y[early], overlap,
                         grain_where(scene, early));
                free(keys);
                return app_config_fail_at(&L->p, grain_where(scene, late), "%s", message);
            }
        }
    }
    free(keys);
    for (int w = 0; w < scene->def.wall_count; ++w) {
        const SimWall *wall = &scene->walls[w];
        double ex = wall->x1 - wall->x0, ey = wall->y1 - wall->y0;
        double length2 = ex * ex + ey * ey;
        for (int i = 0; i < n; ++i) {
            if (b->flags[i] & SIM_GRAIN_FIXED)
                continue;
            double t = ((b->x[i] - wall->x0) * ex + (b->y[i] - wall->y0) * ey) / length2;
            t = fmin(1.0, fmax(0.0, t));
            double d = wall->shape == SIM_WALL_ARC
                           ? sim_wall_contact_distance(wall, b->x[i], b->y[i], b->radius[i])
                           : hypot(b->x[i] - (wall->x0 + t * ex), b->y[i] - (wall->y0 + t * ey));
            if (b->radius[i] - d > OVERLAP_TOLERANCE * b->radius[i]) {
                char field[32];
                snprintf(field, sizeof field, "walls[%d]", w);
                snprintf(message, sizeof message,
                         "grain %d at (%g, %g) overlaps wall %d by %g m at the start (%s)", i,
                         b->x[i], b->y[i], w, b->radius[i] - d, scene_where_field(scene, 0, field));
                return app_config_fail_at(&L->p, grain_where(scene, i), "%s", message);
            }
        }
    }
    return 0;
}

/* ---------------------------------------------------------------- views */

/* The smallest grain radius of the scene, else of its sources' grains; 0 when it has neither. */
static double smallest_radius(const Scene *scene)
{
    double r = INFINITY;
    for (int i = 0; i < scene->grains.count; ++i)
        r = fmin(r, scene->grains.radius[i]);
    for (int k = 0; k < scene->source_count && scene->grains.count == 0; ++k) {
        const SceneSource *s = &scene->sources[k];
        for (int j = 0; j < s->radii_count; ++j) /* a list of radii, else a mixture's ranges */
            r = fmin(r, s->radii[j]);
        for (int j = 0; j < s->mixture_count && s->radii_count == 0; ++j)
            r = fmin(r, s->radius_min[j]);
    }
    return isfinite(r) ? r : 0.0;
}

/* The view of `group` (when it has one) against the smallest radius r. 0, or -1. */
static int check_view(Loader *L, const config_setting_t *group, double r)
{
    double v[4];
    if (!group || !app_config_member(group, "view") ||
        app_config_vector(&L->p, group, "view", v, 4) <= 0)
        return L->p.failed ? -1 : 0;
    double w = v[2] - v[0], h = v[3] - v[1];
    if (w >= 0.1 * r && h >= 0.1 * r && w <= 1e9 * r && h <= 1e9 * r)
        return 0;
    return app_config_fail(&L->p, app_config_member(group, "view"),
                           "`view` of %g x %g m: each side must be within [0.1, 1e9] times the "
                           "smallest grain radius %g m",
                           w, h, r);
}

int loader_check_views(Loader *L)
{
    const double r = smallest_radius(L->scene);
    if (!(r > 0.0)) /* nothing to draw at any scale */
        return 0;
    if (check_view(L, config_lookup(&L->config, "render"), r) < 0)
        return -1;
    const char *lists[] = {"output.figures", "stages"};
    for (int l = 0; l < 2; ++l) {
        const config_setting_t *list = config_lookup(&L->config, lists[l]);
        int n = list && config_setting_is_aggregate(list) ? config_setting_length(list) : 0;
        for (int k = 0; k < n; ++k) {
            const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
            if (config_setting_is_group(g) && check_view(L, g, r) < 0)
                return -1;
        }
    }
    return 0;
}

/* ---------------------------------------------------------------- definitions */

int scene_validate_def(const Scene *scene, int stage, const SimWorldDef *def, char *err,
                       size_t err_size)
{
    SimError error;
    memset(&error, 0, sizeof error);
    /* The time step against the declared contacts: a clear message before sim's own checks. */
    if (def->time_step > 0.0 && def->grains.count > 0) {
        SimTiming timing = sim_world_def_timing(def);
        if (timing.stability_limit > 0.0 && def->time_step > timing.stability_limit) {
            snprintf(err, err_size,
                     "%s: time step %g s is above the stability limit %g s of the declared "
                     "contacts (shortest contact time %g s)",
                     scene->where->stage_dt[stage], def->time_step, timing.stability_limit,
                     timing.contact_time_min);
            return -1;
        }
        if (def->max_dt_fraction > 0.0 && timing.contact_time_min > 0.0 &&
            def->time_step > def->max_dt_fraction * timing.contact_time_min) {
            snprintf(err, err_size,
                     "%s: time step %g s is above max_dt_fraction %g of the shortest contact "
                     "time %g s",
                     scene->where->stage_dt[stage], def->time_step, def->max_dt_fraction,
                     timing.contact_time_min);
            return -1;
        }
    }
    if (sim_world_def_validate(def, &error) != SIM_OK) {
        snprintf(err, err_size, "%s: %s", scene_where_field(scene, stage, error.field),
                 error.message);
        return -1;
    }
    return 0;
}

const char *scene_where_field(const Scene *scene, int stage, const char *field)
{
    const SceneWhere *w = scene->where;
    if (stage < 0 || stage >= scene->stage_count)
        stage = 0;
    if (!field || !field[0])
        return w->fallback;
    if (strncmp(field, "grains[", 7) == 0) {
        if (scene->stages[stage].load != SCENE_LOAD_SCENE)
            return w->stage_load[stage];
        return grain_where(scene, atoi(field + 7));
    }
    if (strcmp(field, "time_step") == 0)
        return w->stage_dt[stage];
    char path[64];
    snprintf(path, sizeof path, "%s", field);
    while (path[0]) {
        for (int k = w->count - 1; k >= 0; --k)
            if (strcmp(w->items[k].field, path) == 0)
                return w->items[k].where;
        /* strip the last component: ".name" or "[k]" */
        size_t n = strlen(path);
        char *cut = NULL;
        if (path[n - 1] == ']')
            cut = strrchr(path, '[');
        else
            cut = strrchr(path, '.');
        if (!cut)
            break;
        *cut = '\0';
    }
    return w->fallback;
}
