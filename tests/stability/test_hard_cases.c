/* SPDX-License-Identifier: MIT */
/* Hard cases for the drum, source, intruder, shear and chute features
 * (docs/physics.md, "Hard cases"): each runs stably within named bounds or is refused (or stopped)
 * with a message naming the reason. Units: d = 1 m, g = 1 m/s^2, disk masses (m ~ 1 kg). */
#include "stab_util.h"
#include "test.h"

/* The classic-experiment material (docs/experiments.md): density 1.27 kg/m^2, k_n = 2000 N/m,
 * e_n = 0.3, tangential spring k_t = 1500 N/m, mu = 0.5; species 1 the same with mu = 0.8. */
static SimWorldDef experiment_def(double k_n, double mu)
{
    SimWorldDef def = tu_def(1.27, k_n, 0.0);
    def.effects = SIM_EFFECT_FRICTION;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.3;
    def.materials[0].tangential_stiffness = 0.75 * k_n;
    def.materials[0].friction = mu;
    def.species_count = 3;
    def.materials[1] = def.materials[0];
    def.materials[1].friction = mu > 0.0 ? 0.8 : 0.0;
    def.materials[2] = def.materials[0];
    def.gravity_y = -1.0;
    def.guard_max_speed = 0.0; /* automatic, as in a scene */
    return def;
}

/* Largest distance of a mobile grain's centre from the origin, and largest speed. */
static void drum_extent(SimWorld *w, double *rho_max, double *v_max)
{
    SimFrame f;
    sim_world_frame(w, &f);
    *rho_max = *v_max = 0.0;
    for (int i = 0; i < f.mobile_count; ++i) {
        *rho_max = fmax(*rho_max, hypot(f.x[i], f.y[i]));
        *v_max = fmax(*v_max, hypot(f.vx[i], f.vy[i]));
    }
}

/* A drum of radius R = 10 d (one full arc wall, touched inside, species 1) about the origin
 * turning at omega (ramped over 5 s), 100 grains (d = 0.9-1.1) on a lattice in its lower part. */
static SimWorld *drum(double omega, double dt, SimError *err, SimWall *wall)
{
    SimWorldDef def = experiment_def(2000.0, 0.5);
    def.effects |= SIM_EFFECT_VIBRATION;
    def.time_step = dt;
    *wall = (SimWall){.shape = SIM_WALL_ARC,
                      .side = SIM_WALL_INSIDE,
                      .radius = 10.0,
                      .angle0 = 0.0,
                      .angle1 = 2.0 * TPI,
                      .species = 1,
                      .motion = 0};
    def.wall_count = 1;
    def.walls = wall;
    def.motion_count = 1;
    def.motions[0] =
        (SimMotion){.kind = SIM_MOTION_ROTATION, .angular_velocity = omega, .ramp = 5.0};
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    SimRng rng;
    sim_rng_seed(&rng, 21);
    st_lattice(&b, &rng, 100, -6.5, 6.5, -6.5, 0.45, 0.55, 0.05);
    def.grains = sim_grain_buffer_view(&b);
    SimWorld *w = sim_world_create(&def, err);
    sim_grain_buffer_free(&b);
    return w;
}

/* Fast drum, Froude number omega^2 R / g = 4.9 (omega = 0.7 rad/s, the wall at 7 d/s): the
 * grains centrifuge (they turn with the drum as a ring on its wall). Bounds over 40 s: no NaN
 * or guard stop; every centre inside the drum (rho < R: the one-sided arc lets none through);
 * no grain faster than 1.5 omega R (nothing drives them beyond the wall's speed); overlaps below
 * 0.1 d (measured 0.056 d: impacts at ~omega R while the bed is spun up; the centrifugal load
 * m omega^2 R of the ring is ~0.01 d of k_n); at the end at
 * least 90 % of the grains move with the wall, |v - omega x r| < 0.1 omega R. */
