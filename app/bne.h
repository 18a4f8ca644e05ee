/* SPDX-License-Identifier: MIT */
/* bne.h: Brazil-nut measures of thesis 002 ch. 5. A scene's `bne` group names the intruder and
 * the motion that shakes the box, sets the shaking by Gamma = A w^2 / g and its period, and the
 * stage from which the box shakes (earlier stages run with the motion stopped: the preparation
 * settles at rest). During a run it writes bne.csv (intruder and surface heights in the box's
 * frame) and at the end bne.json (rise time, rise rate).
 *
 * Rise time (ours; the thesis gives no definition): the first time, counted from the start of the
 * shaking stage, at which the intruder's top (centre + radius, in the box frame) reaches the
 * surface of the bed measured at the start of shaking minus `tolerance`. The surface is the mean
 * over columns one mean diameter wide of the highest grain top (sim_world_surface_profile).
 *
 * Samples (sablier bne): app_bne_samples runs a scene for several seeds and values of one key,
 * and writes mean +- standard deviation curves, rise times and the large-deviation function of
 * the windowed rise rate (docs/brazil_nut.md). */
#ifndef APP_BNE_H
#define APP_BNE_H

#include "scene.h"

#include "sim/sim.h"

#include <libconfig.h>
#include <stddef.h>

typedef struct AppBne AppBne;

/// What one run measured.
typedef struct AppBneResult {
    double gamma, period, amplitude; ///< -, s, m
    double intruder_radius;          ///< m
    double surface;                  ///< bed surface at the start of shaking, box frame, m
    double start_height;             ///< intruder centre at the start of shaking, box frame, m
    double end_height;               ///< at the end of the run, m
    double rise_time;                ///< s from the start of shaking; NAN when it never rose
    double rise_rate;                ///< (end - start height) / shaking time, m/s
    double shaking_time;             ///< s
    int count;                       ///< samples in t, height
    const double *t;                 ///< s from the start of shaking
    const double *height;            ///< intruder centre in the box frame, m
} AppBneResult;

/// Parses `bne` (the scene's motions, grains and stages must be parsed); adjusts the named
/// motion's amplitude and frequency. NULL with "file:line: message" in err on bad input.
AppBne *app_bne_parse(const config_setting_t *group, Scene *scene, char *err, size_t err_size);
void app_bne_free(AppBne *bne);

/// Stops the motion before the shaking stage and phases it to start at rest offset there
/// (called by scene_world_def).
void app_bne_adjust_def(const AppBne *bne, int stage, SimWorldDef *def);
/// 1 when stage k must re-create its world (the motion starts) instead of continuing in memory.
int app_bne_restart(const AppBne *bne, int stage);

/// Runner hooks (see sediment.h).
int app_bne_begin(AppBne *bne, const char *out_dir, char *err, size_t err_size);
void app_bne_stage(AppBne *bne, const Scene *scene, int stage, SimWorld *world);
void app_bne_row(AppBne *bne, SimWorld *world);
int app_bne_end(AppBne *bne, int ok, char *err, size_t err_size);

AppBneResult app_bne_result(const AppBne *bne);

/// Rise time of a height record (see above); NAN if never.
double app_bne_rise_time(const double *t, const double *height, int count, double radius,
                         double surface, double tolerance);

/// Large-deviation estimate of the windowed rise rate v = (h(t + tau) - h(t)) / tau over
/// non-overlapping windows of every record: histogram with `bins` bins over [v_min, v_max]
/// (from the data when v_min >= v_max), I(v) = -ln(P(v) / P_max) / tau. Writes bin centres,
/// probabilities and I (NAN where empty); returns the number of windows.
int app_bne_ldf(const double *const *t, const double *const *height, const int *count, int records,
                double tau, int bins, double v_min, double v_max, double *centre,
                double *probability, double *rate_function);

/// Plot writer given by app/sablier.c (render/): one panel of curves. Returns 0 or -1.
typedef struct AppBneCurve {
    const char *label;
    int count;
    const double *x, *y, *y_err; ///< y_err may be NULL
} AppBneCurve;

typedef int (*AppBnePlot)(void *context, const char *path, const char *title, const char *x_label,
                          const char *y_label, const AppBneCurve *curves, int curve_count,
                          char *err, size_t err_size);

typedef struct AppBneSamplesOptions {
    const char *scene_path;
    const char *out_dir;
    const char *const *sets; ///< KEY=VALUE for every run
    int set_count;
    const char *vary; ///< "KEY=v1,v2,..." or NULL
    int seeds;        ///< runs per value, seeds seed0 .. seed0 + seeds - 1
    long seed0;
    double ldf_periods; ///< window of the large-deviation function, in shaking periods (0 = off)
    int quiet;
    const void *render; ///< AppRenderHooks for each run's movies and figures, or NULL
    AppBnePlot plot;    ///< rise curves and LDF plots, or NULL
    void *plot_context;
} AppBneSamplesOptions;

/// Runs the samples; returns the exit status (0, 1, 2).
int app_bne_samples(const AppBneSamplesOptions *options);

#endif
