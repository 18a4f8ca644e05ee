/* SPDX-License-Identifier: MIT */
/* test_motion.c: prescribed motions (sim.h SimMotion: rotation, constant velocity, schedules,
 * per-stage clocks) and arc walls (a drum). */
#include "sim_test_util.h"
#include "test.h"

/* One mobile grain far from everything (a world needs grains) and one segment wall. */
static SimWorld *one_wall_world(const SimMotion *motion, SimGrainBuffer *b, SimWall *wall)
{
    SimWorldDef def = tu_def(1000.0, 1e5, 1e-4);
    def.effects = SIM_EFFECT_VIBRATION;
    def.motion_count = 1;
    def.motions[0] = *motion;
    sim_grain_buffer_init(b);
    sim_grain_buffer_add(b, 50.0, 50.0, 0.05, 0, 0u, -1);
    *wall = (SimWall){.x0 = 0.3, .y0 = -0.2, .x1 = 1.7, .y1 = 0.4, .species = 0, .motion = 0};
    def.wall_count = 1;
    def.walls = wall;
    return tu_create(&def, b);
}

/* A wall turning about (1, 2) at 0.7 rad/s: its end points are R(omega t)(p - c) + c. */
static int rotating_wall_follows_rotation(void)
{
    SimMotion m = {
        .kind = SIM_MOTION_ROTATION, .center_x = 1.0, .center_y = 2.0, .angular_velocity = 0.7};
    SimGrainBuffer b;
    SimWall wall;
    SimWorld *w = one_wall_world(&m, &b, &wall);
    TEST_ASSERT(w);
    for (int k = 0; k < 5; ++k) {
        TEST_ASSERT(tu_step(w, 2000) == 0);
        SimFrame f;
        sim_world_frame(w, &f);
        double th = 0.7 * f.time, c = cos(th), s = sin(th);
        double ex = c * (0.3 - 1.0) - s * (-0.2 - 2.0) + 1.0;
        double ey = s * (0.3 - 1.0) + c * (-0.2 - 2.0) + 2.0;
        TEST_NEAR(f.walls[0].x0, ex, 1e-13);
        TEST_NEAR(f.walls[0].y0, ey, 1e-13);
        ex = c * (1.7 - 1.0) - s * (0.4 - 2.0) + 1.0;
        ey = s * (1.7 - 1.0) + c * (0.4 - 2.0) + 2.0;
        TEST_NEAR(f.walls[0].x1, ex, 1e-13);
        TEST_NEAR(f.walls[0].y1, ey, 1e-13);
    }
    sim_world_destroy(w);
    sim_grain_buffer_free(&b);
    return 0;
}

/* A wall at constant velocity (0.3, -0.1) m/s has moved v t. */
static int constant_velocity_displacement(void)
{
    SimMotion m = {.kind = SIM_MOTION_VELOCITY, .velocity_x = 0.3, .velocity_y = -0.1};
    SimGrainBuffer b;
    SimWall wall;
    SimWorld *w = one_wall_world(&m, &b, &wall);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 12345) == 0);
    SimFrame f;
    sim_world_frame(w, &f);
    TEST_NEAR(f.walls[0].x0 - 0.3, 0.3 * f.time, 1e-13);
    TEST_NEAR(f.walls[0].y1 - 0.4, -0.1 * f.time, 1e-13);
    sim_world_destroy(w);
    sim_grain_buffer_free(&b);
    return 0;
}

/* start 0.1 s, ramp 0.2 s, stop 0.5 s at 1 m/s: still before 0.1, v = (t - 0.1) / 0.2 on the
 * ramp, 1 m/s until 0.5, then at rest 0.3 m on; each change within one step. */
static int schedule_start_ramp_stop(void)
{
    SimMotion m = {
        .kind = SIM_MOTION_VELOCITY, .velocity_x = 1.0, .start = 0.1, .ramp = 0.2, .stop = 0.5};
    SimGrainBuffer b;
    SimWall wall;
    SimWorld *w = one_wall_world(&m, &b, &wall);
    TEST_ASSERT(w);
    const double dt = sim_world_time_step(w);
    double first_move = -1.0, full_speed = -1.0, last_move = -1.0, previous = 0.3;
    for (int n = 1; n <= 7000; ++n) {
        TEST_ASSERT(tu_step(w, 1) == 0);
        SimFrame f;
        sim_world_frame(w, &f);
        double x = f.walls[0].x0, v = (x - previous) / dt;
        if (x != 0.3 && first_move < 0.0)
            first_move = f.time;
        if (v > 1.0 - 1e-9 && full_speed < 0.0)
            full_speed = f.time;
        if (x != previous)
            last_move = f.time;
        previous = x;
    }
    TEST_NEAR(first_move, 0.1, dt * 1.001);
    TEST_NEAR(full_speed, 0.3, dt * 1.001);
    TEST_NEAR(last_move, 0.5, dt * 1.001);
    TEST_NEAR(previous - 0.3, 0.4 - 0.1, 1e-12); /* 0.1 m on the ramp + 0.3 m at full speed */
    /* the pose itself at the schedule's marks */
    SimPose p = sim_motion_pose(&m, 0, 0.2);
    TEST_NEAR(p.vx, 0.5, 1e-15);
    TEST_NEAR(p.x, 0.5 * 0.1 * 0.1 / 0.2, 1e-15);
    sim_world_destroy(w);
    sim_grain_buffer_free(&b);
    return 0;
}

