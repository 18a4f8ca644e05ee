/* SPDX-License-Identifier: MIT */
/* scene_load.c: libconfig scene file -> SimWorldDef + stages + output settings (docs/scenes.md).
 *
 * Every key is read through a typed getter (config.h) that reports `file:line: message`; every
 * group lists its allowed keys so that a typo is an error, and keys that belong to an effect (mu
 * needs friction, motion needs vibration, ...) are refused unless the effect is declared. After
 * parsing, the loader checks the start configuration (overlaps) and the time step, then hands the
 * definition to sim_world_def_validate and maps the reported field path back to the key that set
 * it. This file holds scene_load and the top-level physics; scene_internal.h lists the others
 * (scene_keys.c: the key rules every part of the loader shares). */
#include "base/experiments.h"
#include "base/sha256.h"
#include "scene/advice.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"
#include "scene/sources.h"
#include "sim/sim.h"

#include <ctype.h>
#include <errno.h>
#include <libconfig.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* ---------------------------------------------------------------- top-level physics */

static const char *const ROOT_KEYS[] = {
    "name",    "seed",     "units",   "effects", "mass_model", "gravity", "integrator", "time",
    "skin",    "guard",    "contact", "species", "grains",     "walls",   "motions",    "sinks",
    "sources", "periodic", "drag",    "stages",  "output",     "render",  "bodies",     NULL};

static int parse_effects(Loader *L, const config_setting_t *root)
{
    config_setting_t *s = app_config_member(root, "effects");
    L->effects = 0;
    L->effects_setting = s;
    if (!s)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_ARRAY && config_setting_type(s) != CONFIG_TYPE_LIST)
        return app_config_fail(&L->p, s,
                               "`effects` must be an array of names, e.g. [\"friction\"]");
    for (int k = 0; k < config_setting_length(s); ++k) {
        const config_setting_t *e = config_setting_get_elem(s, (unsigned)k);
        if (config_setting_type(e) != CONFIG_TYPE_STRING)
            return app_config_fail(&L->p, e, "`effects` must list strings, not %s",
                                   app_config_type_name(e));
        unsigned bit = sim_effect_from_name(config_setting_get_string(e));
        if (!bit)
            return app_config_fail(&L->p, e,
                                   "unknown effect `%s` (expected: friction, rolling_resistance, "
                                   "periodic_x, vibration, fluid_drag, removal)",
                                   config_setting_get_string(e));
        L->effects |= bit;
    }
    loader_where_add(L, "effects", s);
    return 0;
}

static void drag_apply(void *context, const SimBodyForceView *view)
{
    const SceneDrag *drag = context;
    for (int i = 0; i < view->count; ++i) {
        /* Stokes drag on a sphere of diameter d: 3 pi eta d (v - u) */
        double c = drag->model == SCENE_DRAG_LINEAR
                       ? drag->coefficient
                       : 3.0 * SIM_PI * drag->viscosity * 2.0 * view->radius[i];
        view->fx[i] -= c * (view->vx[i] - drag->fluid_vx);
        view->fy[i] -= c * (view->vy[i] - drag->fluid_vy);
    }
}

/* The scene's keys, effects, name, seed and units. */
static int parse_identity(Loader *L, const config_setting_t *root)
{
    static const char *const units[] = {"SI", "si", "reduced", "normalised", "normalized", NULL};
    Scene *scene = L->scene;
    int choice = 0;
    const char *name = NULL;
    long long seed = 0;
    if (app_config_keys(&L->p, root, "the scene", ROOT_KEYS, loader_family_keys(0)) < 0 ||
        parse_effects(L, root) < 0)
        return -1;
    scene->def.effects = L->effects;
    if (app_config_string(&L->p, root, "name", &name) < 0)
        return -1;
    if (name) {
        if (loader_check_file_name(L, root, "name", name) < 0)
            return -1;
        snprintf(scene->name, sizeof scene->name, "%s", name);
    }
    if (app_config_need(&L->p, root, "seed", "the scene") < 0 ||
        app_config_int(&L->p, root, "seed", &seed) < 0)
        return -1;
    if (seed < 0 || seed > SCENE_SEED_MAX)
        return app_config_fail(&L->p, app_config_member(root, "seed"),
                               "`seed` must be in [0, 2^53 - 1] (%lld), got %lld", SCENE_SEED_MAX,
                               seed);
    scene->seed = (uint64_t)seed;
    if (app_config_choice(&L->p, root, "units", units, &choice) < 0)
        return -1;
    scene->units_reduced = choice == 2;
    scene->units_normalised = choice >= 3;
    return 0;
}

