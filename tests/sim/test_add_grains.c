/* SPDX-License-Identifier: MIT */
/* Adding grains to a running world (rain-like deposition, 004 §3.1): counts and ids, contact
 * history carried over, refusals (overlap, duplicate id), the same bits on any thread count. */
#include "sim_test_util.h"
#include "test.h"

#include "sim/sim.h"

#include <math.h>
#include <stdio.h>

/* A row of grains resting on a floor wall with the tangential spring, pushed sideways by a tilted
 * gravity so that every floor contact holds a tangential stretch. */
static SimWorld *make_world(void)
{
    static const SimWall floor_ = {
        .x0 = -10.0, .y0 = 0.0, .x1 = 10.0, .y1 = 0.0, .species = 0, .motion = -1};
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    for (int k = 0; k < 5; ++k)
        sim_grain_buffer_add(&b, 0.3 * k, 0.1, 0.1, 0, 0u, -1);
    SimWorldDef def = sim_world_def_default();
    def.effects = SIM_EFFECT_FRICTION;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.materials[0].density = 1000.0;
    def.materials[0].normal_stiffness = 1e5;
    def.materials[0].tangential_stiffness = 7.5e4;
    def.materials[0].damping_mode = SIM_DAMPING_CRITICAL;
    def.materials[0].critical_fraction = 0.5;
    def.materials[0].friction = 0.5;
    def.gravity_x = 2.0; /* tan = 0.2 < mu: sticks with a stretched spring */
    def.time_step = 1e-4;
    def.wall_count = 1;
    def.walls = &floor_;
    def.grains = sim_grain_buffer_view(&b);
    SimError err;
    SimWorld *w = sim_world_create(&def, &err);
    sim_grain_buffer_free(&b);
    if (w && sim_world_step(w, 5000, &err) != SIM_OK) {
        sim_world_destroy(w);
        return NULL;
    }
    return w;
}

static double tangential_of(SimWorld *w, uint32_t id)
{
    SimFrame f;
    sim_world_frame(w, &f);
    for (int c = 0; c < f.contact_count; ++c)
        if (f.contacts[c].j < 0 && f.id[f.contacts[c].i] == id)
            return f.contacts[c].tangential_force;
    return NAN;
}

static int add_keeps_history_and_ids(void)
{
    SimWorld *w = make_world();
    TEST_ASSERT(w);
    double before = tangential_of(w, 2);
    TEST_ASSERT(fabs(before) > 1.0); /* stretched spring: about m g_x */
    double x[3] = {0.0, 0.3, 0.6}, y[3] = {1.0, 1.0, 1.0}, r[3] = {0.1, 0.1, 0.1};
    SimGrainSet add = {.count = 3, .x = x, .y = y, .radius = r};
    SimError err;
    TEST_ASSERT(sim_world_add_grains(w, &add, &err) == SIM_OK);
    TEST_ASSERT(sim_world_mobile_count(w) == 8);
    TEST_NEAR(tangential_of(w, 2), before, 1e-9 * fabs(before));
    SimFrame f;
    sim_world_frame(w, &f);
    int fresh = 0;
    for (int i = 0; i < f.count; ++i)
        fresh += f.id[i] >= 5 && f.id[i] <= 7;
    TEST_ASSERT(fresh == 3);
    TEST_ASSERT(sim_world_step(w, 8000, &err) == SIM_OK); /* 0.8 s: the newcomers land */
    SimEnergy e = sim_world_energy(w);
    TEST_ASSERT(e.contacts >= 8);
    sim_world_destroy(w);
    return 0;
}

static int add_refuses_overlap_and_duplicate_id(void)
{
    SimWorld *w = make_world();
    TEST_ASSERT(w);
    double x[1] = {0.3}, y[1] = {0.1}, r[1] = {0.1};
    SimGrainSet on_top = {.count = 1, .x = x, .y = y, .radius = r};
    SimError err;
    TEST_ASSERT(sim_world_add_grains(w, &on_top, &err) == SIM_ERROR_INVALID);
    double y2[1] = {2.0};
    uint32_t id[1] = {3};
    SimGrainSet dup = {.count = 1, .x = x, .y = y2, .radius = r, .id = id};
    TEST_ASSERT(sim_world_add_grains(w, &dup, &err) == SIM_ERROR_INVALID);
    TEST_ASSERT(strstr(err.message, "already in use") != NULL);
    TEST_ASSERT(sim_world_mobile_count(w) == 5);
    sim_world_destroy(w);
    return 0;
}

/* A world that starts with small fixed grains alone (a base, as the discharge deposition builds):
 * its automatic skin's range follows the mobile grains once they are added (0.2 of their mean
 * diameter at most), not the base's size. */
