/* SPDX-License-Identifier: MIT */
/* Stability hard cases about boundaries and the grid: the periodic seam at speed, floors vibrating
 * at Gamma = 10 (wall and fixed-grain base), a 1000-grain column, a grain on a cell corner, long
 * and degenerate wall segments, a grain far outside the pile, and a 0.1 vs 1.25 polydisperse pile.
 */
#include "stab_util.h"
#include "test.h"

/* Periodic channel x in [0, 1) between two frictionless horizontal walls, no gravity, gamma 0:
 * 60 grains (r 0.02, disk) at 10-20 m/s in x cross the seam ~3 times each in 0.2 s; k 4e5,
 * automatic dt. Bounds: no NaN; x momentum conserved to 1e-12 of sum m|v|; energy within 1e-3;
 * overlap < 0.05 d (head-on at the largest v_rel = 40 m/s: v_rel sqrt(m_eff / k) = 0.04 d); every
 * grain stays between the walls. */
static int periodic_seam_gas(void)
{
    const double r = 0.02, k = 4e5;
    SimWorldDef def = tu_def(1.0, k, 0.0);
    def.effects |= SIM_EFFECT_PERIODIC_X;
    def.domain_x0 = 0.0;
    def.domain_x1 = 1.0;
    def.guard_max_speed = 0.0;
    SimWall walls[2] = {{.x0 = -1.0, .y0 = 0.0, .x1 = 2.0, .y1 = 0.0, .species = 0, .motion = -1},
                        {.x0 = -1.0, .y0 = 0.4, .x1 = 2.0, .y1 = 0.4, .species = 0, .motion = -1}};
    def.wall_count = 2;
    def.walls = walls;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    SimRng rng;
    sim_rng_seed(&rng, 3);
    st_lattice(&b, &rng, 60, 0.0, 1.0, 0.0, r, r, 0.03);
    double scale = 0.0, px0, py0;
    for (int i = 0; i < b.count; ++i) {
        double sign = (i % 3 == 0) ? -1.0 : 1.0;
        b.vx[i] = sign * (10.0 + 10.0 * sim_rng_uniform(&rng));
        b.vy[i] = 2.0 * sim_rng_uniform(&rng) - 1.0;
        scale += tu_mass(SIM_MASS_DISK, 1.0, r) * fabs(b.vx[i]);
    }
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    sim_world_momentum(w, &px0, &py0);
    long steps = (long)(0.2 / sim_world_time_step(w));
    StRun run = st_run(w, steps, 200);
    st_report("periodic_seam_gas", &run);
    TEST_ASSERT(run.status == SIM_OK && run.finite);
    TEST_ASSERT(run.overlap_max < 0.05);
    TEST_NEAR(run.e_max, run.e0, 1e-3 * run.e0);
    TEST_NEAR(run.e_last, run.e0, 1e-3 * run.e0);
    double px, py;
    sim_world_momentum(w, &px, &py);
    TEST_NEAR(px, px0, 1e-12 * scale);
    SimFrame f;
    sim_world_frame(w, &f);
    for (int i = 0; i < f.count; ++i)
        TEST_ASSERT(f.y[i] > 0.0 && f.y[i] < 0.4);
    sim_world_destroy(w);
    return 0;
}

/* Two grains meeting head-on exactly at the seam at 10 m/s each (elastic, equal masses): they
 * must collide through the seam and exchange velocities (each within 1e-3 relative), not pass
 * through each other. */
static int periodic_seam_head_on(void)
{
    const double r = 0.02;
    SimWorldDef def = tu_def(1.0, 1e5, 0.0);
    def.effects |= SIM_EFFECT_PERIODIC_X;
    def.domain_x0 = 0.0;
    def.domain_x1 = 1.0;
    def.guard_max_speed = 0.0;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.05, 0.1, r, 0, 0u, -1);
    sim_grain_buffer_add(&b, 0.95, 0.1, r, 0, 0u, -1);
    b.vx[0] = -10.0;
    b.vx[1] = 10.0;
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, (long)(0.01 / sim_world_time_step(w))) == 0);
    SimFrame f;
    sim_world_frame(w, &f);
    TEST_REL(f.vx[tu_index(&f, 0)], 10.0, 1e-3);
    TEST_REL(f.vx[tu_index(&f, 1)], -10.0, 1e-3);
    TEST_ASSERT(st_finite(w));
    sim_world_destroy(w);
    return 0;
}

