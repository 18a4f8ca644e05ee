/* SPDX-License-Identifier: MIT */
/* test_command_parse: every command's parse-only entry point (AppCommand.parse, export's and
 * ensemble's), which tests/fuzz/fuzz_cli.c calls on any argument list: 0 for a good command
 * line, 2 for a bad one, and nothing read, made or run either way. */
#include "test.h"

#include "base/experiments.h"
#include "driver/ensemble.h"
#include "output/dump.h"

#include <sys/stat.h>
#include <unistd.h>

typedef struct ParseCase {
    const char *command; /* a family command, or "export", "ensemble" */
    const char *args[8]; /* after `sablier COMMAND`, NULL-ended; "OUT" is the output folder */
    int status;
} ParseCase;

static int parse(const ParseCase *c, const char *out)
{
    static char text[12][128];
    char *argv[12];
    int argc = 0;
    snprintf(text[argc++], sizeof text[0], "sablier");
    snprintf(text[argc++], sizeof text[0], "%s", c->command);
    for (int k = 0; c->args[k]; ++k, ++argc)
        snprintf(text[argc], sizeof text[0], "%s",
                 strcmp(c->args[k], "OUT") == 0 ? out : c->args[k]);
    for (int k = 0; k < argc; ++k)
        argv[k] = text[k];
    argv[argc] = NULL;
    if (strcmp(c->command, "export") == 0)
        return app_dump_export_parse(argc, argv);
    if (strcmp(c->command, "ensemble") == 0)
        return app_ensemble_parse(argc, argv);
    const AppCommand *command = app_experiment_command(c->command);
    return command && command->parse ? command->parse(argc, argv) : -1;
}

static int command_parse_only(void)
{
    for (int f = 0; app_experiments[f]; ++f) /* every family command has one */
        for (int k = 0; k < app_experiments[f]->command_count; ++k)
            TEST_ASSERT(app_experiments[f]->commands[k].parse != NULL);
    static const ParseCase cases[] = {
        {"bne", {"scenes/brazil_nut/small.scene", "--seeds", "2", "--out", "OUT"}, 0},
        {"bne", {"scenes/brazil_nut/small.scene", "--seeds", "0", "--out", "OUT"}, 2},
        {"sweep", {"scenes/crater/sweeps/mu.sweep", "--jobs", "2", "--out", "OUT"}, 0},
        {"sweep", {"scenes/crater/sweeps/mu.sweep", "--jobs", "65", "--out", "OUT"}, 2},
        {"discharge", {"scenes/discharge/poly.scene", "--width", "3", "--out", "OUT"}, 0},
        {"discharge", {"scenes/discharge/poly.scene", "--width", "-1", "--out", "OUT"}, 2},
        {"study", {"scenes/discharge/poly.scene", "--widths", "1:3:1", "--out", "OUT"}, 0},
        {"study", {"scenes/discharge/poly.scene", "--samples", "0", "--out", "OUT"}, 2},
        {"sediment", {"scenes/sediment/viscous.scene", "--shields", "0.1,0.8", "--out", "OUT"}, 0},
        {"sediment", {"scenes/sediment/viscous.scene", "--out", "OUT"}, 2},
        {"ensemble",
         {"scenes/brazil_nut/small.scene", "--dt", "1e-5,2e-5", "--observe", "x", "--out", "OUT"},
         0},
        {"ensemble", {"scenes/brazil_nut/small.scene", "--dt", "1e-5,2e-5", "--out", "OUT"}, 2},
        {"export", {"OUT", "-o", "OUT"}, 2}, /* no format from the name */
        {"export", {"missing.state", "--format", "csv", "-o", "OUT"}, 0},
    };
    char out[96];
    snprintf(out, sizeof out, "/tmp/sablier_test_parse_%ld", (long)getpid());
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        int status = parse(&cases[k], out);
        if (status != cases[k].status)
            fprintf(stderr, "case %zu (%s): status %d\n", k, cases[k].command, status);
        TEST_ASSERT(status == cases[k].status);
        struct stat st;
        TEST_ASSERT(stat(out, &st) != 0); /* nothing made */
    }
    return 0;
}

TEST_MAIN(TEST_CASE(command_parse_only))
