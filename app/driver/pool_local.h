/* SPDX-License-Identifier: MIT */
/* pool_local.h: the local backend of the process pool (pool.h): fork and wait on this host.
 * Private to pool.c and pool_mpi.c (the MPI workers run their tasks through it). */
#ifndef APP_POOL_LOCAL_H
#define APP_POOL_LOCAL_H

#include "driver/pool_task.h"

#include <signal.h>

/// Runs the pool's tasks in child processes on this host, at most pool->jobs at a time (clamped
/// to 1 .. APP_POOL_MAX_JOBS). 0, or -1 when a fork failed or waiting for the children failed.
int app_pool_run_local(const AppPool *pool);

/// SIGINT and SIGTERM caught into the pool's signal flag (restore = 0; the old handlers into
/// saved, the flag cleared), or the old handlers back (restore = 1).
void app_pool_catch_signals(struct sigaction saved[2], int restore);

/// The first SIGINT or SIGTERM caught since app_pool_catch_signals (0: none).
int app_pool_signal(void);

/// A check the local pool makes between its waits (NULL: none): a signal number, acted on as if
/// that signal had come (unless one already had), or 0. An MPI worker sets it while it runs a
/// task, to hear rank 0's stop (pool_mpi.c).
void app_pool_set_poll(int (*poll)(void));

/// 1 when pool->resume is set and task `index`'s folder (pool->folder) holds a run that
/// completed: its summary.json says "status": "ok".
int app_pool_task_finished(const AppPool *pool, int index);

#endif
