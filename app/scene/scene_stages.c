/* SPDX-License-Identifier: MIT */
/* scene_stages.c: the scene's `stages` list (docs/scenes.md): each stage's name, where its
 * grains come from (`load`), its time, settle test, removals and movie flag. A scene without
 * `stages` has one stage, "run". */
#include "base/util.h"
#include "scene/scene_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int parse_stage_time(Loader *L, const config_setting_t *time, SceneStage *stage)
{
    static const char *const keys[] = {"dt", "end", NULL};
    if (app_config_keys(&L->p, time, "stage time", keys, NULL) < 0 ||
        app_config_number(&L->p, time, "dt", &stage->time_step) < 0 ||
        app_config_non_negative(&L->p, time, "dt", stage->time_step) < 0 ||
        app_config_number(&L->p, time, "end", &stage->duration) < 0 ||
        app_config_non_negative(&L->p, time, "end", stage->duration) < 0)
        return -1;
    return 0;
}

/* time: the stage's own `time` group (g may be NULL) on top of the scene's `time`. */
static int parse_times(Loader *L, const config_setting_t *g, int k, const config_setting_t *time)
{
    Scene *scene = L->scene;
    SceneStage *stage = &scene->stages[k];
    stage->time_step = scene->def.time_step;
    stage->duration = 0.0;
    if (app_config_number(&L->p, time, "end", &stage->duration) < 0 ||
        app_config_non_negative(&L->p, time, "end", stage->duration) < 0)
        return -1;
    const config_setting_t *dt_setting = app_config_member(time, "dt");
    const config_setting_t *stage_time = NULL;
    if (app_config_group(&L->p, g, "time", &stage_time) < 0)
        return -1;
    if (stage_time) {
        if (parse_stage_time(L, stage_time, stage) < 0)
            return -1;
        if (app_config_member(stage_time, "dt"))
            dt_setting = app_config_member(stage_time, "dt");
    }
    app_config_where(&L->p, dt_setting, scene->where->stage_dt[k], WHERE_MAX);
    app_config_where(&L->p, g ? g : time, scene->where->stage_load[k], WHERE_MAX);
    return 0;
}

/* A checkpoint file named by `load`, relative to the scene's folder; it must be readable. */
static int checkpoint_path(Loader *L, const config_setting_t *g, const char *load,
                           SceneStage *stage)
{
    size_t dir_length = load[0] == '/' ? 0 : strlen(L->dir) + 1;
    if (dir_length + strlen(load) >= sizeof stage->load_path)
        return app_config_fail(&L->p, app_config_member(g, "load"), "checkpoint path too long");
    if (dir_length) {
        memcpy(stage->load_path, L->dir, dir_length - 1);
        stage->load_path[dir_length - 1] = '/';
    }
    memcpy(stage->load_path + dir_length, load, strlen(load) + 1);
    /* the whole state read now, so that a bad file (grains the scene lacks, or walls that are not
       the scene's) stops the run before any stage */
    char why[1200];
    if (app_state_check(stage->load_path, &L->scene->def, why, sizeof why) != 0)
        return app_config_fail(&L->p, app_config_member(g, "load"), "%s", why);
    return 0;
}

/* load = "previous" | "scene" | "none" | a checkpoint file. */
static int parse_load(Loader *L, const config_setting_t *g, int k)
{
    SceneStage *stage = &L->scene->stages[k];
    const char *load = NULL;
    stage->load = k == 0 ? SCENE_LOAD_SCENE : SCENE_LOAD_PREVIOUS;
    if (app_config_string(&L->p, g, "load", &load) < 0)
        return -1;
    if (!load)
        return 0;
    app_config_where(&L->p, app_config_member(g, "load"), L->scene->where->stage_load[k],
                     WHERE_MAX);
    if (strcmp(load, "previous") == 0) {
        if (k == 0)
            return app_config_fail(&L->p, app_config_member(g, "load"),
                                   "the first stage has no previous stage");
        stage->load = SCENE_LOAD_PREVIOUS;
    } else if (strcmp(load, "none") == 0 || strcmp(load, "scene") == 0) {
        stage->load = SCENE_LOAD_SCENE;
    } else {
        stage->load = SCENE_LOAD_FILE;
        return checkpoint_path(L, g, load, stage);
    }
    return 0;
}

/* settle = { kinetic_below (J) | kinetic_per_grain_below (J); after (s); hold (s); }: 000 §4.1
 * stop when E_kin + E_rot < tol; with `hold`, when it stays below at every energy row for that
 * long (a window, not one sample: an oscillating column passes through troughs). */
