/* SPDX-License-Identifier: MIT */
/* Stability hard cases about single contacts: impacts fast enough to pass through in one step,
 * mass ratio 1000, over-damped contacts, near-coincident and overlapping starts, exactly touching
 * starts, and a zero-gravity elastic gas. */
#include "stab_util.h"
#include "test.h"

/* Two equal grains (disk, r = 0.5 m, k_n = 1e5 N/m, automatic dt = t_c/50 = 1.2e-4 s) closing at
 * 1e4 m/s: the relative displacement per step (1.2 m) exceeds the diameter, so the overlap after
 * one step exceeds the radius. The guard must stop the run with SIM_ERROR_UNSTABLE naming a step
 * and a grain, or the definition must be refused; the grains must never silently pass through
 * each other (after the run either status is UNSTABLE or grain 0 is still left of grain 1). */
static int impact_pass_through_pair(void)
{
    SimWorldDef def = tu_def(1.0, 1e5, 0.0);
    def.guard_max_speed = 0.0;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 0.0, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&b, 1.3, 0.0, 0.5, 0, 0u, -1);
    b.vx[0] = 5e3;
    b.vx[1] = -5e3;
    def.grains = sim_grain_buffer_view(&b);
    SimError err;
    SimWorld *w = sim_world_create(&def, &err);
    sim_grain_buffer_free(&b);
    if (!w) { /* refused at set-up: acceptable with a clear message */
        fprintf(stderr, "refused: %s: %s\n", err.field, err.message);
        TEST_ASSERT(err.status == SIM_ERROR_INVALID && err.message[0]);
        return 0;
    }
    TEST_ASSERT(sim_world_time_step(w) * 1e4 > 1.0);
    SimStatus s = sim_world_step(w, 1000, &err);
    SimFrame f;
    sim_world_frame(w, &f);
    double x0 = f.x[tu_index(&f, 0)], x1 = f.x[tu_index(&f, 1)];
    fprintf(stderr, "status %d (%s), x0 %g x1 %g\n", (int)s, s ? err.message : "", x0, x1);
    if (s == SIM_ERROR_UNSTABLE) {
        TEST_ASSERT(err.step >= 0 && err.grain >= 0);
        TEST_ASSERT(st_mentions(err.message, "step"));
    } else {
        TEST_ASSERT(x0 < x1); /* never passed through */
    }
    TEST_ASSERT(st_finite(w));
    sim_world_destroy(w);
    return 0;
}

/* The same against a wall segment: a grain at 1e4 m/s towards a vertical wall 0.1 m away. After
 * the run either the status is UNSTABLE (step and grain named) or the grain is still on its side
 * of the wall (x + r <= wall x + 0.5 r). */
static int impact_pass_through_wall(void)
{
    SimWorldDef def = tu_def(1.0, 1e5, 0.0);
    def.guard_max_speed = 0.0;
    SimWall wall = {.x0 = 1.1, .y0 = -5.0, .x1 = 1.1, .y1 = 5.0, .species = 0, .motion = -1};
    def.wall_count = 1;
    def.walls = &wall;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.5, 0.0, 0.5, 0, 0u, -1);
    b.vx[0] = 1e4;
    def.grains = sim_grain_buffer_view(&b);
    SimError err;
    SimWorld *w = sim_world_create(&def, &err);
    sim_grain_buffer_free(&b);
    if (!w) {
        fprintf(stderr, "refused: %s: %s\n", err.field, err.message);
        TEST_ASSERT(err.status == SIM_ERROR_INVALID && err.message[0]);
        return 0;
    }
    SimStatus s = sim_world_step(w, 1000, &err);
    SimFrame f;
    sim_world_frame(w, &f);
    fprintf(stderr, "status %d (%s), x %g\n", (int)s, s ? err.message : "", f.x[0]);
    if (s == SIM_ERROR_UNSTABLE)
        TEST_ASSERT(err.step >= 0 && err.grain >= 0);
    else
        TEST_ASSERT(f.x[0] + 0.5 <= 1.1 + 0.25);
    TEST_ASSERT(st_finite(w));
    sim_world_destroy(w);
    return 0;
}

