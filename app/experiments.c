/* SPDX-License-Identifier: MIT */
/* experiments.c: the registry, the only place that lists the experiment families.
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
#include "experiments.h"

#include <string.h>

/* One line per family. The order is the order of `sablier --help`'s family commands and of the
 * runner's hook calls. */
#define APP_FAMILIES                                                                               \
    APP_FAMILY(crater)                                                                             \
    APP_FAMILY(discharge)                                                                          \
    APP_FAMILY(bne)                                                                                \
    APP_FAMILY(sediment)                                                                           \
    APP_FAMILY(surface)                                                                            \
    APP_FAMILY(measures)   /* not a family: the core's measures layer (app/measures.h) */          \
    APP_FAMILY(wall_loads) /* not a family: the forces on walls (app/wall_loads.c), last */

#define APP_FAMILY(name) extern const AppExperiment app_##name##_experiment;
APP_FAMILIES
#undef APP_FAMILY

#define APP_FAMILY(name) &app_##name##_experiment,
const AppExperiment *const app_experiments[] = {APP_FAMILIES NULL};
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
