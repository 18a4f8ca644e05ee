/* SPDX-License-Identifier: MIT */
/* run_summary.c: a run's summary.json (docs/cli.md): the scene, the totals, the stages' reports,
 * the families' members, versions and provenance. */
#include "base/util.h"
#include "run/run_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Grains that left through each sink, in scenes that have sinks (other summaries keep their
 * form). A stage entry's end: `, "removed_by_sinks": [n, ...]}`. */
static size_t stage_sinks_json(char *out, size_t size, const Scene *scene, const StageReport *s)
{
    size_t n = 0;
    if (scene->def.sink_count > 0)
        n += (size_t)snprintf(out, size, ", \"removed_by_sinks\": [");
    for (int k = 0; k < scene->def.sink_count; ++k)
        n +=
            (size_t)snprintf(out + n, n < size ? size - n : 0, "%s%ld", k ? ", " : "", s->sinks[k]);
    n += (size_t)snprintf(out + n, n < size ? size - n : 0, scene->def.sink_count > 0 ? "]}" : "}");
    return n;
}

/* The run's totals: `  "sinks": [{"shape": "below", "removed": n}, ...],\n`. */
static size_t run_sinks_json(char *out, size_t size, const Run *run)
{
    static const char *const shapes[] = {"below", "above", "left", "right", "rect"};
    const Scene *scene = run->scene;
    size_t n = 0;
    if (scene->def.sink_count == 0)
        return 0;
    n += (size_t)snprintf(out, size, "  \"sinks\": [");
    for (int k = 0; k < scene->def.sink_count; ++k) {
        long total = 0;
        for (int s = 0; s < run->stages_done; ++s)
            total += run->stages[s].sinks[k];
        unsigned shape = (unsigned)scene->def.sinks[k].shape;
        n += (size_t)snprintf(out + n, n < size ? size - n : 0,
                              "%s{\"shape\": \"%s\", \"removed\": %ld}", k ? ", " : "",
                              shape < 5 ? shapes[shape] : "?", total);
    }
    n += (size_t)snprintf(out + n, n < size ? size - n : 0, "],\n");
    return n;
}

/* summary.json's "units" member of a scene in its own units: the unit of each quantity that its
 * files hold, from the unit table (scene_unit); "scene" for the scene's own, unnamed unit (a time
 * when |g| is not 1). The number of bytes written, as snprintf. */
static size_t normalised_units_json(const Scene *scene, char *text, size_t size)
{
    static const struct {
        const char *key;
        SceneQuantity quantity;
    } row[] = {{"length", SCENE_LENGTH}, {"time", SCENE_TIME},   {"mass", SCENE_MASS},
               {"speed", SCENE_SPEED},   {"force", SCENE_FORCE}, {"energy", SCENE_ENERGY},
               {"stress", SCENE_STRESS}};

    size_t n = (size_t)snprintf(text, size, "  \"units\": {\"system\": \"normalised\"");
    for (size_t k = 0; k < sizeof row / sizeof row[0] && n < size; ++k) {
        const char *unit = scene_unit(scene, row[k].quantity, 0);
        n += (size_t)snprintf(text + n, size - n, ", \"%s\": \"%s\"", row[k].key,
                              unit[0] ? unit : "scene");
    }
    return n + (size_t)snprintf(text + n, n < size ? size - n : 0, "},\n");
}

/* The entries of summary.json's "stages" array, one per stage run; the characters written. */
static size_t stages_json(const Run *run, char *text, size_t size)
{
    const Scene *scene = run->scene;
    size_t n = 0;
    for (int k = 0; k < run->stages_done && n < size; ++k) {
        const StageReport *s = &run->stages[k];
        char stage_name[160], a[40], b[40], c[40];
        app_json_string(stage_name, sizeof stage_name, scene->stages[k].name);
        app_json_number(a, sizeof a, s->start_time);
        app_json_number(b, sizeof b, s->end_time);
        app_json_number(c, sizeof c, s->wall_seconds);
        n += (size_t)snprintf(text + n, size - n,
                              "%s\n    {\"name\": %s, \"steps\": %ld, \"start_time\": %s, "
                              "\"end_time\": %s, \"wall_seconds\": %s, \"settled\": %s, "
                              "\"removed\": %d, \"mobile_grains\": %d",
                              k ? "," : "", stage_name, s->steps, a, b, c,
                              s->settled ? "true" : "false", s->removed, s->mobile);
        n += stage_sinks_json(text + n, n < size ? size - n : 0, scene, s);
    }
    return n;
}

