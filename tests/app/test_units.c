/* SPDX-License-Identifier: MIT */
/* test_units.c: units = "reduced" (docs/scenes.md#units). The small Brazil-nut scene (settle, a
 * short shaking) runs in SI and in reduced units: the reduced energy.csv's time column is the SI
 * one divided by sqrt(d/g) to 1e-12 (the unit being the one summary.json reports, sqrt(d/g) of
 * its d), the other columns
 * are the same text, summary.json gains the scales, the SI run's has none; a t_star_length is
 * refused in reduced units. units = "normalised" (labels only) writes every output file but
 * summary.json byte for byte as without it, and summary.json names the units. No rendering. */
#include "test.h"

#include "base/render_hooks.h"
#include "run/run.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define BNE "scenes/brazil_nut/small.scene"

static int run_in(const char *units, char *dir, size_t size)
{
    const char *sets[] = {"stages.shake.time.end=3", "bne.phase_field.phases=2", units};
    char err[2048];
    Scene *scene = scene_load(BNE, sets, units ? 3 : 2, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    snprintf(dir, size, "/tmp/sablier_test_units_%ld_%s", (long)getpid(),
             !units                        ? "si"
             : strstr(units, "normalised") ? "normalised"
                                           : "reduced");
    AppRunOptions options = app_run_options_default();
    options.out_dir = dir;
    options.quiet = 1;
    options.render_off = 1;
    int status = app_run(scene, &options);
    scene_free(scene);
    return status;
}

/* Up to `max` rows of energy.csv: the first field (t) and the rest of the line. */
static int read_energy(const char *dir, double *t, char (*rest)[256], int max)
{
    char path[512], line[512];
    snprintf(path, sizeof path, "%s/energy.csv", dir);
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    int n = 0;
    if (!fgets(line, sizeof line, f)) /* header */
        n = -1;
    while (n >= 0 && n < max && fgets(line, sizeof line, f)) {
        char *comma = strchr(line, ',');
        if (!comma)
            break;
        t[n] = strtod(line, NULL);
        snprintf(rest[n], sizeof rest[n], "%s", comma);
        ++n;
    }
    fclose(f);
    return n;
}

/* The number after "KEY": in DIR/summary.json, NAN when absent. */
static double summary_number(const char *dir, const char *key)
{
    char path[512], text[65536], pattern[64];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    FILE *f = fopen(path, "r");
    if (!f)
        return (double)NAN;
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    snprintf(pattern, sizeof pattern, "\"%s\": ", key);
    const char *at = strstr(text, pattern);
    return at ? strtod(at + strlen(pattern), NULL) : (double)NAN;
}

enum { ROWS = 400 };

static int energy_time_in_sqrt_d_over_g(void)
{
    char si[256], red[256];
    TEST_ASSERT(run_in(NULL, si, sizeof si) == 0);
    TEST_ASSERT(run_in("units=\"reduced\"", red, sizeof red) == 0);
    static double t_si[ROWS], t_red[ROWS];
    static char rest_si[ROWS][256], rest_red[ROWS][256];
    int n_si = read_energy(si, t_si, rest_si, ROWS),
        n_red = read_energy(red, t_red, rest_red, ROWS);
    TEST_ASSERT(n_si > 10);
    TEST_ASSERT(n_red == n_si);
    const double d = summary_number(red, "length_m"), tau = summary_number(red, "time_s");
    char err[2048];
    Scene *scene = scene_load(BNE, NULL, 0, err, sizeof err);
    TEST_ASSERT(scene != NULL);
    const double g = hypot(scene->def.gravity_x, scene->def.gravity_y); /* the scene's gravity */
    scene_free(scene);
    TEST_ASSERT(d > 0.0 && tau > 0.0);
    TEST_REL(tau, sqrt(d / g), 1e-9); /* both printed to 10 digits */
    TEST_ASSERT(isnan(summary_number(si, "length_m")));
    TEST_ASSERT(t_red[n_red - 1] > 1.0);
    /* the unit to the last bit, from the last row (summary.json prints 10 digits) */
    const double unit = t_si[n_si - 1] / t_red[n_red - 1];
    TEST_REL(unit, tau, 1e-9);
    for (int k = 0; k < n_si; ++k) {
        TEST_NEAR(t_red[k], t_si[k] / unit, 1e-12 * fmax(1.0, t_red[k]));
        TEST_ASSERT(strcmp(rest_si[k], rest_red[k]) == 0); /* t_star, energies, ... unchanged */
    }
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' '%s'", si, red);
    TEST_ASSERT(system(cmd) == 0);
    return 0;
}

static int t_star_length_refused(void)
{
    const char *sets[] = {"units=\"reduced\"", "output.t_star_length=2.0"};
    char err[2048];
    Scene *scene = scene_load(BNE, sets, 2, err, sizeof err);
    TEST_ASSERT(scene == NULL);
    TEST_ASSERT(strstr(err, "t_star_length") != NULL);
    return 0;
}

/* 1 when DIR_A/NAME and DIR_B/NAME hold the same bytes. */
static int same_file(const char *a, const char *b, const char *name)
{
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "cmp -s '%s/%s' '%s/%s'", a, name, b, name);
    return system(cmd) == 0;
}