static int auto_skin_follows_added_grains(void)
{
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    for (int k = 0; k < 40; ++k) /* base of 0.01 m grains */
        sim_grain_buffer_add(&b, 0.01 + 0.02 * k, 0.01, 0.01, 0, SIM_GRAIN_FIXED, -1);
    SimWorldDef def = sim_world_def_default();
    def.materials[0].density = 1000.0;
    def.materials[0].normal_stiffness = 1e5;
    def.time_step = 1e-5;
    def.grains = sim_grain_buffer_view(&b);
    SimError err;
    SimWorld *w = sim_world_create(&def, &err);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    TEST_ASSERT(sim_world_skin(w) <= 0.2 * 0.02 + 1e-12); /* only the base to go by */
    /* thrown down at 5 m/s: 0.05 mm per step, a skin above the base's range pays */
    double x[4] = {0.1, 0.3, 0.5, 0.7}, y[4] = {0.5, 0.5, 0.5, 0.5}, r[4] = {0.1, 0.1, 0.1, 0.1};
    double vx[4] = {0.0, 0.0, 0.0, 0.0}, vy[4] = {-5.0, -5.0, -5.0, -5.0};
    SimGrainSet add = {.count = 4, .x = x, .y = y, .radius = r, .vx = vx, .vy = vy};
    TEST_ASSERT(sim_world_add_grains(w, &add, &err) == SIM_OK);
    TEST_ASSERT(sim_world_step(w, 2000, &err) == SIM_OK); /* 0.1 m down, still in the air */
    fprintf(stderr, "skin after 2000 steps: %g m\n", sim_world_skin(w));
    TEST_ASSERT(sim_world_skin(w) > 0.2 * 0.02 + 1e-12); /* beyond the base's range */
    TEST_ASSERT(sim_world_skin(w) <= 0.2 * 0.2 + 1e-12); /* within the newcomers' */
    sim_world_destroy(w);
    return 0;
}

/* One batch of `rows` rows of 16 grains (radius 0.045-0.054 m, 0.11 m apart) just above the
 * highest grain of the pile, falling at 1 m/s onto it. */
static SimStatus add_batch(SimWorld *w, int rows, int batch, SimError *err)
{
    enum { COLUMNS = 16, MAX_ROWS = 8 };

    double x[COLUMNS * MAX_ROWS], y[COLUMNS * MAX_ROWS], r[COLUMNS * MAX_ROWS];
    double vx[COLUMNS * MAX_ROWS], vy[COLUMNS * MAX_ROWS];
    SimFrame f;
    sim_world_frame(w, &f);
    double top = 0.0;
    for (int i = 0; i < f.count; ++i)
        top = fmax(top, f.y[i] + f.radius[i]);
    int n = 0;
    for (int row = 0; row < rows && row < MAX_ROWS; ++row)
        for (int c = 0; c < COLUMNS; ++c, ++n) {
            x[n] = 0.15 + 0.11 * c + 0.01 * (row % 2);
            y[n] = top + 0.06 + 0.11 * row;
            r[n] = 0.045 + 0.001 * ((7 * n + 3 * batch) % 10);
            vx[n] = 0.0;
            vy[n] = -1.0;
        }
    SimGrainSet add = {.count = n, .x = x, .y = y, .radius = r, .vx = vx, .vy = vy};
    return sim_world_add_grains(w, &add, err);
}

/* The contact pass's per-entry buffers (the threaded transpose and results, whose stride is the
 * list's capacity) follow the list as grains are added mid-run: batches of grains dropped onto a
 * dense pile on 1, 2, 3 and 8 threads give one thread's bits, and nothing is written out of
 * bounds (the sanitizer build ran a heap-buffer-overflow here: the list grew with the mobile
 * count while the results kept their old size). */
static int add_on_threads_same_hash(void)
{
    static const SimWall walls[3] = {
        {.x0 = 0.0, .y0 = 0.0, .x1 = 2.0, .y1 = 0.0, .species = 0, .motion = -1},
        {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 9.0, .species = 0, .motion = -1},
        {.x0 = 2.0, .y0 = 0.0, .x1 = 2.0, .y1 = 9.0, .species = 0, .motion = -1}};
    static const int threads[4] = {1, 2, 3, 8};
    static const int rows[5] = {1, 4, 8, 2, 8};
    uint64_t hash[4];
    for (int run = 0; run < 4; ++run) {
        SimGrainBuffer b;
        tu_rain_150(&b, 5, 0.06);
        SimWorldDef def = tu_def(1000.0, 1e5, 0.0);
        def.steps_per_contact = 40.0;
        def.gravity_y = -G0;
        def.effects |= SIM_EFFECT_FRICTION | SIM_EFFECT_ROLLING;
        def.contact.tangential = SIM_TANGENTIAL_SPRING;
        def.contact.rolling = SIM_ROLLING_FIXED; /* every per-entry result in use */
        def.materials[0].friction = 0.5;
        def.materials[0].tangential_stiffness = 0.75e5;
        def.materials[0].rolling_friction = 0.005;
        def.materials[0].rolling_stiffness = 25.0;
        def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
        def.materials[0].restitution = 0.3;
        def.wall_count = 3;
        def.walls = walls;
        SimWorld *w = tu_create(&def, &b);
        sim_grain_buffer_free(&b);
        TEST_ASSERT(w != NULL);
        sim_world_set_threads(w, threads[run]);
        TEST_ASSERT(tu_step(w, 2500) == 0); /* the rain lands: a pile in contact */
        TEST_ASSERT(sim_world_energy(w).contacts > 120);
        SimError err;
        for (int batch = 0; batch < 5; ++batch) {
            TEST_ASSERT(add_batch(w, rows[batch], batch, &err) == SIM_OK);
            TEST_ASSERT(tu_step(w, 200) == 0);
        }
        TEST_ASSERT(sim_world_mobile_count(w) == 150 + 16 * 23);
        hash[run] = sim_world_hash(w);
        fprintf(stderr, "%d threads: hash %016llx, %d contacts\n", threads[run],
                (unsigned long long)hash[run], sim_world_energy(w).contacts);
        sim_world_destroy(w);
    }
    for (int run = 1; run < 4; ++run)
        TEST_ASSERT(hash[run] == hash[0]);
    return 0;
}

TEST_MAIN(TEST_CASE(add_keeps_history_and_ids), TEST_CASE(add_refuses_overlap_and_duplicate_id),
          TEST_CASE(auto_skin_follows_added_grains), TEST_CASE(add_on_threads_same_hash))
