/* SPDX-License-Identifier: MIT */
/* test_run_value.c: numbers read from a run's folder by key (app/driver/run_value.h): dotted JSON
 * paths through objects, arrays, strings with braces and nulls; a key,value CSV table's row;
 * another table's column of its last row; keys of a bad form refused. */
#include "test.h"

#include "driver/run_value.h"

#include <stdlib.h>
#include <unistd.h>

static const char SUMMARY[] =
    "{\n  \"scene\": \"a {tricky} \\\"name\\\", [x]\",\n  \"seed\": 7,\n"
    "  \"bed\": {\"coordination\": 3.5, \"hexatic_order\": null},\n"
    "  \"crater\": {\"crater_height\": -0.125, \"removed\": 12},\n"
    "  \"stages\": [\n    {\"name\": \"deposit\", \"end_time\": 2.5},\n"
    "    {\"name\": \"collapse\", \"end_time\": 4e-1, \"sinks\": [1, 2, [3, 4]]}\n  ],\n"
    "  \"ok\": true\n}\n";

static int run_value_json_paths(void)
{
    double v;
    TEST_ASSERT(app_json_path_number(SUMMARY, "seed", &v) == 0 && v == 7.0);
    TEST_ASSERT(app_json_path_number(SUMMARY, "crater.crater_height", &v) == 0 && v == -0.125);
    TEST_ASSERT(app_json_path_number(SUMMARY, "bed.coordination", &v) == 0 && v == 3.5);
    TEST_ASSERT(app_json_path_number(SUMMARY, "stages.1.end_time", &v) == 0 && v == 0.4);
    TEST_ASSERT(app_json_path_number(SUMMARY, "stages.0.end_time", &v) == 0 && v == 2.5);
    TEST_ASSERT(app_json_path_number(SUMMARY, "stages.1.sinks.2.1", &v) == 0 && v == 4.0);
    TEST_ASSERT(app_json_path_number(SUMMARY, "bed.hexatic_order", &v) == 1 && isnan(v));
    TEST_ASSERT(app_json_path_number(SUMMARY, "scene", &v) == -1);  /* a string */
    TEST_ASSERT(app_json_path_number(SUMMARY, "ok", &v) == -1);     /* a bool */
    TEST_ASSERT(app_json_path_number(SUMMARY, "crater", &v) == -1); /* an object */
    TEST_ASSERT(app_json_path_number(SUMMARY, "stages.2.end_time", &v) == -1);
    TEST_ASSERT(app_json_path_number(SUMMARY, "crater.height", &v) == -1);
    TEST_ASSERT(app_json_path_number(SUMMARY, "stages.x", &v) == -1);
    TEST_ASSERT(app_json_path_number("{\"a\": {\"b\": 1}", "a.c", &v) == -1); /* cut short */
    return 0;
}

static int write_text(const char *dir, const char *name, const char *text)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fputs(text, f);
    return fclose(f);
}

static int run_value_folder(void)
{
    char dir[] = "/tmp/sablier-run-value-XXXXXX", err[512];
    TEST_ASSERT(mkdtemp(dir) != NULL);
    TEST_ASSERT(write_text(dir, "summary.json", SUMMARY) == 0);
    TEST_ASSERT(write_text(dir, "observables.csv",
                           "key,value\nbed_coordination,3.25\ncrater_height_m,-0.5\nempty,\n") ==
                0);
    TEST_ASSERT(
        write_text(dir, "energy.csv", "t,t_star,e_kin,e_pot\n0,0,1.5,2\n0.5,1,0.75,nan\n\n") == 0);
    double v;
    TEST_ASSERT(app_run_value(dir, "crater.crater_height", &v, err, sizeof err) == 0 &&
                v == -0.125);
    TEST_ASSERT(app_run_value(dir, "summary.json:stages.1.end_time", &v, err, sizeof err) == 0 &&
                v == 0.4);
    TEST_ASSERT(app_run_value(dir, "observables.csv:crater_height_m", &v, err, sizeof err) == 0 &&
                v == -0.5);
    TEST_ASSERT(app_run_value(dir, "observables.csv:empty", &v, err, sizeof err) == 1 && isnan(v));
    TEST_ASSERT(app_run_value(dir, "energy.csv:e_kin", &v, err, sizeof err) == 0 && v == 0.75);
    TEST_ASSERT(app_run_value(dir, "energy.csv:e_pot", &v, err, sizeof err) == 1 && isnan(v));
    TEST_ASSERT(app_run_value(dir, "energy.csv:e_rot", &v, err, sizeof err) == -1 &&
                strstr(err, "no column `e_rot`"));
    TEST_ASSERT(app_run_value(dir, "observables.csv:nope", &v, err, sizeof err) == -1 &&
                strstr(err, "no row `nope`"));
    TEST_ASSERT(app_run_value(dir, "crater.depth", &v, err, sizeof err) == -1 &&
                strstr(err, "no number at `crater.depth`"));
    TEST_ASSERT(app_run_value(dir, "bne.json:rise_time", &v, err, sizeof err) == -1 &&
                strstr(err, "cannot read"));
    static const char *const names[] = {"summary.json", "observables.csv", "energy.csv"};
    for (int k = 0; k < 3; ++k) {
        char path[256];
        snprintf(path, sizeof path, "%s/%s", dir, names[k]);
        remove(path);
    }
    TEST_ASSERT(rmdir(dir) == 0);
    return 0;
}

static int run_value_bad_keys(void)
{
    static const char *const bad[] = {
        "",          "a.json:", "/etc/x.json:a",  "../x.json:a", "sub/../x.csv:a",
        "log.txt:a", ".a",      "crater..height", "a.csv:b,c"};
    char err[512];
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k)
        if (app_run_value_check(bad[k], err, sizeof err) == 0) {
            fprintf(stderr, "key `%s` accepted\n", bad[k]);
            return 1;
        }
    static const char *const good[] = {"crater.crater_height", "bne.json:rise_time",
                                       "sub/energy.csv:e_kin", "trace.csv:y"};
    for (size_t k = 0; k < sizeof good / sizeof good[0]; ++k)
        TEST_ASSERT(app_run_value_check(good[k], err, sizeof err) == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(run_value_json_paths), TEST_CASE(run_value_folder),
          TEST_CASE(run_value_bad_keys))
