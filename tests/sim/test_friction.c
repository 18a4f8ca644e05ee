/* SPDX-License-Identifier: MIT */
/* Friction and rolling resistance: a block of grains on a slope (gravity tilted by theta) above
 * and below tan(theta) = mu, tangential-spring history across neighbour rebuilds, rolling
 * resistance (004 ch. 4), and friction never injecting energy (000 notes 3.6). */
#include "sim_test_util.h"
#include "test.h"

#define RB      0.05   /* grain radius, m */
#define RHO     1000.0 /* kg/m^2, disk mass model */
#define KN      1e5    /* N/m */
#define MU      0.4
#define GAMMA_S 2000.0 /* kg/s, regularised law */

/* A trapezoid block of five equal grains (three below, two nested on top) on a flat wall along
 * y = 0. Disks roll: even this block rolls as a gear train (the top grains wedge the bottom ones
 * apart, so there is no compressed odd cycle of contacts: bottom grains turn clockwise, top ones
 * counter-clockwise, no contact slips). A strong rolling resistance (mu_r = 1 > tan(theta),
 * k_r = k_n r^2) locks the rotations, so the block can only stick or slide. Tipping needs
 * tan(theta) > 1.18, far above the cases here. */
static void add_block(SimGrainBuffer *b)
{
    for (int k = -1; k <= 1; ++k)
        sim_grain_buffer_add(b, 2.0 * RB * k, RB, RB, 0, 0u, -1);
    sim_grain_buffer_add(b, -RB, RB + sqrt(3.0) * RB, RB, 0, 0u, -1);
    sim_grain_buffer_add(b, RB, RB + sqrt(3.0) * RB, RB, 0, 0u, -1);
}

static SimWorldDef slope_def(SimTangentialLaw law, double tan_theta)
{
    SimWorldDef def = tu_def(RHO, KN, 1e-4);
    double c = 1.0 / sqrt(1.0 + tan_theta * tan_theta);
    def.gravity_x = G0 * tan_theta * c; /* down the slope is +x */
    def.gravity_y = -G0 * c;
    def.effects |= SIM_EFFECT_FRICTION | SIM_EFFECT_ROLLING;
    def.contact.tangential = law;
    def.contact.rolling = SIM_ROLLING_FIXED;
    def.materials[0].friction = MU;
    def.materials[0].tangential_stiffness = 0.75 * KN;
    def.materials[0].tangential_damping = GAMMA_S;
    def.materials[0].rolling_friction = 1.0;
    def.materials[0].rolling_stiffness = KN * RB * RB;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.3;
    return def;
}

typedef struct BlockRun {
    double x_start, x_end;       /* block centre of mass at the window's ends, m */
    double x_min, x_max;         /* over the window, m */
    double v_start, v_end;       /* mean velocity along x at the window's ends, m/s */
    double mean_head, mean_tail; /* mean x over the first and last tenth of the window */
} BlockRun;

/* Settle for `settle` s, then watch the block's centre of mass for `window` s. With
 * `projectile`, a sixth grain far away flies at 30 m/s, so the neighbour list is rebuilt every
 * few steps (skin ~ 0.02 m, 3 mm per step). */
static int block_run(SimWorldDef def, int projectile, double settle, double window, BlockRun *out)
{
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    add_block(&b);
    if (projectile) {
        int p = sim_grain_buffer_add(&b, -20.0, 5.0, RB, 0, 0u, -1);
        b.vy[p] = 30.0;
    }
    SimWall floor_ = {.x0 = -1.0, .y0 = 0.0, .x1 = 3.0, .y1 = 0.0, .species = 0, .motion = -1};
    def.wall_count = 1;
    def.walls = &floor_;
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    if (!w)
        return 1;
    double dt = def.time_step;
    if (tu_step(w, (long)(settle / dt + 0.5))) {
        sim_world_destroy(w);
        return 1;
    }
    long n = (long)(window / dt + 0.5), tenth = n / 10;
    double head = 0.0, tail = 0.0;
    out->x_min = 1e300;
    out->x_max = -1e300;
    for (long s = 0; s <= n; ++s) {
        SimFrame f;
        sim_world_frame(w, &f);
        double x = 0.0, v = 0.0;
        for (uint32_t id = 0; id < 5; ++id) {
            int i = tu_index(&f, id);
            x += f.x[i] / 5.0;
            v += f.vx[i] / 5.0;
        }
        if (s == 0) {
            out->x_start = x;
            out->v_start = v;
        }
        out->x_end = x;
        out->v_end = v;
        if (x < out->x_min)
            out->x_min = x;
        if (x > out->x_max)
            out->x_max = x;
        if (s < tenth)
            head += x / (double)tenth;
        if (s > n - tenth)
            tail += x / (double)tenth;
        if (s < n && tu_step(w, 1)) {
            sim_world_destroy(w);
            return 1;
        }
    }
    out->mean_head = head;
    out->mean_tail = tail;
    sim_world_destroy(w);
    return 0;
}