static int fast_drum_centrifuging(void)
{
    const double omega = 0.7, R = 10.0;
    SimError err;
    SimWall wall;
    SimWorld *w = drum(omega, 1e-3, &err, &wall);
    TEST_ASSERT(w);
    double worst_rho = 0.0, worst_v = 0.0, worst_overlap = 0.0;
    for (int chunk = 0; chunk < 80; ++chunk) {
        TEST_ASSERT(tu_step(w, 500) == 0);
        TEST_ASSERT(st_finite(w));
        double rho, v;
        drum_extent(w, &rho, &v);
        worst_rho = fmax(worst_rho, rho);
        worst_v = fmax(worst_v, v);
        worst_overlap = fmax(worst_overlap, sim_world_max_overlap_ratio(w));
    }
    SimFrame f;
    sim_world_frame(w, &f);
    int with_wall = 0;
    for (int i = 0; i < f.mobile_count; ++i)
        with_wall += hypot(f.vx[i] + omega * f.y[i], f.vy[i] - omega * f.x[i]) < 0.1 * omega * R;
    fprintf(stderr,
            "fast drum: rho_max %.4g, v_max %.4g (omega R %.3g), overlap %.3g d, %d of %d "
            "with the wall\n",
            worst_rho, worst_v, omega * R, worst_overlap, with_wall, f.mobile_count);
    TEST_ASSERT(worst_rho < R);
    TEST_ASSERT(worst_v < 1.5 * omega * R);
    TEST_ASSERT(worst_overlap < 0.1);
    TEST_ASSERT(with_wall >= 0.9 * f.mobile_count);
    sim_world_destroy(w);
    return 0;
}

/* A drum so fast that one step no longer resolves the wall's speed: the rotation's speed bound
 * |omega| (L + |c|) times dt above half the smallest radius is refused at set-up on the motion's
 * field, the message naming the wall-speed limit and the largest time step; 5 % slower is
 * accepted. */
static int drum_wall_speed_unresolved_refused(void)
{
    const double dt = 1e-3;
    SimError err;
    SimWall wall;
    SimWorld *w = drum(1.0, dt, &err, &wall); /* read the limit off a valid world */
    TEST_ASSERT(w);
    SimFrame f;
    sim_world_frame(w, &f);
    double r_min = INFINITY;
    for (int i = 0; i < f.mobile_count; ++i)
        r_min = fmin(r_min, f.radius[i]);
    sim_world_destroy(w);
    /* the extent: the arc's box [-10, 10]^2 holds every grain */
    const double size = hypot(20.0, 20.0), omega_limit = 0.5 * r_min / (size * dt);
    memset(&err, 0, sizeof err);
    TEST_ASSERT(drum(1.05 * omega_limit, dt, &err, &wall) == NULL);
    fprintf(stderr, "refused: %s: %s\n", err.field, err.message);
    TEST_ASSERT(err.status == SIM_ERROR_INVALID);
    TEST_ASSERT(strcmp(err.field, "motions[0]") == 0);
    TEST_ASSERT(st_mentions(err.message, "wall-speed limit"));
    TEST_ASSERT(st_mentions(err.message, "half the smallest grain radius"));
    w = drum(0.95 * omega_limit, dt, &err, &wall);
    TEST_ASSERT(w);
    sim_world_destroy(w);
    return 0;
}

/* Grains added where grains already are: a new grain on top of a grain of a touching pile is
 * refused (SIM_ERROR_INVALID on grains[0], "max_initial_overlap"), the world unchanged and still
 * running; one added at 0.09 d of overlap (just inside the bound) is accepted and pushed out
 * without creating energy: total energy never above its start by more than 1 % (no gravity, no
 * damping) and the pair apart at the end. */
