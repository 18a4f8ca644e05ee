/* SPDX-License-Identifier: MIT */
/* sweep.h: parameter sweeps from one settled bed (thesis 000 Ch. 7: every collapse starts from the
 * same bed). Each member is a `sablier run` process of the scene with --set overrides, its stages
 * up to the bed skipped and the next stage loaded from the bed checkpoint; members run `jobs` at
 * a time and write their own folders, then the sweep writes sweep.csv and comparison plots
 * (energy panels, crater height against the varied parameter, final profiles). A member's result
 * does not depend on the job count: it is a separate, deterministic process.
 *
 *     AppCraterSweepOptions o = app_crater_sweep_options_default();
 *     o.self = "/proc/self/exe"; o.definition = "scenes/crater/sweeps/aspect.sweep";
 *     int status = app_crater_sweep(&o);   // 0 all members ok, 1 a member failed, 2 bad input
 */
#ifndef APP_SWEEP_H
#define APP_SWEEP_H

#include "crater.h"

#include "base/experiment.h"

typedef struct AppCraterSweepOptions {
    const char *self;        ///< the sablier executable the members run
    const char *definition;  ///< a .sweep file (libconfig), or NULL
    const char *scene_path;  ///< the scene (overrides the definition's `scene`)
    const char *from;        ///< bed checkpoint; NULL = run the stages up to the bed first
    const char *bed_stage;   ///< stage whose checkpoint is the bed; NULL = the one before a dig
    const char *out_dir;     ///< NULL = out/<scene name>-sweep or out/<definition name>
    int jobs;                ///< processes at a time (>= 1)
    int quiet;               ///< no per-member lines
    int dry_run;             ///< 1: list the members and their commands, run nothing
    int resume;              ///< 1: skip the bed and members whose folder holds a completed run
    const char *const *sets; ///< KEY=VALUE for the bed run and every member
    int set_count;
    const char *const *vary; ///< "KEY=v1,v2,...": one member per combination
    int vary_count;
    const AppRender *render; ///< comparison figures; NULL = none
} AppCraterSweepOptions;

AppCraterSweepOptions app_crater_sweep_options_default(void);

/// Runs a sweep; prints messages on stderr; returns the exit status (0, 1 or 2).
int app_crater_sweep(const AppCraterSweepOptions *options);
/// `sablier sweep` (one entry).
extern const AppCommand app_crater_commands[];

#endif
