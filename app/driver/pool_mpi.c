/* SPDX-License-Identifier: MIT */
/* pool_mpi.c: the process pool over MPI ranks (pool_mpi.h, docs/cluster.md).
 *
 * Every rank runs the same command. Rank 0 runs the driver; a worker rank runs it too, but only
 * while rank 0 waits at the entry of a pool, so that it reaches the pool with rank 0's state (the
 * same tasks, read from the same files). In a pool each worker asks for work, rank 0 sends the
 * next task index to the first that asks, the worker runs it in a child process of its own (the
 * local pool, one task at a time) and sends back its exit status. At the pool's end the workers
 * wait: when rank 0 enters its next pool it sends them what its start and done hooks saw, which
 * they replay so that their state stays rank 0's; when rank 0 exits they exit. So tables, plots
 * and messages are rank 0's alone; a worker's output outside its tasks goes to /dev/null.
 * After SIGINT or SIGTERM (rank 0's, or a worker's task interrupted) rank 0 sends each busy
 * worker a stop, which the worker's local pool, polling for it, treats as that signal (pool.h). */
#include "driver/pool_mpi.h"

#include "driver/pool_local.h"
#include "run/run.h"

#include <fcntl.h>
#include <mpi.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

enum { TAG_CONTROL = 1, TAG_EVENTS, TAG_READY, TAG_TASK, TAG_RESULT };

enum { CONTROL_NEXT = 1, CONTROL_END };

enum { EVENT_DONE, EVENT_SKIPPED };

/* What rank 0's hooks saw of one task: done with its status, or skipped by start. */
typedef struct Event {
    int index, kind, status;
} Event;

static struct {
    int active, rank, size;
    pid_t pid;          /* the process that joined; its forked children never speak MPI */
    int out_fd, err_fd; /* a worker's own stdout and stderr, handed to its tasks */
    Event *events;      /* rank 0: the last pool's events, until the workers have them */
    int event_count, rc;
} M = {.out_fd = -1, .err_fd = -1};

/* Started by an MPI launcher (mpirun, srun --mpi=pmix), and not one of our own tasks. */

/* Waits until a message is there: probes with short sleeps, as a blocking receive would spin a
 * core that the members need; calls idle(ctx) (when not NULL) before each probe. */
static void wait_idle(int source, int tag, MPI_Status *status, void (*idle)(void *), void *ctx)
{
    const struct timespec nap = {0, 2000000}; /* 2 ms */
    int flag = 0;
    for (;;) {
        if (idle)
            idle(ctx);
        MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, status);
        if (flag)
            return;
        nanosleep(&nap, NULL);
    }
}

static void wait_for(int source, int tag, MPI_Status *status)
{
    wait_idle(source, tag, status, NULL, NULL);
}

static void worker_fail(const char *what)
{
    dprintf(M.err_fd >= 0 ? M.err_fd : STDERR_FILENO, "sablier: mpi: rank %d: %s\n", M.rank, what);
    MPI_Abort(MPI_COMM_WORLD, 2);
}

/* Rank 0 to every worker: the next pool begins (with the last pool's events) or the job ends. */
static void send_control(int kind)
{
    int head[3] = {kind, M.rc, kind == CONTROL_NEXT ? M.event_count : 0};
    for (int w = 1; w < M.size; ++w) {
        MPI_Send(head, 3, MPI_INT, w, TAG_CONTROL, MPI_COMM_WORLD);
        if (head[2] > 0)
            MPI_Send(M.events, 3 * head[2], MPI_INT, w, TAG_EVENTS, MPI_COMM_WORLD);
    }
    free(M.events);
    M.events = NULL;
    M.event_count = 0;
    M.rc = 0;
}

/* A worker between pools: on NEXT, replays the events of the pool it was in (pool; NULL before
 * the first) and returns that pool's status; on END, leaves the job and exits 0. */
