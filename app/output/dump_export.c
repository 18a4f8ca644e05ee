/* SPDX-License-Identifier: MIT */
/* dump_export.c: `sablier export STATE` (docs/cli.md): one frame of a checkpoint as a LAMMPS
 * dump, a VTK PolyData file or a CSV table, with the columns a checkpoint holds (no forces: a
 * checkpoint has no contact forces without a scene's materials). Also the frame of saved grains
 * that `sablier render` draws without a scene. */
#include "base/util.h"
#include "output/dump.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char app_dump_export_usage[] =
    "usage: sablier export STATE -o FILE [--format lammps|vtk|csv]\n"
    "\n"
    "Writes the grains of a checkpoint (.state) as one frame:\n"
    "  --format lammps    LAMMPS text dump (ITEM: ATOMS id type x y z vx vy vz omegaz radius\n"
    "                     angle fixed; id = grain id + 1, type = species + 1)\n"
    "  --format vtk       VTK XML PolyData (.vtp): points and one array per column\n"
    "  --format csv       CSV with the header id,x,y,r,species,fixed,vx,vy,omega,angle\n"
    "  -o, --out FILE     output file (written through FILE.tmp); without --format the format\n"
    "                     comes from its extension: .lammpstrj or .dump, .vtp, .csv\n"
    "Numbers have 17 significant digits (they read back to the same bits).\n"
    "\n"
    "exit status: 0 the file was written, 2 bad input or a file that cannot be read or written,\n"
    "3 disk full\n";

/* The columns a checkpoint has, in the LAMMPS and VTK exports. */
static const unsigned char EXPORT_FIELDS[] = {
    APP_DUMP_ID, APP_DUMP_TYPE,  APP_DUMP_X,      APP_DUMP_Y,     APP_DUMP_VX,
    APP_DUMP_VY, APP_DUMP_OMEGA, APP_DUMP_RADIUS, APP_DUMP_ANGLE, APP_DUMP_FIXED};

int app_state_frame(const SimGrainSet *g, const SimWall *walls, int wall_count, double time,
                    AppStateFrame *s, SimFrame *frame)
{
    size_t n = (size_t)(g->count > 0 ? g->count : 1);
    double **columns[] = {&s->x, &s->y, &s->angle, &s->radius, &s->vx, &s->vy, &s->omega, &s->zero};
    for (size_t c = 0; c < sizeof columns / sizeof columns[0]; ++c)
        *columns[c] = calloc(n, sizeof(double));
    s->species = calloc(n, sizeof(int));
    s->flags = calloc(n, sizeof(unsigned));
    s->id = calloc(n, sizeof(uint32_t));
    for (size_t c = 0; c < sizeof columns / sizeof columns[0]; ++c)
        if (!*columns[c])
            return -1;
    if (!s->species || !s->flags || !s->id)
        return -1;
    int k = 0, mobile = 0;
    for (int pass = 0; pass < 2; ++pass)
        for (int i = 0; i < g->count; ++i) {
            unsigned flags = g->flags ? g->flags[i] : 0u;
            if ((pass == 0) == ((flags & SIM_GRAIN_FIXED) != 0))
                continue;
            s->x[k] = g->x[i];
            s->y[k] = g->y[i];
            s->radius[k] = g->radius[i];
            s->angle[k] = g->angle ? g->angle[i] : 0.0;
            s->vx[k] = g->vx ? g->vx[i] : 0.0;
            s->vy[k] = g->vy ? g->vy[i] : 0.0;
            s->omega[k] = g->omega ? g->omega[i] : 0.0;
            s->species[k] = g->species ? g->species[i] : 0;
            s->flags[k] = flags;
            s->id[k] = g->id ? g->id[i] : (uint32_t)i;
            mobile += pass == 0;
            ++k;
        }
    memset(frame, 0, sizeof *frame);
    frame->count = g->count;
    frame->mobile_count = mobile;
    frame->time = time;
    frame->x = s->x;
    frame->y = s->y;
    frame->angle = s->angle;
    frame->radius = s->radius;
    frame->vx = s->vx;
    frame->vy = s->vy;
    frame->omega = s->omega;
    frame->species = s->species;
    frame->flags = s->flags;
    frame->id = s->id;
    frame->force = frame->fx = frame->fy = frame->torque = s->zero;
    frame->walls = walls;
    frame->wall_count = wall_count;
    return 0;
}

void app_state_frame_free(AppStateFrame *s)
{
    free(s->x);
    free(s->y);
    free(s->angle);
    free(s->radius);
    free(s->vx);
    free(s->vy);
    free(s->omega);
    free(s->zero);
    free(s->species);
    free(s->flags);
    free(s->id);
    memset(s, 0, sizeof *s);
}

