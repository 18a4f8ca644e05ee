/* SPDX-License-Identifier: MIT */
/* pool_task.h: what a process pool is handed (AppPool: its tasks and hooks) and the statuses its
 * done hook reports. Shared by the pool's front (pool.h, pool.c) and its two backends
 * (pool_local.c, pool_mpi.c), which include this header and not pool.h: the backends sit below
 * the front, which alone calls them. */
#ifndef APP_POOL_TASK_H
#define APP_POOL_TASK_H

#include <stddef.h>

/// Jobs beyond this many run this many at a time.
#define APP_POOL_MAX_JOBS 256

/// done's status for a task whose fork failed (errno says why).
#define APP_POOL_NOT_STARTED (-1)
/// done's status for a task SIGINT or SIGTERM stopped: not started, or ended otherwise than
/// with 0 after the pool passed the signal on.
#define APP_POOL_INTERRUPTED (-2)

typedef struct AppPool {
    int count; ///< tasks 0 .. count-1, started in index order
    int jobs;  ///< at most this many children at a time (1 .. APP_POOL_MAX_JOBS)
    void *ctx; ///< handed to every hook
    /// Parent, just before task `index` is forked (optional): 0 to run it; anything else skips it
    /// (not run, done not called; the hook reports why).
    int (*start)(void *ctx, int index);
    /// Child: runs task `index` and returns its exit status; the child then flushes its streams
    /// and _exits with it.
    int (*run)(void *ctx, int index);
    /// Parent, as each task ends, in completion order: its exit status, signal_status when a
    /// signal ended it, or APP_POOL_NOT_STARTED when its fork failed (the later tasks are then
    /// not started; those running are still waited for).
    void (*done)(void *ctx, int index, int status);
    int signal_status;
    /// Parent (optional): task `index`'s output folder into dir: 0, or -1 when it has none.
    int (*folder)(void *ctx, int index, char *dir, size_t size);
    int resume; ///< 1: skip the tasks whose folder holds a completed run (--resume)
} AppPool;

#endif
