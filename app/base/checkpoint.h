/* SPDX-License-Identifier: MIT */
/* checkpoint.h: what the runner's writers and the experiment families keep across a --resume
 * (docs/cli.md#periodic-checkpoints-and---resume). Each keeps a section of DIR/checkpoint.txt,
 * the record of the newest checkpoint, written whole through a temporary name and renamed, so
 * that the world's state and every section always belong to the same step:
 *
 *     begin crater
 *     crater 0x1.4p+3 0x0p+0            <- app_checkpoint_put: KEY and numbers, doubles in %a
 *     file profile.csv 18342            <- app_checkpoint_file: an append file and its length
 *     end crater
 *
 * Numbers are doubles written in hexadecimal, so that they read back to the bit; integers up to
 * 2^53 are exact as doubles, so one writer serves counters, flags and lengths too. */
#ifndef APP_CHECKPOINT_H
#define APP_CHECKPOINT_H

#include <stdio.h>

/// Writes the line `KEY v0 v1 ...` (n values, %a).
void app_checkpoint_put(FILE *out, const char *key, const double *v, long n);
/// Reads the n values of the line `KEY ...` of a section. 0, or -1 (no such line, too few values).
int app_checkpoint_take(const char *record, const char *key, double *v, long n);
/// The bytes written to an output so far (flushed), or -1 without the file (NULL).
long app_checkpoint_bytes(FILE *file);
/// A record read whole (malloc'd, NUL-ended), or NULL (errno set).
char *app_checkpoint_read(const char *path);
/// Writes `file NAME BYTES` for an append file open as PATH.tmp (NAME: the last part of path):
/// the bytes written to it so far (flushed).
void app_checkpoint_file(FILE *out, const char *path, FILE *file);
/// The append file of path continued at its checkpoint: closes *file (a fresh PATH.tmp) and
/// opens PATH.tmp holding the first BYTES bytes the section records for it, taken from PATH.tmp
/// or PATH. 0, or -1 (no record of it, or the file is shorter).
int app_checkpoint_reopen(const char *record, const char *path, FILE **file);
/// Before the files are opened again on --resume: every `file NAME BYTES` of the record whose
/// DIR/NAME.tmp holds the bytes (a run killed before it committed) is renamed to DIR/NAME, so
/// that a writer that opens its PATH.tmp afresh does not lose them.
void app_checkpoint_keep_files(const char *record, const char *dir);
/// PATH.tmp opened holding the first `bytes` bytes of PATH.tmp (when it holds them) or of PATH.
/// NULL (errno set) when neither does or on a write error.
FILE *app_tmp_reopen(const char *path, long bytes);

#endif
