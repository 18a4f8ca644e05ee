/* SPDX-License-Identifier: MIT */
/* sources.h: insertion sources (docs/scenes.md, sources): grains put into a region during a
 * stage at a rate (grains or mass per second) or all at once (a count), with sizes from a
 * uniform range, a mixture of species with number fractions, or a list; never overlapping what
 * is there (a grain that finds no free place in `attempts` tries is skipped and counted);
 * deterministic from the scene's seed. The stage runner (run.c) calls these. */
#ifndef APP_SOURCES_H
#define APP_SOURCES_H

#include "scene/scene.h"

#define SCENE_SOURCE_MAX          8
#define SCENE_SOURCE_MAX_RADII    64
/* The most random places a source tries per grain (`attempts`). */
#define SCENE_SOURCE_MAX_ATTEMPTS 1000000

typedef struct SceneSource {
    char name[SCENE_NAME_MAX];
    double x0, y0, x1, y1; ///< region of the grains' centres, m
    double rate;           ///< grains per second (0: mass_rate, or all `count` at once)
    double mass_rate;      ///< kg/s (0: rate or count)
    long count;            ///< total grains (0: no cap); alone: inserted at the stage start
    int mixture_count;     ///< species mixture: number fractions and radius ranges
    int species[SIM_MAX_SPECIES];
    double fraction[SIM_MAX_SPECIES];
    double radius_min[SIM_MAX_SPECIES], radius_max[SIM_MAX_SPECIES]; ///< m
    int radii_count;                                                 ///< a list of radii, in turn
    double radii[SCENE_SOURCE_MAX_RADII];                            ///< m
    double vx, vy;                                                   ///< m/s
    int attempts;    ///< random places tried per grain
    unsigned stages; ///< bit k: active in stage k
} SceneSource;

typedef struct AppSources AppSources;

/// The timing (sim_world_def_timing) of `def` with, besides its grains, the lightest grain of
/// every species each source of the scene inserts (its smallest radius): the automatic time step
/// of a scene fed by sources resolves their contacts too.
SimTiming app_sources_timing(const Scene *scene, const SimWorldDef *def);

/// Run-time state of the scene's sources (NULL when it has none, or out of memory: *failed).
AppSources *app_sources_create(const Scene *scene, int *failed);
void app_sources_free(AppSources *sources);
/// At a stage start: the stage's clocks begin (rate counts from 0).
void app_sources_stage_begin(AppSources *sources, int stage);
/// The first step after `done` (steps from the stage start, dt s) at which a grain is due.
long app_sources_next_step(const AppSources *sources, long done, double dt, long limit);
/// Inserts the grains due at step `done`. 0, or -1 with err (sim_world_add_grains failed).
/// A run's signal (app_run_signal) raised during the placing stops it: that step's grains are
/// then put off whole (one raised before lets it finish, so that a resumed run is exact).
int app_sources_insert(AppSources *sources, SimWorld *world, long done, double dt, char *err,
                       size_t err_size);
/// `"sources": [...]` members for summary.json (name, inserted, skipped), "" without sources.
void app_sources_json(const AppSources *sources, char *out, size_t size);
/// The sources' run-time state (random generators, counts, the next grain) for a checkpoint
/// record (app/run/run.c, docs/cli.md#periodic-checkpoints-and---resume): one "source K ..." line
/// each, "" without sources.
void app_sources_checkpoint(const AppSources *sources, char *out, size_t size);
/// Restores one "source K ..." line of a checkpoint record. 0, or -1 when it is malformed or
/// names no source of the scene.
int app_sources_restore(AppSources *sources, const char *line);
/// Grains inserted by source k so far.
long app_sources_inserted(const AppSources *sources, int k);

#endif
