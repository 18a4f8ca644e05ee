/* SPDX-License-Identifier: MIT */
/* pool_local.c: the local process pool (pool_local.h): forks the tasks on this host, at most
 * pool->jobs at a time, and waits for them. */
#include "pool_local.h"

#include <errno.h>
#include <stdio.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

/* Forks task `index` into a free slot: 1 started, 0 skipped by the start hook, -1 fork failed. */
static int start_task(const AppPool *pool, int index, pid_t *pids, int *slot_task)
{
    if (pool->start && pool->start(pool->ctx, index) != 0)
        return 0;
    int slot = 0;
    while (pids[slot] != 0)
        ++slot;
    fflush(NULL); /* nothing buffered is written twice */
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        int status = pool->run(pool->ctx, index);
        fflush(NULL);
        _exit(status);
    }
    pids[slot] = pid;
    slot_task[slot] = index;
    return 1;
}

/* Waits for one child and reports it: 0, or -1 when there is none to wait for. */
static int finish_task(const AppPool *pool, pid_t *pids, const int *slot_task)
{
    int wait_status;
    pid_t pid;
    do
        pid = waitpid(-1, &wait_status, 0);
    while (pid < 0 && errno == EINTR);
    if (pid < 0)
        return -1;
    for (int slot = 0; slot < pool->jobs; ++slot)
        if (pids[slot] == pid) {
            pids[slot] = 0;
            int status = WIFEXITED(wait_status) ? WEXITSTATUS(wait_status) : pool->signal_status;
            if (pool->done)
                pool->done(pool->ctx, slot_task[slot], status);
            return 1;
        }
    return 0; /* not one of ours */
}

int app_pool_run_local(const AppPool *pool)
{
    int jobs = pool->jobs < 1 ? 1 : pool->jobs > APP_POOL_MAX_JOBS ? APP_POOL_MAX_JOBS : pool->jobs;
    pid_t pids[APP_POOL_MAX_JOBS] = {0};
    int slot_task[APP_POOL_MAX_JOBS] = {0};
    AppPool p = *pool;
    p.jobs = jobs;
    int next = 0, running = 0, rc = 0;
    while (next < p.count || running > 0) {
        while (running < jobs && next < p.count) {
            int index = next++;
            int started = start_task(&p, index, pids, slot_task);
            if (started < 0) {
                if (p.done)
                    p.done(p.ctx, index, APP_POOL_NOT_STARTED);
                rc = -1;
                next = p.count;
            }
            running += started > 0;
        }
        if (running == 0)
            break;
        int finished = finish_task(&p, pids, slot_task);
        if (finished < 0) {
            rc = -1;
            break;
        }
        running -= finished;
    }
    return rc;
}