/* Mass ratio 1000 (thesis 004 style): one heavy grain (r 0.5, density 10) dropped 0.1 d onto two
 * rows of light grains (r 0.05, density 1; disk masses: 10 x 10^2 = 1000) resting on a base of
 * fixed 0.1 d grains between two walls, k_n = 1e6, critical fraction 0.95 (004 eq. 1.11),
 * automatic dt. Bounds: dt set by the light-light pair (<= t_c,light / 50); no NaN; overlap
 * < 0.1 d_light; nothing tunnels (every mobile grain stays above the base tops minus 0.1 d_light
 * and between the walls); total energy never exceeds the initial one by more than 1e-3 m_H g d. */
static int mass_ratio_1000(void)
{
    const double rl = 0.05, rh = 0.5, width = 2.0, k = 1e6;
    SimWorldDef def = tu_def(1.0, k, 0.0);
    def.species_count = 2;
    def.materials[1] = def.materials[0];
    def.materials[1].density = 10.0;
    for (int s = 0; s < 2; ++s) {
        def.materials[s].damping_mode = SIM_DAMPING_CRITICAL;
        def.materials[s].critical_fraction = 0.95;
    }
    def.gravity_y = -G0;
    def.guard_max_speed = 0.0;
    SimWall walls[2] = {
        {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 5.0, .species = 0, .motion = -1},
        {.x0 = width, .y0 = 0.0, .x1 = width, .y1 = 5.0, .species = 0, .motion = -1}};
    def.wall_count = 2;
    def.walls = walls;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_build_fixed_row(&b, rl, width - rl, 0.0, rl, 0, -1);
    int light = 0;
    for (int row = 0; row < 2; ++row)
        for (double x = 1.5 * rl + row * rl; x < width - 1.5 * rl; x += 2.02 * rl) {
            sim_grain_buffer_add(&b, x, 2.0 * rl + row * 1.8 * rl + 0.001, rl, 0, 0u, -1);
            ++light;
        }
    int heavy =
        sim_grain_buffer_add(&b, 0.5 * width, 2.0 * rl + 3.6 * rl + rh + 0.1, rh, 1, 0u, -1);
    uint32_t heavy_id = (uint32_t)heavy;
    def.grains = sim_grain_buffer_view(&b);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    double ml = tu_mass(SIM_MASS_DISK, 1.0, rl), mh = tu_mass(SIM_MASS_DISK, 10.0, rh);
    TEST_REL(mh / ml, 1000.0, 1e-12);
    /* light-light pair: m_eff = m_l / 2, zeta = 0.95, t_c = pi / (omega sqrt(1 - zeta^2)) */
    double tc_light = TPI / (sqrt(k / (0.5 * ml)) * sqrt(1.0 - 0.95 * 0.95));
    TEST_ASSERT(sim_world_time_step(w) <= tc_light / 50.0 * (1.0 + 1e-9));
    long steps = (long)(0.4 / sim_world_time_step(w));
    StRun run = st_run(w, steps, 200);
    st_report("mass_ratio_1000", &run);
    TEST_ASSERT(run.status == SIM_OK && run.finite);
    TEST_ASSERT(run.overlap_max < 0.1);
    TEST_ASSERT(run.e_max <= run.e0 + 1e-3 * mh * G0 * 2.0 * rh);
    SimFrame f;
    sim_world_frame(w, &f);
    for (int i = 0; i < f.mobile_count; ++i) {
        TEST_ASSERT(f.y[i] - f.radius[i] > 2.0 * rl * 0.5 - 0.1 * 2.0 * rl);
        TEST_ASSERT(f.x[i] > 0.0 && f.x[i] < width);
    }
    int h = tu_index(&f, heavy_id);
    TEST_ASSERT(h >= 0 && f.y[h] > 2.0 * rl + rh); /* still on top of the light grains */
    TEST_ASSERT(light > 30);
    sim_world_destroy(w);
    return 0;
}

/* Head-on collision of two equal grains (disk, r 0.5, k 1e4, no gravity, automatic dt) with an
 * over-damped or nearly over-damped law, 1 m/s closing speed, clipped normal force. Bounds at
 * every step: no NaN; F_n >= 0 (no attraction); KE + elastic energy never exceeds its previous
 * value by more than 1e-12 of the impact energy (the dashpot only removes energy); after the
 * run the grains do not approach (relative normal velocity >= -1e-9 m/s) and the rebound speed
 * is at most e_expected + 0.01 of the impact speed, e_expected being the restitution of the
 * clipped law (the pair separates when k xi + gamma dxi/dt reaches 0, so even e_n = 1e-6 gives a
 * small rebound: tu_e_clipped). */
