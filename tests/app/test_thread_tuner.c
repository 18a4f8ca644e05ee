/* SPDX-License-Identifier: MIT */
/* test_thread_tuner.c: the policy of `--threads auto` (app/run/thread_tuner.h), fed made-up rates
 * (no clock): it keeps one thread when two are slower and two when they are faster, climbs to
 * the fastest of many counts, tries the other counts less and less often while the one it has
 * keeps winning, tries again at once when the grains change beyond the factor or a block runs
 * much slower, never leaves the counts the grains and the CPUs allow; the testing aid's switch
 * cycle and the chunks that end on its switches; summary.json's record. */
#include "test.h"

#include "run/thread_tuner.h"

/* A machine whose rate (particle-steps per second) on n threads is rates[n]. */
typedef struct Machine {
    double rates[APP_TUNER_COUNTS + 1];
} Machine;

/* Runs `blocks` blocks of one second on the tuner from its current count at `mobile` grains:
 * returns the blocks run on `count`, and the tries in *tries. */
static int run_blocks(AppThreadTuner *t, const Machine *m, int blocks, int mobile, int count,
                      long *step)
{
    int on = 0;
    for (int b = 0; b < blocks; ++b) {
        on += t->current == count;
        app_thread_tuner_next(t, ++*step, mobile, m->rates[t->current], 1.0);
    }
    return on;
}

/* Two CPUs and another process: two threads at 0.6 of one. */
static const Machine busy = {.rates = {0, 70e6, 42e6}};

/* Runs blocks until just after a try lost at the longest back-off: the next try is
 * APP_TUNER_MAX_INTERVAL blocks away. */
static void deep_in_back_off(AppThreadTuner *t, const Machine *m, int mobile, long *step)
{
    run_blocks(t, m, 300, mobile, 1, step);
    while (t->countdown != t->interval || t->interval != APP_TUNER_MAX_INTERVAL)
        app_thread_tuner_next(t, ++*step, mobile, m->rates[t->current], 1.0);
}

/* On 2 CPUs with `mobile` grains the tuner starts on one thread and will try `guess` first, is
 * on `best` after `blocks` blocks, and spends at least 95% of the next 400 there (the early
 * tries come 2, 4, 8 ... blocks apart). 0, or 1 with a message. */
static int converges(const Machine *m, int mobile, int guess, int blocks, int best)
{
    AppThreadTuner t;
    app_thread_tuner_init(&t, 2, 0, mobile);
    TEST_ASSERT(t.current == 1 && t.hi == 2 && t.guess == guess);
    TEST_ASSERT(t.logged == 1 && strcmp(t.log[0].why, "start") == 0 && t.log[0].threads == 1);
    long step = 0;
    run_blocks(&t, m, blocks, mobile, best, &step);
    TEST_ASSERT(t.best == best && t.current == best);
    const int on_best = run_blocks(&t, m, 400, mobile, best, &step);
    printf("%d thread(s) for %d blocks of 400, %ld tries\n", best, on_best, t.probes);
    TEST_ASSERT(on_best >= 380);
    return 0;
}

/* 7000 grains on 2 CPUs: two threads suggested, but they run at 0.6 of one (another process on
 * the machine): it keeps one thread, and spends almost every block there. */
static int keeps_one_when_two_are_slower(void)
{
    return converges(&busy, 7000, 2, 3, 1);
}

/* The quiet machine: two threads at 1.8x one. From one thread (1500 grains: one suggested) it
 * moves to two and stays; within the margin, the count it has stays. */
static int takes_two_when_faster(void)
{
    Machine m = {.rates = {0, 60e6, 108e6}};
    TEST_ASSERT(converges(&m, 1500, 1, 2, 2) == 0);
    AppThreadTuner t;
    long step = 0;
    Machine close = {.rates = {0, 100e6, 103e6}};
    app_thread_tuner_init(&t, 2, 0, 1500);
    TEST_ASSERT(run_blocks(&t, &close, 200, 1500, 1, &step) >= 180 && t.best == 1);
    return 0;
}

/* 16 CPUs, 70 000 grains, the fastest count 6 (the others slower the further they are): the
 * suggested 16 loses against one thread, and it climbs from one to 6. */
static int climbs_to_the_fastest(void)
{
    Machine m;
    for (int n = 0; n <= APP_TUNER_COUNTS; ++n)
        m.rates[n] = n == 0 ? 0.0 : 100e6 - 8e6 * (n > 6 ? n - 6 : 6 - n);
    AppThreadTuner t;
    app_thread_tuner_init(&t, 16, 0, 70000);
    TEST_ASSERT(t.current == 1 && t.hi == 16 && t.guess == 16);
    long step = 0;
    run_blocks(&t, &m, 200, 70000, 6, &step);
    TEST_ASSERT(t.best == 6);
    TEST_ASSERT(run_blocks(&t, &m, 400, 70000, 6, &step) >= 380);
    return 0;
}

