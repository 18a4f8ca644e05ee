/* SPDX-License-Identifier: MIT */
/* fuzz_grains: app_grains_read (`grains.file`: a CSV with named columns, or a LAMMPS text dump)
 * on any bytes must append grains or refuse with a "file:line: message", never crash, leak, hang
 * or allocate without bound. */
#include "fuzz_input.h"

#include "scene/grains_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_input_file(data, size, ".csv");
    if (!path)
        return 0;
    SimGrainBuffer buffer;
    sim_grain_buffer_init(&buffer);
    char err[4096] = "";
    int has_ids = -1;
    if (app_grains_read(path, 3, &buffer, &has_ids, err, sizeof err) != 0 && !err[0])
        abort(); /* a refusal always says why */
    sim_grain_buffer_free(&buffer);
    unlink(path);
    return 0;
}