static int parse_settle(Loader *L, const config_setting_t *g, SceneStage *stage)
{
    static const char *const settle_keys[] = {"kinetic_below", "kinetic_per_grain_below", "after",
                                              "hold", NULL};
    const config_setting_t *settle;
    stage->settle_after = 0.2;
    if (app_config_group(&L->p, g, "settle", &settle) < 0 ||
        app_config_keys(&L->p, settle, "settle", settle_keys, NULL) < 0)
        return -1;
    if (!settle)
        return 0;
    const int total = app_config_member(settle, "kinetic_below") != NULL;
    if (total == (app_config_member(settle, "kinetic_per_grain_below") != NULL))
        return app_config_fail(&L->p, settle,
                               "settle: give one of `kinetic_below` (J, all grains) or "
                               "`kinetic_per_grain_below` (J per mobile grain)");
    const char *level = total ? "kinetic_below" : "kinetic_per_grain_below";
    double *value = total ? &stage->settle_kinetic : &stage->settle_per_grain;
    if (app_config_number(&L->p, settle, level, value) < 0 ||
        app_config_positive(&L->p, settle, level, *value) < 0 ||
        app_config_number(&L->p, settle, "after", &stage->settle_after) < 0 ||
        app_config_non_negative(&L->p, settle, "after", stage->settle_after) < 0 ||
        app_config_number(&L->p, settle, "hold", &stage->settle_hold) < 0 ||
        app_config_non_negative(&L->p, settle, "hold", stage->settle_hold) < 0)
        return -1;
    return 0;
}

/* remove_ids = [id, ...]: grains removed at the stage start. */
static int parse_remove_ids(Loader *L, const config_setting_t *g, SceneStage *stage)
{
    const config_setting_t *ids = app_config_member(g, "remove_ids");
    if (!ids)
        return 0;
    if (config_setting_type(ids) != CONFIG_TYPE_ARRAY)
        return app_config_fail(&L->p, ids, "`remove_ids` must be an array of grain ids");
    int n = config_setting_length(ids);
    stage->remove_ids = calloc((size_t)(n > 0 ? n : 1), sizeof *stage->remove_ids);
    if (!stage->remove_ids)
        return app_config_fail(&L->p, ids, "out of memory");
    for (int j = 0; j < n; ++j) {
        const config_setting_t *e = config_setting_get_elem(ids, (unsigned)j);
        if (config_setting_type(e) != CONFIG_TYPE_INT || config_setting_get_int(e) < 0)
            return app_config_fail(&L->p, e, "`remove_ids` must list grain ids (integers >= 0)");
        stage->remove_ids[j] = (uint32_t)config_setting_get_int(e);
    }
    stage->remove_count = n;
    return 0;
}

/* `effects = [...]` of a stage: a subset of the scene's effects, with its periodic_x and
 * vibration (those change the domain and what moves: stop motions with `motions = []`). */
static int parse_stage_effects(Loader *L, const config_setting_t *g, SceneStage *stage)
{
    const config_setting_t *s = app_config_member(g, "effects");
    if (!s)
        return 0;
    if (!config_setting_is_aggregate(s))
        return app_config_fail(&L->p, s,
                               "`effects` must be an array of names, e.g. [\"friction\"]");
    unsigned effects = 0;
    for (int k = 0; k < config_setting_length(s); ++k) {
        const char *name = config_setting_get_string_elem(s, (unsigned)k);
        unsigned bit = name ? sim_effect_from_name(name) : 0;
        if (!bit)
            return app_config_fail(&L->p, s, "unknown effect `%s`", name ? name : "(not a string)");
        if (!(L->scene->def.effects & bit))
            return app_config_fail(&L->p, s,
                                   "effect `%s` is not among the scene's `effects`: a stage "
                                   "chooses a subset of them",
                                   name);
        effects |= bit;
    }
    const unsigned fixed = SIM_EFFECT_PERIODIC_X | SIM_EFFECT_VIBRATION | SIM_EFFECT_FLUID_DRAG;
    if ((effects & fixed) != (L->scene->def.effects & fixed))
        return app_config_fail(&L->p, s,
                               "a stage keeps the scene's periodic_x, vibration and fluid_drag "
                               "(stop motions with `motions = []`)");
    stage->effects = effects;
    return 0;
}

