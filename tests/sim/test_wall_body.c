/* SPDX-License-Identifier: MIT */
/* test_wall_body.c: walls that respond to the grains (sim.h SimWallBody): a servo lid holding its
 * target stress, a free piston at the static balance of its weight, the servo's stability rule,
 * the wall load (SimWallLoad) against the sum of the contact forces, and the same bits for any
 * thread count and across a save and load. */
#include "sim_test_util.h"
#include "test.h"

#include "sim/internal.h"

#include <math.h>
#include <stdlib.h>

/* A box 2 m wide (base, two sides) with a lid (wall 3) at y = 1.9 m over 150 grains rained from
 * y = 0.06 m, gravity on, damped linear contacts, dt = 1e-4 s. `body` makes the lid respond. */
typedef struct Box {
    SimWall walls[4];
    SimWallBody bodies[4];
    SimGrainBuffer grains;
    SimWorldDef def;
} Box;

static void box_def(Box *box, const SimWallBody *lid)
{
    static const SimWall walls[4] = {
        {.x0 = 0.0, .y0 = 0.0, .x1 = 2.0, .y1 = 0.0, .species = 0, .motion = -1},
        {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 3.0, .species = 0, .motion = -1},
        {.x0 = 2.0, .y0 = 0.0, .x1 = 2.0, .y1 = 3.0, .species = 0, .motion = -1},
        {.x0 = 0.0, .y0 = 1.9, .x1 = 2.0, .y1 = 1.9, .species = 0, .motion = -1}};
    memcpy(box->walls, walls, sizeof walls);
    memset(box->bodies, 0, sizeof box->bodies);
    box->bodies[3] = *lid;
    tu_rain_150(&box->grains, 7, 0.06);
    box->def = tu_def(1000.0, 1e5, 1e-4);
    box->def.gravity_y = -G0;
    box->def.materials[0].normal_damping = 200.0; /* damping ratio about 0.16 */
    box->def.wall_count = 4;
    box->def.walls = box->walls;
    box->def.wall_bodies = box->bodies;
}

static SimWorld *box_world(Box *box, const SimWallBody *lid)
{
    box_def(box, lid);
    return tu_create(&box->def, &box->grains);
}

/* The servo lid of the tests: 2000 N/m pressed down (axis -y), gain 1e-3 (m/s)/(N/m): the
 * servo's time scale d / (gain k_n) = 0.092 / (1e-3 1e5) s, about nine time steps. */
static SimWallBody servo_lid(double gain)
{
    return (SimWallBody){.active = 1,
                         .axis_x = 0.0,
                         .axis_y = -1.0,
                         .servo = 1,
                         .target = 2000.0,
                         .gain = gain,
                         .max_speed = 0.5};
}

/* The lid's load averaged over `samples` samples `every` steps apart. */
static int mean_load(SimWorld *w, int samples, long every, SimWallLoad *mean)
{
    memset(mean, 0, sizeof *mean);
    for (int s = 0; s < samples; ++s) {
        if (tu_step(w, every) != 0)
            return -1;
        SimWallLoad l;
        sim_world_wall_load(w, 3, &l);
        mean->fx += l.fx / samples;
        mean->fy += l.fy / samples;
        mean->normal += l.normal / samples;
        mean->offset += l.offset / samples;
        mean->length = l.length;
    }
    return 0;
}

/* The lid comes down on the pile and holds 2000 N/m within 1 % over a 1 s window. */
static int servo_holds_target_stress(void)
{
    SimWallBody lid = servo_lid(1e-3);
    Box box;
    SimWorld *w = box_world(&box, &lid);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 40000) == 0); /* the lid travels about 1 m at 0.5 m/s, then holds */
    SimWallLoad mean;
    TEST_ASSERT(mean_load(w, 1000, 10, &mean) == 0);
    const double stress = mean.fy / mean.length; /* the grains push it up: -F.axis = F_y */
    printf("servo lid: stress %.9g N/m (target 2000), normal/length %.9g, offset %.4g m\n", stress,
           mean.normal / mean.length, mean.offset);
    TEST_ASSERT(mean.offset > 0.5); /* it came down (along its axis -y) onto the pile */
    TEST_NEAR(stress, 2000.0, 20.0);
    TEST_NEAR(mean.normal / mean.length, 2000.0, 20.0);
    sim_world_destroy(w);
    sim_grain_buffer_free(&box.grains);
    return 0;
}

