/* SPDX-License-Identifier: MIT */
/* scene_grains.c: the scene's species and motions, its grains (grains.list, rain, box, rows,
 * columns: stable ids follow that order), walls and sinks (docs/scenes.md). */
#include "base/experiments.h"
#include "scene/grains_file.h"
#include "scene/scene_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- species, motions */

static const char *const SPECIES_KEYS[] = {
    "name", "density", "k_n",  "gamma_n", "restitution", "critical_fraction", "mu", "gamma_s",
    "k_t",  "gamma_t", "mu_r", "k_r",     NULL};

/* SimMaterial fields -> the species keys that set them, and the quantity of each (its unit, the
 * `species` table of docs/scenes.md): for mapping SimError fields to lines, the table the Python
 * module reads (scene_keys "material") and the unit of a swept key (scene_key_quantity). density
 * and k_n as with mass_model "disk" and the linear law. */
static const struct {
    const char *field, *key;
    SceneQuantity quantity;
} MATERIAL_MAP[] = {
    {"density", "density", SCENE_AREAL_DENSITY},
    {"normal_stiffness", "k_n", SCENE_STRESS},
    {"normal_damping", "gamma_n", SCENE_MASS_RATE},
    {"restitution", "restitution", SCENE_DIMENSIONLESS},
    {"critical_fraction", "critical_fraction", SCENE_DIMENSIONLESS},
    {"friction", "mu", SCENE_DIMENSIONLESS},
    {"tangential_damping", "gamma_s", SCENE_MASS_RATE},
    {"tangential_stiffness", "k_t", SCENE_STRESS},
    {"spring_damping", "gamma_t", SCENE_MASS_RATE},
    {"rolling_friction", "mu_r", SCENE_LENGTH}, /* the cap |M_r| <= mu_r F_el (004 eq. 4.1) */
    {"rolling_stiffness", "k_r", SCENE_ROLLING_STIFFNESS},
};

#define MATERIAL_KEY_COUNT (sizeof MATERIAL_MAP / sizeof MATERIAL_MAP[0])

/* The keys of a `grains.rain` group and of `grains.box`, and their quantities (docs/scenes.md,
 * `grains`): fractions and the grain count are dimensionless, a species or motion has no unit. */
const SceneKey loader_rain_keys[] = {{"x0", SCENE_LENGTH},
                                     {"x1", SCENE_LENGTH},
                                     {"y0", SCENE_LENGTH},
                                     {"y1", SCENE_LENGTH},
                                     {"radius_mean", SCENE_LENGTH},
                                     {"polydispersity", SCENE_DIMENSIONLESS},
                                     {"pitch_radius", SCENE_LENGTH},
                                     {"column_gap", SCENE_LENGTH},
                                     {"row_gap", SCENE_LENGTH},
                                     {"column_jitter", SCENE_DIMENSIONLESS},
                                     {"row_jitter", SCENE_DIMENSIONLESS},
                                     {"max_count", SCENE_DIMENSIONLESS},
                                     {"species", SCENE_QUANTITY_COUNT},
                                     {NULL, SCENE_QUANTITY_COUNT}};
const SceneKey loader_box_keys[] = {{"x0", SCENE_LENGTH},
                                    {"x1", SCENE_LENGTH},
                                    {"y0", SCENE_LENGTH},
                                    {"y1", SCENE_LENGTH},
                                    {"radius", SCENE_LENGTH},
                                    {"species", SCENE_QUANTITY_COUNT},
                                    {"motion", SCENE_QUANTITY_COUNT},
                                    {NULL, SCENE_QUANTITY_COUNT}};

static const char *const MOTION_KINDS[] = {"sinusoidal", "velocity", "rotation", "compose", NULL};
static const char *const MOTION_KIND_KEYS[4][6] = {
    {"amplitude", "frequency", "phase", "direction", NULL},
    {"velocity", NULL},
    {"center", "angular_velocity", NULL},
    {"of", NULL}};
static const char *const MOTION_SCHEDULE_KEYS[] = {"kind", "start", "ramp", "stop", NULL};

SimMaterial scene_material_default(void)
{
    SimMaterial m = sim_material_default();
    m.damping_mode = SIM_DAMPING_GAMMA; /* elastic unless a species gives its damping */
    m.normal_damping = 0.0;
    return m;
}

const char *const *scene_keys(const char *group, int k)
{
    static const char *material[2][MATERIAL_KEY_COUNT + 1];
    if (strcmp(group, "species") == 0)
        return SPECIES_KEYS;
    if (strcmp(group, "material") == 0 && (k == 0 || k == 1)) {
        for (size_t j = 0; j < MATERIAL_KEY_COUNT; ++j)
            material[k][j] = k == 0 ? MATERIAL_MAP[j].field : MATERIAL_MAP[j].key;
        material[k][MATERIAL_KEY_COUNT] = NULL;
        return material[k];
    }
    if (strcmp(group, "motion.kinds") == 0)
        return MOTION_KINDS;
    if (strcmp(group, "motion.schedule") == 0)
        return MOTION_SCHEDULE_KEYS;
    if (strcmp(group, "motion") == 0 && k >= 0 && k < 4)
        return MOTION_KIND_KEYS[k];
    return NULL;
}

/* The key after `group` in a --set key, past a list index written ".0", "[0]" or ".[0]" that
 * `index` requires (1) or allows (2): "species.0.mu" -> "mu", "grains.rain.[1].x0" -> "x0". NULL
 * when `key` is not of that group. */
static const char *key_in_group(const char *key, const char *group, int index)
{
    size_t n = strlen(group);
    if (strncmp(key, group, n) != 0)
        return NULL;
    const char *rest = key + n;
    if (index) {
        const char *at = rest + (*rest == '.');
        int bracket = *at == '[';
        at += bracket;
        size_t digits = strspn(at, "0123456789");
        if (digits > 0 && (!bracket || at[digits] == ']'))
            rest = at + digits + (size_t)bracket;
        else if (index == 1 || bracket)
            return NULL;
    }
    return *rest == '.' ? rest + 1 : NULL;
}

