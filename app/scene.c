/* SPDX-License-Identifier: MIT */
/* scene.c: libconfig scene file -> SimWorldDef + stages + output settings (docs/scenes.md).
 *
 * Every key is read through a typed getter that reports `file:line: message`; every group lists its
 * allowed keys so that a typo is an error, and keys that belong to an effect (mu needs friction,
 * motion needs vibration, ...) are refused unless the effect is declared. After parsing, the
 * loader checks the start configuration (overlaps) and the time step, then hands the definition
 * to sim_world_def_validate and maps the reported field path back to the key that set it. */
#include "scene.h"

#include "experiments.h"

#include <ctype.h>
#include <errno.h>
#include <libconfig.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define WHERE_MAX         (SCENE_PATH_MAX + 96)
/* Start overlaps smaller than this fraction of the smaller radius are tolerated: lattices of
 * touching grains (fixed rows) land on exact contact up to rounding. */
#define OVERLAP_TOLERANCE 0.01
#define PI                3.14159265358979323846

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
    char fallback[WHERE_MAX];
};

typedef struct Loader {
    Scene *scene;
    config_t config;
    char *err;
    size_t err_size;
    int failed;
    unsigned effects;
    const config_setting_t *effects_setting;
    char dir[SCENE_PATH_MAX];
    double box_height;  /* grains.box y1 - y0, m: default D of t* */
    char *set_keys[64]; /* copies of --set keys, pointed to by setting hooks */
    int set_count;
} Loader;

/* ---------------------------------------------------------------- errors and locations */

/* libconfig names an @include'd file as written; show it relative to the working folder. */
static void file_name(const Loader *L, const char *file, char *out, size_t size)
{
    if (!file || strcmp(file, L->scene->path) == 0 || file[0] == '/' || strcmp(L->dir, ".") == 0)
        snprintf(out, size, "%s", file ? file : L->scene->path);
    else
        snprintf(out, size, "%.*s/%s", (int)(size / 2), L->dir, file);
}

static void where_of(const Loader *L, const config_setting_t *s, char *out, size_t size)
{
    if (s && config_setting_get_hook(s)) {
        snprintf(out, size, "--set %s", (const char *)config_setting_get_hook(s));
        return;
    }
    if (s && config_setting_source_line(s) > 0) {
        char file[SCENE_PATH_MAX];
        file_name(L, config_setting_source_file(s), file, sizeof file);
        snprintf(out, size, "%s:%u", file, config_setting_source_line(s));
        return;
    }
    snprintf(out, size, "%s:1", L->scene->path);
}

__attribute__((format(printf, 3, 4))) static int fail(Loader *L, const config_setting_t *s,
                                                      const char *format, ...)
{
    if (L->failed)
        return -1;
    char where[WHERE_MAX], message[600];
    where_of(L, s, where, sizeof where);
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    snprintf(L->err, L->err_size, "%s: %s", where, message);
    L->failed = 1;
    return -1;
}

static void where_add(Loader *L, const char *field, const config_setting_t *s)
{
    SceneWhere *w = L->scene->where;
    if (w->count == w->capacity) {
        int capacity = w->capacity ? 2 * w->capacity : 64;
        WhereItem *items = realloc(w->items, (size_t)capacity * sizeof *items);
        if (!items)
            return;
        w->items = items;
        w->capacity = capacity;
    }
    WhereItem *item = &w->items[w->count++];
    snprintf(item->field, sizeof item->field, "%s", field);
    where_of(L, s, item->where, sizeof item->where);
}

/* Records the location of every grain added since `first` as the location of setting s. */
static void where_grains(Loader *L, int first, const config_setting_t *s, const char *field)
{
    SceneWhere *w = L->scene->where;
    int count = L->scene->grains.count;
    if (count > w->grain_capacity) {
        int capacity = count > 2 * w->grain_capacity ? count : 2 * w->grain_capacity;
        int *grow = realloc(w->grain_item, (size_t)capacity * sizeof *grow);
        if (!grow)
            return;
        w->grain_item = grow;
        w->grain_capacity = capacity;
    }
    where_add(L, field, s);
    for (int i = first; i < count; ++i)
        w->grain_item[i] = w->count - 1;
}

static const char *type_name(const config_setting_t *s)
{
    switch (config_setting_type(s)) {
    case CONFIG_TYPE_GROUP:
        return "a group";
    case CONFIG_TYPE_INT:
    case CONFIG_TYPE_INT64:
        return "an integer";
    case CONFIG_TYPE_FLOAT:
        return "a number";
    case CONFIG_TYPE_STRING:
        return "a string";
    case CONFIG_TYPE_BOOL:
        return "a boolean";
    case CONFIG_TYPE_ARRAY:
        return "an array";
    case CONFIG_TYPE_LIST:
        return "a list";
    default:
        return "nothing";
    }
}

/* ---------------------------------------------------------------- typed getters
 * Each returns 1 when the key is present and valid, 0 when absent (output untouched), -1 on
 * error (reported). */

static config_setting_t *member(const config_setting_t *group, const char *key)
{
    return group ? config_setting_get_member(group, key) : NULL;
}

static int number_of(Loader *L, const config_setting_t *s, const char *key, double *out)
{
    switch (config_setting_type(s)) {
    case CONFIG_TYPE_INT:
    case CONFIG_TYPE_INT64:
        *out = (double)config_setting_get_int64(s);
        return 1;
    case CONFIG_TYPE_FLOAT:
        *out = config_setting_get_float(s);
        if (!isfinite(*out))
            return fail(L, s, "`%s` must be a finite number", key);
        return 1;
    default:
        return fail(L, s, "`%s` must be a number, not %s", key, type_name(s));
    }
}

static int get_number(Loader *L, const config_setting_t *g, const char *key, double *out)
{
    const config_setting_t *s = member(g, key);
    return s ? number_of(L, s, key, out) : 0;
}

static int get_int(Loader *L, const config_setting_t *g, const char *key, long long *out)
{
    const config_setting_t *s = member(g, key);
    if (!s)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_INT && config_setting_type(s) != CONFIG_TYPE_INT64)
        return fail(L, s, "`%s` must be an integer, not %s", key, type_name(s));
    *out = config_setting_get_int64(s);
    return 1;
}

static int get_bool(Loader *L, const config_setting_t *g, const char *key, int *out)
{
    const config_setting_t *s = member(g, key);
    if (!s)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_BOOL)
        return fail(L, s, "`%s` must be true or false, not %s", key, type_name(s));
    *out = config_setting_get_bool(s) ? 1 : 0;
    return 1;
}

static int get_string(Loader *L, const config_setting_t *g, const char *key, const char **out)
{
    const config_setting_t *s = member(g, key);
    if (!s)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_STRING)
        return fail(L, s, "`%s` must be a string, not %s", key, type_name(s));
    *out = config_setting_get_string(s);
    return 1;
}

/* A fixed-length array of numbers, e.g. gravity = [0.0, -9.806]. */
static int get_vector(Loader *L, const config_setting_t *g, const char *key, double *out, int n)
{
    const config_setting_t *s = member(g, key);
    if (!s)
        return 0;
    if ((config_setting_type(s) != CONFIG_TYPE_ARRAY &&
         config_setting_type(s) != CONFIG_TYPE_LIST) ||
        config_setting_length(s) != n)
        return fail(L, s, "`%s` must be an array of %d numbers", key, n);
    for (int k = 0; k < n; ++k)
        if (number_of(L, config_setting_get_elem(s, (unsigned)k), key, &out[k]) < 0)
            return -1;
    return 1;
}

static int need(Loader *L, const config_setting_t *g, const char *key, const char *what)
{
    if (member(g, key))
        return 0;
    return fail(L, g, "missing required key `%s` in %s", key, what);
}

static int need_number(Loader *L, const config_setting_t *g, const char *key, const char *what,
                       double *out)
{
    if (need(L, g, key, what) < 0)
        return -1;
    return get_number(L, g, key, out);
}

/* Range checks reported at the key's line. */
static int check_positive(Loader *L, const config_setting_t *g, const char *key, double v)
{
    if (v > 0.0)
        return 0;
    return fail(L, member(g, key) ? member(g, key) : g, "`%s` must be > 0 (got %g)", key, v);
}

static int check_non_negative(Loader *L, const config_setting_t *g, const char *key, double v)
{
    if (v >= 0.0)
        return 0;
    return fail(L, member(g, key) ? member(g, key) : g, "`%s` must be >= 0 (got %g)", key, v);
}

/* Picks one of `names` (NULL-terminated); returns its index, or -1 (reported). */
static int get_choice(Loader *L, const config_setting_t *g, const char *key,
                      const char *const *names, int *out)
{
    const char *value = NULL;
    int found = get_string(L, g, key, &value);
    if (found <= 0)
        return found;
    char list[256] = "";
    for (int k = 0; names[k]; ++k) {
        if (strcmp(value, names[k]) == 0) {
            *out = k;
            return 1;
        }
        size_t used = strlen(list);
        snprintf(list + used, sizeof list - used, "%s%s", k ? ", " : "", names[k]);
    }
    return fail(L, member(g, key), "unknown %s `%s` (expected one of: %s)", key, value, list);
}

static int in_list(const char *key, const char *const *list)
{
    for (int k = 0; list && list[k]; ++k)
        if (strcmp(key, list[k]) == 0)
            return 1;
    return 0;
}

/* Rejects members of g that are in neither list. */
static int check_keys(Loader *L, const config_setting_t *g, const char *what,
                      const char *const *allowed, const char *const *more)
{
    if (!g)
        return 0;
    if (config_setting_type(g) != CONFIG_TYPE_GROUP)
        return fail(L, g, "%s must be a group { ... }, not %s", what, type_name(g));
    for (int k = 0; k < config_setting_length(g); ++k) {
        const config_setting_t *s = config_setting_get_elem(g, (unsigned)k);
        const char *key = config_setting_name(s);
        if (!in_list(key, allowed) && !in_list(key, more))
            return fail(L, s, "unknown key `%s` in %s", key, what);
    }
    return 0;
}

/* A key that only makes sense with an effect: refused when the effect is not declared. */
static int gate(Loader *L, const config_setting_t *g, const char *key, unsigned effect)
{
    const config_setting_t *s = member(g, key);
    if (!s || (L->effects & effect))
        return 0;
    return fail(L, s, "`%s` needs effect \"%s\", which is not declared in `effects`", key,
                sim_effect_name(effect));
}

static int group_of(Loader *L, const config_setting_t *g, const char *key,
                    const config_setting_t **out)
{
    config_setting_t *s = member(g, key);
    *out = NULL;
    if (!s)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_GROUP)
        return fail(L, s, "`%s` must be a group { ... }, not %s", key, type_name(s));
    *out = s;
    return 1;
}

static int list_of(Loader *L, const config_setting_t *g, const char *key,
                   const config_setting_t **out)
{
    config_setting_t *s = member(g, key);
    *out = NULL;
    if (!s)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_LIST)
        return fail(L, s, "`%s` must be a list ( {...}, {...} ), not %s", key, type_name(s));
    for (int k = 0; k < config_setting_length(s); ++k) {
        const config_setting_t *e = config_setting_get_elem(s, (unsigned)k);
        if (config_setting_type(e) != CONFIG_TYPE_GROUP)
            return fail(L, e, "elements of `%s` must be groups { ... }, not %s", key, type_name(e));
    }
    *out = s;
    return 1;
}

