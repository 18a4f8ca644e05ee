/* SPDX-License-Identifier: MIT */
/* test_threads.c: `--threads N` drives the physics step (AppRunOptions.threads, applied to each
 * stage's world with sim_world_set_threads), and the results do not depend on it: a run of the
 * small crater scene (deposit, dig, collapse: checkpoints, energy.csv, profile.csv, crater.csv,
 * observables.csv) on 1, 2, 3 and 8 threads writes byte-identical files; only summary.json
 * differs (wall times and the "threads" it reports). So does a run whose count switches every
 * few steps (AppRunOptions.threads_switch_every, the testing aid behind
 * `--threads-switch-every`). APP_THREADS_AUTO (`sablier run`'s default): the first count it
 * chooses and a tuned run (app/run/thread_tuner.h), with the one-thread run's outputs (the CPUs
 * it counts: tests/sim/test_cpus.c). No rendering. */
#include "app_test_run.h"
#include "test.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define SMALL "scenes/crater/small.scene"

static void run_dir(char *out, size_t size, int threads)
{
    snprintf(out, size, "/tmp/sablier_test_threads_%ld_%d", (long)getpid(), threads);
}

/* The small crater on `threads` (APP_THREADS_AUTO: 0) with `per` grains per thread and auto's
 * blocks of `block` s (0: the default), switching the count every `every` steps when > 0, into
 * run_dir(dir_key). */
static int run_full(int threads, int per, double block, long every, int dir_key)
{
    const char *sets[] = {"stages.deposit.time.end=0.6", "stages.collapse.time.end=0.3"};
    char err[2048], dir[256];
    Scene *scene = scene_load(SMALL, sets, 2, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    run_dir(dir, sizeof dir, dir_key);
    AppRunOptions options = app_run_options_default();
    options.out_dir = dir;
    options.quiet = 1;
    options.threads = threads;
    options.grains_per_thread = per;
    options.threads_switch_every = every;
    options.threads_block_seconds = block;
    int status = app_run(scene, &options);
    scene_free(scene);
    return status;
}

static int run_on(int threads)
{
    return run_full(threads, 0, 0.0, 0, threads);
}

/* 1 when DIR_A/NAME and DIR_B/NAME hold the same bytes. */
static int same_file(const char *dir_a, const char *dir_b, const char *name)
{
    char a[1024], b[1024];
    snprintf(a, sizeof a, "%s/%s", dir_a, name);
    snprintf(b, sizeof b, "%s/%s", dir_b, name);
    long na = -1, nb = -2;
    char *da = test_read_file(a, &na), *db = test_read_file(b, &nb);
    int same = da && db && na == nb && memcmp(da, db, (size_t)na) == 0;
    if (!same)
        fprintf(stderr, "%s and %s differ\n", a, b);
    free(da);
    free(db);
    return same;
}

/* The integer after `"key": ` in a summary.json, or -1. */
static long summary_int(const char *dir, const char *key)
{
    char path[1024], pattern[64];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    snprintf(pattern, sizeof pattern, "\"%s\": ", key);
    long n = 0, value = -1;
    char *text = test_read_file(path, &n);
    const char *at = text ? strstr(text, pattern) : NULL;
    if (at)
        value = strtol(at + strlen(pattern), NULL, 10);
    free(text);
    return value;
}

/* Compares every file of DIR_A but summary.json with its namesake in DIR_B: returns how many
 * differ, or -1 when DIR_A cannot be read; *compared counts the files, *found those among
 * names[0 .. count). */
static int differing_outputs(const char *dir_a, const char *dir_b, const char *const *names,
                             int count, int *found, int *compared)
{
    DIR *d = opendir(dir_a);
    if (!d)
        return -1;
    int differ = 0;
    *found = *compared = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.' || strcmp(e->d_name, "summary.json") == 0)
            continue;
        for (int x = 0; x < count; ++x)
            *found += strcmp(e->d_name, names[x]) == 0;
        differ += !same_file(dir_a, dir_b, e->d_name);
        ++*compared;
    }
    closedir(d);
    return differ;
}

/* Every output of the one-thread run but summary.json is in the others, byte for byte, and the
 * states and tables the brief names are among them. */