/* The quantity of `key` in a SceneKey table; SCENE_QUANTITY_COUNT when it has none. */
static SceneQuantity table_quantity(const SceneKey *table, const char *key)
{
    for (int k = 0; table[k].key; ++k)
        if (strcmp(key, table[k].key) == 0)
            return table[k].quantity;
    return SCENE_QUANTITY_COUNT;
}

/* A species key's quantity: density and k_n follow the mass model and the normal law. */
static SceneQuantity species_quantity(const Scene *scene, const char *rest)
{
    const int sphere = scene && scene->def.mass_model == SIM_MASS_SPHERE;
    const int hertz = scene && scene->def.contact.normal == SIM_NORMAL_HERTZ;
    if (strcmp(rest, "density") == 0 && sphere)
        return SCENE_DENSITY;
    if (strcmp(rest, "k_n") == 0 && hertz)
        return SCENE_HERTZ_STIFFNESS;
    if (strcmp(rest, "gamma_n") == 0 && hertz) /* F_n = sqrt(xi) (k_n xi + gamma_n dxi/dt) */
        return SCENE_QUANTITY_COUNT;
    for (size_t j = 0; j < MATERIAL_KEY_COUNT; ++j)
        if (strcmp(rest, MATERIAL_MAP[j].key) == 0)
            return MATERIAL_MAP[j].quantity;
    return SCENE_QUANTITY_COUNT;
}

SceneQuantity scene_key_quantity(const Scene *scene, const char *key)
{
    static const struct {
        const char *group;
        int index; /* 2: a list's entries may be named by an index */
        const SceneKey *keys;
    } groups[] = {{"time", 0, loader_time_keys},
                  {"grains.rain", 2, loader_rain_keys},
                  {"grains.box", 0, loader_box_keys}};

    const char *rest = key_in_group(key, "species", 1);
    if (rest)
        return species_quantity(scene, rest);
    for (size_t g = 0; g < sizeof groups / sizeof groups[0]; ++g)
        if ((rest = key_in_group(key, groups[g].group, groups[g].index)) != NULL)
            return table_quantity(groups[g].keys, rest);
    return SCENE_QUANTITY_COUNT;
}

static void where_species(Loader *L, const config_setting_t *g, int k)
{
    char field[64];
    snprintf(field, sizeof field, "materials[%d]", k);
    loader_where_add(L, field, g);
    for (size_t j = 0; j < MATERIAL_KEY_COUNT; ++j)
        if (app_config_member(g, MATERIAL_MAP[j].key)) {
            snprintf(field, sizeof field, "materials[%d].%s", k, MATERIAL_MAP[j].field);
            loader_where_add(L, field, app_config_member(g, MATERIAL_MAP[j].key));
        }
}

/* Normal damping: one of three ways (000 eq. 3.25 for restitution), default elastic. */
static int parse_damping(Loader *L, const config_setting_t *g, const char *what, SimMaterial *m)
{
    int ways = (app_config_member(g, "gamma_n") != NULL) +
               (app_config_member(g, "restitution") != NULL) +
               (app_config_member(g, "critical_fraction") != NULL);
    if (ways > 1)
        return app_config_fail(
            &L->p, g, "%s: give only one of gamma_n, restitution, critical_fraction", what);
    m->damping_mode = SIM_DAMPING_GAMMA;
    m->normal_damping = 0.0;
    if (app_config_member(g, "gamma_n")) {
        if (app_config_number(&L->p, g, "gamma_n", &m->normal_damping) < 0 ||
            app_config_non_negative(&L->p, g, "gamma_n", m->normal_damping) < 0)
            return -1;
    } else if (app_config_member(g, "restitution")) {
        m->damping_mode = SIM_DAMPING_RESTITUTION;
        if (app_config_number(&L->p, g, "restitution", &m->restitution) < 0)
            return -1;
        if (!(m->restitution > 0.0 && m->restitution <= 1.0))
            return app_config_fail(&L->p, app_config_member(g, "restitution"),
                                   "`restitution` must be in (0, 1] (got %g)", m->restitution);
    } else if (app_config_member(g, "critical_fraction")) {
        m->damping_mode = SIM_DAMPING_CRITICAL;
        if (app_config_number(&L->p, g, "critical_fraction", &m->critical_fraction) < 0 ||
            app_config_non_negative(&L->p, g, "critical_fraction", m->critical_fraction) < 0)
            return -1;
    }
    return 0;
}

/* mu, and gamma_s or k_t as contact.tangential needs (effect friction). */
static int parse_friction(Loader *L, const config_setting_t *g, const char *what, SimMaterial *m)
{
    SimTangentialLaw law = L->scene->def.contact.tangential;
    if (app_config_need_number(&L->p, g, "mu", what, &m->friction) < 0 ||
        app_config_non_negative(&L->p, g, "mu", m->friction) < 0)
        return -1;
    if (law == SIM_TANGENTIAL_REGULARISED &&
        (app_config_need_number(&L->p, g, "gamma_s", what, &m->tangential_damping) < 0 ||
         app_config_positive(&L->p, g, "gamma_s", m->tangential_damping) < 0))
        return -1;
    if (law == SIM_TANGENTIAL_SPRING &&
        (app_config_need_number(&L->p, g, "k_t", what, &m->tangential_stiffness) < 0 ||
         app_config_positive(&L->p, g, "k_t", m->tangential_stiffness) < 0))
        return -1;
    if (law != SIM_TANGENTIAL_REGULARISED && app_config_member(g, "gamma_s"))
        return app_config_fail(&L->p, app_config_member(g, "gamma_s"),
                               "`gamma_s` is used only by contact.tangential = \"regularised\"");
    if (law == SIM_TANGENTIAL_SPRING &&
        (app_config_number(&L->p, g, "gamma_t", &m->spring_damping) < 0 ||
         app_config_non_negative(&L->p, g, "gamma_t", m->spring_damping) < 0))
        return -1;
    static const char *const spring_keys[] = {"k_t", "gamma_t"};
    for (int j = 0; j < 2; ++j)
        if (law != SIM_TANGENTIAL_SPRING && app_config_member(g, spring_keys[j]))
            return app_config_fail(&L->p, app_config_member(g, spring_keys[j]),
                                   "`%s` is used only by contact.tangential = \"spring\"",
                                   spring_keys[j]);
    return 0;
}