static int add_grains_dense_region(void)
{
    SimWorldDef def = tu_def(1.0, 1e4, 0.0);
    def.guard_max_speed = 0.0;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    for (int k = 0; k < 25; ++k) /* a touching square pile, 5 x 5 */
        sim_grain_buffer_add(&b, (k % 5) * 1.0, (k / 5) * 1.0, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&b, 20.0, 0.0, 0.5, 0, 0u, -1); /* a lone grain, id 25 */
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    const uint64_t before = sim_world_hash(w);
    double x = 2.0, y = 2.0, r = 0.5;
    SimGrainSet one = {.count = 1, .x = &x, .y = &y, .radius = &r};
    SimError err;
    TEST_ASSERT(sim_world_add_grains(w, &one, &err) == SIM_ERROR_INVALID);
    fprintf(stderr, "refused: %s: %s\n", err.field, err.message);
    TEST_ASSERT(strcmp(err.field, "grains[0]") == 0);
    TEST_ASSERT(st_mentions(err.message, "max_initial_overlap"));
    TEST_ASSERT(sim_world_mobile_count(w) == 26 && sim_world_hash(w) == before);
    TEST_ASSERT(tu_step(w, 100) == 0);
    x = 20.0 + 1.0 - 0.09 * 1.0; /* 0.09 d into the lone grain */
    y = 0.0;
    TEST_ASSERT(sim_world_add_grains(w, &one, &err) == SIM_OK);
    TEST_ASSERT(sim_world_mobile_count(w) == 27);
    StRun run = st_run(w, 4000, 20);
    st_report("add_grains_dense_region", &run);
    TEST_ASSERT(run.status == SIM_OK && run.finite);
    TEST_ASSERT(run.e_max <= 1.01 * run.e0);
    SimFrame f;
    sim_world_frame(w, &f);
    int a = tu_index(&f, 25), c = tu_index(&f, 26);
    TEST_ASSERT(a >= 0 && c >= 0 && hypot(f.x[c] - f.x[a], f.y[c] - f.y[a]) > 1.0);
    sim_world_destroy(w);
    return 0;
}

/* The light-heavy pair: light grains r_l = 0.05 m (density 1, k_n = 1e6 N/m) and a heavy
 * intruder r_h = 0.5 m, density 10 (mass ratio 1000), ten times stiffer (k_n = 1e7): the pair's
 * k_n = 5.5e6 and m_eff ~ m_l make it the shortest contact of the scene. e_n = 0.5. A box of fixed
 * light grains 2 m wide; `light` grains on a lattice, the intruder above them. */
static SimWorldDef intruder_def(SimGrainBuffer *b, int light, int with_heavy)
{
    const double rl = 0.05, rh = 0.5;
    SimWorldDef def = tu_def(1.0, 1e6, 0.0);
    def.species_count = 2;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.5;
    def.materials[1] = def.materials[0];
    def.materials[1].density = 10.0;
    def.materials[1].normal_stiffness = 1e7;
    def.gravity_y = -G0;
    def.guard_max_speed = 0.0;
    sim_grain_buffer_init(b);
    st_fixed_box(b, 2.0, 3.0, rl, 0);
    SimRng rng;
    sim_rng_seed(&rng, 3);
    st_lattice(b, &rng, light, 1.5 * rl, 2.0 - 1.5 * rl, 1.2 * rl, 0.9 * rl, rl, 0.1 * rl);
    if (with_heavy) {
        double top = 0.0;
        for (int i = 0; i < b->count; ++i)
            if (!(b->flags[i] & SIM_GRAIN_FIXED))
                top = fmax(top, b->y[i] + b->radius[i]);
        sim_grain_buffer_add(b, 1.0, top + rh + 0.02, rh, 1, 0u, -1);
    }
    def.grains = sim_grain_buffer_view(b);
    return def;
}

/* The automatic dt resolves the light-heavy contact: the stated contact time is that pair's
 * (k_n 5.5e6, m_eff = m_l m_h / (m_l + m_h)) and dt = t_c / 50; a dt that resolves the light
 * grains alone (0.9 of their limit) is refused with the stability limit named. */
