/* SPDX-License-Identifier: MIT */
/* Golden trajectories: a 150-grain rain into a box (with a base row of small fixed grains) runs
 * 3000 steps under each combination of contact laws, and the state hash (positions, velocities,
 * angles, spins, by stable id) must equal the value recorded from the reference implementation:
 * the scalar one-contact-at-a-time kernel of sablier 0.1.0 (commit 2c1095c). The grain-grain
 * kernel now evaluates SIM_LANES contacts at a time; these hashes prove it gives the same bits,
 * and they catch any later change of the arithmetic of the laws, the list or the integrators.
 *
 * The values hold for IEEE double arithmetic without contraction (-ffp-contract=off) and the
 * glibc libm of Debian 12 (set-up uses log and sqrt; the steps use sqrt only). After an intended
 * change of the arithmetic, run this test, check the cause, and paste the printed hashes. */
#include "sim_test_util.h"
#include "test.h"

#include <inttypes.h>
#include <string.h>

typedef struct Case {
    const char *name;
    unsigned effects;
    SimTangentialLaw tangential;
    SimRollingLaw rolling;
    SimNormalLaw normal;
    int clip;
    int two_species;
    uint64_t hash;
} Case;

static SimWorld *make(const Case *c, SimGrainBuffer *b)
{
    static const SimWall box[3] = {{.x0 = 0.0, .y0 = 0.0, .x1 = 2.0, .y1 = 0.0, .motion = -1},
                                   {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 3.0, .motion = -1},
                                   {.x0 = 2.0, .y0 = 0.0, .x1 = 2.0, .y1 = 3.0, .motion = -1}};
    static const SimWall floor_only[1] = {
        {.x0 = -1.0, .y0 = 0.0, .x1 = 3.0, .y1 = 0.0, .motion = -1}};
    tu_rain_150(b, 7, 0.2);
    for (int k = 0; k < b->count; ++k) {
        b->omega[k] = (double)(k % 5 - 2) * 3.0; /* spins, so that rolling resistance acts */
        if (c->two_species && k % 3 == 0)
            b->species[k] = 1;
    }
    /* a base of fixed grains of half a diameter (a polydisperse list) */
    sim_build_fixed_row(b, 0.025, 1.975, 0.025, 0.025, 0, -1);

    SimWorldDef def = tu_def(1000.0, 1e5, 0.0);
    def.time_step = 0.0;
    def.steps_per_contact = 50.0;
    def.gravity_y = -G0;
    def.effects = c->effects;
    def.contact.tangential = c->tangential;
    def.contact.rolling = c->rolling;
    def.contact.normal = c->normal;
    def.contact.clip_tensile = c->clip;
    def.species_count = c->two_species ? 2 : 1;
    for (int s = 0; s < def.species_count; ++s) {
        SimMaterial *m = &def.materials[s];
        *m = def.materials[0];
        m->density = s ? 1500.0 : 1000.0;
        m->normal_stiffness = s ? 3e5 : 1e5;
        m->friction = s ? 0.3 : 0.5;
        m->tangential_stiffness = 0.75 * m->normal_stiffness;
        m->tangential_damping = 20.0;
        m->damping_mode = SIM_DAMPING_RESTITUTION;
        m->restitution = s ? 0.3 : 0.6;
        if (c->normal == SIM_NORMAL_HERTZ) { /* restitution is defined for the linear law only */
            m->normal_stiffness = 3e6;
            m->damping_mode = SIM_DAMPING_GAMMA;
            m->normal_damping = 2e3;
        }
        m->rolling_friction = 0.002;
        m->rolling_stiffness = 5.0;
    }
    /* The fixed skin of the reference, 0.2 mean mobile diameter: the automatic skin (a later
     * change of the list, not of the arithmetic) would move the list builds. */
    double sum = 0.0;
    int mobile = 0;
    for (int k = 0; k < b->count; ++k)
        if (!(b->flags[k] & SIM_GRAIN_FIXED)) {
            sum += 2.0 * b->radius[k];
            ++mobile;
        }
    def.skin = 0.2 * sum / mobile;
    if (c->effects & SIM_EFFECT_PERIODIC_X) {
        def.domain_x0 = 0.0;
        def.domain_x1 = 2.0;
        def.wall_count = 1;
        def.walls = floor_only;
    } else {
        def.wall_count = 3;
        def.walls = box;
    }
    return tu_create(&def, b);
}

static const unsigned F = SIM_EFFECT_FRICTION, R = SIM_EFFECT_ROLLING, P = SIM_EFFECT_PERIODIC_X;
#define NONE_T SIM_TANGENTIAL_NONE
#define REG    SIM_TANGENTIAL_REGULARISED
#define SPR    SIM_TANGENTIAL_SPRING

static const Case golden[] = {
    {"frictionless", 0, NONE_T, SIM_ROLLING_OFF, SIM_NORMAL_LINEAR, 0, 0, 0x6b5ac70819feb7fe},
    {"frictionless_clip", 0, NONE_T, SIM_ROLLING_OFF, SIM_NORMAL_LINEAR, 1, 0, 0x0a9ad7aa57555e69},
    {"regularised_clip", 0, REG, SIM_ROLLING_OFF, SIM_NORMAL_LINEAR, 1, 0, 0x6beecc5fb9ec1bba},
    {"spring", 0, SPR, SIM_ROLLING_OFF, SIM_NORMAL_LINEAR, 0, 0, 0xc8461149ff8929db},
    {"spring_two_species", 0, SPR, SIM_ROLLING_OFF, SIM_NORMAL_LINEAR, 1, 1, 0xe933c0b51cf20a94},
    {"spring_rolling_fixed", 0, SPR, SIM_ROLLING_FIXED, SIM_NORMAL_LINEAR, 1, 0,
     0x38d5524e37e8c3a9},
    {"spring_rolling_chord", 0, SPR, SIM_ROLLING_CHORD, SIM_NORMAL_LINEAR, 1, 0,
     0x061fb723223b1639},
    {"rolling_only", 0, NONE_T, SIM_ROLLING_FIXED, SIM_NORMAL_LINEAR, 1, 0, 0x72e9dc13d62957ac},
    {"hertz_regularised", 0, REG, SIM_ROLLING_OFF, SIM_NORMAL_HERTZ, 1, 0, 0xbeff9c87bd5c735d},
    {"periodic_spring", 0, SPR, SIM_ROLLING_OFF, SIM_NORMAL_LINEAR, 1, 0, 0x731c20f928dec578},
};