/* A gain with dt = 5 tau (the error multiplied by -4 each step) is refused at create, naming the
 * wall; the servo's time scale is d_min / (gain k_n). */
static int servo_unstable_gain_refused(void)
{
    SimWallBody lid = servo_lid(5e-2);
    Box box;
    box_def(&box, &lid);
    box.def.grains = sim_grain_buffer_view(&box.grains);
    double d_min = HUGE_VAL;
    for (int i = 0; i < box.grains.count; ++i)
        d_min = fmin(d_min, 2.0 * box.grains.radius[i]);
    TEST_NEAR(sim_wall_servo_time(&box.def, 3), d_min / (5e-2 * 1e5), 1e-15);
    TEST_ASSERT(isinf(sim_wall_servo_time(&box.def, 0)));
    SimError err;
    SimWorld *w = sim_world_create(&box.def, &err);
    TEST_ASSERT(!w);
    TEST_ASSERT(err.status == SIM_ERROR_INVALID);
    TEST_ASSERT(strcmp(err.field, "walls[3]") == 0);
    TEST_ASSERT(strstr(err.message, "unstable") != NULL);
    sim_grain_buffer_free(&box.grains);
    return 0;
}

/* A free piston of 50 kg dropped on the pile: at rest its load is its weight, F_y = m g
 * (averaged over 2 s, within 1 %). */
static int piston_reaches_static_balance(void)
{
    SimWallBody lid = {.active = 1, .axis_x = 0.0, .axis_y = -1.0, .mass = 50.0, .gravity = 1};
    Box box;
    box_def(&box, &lid);
    /* damping ratio about 0.8 between grains: the piston stops rattling on the bed */
    box.def.materials[0].normal_damping = 1000.0;
    SimWorld *w = tu_create(&box.def, &box.grains);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 50000) == 0);
    SimWallLoad mean;
    TEST_ASSERT(mean_load(w, 2000, 10, &mean) == 0);
    printf("piston: F_y %.6g N, m g %.6g N, offset %.4g m\n", mean.fy, 50.0 * G0, mean.offset);
    TEST_ASSERT(mean.offset > 0.5);
    TEST_NEAR(mean.fy, 50.0 * G0, 0.01 * 50.0 * G0);
    TEST_NEAR(mean.fx, 0.0, 0.01 * 50.0 * G0);
    sim_world_destroy(w);
    sim_grain_buffer_free(&box.grains);
    return 0;
}

/* Sums of the wall contacts of a frame per wall: force on the wall f_n n - f_t s
 * (s = (n_y, -n_x)), its normal part, its torque about the wall's centre. */
static void contact_sums(SimWorld *w, double f[4][4])
{
    SimFrame frame;
    sim_world_frame(w, &frame);
    memset(f, 0, 16 * sizeof(double));
    for (int k = 0; k < frame.contact_count; ++k) {
        const SimContact *c = &frame.contacts[k];
        if (c->j >= 0)
            continue;
        const int wall = -1 - c->j;
        SimWallLoad l;
        sim_world_wall_load(w, wall, &l);
        const double fx = c->normal_force * c->nx - c->tangential_force * c->ny;
        const double fy = c->normal_force * c->ny + c->tangential_force * c->nx;
        f[wall][0] += fx;
        f[wall][1] += fy;
        f[wall][2] += c->normal_force;
        f[wall][3] += (c->x - l.x) * fy - (c->y - l.y) * fx;
    }
}

