/* SPDX-License-Identifier: MIT */
/* pool.c: the process pool of the multi-run drivers (pool.h): forks on this host (pool_local.c),
 * or hands the tasks to MPI ranks (pool_mpi.c) when the command was started by an MPI launcher. */
#include "driver/pool.h"

#include "driver/pool_local.h"
#include "driver/pool_mpi.h"

#include <errno.h>
#include <signal.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

int app_pool_launched(void)
{
    if (getenv("SABLIER_POOL_TASK"))
        return 0;
    const char *size = getenv("OMPI_COMM_WORLD_SIZE");
    if (size)
        return atoi(size) > 1;
    return getenv("PMIX_RANK") || getenv("PMI_RANK") || getenv("PMI_SIZE");
}

void app_pool_launcher_exec(char **argv)
{
#ifdef SABLIER_WITH_MPI
    (void)argv; /* this program is the MPI one */
#else
    if (!app_pool_launched())
        return;
    /* the MPI program beside this one (a build folder), or in <prefix>/libexec/sablier beside
     * <prefix>/bin (the install tree, the sablier-mpi package) */
    char self[4096];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0)
        return;
    self[n] = '\0';
    char *slash = strrchr(self, '/');
    if (!slash)
        return;
    *slash = '\0';
    char path[2][4200]; /* beside it, then in <prefix>/libexec/sablier */
    snprintf(path[0], sizeof path[0], "%s/sablier-mpi", self);
    snprintf(path[1], sizeof path[1], "%s/../libexec/sablier/sablier-mpi", self);
    for (int k = 0; k < 2; ++k) {
        if (access(path[k], X_OK) == 0) {
            fflush(NULL);
            execv(path[k], argv);
            fprintf(stderr, "sablier: cannot run %s: %s\n", path[k], strerror(errno));
            return;
        }
    }
#endif
}

void app_pool_begin(void)
{
#ifdef SABLIER_WITH_MPI
    if (app_pool_launched())
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

const char *app_pool_status_text(int status, char text[16])
{
    if (status == APP_POOL_INTERRUPTED)
        return "interrupted";
    snprintf(text, 16, "%d", status);
    return text;
}

int app_pool_exec_wait(const char *path, char *const argv[], struct rusage *usage)
{
    sigset_t block, mask;
    sigemptyset(&block);
    sigaddset(&block, SIGINT);
    sigaddset(&block, SIGTERM);
    sigprocmask(SIG_BLOCK, &block, &mask); /* until the waiting side ignores them */
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        sigprocmask(SIG_SETMASK, &mask, NULL);
        execv(path, argv);
        fprintf(stderr, "sablier: cannot run %s: %s\n", path, strerror(errno));
        fflush(NULL);
        _exit(2);
    }
    struct sigaction ignore, saved[2];
    memset(&ignore, 0, sizeof ignore);
    ignore.sa_handler = SIG_IGN;
    sigemptyset(&ignore.sa_mask);
    sigaction(SIGINT, &ignore, &saved[0]);
    sigaction(SIGTERM, &ignore, &saved[1]);
    sigprocmask(SIG_SETMASK, &mask, NULL);
    int status = 0;
    pid_t got = pid;
    if (pid > 0)
        do
            got = wait4(pid, &status, 0, usage);
        while (got < 0 && errno == EINTR);
    sigaction(SIGINT, &saved[0], NULL);
    sigaction(SIGTERM, &saved[1], NULL);
    if (pid < 0 || got < 0)
        return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}
