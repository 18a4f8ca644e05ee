/* SPDX-License-Identifier: MIT */
/* test_sediment.c: the `sediment` group (older name `fluid`) and bed-load measures (thesis 002 ch.
 * 6-7) on a reduced bed of scenes/sediment/viscous.scene (150 grains, dt = 1e-3, short stages),
 * without rendering. */
#include "test.h"

#include "run/run.h"
#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sediment/sediment.h"

#define SCENE "scenes/sediment/viscous.scene"

/* The reduced bed of `path`, whose family group is named `group`. */
static Scene *load_named(const char *path, const char *group, const char *shields,
                         const char *flow_end, const char *extra)
{
    char s1[64], s2[64];
    snprintf(s1, sizeof s1, "%s.shields=%s", group, shields);
    snprintf(s2, sizeof s2, "stages.flow.time.end=%s", flow_end);
    const char *sets[] = {"output.movie=[]",
                          "stages.settle.time.end=8.0",
                          "grains.rain.max_count=150",
                          "time.dt=1e-3",
                          s1,
                          s2,
                          extra};
    char err[1024] = "";
    Scene *scene = scene_load(path, sets, extra ? 7 : 6, err, sizeof err);
    if (!scene)
        fprintf(stderr, "%s\n", err);
    return scene;
}

static Scene *load(const char *shields, const char *flow_end, const char *extra)
{
    return load_named(SCENE, "sediment", shields, flow_end, extra);
}

static int run_quiet(const Scene *scene, char *dir, size_t size, const char *tag)
{
    snprintf(dir, size, "/tmp/sablier_test_sediment_%ld_%s", (long)getpid(), tag);
    AppRunOptions o = app_run_options_default();
    o.out_dir = dir;
    o.quiet = 1;
    return app_run(scene, &o);
}

/* The control numbers set rho_f, nu and u* (002 eqs. 40-42). */
static int numbers_from_scene(void)
{
    Scene *scene = load("0.3", "1.0", NULL);
    TEST_ASSERT(scene && app_sediment_of(scene));
    AppSedimentNumbers n = app_sediment_numbers(app_sediment_of(scene));
    const SimFluidDef *fd = sim_fluid_def(app_sediment_fluid(app_sediment_of(scene)));
    double d = n.diameter, scale = sqrt((2.0 - 1.0) * 1.0 * d);
    TEST_NEAR(d, 1.0, 0.02); /* 20 % dispersion around d = 1 */
    TEST_REL(fd->density, 0.318309886183791 / 2.0, 1e-12);
    TEST_REL(fd->viscosity, d * scale / 0.1, 1e-12);
    TEST_REL(fd->shear_velocity, sqrt(0.3) * scale, 1e-12);
    TEST_REL(fd->width, 40.0, 1e-12);
    TEST_ASSERT(fd->geometry == SIM_FLUID_DISK);
    scene_free(scene);
    return 0;
}

/* The fluid drags only when the effect is declared: a `sediment` group without fluid_drag is
 * refused, and so are `sediment` with `drag`, and bad fluid keys. */
static int fluid_needs_effect(void)
{
    const char *sets[] = {"effects=[friction, periodic_x]"};
    char err[1024] = "";
    Scene *scene = scene_load(SCENE, sets, 1, err, sizeof err);
    TEST_ASSERT(!scene);
    printf("%s\n", err);
    TEST_ASSERT(strstr(err, "`sediment` needs effect \"fluid_drag\""));
    const char *with_drag[] = {"drag.model=\"linear\"", "drag.coefficient=1.0"};
    scene = scene_load(SCENE, with_drag, 2, err, sizeof err);
    printf("%s\n", err);
    TEST_ASSERT(!scene && strstr(err, "`sediment` and `drag` both drag the grains"));
    const char *bad_start[] = {"sediment.start=\"later\""};
    scene = scene_load(SCENE, bad_start, 1, err, sizeof err);
    TEST_ASSERT(!scene && strstr(err, "start"));
    const char *bad_cells[] = {"sediment.cells=1"};
    scene = scene_load(SCENE, bad_cells, 1, err, sizeof err);
    TEST_ASSERT(!scene && strstr(err, "layers"));
    return 0;
}