static int overdamped_pair(SimDampingMode mode, double value, double e_expected)
{
    SimWorldDef def = tu_def(1.0, 1e4, 0.0);
    def.materials[0].damping_mode = mode;
    if (mode == SIM_DAMPING_RESTITUTION)
        def.materials[0].restitution = value;
    else
        def.materials[0].critical_fraction = value;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 0.0, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&b, 1.01, 0.0, 0.5, 0, 0u, -1);
    b.vx[0] = 0.5;
    b.vx[1] = -0.5;
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    double m = tu_mass(SIM_MASS_DISK, 1.0, 0.5), e_impact = 2.0 * 0.5 * m * 0.25;
    SimEnergy e = sim_world_energy(w);
    double prev = e.kinetic + e.elastic, min_force = 0.0;
    long steps = (long)(200.0 * sim_world_timing(w).contact_time_min / sim_world_time_step(w));
    SimFrame f;
    for (long s = 0; s < steps; ++s) {
        TEST_ASSERT(tu_step(w, 1) == 0);
        e = sim_world_energy(w);
        double now = e.kinetic + e.elastic;
        TEST_ASSERT(isfinite(now));
        TEST_ASSERT(now <= prev + 1e-12 * e_impact);
        prev = now;
        sim_world_frame(w, &f);
        for (int c = 0; c < f.contact_count; ++c)
            min_force = fmin(min_force, f.contacts[c].normal_force);
    }
    TEST_ASSERT(st_finite(w));
    sim_world_frame(w, &f);
    double v_rel = f.vx[tu_index(&f, 1)] - f.vx[tu_index(&f, 0)];
    fprintf(stderr, "mode %d value %g: rebound %.3g of impact, min F_n %g, final overlap %g\n",
            (int)mode, value, v_rel, min_force, sim_world_max_overlap_ratio(w));
    TEST_ASSERT(min_force >= 0.0);
    TEST_ASSERT(v_rel >= -1e-9);
    TEST_ASSERT(v_rel <= e_expected + 0.01);
    sim_world_destroy(w);
    return 0;
}

/* e_n = 1e-6 (zeta = 0.975). */
static int overdamped_restitution_1e6(void)
{
    double m_eff = 0.5 * tu_mass(SIM_MASS_DISK, 1.0, 0.5);
    return overdamped_pair(SIM_DAMPING_RESTITUTION, 1e-6, tu_e_clipped(1e-6, m_eff, 1e4));
}

/* 0.95 of critical damping (004 eq. 1.11): e_n = exp(-pi zeta / sqrt(1 - zeta^2)). */
static int overdamped_critical_095(void)
{
    double m_eff = 0.5 * tu_mass(SIM_MASS_DISK, 1.0, 0.5);
    double e = exp(-TPI * 0.95 / sqrt(1.0 - 0.95 * 0.95));
    return overdamped_pair(SIM_DAMPING_CRITICAL, 0.95, tu_e_clipped(e, m_eff, 1e4));
}

/* 5 x critical damping (over-damped, 000 §7: t_n and e_n undefined, no sqrt of a negative):
 * timing figures finite and positive, and the pair behaves as above. */
static int overdamped_critical_5(void)
{
    SimWorldDef def = tu_def(1.0, 1e4, 0.0);
    def.materials[0].damping_mode = SIM_DAMPING_CRITICAL;
    def.materials[0].critical_fraction = 5.0;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 0.0, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&b, 1.01, 0.0, 0.5, 0, 0u, -1);
    def.grains = sim_grain_buffer_view(&b);
    SimTiming t = sim_world_def_timing(&def);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(isfinite(t.contact_time_min) && t.contact_time_min > 0.0);
    TEST_ASSERT(isfinite(t.stability_limit) && t.stability_limit > 0.0);
    return overdamped_pair(SIM_DAMPING_CRITICAL, 5.0, 0.04); /* no analytic e: rebound < 5 % */
}

/* A grain dropped on a fixed grain with 5 x critical damping under gravity comes to rest on it
 * without sticking artefacts: at rest the contact force balances the weight within 1e-6 m g
 * (no spurious attraction or glue), overlap = m g / k_n within 1e-6 relative. */
