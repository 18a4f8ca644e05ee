/* SPDX-License-Identifier: MIT */
/* ensemble.h: `sablier ensemble` (docs/accuracy.md#ensemble-accuracy, docs/cli.md): a scene run
 * for N seeds at each of several time steps through the process pool; per observable the
 * ensemble mean at each dt, its shift against the finest dt with Welch's interval, and the CPU
 * time per member. App core: the members are `sablier run` processes, the observables numbers
 * in their output folders (run_value.h). */
#ifndef APP_ENSEMBLE_H
#define APP_ENSEMBLE_H

#include "base/experiment.h"

extern const char app_ensemble_usage[];

/// `sablier ensemble ...` (argv[1] is "ensemble"). Returns the exit status.
int app_ensemble_command(int argc, char **argv, const AppEnv *env);

/// Its command line only (AppCommand.parse): 0, or the exit status of a usage error.
int app_ensemble_parse(int argc, char **argv);

#endif
