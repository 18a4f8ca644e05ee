/* SPDX-License-Identifier: MIT */
/* scene.h: the declarative scene loader. Reads a libconfig scene file (docs/scenes.md), applies
 * `--set KEY=VALUE` overrides, checks every key, and produces plain data: a SimWorldDef per
 * stage, the stage list, and output/render settings (no render types: app/cli/sablier.c maps
 * SceneStyle onto RenderStyle).
 *
 *     Scene *scene = scene_load("scenes/crater/quick.scene", sets, set_count, err, sizeof err);
 *     if (!scene) { fprintf(stderr, "%s\n", err); return 2; }   // err is "file:line: message"
 *     SimWorldDef def = scene_world_def(scene, 0);
 *     scene_free(scene);
 */
#ifndef SCENE_H
#define SCENE_H

#include "base/experiments.h"
#include "base/util.h"
#include "scene/dump_spec.h"
#include "sim/sim.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define SCENE_MAX_STAGES  8
#define SCENE_MAX_FIGURES 16
#define SCENE_MAX_TRACE   64
#define SCENE_NAME_MAX    APP_NAME_MAX
#define SCENE_PATH_MAX    APP_PATH_MAX
/// The largest `seed` (2^53 - 1): summary.json and the figures' metadata write it as a JSON
/// number, which every reader holds exactly only up to 2^53.
#define SCENE_SEED_MAX    9007199254740991ll

/// Colour-by choices; the values of RenderColorBy (render_style.h; render_glue.c asserts it).
typedef enum SceneColorBy {
    SCENE_COLOR_FIXED = 0,
    SCENE_COLOR_FORCE = 1,
    SCENE_COLOR_SPEED = 2,
    SCENE_COLOR_SPECIES = 3,
    SCENE_COLOR_HEIGHT = 4,
} SceneColorBy;

/// Colour maps; the values of RenderColormap (render_glue.c asserts it).
typedef enum SceneColormap {
    SCENE_CMAP_VIRIDIS = 0,
    SCENE_CMAP_YELLOW_RED = 1,
    SCENE_CMAP_GREYS = 2,
} SceneColormap;

/// Drawing settings as written in the scene. Unset fields: ints -1, doubles NaN, strings "",
/// colours -1; unset fields keep the renderer's defaults.
/// SceneStyle.normalised_units (units = "normalised", docs/scenes.md#units): lengths labelled in d;
/// with _G (|g| = 1) times in sqrt(d/g) and speeds in sqrt(g d), else times bare.
enum { SCENE_UNITS_NORMALISED = 1, SCENE_UNITS_NORMALISED_G = 2 };

typedef struct SceneStyle {
    int width, height;                         ///< pixels
    int color_by;                              ///< SceneColorBy
    int colormap;                              ///< SceneColormap
    double range_min, range_max;               ///< colour range in the quantity's unit
    double band_height;                        ///< m
    int outline, orientation_tick;             ///< 0/1
    int force_chains;                          ///< 0/1
    double chain_threshold;                    ///< multiple of the mean normal force
    double chain_width_max;                    ///< pixels
    int velocity_arrows, velocity_field;       ///< 0/1
    int colorbar, time_stamp, scale_bar;       ///< 0/1
    long background_rgb, fill_rgb, fixed_rgb;  ///< 0xRRGGBB
    double view_x0, view_y0, view_x1, view_y1; ///< world window, m
    char title[128];
    int reduced_units;    ///< 1: labels in d and sqrt(d/g) (the scene's units = "reduced")
    int normalised_units; ///< SCENE_UNITS_NORMALISED(_G): units = "normalised" (labels only)
    /* Publication figures (docs/figures.md). */
    int axes;              ///< 0/1; unset: on for figures, off for movies
    double size_w, size_h; ///< print size in size_unit (NaN = unset: width/height pixels)
    int size_inches;       ///< size_unit: 0 cm, 1 in
    double dpi;            ///< pixels per inch (NaN = unset: 300 with a size, else 96)
    double font_pt;        ///< font size, points (NaN = unset)
    int preset;            ///< style: -1 none, 0 single_column, 1 double_column
    int field_color;       ///< 0/1: velocity-field arrows coloured by speed
    int plot_format;       ///< plots also written as: -1 unset (PNG only), 0 png, 1 pdf, 2 svg
} SceneStyle;

/// The most grains one stage's `add` may list.
#define SCENE_MAX_ADDS 10000

/// A grain a stage places at its start (`add`, docs/scenes.md#grains-added-by-a-stage; app/
/// stage_adds.c). Its id is fixed at load: the added grains of every stage, in stage order and
/// list order, take the ids after the largest id of the scene's own grains.
typedef struct SceneAdd {
    char name[SCENE_NAME_MAX];       ///< "" when unnamed; unique in the scene
    double x, y, vx, vy, omega;      ///< m, m/s, rad/s
    double radius;                   ///< m
    int species;                     ///< material index
    int motion;                      ///< -1, or SIM_GRAIN_BODY(b): a fixed grain of body b
    uint32_t id;                     ///< its stable id
    char where[SCENE_PATH_MAX + 32]; ///< "file:line" of its entry
} SceneAdd;