static int same_outputs_any_thread_count(void)
{
    enum { RUNS = 4 };

    static const int counts[RUNS] = {1, 2, 3, 8};
    char dirs[RUNS][256];
    for (int k = 0; k < RUNS; ++k) {
        run_dir(dirs[k], sizeof dirs[k], counts[k]);
        app_test_remove_dir(dirs[k]);
        TEST_ASSERT(run_on(counts[k]) == 0);
    }
    static const char *const expected[] = {"energy.csv",      "profile.csv",   "crater.csv",
                                           "observables.csv", "deposit.state", "collapse.state"};
    const int names = (int)(sizeof expected / sizeof expected[0]);
    int found = 0, compared = 0, differ = 0;
    for (int k = 1; k < RUNS; ++k) {
        int found_k = 0, compared_k = 0;
        differ += differing_outputs(dirs[0], dirs[k], expected, names, &found_k, &compared_k);
        TEST_ASSERT(k == 1 || (found_k == found && compared_k == compared));
        found = found_k;
        compared = compared_k;
    }
    printf("%d files compared across 1, 2, 3 and 8 threads\n", compared);
    const int reports = summary_int(dirs[1], "threads") == 2 && /* the count it ran on */
                        summary_int(dirs[3], "threads") == 8;
    for (int k = 0; k < RUNS; ++k)
        app_test_remove_dir(dirs[k]);
    TEST_ASSERT(found == names);
    TEST_ASSERT(differ == 0);
    TEST_ASSERT(reports);
    return 0;
}

/* The count switched every 37 steps through 1, 2, 3 and 4 threads (deposit, dig and collapse,
 * hundreds of switches, list builds between them): every output but summary.json is the
 * one-thread run's, byte for byte, and summary.json records the switches. */
static int switching_threads_same_bytes(void)
{
    char one[256], switched[256];
    run_dir(one, sizeof one, 1);
    run_dir(switched, sizeof switched, 99);
    app_test_remove_dir(one);
    app_test_remove_dir(switched);
    TEST_ASSERT(run_on(1) == 0);
    TEST_ASSERT(run_full(1, 0, 0.0, 37, 99) == 0);
    int found = 0, compared = 0;
    const int differ = differing_outputs(one, switched, NULL, 0, &found, &compared);
    const long most = summary_int(switched, "threads"), changes = summary_int(switched, "changes");
    const long steps = summary_int(switched, "steps");
    printf("%d files compared; %ld changes of the count, up to %ld threads\n", compared, changes,
           most);
    app_test_remove_dir(one);
    app_test_remove_dir(switched);
    TEST_ASSERT(compared >= 6 && differ == 0);
    TEST_ASSERT(most == 4 && steps > 10000 && changes >= steps / 37 - 1);
    return 0;
}

/* APP_THREADS_AUTO: one thread per APP_GRAINS_PER_THREAD mobile grains, at least 1, at most the
 * CPUs (sim_cpu_count: tests/sim/test_cpus.c). */
static int auto_count(void)
{
    TEST_ASSERT(app_step_threads(0, 8, 0) == 1);
    TEST_ASSERT(app_step_threads(APP_GRAINS_PER_THREAD * 2 - 1, 8, 0) == 1);
    TEST_ASSERT(app_step_threads(APP_GRAINS_PER_THREAD * 2, 8, 0) == 2);
    TEST_ASSERT(app_step_threads(70000, 8, 0) == 8);
    TEST_ASSERT(app_step_threads(70000, 1, 0) == 1);
    TEST_ASSERT(app_step_threads(350, 16, 100) == 3);
    return 0;
}

/* APP_THREADS_AUTO with blocks of 1 ms (hundreds of them in this short run) and one thread per
 * 50 grains suggested (every CPU for the small bed): it starts on one thread, tries the others
 * as it measures them, and again when the dig removes grains; whatever it chose, every output
 * but summary.json is the one-thread run's, byte for byte, and summary.json reports the most
 * threads the step ran on and the tries. */
static int auto_follows_the_grains(void)
{
    char one[256], autod[256];
    run_dir(one, sizeof one, 1);
    run_dir(autod, sizeof autod, APP_THREADS_AUTO);
    app_test_remove_dir(one);
    app_test_remove_dir(autod);
    TEST_ASSERT(run_on(1) == 0);
    TEST_ASSERT(run_full(APP_THREADS_AUTO, 50, 1e-3, 0, APP_THREADS_AUTO) == 0);
    int found = 0, compared = 0;
    const int mismatched = differing_outputs(one, autod, NULL, 0, &found, &compared);
    const long most = summary_int(autod, "threads"), mobile = summary_int(one, "mobile_grains");
    const long probes = summary_int(autod, "probes");
    printf("%d files compared; auto ran on up to %ld threads (%d CPUs, %ld mobile grains), "
           "%ld tries\n",
           compared, most, sim_cpu_count(), mobile, probes);
    app_test_remove_dir(one);
    app_test_remove_dir(autod);
    TEST_ASSERT(compared >= 6 && mismatched == 0);
    /* the bed's grains (before the dig) are more than the collapse's */
    TEST_ASSERT(mobile > 100 && most >= app_step_threads((int)mobile, sim_cpu_count(), 50));
    TEST_ASSERT(most <= sim_cpu_count() && (sim_cpu_count() < 2 || most >= 2));
    TEST_ASSERT(sim_cpu_count() < 2 || probes >= 2);
    return 0;
}

TEST_MAIN(TEST_CASE(same_outputs_any_thread_count), TEST_CASE(switching_threads_same_bytes),
          TEST_CASE(auto_count), TEST_CASE(auto_follows_the_grains))
