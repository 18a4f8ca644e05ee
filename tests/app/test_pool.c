/* SPDX-License-Identifier: MIT */
/* test_pool.c: the multi-run drivers' process pool (app/driver/pool.h). Every task runs once, in a
 * child of its own, whatever the job count; done sees every exit status; a start hook skips a task;
 * a signal reads as signal_status. */
#include "test.h"

#include "driver/pool.h"

#include <signal.h>
#include <string.h>

#define TASKS 12

typedef struct Seen {
    int status[TASKS]; /* -2: done never called */
    int calls, order[TASKS];
    int skip; /* the start hook skips this task (-1: none) */
} Seen;

static int task_status(void *ctx, int index)
{
    (void)ctx;
    if (index == 5)
        raise(SIGKILL);
    return index % 4;
}

static int skip_one(void *ctx, int index)
{
    return ((Seen *)ctx)->skip == index;
}

static void record(void *ctx, int index, int status)
{
    Seen *s = ctx;
    s->status[index] = status;
    s->order[s->calls++] = index;
}

static int run_with(int jobs, Seen *s)
{
    for (int k = 0; k < TASKS; ++k)
        s->status[k] = -2;
    s->calls = 0;
    AppPool pool = {.count = TASKS,
                    .jobs = jobs,
                    .ctx = s,
                    .start = skip_one,
                    .run = task_status,
                    .done = record,
                    .signal_status = 7};
    return app_pool_run(&pool);
}

static int pool_statuses(void)
{
    const int jobs[] = {1, 3, TASKS, 1000};
    for (size_t j = 0; j < sizeof jobs / sizeof jobs[0]; ++j) {
        Seen s = {.skip = -1};
        TEST_ASSERT(run_with(jobs[j], &s) == 0);
        TEST_ASSERT(s.calls == TASKS);
        for (int k = 0; k < TASKS; ++k)
            TEST_ASSERT(s.status[k] == (k == 5 ? 7 : k % 4));
    }
    return 0;
}

static int pool_start_skips(void)
{
    Seen s = {.skip = 2};
    TEST_ASSERT(run_with(2, &s) == 0);
    TEST_ASSERT(s.calls == TASKS - 1 && s.status[2] == -2 && s.status[3] == 3);
    return 0;
}

static int pool_one_job_in_order(void)
{
    Seen s = {.skip = -1};
    TEST_ASSERT(run_with(1, &s) == 0);
    for (int k = 0; k < TASKS; ++k)
        TEST_ASSERT(s.order[k] == k);
    return 0;
}

static int pool_nothing_to_run(void)
{
    Seen s = {.skip = -1};
    AppPool pool = {.count = 0, .jobs = 2, .ctx = &s, .run = task_status, .done = record};
    TEST_ASSERT(app_pool_run(&pool) == 0 && s.calls == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(pool_statuses), TEST_CASE(pool_start_skips), TEST_CASE(pool_one_job_in_order),
          TEST_CASE(pool_nothing_to_run))
