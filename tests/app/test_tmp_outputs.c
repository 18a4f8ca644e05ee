/* SPDX-License-Identifier: MIT */
/* test_tmp_outputs.c: the sediment and sweep outputs go through PATH.tmp (app_tmp_open and
 * app_tmp_commit). A write that fails leaves no PATH.tmp behind and does not touch what stands at
 * PATH: here PATH is a non-empty folder (refused as PATH.tmp is opened: sim_open_output) or
 * PATH.tmp is a folder (the open fails). No simulation runs: the sediment writers are called
 * directly, the sweep's members are /bin/true and the Shields scan's member cannot create its
 * folder. */
#include "test.h"

#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "crater/sweep.h"
#include "sediment/sediment.h"

#define SEDIMENT_SCENE "scenes/sediment/viscous.scene"
#define CRATER_SCENE   "scenes/crater/quick.scene"

static int exists(const char *dir, const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return access(path, F_OK) == 0;
}

/* A fresh folder under /tmp for one case. */
static void fresh_dir(char *dir, size_t size, const char *tag)
{
    snprintf(dir, size, "/tmp/sablier_test_tmp_outputs_%ld_%s", (long)getpid(), tag);
    char command[600];
    snprintf(command, sizeof command, "rm -rf '%s'", dir);
    if (system(command) != 0 || mkdir(dir, 0777) != 0)
        dir[0] = '\0';
}

static void remove_dir(const char *dir)
{
    char command[600];
    snprintf(command, sizeof command, "rm -rf '%s'", dir);
    if (system(command) != 0)
        fprintf(stderr, "cannot remove %s\n", dir);
}

/* DIR/NAME as a folder holding one file `keep`: renaming a file onto it fails. */
static int block(const char *dir, const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    if (mkdir(path, 0777) != 0)
        return -1;
    snprintf(path, sizeof path, "%s/%s/keep", dir, name);
    FILE *f = fopen(path, "w");
    return f && fclose(f) == 0 ? 0 : -1;
}

/* The failed write left no NAME.tmp and did not touch the folder at NAME. */
static int kept(const char *dir, const char *name)
{
    char tmp[256], keep[256];
    snprintf(tmp, sizeof tmp, "%s.tmp", name);
    snprintf(keep, sizeof keep, "%s/keep", name);
    return !exists(dir, tmp) && exists(dir, keep);
}

static int first_line(const char *dir, const char *name, char *line, size_t size)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    int ok = fgets(line, (int)size, f) != NULL;
    fclose(f);
    return ok ? 0 : -1;
}

static Scene *sediment_scene(void)
{
    char err[1024] = "";
    Scene *scene = scene_load(SEDIMENT_SCENE, NULL, 0, err, sizeof err);
    if (!scene)
        fprintf(stderr, "%s\n", err);
    return scene && app_sediment_of(scene) ? scene : NULL;
}

/* begin and end with BLOCKED in the way in DIR: 1 when begin or end fails with "cannot write
 * DIR/WHAT" (a folder at an output's name is refused when its temporary is opened). */
static int end_fails(AppSediment *s, const char *dir, const char *blocked, const char *what)
{
    char err[1024] = "", expected[600];
    if (!dir[0] || block(dir, blocked) != 0)
        return 0;
    if (app_sediment_begin(s, dir, err, sizeof err) == 0 &&
        app_sediment_end(s, 1, err, sizeof err) != -1)
        return 0;
    snprintf(expected, sizeof expected, "cannot write %s/%s", dir, what);
    return strcmp(err, expected) == 0;
}

