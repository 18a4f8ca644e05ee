/* SPDX-License-Identifier: MIT */
/* parallel.c: the step's threads, a small pool of POSIX threads per world (pthreads is part of
 * the C library on the systems we build for; nothing else is needed). Every threaded pass goes
 * through sim_parallel_ranges: chunks of the index range (a fixed cut for a given n and thread
 * count), each thread first taking its own contiguous run of them and then helping with the
 * others', and bodies that write only their own indices, so that the results do not depend on the
 * thread count or on which thread ran a chunk (README.md, Determinism). Helping keeps a thread that
 * the scheduler delays from holding the pass up: with one competing process on 2 cores, 2 threads
 * ran at 57 M particle-steps/s with it against 36-42 without (docs/dev/scaling.md). The fused
 * contact pass on threads runs its parts (sim/parts.c) through sim_parallel_units, the same jobs
 * with chunks of one unit.
 *
 * Waiting: a thread that waits spins for up to SPIN_NS of the monotonic clock (a step's passes
 * follow each other within microseconds), offering its core to any other runnable thread
 * (sched_yield) every YIELD_EVERY checks, and then sleeps on a condition variable. Both limits are
 * measured choices (docs/dev/scaling.md, "Waiting"): a spin of 4000 loads (a few microseconds)
 * made two threads 3x slower than one on a quiet 2-core VM, because every pass then ended in a
 * futex sleep and wake-up that cost more than the pass; spinning without a bound or a yield, as
 * OpenMP's default policy does, was measured 20-35x slower than one thread on a shared, loaded
 * machine, where a spinning thread burns the time slice its partner needs. */
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT */
#include "internal.h"

#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>

/* Below this many indices per thread a loop runs on one thread: the hand-over would cost more
 * than the work (the split does not change the results either way). */
enum { MIN_PER_THREAD = 64, CHUNKS_PER_PART = 8, YIELD_EVERY = 4096 };

#define SPIN_NS 200000LL /* 200 us */

/* A bounded spin: spin_more() is 1 while the waiter should keep checking. */
typedef struct Spin {
    long long start; /* ns */
    unsigned checks;
} Spin;

static Spin spin_start(void)
{
    return (Spin){.start = sim_now_ns(), .checks = 0};
}

static int spin_more(Spin *s)
{
    if (++s->checks % YIELD_EVERY != 0)
        return 1;
    sched_yield();
    return sim_now_ns() - s->start < SPIN_NS;
}

typedef struct SimPool SimPool;

/* The chunks of one part still to run: [next, end), taken one at a time by its own thread and,
 * once their own are done, by the others. A cache line each. */
typedef struct PartQueue {
    _Alignas(64) atomic_int next;
    int end;
} PartQueue;

struct SimPool {
    int workers; /* threads besides the caller's */
    pthread_t *threads;
    pthread_mutex_t mutex;
    pthread_cond_t go, done;
    atomic_ulong generation; /* one more per job */
    atomic_int pending;      /* workers that have not answered the job yet */
    int stop;
    unsigned epoch; /* the fork_epoch of the process that started the workers (pool_here) */
    /* the job (written before generation moves on, read after) */
    SimWorld *world;
    RangeFn *fn;
    int n, chunk, parts;
    int *flags;        /* per part */
    PartQueue *queues; /* per part */
};

typedef struct SimPoolWorker {
    SimPool *pool;
    int part; /* 1..workers */
} Worker;

/* Thread `part` runs its own part's chunks, then helps the parts that are not done yet, so that
 * a thread slowed down (by the scheduler, by its caches) holds the job up for one chunk at most.
 * Which thread runs a chunk does not change what the chunk computes. */
static void run_part(SimPool *p, int part)
{
    int flags = 0;
    for (int k = 0; k < p->parts; ++k) {
        PartQueue *q = &p->queues[(part + k) % p->parts];
        for (int c; (c = atomic_fetch_add_explicit(&q->next, 1, memory_order_relaxed)) < q->end;) {
            const int begin = c * p->chunk;
            const int end = begin + p->chunk < p->n ? begin + p->chunk : p->n;
            flags |= p->fn(p->world, begin, end);
        }
    }
    p->flags[part] = flags;
}

