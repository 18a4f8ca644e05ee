/* SPDX-License-Identifier: MIT */
/* experiments.c: the registry, the only place that lists the experiment families, and the core
 * layers that plug into the runner through the same hook table (docs/dev/architecture.md).
 *
 * How to add an experiment (docs/dev/architecture.md has a worked example):
 *  1. make a folder app/<family>/ with <family>.h and a file that defines
 *         const AppExperiment app_<family>_experiment = {.name = "<family>", ...};
 *     filling only the hooks of experiment.h you need (parse, begin, sample, stage_end, ...);
 *     app/CMakeLists.txt builds every .c file of every folder under app/;
 *  2. add one line APP_FAMILY(<family>) to APP_FAMILIES below.
 * The family's scene group, stage and output keys, its commands and their --help lines are then
 * accepted and listed by the core. Scenes go in scenes/<family>/, tests in tests/app/, docs in
 * docs/<family>.md. */
#include "base/experiments.h"

#include "base/config.h"

#include <string.h>

/* One line per family (a folder app/<family>/). The order is the order of `sablier --help`'s
 * family commands and of the runner's hook calls. */
#define APP_FAMILIES                                                                               \
    APP_FAMILY(crater)                                                                             \
    APP_FAMILY(discharge)                                                                          \
    APP_FAMILY(bne)                                                                                \
    APP_FAMILY(sediment)                                                                           \
    APP_FAMILY(surface)

/* The core layers on the hook table, called after every family: coarse-grained measures
 * (app/output/measures.h), the forces on walls (app/output/wall_loads.c), then a projectile's depth
 * (app/output/depth.c). They are app core, not families:
 * any scene may use them and families may read them. */
#define APP_CORE_LAYERS                                                                            \
    APP_FAMILY(measures)                                                                           \
    APP_FAMILY(wall_loads)                                                                         \
    APP_FAMILY(depth)

#define APP_FAMILY(name) extern const AppExperiment app_##name##_experiment;
APP_FAMILIES
APP_CORE_LAYERS
#undef APP_FAMILY

#define APP_FAMILY(name) &app_##name##_experiment,
const AppExperiment *const app_experiments[] = {APP_FAMILIES APP_CORE_LAYERS NULL};
#undef APP_FAMILY

int app_experiment_count(void)
{
    int n = 0;
    while (app_experiments[n])
        ++n;
    return n;
}

int app_experiment_index(const AppExperiment *family)
{
    for (int k = 0; app_experiments[k]; ++k)
        if (app_experiments[k] == family)
            return k;
    return -1;
}

const AppCommand *app_experiment_command(const char *name)
{
    for (int k = 0; app_experiments[k]; ++k)
        for (int c = 0; c < app_experiments[k]->command_count; ++c)
            if (strcmp(app_experiments[k]->commands[c].name, name) == 0)
                return &app_experiments[k]->commands[c];
    return NULL;
}

const config_setting_t *app_experiment_group(const AppExperiment *family,
                                             const config_setting_t *root)
{
    const config_setting_t *g = family->group ? app_config_member(root, family->group) : NULL;
    if (!g && family->group_alias)
        g = app_config_member(root, family->group_alias);
    return g;
}
