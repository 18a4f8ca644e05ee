/* SPDX-License-Identifier: MIT */
/* surface.h: the `surface` experiment family (docs/experiments.md): the free surface's angle from
 * a least-squares line through the heights of the highest grains, per column of a window; a
 * rotating drum's dynamic angle of repose, a heap's slope. */
#ifndef APP_SURFACE_H
#define APP_SURFACE_H

#include "experiment.h"

/// A least-squares line y = a + b x through the finite points (NAN heights skipped): 0, or -1
/// with fewer than two points. Writes the slope b and intercept a.
int app_surface_fit(const double *x, const double *y, int n, double *slope, double *intercept);

extern const AppExperiment app_surface_experiment;

#endif