/* A box whose floor vibrates vertically at f = 50 Hz, Gamma = A omega^2 / g = 10 (A ~ 0.1 d,
 * peak floor speed 0.31 m/s); 30 grains (sphere masses, r 5 mm, k 1e5, e_n 0.5), 0.5 s = 25
 * cycles. The floor is either a moving SimWall or a row of fixed grains (r 0.4 r) with the same
 * motion. Bounds: no NaN; overlap < 0.1 d; no grain below the floor (y - r >= floor top - 0.1 d at
 * every sample, base grains: y > base centre line); no grain faster than 20 x the peak floor
 * speed; grains stay between the side walls. */
static int vibrating_floor(int fixed_base)
{
    const double r = 0.005, d = 2.0 * r, width = 0.1, g = G0, freq = 50.0;
    const double omega = 2.0 * TPI * freq, amp = 10.0 * g / (omega * omega);
    const double rb = 0.4 * r;
    SimWorldDef def = tu_def(2500.0, 1e5, 0.0);
    def.mass_model = SIM_MASS_SPHERE;
    def.gravity_y = -g;
    def.effects |= SIM_EFFECT_VIBRATION;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.5;
    def.motion_count = 1;
    def.motions[0] = (SimMotion){.amplitude = amp, .frequency = freq, .direction_y = 1.0};
    def.guard_max_speed = 0.0;
    SimWall walls[3] = {
        {.x0 = 0.0, .y0 = -0.05, .x1 = 0.0, .y1 = 0.5, .species = 0, .motion = -1},
        {.x0 = width, .y0 = -0.05, .x1 = width, .y1 = 0.5, .species = 0, .motion = -1},
        {.x0 = 0.0, .y0 = 0.0, .x1 = width, .y1 = 0.0, .species = 0, .motion = 0}};
    def.wall_count = fixed_base ? 2 : 3;
    def.walls = walls;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    double floor_top = 0.0;
    if (fixed_base) {
        sim_build_fixed_row(&b, rb, width - rb, 0.0, rb, 0, 0);
        floor_top = rb;
    }
    SimRng rng;
    sim_rng_seed(&rng, 9);
    st_lattice(&b, &rng, 30, 0.0, width, floor_top + amp + 0.2 * r, 0.9 * r, r, 0.3 * r);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    double floor_speed = amp * omega, worst_speed = 0.0, worst_depth = -1.0;
    long steps = (long)(0.5 / sim_world_time_step(w));
    long chunk = (long)(1e-3 / sim_world_time_step(w)) + 1;
    double overlap = 0.0;
    SimFrame f;
    for (long done = 0; done < steps; done += chunk) {
        TEST_ASSERT(tu_step(w, chunk) == 0);
        TEST_ASSERT(st_finite(w));
        overlap = fmax(overlap, sim_world_max_overlap_ratio(w));
        sim_world_frame(w, &f);
        double offset = amp * sin(omega * f.time);
        for (int i = 0; i < f.mobile_count; ++i) {
            /* depth of the grain's bottom below the current floor top, in d */
            worst_depth = fmax(worst_depth, (floor_top + offset - (f.y[i] - f.radius[i])) / d);
            worst_speed = fmax(worst_speed, hypot(f.vx[i], f.vy[i]));
            TEST_ASSERT(f.x[i] > 0.0 && f.x[i] < width);
            TEST_ASSERT(f.y[i] > offset); /* never through the floor or the base */
        }
    }
    fprintf(stderr,
            "vibrating floor (base %d): overlap %.3g d, depth %.3g d, speed %.3g of floor\n",
            fixed_base, overlap, worst_depth, worst_speed / floor_speed);
    TEST_ASSERT(overlap < 0.1);
    TEST_ASSERT(worst_depth < 0.1 + (fixed_base ? 1.0 : 0.0) * rb / d);
    TEST_ASSERT(worst_speed < 20.0 * floor_speed);
    sim_world_destroy(w);
    return 0;
}

