/* SPDX-License-Identifier: MIT */
/* config.c: typed libconfig getters with "file:line: message" errors (config.h). */
#include "base/config.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#define WHERE_SIZE 1200

/* ---------------------------------------------------------------- messages */

void app_config_file_name(const AppConfig *p, const char *file, char *out, size_t size)
{
    const char *slash = strrchr(p->path, '/');
    int dir = slash ? (int)(slash - p->path) : 0; /* p->path's folder: its first dir chars */
    if (dir > (int)(size / 2))
        dir = (int)(size / 2);
    if (!file || strcmp(file, p->path) == 0 || file[0] == '/' || !slash ||
        (dir == 1 && p->path[0] == '.'))
        snprintf(out, size, "%s", file ? file : p->path);
    else
        snprintf(out, size, "%.*s/%s", dir, p->path, file);
}

void app_config_where(const AppConfig *p, const config_setting_t *s, char *out, size_t size)
{
    if (s && config_setting_get_hook(s)) {
        snprintf(out, size, "--set %s", (const char *)config_setting_get_hook(s));
        return;
    }
    if (s && config_setting_source_line(s) > 0) {
        char file[1024];
        app_config_file_name(p, config_setting_source_file(s), file, sizeof file);
        snprintf(out, size, "%s:%u", file, config_setting_source_line(s));
        return;
    }
    snprintf(out, size, "%s:1", p->path);
}

static void write_message(AppConfig *p, const char *where, const char *group, const char *format,
                          va_list args)
{
    char message[2048];
    vsnprintf(message, sizeof message, format, args);
    snprintf(p->err, p->err_size, "%s: %s%s%s", where, group ? group : "", group ? ": " : "",
             message);
    p->failed = 1;
}

int app_config_fail(AppConfig *p, const config_setting_t *s, const char *format, ...)
{
    if (p->failed)
        return -1;
    char where[WHERE_SIZE];
    app_config_where(p, s, where, sizeof where);
    int from_set = s && config_setting_get_hook(s);
    va_list args;
    va_start(args, format);
    write_message(p, where, from_set ? NULL : p->group, format, args);
    va_end(args);
    return -1;
}

int app_config_fail_at(AppConfig *p, const char *where, const char *format, ...)
{
    if (p->failed)
        return -1;
    va_list args;
    va_start(args, format);
    write_message(p, where, NULL, format, args);
    va_end(args);
    return -1;
}

const char *app_config_type_name(const config_setting_t *s)
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

/* ---------------------------------------------------------------- getters */

config_setting_t *app_config_member(const config_setting_t *g, const char *key)
{
    return g ? config_setting_get_member(g, key) : NULL;
}

int app_config_number_of(AppConfig *p, const config_setting_t *s, const char *key, double *out)
{
    switch (config_setting_type(s)) {
    case CONFIG_TYPE_INT:
    case CONFIG_TYPE_INT64:
        *out = (double)config_setting_get_int64(s);
        return 1;
    case CONFIG_TYPE_FLOAT:
        *out = config_setting_get_float(s);
        if (!isfinite(*out))
            return app_config_fail(p, s, "`%s` must be a finite number", key);
        return 1;
    default:
        return app_config_fail(p, s, "`%s` must be a number, not %s", key, app_config_type_name(s));
    }
}

int app_config_number(AppConfig *p, const config_setting_t *g, const char *key, double *out)
{
    const config_setting_t *s = app_config_member(g, key);
    return s ? app_config_number_of(p, s, key, out) : 0;
}

int app_config_number_min(AppConfig *p, const config_setting_t *g, const char *key, double min,
                          double *out)
{
    int found = app_config_number(p, g, key, out);
    if (found > 0 && app_config_at_least(p, g, key, *out, min) < 0)
        return -1;
    return found;
}

int app_config_int(AppConfig *p, const config_setting_t *g, const char *key, long long *out)
{
    const config_setting_t *s = app_config_member(g, key);
    if (!s)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_INT && config_setting_type(s) != CONFIG_TYPE_INT64)
        return app_config_fail(p, s, "`%s` must be an integer, not %s", key,
                               app_config_type_name(s));
    *out = config_setting_get_int64(s);
    return 1;
}

int app_config_int_in(AppConfig *p, const config_setting_t *g, const char *key, long min, long max,
                      int *out)
{
    long long v = 0;
    int found = app_config_int(p, g, key, &v);
    if (found <= 0)
        return found;
    if (v < min || v > max)
        return app_config_fail(p, app_config_member(g, key),
                               "`%s` must be an integer in [%ld, %ld], got %lld", key, min, max, v);
    *out = (int)v;
    return 1;
}

int app_config_bool(AppConfig *p, const config_setting_t *g, const char *key, int *out)
{
    const config_setting_t *s = app_config_member(g, key);
    if (!s)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_BOOL)
        return app_config_fail(p, s, "`%s` must be true or false, not %s", key,
                               app_config_type_name(s));
    *out = config_setting_get_bool(s) ? 1 : 0;
    return 1;
}

int app_config_string(AppConfig *p, const config_setting_t *g, const char *key, const char **out)
{
    const config_setting_t *s = app_config_member(g, key);
    if (!s)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_STRING)
        return app_config_fail(p, s, "`%s` must be a string, not %s", key, app_config_type_name(s));
    *out = config_setting_get_string(s);
    return 1;
}

static int is_array(const config_setting_t *s)
{
    return config_setting_type(s) == CONFIG_TYPE_ARRAY ||
           config_setting_type(s) == CONFIG_TYPE_LIST;
}