/* mass_model, gravity, integrator. */
static int parse_dynamics(Loader *L, const config_setting_t *root)
{
    static const char *const mass_models[] = {"disk", "sphere", NULL};
    SimWorldDef *def = &L->scene->def;
    int choice = 0;
    /* Mass convention is the thesis's biggest ambiguity (000 §1.5): no silent default. */
    if (app_config_need(&L->p, root, "mass_model", "the scene") < 0 ||
        app_config_choice(&L->p, root, "mass_model", mass_models, &choice) < 0)
        return -1;
    def->mass_model = choice == 1 ? SIM_MASS_SPHERE : SIM_MASS_DISK;
    loader_where_add(L, "mass_model", app_config_member(root, "mass_model"));
    double gravity[2] = {def->gravity_x, def->gravity_y};
    if (app_config_vector(&L->p, root, "gravity", gravity, 2) < 0)
        return -1;
    def->gravity_x = gravity[0];
    def->gravity_y = gravity[1];
    loader_where_add(L, "gravity", app_config_member(root, "gravity"));
    loader_where_add(L, "gravity_x", app_config_member(root, "gravity"));
    loader_where_add(L, "gravity_y", app_config_member(root, "gravity"));
    const char *integrator = NULL;
    int found = app_config_string(&L->p, root, "integrator", &integrator);
    if (found < 0)
        return -1;
    if (found) {
        int i = sim_integrator_from_name(integrator);
        if (i < 0)
            return app_config_fail(&L->p, app_config_member(root, "integrator"),
                                   "unknown integrator `%s` (expected one of: velocity_verlet, "
                                   "symplectic_euler, stormer_verlet, gear, rk4)",
                                   integrator);
        def->integrator = (SimIntegrator)i;
        loader_where_add(L, "integrator", app_config_member(root, "integrator"));
    }
    return 0;
}

/* The keys of `time` and their quantities (docs/scenes.md, `time`). */
const SceneKey loader_time_keys[] = {{"dt", SCENE_TIME},
                                     {"end", SCENE_TIME},
                                     {"steps_per_contact", SCENE_DIMENSIONLESS},
                                     {"max_dt_fraction", SCENE_DIMENSIONLESS},
                                     {"target_error", SCENE_DIMENSIONLESS},
                                     {NULL, SCENE_QUANTITY_COUNT}};

/* time = { dt; end; steps_per_contact; max_dt_fraction; target_error; }, and skin.
 * target_error chooses dt (apply_target_error), so it excludes dt and steps_per_contact. */
static int parse_time(Loader *L, const config_setting_t *root)
{
    SimWorldDef *def = &L->scene->def;
    const config_setting_t *time;
    if (app_config_need(&L->p, root, "time", "the scene") < 0 ||
        app_config_group(&L->p, root, "time", &time) < 0 ||
        loader_keys(L, time, "time", loader_time_keys) < 0)
        return -1;
    const config_setting_t *target = app_config_member(time, "target_error");
    if (target) {
        const char *other = app_config_member(time, "dt")                  ? "dt"
                            : app_config_member(time, "steps_per_contact") ? "steps_per_contact"
                                                                           : NULL;
        if (other)
            return app_config_fail(
                &L->p, target, "time: `target_error` chooses the time step; remove `%s`", other);
        if (app_config_number(&L->p, time, "target_error", &L->scene->target_error) < 0)
            return -1;
        if (!(L->scene->target_error > 0.0 && L->scene->target_error < 0.5))
            return app_config_fail(&L->p, target, "time: `target_error` must be in (0, 0.5)");
        def->time_step = 0.0;
    } else if (app_config_need_number(&L->p, time, "dt", "time", &def->time_step) < 0 ||
               app_config_non_negative(&L->p, time, "dt", def->time_step) < 0) {
        return -1;
    }
    if (app_config_need(&L->p, time, "end", "time") < 0 ||
        app_config_number(&L->p, time, "steps_per_contact", &def->steps_per_contact) < 0 ||
        app_config_positive(&L->p, time, "steps_per_contact", def->steps_per_contact) < 0 ||
        app_config_number(&L->p, time, "max_dt_fraction", &def->max_dt_fraction) < 0 ||
        app_config_non_negative(&L->p, time, "max_dt_fraction", def->max_dt_fraction) < 0)
        return -1;
    const config_setting_t *steps = app_config_member(time, "steps_per_contact");
    const config_setting_t *fraction = app_config_member(time, "max_dt_fraction");
    loader_where_add(L, "steps_per_contact", steps ? steps : target ? target : time);
    loader_where_add(L, "max_dt_fraction", fraction ? fraction : time);
    if (app_config_number(&L->p, root, "skin", &def->skin) < 0 ||
        app_config_non_negative(&L->p, root, "skin", def->skin) < 0)
        return -1;
    loader_where_add(L, "skin", app_config_member(root, "skin"));
    return 0;
}

/* guard = { max_overlap; max_speed; every; } */
static int parse_guard(Loader *L, const config_setting_t *root)
{
    static const char *const guard_keys[] = {"max_overlap", "max_speed", "every", NULL};
    SimWorldDef *def = &L->scene->def;
    const config_setting_t *guard;
    long long every = def->guard_every;
    if (app_config_group(&L->p, root, "guard", &guard) < 0 ||
        app_config_keys(&L->p, guard, "guard", guard_keys, NULL) < 0 ||
        app_config_number(&L->p, guard, "max_overlap", &def->guard_max_overlap) < 0 ||
        app_config_positive(&L->p, guard, "max_overlap", def->guard_max_overlap) < 0 ||
        app_config_number(&L->p, guard, "max_speed", &def->guard_max_speed) < 0 ||
        app_config_non_negative(&L->p, guard, "max_speed", def->guard_max_speed) < 0 ||
        app_config_int(&L->p, guard, "every", &every) < 0)
        return -1;
    if (app_config_member(guard, "every") && (every < 1 || every > 1000000000))
        return app_config_fail(&L->p, app_config_member(guard, "every"), "`every` must be >= 1");
    def->guard_every = (int)every;
    if (guard) {
        loader_where_add(L, "guard_max_overlap", app_config_member(guard, "max_overlap"));
        loader_where_add(L, "guard_max_speed", app_config_member(guard, "max_speed"));
        loader_where_add(L, "guard_every", app_config_member(guard, "every"));
    }
    return 0;
}