/* sediment.csv and sediment.json: written whole, or not at all and no .tmp. */
static int sediment_run_outputs(void)
{
    char dir[256], err[1024] = "", line[256];
    fresh_dir(dir, sizeof dir, "run");
    TEST_ASSERT(dir[0]);
    Scene *scene = sediment_scene();
    TEST_ASSERT(scene);
    AppSediment *s = app_sediment_of(scene);
    /* both complete */
    TEST_ASSERT(app_sediment_begin(s, dir, err, sizeof err) == 0);
    TEST_ASSERT(exists(dir, "sediment.csv.tmp") && !exists(dir, "sediment.csv"));
    TEST_ASSERT(app_sediment_end(s, 1, err, sizeof err) == 0);
    TEST_ASSERT(first_line(dir, "sediment.csv", line, sizeof line) == 0);
    TEST_ASSERT(strcmp(line, "t,q,q_star,grain_vx_mean,bed_level,u_top,shear_velocity\n") == 0);
    TEST_ASSERT(first_line(dir, "sediment.json", line, sizeof line) == 0);
    TEST_ASSERT(strcmp(line, "{\n") == 0);
    TEST_ASSERT(!exists(dir, "sediment.csv.tmp") && !exists(dir, "sediment.json.tmp"));
    /* the CSV cannot be renamed into place: no JSON either */
    remove_dir(dir);
    fresh_dir(dir, sizeof dir, "run");
    TEST_ASSERT(end_fails(s, dir, "sediment.csv", "sediment.csv.tmp"));
    TEST_ASSERT(kept(dir, "sediment.csv"));
    TEST_ASSERT(!exists(dir, "sediment.json") && !exists(dir, "sediment.json.tmp"));
    /* the JSON cannot be renamed into place; the CSV is complete */
    remove_dir(dir);
    fresh_dir(dir, sizeof dir, "run");
    TEST_ASSERT(end_fails(s, dir, "sediment.json", "sediment.json.tmp"));
    TEST_ASSERT(kept(dir, "sediment.json"));
    TEST_ASSERT(exists(dir, "sediment.csv") && !exists(dir, "sediment.csv.tmp"));
    /* the JSON's temporary cannot be opened: the previous sediment.json stays as it was */
    remove_dir(dir);
    fresh_dir(dir, sizeof dir, "run");
    char path[512];
    snprintf(path, sizeof path, "%s/sediment.json", dir);
    FILE *old = fopen(path, "w");
    TEST_ASSERT(old && fputs("old\n", old) >= 0 && fclose(old) == 0);
    TEST_ASSERT(end_fails(s, dir, "sediment.json.tmp", "sediment.json.tmp"));
    TEST_ASSERT(first_line(dir, "sediment.json", line, sizeof line) == 0);
    TEST_ASSERT(strcmp(line, "old\n") == 0);
    /* a run that never ends: freeing the scene leaves neither the CSV nor its .tmp */
    remove_dir(dir);
    fresh_dir(dir, sizeof dir, "run");
    TEST_ASSERT(dir[0] && app_sediment_begin(s, dir, err, sizeof err) == 0);
    scene_free(scene);
    TEST_ASSERT(!exists(dir, "sediment.csv.tmp") && !exists(dir, "sediment.csv"));
    remove_dir(dir);
    return 0;
}

/* STAGE.fluid.csv at a stage's end. */
static int sediment_stage_profile(void)
{
    char dir[256], err[1024] = "", expected[600], line[256];
    fresh_dir(dir, sizeof dir, "stage");
    TEST_ASSERT(dir[0]);
    Scene *scene = sediment_scene();
    TEST_ASSERT(scene);
    TEST_ASSERT(
        app_sediment_stage_end(app_sediment_of(scene), NULL, dir, "flow", err, sizeof err) == 0);
    TEST_ASSERT(first_line(dir, "flow.fluid.csv", line, sizeof line) == 0);
    TEST_ASSERT(strcmp(line, "y,u,phi,grain_vx,tau_fluid,grain_load,tau_total\n") == 0);
    TEST_ASSERT(!exists(dir, "flow.fluid.csv.tmp"));
    TEST_ASSERT(block(dir, "settle.fluid.csv") == 0);
    TEST_ASSERT(
        app_sediment_stage_end(app_sediment_of(scene), NULL, dir, "settle", err, sizeof err) == -1);
    snprintf(expected, sizeof expected, "cannot write %s/settle.fluid.csv.tmp", dir);
    TEST_ASSERT(strcmp(err, expected) == 0);
    TEST_ASSERT(kept(dir, "settle.fluid.csv"));
    scene_free(scene);
    remove_dir(dir);
    return 0;
}