static int vibrating_floor_wall_gamma10(void)
{
    return vibrating_floor(0);
}

static int vibrating_fixed_base_gamma10(void)
{
    return vibrating_floor(1);
}

/* Tangential spring law, grain (disk r 0.5, k_n 1e4, k_t 0.75 k_n, mu 0.5) on a long floor wall,
 * starting exactly touching it (a start at the equilibrium overlap is refused by the wall check:
 * see test_setup.c resting_overlap_on_wall_accepted); it sinks to its equilibrium overlap within
 * a few contact times (e_n 0.5). */
static SimWorldDef spring_def(SimWall *floor_wall)
{
    SimWorldDef def = tu_def(1.0, 1e4, 0.0);
    def.effects |= SIM_EFFECT_FRICTION;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.materials[0].friction = 0.5;
    def.materials[0].tangential_stiffness = 0.75e4;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.5;
    def.gravity_y = -G0;
    def.guard_max_speed = 0.0;
    *floor_wall =
        (SimWall){.x0 = -100.0, .y0 = 0.0, .x1 = 100.0, .y1 = 0.0, .species = 0, .motion = -1};
    def.wall_count = 1;
    def.walls = floor_wall;
    return def;
}

/* Checks the Coulomb cap of the spring on every contact: |F_t| <= mu k_n xi (1 + 1e-12). */
static int spring_capped(SimWorld *w, double mu, double k)
{
    SimFrame f;
    sim_world_frame(w, &f);
    for (int c = 0; c < f.contact_count; ++c) {
        double cap = mu * k * f.contacts[c].overlap;
        if (!(fabs(f.contacts[c].tangential_force) <= cap * (1.0 + 1e-12) + 1e-300)) {
            fprintf(stderr, "F_t %.17g above cap %.17g\n", f.contacts[c].tangential_force, cap);
            return 0;
        }
    }
    return 1;
}

/* Load reversal without sliding: the grain starts on the floor with vx = 0.02 m/s,
 * far below the slip threshold, so the spring catches it and the tangential load oscillates
 * (reverses sign every half period) while the grain settles into rolling. Nothing dissipates
 * tangentially, so total energy (kinetic, rotational, potential, normal and tangential spring)
 * never exceeds the initial one by more than 1e-3 of the initial kinetic energy; the cap holds at
 * every step; the tangential force changes sign (a reversal happened). */
static int tangential_spring_stick_reversal(void)
{
    SimWall floor_wall;
    SimWorldDef def = spring_def(&floor_wall);
    const double r = 0.5, m = tu_mass(SIM_MASS_DISK, 1.0, r), k = 1e4;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, r, r, 0, 0u, -1);
    b.vx[0] = 0.02;
    (void)m;
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    SimEnergy e = sim_world_energy(w);
    double e0 = e.total, ke0 = e.kinetic, e_max = e0, f_min = 0.0, f_max = 0.0;
    SimFrame f;
    for (int s = 0; s < 20000; ++s) {
        TEST_ASSERT(tu_step(w, 1) == 0);
        TEST_ASSERT(spring_capped(w, 0.5, k));
        e = sim_world_energy(w);
        e_max = fmax(e_max, e.total);
        sim_world_frame(w, &f);
        if (f.contact_count == 1) {
            f_min = fmin(f_min, f.contacts[0].tangential_force);
            f_max = fmax(f_max, f.contacts[0].tangential_force);
        }
    }
    fprintf(stderr, "stick: E rise %.3g of KE0, F_t in [%g, %g]\n", (e_max - e0) / ke0, f_min,
            f_max);
    TEST_ASSERT(st_finite(w));
    TEST_ASSERT(e_max <= e0 + 1e-3 * ke0);
    TEST_ASSERT(f_min < 0.0 && f_max > 0.0);
    sim_world_destroy(w);
    return 0;
}

/* Load reversal with sliding: the floor wall moves back and forth along x (A = 0.05 m, 5 Hz, peak
 * speed 1.6 m/s, far above what friction mu g can follow), so the contact slides and reverses
 * every half cycle. Bounds: the cap |F_t| <= mu k_n xi holds at every step (1e-12 relative); the
 * grain stays on the floor (|y - y_eq| < 0.01 r after it has settled, t > 0.1 s: no hopping
 * from spurious energy); its speed
 * never exceeds the peak floor speed (friction cannot drive it faster than the floor). */