/* contact = { normal; tangential; rolling; clip_tensile; onset; } */
static int parse_contact(Loader *L, const config_setting_t *root)
{
    static const char *const normal_laws[] = {"linear", "hertz", NULL};
    static const char *const tangential_laws[] = {"none", "regularised", "spring", NULL};
    static const char *const rolling_laws[] = {"off", "chord", "fixed", NULL};
    static const char *const onsets[] = {"step", "event", NULL};
    static const char *const contact_keys[] = {"normal",       "tangential", "rolling",
                                               "clip_tensile", "onset",      NULL};
    SimWorldDef *def = &L->scene->def;
    const config_setting_t *contact;
    def->contact.tangential =
        (L->effects & SIM_EFFECT_FRICTION) ? SIM_TANGENTIAL_REGULARISED : SIM_TANGENTIAL_NONE;
    def->contact.rolling = (L->effects & SIM_EFFECT_ROLLING) ? SIM_ROLLING_CHORD : SIM_ROLLING_OFF;
    def->contact.clip_tensile = 1; /* 000 [GAP]: a normal force never pulls */
    if (app_config_group(&L->p, root, "contact", &contact) < 0 ||
        app_config_keys(&L->p, contact, "contact", contact_keys, NULL) < 0 ||
        loader_gate(L, contact, "tangential", SIM_EFFECT_FRICTION) < 0 ||
        loader_gate(L, contact, "rolling", SIM_EFFECT_ROLLING) < 0)
        return -1;
    int choice = (int)def->contact.normal;
    if (app_config_choice(&L->p, contact, "normal", normal_laws, &choice) < 0)
        return -1;
    def->contact.normal = (SimNormalLaw)choice;
    choice = (int)def->contact.tangential;
    if (app_config_choice(&L->p, contact, "tangential", tangential_laws, &choice) < 0)
        return -1;
    def->contact.tangential = (SimTangentialLaw)choice;
    choice = (int)def->contact.rolling;
    if (app_config_choice(&L->p, contact, "rolling", rolling_laws, &choice) < 0)
        return -1;
    def->contact.rolling = (SimRollingLaw)choice;
    if (app_config_bool(&L->p, contact, "clip_tensile", &def->contact.clip_tensile) < 0)
        return -1;
    choice = (int)def->contact.onset;
    if (app_config_choice(&L->p, contact, "onset", onsets, &choice) < 0)
        return -1;
    def->contact.onset = (SimOnset)choice;
    if (contact) {
        loader_where_add(L, "contact", contact);
        loader_where_add(L, "contact.normal", app_config_member(contact, "normal"));
        loader_where_add(L, "contact.tangential", app_config_member(contact, "tangential"));
        loader_where_add(L, "contact.rolling", app_config_member(contact, "rolling"));
        loader_where_add(L, "contact.onset", app_config_member(contact, "onset"));
    }
    return 0;
}

static int parse_physics(Loader *L, const config_setting_t *root)
{
    if (parse_identity(L, root) < 0 || parse_dynamics(L, root) < 0 || parse_time(L, root) < 0 ||
        parse_guard(L, root) < 0 || parse_contact(L, root) < 0)
        return -1;
    return 0;
}

/* periodic = { x0; x1; } (effect periodic_x) */
static int parse_periodic(Loader *L, const config_setting_t *root)
{
    static const char *const periodic_keys[] = {"x0", "x1", NULL};
    SimWorldDef *def = &L->scene->def;
    const config_setting_t *g;
    if (app_config_group(&L->p, root, "periodic", &g) < 0)
        return -1;
    if (!g)
        return 0;
    if (app_config_keys(&L->p, g, "periodic", periodic_keys, NULL) < 0 ||
        app_config_need_number(&L->p, g, "x0", "periodic", &def->domain_x0) < 0 ||
        app_config_need_number(&L->p, g, "x1", "periodic", &def->domain_x1) < 0)
        return -1;
    if (!(def->domain_x1 > def->domain_x0))
        return app_config_fail(&L->p, app_config_member(g, "x1"),
                               "`periodic.x1` must be > `periodic.x0`");
    loader_where_add(L, "domain", g);
    loader_where_add(L, "domain_x0", app_config_member(g, "x0"));
    loader_where_add(L, "domain_x1", app_config_member(g, "x1"));
    return 0;
}

