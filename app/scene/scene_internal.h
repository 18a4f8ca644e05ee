/* SPDX-License-Identifier: MIT */
/* scene_internal.h: what the scene loader's files share (not part of the API; scene.h is).
 *
 *     scene_load.c     scene_load: read the file, apply --set, parse in order, check; the top-level
 *                      physics (effects, time, guard, contact, periodic, drag); the public helpers
 *     scene_keys.c     the key rules every file shares (effect gates, file names, family keys)
 *     scene_set.c      --set KEY=VALUE overrides, applied to the libconfig tree before parsing
 *     scene_grains.c   species, motions, grain builders (list, rain, box, rows, columns), walls,
 *                      sinks
 *     scene_stages.c   stages
 *     scene_output.c   output, render styles, figures
 *     scene_check.c    where-mapping (field -> file:line), start overlaps, scene_validate_def
 *     config.c         the typed getters every file uses (config.h) */
#ifndef APP_SCENE_INTERNAL_H
#define APP_SCENE_INTERNAL_H

#include "base/config.h"
#include "scene/scene.h"

#include <libconfig.h>

#define WHERE_MAX (SCENE_PATH_MAX + 96)

typedef struct WhereItem {
    char field[64];
    char where[WHERE_MAX];
} WhereItem;

struct SceneWhere {
    int count, capacity;
    WhereItem *items;
    int *grain_item; /* per scene grain: index into items */
    int grain_capacity;
    char stage_dt[SCENE_MAX_STAGES][WHERE_MAX];
    char stage_load[SCENE_MAX_STAGES][WHERE_MAX];
    char stage_motions[SCENE_MAX_STAGES][WHERE_MAX]; /* its `motions` list ("": none) */
    char motion[SIM_MAX_MOTIONS][WHERE_MAX];         /* motions.NAME */
    char fallback[WHERE_MAX];
};

/// One scene_load in progress.
typedef struct Loader {
    Scene *scene;
    config_t config;
    AppConfig p; ///< errors: path = the scene file, err = scene_load's buffer
    unsigned effects;
    const config_setting_t *effects_setting;
    char dir[SCENE_PATH_MAX]; ///< the scene's folder: @include and checkpoint paths
    double box_height;        ///< grains.box y1 - y0, m: default D of t*
    char *set_keys[64];       ///< copies of --set keys, pointed to by setting hooks
    int set_count;
    int unsetting; ///< 1 while an --unset is applied (its messages)
} Loader;

/// A key of a scene group and the quantity of its value, for its unit (docs/scenes.md#units;
/// SCENE_QUANTITY_COUNT: a name, index or count of things, no unit). A group's table of them,
/// ended by a NULL key, is both the keys the loader accepts (loader_keys) and the units of the
/// keys a sweep varies (scene_key_quantity).
typedef struct SceneKey {
    const char *key;
    SceneQuantity quantity;
} SceneKey;

/// The most keys a SceneKey table holds (loader_keys).
#define SCENE_GROUP_KEYS_MAX 32

/// The tables of the scene's `time` group (scene_load.c) and of `grains.rain` and `grains.box`
/// (scene_grains.c).
extern const SceneKey loader_time_keys[], loader_rain_keys[], loader_box_keys[];

/* scene_keys.c */
/// app_config_keys with the keys of a SceneKey table: 0, or -1 with a message naming `what`.
int loader_keys(Loader *L, const config_setting_t *g, const char *what, const SceneKey *keys);
/// A key that only makes sense with an effect: refused when the effect is not declared.
int loader_gate(Loader *L, const config_setting_t *g, const char *key, unsigned effect);
/// Names used in file names: letters, digits, '_', '-', '.'.
int loader_check_file_name(Loader *L, const config_setting_t *g, const char *key, const char *v);
/// Claims the file NAME of the output folder (a folder: "NAME/") for one output of the scene:
/// `what` writes it ("measure `stress`"), declared at setting `s` (NULL: one of the run's or a
/// family's own files). No two outputs may share a name: -1 with "file:line: ..." through p (at
/// the declared one of the two) when NAME is taken already, else 0. Two undeclared claims of one
/// name are one file (0).
int scene_claim_output(Scene *scene, AppConfig *p, const config_setting_t *s, const char *what,
                       const char *name);