/* Undamped, frictionless walls: the load of each wall is the sum of its contacts' forces. */
static int wall_load_is_contact_sum(void)
{
    SimWallBody none = {0};
    Box box;
    box_def(&box, &none);
    box.def.materials[0].normal_damping = 0.0;
    box.def.materials[0].normal_stiffness = 1e6; /* undamped landing: overlaps below 0.2 d */
    box.def.wall_bodies = NULL;
    SimWorld *w = tu_create(&box.def, &box.grains);
    TEST_ASSERT(w);
    int touched = 0;
    for (int round = 0; round < 80; ++round) {
        TEST_ASSERT(tu_step(w, 100) == 0);
        double sums[4][4];
        contact_sums(w, sums);
        for (int k = 0; k < 4; ++k) {
            SimWallLoad l;
            TEST_ASSERT(sim_world_wall_load(w, k, &l) == 0);
            const double scale = 1e-12 * (fabs(l.normal) + 1.0);
            TEST_NEAR(l.fx, sums[k][0], scale);
            TEST_NEAR(l.fy, sums[k][1], scale);
            TEST_NEAR(l.normal, sums[k][2], scale);
            TEST_NEAR(l.torque, sums[k][3], scale * 2.0);
            touched += l.contacts > 0;
        }
    }
    printf("walls touched in %d of 320 samples\n", touched);
    TEST_ASSERT(touched >= 40);
    sim_world_destroy(w);
    sim_grain_buffer_free(&box.grains);
    return 0;
}

/* The servo lid on 1 and 2 threads, and a run saved and loaded half-way: the same bits (the
 * whole state, the lid's offset and speed included, compared as saved files). */
static int servo_same_bits_threads_and_resume(void)
{
    SimWallBody lid = servo_lid(1e-3);
    Box box[3];
    SimWorld *w[3];
    for (int k = 0; k < 2; ++k) {
        w[k] = box_world(&box[k], &lid);
        TEST_ASSERT(w[k]);
        sim_world_set_threads(w[k], k + 1);
        TEST_ASSERT(tu_step(w[k], 6000) == 0);
    }
    char saved[32], a[32], b[32], c[32];
    TEST_ASSERT(test_tmp_file(saved) == 0 && test_tmp_file(a) == 0 && test_tmp_file(b) == 0 &&
                test_tmp_file(c) == 0);
    SimError err;
    TEST_ASSERT(sim_world_save(w[0], saved, &err) == SIM_OK);
    box_def(&box[2], &lid);
    w[2] = sim_world_load(saved, &box[2].def, &err);
    TEST_ASSERT(w[2]);
    TEST_ASSERT(sim_world_restore_contacts(w[2], saved, &err) == SIM_OK);
    for (int k = 0; k < 3; ++k)
        TEST_ASSERT(tu_step(w[k], 4000) == 0);
    SimWallLoad l0, l1;
    sim_world_wall_load(w[0], 3, &l0);
    sim_world_wall_load(w[1], 3, &l1);
    TEST_ASSERT(l0.offset > 0.1 && l0.offset == l1.offset && l0.speed == l1.speed);
    TEST_ASSERT(sim_world_save(w[0], a, &err) == SIM_OK &&
                sim_world_save(w[1], b, &err) == SIM_OK && sim_world_save(w[2], c, &err) == SIM_OK);
    FILE *f[3] = {fopen(a, "rb"), fopen(b, "rb"), fopen(c, "rb")};
    int same = f[0] && f[1] && f[2];
    while (same) {
        int x = fgetc(f[0]), y = fgetc(f[1]), z = fgetc(f[2]);
        same = x == y && x == z;
        if (x == EOF)
            break;
    }
    for (int k = 0; k < 3; ++k) {
        if (f[k])
            fclose(f[k]);
        sim_world_destroy(w[k]);
        sim_grain_buffer_free(&box[k].grains);
    }
    remove(saved);
    remove(a);
    remove(b);
    remove(c);
    TEST_ASSERT(same);
    return 0;
}

/* The servo lid, its stress taken over `length` = 2 m (its own), following motion 0: `velocity`
 * (vx, vy) from the start (vibration on). */
static void sliding_lid_def(Box *box, double gain, double vx, double vy)
{
    SimWallBody lid = servo_lid(gain);
    lid.length_kind = 1;
    lid.length = 2.0;
    box_def(box, &lid);
    box->walls[3].motion = 0;
    box->def.effects |= SIM_EFFECT_VIBRATION;
    box->def.motion_count = 1;
    box->def.motions[0] =
        (SimMotion){.kind = SIM_MOTION_VELOCITY, .velocity_x = vx, .velocity_y = vy};
}

/* A servo lid that also follows a motion across its axis (x, 1 cm/s: it stays over the box): its
 * centre moves at the motion's speed while the servo holds 2000 N/m within 1 %. */
