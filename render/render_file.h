/* SPDX-License-Identifier: MIT */
/* render_file.h: figures and images are written to PATH.tmp and renamed when complete, so a
 * failed write never leaves a half-written PATH or a stray PATH.tmp; a file name's format; the
 * error messages. Not part of the public API. */
#ifndef RENDER_FILE_H
#define RENDER_FILE_H

#include <stddef.h>

/// PATH.tmp in a new buffer, made anew as an empty regular file (sim_open_output: PATH refused
/// unless it is a regular file or absent), or NULL with "PATH: reason" in err.
char *render_tmp_name(const char *path, char *err, size_t err_size);
/// Finishes a write through `tmp` (from render_tmp_name, freed here): `ok` renames it to PATH,
/// else it is removed (the caller has written the message). A failed rename removes it too and
/// writes "TMP: cannot rename to PATH: reason" in err. 0, or -1.
int render_tmp_commit(char *tmp, const char *path, int ok, char *err, size_t err_size);
/// 1 when path ends in "." ext (ext without its dot, compared without case), else 0.
int render_has_extension(const char *path, const char *ext);
/// printf-style message into err[size] (nothing when err is NULL or size 0).
void render_set_err(char *err, size_t size, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

#endif