/* Names used in file names: letters, digits, '_', '-', '.'. */
static int check_file_name(Loader *L, const config_setting_t *g, const char *key, const char *v)
{
    int ok = v[0] != '\0' && v[0] != '.' && strlen(v) < SCENE_NAME_MAX;
    for (const char *c = v; ok && *c; ++c)
        ok = isalnum((unsigned char)*c) || *c == '_' || *c == '-' || *c == '.';
    if (ok)
        return 0;
    return fail(L, member(g, key), "`%s` = \"%s\" must be a short name of letters, digits, _ - .",
                key, v);
}

/* ---------------------------------------------------------------- --set overrides */

static int parse_long(const char *text, long long *out)
{
    char *end;
    errno = 0;
    long long v = strtoll(text, &end, 10);
    if (end == text || *end != '\0' || errno)
        return 0;
    *out = v;
    return 1;
}

static int parse_double(const char *text, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(text, &end);
    if (end == text || *end != '\0' || errno || !isfinite(v))
        return 0;
    *out = v;
    return 1;
}

static void trim_quotes(char *text)
{
    size_t n = strlen(text);
    if (n >= 2 &&
        ((text[0] == '"' && text[n - 1] == '"') || (text[0] == '\'' && text[n - 1] == '\''))) {
        memmove(text, text + 1, n - 2);
        text[n - 2] = '\0';
    }
}

static int infer_type(const char *value)
{
    long long i;
    double d;
    if (strcmp(value, "true") == 0 || strcmp(value, "false") == 0)
        return CONFIG_TYPE_BOOL;
    if (parse_long(value, &i))
        return CONFIG_TYPE_INT;
    if (parse_double(value, &d))
        return CONFIG_TYPE_FLOAT;
    return CONFIG_TYPE_STRING;
}

/* Writes one scalar value into s, following s's type (an integer is accepted for a number). */
static int set_scalar(Loader *L, config_setting_t *s, const char *key, char *value)
{
    long long i;
    double d;
    int ok = 0;
    switch (config_setting_type(s)) {
    case CONFIG_TYPE_INT:
        ok = parse_long(value, &i) && i >= -2147483647LL && i <= 2147483647LL &&
             config_setting_set_int(s, (int)i);
        if (!ok)
            snprintf(L->err, L->err_size, "--set %s: `%s` is not an integer", key, value);
        break;
    case CONFIG_TYPE_INT64:
        ok = parse_long(value, &i) && config_setting_set_int64(s, i);
        if (!ok)
            snprintf(L->err, L->err_size, "--set %s: `%s` is not an integer", key, value);
        break;
    case CONFIG_TYPE_FLOAT:
        ok = parse_double(value, &d) && config_setting_set_float(s, d);
        if (!ok)
            snprintf(L->err, L->err_size, "--set %s: `%s` is not a number", key, value);
        break;
    case CONFIG_TYPE_BOOL:
        ok = (strcmp(value, "true") == 0 || strcmp(value, "false") == 0) &&
             config_setting_set_bool(s, strcmp(value, "true") == 0);
        if (!ok)
            snprintf(L->err, L->err_size, "--set %s: `%s` is not true or false", key, value);
        break;
    case CONFIG_TYPE_STRING:
        trim_quotes(value);
        ok = config_setting_set_string(s, value);
        if (!ok)
            snprintf(L->err, L->err_size, "--set %s: cannot set `%s`", key, value);
        break;
    default:
        snprintf(L->err, L->err_size, "--set %s: is %s; set one of its elements (KEY.0=...)", key,
                 type_name(s));
        break;
    }
    if (!ok)
        L->failed = 1;
    return ok ? 0 : -1;
}

/* Replaces the elements of an array with "[a, b, c]". */
static int set_array(Loader *L, config_setting_t *s, const char *key, char *value)
{
    size_t n = strlen(value);
    if (n < 2 || value[0] != '[' || value[n - 1] != ']') {
        snprintf(L->err, L->err_size, "--set %s: an array value is written [a, b, ...]", key);
        L->failed = 1;
        return -1;
    }
    value[n - 1] = '\0';
    int type = config_setting_length(s) > 0 ? config_setting_type(config_setting_get_elem(s, 0))
                                            : CONFIG_TYPE_NONE;
    while (config_setting_length(s) > 0)
        config_setting_remove_elem(s, 0);
    char *save = NULL;
    for (char *item = strtok_r(value + 1, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
        while (isspace((unsigned char)*item))
            ++item;
        char *end = item + strlen(item);
        while (end > item && isspace((unsigned char)end[-1]))
            *--end = '\0';
        if (type == CONFIG_TYPE_NONE)
            type = infer_type(item);
        if (type == CONFIG_TYPE_INT && infer_type(item) == CONFIG_TYPE_FLOAT)
            type = CONFIG_TYPE_FLOAT;
        config_setting_t *e = config_setting_add(s, NULL, type);
        if (!e) {
            snprintf(L->err, L->err_size, "--set %s: mixed element types", key);
            L->failed = 1;
            return -1;
        }
        config_setting_set_hook(e, config_setting_get_hook(s));
        if (set_scalar(L, e, key, item) < 0)
            return -1;
    }
    return 0;
}

static int set_error(Loader *L, const char *key, const char *message)
{
    snprintf(L->err, L->err_size, "--set %s: %s", key, message);
    L->failed = 1;
    return -1;
}

/* Finds a child by name (groups), by index (lists, arrays) or by its `name` member (lists of
 * groups, e.g. stages.collapse). */
static config_setting_t *child(config_setting_t *s, const char *part)
{
    long long index;
    if (config_setting_type(s) == CONFIG_TYPE_GROUP)
        return config_setting_get_member(s, part);
    if (config_setting_type(s) != CONFIG_TYPE_LIST && config_setting_type(s) != CONFIG_TYPE_ARRAY)
        return NULL;
    if (parse_long(part, &index))
        return index >= 0 && index < config_setting_length(s)
                   ? config_setting_get_elem(s, (unsigned)index)
                   : NULL;
    for (int k = 0; k < config_setting_length(s); ++k) {
        config_setting_t *e = config_setting_get_elem(s, (unsigned)k);
        const char *name;
        if (config_setting_type(e) == CONFIG_TYPE_GROUP &&
            config_setting_lookup_string(e, "name", &name) && strcmp(name, part) == 0)
            return e;
    }
    return NULL;
}

static int apply_set(Loader *L, const char *assignment)
{
    const char *eq = strchr(assignment, '=');
    size_t key_length = eq ? (size_t)(eq - assignment) : strlen(assignment);
    if (L->set_count == (int)(sizeof L->set_keys / sizeof L->set_keys[0]))
        return set_error(L, assignment, "too many --set options");
    char *key = malloc(key_length + 1);
    char *path = malloc(key_length + 1);
    char *value = strdup(eq ? eq + 1 : "");
    if (!key || !path || !value) {
        free(key);
        free(path);
        free(value);
        return set_error(L, assignment, "out of memory");
    }
    memcpy(key, assignment, key_length);
    key[key_length] = '\0';
    L->set_keys[L->set_count++] = key;
    /* species[0].k_n is accepted as species.0.k_n */
    size_t n = 0;
    for (size_t k = 0; k < key_length; ++k) {
        if (key[k] == ']')
            continue;
        path[n++] = key[k] == '[' ? '.' : key[k];
    }
    path[n] = '\0';
    int rc = 0;
    if (!eq || key_length == 0)
        rc = set_error(L, assignment, "expected KEY=VALUE");
    config_setting_t *s = config_root_setting(&L->config);
    char *save = NULL;
    char *part = rc ? NULL : strtok_r(path, ".", &save);
    if (!rc && !part)
        rc = set_error(L, key, "empty key");
    while (!rc && part) {
        char *next = strtok_r(NULL, ".", &save);
        config_setting_t *c = child(s, part);
        if (!c) {
            /* A missing key may be added inside an existing group; its type follows the value,
             * and the scene checks reject it later if it is not a key the group accepts. */
            if (config_setting_type(s) != CONFIG_TYPE_GROUP) {
                rc = set_error(L, key, "no such element");
                break;
            }
            int type = next ? CONFIG_TYPE_GROUP : infer_type(value);
            if (!next && value[0] == '[')
                type = CONFIG_TYPE_ARRAY;
            c = config_setting_add(s, part, type);
            if (!c) {
                rc = set_error(L, key, "not a valid key name");
                break;
            }
            config_setting_set_hook(c, key);
        }
        s = c;
        part = next;
    }
    if (!rc) {
        config_setting_set_hook(s, key);
        if (config_setting_type(s) == CONFIG_TYPE_ARRAY ||
            config_setting_type(s) == CONFIG_TYPE_LIST)
            rc = value[0] == '[' && config_setting_type(s) == CONFIG_TYPE_ARRAY
                     ? set_array(L, s, key, value)
                     : set_error(L, key, "is a list; set one of its elements (KEY.0=...)");
        else if (config_setting_type(s) == CONFIG_TYPE_GROUP)
            rc = set_error(L, key, "is a group; set one of its keys");
        else if (config_setting_type(s) == CONFIG_TYPE_INT &&
                 infer_type(value) == CONFIG_TYPE_FLOAT && config_setting_parent(s) &&
                 config_setting_type(config_setting_parent(s)) == CONFIG_TYPE_GROUP) {
            /* A number written as an integer in the file may take a fractional value; the
             * scene checks still refuse it where an integer is required (seed). */
            config_setting_t *parent = config_setting_parent(s);
            char name[128];
            snprintf(name, sizeof name, "%s", config_setting_name(s));
            config_setting_remove(parent, name);
            s = config_setting_add(parent, name, CONFIG_TYPE_FLOAT);
            config_setting_set_hook(s, key);
            rc = set_scalar(L, s, key, value);
        } else
            rc = set_scalar(L, s, key, value);
    }
    free(path);
    free(value);
    return rc;
}

/* ---------------------------------------------------------------- species, motions */

static const char *const SPECIES_KEYS[] = {
    "name", "density", "k_n", "gamma_n", "restitution", "critical_fraction",
    "mu",   "gamma_s", "k_t", "mu_r",    "k_r",         NULL};

static int parse_species(Loader *L, const config_setting_t *root)
{
    Scene *scene = L->scene;
    SimWorldDef *def = &scene->def;
    const config_setting_t *list;
    if (need(L, root, "species", "the scene") < 0 || list_of(L, root, "species", &list) < 0)
        return -1;
    int count = config_setting_length(list);
    if (count < 1 || count > SIM_MAX_SPECIES)
        return fail(L, list, "`species` must list 1 to %d species (got %d)", SIM_MAX_SPECIES,
                    count);
    def->species_count = count;
    where_add(L, "species_count", list);
    for (int k = 0; k < count; ++k) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
        SimMaterial *m = &def->materials[k];
        char what[48], field[64];
        snprintf(what, sizeof what, "species %d", k);
        *m = sim_material_default();
        const char *name = NULL;
        if (check_keys(L, g, what, SPECIES_KEYS, NULL) < 0 || get_string(L, g, "name", &name) < 0)
            return -1;
        snprintf(scene->species_names[k], SCENE_NAME_MAX, "%s", name ? name : "");
        for (int j = 0; j < k; ++j)
            if (name && strcmp(scene->species_names[j], name) == 0)
                return fail(L, member(g, "name"), "species name `%s` is used twice", name);
        snprintf(field, sizeof field, "materials[%d]", k);
        where_add(L, field, g);
        /* SimMaterial field -> scene key, for mapping SimError fields back to lines */
        static const char *const map[][2] = {
            {"density", "density"},
            {"normal_stiffness", "k_n"},
            {"normal_damping", "gamma_n"},
            {"restitution", "restitution"},
            {"critical_fraction", "critical_fraction"},
            {"friction", "mu"},
            {"tangential_damping", "gamma_s"},
            {"tangential_stiffness", "k_t"},
            {"rolling_friction", "mu_r"},
            {"rolling_stiffness", "k_r"},
        };
        for (size_t j = 0; j < sizeof map / sizeof map[0]; ++j)
            if (member(g, map[j][1])) {
                snprintf(field, sizeof field, "materials[%d].%s", k, map[j][0]);
                where_add(L, field, member(g, map[j][1]));
            }
        if (need_number(L, g, "density", what, &m->density) < 0 ||
            check_positive(L, g, "density", m->density) < 0 ||
            need_number(L, g, "k_n", what, &m->normal_stiffness) < 0 ||
            check_positive(L, g, "k_n", m->normal_stiffness) < 0)
            return -1;
        /* Normal damping: one of three ways (000 eq. 3.25 for restitution), default elastic. */
        int ways = (member(g, "gamma_n") != NULL) + (member(g, "restitution") != NULL) +
                   (member(g, "critical_fraction") != NULL);
        if (ways > 1)
            return fail(L, g, "%s: give only one of gamma_n, restitution, critical_fraction", what);
        m->damping_mode = SIM_DAMPING_GAMMA;
        m->normal_damping = 0.0;
        if (member(g, "gamma_n")) {
            if (get_number(L, g, "gamma_n", &m->normal_damping) < 0 ||
                check_non_negative(L, g, "gamma_n", m->normal_damping) < 0)
                return -1;
        } else if (member(g, "restitution")) {
            m->damping_mode = SIM_DAMPING_RESTITUTION;
            if (get_number(L, g, "restitution", &m->restitution) < 0)
                return -1;
            if (!(m->restitution > 0.0 && m->restitution <= 1.0))
                return fail(L, member(g, "restitution"), "`restitution` must be in (0, 1] (got %g)",
                            m->restitution);
        } else if (member(g, "critical_fraction")) {
            m->damping_mode = SIM_DAMPING_CRITICAL;
            if (get_number(L, g, "critical_fraction", &m->critical_fraction) < 0 ||
                check_non_negative(L, g, "critical_fraction", m->critical_fraction) < 0)
                return -1;
        }
        static const char *const friction_keys[] = {"mu", "gamma_s", "k_t"};
        static const char *const rolling_keys[] = {"mu_r", "k_r"};
        for (int j = 0; j < 3; ++j)
            if (gate(L, g, friction_keys[j], SIM_EFFECT_FRICTION) < 0)
                return -1;
        for (int j = 0; j < 2; ++j)
            if (gate(L, g, rolling_keys[j], SIM_EFFECT_ROLLING) < 0)
                return -1;
        if (L->effects & SIM_EFFECT_FRICTION) {
            SimTangentialLaw law = def->contact.tangential;
            if (need_number(L, g, "mu", what, &m->friction) < 0 ||
                check_non_negative(L, g, "mu", m->friction) < 0)
                return -1;
            if (law == SIM_TANGENTIAL_REGULARISED &&
                (need_number(L, g, "gamma_s", what, &m->tangential_damping) < 0 ||
                 check_positive(L, g, "gamma_s", m->tangential_damping) < 0))
                return -1;
            if (law == SIM_TANGENTIAL_SPRING &&
                (need_number(L, g, "k_t", what, &m->tangential_stiffness) < 0 ||
                 check_positive(L, g, "k_t", m->tangential_stiffness) < 0))
                return -1;
            if (law != SIM_TANGENTIAL_REGULARISED && member(g, "gamma_s"))
                return fail(L, member(g, "gamma_s"),
                            "`gamma_s` is used only by contact.tangential = \"regularised\"");
            if (law != SIM_TANGENTIAL_SPRING && member(g, "k_t"))
                return fail(L, member(g, "k_t"),
                            "`k_t` is used only by contact.tangential = \"spring\"");
        }
        if (L->effects & SIM_EFFECT_ROLLING) {
            if (need_number(L, g, "mu_r", what, &m->rolling_friction) < 0 ||
                check_non_negative(L, g, "mu_r", m->rolling_friction) < 0)
                return -1;
            if (def->contact.rolling == SIM_ROLLING_FIXED &&
                (need_number(L, g, "k_r", what, &m->rolling_stiffness) < 0 ||
                 check_positive(L, g, "k_r", m->rolling_stiffness) < 0))
                return -1;
            if (def->contact.rolling != SIM_ROLLING_FIXED && member(g, "k_r"))
                return fail(L, member(g, "k_r"),
                            "`k_r` is used only by contact.rolling = \"fixed\"");
        }
    }
    return 0;
}