/* drag = { model; coefficient | viscosity; fluid_velocity; } (effect fluid_drag) */
static int parse_drag(Loader *L, const config_setting_t *root)
{
    static const char *const drag_keys[] = {"model", "coefficient", "viscosity", "fluid_velocity",
                                            NULL};
    static const char *const drag_models[] = {"linear", "stokes", NULL};
    Scene *scene = L->scene;
    const config_setting_t *g;
    if (app_config_group(&L->p, root, "drag", &g) < 0)
        return -1;
    if (!g)
        return 0;
    SceneDrag *d = &scene->drag;
    int model = 0;
    double u[2] = {0.0, 0.0};
    if (app_config_keys(&L->p, g, "drag", drag_keys, NULL) < 0 ||
        app_config_choice(&L->p, g, "model", drag_models, &model) < 0 ||
        app_config_vector(&L->p, g, "fluid_velocity", u, 2) < 0)
        return -1;
    d->model = (SceneDragModel)model;
    d->fluid_vx = u[0];
    d->fluid_vy = u[1];
    const char *key = d->model == SCENE_DRAG_LINEAR ? "coefficient" : "viscosity";
    const char *other = d->model == SCENE_DRAG_LINEAR ? "viscosity" : "coefficient";
    double value = 0.0;
    if (app_config_member(g, other))
        return app_config_fail(&L->p, app_config_member(g, other),
                               "`%s` is not used by drag model `%s`", other, drag_models[model]);
    if (app_config_need_number(&L->p, g, key, "drag", &value) < 0 ||
        app_config_non_negative(&L->p, g, key, value) < 0)
        return -1;
    if (d->model == SCENE_DRAG_LINEAR)
        d->coefficient = value;
    else
        d->viscosity = value;
    scene->def.body_force.apply = drag_apply;
    scene->def.body_force.context = d;
    loader_where_add(L, "body_force", g);
    return 0;
}

/* A family's group given under both of its names (app/base/experiment.h, group_alias). */
static int check_family_groups(Loader *L, const config_setting_t *root)
{
    for (int f = 0; app_experiments[f]; ++f) {
        const AppExperiment *e = app_experiments[f];
        const config_setting_t *old =
            e->group_alias ? app_config_member(root, e->group_alias) : NULL;
        if (old && e->group && app_config_member(root, e->group))
            return app_config_fail(&L->p, old, "`%s` is an older name of `%s`: keep one",
                                   e->group_alias, e->group);
    }
    return 0;
}

/* The family group in `root` that stands for `effect` (app/base/experiment.h, effects), or NULL;
 * with `named`, the first family that has such a group, for messages. */
static const config_setting_t *family_effect_group(const config_setting_t *root, unsigned effect,
                                                   const AppExperiment **named)
{
    *named = NULL;
    for (int f = 0; app_experiments[f]; ++f) {
        const AppExperiment *e = app_experiments[f];
        if (!(e->effects & effect))
            continue;
        if (!*named)
            *named = e;
        const config_setting_t *g = app_experiment_group(e, root);
        if (g)
            return g;
    }
    return NULL;
}

/* The groups an effect needs: periodic (periodic_x), drag or a family's group that stands for it
 * (fluid_drag). */
static int parse_effect_groups(Loader *L, const config_setting_t *root)
{
    if (check_family_groups(L, root) < 0 ||
        loader_gate(L, root, "periodic", SIM_EFFECT_PERIODIC_X) < 0 ||
        loader_gate(L, root, "drag", SIM_EFFECT_FLUID_DRAG) < 0)
        return -1;
    for (int f = 0; app_experiments[f]; ++f) {
        const config_setting_t *g = app_experiment_group(app_experiments[f], root);
        unsigned effects = app_experiments[f]->effects;
        for (unsigned bit = 1; g && bit && bit <= effects; bit <<= 1)
            if ((effects & bit) && loader_gate(L, root, config_setting_name(g), bit) < 0)
                return -1;
    }
    if ((L->effects & SIM_EFFECT_PERIODIC_X) && !app_config_member(root, "periodic"))
        return app_config_fail(
            &L->p, L->effects_setting,
            "effect periodic_x needs a group `periodic = { x0 = ...; x1 = ...; }`");
    const AppExperiment *family = NULL;
    const config_setting_t *fluid = family_effect_group(root, SIM_EFFECT_FLUID_DRAG, &family);
    if ((L->effects & SIM_EFFECT_FLUID_DRAG) && !app_config_member(root, "drag") && !fluid)
        return app_config_fail(
            &L->p, L->effects_setting,
            "effect fluid_drag needs a group `drag = { model = ...; ... }`%s%s%s",
            family ? " or `" : "", family ? family->group : "", family ? " = { ... }`" : "");
    if (app_config_member(root, "drag") && fluid)
        return app_config_fail(&L->p, fluid, "`%s` and `drag` both drag the grains: keep one",
                               config_setting_name(fluid));
    return parse_periodic(L, root) < 0 || parse_drag(L, root) < 0 ? -1 : 0;
}

/* ---------------------------------------------------------------- scene_load */

