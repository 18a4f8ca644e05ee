/* SPDX-License-Identifier: MIT */
/* discharge.h: open-pile deposition, discharge through an orifice, jamming and arches (thesis
 * 004, docs/discharge.md). A scene with a `discharge` group describes the population and the
 * protocol; lengths are in mean diameters d (d = 1), masses in units of a d = 1 grain (disk
 * density 4/pi), time in the unit that makes k_n = 1000 (notes §1.10-1.12).
 *
 *     AppDischargeDeposit dep;
 *     SimWorld *pile = app_discharge_deposit(scene, seed, NULL, &dep, err, sizeof err);   //
 * relaxed pile sim_world_save(pile, "pile.state", &error); AppDischarge out; app_discharge(scene,
 * "pile.state", 3.0, NULL, &out, err, sizeof err);     // s, h, arch
 *
 * Knows nothing about rendering (frames go to an optional SimFrameSink).
 */
#ifndef APP_DISCHARGE_H
#define APP_DISCHARGE_H

#include "base/experiment.h"
#include "scene/scene.h"
#include "sim/sim.h"

#include <libconfig.h>
#include <stddef.h>
#include <stdint.h>

#define APP_DISCHARGE_ARCH_MAX 256

/// The scene's `discharge` group (docs/discharge.md). Lengths in d, times in simulation units.
typedef struct AppDischargeDef {
    double base_length;     ///< L, d: base of touching fixed grains over [-L/2, L/2] at y = 0
    double base_diameter;   ///< diameter of the base grains, d (0.1)
    int thesis_gravity;     ///< 1: g = 1/(L+1) d/t^2, the thesis's 2/(L(L+1)) in its unit L/2
    double release_height;  ///< H, d (0 = L)
    double row_period;      ///< T_dep (0 = sqrt(2 d_max / g), free fall over one d_max)
    double row_fill;        ///< fraction of the base a row covers (0.5)
    double row_jitter;      ///< slot jitter as a fraction of the free half-slot (0.95)
    int max_rows;           ///< rows released at most (0 = ceil(1.5 (L + 1)))
    int stationary_rows;    ///< window of the stationarity test, rows (10; 0 = off)
    double stationary_gain; ///< stop when the pile gained < gain x released over the window (0.1)
    double dt_divisor;      ///< dt = sqrt(m_min / k_n) / divisor (50); 0: the scene's time step
    double tolerance;       ///< static-equilibrium tolerance (004 §3.1: 1e-6)
    int check_every;        ///< steps between equilibrium checks (500)
    double relax_time;      ///< cap of each relaxation, simulation time (0 = auto)
    double discharge_time;  ///< cap of a discharge, simulation time (0 = auto)
    double polydispersity;  ///< uniform half-width of radii as a fraction (0.025)
    int species_count;      ///< entries in fractions/diameters (the scene's species)
    double fractions[SIM_MAX_SPECIES]; ///< probability of each species in a row
    double diameters[SIM_MAX_SPECIES]; ///< mean diameter of each species, d
    int base_species;                  ///< material of the base grains
    double exit_half_width; ///< grains leaving within this of the centre went through (0 = 4 d_max)
    int arch_force_check;   ///< 1: every arch link must carry a positive normal force
    double widths[64];      ///< default orifice widths of `sablier discharge`, d
    int width_count;
} AppDischargeDef;

/// The largest base: at most this many base grains (L / base_diameter), the loader's bound on a
/// fixed row (docs/scenes.md).
#define APP_DISCHARGE_MAX_BASE_GRAINS 1e7

/// 1 when an orifice of width w (d) fits the base of `def`: w in [1, L] (a narrower orifice
/// passes no grain, or none of the base's is removed; a wider one than the base leaves none).
int app_discharge_width_fits(const AppDischargeDef *def, double w);

/// Parses a scene's `discharge` group (called by the scene loader). Returns 0, or -1 with
/// "file:line: message" in err.
int app_discharge_parse(const config_setting_t *group, const char *scene_path, int species_count,
                        AppDischargeDef *def, char *err, size_t err_size);

/// Derived protocol figures for one scene.
typedef struct AppDischargeGeometry {
    double g;            ///< gravity, d/t^2
    double d_max, d_min; ///< largest and smallest possible grain diameter, d
    double d_mean;       ///< population mean diameter, d
    double m_min;        ///< lightest possible grain, mass units
    double dt;           ///< time step
    double row_period;   ///< T_dep
    double height;       ///< H
    int row_size;        ///< grains per row
    int max_rows;
    double relax_time, discharge_time; ///< caps
    double exit_half_width;
} AppDischargeGeometry;

