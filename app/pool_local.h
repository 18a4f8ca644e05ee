/* SPDX-License-Identifier: MIT */
/* pool_local.h: the local backend of the process pool (pool.h): fork and wait on this host.
 * Private to pool.c and pool_mpi.c (the MPI workers run their tasks through it). */
#ifndef APP_POOL_LOCAL_H
#define APP_POOL_LOCAL_H

#include "pool.h"

/// Runs the pool's tasks in child processes on this host, at most pool->jobs at a time (clamped
/// to 1 .. APP_POOL_MAX_JOBS). 0, or -1 when a fork failed or waiting for the children failed.
int app_pool_run_local(const AppPool *pool);

#endif