/* The motions named by the list `key` of stage g as bits into *mask: 1 when listed, 0 when
 * absent, -1 after an error. */
static int motion_list(Loader *L, const config_setting_t *g, const char *key, unsigned *mask)
{
    const config_setting_t *s = app_config_member(g, key);
    if (!s)
        return 0;
    if (!config_setting_is_aggregate(s))
        return app_config_fail(&L->p, s, "`%s` must list motion names, e.g. [\"shake\"]", key);
    if (loader_gate(L, g, key, SIM_EFFECT_VIBRATION) < 0)
        return -1;
    unsigned motions = 0;
    for (int k = 0; k < config_setting_length(s); ++k) {
        const char *name = config_setting_get_string_elem(s, (unsigned)k);
        int found = -1;
        for (int m = 0; name && m < L->scene->def.motion_count; ++m)
            if (strcmp(L->scene->motion_names[m], name) == 0)
                found = m;
        if (found < 0)
            return app_config_fail(&L->p, s, "`%s`: no motion named `%s` in `motions`", key,
                                   name ? name : "(not a string)");
        motions |= 1u << found;
    }
    *mask = motions;
    return 1;
}

/* `motions = ["shake"]`: the motions enabled in the stage (the others are stopped);
 * `restart_motions = ["press"]`: those among them whose clock starts again from 0 (the others
 * keep theirs across stages). */
static int parse_stage_motions(Loader *L, const config_setting_t *g, int k)
{
    SceneStage *stage = &L->scene->stages[k];
    int listed = motion_list(L, g, "motions", &stage->motions);
    int restarts = listed < 0 ? -1 : motion_list(L, g, "restart_motions", &stage->restart_motions);
    if (restarts < 0)
        return -1;
    const unsigned idle = stage->restart_motions & ~stage->motions;
    for (int m = 0; idle && m < L->scene->def.motion_count; ++m)
        if ((idle >> m) & 1u)
            return app_config_fail(&L->p, app_config_member(g, "restart_motions"),
                                   "`restart_motions`: motion `%s` is not enabled in stage `%s` "
                                   "(list it in its `motions`)",
                                   L->scene->motion_names[m], stage->name);
    if (listed || restarts) /* the line of the list, for `sablier check`'s warnings */
        app_config_where(&L->p, app_config_member(g, listed ? "motions" : "restart_motions"),
                         L->scene->where->stage_motions[k], WHERE_MAX);
    return listed || restarts;
}

/* The stage's forcing: its own keys on top of the previous stage's (the scene's). */
static int parse_forcing(Loader *L, const config_setting_t *g, int k)
{
    Scene *scene = L->scene;
    SceneStage *stage = &scene->stages[k];
    const SceneStage *previous = k > 0 ? &scene->stages[k - 1] : NULL;
    stage->gravity_x = previous ? previous->gravity_x : scene->def.gravity_x;
    stage->gravity_y = previous ? previous->gravity_y : scene->def.gravity_y;
    stage->effects = previous ? previous->effects : scene->def.effects;
    stage->motions = previous ? previous->motions : (1u << scene->def.motion_count) - 1u;
    double gravity[2] = {stage->gravity_x, stage->gravity_y};
    if (app_config_vector(&L->p, g, "gravity", gravity, 2) < 0 ||
        parse_stage_effects(L, g, stage) < 0)
        return -1;
    stage->gravity_x = gravity[0];
    stage->gravity_y = gravity[1];
    int listed = parse_stage_motions(L, g, k);
    if (listed < 0)
        return -1;
    if (listed)
        for (int j = 0; j < SCENE_MAX_STAGES; ++j)
            scene->stages[j].declares_motions = 1;
    return 0;
}