/* `species = 1` or `species = "acrylic"`; default 0. */
static int get_species(Loader *L, const config_setting_t *g, int *out)
{
    const config_setting_t *s = member(g, "species");
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
        return fail(L, s, "no species named `%s`", name);
    }
    long long index;
    if (get_int(L, g, "species", &index) < 0)
        return -1;
    if (index < 0 || index >= L->scene->def.species_count)
        return fail(L, s, "`species` = %lld is out of range (the scene has %d species)", index,
                    L->scene->def.species_count);
    *out = (int)index;
    return 1;
}

/* `motion = "shaker"`: needs vibration; default -1 (still). */
static int get_motion(Loader *L, const config_setting_t *g, int *out)
{
    const char *name = NULL;
    *out = -1;
    if (gate(L, g, "motion", SIM_EFFECT_VIBRATION) < 0)
        return -1;
    int found = get_string(L, g, "motion", &name);
    if (found <= 0)
        return found;
    for (int k = 0; k < L->scene->def.motion_count; ++k)
        if (strcmp(L->scene->motion_names[k], name) == 0) {
            *out = k;
            return 1;
        }
    return fail(L, member(g, "motion"), "no motion named `%s` in `motions`", name);
}

static int parse_motions(Loader *L, const config_setting_t *root)
{
    static const char *const keys[] = {"amplitude", "frequency", "phase", "direction", NULL};
    const config_setting_t *group;
    if (gate(L, root, "motions", SIM_EFFECT_VIBRATION) < 0 ||
        group_of(L, root, "motions", &group) <= 0)
        return L->failed ? -1 : 0;
    int count = config_setting_length(group);
    if (count > SIM_MAX_MOTIONS)
        return fail(L, group, "at most %d motions", SIM_MAX_MOTIONS);
    where_add(L, "motions", group);
    for (int k = 0; k < count; ++k) {
        const config_setting_t *g = config_setting_get_elem(group, (unsigned)k);
        const char *name = config_setting_name(g);
        char what[96], field[64];
        snprintf(what, sizeof what, "motion `%s`", name);
        if (config_setting_type(g) != CONFIG_TYPE_GROUP)
            return fail(L, g, "%s must be a group { amplitude; frequency; ... }", what);
        SimMotion *m = &L->scene->def.motions[k];
        double direction[2] = {0.0, 1.0};
        m->phase = 0.0;
        if (check_keys(L, g, what, keys, NULL) < 0 ||
            need_number(L, g, "amplitude", what, &m->amplitude) < 0 ||
            check_non_negative(L, g, "amplitude", m->amplitude) < 0 ||
            need_number(L, g, "frequency", what, &m->frequency) < 0 ||
            check_positive(L, g, "frequency", m->frequency) < 0 ||
            get_number(L, g, "phase", &m->phase) < 0 ||
            get_vector(L, g, "direction", direction, 2) < 0)
            return -1;
        double norm = hypot(direction[0], direction[1]);
        if (!(norm > 0.0))
            return fail(L, member(g, "direction"), "`direction` must not be zero");
        m->direction_x = direction[0] / norm;
        m->direction_y = direction[1] / norm;
        snprintf(L->scene->motion_names[k], SCENE_NAME_MAX, "%s", name);
        snprintf(field, sizeof field, "motions[%d]", k);
        where_add(L, field, g);
        L->scene->def.motion_count = k + 1;
    }
    return 0;
}

/* ---------------------------------------------------------------- grains and walls */

static int parse_rain(Loader *L, const config_setting_t *grains)
{
    static const char *const keys[] = {"x0",           "x1",
                                       "y0",           "y1",
                                       "radius_mean",  "polydispersity",
                                       "pitch_radius", "column_gap",
                                       "row_gap",      "column_jitter",
                                       "row_jitter",   "max_count",
                                       "species",      NULL};
    const config_setting_t *g;
    if (group_of(L, grains, "rain", &g) <= 0)
        return L->failed ? -1 : 0;
    const char *what = "grains.rain";
    SimRainDef rain;
    memset(&rain, 0, sizeof rain);
    long long max_count = 0;
    rain.column_jitter = 0.05; /* 000 §4.2 */
    rain.row_jitter = 0.08;
    if (check_keys(L, g, what, keys, NULL) < 0 || need_number(L, g, "x0", what, &rain.x0) < 0 ||
        need_number(L, g, "x1", what, &rain.x1) < 0 ||
        need_number(L, g, "y0", what, &rain.y0) < 0 ||
        need_number(L, g, "y1", what, &rain.y1) < 0 ||
        need_number(L, g, "radius_mean", what, &rain.radius_mean) < 0 ||
        check_positive(L, g, "radius_mean", rain.radius_mean) < 0 ||
        get_number(L, g, "polydispersity", &rain.polydispersity) < 0 ||
        get_int(L, g, "max_count", &max_count) < 0 || get_species(L, g, &rain.species) < 0)
        return -1;
    if (!(rain.polydispersity >= 0.0 && rain.polydispersity < 1.0))
        return fail(L, member(g, "polydispersity"), "`polydispersity` must be in [0, 1)");
    /* 000 §4.2: pitch from r_max, gaps 0.005 r_max and 0.75 r_max */
    rain.pitch_radius = rain.radius_mean * (1.0 + rain.polydispersity);
    if (get_number(L, g, "pitch_radius", &rain.pitch_radius) < 0 ||
        check_positive(L, g, "pitch_radius", rain.pitch_radius) < 0)
        return -1;
    rain.column_gap = 0.005 * rain.pitch_radius;
    rain.row_gap = 0.75 * rain.pitch_radius;
    if (get_number(L, g, "column_gap", &rain.column_gap) < 0 ||
        check_non_negative(L, g, "column_gap", rain.column_gap) < 0 ||
        get_number(L, g, "row_gap", &rain.row_gap) < 0 ||
        check_non_negative(L, g, "row_gap", rain.row_gap) < 0 ||
        get_number(L, g, "column_jitter", &rain.column_jitter) < 0 ||
        check_non_negative(L, g, "column_jitter", rain.column_jitter) < 0 ||
        get_number(L, g, "row_jitter", &rain.row_jitter) < 0 ||
        check_non_negative(L, g, "row_jitter", rain.row_jitter) < 0)
        return -1;
    if (rain.pitch_radius < rain.radius_mean * (1.0 + rain.polydispersity) * (1.0 - 1e-12))
        return fail(L, member(g, "pitch_radius"),
                    "`pitch_radius` must be at least the largest radius r_mean (1 + "
                    "polydispersity) = %g m",
                    rain.radius_mean * (1.0 + rain.polydispersity));
    if (max_count < 0 || max_count > 10000000)
        return fail(L, member(g, "max_count"), "`max_count` must be in [0, 1e7]");
    rain.max_count = (int)max_count;
    if (!(rain.x1 - rain.x0 >= 2.0 * rain.pitch_radius) ||
        !(rain.y1 - rain.y0 >= 2.0 * rain.pitch_radius))
        return fail(L, g,
                    "grains.rain: the region [x0, x1] x [y0, y1] must hold at least one "
                    "grain (2 pitch_radius = %g m)",
                    2.0 * rain.pitch_radius);
    /* Refuse regions that would need absurd memory before building. */
    double cells =
        (rain.x1 - rain.x0) * (rain.y1 - rain.y0) / (4.0 * rain.pitch_radius * rain.pitch_radius);
    if (cells > 1e7 && rain.max_count == 0)
        return fail(L, g, "grains.rain: the region holds about %.3g grains; set max_count", cells);
    SimRng rng;
    sim_rng_seed(&rng, L->scene->seed);
    int first = L->scene->grains.count;
    int added = sim_build_rain(&L->scene->grains, &rain, &rng);
    if (added <= 0)
        return fail(L, g, "grains.rain produced no grains");
    where_grains(L, first, g, "grains.rain");
    return 0;
}

