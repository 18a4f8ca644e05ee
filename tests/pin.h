/* SPDX-License-Identifier: MIT */
/* pin.h: a probe run with the calling thread pinned to one CPU of its affinity mask, for the
 * tests of what follows the mask (sim_cpu_count; a movie's drawing bands). */
#ifndef SABLIER_TEST_PIN_H
#define SABLIER_TEST_PIN_H

#ifndef _GNU_SOURCE
#error "pin.h needs _GNU_SOURCE defined before the first include (sched_setaffinity)"
#endif
#include <sched.h>

/// probe() with the calling thread pinned to the first CPU of its affinity mask, the mask then
/// restored; -1 when the mask cannot be read, set or restored.
static inline int test_on_one_cpu(int (*probe)(void))
{
    cpu_set_t all, one;
    if (sched_getaffinity(0, sizeof all, &all) != 0)
        return -1;
    int first = 0;
    while (first < CPU_SETSIZE - 1 && !CPU_ISSET(first, &all))
        ++first;
    CPU_ZERO(&one);
    CPU_SET(first, &one);
    if (sched_setaffinity(0, sizeof one, &one) != 0)
        return -1;
    const int value = probe();
    return sched_setaffinity(0, sizeof all, &all) == 0 ? value : -1;
}

#endif