static int tangential_spring_driven_reversal(void)
{
    SimWall floor_wall;
    SimWorldDef def = spring_def(&floor_wall);
    const double r = 0.5, m = tu_mass(SIM_MASS_DISK, 1.0, r), k = 1e4;
    def.effects |= SIM_EFFECT_VIBRATION;
    def.motion_count = 1;
    def.motions[0] = (SimMotion){.amplitude = 0.05, .frequency = 5.0, .direction_x = 1.0};
    floor_wall.motion = 0;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    double y_eq = r - m * G0 / k;
    sim_grain_buffer_add(&b, 0.0, r, r, 0, 0u, -1);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    double peak = 0.05 * 2.0 * TPI * 5.0, worst_y = 0.0, worst_v = 0.0;
    long steps = (long)(1.0 / sim_world_time_step(w));
    SimFrame f;
    for (long s = 0; s < steps; ++s) {
        TEST_ASSERT(tu_step(w, 1) == 0);
        TEST_ASSERT(spring_capped(w, 0.5, k));
        sim_world_frame(w, &f);
        if (f.time > 0.1)
            worst_y = fmax(worst_y, fabs(f.y[0] - y_eq));
        worst_v = fmax(worst_v, hypot(f.vx[0], f.vy[0]));
    }
    fprintf(stderr, "driven: |y - y_eq| %.3g r, speed %.3g of floor peak\n", worst_y / r,
            worst_v / peak);
    TEST_ASSERT(st_finite(w));
    TEST_ASSERT(worst_y < 0.01 * r);
    TEST_ASSERT(worst_v <= peak);
    sim_world_destroy(w);
    return 0;
}

/* A single column of N = 1000 grains (disk r 0.5, density 1) on a fixed grain between two side
 * walls 0.001 r clear of the grains, k_n chosen so that the analytic bottom overlap N m g / k_n is
 * 0.01 d; e_n 0.5. */
static SimWorld *column(int preload, double *xi_bottom)
{
    const int n = 1000;
    const double r = 0.5, m = tu_mass(SIM_MASS_DISK, 1.0, r);
    const double k = n * m * G0 / (0.01 * 2.0 * r);
    SimWorldDef def = tu_def(1.0, k, 0.0);
    def.gravity_y = -G0;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.5;
    def.guard_max_speed = 0.0;
    static SimWall walls[2];
    walls[0] = (SimWall){
        .x0 = -1.001 * r, .y0 = 0.0, .x1 = -1.001 * r, .y1 = 2.0 * n, .species = 0, .motion = -1};
    walls[1] = (SimWall){
        .x0 = 1.001 * r, .y0 = 0.0, .x1 = 1.001 * r, .y1 = 2.0 * n, .species = 0, .motion = -1};
    def.wall_count = 2;
    def.walls = walls;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, -r, r, 0, SIM_GRAIN_FIXED, -1);
    /* preload: each contact already carries the weight above it (static equilibrium) */
    double y = r - (preload ? n * m * G0 / k : 0.0);
    for (int j = 0; j < n; ++j) {
        sim_grain_buffer_add(&b, 0.0, y, r, 0, 0u, -1);
        y += 2.0 * r - (preload ? (n - 1 - j) * m * G0 / k : 0.0);
    }
    *xi_bottom = n * m * G0 / k;
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    return w;
}

/* Preloaded at the analytic equilibrium and left 5000 steps: it must stay there. Bounds: max
 * overlap ratio within 1 % of N m g / (k_n d) = 0.01; kinetic energy < 1e-9 N m g d; no NaN. */
static int column_1000_equilibrium(void)
{
    double xi;
    SimWorld *w = column(1, &xi);
    TEST_ASSERT(w);
    StRun run = st_run(w, 5000, 500);
    st_report("column_1000_equilibrium", &run);
    TEST_ASSERT(run.status == SIM_OK && run.finite);
    TEST_REL(run.overlap_max, xi / 1.0, 0.01);
    TEST_REL(sim_world_max_overlap_ratio(w), xi / 1.0, 0.01);
    const double m = tu_mass(SIM_MASS_DISK, 1.0, 0.5);
    TEST_ASSERT(sim_world_energy(w).kinetic < 1e-9 * 1000.0 * m * G0);
    sim_world_destroy(w);
    return 0;
}

