/* SPDX-License-Identifier: MIT */
/* measures.h: declared measurements any scene can make (docs/measures.md), a core layer of the
 * app, not an experiment family: coarse-grained fields on a grid or as 1D profiles (sim/coarse.c,
 * Weinhart et al. 2012) and flux counters through a segment, written as CSV (and VTK ImageData
 * for grids), drawn as figures, summarised in summary.json. It plugs into the stage runner through
 * the hook table of experiment.h (listed in app/base/experiments.c after the families), so it
 * reuses the runner's scheduling (next_step / step) and costs nothing when a scene declares no
 * measure.
 *
 *     measures = ( { name = "stress"; kind = "profile_y"; width = 0.02; fields = ["syy"]; } );
 */
#ifndef APP_MEASURES_H
#define APP_MEASURES_H

#include "base/experiment.h"
#include "scene/scene.h"

/// Measures one scene can declare (top level and stages together).
#define APP_MEASURES_MAX       16
/// Nodes of one grid measure, and bins of one profile (memory bound checked at load).
#define APP_MEASURES_MAX_NODES (1 << 18)

extern const AppExperiment app_measures_experiment;

typedef struct AppMeasures AppMeasures;

/// The scene's measures (NULL when it declares none).
const AppMeasures *app_measures_of(const Scene *scene);

#endif
