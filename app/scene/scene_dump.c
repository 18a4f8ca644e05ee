/* SPDX-License-Identifier: MIT */
/* scene_dump.c: the `dump` keys of a scene (docs/dumps.md), checked at load: `output.dump` and each
 * stage's own `dump` group into Scene.output.dump (app/scene/dump_spec.h). The writers of a run are
 * app/output/dump.c. */
#include "base/config.h"
#include "scene/dump_spec.h"
#include "scene/scene.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const FIELD_NAMES[] = {
    "id", "type", "x",     "y",       "vx",    "vy",    "omega",  "radius",  "fx",
    "fy", "mass", "angle", "species", "fixed", "force", "torque", "element", NULL};

static const char *const FORMAT_NAMES[] = {"lammps", "vtk", NULL};

const char *app_dump_field_name(int field)
{
    return field >= 0 && field < APP_DUMP_FIELD_COUNT ? FIELD_NAMES[field] : NULL;
}

/* ---------------------------------------------------------------- scene keys */

static AppDumpSpec spec_default(void)
{
    AppDumpSpec s;
    memset(&s, 0, sizeof s);
    static const unsigned char fields[APP_DUMP_DEFAULT_FIELDS] = {
        APP_DUMP_ID, APP_DUMP_TYPE, APP_DUMP_X,     APP_DUMP_Y,
        APP_DUMP_VX, APP_DUMP_VY,   APP_DUMP_OMEGA, APP_DUMP_RADIUS,
        APP_DUMP_FX, APP_DUMP_FY,   APP_DUMP_FIXED, APP_DUMP_ELEMENT};
    s.formats = APP_DUMP_LAMMPS;
    s.field_count = APP_DUMP_DEFAULT_FIELDS;
    memcpy(s.fields, fields, sizeof fields);
    s.contacts = 1;
    s.walls = 1;
    s.binary = -1;
    s.max_frames = APP_DUMP_MAX_FRAMES;
    return s;
}

static int name_index(const char *const *names, const char *name)
{
    for (int k = 0; names[k]; ++k)
        if (strcmp(names[k], name) == 0)
            return k;
    return -1;
}

/* `key` = ["name", ...] of `names`, each at most once: indices into out, their number in *count
 * (an empty array only for `format`: no dump). 1 when present, 0 absent, -1 bad. */
static int names_list(AppConfig *p, const config_setting_t *g, const char *key, const char *what,
                      const char *const *names, unsigned char *out, int *count)
{
    const config_setting_t *s = app_config_member(g, key);
    if (!s)
        return 0;
    char expected[256] = "";
    for (int k = 0; names[k]; ++k)
        snprintf(expected + strlen(expected), sizeof expected - strlen(expected), "%s%s",
                 k ? ", " : "", names[k]);
    int type = config_setting_type(s);
    int n = type == CONFIG_TYPE_ARRAY || type == CONFIG_TYPE_LIST ? config_setting_length(s) : -1;
    if (n < (strcmp(key, "format") == 0 ? 0 : 1))
        return app_config_fail(p, s, "`%s` must be an array of names (%s)", key, expected);
    for (int j = 0; j < n; ++j) {
        const config_setting_t *e = config_setting_get_elem(s, (unsigned)j);
        const char *name =
            config_setting_type(e) == CONFIG_TYPE_STRING ? config_setting_get_string(e) : NULL;
        int index = name ? name_index(names, name) : -1;
        if (index < 0)
            return app_config_fail(p, e, "unknown %s `%s` (expected: %s)", what,
                                   name ? name : app_config_type_name(e), expected);
        for (int i = 0; i < j; ++i)
            if (out[i] == index)
                return app_config_fail(p, e, "`%s` lists `%s` twice", key, name);
        out[j] = (unsigned char)index;
    }
    *count = n;
    return 1;
}

/* The keys of one dump group on top of *spec; *every_at = the setting of `every` when given. */
static int apply_group(AppConfig *p, const config_setting_t *g, AppDumpSpec *spec,
                       const config_setting_t **every_at)
{
    static const char *const keys[] = {"format", "every",      "fields",       "contacts",
                                       "walls",  "max_frames", "vtk_encoding", NULL};
    static const char *const encodings[] = {"ascii", "binary", "auto", NULL};
    unsigned char formats[APP_DUMP_FIELD_COUNT];
    int n = 0, found;
    long long max_frames = spec->max_frames;
    if (app_config_keys(p, g, NULL, keys, NULL) < 0 ||
        (found = names_list(p, g, "format", "format", FORMAT_NAMES, formats, &n)) < 0)
        return -1;
    if (found) {
        spec->formats = 0;
        for (int k = 0; k < n; ++k)
            spec->formats |= formats[k] == 0 ? APP_DUMP_LAMMPS : APP_DUMP_VTK;
    }
    double every = spec->every;
    if ((found = app_config_number(p, g, "every", &every)) < 0)
        return -1;
    if (found) {
        if (!(every > 0.0))
            return app_config_fail(p, app_config_member(g, "every"),
                                   "`every` must be > 0 s of simulated time (got %g)", every);
        spec->every = every;
        *every_at = app_config_member(g, "every");
    }
    if (names_list(p, g, "fields", "field", FIELD_NAMES, spec->fields, &spec->field_count) < 0 ||
        app_config_bool(p, g, "contacts", &spec->contacts) < 0 ||
        app_config_bool(p, g, "walls", &spec->walls) < 0 ||
        app_config_int(p, g, "max_frames", &max_frames) < 0)
        return -1;
    const char *encoding = NULL;
    if (app_config_string(p, g, "vtk_encoding", &encoding) < 0)
        return -1;
    int e = encoding ? name_index(encodings, encoding) : 3;
    if (e < 0)
        return app_config_fail(p, app_config_member(g, "vtk_encoding"),
                               "unknown `vtk_encoding` `%s` (expected: ascii, binary, auto)",
                               encoding);
    if (e < 3)
        spec->binary = e == 2 ? -1 : e;
    if (max_frames < 1 || max_frames > 1000000000LL)
        return app_config_fail(p, app_config_member(g, "max_frames"),
                               "`max_frames` must be in [1, 1e9]");
    spec->max_frames = (long)max_frames;
    return 0;
}

