/* SPDX-License-Identifier: MIT */
/* fuzz_state: sim_state_load and sim_world_load on any bytes: a state or an error, never a crash,
 * a leak or an unbounded allocation. */
#include "fuzz_input.h"

#include "sim/sim.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_input_file(data, size, ".state");
    if (!path)
        return 0;
    SimGrainSet grains;
    SimWall *walls = NULL;
    int wall_count = 0;
    SimError error;
    double time = 0.0;
    if (sim_state_load(path, &grains, &walls, &wall_count, &time, &error) == SIM_OK) {
        sim_grain_set_free(&grains);
        free(walls);
        SimWorldDef def = sim_world_def_default();
        SimWorld *world = sim_world_load(path, &def, &error);
        if (world && sim_world_restore_contacts(world, path, &error) == SIM_OK)
            sim_world_step(world, 2, &error);
        sim_world_destroy(world);
    }
    unlink(path);
    return 0;
}
