/* SPDX-License-Identifier: MIT */
/* Contact laws against their analytic solutions: restitution and duration (000 eqs. 3.22-3.24),
 * tensile clipping, Hertz scaling, mass models, free fall, timing figures. */
#include "sim_test_util.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>

static const double restitutions[] = {0.1, 0.2, 0.3, 0.5, 0.7, 0.87, 0.95};
#define N_RESTITUTIONS ((int)(sizeof restitutions / sizeof restitutions[0]))

/* Steps per contact for the sweeps: t_n/dt = 1000; e_n within tu_e_tol (4 |ln e| dt/t_n), the
 * duration within 1e-3 (measured worst case over phases 6e-4). */
#define STEPS_PER_CONTACT 1000.0
#define T_TOL             1e-3 /* relative, on t_n */

/* One restitution sweep: linear law, damping from e_n (000 eq. 3.25, m_eff per pair),
 * attractive part not clipped so that eq. 3.24 holds exactly. */
static int sweep(int kind, double r0, double r1, SimMassModel model)
{
    const double rho = 1000.0, k = 1e5, v = 0.5;
    double m0 = tu_mass(model, rho, r0), m1 = tu_mass(model, rho, r1);
    double m_eff = kind == TU_PAIR ? m0 * m1 / (m0 + m1) : m0;
    for (int n = 0; n < N_RESTITUTIONS; ++n) {
        double e = restitutions[n];
        double tn = tu_contact_time(m_eff, k, tu_gamma_from_e(e, m_eff, k));
        SimWorldDef def = tu_def(rho, k, tn / STEPS_PER_CONTACT);
        def.mass_model = model;
        def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
        def.materials[0].restitution = e;
        def.contact.clip_tensile = 0;
        TuCollision c = {kind, r0, r1, v, 3.37, 20000};
        TuCollisionResult res;
        TEST_ASSERT(tu_collide(def, &c, &res) == 0);
        TEST_REL(res.e, e, tu_e_tol(e, STEPS_PER_CONTACT));
        TEST_REL(res.t_contact, tn, T_TOL);
        /* the normal force of an unclipped dashpot goes attractive before separation */
        TEST_ASSERT(res.min_force < 0.0);
    }
    return 0;
}

static int restitution_pair_equal(void)
{
    return sweep(TU_PAIR, 0.1, 0.1, SIM_MASS_DISK);
}

static int restitution_pair_unequal(void)
{
    return sweep(TU_PAIR, 0.1, 0.15, SIM_MASS_SPHERE);
}

static int restitution_fixed_grain(void)
{
    return sweep(TU_FIXED, 0.1, 0.105, SIM_MASS_DISK);
}

static int restitution_wall(void)
{
    return sweep(TU_WALL, 0.1, 0.0, SIM_MASS_DISK);
}

/* A fixed grain and a wall segment are both infinite masses: the same collision gives the same
 * e_n, duration and peak force whichever is used. */
static int wall_equals_fixed_grain(void)
{
    const double rho = 1000.0, k = 1e5, m = tu_mass(SIM_MASS_DISK, rho, 0.1);
    double tn = tu_contact_time(m, k, tu_gamma_from_e(0.6, m, k));
    SimWorldDef def = tu_def(rho, k, tn / 500.0);
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.6;
    TuCollision cw = {TU_WALL, 0.1, 0.0, 0.8, 2.5, 20000};
    TuCollision cf = {TU_FIXED, 0.1, 0.2, 0.8, 2.5, 20000};
    TuCollisionResult rw, rf;
    TEST_ASSERT(tu_collide(def, &cw, &rw) == 0);
    TEST_ASSERT(tu_collide(def, &cf, &rf) == 0);
    TEST_NEAR(rw.e, rf.e, 1e-9);
    TEST_REL(rw.t_contact, rf.t_contact, 1e-9);
    TEST_REL(rw.peak_force, rf.peak_force, 1e-9);
    return 0;
}

