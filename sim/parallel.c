/* SPDX-License-Identifier: MIT */
/* parallel.c: the step's threads, a small pool of POSIX threads per world (pthreads is part of
 * the C library on the systems we build for; nothing else is needed). Every threaded pass goes
 * through sim_parallel_ranges: fixed, contiguous ranges, one per thread, and bodies that write
 * only their own indices, so that the results do not depend on the thread count (README.md,
 * Determinism).
 *
 * Waiting: a thread that waits spins for a short while (a step's passes follow each other within
 * microseconds) and then sleeps on a condition variable. Spinning alone, as OpenMP's default
 * policy does, was measured to make two threads 20-35x slower than one on a shared, loaded
 * machine: a spinning thread burns the time slice its partner needs. */
#include "internal.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>

/* Lower bound of range c of `parts` over [0, n), a multiple of align (the last bound is n). */
static int range_bound(int n, int c, int parts, int align)
{
    if (c >= parts)
        return n;
    long long b = (long long)n * c / parts;
    b -= b % align;
    return (int)b;
}

/* Below this many indices per thread a loop runs on one thread: the hand-over would cost more
 * than the work (the split does not change the results either way). */
enum { MIN_PER_THREAD = 64, SPIN = 4000 };

typedef struct SimPool SimPool;

struct SimPool {
    int workers; /* threads besides the caller's */
    pthread_t *threads;
    pthread_mutex_t mutex;
    pthread_cond_t go, done;
    atomic_ulong generation; /* one more per job */
    atomic_int pending;      /* workers that have not answered the job yet */
    int stop;
    pid_t owner; /* the process that started the workers: a fork's child has none of them */
    /* the job (written before generation moves on, read after) */
    SimWorld *world;
    RangeFn *fn;
    int n, align, parts;
    int *flags; /* per part */
};

typedef struct SimPoolWorker {
    SimPool *pool;
    int part; /* 1..workers */
} Worker;

static void run_part(SimPool *p, int part)
{
    const int begin = range_bound(p->n, part, p->parts, p->align);
    const int end = range_bound(p->n, part + 1, p->parts, p->align);
    p->flags[part] = begin < end ? p->fn(p->world, begin, end) : 0;
}

static void *worker_main(void *arg)
{
    Worker *self = arg;
    SimPool *p = self->pool;
    unsigned long seen = 0;
    for (;;) {
        unsigned long g = atomic_load_explicit(&p->generation, memory_order_acquire);
        for (int s = 0; s < SPIN && g == seen; ++s)
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

static void pool_free(SimPool *p)
{
    if (!p)
        return;
    if (p->owner != getpid()) { /* a fork's copy: the workers are the parent's */
        free(p->threads);
        free(p->flags);
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
    }
    if (!p || !w || !p->threads || !p->flags || pthread_mutex_init(&p->mutex, NULL) != 0) {
        if (p) {
            free(p->threads);
            free(p->flags);
        }
        free(p);
        free(w);
        return NULL;
    }
    pthread_cond_init(&p->go, NULL);
    pthread_cond_init(&p->done, NULL);
    atomic_init(&p->generation, 0);
    atomic_init(&p->pending, 0);
    p->owner = getpid();
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

int sim_parallel_ranges(SimWorld *world, RangeFn *fn, int n, int align)
{
    SimPool *p = world->pool;
    /* In a child forked after the workers started (app/pool.c forks members) the world has no
     * workers: it runs on one thread, with the same results. */
    int parts = p && p->owner == getpid() ? p->workers + 1 : 1;
    if (parts > n / MIN_PER_THREAD)
        parts = n / MIN_PER_THREAD;
    if (parts <= 1)
        return n > 0 ? fn(world, 0, n) : 0;
    p->world = world;
    p->fn = fn;
    p->n = n;
    p->align = align;
    p->parts = parts;
    atomic_store_explicit(&p->pending, p->workers, memory_order_relaxed);
    pthread_mutex_lock(&p->mutex);
    atomic_fetch_add_explicit(&p->generation, 1, memory_order_release);
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mutex);
    run_part(p, 0);
    int left = atomic_load_explicit(&p->pending, memory_order_acquire);
    for (int s = 0; s < SPIN && left != 0; ++s)
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

void sim_world_set_threads(SimWorld *world, int threads)
{
    threads = threads > 1 ? threads : 1;
    if (threads == world->threads)
        return;
    sim_parallel_free(world);
    world->threads = 1;
    if (threads > 1) {
        Worker *slots = NULL;
        world->pool = pool_create(threads, &slots);
        world->pool_slots = slots;
        if (world->pool)
            world->threads = world->pool->workers + 1;
    }
}

int sim_world_threads(const SimWorld *world)
{
    return world->threads;
}

void sim_parallel_free(SimWorld *world)
{
    pool_free(world->pool);
    free(world->pool_slots);
    world->pool = NULL;
    world->pool_slots = NULL;
    world->threads = 1;
}
