/* SPDX-License-Identifier: MIT */
/* Grains written in place (sim_world_set_grains): positions, velocities and radii by id or in
 * frame order, a grain made fixed and set free again, refusals that change nothing. */
#include "test.h"

#include "sim/sim.h"

#include <math.h>
#include <stdio.h>

/* Five grains of radius 0.1 m in a row over a floor wall, falling under gravity. */
static SimWorld *make_world(void)
{
    static const SimWall floor_ = {
        .x0 = -10.0, .y0 = 0.0, .x1 = 10.0, .y1 = 0.0, .species = 0, .motion = -1};
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    for (int k = 0; k < 5; ++k)
        sim_grain_buffer_add(&b, 0.3 * k, 0.5, 0.1, 0, 0u, -1);
    SimWorldDef def = sim_world_def_default();
    def.materials[0].density = 1000.0;
    def.materials[0].normal_stiffness = 1e5;
    def.materials[0].damping_mode = SIM_DAMPING_CRITICAL;
    def.materials[0].critical_fraction = 0.5;
    def.time_step = 1e-4;
    def.wall_count = 1;
    def.walls = &floor_;
    def.grains = sim_grain_buffer_view(&b);
    SimError err;
    SimWorld *w = sim_world_create(&def, &err);
    sim_grain_buffer_free(&b);
    return w;
}

/* Frame index of grain `id`, or -1. */
static int index_of(SimWorld *w, uint32_t id)
{
    SimFrame f;
    sim_world_frame(w, &f);
    for (int i = 0; i < f.count; ++i)
        if (f.id[i] == id)
            return i;
    return -1;
}

static int set_by_id_writes_positions_velocities_radii(void)
{
    SimWorld *w = make_world();
    TEST_ASSERT(w);
    SimError err;
    const uint32_t ids[2] = {1, 3};
    const double x[2] = {5.0, 6.0}, y[2] = {2.0, 3.0}, vx[2] = {1.5, -2.0}, vy[2] = {0.0, 4.0};
    const double radius[2] = {0.05, 0.2};
    SimGrainSet v = {.count = 2, .id = ids, .x = x, .y = y, .vx = vx, .vy = vy, .radius = radius};
    TEST_ASSERT(sim_world_set_grains(w, &v, &err) == SIM_OK);
    SimFrame f;
    sim_world_frame(w, &f);
    int i = index_of(w, 3);
    sim_world_frame(w, &f);
    TEST_ASSERT(f.x[i] == 6.0 && f.y[i] == 3.0 && f.vx[i] == -2.0 && f.vy[i] == 4.0);
    TEST_ASSERT(f.radius[i] == 0.2);
    double mass[5];
    sim_world_masses(w, mass);
    TEST_REL(mass[i], 1000.0 * SIM_PI * 0.2 * 0.2, 1e-15); /* disk mass model (default) */
    /* one step of free fall from the new velocity: v_y = 4 - g dt */
    TEST_ASSERT(sim_world_step(w, 1, &err) == SIM_OK);
    i = index_of(w, 3);
    sim_world_frame(w, &f);
    TEST_REL(f.vy[i], 4.0 - 9.806 * 1e-4, 1e-12);
    TEST_REL(f.x[i], 6.0 - 2.0 * 1e-4, 1e-12);
    sim_world_destroy(w);
    return 0;
}

static int set_all_in_frame_order(void)
{
    SimWorld *w = make_world();
    TEST_ASSERT(w);
    SimError err;
    double vx[5] = {0}, vy[5] = {1, 1, 1, 1, 1};
    SimGrainSet v = {.count = 5, .vx = vx, .vy = vy};
    TEST_ASSERT(sim_world_set_grains(w, &v, &err) == SIM_OK);
    SimFrame f;
    sim_world_frame(w, &f);
    for (int i = 0; i < 5; ++i)
        TEST_ASSERT(f.vy[i] == 1.0);
    v.count = 4; /* without ids every grain is written */
    TEST_ASSERT(sim_world_set_grains(w, &v, &err) == SIM_ERROR_INVALID);
    TEST_ASSERT(strcmp(err.field, "grains.count") == 0);
    sim_world_destroy(w);
    return 0;
}

