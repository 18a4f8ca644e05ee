/* SPDX-License-Identifier: MIT */
/* grains_file.c: `grains.file` (docs/scenes.md): grains from a CSV file with a header of named
 * columns (x, y, r required; species, fixed, vx, vy, omega, angle, id optional, in any order:
 * what `sablier export --format csv` writes), or from a LAMMPS text dump (its first snapshot,
 * columns by the `ITEM: ATOMS` names: id type x y [z] vx vy [vz] omegaz radius; species =
 * type - 1). Errors name the file and line. */
#include "scene/grains_file.h"

#include "sim/sim.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum {
    COL_X,
    COL_Y,
    COL_R,
    COL_SPECIES,
    COL_FIXED,
    COL_VX,
    COL_VY,
    COL_OMEGA,
    COL_ANGLE,
    COL_ID,
    COL_COUNT
};

#define MAX_COLUMNS 32
#define LINE_MAX    4096
/* The largest id a file may give (2^31 - 1): the ids of grains added later (sources) count on
 * from the largest in 32 bits, so a larger one would wrap onto the file's. */
#define ID_MAX      2147483647.0

typedef struct Reader {
    const char *path;
    long line;
    char *err;
    size_t err_size;
    int column[COL_COUNT]; /* field index of each known column, -1 when absent */
    int fields;            /* columns per row */
    long *id_line;         /* the line of each row read (for a duplicate id's message) */
    int id_capacity;
} Reader;

static int fail(Reader *r, const char *message, const char *detail)
{
    snprintf(r->err, r->err_size, "%s:%ld: %s%s", r->path, r->line, message, detail ? detail : "");
    return -1;
}

/* The known column a header name stands for (CSV and LAMMPS names), or -1. */
static int column_of(const char *name)
{
    static const struct {
        const char *name;
        int column;
    } names[] = {{"x", COL_X},
                 {"y", COL_Y},
                 {"r", COL_R},
                 {"radius", COL_R},
                 {"species", COL_SPECIES},
                 {"type", COL_SPECIES},
                 {"fixed", COL_FIXED},
                 {"vx", COL_VX},
                 {"vy", COL_VY},
                 {"omega", COL_OMEGA},
                 {"omegaz", COL_OMEGA},
                 {"angle", COL_ANGLE},
                 {"id", COL_ID}};

    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k)
        if (strcmp(name, names[k].name) == 0)
            return names[k].column;
    return -1;
}

/* Splits `line` in place at `sep` (',' or whitespace when 0); returns the number of fields. */
static int split(char *line, char sep, char **field)
{
    int n = 0;
    char *p = line;
    line[strcspn(line, "\r\n")] = '\0';
    while (*p && n < MAX_COLUMNS) {
        if (!sep)
            while (*p == ' ' || *p == '\t')
                ++p;
        if (!*p)
            break;
        field[n++] = p;
        while (*p && (sep ? *p != sep : (*p != ' ' && *p != '\t')))
            ++p;
        if (*p)
            *p++ = '\0';
    }
    return n;
}

/* The header's names: every column known or refused, x, y and r present. */
static int read_header(Reader *r, char **names, int n, int lammps)
{
    for (int c = 0; c < COL_COUNT; ++c)
        r->column[c] = -1;
    for (int k = 0; k < n; ++k) {
        int c = column_of(names[k]);
        if (c < 0 && !(lammps && (strcmp(names[k], "z") == 0 || strcmp(names[k], "vz") == 0 ||
                                  strncmp(names[k], "omega", 5) == 0)))
            return fail(r, "unknown column ", names[k]);
        if (c >= 0 && r->column[c] >= 0)
            return fail(r, "a column given twice: ", names[k]);
        if (c >= 0)
            r->column[c] = k;
    }
    if (r->column[COL_X] < 0 || r->column[COL_Y] < 0 || r->column[COL_R] < 0)
        return fail(r, "the header needs columns x, y and r (radius)", NULL);
    r->fields = n;
    return 0;
}

