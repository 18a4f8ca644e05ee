/* SPDX-License-Identifier: MIT */
/* Observed convergence order of each integrator (SIM_INTEGRATOR_*).
 *
 * Smooth case: a grain resting on a fixed grain under gravity, released with extra compression,
 * never leaves the contact, so it is a harmonic oscillator about y_eq = 0.2 - m g / k:
 * y = y_eq - A cos(w t). The error after 2.3 periods (a generic phase: at a turning point the
 * O(dt) part of symplectic Euler's error vanishes), in phase space sqrt(dy^2 + (dv/w)^2), is
 * measured at dt = P/N, P/2N, P/4N; the order is log2 of successive error ratios (both must
 * pass). Stormer-Verlet reports the backward-difference velocity (x(t) - x(t - dt)) / dt, first
 * order by construction, so its order is measured on the position alone. Non-smooth case: an
 * elastic head-on collision (the force has a kink at xi = 0), error |e - 1| maximised over four
 * phases of the first contact step. */
#include "sim_test_util.h"
#include "test.h"

#define RHO   1000.0
#define DELTA 0.01 /* static overlap m g / k, m */
#define AMP   0.005

static double oscillator_error(SimIntegrator integ, int n, double zeta, int position_only)
{
    double m = tu_mass(SIM_MASS_DISK, RHO, 0.1), k = m * G0 / DELTA, w = sqrt(k / m);
    double period = 2.0 * TPI / w, dt = period / n;
    SimWorldDef def = tu_def(RHO, k, dt);
    def.gravity_y = -G0;
    def.integrator = integ;
    def.materials[0].normal_damping = 2.0 * zeta * m * w;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    double y_eq = 0.2 - DELTA;
    sim_grain_buffer_add(&b, 0.0, y_eq - AMP, 0.1, 0, 0u, -1);
    sim_grain_buffer_add(&b, 0.0, 0.0, 0.1, 0, SIM_GRAIN_FIXED, -1);
    SimWorld *w_ = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    if (!w_)
        return -1.0;
    if (tu_step(w_, 23L * n / 10)) {
        sim_world_destroy(w_);
        return -1.0;
    }
    SimFrame f;
    sim_world_frame(w_, &f);
    int g = tu_index(&f, 0);
    double t = f.time, wd = w * sqrt(1.0 - zeta * zeta), decay = exp(-zeta * w * t);
    double u = decay * (-AMP * cos(wd * t) - zeta * w * AMP / wd * sin(wd * t));
    double udot = decay * AMP * sin(wd * t) * w * w / wd;
    double dy = f.y[g] - (y_eq + u), dv = f.vy[g] - udot;
    sim_world_destroy(w_);
    if (position_only)
        return fabs(dy);
    return sqrt(dy * dy + (dv / w) * (dv / w));
}

static int check_oscillator_order(SimIntegrator integ, int n, double zeta, double lo, double hi)
{
    int pos = integ == SIM_INTEGRATOR_STORMER_VERLET;
    double e1 = oscillator_error(integ, n, zeta, pos),
           e2 = oscillator_error(integ, 2 * n, zeta, pos);
    double e3 = oscillator_error(integ, 4 * n, zeta, pos);
    TEST_ASSERT(e1 > 0.0 && e2 > 0.0 && e3 > 0.0);
    double p1 = log2(e1 / e2), p2 = log2(e2 / e3);
    if (!(p1 >= lo && p2 >= lo && p1 <= hi && p2 <= hi))
        fprintf(stderr, "%s zeta %g: errors %.3g %.3g %.3g, orders %.3f %.3f\n",
                sim_integrator_name(integ), zeta, e1, e2, e3, p1, p2);
    TEST_ASSERT(p1 >= lo && p2 >= lo);
    TEST_ASSERT(p1 <= hi && p2 <= hi);
    /* and the coarsest step is already accurate to a few percent of the amplitude */
    TEST_ASSERT(e1 < 0.3 * AMP);
    return 0;
}

static int order_symplectic_euler(void)
{
    return check_oscillator_order(SIM_INTEGRATOR_SYMPLECTIC_EULER, 40, 0.0, 0.8, 1.3);
}

static int order_velocity_verlet(void)
{
    return check_oscillator_order(SIM_INTEGRATOR_VELOCITY_VERLET, 20, 0.0, 1.8, 2.3);
}