static int intruder_dt_resolves_heavy_pair(void)
{
    SimGrainBuffer b;
    SimWorldDef def = intruder_def(&b, 200, 1);
    const double ml = tu_mass(SIM_MASS_DISK, 1.0, 0.045), mh = tu_mass(SIM_MASS_DISK, 10.0, 0.5);
    SimTiming t = sim_world_def_timing(&def);
    double l = log(0.5), zeta = -l / sqrt(TPI * TPI + l * l);
    double m_light = INFINITY; /* the lightest light grain (lattice radii 0.045-0.05) */
    for (int i = 0; i < b.count; ++i)
        if (!(b.flags[i] & SIM_GRAIN_FIXED) && b.species[i] == 0)
            m_light = fmin(m_light, tu_mass(SIM_MASS_DISK, 1.0, b.radius[i]));
    double m_eff = m_light * mh / (m_light + mh);
    double tc_pair = TPI / (sqrt(5.5e6 / m_eff) * sqrt(1.0 - zeta * zeta));
    fprintf(stderr, "intruder: t_c %g (pair %g), limit %g, dt %g, m_h / m_l %g\n",
            t.contact_time_min, tc_pair, t.stability_limit, t.time_step, mh / ml);
    TEST_REL(t.contact_time_min, tc_pair, 1e-9);
    TEST_REL(t.time_step, tc_pair / 50.0, 1e-9);
    SimGrainBuffer lb;
    SimWorldDef light_only = intruder_def(&lb, 200, 0);
    SimTiming tl = sim_world_def_timing(&light_only);
    TEST_ASSERT(0.9 * tl.stability_limit > t.stability_limit);
    def.time_step = 0.9 * tl.stability_limit;
    SimError err;
    TEST_ASSERT(sim_world_def_validate(&def, &err) == SIM_ERROR_INVALID);
    TEST_ASSERT(strcmp(err.field, "time_step") == 0 && st_mentions(err.message, "stability limit"));
    /* the same intruder added later to the light bed at that dt: refused too, the bed unchanged */
    light_only.time_step = 0.9 * tl.stability_limit;
    SimWorld *w = tu_create(&light_only, &lb);
    TEST_ASSERT(w);
    double x = 1.0, y = 2.5, r = 0.5;
    int species = 1;
    SimGrainSet heavy = {.count = 1, .x = &x, .y = &y, .radius = &r, .species = &species};
    int before = sim_world_grain_count(w);
    TEST_ASSERT(sim_world_add_grains(w, &heavy, &err) == SIM_ERROR_INVALID);
    fprintf(stderr, "add refused: %s: %s\n", err.field, err.message);
    TEST_ASSERT(st_mentions(err.message, "stability limit"));
    TEST_ASSERT(sim_world_grain_count(w) == before);
    sim_world_destroy(w);
    sim_grain_buffer_free(&lb);
    sim_grain_buffer_free(&b);
    return 0;
}

/* The intruder dropped onto 300 light grains, run 0.06 s (~25 000 steps at the automatic dt)
 * with 1, 2 and 3 threads: the same bits (sim_world_hash) every 5000 steps; stable: no NaN, no
 * guard stop, overlaps below 0.05 d, total energy never above its start by more than 1e-3 of
 * m_h g r_h (the dissipative contacts only remove energy). */
static int intruder_threads_identical(void)
{
    uint64_t hash[3][5];
    for (int k = 0; k < 3; ++k) {
        SimGrainBuffer b;
        SimWorldDef def = intruder_def(&b, 300, 1);
        SimWorld *w = tu_create(&def, &b);
        sim_grain_buffer_free(&b);
        TEST_ASSERT(w);
        sim_world_set_threads(w, k + 1);
        const double mh = tu_mass(SIM_MASS_DISK, 10.0, 0.5);
        for (int c = 0; c < 5; ++c) {
            StRun run = st_run(w, 5000, 500);
            if (c == 4 || run.status != SIM_OK)
                st_report("intruder_threads_identical", &run);
            TEST_ASSERT(run.status == SIM_OK && run.finite);
            TEST_ASSERT(run.overlap_max < 0.05);
            TEST_ASSERT(run.e_max <= run.e0 + 1e-3 * mh * G0 * 0.5);
            hash[k][c] = sim_world_hash(w);
        }
        sim_world_destroy(w);
    }
    for (int c = 0; c < 5; ++c)
        TEST_ASSERT(hash[0][c] == hash[1][c] && hash[0][c] == hash[2][c]);
    return 0;
}

