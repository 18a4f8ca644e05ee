/* SPDX-License-Identifier: MIT */
/* test_advice.c: dt advice (app/scene/advice.h): the advised time step, run, meets the target error
 * in e_n; time.target_error chooses it at load and excludes dt and steps_per_contact. */
#include "test.h"

#include "app/scene/advice.h"
#include "app/scene/scene.h"
#include "sim/sim_test_util.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Two equal mobile disks of the thesis 000 material, e_n given. */
static SimWorldDef pair_def(double e, SimOnset onset, SimGrainBuffer *b)
{
    SimWorldDef def = tu_def(1190.0, 7e5, 0.0);
    def.mass_model = SIM_MASS_SPHERE;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = e;
    def.contact.clip_tensile = 0;
    def.contact.onset = onset;
    sim_grain_buffer_init(b);
    sim_grain_buffer_add(b, 0.0, 0.0, 0.08, 0, 0u, -1);
    sim_grain_buffer_add(b, 1.0, 0.0, 0.08, 0, 0u, -1);
    def.grains = sim_grain_buffer_view(b);
    return def;
}

/* The advised dt, run on a head-on impact of the stiffest pair (worst of 16 phases at dt and
 * slightly below), meets the target; for both onset options and three e_n. */
static int advised_dt_meets_target(void)
{
    const double es[] = {0.2, 0.5, 0.9}, target = 1e-3;
    for (int q = 0; q < 3; ++q)
        for (int o = 0; o < 2; ++o) {
            SimGrainBuffer b;
            SimWorldDef def = pair_def(es[q], o ? SIM_ONSET_EVENT : SIM_ONSET_STEP, &b);
            AppAdvice a;
            char err[256];
            TEST_ASSERT(app_dt_advice(&def, 2, target, &a, err, sizeof err) == 0);
            TEST_REL(a.restitution, es[q], 1e-9);
            TEST_REL(a.time_step * a.steps_per_contact, a.contact_time, 1e-12);
            TEST_REL(a.c / pow(a.steps_per_contact, a.p), target, 1e-9);
            double worst = 0.0;
            for (int k = 0; k < 16; ++k) {
                SimWorldDef d = def;
                d.time_step = a.contact_time / (a.steps_per_contact + 0.25 * (k / 4));
                TuCollision c = {TU_PAIR, 0.08, 0.08, 1.0, 3.0 + 0.25 * (k % 4) + 0.1, 100000};
                TuCollisionResult res;
                TEST_ASSERT(tu_collide(d, &c, &res) == 0);
                worst = fmax(worst, fabs(res.e - es[q]));
            }
            if (worst > target)
                fprintf(stderr, "e_n %g onset %d: n %g, worst error %g > %g\n", es[q], o,
                        a.steps_per_contact, worst, target);
            TEST_ASSERT(worst <= target);
            sim_grain_buffer_free(&b);
        }
    return 0;
}

/* The event onset needs far fewer steps for the same target; bad targets are refused. */
static int event_needs_fewer_steps(void)
{
    SimGrainBuffer b;
    SimWorldDef step = pair_def(0.5, SIM_ONSET_STEP, &b), event = step;
    event.contact.onset = SIM_ONSET_EVENT;
    AppAdvice a, e;
    char err[256];
    TEST_ASSERT(app_dt_advice(&step, 1000, 1e-4, &a, err, sizeof err) == 0);
    TEST_ASSERT(app_dt_advice(&event, 1000, 1e-4, &e, err, sizeof err) == 0);
    TEST_ASSERT(e.steps_per_contact * 10.0 < a.steps_per_contact);
    TEST_ASSERT(e.cpu_per_sim_s < a.cpu_per_sim_s);
    TEST_REL(a.cpu_per_sim_s, a.ns_per_particle_step * 1e-9 * 1000 / a.time_step, 1e-12);
    TEST_ASSERT(app_dt_advice(&step, 2, 0.0, &a, err, sizeof err) != 0);
    TEST_ASSERT(strstr(err, "(0, 0.5)") != NULL);
    sim_grain_buffer_free(&b);
    return 0;
}

static const char scene_head[] = "name = \"advice\";\nseed = 1;\nmass_model = \"sphere\";\n"
                                 "effects = [];\ngravity = [0.0, -9.806];\n";
static const char scene_tail[] =
    "species = ( { name = \"g\"; density = 1190.0; k_n = 7e5; restitution = 0.5; } );\n"
    "grains = { list = ( { x = 0.0; y = 1.0; r = 0.08; },\n"
    "                    { x = 0.0; y = 0.5; r = 0.105; fixed = true; } ); };\n";

/* Writes head + time group + tail to dir/name; the path in path. */
static int write_scene(const char *dir, const char *time_group, char *path, size_t size)
{
    snprintf(path, size, "%s/advice.scene", dir);
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fprintf(f, "%s%s%s", scene_head, time_group, scene_tail);
    return fclose(f);
}

/* time.target_error sets steps_per_contact (dt = 0) as the advice computes it; with dt or
 * steps_per_contact it is refused at its line. */
static int scene_target_error(void)
{
    char dir[] = "/tmp/sablier_advice_XXXXXX", path[256], err[2048];
    TEST_ASSERT(mkdtemp(dir) != NULL);
    TEST_ASSERT(
        write_scene(dir, "time = { target_error = 1e-3; end = 0.01; };\n", path, sizeof path) == 0);
    Scene *s = scene_load(path, NULL, 0, err, sizeof err);
    TEST_ASSERT(s != NULL);
    TEST_ASSERT(s->def.time_step == 0.0 && s->target_error == 1e-3);
    SimWorldDef def = scene_world_def(s, 0);
    AppAdvice a;
    TEST_ASSERT(app_dt_advice(&def, 1, 1e-3, &a, err, sizeof err) == 0);
    TEST_ASSERT(s->def.steps_per_contact == a.steps_per_contact);
    SimTiming t = sim_world_def_timing(&def);
    TEST_REL(t.time_step, a.time_step, 1e-12);
    scene_free(s);
    static const char *const bad[][2] = {
        {"time = { dt = 1e-5; target_error = 1e-3; end = 0.01; };\n", "remove `dt`"},
        {"time = { steps_per_contact = 80; target_error = 1e-3; end = 0.01; };\n",
         "remove `steps_per_contact`"},
        {"time = { target_error = 0.7; end = 0.01; };\n", "must be in (0, 0.5)"}};
    for (int k = 0; k < 3; ++k) {
        TEST_ASSERT(write_scene(dir, bad[k][0], path, sizeof path) == 0);
        TEST_ASSERT(scene_load(path, NULL, 0, err, sizeof err) == NULL);
        TEST_ASSERT(strstr(err, bad[k][1]) != NULL);
        char where[300];
        snprintf(where, sizeof where, "%s:6:", path); /* the time group's line */
        TEST_ASSERT(strstr(err, where) == err);
    }
    unlink(path);
    rmdir(dir);
    return 0;
}

TEST_MAIN(TEST_CASE(advised_dt_meets_target), TEST_CASE(event_needs_fewer_steps),
          TEST_CASE(scene_target_error))
