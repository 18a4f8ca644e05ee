/* SPDX-License-Identifier: MIT */
/* provenance.h: how an output folder was made (docs/cli.md "Provenance"): the command line, the
 * --set overrides, the scene file's SHA-256 and its resolved copy, the source revision, the date,
 * host and CPU; and the folder's manifest, which lets the next run into it remove what this one
 * wrote. */
#ifndef APP_PROVENANCE_H
#define APP_PROVENANCE_H

#include "base/sha256.h"

#include <stddef.h>
#include <stdint.h>
#include <time.h>

/// A JSON string literal (quotes, escapes) of text into out[size]; cut to fit.
void app_json_string(char *out, size_t size, const char *text);
/// A double as JSON (%.10g; NaN and infinities have no JSON form: null).
void app_json_number(char *out, size_t size, double v);

/// What a run records of its making.
typedef struct AppProvenance {
    int argc; ///< the command line (0: not known, e.g. a library caller)
    char *const *argv;
    const char *const *sets; ///< the --set overrides, in order
    int set_count;
    const char *revision; ///< version control revision of the build, or NULL/""
    const char *out_dir;  ///< the output folder: absolute paths recorded relative to it
} AppProvenance;

/// The command line as recorded (docs/cli.md "Provenance"): argv[0] as `sablier`; an absolute
/// path (an argument, or the value after `=`) relative to the output folder when inside it (`.`
/// for the folder), else relative to the working directory when inside it, else its last
/// component; so no machine path lands in an output file. Returns the length written.
size_t app_provenance_command(const AppProvenance *p, char *out, size_t size);
/// One path as app_provenance_command records it (a relative path is kept as given).
void app_provenance_path(const AppProvenance *p, const char *path, char *out, size_t size);
/// The date of a run as recorded: SOURCE_DATE_EPOCH when set (reproducible builds), else the
/// clock; UTC, ISO 8601. 1 when it came from SOURCE_DATE_EPOCH.
int app_provenance_date(char *out, size_t size);
/// The last member `"provenance": {...}\n` of summary.json (scene_sha256 and resolved file given
/// by the caller). Returns the length written (cut to size).
size_t app_provenance_json(const AppProvenance *p, const char *scene_sha256,
                           const char *resolved_name, char *out, size_t size);
/// The same on one line for a figure's text chunk or metadata ("command: ...; scene sha256: ...;
/// ..."): no date unless SOURCE_DATE_EPOCH sets one, so that two runs write the same bytes.
void app_provenance_comment(const AppProvenance *p, const char *scene_sha256, char *out,
                            size_t size);

/// The manifest of an output folder: the files this process wrote under dir (the outputs noted
/// by app_output_note, e.g. through app_tmp_commit) that are regular files there now, as
/// relative paths one per line, sorted, into dir/manifest.txt (atomically). Nothing else: a file
/// the run did not write is never listed. keep_listed: the files dir/manifest.txt lists already
/// (still regular files) stay listed too (a resumed run, which continues that run). 0, or -1.
int app_manifest_write(const char *dir, int keep_listed);
/// Removes the files a previous run listed in dir/manifest.txt, and the manifest itself: only
/// regular files inside dir (relative paths without ".."; no link is followed on the way, a
/// listed link, FIFO or device is left alone; `keep` paths, e.g. the scene and the states this
/// run loads, are kept). Returns the number removed; -1 with a message in err when a listed
/// file cannot be removed.
int app_manifest_remove_stale(const char *dir, const char *const *keep, int keep_count, char *err,
                              size_t err_size);

#endif
