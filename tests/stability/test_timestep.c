/* SPDX-License-Identifier: MIT */
/* Stability hard cases about the time step: stiff contacts with the automatic dt, dt at 0.9 and
 * 1.1 of the stated stability limit for each integrator, the thesis 000 dt = 1e-4 case, and the
 * Hertz law at high impact speed. */
#include "stab_util.h"
#include "test.h"

/* A grain stack bouncing on a fixed grain: fixed grain at the origin, two mobile grains above it
 * (first dropped from a gap of `drop` diameters), so both mobile-fixed and mobile-mobile pairs
 * collide repeatedly. Disk masses, radius 0.5 m, density 1 kg/m^2, k_n = 1e4 N/m. */
static SimWorld *bouncing_stack(SimIntegrator integrator, double dt_over_limit, double drop,
                                double restitution, SimTiming *timing)
{
    const double r = 0.5;
    SimWorldDef def = tu_def(1.0, 1e4, 0.0);
    def.integrator = integrator;
    def.gravity_y = -G0;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = restitution;
    def.guard_max_speed = 0.0; /* automatic */
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 0.0, r, 0, SIM_GRAIN_FIXED, -1);
    sim_grain_buffer_add(&b, 0.0, 2.0 * r + drop * 2.0 * r, r, 0, 0u, -1);
    sim_grain_buffer_add(&b, 0.0, 4.0 * r + 2.0 * drop * 2.0 * r, r, 0, 0u, -1);
    def.grains = sim_grain_buffer_view(&b);
    *timing = sim_world_def_timing(&def);
    def.time_step = dt_over_limit * timing->stability_limit;
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    return w;
}

/* k_n = 1e8 N/m (glass-like, sphere masses of 5 mm grains) with time_step = 0: the world chooses
 * dt = min(t_c / steps_per_contact, limit / 2). 40 grains dropped ~0.1-0.2 r onto a floor of
 * fixed grains and left 0.04 s (~1700 contact times).
 * Bounds: dt as documented and below the stated limit; no NaN; overlap < 0.01 d (the analytic
 * impact overlap is ~1e-4 d); total energy never exceeds the initial one by more than 1e-3 of
 * the released potential energy scale m_total g H (velocity Verlet's bounded O((omega dt)^2)
 * in-contact error at 50 steps per contact). */
static int stiff_contacts_auto_dt(void)
{
    const double r = 0.005, rho = 2500.0;
    SimWorldDef def = tu_def(rho, 1e8, 0.0);
    def.mass_model = SIM_MASS_SPHERE;
    def.gravity_y = -G0;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.5;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    st_fixed_box(&b, 20.0 * r * 2.0, 20.0 * r, r, 0);
    SimRng rng;
    sim_rng_seed(&rng, 11);
    st_lattice(&b, &rng, 40, 1.5 * r, 40.0 * r - 1.5 * r, r, 0.9 * r, r, 0.2 * r);
    def.grains = sim_grain_buffer_view(&b);
    SimTiming t = sim_world_def_timing(&def);
    SimWorld *w = tu_create(&def, &b);
    TEST_ASSERT(w);
    double m = tu_mass(SIM_MASS_SPHERE, rho, 0.9 * r);
    double expected_dt = fmin(t.contact_time_min / 50.0, 0.5 * t.stability_limit);
    TEST_REL(sim_world_time_step(w), expected_dt, 1e-12);
    TEST_ASSERT(sim_world_time_step(w) <= t.stability_limit);
    TEST_ASSERT(t.contact_time_min < 2.0 * TPI * sqrt(m / 1e8)); /* the stiff pair sets t_c */
    double scale = 40.0 * m * G0 * 20.0 * r;
    long steps = (long)(0.04 / sim_world_time_step(w));
    StRun run = st_run(w, steps, 500);
    st_report("stiff_contacts_auto_dt", &run);
    TEST_ASSERT(run.status == SIM_OK && run.finite);
    TEST_ASSERT(run.overlap_max < 0.01);
    TEST_ASSERT(run.e_max <= run.e0 + 1e-3 * scale);
    TEST_ASSERT(run.e_last < run.e0); /* restitution 0.5: it dissipated */
    sim_world_destroy(w);
    sim_grain_buffer_free(&b);
    return 0;
}

