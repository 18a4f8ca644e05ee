/* SPDX-License-Identifier: MIT */
/* test_scene.c: the scene loader (app/scene/scene_load.c) and runner (app/run/run.c), without
 * render. */
#include "test.h"

#include "app/crater/crater.h"
#include "app/run/run.h"
#include "app/scene/scene.h"
#include "sim/sim.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define QUICK "scenes/crater/quick.scene"
#define DROP  "scenes/validation/drop_elastic.scene"

/* Line number of the first line of `path` containing `text` (0 if none). */
static int line_of(const char *path, const char *text)
{
    FILE *f = fopen(path, "r");
    char line[512];
    int n = 0;
    while (f && fgets(line, sizeof line, f)) {
        ++n;
        if (strstr(line, text)) {
            fclose(f);
            return n;
        }
    }
    if (f)
        fclose(f);
    return 0;
}

/* The thesis 000 §4.3 parameters come through as written. */
static int quick_scene_parameters(void)
{
    char err[2048];
    Scene *s = scene_load(QUICK, NULL, 0, err, sizeof err);
    if (!s)
        fprintf(stderr, "%s\n", err);
    TEST_ASSERT(s);
    TEST_ASSERT(s->def.effects == SIM_EFFECT_FRICTION);
    TEST_ASSERT(s->def.mass_model == SIM_MASS_SPHERE);
    TEST_ASSERT(s->def.species_count == 1);
    const SimMaterial *m = &s->def.materials[0];
    TEST_NEAR(m->density, 1190.0, 0.0);
    TEST_NEAR(m->normal_stiffness, 7e5, 0.0);
    TEST_ASSERT(m->damping_mode == SIM_DAMPING_GAMMA);
    TEST_NEAR(m->normal_damping, 1.5e3, 0.0);
    TEST_NEAR(m->friction, 0.5, 0.0);
    TEST_NEAR(m->tangential_damping, 5.0, 0.0);
    TEST_ASSERT(s->def.contact.tangential == SIM_TANGENTIAL_REGULARISED);
    TEST_NEAR(s->def.gravity_y, -9.806, 0.0);
    TEST_ASSERT(s->grains.count - s->fixed_count == 1500);
    TEST_ASSERT(s->stage_count == 3);
    TEST_ASSERT(strcmp(s->stages[1].name, "dig") == 0);
    TEST_ASSERT(s->stages[0].load == SCENE_LOAD_SCENE);
    TEST_ASSERT(s->stages[1].load == SCENE_LOAD_PREVIOUS);
    TEST_ASSERT(app_crater_dig(s, 1).dig && app_crater_dig(s, 1).top_surface);
    TEST_NEAR(app_crater_dig(s, 1).width / app_crater_dig(s, 1).height, 1.0, 1e-12); /* H/L = 1 */
    TEST_NEAR(s->stages[0].settle_kinetic, 0.1, 0.0);
    TEST_ASSERT(s->stages[0].movie == 1 && s->stages[1].movie == 0 && s->stages[2].movie == 1);
    /* radii within 8% polydispersity of r_med = 0.08 m; fixed walls at r_max */
    for (int i = 0; i < s->grains.count; ++i) {
        double r = s->grains.radius[i];
        if (s->grains.flags[i] & SIM_GRAIN_FIXED)
            TEST_NEAR(r, 0.105, 1e-12);
        else
            TEST_ASSERT(r >= 0.08 * 0.92 - 1e-12 && r <= 0.08 * 1.08 + 1e-12);
    }
    /* figures inherit the render group and override it */
    TEST_ASSERT(s->output.figure_count >=
                3); /* settled bed, cavity, crater, then collapse frames */
    TEST_ASSERT(s->output.figures[0].style.color_by == SCENE_COLOR_FORCE);
    TEST_ASSERT(s->output.figures[0].style.width == 960);
    TEST_ASSERT(s->style.width == 720);
    TEST_NEAR(s->output.figures[2].style.view_y1, 5.0, 0.0);
    TEST_ASSERT(s->output.figures[1].stage == 1);
    scene_free(s);
    return 0;
}

