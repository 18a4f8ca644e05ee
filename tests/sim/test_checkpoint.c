/* SPDX-License-Identifier: MIT */
/* Checkpoints feed the next stage (sim.h: sim_state_load "used to start a stage from a previous
 * stage's checkpoint"): a settled bed rests on its walls with overlaps m g / k, and the next
 * stage must accept it and continue from exactly the same state. */
#include "sim_test_util.h"
#include "test.h"

#include <stdlib.h>
#include <unistd.h>

static SimWorldDef bed_def(void)
{
    SimWorldDef def = tu_def(1000.0, 1e5, 1e-4);
    def.gravity_y = -G0;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.3;
    return def;
}

/* Settle a few grains on a wall floor, save, load, build a new world from the loaded grains and
 * walls: the loaded state hashes identically (the hash follows stable ids, not storage order).
 * Then step both worlds: the restarted one recomputes its forces from the saved velocities (the
 * original used predicted ones) and sums them in its own order, so the runs agree to rounding,
 * not bit for bit. */
static int restart_from_settled_bed(void)
{
    static const SimWall walls[3] = {
        {.x0 = 0.0, .y0 = 0.0, .x1 = 1.0, .y1 = 0.0, .species = 0, .motion = -1},
        {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 1.0, .species = 0, .motion = -1},
        {.x0 = 1.0, .y0 = 0.0, .x1 = 1.0, .y1 = 1.0, .species = 0, .motion = -1}};
    SimWorldDef def = bed_def();
    def.wall_count = 3;
    def.walls = walls;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    for (int k = 0; k < 8; ++k)
        sim_grain_buffer_add(&b, 0.06 + 0.12 * k, 0.06 + 0.01 * (k % 3), 0.05, 0, 0u, -1);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 5000) == 0); /* 0.5 s: settled on the floor */
    SimEnergy en = sim_world_energy(w);
    TEST_ASSERT(en.contacts >= 8);
    char path[32];
    TEST_ASSERT(test_tmp_file(path) == 0);
    SimError err;
    TEST_ASSERT(sim_world_save(w, path, &err) == SIM_OK);
    SimGrainSet loaded;
    SimWall *loaded_walls = NULL;
    int loaded_wall_count = 0;
    double time = 0.0;
    SimStatus st = sim_state_load(path, &loaded, &loaded_walls, &loaded_wall_count, &time, &err);
    /* sim_world_load: the same grains, walls and time in one call; a missing file is an I/O
     * error, not a bad definition */
    SimWorldDef def_load = bed_def();
    SimWorld *w3 = sim_world_load(path, &def_load, &err);
    remove(path);
    TEST_ASSERT(w3 && sim_world_hash(w3) == sim_world_hash(w));
    TEST_NEAR(sim_world_time(w3), sim_world_time(w), 1e-12);
    sim_world_destroy(w3);
    TEST_ASSERT(!sim_world_load(path, &def_load, &err) && err.status == SIM_ERROR_IO);
    TEST_ASSERT(st == SIM_OK);
    TEST_ASSERT(loaded.count == 8 && loaded_wall_count == 3);
    TEST_NEAR(time, sim_world_time(w), 1e-12);
    SimWorldDef def2 = bed_def();
    def2.grains = loaded;
    def2.wall_count = loaded_wall_count;
    def2.walls = loaded_walls;
    def2.start_time = time;
    SimWorld *w2 = sim_world_create(&def2, &err);
    if (!w2) { /* clean up before failing, so that LeakSanitizer reports only the failure */
        fprintf(stderr, "restart refused: %s: %s\n", err.field, err.message);
        sim_world_destroy(w);
        sim_grain_set_free(&loaded);
        free(loaded_walls);
    }
    TEST_ASSERT(w2);
    TEST_ASSERT(sim_world_hash(w2) == sim_world_hash(w));
    TEST_ASSERT(tu_step(w, 1000) == 0);
    TEST_ASSERT(tu_step(w2, 1000) == 0);
    SimFrame f1, f2;
    sim_world_frame(w, &f1);
    sim_world_frame(w2, &f2);
    TEST_ASSERT(f1.count == f2.count);
    for (int a = 0; a < f1.count; ++a)
        for (int c = 0; c < f2.count; ++c)
            if (f1.id[a] == f2.id[c]) {
                TEST_NEAR(f2.x[c], f1.x[a], 1e-9);
                TEST_NEAR(f2.y[c], f1.y[a], 1e-9);
            }
    sim_world_destroy(w2);
    sim_world_destroy(w);
    sim_grain_set_free(&loaded);
    free(loaded_walls);
    return 0;
}

