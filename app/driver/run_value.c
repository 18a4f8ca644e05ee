/* SPDX-License-Identifier: MIT */
/* run_value.c: a number from a run's output folder by key (run_value.h). */
#include "driver/run_value.h"

#include "sim/sim.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define KEY_MAX 256

/* The key split at its first ':' into file (default summary.json) and path. 0, or -1. */
static int split_key(const char *key, char *file, size_t file_size, const char **path)
{
    const char *colon = strchr(key, ':');
    if (!colon) {
        snprintf(file, file_size, "summary.json");
        *path = key;
        return 0;
    }
    if ((size_t)(colon - key) >= file_size)
        return -1;
    snprintf(file, file_size, "%.*s", (int)(colon - key), key);
    *path = colon + 1;
    return 0;
}

static int ends_with(const char *text, const char *tail)
{
    size_t n = strlen(text), m = strlen(tail);
    return n > m && strcmp(text + n - m, tail) == 0;
}

int app_run_value_check(const char *key, char *err, size_t err_size)
{
    char file[KEY_MAX];
    const char *path;
    if (!key[0] || split_key(key, file, sizeof file, &path) != 0) {
        snprintf(err, err_size, "`%s`: expected [FILE:]PATH", key);
        return -1;
    }
    if (!path[0] || strchr(path, ',') || strchr(path, ':')) {
        snprintf(err, err_size, "`%s`: empty or malformed PATH after the file", key);
        return -1;
    }
    if (file[0] == '/' || strstr(file, "..") ||
        !(ends_with(file, ".json") || ends_with(file, ".csv"))) {
        snprintf(err, err_size,
                 "`%s`: the file must be a .json or .csv file inside the member's folder", key);
        return -1;
    }
    if (ends_with(file, ".json") &&
        (path[0] == '.' || path[strlen(path) - 1] == '.' || strstr(path, ".."))) {
        snprintf(err, err_size, "`%s`: empty part in the JSON path", key);
        return -1;
    }
    return 0;
}

/* ---------------------------------------------------------------- JSON */

static const char *skip_space(const char *p)
{
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')
        ++p;
    return p;
}

/* Past the string at p (p at its opening quote); NULL when unterminated. */
static const char *skip_string(const char *p)
{
    for (++p; *p && *p != '"'; ++p)
        if (*p == '\\' && p[1])
            ++p;
    return *p == '"' ? p + 1 : NULL;
}

/* Past the value at p; NULL when malformed (or nested deeper than 64). */
static const char *skip_value(const char *p, int depth)
{
    p = skip_space(p);
    if (*p == '"')
        return skip_string(p);
    if (*p != '{' && *p != '[') {
        const char *q = p;
        while (*q && !strchr(",]} \t\r\n", *q))
            ++q;
        return q > p ? q : NULL;
    }
    if (depth > 64)
        return NULL;
    char close = *p == '{' ? '}' : ']';
    p = skip_space(p + 1);
    if (*p == close)
        return p + 1;
    for (;;) {
        if (close == '}') {
            if (*p != '"' || !(p = skip_string(p)))
                return NULL;
            p = skip_space(p);
            if (*p++ != ':')
                return NULL;
        }
        if (!(p = skip_value(p, depth + 1)))
            return NULL;
        p = skip_space(p);
        if (*p == close)
            return p + 1;
        if (*p++ != ',')
            return NULL;
        p = skip_space(p);
    }
}

/* The value of member (object) or element (array) `name` of the container at p; NULL if none. */
static const char *child(const char *p, const char *name, size_t length)
{
    p = skip_space(p);
    if (*p != '{' && *p != '[')
        return NULL;
    int object = *p == '{';
    long index = -1, at = 0;
    if (!object) {
        char *end;
        index = strtol(name, &end, 10);
        if (end != name + length || index < 0)
            return NULL;
    }
    p = skip_space(p + 1);
    while (*p && *p != (object ? '}' : ']')) {
        int match = 0;
        if (object) {
            const char *key = p;
            if (*p != '"' || !(p = skip_string(p)))
                return NULL;
            match = (size_t)(p - key - 2) == length && strncmp(key + 1, name, length) == 0;
            p = skip_space(p);
            if (*p++ != ':')
                return NULL;
        } else {
            match = at++ == index;
        }
        if (match)
            return skip_space(p);
        if (!(p = skip_value(p, 0)))
            return NULL;
        p = skip_space(p);
        if (*p == ',')
            p = skip_space(p + 1);
    }
    return NULL;
}

