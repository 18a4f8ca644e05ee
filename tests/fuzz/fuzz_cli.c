/* SPDX-License-Identifier: MIT */
/* fuzz_cli: the command line of every `sablier` command (sablier_parse_arguments, app/cli/cli.h:
 * the checks each command makes before it reads, writes or starts anything). The input is the
 * arguments after `sablier`, one a line (the first names the command); the answer must be 0 or
 * a usage error's exit status 2, never a crash, a leak or a hang. Nothing is run. */
#include "cli/cli.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ARGS 64

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    static char name[] = "sablier";
    char *argv[MAX_ARGS + 2] = {name};
    int argc = 1;
    for (char *p = text; argc < MAX_ARGS && p <= text + size;) { /* lines, empty ones kept */
        char *end = strchr(p, '\n');
        if (end)
            *end = '\0';
        argv[argc++] = p;
        if (!end)
            break;
        p = end + 1;
    }
    argv[argc] = NULL;
    int status = sablier_parse_arguments(argc, argv);
    free(text);
    if (status != 0 && status != 2)
        abort(); /* a bad command line is exit status 2 */
    return 0;
}
