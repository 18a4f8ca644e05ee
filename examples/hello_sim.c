/* SPDX-License-Identifier: MIT */
/* hello_sim: the physics library on its own. Rains grains into a box of fixed grains with the
 * thesis 000 parameters, lets them settle, and prints energies as CSV. No rendering linked.
 * Usage: example_hello_sim [grains (default 500)] [seconds (default 1.0)] */
#include "sim/sim.h"

#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
    int grains = argc > 1 ? atoi(argv[1]) : 500;
    double seconds = argc > 2 ? atof(argv[2]) : 1.0;
    const double r_max = 0.105, width = 20 * 2 * r_max;

    SimGrainBuffer buffer;
    sim_grain_buffer_init(&buffer);
    sim_build_fixed_box(&buffer, 0.0, width, 0.0, 60 * r_max, r_max, 0);
    SimRainDef rain =
        sim_rain_def_thesis000(1.5 * r_max, width - 1.5 * r_max, 1.5 * r_max, 200 * r_max, grains);
    SimRng rng;
    sim_rng_seed(&rng, 1);
    sim_build_rain(&buffer, &rain, &rng);

    SimWorldDef def = sim_world_def_default(); /* thesis 000 §4.3 material by default */
    def.effects = SIM_EFFECT_FRICTION;
    def.mass_model = SIM_MASS_SPHERE;
    def.time_step = 1e-5;
    def.grains = sim_grain_buffer_view(&buffer);
    SimError err;
    SimWorld *world = sim_world_create(&def, &err);
    if (!world) {
        fprintf(stderr, "hello_sim: %s: %s\n", err.field, err.message);
        return 2;
    }
    SimTiming timing = sim_world_timing(world);
    printf("# grains %d, dt %g s, contact time %g s, %.0f steps per contact\n",
           sim_world_mobile_count(world), timing.time_step, timing.contact_time_min,
           timing.steps_per_contact);
    printf("t,e_kin,e_pot,e_rot,e_el,contacts\n");
    long chunk = (long)(0.05 / timing.time_step);
    for (double t = 0.0; t < seconds; t += 0.05) {
        if (sim_world_step(world, chunk, &err) != SIM_OK) {
            fprintf(stderr, "hello_sim: %s\n", err.message);
            sim_world_destroy(world);
            return 1;
        }
        SimEnergy e = sim_world_energy(world);
        printf("%.3f,%.6g,%.6g,%.6g,%.6g,%d\n", sim_world_time(world), e.kinetic, e.potential,
               e.rotational, e.elastic, e.contacts);
    }
    sim_world_destroy(world);
    sim_grain_buffer_free(&buffer);
    return 0;
}