static int overdamped_rest_no_glue(void)
{
    const double r = 0.5, k = 1e4;
    SimWorldDef def = tu_def(1.0, k, 0.0);
    def.gravity_y = -G0;
    def.materials[0].damping_mode = SIM_DAMPING_CRITICAL;
    def.materials[0].critical_fraction = 5.0;
    def.guard_max_speed = 0.0;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 0.0, r, 0, SIM_GRAIN_FIXED, -1);
    sim_grain_buffer_add(&b, 0.0, 2.0 * r + 0.2, r, 0, 0u, -1);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    const double m = tu_mass(SIM_MASS_DISK, 1.0, r);
    long steps = (long)(3.0 / sim_world_time_step(w));
    StRun run = st_run(w, steps, 1000);
    TEST_ASSERT(run.status == SIM_OK && run.finite);
    TEST_ASSERT(run.e_max <= run.e0 + 1e-9 * m * G0);
    SimFrame f;
    sim_world_frame(w, &f);
    TEST_ASSERT(f.contact_count == 1);
    TEST_NEAR(f.contacts[0].normal_force, m * G0, 1e-6 * m * G0);
    TEST_REL(f.contacts[0].overlap, m * G0 / k, 1e-6);
    sim_world_destroy(w);
    return 0;
}

/* Two grains with centres 1e-9 r apart (near-coincident), and exactly coincident. The contact
 * normal is undefined (or nearly so) and the overlap (~1 d) is already twice the guard bound
 * (guard_max_overlap 0.5), so the correct answer is a refusal at set-up: SIM_ERROR_INVALID with a
 * message naming the grains. Whatever happens, nothing may become NaN: if the engine accepts the
 * definition, the run must stop with UNSTABLE or separate the grains with finite states. */
static int coincident_case(double offset)
{
    SimWorldDef def = tu_def(1.0, 1e4, 0.0);
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 0.0, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&b, offset, 0.0, 0.5, 0, 0u, -1);
    def.grains = sim_grain_buffer_view(&b);
    SimError err;
    SimStatus v = sim_world_def_validate(&def, &err);
    SimWorld *w = sim_world_create(&def, &err);
    sim_grain_buffer_free(&b);
    if (w) {
        SimStatus s = sim_world_step(w, 1000, &err);
        int finite = st_finite(w);
        fprintf(stderr, "offset %g: accepted; step status %d (%s), finite %d, overlap %g\n", offset,
                (int)s, s ? err.message : "", finite, sim_world_max_overlap_ratio(w));
        sim_world_destroy(w);
        TEST_ASSERT(finite);
        TEST_ASSERT(s == SIM_OK || s == SIM_ERROR_UNSTABLE);
        TEST_ASSERT(!(s == SIM_ERROR_UNSTABLE && st_mentions(err.message, "non-finite")));
    }
    /* the decided behaviour: refused at set-up */
    TEST_ASSERT(v == SIM_ERROR_INVALID);
    TEST_ASSERT(w == NULL);
    TEST_ASSERT(st_mentions(err.message, "overlap"));
    return 0;
}

static int near_coincident_centres(void)
{
    return coincident_case(0.5e-9);
}

static int coincident_centres(void)
{
    return coincident_case(0.0);
}

/* A moderate initial overlap (0.3 d, below the guard bound 0.5) is accepted and the pair is pushed
 * apart without NaN; the separation speed cannot exceed the elastic energy released:
 * v_rel <= xi sqrt(k / m_eff) (1 + 1e-6). */
static int overlapping_start_separates(void)
{
    const double k = 1e4, xi = 0.3;
    SimWorldDef def = tu_def(1.0, k, 0.0);
    def.max_initial_overlap = 0.5; /* 0.3 d is above the default bound of 0.1 d */
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 0.0, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&b, 1.0 - xi, 0.0, 0.5, 0, 0u, -1);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 2000) == 0);
    TEST_ASSERT(st_finite(w));
    SimFrame f;
    sim_world_frame(w, &f);
    double m_eff = 0.5 * tu_mass(SIM_MASS_DISK, 1.0, 0.5);
    double v_rel = f.vx[tu_index(&f, 1)] - f.vx[tu_index(&f, 0)];
    TEST_ASSERT(f.contact_count == 0);
    TEST_ASSERT(v_rel > 0.0 && v_rel <= xi * sqrt(k / m_eff) * (1.0 + 1e-6));
    sim_world_destroy(w);
    return 0;
}

/* Grains exactly touching each other (d = r_i + r_j) and a wall (distance = r) at the start, no
 * gravity, no velocity: accepted (not an overlap), zero force, and nothing moves: positions
 * bit-identical after 1000 steps. */