static int servo_lid_follows_motion_across(void)
{
    Box box;
    sliding_lid_def(&box, 1e-3, 0.01, 0.0);
    SimWorld *w = tu_create(&box.def, &box.grains);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 40000) == 0);
    SimWallLoad l;
    sim_world_wall_load(w, 3, &l);
    TEST_NEAR(l.x, 1.0 + 0.01 * 4.0, 1e-12); /* the centre (1, 1.9) moved 1 cm/s x 4 s */
    TEST_NEAR(l.length, 2.0, 0.0);
    SimWallLoad mean;
    TEST_ASSERT(mean_load(w, 1000, 10, &mean) == 0);
    printf("sliding servo lid: stress %.9g N/m (target 2000), offset %.4g m\n", mean.fy / 2.0,
           mean.offset);
    TEST_ASSERT(mean.offset > 0.5);
    TEST_NEAR(mean.fy / 2.0, 2000.0, 20.0);
    sim_world_wall_load(w, 3, &l);
    TEST_NEAR(l.x, 1.0 + 0.01 * 5.0, 1e-12);
    sim_world_destroy(w);
    sim_grain_buffer_free(&box.grains);
    return 0;
}

/* A responding wall's motion with a part along its axis, or one that turns, is refused at
 * create, naming the wall. */
static int servo_motion_along_axis_refused(void)
{
    for (int turn = 0; turn < 2; ++turn) {
        Box box;
        sliding_lid_def(&box, 1e-3, 0.3, turn ? 0.0 : 0.1);
        if (turn)
            box.def.motions[0] = (SimMotion){.kind = SIM_MOTION_ROTATION, .angular_velocity = 0.1};
        box.def.grains = sim_grain_buffer_view(&box.grains);
        SimError err;
        SimWorld *w = sim_world_create(&box.def, &err);
        TEST_ASSERT(!w);
        TEST_ASSERT(strcmp(err.field, "walls[3]") == 0);
        TEST_ASSERT(strstr(err.message, turn ? "turns" : "along its axis") != NULL);
        sim_grain_buffer_free(&box.grains);
    }
    return 0;
}

/* The sliding servo lid on 1, 2, 3 and 8 threads, and a run saved and loaded half-way: the same
 * bits (compared as saved files). */
static int sliding_lid_same_bits_threads_and_resume(void)
{
    enum { RUNS = 5 };

    static const int threads[RUNS - 1] = {1, 2, 3, 8};
    Box box[RUNS];
    SimWorld *w[RUNS];
    for (int k = 0; k < RUNS - 1; ++k) {
        sliding_lid_def(&box[k], 1e-3, 0.01, 0.0);
        w[k] = tu_create(&box[k].def, &box[k].grains);
        TEST_ASSERT(w[k]);
        sim_world_set_threads(w[k], threads[k]);
        TEST_ASSERT(tu_step(w[k], 6000) == 0);
    }
    char saved[32], out[RUNS][32];
    TEST_ASSERT(test_tmp_file(saved) == 0);
    SimError err;
    TEST_ASSERT(sim_world_save(w[0], saved, &err) == SIM_OK);
    sliding_lid_def(&box[RUNS - 1], 1e-3, 0.01, 0.0);
    w[RUNS - 1] = sim_world_load(saved, &box[RUNS - 1].def, &err);
    TEST_ASSERT(w[RUNS - 1]);
    TEST_ASSERT(sim_world_restore_contacts(w[RUNS - 1], saved, &err) == SIM_OK);
    int same = 1;
    FILE *f[RUNS];
    for (int k = 0; k < RUNS; ++k) {
        TEST_ASSERT(tu_step(w[k], 4000) == 0);
        TEST_ASSERT(test_tmp_file(out[k]) == 0 && sim_world_save(w[k], out[k], &err) == SIM_OK);
        f[k] = fopen(out[k], "rb");
        same &= f[k] != NULL;
    }
    SimWallLoad l;
    sim_world_wall_load(w[0], 3, &l);
    TEST_ASSERT(l.offset > 0.1);
    while (same) {
        const int x = fgetc(f[0]);
        for (int k = 1; k < RUNS; ++k)
            same &= fgetc(f[k]) == x;
        if (x == EOF)
            break;
    }
    for (int k = 0; k < RUNS; ++k) {
        if (f[k])
            fclose(f[k]);
        remove(out[k]);
        sim_world_destroy(w[k]);
        sim_grain_buffer_free(&box[k].grains);
    }
    remove(saved);
    TEST_ASSERT(same);
    return 0;
}