/* Elastic linear contact: e = 1, t = pi sqrt(m_eff/k), peak force v sqrt(k m_eff). */
static int elastic_linear_pair(void)
{
    const double rho = 1000.0, k = 1e5, v = 0.7;
    double m = tu_mass(SIM_MASS_DISK, rho, 0.1), m_eff = m / 2.0;
    double tn = TPI * sqrt(m_eff / k);
    SimWorldDef def = tu_def(rho, k, tn / STEPS_PER_CONTACT);
    TuCollision c = {TU_PAIR, 0.1, 0.1, v, 1.7, 20000};
    TuCollisionResult res;
    TEST_ASSERT(tu_collide(def, &c, &res) == 0);
    /* velocity Verlet across the kink of the force at xi = 0: O((omega dt)^2) ~ 1e-5 */
    TEST_NEAR(res.e, 1.0, 1e-4);
    TEST_REL(res.t_contact, tn, 1e-4);
    TEST_REL(res.peak_force, v * sqrt(k * m_eff), 1e-4);
    TEST_ASSERT(res.min_force >= 0.0);
    return 0;
}

/* clip_tensile = 1: F_n never negative; the pair separates where k xi + gamma xidot = 0, so the
 * measured e_n is the larger analytic value of tu_e_clipped. clip_tensile = 0 gives eq. 3.24. */
static int tensile_clipping(void)
{
    const double rho = 1000.0, k = 1e5, v = 0.5;
    double m = tu_mass(SIM_MASS_DISK, rho, 0.1), m_eff = m / 2.0;
    const double es[] = {0.1, 0.3, 0.6, 0.9};
    for (int n = 0; n < 4; ++n) {
        double e = es[n];
        double tn = tu_contact_time(m_eff, k, tu_gamma_from_e(e, m_eff, k));
        SimWorldDef def = tu_def(rho, k, tn / STEPS_PER_CONTACT);
        def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
        def.materials[0].restitution = e;
        def.contact.clip_tensile = 1;
        TuCollision c = {TU_PAIR, 0.1, 0.1, v, 2.2, 20000};
        TuCollisionResult clipped, free_;
        TEST_ASSERT(tu_collide(def, &c, &clipped) == 0);
        TEST_ASSERT(clipped.min_force >= 0.0);
        double e_clip = tu_e_clipped(e, m_eff, k);
        TEST_ASSERT(e_clip > e);
        TEST_REL(clipped.e, e_clip, tu_e_tol(e, STEPS_PER_CONTACT));
        def.contact.clip_tensile = 0;
        TEST_ASSERT(tu_collide(def, &c, &free_) == 0);
        TEST_ASSERT(free_.min_force < 0.0);
        TEST_REL(free_.e, e, tu_e_tol(e, STEPS_PER_CONTACT));
        TEST_ASSERT(clipped.e > free_.e);
    }
    return 0;
}

/* Elastic Hertz contact, F = k xi^{3/2}: t_c = 2 I xi_max / v with
 * xi_max = (5 m_eff v^2 / (4 k))^{2/5} and I = int_0^1 (1 - u^{5/2})^{-1/2} du = (2/5) B(2/5, 1/2),
 * so t_c ~ v^{-1/5}. */
static int hertz_contact_time_scaling(void)
{
    const double rho = 1000.0, k = 1e7;
    double m = tu_mass(SIM_MASS_DISK, rho, 0.1);
    double integral = 0.4 * tgamma(0.4) * tgamma(0.5) / tgamma(0.9);
    const double vs[] = {0.25, 1.0, 4.0};
    double tc[3];
    double t_fast = 2.0 * integral * pow(5.0 * m * 16.0 / (4.0 * k), 0.4) / 4.0;
    for (int n = 0; n < 3; ++n) {
        SimWorldDef def = tu_def(rho, k, t_fast / 2000.0);
        def.contact.normal = SIM_NORMAL_HERTZ;
        TuCollision c = {TU_FIXED, 0.1, 0.1, vs[n], 3.1, 200000};
        TuCollisionResult res;
        TEST_ASSERT(tu_collide(def, &c, &res) == 0);
        double xi_max = pow(5.0 * m * vs[n] * vs[n] / (4.0 * k), 0.4);
        TEST_REL(res.t_contact, 2.0 * integral * xi_max / vs[n], 1e-3);
        TEST_NEAR(res.e, 1.0, 1e-4);
        TEST_REL(res.peak_force, k * pow(xi_max, 1.5), 1e-3);
        tc[n] = res.t_contact;
    }
    double slope1 = log(tc[1] / tc[0]) / log(vs[1] / vs[0]);
    double slope2 = log(tc[2] / tc[1]) / log(vs[2] / vs[1]);
    TEST_NEAR(slope1, -0.2, 2e-3);
    TEST_NEAR(slope2, -0.2, 2e-3);
    return 0;
}

