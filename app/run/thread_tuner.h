/* SPDX-License-Identifier: MIT */
/* thread_tuner.h: the threads of `sablier run`'s physics step (docs/cli.md, "Threads").
 *
 * --threads auto measures the run's own throughput (work x steps per second of step time, the
 * work of a step its mobile grains and list entries: app_threads_work) over blocks of steps and
 * keeps the count that steps fastest now. It starts on one thread, tries the count the world's
 * size suggests (app_step_threads) after the first block, and then
 * a neighbouring count from time to time, less and less often while the count it has keeps
 * winning (the blocks between two tries double up to APP_TUNER_MAX_INTERVAL), and at once when
 * the number of grains changes by more than APP_TUNER_GRAIN_FACTOR or a block runs much slower
 * than the one before it (another process took a core); a try much slower than the count it has
 * ends early. The counts stay within the CPUs of the affinity mask (sim_cpu_count, sim.h). The
 * results are the same bits on any count (README.md, Determinism), so the count may change at any
 * step.
 *
 * The decision (AppThreadTuner) is pure: it is fed each block's steps and seconds and answers the
 * count of the next block, with no clock and no world, so that tests drive it with made-up rates.
 * AppThreads wraps it for the stage runner (app/run/run.c): the mode (a fixed count, auto, or the
 * testing aid that switches the count every few steps), the blocks, the chunk lengths, and the
 * record that summary.json's "thread_choices" prints.
 *
 *     AppThreads t;
 *     app_threads_init(&t, options.threads, options.threads_switch_every, sim_cpu_count(), 0, 0);
 *     for (...) {
 *         sim_world_set_threads(world, app_threads_want(&t, mobile));
 *         long steps = app_threads_chunk(&t, wanted_steps);
 *         ... step `steps`, timed ...
 *         app_threads_done(&t, steps, mobile, app_threads_work(mobile, entries), seconds);
 *     }
 */
#ifndef APP_THREAD_TUNER_H
#define APP_THREAD_TUNER_H

#include <stddef.h>

/// The count APP_THREADS_AUTO tries first on a world of `mobile` grains on `cpus` CPUs: one per
/// `grains_per_thread` grains (0: APP_GRAINS_PER_THREAD), at least 1, at most `cpus`.
int app_step_threads(int mobile, int cpus, int grains_per_thread);

#define APP_THREADS_AUTO        0
/// Mobile grains per thread of the count APP_THREADS_AUTO tries first: two threads on 1500 grains
/// already took 0.77 of one thread's time with the fused pass in parts; 1000 per thread keeps a
/// margin (docs/dev/scaling.md, "Threads by default").
#define APP_GRAINS_PER_THREAD   1000
/// The tuner tries counts up to this many times that one (down to 250 grains a
/// thread with the default): below that a pass's hand-over costs more than its work.
#define APP_TUNER_DENSITY       4
/// Wall seconds of step time per measured block: long enough that a block's rate is not the
/// scheduler's noise, short enough that a wrong count costs little.
#define APP_TUNER_BLOCK_SECONDS 0.25
/// A tried count replaces the one it is compared with only when faster by this fraction.
#define APP_TUNER_MARGIN        0.05
/// A try at less than this fraction of the rate it is compared with ends after its first
/// measured chunk (0.5 and a quarter of a block until measured: a whole block of two threads at
/// 0.6 of one, under a competing process, cost auto 6-9 % of a 1.5 s deposit;
/// docs/dev/scaling.md, "Threads by measurement").
#define APP_TUNER_EARLY_OUT     0.8
/// A list entry's cost in mobile grains' (the drift's) on the settled pile: the pair kernel and
/// the scatter take about 80 % of a step for 2.4 entries a grain, the drift about 12 %.
#define APP_TUNER_ENTRY_WORK    3.0
/// A try runs in chunks of a block's 1 / this (others in quarters).
#define APP_TUNER_TRY_PARTS     8.0
/// A block slower than this fraction of the block before it is a sudden slowdown: try again.
#define APP_TUNER_SLOWDOWN      0.7
/// The mobile grains changed by more than this factor since the counts were last tried.
#define APP_TUNER_GRAIN_FACTOR  1.5
/// The most blocks between two tries (the back-off stops doubling there): 8 s of steps.
#define APP_TUNER_MAX_INTERVAL  32
/// Steps of the first chunk on a count not timed yet (at the start, at a try).
#define APP_TUNER_FIRST_STEPS   5
/// Choices kept for summary.json (the first ones; the totals count every one).
#define APP_TUNER_LOG           48
/// Counts whose step seconds are kept apart (summary.json's "seconds_on"); more: the last slot.
#define APP_TUNER_COUNTS        64

