/* SPDX-License-Identifier: MIT */
/* config.h: the one set of typed libconfig getters of the app (scene loader, experiment families,
 * .sweep files). Every getter reports a bad value as "FILE:LINE: GROUP: message" (or
 * "--set KEY: message" for a value that came from a --set override) in the context's buffer.
 *
 *     AppConfig p = {.path = scene->path, .err = err, .err_size = err_size, .group = "bne"};
 *     double gamma = NAN;   // stays NAN when the key is absent
 *     if (app_config_keys(&p, g, NULL, keys, NULL) < 0 ||
 *         app_config_number_min(&p, g, "gamma", 0.0, &gamma) < 0)
 *         return -1;   // err: "scene.scene:12: bne: `gamma` must be >= 0 (got -1)"
 *
 * Getters return 1 when the key is present and valid, 0 when it is absent (the output untouched)
 * and -1 when it is bad (message written); checks return 0 or -1. The first message wins: once
 * a context has failed, later failures keep it. */
#ifndef APP_CONFIG_H
#define APP_CONFIG_H

#include <libconfig.h>
#include <stddef.h>

/// Where a file's errors go.
typedef struct AppConfig {
    /// The file read: named for settings without a source line; its folder is the one that
    /// libconfig's @include names are relative to (they are shown as "FOLDER/NAME").
    const char *path;
    char *err; ///< message buffer
    size_t err_size;
    const char *group; ///< "GROUP: " put before every message ("bne", "fluid"); NULL: none
    int failed;        ///< 1 once a message is written
} AppConfig;

/* ---------------------------------------------------------------- messages */

/// Writes "WHERE: GROUP: message" for setting `s` (NULL: the file, line 1) and returns -1.
__attribute__((format(printf, 3, 4))) int app_config_fail(AppConfig *p, const config_setting_t *s,
                                                          const char *format, ...);
/// The same at a location given as text ("file:line", "--set KEY"), without the group prefix.
__attribute__((format(printf, 3, 4))) int app_config_fail_at(AppConfig *p, const char *where,
                                                             const char *format, ...);
/// "file:line" of setting `s` ("--set KEY" for an override, "path:1" for NULL).
void app_config_where(const AppConfig *p, const config_setting_t *s, char *out, size_t size);
/// A file name as libconfig reports it (an @include'd one is relative to the folder of p->path)
/// as the user reaches it from the working folder.
void app_config_file_name(const AppConfig *p, const char *file, char *out, size_t size);
/// "a number", "a string", "a group", ... for messages.
const char *app_config_type_name(const config_setting_t *s);

/* ---------------------------------------------------------------- getters */

/// Member `key` of `g`; NULL when g is NULL or has no such member.
config_setting_t *app_config_member(const config_setting_t *g, const char *key);
/// Setting `s` (named `key` in messages) as a finite number; integers are accepted.
int app_config_number_of(AppConfig *p, const config_setting_t *s, const char *key, double *out);
int app_config_number(AppConfig *p, const config_setting_t *g, const char *key, double *out);
/// A number >= min (app_config_number, then app_config_at_least when present).
int app_config_number_min(AppConfig *p, const config_setting_t *g, const char *key, double min,
                          double *out);
int app_config_int(AppConfig *p, const config_setting_t *g, const char *key, long long *out);
/// An integer in [min, max].
int app_config_int_in(AppConfig *p, const config_setting_t *g, const char *key, long min, long max,
                      int *out);
int app_config_bool(AppConfig *p, const config_setting_t *g, const char *key, int *out);
int app_config_string(AppConfig *p, const config_setting_t *g, const char *key, const char **out);
/// An array (or list) of exactly n numbers, e.g. gravity = [0.0, -9.806].
int app_config_vector(AppConfig *p, const config_setting_t *g, const char *key, double *out, int n);
/// An array of 1 to `max` finite numbers >= 0; their number in *count.
int app_config_array(AppConfig *p, const config_setting_t *g, const char *key, int max, double *out,
                     int *count);
/// One of `names` (NULL-ended) as a string: its index in *out.
int app_config_choice(AppConfig *p, const config_setting_t *g, const char *key,
                      const char *const *names, int *out);
/// A group { ... } (*out = the group, NULL when absent).
int app_config_group(AppConfig *p, const config_setting_t *g, const char *key,
                     const config_setting_t **out);
/// A list of groups ( {...}, {...} ) (*out = the list, NULL when absent).
int app_config_list(AppConfig *p, const config_setting_t *g, const char *key,
                    const config_setting_t **out);

/* ---------------------------------------------------------------- checks (0 or -1) */

/// `key` is present in g (`what` names g: "the scene", "species 0").
int app_config_need(AppConfig *p, const config_setting_t *g, const char *key, const char *what);
/// app_config_need, then app_config_number.
int app_config_need_number(AppConfig *p, const config_setting_t *g, const char *key,
                           const char *what, double *out);
/// v > 0, v >= 0, v >= min; reported at `key`'s line (g's when absent).
int app_config_positive(AppConfig *p, const config_setting_t *g, const char *key, double v);
int app_config_non_negative(AppConfig *p, const config_setting_t *g, const char *key, double v);
int app_config_at_least(AppConfig *p, const config_setting_t *g, const char *key, double v,
                        double min);
/// g (NULL: nothing to check) is a group whose keys are all in `allowed` or `more` (NULL-ended,
/// `more` may be NULL). `what` names g in the messages ("grains.rain"); NULL: the message names
/// only the key, and the group is `p->group`.
int app_config_keys(AppConfig *p, const config_setting_t *g, const char *what,
                    const char *const *allowed, const char *const *more);

#endif