int app_config_vector(AppConfig *p, const config_setting_t *g, const char *key, double *out, int n)
{
    const config_setting_t *s = app_config_member(g, key);
    if (!s)
        return 0;
    if (!is_array(s) || config_setting_length(s) != n)
        return app_config_fail(p, s, "`%s` must be an array of %d numbers", key, n);
    for (int k = 0; k < n; ++k)
        if (app_config_number_of(p, config_setting_get_elem(s, (unsigned)k), key, &out[k]) < 0)
            return -1;
    return 1;
}

int app_config_array(AppConfig *p, const config_setting_t *g, const char *key, int max, double *out,
                     int *count)
{
    const config_setting_t *s = app_config_member(g, key);
    if (!s)
        return 0;
    if (!is_array(s))
        return app_config_fail(p, s, "`%s` must be an array of numbers", key);
    int n = config_setting_length(s);
    if (n < 1 || n > max)
        return app_config_fail(p, s, "`%s` must have 1 to %d entries", key, max);
    for (int k = 0; k < n; ++k) {
        const config_setting_t *e = config_setting_get_elem(s, (unsigned)k);
        int type = config_setting_type(e);
        if (type == CONFIG_TYPE_FLOAT)
            out[k] = config_setting_get_float(e);
        else if (type == CONFIG_TYPE_INT || type == CONFIG_TYPE_INT64)
            out[k] = (double)config_setting_get_int64(e);
        else
            return app_config_fail(p, s, "`%s` must be an array of numbers", key);
        if (!isfinite(out[k]) || out[k] < 0.0)
            return app_config_fail(p, s, "`%s` entries must be finite and >= 0", key);
    }
    *count = n;
    return 1;
}

int app_config_choice(AppConfig *p, const config_setting_t *g, const char *key,
                      const char *const *names, int *out)
{
    const char *value = NULL;
    int found = app_config_string(p, g, key, &value);
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
    return app_config_fail(p, app_config_member(g, key), "unknown %s `%s` (expected one of: %s)",
                           key, value, list);
}

int app_config_group(AppConfig *p, const config_setting_t *g, const char *key,
                     const config_setting_t **out)
{
    const config_setting_t *s = app_config_member(g, key);
    *out = NULL;
    if (!s)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_GROUP)
        return app_config_fail(p, s, "`%s` must be a group { ... }, not %s", key,
                               app_config_type_name(s));
    *out = s;
    return 1;
}

int app_config_list(AppConfig *p, const config_setting_t *g, const char *key,
                    const config_setting_t **out)
{
    const config_setting_t *s = app_config_member(g, key);
    *out = NULL;
    if (!s)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_LIST)
        return app_config_fail(p, s, "`%s` must be a list ( {...}, {...} ), not %s", key,
                               app_config_type_name(s));
    for (int k = 0; k < config_setting_length(s); ++k) {
        const config_setting_t *e = config_setting_get_elem(s, (unsigned)k);
        if (config_setting_type(e) != CONFIG_TYPE_GROUP)
            return app_config_fail(p, e, "elements of `%s` must be groups { ... }, not %s", key,
                                   app_config_type_name(e));
    }
    *out = s;
    return 1;
}

/* ---------------------------------------------------------------- checks */

int app_config_need(AppConfig *p, const config_setting_t *g, const char *key, const char *what)
{
    if (app_config_member(g, key))
        return 0;
    return app_config_fail(p, g, "missing required key `%s` in %s", key, what);
}

int app_config_need_number(AppConfig *p, const config_setting_t *g, const char *key,
                           const char *what, double *out)
{
    if (app_config_need(p, g, key, what) < 0)
        return -1;
    return app_config_number(p, g, key, out);
}

/* The key's own line, or its group's when it is absent (a default out of range). */
static const config_setting_t *key_or_group(const config_setting_t *g, const char *key)
{
    const config_setting_t *s = app_config_member(g, key);
    return s ? s : g;
}

int app_config_positive(AppConfig *p, const config_setting_t *g, const char *key, double v)
{
    if (v > 0.0)
        return 0;
    return app_config_fail(p, key_or_group(g, key), "`%s` must be > 0 (got %g)", key, v);
}

int app_config_non_negative(AppConfig *p, const config_setting_t *g, const char *key, double v)
{
    return app_config_at_least(p, g, key, v, 0.0);
}

int app_config_at_least(AppConfig *p, const config_setting_t *g, const char *key, double v,
                        double min)
{
    if (v >= min)
        return 0;
    return app_config_fail(p, key_or_group(g, key), "`%s` must be >= %g (got %g)", key, min, v);
}

static int in_list(const char *key, const char *const *list)
{
    for (int k = 0; list && list[k]; ++k)
        if (strcmp(key, list[k]) == 0)
            return 1;
    return 0;
}

int app_config_keys(AppConfig *p, const config_setting_t *g, const char *what,
                    const char *const *allowed, const char *const *more)
{
    if (!g)
        return 0;
    if (config_setting_type(g) != CONFIG_TYPE_GROUP) {
        if (what)
            return app_config_fail(p, g, "%s must be a group { ... }, not %s", what,
                                   app_config_type_name(g));
        return app_config_fail(p, g, "`%s` must be a group { ... }, not %s",
                               p->group ? p->group : config_setting_name(g),
                               app_config_type_name(g));
    }
    for (int k = 0; k < config_setting_length(g); ++k) {
        const config_setting_t *s = config_setting_get_elem(g, (unsigned)k);
        const char *key = config_setting_name(s);
        if (in_list(key, allowed) || in_list(key, more))
            continue;
        if (what)
            return app_config_fail(p, s, "unknown key `%s` in %s", key, what);
        return app_config_fail(p, s, "unknown key `%s`", key);
    }
    return 0;
}
