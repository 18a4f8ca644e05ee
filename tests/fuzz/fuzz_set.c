/* SPDX-License-Identifier: MIT */
/* fuzz_set: scene_load with `--set KEY=VALUE` overrides. The input is the overrides, one a line,
 * then a NUL byte, then the scene text; the scene loaded with them must come back or be refused
 * with a message, never crash, leak, hang or allocate without bound. */
#include "fuzz_input.h"

#include "base/util.h"
#include "scene/scene.h"

#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const uint8_t *nul = memchr(data, 0, size);
    if (!nul)
        return 0; /* no scene part */
    size_t set_size = (size_t)(nul - data);
    const char *path = fuzz_input_file(nul + 1, size - set_size - 1, ".scene");
    char *text = malloc(set_size + 1);
    if (!path || !text) {
        free(text);
        return 0;
    }
    memcpy(text, data, set_size);
    text[set_size] = '\0';
    const char *sets[APP_MAX_SETS];
    int count = 0;
    for (char *line = strtok(text, "\n"); line && count < APP_MAX_SETS; line = strtok(NULL, "\n"))
        sets[count++] = line;
    char err[4096] = "";
    Scene *scene = scene_load(path, sets, count, err, sizeof err);
    if (!scene && !err[0])
        abort(); /* a refusal always says why */
    scene_free(scene);
    free(text);
    unlink(path);
    return 0;
}
