/* SPDX-License-Identifier: MIT */
/* test_wall_body_group.c: grain bodies (sim.h SimWorldDef.grain_bodies, a rough piston: fixed
 * grains moving as one rigid body) and bodies that turn (SimWallBody.rotation): the group's load
 * against the sum of its grains' contact forces, the same bits for any thread count and across
 * a save and load, a hinged plate and a hinged group turning under an off-centre impact with the
 * angular momentum about the hinge conserved, and a group without grains dormant until its grains
 * are added. */
#include "sim_test_util.h"
#include "test.h"

#include <stdlib.h>

/* A box 2 m wide (base, two sides) over 150 grains rained from y = 0.06 m, with a row of fixed
 * grains of radius 0.05 m at y = 1.95 m, the group of grain body 0 (`piston`). */
typedef struct Piston {
    SimWall walls[3];
    SimWallBody body;
    SimGrainBuffer grains;
    SimWorldDef def;
} Piston;

static void piston_def(Piston *p, const SimWallBody *body)
{
    static const SimWall walls[3] = {
        {.x0 = 0.0, .y0 = 0.0, .x1 = 2.0, .y1 = 0.0, .species = 0, .motion = -1},
        {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 3.0, .species = 0, .motion = -1},
        {.x0 = 2.0, .y0 = 0.0, .x1 = 2.0, .y1 = 3.0, .species = 0, .motion = -1}};
    memcpy(p->walls, walls, sizeof walls);
    p->body = *body;
    tu_rain_150(&p->grains, 7, 0.06);
    sim_build_fixed_row(&p->grains, 0.05, 1.95, 1.95, 0.05, 0, SIM_GRAIN_BODY(0));
    p->def = tu_def(1000.0, 1e5, 1e-4);
    p->def.gravity_y = -G0;
    p->def.materials[0].normal_damping = 200.0;
    p->def.wall_count = 3;
    p->def.walls = p->walls;
    p->def.grain_bodies = &p->body;
    p->def.grain_body_count = 1;
}

static const SimWallBody free_piston = {
    .active = 1, .axis_x = 0.0, .axis_y = -1.0, .mass = 20.0, .gravity = 1};

/* The group's load (wall_count + 0) is the sum of its grains' forces in frame order, and its
 * torque about its centre; it falls onto the pile. */
static int group_load_is_contact_sum(void)
{
    Piston p;
    piston_def(&p, &free_piston);
    SimWorld *w = tu_create(&p.def, &p.grains);
    TEST_ASSERT(w);
    int touched = 0;
    for (int round = 0; round < 60; ++round) {
        TEST_ASSERT(tu_step(w, 200) == 0);
        SimWallLoad l;
        TEST_ASSERT(sim_world_wall_load(w, 3, &l) == 0);
        SimFrame f;
        sim_world_frame(w, &f);
        double fx = 0.0, fy = 0.0, torque = 0.0;
        for (int i = f.mobile_count; i < f.count; ++i) {
            fx += f.fx[i];
            fy += f.fy[i];
            torque += (f.x[i] - l.x) * f.fy[i] - (f.y[i] - l.y) * f.fx[i];
        }
        const double scale = 1e-12 * (fabs(fy) + 1.0);
        TEST_NEAR(l.fx, fx, scale);
        TEST_NEAR(l.fy, fy, scale);
        TEST_NEAR(l.normal, fy, scale); /* -F.axis, axis -y */
        TEST_NEAR(l.torque, torque, 10.0 * scale);
        touched += l.contacts > 0;
    }
    SimWallLoad l;
    TEST_ASSERT(sim_world_wall_load(w, 3, &l) == 0);
    printf("piston: offset %.4g m, F_y %.6g N (m g %.6g N), touched in %d of 60\n", l.offset, l.fy,
           20.0 * G0, touched);
    TEST_ASSERT(l.offset > 0.1 && touched >= 10);
    TEST_NEAR(l.length, 2.0, 1e-12); /* 20 grains from x = 0 to 2 m */
    TEST_ASSERT(sim_world_wall_load(w, 5, &l) == -1);
    sim_world_destroy(w);
    sim_grain_buffer_free(&p.grains);
    return 0;
}