/* Stage k from group g (NULL: the single stage of a scene without `stages`). */
static int parse_stage(Loader *L, const config_setting_t *g, int k, const config_setting_t *time)
{
    static const char *const keys[] = {"name",    "load", "time",    "settle",  "remove_ids",
                                       "movie",   "skip", "gravity", "effects", "restart_motions",
                                       "motions", "dump", "view",    "add",     NULL};
    Scene *scene = L->scene;
    SceneStage *stage = &scene->stages[k];
    char what[96];
    snprintf(what, sizeof what, "stage %d", k);
    const char *name = "run";
    if (g && (app_config_keys(&L->p, g, what, keys, loader_family_keys(1)) < 0 ||
              app_config_need(&L->p, g, "name", what) < 0 ||
              app_config_string(&L->p, g, "name", &name) < 0 ||
              loader_check_file_name(L, g, "name", name) < 0))
        return -1;
    if (strchr(name, '.')) /* STAGE.state, STAGE.last_good.state: a dot makes them collide */
        return app_config_fail(&L->p, app_config_member(g, "name"),
                               "stage name `%s` must not contain `.` (its files are "
                               "<stage>.state, <stage>.last_good.state, <stage>.mp4)",
                               name);
    snprintf(stage->name, sizeof stage->name, "%s", name);
    for (int j = 0; j < k; ++j)
        if (strcmp(scene->stages[j].name, name) == 0)
            return app_config_fail(&L->p, app_config_member(g, "name"),
                                   "stage name `%s` is used twice", name);
    if (parse_times(L, g, k, time) < 0 || parse_load(L, g, k) < 0 ||
        parse_settle(L, g, stage) < 0 || parse_remove_ids(L, g, stage) < 0 ||
        parse_forcing(L, g, k) < 0 || loader_parse_adds(L, g, k) < 0)
        return -1;
    stage->movie = -1; /* unset: output.movie decides */
    if (app_config_bool(&L->p, g, "movie", &stage->movie) < 0 ||
        app_config_bool(&L->p, g, "skip", &stage->skip) < 0)
        return -1;
    /* view = [x0, y0, x1, y1]: the window of the stage's movie (docs/figures.md#movies) */
    int found = g ? app_config_vector(&L->p, g, "view", stage->movie_view, 4) : 0;
    if (found < 0)
        return -1;
    double *v = stage->movie_view;
    if (found && !(v[2] > v[0] && v[3] > v[1]))
        return app_config_fail(&L->p, app_config_member(g, "view"),
                               "`view` = [x0, y0, x1, y1] needs x1 > x0, y1 > y0");
    return 0;
}

int loader_parse_stages(Loader *L, const config_setting_t *root)
{
    Scene *scene = L->scene;
    const config_setting_t *time = app_config_member(root, "time");
    const config_setting_t *list;
    if (app_config_list(&L->p, root, "stages", &list) < 0)
        return -1;
    if (!list) {
        scene->stage_count = 1;
        return parse_stage(L, NULL, 0, time);
    }
    int count = config_setting_length(list);
    if (count < 1 || count > SCENE_MAX_STAGES)
        return app_config_fail(&L->p, list, "`stages` must list 1 to %d stages", SCENE_MAX_STAGES);
    scene->stage_count = count;
    for (int k = 0; k < count; ++k)
        if (parse_stage(L, config_setting_get_elem(list, (unsigned)k), k, time) < 0)
            return -1;
    return loader_assign_add_ids(L);
}

/* 1 when the scene's own grains hold `id`. */
static int scene_has_id(const Scene *scene, uint32_t id)
{
    const SimGrainBuffer *b = &scene->grains;
    for (int i = 0; i < b->count; ++i)
        if ((b->id ? b->id[i] : (uint32_t)i) == id)
            return 1;
    return 0;
}

/* 1 when a stage before stage k adds the grain `id`. */
static int added_before(const Scene *scene, int k, uint32_t id)
{
    for (int m = 0; m < k; ++m)
        for (int j = 0; j < scene->stages[m].add_count; ++j)
            if (scene->stages[m].adds[j].id == id)
                return 1;
    return 0;
}

int loader_check_remove_ids(Loader *L, const config_setting_t *root)
{
    const Scene *scene = L->scene;
    const config_setting_t *list = config_setting_get_member(root, "stages");
    if (scene->source_count > 0 || !list)
        return 0; /* sources add grains with new ids as the run goes */
    for (int k = 0; k < scene->stage_count; ++k) {
        const SceneStage *stage = &scene->stages[k];
        if (stage->load == SCENE_LOAD_FILE)
            return 0; /* from here on the grains come from a state file */
        const config_setting_t *ids =
            config_setting_get_member(config_setting_get_elem(list, (unsigned)k), "remove_ids");
        for (int j = 0; j < stage->remove_count; ++j) {
            if (!scene_has_id(scene, stage->remove_ids[j]) &&
                !added_before(scene, k, stage->remove_ids[j]))
                return app_config_fail(
                    &L->p, ids ? config_setting_get_elem(ids, (unsigned)j) : NULL,
                    "`remove_ids`: no grain of the scene or of an earlier stage's `add` has id "
                    "%u",
                    stage->remove_ids[j]);
        }
    }
    return 0;
}