static int check(int index)
{
    Case c = golden[index];
    if (c.tangential != SIM_TANGENTIAL_NONE)
        c.effects |= F;
    if (c.rolling != SIM_ROLLING_OFF)
        c.effects |= R;
    if (strncmp(c.name, "periodic", 8) == 0)
        c.effects |= P;
    SimGrainBuffer b;
    SimWorld *w = make(&c, &b);
    TEST_ASSERT(w != NULL);
    TEST_ASSERT(tu_step(w, 3000) == 0);
    uint64_t h = sim_world_hash(w);
    if (h != c.hash)
        fprintf(stderr, "golden %s: hash 0x%016" PRIx64 " (expected 0x%016" PRIx64 ")\n", c.name, h,
                c.hash);
    TEST_ASSERT(h == c.hash);
    sim_world_destroy(w);
    sim_grain_buffer_free(&b);
    return 0;
}

/* Every golden trajectory on `threads` threads (sim_world_set_threads) with the hot loops of
 * instruction set `isa` (sim_isa_set; -1: the default choice) gives the recorded hash, whatever
 * the count (8 oversubscribes a small machine, which is fine: the split of the work is fixed by
 * the count, never by timing) and whatever the set. */
static int check_all(int threads, int isa)
{
    const int cases = (int)(sizeof golden / sizeof golden[0]);
    const SimIsa before = sim_isa();
    if (isa >= 0 && sim_isa_set((SimIsa)isa) != SIM_OK) {
        /* not compiled in, or this CPU lacks it: refused, and the choice stays */
        TEST_ASSERT(!sim_isa_supported((SimIsa)isa));
        TEST_ASSERT(sim_isa() == before);
        fprintf(stderr, "golden: %s not supported here, nothing to run\n",
                sim_isa_name((SimIsa)isa));
        return 0;
    }
    int failed = 0;
    for (int index = 0; index < cases; ++index) {
        Case c = golden[index];
        if (c.tangential != SIM_TANGENTIAL_NONE)
            c.effects |= F;
        if (c.rolling != SIM_ROLLING_OFF)
            c.effects |= R;
        if (strncmp(c.name, "periodic", 8) == 0)
            c.effects |= P;
        SimGrainBuffer b;
        SimWorld *w = make(&c, &b);
        TEST_ASSERT(w != NULL);
        sim_world_set_threads(w, threads);
        TEST_ASSERT(sim_world_threads(w) == threads);
        TEST_ASSERT(tu_step(w, 3000) == 0);
        uint64_t h = sim_world_hash(w);
        if (h != c.hash) {
            fprintf(stderr,
                    "golden %s on %d threads, %s: hash 0x%016" PRIx64 " (expected 0x%016" PRIx64
                    ")\n",
                    c.name, threads, sim_isa_name(sim_isa()), h, c.hash);
            failed = 1;
        }
        sim_world_destroy(w);
        sim_grain_buffer_free(&b);
    }
    TEST_ASSERT(!failed);
    return 0;
}

/* clang-format off */
static int threads_1(void) { return check_all(1, -1); }
static int threads_2(void) { return check_all(2, -1); }
static int threads_3(void) { return check_all(3, -1); }
static int threads_8(void) { return check_all(8, -1); }
static int isa_sse2(void) { return check_all(1, SIM_ISA_BASELINE); }
static int isa_avx2(void) { return check_all(1, SIM_ISA_AVX2); }
static int isa_avx512(void) { return check_all(1, SIM_ISA_AVX512); }
static int isa_native(void) { return check_all(1, SIM_ISA_NATIVE); }
static int isa_avx2_threads_2(void) { return check_all(2, SIM_ISA_AVX2); }
static int frictionless(void) { return check(0); }
static int frictionless_clip(void) { return check(1); }
static int regularised_clip(void) { return check(2); }
static int spring(void) { return check(3); }
static int spring_two_species(void) { return check(4); }
static int spring_rolling_fixed(void) { return check(5); }
static int spring_rolling_chord(void) { return check(6); }
static int rolling_only(void) { return check(7); }
static int hertz_regularised(void) { return check(8); }
static int periodic_spring(void) { return check(9); }
/* clang-format on */

TEST_MAIN(TEST_CASE(frictionless), TEST_CASE(frictionless_clip), TEST_CASE(regularised_clip),
          TEST_CASE(spring), TEST_CASE(spring_two_species), TEST_CASE(spring_rolling_fixed),
          TEST_CASE(spring_rolling_chord), TEST_CASE(rolling_only), TEST_CASE(hertz_regularised),
          TEST_CASE(periodic_spring), TEST_CASE(threads_1), TEST_CASE(threads_2),
          TEST_CASE(threads_3), TEST_CASE(threads_8), TEST_CASE(isa_sse2), TEST_CASE(isa_avx2),
          TEST_CASE(isa_avx512), TEST_CASE(isa_native), TEST_CASE(isa_avx2_threads_2))