static int normalised_writes_numbers_as_given(void)
{
    char si[256], nu[256];
    TEST_ASSERT(run_in(NULL, si, sizeof si) == 0);
    TEST_ASSERT(run_in("units=\"normalised\"", nu, sizeof nu) == 0);
    const char *files[] = {"energy.csv",      "trace.csv",    "bne.csv",
                           "phase_field.csv", "settle.state", "shake.state"};
    for (size_t k = 0; k < sizeof files / sizeof files[0]; ++k)
        TEST_ASSERT(same_file(si, nu, files[k]));
    char path[512], text[65536];
    snprintf(path, sizeof path, "%s/summary.json", nu);
    FILE *f = fopen(path, "r");
    TEST_ASSERT(f != NULL);
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    /* the scene's gravity is 1 in its units: times in sqrt(d/g) */
    TEST_ASSERT(strstr(text, "\"units\": {\"system\": \"normalised\", \"length\": \"d\", "
                             "\"time\": \"sqrt(d/g)\", \"mass\": \"m\", \"speed\": \"sqrt(g d)\", "
                             "\"force\": \"m g\", \"energy\": \"m g d\", \"stress\": \"m g/d\"}") !=
                NULL);
    /* the simulated time is in the scene's unit, not seconds */
    TEST_ASSERT(strstr(text, "\"simulated_time\": ") != NULL);
    TEST_ASSERT(strstr(text, "\"simulated_seconds\"") == NULL);
    TEST_ASSERT(isnan(summary_number(nu, "length_m")));
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' '%s'", si, nu);
    TEST_ASSERT(system(cmd) == 0);
    return 0;
}

/* The shipped measure and chute scenes are written in d = g = 1 and declare it: one unit table
 * names their units (scene_unit) and their axes; SI scenes keep m, s and N. */
static int shipped_scenes_name_their_units(void)
{
    const char *paths[] = {"scenes/measure/column.scene", "scenes/chute/chute.scene"};
    char err[2048], label[64];
    for (int k = 0; k < 2; ++k) {
        Scene *scene = scene_load(paths[k], NULL, 0, err, sizeof err);
        TEST_ASSERT(scene != NULL);
        TEST_ASSERT(scene->units_normalised);
        TEST_ASSERT(strcmp(scene_unit(scene, SCENE_LENGTH, 0), "d") == 0);
        TEST_ASSERT(strcmp(scene_unit(scene, SCENE_TIME, 0), "sqrt(d/g)") == 0);
        TEST_ASSERT(strcmp(scene_unit(scene, SCENE_FORCE, 0), "m g") == 0);
        TEST_ASSERT(strcmp(scene_unit(scene, SCENE_STRESS, 0), "m g/d") == 0);
        TEST_ASSERT(
            strcmp(scene_axis_label(scene, "y", SCENE_LENGTH, label, sizeof label), "y / d") == 0);
        TEST_ASSERT(strcmp(scene_axis_label(scene, "t", SCENE_TIME, label, sizeof label),
                           "t / \xe2\x88\x9a(d/g)") == 0);
        TEST_ASSERT(
            strcmp(scene_axis_label(scene, "\\phi", SCENE_DIMENSIONLESS, label, sizeof label),
                   "\\phi (1)") == 0); /* a pure number says so: "(1)" */
        scene_free(scene);
    }
    Scene *si = scene_load("scenes/crater/small.scene", NULL, 0, err, sizeof err);
    TEST_ASSERT(si != NULL);
    TEST_ASSERT(strcmp(scene_unit(si, SCENE_FORCE, 0), "N") == 0);
    TEST_ASSERT(strcmp(scene_axis_label(si, "x", SCENE_LENGTH, label, sizeof label), "x (m)") == 0);
    TEST_ASSERT(
        strcmp(scene_axis_label(si, "Z", SCENE_DIMENSIONLESS, label, sizeof label), "Z (1)") == 0);
    scene_free(si);
    return 0;
}

