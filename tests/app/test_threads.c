/* SPDX-License-Identifier: MIT */
/* test_threads.c: `--threads N` drives the physics step (AppRunOptions.threads, applied to each
 * stage's world with sim_world_set_threads), and the results do not depend on it: a run of the
 * small crater scene (deposit, dig, collapse: checkpoints, energy.csv, profile.csv, crater.csv,
 * observables.csv) on 1, 2 and 3 threads writes byte-identical files; only summary.json differs
 * (wall times and the "threads" it reports). No rendering. */
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

static int run_on(int threads)
{
    const char *sets[] = {"stages.deposit.time.end=0.6", "stages.collapse.time.end=0.3"};
    char err[2048], dir[256];
    Scene *scene = scene_load(SMALL, sets, 2, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    run_dir(dir, sizeof dir, threads);
    AppRunOptions options = app_run_options_default();
    options.out_dir = dir;
    options.quiet = 1;
    options.threads = threads;
    int status = app_run(scene, &options);
    scene_free(scene);
    return status;
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

/* Every output of the one-thread run but summary.json is in the others, byte for byte, and the
 * states and tables the brief names are among them. */
static int same_outputs_any_thread_count(void)
{
    static const int counts[] = {1, 2, 3};
    char dirs[3][256];
    for (int k = 0; k < 3; ++k) {
        run_dir(dirs[k], sizeof dirs[k], counts[k]);
        app_test_remove_dir(dirs[k]);
        TEST_ASSERT(run_on(counts[k]) == 0);
    }
    static const char *const expected[] = {"energy.csv",      "profile.csv",   "crater.csv",
                                           "observables.csv", "deposit.state", "collapse.state"};
    int found = 0, compared = 0, mismatched = 0;
    DIR *d = opendir(dirs[0]);
    TEST_ASSERT(d);
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.' || strcmp(e->d_name, "summary.json") == 0)
            continue;
        for (size_t x = 0; x < sizeof expected / sizeof expected[0]; ++x)
            found += strcmp(e->d_name, expected[x]) == 0;
        for (int k = 1; k < 3; ++k)
            mismatched += !same_file(dirs[0], dirs[k], e->d_name);
        ++compared;
    }
    closedir(d);
    printf("%d files compared across 1, 2 and 3 threads\n", compared);
    /* summary.json reports the count */
    char path[1024];
    snprintf(path, sizeof path, "%s/summary.json", dirs[1]);
    long n = 0;
    char *summary = test_read_file(path, &n);
    int reports = summary && (summary[n] = '\0', strstr(summary, "\"threads\": 2") != NULL);
    free(summary);
    for (int k = 0; k < 3; ++k)
        app_test_remove_dir(dirs[k]);
    TEST_ASSERT(found == (int)(sizeof expected / sizeof expected[0]));
    TEST_ASSERT(mismatched == 0);
    TEST_ASSERT(reports);
    return 0;
}

TEST_MAIN(TEST_CASE(same_outputs_any_thread_count))