/* A scene with its defaults; its name and the loader's folder from the path. NULL: no memory. */
static Scene *scene_new(Loader *L, const char *path, char *err, size_t err_size)
{
    Scene *scene = calloc(1, sizeof *scene);
    SceneWhere *where = calloc(1, sizeof *where);
    if (!scene || !where) {
        free(scene);
        free(where);
        snprintf(err, err_size, "%s: out of memory", path);
        return NULL;
    }
    scene->where = where;
    scene->def = sim_world_def_default();
    sim_grain_buffer_init(&scene->grains);
    snprintf(scene->path, sizeof scene->path, "%s", path);
    snprintf(where->fallback, sizeof where->fallback, "%s:1", path);
    /* name and include folder from the path */
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    if (slash)
        snprintf(L->dir, sizeof L->dir, "%.*s", (int)(slash - path), path);
    else
        snprintf(L->dir, sizeof L->dir, ".");
    snprintf(scene->name, sizeof scene->name, "%s", base);
    char *dot = strrchr(scene->name, '.');
    if (dot && dot != scene->name)
        *dot = '\0';
    L->scene = scene;
    L->p = (AppConfig){.path = scene->path, .err = err, .err_size = err_size};
    return scene;
}

/* The provenance of the scene: its file's SHA-256 and the resolved text (includes expanded,
 * overrides applied) that a run copies beside its outputs. 0, or -1 (no memory). */
static int resolve_scene(Loader *L, const char *path)
{
    if (app_sha256_file(path, L->scene->sha256) != 0)
        L->scene->sha256[0] = '\0';
    size_t size = 0;
    FILE *text = open_memstream(&L->scene->resolved, &size);
    if (!text) {
        snprintf(L->p.err, L->p.err_size, "%s: out of memory", path);
        return -1;
    }
    config_write(&L->config, text);
    return fclose(text) == 0 ? 0 : -1;
}

/* libconfig keeps an integer literal in 32 bits unless it ends in L (4294969314 reads as 2018),
 * so the loader refuses a literal outside [-2^31, 2^31) without the suffix (and one outside
 * 64 bits with it, which libconfig would wrap) before libconfig
 * reads the file: `file:line: integer 4294969314 is out of range ...`. Strings and comments are
 * skipped; @include files are checked the same way (to a depth of 10). */
static int int_literal_fail(Loader *L, const char *path, int line, const char *start, size_t n)
{
    int suffix = start[n] == 'L' || start[n] == 'l';
    snprintf(L->p.err, L->p.err_size,
             suffix ? "%s:%d: integer %.*sL is out of range of 64-bit integers"
                    : "%s:%d: integer %.*s is out of range of libconfig's 32-bit integers (write "
                      "it with the suffix L for a 64-bit integer, or as a float)",
             path, line, (int)(n > 40 ? 40 : n), start);
    return -1;
}

static int is_name_char(char c)
{
    return isalnum((unsigned char)c) || c == '_' || c == '.' || c == '-' || c == '*';
}

/* One integer literal at text[*at] (a digit): 0, or -1 when it does not fit 32 bits. */
static int check_literal(Loader *L, const char *path, int line, const char *text, size_t *at)
{
    size_t k = *at, start = k;
    if (start > 0 && (text[start - 1] == '-' || text[start - 1] == '+'))
        --start;
    int hex = text[k] == '0' && (text[k + 1] == 'x' || text[k + 1] == 'X');
    if (hex)
        k += 2;
    while (hex ? isxdigit((unsigned char)text[k]) : isdigit((unsigned char)text[k]))
        ++k;
    int is_float = !hex && (text[k] == '.' || text[k] == 'e' || text[k] == 'E');
    int suffix = text[k] == 'L' || text[k] == 'l';
    *at = k;
    if (is_float)
        return 0;
    errno = 0;
    char *end = NULL;
    long long v = strtoll(text + start, &end, hex ? 16 : 10);
    int fits = errno == 0 && (suffix || (hex ? (unsigned long long)v <= 0xffffffffull
                                             : v >= -2147483648ll && v <= 2147483647ll));
    return fits ? 0 : int_literal_fail(L, path, line, text + start, k - start);
}

static int check_int_literals(Loader *L, const char *path, int depth);

/* 0 when `path` is a regular file; else -1 with why in `why` (a folder, a FIFO or device, which
 * libconfig would fail on without a line or block on, or why it cannot be opened): checked
 * through sim_open_input, which never blocks. */
static int regular_file(const char *path, char *why, size_t size)
{
    const char *reason = NULL;
    FILE *f = sim_open_input(path, &reason);
    if (!f) {
        snprintf(why, size, "%s", reason);
        return -1;
    }
    fclose(f);
    return 0;
}

/* An `@include "NAME"` at text[*at], line `line` of `file`: the included file checked (NAME
 * against the scene's folder, as libconfig 1.5 resolves it: it prefixes that folder to every
 * name, so an absolute NAME is refused here with its line rather than failing there). */
static int check_include(Loader *L, const char *file, int line, const char *text, size_t size,
                         size_t *at, int depth)
{
    size_t k = *at + 8;
    while (k < size && (text[k] == ' ' || text[k] == '\t'))
        ++k;
    if (k >= size || text[k] != '"' || depth >= 10)
        return 0;
    size_t end = k + 1;
    while (end < size && text[end] != '"' && text[end] != '\n')
        ++end;
    *at = end;
    char name[SCENE_PATH_MAX], path[2 * SCENE_PATH_MAX + 2];
    snprintf(name, sizeof name, "%.*s", (int)(end - k - 1), text + k + 1);
    if (name[0] == '/') {
        snprintf(L->p.err, L->p.err_size,
                 "%s:%d: @include \"%s\": an included file is named relative to the scene's "
                 "folder (%s), not by an absolute path",
                 file, line, name, L->dir);
        return -1;
    }
    snprintf(path, sizeof path, "%s/%s", L->dir, name);
    char why[256];
    if (regular_file(path, why, sizeof why) != 0) {
        snprintf(L->p.err, L->p.err_size, "%s:%d: @include \"%s\": cannot read %s: %s", file, line,
                 name, path, why);
        return -1;
    }
    return check_int_literals(L, path, depth + 1);
}