/* A world clock: a motion enabled at t = 0.2 (sim_world_set_motion) is still before, its own
 * time starts there; disabled at 0.4 it holds its pose. */
static int motion_clock_on_off(void)
{
    SimMotion m = {.kind = SIM_MOTION_VELOCITY, .velocity_x = 1.0};
    SimGrainBuffer b;
    SimWall wall;
    SimWorld *w = one_wall_world(&m, &b, &wall);
    TEST_ASSERT(w);
    sim_world_set_motion(w, 0, INFINITY, INFINITY);
    TEST_ASSERT(tu_step(w, 2000) == 0);
    SimFrame f;
    sim_world_frame(w, &f);
    TEST_ASSERT(f.walls[0].x0 == 0.3);
    sim_world_set_motion(w, 0, 0.2, 0.4);
    TEST_ASSERT(tu_step(w, 1000) == 0);
    sim_world_frame(w, &f);
    TEST_NEAR(f.walls[0].x0, 0.3 + 0.1, 1e-12);
    TEST_ASSERT(tu_step(w, 3000) == 0);
    sim_world_frame(w, &f);
    TEST_NEAR(f.walls[0].x0, 0.3 + 0.2, 1e-12);
    sim_world_destroy(w);
    sim_grain_buffer_free(&b);
    return 0;
}

/* A drum: one full arc wall of radius 0.5 m about the origin, touched inside, turning at omega
 * (ramped over 0.5 s), and one grain of radius 0.05 m resting at its bottom. */
static SimWorld *drum_world(double mu, double omega, SimGrainBuffer *b, SimWall *wall)
{
    SimWorldDef def = tu_def(1000.0, 2e4, 5e-5);
    def.effects = SIM_EFFECT_VIBRATION;
    def.gravity_y = -9.806;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.3;
    if (mu > 0.0) {
        /* friction and a stiff rolling resistance: the grain sticks to the wall, it does not
         * roll on it (004 ch. 4) */
        def.effects |= SIM_EFFECT_FRICTION | SIM_EFFECT_ROLLING;
        def.contact.tangential = SIM_TANGENTIAL_REGULARISED;
        def.contact.rolling = SIM_ROLLING_FIXED;
        def.materials[0].friction = mu;
        def.materials[0].tangential_damping = 1e5;
        def.materials[0].rolling_friction = 0.05;
        def.materials[0].rolling_stiffness = 50.0;
    }
    def.motion_count = 1;
    def.motions[0] =
        (SimMotion){.kind = SIM_MOTION_ROTATION, .angular_velocity = omega, .ramp = 0.5};
    sim_grain_buffer_init(b);
    sim_grain_buffer_add(b, 0.0, -0.45, 0.05, 0, 0u, -1);
    *wall = (SimWall){.shape = SIM_WALL_ARC,
                      .side = SIM_WALL_INSIDE,
                      .radius = 0.5,
                      .angle0 = 0.0,
                      .angle1 = 2.0 * TPI,
                      .species = 0,
                      .motion = 0};
    def.wall_count = 1;
    def.walls = wall;
    return tu_create(&def, b);
}

/* With friction the grain is carried up the turning wall at its speed (its centre turns about
 * the drum's at omega); without friction it stays at the bottom. */