/* Keeps the line of row `row` (of the buffer) for a duplicate id's message: 0, or -1. */
static int note_line(Reader *r, int row)
{
    if (row >= r->id_capacity) {
        int capacity = row < 512 ? 1024 : 2 * row;
        long *grown = realloc(r->id_line, (size_t)capacity * sizeof *grown);
        if (!grown)
            return -1;
        r->id_line = grown;
        r->id_capacity = capacity;
    }
    r->id_line[row] = r->line;
    return 0;
}

static int by_id(const void *a, const void *b)
{
    const uint64_t ka = *(const uint64_t *)a, kb = *(const uint64_t *)b;
    return (ka > kb) - (ka < kb);
}

/* Every id of rows first.. of the buffer once: 0, or -1 at the line of a repeated id. */
static int ids_unique(Reader *r, const SimGrainBuffer *b, int first)
{
    const int n = b->count - first;
    uint64_t *key = malloc((size_t)(n > 0 ? n : 1) * sizeof *key); /* id << 32 | row */
    if (!key)
        return fail(r, "out of memory", NULL);
    for (int k = 0; k < n; ++k)
        key[k] = ((uint64_t)b->id[first + k] << 32) | (uint64_t)k;
    qsort(key, (size_t)n, sizeof *key, by_id);
    for (int k = 1; k < n; ++k)
        if (key[k] >> 32 == key[k - 1] >> 32) {
            uint32_t a = (uint32_t)key[k - 1], c = (uint32_t)key[k];
            r->line = r->id_line[first + (int)(a > c ? a : c)];
            char id[16];
            snprintf(id, sizeof id, "%u", (unsigned)(key[k] >> 32));
            free(key);
            return fail(r, "an id given twice (every grain's id must differ): ", id);
        }
    free(key);
    return 0;
}

/* One row into the buffer. */
static int read_row(Reader *r, char **field, int n, int lammps, int species_count,
                    SimGrainBuffer *b)
{
    if (n != r->fields)
        return fail(r, "wrong number of fields for the header", NULL);
    double v[COL_COUNT] = {0};
    for (int c = 0; c < COL_COUNT; ++c) {
        if (r->column[c] < 0)
            continue;
        char *end;
        errno = 0;
        v[c] = strtod(field[r->column[c]], &end);
        if (end == field[r->column[c]] || *end || errno == ERANGE || !isfinite(v[c]))
            return fail(r, "not a number: ", field[r->column[c]]);
    }
    /* the range tested on the double: a cast of 1e10 to int is undefined (fuzz_grains) */
    double first = lammps ? 1.0 : 0.0;
    if (r->column[COL_SPECIES] >= 0 &&
        (v[COL_SPECIES] != floor(v[COL_SPECIES]) || v[COL_SPECIES] < first ||
         v[COL_SPECIES] >= first + species_count))
        return fail(r, lammps ? "atom type out of the scene's species" : "species out of range",
                    NULL);
    int species = (int)(v[COL_SPECIES] - first);
    if (!(v[COL_R] > 0.0))
        return fail(r, "the radius must be > 0", NULL);
    if (v[COL_FIXED] != 0.0 && v[COL_FIXED] != 1.0)
        return fail(r, "`fixed` must be 0 or 1, got ", field[r->column[COL_FIXED]]);
    if (r->column[COL_ID] >= 0 &&
        (v[COL_ID] < 0 || v[COL_ID] > ID_MAX || v[COL_ID] != floor(v[COL_ID])))
        return fail(r, "ids must be integers in [0, 2^31 - 1], got ", field[r->column[COL_ID]]);
    if (r->column[COL_ID] >= 0 && note_line(r, b->count) < 0)
        return fail(r, "out of memory", NULL);
    int i = sim_grain_buffer_add(b, v[COL_X], v[COL_Y], v[COL_R], species,
                                 v[COL_FIXED] != 0.0 ? SIM_GRAIN_FIXED : 0u, -1);
    b->vx[i] = v[COL_VX];
    b->vy[i] = v[COL_VY];
    b->omega[i] = v[COL_OMEGA];
    b->angle[i] = v[COL_ANGLE];
    if (r->column[COL_ID] >= 0)
        b->id[i] = (uint32_t)v[COL_ID];
    return 0;
}