/* --set overrides by dotted path, list index and stage name. */
static int set_overrides(void)
{
    char err[2048];
    const char *sets[] = {"time.dt=2e-5", "species.0.k_n=9e5", "stages.collapse.time.end=1.25",
                          "seed=7", "species[0].mu=1"};
    Scene *s = scene_load(QUICK, sets, 5, err, sizeof err);
    if (!s)
        fprintf(stderr, "%s\n", err);
    TEST_ASSERT(s);
    TEST_NEAR(s->stages[0].time_step, 2e-5, 0.0);
    TEST_NEAR(s->stages[2].time_step, 2e-5, 0.0);
    TEST_NEAR(s->def.materials[0].normal_stiffness, 9e5, 0.0);
    TEST_NEAR(s->def.materials[0].friction, 1.0, 0.0);
    TEST_NEAR(s->stages[2].duration, 1.25, 0.0);
    TEST_NEAR(s->stages[0].duration, 5.0, 0.0);
    TEST_ASSERT(s->seed == 7);
    scene_free(s);
    /* a bad --set names the option, not a file line */
    const char *bad[] = {"time.dt=-1"};
    s = scene_load(QUICK, bad, 1, err, sizeof err);
    TEST_ASSERT(!s);
    TEST_ASSERT(strncmp(err, "--set time.dt: ", 15) == 0);
    return 0;
}

/* Errors point at the key's line; SimError fields map back to scene lines. */
static int error_lines(void)
{
    char err[2048], expect[128];
    Scene *s = scene_load("tests/scenes_bad/negative_stiffness.scene", NULL, 0, err, sizeof err);
    TEST_ASSERT(!s);
    snprintf(expect, sizeof expect, "negative_stiffness.scene:%d: ",
             line_of("tests/scenes_bad/negative_stiffness.scene", "k_n = -5e5"));
    TEST_ASSERT(strstr(err, expect) != NULL);
    s = scene_load(DROP, NULL, 0, err, sizeof err);
    TEST_ASSERT(s);
    snprintf(expect, sizeof expect, DROP ":%d", line_of(DROP, "k_n = 5e5"));
    TEST_ASSERT(strcmp(scene_where_field(s, 0, "materials[0].normal_stiffness"), expect) == 0);
    snprintf(expect, sizeof expect, DROP ":%d", line_of(DROP, "dt = 1e-5"));
    TEST_ASSERT(strcmp(scene_where_field(s, 0, "time_step"), expect) == 0);
    snprintf(expect, sizeof expect, DROP ":%d", line_of(DROP, "fixed = true"));
    TEST_ASSERT(strcmp(scene_where_field(s, 0, "grains[1]"), expect) == 0);
    /* an unknown sub-field falls back to its parent: the species group */
    snprintf(expect, sizeof expect, DROP ":%d", line_of(DROP, "name = \"grain\""));
    TEST_ASSERT(strcmp(scene_where_field(s, 0, "materials[0].restitution"), expect) == 0);
    /* validation of a modified definition reports the scene line */
    SimWorldDef def = scene_world_def(s, 0);
    def.time_step = 1.0;
    TEST_ASSERT(scene_validate_def(s, 0, &def, err, sizeof err) != 0);
    snprintf(expect, sizeof expect, DROP ":%d: ", line_of(DROP, "dt = 1e-5"));
    TEST_ASSERT(strncmp(err, expect, strlen(expect)) == 0);
    scene_free(s);
    return 0;
}

/* The rain lattice follows the seed: same seed, same grains. */
static int rain_follows_seed(void)
{
    char err[2048];
    const char *seed2[] = {"seed=2"};
    Scene *a = scene_load(QUICK, NULL, 0, err, sizeof err);
    Scene *b = scene_load(QUICK, NULL, 0, err, sizeof err);
    Scene *c = scene_load(QUICK, seed2, 1, err, sizeof err);
    TEST_ASSERT(a && b && c);
    TEST_ASSERT(a->grains.count == b->grains.count);
    TEST_ASSERT(memcmp(a->grains.x, b->grains.x, (size_t)a->grains.count * sizeof(double)) == 0);
    TEST_ASSERT(memcmp(a->grains.radius, c->grains.radius, 100 * sizeof(double)) != 0);
    scene_free(a);
    scene_free(b);
    scene_free(c);
    return 0;
}

