/* SPDX-License-Identifier: MIT */
/* Staggered storage (sim/stagger.c) and the grain storage (sim/grains.c): the arrays one loop reads
 * at the same index (the grain arrays the drift streams, the list's per-entry arrays the contact
 * pass reads) begin at different places within their pages, so that element i of each does not
 * fall into one set of the L1 cache when the allocator gives every large block the same page
 * offset (glibc: mmap); growing keeps every value and zeroes the new grains. */
#include "sim_test_util.h"
#include "test.h"

#include "sim/internal.h"

#include <stdint.h>

/* The cache-line set (64 sets of 64 B: a 32 KiB, 8-way L1) of an address. */
static int line_set(const void *a)
{
    return (int)(((uintptr_t)a / 64) % 64);
}

/* The set where element 0 of staggered array `a` falls when its block begins at a page start (the
 * allocator's header aside): fixed by its lead, whatever the allocator. */
static int lead_set(const void *a)
{
    return (int)((sim_stagger_offset(a) / 64) % 64);
}

/* Arrays of one element size read at the same index: different sets by their leads, and, when the
 * allocator gave all their blocks one page offset (glibc's mmap for large blocks, the case the
 * stagger is for), in the addresses themselves. */
static int in_different_sets(const void *const *arrays, int n)
{
    int same_page_offset = 1;
    for (int a = 0; a < n; ++a) {
        TEST_ASSERT(arrays[a] != NULL);
        const char *block = (const char *)arrays[a] - sim_stagger_offset(arrays[a]);
        const char *block0 = (const char *)arrays[0] - sim_stagger_offset(arrays[0]);
        same_page_offset &= (uintptr_t)block % 4096 == (uintptr_t)block0 % 4096;
    }
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b) {
            TEST_ASSERT(lead_set(arrays[a]) != lead_set(arrays[b]));
            if (same_page_offset)
                TEST_ASSERT(line_set(arrays[a]) != line_set(arrays[b]));
        }
    return 0;
}

/* A staggered block keeps its contents and its lead when it grows from the heap to mmap sizes (a
 * later k does not move it: blocks may change owners, as the history and its spare do), and a
 * new block's data begin at sim_stagger_lead(k), aligned for doubles. */
static int stagger_keeps_contents_and_lead(void)
{
    double *p = sim_stagger_grow(NULL, 100 * sizeof *p, 5);
    TEST_ASSERT(p != NULL && sim_stagger_offset(p) == sim_stagger_lead(5));
    TEST_ASSERT((uintptr_t)p % 16 == 0);
    for (int i = 0; i < 100; ++i)
        p[i] = i * 0.25;
    p = sim_stagger_grow(p, 300000 * sizeof *p, 0);
    TEST_ASSERT(p != NULL && sim_stagger_offset(p) == sim_stagger_lead(5));
    for (int i = 0; i < 100; ++i)
        TEST_ASSERT(p[i] == i * 0.25);
    p[299999] = 1.0; /* the whole size is there (ASan) */
    sim_stagger_free(p);
    sim_stagger_free(NULL);
    TEST_ASSERT(sim_stagger_offset(NULL) == 0);
    return 0;
}

/* Without the stagger, the 19 + 3 arrays of 200 000 grains (mmap'd, each at a page start) would
 * share one set. Each array's set differs from every other's among those the velocity-Verlet drift
 * streams (16 arrays). */
static int large_arrays_in_different_sets(void)
{
    SimWorld w;
    memset(&w, 0, sizeof w);
    w.scratch_count = 3; /* velocity Verlet with rotation: the half-step vx, vy, omega */
    TEST_ASSERT(sim_grains_reserve(&w, 200000) == 0);
    const void *hot[] = {w.x,      w.y,          w.vx,         w.vy,        w.fx,          w.fy,
                         w.torque, w.omega,      w.angle,      w.inv_mass,  w.inv_inertia, w.x_ref,
                         w.y_ref,  w.scratch[0], w.scratch[1], w.scratch[2]};
    TEST_ASSERT(in_different_sets(hot, (int)(sizeof hot / sizeof hot[0])) == 0);
    sim_grains_free(&w);
    sim_neighbour_free(&w); /* the list starts and cells that sim_grains_reserve grows */
    return 0;
}

/* The list's per-entry arrays that the contact pass reads at one entry index, per element size
 * (partner and owner; damping, history and the history's spare, which swap after every pass):
 * different sets before and after the swaps, on a periodic pile with the spring law and rolling. */
static int list_arrays_in_different_sets(void)
{
    SimGrainBuffer b;
    tu_rain(&b, 3, 0.2, 0.015, 0.0162, 1500);
    SimWorldDef def = tu_def(1000.0, 1e5, 0.0);
    def.gravity_y = -G0;
    def.effects = SIM_EFFECT_FRICTION | SIM_EFFECT_ROLLING | SIM_EFFECT_PERIODIC_X;
    def.domain_x0 = 0.0;
    def.domain_x1 = 2.0;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.contact.rolling = SIM_ROLLING_FIXED;
    def.materials[0].friction = 0.5;
    def.materials[0].rolling_friction = 0.002;
    def.materials[0].rolling_stiffness = 5.0;
    SimWorld *w = tu_create(&def, &b);
    TEST_ASSERT(w != NULL);
    for (int pass = 0; pass < 3; ++pass) {
        TEST_ASSERT(tu_step(w, 1) == 0);
        const NeighbourList *nl = &w->nl;
        TEST_ASSERT(nl->start[w->mobile_count] > 0);
        const void *ints[] = {nl->j, nl->owner};
        const void *doubles[] = {nl->gamma,  nl->shift,        nl->hist_t,
                                 nl->hist_r, nl->hist_t_spare, nl->hist_r_spare};
        TEST_ASSERT(in_different_sets(ints, 2) == 0);
        TEST_ASSERT(in_different_sets(doubles, 6) == 0);
    }
    sim_world_destroy(w);
    sim_grain_buffer_free(&b);
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

TEST_MAIN(TEST_CASE(stagger_keeps_contents_and_lead), TEST_CASE(large_arrays_in_different_sets),
          TEST_CASE(list_arrays_in_different_sets), TEST_CASE(growth_keeps_values))
