/* SPDX-License-Identifier: MIT */
/* experiments.h: the registry of experiment families (app/base/experiments.c) and a scene's
 * per-family states. The core (scene loader, runner, CLI) walks this list; it never names a family.
 */
#ifndef APP_EXPERIMENTS_H
#define APP_EXPERIMENTS_H

#include "base/experiment.h"

/// Upper bound of registered families (a Scene keeps one state pointer per family).
#define APP_EXPERIMENT_MAX 16

/// The registered families, in registry order (NULL-ended).
extern const AppExperiment *const app_experiments[];

/// Number of registered families.
int app_experiment_count(void);

/// Index of `family` in the registry, -1 when it is not registered.
int app_experiment_index(const AppExperiment *family);

/// The command `name` of any family, or NULL.
const AppCommand *app_experiment_command(const char *name);

/// The family's top-level group in the scene `root`: `group`, else `group_alias`; NULL when the
/// scene has neither (or the family has no group).
const config_setting_t *app_experiment_group(const AppExperiment *family,
                                             const config_setting_t *root);

#endif