/* The tries back off: with one count always the fastest, the gaps between tries double up to
 * APP_TUNER_MAX_INTERVAL blocks, so few blocks go to the slower count. */
static int tries_back_off(void)
{
    AppThreadTuner t;
    app_thread_tuner_init(&t, 2, 0, 7000);
    long step = 0;
    run_blocks(&t, &busy, 4, 7000, 1, &step);
    const long before = t.probes;
    run_blocks(&t, &busy, 64 * APP_TUNER_MAX_INTERVAL, 7000, 1, &step);
    const long tries = t.probes - before;
    printf("%ld tries in %d blocks\n", tries, 64 * APP_TUNER_MAX_INTERVAL);
    TEST_ASSERT(tries >= 60 && tries <= 72); /* one per APP_TUNER_MAX_INTERVAL blocks */
    TEST_ASSERT(t.interval == APP_TUNER_MAX_INTERVAL);
    return 0;
}

/* A change in the grains beyond the factor: the counts are tried again at the next block, even
 * far into the back-off; a smaller change does not. */
static int tries_again_when_the_grains_change(void)
{
    const Machine m = busy;
    AppThreadTuner t;
    app_thread_tuner_init(&t, 2, 0, 7000);
    long step = 0;
    deep_in_back_off(&t, &m, 7000, &step);
    TEST_ASSERT(t.current == 1);
    const long tries = t.probes;
    app_thread_tuner_next(&t, ++step, 8000, m.rates[1], 1.0); /* x1.14: no */
    TEST_ASSERT(t.current == 1 && t.probes == tries);
    app_thread_tuner_next(&t, ++step, 14000, m.rates[1], 1.0); /* x2: the first count, 2 */
    TEST_ASSERT(t.current == 2 && t.interval == 1);
    TEST_ASSERT(strcmp(t.log[t.logged - 1].why, "grains") == 0);
    run_blocks(&t, &m, 100, 14000, 1, &step);
    TEST_ASSERT(t.best == 1); /* two still slower */
    /* grains leave (a dig): 400 grains allow one thread only, at once */
    app_thread_tuner_next(&t, ++step, 400, m.rates[1], 1.0);
    TEST_ASSERT(t.hi == 1 && t.current == 1);
    const long now = t.probes;
    run_blocks(&t, &m, 100, 400, 1, &step);
    TEST_ASSERT(t.probes == now);
    return 0;
}

/* A block at less than APP_TUNER_SLOWDOWN of the one before: a try at once; and when the other
 * count is now faster (a process took one core), it moves there. */
static int tries_again_after_a_slowdown(void)
{
    Machine quiet = {.rates = {0, 60e6, 108e6}}, loaded = {.rates = {0, 45e6, 30e6}};
    AppThreadTuner t;
    app_thread_tuner_init(&t, 2, 0, 1500);
    long step = 0;
    deep_in_back_off(&t, &quiet, 1500, &step);
    TEST_ASSERT(t.current == 2);
    app_thread_tuner_next(&t, ++step, 1500, loaded.rates[2], 1.0);
    TEST_ASSERT(t.current == 1 && strcmp(t.log[t.logged - 1].why, "slowdown") == 0);
    run_blocks(&t, &loaded, 50, 1500, 1, &step);
    TEST_ASSERT(t.best == 1 && t.current == 1);
    return 0;
}

/* The counts it may try: at most the CPUs (the affinity mask's), at most one per
 * grains_per_thread / APP_TUNER_DENSITY grains; one CPU or a small world: never another. */
static int stays_within_its_range(void)
{
    Machine m;
    for (int n = 0; n <= APP_TUNER_COUNTS; ++n)
        m.rates[n] = 10e6 * n; /* more is always faster */
    AppThreadTuner t;
    long step = 0;
    app_thread_tuner_init(&t, 1, 0, 100000);
    TEST_ASSERT(run_blocks(&t, &m, 100, 100000, 1, &step) == 100 && t.probes == 0);
    app_thread_tuner_init(&t, 8, 0, 300); /* 300 grains: one thread */
    TEST_ASSERT(run_blocks(&t, &m, 100, 300, 1, &step) == 100 && t.probes == 0);
    app_thread_tuner_init(&t, 8, 0, 1000); /* 1000 grains: up to 4 */
    TEST_ASSERT(t.current == 1 && t.hi == 4);
    int most = 0;
    for (int b = 0; b < 200; ++b) {
        app_thread_tuner_next(&t, ++step, 1000, m.rates[t.current], 1.0);
        most = t.current > most ? t.current : most;
    }
    TEST_ASSERT(most == 4 && t.best == 4);
    app_thread_tuner_init(&t, 8, 50, 1000); /* 50 grains a thread: up to 8, tried first */
    TEST_ASSERT(t.current == 1 && t.hi == 8 && t.guess == 8);
    app_thread_tuner_next(&t, ++step, 1000, m.rates[1], 1.0);
    TEST_ASSERT(t.current == 8);
    return 0;
}

