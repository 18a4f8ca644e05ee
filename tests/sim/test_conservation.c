/* SPDX-License-Identifier: MIT */
/* Conservation laws: energy over many elastic bounces (velocity Verlet), momentum with
 * pair forces, angular momentum with friction, energy in a closed elastic box. */
#include "sim_test_util.h"
#include "test.h"

/* 100 elastic bounces of a grain on a fixed grain under gravity, velocity Verlet, linear law,
 * t_c / dt = 2000. Between contacts velocity Verlet is exact; each passage through the kink of
 * the force at xi = 0 leaves an O((omega dt)^2) error that does not accumulate (bounded
 * shadow energy), ~6e-7 of the impact energy at this resolution. Total energy (kinetic,
 * potential, spring) stays within 1e-6 of the impact energy m g h at every step. */
static int energy_100_elastic_bounces(void)
{
    const double rho = 1190.0, k = 5e5, r = 0.1, rg = 0.105;
    double m = tu_mass(SIM_MASS_SPHERE, rho, r), tc = TPI * sqrt(m / k);
    double v0 = 2.0 * G0 * tc, h = v0 * v0 / (2.0 * G0); /* flight = 4 t_c */
    SimWorldDef def = tu_def(rho, k, tc / 2000.0);
    def.mass_model = SIM_MASS_SPHERE;
    def.gravity_y = -G0;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, r + rg + h, r, 0, 0u, -1);
    sim_grain_buffer_add(&b, 0.0, 0.0, rg, 0, SIM_GRAIN_FIXED, -1);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    SimEnergy en = sim_world_energy(w);
    double e0 = en.total, scale = m * G0 * h, worst = 0.0;
    TEST_REL(en.kinetic + en.potential + en.rotational + en.elastic, e0, 1e-14);
    int bounces = 0, contact = 0;
    while (bounces < 100) {
        TEST_ASSERT(tu_step(w, 1) == 0);
        en = sim_world_energy(w);
        double dev = fabs(en.total - e0);
        if (dev > worst)
            worst = dev;
        if (en.contacts > 0)
            contact = 1;
        else if (contact) {
            contact = 0;
            ++bounces;
        }
        TEST_ASSERT(sim_world_time(w) < 100.0 * 6.0 * tc);
    }
    TEST_NEAR(worst / scale, 0.0, 1e-6);
    sim_world_destroy(w);
    return 0;
}

/* Mobile grains in a channel periodic in x between two frictionless horizontal walls, no
 * gravity, dissipative contacts: walls push along y only, so the x momentum is conserved to
 * rounding however many grain-grain contacts and seam crossings happen. */
static int momentum_periodic_channel(void)
{
    const double rho = 1000.0, k = 1e4, lx = 1.0;
    const double radii[] = {0.02, 0.025, 0.03, 0.012};
    SimWorldDef def = tu_def(rho, k, 1e-4);
    def.effects |= SIM_EFFECT_PERIODIC_X;
    def.domain_x0 = 0.0;
    def.domain_x1 = lx;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.5;
    SimWall walls[2] = {
        {.x0 = -1.0, .y0 = 0.0, .x1 = lx + 1.0, .y1 = 0.0, .species = 0, .motion = -1},
        {.x0 = -1.0, .y0 = 0.4, .x1 = lx + 1.0, .y1 = 0.4, .species = 0, .motion = -1}};
    def.wall_count = 2;
    def.walls = walls;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    SimRng rng;
    sim_rng_seed(&rng, 7);
    int n = tu_random_grains(&b, &rng, 120, radii, 4, 0.0, lx, 0.0, 0.4, lx, 0.0);
    TEST_ASSERT(n > 100);
    double scale = 0.0;
    for (int i = 0; i < b.count; ++i) {
        b.vx[i] = 2.0 * sim_rng_uniform(&rng) - 1.0 + 0.3; /* net drift across the seam */
        b.vy[i] = 2.0 * sim_rng_uniform(&rng) - 1.0;
        scale += tu_mass(SIM_MASS_DISK, rho, b.radius[i]) * (fabs(b.vx[i]) + fabs(b.vy[i]));
    }
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    double px0, py0, px, py;
    sim_world_momentum(w, &px0, &py0);
    TEST_ASSERT(fabs(px0) > 0.1 * scale / n);
    SimEnergy e0 = sim_world_energy(w);
    for (int s = 0; s < 20; ++s) {
        TEST_ASSERT(tu_step(w, 100) == 0);
        sim_world_momentum(w, &px, &py);
        TEST_NEAR(px, px0, 1e-12 * scale);
    }
    /* something happened: energy dissipated in contacts */
    SimEnergy e1 = sim_world_energy(w);
    TEST_ASSERT(e1.kinetic < 0.9 * e0.kinetic);
    SimFrame f;
    sim_world_frame(w, &f);
    TEST_ASSERT(f.periodic == 1);
    for (int i = 0; i < f.count; ++i)
        TEST_ASSERT(f.x[i] >= 0.0 && f.x[i] < lx);
    sim_world_destroy(w);
    return 0;
}

static double angular_momentum(const SimFrame *f, double rho, double *spin)
{
    double total = 0.0;
    *spin = 0.0;
    for (int i = 0; i < f->mobile_count; ++i) {
        double m = tu_mass(SIM_MASS_DISK, rho, f->radius[i]);
        double s = tu_inertia(SIM_MASS_DISK, rho, f->radius[i]) * f->omega[i];
        total += m * (f->x[i] * f->vy[i] - f->y[i] * f->vx[i]) + s;
        *spin += s;
    }
    return total;
}

