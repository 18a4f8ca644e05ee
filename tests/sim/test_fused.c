/* SPDX-License-Identifier: MIT */
/* The fused drift (sim/isa/contact_pass.c, fused_run): the velocity-Verlet drift runs inside the
 * contact pass (on threads, in each part of the pile: sim/parts.c). It must make the same
 * operations as the separate passes: the same grains, forces and contact history to the bit, with
 * steps where a grain passes the rebuild threshold in the middle of the pass (which must then leave
 * the history as it was). */
#include "sim_test_util.h"
#include "test.h"

#include "sim/internal.h"

#include <math.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

/* `large`: 1500 grains instead of 150, a list of many of the passes' blocks of entries. */
static SimWorld *make_pile(SimTangentialLaw tangential, SimRollingLaw rolling, SimGrainBuffer *b,
                           int large)
{
    static const SimWall box[3] = {{.x0 = 0.0, .y0 = 0.0, .x1 = 2.0, .y1 = 0.0, .motion = -1},
                                   {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 3.0, .motion = -1},
                                   {.x0 = 2.0, .y0 = 0.0, .x1 = 2.0, .y1 = 3.0, .motion = -1}};
    if (large)
        tu_rain(b, 11, 0.2, 0.015, 0.0162, 1500);
    else
        tu_rain_150(b, 11, 0.2);
    for (int k = 0; k < b->count; ++k)
        b->omega[k] = (double)(k % 7 - 3) * 2.0;
    const double row = large ? 0.01 : 0.025;
    sim_build_fixed_row(b, row, 2.0 - row, row, row, 0, -1); /* fixed partners of the list */
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

/* Two identical piles (make_pile): `one` stays on one thread, `two` is given `threads` threads
 * (0: left as made, for a test that gives them later). */
typedef struct Twins {
    SimGrainBuffer b1, b2;
    SimWorld *one, *two;
} Twins;

static int twins_make(Twins *t, SimTangentialLaw tangential, SimRollingLaw rolling, int large,
                      int threads)
{
    t->one = make_pile(tangential, rolling, &t->b1, large);
    t->two = make_pile(tangential, rolling, &t->b2, large);
    if (!t->one || !t->two)
        return 1;
    if (threads > 0)
        sim_world_set_threads(t->two, threads);
    return 0;
}

static void twins_free(Twins *t)
{
    sim_world_destroy(t->one);
    sim_world_destroy(t->two);
    sim_grain_buffer_free(&t->b1);
    sim_grain_buffer_free(&t->b2);
}

/* One world fused (on `threads` threads: in parts, sim/parts.c), one with the separate passes on
 * one thread, stepped in batches (so that the closing kick is deferred into the next drift, as in
 * a run); compared after every batch. */
static int same_as_separate_on(SimTangentialLaw tangential, SimRollingLaw rolling, int large,
                               int threads)
{
    Twins t;
    TEST_ASSERT(twins_make(&t, tangential, rolling, large, threads) == 0);
    SimWorld *fused = t.two, *plain = t.one;
    plain->fused_pass = NULL;
    TEST_ASSERT(sim_world_threads(fused) == threads);
    fused->nl.plan.even_cut = 1; /* the cut where the checks below expect it, whatever the timing */
    int fixed_shared = 0;
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
        if (threads > 1) { /* in parts, with shared grains */
            const PartPlan *pp = &fused->nl.plan;
            TEST_ASSERT(pp->count >= 2 && pp->shared > 0);
            fixed_shared |= pp->shared_grain[pp->shared - 1] >= fused->mobile_count;
        }
    }
    /* parts thinner than a row: the fixed base is reached from two parts */
    TEST_ASSERT(threads < 16 || fixed_shared);
    /* the path under test ran, and met rebuilds found mid-pass */
    TEST_ASSERT(fused->fused_steps > 2000 && fused->fused_trips > 3);
    TEST_ASSERT(plain->fused_steps == 0);
    SimEnergy e = sim_world_energy(fused);
    TEST_ASSERT(e.contacts > 100);
    /* the large pile's list spans many blocks of the passes (FUSED_BLOCK entries) */
    TEST_ASSERT(!large || fused->nl.start[fused->mobile_count] > 2500);
    twins_free(&t);
    return 0;
}

static int same_as_separate(SimTangentialLaw tangential, SimRollingLaw rolling, int large)
{
    return same_as_separate_on(tangential, rolling, large, 1);
}

