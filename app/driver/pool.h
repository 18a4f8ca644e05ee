/* SPDX-License-Identifier: MIT */
/* pool.h: the one process pool of the multi-run drivers (sweeps, scans, studies). Each task runs
 * in a child process of its own, so its results are those of a lone run whatever the job count.
 * App core: knows nothing of the families.
 *
 * Under an MPI launcher (`mpirun -n N sablier sweep ...`, built with SABLIER_WITH_MPI) the
 * tasks run on the N - 1 worker ranks, one at a time each, on any number of hosts (pool_mpi.c,
 * docs/cluster.md); `jobs` is then ignored. Rank 0 runs the command and calls start and done;
 * the workers run the command too, but only up to each pool while rank 0 waits at it, so a
 * driver writes nothing but folders before a pool (the workers see the files rank 0 saw),
 * and what it writes after a pool is rank 0's alone. start is called on rank 0 as a task is
 * handed out and again on the worker that runs it (a skip there ends the task with status 2).
 *
 * Signals: SIGINT and SIGTERM are caught while a pool runs. After one, no task starts; every
 * running task's process group (each task runs in a group of its own, with SIGINT and SIGTERM
 * at their defaults, so a member's own children are reached too) gets the signal once, and the
 * pool waits for them (a `sablier run` member finishes its step, saves its state and exits 130
 * or 143); a second signal kills them (SIGKILL). done reports APP_POOL_INTERRUPTED for every
 * task that did not end with 0 then, and for every task not started; app_pool_run returns 128
 * plus the first signal, the exit status the driver ends with after writing its tables. Under
 * MPI a worker rank that gets the signal passes it on to its task and runs no further one (a
 * worker heeds the signals only through the flag, so it never dies between tasks); rank 0 hands
 * out no further task once it or a worker got one, sends a stop to every worker whose task runs
 * (the worker passes that signal on to its task, as if it had got it), and waits for them.
 *
 * Resume: with `resume` set and a `folder` hook, a task whose folder holds a run that completed
 * (summary.json: "status": "ok") is not run again: done reports 0 for it, start is not called. */
#ifndef APP_POOL_H
#define APP_POOL_H

#include "driver/pool_task.h"

#include <stddef.h>

/// Joins the MPI job when the command was started by an MPI launcher with more than one rank
/// (main calls it first; without SABLIER_WITH_MPI, or outside a launcher, it does nothing).
/// A worker rank returns from it only when rank 0 enters a pool.
void app_pool_begin(void);

/// 1 when an MPI launcher (Open MPI's mpirun, a PMI or PMIx one) started this process in a job
/// of more than one rank, and it is not a pool's member command.
int app_pool_launched(void);

/// In the program built without MPI (`sablier`), under an MPI launcher: replaces this process by
/// the MPI program `sablier-mpi` (beside it, or in <prefix>/libexec/sablier) with the same
/// arguments, so that `mpirun -n N sablier ...` needs MPI only where sablier-mpi is installed.
/// Returns when there is none (the command then runs as without a launcher) or in sablier-mpi.
void app_pool_launcher_exec(char **argv);

/// How many tasks run at once: jobs, or the worker ranks under MPI (for the drivers' messages).
int app_pool_width(int jobs);

/// The `--threads` value for a member command the pool starts: "1" when members run side by side
/// (app_pool_width > 1: the cores go to members, one each), NULL when they run one at a time (the
/// member then takes the threads `--threads auto` gives it). Results do not depend on it.
const char *app_pool_member_threads(int jobs);

/// A task's status as the drivers' tables write it: "interrupted" for APP_POOL_INTERRUPTED,
/// else the number (an exit status, -1: not run). `text` holds at least 16 bytes.
const char *app_pool_status_text(int status, char text[16]);

struct rusage;

/// For a task (in its child) that runs a program as a child of its own and waits for it (to
/// measure its CPU time): forks, execs `path` with argv, waits, the resources used into usage.
/// SIGINT and SIGTERM are ignored while it waits, so that the signal the pool passes on to the
/// task's group stops the program, not the waiting task. The program's exit status (1 when a
/// signal ended it), or -1 when the fork or the wait failed (errno says why; a failed exec:
/// status 2 with a message).
int app_pool_exec_wait(const char *path, char *const argv[], struct rusage *usage);

/// Runs the pool's tasks. 0, -1 when a fork failed or waiting for the children failed, or 128 +
/// the signal when SIGINT (130) or SIGTERM (143) stopped the pool.
int app_pool_run(const AppPool *pool);

#endif
