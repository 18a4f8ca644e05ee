/* SPDX-License-Identifier: MIT */
/* util.h: small helpers shared by the app/ modules (output files, command options, comma lists).
 * The typed scene-file getters are config.h. */
#ifndef APP_UTIL_H
#define APP_UTIL_H

#include <stddef.h>
#include <stdio.h>

/// Output files are written to PATH.tmp and renamed when complete. Opens PATH.tmp for writing and
/// writes `header` and a newline when not NULL; NULL when it cannot be opened, or when PATH is
/// not a regular file (a link or a special file is never replaced: sim_open_output, errno set).
FILE *app_tmp_open(const char *path, const char *header);
/// Closes *file (NULL: nothing to do, 0) and renames PATH.tmp to PATH (noted: app_output_note);
/// on failure removes PATH.tmp and returns -1.
int app_tmp_commit(FILE **file, const char *path);
/// Notes that this process wrote the output PATH (committed under that name): every writer of
/// an output folder's files calls it (app_tmp_commit does), and the folder's manifest lists
/// what was noted under the folder (app_manifest_write), nothing else.
void app_output_note(const char *path);
/// The k-th output noted (from 0, in the order noted, repeats included), or NULL past the last.
const char *app_output_committed(int k);
/// Closes *file (NULL: nothing to do) and removes PATH.tmp: an output abandoned before it was
/// complete leaves nothing behind.
void app_tmp_discard(FILE **file, const char *path);
/// Writes `text` to PATH through PATH.tmp. 0, or -1.
int app_write_atomic(const char *path, const char *text);
/// 1 once an output failed because the disk (or the quota) was full (ENOSPC, EDQUOT).
int app_out_of_space(void);
/// After a failed write reported as `message`: 1 when it failed for lack of space
/// (app_out_of_space, errno as the failing call left it, or `message` naming ENOSPC or EDQUOT),
/// which a command reports with exit status 3 (APP_EXIT_DISK_FULL), not 2.
int app_failed_for_space(const char *message);
/// Exit status of a run whose outputs could not be written because the disk or the quota was
/// full: no truncated file is left under a final name, and the message names the first one.
#define APP_EXIT_DISK_FULL 3

/// Doubles the capacity (first: `initial`) of two parallel arrays, e.g. a time series t and v.
/// 0, or -1 when out of memory (the arrays keep their contents).
int app_series_grow(double **t, double **v, int *capacity, int initial);

/// At most this many --set options on one command line.
#define APP_MAX_SETS 64

/// The longest name (of a stage, a species, a source) and path the app holds; the scene's bounds
/// SCENE_NAME_MAX and SCENE_PATH_MAX (app/scene/scene.h) are these.
#define APP_NAME_MAX 64
#define APP_PATH_MAX 1024

/// `--set KEY=VALUE` or `--unset KEY` at argv[*i] (*i moves past its value), appended to
/// sets[*count] (capacity max) in command-line order: an --unset's entry is its KEY alone (no
/// `=`; scene_load removes it). 1 when taken, 0 when argv[*i] is neither, -1 after a message
/// on stderr (no value, --set without `=`, --unset with one, the list full).
int app_set_option(int argc, char **argv, int *i, const char **sets, int *count, int max);

/// The option that gives a sets[] entry on a command line: "--set", or "--unset" for a KEY alone.
const char *app_set_option_name(const char *entry);

/// A decimal integer in [min, max]: 0 and *out, or -1.
int app_parse_count(const char *text, long min, long max, long *out);

/// The items of a comma list, one at a time: the next item of *list (up to a comma or the end),
/// its length in *length, and *list moved past it and its comma; NULL at the end. Every comma
/// separates two items, so ",,", a leading and a trailing comma give empty items (length 0),
/// which every list refuses (an empty string is one empty item).
const char *app_list_item(const char **list, size_t *length);

/// How app_parse_numbers reads a list (the drivers' lists differ in these, as they always have).
typedef struct AppNumberList {
    double min; ///< smallest value accepted (-INFINITY: any finite number)
    int strict; ///< 1: a value strtod finds out of range (ERANGE: 1e-400) is malformed
    int exact;  ///< 1: more than max values is malformed; 0: the first max are read
} AppNumberList;

/// A comma list of finite numbers (each item all of one strtod number) into at most `max`
/// values: the count (0 for an empty string), or -1 when malformed (an empty item: "1,,2",
/// "1,2,", ",1").
int app_parse_numbers(const char *text, const AppNumberList *how, double *values, int max);

/// A `KEY=v1,v2,...` list of numbers: the key into key[key_size] and at most `max` values (the
/// first max; app_parse_numbers, empty items malformed). Returns the number of values, or -1
/// when malformed (no '=', empty key, a value that is not a finite number).
int app_parse_key_values(const char *text, char *key, size_t key_size, double *values, int max);

/// mkdir -p; 0 on success.
int app_make_dirs(const char *path);

/// Reads the checkpoint at `path` whole (sim_state_load), so that a bad file is refused before
/// anything runs. With `def` (not NULL, the scene that will load it), its grains must fit the
/// scene (each species below def->species_count, each motion below def->motion_count, -1: none)
/// and its walls must be def's walls, in order, motions included (a stage that loads a
/// checkpoint keeps its walls). 0, or -1 with why in err ("cannot read checkpoint `PATH`:
/// reason", or "checkpoint `PATH`: " and the first thing wrong).
struct SimWorldDef;
int app_state_check(const char *path, const struct SimWorldDef *def, char *err, size_t err_size);

struct sigaction;
/// SIGINT and SIGTERM to `handler` with sa_flags `flags` (restore = 0; the old actions into
/// saved[0] and saved[1]), or the old actions back from them (restore = 1). The runner and the
/// process pool catch the two signals through it.
void app_catch_signals(void (*handler)(int), int flags, struct sigaction *saved, int restore);

/// The signal (SIGINT or SIGTERM) that asked the run in progress to stop, 0 while none: every
/// loop of the run over a size the user gives (a source's insertion attempts) looks at it, so
/// that it ends within one step of the signal.
int app_run_signal(void);

/// Clears the run's signal and catches SIGINT and SIGTERM for app_run_signal (restore 0; the
/// old handlers into saved[0..1]), or puts the old handlers back (restore 1). The handler is reset
/// by the first signal (SA_RESETHAND): a second one kills.
void app_run_signal_catch(struct sigaction *saved, int restore);

struct SimWorld;
struct SimError;
/// sim_world_save to PATH (an output: noted with app_output_note once saved). 0, or -1 with the
/// reason in *error.
int app_state_save(struct SimWorld *world, const char *path, struct SimError *error);

/// Writes "sablier: MESSAGE ARG" and the usage text to stderr; returns 2 (bad command line).
int app_usage_error(const char *usage, const char *message, const char *arg);

/// The rest of a command line of the form `COMMAND [options] SCENE`: an argument that no option
/// took. An unknown option or a second scene is a usage error (returns 2, message on stderr);
/// else *scene = arg and 0.
int app_scene_argument(const char *usage, const char *arg, const char **scene);

/// Command-line option NAME with a value, as "NAME VALUE" or "NAME=VALUE". Returns 1 and sets
/// *value when argv[*i] is that option (advancing *i past a separate value), 0 when it is not,
/// -1 (message on stderr) when the value is missing.
int app_option(int argc, char **argv, int *i, const char *name, const char **value);

#endif