/* Saved states of worlds a and b compared byte for byte. */
static int same_states(SimWorld *a, SimWorld *b)
{
    char pa[32], pb[32];
    SimError err;
    if (test_tmp_file(pa) != 0 || test_tmp_file(pb) != 0 || sim_world_save(a, pa, &err) != SIM_OK ||
        sim_world_save(b, pb, &err) != SIM_OK)
        return 0;
    FILE *f[2] = {fopen(pa, "rb"), fopen(pb, "rb")};
    int same = f[0] && f[1];
    while (same) {
        int x = fgetc(f[0]), y = fgetc(f[1]);
        same = x == y;
        if (x == EOF)
            break;
    }
    for (int k = 0; k < 2; ++k)
        if (f[k])
            fclose(f[k]);
    remove(pa);
    remove(pb);
    return same;
}

/* A turning piston on 1, 2, 3 and 8 threads and one saved and loaded half-way: the same bits. */
static int group_same_bits_threads_and_resume(void)
{
    SimWallBody body = free_piston;
    body.rotation = 1;
    Piston p[5];
    SimWorld *w[5];
    const int threads[4] = {1, 2, 3, 8};
    for (int k = 0; k < 4; ++k) {
        piston_def(&p[k], &body);
        w[k] = tu_create(&p[k].def, &p[k].grains);
        TEST_ASSERT(w[k]);
        sim_world_set_threads(w[k], threads[k]);
        TEST_ASSERT(tu_step(w[k], 5000) == 0);
    }
    char saved[32];
    SimError err;
    TEST_ASSERT(test_tmp_file(saved) == 0 && sim_world_save(w[0], saved, &err) == SIM_OK);
    piston_def(&p[4], &body);
    w[4] = sim_world_load(saved, &p[4].def, &err);
    TEST_ASSERT(w[4]);
    TEST_ASSERT(sim_world_restore_contacts(w[4], saved, &err) == SIM_OK);
    remove(saved);
    for (int k = 0; k < 5; ++k)
        TEST_ASSERT(tu_step(w[k], 3000) == 0);
    SimWallLoad l;
    sim_world_wall_load(w[0], 3, &l);
    printf("turning piston: offset %.4g m\n", l.offset);
    TEST_ASSERT(l.offset > 0.1);
    for (int k = 1; k < 5; ++k)
        TEST_ASSERT(same_states(w[0], w[k]));
    for (int k = 0; k < 5; ++k) {
        sim_world_destroy(w[k]);
        sim_grain_buffer_free(&p[k].grains);
    }
    return 0;
}

/* The angular momentum of the mobile grains about (1, 1), kg m^2/s. */
static double angular_momentum(SimWorld *w)
{
    SimFrame f;
    sim_world_frame(w, &f);
    double l = 0.0;
    for (int i = 0; i < f.mobile_count; ++i) {
        const double m = tu_mass(SIM_MASS_DISK, 1000.0, f.radius[i]);
        l += m * ((f.x[i] - 1.0) * f.vy[i] - (f.y[i] - 1.0) * f.vx[i]) +
             tu_inertia(SIM_MASS_DISK, 1000.0, f.radius[i]) * f.omega[i];
    }
    return l;
}

/* A body hinged at (1, 1) (no axis, turning), hit off-centre by one grain falling at 1 m/s
 * with no gravity: before and after the impact it turns freely (no contact: omega constant),
 * the impact turns it clockwise, and the grains' angular momentum about the hinge plus the
 * body's I omega stays the grain's initial m x v_y = -0.8 m (0.1 %). `group`: a row of fixed
 * grains at y = 1 (I from the mass), else a segment from (0, 1) to (2, 1) (I = m L^2 / 12). */