/* The line after `ITEM: NUMBER OF ATOMS`: an integer in [1, 1e9] into *atoms, or -1. */
static int atom_count(Reader *r, const char *line, long *atoms)
{
    char *end;
    errno = 0;
    long n = strtol(line, &end, 10);
    if (end == line || end[strspn(end, " \t\r\n")] != '\0' || errno || n < 1 || n > 1000000000L) {
        char shown[48];
        snprintf(shown, sizeof shown, "`%.*s`", (int)strcspn(line, "\r\n"), line);
        return fail(r, "NUMBER OF ATOMS must be a count in [1, 1e9], got ", shown);
    }
    *atoms = n;
    return 0;
}

/* A LAMMPS dump: skip to `ITEM: ATOMS`, read its names, then NUMBER OF ATOMS rows. */
static int read_lammps(Reader *r, FILE *f, int species_count, SimGrainBuffer *b)
{
    char line[LINE_MAX], *field[MAX_COLUMNS];
    long atoms = -1;
    while (fgets(line, sizeof line, f)) {
        ++r->line;
        if (strncmp(line, "ITEM: NUMBER OF ATOMS", 21) == 0) {
            if (!fgets(line, sizeof line, f))
                break;
            ++r->line;
            if (atom_count(r, line, &atoms) < 0)
                return -1;
        } else if (strncmp(line, "ITEM: ATOMS", 11) == 0) {
            int n = split(line + 11, 0, field);
            if (atoms < 0 || read_header(r, field, n, 1) < 0)
                return atoms < 0 ? fail(r, "ITEM: ATOMS before ITEM: NUMBER OF ATOMS", NULL) : -1;
            for (long k = 0; k < atoms; ++k) {
                if (!fgets(line, sizeof line, f))
                    return fail(r, "the file ends before NUMBER OF ATOMS rows", NULL);
                ++r->line;
                n = split(line, 0, field);
                if (read_row(r, field, n, 1, species_count, b) < 0)
                    return -1;
            }
            if (fgets(line, sizeof line, f) && strncmp(line, "ITEM:", 5) != 0 &&
                line[strspn(line, " \t\r\n")] != '\0') {
                ++r->line;
                return fail(r, "more atom rows than NUMBER OF ATOMS says (a wrong atom count?)",
                            NULL);
            }
            return 0;
        }
    }
    return fail(r, "no `ITEM: ATOMS` section (not a LAMMPS text dump?)", NULL);
}

static int read_csv(Reader *r, FILE *f, char *first, int species_count, SimGrainBuffer *b)
{
    char line[LINE_MAX], *field[MAX_COLUMNS];
    int n = split(first, ',', field);
    if (read_header(r, field, n, 0) < 0)
        return -1;
    while (fgets(line, sizeof line, f)) {
        ++r->line;
        if (line[strspn(line, " \t\r\n")] == '\0' || line[0] == '#')
            continue;
        n = split(line, ',', field);
        if (read_row(r, field, n, 0, species_count, b) < 0)
            return -1;
    }
    return 0;
}

int app_grains_read(const char *path, int species_count, SimGrainBuffer *buffer, int *has_ids,
                    char *err, size_t err_size)
{
    *has_ids = 0;
    Reader r = {.path = path, .line = 0, .err = err, .err_size = err_size, .column = {-1}};
    const char *why = NULL;
    FILE *f = sim_open_input(path, &why);
    if (!f) {
        snprintf(err, err_size, "%s:1: cannot read the grains file: %s", path, why);
        return -1;
    }
    char first[LINE_MAX];
    const int first_row = buffer->count;
    int status;
    if (!fgets(first, sizeof first, f)) {
        r.line = 1;
        status = fail(&r, "empty grains file", NULL);
    } else if (strncmp(first, "ITEM:", 5) == 0) {
        rewind(f);
        status = read_lammps(&r, f, species_count, buffer);
    } else {
        r.line = 1;
        status = read_csv(&r, f, first, species_count, buffer);
    }
    fclose(f);
    *has_ids = r.column[COL_ID] >= 0;
    if (status == 0 && *has_ids)
        status = ids_unique(&r, buffer, first_row);
    free(r.id_line);
    return status;
}