static void *worker_main(void *arg)
{
    Worker *self = arg;
    SimPool *p = self->pool;
    unsigned long seen = 0;
    for (;;) {
        unsigned long g = atomic_load_explicit(&p->generation, memory_order_acquire);
        for (Spin s = spin_start(); g == seen && spin_more(&s);)
            g = atomic_load_explicit(&p->generation, memory_order_acquire);
        int stop = 0;
        if (g == seen) {
            pthread_mutex_lock(&p->mutex);
            while ((g = atomic_load_explicit(&p->generation, memory_order_acquire)) == seen &&
                   !p->stop)
                pthread_cond_wait(&p->go, &p->mutex);
            stop = p->stop;
            pthread_mutex_unlock(&p->mutex);
        }
        if (stop)
            break;
        seen = g;
        /* Every worker answers every job, with a part or without: the caller waits for all of
         * them, so none can still be reading this job's fields when the next one is written. */
        if (self->part < p->parts)
            run_part(p, self->part);
        if (atomic_fetch_sub_explicit(&p->pending, 1, memory_order_acq_rel) == 1) {
            pthread_mutex_lock(&p->mutex);
            pthread_cond_signal(&p->done);
            pthread_mutex_unlock(&p->mutex);
        }
    }
    return NULL;
}

/* How many forks this process is from the one that started: 0 there, one more in each child
 * (pthread_atfork). A pool's workers exist only in the process that started them, and each job
 * asks; getpid() would tell too, but it is a system call (973 ns against 27 ns for
 * clock_gettime on the 2-vCPU VM of docs/dev/scaling.md), and a two-thread step is one job of
 * about 50 us. A child made by the raw fork system call (no atfork handlers) would not be seen;
 * glibc's fork and posix_spawn (which runs none of this before exec) are. */
static atomic_uint fork_epoch;
static pthread_once_t fork_watch = PTHREAD_ONCE_INIT;

static void forked_child(void)
{
    atomic_fetch_add_explicit(&fork_epoch, 1u, memory_order_relaxed);
}

static void watch_forks(void)
{
    pthread_atfork(NULL, NULL, forked_child);
}

/* The pool's workers run in this process (not in a fork's copy of the pool). */
static int pool_here(const SimPool *p)
{
    return p && p->epoch == atomic_load_explicit(&fork_epoch, memory_order_relaxed);
}

static void pool_free(SimPool *p)
{
    if (!p)
        return;
    if (!pool_here(p)) { /* a fork's copy: the workers are the parent's */
        free(p->threads);
        free(p->flags);
        free(p->queues);
        free(p);
        return;
    }
    pthread_mutex_lock(&p->mutex);
    p->stop = 1;
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mutex);
    for (int k = 0; k < p->workers; ++k)
        pthread_join(p->threads[k], NULL);
    pthread_cond_destroy(&p->go);
    pthread_cond_destroy(&p->done);
    pthread_mutex_destroy(&p->mutex);
    free(p->threads);
    free(p->flags);
    free(p->queues);
    free(p);
}

/* A pool of `threads - 1` workers, or NULL (out of memory or no thread could start: the step
 * then runs on the threads that did start, or on one, with the same results). */
static SimPool *pool_create(int threads, Worker **slots)
{
    SimPool *p = calloc(1, sizeof *p);
    Worker *w = calloc((size_t)threads, sizeof *w);
    if (p) {
        p->threads = calloc((size_t)threads, sizeof *p->threads);
        p->flags = calloc((size_t)threads, sizeof *p->flags);
        p->queues = aligned_alloc(_Alignof(PartQueue), (size_t)threads * sizeof *p->queues);
    }
    if (!p || !w || !p->threads || !p->flags || !p->queues ||
        pthread_mutex_init(&p->mutex, NULL) != 0) {
        if (p) {
            free(p->threads);
            free(p->flags);
            free(p->queues);
        }
        free(p);
        free(w);
        return NULL;
    }
    pthread_cond_init(&p->go, NULL);
    pthread_cond_init(&p->done, NULL);
    atomic_init(&p->generation, 0);
    atomic_init(&p->pending, 0);
    pthread_once(&fork_watch, watch_forks);
    p->epoch = atomic_load_explicit(&fork_epoch, memory_order_relaxed);
    for (int k = 0; k + 1 < threads; ++k) {
        w[k] = (Worker){p, k + 1};
        if (pthread_create(&p->threads[k], NULL, worker_main, &w[k]) != 0)
            break;
        p->workers = k + 1;
    }
    if (p->workers == 0) {
        pool_free(p);
        free(w);
        return NULL;
    }
    *slots = w;
    return p;
}