/* `fluid`, the group's older name, loads the same column and the messages name `fluid`; a scene
 * that gives both names is refused. */
static int fluid_is_an_alias(void)
{
    char path[256], line[512];
    snprintf(path, sizeof path, "/tmp/sablier_test_sediment_%ld_old.scene", (long)getpid());
    FILE *in = fopen(SCENE, "r"), *out = fopen(path, "w");
    TEST_ASSERT(in && out);
    int renamed = 0;
    while (fgets(line, sizeof line, in)) {
        if (strncmp(line, "sediment = {", 12) == 0) {
            fprintf(out, "fluid = {%s", line + 12);
            ++renamed;
        } else {
            fputs(line, out);
        }
    }
    fclose(in);
    fclose(out);
    TEST_ASSERT(renamed == 1);
    char err[1024] = "";
    Scene *old = load_named(path, "fluid", "0.3", "1.0", NULL);
    Scene *now = load("0.3", "1.0", NULL);
    TEST_ASSERT(old && app_sediment_of(old) && now && app_sediment_of(now));
    TEST_ASSERT(strcmp(app_sediment_group(app_sediment_of(old)), "fluid") == 0);
    TEST_ASSERT(strcmp(app_sediment_group(app_sediment_of(now)), "sediment") == 0);
    const SimFluidDef *a = sim_fluid_def(app_sediment_fluid(app_sediment_of(old)));
    const SimFluidDef *b = sim_fluid_def(app_sediment_fluid(app_sediment_of(now)));
    TEST_ASSERT(a->shear_velocity == b->shear_velocity && a->viscosity == b->viscosity);
    scene_free(old);
    scene_free(now);
    const char *no_effect[] = {"effects=[friction, periodic_x]"};
    TEST_ASSERT(!scene_load(path, no_effect, 1, err, sizeof err));
    printf("%s\n", err);
    TEST_ASSERT(strstr(err, "`fluid` needs effect \"fluid_drag\""));
    const char *bad_cells[] = {"fluid.cells=1"};
    TEST_ASSERT(!scene_load(path, bad_cells, 1, err, sizeof err));
    printf("%s\n", err);
    TEST_ASSERT(strstr(err, "--set fluid.cells: ") && strstr(err, "layers"));
    const char *both[] = {"sediment.shields=0.3"};
    TEST_ASSERT(!scene_load(path, both, 1, err, sizeof err));
    printf("%s\n", err);
    TEST_ASSERT(strstr(err, "`fluid` is an older name of `sediment`: keep one"));
    remove(path);
    return 0;
}

/* Well below threshold (Theta = 0.02) nothing moves: |q*| < 5e-4, and at steady state the fluid
 * stress plus the load carried by the grains is uniform, rho_f u*^2 within 5 % (002 fig. 34). */
static int below_threshold(void)
{
    Scene *scene = load("0.02", "20.0", NULL);
    TEST_ASSERT(scene);
    char dir[256];
    TEST_ASSERT(run_quiet(scene, dir, sizeof dir, "below") == 0);
    SimFluid *fluid = app_sediment_fluid(app_sediment_of(scene));
    const SimFluidDef *fd = sim_fluid_def(fluid);
    double target = fd->density * fd->shear_velocity * fd->shear_velocity;
    SimFluidProfile p;
    sim_fluid_profile(fluid, &p);
    double load = 0.0, worst = 0.0, carried = 0.0;
    for (int k = p.cells; k >= 0; --k) {
        if (k < p.cells)
            load += p.grain_force[k] * p.dy;
        worst = fmax(worst, fabs(p.stress[k] + load - target));
        if (k == 0)
            carried = load;
    }
    printf("rho u*^2 = %.4g, max |tau_f + grain load - rho u*^2| = %.3g, carried by grains %.4g\n",
           target, worst, carried);
    TEST_ASSERT(worst < 0.05 * target);
    TEST_ASSERT(carried > 0.9 * target); /* the bed, not the base, takes the stress */
    /* the flux record */
    char path[512];
    snprintf(path, sizeof path, "%s/sediment.csv", dir);
    FILE *f = fopen(path, "r");
    TEST_ASSERT(f);
    char line[512];
    double worst_q = 0.0, t, q, q_star;
    TEST_ASSERT(fgets(line, sizeof line, f));
    while (fgets(line, sizeof line, f))
        if (sscanf(line, "%lf,%lf,%lf", &t, &q, &q_star) == 3 && t > 12.0)
            worst_q = fmax(worst_q, fabs(q_star));
    fclose(f);
    printf("largest |q*| after the start-up: %.3g\n", worst_q);
    TEST_ASSERT(worst_q < 5e-4);
    snprintf(path, sizeof path, "%s/flow.fluid.csv", dir);
    TEST_ASSERT(access(path, R_OK) == 0);
    snprintf(path, sizeof path, "%s/sediment.json", dir);
    TEST_ASSERT(access(path, R_OK) == 0);
    scene_free(scene);
    return 0;
}