/* The CSV table a grains file reader reads by its header names. */
static int write_csv(const char *path, const SimFrame *f)
{
    FILE *out = app_tmp_open(path, "id,x,y,r,species,fixed,vx,vy,omega,angle");
    if (!out)
        return -1;
    for (int i = 0; i < f->count; ++i)
        fprintf(out, "%u,%.17g,%.17g,%.17g,%d,%d,%.17g,%.17g,%.17g,%.17g\n", f->id[i], f->x[i],
                f->y[i], f->radius[i], f->species[i], (f->flags[i] & SIM_GRAIN_FIXED) != 0,
                f->vx[i], f->vy[i], f->omega[i], f->angle[i]);
    if (ferror(out)) {
        app_tmp_discard(&out, path);
        return -1;
    }
    return app_tmp_commit(&out, path);
}

static int write_lammps(const char *path, const SimFrame *f)
{
    FILE *out = app_tmp_open(path, NULL);
    if (!out)
        return -1;
    int count = (int)sizeof EXPORT_FIELDS;
    if (app_dump_lammps_frame(out, f, EXPORT_FIELDS, count, NULL, NULL) != 0) {
        app_tmp_discard(&out, path);
        return -1;
    }
    return app_tmp_commit(&out, path);
}

/* "lammps", "vtk" or "csv" from FILE's extension; -1 when it names none. */
static int format_of(const char *path)
{
    static const char *const ends[] = {".lammpstrj", ".dump", ".vtp", ".csv"};
    static const int formats[] = {0, 0, 1, 2};
    size_t n = strlen(path);
    for (int k = 0; k < 4; ++k) {
        size_t m = strlen(ends[k]);
        if (n > m && strcmp(path + n - m, ends[k]) == 0)
            return formats[k];
    }
    return -1;
}

/* The command line of `sablier export`: the state, the output and its format (0 lammps, 1 vtk,
 * 2 csv). 0, or the exit status of a usage error (message on stderr). */
static int export_arguments(int argc, char **argv, const char **state_path, const char **out_path,
                            int *format_index)
{
    static const char *const formats[] = {"lammps", "vtk", "csv"};
    const char *state = NULL, *out = NULL, *value;
    int format = -1;
    for (int i = 2; i < argc; ++i) {
        int m;
        if ((m = app_option(argc, argv, &i, "-o", &value)) != 0 ||
            (m = app_option(argc, argv, &i, "--out", &value)) != 0) {
            if (m < 0)
                return 2;
            out = value;
        } else if ((m = app_option(argc, argv, &i, "--format", &value)) != 0) {
            if (m < 0)
                return 2;
            for (format = 2; format >= 0 && strcmp(value, formats[format]) != 0; --format)
                ;
            if (format < 0)
                return app_usage_error(app_dump_export_usage, "unknown --format", value);
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return app_usage_error(app_dump_export_usage, "unknown option", argv[i]);
        } else if (!state) {
            state = argv[i];
        } else {
            return app_usage_error(app_dump_export_usage, "one state at a time; extra argument",
                                   argv[i]);
        }
    }
    if (!state || !out)
        return app_usage_error(app_dump_export_usage, state ? "missing -o FILE" : "missing STATE",
                               NULL);
    if (format < 0 && (format = format_of(out)) < 0)
        return app_usage_error(app_dump_export_usage,
                               "give --format: no format from the extension of", out);
    *state_path = state;
    *out_path = out;
    *format_index = format;
    return 0;
}

int app_dump_export_parse(int argc, char **argv)
{
    const char *state, *out;
    int format;
    return export_arguments(argc, argv, &state, &out, &format);
}

int app_dump_export(int argc, char **argv)
{
    const char *state = NULL, *out = NULL;
    int format = -1;
    int bad = export_arguments(argc, argv, &state, &out, &format);
    if (bad)
        return bad;
    const char *why = NULL;
    if (sim_output_target(out, &why) != 0) { /* a device or a link is never replaced */
        fprintf(stderr, "sablier: export: cannot write %s: %s\n", out, why);
        return 2;
    }
    SimGrainSet grains;
    SimWall *walls = NULL;
    int wall_count = 0;
    double time = 0.0;
    SimError error;
    if (sim_state_load(state, &grains, &walls, &wall_count, &time, &error) != SIM_OK) {
        fprintf(stderr, "sablier: export: cannot load %s: %s\n", state, error.message);
        return 2;
    }
    AppStateFrame columns;
    SimFrame frame;
    memset(&columns, 0, sizeof columns);
    int status = 0;
    if (app_state_frame(&grains, walls, wall_count, time, &columns, &frame) != 0) {
        fprintf(stderr, "sablier: export: out of memory\n");
        status = 2;
    } else {
        errno = 0;
        int rc = format == 0   ? write_lammps(out, &frame)
                 : format == 1 ? app_dump_vtp_grains(out, &frame, EXPORT_FIELDS,
                                                     (int)sizeof EXPORT_FIELDS, NULL, -1)
                               : write_csv(out, &frame);
        if (rc != 0) {
            int full = app_failed_for_space(NULL), reason = full ? ENOSPC : errno;
            fprintf(stderr, "sablier: export: %scannot write %s%s%s\n", full ? "disk full: " : "",
                    out, reason ? ": " : "", reason ? strerror(reason) : "");
            status = full ? APP_EXIT_DISK_FULL : 2;
        }
    }
    app_state_frame_free(&columns);
    sim_grain_set_free(&grains);
    free(walls);
    return status;
}