/* Grains held on a floor by stretched tangential springs (tilted gravity): a world rebuilt from
 * the checkpoint with sim_world_restore_contacts carries the same spring forces; without it they
 * restart from zero. */
static double floor_tangential(SimWorld *w, uint32_t id)
{
    SimFrame f;
    sim_world_frame(w, &f);
    for (int c = 0; c < f.contact_count; ++c)
        if (f.contacts[c].j < 0 && f.id[f.contacts[c].i] == id)
            return f.contacts[c].tangential_force;
    return NAN;
}

static int restore_contact_history(void)
{
    static const SimWall floor_ = {
        .x0 = -5.0, .y0 = 0.0, .x1 = 5.0, .y1 = 0.0, .species = 0, .motion = -1};
    SimWorldDef def = bed_def();
    def.effects = SIM_EFFECT_FRICTION;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.materials[0].friction = 0.5;
    def.materials[0].tangential_stiffness = 7.5e4;
    def.gravity_x = 2.0; /* tan = 0.2 < mu: the springs hold */
    def.wall_count = 1;
    def.walls = &floor_;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    for (int k = 0; k < 4; ++k)
        sim_grain_buffer_add(&b, 0.3 * k, 0.05, 0.05, 0, 0u, -1);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 5000) == 0);
    double held = floor_tangential(w, 1);
    TEST_ASSERT(fabs(held) > 1.0);
    char path[32];
    TEST_ASSERT(test_tmp_file(path) == 0);
    SimError err;
    TEST_ASSERT(sim_world_save(w, path, &err) == SIM_OK);
    SimGrainSet loaded;
    SimWall *walls = NULL;
    int wall_count = 0;
    double time = 0.0;
    TEST_ASSERT(sim_state_load(path, &loaded, &walls, &wall_count, &time, &err) == SIM_OK);
    SimWorldDef def2 = def;
    def2.grains = loaded;
    def2.start_time = time;
    SimWorld *fresh = sim_world_create(&def2, &err), *restored = sim_world_create(&def2, &err);
    TEST_ASSERT(fresh && restored);
    TEST_ASSERT(sim_world_restore_contacts(restored, path, &err) == SIM_OK);
    remove(path);
    TEST_NEAR(floor_tangential(restored, 1), held, 1e-9 * fabs(held));
    TEST_ASSERT(fabs(floor_tangential(fresh, 1)) < 1e-6 * fabs(held));
    sim_world_destroy(fresh);
    sim_world_destroy(restored);
    sim_world_destroy(w);
    sim_grain_set_free(&loaded);
    free(walls);
    return 0;
}

/* A saved state always loads: a deep pile of soft grains settles with overlaps above
 * the start-overlap bound max_initial_overlap (0.1 d), which is for new grains only. The engine's
 * own checkpoint of it reloads (sim_world_load), while the same grains given as a user grain list
 * are still refused; and the reloaded world continues to the bit like the run that was never
 * saved. Bit-identity needs the reload to see what the running world saw: the checkpoint is taken
 * right after a neighbour-list build (so the reload's build sorts and lists the grains as the
 * running world did), with a fixed skin, and with symplectic Euler, whose forces depend only on
 * the saved positions and velocities (velocity Verlet's damping sees a predicted velocity that a
 * checkpoint does not hold: restart_from_settled_bed above). */
