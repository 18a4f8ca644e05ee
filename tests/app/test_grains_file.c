/* SPDX-License-Identifier: MIT */
/* test_grains_file.c: `grains.file` (app/scene/grains_file.c): a CSV written from a world with
 * %.17g in the `sablier export --format csv` layout reads back the same positions bit for bit; a
 * LAMMPS dump's columns are found by name; a bad row names the file and line; a column given twice,
 * `fixed` not 0/1, ids out of range or repeated and a wrong atom count are refused. */
#include "test.h"

#include "scene/grains_file.h"
#include "scene/scene.h"

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

/* Files refused at their line: a column given twice, `fixed` other than 0/1, an id
 * beyond 2^31 - 1 (99999999999 was wrapped to 1215752191), an id given twice, and a LAMMPS dump
 * whose atom count is not a count or is smaller than its rows (was "no mobile grains"). */
static int grains_file_refused(void)
{
    static const char dump_head[] = "ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n";
    static const char dump_atoms[] = "ITEM: BOX BOUNDS pp pp pp\n0 2\n0 2\n-1 1\n"
                                     "ITEM: ATOMS id type x y radius\n"
                                     "1 1 0.5 0.5 0.1\n2 1 1.0 0.5 0.1\n";

    static const struct {
        const char *head, *body;
        int line;
        const char *says;
    } cases[] = {
        {"", "x,y,r,x\n0.5,0.5,0.1,0.5\n", 1, "a column given twice: x"},
        {"", "x,y,r,fixed\n0.5,0.5,0.1,1\n1.5,0.5,0.1,2\n", 3, "`fixed` must be 0 or 1, got 2"},
        {"", "id,x,y,r\n99999999999,0.5,0.5,0.1\n", 2, "ids must be integers in [0, 2^31 - 1]"},
        {"", "id,x,y,r\n3,0.5,0.5,0.1\n4,1.5,0.5,0.1\n3,2.5,0.5,0.1\n", 4,
         "an id given twice (every grain's id must differ): 3"},
        {dump_head, "many\n", 4, "NUMBER OF ATOMS must be a count in [1, 1e9], got `many`"},
        {dump_head, "0\n", 4, "NUMBER OF ATOMS must be a count in [1, 1e9], got `0`"},
        {dump_head, "1\n", 11, "more atom rows than NUMBER OF ATOMS says"},
    };

    char path[64], err[512], expect[256];
    snprintf(path, sizeof path, "/tmp/sablier_test_grains_bad_%ld.csv", (long)getpid());
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        FILE *f = fopen(path, "w");
        TEST_ASSERT(f);
        fprintf(f, "%s%s%s", cases[k].head, cases[k].body, cases[k].head[0] ? dump_atoms : "");
        fclose(f);
        SimGrainBuffer r;
        sim_grain_buffer_init(&r);
        int has_ids = 0;
        err[0] = '\0';
        int rc = app_grains_read(path, 1, &r, &has_ids, err, sizeof err);
        sim_grain_buffer_free(&r);
        snprintf(expect, sizeof expect, "%s:%d: %s", path, cases[k].line, cases[k].says);
        if (rc == 0 || strncmp(err, expect, strlen(expect)) != 0)
            fprintf(stderr, "case %zu: got `%s`, expected `%s...`\n", k, err, expect);
        TEST_ASSERT(rc != 0 && strncmp(err, expect, strlen(expect)) == 0);
    }
    remove(path);
    return 0;
}

TEST_MAIN(TEST_CASE(grains_csv_round_trip), TEST_CASE(grains_file_formats_and_errors),
          TEST_CASE(grains_file_refused))
