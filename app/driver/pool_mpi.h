/* SPDX-License-Identifier: MIT */
/* pool_mpi.h: the MPI backend of the process pool (pool.h), built with SABLIER_WITH_MPI.
 * Private to pool.c. */
#ifndef APP_POOL_MPI_H
#define APP_POOL_MPI_H

#include "driver/pool_task.h"

/// Called (by app_pool_begin) only under an MPI launcher (app_pool_launched): joins the job
/// (MPI_Init) and returns on rank 0; a worker rank returns only when rank 0 enters a pool, or
/// exits with status 0 when rank 0 ends. A job of one rank: nothing (the local pool).
void app_pool_mpi_begin(void);

/// 1 when app_pool_mpi_begin joined a job of more than one rank.
int app_pool_mpi_active(void);

/// The worker ranks (the job's ranks less rank 0).
int app_pool_mpi_workers(void);

/// The pool over the ranks: rank 0 hands task indices to the first free worker rank and calls
/// start and done; each worker runs its tasks through the local pool, one at a time.
int app_pool_mpi_run(const AppPool *pool);

#endif
