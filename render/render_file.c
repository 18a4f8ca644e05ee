/* SPDX-License-Identifier: MIT */
/* render_file.c: the temporary-name-then-rename tail shared by the PNG and PDF/SVG writers, a
 * file name's format and the error message of every writer and reader. */

#include "render/internal.h"
#include "sim/sim.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

char *render_tmp_name(const char *path, char *err, size_t err_size)
{
    size_t n = strlen(path) + 5;
    char *tmp = malloc(n);
    const char *why = "out of memory";
    FILE *fresh = tmp ? sim_open_output(path, &why) : NULL;
    if (fresh) {
        fclose(fresh);
        snprintf(tmp, n, "%s.tmp", path);
        return tmp;
    }
    if (err && err_size)
        snprintf(err, err_size, "%s: %s", path, why);
    free(tmp);
    return NULL;
}

int render_tmp_commit(char *tmp, const char *path, int ok, char *err, size_t err_size)
{
    if (ok && rename(tmp, path) != 0) {
        if (err && err_size)
            snprintf(err, err_size, "%s: cannot rename to %s: %s", tmp, path, strerror(errno));
        ok = 0;
    }
    if (!ok)
        remove(tmp);
    free(tmp);
    return ok ? 0 : -1;
}

int render_has_extension(const char *path, const char *ext)
{
    const char *dot = strrchr(path, '.');
    if (!dot)
        return 0;
    ++dot;
    size_t n = strlen(ext);
    if (strlen(dot) != n)
        return 0;
    for (size_t k = 0; k < n; ++k)
        if (tolower((unsigned char)dot[k]) != ext[k])
            return 0;
    return 1;
}

void render_set_err(char *err, size_t size, const char *fmt, ...)
{
    if (!err || size == 0)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, size, fmt, ap);
    va_end(ap);
}