/* mu_r, and k_r for contact.rolling = "fixed" (effect rolling_resistance). */
static int parse_rolling(Loader *L, const config_setting_t *g, const char *what, SimMaterial *m)
{
    SimRollingLaw law = L->scene->def.contact.rolling;
    if (app_config_need_number(&L->p, g, "mu_r", what, &m->rolling_friction) < 0 ||
        app_config_non_negative(&L->p, g, "mu_r", m->rolling_friction) < 0)
        return -1;
    if (law == SIM_ROLLING_FIXED &&
        (app_config_need_number(&L->p, g, "k_r", what, &m->rolling_stiffness) < 0 ||
         app_config_positive(&L->p, g, "k_r", m->rolling_stiffness) < 0))
        return -1;
    if (law != SIM_ROLLING_FIXED && app_config_member(g, "k_r"))
        return app_config_fail(&L->p, app_config_member(g, "k_r"),
                               "`k_r` is used only by contact.rolling = \"fixed\"");
    return 0;
}

/* Species k: the group g -> materials[k] and species_names[k]. */
static int parse_one_species(Loader *L, const config_setting_t *g, int k)
{
    static const char *const friction_keys[] = {"mu", "gamma_s", "k_t", "gamma_t"};
    static const char *const rolling_keys[] = {"mu_r", "k_r"};
    Scene *scene = L->scene;
    SimMaterial *m = &scene->def.materials[k];
    char what[48];
    snprintf(what, sizeof what, "species %d", k);
    *m = scene_material_default();
    const char *name = NULL;
    if (app_config_keys(&L->p, g, what, SPECIES_KEYS, NULL) < 0 ||
        app_config_string(&L->p, g, "name", &name) < 0)
        return -1;
    snprintf(scene->species_names[k], SCENE_NAME_MAX, "%s", name ? name : "");
    for (int j = 0; j < k; ++j)
        if (name && strcmp(scene->species_names[j], name) == 0)
            return app_config_fail(&L->p, app_config_member(g, "name"),
                                   "species name `%s` is used twice", name);
    where_species(L, g, k);
    if (app_config_need_number(&L->p, g, "density", what, &m->density) < 0 ||
        app_config_positive(&L->p, g, "density", m->density) < 0 ||
        app_config_need_number(&L->p, g, "k_n", what, &m->normal_stiffness) < 0 ||
        app_config_positive(&L->p, g, "k_n", m->normal_stiffness) < 0 ||
        parse_damping(L, g, what, m) < 0)
        return -1;
    for (int j = 0; j < 4; ++j)
        if (loader_gate(L, g, friction_keys[j], SIM_EFFECT_FRICTION) < 0)
            return -1;
    for (int j = 0; j < 2; ++j)
        if (loader_gate(L, g, rolling_keys[j], SIM_EFFECT_ROLLING) < 0)
            return -1;
    if ((L->effects & SIM_EFFECT_FRICTION) && parse_friction(L, g, what, m) < 0)
        return -1;
    if ((L->effects & SIM_EFFECT_ROLLING) && parse_rolling(L, g, what, m) < 0)
        return -1;
    return 0;
}

int loader_parse_species(Loader *L, const config_setting_t *root)
{
    SimWorldDef *def = &L->scene->def;
    const config_setting_t *list;
    if (app_config_need(&L->p, root, "species", "the scene") < 0 ||
        app_config_list(&L->p, root, "species", &list) < 0)
        return -1;
    int count = config_setting_length(list);
    if (count < 1 || count > SIM_MAX_SPECIES)
        return app_config_fail(&L->p, list, "`species` must list 1 to %d species (got %d)",
                               SIM_MAX_SPECIES, count);
    def->species_count = count;
    loader_where_add(L, "species_count", list);
    for (int k = 0; k < count; ++k)
        if (parse_one_species(L, config_setting_get_elem(list, (unsigned)k), k) < 0)
            return -1;
    return 0;
}

/* `species = 1` or `species = "acrylic"`; default 0. */
int loader_get_species(Loader *L, const config_setting_t *g, int *out)
{
    const config_setting_t *s = app_config_member(g, "species");
    *out = 0;
    if (!s)
        return 0;
    if (config_setting_type(s) == CONFIG_TYPE_STRING) {
        const char *name = config_setting_get_string(s);
        for (int k = 0; k < L->scene->def.species_count; ++k)
            if (strcmp(L->scene->species_names[k], name) == 0) {
                *out = k;
                return 1;
            }
        return app_config_fail(&L->p, s, "no species named `%s`", name);
    }
    long long index;
    if (app_config_int(&L->p, g, "species", &index) < 0)
        return -1;
    if (index < 0 || index >= L->scene->def.species_count)
        return app_config_fail(&L->p, s,
                               "`species` = %lld is out of range (the scene has %d species)", index,
                               L->scene->def.species_count);
    *out = (int)index;
    return 1;
}

/* `motion = "shaker"`: needs vibration; default -1 (still). */
static int get_motion(Loader *L, const config_setting_t *g, int *out)
{
    const char *name = NULL;
    *out = -1;
    if (loader_gate(L, g, "motion", SIM_EFFECT_VIBRATION) < 0)
        return -1;
    int found = app_config_string(&L->p, g, "motion", &name);
    if (found <= 0)
        return found;
    for (int k = 0; k < L->scene->def.motion_count; ++k)
        if (strcmp(L->scene->motion_names[k], name) == 0) {
            *out = k;
            return 1;
        }
    return app_config_fail(&L->p, app_config_member(g, "motion"),
                           "no motion named `%s` in `motions`", name);
}

