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
 * Phase-averaged velocity field (ours; `bne.phase_field`): during the shaking stage the grains are
 * sampled at fixed phases of the shaking cycle, on the steps nearest t0 + (n + phase + k / phases)
 * T (within half a step), and the coarse-grained velocity (Lucy kernel, mass-weighted: V = sum j /
 * sum rho over the samples, MercuryCG-style) is accumulated in the box's frame (positions minus the
 * box offset, velocities minus the box velocity). At the end of the stage: phase_field.csv and the
 * figure phase_field.png (arrows over the final pile, through the runner's figure hook).
 *
 * Samples (sablier bne): app_bne_samples runs a scene for several seeds and values of one key,
 * and writes mean +- standard deviation curves, rise times and the large-deviation function of
 * the windowed rise rate (docs/brazil_nut.md). */
#ifndef APP_BNE_H
#define APP_BNE_H

#include "base/experiment.h"
#include "scene/scene.h"
#include "sim/sim.h"

#include <libconfig.h>
#include <stddef.h>
#include <stdio.h>

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

/// The Brazil-nut family (app/base/experiment.h): parses `bne`, stops the named motion before the
/// shaking stage and phases it to start at rest offset there (adjust_def), re-creates the world
/// at the shaking stage, writes bne.csv at every energy row, the phase samples at their steps,
/// phase_field.csv and phase_field.png at the end of the shaking stage, and bne.json at the end.
extern const AppExperiment app_bne_experiment;
/// The scene's Brazil-nut state (NULL when it has no `bne` group).
AppBne *app_bne_of(const Scene *scene);

/* ---------------------------------------------------------------- phase-averaged field */

/// Step, counted from the shaking stage's start, of phase sample m: phase bin k = m mod phases of
/// cycle n = m / phases, due at tau = (n + phase + k / phases) T and taken on the nearest step,
/// so |step dt - tau| <= dt / 2.
long app_bne_phase_step(double phase, int phases, double period, double dt, long m);

/// Coarse-grained sums over samples on a node grid in the box's frame. Node (i, j), index
/// j * nx + i, sits at (x0 + (i + 1/2) cell, y0 + (j + 1/2) cell). Lucy kernel of cutoff `width`
/// normalised over the plane; grain masses from the species densities and the mass model.
typedef struct AppBneField {
    int nx, ny;
    double x0, y0, cell;             ///< m
    double width;                    ///< kernel cutoff radius, m
    SimMassModel mass_model;         ///< m = rho pi r^2 (disk) or rho 4/3 pi r^3 (sphere)
    double density[SIM_MAX_SPECIES]; ///< kg/m^2 (disk) or kg/m^3 (sphere)
    int samples;                     ///< frames added
    double *rho, *jx, *jy; ///< per node, sums over samples: sum m W (kg/m^2), sum m v W (kg/m/s)
    double *solid;         ///< per node, sum over samples of the solid fraction sum pi r^2 W
    int *hits;             ///< per node, samples in which rho > 0
    long *stamp;           ///< per node, last sample that touched it (bookkeeping)
} AppBneField;

/// Allocates an empty grid covering [x0, x1] x [y0, y1] (ceil of the spans in cells, centred
/// in x, starting at y0); density and mass_model are to be set by the caller. 0, or -1 (bad
/// size, more than 4e6 nodes, no memory).
int app_bne_field_init(AppBneField *field, double x0, double y0, double x1, double y1, double cell,
                       double width);
void app_bne_field_free(AppBneField *field);
/// Adds one sample of the mobile grains, in the frame moving with the box: positions minus
/// (shift_x, shift_y), velocities minus (velocity_x, velocity_y). Periodic frames wrap in x.
void app_bne_field_add(AppBneField *field, const SimFrame *frame, double shift_x, double shift_y,
                       double velocity_x, double velocity_y);
/// Mean over the samples at node k: velocity sum j / sum rho (0 where never occupied), m/s, and
/// solid fraction.
void app_bne_field_node(const AppBneField *field, int k, double *vx, double *vy, double *solid);
/// Cycle mean of fields sampled at `count` phases: each phase weighs equally (its sums divided by
/// its samples), V = sum_k <j>_k / sum_k <rho>_k. `out` must be unallocated. 0, or -1.
int app_bne_field_combine(const AppBneField *phases, int count, AppBneField *out);
/// Writes x,y,vx,vy,samples,solid_fraction per node (`phase` >= 0 adds a leading phase column)
/// to an open CSV file.
void app_bne_field_rows(const AppBneField *field, double phase, FILE *csv);

/// After a run: the field drawn and written (the cycle mean with several phases; NULL when off or
/// before the end of the shaking stage), and the sample times, s from the start of shaking.
const AppBneField *app_bne_phase_field(const AppBne *bne);
int app_bne_phase_times(const AppBne *bne, const double **times);

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

/// The axes of the rise chart (x: time since shaking starts, y: intruder height rise) and of
/// the LDF's x axis (the windowed rise rate, a speed), in the scene's units (scene_axis_label);
/// bare names when scene is NULL (a scene that no longer loads: its units are unknown).
void app_bne_axis_labels(const Scene *scene, char time[64], char rise[64], char rate[64]);

typedef struct AppBneSamplesOptions {
    const char *scene_path;
    const char *out_dir;
    const char *const *sets; ///< KEY=VALUE for every run
    int set_count;
    const char *vary; ///< "KEY=v1,v2,..." or NULL
    int seeds;        ///< runs per value, seeds seed0 .. seed0 + seeds - 1
    long seed0;
    int jobs; ///< runs at a time (child processes, app/driver/pool.h); MPI ranks under mpirun
    double ldf_periods; ///< window of the large-deviation function, in shaking periods (0 = off)
    int quiet;
    int resume;              ///< 1: skip the runs whose folder holds a completed run
    const AppRender *render; ///< each run's movies and figures, or NULL
    const AppRender *plot;   ///< rise curves and LDF plots, or NULL
} AppBneSamplesOptions;

/// Runs the samples; returns the exit status (0, 1, 2).
int app_bne_samples(const AppBneSamplesOptions *options);
/// `sablier bne` (one entry).
extern const AppCommand app_bne_commands[];

#endif
