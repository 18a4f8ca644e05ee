/* SPDX-License-Identifier: MIT */
/* study.h: the `sablier discharge` and `sablier study` commands (thesis 004, docs/discharge.md).
 * `discharge` builds one pile and discharges it at a few widths (figures, movies); `study` runs
 * independent samples over base lengths and widths in parallel processes, resumes where it
 * stopped, and reduces them to per-(L, w) tables, fits (w_t, w_c), F(s) and plots. Rendering
 * comes through hooks that app/sablier.c fills (NULL hooks: figures, movies and plots skipped). */
#ifndef APP_STUDY_H
#define APP_STUDY_H

#include "discharge.h"
#include "run.h"

#include <stddef.h>

typedef struct AppPlotSeries {
    const char *label;
    int count;
    const double *x, *y, *y_err; ///< y_err may be NULL
    int line, dashed;
    int marker; ///< 0 none, 1 circle, 2 square, 3 triangle, 4 cross (RenderMarker order)
} AppPlotSeries;

typedef struct AppPlot {
    const char *title, *x_label, *y_label;
    int y_log;
    int series_count;
    const AppPlotSeries *series;
} AppPlot;

typedef struct AppDischargeRender {
    void *context;
    /// A pile snapshot: species colours from the scene's `render` group; arch_marks (frame
    /// order, -1 none; NULL = no arch) highlighted with a zoomed inset and force chains.
    int (*figure)(void *context, const Scene *scene, const SimFrame *frame, const int *arch_marks,
                  const char *title, const char *path, char *err, size_t err_size);
    int (*plot)(void *context, const Scene *scene, const AppPlot *plot, const char *path, char *err,
                size_t err_size);
    const AppRenderHooks *movie; ///< movie_open / movie_close of the stage runner
} AppDischargeRender;

/// `sablier discharge SCENE ...`; returns the exit status.
int app_discharge_command(int argc, char **argv, const AppDischargeRender *render);
/// `sablier study SCENE ...`; returns the exit status.
int app_study_command(int argc, char **argv, const AppDischargeRender *render);

extern const char APP_DISCHARGE_USAGE[];
extern const char APP_STUDY_USAGE[];

/// Gaussian fit of sigma(w) through its peak: a parabola fitted to log sigma over the points
/// above half the maximum (at least three, else the arg-max). Returns the peak position w_t.
double app_gaussian_peak(const double *w, const double *sigma, int n);
/// Least-squares line y = a + b x; a_err is the standard error of the intercept (0 if n < 3).
void app_linear_fit(const double *x, const double *y, int n, double *a, double *b, double *a_err);

/// Reduces finished runs of a study folder to tables (per-(L, w) CSV, study.csv, fits.csv, F(s))
/// and plots; returns 0, or -1 with a message.
int app_study_reduce(const Scene *scene, const char *dir, const double *lengths, int length_count,
                     const double *widths, int width_count, int samples,
                     const AppDischargeRender *render, char *err, size_t err_size);

#endif