/// Frees the claims (NULL-safe); scene->claims NULL after.
void scene_claims_free(Scene *scene);
/// The run's own files and each stage's (STAGE.state, STAGE.mp4, ...) claimed. 0, or -1.
int loader_claim_run_outputs(Loader *L, const config_setting_t *root);
/// The keys the registered experiment families own (app/base/experiments.c): their top-level groups
/// (which = 0), stage keys (1) or output keys (2); NULL-ended.
const char *const *loader_family_keys(int which);

/* scene_set.c */
/// Applies one "KEY=VALUE" to the libconfig tree. 0, or -1 with "--set KEY: message".
int loader_apply_set(Loader *L, const char *assignment);

/* scene_grains.c */
int loader_parse_species(Loader *L, const config_setting_t *root);
/// `species = "name"` or an index in g: 1 found, 0 absent (*out = 0), -1 error.
int loader_get_species(Loader *L, const config_setting_t *g, int *out);
int loader_parse_motions(Loader *L, const config_setting_t *root);
int loader_parse_grains(Loader *L, const config_setting_t *root);
int loader_parse_walls(Loader *L, const config_setting_t *root);
/* walls.N's mass, axis, force, gravity and servo into scene->wall_bodies[k] (scene_walls.c):
 * 0, or -1 with the message. */
int loader_parse_wall_body(Loader *L, const config_setting_t *g, const char *what, int k);
/* `bodies`: rigid groups of fixed grains (scene_walls.c), parsed before the grains; each entry's
 * group is named by the grains.rows and columns entries' `group` (loader_get_group: 1 with
 * *motion set to the body's SIM_GRAIN_BODY, 0 absent, -1 an unknown group or a grain that also
 * follows a motion); loader_check_bodies, once the stages are read, refuses a group without
 * grains (rows, columns or a stage's `add`), one filled both by rows or columns and by a stage,
 * and one that two stages add to (a body takes its grains once). 0, or -1. */
int loader_parse_bodies(Loader *L, const config_setting_t *root);
int loader_get_group(Loader *L, const config_setting_t *g, const char *what, int *motion);
int loader_check_bodies(Loader *L, const config_setting_t *root);
int loader_parse_sinks(Loader *L, const config_setting_t *root);

/* sources.c */
int loader_parse_sources(Loader *L, const config_setting_t *root);
/// What one step may ask of each source, against the time step of every stage it is active in
/// (stage_dt[stage], s, as a run takes it); 0, or -1 with the message.
int loader_check_sources(Loader *L, const config_setting_t *root, const double *stage_dt);

/* scene_stages.c */
int loader_parse_stages(Loader *L, const config_setting_t *root);
/* Every `remove_ids` id names a grain of the scene (while the grains are the scene's own: no
 * sources, no stage loading a file before). 0, or -1 with file:line. */
int loader_check_remove_ids(Loader *L, const config_setting_t *root);

/* stage_adds.c */
/// Stage k's `add` list (g: its group). 0, or -1.
int loader_parse_adds(Loader *L, const config_setting_t *g, int k);
/// The added grains' ids (SceneAdd.id, Scene.added_id_end), their names unique, and their overlaps
/// where the world is known at load (the first stage built from the scene; among each stage's
/// own). Once the grains, walls and stages are read. 0, or -1.
int loader_assign_add_ids(Loader *L);

/* scene_output.c */
int loader_parse_output(Loader *L, const config_setting_t *root);

/* scene_check.c */
/// Records that SimWorldDef field `field` ("materials[0].normal_stiffness") was set by s.
void loader_where_add(Loader *L, const char *field, const config_setting_t *s);
/// Records the location of every grain added since `first` as the location of setting s.
void loader_where_grains(Loader *L, int first, const config_setting_t *s, const char *field);
/// Grains overlapping grains (a mobile one involved) or walls at the start. 0, or -1.
int loader_check_overlaps(Loader *L);
/// Every `view` = [x0, y0, x1, y1] of the scene (render, figures, stages), once every group is
/// read: each side within [0.1, 1e9] times the smallest grain radius of the scene (of its
/// sources when it has no grains), so that a view of 1e-300 never sends the renderer into
/// endless drawing. 0, or -1 at the view's line.
int loader_check_views(Loader *L);

#endif