/* Below the threshold (tan theta = mu / 2) the Cundall-Strack spring holds the block exactly:
 * after settling (3 s: the rotational modes are only weakly damped) it only oscillates
 * elastically, with an amplitude of the order of the spring stretch m g sin(theta) / k_t ~ 2e-4 m,
 * and does not drift. */
static int slope_spring_sticks(void)
{
    BlockRun r;
    TEST_ASSERT(block_run(slope_def(SIM_TANGENTIAL_SPRING, 0.5 * MU), 0, 3.0, 2.0, &r) == 0);
    double m = tu_mass(SIM_MASS_DISK, RHO, RB), stretch = m * G0 * 0.2 / (0.75 * KN);
    TEST_NEAR(r.x_max - r.x_min, 0.0, 2.0 * stretch);
    TEST_NEAR(r.mean_tail - r.mean_head, 0.0, 0.05 * stretch);
    TEST_NEAR(r.v_end, 0.0, 1e-2);
    return 0;
}

/* The regularised law (000 eq. 3.28) has no static state: below the threshold the block creeps
 * downhill at the speed where the three floor contacts' viscous friction gamma_s v balances the
 * weight along the slope: v = 5 m g sin(theta) / (3 gamma_s), steadily. */
static int slope_regularised_creeps(void)
{
    BlockRun r;
    TEST_ASSERT(block_run(slope_def(SIM_TANGENTIAL_REGULARISED, 0.5 * MU), 0, 0.5, 1.0, &r) == 0);
    double g_along = G0 * 0.2 / sqrt(1.04);
    double m = tu_mass(SIM_MASS_DISK, RHO, RB), creep = 5.0 * m * g_along / (3.0 * GAMMA_S);
    TEST_REL(r.x_end - r.x_start, creep * 1.0, 0.05);
    TEST_REL(r.v_end, creep, 0.05);
    TEST_REL(r.v_start, creep, 0.05);
    return 0;
}

/* Above the threshold (tan theta = 2 mu) the block slides: its acceleration is that of a rigid
 * block under Coulomb friction, g (sin(theta) - mu cos(theta)), and never more than g sin(theta).
 */
static int slope_slides(void)
{
    const SimTangentialLaw laws[2] = {SIM_TANGENTIAL_SPRING, SIM_TANGENTIAL_REGULARISED};
    for (int l = 0; l < 2; ++l) {
        BlockRun r;
        TEST_ASSERT(block_run(slope_def(laws[l], 2.0 * MU), 0, 0.1, 0.3, &r) == 0);
        double c = 1.0 / sqrt(1.0 + 4.0 * MU * MU), s = 2.0 * MU * c;
        double a = (r.v_end - r.v_start) / 0.3;
        TEST_REL(a, G0 * (s - MU * c), 0.02);
        TEST_ASSERT(a < G0 * s);
        TEST_ASSERT(r.x_end - r.x_start > 0.0);
    }
    return 0;
}

/* The tangential spring is contact history: it must survive neighbour-list rebuilds. The
 * sticking block with a fast projectile elsewhere (a rebuild every few steps) behaves exactly as
 * without it; a lost spring would restart from zero at each rebuild and let the block creep. */
static int spring_history_survives_rebuilds(void)
{
    BlockRun quiet, busy;
    SimWorldDef def = slope_def(SIM_TANGENTIAL_SPRING, 0.5 * MU);
    TEST_ASSERT(block_run(def, 0, 3.0, 2.0, &quiet) == 0);
    TEST_ASSERT(block_run(def, 1, 3.0, 2.0, &busy) == 0);
    double m = tu_mass(SIM_MASS_DISK, RHO, RB), stretch = m * G0 * 0.2 / (0.75 * KN);
    TEST_NEAR(busy.x_end, quiet.x_end, 1e-9);
    TEST_NEAR(busy.x_max - busy.x_min, 0.0, 2.0 * stretch);
    TEST_NEAR(busy.mean_tail - busy.mean_head, 0.0, 0.05 * stretch);
    return 0;
}

/* ---------------------------------------------------------------- rolling */