/* A box whose side walls are longer than the sample (y from -1 to 4 m), gravity on: the base
 * (y = 0), the left wall (x = 0) and the lid (y = 1.9) still, the right wall (x = 2) a servo
 * along -x holding sigma_xx = 2000 N/m over the distance between the base and the lid
 * (`between`), 1.9 m, not over its own 5 m: the load's length is that distance, the servo's
 * speed follows its gain law with it at every sample, and the mean of force / 1.9 m holds the
 * target within 1 % (the pile settles as tall as its lateral load needs, about 1 m). */
static int servo_stress_over_walls_between(void)
{
    SimWallBody none = {0};
    Box box;
    box_def(&box, &none);
    box.walls[1].y0 = box.walls[2].y0 = -1.0;
    box.walls[1].y1 = box.walls[2].y1 = 4.0;
    box.bodies[2] = (SimWallBody){.active = 1,
                                  .axis_x = -1.0,
                                  .servo = 1,
                                  .target = 2000.0,
                                  .gain = 2e-4,
                                  .max_speed = 0.5,
                                  .length_kind = 2,
                                  .between = {0, 3},
                                  .servo_explicit = 1}; /* the law checked below, exactly */
    SimWorld *w = tu_create(&box.def, &box.grains);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 60000) == 0);
    double sxx = 0.0, height = 0.0, width = 0.0;
    const int samples = 1000;
    for (int s = 0; s < samples; ++s) {
        TEST_ASSERT(tu_step(w, 10) == 0);
        SimWallLoad l[4];
        for (int k = 0; k < 4; ++k)
            sim_world_wall_load(w, k, &l[k]);
        const double h = l[3].y - l[0].y, b = l[2].x - l[1].x;
        TEST_NEAR(l[2].length, h, 1e-12);
        /* the servo's law on this length: u = gain (target - F_x / h), |u| <= max_speed */
        const double u = fmax(-0.5, fmin(0.5, 2e-4 * (2000.0 - l[2].fx / h)));
        TEST_NEAR(l[2].speed, u, 1e-12);
        sxx += l[2].fx / h / samples; /* the grains push the right wall along +x */
        height += h / samples;
        width += b / samples;
    }
    printf("box %.4g x %.4g m: sigma_xx %.9g N/m (target 2000)\n", width, height, sxx);
    TEST_ASSERT(width < 1.8); /* the servo closed on the sample */
    TEST_NEAR(sxx, 2000.0, 20.0);
    sim_world_destroy(w);
    sim_grain_buffer_free(&box.grains);
    return 0;
}

/* The 1.98 m lid (a force servo, 4000 N, gain 1e-3, slightly shorter than the box) on its law
 * `explicit_law` (SimWallBody servo_explicit), `threads` threads, after 30000 steps. */
static SimWorld *force_lid(Box *box, int explicit_law, int threads)
{
    SimWallBody lid = servo_lid(1e-3);
    lid.servo = 2;
    lid.target = 4000.0;
    lid.servo_explicit = explicit_law;
    box_def(box, &lid);
    box->walls[3].x0 = 0.01;
    box->walls[3].x1 = 1.99;
    SimWorld *w = tu_create(&box->def, &box->grains);
    if (w)
        sim_world_set_threads(w, threads);
    return w && tu_step(w, 30000) == 0 ? w : NULL;
}

/* The implicit law (the default) holds the 1.98 m lid's 4000 N within 1 % over 1 s whether
 * sampled every 10 or every 2 steps, never flipping, with the same bits on 1, 2, 3 and 8 threads;
 * the explicit law flips it between +-max_speed every step (gain gamma_n = 0.2 per contact over
 * a row of grains): counted, from a time within the run. */