/* Hertz with the dashpot in sqrt(xi) gamma xidot (Kuwabara-Kono form): in units of the elastic
 * contact time t_c ~ v^{-1/5} the damping is gamma t_c / m, so for weak damping
 * 1 - e ~ v^{1/5}: e decreases with the impact speed. */
static int hertz_restitution_speed_dependence(void)
{
    const double rho = 1000.0, k = 1e7;
    double m = tu_mass(SIM_MASS_DISK, rho, 0.1);
    double integral = 0.4 * tgamma(0.4) * tgamma(0.5) / tgamma(0.9);
    const double vs[] = {0.25, 4.0};
    double one_minus_e[2];
    double t_fast = 2.0 * integral * pow(5.0 * m * 16.0 / (4.0 * k), 0.4) / 4.0;
    for (int n = 0; n < 2; ++n) {
        SimWorldDef def = tu_def(rho, k, t_fast / 2000.0);
        def.contact.normal = SIM_NORMAL_HERTZ;
        def.contact.clip_tensile = 0;
        def.materials[0].damping_mode = SIM_DAMPING_GAMMA;
        def.materials[0].normal_damping = 2e-4 * k; /* 1 - e of a few percent */
        TuCollision c = {TU_FIXED, 0.1, 0.1, vs[n], 3.1, 200000};
        TuCollisionResult res;
        TEST_ASSERT(tu_collide(def, &c, &res) == 0);
        TEST_ASSERT(res.e > 0.9 && res.e < 1.0);
        one_minus_e[n] = 1.0 - res.e;
    }
    /* first order in the damping; the second-order term shifts the ratio by ~ (1 - e) */
    TEST_REL(one_minus_e[1] / one_minus_e[0], pow(16.0, 0.2), 0.05);
    return 0;
}

/* Disk: m = rho pi r^2, I = m r^2 / 2; sphere: m = rho 4/3 pi r^3, I = 2/5 m r^2. Checked through
 * the momentum and the kinetic and rotational energies the library reports. */
static int mass_models(void)
{
    const double rho = 1190.0, r = 0.08, vx = 2.0, vy = -0.5, omega = 3.0;
    for (int model = 0; model < 2; ++model) {
        SimWorldDef def = tu_def(rho, 1e5, 1e-5);
        def.mass_model = (SimMassModel)model;
        /* rotation is integrated (and counted in the energy) only when a law makes torques */
        def.effects |= SIM_EFFECT_FRICTION;
        def.contact.tangential = SIM_TANGENTIAL_REGULARISED;
        SimGrainBuffer b;
        sim_grain_buffer_init(&b);
        int g = sim_grain_buffer_add(&b, 0.3, 0.7, r, 0, 0u, -1);
        b.vx[g] = vx;
        b.vy[g] = vy;
        b.omega[g] = omega;
        SimWorld *w = tu_create(&def, &b);
        sim_grain_buffer_free(&b);
        TEST_ASSERT(w);
        double m = model == SIM_MASS_DISK ? rho * TPI * r * r : rho * 4.0 / 3.0 * TPI * r * r * r;
        double inertia = (model == SIM_MASS_DISK ? 0.5 : 0.4) * m * r * r;
        double px, py, dm, dd;
        sim_world_momentum(w, &px, &py);
        TEST_REL(px, m * vx, 1e-12);
        TEST_REL(py, m * vy, 1e-12);
        SimEnergy en = sim_world_energy(w);
        TEST_REL(en.kinetic, 0.5 * m * (vx * vx + vy * vy), 1e-12);
        TEST_REL(en.rotational, 0.5 * inertia * omega * omega, 1e-12);
        sim_world_means(w, &dd, &dm);
        TEST_REL(dm, m, 1e-12);
        TEST_REL(dd, 2.0 * r, 1e-12);
        sim_world_destroy(w);
    }
    return 0;
}

/* Free fall from rest. Velocity Verlet, RK4 and Gear integrate a constant force exactly:
 * y = y0 - g t^2/2 to rounding. Symplectic Euler (000 eqs. 4.16-4.17: v first, then x with the
 * new v) gives y_n = y0 - g dt^2 n (n + 1) / 2 exactly. */