static int parse_box(Loader *L, const config_setting_t *grains)
{
    static const char *const keys[] = {"x0", "x1", "y0", "y1", "radius", "species", "motion", NULL};
    const config_setting_t *g;
    if (group_of(L, grains, "box", &g) <= 0)
        return L->failed ? -1 : 0;
    const char *what = "grains.box";
    double x0 = 0.0, x1 = 0.0, y0 = 0.0, y1 = 0.0, r = 0.0;
    int species = 0, motion = -1;
    if (check_keys(L, g, what, keys, NULL) < 0 || need_number(L, g, "x0", what, &x0) < 0 ||
        need_number(L, g, "x1", what, &x1) < 0 || need_number(L, g, "y0", what, &y0) < 0 ||
        need_number(L, g, "y1", what, &y1) < 0 || need_number(L, g, "radius", what, &r) < 0 ||
        check_positive(L, g, "radius", r) < 0 || get_species(L, g, &species) < 0 ||
        get_motion(L, g, &motion) < 0)
        return -1;
    if (!(x1 - x0 >= 4.0 * r) || !(y1 - y0 >= 2.0 * r))
        return fail(L, g, "grains.box: needs x1 - x0 >= 4 radius and y1 - y0 >= 2 radius");
    L->box_height = y1 - y0;
    int first = L->scene->grains.count;
    /* floor row of centres at y0 from x0 to x1, side columns at x0 and x1 above it (000 §1.6) */
    sim_build_fixed_row(&L->scene->grains, x0, x1, y0, r, species, motion);
    sim_build_fixed_column(&L->scene->grains, x0, y0 + 2.0 * r, y1, r, species, motion);
    sim_build_fixed_column(&L->scene->grains, x1, y0 + 2.0 * r, y1, r, species, motion);
    where_grains(L, first, g, "grains.box");
    return 0;
}

static int parse_rows(Loader *L, const config_setting_t *grains, int columns)
{
    static const char *const row_keys[] = {"x0", "x1", "y", "radius", "species", "motion", NULL};
    static const char *const column_keys[] = {"x", "y0", "y1", "radius", "species", "motion", NULL};
    const char *key = columns ? "columns" : "rows";
    const config_setting_t *list;
    if (list_of(L, grains, key, &list) <= 0)
        return L->failed ? -1 : 0;
    for (int k = 0; k < config_setting_length(list); ++k) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
        char what[48];
        snprintf(what, sizeof what, "grains.%s.%d", key, k);
        double a = 0.0, b = 0.0, c = 0.0, r = 0.0;
        int species = 0, motion = -1;
        if (check_keys(L, g, what, columns ? column_keys : row_keys, NULL) < 0 ||
            need_number(L, g, columns ? "x" : "x0", what, &a) < 0 ||
            need_number(L, g, columns ? "y0" : "x1", what, &b) < 0 ||
            need_number(L, g, columns ? "y1" : "y", what, &c) < 0 ||
            need_number(L, g, "radius", what, &r) < 0 || check_positive(L, g, "radius", r) < 0 ||
            get_species(L, g, &species) < 0 || get_motion(L, g, &motion) < 0)
            return -1;
        int first = L->scene->grains.count;
        if (columns) {
            if (!(c >= b))
                return fail(L, g, "%s: needs y1 >= y0", what);
            sim_build_fixed_column(&L->scene->grains, a, b, c, r, species, motion);
        } else {
            if (!(b >= a))
                return fail(L, g, "%s: needs x1 >= x0", what);
            sim_build_fixed_row(&L->scene->grains, a, b, c, r, species, motion);
        }
        where_grains(L, first, g, what);
    }
    return 0;
}

static int parse_list(Loader *L, const config_setting_t *grains)
{
    static const char *const keys[] = {"x",  "y",     "r",     "species", "fixed", "vx",
                                       "vy", "omega", "angle", "motion",  NULL};
    const config_setting_t *list;
    if (list_of(L, grains, "list", &list) <= 0)
        return L->failed ? -1 : 0;
    for (int k = 0; k < config_setting_length(list); ++k) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
        char what[48];
        snprintf(what, sizeof what, "grains.list.%d", k);
        double x = 0.0, y = 0.0, r = 0.0, vx = 0.0, vy = 0.0, omega = 0.0, angle = 0.0;
        int species = 0, fixed = 0, motion = -1;
        if (check_keys(L, g, what, keys, NULL) < 0 || need_number(L, g, "x", what, &x) < 0 ||
            need_number(L, g, "y", what, &y) < 0 || need_number(L, g, "r", what, &r) < 0 ||
            get_species(L, g, &species) < 0 || get_bool(L, g, "fixed", &fixed) < 0 ||
            get_number(L, g, "vx", &vx) < 0 || get_number(L, g, "vy", &vy) < 0 ||
            get_number(L, g, "omega", &omega) < 0 || get_number(L, g, "angle", &angle) < 0 ||
            get_motion(L, g, &motion) < 0)
            return -1;
        if (!(r > 0.0))
            return fail(L, member(g, "r"), "`r` must be > 0 (got %g)", r);
        if (motion >= 0 && !fixed)
            return fail(L, member(g, "motion"), "`motion` applies to fixed grains only");
        int first = L->scene->grains.count;
        int i = sim_grain_buffer_add(&L->scene->grains, x, y, r, species,
                                     fixed ? SIM_GRAIN_FIXED : 0u, motion);
        L->scene->grains.vx[i] = vx;
        L->scene->grains.vy[i] = vy;
        L->scene->grains.omega[i] = omega;
        L->scene->grains.angle[i] = angle;
        where_grains(L, first, g, what);
    }
    return 0;
}

static int parse_grains(Loader *L, const config_setting_t *root)
{
    static const char *const keys[] = {"list", "rain", "box", "rows", "columns", NULL};
    const config_setting_t *grains;
    if (need(L, root, "grains", "the scene") < 0 || group_of(L, root, "grains", &grains) < 0 ||
        check_keys(L, grains, "grains", keys, NULL) < 0)
        return -1;
    /* Stable ids follow this order: list, rain, box, rows, columns. */
    if (parse_list(L, grains) < 0 || parse_rain(L, grains) < 0 || parse_box(L, grains) < 0 ||
        parse_rows(L, grains, 0) < 0 || parse_rows(L, grains, 1) < 0)
        return -1;
    Scene *scene = L->scene;
    scene->fixed_count = 0;
    for (int i = 0; i < scene->grains.count; ++i)
        scene->fixed_count += (scene->grains.flags[i] & SIM_GRAIN_FIXED) != 0;
    /* a `discharge` scene rains its grains during the run (app/discharge.c) */
    if (scene->grains.count == scene->fixed_count && !member(root, "discharge"))
        return fail(L, grains, "the scene has no mobile grains");
    return 0;
}

static int parse_walls(Loader *L, const config_setting_t *root)
{
    static const char *const keys[] = {"from", "to", "species", "motion", NULL};
    const config_setting_t *list;
    if (list_of(L, root, "walls", &list) <= 0)
        return L->failed ? -1 : 0;
    int count = config_setting_length(list);
    L->scene->walls = calloc((size_t)(count > 0 ? count : 1), sizeof *L->scene->walls);
    if (!L->scene->walls)
        return fail(L, list, "out of memory");
    for (int k = 0; k < count; ++k) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
        char what[32], field[32];
        snprintf(what, sizeof what, "walls.%d", k);
        double from[2] = {0.0, 0.0}, to[2] = {0.0, 0.0};
        SimWall *w = &L->scene->walls[k];
        if (check_keys(L, g, what, keys, NULL) < 0 || need(L, g, "from", what) < 0 ||
            get_vector(L, g, "from", from, 2) < 0 || need(L, g, "to", what) < 0 ||
            get_vector(L, g, "to", to, 2) < 0 || get_species(L, g, &w->species) < 0 ||
            get_motion(L, g, &w->motion) < 0)
            return -1;
        if (!(hypot(to[0] - from[0], to[1] - from[1]) > 0.0))
            return fail(L, g, "%s: `from` and `to` must differ", what);
        w->x0 = from[0];
        w->y0 = from[1];
        w->x1 = to[0];
        w->y1 = to[1];
        snprintf(field, sizeof field, "walls[%d]", k);
        where_add(L, field, g);
    }
    L->scene->def.wall_count = count;
    L->scene->def.walls = L->scene->walls;
    return 0;
}

static int parse_sinks(Loader *L, const config_setting_t *root)
{
    static const char *const keys[] = {"below", "above", "left", "right", "rect", NULL};
    const config_setting_t *list;
    if (gate(L, root, "sinks", SIM_EFFECT_REMOVAL) < 0 || list_of(L, root, "sinks", &list) <= 0)
        return L->failed ? -1 : 0;
    int count = config_setting_length(list);
    if (count > SIM_MAX_SINKS)
        return fail(L, list, "at most %d sinks", SIM_MAX_SINKS);
    where_add(L, "sinks", list);
    for (int k = 0; k < count; ++k) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
        char what[32], field[32];
        snprintf(what, sizeof what, "sinks.%d", k);
        if (check_keys(L, g, what, keys, NULL) < 0)
            return -1;
        if (config_setting_length(g) != 1)
            return fail(L, g, "%s: give exactly one of below, above, left, right, rect", what);
        SimSink *sink = &L->scene->def.sinks[k];
        const char *key = config_setting_name(config_setting_get_elem(g, 0));
        if (strcmp(key, "rect") == 0) {
            double r[4] = {0.0, 0.0, 0.0, 0.0};
            sink->shape = SIM_SINK_RECT;
            if (get_vector(L, g, "rect", r, 4) < 0)
                return -1;
            if (!(r[2] > r[0] && r[3] > r[1]))
                return fail(L, member(g, "rect"),
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
            if (get_number(L, g, key, &sink->level) < 0)
                return -1;
        }
        snprintf(field, sizeof field, "sinks[%d]", k);
        where_add(L, field, g);
        L->scene->def.sink_count = k + 1;
    }
    return 0;
}

