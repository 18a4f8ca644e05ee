/* SPDX-License-Identifier: MIT */
/* pool.c: the process pool of the multi-run drivers (pool.h): forks on this host (pool_local.c),
 * or hands the tasks to MPI ranks (pool_mpi.c) when the command was started by an MPI launcher. */
#include "pool.h"

#include "pool_local.h"
#include "pool_mpi.h"

#include <stddef.h>

void app_pool_begin(void)
{
#ifdef SABLIER_WITH_MPI
    app_pool_mpi_begin();
#endif
}

int app_pool_width(int jobs)
{
#ifdef SABLIER_WITH_MPI
    if (app_pool_mpi_active())
        return app_pool_mpi_workers();
#endif
    return jobs < 1 ? 1 : jobs > APP_POOL_MAX_JOBS ? APP_POOL_MAX_JOBS : jobs;
}

const char *app_pool_member_threads(int jobs)
{
    return app_pool_width(jobs) > 1 ? "1" : NULL;
}

int app_pool_run(const AppPool *pool)
{
#ifdef SABLIER_WITH_MPI
    if (app_pool_mpi_active())
        return app_pool_mpi_run(pool);
#endif
    return app_pool_run_local(pool);
}