static int exactly_touching_start(void)
{
    SimWorldDef def = tu_def(1.0, 1e4, 0.0);
    SimWall wall = {.x0 = -0.5, .y0 = -2.0, .x1 = -0.5, .y1 = 2.0, .species = 0, .motion = -1};
    def.wall_count = 1;
    def.walls = &wall;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 0.0, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&b, 1.25, 0.0, 0.75, 0, 0u, -1);
    sim_grain_buffer_add(&b, 0.0, 1.0, 0.5, 0, 0u, -1);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 1000) == 0);
    SimFrame f;
    sim_world_frame(w, &f);
    TEST_ASSERT(f.x[tu_index(&f, 0)] == 0.0 && f.y[tu_index(&f, 0)] == 0.0);
    TEST_ASSERT(f.x[tu_index(&f, 1)] == 1.25 && f.y[tu_index(&f, 1)] == 0.0);
    TEST_ASSERT(f.x[tu_index(&f, 2)] == 0.0 && f.y[tu_index(&f, 2)] == 1.0);
    for (int c = 0; c < f.contact_count; ++c)
        TEST_ASSERT(f.contacts[c].normal_force == 0.0);
    sim_world_destroy(w);
    return 0;
}

/* Zero-gravity elastic gas: 200 grains (r 0.01, disk, k 1e3, gamma 0, no friction) with random
 * velocities up to 1 m/s per axis in a closed box of four wall segments, automatic dt (50 steps per
 * contact), 0.5 s (~several collisions per grain). Bounds: no NaN; overlap < 0.07 d (the head-on
 * overlap of the fastest possible pair, v_rel = 2 sqrt(2) m/s: xi = v_rel sqrt(m_eff / k) =
 * 0.056 d, plus 25 %); total energy stays within 1e-3 of the initial one (per-collision O((omega
 * dt)^2) errors at 50 steps per contact, not accumulating into growth); every grain stays inside
 * the box. */
static int zero_gravity_gas(void)
{
    const double r = 0.01, side = 0.5;
    SimWorldDef def = tu_def(1.0, 1e3, 0.0);
    SimWall walls[4] = {{.x0 = 0.0, .y0 = 0.0, .x1 = side, .y1 = 0.0, .species = 0, .motion = -1},
                        {.x0 = side, .y0 = 0.0, .x1 = side, .y1 = side, .species = 0, .motion = -1},
                        {.x0 = side, .y0 = side, .x1 = 0.0, .y1 = side, .species = 0, .motion = -1},
                        {.x0 = 0.0, .y0 = side, .x1 = 0.0, .y1 = 0.0, .species = 0, .motion = -1}};
    def.wall_count = 4;
    def.walls = walls;
    def.guard_max_speed = 0.0;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    SimRng rng;
    sim_rng_seed(&rng, 5);
    st_lattice(&b, &rng, 200, 0.0, side, 0.0, r, r, 0.5 * r);
    for (int i = 0; i < b.count; ++i) {
        b.vx[i] = 2.0 * sim_rng_uniform(&rng) - 1.0;
        b.vy[i] = 2.0 * sim_rng_uniform(&rng) - 1.0;
    }
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    long steps = (long)(0.5 / sim_world_time_step(w));
    StRun run = st_run(w, steps, 100);
    st_report("zero_gravity_gas", &run);
    TEST_ASSERT(run.status == SIM_OK && run.finite);
    TEST_ASSERT(run.overlap_max < 0.07);
    TEST_NEAR(run.e_max, run.e0, 1e-3 * run.e0);
    TEST_NEAR(run.e_last, run.e0, 1e-3 * run.e0);
    SimFrame f;
    sim_world_frame(w, &f);
    for (int i = 0; i < f.count; ++i)
        TEST_ASSERT(f.x[i] > 0.0 && f.x[i] < side && f.y[i] > 0.0 && f.y[i] < side);
    sim_world_destroy(w);
    return 0;
}

TEST_MAIN(TEST_CASE(impact_pass_through_pair), TEST_CASE(impact_pass_through_wall),
          TEST_CASE(mass_ratio_1000), TEST_CASE(overdamped_restitution_1e6),
          TEST_CASE(overdamped_critical_095), TEST_CASE(overdamped_critical_5),
          TEST_CASE(overdamped_rest_no_glue), TEST_CASE(near_coincident_centres),
          TEST_CASE(coincident_centres), TEST_CASE(overlapping_start_separates),
          TEST_CASE(exactly_touching_start), TEST_CASE(zero_gravity_gas))
