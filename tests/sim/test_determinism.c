/* SPDX-License-Identifier: MIT */
/* Determinism: the same seed gives the same grains and the same state hash in two independent
 * worlds; a different seed a different hash; splitting a run into pieces changes nothing. */
#include "sim_test_util.h"
#include "test.h"

#include <string.h>

static void build(SimGrainBuffer *b, uint64_t seed)
{
    tu_rain_150(b, seed, 0.15);
}

static SimWorld *make(uint64_t seed, SimGrainBuffer *b)
{
    static const SimWall walls[3] = {
        {.x0 = 0.0, .y0 = 0.0, .x1 = 2.0, .y1 = 0.0, .species = 0, .motion = -1},
        {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 3.0, .species = 0, .motion = -1},
        {.x0 = 2.0, .y0 = 0.0, .x1 = 2.0, .y1 = 3.0, .species = 0, .motion = -1}};
    build(b, seed);
    SimWorldDef def = tu_def(1000.0, 1e5, 0.0);
    def.time_step = 0.0; /* from steps_per_contact */
    def.steps_per_contact = 50.0;
    def.gravity_y = -G0;
    def.effects |= SIM_EFFECT_FRICTION;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.materials[0].friction = 0.5;
    def.materials[0].tangential_stiffness = 0.75e5;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.5;
    def.wall_count = 3;
    def.walls = walls;
    return tu_create(&def, b);
}

static int same_seed_same_hash(void)
{
    SimGrainBuffer b1, b2;
    SimWorld *w1 = make(42, &b1), *w2 = make(42, &b2);
    TEST_ASSERT(w1 && w2);
    TEST_ASSERT(b1.count == b2.count && b1.count > 100);
    TEST_ASSERT(memcmp(b1.x, b2.x, sizeof(double) * (size_t)b1.count) == 0);
    TEST_ASSERT(memcmp(b1.radius, b2.radius, sizeof(double) * (size_t)b1.count) == 0);
    uint64_t h0 = sim_world_hash(w1);
    TEST_ASSERT(h0 == sim_world_hash(w2));
    TEST_ASSERT(tu_step(w1, 2000) == 0);
    TEST_ASSERT(tu_step(w2, 2000) == 0);
    TEST_ASSERT(sim_world_hash(w1) == sim_world_hash(w2));
    TEST_ASSERT(sim_world_hash(w1) != h0); /* the hash sees motion */
    SimEnergy e = sim_world_energy(w1);
    TEST_ASSERT(e.contacts > 50); /* the grains have landed and interact */
    sim_world_destroy(w1);
    sim_world_destroy(w2);
    sim_grain_buffer_free(&b1);
    sim_grain_buffer_free(&b2);
    return 0;
}

static int different_seed_different_hash(void)
{
    SimGrainBuffer b1, b2;
    SimWorld *w1 = make(42, &b1), *w2 = make(43, &b2);
    TEST_ASSERT(w1 && w2);
    TEST_ASSERT(sim_world_hash(w1) != sim_world_hash(w2));
    TEST_ASSERT(tu_step(w1, 500) == 0);
    TEST_ASSERT(tu_step(w2, 500) == 0);
    TEST_ASSERT(sim_world_hash(w1) != sim_world_hash(w2));
    sim_world_destroy(w1);
    sim_world_destroy(w2);
    sim_grain_buffer_free(&b1);
    sim_grain_buffer_free(&b2);
    return 0;
}

/* step(2000) == step(700) + step(1) + step(1299), and frames in between change nothing. */
static int split_steps_same_hash(void)
{
    SimGrainBuffer b1, b2;
    SimWorld *w1 = make(7, &b1), *w2 = make(7, &b2);
    TEST_ASSERT(w1 && w2);
    TEST_ASSERT(tu_step(w1, 2000) == 0);
    SimFrame f;
    TEST_ASSERT(tu_step(w2, 700) == 0);
    sim_world_frame(w2, &f);
    (void)sim_world_energy(w2);
    TEST_ASSERT(tu_step(w2, 1) == 0);
    sim_world_frame(w2, &f);
    TEST_ASSERT(tu_step(w2, 1299) == 0);
    TEST_ASSERT(sim_world_step_count(w1) == sim_world_step_count(w2));
    TEST_ASSERT(sim_world_hash(w1) == sim_world_hash(w2));
    sim_world_destroy(w1);
    sim_world_destroy(w2);
    sim_grain_buffer_free(&b1);
    sim_grain_buffer_free(&b2);
    return 0;
}

/* The RNG itself: same seed, same stream; uniform in [0, 1). */
static int rng_stream(void)
{
    SimRng a, b;
    sim_rng_seed(&a, 123);
    sim_rng_seed(&b, 123);
    double sum = 0.0;
    for (int k = 0; k < 10000; ++k) {
        TEST_ASSERT(sim_rng_next(&a) == sim_rng_next(&b));
        double u = sim_rng_uniform(&a);
        (void)sim_rng_uniform(&b);
        TEST_ASSERT(u >= 0.0 && u < 1.0);
        sum += u;
    }
    TEST_NEAR(sum / 10000.0, 0.5, 0.02);
    sim_rng_seed(&b, 124);
    sim_rng_seed(&a, 123);
    TEST_ASSERT(sim_rng_next(&a) != sim_rng_next(&b));
    return 0;
}

/* Event-aware onset (SIM_ONSET_EVENT): the same bits on 1 and 3 threads and with every supported
 * instruction set, and not the step onset's bits (the option acts). Runs 3.. use the sets. */
