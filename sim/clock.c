/* SPDX-License-Identifier: MIT */
/* clock.c: the clocks sim and its users time themselves with (sim.h sim_clock_seconds; the
 * internal sim_now_ns of the parts' timing and the workers' spin). */
#include "internal.h"

#include <time.h>

static struct timespec clock_read(const SimClock clock)
{
    clockid_t id = CLOCK_MONOTONIC;
    if (clock == SIM_CLOCK_PROCESS)
        id = CLOCK_PROCESS_CPUTIME_ID;
    else if (clock == SIM_CLOCK_THREAD)
        id = CLOCK_THREAD_CPUTIME_ID;
    struct timespec t;
    clock_gettime(id, &t);
    return t;
}

double sim_clock_seconds(const SimClock clock)
{
    const struct timespec t = clock_read(clock);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

long long sim_now_ns(void)
{
    const struct timespec t = clock_read(SIM_CLOCK_WALL);
    return (long long)t.tv_sec * 1000000000LL + t.tv_nsec;
}
