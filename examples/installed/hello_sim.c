/* SPDX-License-Identifier: MIT */
/* hello_sim (installed): a program outside the tree on the installed libsablier-sim
 * (docs/install.md). Rains 300 grains (seed 1) into a box of fixed grains with the thesis 000
 * parameters, runs 50000 steps of 1e-5 s with friction, and prints the state hash and the
 * energies to the last bit, so that the C and C++ clients (hello_sim.cpp), the pkg-config and
 * the CMake builds, and other bindings can be checked to agree bit for bit.
 * Build: cc -std=c17 hello_sim.c $(pkg-config --cflags --libs sablier-sim) -o hello_sim */
#include <inttypes.h>
#include <sim/sim.h>
#include <stdio.h>

int main(void)
{
    const double r_max = 0.105, width = 20 * 2 * r_max;
    const long steps = 50000; /* 0.5 s: the grains land and touch */
    SimGrainBuffer buffer;
    sim_grain_buffer_init(&buffer);
    sim_build_fixed_box(&buffer, 0.0, width, 0.0, 60 * r_max, r_max, 0);
    SimRainDef rain =
        sim_rain_def_thesis000(1.5 * r_max, width - 1.5 * r_max, 1.5 * r_max, 200 * r_max, 300);
    SimRng rng;
    sim_rng_seed(&rng, 1);
    sim_build_rain(&buffer, &rain, &rng);

    SimWorldDef def = sim_world_def_default();
    def.effects = SIM_EFFECT_FRICTION;
    def.mass_model = SIM_MASS_SPHERE;
    def.time_step = 1e-5;
    def.grains = sim_grain_buffer_view(&buffer);
    SimError err;
    SimWorld *world = sim_world_create(&def, &err);
    sim_grain_buffer_free(&buffer);
    if (!world) {
        fprintf(stderr, "hello_sim: %s: %s\n", err.field, err.message);
        return 2;
    }
    if (sim_world_step(world, steps, &err) != SIM_OK) {
        fprintf(stderr, "hello_sim: %s\n", err.message);
        sim_world_destroy(world);
        return 1;
    }
    SimEnergy e = sim_world_energy(world);
    printf("sablier %s: %d grains, step %ld, t %.17g s\n", SIM_VERSION,
           sim_world_mobile_count(world), steps, sim_world_time(world));
    printf("hash 0x%016" PRIx64 "\n", sim_world_hash(world));
    printf("energy kinetic %.17g potential %.17g rotational %.17g elastic %.17g J, %d contacts\n",
           e.kinetic, e.potential, e.rotational, e.elastic, e.contacts);
    sim_world_destroy(world);
    return 0;
}