static void drag_apply(void *context, const SimBodyForceView *view)
{
    const SceneDrag *drag = context;
    for (int i = 0; i < view->count; ++i) {
        /* Stokes drag on a sphere of diameter d: 3 pi eta d (v - u) */
        double c = drag->model == SCENE_DRAG_LINEAR
                       ? drag->coefficient
                       : 3.0 * PI * drag->viscosity * 2.0 * view->radius[i];
        view->fx[i] -= c * (view->vx[i] - drag->fluid_vx);
        view->fy[i] -= c * (view->vy[i] - drag->fluid_vy);
    }
}

static int parse_effect_groups(Loader *L, const config_setting_t *root)
{
    Scene *scene = L->scene;
    const config_setting_t *g;
    if (gate(L, root, "periodic", SIM_EFFECT_PERIODIC_X) < 0 ||
        gate(L, root, "drag", SIM_EFFECT_FLUID_DRAG) < 0 ||
        gate(L, root, "fluid", SIM_EFFECT_FLUID_DRAG) < 0)
        return -1;
    if ((L->effects & SIM_EFFECT_PERIODIC_X) && !member(root, "periodic"))
        return fail(L, L->effects_setting,
                    "effect periodic_x needs a group `periodic = { x0 = ...; x1 = ...; }`");
    if ((L->effects & SIM_EFFECT_FLUID_DRAG) && !member(root, "drag") && !member(root, "fluid"))
        return fail(L, L->effects_setting,
                    "effect fluid_drag needs a group `drag = { model = ...; ... }` or a fluid "
                    "column `fluid = { ... }`");
    if (member(root, "drag") && member(root, "fluid"))
        return fail(L, member(root, "fluid"), "`fluid` and `drag` both drag the grains: keep one");
    static const char *const periodic_keys[] = {"x0", "x1", NULL};
    if (group_of(L, root, "periodic", &g) < 0)
        return -1;
    if (g) {
        if (check_keys(L, g, "periodic", periodic_keys, NULL) < 0 ||
            need_number(L, g, "x0", "periodic", &scene->def.domain_x0) < 0 ||
            need_number(L, g, "x1", "periodic", &scene->def.domain_x1) < 0)
            return -1;
        if (!(scene->def.domain_x1 > scene->def.domain_x0))
            return fail(L, member(g, "x1"), "`periodic.x1` must be > `periodic.x0`");
        where_add(L, "domain", g);
        where_add(L, "domain_x0", member(g, "x0"));
        where_add(L, "domain_x1", member(g, "x1"));
    }
    static const char *const drag_keys[] = {"model", "coefficient", "viscosity", "fluid_velocity",
                                            NULL};
    static const char *const drag_models[] = {"linear", "stokes", NULL};
    if (group_of(L, root, "drag", &g) < 0)
        return -1;
    if (g) {
        SceneDrag *d = &scene->drag;
        int model = 0;
        double u[2] = {0.0, 0.0};
        if (check_keys(L, g, "drag", drag_keys, NULL) < 0 ||
            get_choice(L, g, "model", drag_models, &model) < 0 ||
            get_vector(L, g, "fluid_velocity", u, 2) < 0)
            return -1;
        d->model = (SceneDragModel)model;
        d->fluid_vx = u[0];
        d->fluid_vy = u[1];
        const char *key = d->model == SCENE_DRAG_LINEAR ? "coefficient" : "viscosity";
        const char *other = d->model == SCENE_DRAG_LINEAR ? "viscosity" : "coefficient";
        double value = 0.0;
        if (member(g, other))
            return fail(L, member(g, other), "`%s` is not used by drag model `%s`", other,
                        drag_models[model]);
        if (need_number(L, g, key, "drag", &value) < 0 || check_non_negative(L, g, key, value) < 0)
            return -1;
        if (d->model == SCENE_DRAG_LINEAR)
            d->coefficient = value;
        else
            d->viscosity = value;
        scene->def.body_force.apply = drag_apply;
        scene->def.body_force.context = d;
        where_add(L, "body_force", g);
    }
    return 0;
}

/* ---------------------------------------------------------------- top level physics */

static const char *const ROOT_KEYS[] = {
    "name",     "seed",  "units",   "effects", "mass_model", "gravity", "integrator", "time",
    "skin",     "guard", "contact", "species", "grains",     "walls",   "motions",    "sinks",
    "periodic", "drag",  "stages",  "output",  "render",     NULL};

/* The keys the registered experiment families own (app/experiments.c): their top-level groups
 * (which = 0), stage keys (1) or output keys (2). NULL-ended in a static buffer per kind. */
static const char *const *family_keys(int which)
{
    static const char *keys[3][4 * APP_EXPERIMENT_MAX + 1];
    int n = 0;
    for (int f = 0; app_experiments[f]; ++f) {
        const AppExperiment *e = app_experiments[f];
        const char *const *list = which == 1 ? e->stage_keys : which == 2 ? e->output_keys : NULL;
        if (which == 0 && e->group && n < 4 * APP_EXPERIMENT_MAX)
            keys[0][n++] = e->group;
        for (int k = 0; list && list[k] && n < 4 * APP_EXPERIMENT_MAX; ++k)
            keys[which][n++] = list[k];
    }
    keys[which][n] = NULL;
    return keys[which];
}

static int parse_effects(Loader *L, const config_setting_t *root)
{
    config_setting_t *s = member(root, "effects");
    L->effects = 0;
    L->effects_setting = s;
    if (!s)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_ARRAY && config_setting_type(s) != CONFIG_TYPE_LIST)
        return fail(L, s, "`effects` must be an array of names, e.g. [\"friction\"]");
    for (int k = 0; k < config_setting_length(s); ++k) {
        const config_setting_t *e = config_setting_get_elem(s, (unsigned)k);
        if (config_setting_type(e) != CONFIG_TYPE_STRING)
            return fail(L, e, "`effects` must list strings, not %s", type_name(e));
        unsigned bit = sim_effect_from_name(config_setting_get_string(e));
        if (!bit)
            return fail(L, e,
                        "unknown effect `%s` (expected: friction, rolling_resistance, "
                        "periodic_x, vibration, fluid_drag, removal)",
                        config_setting_get_string(e));
        L->effects |= bit;
    }
    where_add(L, "effects", s);
    return 0;
}

static int parse_physics(Loader *L, const config_setting_t *root)
{
    Scene *scene = L->scene;
    SimWorldDef *def = &scene->def;
    static const char *const mass_models[] = {"disk", "sphere", NULL};
    static const char *const normal_laws[] = {"linear", "hertz", NULL};
    static const char *const tangential_laws[] = {"none", "regularised", "spring", NULL};
    static const char *const rolling_laws[] = {"off", "chord", "fixed", NULL};
    static const char *const units[] = {"SI", NULL};
    static const char *const time_keys[] = {"dt", "end", "steps_per_contact", "max_dt_fraction",
                                            NULL};
    static const char *const contact_keys[] = {"normal", "tangential", "rolling", "clip_tensile",
                                               NULL};
    static const char *const guard_keys[] = {"max_overlap", "max_speed", "every", NULL};
    int choice = 0;
    const char *name = NULL;
    long long seed = 0;
    if (check_keys(L, root, "the scene", ROOT_KEYS, family_keys(0)) < 0 ||
        parse_effects(L, root) < 0)
        return -1;
    def->effects = L->effects;
    if (get_string(L, root, "name", &name) < 0)
        return -1;
    if (name) {
        if (check_file_name(L, root, "name", name) < 0)
            return -1;
        snprintf(scene->name, sizeof scene->name, "%s", name);
    }
    if (need(L, root, "seed", "the scene") < 0 || get_int(L, root, "seed", &seed) < 0)
        return -1;
    if (seed < 0)
        return fail(L, member(root, "seed"), "`seed` must be >= 0");
    scene->seed = (uint64_t)seed;
    if (get_choice(L, root, "units", units, &choice) < 0)
        return -1;
    /* Mass convention is the thesis's biggest ambiguity (000 §1.5): no silent default. */
    if (need(L, root, "mass_model", "the scene") < 0 ||
        get_choice(L, root, "mass_model", mass_models, &choice) < 0)
        return -1;
    def->mass_model = choice == 1 ? SIM_MASS_SPHERE : SIM_MASS_DISK;
    where_add(L, "mass_model", member(root, "mass_model"));
    double gravity[2] = {def->gravity_x, def->gravity_y};
    if (get_vector(L, root, "gravity", gravity, 2) < 0)
        return -1;
    def->gravity_x = gravity[0];
    def->gravity_y = gravity[1];
    where_add(L, "gravity", member(root, "gravity"));
    where_add(L, "gravity_x", member(root, "gravity"));
    where_add(L, "gravity_y", member(root, "gravity"));
    const char *integrator = NULL;
    int found = get_string(L, root, "integrator", &integrator);
    if (found < 0)
        return -1;
    if (found) {
        int i = sim_integrator_from_name(integrator);
        if (i < 0)
            return fail(L, member(root, "integrator"),
                        "unknown integrator `%s` (expected one of: velocity_verlet, "
                        "symplectic_euler, stormer_verlet, gear, rk4)",
                        integrator);
        def->integrator = (SimIntegrator)i;
        where_add(L, "integrator", member(root, "integrator"));
    }
    /* time = { dt; end; steps_per_contact; max_dt_fraction; } */
    const config_setting_t *time;
    if (need(L, root, "time", "the scene") < 0 || group_of(L, root, "time", &time) < 0 ||
        check_keys(L, time, "time", time_keys, NULL) < 0 ||
        need_number(L, time, "dt", "time", &def->time_step) < 0 ||
        check_non_negative(L, time, "dt", def->time_step) < 0 || need(L, time, "end", "time") < 0 ||
        get_number(L, time, "steps_per_contact", &def->steps_per_contact) < 0 ||
        check_positive(L, time, "steps_per_contact", def->steps_per_contact) < 0 ||
        get_number(L, time, "max_dt_fraction", &def->max_dt_fraction) < 0 ||
        check_non_negative(L, time, "max_dt_fraction", def->max_dt_fraction) < 0)
        return -1;
    where_add(L, "steps_per_contact",
              member(time, "steps_per_contact") ? member(time, "steps_per_contact") : time);
    where_add(L, "max_dt_fraction",
              member(time, "max_dt_fraction") ? member(time, "max_dt_fraction") : time);
    if (get_number(L, root, "skin", &def->skin) < 0 ||
        check_non_negative(L, root, "skin", def->skin) < 0)
        return -1;
    where_add(L, "skin", member(root, "skin"));
    const config_setting_t *guard;
    long long every = def->guard_every;
    if (group_of(L, root, "guard", &guard) < 0 ||
        check_keys(L, guard, "guard", guard_keys, NULL) < 0 ||
        get_number(L, guard, "max_overlap", &def->guard_max_overlap) < 0 ||
        check_positive(L, guard, "max_overlap", def->guard_max_overlap) < 0 ||
        get_number(L, guard, "max_speed", &def->guard_max_speed) < 0 ||
        check_non_negative(L, guard, "max_speed", def->guard_max_speed) < 0 ||
        get_int(L, guard, "every", &every) < 0)
        return -1;
    if (member(guard, "every") && (every < 1 || every > 1000000000))
        return fail(L, member(guard, "every"), "`every` must be >= 1");
    def->guard_every = (int)every;
    if (guard) {
        where_add(L, "guard_max_overlap", member(guard, "max_overlap"));
        where_add(L, "guard_max_speed", member(guard, "max_speed"));
        where_add(L, "guard_every", member(guard, "every"));
    }
    /* contact = { normal; tangential; rolling; clip_tensile; } */
    const config_setting_t *contact;
    def->contact.tangential =
        (L->effects & SIM_EFFECT_FRICTION) ? SIM_TANGENTIAL_REGULARISED : SIM_TANGENTIAL_NONE;
    def->contact.rolling = (L->effects & SIM_EFFECT_ROLLING) ? SIM_ROLLING_CHORD : SIM_ROLLING_OFF;
    def->contact.clip_tensile = 1; /* 000 [GAP]: a normal force never pulls */
    if (group_of(L, root, "contact", &contact) < 0 ||
        check_keys(L, contact, "contact", contact_keys, NULL) < 0 ||
        gate(L, contact, "tangential", SIM_EFFECT_FRICTION) < 0 ||
        gate(L, contact, "rolling", SIM_EFFECT_ROLLING) < 0)
        return -1;
    choice = (int)def->contact.normal;
    if (get_choice(L, contact, "normal", normal_laws, &choice) < 0)
        return -1;
    def->contact.normal = (SimNormalLaw)choice;
    choice = (int)def->contact.tangential;
    if (get_choice(L, contact, "tangential", tangential_laws, &choice) < 0)
        return -1;
    def->contact.tangential = (SimTangentialLaw)choice;
    choice = (int)def->contact.rolling;
    if (get_choice(L, contact, "rolling", rolling_laws, &choice) < 0)
        return -1;
    def->contact.rolling = (SimRollingLaw)choice;
    if (get_bool(L, contact, "clip_tensile", &def->contact.clip_tensile) < 0)
        return -1;
    if (contact) {
        where_add(L, "contact", contact);
        where_add(L, "contact.normal", member(contact, "normal"));
        where_add(L, "contact.tangential", member(contact, "tangential"));
        where_add(L, "contact.rolling", member(contact, "rolling"));
    }
    return 0;
}