static int order_stormer_verlet(void)
{
    return check_oscillator_order(SIM_INTEGRATOR_STORMER_VERLET, 20, 0.0, 1.8, 2.3);
}

static int order_gear(void)
{
    return check_oscillator_order(SIM_INTEGRATOR_GEAR, 20, 0.0, 2.5, 6.0);
}

static int order_rk4(void)
{
    return check_oscillator_order(SIM_INTEGRATOR_RK4, 20, 0.0, 3.5, 4.5);
}

/* With a dashpot (zeta = 0.1) the force depends on the velocity; every scheme must keep its
 * order when the velocity it feeds to the force is consistent (RK4 stages, Gear predictor), and
 * velocity Verlet at least first order (the damping sees a lagged velocity). */
static int order_with_damping(void)
{
    if (check_oscillator_order(SIM_INTEGRATOR_VELOCITY_VERLET, 20, 0.1, 0.9, 2.3))
        return 1;
    if (check_oscillator_order(SIM_INTEGRATOR_SYMPLECTIC_EULER, 40, 0.1, 0.8, 1.3))
        return 1;
    if (check_oscillator_order(SIM_INTEGRATOR_RK4, 20, 0.1, 3.5, 4.5))
        return 1;
    return 0;
}

/* Elastic collision: max over phases of |e - 1|, t_c / dt = n. */
static double collision_error(SimIntegrator integ, double n)
{
    double m = tu_mass(SIM_MASS_DISK, RHO, 0.1), k = 1e5, tc = TPI * sqrt(m / 2.0 / k);
    SimWorldDef def = tu_def(RHO, k, tc / n);
    def.integrator = integ;
    double worst = 0.0;
    for (int p = 0; p < 4; ++p) {
        TuCollision c = {TU_PAIR, 0.1, 0.1, 0.5, 3.0 + 0.25 * p, 100000};
        TuCollisionResult r;
        if (tu_collide(def, &c, &r))
            return -1.0;
        if (fabs(r.e - 1.0) > worst)
            worst = fabs(r.e - 1.0);
    }
    return worst;
}

static int collision_orders(void)
{
    const struct {
        SimIntegrator integ;
        double lo;
    } cases[] = {{SIM_INTEGRATOR_SYMPLECTIC_EULER, 0.8},
                 {SIM_INTEGRATOR_VELOCITY_VERLET, 1.8},
                 {SIM_INTEGRATOR_STORMER_VERLET, 1.8},
                 {SIM_INTEGRATOR_RK4, 1.8},
                 {SIM_INTEGRATOR_GEAR, 1.8}};

    for (int k = 0; k < 5; ++k) {
        double e1 = collision_error(cases[k].integ, 25.0),
               e2 = collision_error(cases[k].integ, 50.0);
        double e3 = collision_error(cases[k].integ, 100.0);
        TEST_ASSERT(e1 > 0.0 && e2 > 0.0 && e3 > 0.0);
        double p = log2(e1 / e3) / 2.0; /* over the whole range: phase noise averages out */
        if (p < cases[k].lo)
            fprintf(stderr, "%s: |e-1| %.3g %.3g %.3g, order %.3f\n",
                    sim_integrator_name(cases[k].integ), e1, e2, e3, p);
        TEST_ASSERT(p >= cases[k].lo);
        TEST_ASSERT(e3 < e2 && e2 < e1);
    }
    return 0;
}

/* Names round-trip. */
static int integrator_names(void)
{
    for (int k = 0; k < SIM_INTEGRATOR_COUNT; ++k)
        TEST_ASSERT(sim_integrator_from_name(sim_integrator_name((SimIntegrator)k)) == k);
    TEST_ASSERT(sim_integrator_from_name("velocity_verlet") == SIM_INTEGRATOR_VELOCITY_VERLET);
    TEST_ASSERT(sim_integrator_from_name("rk4") == SIM_INTEGRATOR_RK4);
    TEST_ASSERT(sim_integrator_from_name("leapfrog-ish") == -1);
    return 0;
}

TEST_MAIN(TEST_CASE(order_symplectic_euler), TEST_CASE(order_velocity_verlet),
          TEST_CASE(order_stormer_verlet), TEST_CASE(order_gear), TEST_CASE(order_rk4),
          TEST_CASE(order_with_damping), TEST_CASE(collision_orders), TEST_CASE(integrator_names))
