/* SPDX-License-Identifier: MIT */
/* test_grains_file.c: `grains.file` (app/grains_file.c): a CSV written from a world with %.17g in
 * the `sablier export --format csv` layout reads back the same positions bit for bit; a LAMMPS
 * dump's columns are found by name; a bad row names the file and line. */
#include "grains_file.h"
#include "scene.h"
#include "test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A settled-looking set: 40 grains with irrational coordinates and velocities. */
static void make_grains(SimGrainBuffer *b)
{
    SimRng rng;
    sim_rng_seed(&rng, 11);
    sim_grain_buffer_init(b);
    for (int k = 0; k < 40; ++k) {
        int i = sim_grain_buffer_add(
            b, 0.3 + 0.5 * k + 0.1 * sim_rng_uniform(&rng), 0.2 + sim_rng_uniform(&rng) / 3.0,
            0.1 + 0.01 * sim_rng_uniform(&rng), k % 2, k % 7 == 0 ? SIM_GRAIN_FIXED : 0u, -1);
        b->vx[i] = sim_rng_uniform(&rng) - 0.5;
        b->vy[i] = sim_rng_uniform(&rng) / 7.0;
        b->omega[i] = sim_rng_uniform(&rng) * 3.0;
        b->angle[i] = sim_rng_uniform(&rng) * SIM_PI;
    }
}

static int grains_csv_round_trip(void)
{
    SimGrainBuffer b;
    make_grains(&b);
    char path[64];
    snprintf(path, sizeof path, "/tmp/sablier_test_grains_%ld.csv", (long)getpid());
    FILE *f = fopen(path, "w");
    TEST_ASSERT(f);
    fprintf(f, "id,x,y,r,species,fixed,vx,vy,omega,angle\n");
    for (int i = 0; i < b.count; ++i)
        fprintf(f, "%u,%.17g,%.17g,%.17g,%d,%d,%.17g,%.17g,%.17g,%.17g\n", b.id[i], b.x[i], b.y[i],
                b.radius[i], b.species[i], (b.flags[i] & SIM_GRAIN_FIXED) ? 1 : 0, b.vx[i], b.vy[i],
                b.omega[i], b.angle[i]);
    fclose(f);
    SimGrainBuffer r;
    sim_grain_buffer_init(&r);
    char err[512];
    int has_ids = 0;
    TEST_ASSERT(app_grains_read(path, 2, &r, &has_ids, err, sizeof err) == 0);
    remove(path);
    TEST_ASSERT(has_ids && r.count == b.count);
    size_t n = (size_t)b.count * sizeof(double);
    TEST_ASSERT(memcmp(r.x, b.x, n) == 0 && memcmp(r.y, b.y, n) == 0);
    TEST_ASSERT(memcmp(r.radius, b.radius, n) == 0 && memcmp(r.vx, b.vx, n) == 0);
    TEST_ASSERT(memcmp(r.vy, b.vy, n) == 0 && memcmp(r.omega, b.omega, n) == 0);
    TEST_ASSERT(memcmp(r.angle, b.angle, n) == 0);
    TEST_ASSERT(memcmp(r.species, b.species, (size_t)b.count * sizeof(int)) == 0);
    TEST_ASSERT(memcmp(r.flags, b.flags, (size_t)b.count * sizeof(unsigned)) == 0);
    TEST_ASSERT(memcmp(r.id, b.id, (size_t)b.count * sizeof(uint32_t)) == 0);
    sim_grain_buffer_free(&b);
    sim_grain_buffer_free(&r);
    return 0;
}

/* Columns in another order and a LAMMPS dump (type 2 = species 1); a bad number names line 3. */
static int grains_file_formats_and_errors(void)
{
    char path[64], err[512];
    snprintf(path, sizeof path, "/tmp/sablier_test_grains_%ld.dump", (long)getpid());
    FILE *f = fopen(path, "w");
    TEST_ASSERT(f);
    fprintf(f, "ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 2\n0 2\n"
               "-1 1\nITEM: ATOMS id type x y z vx vy vz omegaz radius\n"
               "7 2 0.5 0.25 0 1.5 0 0 2.0 0.1\n8 1 1.0 0.5 0 0 0 0 0 0.2\n");
    fclose(f);
    SimGrainBuffer r;
    sim_grain_buffer_init(&r);
    int has_ids = 0;
    TEST_ASSERT(app_grains_read(path, 2, &r, &has_ids, err, sizeof err) == 0);
    TEST_ASSERT(r.count == 2 && r.species[0] == 1 && r.species[1] == 0 && r.id[0] == 7);
    TEST_ASSERT(r.vx[0] == 1.5 && r.omega[0] == 2.0 && r.radius[1] == 0.2 && r.y[0] == 0.25);
    sim_grain_buffer_free(&r);
    f = fopen(path, "w");
    TEST_ASSERT(f);
    fprintf(f, "r,y,x\n0.1,0.5,0.5\n0.1,zero,1.0\n");
    fclose(f);
    sim_grain_buffer_init(&r);
    TEST_ASSERT(app_grains_read(path, 1, &r, &has_ids, err, sizeof err) != 0);
    remove(path);
    sim_grain_buffer_free(&r);
    char expect[96];
    snprintf(expect, sizeof expect, "%s:3: ", path);
    TEST_ASSERT(strncmp(err, expect, strlen(expect)) == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(grains_csv_round_trip), TEST_CASE(grains_file_formats_and_errors))