int app_run_summary_write(const Run *run, double wall_seconds)
{
    const Scene *scene = run->scene;
    size_t size = 24576 + 512 * SCENE_MAX_STAGES;
    char *text = malloc(size);
    if (!text)
        return -1;
    char name[256], file[2 * SCENE_PATH_MAX], message[2200], render[600], effects[256],
        effects_json[300], n1[40], n2[40], n3[40], n4[40];
    app_json_string(name, sizeof name, scene->name);
    char recorded[SCENE_PATH_MAX]; /* no machine path in the output (docs/cli.md "Provenance") */
    app_provenance_path(&run->options->provenance, scene->path, recorded, sizeof recorded);
    app_json_string(file, sizeof file, recorded);
    app_json_string(message, sizeof message, run->message);
    app_json_string(render, sizeof render,
                    run->options->render_versions ? run->options->render_versions : "not built");
    scene_effect_names(scene->def.effects, effects, sizeof effects);
    app_json_string(effects_json, sizeof effects_json, effects);
    int grains = run->world ? sim_world_grain_count(run->world) : scene->grains.count;
    int mobile =
        run->world ? sim_world_mobile_count(run->world) : scene->grains.count - scene->fixed_count;
    app_json_number(n1, sizeof n1, run->simulated);
    app_json_number(n2, sizeof n2, wall_seconds);
    app_json_number(n3, sizeof n3,
                    run->step_seconds > 0.0 ? run->particle_steps / run->step_seconds : 0.0);
    app_json_number(n4, sizeof n4,
                    run->contacts_samples ? run->contacts_sum / (double)run->contacts_samples
                                          : 0.0);
    const char *status = run->status == 0                    ? "ok"
                         : run->status == 1                  ? "unstable"
                         : run->status > APP_EXIT_SIGNAL     ? "interrupted"
                         : run->status == APP_EXIT_DISK_FULL ? "disk_full"
                                                             : "error";
    size_t n = (size_t)snprintf(
        text, size,
        "{\n  \"scene\": %s,\n  \"scene_file\": %s,\n  \"seed\": %llu,\n  \"grains\": %d,\n"
        "  \"mobile_grains\": %d,\n  \"steps\": %ld,\n  \"%s\": %s,\n"
        "  \"wall_seconds\": %s,\n  \"particle_steps_per_second\": %s,\n"
        "  \"contacts_mean\": %s,\n  \"status\": \"%s\",\n  \"message\": %s,\n"
        "  \"effects\": %s,\n  \"threads\": %d,\n",
        name, file, (unsigned long long)scene->seed, grains, mobile, run->steps,
        scene->units_normalised ? "simulated_time" : "simulated_seconds", n1, n2, n3, n4, status,
        message, effects_json,
        run->threads_most > 0 ? run->threads_most
                              : (run->options->threads > 0 ? run->options->threads : 1));
    n += run_sinks_json(text + n, size - n, run);
    if (run->unit_time > 0.0 && n < size) {
        char d[40], m[40], t[40];
        app_json_number(d, sizeof d, run->unit_length);
        app_json_number(m, sizeof m, run->unit_mass);
        app_json_number(t, sizeof t, run->unit_time);
        n += (size_t)snprintf(text + n, size - n,
                              "  \"units\": {\"system\": \"reduced\", \"length_m\": %s, "
                              "\"mass_kg\": %s, \"time_s\": %s},\n",
                              d, m, t);
    }
    if (run->scene->units_normalised && n < size)
        n += normalised_units_json(run->scene, text + n, size - n);
    char sources[2048];
    app_sources_json(run->sources, sources, sizeof sources);
    n += (size_t)snprintf(text + n, n < size ? size - n : 0, "%s%s  \"stages\": [", sources,
                          run->observed);
    if (n < size)
        n += stages_json(run, text + n, size - n);
    if (n < size) {
        char sablier[80];
        app_json_string(sablier, sizeof sablier, run->options->sablier_version);
        n += (size_t)snprintf(text + n, size - n,
                              "\n  ],\n  \"versions\": {\"sablier\": %s, \"sim\": \"%s\", "
                              "\"libconfig\": \"%s\", \"render\": %s},\n",
                              sablier, SIM_VERSION,
                              scene_libconfig_version() + strlen("libconfig "), render);
    }
    if (n < size) /* last: the fields above keep their lines whatever the command line */
        n += app_provenance_json(&run->options->provenance, scene->sha256, RESOLVED_NAME, text + n,
                                 size - n);
    if (n < size && n > 0 && text[n - 1] == '\n') { /* after it: they differ between runs too */
        n += (size_t)snprintf(text + n - 1, size - n + 1, ",\n") - 1;
        n += app_threads_json(&run->threads, text + n, size - n);
        n += (size_t)snprintf(text + n, n < size ? size - n : 0, "\n");
    }
    if (n < size)
        n += (size_t)snprintf(text + n, size - n, "}\n");
    char path[PATH_SIZE];
    snprintf(path, sizeof path, "%s/summary.json", run->options->out_dir);
    int rc = n < size ? app_write_atomic(path, text) : -1;
    free(text);
    return rc;
}