/* A swept species key's unit from the species table (scene_key_quantity), as a sweep's x axis
 * names it: by the scene's mass model and normal law, in its unit system; none for a key whose
 * unit is not recorded. */
static int species_keys_name_their_units(void)
{
    const char *hertz[] = {"contact.normal=\"hertz\""}, *disk[] = {"mass_model=\"disk\""};
    char err[2048], label[64];
    Scene *si = scene_load("scenes/crater/small.scene", NULL, 0, err, sizeof err); /* sphere */
    TEST_ASSERT(si != NULL);
    TEST_ASSERT(scene_key_quantity(si, "species.0.mu") == SCENE_DIMENSIONLESS);
    TEST_ASSERT(scene_key_quantity(si, "species[0].k_n") == SCENE_STRESS);
    TEST_ASSERT(scene_key_quantity(si, "species.[1].gamma_s") == SCENE_MASS_RATE);
    TEST_ASSERT(scene_key_quantity(si, "species.0.density") == SCENE_DENSITY);
    TEST_ASSERT(scene_key_quantity(si, "species.0.mu_r") == SCENE_LENGTH);
    const char *unknown[] = {"guard.every",    "species.0.name", "species.mu", "species[0.mu",
                             "species.0.frob", "species0mu",     "species.0"};
    for (int k = 0; k < 7; ++k)
        TEST_ASSERT(scene_key_quantity(si, unknown[k]) == SCENE_QUANTITY_COUNT);
    TEST_ASSERT(
        strcmp(scene_axis_label(si, "species.0.mu", SCENE_DIMENSIONLESS, label, sizeof label),
               "species.0.mu (1)") == 0);
    TEST_ASSERT(strcmp(scene_axis_label(si, "k_r", scene_key_quantity(si, "species.0.k_r"), label,
                                        sizeof label),
                       "k_r (N m/rad)") == 0);
    TEST_ASSERT(strcmp(scene_unit(si, SCENE_DENSITY, 0), "kg/m^3") == 0);
    scene_free(si);
    Scene *h = scene_load("scenes/crater/small.scene", hertz, 1, err, sizeof err);
    TEST_ASSERT(h != NULL);
    TEST_ASSERT(scene_key_quantity(h, "species.0.k_n") == SCENE_HERTZ_STIFFNESS);
    TEST_ASSERT(scene_key_quantity(h, "species.0.gamma_n") == SCENE_QUANTITY_COUNT);
    TEST_ASSERT(strcmp(scene_unit(h, SCENE_HERTZ_STIFFNESS, 0), "N/m^1.5") == 0);
    scene_free(h);
    Scene *d = scene_load("scenes/crater/small.scene", disk, 1, err, sizeof err);
    TEST_ASSERT(d != NULL);
    TEST_ASSERT(scene_key_quantity(d, "species.0.density") == SCENE_AREAL_DENSITY);
    scene_free(d);
    Scene *own = scene_load("scenes/measure/column.scene", NULL, 0, err, sizeof err);
    TEST_ASSERT(own != NULL && own->units_normalised);
    TEST_ASSERT(strcmp(scene_axis_label(own, "k_n", scene_key_quantity(own, "species.0.k_n"), label,
                                        sizeof label),
                       "k_n / (m g/d)") == 0);
    scene_free(own);
    return 0;
}

/* A swept scalar key's unit from its group's key table (scene_key_quantity): the table the loader
 * checks the group's keys against, so "time.dt (s)" on a sweep's x axis; a rain group may be
 * named by its index in a list, the box may not; names, indices and unknown keys have none. */