/* Started with all grains exactly touching (unloaded), gravity applied suddenly; 1 s (about half
 * the period of the column's slowest mode, when the bottom compression peaks). Bounds: no NaN;
 * max overlap ratio never above 2.2 x the static N m g / (k_n d) (a suddenly loaded linear system
 * overshoots to at most 2 x its static deflection; 10 % for the discrete chain); at the end the
 * column is still one column (every grain within 0.01 r of x = 0). */
static int column_1000_sudden_load(void)
{
    double xi;
    SimWorld *w = column(0, &xi);
    TEST_ASSERT(w);
    long steps = (long)(1.0 / sim_world_time_step(w));
    StRun run = st_run(w, steps, 500);
    st_report("column_1000_sudden_load", &run);
    TEST_ASSERT(run.status == SIM_OK && run.finite);
    TEST_ASSERT(run.overlap_max <= 2.2 * xi);
    SimFrame f;
    sim_world_frame(w, &f);
    for (int i = 0; i < f.mobile_count; ++i)
        TEST_ASSERT(fabs(f.x[i]) < 0.01 * 0.5);
    sim_world_destroy(w);
    return 0;
}

/* A grain centred exactly on a cell corner: skin 0.1, r 0.5, so cells are 2 r + skin = 1.1 wide
 * from the lowest, leftmost grain at (0, 0); grain A sits at (1.1, 1.1) with four neighbours at
 * 0.99 (overlap 0.01) left, right, above and below, in four different cells. Bounds: all four
 * contacts found (count 4, each overlap 0.01 within 1e-12, elastic energy 4 x k xi^2 / 2 within
 * 1e-9 relative); after 200 steps without gravity A has not moved (1e-12 m: the forces cancel). */
static int grain_on_cell_corner(void)
{
    const double c = 1.1, k = 1e4;
    SimWorldDef def = tu_def(1.0, k, 0.0);
    def.skin = 0.1;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 0.0, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&b, c, c, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&b, c - 0.99, c, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&b, c + 0.99, c, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&b, c, c - 0.99, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&b, c, c + 0.99, 0.5, 0, 0u, -1);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    SimFrame f;
    sim_world_frame(w, &f);
    TEST_ASSERT(f.contact_count == 4);
    for (int k2 = 0; k2 < f.contact_count; ++k2)
        TEST_NEAR(f.contacts[k2].overlap, 0.01, 1e-12);
    TEST_REL(sim_world_energy(w).elastic, 4.0 * 0.5 * k * 0.01 * 0.01, 1e-9);
    TEST_ASSERT(tu_step(w, 200) == 0);
    sim_world_frame(w, &f);
    int a = tu_index(&f, 1);
    TEST_NEAR(f.x[a], c, 1e-12);
    TEST_NEAR(f.y[a], c, 1e-12);
    TEST_ASSERT(st_finite(w));
    sim_world_destroy(w);
    return 0;
}

/* Long thin walls: a frictionless incline 1000 m long (20000 d, 10 degrees) with 5 grains sliding
 * down it, a horizontal thin segment hit end-on at its end point, and a zero-length wall (a
 * point) hit head-on. Bounds: no NaN; the sliding grains stay on the incline's upper side
 * (signed distance > r - 0.05 d); the end-on and point grains rebound (vx < 0 after 0.2 s) and
 * never get past the end point by more than 0.05 d of overlap. */