static int free_fall(void)
{
    const double y0 = 1.5, dt = 1e-3;
    const long n = 1000;
    for (int integ = 0; integ < SIM_INTEGRATOR_COUNT; ++integ) {
        SimWorldDef def = tu_def(1000.0, 1e5, dt);
        def.gravity_y = -G0;
        def.integrator = (SimIntegrator)integ;
        SimGrainBuffer b;
        sim_grain_buffer_init(&b);
        sim_grain_buffer_add(&b, 0.0, y0, 0.01, 0, 0u, -1);
        SimWorld *w = tu_create(&def, &b);
        sim_grain_buffer_free(&b);
        TEST_ASSERT(w);
        SimEnergy e0 = sim_world_energy(w);
        TEST_ASSERT(tu_step(w, n) == 0);
        SimFrame f;
        sim_world_frame(w, &f);
        double t = (double)n * dt;
        TEST_REL(f.time, t, 1e-12);
        TEST_NEAR(f.x[0], 0.0, 0.0);
        if (integ != SIM_INTEGRATOR_STORMER_VERLET)
            TEST_REL(f.vy[0], -G0 * t, 1e-12);
        if (integ == SIM_INTEGRATOR_SYMPLECTIC_EULER) {
            TEST_NEAR(f.y[0], y0 - G0 * dt * dt * (double)n * (double)(n + 1) / 2.0, 1e-12);
        } else if (integ == SIM_INTEGRATOR_STORMER_VERLET) {
            /* positions exact (second-order start x(-dt) = x - v dt + a dt^2/2); the reported
             * velocity is the backward difference (x(t) - x(t - dt)) / dt = v(t - dt/2) */
            TEST_NEAR(f.y[0], y0 - 0.5 * G0 * t * t, 1e-12);
            TEST_NEAR(f.vy[0], -G0 * t, 0.5 * G0 * dt * (1.0 + 1e-9));
        } else {
            TEST_NEAR(f.y[0], y0 - 0.5 * G0 * t * t, 1e-12);
            SimEnergy e1 = sim_world_energy(w);
            TEST_REL(e1.total, e0.total, 1e-12);
        }
        sim_world_destroy(w);
    }
    return 0;
}

/* sim_world_def_timing: for two equal mobile grains on an undamped linear law the worst pair has
 * m_eff = m/2, t_c = pi sqrt(m_eff/k) (000 eq. 3.22), and steps_per_contact = t_c / dt. */
static int timing_contact_time(void)
{
    const double rho = 1000.0, k = 2e5, r = 0.05, dt = 1e-5;
    SimWorldDef def = tu_def(rho, k, dt);
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 0.0, r, 0, 0u, -1);
    sim_grain_buffer_add(&b, 1.0, 0.0, r, 0, 0u, -1);
    def.grains = sim_grain_buffer_view(&b);
    SimTiming tm = sim_world_def_timing(&def);
    double tc = TPI * sqrt(tu_mass(SIM_MASS_DISK, rho, r) / 2.0 / k);
    TEST_REL(tm.contact_time_min, tc, 1e-9);
    TEST_REL(tm.time_step, dt, 1e-12);
    TEST_REL(tm.steps_per_contact, tc / dt, 1e-9);
    TEST_ASSERT(tm.stability_limit > dt);
    /* time_step = 0: chosen from steps_per_contact */
    def.time_step = 0.0;
    def.steps_per_contact = 80.0;
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    TEST_REL(sim_world_time_step(w), tc / 80.0, 1e-9);
    sim_world_destroy(w);
    return 0;
}

/* Worst |e - e_n| over 16 phases (4 first-touch instants within a step x contact lengths of n,
 * n + 1/4, n + 1/2, n + 3/4 steps), as bench/bench_accuracy.c measures it. */