static int worker_wait(const AppPool *pool)
{
    MPI_Status status;
    int head[3];
    wait_for(0, TAG_CONTROL, &status);
    MPI_Recv(head, 3, MPI_INT, 0, TAG_CONTROL, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (head[0] == CONTROL_END) {
        fflush(NULL);
        MPI_Finalize();
        M.active = 0;
        _exit(0);
    }
    if (head[2] <= 0)
        return head[1];
    Event *events = malloc((size_t)head[2] * sizeof *events);
    if (!events)
        worker_fail("out of memory");
    MPI_Recv(events, 3 * head[2], MPI_INT, 0, TAG_EVENTS, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    for (int k = 0; pool && k < head[2]; ++k) {
        const Event *e = &events[k];
        if (e->kind == EVENT_SKIPPED && pool->start)
            pool->start(pool->ctx, e->index);
        else if (e->kind == EVENT_DONE && pool->done)
            pool->done(pool->ctx, e->index, e->status);
    }
    free(events);
    return head[1];
}

/* At exit: rank 0 lets the workers go; a worker that gets here on its own has left rank 0's
 * path (its inputs differ), which would hang the job: it aborts it instead. */
static void finish(void)
{
    if (!M.active || getpid() != M.pid)
        return;
    if (M.rank != 0)
        worker_fail("ended its command before rank 0 (the ranks do not see the same inputs)");
    send_control(CONTROL_END);
    MPI_Finalize();
    M.active = 0;
}

void app_pool_mpi_begin(void)
{
    if (M.active || MPI_Init(NULL, NULL) != MPI_SUCCESS)
        return;
    MPI_Comm_size(MPI_COMM_WORLD, &M.size);
    MPI_Comm_rank(MPI_COMM_WORLD, &M.rank);
    if (M.size < 2) { /* a singleton: the local pool */
        MPI_Finalize();
        return;
    }
    M.active = 1;
    M.pid = getpid();
    atexit(finish);
    if (M.rank == 0)
        return;
    struct sigaction saved[2]; /* a worker heeds SIGINT and SIGTERM through the pool's flag */
    app_pool_catch_signals(saved, 0);
    fflush(NULL);
    M.out_fd = fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 3);
    M.err_fd = fcntl(STDERR_FILENO, F_DUPFD_CLOEXEC, 3);
    int null = open("/dev/null", O_WRONLY);
    if (null >= 0) {
        dup2(null, STDOUT_FILENO);
        dup2(null, STDERR_FILENO);
        close(null);
    }
    worker_wait(NULL);
}

int app_pool_mpi_active(void)
{
    return M.active;
}

int app_pool_mpi_workers(void)
{
    return M.size - 1;
}

/* ---------------------------------------------------------------- a worker */

/* Rank 0's stop to a worker whose task runs: on TAG_TASK (the only message rank 0 sends a busy
 * worker), -2 - the signal to pass on. */
static int stop_code(int signo)
{
    return -2 - signo;
}

/* The local pool's poll while the worker's task runs: rank 0's stop, its signal (0: none). */
static int stop_requested(void)
{
    int flag = 0, code;
    MPI_Status status;
    MPI_Iprobe(0, TAG_TASK, MPI_COMM_WORLD, &flag, &status);
    if (!flag)
        return 0;
    MPI_Recv(&code, 1, MPI_INT, 0, TAG_TASK, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return code < -2 ? -2 - code : SIGTERM;
}

/* One task of a worker, through the local pool (a child process of its own). */
typedef struct Task {
    const AppPool *pool;
    int index, status;
} Task;

static int task_start(void *ctx, int one)
{
    (void)one;
    const Task *t = ctx;
    return t->pool->start ? t->pool->start(t->pool->ctx, t->index) : 0;
}

/* The child: the worker's own output back, and the mark that keeps a `sablier` it execs out of
 * the job. */
static int task_run(void *ctx, int one)
{
    (void)one;
    const Task *t = ctx;
    if (M.out_fd >= 0)
        dup2(M.out_fd, STDOUT_FILENO);
    if (M.err_fd >= 0)
        dup2(M.err_fd, STDERR_FILENO);
    setenv("SABLIER_POOL_TASK", "1", 1);
    return t->pool->run(t->pool->ctx, t->index);
}

static void task_done(void *ctx, int one, int status)
{
    (void)one;
    ((Task *)ctx)->status = status;
}

static int run_task(const AppPool *pool, int index)
{
    Task t = {pool, index, 2}; /* 2 unless it ran: the worker's start hook skipped it */
    AppPool one = {.count = 1,
                   .jobs = 1,
                   .ctx = &t,
                   .start = task_start,
                   .run = task_run,
                   .done = task_done,
                   .signal_status = pool->signal_status};
    app_pool_set_poll(stop_requested);
    app_pool_run_local(&one);
    app_pool_set_poll(NULL);
    return t.status;
}

static int serve(const AppPool *pool)
{
    int count = pool->count;
    MPI_Send(&count, 1, MPI_INT, 0, TAG_READY, MPI_COMM_WORLD);
    for (;;) {
        MPI_Status status;
        int index;
        wait_for(0, TAG_TASK, &status);
        MPI_Recv(&index, 1, MPI_INT, 0, TAG_TASK, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (index < -1)
            continue; /* rank 0's stop, come after the task it was for ended */
        if (index < 0)
            break;
        /* after a signal the worker runs no further task (its running one got it: pool.h) */
        int result[2] = {index, app_pool_signal() ? APP_POOL_INTERRUPTED : run_task(pool, index)};
        MPI_Send(result, 2, MPI_INT, 0, TAG_RESULT, MPI_COMM_WORLD);
    }
    return worker_wait(pool);
}

/* ---------------------------------------------------------------- rank 0 */

/* Every worker at the pool's entry, with the same task count: the free workers, in order of
 * arrival. A worker that counts differently saw other inputs: the job is aborted. */
static void gather_workers(const AppPool *pool, int *free_ranks)
{
    for (int w = 0; w < M.size - 1; ++w) {
        MPI_Status status;
        int count;
        wait_for(MPI_ANY_SOURCE, TAG_READY, &status);
        MPI_Recv(&count, 1, MPI_INT, status.MPI_SOURCE, TAG_READY, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE);
        if (count != pool->count) {
            fprintf(stderr,
                    "sablier: mpi: rank %d has %d tasks, rank 0 %d: the ranks do not see the "
                    "same inputs\n",
                    status.MPI_SOURCE, count, pool->count);
            MPI_Abort(MPI_COMM_WORLD, 2);
        }
        free_ranks[w] = status.MPI_SOURCE;
    }
}

/* Rank 0's record of one task's end: done called, the event kept for the workers. */
static void report(const AppPool *pool, Event *events, int *n, int index, int status)
{
    if (pool->done)
        pool->done(pool->ctx, index, status);
    events[(*n)++] = (Event){index, EVENT_DONE, status};
}

/* The next task to hand out: its index, or -1 when none is left (skipped ones recorded). */
static int next_task(const AppPool *pool, int *next, Event *events, int *n)
{
    while (*next < pool->count) {
        int index = (*next)++;
        if (app_pool_task_finished(pool, index))
            report(pool, events, n, index, 0); /* --resume: a completed run */
        else if (pool->start && pool->start(pool->ctx, index) != 0)
            events[(*n)++] = (Event){index, EVENT_SKIPPED, 0};
        else
            return index;
    }
    return -1;
}

/* Rank 0 once the pool is stopped (its own signal, or a worker's task interrupted): the stop,
 * with signo, to every worker whose task runs; once (*stopped). */
static void halt(const int *busy, int *stopped, int signo)
{
    if (*stopped)
        return;
    *stopped = 1;
    int code = stop_code(signo ? signo : SIGTERM);
    for (int w = 1; w < M.size; ++w)
        if (busy[w])
            MPI_Send(&code, 1, MPI_INT, w, TAG_TASK, MPI_COMM_WORLD);
}

/* Rank 0's busy workers and whether the pool is stopped, for halt while it waits. */
typedef struct Busy {
    int *busy, *stopped;
} Busy;

/* While rank 0 waits: a signal that came stops the busy workers at once. */
static void halt_on_signal(void *ctx)
{
    Busy *b = ctx;
    if (app_pool_signal())
        halt(b->busy, b->stopped, app_pool_signal());
}

/* Rank 0: the next result from a worker into result (halt_on_signal while it waits). Returns the
 * worker's rank, free again. */
static int next_result(int *busy, int *stopped, int result[2])
{
    MPI_Status status;
    Busy b = {busy, stopped};
    wait_idle(MPI_ANY_SOURCE, TAG_RESULT, &status, halt_on_signal, &b);
    MPI_Recv(result, 2, MPI_INT, status.MPI_SOURCE, TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    busy[status.MPI_SOURCE] = 0;
    if ((app_pool_signal() || result[1] == APP_POOL_INTERRUPTED) && result[1] != 0) {
        result[1] = APP_POOL_INTERRUPTED; /* a worker's signal stops the pool too */
        halt(busy, stopped, app_pool_signal());
    }
    return status.MPI_SOURCE;
}

static int schedule(const AppPool *pool)
{
    send_control(CONTROL_NEXT);
    int workers = M.size - 1;
    int *free_ranks = malloc((size_t)workers * sizeof *free_ranks);
    Event *events = malloc((size_t)(pool->count + 1) * sizeof *events);
    int *busy = calloc((size_t)M.size, sizeof *busy); /* by rank: 1 while its task runs */
    if (!free_ranks || !events || !busy) {
        fprintf(stderr, "sablier: mpi: out of memory\n");
        MPI_Abort(MPI_COMM_WORLD, 2);
    }
    struct sigaction saved[2];
    app_pool_catch_signals(saved, 0);
    gather_workers(pool, free_ranks);
    int free_count = workers, next = 0, running = 0, n = 0, rc = 0, stopped = 0;
    for (;;) {
        if (app_pool_signal())
            halt(busy, &stopped, app_pool_signal());
        int index;
        while (free_count > 0 && !stopped && (index = next_task(pool, &next, events, &n)) >= 0) {
            int rank = free_ranks[--free_count];
            MPI_Send(&index, 1, MPI_INT, rank, TAG_TASK, MPI_COMM_WORLD);
            busy[rank] = 1;
            ++running;
        }
        if (running == 0)
            break;
        int result[2];
        free_ranks[free_count++] = next_result(busy, &stopped, result);
        --running;
        report(pool, events, &n, result[0], result[1]);
        if (result[1] == APP_POOL_NOT_STARTED) { /* as the local pool: no later task starts */
            rc = -1;
            next = pool->count;
        }
    }
    for (; stopped && next < pool->count; ++next) /* the tasks the signal kept from starting */
        report(pool, events, &n, next, APP_POOL_INTERRUPTED);
    int signo = app_pool_signal();
    app_pool_catch_signals(saved, 1);
    int none = -1;
    for (int w = 1; w < M.size; ++w)
        MPI_Send(&none, 1, MPI_INT, w, TAG_TASK, MPI_COMM_WORLD);
    free(free_ranks);
    free(busy);
    M.events = events;
    M.event_count = n;
    M.rc = stopped ? APP_EXIT_SIGNAL + (signo ? signo : SIGTERM) : rc;
    return M.rc;
}

int app_pool_mpi_run(const AppPool *pool)
{
    return M.rank == 0 ? schedule(pool) : serve(pool);
}