static int deep_soft_pile_reloads(void)
{
    static const SimWall walls[3] = {
        {.x0 = 0.0, .y0 = 0.0, .x1 = 0.8, .y1 = 0.0, .species = 0, .motion = -1},
        {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 4.0, .species = 0, .motion = -1},
        {.x0 = 0.8, .y0 = 0.0, .x1 = 0.8, .y1 = 4.0, .species = 0, .motion = -1}};
    SimWorldDef def = tu_def(1000.0, 5e4, 0.0);
    def.time_step = 0.0; /* from steps_per_contact */
    def.gravity_y = -G0;
    def.integrator = SIM_INTEGRATOR_SYMPLECTIC_EULER;
    def.effects = SIM_EFFECT_FRICTION;
    def.contact.tangential = SIM_TANGENTIAL_REGULARISED;
    def.materials[0].friction = 0.3;
    def.materials[0].tangential_damping = 5.0;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.1;
    def.skin = 0.002; /* fixed (0.02 d): the list is rebuilt now and then as the pile creeps */
    def.wall_count = 3;
    def.walls = walls;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    for (int row = 0; row < 16; ++row) /* 120 grains in 16 staggered rows, radii 0.046-0.05 m */
        for (int c = 0; c < 8 - row % 2; ++c)
            sim_grain_buffer_add(&b, 0.05 + 0.05 * (row % 2) + 0.1 * c, 0.055 + 0.092 * row,
                                 0.05 - 0.001 * ((row + c) % 5), 0, 0u, -1);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 5000) == 0); /* 3.2 s: settled, still creeping */
    /* step on to just after a list build */
    const long builds = sim_world_list_builds(w);
    for (long s = 0; s < 20000 && sim_world_list_builds(w) == builds; ++s)
        TEST_ASSERT(tu_step(w, 1) == 0);
    TEST_ASSERT(sim_world_list_builds(w) > builds);
    SimFrame f;
    sim_world_frame(w, &f);
    double worst = 0.0;
    for (int c = 0; c < f.contact_count; ++c) {
        const SimContact *k = &f.contacts[c];
        double d = 2.0 * f.radius[k->i];
        if (k->j >= 0 && 2.0 * f.radius[k->j] < d)
            d = 2.0 * f.radius[k->j];
        worst = fmax(worst, k->overlap / d);
    }
    fprintf(stderr, "deep soft pile: worst overlap %.3f d (bound %g)\n", worst,
            def.max_initial_overlap);
    TEST_ASSERT(worst > 1.5 * def.max_initial_overlap);
    TEST_ASSERT(worst < def.guard_max_overlap);

    char path[32];
    TEST_ASSERT(test_tmp_file(path) == 0);
    SimError err;
    TEST_ASSERT(sim_world_save(w, path, &err) == SIM_OK);
    SimWorldDef def_load = def;
    def_load.wall_count = 0; /* the walls come from the state */
    def_load.walls = NULL;
    SimWorld *r = sim_world_load(path, &def_load, &err);
    if (!r)
        fprintf(stderr, "reload refused: %s: %s\n", err.field, err.message);
    /* the same grains as a user grain list: still under the bound */
    SimGrainSet loaded;
    SimWall *loaded_walls = NULL;
    int loaded_wall_count = 0;
    double time = 0.0;
    TEST_ASSERT(sim_state_load(path, &loaded, &loaded_walls, &loaded_wall_count, &time, &err) ==
                SIM_OK);
    remove(path);
    SimWorldDef def_user = def;
    def_user.grains = loaded;
    def_user.walls = loaded_walls;
    def_user.wall_count = loaded_wall_count;
    SimWorld *u = sim_world_create(&def_user, &err);
    const int refused = !u && err.status == SIM_ERROR_INVALID && strstr(err.message, "at start");
    if (!refused)
        fprintf(stderr, "user grain list: %s\n", u ? "accepted" : err.message);
    sim_world_destroy(u);
    sim_grain_set_free(&loaded);
    free(loaded_walls);
    TEST_ASSERT(r);
    TEST_ASSERT(refused);
    TEST_ASSERT(sim_world_hash(r) == sim_world_hash(w));
    const long reload_builds = sim_world_list_builds(r);
    for (int round = 0; round < 4; ++round) { /* 4 x 500 steps */
        TEST_ASSERT(tu_step(w, 500) == 0);
        TEST_ASSERT(tu_step(r, 500) == 0);
        TEST_ASSERT(sim_world_hash(r) == sim_world_hash(w));
    }
    fprintf(stderr, "deep soft pile: %ld list builds after the reload\n",
            sim_world_list_builds(r) - reload_builds);
    TEST_ASSERT(sim_world_list_builds(r) > reload_builds); /* the continuation re-sorted too */
    sim_world_destroy(r);
    sim_world_destroy(w);
    return 0;
}

