/* SPDX-License-Identifier: MIT */
/* hello_sim (installed, C++17): the same world and output as hello_sim.c, from C++ through the
 * extern "C" header: the two programs must print the same lines, bit for bit.
 * Build: c++ -std=c++17 hello_sim.cpp $(pkg-config --cflags --libs sablier-sim) -o hello_sim_cpp */
#include <cinttypes>
#include <cstdio>
#include <memory>
#include <sim/sim.h>

namespace
{

struct WorldDeleter {
    void operator()(SimWorld *world) const
    {
        sim_world_destroy(world);
    }
};

using World = std::unique_ptr<SimWorld, WorldDeleter>;

struct GrainBuffer {
    SimGrainBuffer buffer;

    GrainBuffer()
    {
        sim_grain_buffer_init(&buffer);
    }

    ~GrainBuffer()
    {
        sim_grain_buffer_free(&buffer);
    }

    GrainBuffer(const GrainBuffer &) = delete;
    GrainBuffer &operator=(const GrainBuffer &) = delete;
};

} // namespace

int main()
{
    constexpr double r_max = 0.105, width = 20 * 2 * r_max;
    constexpr long steps = 50000; // 0.5 s: the grains land and touch
    World world;
    {
        GrainBuffer grains;
        sim_build_fixed_box(&grains.buffer, 0.0, width, 0.0, 60 * r_max, r_max, 0);
        SimRainDef rain =
            sim_rain_def_thesis000(1.5 * r_max, width - 1.5 * r_max, 1.5 * r_max, 200 * r_max, 300);
        SimRng rng;
        sim_rng_seed(&rng, 1);
        sim_build_rain(&grains.buffer, &rain, &rng);

        SimWorldDef def = sim_world_def_default();
        def.effects = SIM_EFFECT_FRICTION;
        def.mass_model = SIM_MASS_SPHERE;
        def.time_step = 1e-5;
        def.grains = sim_grain_buffer_view(&grains.buffer);
        SimError err;
        world.reset(sim_world_create(&def, &err));
        if (!world) {
            std::fprintf(stderr, "hello_sim: %s: %s\n", err.field, err.message);
            return 2;
        }
    }
    SimError err;
    if (sim_world_step(world.get(), steps, &err) != SIM_OK) {
        std::fprintf(stderr, "hello_sim: %s\n", err.message);
        return 1;
    }
    const SimEnergy e = sim_world_energy(world.get());
    std::printf("sablier %s: %d grains, step %ld, t %.17g s\n", SIM_VERSION,
                sim_world_mobile_count(world.get()), steps, sim_world_time(world.get()));
    std::printf("hash 0x%016" PRIx64 "\n", sim_world_hash(world.get()));
    std::printf(
        "energy kinetic %.17g potential %.17g rotational %.17g elastic %.17g J, %d contacts\n",
        e.kinetic, e.potential, e.rotational, e.elastic, e.contacts);
    return 0;
}