/* Free-surface height: the highest grain top within the band. */
static int surface_height(void)
{
    double x[] = {0.0, 1.0, 5.0, 0.5}, y[] = {1.0, 2.0, 9.0, 3.0}, r[] = {0.1, 0.2, 0.1, 0.1};
    SimFrame f;
    memset(&f, 0, sizeof f);
    f.count = 4;
    f.mobile_count = 3; /* the last is fixed and ignored */
    f.x = x;
    f.y = y;
    f.radius = r;
    double top = 0.0;
    TEST_ASSERT(app_crater_surface_height(&f, 0.5, 1.0, &top) == 0);
    TEST_NEAR(top, 2.2, 1e-15);
    TEST_ASSERT(app_crater_surface_height(&f, 20.0, 1.0, &top) != 0);
    return 0;
}

static int effect_names(void)
{
    char text[128];
    scene_effect_names(SIM_EFFECT_FRICTION | SIM_EFFECT_REMOVAL, text, sizeof text);
    TEST_ASSERT(strcmp(text, "friction, removal") == 0);
    scene_effect_names(0, text, sizeof text);
    TEST_ASSERT(strcmp(text, "none") == 0);
    return 0;
}

/* --set paths are strict: every malformed one is refused, naming what is wrong. */
static int set_key_syntax(void)
{
    const char *bad[][2] = {{".time.dt=1e-5", "empty part"},
                            {"time..dt=1e-5", "empty part"},
                            {"time.dt.=1e-5", "empty part"},
                            {"species[0.k_n=1e6", "digits closed by `]`"},
                            {"species[x].k_n=1e6", "digits closed by `]`"},
                            {"species.0]=1", "`]` without `[`"},
                            {"species[0]k_n=1e6", "followed by `.`"},
                            {"[0].k_n=1e6", "must follow a name"}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        char err[2048] = "";
        const char *sets[] = {bad[k][0]};
        Scene *s = scene_load(DROP, sets, 1, err, sizeof err);
        if (s || !strstr(err, bad[k][1]) || !strstr(err, "--set ")) {
            fprintf(stderr, "--set %s: %s\n", bad[k][0], s ? "accepted" : err);
            scene_free(s);
            return 1;
        }
    }
    const char *good[] = {"species[0].k_n=2e6"};
    char err[2048];
    Scene *s = scene_load(DROP, good, 1, err, sizeof err);
    TEST_ASSERT(s);
    scene_free(s);
    return 0;
}

/* A run without renderer writes energy.csv, summary.json and the checkpoint. */
static int run_writes_outputs(void)
{
    char err[2048], dir[] = "/tmp/sablier_test_XXXXXX", path[256];
    TEST_ASSERT(mkdtemp(dir));
    const char *sets[] = {"time.end=0.01"};
    Scene *s = scene_load(DROP, sets, 1, err, sizeof err);
    TEST_ASSERT(s);
    AppRunOptions options = app_run_options_default();
    options.out_dir = dir;
    options.quiet = 1;
    TEST_ASSERT(app_run(s, &options) == 0);
    struct stat st;
    const char *files[] = {"energy.csv", "summary.json", "run.state",
                           "trace.csv",  "manifest.txt", "scene.resolved.cfg"};
    for (int k = 0; k < 6; ++k) {
        snprintf(path, sizeof path, "%s/%s", dir, files[k]);
        TEST_ASSERT(stat(path, &st) == 0 && st.st_size > 0);
        remove(path);
    }
    snprintf(path, sizeof path, "%s/energy.csv.tmp", dir);
    TEST_ASSERT(stat(path, &st) != 0);
    rmdir(dir);
    scene_free(s);
    return 0;
}

TEST_MAIN(TEST_CASE(quick_scene_parameters), TEST_CASE(set_overrides), TEST_CASE(error_lines),
          TEST_CASE(rain_follows_seed), TEST_CASE(surface_height), TEST_CASE(effect_names),
          TEST_CASE(run_writes_outputs), TEST_CASE(set_key_syntax))