static int fixed_flag_stops_and_frees(void)
{
    SimWorld *w = make_world();
    TEST_ASSERT(w);
    SimError err;
    const uint32_t id = 0;
    const unsigned fixed = SIM_GRAIN_FIXED, free_ = 0u;
    SimGrainSet v = {.count = 1, .id = &id, .flags = &fixed};
    TEST_ASSERT(sim_world_step(w, 100, &err) == SIM_OK);
    TEST_ASSERT(sim_world_set_grains(w, &v, &err) == SIM_OK);
    TEST_ASSERT(sim_world_mobile_count(w) == 4);
    int i = index_of(w, 0);
    TEST_ASSERT(i == 4); /* fixed grains last */
    SimFrame f;
    sim_world_frame(w, &f);
    const double y0 = f.y[i];
    TEST_ASSERT(f.vy[i] == 0.0 && (f.flags[i] & SIM_GRAIN_FIXED));
    TEST_ASSERT(sim_world_step(w, 1000, &err) == SIM_OK);
    i = index_of(w, 0);
    sim_world_frame(w, &f);
    TEST_ASSERT(f.y[i] == y0); /* held while the others fall */
    v.flags = &free_;
    TEST_ASSERT(sim_world_set_grains(w, &v, &err) == SIM_OK);
    TEST_ASSERT(sim_world_mobile_count(w) == 5);
    TEST_ASSERT(sim_world_step(w, 100, &err) == SIM_OK);
    i = index_of(w, 0);
    sim_world_frame(w, &f);
    TEST_ASSERT(f.y[i] < y0); /* falls again */
    sim_world_destroy(w);
    return 0;
}

static int refusals_change_nothing(void)
{
    SimWorld *w = make_world();
    TEST_ASSERT(w);
    SimError err;
    uint64_t before = sim_world_hash(w);
    const uint32_t missing = 99, one = 1;
    const double x = 1.0, y = NAN, r0 = 0.0, r_tiny = 1e-5;
    const unsigned odd = 4u;
    SimGrainSet v = {.count = 1, .id = &missing, .x = &x, .y = &x};
    TEST_ASSERT(sim_world_set_grains(w, &v, &err) == SIM_ERROR_INVALID);
    TEST_ASSERT(strcmp(err.field, "grains.id[0]") == 0);
    v = (SimGrainSet){.count = 1, .id = &one, .x = &x, .y = &y};
    TEST_ASSERT(sim_world_set_grains(w, &v, &err) == SIM_ERROR_INVALID);
    TEST_ASSERT(strcmp(err.field, "grains.y[0]") == 0);
    v = (SimGrainSet){.count = 1, .id = &one, .x = &x};
    TEST_ASSERT(sim_world_set_grains(w, &v, &err) == SIM_ERROR_INVALID);
    v = (SimGrainSet){.count = 1, .id = &one, .radius = &r0};
    TEST_ASSERT(sim_world_set_grains(w, &v, &err) == SIM_ERROR_INVALID);
    v = (SimGrainSet){.count = 1, .id = &one, .flags = &odd};
    TEST_ASSERT(sim_world_set_grains(w, &v, &err) == SIM_ERROR_INVALID);
    v = (SimGrainSet){.count = 1, .id = &one, .radius = &r_tiny}; /* t_c far below dt */
    TEST_ASSERT(sim_world_set_grains(w, &v, &err) == SIM_ERROR_INVALID);
    TEST_ASSERT(strstr(err.message, "stability limit") != NULL);
    TEST_ASSERT(sim_world_hash(w) == before);
    sim_world_destroy(w);
    return 0;
}

TEST_MAIN(TEST_CASE(set_by_id_writes_positions_velocities_radii), TEST_CASE(set_all_in_frame_order),
          TEST_CASE(fixed_flag_stops_and_frees), TEST_CASE(refusals_change_nothing))
