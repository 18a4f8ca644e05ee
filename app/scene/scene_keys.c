/* SPDX-License-Identifier: MIT */
/* scene_keys.c: the key rules every part of the scene loader shares: keys gated by an effect,
 * names used in file names, stage names, and the keys the experiment families own (from the
 * registry). */
#include "base/experiments.h"
#include "scene/scene_internal.h"

#include <ctype.h>
#include <string.h>

/* ---------------------------------------------------------------- scene-wide checks */

int loader_gate(Loader *L, const config_setting_t *g, const char *key, unsigned effect)
{
    const config_setting_t *s = app_config_member(g, key);
    if (!s || (L->effects & effect))
        return 0;
    return app_config_fail(&L->p, s, "`%s` needs effect \"%s\", which is not declared in `effects`",
                           key, sim_effect_name(effect));
}

int loader_keys(Loader *L, const config_setting_t *g, const char *what, const SceneKey *keys)
{
    const char *names[SCENE_GROUP_KEYS_MAX + 1];
    int n = 0;
    for (; keys[n].key && n < SCENE_GROUP_KEYS_MAX; ++n)
        names[n] = keys[n].key;
    names[n] = NULL;
    return app_config_keys(&L->p, g, what, names, NULL);
}

int loader_check_file_name(Loader *L, const config_setting_t *g, const char *key, const char *v)
{
    int ok = v[0] != '\0' && v[0] != '.' && strlen(v) < SCENE_NAME_MAX;
    for (const char *c = v; ok && *c; ++c)
        ok = isalnum((unsigned char)*c) || *c == '_' || *c == '-' || *c == '.';
    if (ok)
        return 0;
    return app_config_fail(&L->p, app_config_member(g, key),
                           "`%s` = \"%s\" must be a short name of letters, digits, _ - .", key, v);
}

/* The keys the registered experiment families own (app/base/experiments.c): their top-level groups
 * (which = 0), stage keys (1) or output keys (2). NULL-ended in a static buffer per kind. */
const char *const *loader_family_keys(int which)
{
    static const char *keys[3][4 * APP_EXPERIMENT_MAX + 1];
    int n = 0;
    for (int f = 0; app_experiments[f]; ++f) {
        const AppExperiment *e = app_experiments[f];
        const char *const *list = which == 1 ? e->stage_keys : which == 2 ? e->output_keys : NULL;
        if (which == 0 && e->group && n < 4 * APP_EXPERIMENT_MAX)
            keys[0][n++] = e->group;
        if (which == 0 && e->group_alias && n < 4 * APP_EXPERIMENT_MAX)
            keys[0][n++] = e->group_alias;
        for (int k = 0; list && list[k] && n < 4 * APP_EXPERIMENT_MAX; ++k)
            keys[which][n++] = list[k];
    }
    keys[which][n] = NULL;
    return keys[which];
}

int scene_stage_index(const Scene *scene, const char *name)
{
    for (int k = 0; k < scene->stage_count; ++k)
        if (strcmp(scene->stages[k].name, name) == 0)
            return k;
    return -1;
}