/* dt = 1.1 x the stated limit is refused by both sim_world_def_validate and sim_world_create,
 * with SIM_ERROR_INVALID on field "time_step" and a message naming the stability limit; for all
 * five integrators. */
static int dt_above_limit_refused(void)
{
    for (int k = 0; k < SIM_INTEGRATOR_COUNT; ++k) {
        SimTiming t;
        SimWorld *w = bouncing_stack((SimIntegrator)k, 1.1, 0.5, 0.5, &t);
        TEST_ASSERT(w == NULL);
        SimWorldDef def = tu_def(1.0, 1e4, 0.0);
        def.integrator = (SimIntegrator)k;
        def.gravity_y = -G0;
        def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
        def.materials[0].restitution = 0.5;
        SimGrainBuffer b;
        sim_grain_buffer_init(&b);
        sim_grain_buffer_add(&b, 0.0, 0.0, 0.5, 0, SIM_GRAIN_FIXED, -1);
        sim_grain_buffer_add(&b, 0.0, 2.0, 0.5, 0, 0u, -1);
        def.grains = sim_grain_buffer_view(&b);
        SimTiming tt = sim_world_def_timing(&def);
        TEST_ASSERT(isfinite(tt.stability_limit) && tt.stability_limit > 0.0);
        def.time_step = 1.1 * tt.stability_limit;
        SimError err;
        TEST_ASSERT(sim_world_def_validate(&def, &err) == SIM_ERROR_INVALID);
        TEST_ASSERT(err.status == SIM_ERROR_INVALID);
        TEST_ASSERT(strcmp(err.field, "time_step") == 0);
        TEST_ASSERT(st_mentions(err.message, "stability limit"));
        memset(&err, 0, sizeof err);
        TEST_ASSERT(sim_world_create(&def, &err) == NULL);
        TEST_ASSERT(err.status == SIM_ERROR_INVALID);
        TEST_ASSERT(st_mentions(err.message, "stability limit"));
        def.time_step = 0.9 * tt.stability_limit; /* and just below it, accepted */
        TEST_ASSERT(sim_world_def_validate(&def, &err) == SIM_OK);
        sim_grain_buffer_free(&b);
    }
    return 0;
}

/* Each of the five integrators at 0.9 x its own stated limit on the bouncing two-grain stack
 * (e_n = 0.5), 400 contact times of bouncing. Bounds: accepted; never UNSTABLE; no NaN; overlap
 * < 0.2 d (at ~1.7 steps per contact the entry overlap is up to v dt ~ 0.05 d); total energy
 * never exceeds the initial one by more than 10 % of the drop energy 2 m g h (few-step contacts
 * have large per-collision energy errors, but they must not accumulate); and the stack loses
 * energy overall (E_last < E0). */
static int integrators_at_09_limit(void)
{
    for (int k = 0; k < SIM_INTEGRATOR_COUNT; ++k) {
        SimTiming t;
        SimWorld *w = bouncing_stack((SimIntegrator)k, 0.9, 0.5, 0.5, &t);
        TEST_ASSERT(w);
        const double m = tu_mass(SIM_MASS_DISK, 1.0, 0.5), h = 0.5;
        double scale = 2.0 * m * G0 * h;
        long steps = (long)(400.0 * t.contact_time_min / sim_world_time_step(w)) + 1000;
        StRun run = st_run(w, steps, 10);
        fprintf(stderr, "%s: dt %g limit %g t_c %g: ", sim_integrator_name((SimIntegrator)k),
                sim_world_time_step(w), t.stability_limit, t.contact_time_min);
        st_report("integrators_at_09_limit", &run);
        TEST_ASSERT(run.status == SIM_OK && run.finite);
        TEST_ASSERT(run.overlap_max < 0.2);
        TEST_ASSERT(run.e_max <= run.e0 + 0.1 * scale);
        TEST_ASSERT(run.e_last < run.e0);
        sim_world_destroy(w);
    }
    return 0;
}

/* Velocity Verlet at 0.9 x the limit on a resting multi-contact configuration: a grain resting
 * in the pocket between two fixed grains and a second grain on top of it. The stated limit is
 * "the largest stable dt" (sim.h SimTiming), so a resting pile must stay at rest.
 * Bounds: never UNSTABLE, no NaN, kinetic energy after 2000 steps < 1e-6 m g d per grain, overlap
 * < 0.1 d. */
