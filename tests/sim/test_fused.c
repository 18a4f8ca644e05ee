/* SPDX-License-Identifier: MIT */
/* The fused drift (sim/isa/contact_pass.c, fused_pass): on one thread the velocity-Verlet drift
 * runs inside the contact pass. It must make the same operations as the separate passes: the
 * same grains, forces and contact history to the bit, with steps where a grain passes the
 * rebuild threshold in the middle of the pass (which must then leave the history as it was). */
#include "sim_test_util.h"
#include "test.h"

#include "sim/internal.h"

#include <string.h>

static SimWorld *make(SimTangentialLaw tangential, SimRollingLaw rolling, SimGrainBuffer *b)
{
    static const SimWall box[3] = {{.x0 = 0.0, .y0 = 0.0, .x1 = 2.0, .y1 = 0.0, .motion = -1},
                                   {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 3.0, .motion = -1},
                                   {.x0 = 2.0, .y0 = 0.0, .x1 = 2.0, .y1 = 3.0, .motion = -1}};
    tu_rain_150(b, 11, 0.2);
    for (int k = 0; k < b->count; ++k)
        b->omega[k] = (double)(k % 7 - 3) * 2.0;
    sim_build_fixed_row(b, 0.025, 1.975, 0.025, 0.025, 0, -1); /* fixed partners of the list */
    SimWorldDef def = tu_def(1000.0, 1e5, 0.0);
    def.steps_per_contact = 50.0;
    def.gravity_y = -G0;
    def.effects = SIM_EFFECT_FRICTION | (rolling != SIM_ROLLING_OFF ? SIM_EFFECT_ROLLING : 0u);
    def.contact.tangential = tangential;
    def.contact.rolling = rolling;
    SimMaterial *m = &def.materials[0];
    m->friction = 0.5;
    m->tangential_stiffness = 0.75e5;
    m->damping_mode = SIM_DAMPING_RESTITUTION;
    m->restitution = 0.5;
    m->rolling_friction = 0.002;
    m->rolling_stiffness = 5.0;
    def.wall_count = 3;
    def.walls = box;
    return tu_create(&def, b);
}

#define SAME(a, b, n) (memcmp((a), (b), (size_t)(n) * sizeof *(a)) == 0)

/* One world fused, one with the separate passes, stepped in batches (so that the closing kick is
 * deferred into the next drift, as in a run); compared after every batch. */
static int same_as_separate(SimTangentialLaw tangential, SimRollingLaw rolling)
{
    SimGrainBuffer b1, b2;
    SimWorld *fused = make(tangential, rolling, &b1), *plain = make(tangential, rolling, &b2);
    TEST_ASSERT(fused && plain);
    plain->fused_pass = NULL;
    for (int batch = 0; batch < 40; ++batch) {
        TEST_ASSERT(tu_step(fused, 75) == 0);
        TEST_ASSERT(tu_step(plain, 75) == 0);
        TEST_ASSERT(sim_world_hash(fused) == sim_world_hash(plain));
        const int n = fused->count, entries = fused->nl.start[fused->mobile_count];
        TEST_ASSERT(n == plain->count && entries == plain->nl.start[plain->mobile_count]);
        TEST_ASSERT(SAME(fused->fx, plain->fx, n) && SAME(fused->fy, plain->fy, n));
        TEST_ASSERT(SAME(fused->torque, plain->torque, n));
        TEST_ASSERT(SAME(fused->nl.j, plain->nl.j, entries));
        TEST_ASSERT(SAME(fused->nl.hist_t, plain->nl.hist_t, entries));
        TEST_ASSERT(SAME(fused->nl.hist_r, plain->nl.hist_r, entries));
    }
    /* the path under test ran, and met rebuilds found mid-pass */
    TEST_ASSERT(fused->fused_steps > 2000 && fused->fused_trips > 3);
    TEST_ASSERT(plain->fused_steps == 0);
    SimEnergy e = sim_world_energy(fused);
    TEST_ASSERT(e.contacts > 100);
    sim_world_destroy(fused);
    sim_world_destroy(plain);
    sim_grain_buffer_free(&b1);
    sim_grain_buffer_free(&b2);
    return 0;
}

static int spring(void)
{
    return same_as_separate(SIM_TANGENTIAL_SPRING, SIM_ROLLING_OFF);
}

static int spring_rolling(void)
{
    return same_as_separate(SIM_TANGENTIAL_SPRING, SIM_ROLLING_FIXED);
}

static int regularised_rolling(void)
{
    return same_as_separate(SIM_TANGENTIAL_REGULARISED, SIM_ROLLING_CHORD);
}

/* Two threads take the separate passes (the fused one is for one thread) with the same bits. */
static int threads_not_fused(void)
{
    SimGrainBuffer b1, b2;
    SimWorld *one = make(SIM_TANGENTIAL_SPRING, SIM_ROLLING_OFF, &b1);
    SimWorld *two = make(SIM_TANGENTIAL_SPRING, SIM_ROLLING_OFF, &b2);
    TEST_ASSERT(one && two);
    sim_world_set_threads(two, 2);
    TEST_ASSERT(tu_step(one, 1500) == 0 && tu_step(two, 1500) == 0);
    TEST_ASSERT(sim_world_hash(one) == sim_world_hash(two));
    TEST_ASSERT(one->fused_steps > 1000 && two->fused_steps == 0);
    sim_world_destroy(one);
    sim_world_destroy(two);
    sim_grain_buffer_free(&b1);
    sim_grain_buffer_free(&b2);
    return 0;
}

TEST_MAIN(TEST_CASE(spring), TEST_CASE(spring_rolling), TEST_CASE(regularised_rolling),
          TEST_CASE(threads_not_fused))
