/* SPDX-License-Identifier: MIT */
/* Pair parameters from two species: stiffness is the arithmetic mean, friction the harmonic
 * mean, so a frictionless wall species gives frictionless contacts (002 smooth side walls). */
#include "test.h"

#include "sim/sim.h"

/* A grain sliding along a floor wall of species `floor_species`; returns its speed after 0.5 s. */
static double slide(double wall_mu, double *tangential)
{
    SimWall floor_ = {.x0 = -50.0, .y0 = 0.0, .x1 = 50.0, .y1 = 0.0, .species = 1, .motion = -1};
    double x = 0.0, y = 0.1, r = 0.1, vx = 2.0;
    int species = 0;
    SimGrainSet g = {.count = 1, .x = &x, .y = &y, .radius = &r, .vx = &vx, .species = &species};
    SimWorldDef def = sim_world_def_default();
    def.effects = SIM_EFFECT_FRICTION;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.species_count = 2;
    for (int s = 0; s < 2; ++s) {
        def.materials[s].density = 1000.0;
        def.materials[s].normal_stiffness = 1e5;
        def.materials[s].tangential_stiffness = 7.5e4;
        def.materials[s].damping_mode = SIM_DAMPING_CRITICAL;
        def.materials[s].critical_fraction = 0.5;
    }
    def.materials[0].friction = 0.5;
    def.materials[1].friction = wall_mu;
    def.time_step = 1e-4;
    def.wall_count = 1;
    def.walls = &floor_;
    def.grains = g;
    SimError err;
    SimWorld *w = sim_world_create(&def, &err);
    if (!w || sim_world_step(w, 5000, &err) != SIM_OK)
        return -1.0;
    SimFrame f;
    sim_world_frame(w, &f);
    *tangential = f.contact_count ? f.contacts[0].tangential_force : 0.0;
    double v = f.vx[0];
    sim_world_destroy(w);
    return v;
}

static int frictionless_wall_species(void)
{
    double ft = 1.0;
    /* mu = harmonic(0.5, 0) = 0: the grain slides on without losing speed */
    TEST_NEAR(slide(0.0, &ft), 2.0, 1e-9);
    TEST_NEAR(ft, 0.0, 1e-12);
    /* mu = harmonic(0.5, 0.5) = 0.5: friction stops the sliding (then it rolls) */
    TEST_ASSERT(slide(0.5, &ft) < 1.9);
    return 0;
}

TEST_MAIN(TEST_CASE(frictionless_wall_species))