static int dt_09_limit_resting_pocket(void)
{
    const double r = 0.5;
    SimWorldDef def = tu_def(1.0, 1e4, 0.0);
    def.gravity_y = -G0;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.5;
    def.guard_max_speed = 0.0;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, -1.2 * r, 0.0, r, 0, SIM_GRAIN_FIXED, -1);
    sim_grain_buffer_add(&b, 1.2 * r, 0.0, r, 0, SIM_GRAIN_FIXED, -1);
    double y1 = sqrt(4.0 * r * r - 1.44 * r * r);
    sim_grain_buffer_add(&b, 0.0, y1, r, 0, 0u, -1);
    sim_grain_buffer_add(&b, 0.0, y1 + 2.0 * r, r, 0, 0u, -1);
    def.grains = sim_grain_buffer_view(&b);
    SimTiming t = sim_world_def_timing(&def);
    def.time_step = 0.9 * t.stability_limit;
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    StRun run = st_run(w, 4000, 10);
    st_report("dt_09_limit_resting_pocket", &run);
    const double m = tu_mass(SIM_MASS_DISK, 1.0, r);
    SimEnergy e = sim_world_energy(w);
    TEST_ASSERT(run.status == SIM_OK && run.finite);
    TEST_ASSERT(run.overlap_max < 0.1);
    TEST_ASSERT(e.kinetic < 2.0 * 1e-6 * m * G0 * 2.0 * r);
    sim_world_destroy(w);
    return 0;
}

/* Thesis 000 material (k_n 7e5 N/m, gamma_n 1.5e3 kg/s, rho 1190 kg/m^3, sphere masses,
 * r = 0.08 m +- 8 %, walls of fixed grains of r_max = 0.105 m) with the thesis's failing
 * dt = 1e-4 s (~69 steps per contact). */
static SimWorldDef thesis000_def(SimGrainBuffer *b, int grains)
{
    const double r_max = 0.105, width = 20 * 2 * r_max;
    sim_build_fixed_box(b, 0.0, width, 0.0, 60 * r_max, r_max, 0);
    SimRainDef rain =
        sim_rain_def_thesis000(1.5 * r_max, width - 1.5 * r_max, 1.5 * r_max, 200 * r_max, grains);
    SimRng rng;
    sim_rng_seed(&rng, 1);
    sim_build_rain(b, &rain, &rng);
    SimWorldDef def = sim_world_def_default(); /* defaults are the thesis 000 material */
    def.effects = SIM_EFFECT_FRICTION;
    def.mass_model = SIM_MASS_SPHERE;
    def.time_step = 1e-4;
    def.grains = sim_grain_buffer_view(b);
    return def;
}

/* With max_dt_fraction = 0.01 (>= 100 steps per contact) dt = 1e-4 is refused at set-up:
 * SIM_ERROR_INVALID on "time_step", message naming the contact time. */
static int thesis000_dt_1e4_fraction_refused(void)
{
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    SimWorldDef def = thesis000_def(&b, 200);
    def.max_dt_fraction = 0.01;
    SimTiming t = sim_world_def_timing(&def);
    TEST_ASSERT(t.steps_per_contact > 50.0 && t.steps_per_contact < 100.0);
    SimError err;
    TEST_ASSERT(sim_world_def_validate(&def, &err) == SIM_ERROR_INVALID);
    TEST_ASSERT(strcmp(err.field, "time_step") == 0);
    TEST_ASSERT(st_mentions(err.message, "contact time"));
    TEST_ASSERT(sim_world_create(&def, &err) == NULL);
    TEST_ASSERT(err.status == SIM_ERROR_INVALID);
    sim_grain_buffer_free(&b);
    return 0;
}

/* Without the fraction, dt = 1e-4 is accepted (it is far below the velocity-Verlet limit) and must
 * either run stably or stop with SIM_ERROR_UNSTABLE. What happens: it runs stably (our integrator
 * evaluates all forces before moving any grain, 000 notes §7), so assert that: 400 grains rain
 * and settle for 2 s. Bounds: OK status, no NaN, overlap < 0.25 d (000 §7: < 0.5 r); total
 * energy never exceeds its running minimum by more than 1e-3 of the initial potential energy
 * above the floor (dissipative contacts and friction only remove energy). */