/* Rewrites `size` bytes at `offset` of a file. 0, or -1. */
static int patch_file(const char *path, long offset, const void *bytes, size_t size)
{
    FILE *f = fopen(path, "r+b");
    if (!f)
        return -1;
    int ok = fseek(f, offset, SEEK_SET) == 0 && fwrite(bytes, 1, size, f) == size;
    return fclose(f) == 0 && ok ? 0 : -1;
}

/* A state whose time is not finite, or whose header announces more grains or contact records
 * than the file holds, is refused before anything is allocated for them; one holding a grain no
 * world would save (NaN position, radius <= 0: `sablier render` drew it) is refused too. */
static int bad_states_refused(void)
{
    SimWorldDef def = bed_def();
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.5, 0.5, 0.05, 0, 0u, -1);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    char path[32];
    TEST_ASSERT(test_tmp_file(path) == 0);
    SimError err;
    SimGrainSet g;
    SimWall *walls = NULL;
    int wall_count = 0;
    double time = 0.0;
    const double nan = NAN;
    const int32_t huge = 2000000000;
    const double negative = -0.05;
    const long header = 48 + 8 * SIM_MAX_SINKS; /* magic, 4 counts, time, step, sink counters */

    /* header: magic[16], count, mobile_count, wall_count, wall_size (int32), time (double) */
    const struct {
        long offset;
        const void *bytes;
        size_t size;
        const char *message;
    } cases[] = {{32, &nan, sizeof nan, "time not finite"},
                 {16, &huge, sizeof huge, "shorter than its header says"},
                 /* the one grain's x (first array after the header), then its radius (7th) */
                 {header, &nan, sizeof nan, "non-finite position"},
                 {header + 6 * 8, &negative, sizeof negative, "not a positive finite number"}};

    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        TEST_ASSERT(sim_world_save(w, path, &err) == SIM_OK);
        TEST_ASSERT(patch_file(path, cases[k].offset, cases[k].bytes, cases[k].size) == 0);
        TEST_ASSERT(sim_state_load(path, &g, &walls, &wall_count, &time, &err) != SIM_OK);
        TEST_ASSERT(strstr(err.message, cases[k].message));
    }
    /* a negative wall record size must not cancel the bytes a huge grain count needs (fuzz
     * finding: 201 million grains announced in 280 bytes, 1.6 GB allocated) */
    const int32_t many_walls = 52, negative_size = -536870912;
    TEST_ASSERT(sim_world_save(w, path, &err) == SIM_OK);
    TEST_ASSERT(patch_file(path, 16, &huge, sizeof huge) == 0);
    TEST_ASSERT(patch_file(path, 24, &many_walls, sizeof many_walls) == 0);
    TEST_ASSERT(patch_file(path, 28, &negative_size, sizeof negative_size) == 0);
    TEST_ASSERT(sim_state_load(path, &g, &walls, &wall_count, &time, &err) != SIM_OK);
    TEST_ASSERT(strstr(err.message, "bad header"));
    TEST_ASSERT(sim_world_restore_contacts(w, path, &err) != SIM_OK);
    /* the contact-history count beyond the file: refused, not allocated */
    TEST_ASSERT(sim_world_save(w, path, &err) == SIM_OK);
    FILE *f = fopen(path, "rb");
    TEST_ASSERT(f);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fclose(f);
    const int32_t counts[2] = {huge, 0};
    /* after the header (176 bytes) and one mobile grain (72 bytes), no walls */
    long at = 176 + 72;
    TEST_ASSERT(size > at + (long)sizeof counts);
    TEST_ASSERT(patch_file(path, at, counts, sizeof counts) == 0);
    TEST_ASSERT(sim_world_restore_contacts(w, path, &err) != SIM_OK);
    unlink(path);
    sim_world_destroy(w);
    return 0;
}

TEST_MAIN(TEST_CASE(restart_from_settled_bed), TEST_CASE(restore_contact_history),
          TEST_CASE(deep_soft_pile_reloads), TEST_CASE(bad_states_refused))