long app_dump_every_steps(const AppDumpSpec *spec, double dt)
{
    return (long)fmax(1.0, (double)llround(spec->every / dt)); /* as the energy rows' cadence */
}

long app_dump_frame_bound(const AppDumpSpec *spec, double duration, double dt)
{
    if (dt > 0.0) {
        double total = (double)llround(duration / dt),
               every = (double)app_dump_every_steps(spec, dt);
        double n = floor(total / every) + 1.0 + (fmod(total, every) != 0.0);
        return n < (double)(LONG_MAX / 2) ? (long)n : LONG_MAX / 2;
    }
    double n = floor(duration / spec->every) + 2.0; /* the start, every `every`, the end */
    return n < (double)(LONG_MAX / 2) ? (long)n : LONG_MAX / 2;
}

/* Stage k's dump: output.dump (`base`, may be NULL) with the stage's own `dump` on top. */
static int stage_spec(AppConfig *p, const config_setting_t *base, const AppDumpSpec *common,
                      const config_setting_t *common_every, const config_setting_t *stage_group,
                      struct Scene *scene, int k)
{
    const SceneStage *stage = &scene->stages[k];
    const config_setting_t *own = app_config_member(stage_group, "dump");
    const config_setting_t *every_at = common_every, *where = base;
    AppDumpSpec spec = *common;
    int declared = base != NULL;
    char label[SCENE_NAME_MAX + 24];
    snprintf(label, sizeof label, "stage %s: dump", stage->name);
    p->group = own ? label : "output.dump";
    if (own && config_setting_type(own) == CONFIG_TYPE_BOOL) {
        declared = config_setting_get_bool(own);
        if (declared && !base)
            return app_config_fail(p, own, "`dump = true` needs an `output.dump` group to use");
    } else if (own && config_setting_type(own) == CONFIG_TYPE_GROUP) {
        if (apply_group(p, own, &spec, &every_at) < 0)
            return -1;
        declared = 1;
        where = own;
    } else if (own) {
        return app_config_fail(p, own, "`dump` must be a group { every = ...; } or false");
    }
    memset(&scene->output.dump[k], 0, sizeof scene->output.dump[k]);
    if (!declared || !spec.formats) /* dump = false, or format = [] */
        return 0;
    if (!every_at)
        return app_config_fail(p, where, "`every` is required (simulated seconds between frames)");
    long bound = app_dump_frame_bound(&spec, stage->duration, stage->time_step);
    if (!stage->skip && bound > spec.max_frames)
        return app_config_fail(p, every_at,
                               "`every` = %g s over stage `%s` (%g s) makes up to %ld frames, "
                               "more than max_frames = %ld: raise `max_frames` to ask for them",
                               spec.every, stage->name, stage->duration, bound, spec.max_frames);
    scene->output.dump[k] = spec;
    return 0;
}

int app_dump_parse(AppConfig *p, const config_setting_t *root, struct Scene *scene)
{
    const char *group = p->group;
    const config_setting_t *output = app_config_member(root, "output");
    const config_setting_t *base = app_config_member(output, "dump");
    const config_setting_t *stages = app_config_member(root, "stages"), *common_every = NULL;
    AppDumpSpec common = spec_default();
    int rc = 0;
    p->group = "output.dump";
    if (base && config_setting_type(base) != CONFIG_TYPE_GROUP)
        rc = app_config_fail(p, base, "`dump` must be a group { every = ...; }");
    else if (base)
        rc = apply_group(p, base, &common, &common_every);
    for (int k = 0; rc == 0 && k < scene->stage_count; ++k)
        rc = stage_spec(p, base, &common, common_every,
                        stages ? config_setting_get_elem(stages, (unsigned)k) : NULL, scene, k);
    p->group = group;
    return rc;
}

void app_dump_describe(const AppDumpSpec *spec, double duration, double dt, FILE *out)
{
    if (!spec->formats)
        return;
    fprintf(out, "  dump             %s%s%s every %g s, at most %ld frames (max_frames %ld):",
            spec->formats & APP_DUMP_LAMMPS ? "lammps" : "",
            spec->formats == (APP_DUMP_LAMMPS | APP_DUMP_VTK) ? ", " : "",
            spec->formats & APP_DUMP_VTK ? (spec->contacts ? "vtk (+ contacts)" : "vtk") : "",
            spec->every, app_dump_frame_bound(spec, duration, dt), spec->max_frames);
    for (int k = 0; k < spec->field_count; ++k)
        fprintf(out, " %s", FIELD_NAMES[spec->fields[k]]);
    fputc('\n', out);
}
