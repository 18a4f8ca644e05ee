/* SPDX-License-Identifier: MIT */
/* Exact resume (docs/state-format.md version 2): a world loaded from a state
 * continues bit for bit as the saved world does. A pile rains onto a floor between walls (the
 * lists rebuild, the automatic skin moves, contacts gain history); saved mid-fall, the saved
 * world and the loaded one step on, and their checkpoints then are the same bytes. */
#include "sim_test_util.h"
#include "test.h"

#include <stdlib.h>

static const SimWall box_walls[3] = {
    {.x0 = 0.0, .y0 = 0.0, .x1 = 2.0, .y1 = 0.0, .species = 0, .motion = -1},
    {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 2.0, .species = 0, .motion = -1},
    {.x0 = 2.0, .y0 = 0.0, .x1 = 2.0, .y1 = 2.0, .species = 0, .motion = -1}};

static SimWorldDef pile_def(SimIntegrator integrator, int periodic)
{
    SimWorldDef def = tu_def(1000.0, 1e5, 1e-4);
    def.gravity_y = -G0;
    def.gravity_x = 2.0; /* the pile shears: tangential springs stretch */
    def.integrator = integrator;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.3;
    def.effects |= SIM_EFFECT_FRICTION | SIM_EFFECT_ROLLING;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.contact.rolling = SIM_ROLLING_FIXED;
    def.materials[0].friction = 0.5;
    def.materials[0].tangential_stiffness = 7.5e4;
    def.materials[0].rolling_friction = 0.05;
    def.materials[0].rolling_stiffness = 5.0;
    def.walls = box_walls;
    def.wall_count = periodic ? 1 : 3;
    if (periodic) {
        def.effects |= SIM_EFFECT_PERIODIC_X;
        def.domain_x0 = 0.0;
        def.domain_x1 = 2.0;
    }
    return def;
}

static int file_bytes(const char *path, unsigned char **data, long *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    fseek(f, 0, SEEK_END);
    *size = ftell(f);
    fseek(f, 0, SEEK_SET);
    *data = malloc((size_t)*size + 1);
    int ok = *data && fread(*data, 1, (size_t)*size, f) == (size_t)*size;
    fclose(f);
    return ok ? 0 : -1;
}

/* 1 when the two files hold the same bytes. */
static int same_files(const char *a, const char *b)
{
    unsigned char *da = NULL, *db = NULL;
    long na = 0, nb = 0;
    int same = file_bytes(a, &da, &na) == 0 && file_bytes(b, &db, &nb) == 0 && na == nb &&
               memcmp(da, db, (size_t)na) == 0;
    free(da);
    free(db);
    return same;
}

/* Writes the first `size` bytes of `data` as the file. 0, or -1. */
static int rewrite(const char *path, const unsigned char *data, long size)
{
    FILE *f = fopen(path, "wb");
    int ok = f && fwrite(data, 1, (size_t)size, f) == (size_t)size;
    return f && fclose(f) == 0 && ok ? 0 : -1;
}

/* The pile (velocity Verlet, walls) after `steps` steps, saved to a new temporary file `saved`;
 * NULL on failure. */
static SimWorld *pile_saved(long steps, char saved[32])
{
    SimWorldDef def = pile_def(SIM_INTEGRATOR_VELOCITY_VERLET, 0);
    SimGrainBuffer b;
    tu_rain_150(&b, 7, 0.06);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    SimError err;
    if (w && (tu_step(w, steps) != 0 || test_tmp_file(saved) != 0 ||
              sim_world_save(w, saved, &err) != SIM_OK)) {
        sim_world_destroy(w);
        w = NULL;
    }
    return w;
}

static int resume_case(SimIntegrator integrator, int periodic)
{
    SimWorldDef def = pile_def(integrator, periodic);
    SimGrainBuffer b;
    tu_rain_150(&b, 7, 0.06);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 12000) == 0); /* falling and landing: rebuilds, history */
    TEST_ASSERT(sim_world_energy(w).contacts > 50);
    char saved[32], a[32], c[32];
    TEST_ASSERT(test_tmp_file(saved) == 0 && test_tmp_file(a) == 0 && test_tmp_file(c) == 0);
    SimError err;
    TEST_ASSERT(sim_world_save(w, saved, &err) == SIM_OK);
    SimWorldDef def_load = pile_def(integrator, periodic);
    SimWorld *r = sim_world_load(saved, &def_load, &err);
    TEST_ASSERT(r);
    TEST_ASSERT(sim_world_restore_contacts(r, saved, &err) == SIM_OK);
    sim_world_set_threads(r, 2); /* same bits for any thread count */
    TEST_ASSERT(sim_world_step_count(r) == sim_world_step_count(w));
    TEST_ASSERT(tu_step(w, 1500) == 0 && tu_step(r, 1500) == 0);
    TEST_ASSERT(sim_world_time(r) == sim_world_time(w));
    TEST_ASSERT(sim_world_save(w, a, &err) == SIM_OK && sim_world_save(r, c, &err) == SIM_OK);
    int same = same_files(a, c);
    remove(saved);
    remove(a);
    remove(c);
    sim_world_destroy(w);
    sim_world_destroy(r);
    TEST_ASSERT(same);
    return 0;
}