typedef struct RollRun {
    double v_half, x_late, v_late_max, omega_late_max, v_end, omega_end, x_end;
} RollRun;

/* A disk rolling without slip (v0 = 0.5 m/s, omega = -v0/r) on a wall, resting at its static
 * overlap m g / k. */
static int roll(SimWorldDef def, double t_half, double t_late, double t_end, RollRun *out)
{
    const double v0 = 0.5;
    double m = tu_mass(SIM_MASS_DISK, RHO, RB);
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    /* starts touching (create refuses overlaps with walls) and sinks to m g / k */
    int g = sim_grain_buffer_add(&b, 0.0, RB, RB, 0, 0u, -1);
    (void)m;
    b.vx[g] = v0;
    b.omega[g] = -v0 / RB;
    SimWall floor_ = {.x0 = -1.0, .y0 = 0.0, .x1 = 5.0, .y1 = 0.0, .species = 0, .motion = -1};
    def.wall_count = 1;
    def.walls = &floor_;
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    if (!w)
        return 1;
    double dt = def.time_step, xsum = 0.0;
    long n_late = 0;
    memset(out, 0, sizeof *out);
    SimFrame f;
    for (long s = 1; s * dt <= t_end + 0.5 * dt; ++s) {
        if (tu_step(w, 1)) {
            sim_world_destroy(w);
            return 1;
        }
        sim_world_frame(w, &f);
        double t = f.time;
        if (fabs(t - t_half) < 0.5 * dt)
            out->v_half = f.vx[0];
        if (t >= t_late) {
            xsum += f.x[0];
            ++n_late;
            if (fabs(f.vx[0]) > out->v_late_max)
                out->v_late_max = fabs(f.vx[0]);
            if (fabs(f.omega[0]) > out->omega_late_max)
                out->omega_late_max = fabs(f.omega[0]);
        }
    }
    out->x_late = n_late ? xsum / (double)n_late : 0.0;
    out->v_end = f.vx[0];
    out->omega_end = f.omega[0];
    out->x_end = f.x[0];
    sim_world_destroy(w);
    return 0;
}

static SimWorldDef roll_def(SimRollingLaw law)
{
    SimWorldDef def = tu_def(RHO, KN, 1e-4);
    def.gravity_y = -G0;
    def.effects |= SIM_EFFECT_FRICTION;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.materials[0].friction = 0.5;
    def.materials[0].tangential_stiffness = 0.75 * KN;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.3;
    if (law != SIM_ROLLING_OFF) {
        def.effects |= SIM_EFFECT_ROLLING;
        def.contact.rolling = law;
        /* mu_r is a length (004 eq. 4.1: |M| <= mu_r k_n xi): 0.05 r, i.e. a rolling
         * friction coefficient of 0.05 */
        def.materials[0].rolling_friction = 0.05 * RB;
        def.materials[0].rolling_stiffness = 100.0;
    }
    return def;
}

/* Without rolling resistance nothing dissipates: the disk keeps rolling at v0, omega = -v0/r. */
static int rolling_off_keeps_rolling(void)
{
    RollRun r;
    TEST_ASSERT(roll(roll_def(SIM_ROLLING_OFF), 1.0, 1.5, 2.0, &r) == 0);
    TEST_REL(r.v_end, 0.5, 1e-6);
    TEST_REL(r.omega_end, -0.5 / RB, 1e-6);
    TEST_REL(r.x_end, 0.5 * 2.0, 1e-6);
    /* declaring the effect with the law off changes nothing */
    SimWorldDef def = roll_def(SIM_ROLLING_OFF);
    def.effects |= SIM_EFFECT_ROLLING;
    RollRun r2;
    TEST_ASSERT(roll(def, 1.0, 1.5, 2.0, &r2) == 0);
    TEST_NEAR(r2.x_end, r.x_end, 1e-12);
    return 0;
}

/* With rolling resistance the torque saturates at mu_r f_el (004 eq. 4.1) with f_el = m g on a
 * wall, so a disk rolling without slip decelerates at a = (mu_r / r) g / (1 + I/(m r^2))
 * = mu_r g / (1.5 r), stops after v0^2 / (2 a), and stays (up to the elastic rolling spring's
 * small oscillation). Fixed law: mu_r = 0.05 r as set. Chord law (004 §1.7): mu_r = mu l_c with
 * l_c the chord of the disk cut by the wall at the static overlap xi = m g / k_n. */