/* A free cluster (no walls, no gravity) collapsing on itself while turning, with spins opposite
 * to its rotation, Cundall-Strack friction: linear momentum is conserved to rounding; friction
 * moves angular momentum between spins and orbits, and the total is conserved up to the lever-arm
 * difference (torques use R_i and R_j, 000 eq. 4.4, while the centres are R_i + R_j - xi apart:
 * a fraction ~ xi/R of the transfer; 2% here, shrinking as sqrt(1/k)). A wrong torque sign or
 * size would break it by the order of the whole transfer. */
static int angular_momentum_with_friction(void)
{
    const double rho = 1000.0, k = 1e5;
    const double radii[] = {0.02, 0.025, 0.03};
    SimWorldDef def = tu_def(rho, k, 5e-5);
    def.effects |= SIM_EFFECT_FRICTION;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.materials[0].friction = 0.5;
    def.materials[0].tangential_stiffness = 0.75 * k;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.7;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    SimRng rng;
    sim_rng_seed(&rng, 11);
    int n = tu_random_grains(&b, &rng, 60, radii, 3, -0.3, 0.3, -0.3, 0.3, 0.0, 0.0);
    TEST_ASSERT(n > 40);
    for (int i = 0; i < b.count; ++i) {
        /* inward flow plus rigid rotation; spins against it */
        b.vx[i] = -4.0 * b.x[i] - 1.0 * b.y[i];
        b.vy[i] = -4.0 * b.y[i] + 1.0 * b.x[i];
        b.omega[i] = -10.0;
    }
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    SimFrame f;
    sim_world_frame(w, &f);
    double spin0, spin1, l0 = angular_momentum(&f, rho, &spin0), px0, py0, px, py;
    sim_world_momentum(w, &px0, &py0);
    double pscale = 0.0;
    for (int i = 0; i < f.mobile_count; ++i)
        pscale += tu_mass(SIM_MASS_DISK, rho, f.radius[i]) * hypot(f.vx[i], f.vy[i]);
    TEST_ASSERT(tu_step(w, 9000) == 0);
    sim_world_frame(w, &f);
    double l1 = angular_momentum(&f, rho, &spin1);
    sim_world_momentum(w, &px, &py);
    TEST_NEAR(px, px0, 1e-12 * pscale);
    TEST_NEAR(py, py0, 1e-12 * pscale);
    double transfer = fabs(spin1 - spin0);
    TEST_ASSERT(transfer > 0.5 * fabs(spin0));
    TEST_NEAR(l1, l0, 0.05 * transfer);
    sim_world_destroy(w);
    return 0;
}

/* A closed box of four wall segments, no gravity, elastic frictionless grains: kinetic plus
 * spring energy stays within O((omega dt)^2) per contact of its start value. */
static int closed_box_elastic_energy(void)
{
    const double rho = 1000.0, k = 1e5;
    const double radii[] = {0.02, 0.03};
    double m_min = tu_mass(SIM_MASS_DISK, rho, 0.02);
    double tc = TPI * sqrt(m_min / 2.0 / k);
    SimWorldDef def = tu_def(rho, k, tc / 300.0);
    SimWall walls[4] = {{.x0 = 0.0, .y0 = 0.0, .x1 = 0.5, .y1 = 0.0, .species = 0, .motion = -1},
                        {.x0 = 0.5, .y0 = 0.0, .x1 = 0.5, .y1 = 0.5, .species = 0, .motion = -1},
                        {.x0 = 0.5, .y0 = 0.5, .x1 = 0.0, .y1 = 0.5, .species = 0, .motion = -1},
                        {.x0 = 0.0, .y0 = 0.5, .x1 = 0.0, .y1 = 0.0, .species = 0, .motion = -1}};
    def.wall_count = 4;
    def.walls = walls;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    SimRng rng;
    sim_rng_seed(&rng, 3);
    int n = tu_random_grains(&b, &rng, 40, radii, 2, 0.031, 0.469, 0.0, 0.5, 0.0, 0.0);
    TEST_ASSERT(n >= 30);
    for (int i = 0; i < b.count; ++i) {
        b.vx[i] = 2.0 * sim_rng_uniform(&rng) - 1.0;
        b.vy[i] = 2.0 * sim_rng_uniform(&rng) - 1.0;
    }
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    SimEnergy en = sim_world_energy(w);
    double e0 = en.kinetic + en.elastic, worst = 0.0;
    for (int s = 0; s < 100; ++s) {
        TEST_ASSERT(tu_step(w, 100) == 0);
        en = sim_world_energy(w);
        double dev = fabs(en.kinetic + en.elastic - e0) / e0;
        if (dev > worst)
            worst = dev;
    }
    TEST_NEAR(worst, 0.0, 1e-3);
    SimFrame f;
    sim_world_frame(w, &f);
    for (int i = 0; i < f.count; ++i)
        TEST_ASSERT(f.x[i] > 0.0 && f.x[i] < 0.5 && f.y[i] > 0.0 && f.y[i] < 0.5);
    sim_world_destroy(w);
    return 0;
}

TEST_MAIN(TEST_CASE(energy_100_elastic_bounces), TEST_CASE(momentum_periodic_channel),
          TEST_CASE(angular_momentum_with_friction), TEST_CASE(closed_box_elastic_energy))