/* ---------------------------------------------------------------- stages */

static int parse_stage_time(Loader *L, const config_setting_t *time, SceneStage *stage)
{
    static const char *const keys[] = {"dt", "end", NULL};
    if (check_keys(L, time, "stage time", keys, NULL) < 0 ||
        get_number(L, time, "dt", &stage->time_step) < 0 ||
        check_non_negative(L, time, "dt", stage->time_step) < 0 ||
        get_number(L, time, "end", &stage->duration) < 0 ||
        check_non_negative(L, time, "end", stage->duration) < 0)
        return -1;
    return 0;
}

static int parse_stage(Loader *L, const config_setting_t *g, int k, const config_setting_t *time)
{
    static const char *const keys[] = {"name",       "load",  "time", "settle",
                                       "remove_ids", "movie", "skip", NULL};
    static const char *const settle_keys[] = {"kinetic_below", "after", NULL};
    Scene *scene = L->scene;
    SceneStage *stage = &scene->stages[k];
    char what[96];
    snprintf(what, sizeof what, "stage %d", k);
    const char *name = "run", *load = NULL;
    if (g && (check_keys(L, g, what, keys, family_keys(1)) < 0 || need(L, g, "name", what) < 0 ||
              get_string(L, g, "name", &name) < 0 || check_file_name(L, g, "name", name) < 0))
        return -1;
    snprintf(stage->name, sizeof stage->name, "%s", name);
    for (int j = 0; j < k; ++j)
        if (strcmp(scene->stages[j].name, name) == 0)
            return fail(L, member(g, "name"), "stage name `%s` is used twice", name);
    /* time: the stage's own `time` group on top of the scene's */
    stage->time_step = scene->def.time_step;
    stage->duration = 0.0;
    if (get_number(L, time, "end", &stage->duration) < 0 ||
        check_non_negative(L, time, "end", stage->duration) < 0)
        return -1;
    const config_setting_t *dt_setting = member(time, "dt");
    const config_setting_t *stage_time = NULL;
    if (group_of(L, g, "time", &stage_time) < 0)
        return -1;
    if (stage_time) {
        if (parse_stage_time(L, stage_time, stage) < 0)
            return -1;
        if (member(stage_time, "dt"))
            dt_setting = member(stage_time, "dt");
    }
    where_of(L, dt_setting, scene->where->stage_dt[k], WHERE_MAX);
    where_of(L, g ? g : time, scene->where->stage_load[k], WHERE_MAX);
    stage->load = k == 0 ? SCENE_LOAD_SCENE : SCENE_LOAD_PREVIOUS;
    if (get_string(L, g, "load", &load) < 0)
        return -1;
    if (load) {
        where_of(L, member(g, "load"), scene->where->stage_load[k], WHERE_MAX);
        if (strcmp(load, "previous") == 0) {
            if (k == 0)
                return fail(L, member(g, "load"), "the first stage has no previous stage");
            stage->load = SCENE_LOAD_PREVIOUS;
        } else if (strcmp(load, "none") == 0 || strcmp(load, "scene") == 0) {
            stage->load = SCENE_LOAD_SCENE;
        } else {
            stage->load = SCENE_LOAD_FILE;
            size_t dir_length = load[0] == '/' ? 0 : strlen(L->dir) + 1;
            if (dir_length + strlen(load) >= sizeof stage->load_path)
                return fail(L, member(g, "load"), "checkpoint path too long");
            if (dir_length) {
                memcpy(stage->load_path, L->dir, dir_length - 1);
                stage->load_path[dir_length - 1] = '/';
            }
            memcpy(stage->load_path + dir_length, load, strlen(load) + 1);
            FILE *f = fopen(stage->load_path, "rb");
            if (!f)
                return fail(L, member(g, "load"), "cannot read checkpoint `%s`: %s",
                            stage->load_path, strerror(errno));
            fclose(f);
        }
    }
    /* settle = { kinetic_below (J); after (s); }: 000 §4.1 stop when E_kin + E_rot < tol */
    const config_setting_t *settle;
    stage->settle_after = 0.2;
    if (group_of(L, g, "settle", &settle) < 0 ||
        check_keys(L, settle, "settle", settle_keys, NULL) < 0)
        return -1;
    if (settle && (need_number(L, settle, "kinetic_below", "settle", &stage->settle_kinetic) < 0 ||
                   check_positive(L, settle, "kinetic_below", stage->settle_kinetic) < 0 ||
                   get_number(L, settle, "after", &stage->settle_after) < 0 ||
                   check_non_negative(L, settle, "after", stage->settle_after) < 0))
        return -1;
    const config_setting_t *ids = member(g, "remove_ids");
    if (ids) {
        if (config_setting_type(ids) != CONFIG_TYPE_ARRAY)
            return fail(L, ids, "`remove_ids` must be an array of grain ids");
        int n = config_setting_length(ids);
        stage->remove_ids = calloc((size_t)(n > 0 ? n : 1), sizeof *stage->remove_ids);
        if (!stage->remove_ids)
            return fail(L, ids, "out of memory");
        for (int j = 0; j < n; ++j) {
            const config_setting_t *e = config_setting_get_elem(ids, (unsigned)j);
            if (config_setting_type(e) != CONFIG_TYPE_INT || config_setting_get_int(e) < 0)
                return fail(L, e, "`remove_ids` must list grain ids (integers >= 0)");
            stage->remove_ids[j] = (uint32_t)config_setting_get_int(e);
        }
        stage->remove_count = n;
    }
    stage->movie = -1; /* unset: output.movie decides */
    if (get_bool(L, g, "movie", &stage->movie) < 0 || get_bool(L, g, "skip", &stage->skip) < 0)
        return -1;
    return 0;
}

static int parse_stages(Loader *L, const config_setting_t *root)
{
    Scene *scene = L->scene;
    const config_setting_t *time = member(root, "time");
    const config_setting_t *list;
    if (list_of(L, root, "stages", &list) < 0)
        return -1;
    if (!list) {
        scene->stage_count = 1;
        return parse_stage(L, NULL, 0, time);
    }
    int count = config_setting_length(list);
    if (count < 1 || count > SCENE_MAX_STAGES)
        return fail(L, list, "`stages` must list 1 to %d stages", SCENE_MAX_STAGES);
    scene->stage_count = count;
    for (int k = 0; k < count; ++k)
        if (parse_stage(L, config_setting_get_elem(list, (unsigned)k), k, time) < 0)
            return -1;
    return 0;
}

/* ---------------------------------------------------------------- output and render */

static const char *const STYLE_KEYS[] = {"width",           "height",
                                         "color_by",        "colormap",
                                         "range",           "band_height",
                                         "outline",         "orientation_tick",
                                         "force_chains",    "chain_threshold",
                                         "chain_width_max", "velocity_arrows",
                                         "velocity_field",  "colorbar",
                                         "time_stamp",      "scale_bar",
                                         "background",      "fill",
                                         "fixed_color",     "view",
                                         "title",           NULL};

SceneStyle scene_style_unset(void)
{
    SceneStyle s;
    memset(&s, 0, sizeof s);
    s.width = s.height = s.color_by = s.colormap = -1;
    s.outline = s.orientation_tick = s.force_chains = -1;
    s.velocity_arrows = s.velocity_field = s.colorbar = s.time_stamp = s.scale_bar = -1;
    const double unset = (double)NAN;
    s.range_min = s.range_max = s.band_height = unset;
    s.chain_threshold = s.chain_width_max = unset;
    s.view_x0 = s.view_y0 = s.view_x1 = s.view_y1 = unset;
    s.background_rgb = s.fill_rgb = s.fixed_rgb = -1;
    return s;
}

static int get_color(Loader *L, const config_setting_t *g, const char *key, long *out)
{
    const char *text = NULL;
    int found = get_string(L, g, key, &text);
    if (found <= 0)
        return found;
    char *end = NULL;
    long v = text && text[0] == '#' && strlen(text) == 7 ? strtol(text + 1, &end, 16) : -1;
    if (v < 0 || !end || *end != '\0')
        return fail(L, member(g, key), "`%s` must be a colour \"#rrggbb\"", key);
    *out = v;
    return 1;
}

static int get_pixels(Loader *L, const config_setting_t *g, const char *key, int *out)
{
    long long v;
    int found = get_int(L, g, key, &v);
    if (found <= 0)
        return found;
    /* H.264 needs even sizes; figures accept any */
    if (v < 16 || v > 16384)
        return fail(L, member(g, key), "`%s` must be in [16, 16384] pixels", key);
    *out = (int)v;
    return 1;
}

