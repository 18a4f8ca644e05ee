/* SPDX-License-Identifier: MIT */
/* checkpoint.c: the sections of a checkpoint record (checkpoint.h). */
#include "base/checkpoint.h"

#include "base/util.h"
#include "sim/sim.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

void app_checkpoint_put(FILE *out, const char *key, const double *v, long n)
{
    fputs(key, out);
    for (long k = 0; k < n; ++k)
        fprintf(out, " %a", v[k]);
    fputc('\n', out);
}

/* The text after `KEY ` of the line that starts with KEY, or NULL. */
static const char *find_line(const char *record, const char *key)
{
    size_t n = strlen(key);
    for (const char *line = record; line && *line;) {
        if (strncmp(line, key, n) == 0 && (line[n] == ' ' || line[n] == '\n' || !line[n]))
            return line + n;
        line = strchr(line, '\n');
        line = line ? line + 1 : NULL;
    }
    return NULL;
}

int app_checkpoint_take(const char *record, const char *key, double *v, long n)
{
    const char *p = record ? find_line(record, key) : NULL;
    if (!p)
        return -1;
    for (long k = 0; k < n; ++k) {
        char *end;
        while (*p == ' ')
            ++p;
        if (*p == '\n' || !*p)
            return -1;
        v[k] = strtod(p, &end); /* reads %a (and nan, inf) back to the bit */
        if (end == p)
            return -1;
        p = end;
    }
    return 0;
}

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

long app_checkpoint_bytes(FILE *file)
{
    return file && fflush(file) == 0 ? ftell(file) : -1;
}

char *app_checkpoint_read(const char *path)
{
    FILE *f = sim_open_input(path, NULL);
    long size = f && fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    char *text = size >= 0 && fseek(f, 0, SEEK_SET) == 0 ? malloc((size_t)size + 1) : NULL;
    if (text && fread(text, 1, (size_t)size, f) != (size_t)size) {
        free(text);
        text = NULL;
    }
    if (text)
        text[size] = '\0';
    if (f)
        fclose(f);
    return text;
}

void app_checkpoint_file(FILE *out, const char *path, FILE *file)
{
    fprintf(out, "file %s %ld\n", base_name(path), app_checkpoint_bytes(file));
}

/* The recorded length of NAME in a section, or -1. */
static long file_bytes(const char *record, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = record; p && (p = strstr(p, "file ")) != NULL; p += 5) {
        if ((p == record || p[-1] == '\n') && strncmp(p + 5, name, n) == 0 && p[5 + n] == ' ')
            return strtol(p + 6 + n, NULL, 10);
    }
    return -1;
}

FILE *app_tmp_reopen(const char *path, long bytes)
{
    size_t size = strlen(path) + 8;
    char *tmp = malloc(size);
    char *text = malloc((size_t)(bytes > 0 ? bytes : 0) + 1);
    FILE *out = NULL;
    errno = 0;
    if (tmp && text && bytes >= 0) {
        snprintf(tmp, size, "%s.tmp", path);
        const char *from[2] = {tmp, path};
        for (int k = 0; k < 2 && !out; ++k) {
            FILE *f = sim_open_input(from[k], NULL);
            size_t got = f ? fread(text, 1, (size_t)bytes, f) : 0;
            if (f)
                fclose(f);
            if (f && got == (size_t)bytes)
                out = app_tmp_open(path, NULL);
        }
        if (out && fwrite(text, 1, (size_t)bytes, out) != (size_t)bytes) {
            fclose(out);
            out = NULL;
        }
        if (!out && errno == 0)
            errno = ENOENT;
    }
    free(tmp);
    free(text);
    return out;
}

int app_checkpoint_reopen(const char *record, const char *path, FILE **file)
{
    long bytes = record ? file_bytes(record, base_name(path)) : -1;
    if (*file)
        fclose(*file); /* the fresh PATH.tmp a begin hook opened: rewritten below */
    *file = bytes >= 0 ? app_tmp_reopen(path, bytes) : NULL;
    return *file ? 0 : -1;
}

void app_checkpoint_keep_files(const char *record, const char *dir)
{
    for (const char *p = record; p && (p = strstr(p, "file ")) != NULL; p += 5) {
        char name[256], path[4096], tmp[4104];
        long bytes;
        if ((p != record && p[-1] != '\n') || sscanf(p, "file %255s %ld", name, &bytes) != 2 ||
            strchr(name, '/') || bytes < 0)
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, name);
        snprintf(tmp, sizeof tmp, "%s.tmp", path);
        FILE *f = sim_open_input(tmp, NULL);
        long size = f && fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
        if (f)
            fclose(f);
        if (size >= bytes)
            rename(tmp, path);
    }
}
