/* SPDX-License-Identifier: MIT */
/* sediment.h: bed-load transport under the 1D fluid column of thesis 002 ch. 6-7 (sim/fluid.c).
 * Parses a scene's `sediment` group (older name `fluid`; effect fluid_drag), owns the SimFluid
 * whose body-force stage drags the grains, and measures during a run: sediment.csv (flux q(t), bed
 * level, fluid velocity at the top), <stage>.fluid.csv (fluid, concentration, grain-velocity and
 * stress profiles) and sediment.json (q_sat, T_sat, the control numbers).
 *
 *     // in scene_load, after grains and stages:
 *     scene->sediment = app_sediment_parse(member(root, "sediment"), scene, err, sizeof err);
 *     // in the runner: app_sediment_begin / _stage / _row / _stage_end / _end
 */
#ifndef APP_SEDIMENT_H
#define APP_SEDIMENT_H

#include "base/experiment.h"
#include "scene/scene.h"
#include "sim/sim.h"

#include <libconfig.h>
#include <stddef.h>
#include <stdio.h>

/// Control numbers of the column (002 eqs. 40-42) and what a run measured.
typedef struct AppSedimentNumbers {
    double diameter;      ///< d, m
    double density_ratio; ///< D_R = rho_p / rho_f
    double galileo;       ///< R = (d / nu) sqrt((D_R - 1) g d) (the thesis's "Reynolds")
    double shields;       ///< Theta = u*^2 / ((D_R - 1) g d)
    double flux_scale;    ///< d sqrt((D_R - 1) g d): q* = q / this, m^2/s
} AppSedimentNumbers;

typedef struct AppSediment AppSediment;

/// Parses `sediment` (NULL when absent: returns NULL with err empty) and creates the fluid; sets
/// the scene's body force. NULL with "file:line: message" in err on bad input.
AppSediment *app_sediment_parse(const config_setting_t *group, Scene *scene, char *err,
                                size_t err_size);
void app_sediment_free(AppSediment *sediment);

SimFluid *app_sediment_fluid(const AppSediment *sediment);
/// The family's group as the scene names it: "sediment", or its older name "fluid".
const char *app_sediment_group(const AppSediment *sediment);
AppSedimentNumbers app_sediment_numbers(const AppSediment *sediment);

/// Runner hooks. begin opens sediment.csv in out_dir; stage is called at each stage start (the
/// fluid acts from the `flow_stage` on; before it the grains settle dry); row after every energy
/// row; stage_end writes <stage>.fluid.csv; end closes the CSV and writes sediment.json. Each
/// returns 0 or -1 with a message in err.
int app_sediment_begin(AppSediment *s, const char *out_dir, char *err, size_t err_size);
void app_sediment_stage(AppSediment *s, const Scene *scene, int stage, SimWorld *world);
void app_sediment_row(AppSediment *s, SimWorld *world);
int app_sediment_stage_end(AppSediment *s, SimWorld *world, const char *out_dir,
                           const char *stage_name, char *err, size_t err_size);
int app_sediment_end(AppSediment *s, int ok, char *err, size_t err_size);

/// Volume (2D area) flux per unit bed width of a frame's mobile grains, sum pi r^2 v_x / L_x,
/// m^2/s.
double app_sediment_flux(const SimFrame *frame, double width);

/// Saturation of a flux record: q_sat = mean over the last third of [t_start, t_end]; T_sat = the
/// integral of (1 - q / q_sat) dt from t_start (exactly T for q_sat (1 - exp(-t / T))).
/// Returns q_sat (NAN without samples).
double app_sediment_saturation(const double *t, const double *q, int count, double t_start,
                               double *t_sat);

/* ---------------------------------------------------------------- Shields scans */

/// Transport threshold of a Shields scan (ours; the thesis gives no method): the points with
/// q* > level transport. Theta_c is the zero-flux intercept of the line through the two lowest
/// transporting points, clamped to the bracket [highest Theta below the first transporting point
/// that does not transport, first transporting Theta]; the bracket's middle when only one point
/// transports. Writes the bracket to *below and *above (NAN when a side is missing) and returns
/// Theta_c, or NAN when no point transports or the lowest one already does. The values need not
/// be sorted; non-finite q* are ignored.
double app_sediment_threshold(const double *shields, const double *q_star, int count, double level,
                              double *below, double *above);

#define APP_SEDIMENT_USAGE                                                                         \
    "usage: sablier sediment SCENE --shields T1,T2,... [--jobs J] [--level Q] [--out DIR]\n"       \
    "                        [--set KEY=VALUE]... [--render] [--resume] [--quiet|-q]\n"            \
    "Shields scan (thesis 002 ch. 7): runs a scene with a `sediment` group once per Shields\n"     \
    "number (--set sediment.shields=T) into DIR/shields=T/, J at a time (default 2), then\n"       \
    "writes DIR/flux.csv (q_sat, q*_sat, T_sat per value), DIR/threshold.json and DIR/flux.png\n"  \
    "(q* against Theta with the threshold estimate; docs/sediment.md).\n"                          \
    "  --level Q   q* above which a point transports (default 1e-3)\n"                             \
    "  --render    each member's own figures and movies (default: none)\n"                         \
    "  --resume    skip the members whose folder holds a completed run\n"                          \
    "SIGINT or SIGTERM stops the members, writes flux.csv (status `interrupted` for those not\n"   \
    "finished) and exits 130 or 143.\n"                                                            \
    "\n"                                                                                           \
    "exit status: 0 every member succeeded, 1 a member failed, 2 bad input (nothing runs) or a\n"  \
    "table that cannot be written, 130/143 SIGINT/SIGTERM\n"

/// `sablier sediment`: parses argv (argv[1] is "sediment"), runs the scan; returns the exit status.
int app_sediment_command(int argc, char **argv, const AppEnv *env);
/// `sablier sediment` (one entry).
extern const AppCommand app_sediment_commands[];

/// The sediment family (app/base/experiment.h): the `sediment` group (older name `fluid`),
/// sediment.csv at every energy row, <stage>.fluid.csv at each stage end, sediment.json at the end;
/// figures get the column's velocity and concentration profiles beside the bed.
extern const AppExperiment app_sediment_experiment;
/// The scene's sediment state (NULL when it has no `sediment` group).
AppSediment *app_sediment_of(const Scene *scene);

#endif