static int servo_implicit_damping_holds_lid(void)
{
    static const int threads[4] = {1, 2, 3, 8};
    Box box[5];
    SimWorld *w[5];
    SimWallLoad mean[2], l[4];
    for (int k = 0; k < 4; ++k) {
        w[k] = force_lid(&box[k], 0, threads[k]);
        TEST_ASSERT(w[k]);
    }
    TEST_ASSERT(mean_load(w[0], 1000, 10, &mean[0]) == 0);
    TEST_ASSERT(mean_load(w[1], 5000, 2, &mean[1]) == 0);
    TEST_ASSERT(tu_step(w[2], 10000) == 0 && tu_step(w[3], 10000) == 0);
    for (int k = 0; k < 4; ++k)
        sim_world_wall_load(w[k], 3, &l[k]);
    printf("implicit lid: %.9g N (every 10 steps), %.9g N (every 2)\n", mean[0].normal,
           mean[1].normal);
    TEST_NEAR(mean[0].normal, 4000.0, 40.0);
    TEST_NEAR(mean[1].normal, 4000.0, 40.0);
    TEST_NEAR(mean[0].normal, mean[1].normal, 40.0);
    for (int k = 1; k < 4; ++k)
        TEST_ASSERT(l[k].offset == l[0].offset && l[k].speed == l[0].speed &&
                    l[k].normal == l[0].normal);
    TEST_ASSERT(l[0].servo_flips == 0 && isnan(l[0].servo_flip_time));
    w[4] = force_lid(&box[4], 1, 1);
    TEST_ASSERT(w[4]);
    sim_world_wall_load(w[4], 3, &l[0]);
    printf("explicit lid: %ld steps flipping since t = %g s\n", l[0].servo_flips,
           l[0].servo_flip_time);
    TEST_ASSERT(l[0].servo_flips > SIM_SERVO_FLIP_STEPS && l[0].servo_flip_time > 0.0 &&
                l[0].servo_flip_time <= 3.0);
    for (int k = 0; k < 5; ++k) {
        sim_world_destroy(w[k]);
        sim_grain_buffer_free(&box[k].grains);
    }
    return 0;
}

/* 1 when the two files hold the same bytes. */
static int same_files(const char *a, const char *b)
{
    FILE *f[2] = {fopen(a, "rb"), fopen(b, "rb")};
    int same = f[0] && f[1];
    while (same) {
        const int x = fgetc(f[0]);
        same = fgetc(f[1]) == x;
        if (x == EOF)
            break;
    }
    for (int k = 0; k < 2; ++k)
        if (f[k])
            fclose(f[k]);
    return same;
}

/* Saves the two worlds and compares the files (1: the same bytes), then frees both runs and
 * removes `saved`, the state the second was loaded from. */
static int ends_alike(SimWorld *w[2], Box box[2], const char *saved)
{
    char out[2][32];
    SimError err;
    int saved_both = 1;
    for (int k = 0; k < 2; ++k)
        saved_both &= test_tmp_file(out[k]) == 0 && sim_world_save(w[k], out[k], &err) == SIM_OK;
    const int same = saved_both && same_files(out[0], out[1]);
    for (int k = 0; k < 2; ++k) {
        remove(out[k]);
        sim_world_destroy(w[k]);
        sim_grain_buffer_free(&box[k].grains);
    }
    remove(saved);
    return same;
}

/* The sliding lid of sliding_lid_def, its motion (5 cm/s across) enabled at t = 0.2 s as a
 * stage would (sim_world_set_motion), saved at t = 0.6 s and loaded as a resumed run does:
 * created from the state (the motions' clocks are the defaults then: on at 0), then its clock
 * set. The loaded world holds the lid where the uninterrupted one has it, with the same list
 * bookkeeping (the walls' shift since the last build, the build step), and both go on to the
 * same bits. A footer without the lid's motion offset (WBODY-2) placed the lid at load by the
 * default clock, 2 cm off, and counted that as the lid's shift since the build. */