/// How a stage gets its grains.
typedef enum SceneLoad {
    SCENE_LOAD_SCENE = 0,    ///< build from the scene's `grains` (first stage default)
    SCENE_LOAD_PREVIOUS = 1, ///< continue from the previous stage (later stages default)
    SCENE_LOAD_FILE = 2,     ///< a checkpoint file (sim_world_save)
} SceneLoad;

typedef struct SceneStage {
    char name[SCENE_NAME_MAX];
    SceneLoad load;
    char load_path[SCENE_PATH_MAX]; ///< resolved against the scene's folder (SCENE_LOAD_FILE)
    double time_step;               ///< dt, s (0 = from steps_per_contact)
    double duration;                ///< time.end: simulated time of the stage, s (the cap)
    double settle_kinetic;          ///< stop once E_kin + E_rot < this, J; 0 = off
    double settle_after;            ///< the settle test starts this long into the stage, s
    double settle_per_grain;        ///< stop once (E_kin + E_rot) / mobile grains < this, J
    double settle_hold;             ///< ... at every energy row for this long, s (0: one row)
    int remove_count;
    uint32_t *remove_ids; ///< stable ids removed at the stage start
    int movie;            ///< 1: write <stage>.mp4
    int skip;             ///< 1: not run (a sweep member starts from a saved bed)
    /* Forcing of the stage (docs/scenes.md, stages): its own `gravity`, `effects` and `motions`,
     * or the previous stage's (the scene's for the first). */
    double gravity_x, gravity_y; ///< m/s^2
    unsigned effects;            ///< SimEffect bits in force (a subset of the scene's)
    unsigned motions;            ///< bit m: motion m is enabled in this stage
    unsigned restart_motions;    ///< bit m: motion m's clock restarts at the stage start
    int declares_motions;        ///< 1: some stage of the scene has a `motions` list
    double movie_view[4];        ///< the stage movie's window [x0, y0, x1, y1], m; x1 <= x0: none
    int add_count;
    SceneAdd *adds; ///< grains placed at the stage start, after its removals
} SceneStage;

typedef struct SceneFigure {
    char name[SCENE_NAME_MAX];
    int stage;  ///< index into stages
    int at_end; ///< 1: at the stage end, 0: at its start (after load, dig, removals), 2: at_time
    double at_time;   ///< s after the stage start (at_end == 2)
    char format[8];   ///< "png", "pdf" or "svg"
    SceneStyle style; ///< the scene's `render` style with the figure's own keys on top
} SceneFigure;

typedef enum SceneDragModel {
    SCENE_DRAG_LINEAR = 0, ///< F = -c (v - u)
    SCENE_DRAG_STOKES = 1, ///< F = -3 pi eta d (v - u)
} SceneDragModel;

/// Fluid drag parameters (effect fluid_drag), applied through SimBodyForce.
typedef struct SceneDrag {
    SceneDragModel model;
    double coefficient;        ///< c, kg/s (linear)
    double viscosity;          ///< eta, Pa s (stokes)
    double fluid_vx, fluid_vy; ///< u, m/s
} SceneDrag;

typedef struct SceneOutput {
    double frame_rate;         ///< movie frames per simulated second, 1/s
    double fps;                ///< video frames per second of movie, 1/s
    double movie_speed;        ///< simulated s per s of video (0: frame_rate or movie_duration)
    double movie_duration;     ///< s of video per stage of time.end (0: unset)
    int crf;                   ///< libx264 quality
    int drawer;                ///< 0 cairo, 1 osmesa (RenderDrawer order)
    double energy_every;       ///< s of simulated time between energy.csv rows
    double checkpoint_every;   ///< s of simulated time between periodic checkpoints (0: none)
    double checkpoint_minutes; ///< minutes of wall clock between periodic checkpoints (0: none)
    int trace_count;
    uint32_t trace_ids[SCENE_MAX_TRACE];
    double trace_every;   ///< s between trace.csv rows
    double t_star_length; ///< D of t* = t / sqrt(D/g), m (0 = the sim's time scale)
    int figure_count;
    SceneFigure figures[SCENE_MAX_FIGURES];
    AppDumpSpec dump[SCENE_MAX_STAGES]; ///< per-grain dumps of each stage (app/scene/dump_spec.h)
    int movie_view; ///< 0 "grains": the grains' box at the stage start; 1 "container": all, per
                    ///< frame
} SceneOutput;

typedef struct SceneWhere SceneWhere; /* private: field path -> file:line */

