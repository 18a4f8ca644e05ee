/* SPDX-License-Identifier: MIT */
/* fuzz_scene: scene_load on any bytes must return a scene or a "file:line: message", never crash,
 * leak, hang or allocate without bound. */
#include "fuzz_input.h"

#include "scene/scene.h"

#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_input_file(data, size, ".scene");
    if (!path)
        return 0;
    char err[4096] = "";
    Scene *scene = scene_load(path, NULL, 0, err, sizeof err);
    if (!scene && !err[0])
        abort(); /* a refusal always says why */
    scene_free(scene);
    unlink(path);
    return 0;
}
