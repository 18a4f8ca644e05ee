/* SPDX-License-Identifier: MIT */
/* test_long_bne.c: the Brazil nut effect itself on the reduced box (scenes/brazil_nut/small.scene:
 * 300 grains, 15 d wide, frictional walls, Gamma = 3, 30 periods of 3.953), three seeds, about
 * 3 s in Release (label slow). Bounds from the measured rises 8.4, 11.8 and 13.3 d: every seed
 * rises by more than 5 d and the mean by more than 8 d, while the same box at Gamma = 0.8 moves the
 * intruder by less than 0.2 d (test_bne.c). */
#include "bne.h"
#include "run.h"
#include "scene.h"
#include "test.h"

#include <stdio.h>
#include <unistd.h>

static int rises_with_frictional_walls(void)
{
    double sum = 0.0;
    for (int seed = 1; seed <= 3; ++seed) {
        char seed_set[32], dir[256], err[1024] = "";
        snprintf(seed_set, sizeof seed_set, "seed=%d", seed);
        const char *sets[] = {seed_set};
        Scene *scene = scene_load("scenes/brazil_nut/small.scene", sets, 1, err, sizeof err);
        TEST_ASSERT(scene);
        snprintf(dir, sizeof dir, "/tmp/sablier_test_long_bne_%ld_%d", (long)getpid(), seed);
        AppRunOptions o = app_run_options_default();
        o.out_dir = dir;
        o.quiet = 1;
        TEST_ASSERT(app_run(scene, &o) == 0);
        AppBneResult r = app_bne_result(scene->bne);
        double rise = r.end_height - r.start_height;
        printf("seed %d: rise %.2f d in %.1f (rise time %g)\n", seed, rise, r.shaking_time,
               r.rise_time);
        TEST_ASSERT(rise > 5.0);
        sum += rise;
        scene_free(scene);
    }
    TEST_ASSERT(sum / 3.0 > 8.0);
    return 0;
}

TEST_MAIN(TEST_CASE(rises_with_frictional_walls))