static int spring(void)
{
    return same_as_separate(SIM_TANGENTIAL_SPRING, SIM_ROLLING_OFF, 0);
}

static int spring_rolling(void)
{
    return same_as_separate(SIM_TANGENTIAL_SPRING, SIM_ROLLING_FIXED, 0);
}

static int regularised_rolling(void)
{
    return same_as_separate(SIM_TANGENTIAL_REGULARISED, SIM_ROLLING_CHORD, 0);
}

/* Many blocks of entries: each block's results stay on the stack and are scattered in turn. */
static int spring_rolling_large(void)
{
    return same_as_separate(SIM_TANGENTIAL_SPRING, SIM_ROLLING_FIXED, 1);
}

/* A sparse row of grains on a floor of fixed grains, no two within reach of each other: every
 * entry's partner is fixed, and the pass must still drift each block's owners before it reads
 * them (a drift front that followed the mobile partners alone left them behind). */
static SimWorld *make_sparse_row(SimGrainBuffer *b)
{
    sim_grain_buffer_init(b);
    sim_build_fixed_row(b, 0.0, 48.0, 0.0, 0.005, 0, -1);
    for (int k = 0; k < 600; ++k) /* 1 mm above touching the floor; 5 cm gaps between them */
        sim_grain_buffer_add(b, 0.03 + 0.08 * k, 0.021, 0.015, 0, 0, -1);
    for (int k = 0; k < b->count; ++k)
        if (!(b->flags[k] & SIM_GRAIN_FIXED))
            b->vx[k] = (double)(k % 5 - 2) * 0.01;
    SimWorldDef def = tu_def(1000.0, 1e5, 0.0);
    def.steps_per_contact = 50.0;
    def.gravity_y = -G0;
    return tu_create(&def, b);
}

static int fixed_partners_only(void)
{
    for (int threads = 1; threads <= 2; ++threads) {
        SimGrainBuffer b1, b2;
        SimWorld *fused = make_sparse_row(&b1), *plain = make_sparse_row(&b2);
        TEST_ASSERT(fused && plain);
        plain->fused_pass = NULL;
        sim_world_set_threads(fused, threads);
        TEST_ASSERT(tu_step(fused, 1) == 0 && tu_step(plain, 1) == 0);
        /* several blocks of entries, none with a mobile partner */
        const int entries = fused->nl.start[fused->mobile_count];
        TEST_ASSERT(entries > 1200);
        for (int k = 0; k < entries; ++k)
            TEST_ASSERT(fused->nl.j[k] >= fused->mobile_count);
        for (int batch = 0; batch < 10; ++batch) {
            TEST_ASSERT(tu_step(fused, 50) == 0 && tu_step(plain, 50) == 0);
            TEST_ASSERT(sim_world_hash(fused) == sim_world_hash(plain));
            TEST_ASSERT(SAME(fused->fy, plain->fy, fused->count));
        }
        TEST_ASSERT(fused->fused_steps > 400);
        sim_world_destroy(fused);
        sim_world_destroy(plain);
        sim_grain_buffer_free(&b1);
        sim_grain_buffer_free(&b2);
    }
    return 0;
}

/* On threads the fused pass runs in parts (sim/parts.c): each part writes only its own grains,
 * the entries that reach a shared grain leave their results in slots, added after the parts in
 * the serial order. Every law's results, forces, torques and history equal the separate passes'
 * on one thread, with rebuilds found mid-pass, on 2, 3, 8 and 16 threads (8 on the small pile:
 * parts of about a row, most grains shared; 16 on the large one: 32 parts, the fixed base reached
 * from two of them). */
static int parts_spring_rolling(void)
{
    return same_as_separate_on(SIM_TANGENTIAL_SPRING, SIM_ROLLING_FIXED, 1, 2);
}

static int parts_regularised_chord(void)
{
    return same_as_separate_on(SIM_TANGENTIAL_REGULARISED, SIM_ROLLING_CHORD, 1, 3);
}

static int parts_small_pile(void)
{
    return same_as_separate_on(SIM_TANGENTIAL_SPRING, SIM_ROLLING_OFF, 0, 8);
}

static int parts_thin(void)
{
    return same_as_separate_on(SIM_TANGENTIAL_SPRING, SIM_ROLLING_FIXED, 1, 16);
}

