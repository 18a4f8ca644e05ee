/* SPDX-License-Identifier: MIT */
/* thread_tuner.c: the threads of the physics step, fixed, tuned by measurement (--threads auto)
 * or switched every few steps (a testing aid); thread_tuner.h says how. The tuner times the
 * work on a few counts and keeps the fastest, as Feedback-Driven Threading does for a loop
 * (M. A. Suleman, M. K. Qureshi, Y. N. Patt, ASPLOS 2008), but never stops measuring: a hill
 * climb over the count, one neighbour at a time, with an exponential back-off between tries
 * while the count in use keeps winning, so that trying a slower count costs a few percent of the
 * run at most (one block in APP_TUNER_MAX_INTERVAL). */
#include "run/thread_tuner.h"

#include "output/provenance.h"

#include <stdio.h>
#include <string.h>

int app_step_threads(int mobile, int cpus, int grains_per_thread)
{
    const int per = grains_per_thread > 0 ? grains_per_thread : APP_GRAINS_PER_THREAD;
    int n = mobile / per;
    n = n < cpus ? n : cpus;
    return n > 1 ? n : 1;
}

/* ---------------------------------------------------------------- the tuner (pure) */

static void tuner_log(AppThreadTuner *t, long step, double rate, const char *why)
{
    if (t->logged < APP_TUNER_LOG)
        t->log[t->logged++] = (AppThreadChoice){step, t->current, rate, why};
}

/* The counts it may try for `mobile` grains (1 .. hi), and the first one to try: the count the
 * size of the world suggests (app_step_threads). */
static void tuner_range(AppThreadTuner *t, int mobile)
{
    const int per = t->grains_per_thread > 0 ? t->grains_per_thread : APP_GRAINS_PER_THREAD;
    const int sparse = per / APP_TUNER_DENSITY > 0 ? per / APP_TUNER_DENSITY : 1;
    t->hi = app_step_threads(mobile, t->cpus, sparse);
    t->guess = app_step_threads(mobile, t->cpus, per);
    t->mobile_ref = mobile > 1 ? mobile : 1;
    t->interval = 1;
    t->countdown = 1;
}

/* It starts on one thread, the count that can never be much slower than the others, and tries
 * the suggested count after one block: a try that runs clearly slower ends early
 * (app_threads_done), so a machine where more threads are much slower costs little. */
void app_thread_tuner_init(AppThreadTuner *t, int cpus, int grains_per_thread, int mobile)
{
    memset(t, 0, sizeof *t);
    t->cpus = cpus > 1 ? cpus : 1;
    t->grains_per_thread = grains_per_thread;
    tuner_range(t, mobile);
    t->best = t->current = 1;
    t->direction = 1;
    tuner_log(t, 0, 0.0, "start");
}

/* The neighbour of `best` to try (a quarter of it away on many cores), or `best` when the
 * range has no other count. */
static int tuner_neighbour(AppThreadTuner *t)
{
    const int stride = t->best / 4 > 1 ? t->best / 4 : 1;
    for (int turn = 0; turn < 2; ++turn, t->direction = -t->direction) {
        int n = t->best + t->direction * stride;
        n = n < 1 ? 1 : n > t->hi ? t->hi : n;
        if (n != t->best)
            return n;
    }
    return t->best;
}

static int grains_changed(const AppThreadTuner *t, int mobile)
{
    const double ratio = (double)(mobile > 1 ? mobile : 1) / (double)t->mobile_ref;
    return ratio > APP_TUNER_GRAIN_FACTOR || ratio * APP_TUNER_GRAIN_FACTOR < 1.0;
}

static void set_current(AppThreadTuner *t, int n, long step, double rate, const char *why)
{
    t->changes += n != t->current;
    t->current = n;
    tuner_log(t, step, rate, why);
}

/* Tries the suggested count, or else a neighbour of `best`, now, if the range has another. */
static void try_neighbour(AppThreadTuner *t, long step, double rate, const char *why)
{
    const int n = t->guess > 1 && t->guess != t->best ? t->guess : tuner_neighbour(t);
    t->guess = 0;
    if (n != t->best) {
        ++t->probes;
        set_current(t, n, step, rate, why);
    }
}

