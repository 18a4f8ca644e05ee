/* SPDX-License-Identifier: MIT */
/* sim_clock_seconds (sim.h), the one clock the runner, the renderer and the benchmarks time
 * themselves with: each of its clocks measures what its name says. The bounds are one-sided (a
 * clock must advance at least so much), never a speed. */
#include "test.h"

#include "sim/sim.h"

#include <pthread.h>
#include <time.h>

/* Sleeps `seconds` of wall time (restarted after a signal). */
static void doze(double seconds)
{
    struct timespec t = {(time_t)seconds, (long)((seconds - (double)(time_t)seconds) * 1e9)};
    while (nanosleep(&t, &t) != 0) {
    }
}

/* Keeps this thread busy until its own CPU clock has advanced `seconds`. */
static double spin_cpu(double seconds)
{
    volatile double sink = 0.0;
    const double t0 = sim_clock_seconds(SIM_CLOCK_THREAD);
    while (sim_clock_seconds(SIM_CLOCK_THREAD) - t0 < seconds)
        for (int k = 0; k < 1000; ++k)
            sink += 1e-9 * k;
    return sink;
}

/* The wall clock advances over a sleep, by the sleep at least; CPU clocks hardly do. */
static int wall_counts_a_sleep(void)
{
    const double w0 = sim_clock_seconds(SIM_CLOCK_WALL), c0 = sim_clock_seconds(SIM_CLOCK_THREAD);
    const double p0 = sim_clock_seconds(SIM_CLOCK_PROCESS);
    doze(0.05);
    const double w = sim_clock_seconds(SIM_CLOCK_WALL) - w0;
    TEST_ASSERT(w >= 0.05);
    TEST_ASSERT(sim_clock_seconds(SIM_CLOCK_THREAD) - c0 < 0.025);
    TEST_ASSERT(sim_clock_seconds(SIM_CLOCK_PROCESS) - p0 < 0.025);
    /* an unknown clock reads the wall clock */
    const double u = sim_clock_seconds((SimClock)99), v = sim_clock_seconds(SIM_CLOCK_WALL);
    TEST_ASSERT(u <= v && v - u < 1.0);
    return 0;
}

/* Readings never go back. */
static int readings_are_monotonic(void)
{
    for (int c = SIM_CLOCK_WALL; c <= SIM_CLOCK_THREAD; ++c) {
        double last = sim_clock_seconds((SimClock)c);
        for (int k = 0; k < 10000; ++k) {
            const double now = sim_clock_seconds((SimClock)c);
            TEST_ASSERT(now >= last);
            last = now;
        }
    }
    return 0;
}

static void *busy_thread(void *arg)
{
    *(double *)arg = spin_cpu(0.05);
    return NULL;
}

/* The process clock counts every thread's CPU time; the thread clock only the caller's. */
static int process_counts_every_thread(void)
{
    const double p0 = sim_clock_seconds(SIM_CLOCK_PROCESS),
                 c0 = sim_clock_seconds(SIM_CLOCK_THREAD);
    double sink = 0.0;
    pthread_t t;
    TEST_ASSERT(pthread_create(&t, NULL, busy_thread, &sink) == 0);
    pthread_join(t, NULL);
    TEST_ASSERT(sim_clock_seconds(SIM_CLOCK_PROCESS) - p0 >= 0.05);
    TEST_ASSERT(sim_clock_seconds(SIM_CLOCK_THREAD) - c0 < 0.025);
    const double c1 = sim_clock_seconds(SIM_CLOCK_THREAD);
    spin_cpu(0.02);
    TEST_ASSERT(sim_clock_seconds(SIM_CLOCK_THREAD) - c1 >= 0.02);
    return sink < 0.0;
}

TEST_MAIN(TEST_CASE(wall_counts_a_sleep), TEST_CASE(readings_are_monotonic),
          TEST_CASE(process_counts_every_thread))