/* The threaded separate passes (what a step takes when the fused one cannot run: a rebuild, a
 * prescribed motion) give the one-thread bits too. */
static int threads_separate_passes(void)
{
    Twins t;
    TEST_ASSERT(twins_make(&t, SIM_TANGENTIAL_SPRING, SIM_ROLLING_FIXED, 0, 2) == 0);
    SimWorld *one = t.one, *two = t.two;
    two->fused_pass = NULL;
    TEST_ASSERT(tu_step(one, 1500) == 0 && tu_step(two, 1500) == 0);
    TEST_ASSERT(sim_world_hash(one) == sim_world_hash(two));
    TEST_ASSERT(one->fused_steps > 1000 && two->fused_steps == 0);
    twins_free(&t);
    return 0;
}

/* The threaded arrays (the parts' plan; the transposed list and per-entry results of the
 * separate passes) exist only with threads, and a world given threads between steps builds them
 * for its present list at once: its steps then run in parts with the same bits as a one-thread
 * twin. */
static int threads_build_their_arrays(void)
{
    Twins t;
    TEST_ASSERT(twins_make(&t, SIM_TANGENTIAL_SPRING, SIM_ROLLING_OFF, 1, 0) == 0);
    SimWorld *one = t.one, *two = t.two;
    TEST_ASSERT(tu_step(one, 300) == 0 && tu_step(two, 300) == 0);
    TEST_ASSERT(!two->nl.in_ready && two->nl.out == NULL && two->nl.in_entry == NULL);
    const long builds = two->rebuilds, fused = two->fused_steps;
    sim_world_set_threads(two, 2);
    TEST_ASSERT(two->nl.in_ready && two->nl.out && two->rebuilds == builds);
    TEST_ASSERT(two->nl.plan.count == 2 && two->nl.plan.first[2] == two->mobile_count);
    const int entries = two->nl.start[two->mobile_count];
    TEST_ASSERT(two->nl.in_start[two->count] == entries);
    TEST_ASSERT(tu_step(one, 900) == 0 && tu_step(two, 900) == 0);
    TEST_ASSERT(two->fused_steps > fused + 800);
    TEST_ASSERT(sim_world_hash(one) == sim_world_hash(two));
    TEST_ASSERT(SAME(one->fx, two->fx, one->count) && SAME(one->torque, two->torque, one->count));
    sim_world_set_threads(two, 1); /* back to the fused pass, the arrays idle until freed */
    TEST_ASSERT(!two->nl.in_ready && two->nl.plan.count == 0);
    TEST_ASSERT(tu_step(one, 300) == 0 && tu_step(two, 300) == 0);
    TEST_ASSERT(two->fused_steps > fused && sim_world_hash(one) == sim_world_hash(two));
    twins_free(&t);
    return 0;
}

/* The cut by measurement (sim/parts.c, balance_shares): from a plan's timing (part 1 beginning
 * 0.4 us after part 0, both at 5 ns an entry) the next plan's shares move halfway to those that end
 * both parts together, and the cut follows them; a part ten times slower is held at 1.5 equal
 * shares. The steps on the skewed cut keep the bits of a one-thread twin. */