static int run_job(SimPool *p, SimWorld *world, RangeFn *fn, int n, int chunk, int parts);

int sim_parallel_ranges(SimWorld *world, RangeFn *fn, int n, int align)
{
    SimPool *p = world->pool;
    /* In a child forked after the workers started (app/driver/pool.c forks members) the world has
     * no workers: it runs on one thread, with the same results. */
    int parts = pool_here(p) ? p->workers + 1 : 1;
    if (parts > n / MIN_PER_THREAD)
        parts = n / MIN_PER_THREAD;
    if (parts <= 1)
        return n > 0 ? fn(world, 0, n) : 0;
    /* Chunks of a multiple of align, about CHUNKS_PER_PART per part; part c owns a contiguous
     * run of them. */
    int chunk = n / (parts * CHUNKS_PER_PART);
    chunk = chunk > align ? chunk - chunk % align : align;
    return run_job(p, world, fn, n, chunk, parts);
}

int sim_parallel_units(SimWorld *world, RangeFn *fn, int n)
{
    SimPool *p = world->pool;
    int parts = pool_here(p) ? p->workers + 1 : 1;
    parts = parts < n ? parts : n;
    if (parts <= 1)
        return n > 0 ? fn(world, 0, n) : 0;
    return run_job(p, world, fn, n, 1, parts);
}

/* Runs fn over [0, n) in chunks of `chunk` on `parts` threads (the caller's and parts - 1
 * workers); the OR of the results. */
static int run_job(SimPool *p, SimWorld *world, RangeFn *fn, int n, int chunk, int parts)
{
    const int chunks = (n + chunk - 1) / chunk;
    for (int c = 0; c < parts; ++c) {
        atomic_store_explicit(&p->queues[c].next, (int)((long long)chunks * c / parts),
                              memory_order_relaxed);
        p->queues[c].end = (int)((long long)chunks * (c + 1) / parts);
    }
    p->world = world;
    p->fn = fn;
    p->n = n;
    p->chunk = chunk;
    p->parts = parts;
    atomic_store_explicit(&p->pending, p->workers, memory_order_relaxed);
    pthread_mutex_lock(&p->mutex);
    atomic_fetch_add_explicit(&p->generation, 1, memory_order_release);
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mutex);
    run_part(p, 0);
    int left = atomic_load_explicit(&p->pending, memory_order_acquire);
    for (Spin s = spin_start(); left != 0 && spin_more(&s);)
        left = atomic_load_explicit(&p->pending, memory_order_acquire);
    if (left != 0) {
        pthread_mutex_lock(&p->mutex);
        while (atomic_load_explicit(&p->pending, memory_order_acquire) != 0)
            pthread_cond_wait(&p->done, &p->mutex);
        pthread_mutex_unlock(&p->mutex);
    }
    int flags = 0;
    for (int c = 0; c < parts; ++c)
        flags |= p->flags[c];
    return flags;
}

void sim_parallel_start(SimWorld *world, int threads)
{
    sim_parallel_free(world);
    if (threads > 1) {
        Worker *slots = NULL;
        world->pool = pool_create(threads, &slots);
        world->pool_slots = slots;
        if (world->pool)
            world->threads = world->pool->workers + 1;
    }
}

void sim_parallel_free(SimWorld *world)
{
    pool_free(world->pool);
    free(world->pool_slots);
    world->pool = NULL;
    world->pool_slots = NULL;
    world->threads = 1;
}

int sim_cpu_count(void)
{
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0)
        return CPU_COUNT(&set);
    const long online = sysconf(_SC_NPROCESSORS_ONLN);
    return online > 0 ? (int)(online < 1024 ? online : 1024) : 1;
}
