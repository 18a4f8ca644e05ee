/* SPDX-License-Identifier: MIT */
/* grains_file.h: grains from a file (`grains.file`, docs/scenes.md): a CSV with a header of named
 * columns, or a LAMMPS text dump. */
#ifndef APP_GRAINS_FILE_H
#define APP_GRAINS_FILE_H

#include "sim/sim.h"

#include <stddef.h>

/// Appends the file's grains to `buffer`; species must be below species_count. *has_ids: 1 when
/// the file gave ids (an `id` column). 0, or -1 with "path:line: message" in err.
int app_grains_read(const char *path, int species_count, SimGrainBuffer *buffer, int *has_ids,
                    char *err, size_t err_size);

#endif