static int hinged_body_case(int group)
{
    SimWall plate = {.x0 = 0.0, .y0 = 1.0, .x1 = 2.0, .y1 = 1.0, .species = 0, .motion = -1};
    SimWallBody hinge = {.active = 1, .mass = 10.0, .rotation = 1};
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 1.8, 1.3, 0.05, 0, 0, -1);
    if (group)
        sim_build_fixed_row(&b, 0.05, 1.95, 1.0, 0.05, 0, SIM_GRAIN_BODY(0));
    SimWorldDef def = tu_def(1000.0, 1e5, 1e-4);
    def.gravity_y = 0.0;
    def.materials[0].friction = 0.0;
    if (group) {
        def.grain_bodies = &hinge;
        def.grain_body_count = 1;
    } else {
        def.wall_count = 1;
        def.walls = &plate;
        def.wall_bodies = &hinge;
    }
    SimWorld *w = tu_create(&def, &b);
    TEST_ASSERT(w);
    SimGrainSet v = {
        .count = 1, .vy = (double[]){-1.0}, .vx = (double[]){0.0}, .id = (uint32_t[]){0}};
    SimError err;
    TEST_ASSERT(sim_world_set_grains(w, &v, &err) == SIM_OK);
    /* I about the hinge: a rod m L^2 / 12, or the mass over 20 discs of radius 0.05 */
    double inertia = 10.0 * 4.0 / 12.0;
    if (group) {
        double spread = 0.0;
        for (int k = 0; k < 20; ++k)
            spread += (0.05 + 0.1 * k - 1.0) * (0.05 + 0.1 * k - 1.0) + 0.5 * 0.05 * 0.05;
        inertia = 10.0 * spread / 20.0;
    }
    const double m = tu_mass(SIM_MASS_DISK, 1000.0, 0.05), l0 = -0.8 * m;
    TEST_NEAR(angular_momentum(w), l0, 1e-12);
    TEST_ASSERT(tu_step(w, 5000) == 0); /* it falls 0.25 m, bounces and leaves */
    SimWallLoad c;
    SimFrame f;
    sim_world_frame(w, &f);
    /* the body's angular speed: from its grains (group) or a point of the plate */
    double wz;
    if (group) {
        wz = f.omega[f.mobile_count];
    } else {
        const double dx = f.walls[0].x1 - f.walls[0].x0, dy = f.walls[0].y1 - f.walls[0].y0;
        TEST_ASSERT(tu_step(w, 100) == 0);
        sim_world_frame(w, &f);
        const double dx2 = f.walls[0].x1 - f.walls[0].x0, dy2 = f.walls[0].y1 - f.walls[0].y0;
        wz = (atan2(dy2, dx2) - atan2(dy, dx)) / (100 * 1e-4);
    }
    TEST_ASSERT(sim_world_wall_load(w, 0, &c) == 0);
    TEST_ASSERT(c.contacts == 0 && c.offset == 0.0);
    const double l1 = angular_momentum(w) + inertia * wz;
    printf("%s: omega %.9g rad/s, L %.9g -> %.9g kg m^2/s\n",
           group ? "hinged group" : "hinged plate", wz, l0, l1);
    TEST_ASSERT(wz < -0.01);
    TEST_NEAR(l1, l0, 1e-3 * fabs(l0));
    sim_world_destroy(w);
    sim_grain_buffer_free(&b);
    return 0;
}

static int hinged_plate_conserves_angular_momentum(void)
{
    return hinged_body_case(0);
}

static int hinged_group_conserves_angular_momentum(void)
{
    return hinged_body_case(1);
}

