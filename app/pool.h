/* SPDX-License-Identifier: MIT */
/* pool.h: the one process pool of the multi-run drivers (sweeps, scans, studies). Each task runs
 * in a child process of its own, so its results are those of a lone run whatever the job count.
 * App core: knows nothing of the families. */
#ifndef APP_POOL_H
#define APP_POOL_H

/// Jobs beyond this many run this many at a time.
#define APP_POOL_MAX_JOBS 256

/// done's status for a task whose fork failed (errno says why).
#define APP_POOL_NOT_STARTED (-1)

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
} AppPool;

/// Runs the pool's tasks. 0, or -1 when a fork failed or waiting for the children failed.
int app_pool_run(const AppPool *pool);

#endif