static int scalar_keys_name_their_units(void)
{
    char err[2048], label[64];
    Scene *si = scene_load("scenes/crater/small.scene", NULL, 0, err, sizeof err);
    TEST_ASSERT(si != NULL);
    TEST_ASSERT(scene_key_quantity(si, "time.dt") == SCENE_TIME);
    TEST_ASSERT(scene_key_quantity(si, "time.end") == SCENE_TIME);
    TEST_ASSERT(scene_key_quantity(si, "time.steps_per_contact") == SCENE_DIMENSIONLESS);
    TEST_ASSERT(scene_key_quantity(si, "grains.rain.x1") == SCENE_LENGTH);
    TEST_ASSERT(scene_key_quantity(si, "grains.rain.[1].radius_mean") == SCENE_LENGTH);
    TEST_ASSERT(scene_key_quantity(si, "grains.rain.0.polydispersity") == SCENE_DIMENSIONLESS);
    TEST_ASSERT(scene_key_quantity(si, "grains.box.radius") == SCENE_LENGTH);
    const char *none[] = {"time.frob",
                          "timedt",
                          "time",
                          "grains.rain.species",
                          "grains.rain.[0.x0",
                          "grains.box.0.x0",
                          "grains.box.motion",
                          "stages.deposit.time.end"};
    for (int k = 0; k < 8; ++k)
        TEST_ASSERT(scene_key_quantity(si, none[k]) == SCENE_QUANTITY_COUNT);
    TEST_ASSERT(strcmp(scene_axis_label(si, "time.dt", scene_key_quantity(si, "time.dt"), label,
                                        sizeof label),
                       "time.dt (s)") == 0);
    TEST_ASSERT(
        strcmp(scene_axis_label(si, "grains.rain.x1", scene_key_quantity(si, "grains.rain.x1"),
                                label, sizeof label),
               "grains.rain.x1 (m)") == 0);
    scene_free(si);
    return 0;
}

/* Every axis and colour-bar label the measures give the renderer, recorded. */
typedef struct Labels {
    char text[4096];
} Labels;

static void keep(Labels *l, const char *label)
{
    size_t n = strlen(l->text);
    if (label)
        snprintf(l->text + n, sizeof l->text - n, "%s|", label);
}

static int record_plot(void *context, const AppPlot *plot, const char *path, char *err,
                       size_t err_size)
{
    (void)path, (void)err, (void)err_size;
    for (int k = 0; k < plot->panel_count; ++k) {
        keep(context, plot->panels[k].x_label);
        keep(context, plot->panels[k].y_label);
    }
    return 0;
}

static int record_map(void *context, const Scene *scene, const AppMap *map, const char *path,
                      char *err, size_t err_size)
{
    (void)scene, (void)path, (void)err, (void)err_size;
    keep(context, map->x_label);
    keep(context, map->y_label);
    keep(context, map->bar_label);
    keep(context, map->arrow_unit);
    return 0;
}

/* column.scene's profile and maps: axes in d, the stress in m g/d, speeds in sqrt(g d); no SI
 * unit anywhere. */
static int measure_labels_in_scene_units(void)
{
    const char *sets[] = {"grains.rain.max_count=40", "stages.rain.time.end=1",
                          "stages.rest.time.end=1", "stages.rest.measures.0.window=0.5"};
    char err[2048], dir[256];
    Scene *scene = scene_load("scenes/measure/column.scene", sets, 4, err, sizeof err);
    TEST_ASSERT(scene != NULL);
    snprintf(dir, sizeof dir, "/tmp/sablier_test_units_%ld_labels", (long)getpid());
    Labels labels = {{0}};
    AppRender render = {.context = &labels, .plot = record_plot, .map = record_map};
    AppRunOptions options = app_run_options_default();
    options.out_dir = dir;
    options.quiet = 1;
    options.render = &render;
    TEST_ASSERT(app_run(scene, &options) == 0);
    scene_free(scene);
    TEST_ASSERT(strstr(labels.text, "\\sigma_{yy} / (m g/d)|y / d|") != NULL);
    TEST_ASSERT(strstr(labels.text, "x / d|y / d|\\phi (1)|") != NULL); /* dimensionless */
    TEST_ASSERT(strstr(labels.text, "|\xe2\x88\x9a(gd)|") != NULL);
    TEST_ASSERT(strstr(labels.text, "(m)") == NULL && strstr(labels.text, "N/m") == NULL &&
                strstr(labels.text, "m/s") == NULL);
    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    TEST_ASSERT(system(cmd) == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(energy_time_in_sqrt_d_over_g), TEST_CASE(t_star_length_refused),
          TEST_CASE(normalised_writes_numbers_as_given), TEST_CASE(shipped_scenes_name_their_units),
          TEST_CASE(species_keys_name_their_units), TEST_CASE(scalar_keys_name_their_units),
          TEST_CASE(measure_labels_in_scene_units))