static int long_thin_walls(void)
{
    const double r = 0.025, d = 2.0 * r, angle = 10.0 * TPI / 180.0, len = 1000.0;
    const double ca = cos(angle), sa = sin(angle);
    SimWorldDef def = tu_def(1.0, 1e4, 0.0);
    def.gravity_y = -G0;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.5;
    def.guard_max_speed = 0.0;
    SimWall walls[3] = {
        {.x0 = 0.0, .y0 = 0.0, .x1 = len * ca, .y1 = -len * sa, .species = 0, .motion = -1},
        {.x0 = -10.0, .y0 = 100.0, .x1 = -5.0, .y1 = 100.0, .species = 0, .motion = -1},
        {.x0 = -10.0, .y0 = 50.0, .x1 = -10.0, .y1 = 50.0, .species = 0, .motion = -1}};
    def.wall_count = 3;
    def.walls = walls;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    for (int k = 0; k < 5; ++k) { /* on the incline, just above it */
        double s = 1.0 + 0.2 * k;
        sim_grain_buffer_add(&b, s * ca + 1.001 * r * sa, -s * sa + 1.001 * r * ca, r, 0, 0u, -1);
    }
    int end_on = sim_grain_buffer_add(&b, -5.0 + 2.0 * r, 100.0, r, 0, 0u, -1);
    b.vx[end_on] = -2.0;
    int point = sim_grain_buffer_add(&b, -10.0 + 2.0 * r, 50.0, r, 0, 0u, -1);
    b.vx[point] = -2.0;
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    double worst = INFINITY, end_x = INFINITY, point_x = INFINITY;
    long chunk = 20, steps = (long)(0.2 / sim_world_time_step(w));
    SimFrame f;
    for (long done = 0; done < steps; done += chunk) {
        TEST_ASSERT(tu_step(w, chunk) == 0);
        TEST_ASSERT(st_finite(w));
        sim_world_frame(w, &f);
        for (int i = 0; i < f.count; ++i) {
            if (f.id[i] < 5) /* signed distance from the incline line (normal (sa, ca)) */
                worst = fmin(worst, f.x[i] * sa + f.y[i] * ca);
            else if (f.id[i] == (uint32_t)end_on)
                end_x = fmin(end_x, f.x[i]);
            else
                point_x = fmin(point_x, f.x[i]);
        }
    }
    sim_world_frame(w, &f);
    fprintf(stderr, "incline distance %.6g r, end-on min x %.6g, point min x %.6g\n", worst / r,
            end_x, point_x);
    TEST_ASSERT(worst > r - 0.05 * d);
    TEST_ASSERT(end_x > -5.0 + r - 0.05 * d);
    TEST_ASSERT(point_x > -10.0 + r - 0.05 * d);
    TEST_ASSERT(f.vx[tu_index(&f, (uint32_t)end_on)] > 0.0);
    TEST_ASSERT(f.vx[tu_index(&f, (uint32_t)point)] > 0.0);
    sim_world_destroy(w);
    return 0;
}

/* A lattice of 300 grains (touching columns, rows 1.98 r apart) settling for 2000 steps on a row
 * of fixed grains under gravity, with and without one extra grain at y = 1e6 m (it falls less
 * than 1 m meanwhile). The grid must stay bounded (it is capped at 4 N + 1024 cells)
 * and still find every contact: same contact count and max overlap (1e-9 relative) and the same
 * elastic energy after 2000 steps with and without the far grain; no NaN. */
static int far_away_grain(void)
{
    double overlap[2], elastic[2];
    int contacts[2];
    for (int far = 0; far < 2; ++far) {
        const double r = 0.05;
        SimWorldDef def = tu_def(1.0, 1e4, 0.0);
        def.gravity_y = -G0;
        def.guard_max_speed = 0.0;
        def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
        def.materials[0].restitution = 0.5;
        SimGrainBuffer b;
        sim_grain_buffer_init(&b);
        sim_build_fixed_row(&b, -r, 40.0 * r, -2.0 * r, r, 0, -1);
        for (int i = 0; i < 300; ++i)
            sim_grain_buffer_add(&b, (i % 20) * 2.0 * r, (i / 20) * 1.98 * r, r, 0, 0u, -1);
        if (far)
            sim_grain_buffer_add(&b, 0.3, 1e6, r, 0, 0u, -1);
        SimWorld *w = tu_create(&def, &b);
        sim_grain_buffer_free(&b);
        TEST_ASSERT(w);
        TEST_ASSERT(tu_step(w, 2000) == 0);
        TEST_ASSERT(st_finite(w));
        SimEnergy e = sim_world_energy(w);
        contacts[far] = e.contacts;
        elastic[far] = e.elastic;
        overlap[far] = sim_world_max_overlap_ratio(w);
        sim_world_destroy(w);
    }
    fprintf(stderr, "far grain: contacts %d %d, elastic %g %g\n", contacts[0], contacts[1],
            elastic[0], elastic[1]);
    TEST_ASSERT(contacts[0] == contacts[1] && contacts[0] > 150);
    TEST_REL(overlap[1], overlap[0], 1e-9);
    TEST_REL(elastic[1], elastic[0], 1e-9);
    return 0;
}

