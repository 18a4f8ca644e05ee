/* SPDX-License-Identifier: MIT */
/* vtk_xml.h: the VTK XML file writer that the dumps (dump.c) and the grid measures' .vti
 * (measures.c) share, and ParaView's .pvd time indexes. A file is written through PATH.tmp:
 *
 *     AppVtk v;
 *     if (app_vtk_begin(&v, path, "PolyData", "", binary, time) != 0) ...;
 *     fprintf(v.out, "<Piece NumberOfPoints=\"%d\" ...>\n<PointData>\n", n);
 *     app_vtk_doubles(&v, "radius", 1, n, radius);
 *     fputs("</PointData>\n...</Piece>\n", v.out);
 *     app_vtk_end(&v, path);   // appended data, </VTKFile>, rename (or discard on error)
 *
 * Each file holds its simulated time as the field data array `TimeValue` (the name VTK's readers
 * and ParaView take as the data set's time). ASCII arrays have 17 significant digits (every double
 * reads back to the same bits); binary arrays are raw appended data (the VTK XML file format,
 * "AppendedData encoding=raw", each block a UInt64 byte count then the values), exact as well. */
#ifndef APP_VTK_XML_H
#define APP_VTK_XML_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/// Above this many points a VTK file is binary unless asked otherwise (the dumps' `vtk_encoding`
/// "auto", the grid measures' .vti).
#define APP_VTK_BINARY_POINTS 10000

typedef struct AppVtk {
    FILE *out;
    int binary;
    char type[32];
    unsigned char *data; /* the appended block (binary) */
    size_t size, capacity;
    int failed;
} AppVtk;

/// Opens path.tmp and writes the header, `<TYPE attributes>` and the TimeValue field data.
/// 0, or -1 (nothing left behind).
int app_vtk_begin(AppVtk *v, const char *path, const char *type, const char *attributes, int binary,
                  double time);
/// One DataArray of n tuples of `components` doubles (Float64).
void app_vtk_doubles(AppVtk *v, const char *name, int components, size_t n, const double *values);
/// One DataArray of n tuples of `components` integers (Int64).
void app_vtk_int64(AppVtk *v, const char *name, int components, size_t n, const int64_t *values);
/// Closes the data set, writes the appended data and renames path.tmp to path (a write error or
/// an earlier failure: path.tmp removed). 0, or -1.
int app_vtk_end(AppVtk *v, const char *path);

/// Opens a ParaView .pvd collection through path.tmp (NULL on failure).
FILE *app_pvd_open(const char *path);
/// One data set: `file` (relative to the .pvd) at simulated time `time` (s), block `part`.
void app_pvd_entry(FILE *out, double time, int part, const char *file);
/// Closes the collection and renames path.tmp to path. 0, or -1.
int app_pvd_commit(FILE **out, const char *path);
/// The `TimeValue` of a VTK XML file that app_vtk_begin started, or NAN.
double app_vtk_time_value(const char *path);

#endif
