/* SPDX-License-Identifier: MIT */
/* sim_cpu_count (sim.h): the CPUs of the process's affinity mask, which `--threads auto` and a
 * movie's drawing bands stay within (taskset, a batch system's CPU set). */
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT; pin.h */
#include "pin.h"
#include "test.h"

#include "sim/sim.h"

#include <sched.h>

/* The count is the mask's, and follows the mask: pinned to one CPU, it is 1. */
static int counts_the_affinity_mask(void)
{
    cpu_set_t all;
    TEST_ASSERT(sched_getaffinity(0, sizeof all, &all) == 0);
    TEST_ASSERT(sim_cpu_count() == CPU_COUNT(&all));
    TEST_ASSERT(test_on_one_cpu(sim_cpu_count) == 1);
    TEST_ASSERT(sim_cpu_count() == CPU_COUNT(&all));
    return 0;
}

TEST_MAIN(TEST_CASE(counts_the_affinity_mask))