/* Auto on 2 CPUs with 7000 grains: one thread's first chunk (not measured), then a block at
 * 70e6 particle-steps/s; the try of two threads begins. */
static void try_two(AppThreads *t)
{
    app_threads_init(t, APP_THREADS_AUTO, 0, 2, 0, 0);
    app_threads_want(t, 7000);
    app_threads_done(t, 5, 7000, 7000, 5e-4);
    app_threads_done(t, 2500, 7000, 7000, 0.25);
}

/* The run's threads: a fixed count stays; the testing aid cycles 1, 2, 3, 4 on every
 * switch_every-th step, its chunks ending there; auto's chunks fit its blocks. */
static int run_modes(void)
{
    AppThreads t;
    app_threads_init(&t, 3, 0, 2, 0, 0);
    TEST_ASSERT(app_threads_want(&t, 7000) == 3);
    app_threads_done(&t, 100000, 7000, 7000, 100.0);
    TEST_ASSERT(app_threads_want(&t, 70) == 3 && app_threads_chunk(&t, 2000) == 2000);
    app_threads_init(&t, 1, 7, 2, 0, 0);
    long at = 0;
    for (int k = 0; k < 12; ++k) {
        const int n = app_threads_want(&t, 300);
        TEST_ASSERT(n == 1 + (int)(at / 7 % 4));
        const long steps = app_threads_chunk(&t, 5);
        TEST_ASSERT((at % 7) + steps <= 7); /* never across a switch */
        app_threads_done(&t, steps, 300, 300, 1e-3);
        at += steps;
    }
    app_threads_init(&t, APP_THREADS_AUTO, 0, 2, 0, 0);
    TEST_ASSERT(app_threads_want(&t, 7000) == 1);
    TEST_ASSERT(app_threads_chunk(&t, 2000) == APP_TUNER_FIRST_STEPS); /* not timed yet */
    /* 1e-4 s a step; a first chunk: not in the block */
    app_threads_done(&t, 100, 7000, 7000, 0.01);
    TEST_ASSERT(app_threads_chunk(&t, 2000) == 625); /* a quarter of a block */
    TEST_ASSERT(app_threads_chunk(&t, 300) == 300);
    app_threads_done(&t, 2400, 7000, 7000, 0.24);
    TEST_ASSERT(t.tuner.current == 1);           /* 0.24 s measured: the block goes on */
    app_threads_done(&t, 100, 7000, 7000, 0.01); /* the block: 70e6 particle-steps/s on 1 */
    TEST_ASSERT(t.tuner.current == 2);           /* the try of the suggested count */
    TEST_ASSERT(app_threads_chunk(&t, 2000) == APP_TUNER_FIRST_STEPS);
    /* its first chunk at 1/20 (the workers' start) is not its rate; at 1/3 after that, the try
     * is over after an eighth of a block, not a whole one; a try's chunks are eighths */
    app_threads_done(&t, 5, 7000, 7000, 0.01);
    TEST_ASSERT(t.tuner.current == 2 && app_threads_chunk(&t, 2000) == 15); /* 0.03125 s */
    app_threads_done(&t, 50, 7000, 7000, 0.015);
    TEST_ASSERT(t.tuner.current == 2);
    app_threads_done(&t, 100, 7000, 7000, 0.03);
    TEST_ASSERT(t.tuner.current == 1 && t.tuner.best == 1);
    /* a slow first chunk, then 1.5 times the rate: two threads win (the quiet machine) */
    try_two(&t);
    TEST_ASSERT(t.tuner.current == 2);
    app_threads_done(&t, 5, 7000, 7000, 0.006); /* 5.8e6: 0.08 of one thread */
    app_threads_done(&t, 3750, 7000, 7000, 0.25);
    TEST_ASSERT(t.tuner.current == 2 && t.tuner.best == 2);
    /* a try at 0.6 (two threads beside a competing process): over after an eighth of a block;
     * one at 0.85 runs its whole block */
    try_two(&t);
    TEST_ASSERT(t.tuner.current == 2);
    app_threads_done(&t, 5, 7000, 7000, 5e-4);
    app_threads_done(&t, 240, 7000, 7000, 0.04); /* 42e6 */
    TEST_ASSERT(t.tuner.current == 1 && t.tuner.best == 1);
    try_two(&t);
    app_threads_done(&t, 5, 7000, 7000, 5e-4);
    app_threads_done(&t, 850, 7000, 7000, 0.1); /* 59.5e6 */
    TEST_ASSERT(t.tuner.current == 2);
    app_threads_done(&t, 1275, 7000, 7000, 0.15); /* the block's 0.25 s */
    TEST_ASSERT(t.tuner.current == 1 && t.tuner.best == 1);
    /* a try at 1/10: over after its first measured chunk */
    try_two(&t);
    TEST_ASSERT(t.tuner.current == 2);
    app_threads_done(&t, APP_TUNER_FIRST_STEPS, 7000, 7000, APP_TUNER_FIRST_STEPS * 1e-3);
    TEST_ASSERT(t.tuner.current == 2);
    app_threads_done(&t, APP_TUNER_FIRST_STEPS, 7000, 7000, APP_TUNER_FIRST_STEPS * 1e-3);
    TEST_ASSERT(t.tuner.current == 1);
    return 0;
}

