/* SPDX-License-Identifier: MIT */
/* surface.h: the `surface` experiment family (docs/experiments.md): the free surface's angle from
 * a least-squares line through the heights of the highest grains, per column of a window; a
 * rotating drum's dynamic angle of repose, a heap's slope. */
#ifndef APP_SURFACE_H
#define APP_SURFACE_H

#include "base/experiment.h"

extern const AppExperiment app_surface_experiment;

#endif