/// The most steps one stage may take (about three years of a 10 000 steps/s run); beyond it
/// the loader refuses the stage (step counts are 64-bit, their time sums exact).
#define SCENE_MAX_STEPS 1e12

/// The most grains a scene may build (rain, rows, columns, box): bounds memory before it is
/// allocated.
#define SCENE_MAX_GRAINS 1e7
/// Movie frame rates above this are refused at load (render's RENDER_VIDEO_MAX_FPS; render_glue.c
/// asserts that the two agree).
#define SCENE_MAX_FPS    1000.0

typedef struct Scene {
    char path[SCENE_PATH_MAX];
    char name[SCENE_NAME_MAX];
    uint64_t seed;
    SimWorldDef def;       ///< grains and walls point into this scene (valid until scene_free)
    SimGrainBuffer grains; ///< the scene's own grains (first stage)
    int fixed_count;       ///< fixed grains among them
    SimWall *walls;
    SimWallBody *wall_bodies; ///< one per wall when a wall responds (a mass or a servo), else NULL
    char motion_names[SIM_MAX_MOTIONS][SCENE_NAME_MAX];
    char species_names[SIM_MAX_SPECIES][SCENE_NAME_MAX];
    SceneDrag drag;
    int stage_count;
    SceneStage stages[SCENE_MAX_STAGES];
    SceneOutput output;
    SceneStyle style; ///< `render` group
    SceneWhere *where;
    /// The names of the output folder's files taken while the scene loads (scene_claim_output),
    /// so that no two outputs share one; freed once loaded.
    struct SceneClaims *claims;
    char sha256[65]; ///< SHA-256 of the scene file as read (hex; "" when unreadable)
    char *resolved;  ///< the scene as loaded: includes expanded, --set applied (libconfig text)
    /// Per experiment family, in registry order (app/base/experiments.h): its parsed state, NULL
    /// when the scene does not use it. Read through the family's own accessor.
    void *experiments[APP_EXPERIMENT_MAX];
    /// units = "reduced": outputs in d (mean diameter of the mobile grains), m (their mean mass)
    /// and sqrt(d/g) (docs/scenes.md#units); 0 = SI
    int units_reduced;
    /// units = "normalised": the scene's numbers are already in its own units (lengths in d, times
    /// in sqrt(d/g) when |g| = 1, else in the scene's time unit); outputs are written as given and
    /// figures are labelled in d (docs/scenes.md#units); 0 = not declared
    int units_normalised;
    int source_count;
    struct SceneSource *sources; ///< insertion sources (app/scene/sources.h), malloc'd
    /// time.target_error: |e - e_n| the time step was chosen for (app/scene/advice.h); 0 = not used
    double target_error;
    /// One above the largest id of the grains the stages add (a source's grains take ids from
    /// here up); 0 when no stage adds grains.
    uint32_t added_id_end;
    /// `bodies`: rigid groups of fixed grains (def.grain_bodies points here), their group names
    SimWallBody *grain_bodies;
    char (*body_names)[SCENE_NAME_MAX];
} Scene;

/// Loads, overrides and checks a scene. `sets` are "KEY=VALUE" strings. Returns NULL with
/// "file:line: message" (or "--set KEY: message") in err when anything is wrong.
Scene *scene_load(const char *path, const char *const *sets, int set_count, char *err,
                  size_t err_size);
void scene_free(Scene *scene);

/// The world definition of one stage (its time step; the scene's own grains).
SimWorldDef scene_world_def(const Scene *scene, int stage);

/// Runs sim_world_def_validate on a definition derived from this scene and maps the reported
/// field back to "file:line: message". Returns 0 when valid.
int scene_validate_def(const Scene *scene, int stage, const SimWorldDef *def, char *err,
                       size_t err_size);

/// "file:line" of the scene key behind a SimError field ("materials[0].normal_stiffness").
const char *scene_where_field(const Scene *scene, int stage, const char *field);

/// The scene's parsed state of experiment `family` (NULL when the scene does not use it); each
/// family reads its own through this (app_bne_of, app_crater_of, ...).
void *scene_experiment_state(const Scene *scene, const AppExperiment *family);

/// The grain a stage adds (SceneAdd) named `name`, or with id `id` when name is NULL; NULL when
/// no stage adds it.
const SceneAdd *scene_added_grain(const Scene *scene, const char *name, uint32_t id);

/// Places stage k's added grains into the world at the stage start: refused (-1 with "file:line:
/// message" in err) when one overlaps a wall, a grain of the world or another added grain, or
/// when its id is in use (a state loaded by `load`). 0 when placed.
int scene_stage_add(const Scene *scene, int k, SimWorld *world, char *err, size_t err_size);

/// One line on `out` naming the scene's tangential law and whether it has static friction.
void scene_describe_friction(const Scene *scene, FILE *out);

