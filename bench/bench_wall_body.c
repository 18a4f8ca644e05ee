/* SPDX-License-Identifier: MIT */
/* bench_wall_body: what a responding wall costs per step (sim.h SimWallBody, sim/wall_body.c).
 *
 * A box 4 m wide of about N grains (radius 0.05 m +- 8 %, rained and settled under gravity,
 * damped linear contacts k_n = 1e6 N/m, dt = 1e-4 s) with a lid over it, run three ways from the
 * same settled grains: the lid still (the reference: the wall pass already sums every wall's load),
 * the lid a servo holding 2000 N/m, the lid a free piston of 200 kg. Each variant steps M steps,
 * timed round-robin, best of K repeats, wall time; the servo's cost is its extra time per step over
 * the still lid (noise: the still lid timed twice).
 *
 * A benchmark reports; it asserts nothing about time.
 *
 * Usage: bench_wall_body [--grains N] [--steps M] [--repeats K] */
#include "sim/sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { STILL, STILL_AGAIN, SERVO, PISTON, VARIANTS };

static const char *const names[VARIANTS] = {"still lid", "still lid (again)", "servo lid",
                                            "piston lid"};

typedef struct Bench {
    SimWall walls[4];
    SimWallBody bodies[4];
    SimGrainBuffer grains;
    SimWorldDef def;
} Bench;

static void bench_def(Bench *b, int grains)
{
    const double width = 4.0;
    const SimWall walls[4] = {
        {.x0 = 0.0, .y0 = 0.0, .x1 = width, .y1 = 0.0, .species = 0, .motion = -1},
        {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 40.0, .species = 0, .motion = -1},
        {.x0 = width, .y0 = 0.0, .x1 = width, .y1 = 40.0, .species = 0, .motion = -1},
        {.x0 = 0.0, .y0 = 4.8, .x1 = width, .y1 = 4.8, .species = 0, .motion = -1}};
    memcpy(b->walls, walls, sizeof walls);
    memset(b->bodies, 0, sizeof b->bodies);
    SimRainDef rd;
    memset(&rd, 0, sizeof rd);
    rd.x0 = 0.1;
    rd.x1 = width - 0.1;
    rd.y0 = 0.06;
    rd.y1 = 4.5;
    rd.radius_mean = 0.05;
    rd.polydispersity = 0.08;
    rd.pitch_radius = 0.054;
    rd.column_gap = 0.005 * rd.pitch_radius;
    rd.row_gap = 0.75 * rd.pitch_radius;
    rd.column_jitter = 0.05;
    rd.row_jitter = 0.08;
    rd.max_count = grains;
    SimRng rng;
    sim_rng_seed(&rng, 7);
    sim_grain_buffer_init(&b->grains);
    sim_build_rain(&b->grains, &rd, &rng);
    b->def = sim_world_def_default();
    b->def.species_count = 1;
    b->def.materials[0] = sim_material_default();
    b->def.materials[0].density = 1000.0;
    b->def.materials[0].normal_stiffness = 1e6;
    b->def.materials[0].damping_mode = SIM_DAMPING_GAMMA;
    b->def.materials[0].normal_damping = 600.0;
    b->def.materials[0].friction = 0.0;
    b->def.contact.tangential = SIM_TANGENTIAL_NONE;
    b->def.time_step = 1e-4;
    b->def.max_dt_fraction = 0.0;
    b->def.gravity_y = -9.806;
    b->def.wall_count = 4;
    b->def.walls = b->walls;
    b->def.grains = sim_grain_buffer_view(&b->grains);
}

/* The world of variant v from the settled state at `state`. */
static SimWorld *variant_world(Bench *b, int v, const char *state)
{
    SimWallBody *lid = &b->bodies[3];
    memset(lid, 0, sizeof *lid);
    if (v == SERVO)
        *lid = (SimWallBody){.active = 1,
                             .axis_y = -1.0,
                             .servo = 1,
                             .target = 2000.0,
                             .gain = 1e-4,
                             .max_speed = 0.5};
    else if (v == PISTON)
        *lid = (SimWallBody){.active = 1, .axis_y = -1.0, .mass = 200.0, .gravity = 1};
    b->def.wall_bodies = v == SERVO || v == PISTON ? b->bodies : NULL;
    SimError err;
    SimWorld *w = sim_world_load(state, &b->def, &err);
    if (!w)
        fprintf(stderr, "bench_wall_body: %s: %s\n", err.field, err.message);
    return w;
}

int main(int argc, char **argv)
{
    int grains = 1000, repeats = 3;
    long steps = 5000;
    for (int a = 1; a + 1 < argc; a += 2) {
        if (strcmp(argv[a], "--grains") == 0)
            grains = atoi(argv[a + 1]);
        else if (strcmp(argv[a], "--steps") == 0)
            steps = atol(argv[a + 1]);
        else if (strcmp(argv[a], "--repeats") == 0)
            repeats = atoi(argv[a + 1]);
    }
    Bench b;
    bench_def(&b, grains);
    SimError err;
    SimWorld *settle = sim_world_create(&b.def, &err);
    if (!settle || sim_world_step(settle, 30000, &err) != SIM_OK) {
        fprintf(stderr, "bench_wall_body: settling: %s\n", err.message);
        return 1;
    }
    char state[] = "/tmp/sablier-bench-wall-body-XXXXXX";
    int fd = mkstemp(state);
    if (fd >= 0)
        close(fd);
    if (fd < 0 || sim_world_save(settle, state, &err) != SIM_OK) {
        fprintf(stderr, "bench_wall_body: cannot save the settled pile\n");
        return 1;
    }
    sim_world_destroy(settle);
    double best[VARIANTS];
    for (int v = 0; v < VARIANTS; ++v)
        best[v] = INFINITY;
    for (int r = 0; r < repeats; ++r)
        for (int v = 0; v < VARIANTS; ++v) {
            SimWorld *w = variant_world(&b, v, state);
            if (!w)
                return 1;
            double t0 = sim_clock_seconds(SIM_CLOCK_WALL);
            if (sim_world_step(w, steps, &err) != SIM_OK) {
                fprintf(stderr, "bench_wall_body: %s: %s\n", names[v], err.message);
                return 1;
            }
            best[v] = fmin(best[v], sim_clock_seconds(SIM_CLOCK_WALL) - t0);
            sim_world_destroy(w);
        }
    remove(state);
    printf("bench_wall_body: %d grains, %ld steps, best of %d\n", b.grains.count, steps, repeats);
    for (int v = 0; v < VARIANTS; ++v)
        printf("  %-18s %8.3f us/step  (%+.3f us/step over the still lid)\n", names[v],
               1e6 * best[v] / (double)steps, 1e6 * (best[v] - best[STILL]) / (double)steps);
    sim_grain_buffer_free(&b.grains);
    return 0;
}