int app_json_path_number(const char *text, const char *path, double *value)
{
    *value = NAN;
    const char *p = text;
    while (p && *path) {
        size_t length = strcspn(path, ".");
        p = child(p, path, length);
        path += length + (path[length] == '.');
    }
    if (!p)
        return -1;
    if (strncmp(p, "null", 4) == 0)
        return 1;
    char *end;
    errno = 0;
    double v = strtod(p, &end);
    if (end == p || (*end && !strchr(",]} \t\r\n", *end)))
        return -1;
    *value = v;
    return 0;
}

/* ---------------------------------------------------------------- CSV */

/* Field `index` of a comma line (no quoting: sablier's tables) into out; 0, or -1. */
static int csv_field(const char *line, int index, char *out, size_t size)
{
    for (int k = 0; k < index; ++k) {
        line = strchr(line, ',');
        if (!line)
            return -1;
        ++line;
    }
    size_t n = strcspn(line, ",\r\n");
    if (n >= size)
        return -1;
    memcpy(out, line, n);
    out[n] = '\0';
    return 0;
}

static int csv_column(const char *header, const char *name)
{
    char field[KEY_MAX];
    for (int k = 0; csv_field(header, k, field, sizeof field) == 0; ++k)
        if (strcmp(field, name) == 0)
            return k;
    return -1;
}

/* A field as a number: 0, 1 for empty, nan or null, -1 for anything else. */
static int csv_number(const char *field, double *value)
{
    *value = NAN;
    if (!field[0] || strcmp(field, "null") == 0 || strcmp(field, "nan") == 0)
        return 1;
    char *end;
    double v = strtod(field, &end);
    if (*end)
        return -1;
    *value = v;
    return isnan(v) ? 1 : 0;
}

static int csv_value(FILE *f, const char *file, const char *path, double *value, char *err,
                     size_t err_size)
{
    static char line[1 << 16], last[1 << 16];
    if (!fgets(line, sizeof line, f)) {
        snprintf(err, err_size, "%s is empty", file);
        return -1;
    }
    line[strcspn(line, "\r\n")] = '\0';
    int table = strcmp(line, "key,value") == 0; /* observables.csv */
    int column = table ? 1 : csv_column(line, path);
    if (column < 0) {
        snprintf(err, err_size, "%s has no column `%s`", file, path);
        return -1;
    }
    int found = 0;
    char field[KEY_MAX];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '\n' || line[0] == '\0')
            continue;
        if (table) {
            if (csv_field(line, 0, field, sizeof field) == 0 && strcmp(field, path) == 0) {
                memcpy(last, line, strlen(line) + 1);
                found = 1;
                break;
            }
        } else {
            memcpy(last, line, strlen(line) + 1);
            found = 1;
        }
    }
    if (!found) {
        snprintf(err, err_size, table ? "%s has no row `%s`" : "%s has no rows", file, path);
        return -1;
    }
    int rc = csv_field(last, column, field, sizeof field) == 0 ? csv_number(field, value) : -1;
    if (rc < 0)
        snprintf(err, err_size, "%s: `%s` is not a number", file, path);
    return rc;
}

/* ---------------------------------------------------------------- a folder's value */

static char *read_all(FILE *f)
{
    size_t capacity = 1 << 16, n = 0;
    char *text = malloc(capacity);
    while (text) {
        n += fread(text + n, 1, capacity - n - 1, f);
        if (n < capacity - 1)
            break;
        char *bigger = realloc(text, capacity * 2);
        if (!bigger)
            free(text);
        text = bigger;
        capacity *= 2;
    }
    if (text)
        text[n] = '\0';
    return text;
}

int app_run_value(const char *dir, const char *key, double *value, char *err, size_t err_size)
{
    *value = NAN;
    char file[KEY_MAX], full[4096];
    const char *path;
    if (app_run_value_check(key, err, err_size) != 0 ||
        split_key(key, file, sizeof file, &path) != 0)
        return -1;
    snprintf(full, sizeof full, "%s/%s", dir, file);
    const char *why = NULL;
    FILE *f = sim_open_input(full, &why);
    if (!f) {
        snprintf(err, err_size, "cannot read %s: %s", full, why);
        return -1;
    }
    int rc;
    if (ends_with(file, ".csv")) {
        rc = csv_value(f, full, path, value, err, err_size);
    } else {
        char *text = read_all(f);
        rc = text ? app_json_path_number(text, path, value) : -1;
        if (rc < 0)
            snprintf(err, err_size, text ? "%s: no number at `%s`" : "%s: out of memory", full,
                     path);
        free(text);
    }
    fclose(f);
    return rc;
}