/* Extremely polydisperse pile: 12 grains of r 0.625 and 120 of r 0.05 (radius ratio 12.5, the 004
 * base-disc vs large-grain ratio) rain into a box of wall segments and settle for 1.5 s (disk,
 * density 1, k 4e5, e_n 0.5, automatic dt from the small-small pair). Bounds: no NaN; overlap
 * < 0.05 d_min; every grain inside the box (no small grain squeezed through a wall); total
 * energy never exceeds its running minimum by more than 1e-3 of the initial potential energy. */
static int polydisperse_012_125(void)
{
    const double rs = 0.05, rl = 0.625, width = 6.0;
    SimWorldDef def = tu_def(1.0, 4e5, 0.0);
    def.gravity_y = -G0;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.5;
    def.guard_max_speed = 0.0;
    SimWall walls[3] = {
        {.x0 = 0.0, .y0 = 0.0, .x1 = width, .y1 = 0.0, .species = 0, .motion = -1},
        {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 20.0, .species = 0, .motion = -1},
        {.x0 = width, .y0 = 0.0, .x1 = width, .y1 = 20.0, .species = 0, .motion = -1}};
    def.wall_count = 3;
    def.walls = walls;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    SimRng rng;
    sim_rng_seed(&rng, 21);
    double y = 0.0;
    for (int row = 0; row < 3; ++row) { /* alternate rows of 4 large and 40 small grains */
        y += rl + 0.05;
        for (int k = 0; k < 4; ++k)
            sim_grain_buffer_add(&b, 0.8 + k * 1.45 + 0.1 * sim_rng_uniform(&rng), y, rl, 0, 0u,
                                 -1);
        y += rl + 0.05 + rs;
        for (int k = 0; k < 40; ++k)
            sim_grain_buffer_add(&b, 0.1 + k * 0.145, y, rs, 0, 0u, -1);
        y += rs + 0.05;
    }
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    SimEnergy e = sim_world_energy(w);
    double e_min = e.total, rise = 0.0, scale = e.potential, overlap = 0.0;
    long chunk = 200, steps = (long)(1.5 / sim_world_time_step(w));
    for (long done = 0; done < steps; done += chunk) {
        TEST_ASSERT(tu_step(w, chunk) == 0);
        e = sim_world_energy(w);
        TEST_ASSERT(isfinite(e.total));
        rise = fmax(rise, e.total - e_min);
        e_min = fmin(e_min, e.total);
        overlap = fmax(overlap, sim_world_max_overlap_ratio(w));
    }
    fprintf(stderr, "polydisperse: overlap %.3g d_min, rise %.3g of scale, KE %.3g of scale\n",
            overlap, rise / scale, e.kinetic / scale);
    TEST_ASSERT(st_finite(w));
    TEST_ASSERT(overlap < 0.05);
    TEST_ASSERT(rise <= 1e-3 * scale);
    SimFrame f;
    sim_world_frame(w, &f);
    for (int i = 0; i < f.count; ++i)
        TEST_ASSERT(f.x[i] > 0.0 && f.x[i] < width && f.y[i] > 0.0);
    sim_world_destroy(w);
    return 0;
}

TEST_MAIN(TEST_CASE(periodic_seam_gas), TEST_CASE(periodic_seam_head_on),
          TEST_CASE(vibrating_floor_wall_gamma10), TEST_CASE(vibrating_fixed_base_gamma10),
          TEST_CASE(tangential_spring_stick_reversal), TEST_CASE(tangential_spring_driven_reversal),
          TEST_CASE(column_1000_equilibrium), TEST_CASE(column_1000_sudden_load),
          TEST_CASE(grain_on_cell_corner), TEST_CASE(long_thin_walls), TEST_CASE(far_away_grain),
          TEST_CASE(polydisperse_012_125))