static int rolling_resistance_stops(void)
{
    const SimRollingLaw laws[2] = {SIM_ROLLING_FIXED, SIM_ROLLING_CHORD};
    const double m = tu_mass(SIM_MASS_DISK, RHO, RB), xi = m * G0 / KN;
    const double chord = 2.0 * sqrt(RB * RB - (RB - xi) * (RB - xi));
    const double mu_r[2] = {0.05 * RB, 0.5 * chord};
    for (int l = 0; l < 2; ++l) {
        double a = mu_r[l] * G0 / (1.5 * RB), t_stop = 0.5 / a, x_stop = 0.5 * 0.5 / (2.0 * a);
        RollRun r;
        TEST_ASSERT(roll(roll_def(laws[l]), 0.5 * t_stop, 1.3 * t_stop, 2.0 * t_stop, &r) == 0);
        TEST_REL(r.v_half, 0.25, 0.05);
        TEST_REL(r.x_late, x_stop, 0.05);
        TEST_ASSERT(r.v_late_max < 0.1 * 0.5);
    }
    return 0;
}

/* ---------------------------------------------------------------- friction dissipates */

/* Oblique elastic impacts of a spinning grain on a fixed grain, no gravity: the normal force is
 * conservative, so any change of kinetic plus rotational energy is friction's work, which must be
 * <= 0 (000 notes 3.6: pins the sign convention) and is strictly negative when the contact
 * slips. Both tangential laws. */
static int friction_dissipates(void)
{
    const double k = 1e5, r = 0.1, v = 1.0;
    const double offsets[] = {0.0, 0.05, 0.12, -0.12};
    const double spins[] = {-20.0, 0.0, 20.0};
    const SimTangentialLaw laws[2] = {SIM_TANGENTIAL_REGULARISED, SIM_TANGENTIAL_SPRING};
    double m = tu_mass(SIM_MASS_DISK, RHO, r), inertia = tu_inertia(SIM_MASS_DISK, RHO, r);
    double tc = TPI * sqrt(m / k);
    for (int l = 0; l < 2; ++l)
        for (int o = 0; o < 4; ++o)
            for (int s = 0; s < 3; ++s) {
                if (offsets[o] == 0.0 && spins[s] == 0.0)
                    continue;
                SimWorldDef def = tu_def(RHO, k, tc / 2000.0);
                def.effects |= SIM_EFFECT_FRICTION;
                def.contact.tangential = laws[l];
                def.materials[0].friction = 0.5;
                def.materials[0].tangential_damping = 300.0;
                def.materials[0].tangential_stiffness = 0.75 * k;
                SimGrainBuffer b;
                sim_grain_buffer_init(&b);
                int g = sim_grain_buffer_add(&b, -2.0 * r - 0.01, offsets[o], r, 0, 0u, -1);
                b.vx[g] = v;
                b.omega[g] = spins[s];
                sim_grain_buffer_add(&b, 0.0, 0.0, r, 0, SIM_GRAIN_FIXED, -1);
                SimWorld *w = tu_create(&def, &b);
                sim_grain_buffer_free(&b);
                TEST_ASSERT(w);
                double e0 = 0.5 * m * v * v + 0.5 * inertia * spins[s] * spins[s];
                int touched = 0;
                long steps = 0;
                for (;;) {
                    TEST_ASSERT(tu_step(w, 1) == 0);
                    ++steps;
                    SimEnergy en = sim_world_energy(w);
                    if (en.contacts > 0)
                        touched = 1;
                    else if (touched)
                        break;
                    TEST_ASSERT(steps < 100000);
                }
                TEST_ASSERT(tu_step(w, 10) == 0);
                SimEnergy en = sim_world_energy(w);
                double e1 = en.kinetic + en.rotational;
                if (e1 > e0 * (1.0 + 2e-6) || e1 > e0 - 1e-4 * e0) {
                    fprintf(stderr, "law %d offset %g spin %g: E %.9g -> %.9g\n", (int)laws[l],
                            offsets[o], spins[s], e0, e1);
                }
                TEST_ASSERT(e1 <= e0 * (1.0 + 2e-6));
                TEST_ASSERT(e1 < e0 - 1e-4 * e0); /* it slipped: friction did work */
                sim_world_destroy(w);
            }
    return 0;
}

TEST_MAIN(TEST_CASE(slope_spring_sticks), TEST_CASE(slope_regularised_creeps),
          TEST_CASE(slope_slides), TEST_CASE(spring_history_survives_rebuilds),
          TEST_CASE(rolling_off_keeps_rolling), TEST_CASE(rolling_resistance_stops),
          TEST_CASE(friction_dissipates))