static int thesis000_dt_1e4_runs_stably(void)
{
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    SimWorldDef def = thesis000_def(&b, 400);
    SimWorld *w = tu_create(&def, &b);
    TEST_ASSERT(w);
    SimEnergy e = sim_world_energy(w);
    double e_min = e.total, worst_rise = 0.0, overlap = 0.0;
    double scale = e.potential; /* heights are above the floor at y = 0 */
    SimStatus status = SIM_OK;
    SimError err;
    for (int chunk = 0; chunk < 200 && status == SIM_OK; ++chunk) {
        status = sim_world_step(w, 100, &err);
        if (status != SIM_OK)
            break;
        e = sim_world_energy(w);
        TEST_ASSERT(isfinite(e.total));
        worst_rise = fmax(worst_rise, e.total - e_min);
        e_min = fmin(e_min, e.total);
        overlap = fmax(overlap, sim_world_max_overlap_ratio(w));
    }
    fprintf(stderr, "thesis000 dt 1e-4: status %d, worst rise %.3g of scale, overlap %.3g d\n",
            (int)status, worst_rise / scale, overlap);
    TEST_ASSERT(status == SIM_OK || status == SIM_ERROR_UNSTABLE);
    TEST_ASSERT(status == SIM_OK); /* what actually happens */
    TEST_ASSERT(st_finite(w));
    TEST_ASSERT(overlap < 0.25);
    TEST_ASSERT(worst_rise <= 1e-3 * scale);
    TEST_ASSERT(sim_world_energy(w).kinetic < 1e-3 * scale); /* it settled */
    sim_world_destroy(w);
    sim_grain_buffer_free(&b);
    return 0;
}

/* Hertz law (F = k xi^1.5, gamma_n = 0) at 20 m/s against a fixed grain, automatic dt (the
 * timing linearises Hertz at 1 m/s, so at 20 m/s the contact is 20^0.2 = 1.8x shorter: ~28
 * steps). Bounds: peak overlap within 3 % of the analytic (5 m v^2 / (4 k))^(2/5); restitution
 * within 1e-2 of 1 (no energy creation beyond 2 %); no NaN. */
static int hertz_high_speed(void)
{
    const double r = 0.01, rho = 2500.0, k = 1e9, v = 20.0;
    SimWorldDef def = tu_def(rho, k, 0.0);
    def.mass_model = SIM_MASS_SPHERE;
    def.contact.normal = SIM_NORMAL_HERTZ;
    def.guard_max_speed = 0.0;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 0.0, r, 0, 0u, -1);
    b.vx[0] = v;
    sim_grain_buffer_add(&b, 2.0 * r + 0.1 * r, 0.0, r, 0, SIM_GRAIN_FIXED, -1);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    double m = tu_mass(SIM_MASS_SPHERE, rho, r);
    double xi_analytic = pow(1.25 * m * v * v / k, 0.4);
    double peak = 0.0;
    SimFrame f;
    long steps = 0;
    for (; steps < 100000; ++steps) {
        TEST_ASSERT(tu_step(w, 1) == 0);
        sim_world_frame(w, &f);
        for (int c = 0; c < f.contact_count; ++c)
            peak = fmax(peak, f.contacts[c].overlap);
        if (f.vx[0] < 0.0 && f.contact_count == 0)
            break;
    }
    TEST_ASSERT(st_finite(w));
    sim_world_frame(w, &f);
    fprintf(stderr, "hertz: peak %.6g analytic %.6g, e %.6g, dt %g\n", peak, xi_analytic,
            -f.vx[0] / v, sim_world_time_step(w));
    TEST_REL(peak, xi_analytic, 0.03);
    TEST_NEAR(-f.vx[0] / v, 1.0, 1e-2);
    sim_world_destroy(w);
    return 0;
}

TEST_MAIN(TEST_CASE(stiff_contacts_auto_dt), TEST_CASE(dt_above_limit_refused),
          TEST_CASE(integrators_at_09_limit), TEST_CASE(dt_09_limit_resting_pocket),
          TEST_CASE(thesis000_dt_1e4_fraction_refused), TEST_CASE(thesis000_dt_1e4_runs_stably),
          TEST_CASE(hertz_high_speed))