static int check_int_literals(Loader *L, const char *path, int depth)
{
    FILE *f = sim_open_input(path, NULL);
    if (!f)
        return 0; /* libconfig reports it */
    char *text = NULL;
    size_t size = 0;
    FILE *copy = open_memstream(&text, &size);
    int c;
    while (copy && (c = fgetc(f)) != EOF)
        fputc(c, copy);
    fclose(f);
    if (!copy || fclose(copy) != 0) {
        free(text);
        return 0;
    }
    const char *nul = memchr(text, '\0', size);
    if (nul) { /* libconfig would end the string (or the file) there without a word */
        int at = 1;
        for (const char *q = text; q < nul; ++q)
            at += *q == '\n';
        snprintf(L->p.err, L->p.err_size, "%s:%d: a NUL byte: a scene is text", path, at);
        free(text);
        return -1;
    }
    int line = 1, rc = 0;
    for (size_t k = 0; k < size && rc == 0; ++k) {
        char ch = text[k];
        if (ch == '\n') {
            ++line;
        } else if (ch == '@' && strncmp(text + k, "@include", 8) == 0) {
            rc = check_include(L, path, line, text, size, &k, depth);
        } else if (ch == '#' || (ch == '/' && text[k + 1] == '/')) {
            while (k + 1 < size && text[k + 1] != '\n')
                ++k;
        } else if (ch == '/' && text[k + 1] == '*') {
            int opened = line;
            for (k += 2; k + 1 < size && !(text[k] == '*' && text[k + 1] == '/'); ++k)
                line += text[k] == '\n';
            if (k + 1 >= size) { /* libconfig would drop the rest of the file without a word */
                snprintf(L->p.err, L->p.err_size,
                         "%s:%d: a `/*` comment that is never closed (no `*/` before the end of "
                         "the file)",
                         path, opened);
                rc = -1;
            }
            ++k;
        } else if (ch == '"') {
            for (++k; k < size && text[k] != '"'; ++k) {
                k += text[k] == '\\' && k + 1 < size;
                line += text[k] == '\n';
            }
        } else if (isdigit((unsigned char)ch) &&
                   (k == 0 || !is_name_char(text[k - 1]) || text[k - 1] == '-')) {
            rc = check_literal(L, path, line, text, &k);
            --k;
        } else if (isalpha((unsigned char)ch) || ch == '_') {
            while (k + 1 < size && is_name_char(text[k + 1]))
                ++k; /* a name (k_n2, e1): no literal inside */
        }
    }
    free(text);
    return rc;
}

/* Reads the file into L->config (initialised) and applies the --set overrides. 0, or -1. */
static int read_scene(Loader *L, const char *path, const char *const *sets, int set_count)
{
    config_set_include_dir(&L->config, L->dir);
    char why[256];
    if (regular_file(path, why, sizeof why) != 0) {
        snprintf(L->p.err, L->p.err_size, "%s: cannot read scene file: %s", path, why);
        return -1;
    }
    if (check_int_literals(L, path, 0) != 0)
        return -1;
    if (!config_read_file(&L->config, path)) {
        if (config_error_type(&L->config) == CONFIG_ERR_FILE_IO)
            snprintf(L->p.err, L->p.err_size, "%s: cannot read scene file: %s", path,
                     errno ? strerror(errno) : "I/O error");
        else {
            char file[SCENE_PATH_MAX];
            app_config_file_name(&L->p, config_error_file(&L->config), file, sizeof file);
            snprintf(L->p.err, L->p.err_size, "%s:%d: %s", file, config_error_line(&L->config),
                     config_error_text(&L->config));
        }
        return -1;
    }
    for (int k = 0; k < set_count; ++k)
        if (loader_apply_set(L, sets[k]) != 0)
            return -1;
    return resolve_scene(L, path);
}

/* time.target_error: steps per contact from the measured convergence law (app/scene/advice.h), for
 * the scene's own grains (t_c,min and the stiffest pair) or its species' e_n. 0, or -1. */
static int apply_target_error(Loader *L)
{
    Scene *scene = L->scene;
    if (!(scene->target_error > 0.0))
        return 0;
    SimWorldDef def = scene->def;
    def.grains = sim_grain_buffer_view(&scene->grains);
    AppAdvice advice;
    char why[256];
    if (app_dt_advice(&def, scene->grains.count - scene->fixed_count, scene->target_error, &advice,
                      why, sizeof why) != 0)
        return app_config_fail(&L->p, config_lookup(&L->config, "time.target_error"),
                               "time: `target_error`: %s", why);
    scene->def.steps_per_contact = advice.steps_per_contact;
    return 0;
}

/* units = "normalised": labels only, every number is written as given (docs/scenes.md#units).
 * Before the families parse, so that their figures' labels follow. */