/* The index of motion `name` among the first `count`, or -1. */
static int motion_index(const Scene *scene, int count, const char *name)
{
    for (int k = 0; k < count; ++k)
        if (strcmp(scene->motion_names[k], name) == 0)
            return k;
    return -1;
}

/* A sinusoidal shaker: amplitude, frequency (required), phase, direction. */
static int parse_sinusoidal(Loader *L, const config_setting_t *g, const char *what, SimMotion *m)
{
    double direction[2] = {0.0, 1.0};
    if (app_config_need_number(&L->p, g, "amplitude", what, &m->amplitude) < 0 ||
        app_config_non_negative(&L->p, g, "amplitude", m->amplitude) < 0 ||
        app_config_need_number(&L->p, g, "frequency", what, &m->frequency) < 0 ||
        app_config_positive(&L->p, g, "frequency", m->frequency) < 0 ||
        app_config_number(&L->p, g, "phase", &m->phase) < 0 ||
        app_config_vector(&L->p, g, "direction", direction, 2) < 0)
        return -1;
    double norm = hypot(direction[0], direction[1]);
    if (!(norm > 0.0))
        return app_config_fail(&L->p, app_config_member(g, "direction"),
                               "`direction` must not be zero");
    m->direction_x = direction[0] / norm;
    m->direction_y = direction[1] / norm;
    return 0;
}

/* `of = ["spin", "shake"]`: motions defined above this one, applied in that order. */
static int parse_compose(Loader *L, const config_setting_t *g, const char *what, int k,
                         SimMotion *m)
{
    const config_setting_t *of = app_config_member(g, "of");
    if (app_config_need(&L->p, g, "of", what) < 0)
        return -1;
    int n = config_setting_length(of);
    if (!config_setting_is_aggregate(of) || n < 1 || n > SIM_MOTION_MAX_PARTS)
        return app_config_fail(&L->p, of, "`of` must list 1 to %d motion names",
                               SIM_MOTION_MAX_PARTS);
    for (int j = 0; j < n; ++j) {
        const char *name = config_setting_get_string_elem(of, (unsigned)j);
        int index = name ? motion_index(L->scene, k, name) : -1;
        if (index < 0)
            return app_config_fail(&L->p, of, "`of`: `%s` is not a motion defined above this one",
                                   name ? name : "(not a string)");
        m->parts[j] = index;
    }
    m->part_count = n;
    return 0;
}

/* The kind's own keys (SimMotion). */
static int parse_motion_kind(Loader *L, const config_setting_t *g, const char *what, int k,
                             SimMotion *m)
{
    int kind = SIM_MOTION_SINUSOIDAL;
    if (app_config_member(g, "kind") &&
        app_config_choice(&L->p, g, "kind", MOTION_KINDS, &kind) < 0)
        return -1;
    m->kind = (SimMotionKind)kind;
    if (app_config_keys(&L->p, g, what, MOTION_KIND_KEYS[kind], MOTION_SCHEDULE_KEYS) < 0)
        return -1;
    double v[2] = {0.0, 0.0};
    switch (m->kind) {
    case SIM_MOTION_SINUSOIDAL:
        return parse_sinusoidal(L, g, what, m);
    case SIM_MOTION_VELOCITY:
        if (app_config_need(&L->p, g, "velocity", what) < 0 ||
            app_config_vector(&L->p, g, "velocity", v, 2) < 0)
            return -1;
        m->velocity_x = v[0];
        m->velocity_y = v[1];
        return 0;
    case SIM_MOTION_ROTATION:
        if (app_config_need(&L->p, g, "center", what) < 0 ||
            app_config_vector(&L->p, g, "center", v, 2) < 0 ||
            app_config_need_number(&L->p, g, "angular_velocity", what, &m->angular_velocity) < 0)
            return -1;
        m->center_x = v[0];
        m->center_y = v[1];
        return 0;
    case SIM_MOTION_COMPOSE:
        return parse_compose(L, g, what, k, m);
    }
    return -1;
}

/* start, ramp, stop (s; sim.h SimMotion). */
static int parse_schedule(Loader *L, const config_setting_t *g, SimMotion *m)
{
    if (app_config_number(&L->p, g, "start", &m->start) < 0 ||
        app_config_non_negative(&L->p, g, "start", m->start) < 0 ||
        app_config_number(&L->p, g, "ramp", &m->ramp) < 0 ||
        app_config_non_negative(&L->p, g, "ramp", m->ramp) < 0 ||
        app_config_number(&L->p, g, "stop", &m->stop) < 0)
        return -1;
    if (app_config_member(g, "stop") && !(m->stop > m->start))
        return app_config_fail(&L->p, app_config_member(g, "stop"),
                               "`stop` = %g must be after `start` = %g", m->stop, m->start);
    if (m->kind == SIM_MOTION_COMPOSE && m->ramp > 0.0)
        return app_config_fail(&L->p, app_config_member(g, "ramp"),
                               "a composition has no `ramp` of its own: ramp its parts");
    return 0;
}

int loader_parse_motions(Loader *L, const config_setting_t *root)
{
    const config_setting_t *group;
    if (loader_gate(L, root, "motions", SIM_EFFECT_VIBRATION) < 0 ||
        app_config_group(&L->p, root, "motions", &group) <= 0)
        return L->p.failed ? -1 : 0;
    int count = config_setting_length(group);
    if (count > SIM_MAX_MOTIONS)
        return app_config_fail(&L->p, group, "at most %d motions", SIM_MAX_MOTIONS);
    loader_where_add(L, "motions", group);
    for (int k = 0; k < count; ++k) {
        const config_setting_t *g = config_setting_get_elem(group, (unsigned)k);
        const char *name = config_setting_name(g);
        char what[96], field[64];
        snprintf(what, sizeof what, "motion `%s`", name);
        if (config_setting_type(g) != CONFIG_TYPE_GROUP)
            return app_config_fail(&L->p, g, "%s must be a group { kind; ... }", what);
        SimMotion *m = &L->scene->def.motions[k];
        memset(m, 0, sizeof *m);
        if (parse_motion_kind(L, g, what, k, m) < 0 || parse_schedule(L, g, m) < 0)
            return -1;
        snprintf(L->scene->motion_names[k], SCENE_NAME_MAX, "%s", name);
        app_config_where(&L->p, g, L->scene->where->motion[k], WHERE_MAX);
        snprintf(field, sizeof field, "motions[%d]", k);
        loader_where_add(L, field, g);
        L->scene->def.motion_count = k + 1;
    }
    return 0;
}

