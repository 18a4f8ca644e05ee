/* SPDX-License-Identifier: MIT */
/* scene_set.c: `--set KEY=VALUE` overrides and `--unset KEY` removals (docs/cli.md), applied to
 * the libconfig tree in command-line order before the scene is parsed. A setting an override
 * touched carries the key as its hook, so that every later message about it reads "--set KEY:
 * message" instead of a file line. */
#include "base/util.h"
#include "scene/scene_internal.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

__attribute__((format(printf, 3, 4))) static int set_fail(Loader *L, const char *key,
                                                          const char *format, ...)
{
    char where[WHERE_MAX], message[600];
    snprintf(where, sizeof where, "%s %s", L->unsetting ? "--unset" : "--set", key);
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    return app_config_fail_at(&L->p, where, "%s", message);
}

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
    switch (config_setting_type(s)) {
    case CONFIG_TYPE_INT:
        if (parse_long(value, &i) && i >= -2147483647LL && i <= 2147483647LL &&
            config_setting_set_int(s, (int)i))
            return 0;
        return set_fail(L, key, "`%s` is not an integer", value);
    case CONFIG_TYPE_INT64:
        if (parse_long(value, &i) && config_setting_set_int64(s, i))
            return 0;
        return set_fail(L, key, "`%s` is not an integer", value);
    case CONFIG_TYPE_FLOAT:
        if (parse_double(value, &d) && config_setting_set_float(s, d))
            return 0;
        return set_fail(L, key, "`%s` is not a number", value);
    case CONFIG_TYPE_BOOL:
        if ((strcmp(value, "true") == 0 || strcmp(value, "false") == 0) &&
            config_setting_set_bool(s, strcmp(value, "true") == 0))
            return 0;
        return set_fail(L, key, "`%s` is not true or false", value);
    case CONFIG_TYPE_STRING:
        trim_quotes(value);
        if (config_setting_set_string(s, value))
            return 0;
        return set_fail(L, key, "cannot set `%s`", value);
    default:
        return set_fail(L, key, "is %s; set one of its elements (KEY.0=...)",
                        app_config_type_name(s));
    }
}

