/* SPDX-License-Identifier: MIT */
/* experiments.c: the registry, the only place that lists the experiment families.
 *
 * How to add an experiment (docs/dev/architecture.md has a worked example):
 *  1. make a folder app/<family>/ with <family>.h and a file that defines
 *         const AppExperiment app_<family>_experiment = {.name = "<family>", .group = "<key>",
 * ...}; filling only the hooks of experiment.h you need (parse, begin, sample, stage_end, ...);
 *  2. add its .c files to APP_FAMILY_SOURCES in app/CMakeLists.txt;
 *  3. add one `extern` line and one entry to the list below.
 * The scene key `<key>`, the family's stage/output keys, its commands and their --help lines are
 * then accepted and listed by the core. Scenes go in scenes/<family>/, tests in tests/app/, docs
 * in docs/<family>.md. */
#include "experiments.h"

#include <string.h>

extern const AppExperiment app_crater_experiment;
extern const AppExperiment app_discharge_experiment;
extern const AppExperiment app_bne_experiment;
extern const AppExperiment app_sediment_experiment;

/* The order is the order of `sablier --help`'s family commands and of the runner's hook calls. */
const AppExperiment *const app_experiments[] = {
    &app_crater_experiment,
    &app_discharge_experiment,
    &app_bne_experiment,
    &app_sediment_experiment,
    NULL,
};

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
