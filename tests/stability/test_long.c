/* SPDX-License-Identifier: MIT */
/* The long stability case (slow: about a million steps; the ASan run skips this file). A dense
 * pile at rest must stay at rest for 1e6 steps (004 §7.12, 000 §7 static bed). */
#include "stab_util.h"
#include "test.h"

/* 200 grains (disk r 0.5 +- 10 %, density 1, k_n 1e4, e_n 0.3, tangential spring mu 0.5,
 * k_t 0.75 k_n) settle for 20 s in a box of fixed grains, then run 1e6 more steps (~400 s).
 * Bounds over the million steps (sampled every 1000): OK status, no NaN; kinetic energy never
 * above 1e-6 N m g d (the settled pile stays settled: no creep, no energy growth); the free
 * surface (highest grain top) and the mean height move by less than 0.01 d; overlap < 0.02 d. */
static int dense_pile_million_steps(void)
{
    const double r = 0.5, d = 2.0 * r;
    SimWorldDef def = tu_def(1.0, 1e4, 0.0);
    def.gravity_y = -G0;
    def.guard_max_speed = 0.0;
    def.effects |= SIM_EFFECT_FRICTION;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.materials[0].friction = 0.5;
    def.materials[0].tangential_stiffness = 0.75e4;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.3;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    st_fixed_box(&b, 21.0, 40.0, r, 0);
    SimRng rng;
    sim_rng_seed(&rng, 23);
    st_lattice(&b, &rng, 200, 0.5, 20.5, r, 0.9 * r, 1.1 * r, 0.02);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, (long)(20.0 / sim_world_time_step(w))) == 0);
    fprintf(stderr, "settled: KE %g\n", sim_world_energy(w).kinetic);
    const double m = tu_mass(SIM_MASS_DISK, 1.0, r), ke_bound = 1e-6 * 200.0 * m * G0 * d;
    SimFrame f;
    double top0 = -INFINITY, mean0 = 0.0;
    sim_world_frame(w, &f);
    for (int i = 0; i < f.mobile_count; ++i) {
        top0 = fmax(top0, f.y[i] + f.radius[i]);
        mean0 += f.y[i] / f.mobile_count;
    }
    StRun run = st_run(w, 1000000, 1000);
    st_report("dense_pile_million_steps", &run);
    TEST_ASSERT(run.status == SIM_OK && run.finite);
    TEST_ASSERT(run.overlap_max < 0.02);
    fprintf(stderr, "KE_max %.3g of bound\n", run.ke_max / ke_bound);
    TEST_ASSERT(run.ke_max < ke_bound);
    double top = -INFINITY, mean = 0.0;
    sim_world_frame(w, &f);
    for (int i = 0; i < f.mobile_count; ++i) {
        top = fmax(top, f.y[i] + f.radius[i]);
        mean += f.y[i] / f.mobile_count;
    }
    fprintf(stderr, "surface drift %.3g d, mean drift %.3g d, KE_max %.3g of bound\n",
            (top - top0) / d, (mean - mean0) / d, run.ke_max / ke_bound);
    TEST_NEAR(top, top0, 0.01 * d);
    TEST_NEAR(mean, mean0, 0.01 * d);
    sim_world_destroy(w);
    return 0;
}

TEST_MAIN(TEST_CASE(dense_pile_million_steps))