/* Saturation measures on a synthetic record q = q_sat (1 - exp(-t / T)). */
static int saturation_measure(void)
{
    double t[4001], q[4001];
    for (int k = 0; k <= 4000; ++k) {
        t[k] = 10.0 + 0.01 * k;
        q[k] = 2.0 * (1.0 - exp(-(t[k] - 10.0) / 3.0));
    }
    double t_sat;
    double q_sat = app_sediment_saturation(t, q, 4001, 10.0, &t_sat);
    TEST_REL(q_sat, 2.0, 1e-4);
    TEST_REL(t_sat, 3.0, 1e-3);
    return 0;
}

/* The Shields-scan threshold: zero-flux intercept of the two lowest transporting points, clamped
 * to the bracket; the bracket's middle with one transporting point; NAN without a bracket. */
static int shields_threshold(void)
{
    /* q* = 0.05 (Theta - 0.3) above 0.3, creep noise below; unsorted input */
    double theta[6] = {0.8, 0.1, 0.4, 0.2, 0.6, 0.05}, q[6];
    for (int k = 0; k < 6; ++k)
        q[k] = theta[k] > 0.3 ? 0.05 * (theta[k] - 0.3) : 1e-5 * theta[k];
    double below, above;
    double c = app_sediment_threshold(theta, q, 6, 1e-3, &below, &above);
    TEST_NEAR(c, 0.3, 1e-12);
    TEST_NEAR(below, 0.2, 0.0);
    TEST_NEAR(above, 0.4, 0.0);
    /* a steep law whose intercept falls under the bracket is clamped to its lower end */
    double q2[6];
    for (int k = 0; k < 6; ++k)
        q2[k] = theta[k] >= 0.4 ? theta[k] * theta[k] * theta[k] : 0.0;
    c = app_sediment_threshold(theta, q2, 6, 1e-3, &below, &above);
    TEST_ASSERT(c >= 0.2 && c <= 0.4);
    /* one transporting point: the middle of the bracket */
    double t3[3] = {0.1, 0.2, 0.4}, q3[3] = {0.0, 1e-4, 0.02};
    TEST_NEAR(app_sediment_threshold(t3, q3, 3, 1e-3, &below, &above), 0.3, 1e-12);
    /* nothing transports, or everything does: no estimate */
    double q4[3] = {0.0, 1e-4, 2e-4}, q5[3] = {0.01, 0.02, 0.05};
    TEST_ASSERT(isnan(app_sediment_threshold(t3, q4, 3, 1e-3, &below, &above)));
    TEST_ASSERT(isnan(app_sediment_threshold(t3, q5, 3, 1e-3, &below, &above)));
    TEST_NEAR(above, 0.1, 0.0);
    return 0;
}

TEST_MAIN(TEST_CASE(numbers_from_scene), TEST_CASE(fluid_needs_effect),
          TEST_CASE(fluid_is_an_alias), TEST_CASE(below_threshold), TEST_CASE(saturation_measure),
          TEST_CASE(shields_threshold))