static int drum_carries_grain_with_friction(void)
{
    const double omega = 0.2;
    for (int with = 1; with >= 0; --with) {
        SimGrainBuffer b;
        SimWall wall;
        SimWorld *w = drum_world(with ? 1.0 : 0.0, omega, &b, &wall);
        TEST_ASSERT(w);
        TEST_ASSERT(tu_step(w, 20000) == 0); /* 1 s: the ramp done */
        SimFrame f;
        sim_world_frame(w, &f);
        double a0 = atan2(f.x[0], -f.y[0]), t0 = f.time;
        TEST_ASSERT(tu_step(w, 20000) == 0);
        sim_world_frame(w, &f);
        double a1 = atan2(f.x[0], -f.y[0]);
        double rate = (a1 - a0) / (f.time - t0);
        if (with) {
            TEST_NEAR(rate, omega, 0.04 * omega);
            /* its speed is the wall's tangential speed at the grain's centre (to the rocking
             * of the undamped rolling spring) */
            TEST_NEAR(hypot(f.vx[0], f.vy[0]), omega * 0.45, 0.1 * omega * 0.45);
        } else {
            TEST_NEAR(a1, 0.0, 1e-6);
            TEST_NEAR(hypot(f.vx[0], f.vy[0]), 0.0, 1e-6);
        }
        sim_world_destroy(w);
        sim_grain_buffer_free(&b);
    }
    return 0;
}

/* The arc pushes inside grains inwards and outside grains outwards (one-sided arcs), and its
 * ends act as points. */
static int arc_contact_sides(void)
{
    SimGrainBuffer b;
    SimWorldDef def = tu_def(1000.0, 1e5, 1e-5);
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, -0.96, 0.05, 0, 0u, -1); /* inside, touching */
    sim_grain_buffer_add(&b, 3.0, -1.04, 0.05, 0, 0u, -1); /* outside, touching */
    SimWall walls[2] = {{.shape = SIM_WALL_ARC,
                         .side = SIM_WALL_INSIDE,
                         .radius = 1.0,
                         .angle1 = 2.0 * TPI,
                         .motion = -1},
                        {.shape = SIM_WALL_ARC,
                         .side = SIM_WALL_OUTSIDE,
                         .center_x = 3.0,
                         .radius = 1.0,
                         .angle0 = -TPI,
                         .angle1 = 0.0,
                         .motion = -1}};
    def.wall_count = 2;
    def.walls = walls;
    SimWorld *w = tu_create(&def, &b);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 1) == 0);
    SimFrame f;
    sim_world_frame(w, &f);
    TEST_ASSERT(f.fy[0] > 0.0); /* up, to the centre */
    TEST_ASSERT(f.fy[1] < 0.0); /* down, away from the centre */
    TEST_NEAR(f.fx[0], 0.0, 1e-9 * fabs(f.fy[0]));
    sim_world_destroy(w);
    sim_grain_buffer_free(&b);
    return 0;
}

/* A composition: a rotation by omega t about c, then a translation v t. A point p goes to
 * R(omega t)(p - c) + c + v t, and the pose's velocity field is the time derivative of that. */
static int composed_motion_pose(void)
{
    SimMotion m[3] = {
        {.kind = SIM_MOTION_ROTATION, .center_x = 1.0, .center_y = -0.5, .angular_velocity = 0.8},
        {.kind = SIM_MOTION_VELOCITY, .velocity_x = 0.3, .velocity_y = 0.2},
        {.kind = SIM_MOTION_COMPOSE, .part_count = 2, .parts = {0, 1}}};
    const double t = 1.7, px = 2.0, py = 0.5, h = 1e-6;
    SimPose p = sim_motion_pose(m, 2, t);
    double c = cos(0.8 * t), s = sin(0.8 * t);
    double qx = c * (px - 1.0) - s * (py + 0.5) + 1.0 + 0.3 * t;
    double qy = s * (px - 1.0) + c * (py + 0.5) - 0.5 + 0.2 * t;
    TEST_NEAR(c * px - s * py + p.x, qx, 1e-14);
    TEST_NEAR(s * px + c * py + p.y, qy, 1e-14);
    /* velocity of the point now at q: V + Omega z x (q - T), against a central difference */
    SimPose a = sim_motion_pose(m, 2, t - h), b = sim_motion_pose(m, 2, t + h);
    double xa = cos(a.angle) * px - sin(a.angle) * py + a.x;
    double xb = cos(b.angle) * px - sin(b.angle) * py + b.x;
    double ya = sin(a.angle) * px + cos(a.angle) * py + a.y;
    double yb = sin(b.angle) * px + cos(b.angle) * py + b.y;
    TEST_NEAR(p.vx - p.omega * (qy - p.y), (xb - xa) / (2.0 * h), 1e-8);
    TEST_NEAR(p.vy + p.omega * (qx - p.x), (yb - ya) / (2.0 * h), 1e-8);
    TEST_NEAR(p.omega, 0.8, 1e-15);
    return 0;
}

TEST_MAIN(TEST_CASE(composed_motion_pose), TEST_CASE(rotating_wall_follows_rotation),
          TEST_CASE(constant_velocity_displacement), TEST_CASE(schedule_start_ramp_stop),
          TEST_CASE(motion_clock_on_off), TEST_CASE(drum_carries_grain_with_friction),
          TEST_CASE(arc_contact_sides))
