/* SPDX-License-Identifier: MIT */
/* crater.h: crater observables of a run (thesis 000 §5.4, Ch. 7): the free-surface profile over
 * time (profile.csv), the crater height (crater.csv), the settled bed's structure (coordination,
 * packing fraction, hexatic order) and a key/value summary (observables.csv); plus plain plot
 * descriptions (AppCraterChart) built from those CSV files, which app/cli/sablier.c draws with
 * render/. Knows nothing about rendering.
 *
 *     AppCraterObserver *obs = app_crater_observer_open(scene, "out/quick", err, sizeof err);
 *     app_crater_observer_before_edit(obs, world, stage);  // bed measures before a dig
 *     app_crater_observer_sample(obs, world, stage, t0);   // one profile + crater row
 *     app_crater_observer_close(obs, world, err, sizeof err);
 */
#ifndef APP_CRATER_H
#define APP_CRATER_H

#include "base/experiment.h"
#include "base/render_hooks.h"
#include "scene/scene.h"
#include "sim/sim.h"

#include <stddef.h>

/* ---------------------------------------------------------------- measures */

/// Free-surface profile: `bins` equal bins over the container interior [x0, x1].
typedef struct AppCraterProfile {
    int bins;
    double x0, x1, bin; ///< interior and bin width, m
    double floor_top;   ///< top of the floor (lowest fixed grain's y + r), m
    double *x;          ///< bin centres, m
    double *y;          ///< highest top (y + r) of a mobile grain centred in the bin, m; an empty
                        ///< bin is at floor_top (the cavity reaches the floor there)
} AppCraterProfile;

/// Measures the profile with bins about `bin_width` wide (0 = the mean diameter). The interior is
/// the span between the innermost edges of the fixed grains left and right of the mobile grains'
/// centre (the container's side columns), else the mobile grains' extent. 0, or -1 (no grains).
int app_crater_profile_measure(SimWorld *world, double bin_width, AppCraterProfile *profile);
void app_crater_profile_free(AppCraterProfile *profile);

/// Mean profile height over the interior without the `margin` bins next to each wall, m.
double app_crater_profile_level(const AppCraterProfile *profile, int margin);

/// Crater of a profile over the cavity span [x0, x1] (000 §5.4, fig. 7.28).
typedef struct AppCrater {
    double surface_min; ///< lowest profile height in the span, m
    double x_min;       ///< where, m
    double height;      ///< crater height h = level - surface_min, m
} AppCrater;

/// Lowest bin whose centre lies in [x0, x1] (at least the bin nearest the span's centre).
AppCrater app_crater_measure(const AppCraterProfile *profile, double x0, double x1, double level);

/// Structure of a settled bed (000 §4.2: polydispersity against crystallisation).
typedef struct AppCraterBed {
    double coordination;     ///< mean contacts per mobile grain (walls included)
    double packing_fraction; ///< disk area / area in the bulk window
    double hexatic_order;    ///< mean local |psi_6|
    double level;            ///< mean free-surface height, m
    double window[4];        ///< bulk window x0, y0, x1, y1 (m): one diameter from the walls and
                             ///< the floor, three below the lowest surface bin
} AppCraterBed;

/// Measures the bed (the profile `profile` of the same world gives the window).
AppCraterBed app_crater_bed_measure(SimWorld *world, const AppCraterProfile *profile);

/* ---------------------------------------------------------------- observer of a run */

typedef struct AppCraterObserver AppCraterObserver;

/// Opens profile.csv and crater.csv in out_dir; profiles in bins about `profile_bin` wide (0 = the
/// mean diameter). NULL with a message on error.
AppCraterObserver *app_crater_observer_open(const Scene *scene, double profile_bin,
                                            const char *out_dir, char *err, size_t err_size);
/// Before a stage digs the cavity [x0, x1] (m): measures the bed it digs into.
void app_crater_observer_before_dig(AppCraterObserver *observer, SimWorld *world, double x0,
                                    double x1);
/// After a stage's edits: records the scales of t* and E* at the start of the last stage.
void app_crater_observer_stage_start(AppCraterObserver *observer, SimWorld *world, int stage);
/// One profile.csv block and one crater.csv row (after a dig) at the world's time; stage_start
/// is the stage's start time, s.
void app_crater_observer_sample(AppCraterObserver *observer, SimWorld *world, int stage,
                                double stage_start);
/// A checkpoint of the running stage: the measures so far and the lengths of profile.csv and
/// crater.csv, as lines of the family's section (app/base/checkpoint.h).
void app_crater_observer_checkpoint(const AppCraterObserver *observer, FILE *out);
/// --resume: the observer just opened continues from those lines (its CSV files cut back to the
/// recorded lengths). 0, or -1 with a message.
int app_crater_observer_resume(AppCraterObserver *observer, const char *record, char *err,
                               size_t err_size);
