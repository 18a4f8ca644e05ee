/* SPDX-License-Identifier: MIT */
/* vtk_xml.c: VTK XML files (version 1.0, header_type UInt64; "VTK File Formats", VTK User's
 * Guide, Kitware, 11th ed., ch. 19) and ParaView .pvd collections, through PATH.tmp. */
#include "output/vtk_xml.h"

#include "base/util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* 1 on a little-endian host (the raw blocks are the host's bytes; byte_order says which). */
static int little_endian(void)
{
    const uint16_t one = 1;
    unsigned char first;
    memcpy(&first, &one, 1);
    return first == 1;
}

int app_vtk_begin(AppVtk *v, const char *path, const char *type, const char *attributes, int binary,
                  double time)
{
    memset(v, 0, sizeof v[0]);
    v->binary = binary != 0;
    snprintf(v->type, sizeof v->type, "%s", type);
    v->out = app_tmp_open(path, "<?xml version=\"1.0\"?>");
    if (!v->out)
        return -1;
    fprintf(v->out,
            "<VTKFile type=\"%s\" version=\"1.0\" byte_order=\"%s\" header_type=\"UInt64\">\n"
            "<%s%s%s>\n<FieldData>\n<DataArray type=\"Float64\" Name=\"TimeValue\" "
            "NumberOfTuples=\"1\" format=\"ascii\">%.17g</DataArray>\n</FieldData>\n",
            type, little_endian() ? "LittleEndian" : "BigEndian", type, *attributes ? " " : "",
            attributes, time);
    return 0;
}

/* Appends `bytes` bytes behind a UInt64 count to the appended block; its offset, or -1. */
static long append_block(AppVtk *v, const void *values, size_t bytes)
{
    uint64_t count = bytes;
    if (v->size + bytes + sizeof count > v->capacity) {
        size_t capacity = 2 * (v->size + bytes + sizeof count) + 1024;
        unsigned char *data = realloc(v->data, capacity);
        if (!data) {
            v->failed = 1;
            return -1;
        }
        v->data = data;
        v->capacity = capacity;
    }
    long offset = (long)v->size;
    memcpy(v->data + v->size, &count, sizeof count);
    if (bytes)
        memcpy(v->data + v->size + sizeof count, values, bytes);
    v->size += bytes + sizeof count;
    return offset;
}

/* The opening tag of a DataArray; 1 when its values follow as ASCII. */
static int array_open(AppVtk *v, const char *type, const char *name, int components,
                      const void *values, size_t bytes)
{
    fprintf(v->out, "<DataArray type=\"%s\" Name=\"%s\"", type, name);
    if (components != 1)
        fprintf(v->out, " NumberOfComponents=\"%d\"", components);
    if (v->binary) {
        long offset = append_block(v, values, bytes);
        fprintf(v->out, " format=\"appended\" offset=\"%ld\"/>\n", offset < 0 ? 0 : offset);
        return 0;
    }
    fputs(" format=\"ascii\">\n", v->out);
    return 1;
}

void app_vtk_doubles(AppVtk *v, const char *name, int components, size_t n, const double *values)
{
    size_t total = n * (size_t)components;
    if (!array_open(v, "Float64", name, components, values, total * sizeof *values))
        return;
    for (size_t k = 0; k < total; ++k)
        fprintf(v->out, "%.17g%c", values[k], (k + 1) % (size_t)components ? ' ' : '\n');
    fputs("</DataArray>\n", v->out);
}

void app_vtk_int64(AppVtk *v, const char *name, int components, size_t n, const int64_t *values)
{
    size_t total = n * (size_t)components;
    if (!array_open(v, "Int64", name, components, values, total * sizeof *values))
        return;
    for (size_t k = 0; k < total; ++k)
        fprintf(v->out, "%lld%c", (long long)values[k], (k + 1) % (size_t)components ? ' ' : '\n');
    fputs("</DataArray>\n", v->out);
}

int app_vtk_end(AppVtk *v, const char *path)
{
    fprintf(v->out, "</%s>\n", v->type);
    if (v->binary) { /* "_" then the raw blocks (the format's marker of the data's start) */
        fputs("<AppendedData encoding=\"raw\">\n_", v->out);
        if (v->size)
            fwrite(v->data, 1, v->size, v->out);
        fputs("\n</AppendedData>\n", v->out);
    }
    fputs("</VTKFile>\n", v->out);
    free(v->data);
    v->data = NULL;
    if (v->failed || ferror(v->out)) {
        app_tmp_discard(&v->out, path);
        return -1;
    }
    return app_tmp_commit(&v->out, path);
}

FILE *app_pvd_open(const char *path)
{
    return app_tmp_open(path, "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" "
                              "version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>");
}

void app_pvd_entry(FILE *out, double time, int part, const char *file)
{
    fprintf(out, "<DataSet timestep=\"%.17g\" group=\"\" part=\"%d\" file=\"%s\"/>\n", time, part,
            file);
}

int app_pvd_commit(FILE **out, const char *path)
{
    fputs("</Collection>\n</VTKFile>\n", *out);
    if (ferror(*out)) {
        app_tmp_discard(out, path);
        return -1;
    }
    return app_tmp_commit(out, path);
}

double app_vtk_time_value(const char *path)
{
    FILE *in = fopen(path, "rb");
    if (!in)
        return (double)NAN;
    char head[1024];
    size_t n = fread(head, 1, sizeof head - 1, in);
    fclose(in);
    head[n] = '\0';
    const char *p = strstr(head, "Name=\"TimeValue\"");
    p = p ? strchr(p, '>') : NULL;
    return p ? strtod(p + 1, NULL) : (double)NAN;
}