static double worst_e_error(int kind, double e, double n, SimOnset onset)
{
    const double rho = 1000.0, k = 1e5, v = 0.5, r0 = 0.1, r1 = 0.15;
    double m0 = tu_mass(SIM_MASS_SPHERE, rho, r0), m1 = tu_mass(SIM_MASS_SPHERE, rho, r1);
    double m_eff = kind == TU_PAIR ? m0 * m1 / (m0 + m1) : m0;
    double tn = tu_contact_time(m_eff, k, tu_gamma_from_e(e, m_eff, k));
    double worst = 0.0;
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
            SimWorldDef def = tu_def(rho, k, tn / (n + 0.25 * b));
            def.mass_model = SIM_MASS_SPHERE;
            def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
            def.materials[0].restitution = e;
            def.contact.clip_tensile = 0;
            def.contact.onset = onset;
            TuCollision c = {kind, r0, r1, v, 3.0 + 0.25 * a + 0.1, 100000};
            TuCollisionResult res;
            if (tu_collide(def, &c, &res) != 0)
                return INFINITY;
            worst = fmax(worst, fabs(res.e - e));
        }
    return worst;
}

/* Least-squares slope of -log(error) against log(n). */
static double observed_order(int kind, double e, SimOnset onset, double *at_40)
{
    static const double ns[] = {20.0, 40.0, 80.0, 160.0, 320.0, 640.0, 1280.0, 2000.0};
    const int count = (int)(sizeof ns / sizeof ns[0]);
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    for (int q = 0; q < count; ++q) {
        double err = worst_e_error(kind, e, ns[q], onset);
        if (q == 1)
            *at_40 = err;
        double lx = log(ns[q]), ly = log(err);
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
    }
    return -(count * sxy - sx * sy) / (count * sxx - sx * sx);
}

/* Event-aware onset (docs/accuracy.md, eqs. A1-A5): e_n converges at second order with velocity
 * Verlet (n = 20 ... 2000, worst of 16 phases), the step onset at first order; both for a pair of
 * unequal disks and against a wall. */
static int event_onset_second_order(void)
{
    const double es[] = {0.2, 0.5, 0.9};
    for (int q = 0; q < 3; ++q) {
        double step40 = 0.0, event40 = 0.0;
        double p_step = observed_order(TU_PAIR, es[q], SIM_ONSET_STEP, &step40);
        double p_event = observed_order(TU_PAIR, es[q], SIM_ONSET_EVENT, &event40);
        fprintf(stderr, "e_n %.1f: observed order %.2f (step), %.2f (event); n = 40: %.2g, %.2g\n",
                es[q], p_step, p_event, step40, event40);
        TEST_ASSERT(p_step > 0.8 && p_step < 1.3);
        TEST_ASSERT(p_event >= 1.8);
        TEST_ASSERT(event40 < step40);
    }
    double at40 = 0.0, wall = observed_order(TU_WALL, 0.5, SIM_ONSET_EVENT, &at40);
    fprintf(stderr, "wall, e_n 0.5: observed order %.2f (event)\n", wall);
    TEST_ASSERT(wall >= 1.8);
    return 0;
}

/* The option is refused where its derivation does not hold. */
static int event_onset_refused(void)
{
    SimWorldDef def = tu_def(1000.0, 1e5, 1e-5);
    def.contact.onset = SIM_ONSET_EVENT;
    def.contact.normal = SIM_NORMAL_HERTZ;
    SimError err;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 0.0, 0.1, 0, 0u, -1);
    def.grains = sim_grain_buffer_view(&b);
    SimWorld *w = sim_world_create(&def, &err);
    TEST_ASSERT(w == NULL && strcmp(err.field, "contact.onset") == 0);
    def.contact.normal = SIM_NORMAL_LINEAR;
    def.integrator = SIM_INTEGRATOR_RK4;
    w = sim_world_create(&def, &err);
    TEST_ASSERT(w == NULL && strcmp(err.field, "contact.onset") == 0);
    sim_grain_buffer_free(&b);
    return 0;
}

TEST_MAIN(TEST_CASE(restitution_pair_equal), TEST_CASE(restitution_pair_unequal),
          TEST_CASE(restitution_fixed_grain), TEST_CASE(restitution_wall),
          TEST_CASE(wall_equals_fixed_grain), TEST_CASE(elastic_linear_pair),
          TEST_CASE(tensile_clipping), TEST_CASE(hertz_contact_time_scaling),
          TEST_CASE(hertz_restitution_speed_dependence), TEST_CASE(mass_models),
          TEST_CASE(free_fall), TEST_CASE(timing_contact_time), TEST_CASE(event_onset_second_order),
          TEST_CASE(event_onset_refused))
