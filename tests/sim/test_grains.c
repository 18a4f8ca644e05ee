/* SPDX-License-Identifier: MIT */
/* The grain storage (sim/grains.c): the double arrays of a large pile begin at different places
 * within their pages (so that grain i of the arrays the drift streams does not fall into one set
 * of the L1 cache), and growing keeps every value and zeroes the new ones. */
#include "test.h"

#include "sim/internal.h"

#include <stdint.h>

/* The cache-line set (64 sets of 64 B: a 32 KiB, 8-way L1) where an array's grain 0 falls. */
static int line_set(const double *a)
{
    return (int)(((uintptr_t)a / 64) % 64);
}

/* Arrays of 200 000 grains come from mmap, each at a page start: without the stagger all 19 + 3
 * would share one set. Each array's set differs from every other's among those the velocity-Verlet
 * drift streams (16 arrays). */
static int large_arrays_in_different_sets(void)
{
    SimWorld w;
    memset(&w, 0, sizeof w);
    w.scratch_count = 3; /* velocity Verlet with rotation: the half-step vx, vy, omega */
    TEST_ASSERT(sim_grains_reserve(&w, 200000) == 0);
    const double *hot[] = {w.x,     w.y,          w.vx,          w.vy,
                           w.fx,    w.fy,         w.torque,      w.omega,
                           w.angle, w.inv_mass,   w.inv_inertia, w.x_ref,
                           w.y_ref, w.scratch[0], w.scratch[1],  w.scratch[2]};
    const int n = (int)(sizeof hot / sizeof hot[0]);
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b)
            TEST_ASSERT(line_set(hot[a]) != line_set(hot[b]));
    sim_grains_free(&w);
    sim_neighbour_free(&w); /* the list starts and cells that sim_grains_reserve grows */
    return 0;
}

/* Growing from a small capacity (heap) to a large one (mmap) and again keeps the grains' values,
 * and the new places, the spare sinks past the capacity included, are +0.0. */
static int growth_keeps_values(void)
{
    SimWorld w;
    memset(&w, 0, sizeof w);
    w.scratch_count = 2;
    TEST_ASSERT(sim_grains_reserve(&w, 1000) == 0);
    for (int i = 0; i < 1000; ++i) {
        w.x[i] = i + 0.5;
        w.force_mag[i] = -i;
        w.scratch[1][i] = 3.0 * i;
    }
    for (int capacity = 150000; capacity <= 300000; capacity += 150000) {
        TEST_ASSERT(sim_grains_reserve(&w, capacity) == 0 && w.capacity == capacity);
        for (int i = 0; i < 1000; ++i)
            TEST_ASSERT(w.x[i] == i + 0.5 && w.force_mag[i] == -i && w.scratch[1][i] == 3.0 * i);
        for (int i = 1000; i < capacity + SIM_GRAIN_SLACK; ++i)
            TEST_ASSERT(w.x[i] == 0.0 && w.force_mag[i] == 0.0 && w.scratch[1][i] == 0.0);
    }
    TEST_ASSERT(w.scratch[2] == NULL);
    sim_grains_free(&w);
    sim_neighbour_free(&w); /* the list starts and cells that sim_grains_reserve grows */
    return 0;
}

TEST_MAIN(TEST_CASE(large_arrays_in_different_sets), TEST_CASE(growth_keeps_values))