/* ---------------------------------------------------------------- grains and walls */

/* One rain group g (`what` names it); group `index` of a list seeds its own stream. */
static int parse_rain_group(Loader *L, const config_setting_t *g, const char *what, int index)
{
    SimRainDef rain;
    memset(&rain, 0, sizeof rain);
    long long max_count = 0;
    rain.column_jitter = 0.05; /* 000 §4.2 */
    rain.row_jitter = 0.08;
    if (loader_keys(L, g, what, loader_rain_keys) < 0 ||
        app_config_need_number(&L->p, g, "x0", what, &rain.x0) < 0 ||
        app_config_need_number(&L->p, g, "x1", what, &rain.x1) < 0 ||
        app_config_need_number(&L->p, g, "y0", what, &rain.y0) < 0 ||
        app_config_need_number(&L->p, g, "y1", what, &rain.y1) < 0 ||
        app_config_need_number(&L->p, g, "radius_mean", what, &rain.radius_mean) < 0 ||
        app_config_positive(&L->p, g, "radius_mean", rain.radius_mean) < 0 ||
        app_config_number(&L->p, g, "polydispersity", &rain.polydispersity) < 0 ||
        app_config_int(&L->p, g, "max_count", &max_count) < 0 ||
        loader_get_species(L, g, &rain.species) < 0)
        return -1;
    if (!(rain.polydispersity >= 0.0 && rain.polydispersity < 1.0))
        return app_config_fail(&L->p, app_config_member(g, "polydispersity"),
                               "`polydispersity` must be in [0, 1)");
    /* 000 §4.2: pitch from r_max, gaps 0.005 r_max and 0.75 r_max */
    rain.pitch_radius = rain.radius_mean * (1.0 + rain.polydispersity);
    if (app_config_number(&L->p, g, "pitch_radius", &rain.pitch_radius) < 0 ||
        app_config_positive(&L->p, g, "pitch_radius", rain.pitch_radius) < 0)
        return -1;
    rain.column_gap = 0.005 * rain.pitch_radius;
    rain.row_gap = 0.75 * rain.pitch_radius;
    if (app_config_number(&L->p, g, "column_gap", &rain.column_gap) < 0 ||
        app_config_non_negative(&L->p, g, "column_gap", rain.column_gap) < 0 ||
        app_config_number(&L->p, g, "row_gap", &rain.row_gap) < 0 ||
        app_config_non_negative(&L->p, g, "row_gap", rain.row_gap) < 0 ||
        app_config_number(&L->p, g, "column_jitter", &rain.column_jitter) < 0 ||
        app_config_non_negative(&L->p, g, "column_jitter", rain.column_jitter) < 0 ||
        app_config_number(&L->p, g, "row_jitter", &rain.row_jitter) < 0 ||
        app_config_non_negative(&L->p, g, "row_jitter", rain.row_jitter) < 0)
        return -1;
    if (rain.pitch_radius < rain.radius_mean * (1.0 + rain.polydispersity) * (1.0 - 1e-12))
        return app_config_fail(&L->p, app_config_member(g, "pitch_radius"),
                               "`pitch_radius` must be at least the largest radius r_mean (1 + "
                               "polydispersity) = %g m",
                               rain.radius_mean * (1.0 + rain.polydispersity));
    if (max_count < 0 || max_count > 10000000)
        return app_config_fail(&L->p, app_config_member(g, "max_count"),
                               "`max_count` must be in [0, 1e7]");
    rain.max_count = (int)max_count;
    if (!(rain.x1 - rain.x0 >= 2.0 * rain.pitch_radius) ||
        !(rain.y1 - rain.y0 >= 2.0 * rain.pitch_radius))
        return app_config_fail(&L->p, g,
                               "%s: the region [x0, x1] x [y0, y1] must hold at least one "
                               "grain (2 pitch_radius = %g m)",
                               what, 2.0 * rain.pitch_radius);
    /* Refuse regions that would need absurd memory before building. */
    double cells =
        (rain.x1 - rain.x0) * (rain.y1 - rain.y0) / (4.0 * rain.pitch_radius * rain.pitch_radius);
    if (cells > SCENE_MAX_GRAINS && rain.max_count == 0)
        return app_config_fail(&L->p, g, "%s: the region holds about %.3g grains; set max_count",
                               what, cells);
    /* the builder keeps one offset per lattice column, whatever max_count says */
    if ((rain.x1 - rain.x0) / (2.0 * rain.pitch_radius) > SCENE_MAX_GRAINS)
        return app_config_fail(&L->p, g, "%s: the region is %.3g grains wide; at most %.0e", what,
                               (rain.x1 - rain.x0) / (2.0 * rain.pitch_radius), SCENE_MAX_GRAINS);
    SimRng rng;
    sim_rng_seed(&rng, L->scene->seed + (uint64_t)index); /* group 0: the single rain's seed */
    int first = L->scene->grains.count;
    int added = sim_build_rain(&L->scene->grains, &rain, &rng);
    if (added <= 0)
        return app_config_fail(&L->p, g, "%s produced no grains", what);
    loader_where_grains(L, first, g, "grains.rain");
    return 0;
}

/* A fixed row or column of `span` / (2 radius) + 1 grains within what a scene may hold (a row
 * with x1 = 1e9 would need gigabytes, or overflow the count). 0, or -1. */
static int check_line_count(Loader *L, const config_setting_t *g, const char *what, double span,
                            double radius)
{
    double n = span / (2.0 * radius) + 1.0;
    if (n <= SCENE_MAX_GRAINS)
        return 0;
    return app_config_fail(&L->p, g, "%s: %.3g grains in one line; a scene holds at most %.0e",
                           what, n, SCENE_MAX_GRAINS);
}