/* Plane Couette shear at a high inertial number: periodic x over 20 d, a rough floor (a row of
 * touching fixed grains, y = 0) sliding at V = 20 d/s (ramped over 1 s) under a still rough lid
 * (y = 10), 144 grains between them, g = 1 towards the floor, k_n = 2e4 N/m, dt = 2e-4 s (78 steps
 * per contact). Measured over the last 5 of 10 s: I = (V / h) d / sqrt(P / rho) with P the
 * floor's normal load per width, h = 9 d between the rows' surfaces (measured 0.74). Bounds:
 * I >= 0.5 (the case asked for); at every sample no NaN, every centre strictly between the two
 * rows (no grain through the moving or the still wall), kinetic energy below 1/2 M V^2 (the floor
 * drives the bed, nothing else), speeds below 2 V, overlaps below 0.1 d. */
static int shear_high_inertial_number(void)
{
    const double V = 20.0, L = 20.0, H = 10.0;
    SimWorldDef def = experiment_def(2e4, 0.5);
    def.effects |= SIM_EFFECT_PERIODIC_X | SIM_EFFECT_VIBRATION;
    def.domain_x0 = 0.0;
    def.domain_x1 = L;
    def.time_step = 2e-4;
    def.motion_count = 1; /* the floor slides, the bed resting on it under gravity */
    def.motions[0] = (SimMotion){.kind = SIM_MOTION_VELOCITY, .velocity_x = V, .ramp = 1.0};
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_build_fixed_row(&b, 0.5, L - 0.5, 0.0, 0.5, 1, 0);
    sim_build_fixed_row(&b, 0.5, L - 0.5, H, 0.5, 2, -1);
    SimRng rng;
    sim_rng_seed(&rng, 4);
    st_lattice(&b, &rng, 144, 0.0, L, 0.6, 0.45, 0.55, 0.01); /* 8 rows filling the gap */
    def.grains = sim_grain_buffer_view(&b);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    double mass_total = 0.0, d_mean, m_mean;
    sim_world_means(w, &d_mean, &m_mean);
    mass_total = m_mean * sim_world_mobile_count(w);
    double p_sum = 0.0, y_lo = H, y_hi = 0.0, v_max = 0.0, ke_max = 0.0, overlap = 0.0;
    int samples = 0;
    for (int chunk = 0; chunk < 100; ++chunk) {
        TEST_ASSERT(tu_step(w, 500) == 0);
        TEST_ASSERT(st_finite(w));
        SimFrame f;
        sim_world_frame(w, &f);
        for (int i = 0; i < f.mobile_count; ++i) {
            y_lo = fmin(y_lo, f.y[i]);
            y_hi = fmax(y_hi, f.y[i]);
            v_max = fmax(v_max, hypot(f.vx[i], f.vy[i]));
        }
        SimEnergy e = sim_world_energy(w);
        ke_max = fmax(ke_max, e.kinetic + e.rotational);
        overlap = fmax(overlap, sim_world_max_overlap_ratio(w));
        if (chunk >= 50) {
            double fx, fy;
            sim_world_fixed_load(w, 1, &fx, &fy);
            p_sum += fabs(fy) / L;
            ++samples;
        }
    }
    const double P = p_sum / samples, rho = 1.27, h = H - 1.0;
    const double I = (V / h) * d_mean / sqrt(P / rho);
    fprintf(stderr,
            "shear: I %.3g (P %.3g N/m), y in [%.3g, %.3g], v_max %.3g, KE_max %.3g "
            "(1/2 M V^2 %.3g), overlap %.3g d\n",
            I, P, y_lo, y_hi, v_max, ke_max, 0.5 * mass_total * V * V, overlap);
    TEST_ASSERT(I >= 0.5);
    TEST_ASSERT(y_lo > 0.5 && y_hi < H - 0.5);
    TEST_ASSERT(ke_max < 0.5 * mass_total * V * V);
    TEST_ASSERT(v_max < 2.0 * V);
    TEST_ASSERT(overlap < 0.1);
    sim_world_destroy(w);
    return 0;
}

