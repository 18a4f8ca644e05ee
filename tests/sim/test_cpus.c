/* SPDX-License-Identifier: MIT */
/* sim_cpu_count (sim.h): the CPUs of the process's affinity mask, which `--threads auto` and a
 * movie's drawing and encoding threads stay within (taskset, a batch system's CPU set). */
#define _GNU_SOURCE /* sched_getaffinity, sched_setaffinity, CPU_COUNT */
#include "test.h"

#include "sim/sim.h"

#include <sched.h>

/* The count is the mask's, and follows the mask: pinned to one CPU, it is 1. */
static int counts_the_affinity_mask(void)
{
    cpu_set_t all, one;
    TEST_ASSERT(sched_getaffinity(0, sizeof all, &all) == 0);
    TEST_ASSERT(sim_cpu_count() == CPU_COUNT(&all));
    int first = 0;
    while (!CPU_ISSET(first, &all))
        ++first;
    CPU_ZERO(&one);
    CPU_SET(first, &one);
    TEST_ASSERT(sched_setaffinity(0, sizeof one, &one) == 0);
    const int pinned = sim_cpu_count();
    TEST_ASSERT(sched_setaffinity(0, sizeof all, &all) == 0);
    TEST_ASSERT(pinned == 1);
    TEST_ASSERT(sim_cpu_count() == CPU_COUNT(&all));
    return 0;
}

TEST_MAIN(TEST_CASE(counts_the_affinity_mask))