static int parse_style(Loader *L, const config_setting_t *g, SceneStyle *s)
{
    static const char *const color_by[] = {"fixed", "force", "speed", "species", "height", NULL};
    static const char *const colormaps[] = {"viridis", "yellow_red", "greys", NULL};
    static const char *const flags[] = {"outline",         "orientation_tick", "force_chains",
                                        "velocity_arrows", "velocity_field",   "colorbar",
                                        "time_stamp",      "scale_bar"};
    int *flag_fields[] = {&s->outline,         &s->orientation_tick, &s->force_chains,
                          &s->velocity_arrows, &s->velocity_field,   &s->colorbar,
                          &s->time_stamp,      &s->scale_bar};
    double range[2] = {0.0, 0.0}, view[4] = {0.0, 0.0, 0.0, 0.0};
    const char *title = NULL;
    if (get_pixels(L, g, "width", &s->width) < 0 || get_pixels(L, g, "height", &s->height) < 0 ||
        get_choice(L, g, "color_by", color_by, &s->color_by) < 0 ||
        get_choice(L, g, "colormap", colormaps, &s->colormap) < 0)
        return -1;
    for (int k = 0; k < 8; ++k)
        if (get_bool(L, g, flags[k], flag_fields[k]) < 0)
            return -1;
    int found = get_vector(L, g, "range", range, 2);
    if (found < 0)
        return -1;
    if (found) {
        if (!(range[1] > range[0]))
            return fail(L, member(g, "range"), "`range` = [min, max] needs max > min");
        s->range_min = range[0];
        s->range_max = range[1];
    }
    found = get_vector(L, g, "view", view, 4);
    if (found < 0)
        return -1;
    if (found) {
        if (!(view[2] > view[0] && view[3] > view[1]))
            return fail(L, member(g, "view"), "`view` = [x0, y0, x1, y1] needs x1 > x0, y1 > y0");
        s->view_x0 = view[0];
        s->view_y0 = view[1];
        s->view_x1 = view[2];
        s->view_y1 = view[3];
    }
    if (get_number(L, g, "band_height", &s->band_height) < 0 ||
        (member(g, "band_height") && check_positive(L, g, "band_height", s->band_height) < 0) ||
        get_number(L, g, "chain_threshold", &s->chain_threshold) < 0 ||
        (member(g, "chain_threshold") &&
         check_non_negative(L, g, "chain_threshold", s->chain_threshold) < 0) ||
        get_number(L, g, "chain_width_max", &s->chain_width_max) < 0 ||
        (member(g, "chain_width_max") &&
         check_positive(L, g, "chain_width_max", s->chain_width_max) < 0) ||
        get_color(L, g, "background", &s->background_rgb) < 0 ||
        get_color(L, g, "fill", &s->fill_rgb) < 0 ||
        get_color(L, g, "fixed_color", &s->fixed_rgb) < 0)
        return -1;
    found = get_string(L, g, "title", &title);
    if (found < 0)
        return -1;
    if (found)
        snprintf(s->title, sizeof s->title, "%s", title);
    return 0;
}

/* Figure keys override the scene's render keys. */
static void style_merge(SceneStyle *out, const SceneStyle *over)
{
    int *ints[] = {&out->width,        &out->height,          &out->color_by,
                   &out->colormap,     &out->outline,         &out->orientation_tick,
                   &out->force_chains, &out->velocity_arrows, &out->velocity_field,
                   &out->colorbar,     &out->time_stamp,      &out->scale_bar};
    const int *over_ints[] = {&over->width,        &over->height,          &over->color_by,
                              &over->colormap,     &over->outline,         &over->orientation_tick,
                              &over->force_chains, &over->velocity_arrows, &over->velocity_field,
                              &over->colorbar,     &over->time_stamp,      &over->scale_bar};
    for (size_t k = 0; k < sizeof ints / sizeof ints[0]; ++k)
        if (*over_ints[k] >= 0)
            *ints[k] = *over_ints[k];
    double *doubles[] = {&out->range_min, &out->range_max, &out->band_height, &out->chain_threshold,
                         &out->chain_width_max};
    const double *over_doubles[] = {&over->range_min, &over->range_max, &over->band_height,
                                    &over->chain_threshold, &over->chain_width_max};
    for (size_t k = 0; k < sizeof doubles / sizeof doubles[0]; ++k)
        if (!isnan(*over_doubles[k]))
            *doubles[k] = *over_doubles[k];
    if (!isnan(over->view_x0)) {
        out->view_x0 = over->view_x0;
        out->view_y0 = over->view_y0;
        out->view_x1 = over->view_x1;
        out->view_y1 = over->view_y1;
    }
    if (over->background_rgb >= 0)
        out->background_rgb = over->background_rgb;
    if (over->fill_rgb >= 0)
        out->fill_rgb = over->fill_rgb;
    if (over->fixed_rgb >= 0)
        out->fixed_rgb = over->fixed_rgb;
    if (over->title[0])
        snprintf(out->title, sizeof out->title, "%s", over->title);
}

static int parse_figures(Loader *L, const config_setting_t *output)
{
    static const char *const keys[] = {"name", "stage", "at", "format", NULL};
    static const char *const at_names[] = {"start", "end", NULL};
    static const char *const formats[] = {"png", "pdf", "svg", NULL};
    Scene *scene = L->scene;
    const config_setting_t *list;
    if (list_of(L, output, "figures", &list) <= 0)
        return L->failed ? -1 : 0;
    int count = config_setting_length(list);
    if (count > SCENE_MAX_FIGURES)
        return fail(L, list, "at most %d figures", SCENE_MAX_FIGURES);
    for (int k = 0; k < count; ++k) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
        SceneFigure *f = &scene->output.figures[k];
        char what[48];
        snprintf(what, sizeof what, "figure %d", k);
        const char *name = NULL, *stage = NULL;
        int at = 1, format = 0;
        SceneStyle own = scene_style_unset();
        if (check_keys(L, g, what, keys, STYLE_KEYS) < 0 || need(L, g, "name", what) < 0 ||
            get_string(L, g, "name", &name) < 0 || check_file_name(L, g, "name", name) < 0 ||
            get_string(L, g, "stage", &stage) < 0 ||
            get_choice(L, g, "format", formats, &format) < 0 || parse_style(L, g, &own) < 0)
            return -1;
        /* at = "start" | "end" | seconds after the stage start (000 figs. 7.2, 7.9-7.23) */
        const config_setting_t *at_setting = member(g, "at");
        double at_time = 0.0;
        if (at_setting && config_setting_type(at_setting) != CONFIG_TYPE_STRING) {
            if (number_of(L, at_setting, "at", &at_time) < 0)
                return -1;
            if (!(at_time >= 0.0))
                return fail(L, at_setting, "`at` must be \"start\", \"end\" or a time >= 0 s");
            at = 2;
        } else if (get_choice(L, g, "at", at_names, &at) < 0) {
            return -1;
        }
        snprintf(f->name, sizeof f->name, "%s", name);
        for (int j = 0; j < k; ++j)
            if (strcmp(scene->output.figures[j].name, name) == 0 &&
                strcmp(scene->output.figures[j].format, formats[format]) == 0)
                return fail(L, member(g, "name"), "figure `%s` is declared twice", name);
        f->stage = scene->stage_count - 1;
        if (stage) {
            f->stage = scene_stage_index(scene, stage);
            if (f->stage < 0)
                return fail(L, member(g, "stage"), "no stage named `%s`", stage);
        }
        f->at_end = at;
        f->at_time = at_time;
        snprintf(f->format, sizeof f->format, "%s", formats[format]);
        f->style = scene->style;
        style_merge(&f->style, &own);
        scene->output.figure_count = k + 1;
    }
    return 0;
}

static int parse_output(Loader *L, const config_setting_t *root)
{
    static const char *const keys[] = {"frame_rate",    "fps",          "crf",   "movie",
                                       "drawer",        "energy_every", "trace", "trace_every",
                                       "t_star_length", "figures",      NULL};
    static const char *const drawers[] = {"cairo", "osmesa", NULL};
    Scene *scene = L->scene;
    SceneOutput *out = &scene->output;
    const config_setting_t *render, *output;
    out->frame_rate = 25.0;
    out->fps = 25.0;
    out->crf = 20;
    out->energy_every = 0.01;
    out->trace_every = -1.0;
    scene->style = scene_style_unset();
    if (group_of(L, root, "render", &render) < 0 ||
        check_keys(L, render, "render", STYLE_KEYS, NULL) < 0 ||
        (render && parse_style(L, render, &scene->style) < 0))
        return -1;
    if (group_of(L, root, "output", &output) < 0 ||
        check_keys(L, output, "output", keys, family_keys(2)) < 0)
        return -1;
    long long crf = out->crf;
    if (get_number(L, output, "frame_rate", &out->frame_rate) < 0 ||
        check_positive(L, output, "frame_rate", out->frame_rate) < 0 ||
        get_number(L, output, "fps", &out->fps) < 0 ||
        check_positive(L, output, "fps", out->fps) < 0 || get_int(L, output, "crf", &crf) < 0 ||
        get_choice(L, output, "drawer", drawers, &out->drawer) < 0 ||
        get_number(L, output, "energy_every", &out->energy_every) < 0 ||
        check_positive(L, output, "energy_every", out->energy_every) < 0 ||
        get_number(L, output, "trace_every", &out->trace_every) < 0 ||
        (member(output, "trace_every") &&
         check_positive(L, output, "trace_every", out->trace_every) < 0) ||
        get_number(L, output, "t_star_length", &out->t_star_length) < 0 ||
        check_non_negative(L, output, "t_star_length", out->t_star_length) < 0)
        return -1;
    if (crf < 0 || crf > 51)
        return fail(L, member(output, "crf"), "`crf` must be in [0, 51]");
    out->crf = (int)crf;
    if (out->trace_every < 0.0)
        out->trace_every = out->energy_every;
    /* movie = true | false | ["stage", ...]; a stage's own `movie` wins */
    const config_setting_t *movie = member(output, "movie");
    for (int k = 0; k < scene->stage_count; ++k) {
        int wanted = 0;
        if (movie && config_setting_type(movie) == CONFIG_TYPE_BOOL)
            wanted = config_setting_get_bool(movie);
        if (scene->stages[k].movie < 0)
            scene->stages[k].movie = wanted;
    }
    if (movie && config_setting_type(movie) != CONFIG_TYPE_BOOL) {
        if (config_setting_type(movie) != CONFIG_TYPE_ARRAY)
            return fail(L, movie, "`movie` must be true, false or an array of stage names");
        for (int j = 0; j < config_setting_length(movie); ++j) {
            const config_setting_t *e = config_setting_get_elem(movie, (unsigned)j);
            int stage = config_setting_type(e) == CONFIG_TYPE_STRING
                            ? scene_stage_index(scene, config_setting_get_string(e))
                            : -1;
            if (stage < 0)
                return fail(L, e, "`movie` names no stage `%s`",
                            config_setting_type(e) == CONFIG_TYPE_STRING
                                ? config_setting_get_string(e)
                                : "?");
            scene->stages[stage].movie = 1;
        }
    }
    const config_setting_t *trace = member(output, "trace");
    if (trace) {
        int n = config_setting_type(trace) == CONFIG_TYPE_ARRAY ? config_setting_length(trace) : -1;
        if (n < 0 || n > SCENE_MAX_TRACE)
            return fail(L, trace, "`trace` must be an array of at most %d grain ids",
                        SCENE_MAX_TRACE);
        for (int j = 0; j < n; ++j) {
            const config_setting_t *e = config_setting_get_elem(trace, (unsigned)j);
            if (config_setting_type(e) != CONFIG_TYPE_INT || config_setting_get_int(e) < 0)
                return fail(L, e, "`trace` must list grain ids (integers >= 0)");
            out->trace_ids[j] = (uint32_t)config_setting_get_int(e);
        }
        out->trace_count = n;
    }
    return parse_figures(L, output);
}