/// JSON members `"bed": {...}, "crater": {...}, ` for summary.json (empty when not measured).
void app_crater_observer_json(const AppCraterObserver *observer, char *out, size_t size);
/// Finishes the CSV files and writes observables.csv (world may be NULL). 0, or -1 with err.
int app_crater_observer_close(AppCraterObserver *observer, SimWorld *world, char *err,
                              size_t err_size);

/* ---------------------------------------------------------------- plots from the CSV files */

#define APP_CRATER_CHART_MAX_SERIES 24
#define APP_CRATER_CHART_MAX_PANELS 4

typedef struct AppCraterChartSeries {
    char label[64];
    int count;
    double *x, *y; ///< owned
    int line;      ///< 1: joined
    int marker;    ///< 1: circles
} AppCraterChartSeries;

typedef struct AppCraterChartPanel {
    char title[64], x_label[64], y_label[64]; ///< markup (docs/figures.md#markup)
    double x_domain[2];                       ///< the x axis' physical domain (min >= max: none)
    int series_count;
    AppCraterChartSeries series[APP_CRATER_CHART_MAX_SERIES];
} AppCraterChartPanel;

typedef struct AppCraterChart {
    char title[160];
    int rows, cols, width, height;  ///< panel grid, pixels
    const struct SceneStyle *print; ///< the scene's print keys (NULL = none)
    AppCraterChartPanel panels[APP_CRATER_CHART_MAX_PANELS];
} AppCraterChart;

/// Draws and writes a chart through render->plot (nothing when render has no plot); 0, or -1.
int app_crater_chart_write(const AppCraterChart *chart, const AppRender *render, const char *path,
                           char *err, size_t err_size);

void app_crater_chart_init(AppCraterChart *plot, int rows, int cols, const char *title);
void app_crater_chart_free(AppCraterChart *plot);
/// Adds a series (copies the data) to a panel; returns 0, -1 when full or out of memory.
int app_crater_chart_add(AppCraterChart *plot, int panel, const char *label, const double *x,
                         const double *y, int count, int line, int marker);

/// Adds the 2x2 dimensionless energy curves of a run folder (E* = E / (N m g D) against
/// t* = (t - t0) / sqrt(D/g) over the stage named `stage`, NULL = the last; potential relative
/// to its start; 000 eqs. 6.1-6.6) to a plot made with app_crater_chart_init(plot, 2, 2, ...). 0,
/// or -1 when unreadable or the stage wrote no energy rows.
int app_crater_chart_energy_run(AppCraterChart *plot, const char *run_dir, const char *label,
                                const char *stage);
/// Adds profiles of a run folder's last stage: `curves` evenly spaced times (curves = 1: the
/// final profile only, labelled `label`). 0, or -1 when unreadable.
int app_crater_chart_profiles_run(AppCraterChart *plot, int panel, const char *run_dir, int curves,
                                  const char *label);

/// Reads one value of a run folder's observables.csv; NAN when absent.
double app_crater_observable(const char *run_dir, const char *key);

/// The figures of a crater run: energy_panels.png (E* against t* over stage `energy_stage`, -1 =
/// the last: 000 fig. 6.15 for a deposit, 7.1 for a collapse) and profiles.png (profile
/// evolution, fig. 7.30), from the run folder's CSV files. 0, or -1 with a message.
int app_crater_plots(const Scene *scene, int energy_stage, const char *out_dir,
                     const AppRender *render, char *err, size_t err_size);

/// Free-surface height near x: highest top (y + r) of mobile grains with |x_i - x| <= half_width,
/// m. Returns 0 and sets *top, or -1 when no mobile grain is in the band.
int app_crater_surface_height(const SimFrame *frame, double x, double half_width, double *top);

/* ---------------------------------------------------------------- the crater experiment */

/// A stage's cavity (000 §4.1 stage 2): `dig = { center_x; width; height; top; }` in the stage.
typedef struct AppCraterDig {
    int dig;                        ///< 1: remove a rectangle at the stage start
    double center_x, width, height; ///< m
    int top_surface;                ///< 1: the cavity top is the free surface near center_x
    double top;                     ///< m, when top_surface is 0
} AppCraterDig;

typedef struct AppCraterState AppCraterState;
extern const AppExperiment app_crater_experiment;

/// The scene's crater settings (NULL when it neither digs nor writes profiles).
const AppCraterState *app_crater_of(const Scene *scene);
/// Stage k's cavity (dig = 0 when the stage does not dig, or the scene has no crater state).
AppCraterDig app_crater_dig(const Scene *scene, int stage);

#endif
