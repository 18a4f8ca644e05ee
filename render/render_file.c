/* SPDX-License-Identifier: MIT */
/* render_file.c: the temporary-name-then-rename tail shared by the PNG and PDF/SVG writers. */
#include "render/render_file.h"

#include "sim/sim.h"

#include <errno.h>
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