/// Warnings "file:line: warning: ..." on `out` for motions that move nothing and stages that
/// enable one (app/scene/scene_advise.c); returns their count.
int scene_warn(const Scene *scene, FILE *out);

/// Index of a stage by name, -1 when absent.
int scene_stage_index(const Scene *scene, const char *name);
/// A species' material before its keys are read: sim_material_default() without damping
/// (damping_mode GAMMA, gamma_n 0), what a scene's species that gives none of gamma_n,
/// restitution, critical_fraction gets.
SimMaterial scene_material_default(void);
/// The key tables of the scene loader, NULL-ended (bindings check their dictionaries against
/// them, docs/python.md): "species" (every key of a species), "material" (k = 0: SimMaterial
/// field names; k = 1: the species key of each, same order), "motion.kinds" (values of `kind`,
/// in SimMotionKind order), "motion" (k = the kind: its own keys), "motion.schedule" (keys of
/// every kind). NULL for an unknown group.
const char *const *scene_keys(const char *group, int k);

/// Comma-separated names of declared effects ("friction, removal"; "none").
void scene_effect_names(unsigned effects, char *out, size_t out_size);

/// The style with every field unset.
SceneStyle scene_style_unset(void);

/// A physical quantity, for the scene's unit names (scene_unit, scene_axis_label).
typedef enum SceneQuantity {
    SCENE_LENGTH,
    SCENE_TIME,
    SCENE_SPEED,
    SCENE_ACCELERATION,
    SCENE_MASS,
    SCENE_FORCE,
    SCENE_ENERGY,
    SCENE_STRESS,           ///< force per length (2D stress, stiffness)
    SCENE_AREAL_DENSITY,    ///< mass per area
    SCENE_MOMENTUM_DENSITY, ///< mass per length per time
    SCENE_SPEED_SQUARED,
    SCENE_RATE,      ///< per time
    SCENE_MASS_RATE, ///< mass per time
    SCENE_DIMENSIONLESS,
    SCENE_DENSITY,           ///< mass per volume (a species' density with mass_model "sphere")
    SCENE_HERTZ_STIFFNESS,   ///< force per length^1.5 (k_n of the Hertz law)
    SCENE_ROLLING_STIFFNESS, ///< torque per radian (k_r)
    SCENE_QUANTITY_COUNT
} SceneQuantity;

/// The unit of `quantity` in the scene's unit system, the one table that every label, check
/// line and summary reads (docs/scenes.md#units): SI ("m", "s", "N/m"; also in reduced units,
/// whose inputs and families' files are SI); units = "normalised" with |g| = 1 in d, m and
/// sqrt(d/g) ("d", "sqrt(d/g)", "m g/d"); normalised with another g in d and m with times bare
/// (""). `figure` 1: figure text ("√(d/g)", "m/d²"), 0: ASCII for terminals, CSV and JSON.
/// "" for no unit. scene NULL: SI.
const char *scene_unit(const Scene *scene, SceneQuantity quantity, int figure);
/// scene_unit for a style (its normalised_units), for what holds a style but no scene: a
/// figure's or a movie's colour bar. style NULL: SI.
const char *scene_style_unit(const SceneStyle *style, SceneQuantity quantity, int figure);

/// The ASCII unit of `quantity` after a number, with its space: " m", " sqrt(d/g)", or "" where
/// the unit is "" (scene_unit). Returns buf.
const char *scene_unit_after(const Scene *scene, SceneQuantity quantity, char *buf, size_t size);

/// The label of an axis `name` of `quantity` in the scene's units (scene_unit): "x (m)", "t (s)",
/// "u (m/s)" in SI (and in reduced units, where the families' own files stay SI); with units =
/// "normalised" "x / d", "t / √(d/g)", "σ / (m g/d)", the name bare where the unit is "";
/// a dimensionless quantity is "φ (1)" in every system (docs/figures.md#figure-lint).
/// scene NULL: SI. Returns buf.
const char *scene_axis_label(const Scene *scene, const char *name, SceneQuantity quantity,
                             char *buf, size_t size);

/// The quantity of the value a `--set KEY` sets, for its unit (scene_axis_label): a species key
/// ("species.0.mu", "species[1].k_n") by the species table (app/scene/scene_grains.c), whose
/// density and k_n follow the scene's mass model and normal law; SCENE_QUANTITY_COUNT for a key
/// whose unit is not recorded (every other key, gamma_n of the Hertz law).
SceneQuantity scene_key_quantity(const Scene *scene, const char *key);
/// "libconfig 1.5.0"
const char *scene_libconfig_version(void);
/// Simulated time between stage k's movie frames, s: movie_speed / fps, else time.end /
/// (movie_duration fps), else 1 / frame_rate (docs/scenes.md#output).
double scene_frame_interval(const Scene *scene, int k);

#endif