/* A try on t->current ended at `rate`: the faster of it and `best` stays. */
static void try_ended(AppThreadTuner *t, long step, double rate)
{
    if (rate > t->best_rate * (1.0 + APP_TUNER_MARGIN)) {
        t->best = t->current;
        t->best_rate = rate;
        t->interval = t->countdown = 1; /* and on in the same direction */
        tuner_log(t, step, rate, "faster");
        return;
    }
    t->interval =
        t->interval * 2 < APP_TUNER_MAX_INTERVAL ? t->interval * 2 : APP_TUNER_MAX_INTERVAL;
    t->countdown = t->interval;
    t->direction = -t->direction;
    set_current(t, t->best, step, rate, "back");
}

int app_thread_tuner_next(AppThreadTuner *t, long step, int mobile, double work_steps,
                          double seconds)
{
    const double rate = seconds > 0.0 ? work_steps / seconds : 0.0;
    if (grains_changed(t, mobile)) { /* another world: tries from the count it has */
        const int measured = t->current == t->best;
        tuner_range(t, mobile);
        t->best = t->best < t->hi ? t->best : t->hi;
        t->best_rate = measured ? rate : 0.0;
        if (t->best != t->current) /* a try cut short, or more threads than the grains allow */
            set_current(t, t->best, step, rate, "grains");
        else
            try_neighbour(t, step, rate, "grains");
        return t->current;
    }
    if (t->current != t->best) {
        try_ended(t, step, rate);
        return t->current;
    }
    const char *why = "probe";
    if (t->best_rate > 0.0 && rate < APP_TUNER_SLOWDOWN * t->best_rate) {
        t->interval = 1; /* another process took a core, or the world got harder: try now */
        t->countdown = 0;
        why = "slowdown";
    }
    t->best_rate = rate;
    if (--t->countdown <= 0)
        try_neighbour(t, step, rate, why);
    return t->current;
}

/* ---------------------------------------------------------------- the run's threads */

void app_threads_init(AppThreads *t, int threads, long switch_every, int cpus,
                      int grains_per_thread, double block_seconds)
{
    memset(t, 0, sizeof *t);
    t->mode = switch_every > 0 ? APP_THREADS_SWITCH
              : threads > 0    ? APP_THREADS_FIXED
                               : APP_THREADS_TUNED;
    t->fixed = threads > 0 ? threads : 1;
    t->switch_every = switch_every;
    t->cpus = cpus > 1 ? cpus : 1;
    t->grains_per_thread = grains_per_thread;
    t->block_length = block_seconds > 0.0 ? block_seconds : APP_TUNER_BLOCK_SECONDS;
}

/* The testing aid's cycle: 1, 2, 3, 4 threads, every switch_every steps of the run. */
static int switch_count(const AppThreads *t)
{
    return 1 + (int)(t->stepped / t->switch_every % 4);
}

int app_threads_want(AppThreads *t, int mobile)
{
    if (!t->started) {
        t->started = 1;
        app_thread_tuner_init(&t->tuner, t->cpus, t->grains_per_thread, mobile);
        if (t->mode != APP_THREADS_TUNED) { /* the record: the count it starts on */
            t->tuner.current = t->mode == APP_THREADS_FIXED ? t->fixed : switch_count(t);
            t->tuner.log[0].threads = t->tuner.current;
        }
    }
    if (t->mode == APP_THREADS_SWITCH) {
        const int n = switch_count(t);
        if (n != t->tuner.current) {
            t->tuner.current = n;
            ++t->tuner.changes;
            tuner_log(&t->tuner, t->stepped, 0.0, "switch");
        }
    }
    return t->tuner.current;
}

long app_threads_chunk(const AppThreads *t, long steps)
{
    if (t->mode == APP_THREADS_SWITCH) {
        const long left = t->switch_every - t->stepped % t->switch_every;
        return steps < left ? steps : left;
    }
    if (t->mode != APP_THREADS_TUNED || t->tuner.hi <= 1)
        return steps;
    /* A count not timed yet (the start, a try) begins with a few steps: on a loaded machine one
     * count can be 20 times slower than another, and a whole chunk of it would cost seconds. */
    if (t->seconds_per_step <= 0.0 || t->timed_count != t->tuner.current)
        return steps < APP_TUNER_FIRST_STEPS ? steps : APP_TUNER_FIRST_STEPS;
    /* then a few chunks a block, so that a block ends close to its length; a try's are shorter,
     * so that a slower count is found out early (block_over) */
    const double parts = t->tuner.current != t->tuner.best ? APP_TUNER_TRY_PARTS : 4.0;
    const double fit = t->block_length / parts / t->seconds_per_step;
    const long most = fit < APP_TUNER_FIRST_STEPS ? APP_TUNER_FIRST_STEPS
                      : fit > (double)steps       ? steps
                                                  : (long)fit;
    return steps < most ? steps : most;
}