/* `sablier sediment`: flux.csv and threshold.json after the members, first with nothing in the
 * way, then with each blocked in turn. The member fails at once: its folder name is a file. */
static int sediment_scan_outputs(void)
{
    static const char *const blocked[] = {NULL, "flux.csv", "threshold.json"};
    for (int k = 0; k < 3; ++k) {
        char dir[256], member[512], line[256];
        fresh_dir(dir, sizeof dir, "scan");
        snprintf(member, sizeof member, "%s/shields=0.1", dir);
        FILE *f = dir[0] ? fopen(member, "w") : NULL;
        TEST_ASSERT(f && fclose(f) == 0);
        TEST_ASSERT(!blocked[k] || block(dir, blocked[k]) == 0);
        char *argv[] = {"sablier", "sediment", SEDIMENT_SCENE, "--shields", "0.1", "--jobs",
                        "1",       "--quiet",  "--out",        dir,         NULL};
        TEST_ASSERT(app_sediment_command((int)(sizeof argv / sizeof argv[0]) - 1, argv, NULL) == 1);
        TEST_ASSERT(!exists(dir, "flux.csv.tmp") && !exists(dir, "threshold.json.tmp"));
        if (k == 1) {
            TEST_ASSERT(kept(dir, "flux.csv") && !exists(dir, "threshold.json"));
        } else {
            TEST_ASSERT(first_line(dir, "flux.csv", line, sizeof line) == 0);
            TEST_ASSERT(strcmp(line, "shields,q_sat,q_sat_star,t_sat,transport,status\n") == 0);
            TEST_ASSERT(k == 2 ? kept(dir, "threshold.json")
                               : first_line(dir, "threshold.json", line, sizeof line) == 0);
        }
        remove_dir(dir);
    }
    return 0;
}

/* `sablier sweep`: sweep.csv after the members (here /bin/true: no run, status 0). */
static int sweep_table(void)
{
    char dir[256], line[256];
    fresh_dir(dir, sizeof dir, "sweep");
    TEST_ASSERT(dir[0]);
    const char *vary[] = {"seed=1,2"};
    AppCraterSweepOptions o = app_crater_sweep_options_default();
    o.self = "/bin/true";
    o.scene_path = CRATER_SCENE;
    /* a real checkpoint (--from is read whole before anything runs); the members do not load it */
    o.from = "tests/fuzz/corpus/state/drop_elastic.state";
    o.out_dir = dir;
    o.jobs = 1;
    o.quiet = 1;
    o.vary = vary;
    o.vary_count = 1;
    TEST_ASSERT(app_crater_sweep(&o) == 0);
    TEST_ASSERT(first_line(dir, "sweep.csv", line, sizeof line) == 0);
    TEST_ASSERT(strncmp(line, "member,label,value,status,crater_height_m,", 42) == 0);
    TEST_ASSERT(!exists(dir, "sweep.csv.tmp"));
    remove_dir(dir);
    fresh_dir(dir, sizeof dir, "sweep");
    TEST_ASSERT(dir[0] && block(dir, "sweep.csv") == 0);
    TEST_ASSERT(app_crater_sweep(&o) == 2);
    TEST_ASSERT(kept(dir, "sweep.csv"));
    remove_dir(dir);
    return 0;
}

TEST_MAIN(TEST_CASE(sediment_run_outputs), TEST_CASE(sediment_stage_profile),
          TEST_CASE(sediment_scan_outputs), TEST_CASE(sweep_table))