/* summary.json's member: the mode, the choices with their reasons, the seconds on each count. */
static int record(void)
{
    AppThreads t;
    app_threads_init(&t, APP_THREADS_AUTO, 0, 2, 0, 0);
    TEST_ASSERT(app_threads_want(&t, 7000) == 1);
    /* 4 chunks on 1 (the first not measured, then a block), 2 on 2 (the first not measured,
     * then a try at half the rate, over after a quarter of a block), 2 on 1 */
    for (int k = 0; k < 8; ++k)
        app_threads_done(&t, 1000, 7000, 7000, t.tuner.current == 1 ? 0.1 : 0.2);
    char json[8192];
    const size_t n = app_threads_json(&t, json, sizeof json);
    printf("%s\n", json);
    TEST_ASSERT(n == strlen(json));
    TEST_ASSERT(strncmp(json, "  \"thread_choices\": {\"mode\": \"auto\", \"cpus\": 2", 46) == 0);
    TEST_ASSERT(strstr(json,
                       "[{\"step\": 0, \"threads\": 1, \"rate\": 0, \"why\": \"start\"}, "
                       "{\"step\": 4000, \"threads\": 2, \"rate\": 70000000, \"why\": \"probe\"}, "
                       "{\"step\": 6000, \"threads\": 1, \"rate\": 35000000, \"why\": \"back\"}]"));
    TEST_ASSERT(strstr(json, "\"seconds_on\": [[1, 0.6], [2, 0.4]]}"));
    TEST_ASSERT(json[n - 1] == '}');
    app_threads_init(&t, 8, 0, 2, 0, 0);
    app_threads_want(&t, 7000);
    app_threads_done(&t, 10, 7000, 7000, 0.5);
    app_threads_json(&t, json, sizeof json);
    TEST_ASSERT(strstr(json, "\"mode\": \"fixed\"") && strstr(json, "\"seconds_on\": [[8, 0.5]]"));
    return 0;
}

/* A growing bed (the rain): the try of two threads steps as many times a second as one thread
 * did a block before, but each step now has 1000 more list entries. In work per second
 * (app_threads_work: grains + 3 x entries) it is 1.43 times faster and stays; in grains x steps
 * per second it would have tied and gone back. */
static int growing_bed_counts_work(void)
{
    TEST_NEAR(app_threads_work(7000, 1000), 7000.0 + APP_TUNER_ENTRY_WORK * 1000.0, 0.0);
    TEST_ASSERT(app_threads_work(7000, 0) == 7000.0);
    AppThreads t;
    try_two(&t); /* one thread: 1e4 steps/s of work 7000 */
    TEST_ASSERT(t.tuner.current == 2);
    const double work = app_threads_work(7000, 1000);
    app_threads_done(&t, 5, 7000, work, 5e-4);    /* the first chunk: not measured */
    app_threads_done(&t, 2500, 7000, work, 0.25); /* 1e4 steps/s again, of work 10 000 */
    TEST_ASSERT(t.tuner.current == 2 && t.tuner.best == 2);
    TEST_NEAR(t.tuner.best_rate, 1e4 * work, 1e-3 * work);
    return 0;
}

TEST_MAIN(TEST_CASE(keeps_one_when_two_are_slower), TEST_CASE(takes_two_when_faster),
          TEST_CASE(climbs_to_the_fastest), TEST_CASE(tries_back_off),
          TEST_CASE(tries_again_when_the_grains_change), TEST_CASE(tries_again_after_a_slowdown),
          TEST_CASE(stays_within_its_range), TEST_CASE(run_modes), TEST_CASE(record),
          TEST_CASE(growing_bed_counts_work))