static int resume_exact_velocity_verlet(void)
{
    return resume_case(SIM_INTEGRATOR_VELOCITY_VERLET, 0);
}

static int resume_exact_gear_periodic(void)
{
    return resume_case(SIM_INTEGRATOR_GEAR, 1);
}

/* A state loaded by a world with another time step starts afresh from its grains (the
 * continuation section does not fit), at the saved time. */
static int resume_other_time_step_starts_afresh(void)
{
    char saved[32];
    SimError err;
    SimWorld *w = pile_saved(500, saved);
    TEST_ASSERT(w);
    SimWorldDef def_load = pile_def(SIM_INTEGRATOR_VELOCITY_VERLET, 0);
    def_load.time_step = 5e-5;
    SimWorld *r = sim_world_load(saved, &def_load, &err);
    TEST_ASSERT(r && sim_world_restore_contacts(r, saved, &err) == SIM_OK);
    remove(saved);
    TEST_ASSERT(sim_world_time(r) == sim_world_time(w) && sim_world_step_count(r) == 0);
    TEST_ASSERT(sim_world_hash(r) == sim_world_hash(w));
    sim_world_destroy(r);
    sim_world_destroy(w);
    return 0;
}

/* A version-1 file (no continuation section) still loads, afresh from its grains. */
static int resume_version_1_still_loads(void)
{
    char saved[32];
    SimError err;
    SimWorld *w = pile_saved(12000, saved);
    TEST_ASSERT(w);
    unsigned char *data = NULL;
    long size = 0;
    TEST_ASSERT(file_bytes(saved, &data, &size) == 0);
    /* the version-1 layout: the same sections up to the contact history */
    int32_t header[3];
    memcpy(header, data + 16, sizeof header);
    long n = header[0], m = header[1], walls = header[2];
    long at = 176 + n * 72 + (n - m) * 16 + walls * 40;
    int32_t counts[2];
    memcpy(counts, data + at, sizeof counts);
    TEST_ASSERT(counts[0] > 0);
    long v1_size = at + 8 + 24L * ((long)counts[0] + counts[1]);
    TEST_ASSERT(v1_size < size);
    data[14] = '1';
    TEST_ASSERT(rewrite(saved, data, v1_size) == 0);
    free(data);
    SimWorldDef def_load = pile_def(SIM_INTEGRATOR_VELOCITY_VERLET, 0);
    SimWorld *r = sim_world_load(saved, &def_load, &err);
    TEST_ASSERT(r && sim_world_restore_contacts(r, saved, &err) == SIM_OK);
    remove(saved);
    TEST_ASSERT(sim_world_hash(r) == sim_world_hash(w) && sim_world_step_count(r) == 0);
    TEST_ASSERT(tu_step(r, 100) == 0);
    sim_world_destroy(r);
    sim_world_destroy(w);
    return 0;
}

/* A version-2 file cut inside its continuation section is refused as truncated. */
static int resume_truncated_section_refused(void)
{
    char saved[32];
    SimError err;
    SimWorld *w = pile_saved(3000, saved);
    TEST_ASSERT(w);
    unsigned char *data = NULL;
    long size = 0;
    TEST_ASSERT(file_bytes(saved, &data, &size) == 0);
    TEST_ASSERT(rewrite(saved, data, size - 100) == 0);
    free(data);
    SimWorldDef def_load = pile_def(SIM_INTEGRATOR_VELOCITY_VERLET, 0);
    SimWorld *r = sim_world_load(saved, &def_load, &err);
    remove(saved);
    sim_world_destroy(w);
    TEST_ASSERT(!r && err.status == SIM_ERROR_IO && strstr(err.message, "truncated"));
    return 0;
}

TEST_MAIN(TEST_CASE(resume_truncated_section_refused), TEST_CASE(resume_version_1_still_loads),
          TEST_CASE(resume_exact_velocity_verlet), TEST_CASE(resume_exact_gear_periodic),
          TEST_CASE(resume_other_time_step_starts_afresh))