/* Replaces the elements of an array with "[a, b, c]". */
static int set_array(Loader *L, config_setting_t *s, const char *key, char *value)
{
    size_t n = strlen(value);
    if (n < 2 || value[0] != '[' || value[n - 1] != ']')
        return set_fail(L, key, "an array value is written [a, b, ...]");
    value[n - 1] = '\0';
    int type = config_setting_length(s) > 0 ? config_setting_type(config_setting_get_elem(s, 0))
                                            : CONFIG_TYPE_NONE;
    while (config_setting_length(s) > 0)
        config_setting_remove_elem(s, 0);
    const char *list = value + 1;
    size_t length;
    while (isspace((unsigned char)*list))
        ++list;
    if (!*list) /* [] */
        return 0;
    for (const char *next; (next = app_list_item(&list, &length)) != NULL;) {
        char element[256], *item = element;
        snprintf(element, sizeof element, "%.*s", (int)length, next);
        while (isspace((unsigned char)*item))
            ++item;
        char *end = item + strlen(item);
        while (end > item && isspace((unsigned char)end[-1]))
            *--end = '\0';
        if (!*item || length >= sizeof element)
            return set_fail(L, key,
                            !*item ? "an empty element in [a, b, ...] (`,,` or a comma at an end)"
                                   : "an array element longer than 255 characters");
        if (type == CONFIG_TYPE_NONE)
            type = infer_type(item);
        if (type == CONFIG_TYPE_INT && infer_type(item) == CONFIG_TYPE_FLOAT)
            type = CONFIG_TYPE_FLOAT;
        config_setting_t *e = config_setting_add(s, NULL, type);
        if (!e)
            return set_fail(L, key, "mixed element types");
        config_setting_set_hook(e, config_setting_get_hook(s));
        if (set_scalar(L, e, key, item) < 0)
            return -1;
    }
    return 0;
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

/* Walks KEY's path (dots, or [k] for list elements: species[0].k_n is species.0.k_n) from the
 * root. A missing key is added inside an existing group; its type follows the value, and the
 * scene checks reject it later if it is not a key the group accepts. NULL: reported. */
/* A --set path: names and indices joined by dots, an index also as [N] right after a name:
 * `time.dt`, `species.0.k_n`, `species[0].k_n`. No empty part (`.time`, `time..dt`, `dt.`), no
 * unclosed or stray bracket, nothing but digits inside one. NULL, or what is wrong. */
static const char *key_syntax(const char *key)
{
    int part = 0; /* characters in the present part */
    for (const char *c = key; *c; ++c) {
        if (*c == '.') {
            if (part == 0)
                return "empty part in the key (two dots, or a dot at an end)";
            part = 0;
        } else if (*c == '[') {
            if (part == 0)
                return "`[` must follow a name";
            const char *d = c + 1;
            while (*d >= '0' && *d <= '9')
                ++d;
            if (d == c + 1 || *d != ']')
                return "an index in brackets must be digits closed by `]`";
            if (d[1] != '\0' && d[1] != '.' && d[1] != '[')
                return "`]` must end the key or be followed by `.`";
            c = d;
            part = 1;
        } else if (*c == ']') {
            return "`]` without `[`";
        } else {
            ++part;
        }
    }
    return part == 0 ? "empty part in the key (two dots, or a dot at an end)" : NULL;
}

/* The setting KEY names; a missing key is added (--set) unless value is NULL (--unset). */
static config_setting_t *walk(Loader *L, char *key, const char *value)
{
    const char *bad = key_syntax(key);
    if (bad) {
        set_fail(L, key, "%s", bad);
        return NULL;
    }
    size_t key_length = strlen(key);
    char *path = malloc(key_length + 1);
    if (!path) {
        set_fail(L, key, "out of memory");
        return NULL;
    }
    size_t n = 0;
    for (size_t k = 0; k < key_length; ++k) {
        if (key[k] == ']')
            continue;
        path[n++] = key[k] == '[' ? '.' : key[k];
    }
    path[n] = '\0';
    config_setting_t *s = config_root_setting(&L->config);
    char *save = NULL;
    char *part = strtok_r(path, ".", &save);
    if (!part) {
        set_fail(L, key, "empty key");
        s = NULL;
    }
    while (s && part) {
        char *next = strtok_r(NULL, ".", &save);
        config_setting_t *c = child(s, part);
        if (!c && !value) {
            set_fail(L, key, "no such key in the scene (`%s` is missing)", part);
        } else if (!c && config_setting_type(s) != CONFIG_TYPE_GROUP) {
            set_fail(L, key, "no such element");
        } else if (!c) {
            int type = next ? CONFIG_TYPE_GROUP : infer_type(value);
            if (!next && value[0] == '[')
                type = CONFIG_TYPE_ARRAY;
            c = config_setting_add(s, part, type);
            if (c)
                config_setting_set_hook(c, key);
            else
                set_fail(L, key, "not a valid key name");
        }
        s = c;
        part = next;
    }
    free(path);
    return s;
}

/* Writes VALUE into the setting KEY reached. */
static int assign(Loader *L, config_setting_t *s, char *key, char *value)
{
    config_setting_set_hook(s, key);
    int type = config_setting_type(s);
    if (type == CONFIG_TYPE_ARRAY || type == CONFIG_TYPE_LIST)
        return value[0] == '[' && type == CONFIG_TYPE_ARRAY
                   ? set_array(L, s, key, value)
                   : set_fail(L, key, "is a list; set one of its elements (KEY.0=...)");
    if (type == CONFIG_TYPE_GROUP)
        return set_fail(L, key, "is a group; set one of its keys");
    if (type == CONFIG_TYPE_INT && infer_type(value) == CONFIG_TYPE_FLOAT &&
        config_setting_parent(s) &&
        config_setting_type(config_setting_parent(s)) == CONFIG_TYPE_GROUP) {
        /* A number written as an integer in the file may take a fractional value; the scene
         * checks still refuse it where an integer is required (seed). */
        config_setting_t *parent = config_setting_parent(s);
        char name[128];
        snprintf(name, sizeof name, "%s", config_setting_name(s));
        config_setting_remove(parent, name);
        s = config_setting_add(parent, name, CONFIG_TYPE_FLOAT);
        config_setting_set_hook(s, key);
    }
    return set_scalar(L, s, key, value);
}

/* The keys that only one contact law accepts, removed with the law's key (its dependents). */
static void remove_law_keys(Loader *L, const char *law)
{
    static const char *const tangential[] = {"k_t", "gamma_t", NULL}, *const rolling[] = {"k_r",
                                                                                          NULL};
    const char *const *keys = strcmp(law, "tangential") == 0 ? tangential
                              : strcmp(law, "rolling") == 0  ? rolling
                                                             : NULL;
    config_setting_t *species = config_lookup(&L->config, "species");
    for (int k = 0; keys && species && k < config_setting_length(species); ++k) {
        config_setting_t *g = config_setting_get_elem(species, (unsigned)k);
        for (int j = 0; config_setting_type(g) == CONFIG_TYPE_GROUP && keys[j]; ++j)
            if (config_setting_get_member(g, keys[j]))
                config_setting_remove(g, keys[j]);
    }
}

/* --unset KEY: the setting removed with what it holds; contact.tangential and contact.rolling
 * also take the species keys only their law accepts (k_t and gamma_t; k_r). */
static int unset(Loader *L, char *key)
{
    config_setting_t *s = walk(L, key, NULL);
    if (!s)
        return -1;
    config_setting_t *parent = config_setting_parent(s);
    if (!parent)
        return set_fail(L, key, "cannot remove the whole scene");
    char name[128];
    snprintf(name, sizeof name, "%s", config_setting_name(s) ? config_setting_name(s) : "");
    const config_setting_t *grand = config_setting_parent(parent);
    const int law = grand && config_setting_is_root(grand) &&
                    strcmp(config_setting_name(parent), "contact") == 0;
    if (!config_setting_remove_elem(parent, (unsigned)config_setting_index(s)))
        return set_fail(L, key, "cannot remove it");
    if (law)
        remove_law_keys(L, name);
    return 0;
}

int loader_apply_set(Loader *L, const char *assignment)
{
    const char *eq = strchr(assignment, '=');
    size_t key_length = eq ? (size_t)(eq - assignment) : strlen(assignment);
    if (L->set_count == (int)(sizeof L->set_keys / sizeof L->set_keys[0]))
        return set_fail(L, assignment, "too many --set options");
    char *key = malloc(key_length + 1);
    char *value = strdup(eq ? eq + 1 : "");
    if (!key || !value) {
        free(key);
        free(value);
        return set_fail(L, assignment, "out of memory");
    }
    memcpy(key, assignment, key_length);
    key[key_length] = '\0';
    L->set_keys[L->set_count++] = key; /* setting hooks point to it until scene_load returns */
    int rc = -1;
    L->unsetting = !eq;
    if (!eq) /* an --unset: the key alone (app_set_option) */
        rc = unset(L, key);
    else if (key_length == 0)
        set_fail(L, assignment, "expected KEY=VALUE");
    else {
        config_setting_t *s = walk(L, key, value);
        rc = s ? assign(L, s, key, value) : -1;
    }
    free(value);
    return rc;
}