/// One change of the count (or the start): at the run's step `step`, `threads` chosen because
/// of `why` ("start", "probe", "faster", "back", "grains", "slowdown"), after a block that ran
/// at `rate` work x steps per second (app_threads_work; 0: none measured).
typedef struct AppThreadChoice {
    long step;
    int threads;
    double rate;
    const char *why;
} AppThreadChoice;

typedef struct AppThreadTuner {
    int cpus, grains_per_thread; ///< the affinity mask's CPUs; grains a thread of the first try
    int hi;                      ///< the counts it may choose: 1 .. hi
    int guess;                   ///< the count to try first (0: tried)
    int best;                    ///< the fastest count known now
    int current;                 ///< the count of the next block (best, or one being tried)
    int direction;               ///< of the next try: +1 or -1
    double best_rate;            ///< the last block's rate on `best` (0: none yet)
    int mobile_ref;              ///< the mobile grains when the counts were last tried
    int interval, countdown;     ///< blocks between tries; blocks left to the next
    long probes, changes;        ///< tries so far; changes of the count so far
    int logged;
    AppThreadChoice log[APP_TUNER_LOG];
} AppThreadTuner;

/// Starts on one thread (a step of 0: "start"); the first try is app_step_threads(mobile, cpus,
/// grains_per_thread).
void app_thread_tuner_init(AppThreadTuner *t, int cpus, int grains_per_thread, int mobile);

/// A block of `work_steps` (work x steps, app_threads_work) that took `seconds` on t->current
/// threads, with `mobile` grains at its end and the run at step `step`: returns the count for
/// the next block (also t->current).
int app_thread_tuner_next(AppThreadTuner *t, long step, int mobile, double work_steps,
                          double seconds);

typedef enum AppThreadsMode {
    APP_THREADS_FIXED,
    APP_THREADS_TUNED,  ///< --threads auto
    APP_THREADS_SWITCH, ///< --threads-switch-every STEPS (a testing aid)
} AppThreadsMode;

typedef struct AppThreads {
    AppThreadsMode mode;
    int fixed, cpus, grains_per_thread, started;
    long switch_every;
    long stepped;                         ///< steps run so far
    double block_length;                  ///< wall seconds of a block (APP_TUNER_BLOCK_SECONDS)
    double block_seconds, block_work;     ///< the block being measured
    double seconds_per_step;              ///< of the last chunk (0: none yet)
    int timed_count;                      ///< the count of that chunk
    double seconds[APP_TUNER_COUNTS + 1]; ///< step seconds on each count (index = count)
    AppThreadTuner tuner;                 ///< also the record of a fixed or switching run
} AppThreads;

/// `threads`: N, or APP_THREADS_AUTO; `switch_every` > 0: the count cycles through 1, 2, 3, 4
/// every `switch_every` steps whatever `threads` says; `grains_per_thread`, `block_seconds`: 0
/// for the defaults (APP_GRAINS_PER_THREAD, APP_TUNER_BLOCK_SECONDS).
void app_threads_init(AppThreads *t, int threads, long switch_every, int cpus,
                      int grains_per_thread, double block_seconds);
/// The count for the next chunk of a world with `mobile` grains.
int app_threads_want(AppThreads *t, int mobile);
/// The steps of the next chunk, at most `steps`: shorter where a switch or a block is due.
long app_threads_chunk(const AppThreads *t, long steps);
/// The work of one step that --threads auto divides its blocks' seconds by: the mobile grains
/// plus APP_TUNER_ENTRY_WORK times the neighbour list's entries (sim_world_list_entries). In a
/// growing bed (a rain) the contacts grow faster than the grains, and a rate in grains x steps
/// fell from block to block, so a count tried later lost against the one it was compared with
/// at equal speed (docs/dev/scaling.md, "Frames: the serial part of a real run").
double app_threads_work(int mobile, long entries);
/// A chunk of `steps` with `mobile` grains and `work` per step (app_threads_work) took `seconds`.
void app_threads_done(AppThreads *t, long steps, int mobile, double work, double seconds);
/// summary.json's member, `  "thread_choices": {...}` (no comma, no newline); the length.
size_t app_threads_json(const AppThreads *t, char *out, size_t size);

#endif
