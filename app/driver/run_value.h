/* SPDX-License-Identifier: MIT */
/* run_value.h: one number from a run's output folder, named by a key (`sablier ensemble
 * --observe`, docs/cli.md). App core: knows the file formats sablier writes, not the families.
 *
 *     KEY = [FILE:]PATH        FILE relative to the folder, default summary.json
 *     FILE.json  PATH = members and array indices joined by dots: crater.crater_height,
 *                stages.2.end_time
 *     FILE.csv   a `key,value` table (observables.csv): the row PATH; any other table
 *                (energy.csv, trace.csv, discharge.csv): column PATH of the last row */
#ifndef APP_RUN_VALUE_H
#define APP_RUN_VALUE_H

#include <stddef.h>

/// Checks a key's form (a FILE ending .json or .csv, no absolute path or "..", a non-empty
/// PATH): 0, or -1 with why in err.
int app_run_value_check(const char *key, char *err, size_t err_size);

/// The number at `path` in the JSON text: 0 and *value; 1 when it is null (*value NaN); -1 when
/// there is no such member or it is not a number.
int app_json_path_number(const char *text, const char *path, double *value);

/// The number KEY names in folder `dir`: 0 and *value; 1 when it is null or empty (*value NaN);
/// -1 with why in err (no such file, member or column, not a number).
int app_run_value(const char *dir, const char *key, double *value, char *err, size_t err_size);

#endif