static int parse_box(Loader *L, const config_setting_t *grains)
{
    const config_setting_t *g;
    if (app_config_group(&L->p, grains, "box", &g) <= 0)
        return L->p.failed ? -1 : 0;
    const char *what = "grains.box";
    double x0 = 0.0, x1 = 0.0, y0 = 0.0, y1 = 0.0, r = 0.0;
    int species = 0, motion = -1;
    if (loader_keys(L, g, what, loader_box_keys) < 0 ||
        app_config_need_number(&L->p, g, "x0", what, &x0) < 0 ||
        app_config_need_number(&L->p, g, "x1", what, &x1) < 0 ||
        app_config_need_number(&L->p, g, "y0", what, &y0) < 0 ||
        app_config_need_number(&L->p, g, "y1", what, &y1) < 0 ||
        app_config_need_number(&L->p, g, "radius", what, &r) < 0 ||
        app_config_positive(&L->p, g, "radius", r) < 0 || loader_get_species(L, g, &species) < 0 ||
        get_motion(L, g, &motion) < 0)
        return -1;
    if (!(x1 - x0 >= 4.0 * r) || !(y1 - y0 >= 2.0 * r))
        return app_config_fail(&L->p, g,
                               "grains.box: needs x1 - x0 >= 4 radius and y1 - y0 >= 2 radius");
    if (check_line_count(L, g, what, x1 - x0, r) < 0 ||
        check_line_count(L, g, what, y1 - y0, r) < 0)
        return -1;
    L->box_height = y1 - y0;
    int first = L->scene->grains.count;
    /* floor row of centres at y0 from x0 to x1, side columns at x0 and x1 above it (000 §1.6) */
    sim_build_fixed_row(&L->scene->grains, x0, x1, y0, r, species, motion);
    sim_build_fixed_column(&L->scene->grains, x0, y0 + 2.0 * r, y1, r, species, motion);
    sim_build_fixed_column(&L->scene->grains, x1, y0 + 2.0 * r, y1, r, species, motion);
    loader_where_grains(L, first, g, "grains.box");
    return 0;
}

static int parse_rows(Loader *L, const config_setting_t *grains, int columns)
{
    static const char *const row_keys[] = {"x0",      "x1",     "y",     "radius",
                                           "species", "motion", "group", NULL};
    static const char *const column_keys[] = {"x",       "y0",     "y1",    "radius",
                                              "species", "motion", "group", NULL};
    const char *key = columns ? "columns" : "rows";
    const config_setting_t *list;
    if (app_config_list(&L->p, grains, key, &list) <= 0)
        return L->p.failed ? -1 : 0;
    for (int k = 0; k < config_setting_length(list); ++k) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
        char what[48];
        snprintf(what, sizeof what, "grains.%s.%d", key, k);
        double a = 0.0, b = 0.0, c = 0.0, r = 0.0;
        int species = 0, motion = -1;
        if (app_config_keys(&L->p, g, what, columns ? column_keys : row_keys, NULL) < 0 ||
            app_config_need_number(&L->p, g, columns ? "x" : "x0", what, &a) < 0 ||
            app_config_need_number(&L->p, g, columns ? "y0" : "x1", what, &b) < 0 ||
            app_config_need_number(&L->p, g, columns ? "y1" : "y", what, &c) < 0 ||
            app_config_need_number(&L->p, g, "radius", what, &r) < 0 ||
            app_config_positive(&L->p, g, "radius", r) < 0 ||
            loader_get_species(L, g, &species) < 0 || get_motion(L, g, &motion) < 0 ||
            loader_get_group(L, g, what, &motion) < 0)
            return -1;
        if (check_line_count(L, g, what, fabs(columns ? c - b : b - a), r) < 0)
            return -1;
        int first = L->scene->grains.count;
        if (columns) {
            if (!(c >= b))
                return app_config_fail(&L->p, g, "%s: needs y1 >= y0", what);
            sim_build_fixed_column(&L->scene->grains, a, b, c, r, species, motion);
        } else {
            if (!(b >= a))
                return app_config_fail(&L->p, g, "%s: needs x1 >= x0", what);
            sim_build_fixed_row(&L->scene->grains, a, b, c, r, species, motion);
        }
        loader_where_grains(L, first, g, what);
    }
    return 0;
}

/* `rain = { ... }`, or a list of such groups (several species, regions or sizes), filled in
 * order. */
static int parse_rain(Loader *L, const config_setting_t *grains)
{
    const config_setting_t *r = app_config_member(grains, "rain");
    if (!r)
        return 0;
    if (config_setting_type(r) == CONFIG_TYPE_GROUP)
        return parse_rain_group(L, r, "grains.rain", 0);
    if (config_setting_type(r) != CONFIG_TYPE_LIST)
        return app_config_fail(&L->p, r, "`rain` must be a group { ... } or a list of groups");
    for (int k = 0; k < config_setting_length(r); ++k) {
        char what[48];
        snprintf(what, sizeof what, "grains.rain.%d", k);
        const config_setting_t *g = config_setting_get_elem(r, (unsigned)k);
        if (config_setting_type(g) != CONFIG_TYPE_GROUP)
            return app_config_fail(&L->p, g, "%s must be a group { x0; x1; ... }", what);
        if (parse_rain_group(L, g, what, k) < 0)
            return -1;
    }
    return 0;
}