static const SimIsa isas[] = {SIM_ISA_BASELINE, SIM_ISA_AVX2, SIM_ISA_AVX512};

static int event_onset_threads_same_hash(void)
{
    uint64_t hashes[6];
    const SimIsa before = sim_isa();
    for (int run = 0; run < 6; ++run) {
        if (run >= 3 && sim_isa_set(isas[run - 3]) != SIM_OK) {
            hashes[run] = 0; /* not compiled in or not on this CPU */
            continue;
        }
        SimGrainBuffer b;
        tu_rain_150(&b, 11, 0.15);
        static const SimWall walls[3] = {
            {.x0 = 0.0, .y0 = 0.0, .x1 = 2.0, .y1 = 0.0, .species = 0, .motion = -1},
            {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 3.0, .species = 0, .motion = -1},
            {.x0 = 2.0, .y0 = 0.0, .x1 = 2.0, .y1 = 3.0, .species = 0, .motion = -1}};
        SimWorldDef def = tu_def(1000.0, 1e5, 0.0);
        def.time_step = 0.0;
        def.steps_per_contact = 50.0;
        def.gravity_y = -G0;
        def.effects |= SIM_EFFECT_FRICTION;
        def.materials[0].friction = 0.5;
        def.materials[0].tangential_damping = 10.0;
        def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
        def.materials[0].restitution = 0.5;
        def.contact.onset = run == 2 ? SIM_ONSET_STEP : SIM_ONSET_EVENT;
        def.wall_count = 3;
        def.walls = walls;
        SimWorld *w = tu_create(&def, &b);
        TEST_ASSERT(w != NULL);
        sim_world_set_threads(w, run == 1 ? 3 : 1);
        TEST_ASSERT(tu_step(w, 2000) == 0);
        TEST_ASSERT(sim_world_energy(w).contacts > 50);
        hashes[run] = sim_world_hash(w);
        sim_world_destroy(w);
        sim_grain_buffer_free(&b);
    }
    TEST_ASSERT(sim_isa_set(before) == SIM_OK);
    TEST_ASSERT(hashes[0] == hashes[1]);
    TEST_ASSERT(hashes[0] != hashes[2]);
    for (int run = 3; run < 6; ++run)
        TEST_ASSERT(hashes[run] == 0 || hashes[run] == hashes[0]);
    return 0;
}

/* The run guard on threads (world.c guard_check, guard_snapshot): its scans and its snapshot run
 * on the world's threads, so a failure must name the same step and grain as on one thread, and
 * the roll-back must restore the last good state. 400 grains at rest on a lattice with no contact
 * (no gravity), and above them the grains 400 and 401, the last in the sorted order (the last
 * thread's range). `overlap`: 401 approaches 400 at 0.2 m/s from 1 % of a diameter away, so the
 * guard at step 100 passes (and takes its snapshot on the threads) and the one at step 200 finds
 * them overlapping by 1 % of the diameter (bound 0.5 %); otherwise grain 400 moves at 2 m/s
 * (bound 1 m/s) and the guard stops the run at step 100. */
static int guard_failure_on_threads(int overlap, const char *expected)
{
    char messages[2][sizeof(((SimError *)0)->message)];
    for (int run = 0; run < 2; ++run) {
        SimGrainBuffer b;
        sim_grain_buffer_init(&b);
        for (int k = 0; k < 400; ++k)
            sim_grain_buffer_add(&b, 0.03 * (k % 20), 0.03 * (k / 20), 0.01, 0, 0, -1);
        int top = sim_grain_buffer_add(&b, 0.3, 0.7, 0.01, 0, 0, -1);
        int other = sim_grain_buffer_add(&b, overlap ? 0.3202 : 0.4, 0.7, 0.01, 0, 0, -1);
        if (overlap)
            b.vx[other] = -0.2;
        else
            b.vx[top] = 2.0;
        SimWorldDef def = tu_def(1000.0, 1e3, 1e-5);
        def.guard_max_overlap = 0.005;
        def.guard_max_speed = 1.0;
        SimWorld *w = tu_create(&def, &b);
        TEST_ASSERT(w != NULL);
        sim_world_set_threads(w, run == 0 ? 1 : 3);
        if (overlap)
            TEST_ASSERT(tu_step(w, 100) == 0);
        const uint64_t good = sim_world_hash(w);
        SimError err;
        TEST_ASSERT(sim_world_step(w, 300, &err) == SIM_ERROR_UNSTABLE);
        TEST_ASSERT(err.step == (overlap ? 200 : 100) && err.grain == 400);
        TEST_ASSERT(strstr(err.message, expected) != NULL);
        TEST_ASSERT(sim_world_hash(w) == good); /* rolled back to the last good check */
        memcpy(messages[run], err.message, sizeof messages[run]);
        sim_world_destroy(w);
        sim_grain_buffer_free(&b);
    }
    TEST_ASSERT(strcmp(messages[0], messages[1]) == 0);
    return 0;
}

static int guard_overlap_same_on_threads(void)
{
    return guard_failure_on_threads(1, "step 200: grain 400 overlaps grain 401 by 0.00");
}

static int guard_speed_same_on_threads(void)
{
    return guard_failure_on_threads(0, "grain 400 at (0.3");
}

TEST_MAIN(TEST_CASE(same_seed_same_hash), TEST_CASE(different_seed_different_hash),
          TEST_CASE(split_steps_same_hash), TEST_CASE(rng_stream),
          TEST_CASE(event_onset_threads_same_hash), TEST_CASE(guard_overlap_same_on_threads),
          TEST_CASE(guard_speed_same_on_threads))