static int parts_cut_by_measurement(void)
{
    Twins t;
    TEST_ASSERT(twins_make(&t, SIM_TANGENTIAL_REGULARISED, SIM_ROLLING_OFF, 1, 2) == 0);
    SimWorld *one = t.one, *two = t.two;
    TEST_ASSERT(tu_step(one, 300) == 0 && tu_step(two, 300) == 0);
    PartPlan *pp = &two->nl.plan;
    TEST_ASSERT(pp->count == 2 && pp->shared_parts == 2);
    const int total = two->nl.start[two->mobile_count], steps = 50;
    pp->timed = steps;
    pp->begin_ns[0] = 0;
    pp->begin_ns[1] = 400LL * steps;
    pp->entries[0] = pp->entries[1] = (long long)(total / 2) * steps;
    pp->run_ns[0] = pp->run_ns[1] = 5 * pp->entries[0];
    double was = pp->share[0] > 0.0 ? pp->share[0] : 0.5;
    sim_world_rebuild_now(one);
    sim_world_rebuild_now(two);
    /* n = 2 (total / 2) entries a step; T = (n + 400 / 5) / (2 / 5); part 0 wants T / 5 / n */
    const double n = 2.0 * (total / 2), end = (n + 400.0 / 5.0) / (2.0 / 5.0);
    const double want = 0.5 * (was + end / 5.0 / n);
    TEST_ASSERT(fabs(pp->share[0] - want) < 1e-12 &&
                fabs(pp->share[0] + pp->share[1] - 1.0) < 1e-12);
    TEST_ASSERT(end / 5.0 / n > 0.5 && end / 5.0 / n < 0.75); /* not held at a bound */
    TEST_ASSERT(pp->timed == 0 && pp->run_ns[0] == 0);
    const int *start = two->nl.start, cut = pp->first[1];
    const int listed = start[two->mobile_count]; /* the rebuilt list's entries */
    TEST_ASSERT(cut % 8 == 0 && start[cut] >= (long long)(listed * pp->share[0]));
    TEST_ASSERT(cut < 8 || start[cut - 8] < (long long)(listed * pp->share[0]));
    TEST_ASSERT(tu_step(one, 200) == 0 && tu_step(two, 200) == 0);
    TEST_ASSERT(sim_world_hash(one) == sim_world_hash(two));
    /* part 1 ten times slower per entry: part 0 would take it all, held at 0.75 */
    was = pp->share[0];
    pp->timed = steps;
    memset(pp->begin_ns, 0, sizeof pp->begin_ns);
    pp->entries[0] = pp->entries[1] = 1000LL * steps;
    pp->run_ns[0] = 1000LL * steps;
    pp->run_ns[1] = 10000LL * steps;
    sim_world_rebuild_now(one);
    sim_world_rebuild_now(two);
    TEST_ASSERT(fabs(pp->share[0] -
                     0.5 * (was + 0.75) / (0.5 * (was + 0.75) + 0.5 * (1.0 - was + 0.25))) < 1e-12);
    TEST_ASSERT(tu_step(one, 200) == 0 && tu_step(two, 200) == 0);
    TEST_ASSERT(sim_world_hash(one) == sim_world_hash(two));
    twins_free(&t);
    return 0;
}

/* A child forked from a process whose world has threads has none of its workers (fork copies
 * the calling thread only): its steps run on one thread (sim/parallel.c, pool_here) with the
 * bits of a one-thread twin, and the parent's world keeps its threads. A child that waited for
 * the missing workers would be stopped by its alarm (30 s). */
static int forked_child_runs_alone(void)
{
    Twins t;
    TEST_ASSERT(twins_make(&t, SIM_TANGENTIAL_SPRING, SIM_ROLLING_OFF, 0, 2) == 0);
    SimWorld *one = t.one, *two = t.two;
    TEST_ASSERT(tu_step(one, 100) == 0 && tu_step(two, 100) == 0);
    int fd[2];
    TEST_ASSERT(pipe(fd) == 0);
    fflush(NULL);
    const pid_t child = fork();
    TEST_ASSERT(child >= 0);
    if (child == 0) {
        alarm(30);
        uint64_t hash = tu_step(two, 300) == 0 ? sim_world_hash(two) : 0;
        _exit(write(fd[1], &hash, sizeof hash) == (ssize_t)sizeof hash ? 0 : 1);
    }
    close(fd[1]);
    uint64_t hash = 0;
    const ssize_t got = read(fd[0], &hash, sizeof hash);
    close(fd[0]);
    int status = 0;
    TEST_ASSERT(waitpid(child, &status, 0) == child);
    TEST_ASSERT(WIFEXITED(status) && WEXITSTATUS(status) == 0 && got == (ssize_t)sizeof hash);
    TEST_ASSERT(tu_step(one, 300) == 0 && hash == sim_world_hash(one));
    TEST_ASSERT(sim_world_threads(two) == 2 && tu_step(two, 300) == 0);
    TEST_ASSERT(sim_world_hash(one) == sim_world_hash(two));
    twins_free(&t);
    return 0;
}

TEST_MAIN(TEST_CASE(spring), TEST_CASE(spring_rolling), TEST_CASE(regularised_rolling),
          TEST_CASE(spring_rolling_large), TEST_CASE(parts_spring_rolling),
          TEST_CASE(parts_regularised_chord), TEST_CASE(parts_small_pile), TEST_CASE(parts_thin),
          TEST_CASE(fixed_partners_only), TEST_CASE(threads_separate_passes),
          TEST_CASE(threads_build_their_arrays), TEST_CASE(parts_cut_by_measurement),
          TEST_CASE(forked_child_runs_alone))