/* `file = "pile.csv"` (relative to the scene's folder): app/scene/grains_file.c. */
static int parse_file(Loader *L, const config_setting_t *grains)
{
    const char *name = NULL;
    if (app_config_string(&L->p, grains, "file", &name) <= 0)
        return L->p.failed ? -1 : 0;
    char path[SCENE_PATH_MAX + 8];
    if (name[0] == '/')
        snprintf(path, sizeof path, "%s", name);
    else
        snprintf(path, sizeof path, "%.*s/%s", (int)(SCENE_PATH_MAX / 2), L->dir, name);
    const int first = L->scene->grains.count;
    int has_ids = 0;
    char err[SCENE_PATH_MAX + 256];
    if (app_grains_read(path, L->scene->def.species_count, &L->scene->grains, &has_ids, err,
                        sizeof err) != 0) {
        /* "path:line: message": reported at the grains file's line, naming the scene's key */
        size_t cut = strlen(path) + 1;
        cut = cut < strlen(err) ? cut + strspn(err + cut, "0123456789") : strlen(err);
        char where[sizeof err], key[WHERE_MAX];
        snprintf(where, sizeof where, "%.*s", (int)cut, err);
        app_config_where(&L->p, app_config_member(grains, "file"), key, sizeof key);
        return app_config_fail_at(&L->p, where, "%s (grains.file, %s)",
                                  err[cut] ? err + cut + 2 : err, key);
    }
    if (has_ids && first > 0)
        return app_config_fail(&L->p, app_config_member(grains, "file"),
                               "a grains file with an `id` column must be the scene's only "
                               "grains (its ids would clash)");
    loader_where_grains(L, first, app_config_member(grains, "file"), "grains.file");
    return 0;
}

static int parse_list(Loader *L, const config_setting_t *grains)
{
    static const char *const keys[] = {"x",  "y",     "r",     "species", "fixed", "vx",
                                       "vy", "omega", "angle", "motion",  NULL};
    const config_setting_t *list;
    if (app_config_list(&L->p, grains, "list", &list) <= 0)
        return L->p.failed ? -1 : 0;
    for (int k = 0; k < config_setting_length(list); ++k) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
        char what[48];
        snprintf(what, sizeof what, "grains.list.%d", k);
        double x = 0.0, y = 0.0, r = 0.0, vx = 0.0, vy = 0.0, omega = 0.0, angle = 0.0;
        int species = 0, fixed = 0, motion = -1;
        if (app_config_keys(&L->p, g, what, keys, NULL) < 0 ||
            app_config_need_number(&L->p, g, "x", what, &x) < 0 ||
            app_config_need_number(&L->p, g, "y", what, &y) < 0 ||
            app_config_need_number(&L->p, g, "r", what, &r) < 0 ||
            loader_get_species(L, g, &species) < 0 ||
            app_config_bool(&L->p, g, "fixed", &fixed) < 0 ||
            app_config_number(&L->p, g, "vx", &vx) < 0 ||
            app_config_number(&L->p, g, "vy", &vy) < 0 ||
            app_config_number(&L->p, g, "omega", &omega) < 0 ||
            app_config_number(&L->p, g, "angle", &angle) < 0 || get_motion(L, g, &motion) < 0)
            return -1;
        if (!(r > 0.0))
            return app_config_fail(&L->p, app_config_member(g, "r"), "`r` must be > 0 (got %g)", r);
        if (motion >= 0 && !fixed)
            return app_config_fail(&L->p, app_config_member(g, "motion"),
                                   "`motion` applies to fixed grains only");
        int first = L->scene->grains.count;
        int i = sim_grain_buffer_add(&L->scene->grains, x, y, r, species,
                                     fixed ? SIM_GRAIN_FIXED : 0u, motion);
        L->scene->grains.vx[i] = vx;
        L->scene->grains.vy[i] = vy;
        L->scene->grains.omega[i] = omega;
        L->scene->grains.angle[i] = angle;
        loader_where_grains(L, first, g, what);
    }
    return 0;
}

int loader_parse_grains(Loader *L, const config_setting_t *root)
{
    static const char *const keys[] = {"list", "rain", "box", "rows", "columns", "file", NULL};
    const config_setting_t *grains;
    if (app_config_need(&L->p, root, "grains", "the scene") < 0 ||
        app_config_group(&L->p, root, "grains", &grains) < 0 ||
        app_config_keys(&L->p, grains, "grains", keys, NULL) < 0)
        return -1;
    /* Stable ids follow this order: list, rain, box, rows, columns. */
    if (parse_list(L, grains) < 0 || parse_rain(L, grains) < 0 || parse_box(L, grains) < 0 ||
        parse_rows(L, grains, 0) < 0 || parse_rows(L, grains, 1) < 0 || parse_file(L, grains) < 0)
        return -1;
    Scene *scene = L->scene;
    scene->fixed_count = 0;
    for (int i = 0; i < scene->grains.count; ++i)
        scene->fixed_count += (scene->grains.flags[i] & SIM_GRAIN_FIXED) != 0;
    /* a family may make the grains during the run (app/base/experiment.h, grains_from_run), or the
     * scene's sources feed it (app/scene/sources.c) */
    int from_run = app_config_member(root, "sources") != NULL;
    for (int f = 0; app_experiments[f] && !from_run; ++f)
        from_run = app_experiments[f]->grains_from_run &&
                   app_experiment_group(app_experiments[f], root) != NULL;
    if (scene->grains.count == scene->fixed_count && !from_run)
        return app_config_fail(&L->p, grains, "the scene has no mobile grains");
    return 0;
}

/* A segment: from = [x, y], to = [x, y]. */
static int parse_segment(Loader *L, const config_setting_t *g, const char *what, SimWall *w)
{
    double from[2] = {0.0, 0.0}, to[2] = {0.0, 0.0};
    if (app_config_need(&L->p, g, "from", what) < 0 ||
        app_config_vector(&L->p, g, "from", from, 2) < 0 ||
        app_config_need(&L->p, g, "to", what) < 0 || app_config_vector(&L->p, g, "to", to, 2) < 0)
        return -1;
    if (!(hypot(to[0] - from[0], to[1] - from[1]) > 0.0))
        return app_config_fail(&L->p, g, "%s: `from` and `to` must differ", what);
    w->x0 = from[0];
    w->y0 = from[1];
    w->x1 = to[0];
    w->y1 = to[1];
    return 0;
}

/* An arc: center = [x, y], radius (m), angles = [from, to] in degrees counter-clockwise
 * (default the full circle), side = "inside" | "outside" | "both". */
