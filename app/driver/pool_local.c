/* SPDX-License-Identifier: MIT */
/* pool_local.c: the local process pool (pool_local.h): forks the tasks on this host, at most
 * pool->jobs at a time, and waits for them; passes SIGINT and SIGTERM on to them (pool.h). */
#include "driver/pool_local.h"

#include "base/checkpoint.h"
#include "base/util.h"
#include "run/run.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* The first signal that stopped the pool (0: none) and how many came. */
static volatile sig_atomic_t pool_signal, pool_signal_count;

static void on_signal(int signo)
{
    if (!pool_signal)
        pool_signal = signo;
    pool_signal_count = pool_signal_count + 1;
}

static int (*pool_poll)(void);

void app_pool_set_poll(int (*poll)(void))
{
    pool_poll = poll;
}

/* The poll hook's signal, as if it had been caught (unless one was): once, as rank 0 sends. */
static void poll_signal(void)
{
    int signo = pool_poll ? pool_poll() : 0;
    if (signo && !pool_signal)
        on_signal(signo);
}

void app_pool_catch_signals(struct sigaction saved[2], int restore)
{
    if (!restore)
        pool_signal = pool_signal_count = 0;
    app_catch_signals(on_signal, 0, saved, restore); /* no SA_RESTART: a signal cuts a nap */
}

int app_pool_signal(void)
{
    return pool_signal;
}

int app_pool_task_finished(const AppPool *pool, int index)
{
    char dir[4096], path[4096 + 16];
    if (!pool->resume || !pool->folder || pool->folder(pool->ctx, index, dir, sizeof dir) != 0)
        return 0;
    snprintf(path, sizeof path, "%s/summary.json", dir);
    char *text = app_checkpoint_read(path);
    int ok = text && strstr(text, "\"status\": \"ok\"") != NULL;
    free(text);
    return ok;
}

/* The child of task `index`: a process group of its own (the pool passes signals on to the
 * group: a member's own children too), SIGINT and SIGTERM at their defaults (a member that
 * handles them, `sablier run`, installs its handlers). Never returns. */
static void task_child(const AppPool *pool, int index, const sigset_t *mask)
{
    setpgid(0, 0);
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    sigprocmask(SIG_SETMASK, mask, NULL);
    int status = pool->run(pool->ctx, index);
    fflush(NULL);
    _exit(status);
}

/* Forks task `index` into a free slot: 1 started, 0 skipped by the start hook, -1 fork failed.
 * SIGINT and SIGTERM are blocked across the fork, so that one sent to the new group reaches the
 * child only once its defaults are back. */
static int start_task(const AppPool *pool, int index, pid_t *pids, int *slot_task)
{
    if (pool->start && pool->start(pool->ctx, index) != 0)
        return 0;
    int slot = 0;
    while (pids[slot] != 0)
        ++slot;
    fflush(NULL); /* nothing buffered is written twice */
    sigset_t block, mask;
    sigemptyset(&block);
    sigaddset(&block, SIGINT);
    sigaddset(&block, SIGTERM);
    sigprocmask(SIG_BLOCK, &block, &mask);
    pid_t pid = fork();
    if (pid == 0)
        task_child(pool, index, &mask);
    if (pid > 0)
        setpgid(pid, pid); /* as the child does: whichever runs first */
    sigprocmask(SIG_SETMASK, &mask, NULL);
    if (pid < 0)
        return -1;
    pids[slot] = pid;
    slot_task[slot] = index;
    return 1;
}

/* The signal passed on to every running task's group: the pool's signal once, SIGKILL from the
 * second signal on. */
static void pass_signal(const pid_t *pids, int jobs, int *passed)
{
    int count = pool_signal_count;
    if (count == 0 || count == *passed)
        return;
    for (int slot = 0; slot < jobs; ++slot)
        if (pids[slot] > 0)
            kill(-pids[slot], count > 1 ? SIGKILL : pool_signal);
    *passed = count;
}

/* Reports one child that ended, if any: 1, 0 when none has ended yet (a short sleep, cut short
 * by a signal), or -1 when there is none to wait for. */
static int finish_task(const AppPool *pool, pid_t *pids, const int *slot_task)
{
    int wait_status;
    pid_t pid = waitpid(-1, &wait_status, WNOHANG);
    if (pid == 0) {
        const struct timespec nap = {0, 10000000}; /* 10 ms */
        nanosleep(&nap, NULL);
        return 0;
    }
    if (pid < 0)
        return errno == EINTR ? 0 : -1;
    for (int slot = 0; slot < pool->jobs; ++slot)
        if (pids[slot] == pid) {
            pids[slot] = 0;
            int status = WIFEXITED(wait_status) ? WEXITSTATUS(wait_status) : pool->signal_status;
            if (pool_signal && status != 0)
                status = APP_POOL_INTERRUPTED; /* stopped by the signal passed on */
            if (pool->done)
                pool->done(pool->ctx, slot_task[slot], status);
            return 1;
        }
    return 0; /* not one of ours */
}

/* Starts tasks into the free slots until a signal or a failed fork: the running count. */
static int fill_slots(const AppPool *p, int *next, int running, pid_t *pids, int *slot_task,
                      int *rc)
{
    while (running < p->jobs && *next < p->count && !pool_signal) {
        int index = (*next)++;
        if (app_pool_task_finished(p, index)) {
            if (p->done)
                p->done(p->ctx, index, 0); /* --resume: its folder holds a completed run */
            continue;
        }
        int started = start_task(p, index, pids, slot_task);
        if (started < 0) {
            if (p->done)
                p->done(p->ctx, index, APP_POOL_NOT_STARTED);
            *rc = -1;
            *next = p->count;
        }
        running += started > 0;
    }
    return running;
}

int app_pool_run_local(const AppPool *pool)
{
    int jobs = pool->jobs < 1 ? 1 : pool->jobs > APP_POOL_MAX_JOBS ? APP_POOL_MAX_JOBS : pool->jobs;
    pid_t pids[APP_POOL_MAX_JOBS] = {0};
    int slot_task[APP_POOL_MAX_JOBS] = {0};
    AppPool p = *pool;
    p.jobs = jobs;
    struct sigaction saved[2];
    app_pool_catch_signals(saved, 0);
    int next = 0, running = 0, rc = 0, passed = 0;
    for (;;) {
        poll_signal();
        running = fill_slots(&p, &next, running, pids, slot_task, &rc);
        pass_signal(pids, jobs, &passed);
        if (running == 0)
            break;
        int finished = finish_task(&p, pids, slot_task);
        if (finished < 0) {
            rc = -1;
            break;
        }
        running -= finished;
    }
    for (; pool_signal && next < p.count; ++next) /* the tasks the signal kept from starting */
        if (p.done)
            p.done(p.ctx, next, APP_POOL_INTERRUPTED);
    int signo = pool_signal;
    app_pool_catch_signals(saved, 1);
    return signo ? APP_EXIT_SIGNAL + signo : rc;
}