static void normalised_labels(Scene *scene)
{
    if (!scene->units_normalised)
        return;
    const double g = hypot(scene->def.gravity_x, scene->def.gravity_y);
    const int labels = g == 1.0 ? SCENE_UNITS_NORMALISED_G : SCENE_UNITS_NORMALISED;
    scene->style.normalised_units = labels;
    for (int k = 0; k < scene->output.figure_count; ++k)
        scene->output.figures[k].style.normalised_units = labels;
}

/* The sources against the time step of each stage as a run takes it (its own, or the automatic
 * one). 0, or -1. */
static int check_sources(Loader *L, const config_setting_t *root)
{
    const Scene *scene = L->scene;
    double stage_dt[SCENE_MAX_STAGES];
    if (scene->source_count == 0)
        return 0;
    for (int k = 0; k < scene->stage_count; ++k) {
        SimWorldDef def = scene_world_def(scene, k);
        stage_dt[k] =
            def.time_step > 0.0 ? def.time_step : app_sources_timing(scene, &def).time_step;
    }
    return loader_check_sources(L, root, stage_dt);
}

/* The scene's own groups in order, then each family's. 0, or -1. */
static int parse_scene(Loader *L, const config_setting_t *root)
{
    Scene *scene = L->scene;
    if (parse_physics(L, root) < 0 || loader_parse_species(L, root) < 0 ||
        loader_parse_motions(L, root) < 0 || parse_effect_groups(L, root) < 0 ||
        loader_parse_bodies(L, root) < 0 || loader_parse_grains(L, root) < 0 ||
        loader_parse_walls(L, root) < 0 || apply_target_error(L) < 0 ||
        loader_parse_sinks(L, root) < 0 || loader_parse_stages(L, root) < 0 ||
        loader_check_bodies(L, root) < 0 || loader_parse_sources(L, root) < 0 ||
        check_sources(L, root) < 0 || loader_check_remove_ids(L, root) < 0 ||
        loader_claim_run_outputs(L, root) < 0 || loader_parse_output(L, root) < 0)
        return -1;
    normalised_labels(scene);
    for (int f = 0; app_experiments[f]; ++f) { /* each family parses its own keys */
        const AppExperiment *e = app_experiments[f];
        if (e->parse && e->parse(root, app_experiment_group(e, root), scene, &scene->experiments[f],
                                 L->p.err, L->p.err_size) != 0)
            return -1;
        /* the family's own files, which no figure or measure may overwrite */
        for (int k = 0; scene->experiments[f] && e->outputs && e->outputs[k]; ++k)
            if (scene_claim_output(scene, &L->p, NULL, e->name, e->outputs[k]) < 0)
                return -1;
    }
    return 0;
}

/* t*, the traced grains and the views, once every group is read. */
static int finish_output(Loader *L)
{
    Scene *scene = L->scene;
    /* t* = t / sqrt(D/g) with D the container height (000 eq. 6.1); in reduced units D = d, the
     * mean diameter (t_star_length 0: the sim's own scale), and the labels follow. */
    if (scene->units_reduced) {
        const config_setting_t *set = config_lookup(&L->config, "output.t_star_length");
        if (set && scene->output.t_star_length != 0.0)
            return app_config_fail(&L->p, set,
                                   "units = \"reduced\" takes t* from the mean diameter d: "
                                   "`t_star_length` must be 0 or absent");
        scene->style.reduced_units = 1;
        for (int k = 0; k < scene->output.figure_count; ++k)
            scene->output.figures[k].style.reduced_units = 1;
    } else if (scene->output.t_star_length == 0.0) {
        scene->output.t_star_length = L->box_height;
    }
    scene->def.length_scale = scene->output.t_star_length; /* frames' t* agree with CSV */
    /* an id the run may hold: the scene's own, an added grain's, or one a source inserts (from
       the first id above both) */
    const uint32_t inserted =
        scene->added_id_end > 0 ? scene->added_id_end : (uint32_t)scene->grains.count;
    for (int k = 0; k < scene->output.trace_count; ++k) {
        uint32_t id = scene->output.trace_ids[k];
        if (id >= (uint32_t)scene->grains.count && scene->stages[0].load == SCENE_LOAD_SCENE &&
            !scene_added_grain(scene, NULL, id) && !(scene->source_count > 0 && id >= inserted))
            return app_config_fail(&L->p, config_lookup(&L->config, "output.trace"),
                                   "`trace` id %u is not a grain of the scene (ids 0 to %d), of a "
                                   "stage's `add`%s",
                                   id, scene->grains.count - 1,
                                   scene->source_count > 0 ? " or of a source" : " (no source)");
    }
    return loader_check_views(L);
}

/* Stage k's step count, duration / dt, within what a run can count (a `time.end = 1e15`, a
 * denormal dt or `steps_per_contact = 1e308` would overflow it and run nothing). 0, or -1. */