/* The block ends: a full one; or a try already at less than a quarter of the rate of the count
 * it is compared with, or at less than APP_TUNER_EARLY_OUT of it after its first chunk of a
 * block's 1 / APP_TUNER_TRY_PARTS (no need to lose more time on it: on a loaded machine a count
 * can be 20 times slower than another, and one 0.6 times as fast loses 40 % of every step). */
static int block_over(const AppThreads *t)
{
    if (t->block_seconds >= t->block_length)
        return 1;
    const AppThreadTuner *u = &t->tuner;
    if (u->current == u->best || !(t->block_seconds > 0.0))
        return 0;
    const double rate = t->block_work / t->block_seconds;
    return rate < 0.25 * u->best_rate ||
           (t->block_seconds >= t->block_length / APP_TUNER_TRY_PARTS &&
            rate < APP_TUNER_EARLY_OUT * u->best_rate);
}

double app_threads_work(int mobile, long entries)
{
    return (double)mobile + APP_TUNER_ENTRY_WORK * (double)entries;
}

void app_threads_done(AppThreads *t, long steps, int mobile, double work, double seconds)
{
    const int c = t->tuner.current;
    t->seconds[c < APP_TUNER_COUNTS ? c : APP_TUNER_COUNTS] += seconds;
    t->stepped += steps;
    const int first_chunk = t->timed_count != c;
    if (steps > 0) {
        t->seconds_per_step = seconds / (double)steps;
        t->timed_count = c;
    }
    /* A count's first chunk pays for its start (the workers' first wake-up, caches filled on other
     * cores): on the quiet 2-vCPU VM the first 5 steps of a try on two threads ran at 0.08-0.15
     * of one thread's rate, and the try ended there although two threads were the faster count.
     * Its rate is the next chunks'. */
    if (t->mode != APP_THREADS_TUNED || (first_chunk && steps > 0))
        return;
    t->block_seconds += seconds;
    t->block_work += work * (double)steps;
    if (!block_over(t))
        return;
    app_thread_tuner_next(&t->tuner, t->stepped, mobile, t->block_work, t->block_seconds);
    t->block_seconds = t->block_work = 0.0;
}

size_t app_threads_json(const AppThreads *t, char *out, size_t size)
{
    static const char *const modes[] = {"fixed", "auto", "switch"};
    const AppThreadTuner *u = &t->tuner;
    size_t n = (size_t)snprintf(out, size,
                                "  \"thread_choices\": {\"mode\": \"%s\", \"cpus\": %d, "
                                "\"most_tried\": %d, \"probes\": %ld, \"changes\": %ld, "
                                "\"choices\": [",
                                modes[t->mode], t->cpus, t->mode == APP_THREADS_TUNED ? u->hi : 0,
                                u->probes, u->changes);
    for (int k = 0; k < u->logged && n < size; ++k) {
        char rate[40];
        app_json_number(rate, sizeof rate, u->log[k].rate);
        n += (size_t)snprintf(
            out + n, size - n, "%s{\"step\": %ld, \"threads\": %d, \"rate\": %s, \"why\": \"%s\"}",
            k ? ", " : "", u->log[k].step, u->log[k].threads, rate, u->log[k].why);
    }
    if (n < size)
        n += (size_t)snprintf(out + n, size - n, "], \"seconds_on\": [");
    for (int c = 1, first = 1; c <= APP_TUNER_COUNTS && n < size; ++c) {
        if (t->seconds[c] <= 0.0)
            continue;
        char s[40];
        app_json_number(s, sizeof s, t->seconds[c]);
        n += (size_t)snprintf(out + n, size - n, "%s[%d, %s]", first ? "" : ", ", c, s);
        first = 0;
    }
    if (n < size)
        n += (size_t)snprintf(out + n, size - n, "]}");
    return n < size ? n : size;
}