/* The piston's row added to a world made without it: SIM_OK or the error. */
static SimStatus add_piston_row(SimWorld *w, SimError *err)
{
    SimGrainBuffer row;
    sim_grain_buffer_init(&row);
    sim_build_fixed_row(&row, 0.05, 1.95, 1.95, 0.05, 0, SIM_GRAIN_BODY(0));
    for (int k = 0; k < row.count; ++k)
        row.id[k] = 150u + (uint32_t)k; /* the ids the row has in piston_def */
    SimGrainSet set = sim_grain_buffer_view(&row);
    const SimStatus s = sim_world_add_grains(w, &set, err);
    sim_grain_buffer_free(&row);
    return s;
}

/* A grain body with no grains is dormant (it neither moves nor is checked) until its grains
 * join, all at once (sim_world_add_grains): the piston's row added after 2000 steps then falls
 * onto the pile, the same bits on 1 and 3 threads and across a save and load; grains added to
 * it once it moves are refused, naming the body, as is a grain naming a body that is not
 * there. */
static int empty_group_dormant_until_added(void)
{
    Piston p[3];
    SimWorld *w[3];
    SimError err;
    SimWallLoad l;
    for (int k = 0; k < 2; ++k) {
        piston_def(&p[k], &free_piston);
        p[k].grains.count -= 20; /* the row (20 grains, the last ones) is not there */
        w[k] = tu_create(&p[k].def, &p[k].grains);
        TEST_ASSERT(w[k]);
        sim_world_set_threads(w[k], 1 + 2 * k);
        TEST_ASSERT(tu_step(w[k], 2000) == 0);
        TEST_ASSERT(sim_world_wall_load(w[k], 3, &l) == 0 && l.offset == 0.0 && l.speed == 0.0);
        const SimStatus added = add_piston_row(w[k], &err);
        if (added != SIM_OK)
            printf("add: %s: %s\n", err.field, err.message);
        TEST_ASSERT(added == SIM_OK);
        TEST_ASSERT(tu_step(w[k], 3000) == 0);
    }
    sim_world_wall_load(w[0], 3, &l);
    printf("added piston: offset %.4g m, speed %.4g m/s, length %.4g m\n", l.offset, l.speed,
           l.length);
    TEST_ASSERT(l.offset > 0.1);
    TEST_NEAR(l.length, 2.0, 1e-12); /* its extent from the grains as they were put */
    TEST_ASSERT(add_piston_row(w[0], &err) == SIM_ERROR_INVALID);
    TEST_ASSERT(strcmp(err.field, "bodies[0]") == 0 && strstr(err.message, "dormant") != NULL);
    char saved[32];
    TEST_ASSERT(test_tmp_file(saved) == 0 && sim_world_save(w[0], saved, &err) == SIM_OK);
    piston_def(&p[2], &free_piston);
    w[2] = sim_world_load(saved, &p[2].def, &err);
    TEST_ASSERT(w[2]);
    remove(saved);
    for (int k = 0; k < 3; ++k)
        TEST_ASSERT(tu_step(w[k], 2000) == 0);
    for (int k = 1; k < 3; ++k)
        TEST_ASSERT(same_states(w[0], w[k]));
    p[0].grains.count += 20; /* the row back in the buffer, naming body 0 of none */
    p[0].def.grains = sim_grain_buffer_view(&p[0].grains);
    p[0].def.grain_body_count = 0;
    SimWorld *none = sim_world_create(&p[0].def, &err);
    TEST_ASSERT(!none && strstr(err.message, "grain body 0, not defined") != NULL);
    for (int k = 0; k < 3; ++k) {
        sim_world_destroy(w[k]);
        sim_grain_buffer_free(&p[k].grains);
    }
    return 0;
}

TEST_MAIN(TEST_CASE(group_load_is_contact_sum), TEST_CASE(group_same_bits_threads_and_resume),
          TEST_CASE(hinged_plate_conserves_angular_momentum),
          TEST_CASE(hinged_group_conserves_angular_momentum),
          TEST_CASE(empty_group_dormant_until_added))