static int sliding_lid_resumed_keeps_list_bookkeeping(void)
{
    Box box[2];
    sliding_lid_def(&box[0], 1e-3, 0.05, 0.0);
    SimWorld *w[2] = {tu_create(&box[0].def, &box[0].grains), NULL};
    TEST_ASSERT(w[0]);
    sim_world_set_motion(w[0], 0, 0.2, INFINITY);
    TEST_ASSERT(tu_step(w[0], 6000) == 0);
    char saved[32];
    SimError err;
    TEST_ASSERT(test_tmp_file(saved) == 0 && sim_world_save(w[0], saved, &err) == SIM_OK);
    sliding_lid_def(&box[1], 1e-3, 0.05, 0.0);
    w[1] = sim_world_load(saved, &box[1].def, &err);
    TEST_ASSERT(w[1] && w[1]->exact_restored);
    sim_world_set_motion(w[1], 0, 0.2, INFINITY);
    printf("sliding lid at load: x0 %.17g (run %.17g), wall shift %.17g (run %.17g), built at "
           "step %ld (run %ld)\n",
           w[1]->walls[3].x0, w[0]->walls[3].x0, w[1]->wall_shift, w[0]->wall_shift,
           w[1]->build_step, w[0]->build_step);
    TEST_ASSERT(memcmp(&w[1]->walls[3], &w[0]->walls[3], sizeof(SimWall)) == 0);
    TEST_ASSERT(w[1]->wall_shift == w[0]->wall_shift && w[1]->build_step == w[0]->build_step);
    for (int k = 0; k < 2; ++k)
        TEST_ASSERT(tu_step(w[k], 4000) == 0);
    TEST_ASSERT(w[1]->build_step == w[0]->build_step && w[1]->rebuilds == w[0]->rebuilds);
    TEST_ASSERT(ends_alike(w, box, saved));
    return 0;
}

/* A state whose footer is of the second version (WBODY-2: offsets, speeds, angles and angular
 * speeds, no motion offsets, rest geometry or flip counters), made from a saved one by cutting
 * those out: it
 * still loads, the lid at its saved offset and speed, and (its clock the default one, as when
 * it was saved) goes on to the same bits as the uninterrupted run. */
static int older_footer_still_loads(void)
{
    Box box[2];
    sliding_lid_def(&box[0], 1e-3, 0.01, 0.0);
    SimWorld *w[2] = {tu_create(&box[0].def, &box[0].grains), NULL};
    TEST_ASSERT(w[0] && tu_step(w[0], 6000) == 0);
    char saved[32];
    SimError err;
    TEST_ASSERT(test_tmp_file(saved) == 0 && sim_world_save(w[0], saved, &err) == SIM_OK);
    FILE *f = fopen(saved, "rb");
    TEST_ASSERT(f && fseek(f, 0, SEEK_END) == 0);
    const long size = ftell(f), n = w[0]->body_count, cut = 11 * n * (long)sizeof(double);
    char *bytes = malloc((size_t)size);
    TEST_ASSERT(bytes && fseek(f, 0, SEEK_SET) == 0 &&
                fread(bytes, 1, (size_t)size, f) == (size_t)size);
    fclose(f);
    TEST_ASSERT(memcmp(bytes + size - 8, "WBODY-3\n", 8) == 0);
    memmove(bytes + size - 12 - cut, bytes + size - 12, 12); /* count and tag after the 4 arrays */
    memcpy(bytes + size - cut - 8, "WBODY-2\n", 8);
    f = fopen(saved, "wb");
    TEST_ASSERT(f && fwrite(bytes, 1, (size_t)(size - cut), f) == (size_t)(size - cut));
    fclose(f);
    free(bytes);
    sliding_lid_def(&box[1], 1e-3, 0.01, 0.0);
    w[1] = sim_world_load(saved, &box[1].def, &err);
    TEST_ASSERT(w[1]);
    SimWallLoad l[2];
    for (int k = 0; k < 2; ++k)
        sim_world_wall_load(w[k], 3, &l[k]);
    TEST_ASSERT(l[0].offset > 0.1 && l[1].offset == l[0].offset && l[1].speed == l[0].speed);
    for (int k = 0; k < 2; ++k)
        TEST_ASSERT(tu_step(w[k], 2000) == 0);
    TEST_ASSERT(ends_alike(w, box, saved));
    return 0;
}

TEST_MAIN(TEST_CASE(servo_holds_target_stress), TEST_CASE(servo_unstable_gain_refused),
          TEST_CASE(piston_reaches_static_balance), TEST_CASE(wall_load_is_contact_sum),
          TEST_CASE(servo_same_bits_threads_and_resume), TEST_CASE(servo_lid_follows_motion_across),
          TEST_CASE(servo_motion_along_axis_refused),
          TEST_CASE(sliding_lid_same_bits_threads_and_resume),
          TEST_CASE(servo_stress_over_walls_between),
          TEST_CASE(sliding_lid_resumed_keeps_list_bookkeeping),
          TEST_CASE(older_footer_still_loads), TEST_CASE(servo_implicit_damping_holds_lid))