void app_discharge_geometry(const Scene *scene, AppDischargeGeometry *geo);

/// Frames during a run (movies): every `every` steps to `sink` (NULL sink = none).
typedef struct AppDischargeFrames {
    SimFrameSink sink;
    long every;
} AppDischargeFrames;

typedef struct AppDischargeDeposit {
    int rows;        ///< rows released
    int released;    ///< grains released
    int pile;        ///< mobile grains left at the end
    long lost;       ///< grains that fell over the edges
    int equilibrium; ///< 1: relaxed to the 004 §3.1 criteria, 0: cap reached
    double time;     ///< simulation time at the end
    long steps;
    double wall_seconds;
    double height;        ///< central height h of the pile (y of the top centre in |x| < d/2), d
    int pile_count_rows;  ///< entries in pile_count
    int pile_count[1024]; ///< grains with >= 1 contact after each row (004 fig. 2.8)
} AppDischargeDeposit;

/// Builds the base, rains rows and relaxes to static equilibrium (testing it every check_every
/// steps), on the stage runner (app/discharge/discharge.c). Returns the world (caller destroys), or
/// NULL with a message. `trace` (optional) gets "t,row,released,pile,mobile" rows.
SimWorld *app_discharge_deposit(const Scene *scene, uint64_t seed, const AppDischargeFrames *frames,
                                FILE *trace, AppDischargeDeposit *out, char *err, size_t err_size);

/// Removes the fixed grains whose centre lies within width/2 of center_x; returns how many.
int app_discharge_open_orifice(SimWorld *world, double width, double center_x);

/// Order parameter h: y of the highest mobile-grain centre in |x - center_x| < half_width, 0
/// when that strip is empty (the pile split in two, 004 §3.3).
double app_discharge_central_height(const SimFrame *frame, double center_x, double half_width);

typedef struct AppDischarge {
    double width;                              ///< w, d
    int opened;                                ///< base grains removed
    long through;                              ///< s: grains out through the orifice
    long edges;                                ///< grains lost over the edges
    int pile;                                  ///< mobile grains left
    int pile_species[SIM_MAX_SPECIES];         ///< per species
    double height;                             ///< h, d
    int arch;                                  ///< arch grains (0 = none)
    int arch_species[SIM_MAX_SPECIES];         ///< per species
    uint32_t arch_ids[APP_DISCHARGE_ARCH_MAX]; ///< stable ids of the arch grains, left to right
    int equilibrium;                           ///< 1: stopped at static equilibrium
    int settled_before;                        ///< 1: the reloaded pile was at equilibrium
    double time;                               ///< simulation time of the discharge
    long steps;
    double wall_seconds;
} AppDischarge;

/// Loads a pile checkpoint, relaxes it (checkpoints carry no contact history: the frictional
/// forces rebuild), opens the orifice, runs to a new equilibrium (or the cap) and measures.
/// Returns the world at the end (caller destroys; NULL on failure with a message).
SimWorld *app_discharge(const Scene *scene, const char *pile_path, double width,
                        const AppDischargeFrames *frames, AppDischarge *out, char *err,
                        size_t err_size);

/// Measures s, h, arch and composition on a world (used by app_discharge).
void app_discharge_measure(SimWorld *world, const AppDischargeDef *def, AppDischarge *out);

/// Per-grain arch marks in frame order (1 for arch members, -1 otherwise) for the renderer.
void app_discharge_arch_marks(const SimFrame *frame, const AppDischarge *result, int *marks);

/// One CSV row of a discharge result (no newline); header from app_discharge_csv_header().
const char *app_discharge_csv_header(void);
void app_discharge_csv_row(const AppDischarge *r, long sample, double base_length, char *out,
                           size_t size);

/// The discharge family (app/base/experiment.h): the `discharge` group and the commands `discharge`
/// and `study` (app_discharge_commands, two entries).
extern const AppExperiment app_discharge_experiment;
/// The protocol world's timing with the scene's own time step (time.dt, or
/// time.steps_per_contact when time.dt = 0), as `discharge.dt_divisor = 0` uses it.
SimTiming app_discharge_timing(const Scene *scene);
extern const AppCommand app_discharge_commands[];
/// The scene's discharge protocol (NULL when it has no `discharge` group).
const AppDischargeDef *app_discharge_of(const Scene *scene);

#endif