/* ---------------------------------------------------------------- start-configuration checks */

typedef struct SortKey {
    double x;
    int i;
} SortKey;

static int compare_keys(const void *a, const void *b)
{
    double xa = ((const SortKey *)a)->x, xb = ((const SortKey *)b)->x;
    return (xa > xb) - (xa < xb);
}

static const char *grain_where(const Scene *scene, int i)
{
    const SceneWhere *w = scene->where;
    if (i >= 0 && i < scene->grains.count && i < w->grain_capacity && w->grain_item)
        return w->items[w->grain_item[i]].where;
    return w->fallback;
}

static int fail_at(Loader *L, const char *where, const char *message)
{
    if (!L->failed)
        snprintf(L->err, L->err_size, "%s: %s", where, message);
    L->failed = 1;
    return -1;
}

/* Grains overlapping grains (a mobile one involved) or walls at the start: sweep over x. */
static int check_overlaps(Loader *L)
{
    const Scene *scene = L->scene;
    const SimGrainBuffer *b = &scene->grains;
    int n = b->count;
    SortKey *keys = malloc((size_t)(n > 0 ? n : 1) * sizeof *keys);
    if (!keys)
        return fail(L, NULL, "out of memory");
    double r_max = 0.0;
    for (int i = 0; i < n; ++i) {
        keys[i] = (SortKey){b->x[i], i};
        r_max = fmax(r_max, b->radius[i]);
    }
    qsort(keys, (size_t)n, sizeof *keys, compare_keys);
    char message[WHERE_MAX + 400];
    for (int a = 0; a < n; ++a) {
        int i = keys[a].i;
        for (int c = a + 1; c < n && keys[c].x - keys[a].x < b->radius[i] + r_max; ++c) {
            int j = keys[c].i;
            if ((b->flags[i] & SIM_GRAIN_FIXED) && (b->flags[j] & SIM_GRAIN_FIXED))
                continue;
            double d = hypot(b->x[j] - b->x[i], b->y[j] - b->y[i]);
            double overlap = b->radius[i] + b->radius[j] - d;
            if (overlap > OVERLAP_TOLERANCE * fmin(b->radius[i], b->radius[j])) {
                int late = i > j ? i : j, early = i > j ? j : i;
                snprintf(message, sizeof message,
                         "grain %d at (%g, %g) overlaps grain %d at (%g, %g) by %g m at the start "
                         "(%s)",
                         late, b->x[late], b->y[late], early, b->x[early], b->y[early], overlap,
                         grain_where(scene, early));
                free(keys);
                return fail_at(L, grain_where(scene, late), message);
            }
        }
    }
    free(keys);
    for (int w = 0; w < scene->def.wall_count; ++w) {
        const SimWall *wall = &scene->walls[w];
        double ex = wall->x1 - wall->x0, ey = wall->y1 - wall->y0;
        double length2 = ex * ex + ey * ey;
        for (int i = 0; i < n; ++i) {
            if (b->flags[i] & SIM_GRAIN_FIXED)
                continue;
            double t = ((b->x[i] - wall->x0) * ex + (b->y[i] - wall->y0) * ey) / length2;
            t = fmin(1.0, fmax(0.0, t));
            double d = hypot(b->x[i] - (wall->x0 + t * ex), b->y[i] - (wall->y0 + t * ey));
            if (b->radius[i] - d > OVERLAP_TOLERANCE * b->radius[i]) {
                char field[32];
                snprintf(field, sizeof field, "walls[%d]", w);
                snprintf(message, sizeof message,
                         "grain %d at (%g, %g) overlaps wall %d by %g m at the start (%s)", i,
                         b->x[i], b->y[i], w, b->radius[i] - d, scene_where_field(scene, 0, field));
                return fail_at(L, grain_where(scene, i), message);
            }
        }
    }
    return 0;
}

int scene_validate_def(const Scene *scene, int stage, const SimWorldDef *def, char *err,
                       size_t err_size)
{
    SimError error;
    memset(&error, 0, sizeof error);
    /* The time step against the declared contacts: a clear message before sim's own checks. */
    if (def->time_step > 0.0 && def->grains.count > 0) {
        SimTiming timing = sim_world_def_timing(def);
        if (timing.stability_limit > 0.0 && def->time_step > timing.stability_limit) {
            snprintf(err, err_size,
                     "%s: time step %g s is above the stability limit %g s of the declared "
                     "contacts (shortest contact time %g s)",
                     scene->where->stage_dt[stage], def->time_step, timing.stability_limit,
                     timing.contact_time_min);
            return -1;
        }
        if (def->max_dt_fraction > 0.0 && timing.contact_time_min > 0.0 &&
            def->time_step > def->max_dt_fraction * timing.contact_time_min) {
            snprintf(err, err_size,
                     "%s: time step %g s is above max_dt_fraction %g of the shortest contact "
                     "time %g s",
                     scene->where->stage_dt[stage], def->time_step, def->max_dt_fraction,
                     timing.contact_time_min);
            return -1;
        }
    }
    if (sim_world_def_validate(def, &error) != SIM_OK) {
        snprintf(err, err_size, "%s: %s", scene_where_field(scene, stage, error.field),
                 error.message);
        return -1;
    }
    return 0;
}

const char *scene_where_field(const Scene *scene, int stage, const char *field)
{
    const SceneWhere *w = scene->where;
    if (stage < 0 || stage >= scene->stage_count)
        stage = 0;
    if (!field || !field[0])
        return w->fallback;
    if (strncmp(field, "grains[", 7) == 0) {
        if (scene->stages[stage].load != SCENE_LOAD_SCENE)
            return w->stage_load[stage];
        return grain_where(scene, atoi(field + 7));
    }
    if (strcmp(field, "time_step") == 0)
        return w->stage_dt[stage];
    char path[64];
    snprintf(path, sizeof path, "%s", field);
    while (path[0]) {
        for (int k = w->count - 1; k >= 0; --k)
            if (strcmp(w->items[k].field, path) == 0)
                return w->items[k].where;
        /* strip the last component: ".name" or "[k]" */
        size_t n = strlen(path);
        char *cut = NULL;
        if (path[n - 1] == ']')
            cut = strrchr(path, '[');
        else
            cut = strrchr(path, '.');
        if (!cut)
            break;
        *cut = '\0';
    }
    return w->fallback;
}

/* ---------------------------------------------------------------- public */

Scene *scene_load(const char *path, const char *const *sets, int set_count, char *err,
                  size_t err_size)
{
    Scene *scene = calloc(1, sizeof *scene);
    SceneWhere *where = calloc(1, sizeof *where);
    if (!scene || !where) {
        free(scene);
        free(where);
        snprintf(err, err_size, "%s: out of memory", path);
        return NULL;
    }
    Loader loader = {.scene = scene, .err = err, .err_size = err_size};
    Loader *L = &loader;
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

    config_init(&L->config);
    config_set_include_dir(&L->config, L->dir);
    int ok = 1;
    if (!config_read_file(&L->config, path)) {
        if (config_error_type(&L->config) == CONFIG_ERR_FILE_IO)
            snprintf(err, err_size, "%s: cannot read scene file: %s", path,
                     errno ? strerror(errno) : "I/O error");
        else {
            char file[SCENE_PATH_MAX];
            file_name(L, config_error_file(&L->config), file, sizeof file);
            snprintf(err, err_size, "%s:%d: %s", file, config_error_line(&L->config),
                     config_error_text(&L->config));
        }
        ok = 0;
    }
    for (int k = 0; ok && k < set_count; ++k)
        ok = apply_set(L, sets[k]) == 0;
    const config_setting_t *root = config_root_setting(&L->config);
    if (ok)
        ok = parse_physics(L, root) == 0 && parse_species(L, root) == 0 &&
             parse_motions(L, root) == 0 && parse_effect_groups(L, root) == 0 &&
             parse_grains(L, root) == 0 && parse_walls(L, root) == 0 && parse_sinks(L, root) == 0 &&
             parse_stages(L, root) == 0 && parse_output(L, root) == 0;
    for (int f = 0; ok && app_experiments[f]; ++f) { /* each family parses its own keys */
        const AppExperiment *e = app_experiments[f];
        if (e->parse)
            ok = e->parse(root, e->group ? member(root, e->group) : NULL, scene,
                          &scene->experiments[f], err, err_size) == 0;
    }
    if (ok) {
        /* t* = t / sqrt(D/g) with D the container height (000 eq. 6.1) */
        if (scene->output.t_star_length == 0.0)
            scene->output.t_star_length = L->box_height;
        scene->def.length_scale = scene->output.t_star_length; /* frames' t* agree with CSV */
        for (int k = 0; k < scene->output.trace_count; ++k)
            if (scene->output.trace_ids[k] >= (uint32_t)scene->grains.count &&
                scene->stages[0].load == SCENE_LOAD_SCENE) {
                const config_setting_t *trace = config_lookup(&L->config, "output.trace");
                fail(L, trace, "`trace` id %u is not a grain of the scene (ids 0 to %d)",
                     scene->output.trace_ids[k], scene->grains.count - 1);
                ok = 0;
                break;
            }
    }
    if (ok)
        ok = check_overlaps(L) == 0;
    for (int k = 0; ok && k < scene->stage_count; ++k) {
        int seen = 0; /* validate each distinct time step once */
        for (int j = 0; j < k; ++j)
            seen |= scene->stages[j].time_step == scene->stages[k].time_step;
        if (seen && k > 0)
            continue;
        SimWorldDef def = scene_world_def(scene, k);
        ok = scene_validate_def(scene, k, &def, err, err_size) == 0;
    }
    config_destroy(&L->config);
    for (int k = 0; k < L->set_count; ++k)
        free(L->set_keys[k]);
    if (!ok) {
        scene_free(scene);
        return NULL;
    }
    return scene;
}

void scene_free(Scene *scene)
{
    if (!scene)
        return;
    for (int k = 0; k < SCENE_MAX_STAGES; ++k)
        free(scene->stages[k].remove_ids);
    sim_grain_buffer_free(&scene->grains);
    free(scene->walls);
    for (int f = 0; app_experiments[f]; ++f)
        if (scene->experiments[f] && app_experiments[f]->free)
            app_experiments[f]->free(scene->experiments[f]);
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
    def.grains = sim_grain_buffer_view(&scene->grains);
    def.time_step = scene->stages[stage].time_step;
    for (int f = 0; app_experiments[f]; ++f)
        if (scene->experiments[f] && app_experiments[f]->adjust_def)
            app_experiments[f]->adjust_def(scene->experiments[f], stage, &def);
    return def;
}

void *scene_experiment_state(const Scene *scene, const AppExperiment *family)
{
    int k = scene ? app_experiment_index(family) : -1;
    return k >= 0 ? scene->experiments[k] : NULL;
}

int scene_stage_index(const Scene *scene, const char *name)
{
    for (int k = 0; k < scene->stage_count; ++k)
        if (strcmp(scene->stages[k].name, name) == 0)
            return k;
    return -1;
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