static int check_step_count(const Scene *scene, int k, char *err, size_t err_size)
{
    SimWorldDef def = scene_world_def(scene, k);
    double dt = def.time_step > 0.0 ? def.time_step : sim_world_def_timing(&def).time_step;
    if (!(dt > 0.0)) /* chosen when the stage's state is loaded */
        return 0;
    double steps = scene->stages[k].duration / dt;
    if (isfinite(dt) && dt >= 1e-300 && steps <= SCENE_MAX_STEPS)
        return 0;
    snprintf(err, err_size,
             "%s: stage %s would take %.3g steps of dt = %.3g s (time.end %g s): more than the "
             "%.0e steps a run counts; lower time.end or raise the time step",
             scene->where->stage_dt[k], scene->stages[k].name, steps, dt, scene->stages[k].duration,
             SCENE_MAX_STEPS);
    return -1;
}

/* Every stage's world definition, as the stage will build it (its time step, forcing and what a
 * family's adjust_def makes of it: a Brazil-nut box at rest, then shaken), against the contacts
 * and sim's checks, so that nothing a later stage needs is first found wrong once earlier stages
 * ran. 0, or -1. */
static int validate_stages(const Scene *scene, char *err, size_t err_size)
{
    for (int k = 0; k < scene->stage_count; ++k)
        if (check_step_count(scene, k, err, err_size) != 0)
            return -1;
    for (int k = 0; k < scene->stage_count; ++k) {
        SimWorldDef def = scene_world_def(scene, k);
        if (scene_validate_def(scene, k, &def, err, err_size) != 0)
            return -1;
    }
    return 0;
}

Scene *scene_load(const char *path, const char *const *sets, int set_count, char *err,
                  size_t err_size)
{
    Loader loader;
    memset(&loader, 0, sizeof loader);
    Loader *L = &loader;
    Scene *scene = scene_new(L, path, err, err_size);
    if (!scene)
        return NULL;
    config_init(&L->config);
    int ok = read_scene(L, path, sets, set_count) == 0 &&
             parse_scene(L, config_root_setting(&L->config)) == 0 && finish_output(L) == 0 &&
             loader_check_overlaps(L) == 0 && validate_stages(scene, err, err_size) == 0;
    config_destroy(&L->config);
    for (int k = 0; k < L->set_count; ++k)
        free(L->set_keys[k]);
    scene_claims_free(scene);
    if (!ok) {
        scene_free(scene);
        return NULL;
    }
    return scene;
}

/* ---------------------------------------------------------------- public */

void scene_free(Scene *scene)
{
    if (!scene)
        return;
    for (int k = 0; k < SCENE_MAX_STAGES; ++k)
        free(scene->stages[k].remove_ids);
    for (int k = 0; k < SCENE_MAX_STAGES; ++k)
        free(scene->stages[k].adds);
    sim_grain_buffer_free(&scene->grains);
    free(scene->walls);
    free(scene->wall_bodies);
    free(scene->grain_bodies);
    free(scene->body_names);
    free(scene->resolved);
    free(scene->sources);
    for (int f = 0; app_experiments[f]; ++f)
        if (scene->experiments[f] && app_experiments[f]->free)
            app_experiments[f]->free(scene->experiments[f]);
    scene_claims_free(scene);
    if (scene->where) {
        free(scene->where->items);
        free(scene->where->grain_item);
        free(scene->where);
    }
    free(scene);
}

SimWorldDef scene_world_def(const Scene *scene, int stage)
{
    SimWorldDef def = scene->def;
    const SceneStage *s = &scene->stages[stage];
    def.grains = sim_grain_buffer_view(&scene->grains);
    def.time_step = s->time_step;
    /* the stage's forcing: its pipeline is built from its own effects */
    def.gravity_x = s->gravity_x;
    def.gravity_y = s->gravity_y;
    def.effects = s->effects;
    if (!(def.effects & SIM_EFFECT_REMOVAL))
        def.sink_count = 0;
    for (int f = 0; app_experiments[f]; ++f)
        if (scene->experiments[f] && app_experiments[f]->adjust_def)
            app_experiments[f]->adjust_def(scene->experiments[f], stage, &def);
    /* the automatic time step of a world built from the scene resolves the grains its sources
     * will insert too (a scene fed by sources alone had no grains to choose it from: dt 0) */
    if (def.time_step == 0.0 && scene->source_count > 0 && s->load == SCENE_LOAD_SCENE)
        def.time_step = app_sources_timing(scene, &def).time_step;
    return def;
}

void *scene_experiment_state(const Scene *scene, const AppExperiment *family)
{
    int k = scene ? app_experiment_index(family) : -1;
    return k >= 0 ? scene->experiments[k] : NULL;
}

void scene_effect_names(unsigned effects, char *out, size_t out_size)
{
    size_t used = 0;
    out[0] = '\0';
    for (unsigned bit = 1; bit && bit <= SIM_EFFECT_REMOVAL; bit <<= 1)
        if (effects & bit) {
            const char *name = sim_effect_name(bit);
            used += (size_t)snprintf(out + used, used < out_size ? out_size - used : 0, "%s%s",
                                     used ? ", " : "", name ? name : "?");
        }
    if (!out[0])
        snprintf(out, out_size, "none");
}

const char *scene_libconfig_version(void)
{
#define SCENE_STR2(x) #x
#define SCENE_STR(x)  SCENE_STR2(x)
    return "libconfig " SCENE_STR(LIBCONFIG_VER_MAJOR) "." SCENE_STR(
        LIBCONFIG_VER_MINOR) "." SCENE_STR(LIBCONFIG_VER_REVISION);
}