/* A chute that accelerates without bound: 60 frictionless grains on a frictionless floor (a
 * segment wall), periodic x over 20 d, gravity tilted 60 degrees (|g| = 1), dt = 2e-3 s, the
 * automatic guard. Nothing can stop the slide: the run must end with SIM_ERROR_UNSTABLE once the
 * grains move more than half a radius per step (about 125 m/s, near t = 145 s), the message
 * naming the step, the time and the cause (the flow accelerating, not a numerical blow-up); no
 * NaN before, and the last good state restored. */
static int chute_unbounded_stopped(void)
{
    SimWorldDef def = experiment_def(2000.0, 0.0);
    def.effects = SIM_EFFECT_PERIODIC_X;
    def.contact.tangential = SIM_TANGENTIAL_NONE;
    def.domain_x0 = 0.0;
    def.domain_x1 = 20.0;
    def.time_step = 2e-3;
    def.gravity_x = sin(TPI / 3.0);
    def.gravity_y = -cos(TPI / 3.0);
    SimWall floor = {.x0 = -1.0, .y0 = 0.0, .x1 = 21.0, .y1 = 0.0, .species = 1, .motion = -1};
    def.wall_count = 1;
    def.walls = &floor;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    SimRng rng;
    sim_rng_seed(&rng, 5);
    st_lattice(&b, &rng, 60, 0.0, 20.0, 0.0, 0.45, 0.55, 0.05);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    SimStatus s = SIM_OK;
    SimError err;
    memset(&err, 0, sizeof err);
    long chunks = 0;
    for (; chunks < 200 && s == SIM_OK; ++chunks) {
        s = sim_world_step(w, 1000, &err);
        TEST_ASSERT(st_finite(w));
    }
    fprintf(stderr, "chute: status %d at t = %g s: %s\n", (int)s, sim_world_time(w), err.message);
    TEST_ASSERT(s == SIM_ERROR_UNSTABLE);
    TEST_ASSERT(err.step > 0 && err.grain >= 0);
    TEST_ASSERT(st_mentions(err.message, "(t = "));
    TEST_ASSERT(st_mentions(err.message, "accelerates without bound"));
    TEST_ASSERT(!st_mentions(err.message, "time step"));
    TEST_ASSERT(sim_world_step_count(w) < err.step); /* rolled back to the last good check */
    sim_world_destroy(w);
    return 0;
}

/* The control: a real blow-up is not called a flow. Two grains started 0.4 d into each other
 * (max_initial_overlap raised), no gravity, guard bound 0.5 m/s: the repulsion throws them apart
 * above it within a few steps; the message names the time step, not an accelerating flow. */
static int blowup_named_as_blowup(void)
{
    SimWorldDef def = tu_def(1.0, 1e4, 0.0);
    def.max_initial_overlap = 0.5;
    def.guard_max_speed = 0.5;
    def.guard_every = 10;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 0.0, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&b, 0.6, 0.0, 0.5, 0, 0u, -1);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    SimError err;
    TEST_ASSERT(sim_world_step(w, 1000, &err) == SIM_ERROR_UNSTABLE);
    fprintf(stderr, "blow-up: %s\n", err.message);
    TEST_ASSERT(st_mentions(err.message, "energy blow-up"));
    TEST_ASSERT(st_mentions(err.message, "time step"));
    TEST_ASSERT(!st_mentions(err.message, "accelerates"));
    sim_world_destroy(w);
    return 0;
}

TEST_MAIN(TEST_CASE(fast_drum_centrifuging), TEST_CASE(drum_wall_speed_unresolved_refused),
          TEST_CASE(add_grains_dense_region), TEST_CASE(intruder_dt_resolves_heavy_pair),
          TEST_CASE(intruder_threads_identical), TEST_CASE(shear_high_inertial_number),
          TEST_CASE(chute_unbounded_stopped), TEST_CASE(blowup_named_as_blowup))