static int parse_arc(Loader *L, const config_setting_t *g, const char *what, SimWall *w)
{
    static const char *const sides[] = {"both", "inside", "outside", NULL};
    double center[2] = {0.0, 0.0}, angles[2] = {0.0, 360.0};
    int side = SIM_WALL_BOTH;
    if (app_config_need(&L->p, g, "center", what) < 0 ||
        app_config_vector(&L->p, g, "center", center, 2) < 0 ||
        app_config_need_number(&L->p, g, "radius", what, &w->radius) < 0 ||
        app_config_positive(&L->p, g, "radius", w->radius) < 0 ||
        app_config_vector(&L->p, g, "angles", angles, 2) < 0 ||
        (app_config_member(g, "side") && app_config_choice(&L->p, g, "side", sides, &side) < 0))
        return -1;
    if (!(angles[1] > angles[0]))
        return app_config_fail(
            &L->p, app_config_member(g, "angles"),
            "`angles` = [from, to] needs to > from (degrees, counter-clockwise)");
    w->shape = SIM_WALL_ARC;
    w->side = (SimWallSide)side;
    w->center_x = center[0];
    w->center_y = center[1];
    w->angle0 = angles[0] * SIM_PI / 180.0;
    w->angle1 =
        angles[1] - angles[0] >= 360.0 ? w->angle0 + 2.0 * SIM_PI : angles[1] * SIM_PI / 180.0;
    /* the end points, for readers that know segments only */
    w->x0 = center[0] + w->radius * cos(w->angle0);
    w->y0 = center[1] + w->radius * sin(w->angle0);
    w->x1 = center[0] + w->radius * cos(w->angle1);
    w->y1 = center[1] + w->radius * sin(w->angle1);
    return 0;
}

int loader_parse_walls(Loader *L, const config_setting_t *root)
{
    static const char *const keys[] = {
        "from", "to",   "center", "radius",  "angles", "side",     "species", "motion",
        "mass", "axis", "force",  "gravity", "servo",  "rotation", "inertia", NULL};
    const config_setting_t *list;
    if (app_config_list(&L->p, root, "walls", &list) <= 0)
        return L->p.failed ? -1 : 0;
    int count = config_setting_length(list);
    L->scene->walls = calloc((size_t)(count > 0 ? count : 1), sizeof *L->scene->walls);
    if (!L->scene->walls)
        return app_config_fail(&L->p, list, "out of memory");
    for (int k = 0; k < count; ++k) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
        char what[32], field[32];
        snprintf(what, sizeof what, "walls.%d", k);
        SimWall *w = &L->scene->walls[k];
        const int arc = app_config_member(g, "center") || app_config_member(g, "radius");
        if (app_config_keys(&L->p, g, what, keys, NULL) < 0)
            return -1;
        if (arc && (app_config_member(g, "from") || app_config_member(g, "to")))
            return app_config_fail(&L->p, g,
                                   "%s: a wall is a segment (from, to) or an arc (center, radius), "
                                   "not both",
                                   what);
        if (!arc && (app_config_member(g, "angles") || app_config_member(g, "side")))
            return app_config_fail(&L->p, g,
                                   "%s: `angles` and `side` are for arcs (center, radius)", what);
        if ((arc ? parse_arc(L, g, what, w) : parse_segment(L, g, what, w)) < 0 ||
            loader_get_species(L, g, &w->species) < 0 || get_motion(L, g, &w->motion) < 0 ||
            loader_parse_wall_body(L, g, what, k) < 0)
            return -1;
        snprintf(field, sizeof field, "walls[%d]", k);
        loader_where_add(L, field, g);
    }
    L->scene->def.wall_count = count;
    L->scene->def.walls = L->scene->walls;
    return 0;
}

int loader_parse_sinks(Loader *L, const config_setting_t *root)
{
    static const char *const keys[] = {"below", "above", "left", "right", "rect", NULL};
    const config_setting_t *list;
    if (loader_gate(L, root, "sinks", SIM_EFFECT_REMOVAL) < 0 ||
        app_config_list(&L->p, root, "sinks", &list) <= 0)
        return L->p.failed ? -1 : 0;
    int count = config_setting_length(list);
    if (count > SIM_MAX_SINKS)
        return app_config_fail(&L->p, list, "at most %d sinks", SIM_MAX_SINKS);
    loader_where_add(L, "sinks", list);
    for (int k = 0; k < count; ++k) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
        char what[32], field[32];
        snprintf(what, sizeof what, "sinks.%d", k);
        if (app_config_keys(&L->p, g, what, keys, NULL) < 0)
            return -1;
        if (config_setting_length(g) != 1)
            return app_config_fail(&L->p, g,
                                   "%s: give exactly one of below, above, left, right, rect", what);
        SimSink *sink = &L->scene->def.sinks[k];
        const char *key = config_setting_name(config_setting_get_elem(g, 0));
        if (strcmp(key, "rect") == 0) {
            double r[4] = {0.0, 0.0, 0.0, 0.0};
            sink->shape = SIM_SINK_RECT;
            if (app_config_vector(&L->p, g, "rect", r, 4) < 0)
                return -1;
            if (!(r[2] > r[0] && r[3] > r[1]))
                return app_config_fail(&L->p, app_config_member(g, "rect"),
                                       "`rect` = [x0, y0, x1, y1] needs x1 > x0 and "
                                       "y1 > y0");
            sink->x0 = r[0];
            sink->y0 = r[1];
            sink->x1 = r[2];
            sink->y1 = r[3];
        } else {
            sink->shape = strcmp(key, "below") == 0   ? SIM_SINK_BELOW
                          : strcmp(key, "above") == 0 ? SIM_SINK_ABOVE
                          : strcmp(key, "left") == 0  ? SIM_SINK_LEFT
                                                      : SIM_SINK_RIGHT;
            if (app_config_number(&L->p, g, key, &sink->level) < 0)
                return -1;
        }
        snprintf(field, sizeof field, "sinks[%d]", k);
        loader_where_add(L, field, g);
        L->scene->def.sink_count = k + 1;
    }
    return 0;
}
