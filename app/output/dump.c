/* SPDX-License-Identifier: MIT */
/* dump.c: per-grain dumps (docs/dumps.md), the writers of a run (the `dump` keys of a scene,
 * checked at load, are app/scene/scene_dump.c): a LAMMPS text dump per stage, streamed into
 * PATH.tmp and renamed at the stage end, and a VTK XML PolyData file per frame (grains as points,
 * contacts as lines), each written through PATH.tmp, with a ParaView .pvd time index per series.
 * VTK data are ASCII with 17 significant digits, so every double reads back to the same bits. The
 * export command and the checkpoint frame are dump_export.c. */
#include "output/dump.h"

#include "base/checkpoint.h"
#include "base/util.h"
#include "output/vtk_xml.h"
#include "scene/scene.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A path under the output folder (at most SCENE_PATH_MAX): DIR/<stage>/<stage>_contacts_N.vtp */
#define DUMP_PATH (SCENE_PATH_MAX + 3 * SCENE_NAME_MAX + 32)

/* LAMMPS column names of each field: y, vy and fy carry the 2D slab's zero z component. */
static const char *const LAMMPS_NAMES[] = {"id",      "type",   "x",     "y z",   "vx",     "vy vz",
                                           "omegaz",  "radius", "fx",    "fy fz", "mass",   "angle",
                                           "species", "fixed",  "force", "tqz",   "element"};

/* ---------------------------------------------------------------- one frame */

/* Field `field` of grain i: an integer into *n (returns 1) or a real into *v (returns 0). The
 * LAMMPS ids start at 1 (lammps = 1). */
static int field_value(const SimFrame *f, const SimWorldDef *def, int field, int i, int lammps,
                       double *v, long long *n)
{
    switch ((AppDumpField)field) {
    case APP_DUMP_ID:
        *n = (long long)f->id[i] + (lammps ? 1 : 0);
        return 1;
    case APP_DUMP_TYPE:
        *n = f->species[i] + 1;
        return 1;
    case APP_DUMP_SPECIES:
    case APP_DUMP_ELEMENT:
        *n = f->species[i];
        return 1;
    case APP_DUMP_FIXED:
        *n = (f->flags[i] & SIM_GRAIN_FIXED) != 0;
        return 1;
    case APP_DUMP_X:
        *v = f->x[i];
        break;
    case APP_DUMP_Y:
        *v = f->y[i];
        break;
    case APP_DUMP_VX:
        *v = f->vx[i];
        break;
    case APP_DUMP_VY:
        *v = f->vy[i];
        break;
    case APP_DUMP_OMEGA:
        *v = f->omega[i];
        break;
    case APP_DUMP_RADIUS:
        *v = f->radius[i];
        break;
    case APP_DUMP_FX:
        *v = f->fx ? f->fx[i] : 0.0;
        break;
    case APP_DUMP_FY:
        *v = f->fy ? f->fy[i] : 0.0;
        break;
    case APP_DUMP_MASS:
        *v = def ? sim_grain_mass(def->mass_model, def->materials[f->species[i]].density,
                                  f->radius[i])
                 : (double)NAN;
        break;
    case APP_DUMP_ANGLE:
        *v = f->angle[i];
        break;
    case APP_DUMP_FORCE:
        *v = f->force ? f->force[i] : 0.0;
        break;
    case APP_DUMP_TORQUE:
        *v = f->torque ? f->torque[i] : 0.0;
        break;
    case APP_DUMP_FIELD_COUNT:
        *v = 0.0;
        break;
    }
    return 0;
}

/* The box of a frame: x over the periodic domain or the grains' and walls' extent, y over that
 * extent, z a slab one largest diameter thick around z = 0. */
static void frame_box(const SimFrame *f, double lo[3], double hi[3])
{
    double r_max = 0.0;
    lo[0] = lo[1] = INFINITY;
    hi[0] = hi[1] = -INFINITY;
    for (int i = 0; i < f->count; ++i) {
        lo[0] = fmin(lo[0], f->x[i] - f->radius[i]);
        hi[0] = fmax(hi[0], f->x[i] + f->radius[i]);
        lo[1] = fmin(lo[1], f->y[i] - f->radius[i]);
        hi[1] = fmax(hi[1], f->y[i] + f->radius[i]);
        r_max = fmax(r_max, f->radius[i]);
    }
    for (int w = 0; w < f->wall_count; ++w) {
        lo[0] = fmin(lo[0], fmin(f->walls[w].x0, f->walls[w].x1));
        hi[0] = fmax(hi[0], fmax(f->walls[w].x0, f->walls[w].x1));
        lo[1] = fmin(lo[1], fmin(f->walls[w].y0, f->walls[w].y1));
        hi[1] = fmax(hi[1], fmax(f->walls[w].y0, f->walls[w].y1));
    }
    if (f->periodic) {
        lo[0] = f->domain_x0;
        hi[0] = f->domain_x1;
    }
    for (int a = 0; a < 2; ++a)
        if (!(hi[a] > lo[a])) { /* no grains, or a single point */
            double mid = isfinite(lo[a]) ? 0.5 * (lo[a] + hi[a]) : 0.0;
            lo[a] = mid - 0.5;
            hi[a] = mid + 0.5;
        }
    lo[2] = r_max > 0.0 ? -r_max : -0.5;
    hi[2] = -lo[2];
}

/* The header of a LAMMPS dump frame up to its BOX BOUNDS (`what`: ATOMS or ENTRIES). */
static void lammps_header(FILE *out, const SimFrame *f, const char *what, long count)
{
    double lo[3], hi[3];
    frame_box(f, lo, hi);
    fprintf(out,
            "ITEM: UNITS\nsi\nITEM: TIME\n%.17g\nITEM: TIMESTEP\n%ld\nITEM: NUMBER OF %s\n%ld\n"
            "ITEM: BOX BOUNDS %s ff pp\n%.17g %.17g\n%.17g %.17g\n%.17g %.17g\n",
            f->time, f->step, what, count, f->periodic ? "pp" : "ff", lo[0], hi[0], lo[1], hi[1],
            lo[2], hi[2]);
}

/* A species name as one word of a dump row (blanks as '_'). */
static void put_word(FILE *out, const char *name)
{
    for (const char *c = name; *c; ++c)
        fputc(*c == ' ' || *c == '\t' || *c == '\n' ? '_' : *c, out);
}

int app_dump_lammps_frame(FILE *out, const SimFrame *f, const unsigned char *fields, int count,
                          const SimWorldDef *def, const char *const *species)
{
    lammps_header(out, f, "ATOMS", f->count);
    fputs("ITEM: ATOMS", out);
    for (int k = 0; k < count; ++k)
        fprintf(out, " %s", LAMMPS_NAMES[fields[k]]);
    fputc('\n', out);
    for (int i = 0; i < f->count; ++i) {
        for (int k = 0; k < count; ++k) {
            double v = 0.0;
            long long n = 0;
            const char *gap = k ? " " : "";
            if (fields[k] == APP_DUMP_ELEMENT && species) {
                fputs(gap, out);
                put_word(out, species[f->species[i]]);
            } else if (field_value(f, def, fields[k], i, 1, &v, &n)) {
                fprintf(out, "%s%lld", gap, n);
            } else {
                fprintf(out, "%s%.17g", gap, v);
            }
            if (fields[k] == APP_DUMP_Y || fields[k] == APP_DUMP_VY || fields[k] == APP_DUMP_FY)
                fputs(" 0", out); /* z, vz, fz of the slab */
        }
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}

int app_dump_lammps_contacts(FILE *out, const SimFrame *f)
{
    long pairs = 0;
    for (int c = 0; c < f->contact_count; ++c)
        pairs += f->contacts[c].j >= 0; /* a wall is no atom: no bond */
    lammps_header(out, f, "ENTRIES", pairs);
    fputs("ITEM: ENTRIES index id1 id2 fn ft\n", out);
    long index = 0;
    for (int c = 0; c < f->contact_count; ++c) {
        const SimContact *k = &f->contacts[c];
        if (k->j >= 0)
            fprintf(out, "%ld %lld %lld %.17g %.17g\n", ++index, (long long)f->id[k->i] + 1,
                    (long long)f->id[k->j] + 1, k->normal_force, k->tangential_force);
    }
    return ferror(out) ? -1 : 0;
}

/* binary -1 (auto): raw above APP_VTK_BINARY_POINTS points. */
static int encoding(int binary, int points)
{
    return binary < 0 ? points > APP_VTK_BINARY_POINTS : binary;
}

/* Cells of `count` single points (verts) or point pairs (lines): connectivity and offsets. */
static int vtk_cells(AppVtk *v, const char *what, const int *pairs, int count, int size)
{
    size_t n = (size_t)(count > 0 ? count : 1);
    int64_t *connectivity = malloc(n * (size_t)size * sizeof *connectivity),
            *offsets = malloc(n * sizeof *offsets);
    if (!connectivity || !offsets) {
        free(connectivity);
        free(offsets);
        return -1;
    }
    for (int c = 0; c < count; ++c) {
        for (int k = 0; k < size; ++k)
            connectivity[c * size + k] = size == 1 ? c : pairs[2 * c + k];
        offsets[c] = (int64_t)(c + 1) * size;
    }
    fprintf(v->out, "<%s>\n", what);
    app_vtk_int64(v, "connectivity", 1, (size_t)count * (size_t)size, connectivity);
    app_vtk_int64(v, "offsets", 1, (size_t)count, offsets);
    fprintf(v->out, "</%s>\n", what);
    free(connectivity);
    free(offsets);
    return 0;
}

/* The points (x, y, 0) of n grains then n2 extra points. */
static int vtk_points(AppVtk *v, const double *x, const double *y, int n, const double *x2,
                      const double *y2, int n2)
{
    size_t total = (size_t)n + (size_t)n2;
    double *p = malloc((total > 0 ? total : 1) * 3 * sizeof *p);
    if (!p)
        return -1;
    for (size_t i = 0; i < total; ++i) {
        int extra = i >= (size_t)n;
        p[3 * i] = extra ? x2[i - (size_t)n] : x[i];
        p[3 * i + 1] = extra ? y2[i - (size_t)n] : y[i];
        p[3 * i + 2] = 0.0;
    }
    fputs("<Points>\n", v->out);
    app_vtk_doubles(v, "Points", 3, total, p);
    fputs("</Points>\n", v->out);
    free(p);
    return 0;
}

/* Opens a PolyData piece. */
static int vtp_begin(AppVtk *v, const char *path, int binary, double time, int points, int verts,
                     int lines)
{
    if (app_vtk_begin(v, path, "PolyData", "", encoding(binary, points), time) != 0)
        return -1;
    fprintf(v->out,
            "<Piece NumberOfPoints=\"%d\" NumberOfVerts=\"%d\" NumberOfLines=\"%d\" "
            "NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n",
            points, verts, lines);
    return 0;
}

/* One point-data array of a grain field (integers as Int64). */
static int vtp_field(AppVtk *v, const SimFrame *f, const SimWorldDef *def, int field)
{
    size_t n = (size_t)(f->count > 0 ? f->count : 1);
    double *d = malloc(n * sizeof *d);
    int64_t *l = malloc(n * sizeof *l);
    int integer = field == APP_DUMP_ID || field == APP_DUMP_TYPE || field == APP_DUMP_SPECIES ||
                  field == APP_DUMP_FIXED;
    if (!d || !l) {
        free(d);
        free(l);
        return -1;
    }
    for (int i = 0; i < f->count; ++i) {
        long long m = 0;
        field_value(f, def, field, i, 0, &d[i], &m);
        l[i] = (int64_t)m;
    }
    if (integer)
        app_vtk_int64(v, app_dump_field_name(field), 1, (size_t)f->count, l);
    else
        app_vtk_doubles(v, app_dump_field_name(field), 1, (size_t)f->count, d);
    free(d);
    free(l);
    return 0;
}

int app_dump_vtp_grains(const char *path, const SimFrame *f, const unsigned char *fields, int count,
                        const SimWorldDef *def, int binary)
{
    AppVtk v;
    if (vtp_begin(&v, path, binary, f->time, f->count, f->count, 0) != 0)
        return -1;
    int has[APP_DUMP_FIELD_COUNT] = {0};
    for (int k = 0; k < count; ++k)
        has[fields[k]] = 1;
    int velocity = has[APP_DUMP_VX] && has[APP_DUMP_VY];
    fprintf(v.out, "<PointData%s%s>\n", has[APP_DUMP_RADIUS] ? " Scalars=\"radius\"" : "",
            velocity ? " Vectors=\"velocity\"" : "");
    for (int k = 0; k < count; ++k)
        if (fields[k] != APP_DUMP_X && fields[k] != APP_DUMP_Y && fields[k] != APP_DUMP_ELEMENT &&
            vtp_field(&v, f, def, fields[k]) != 0)
            v.failed = 1; /* x, y: the points; element: LAMMPS only */
    if (velocity) {       /* vx, vy, 0 for glyphs */
        double *u = malloc((size_t)(f->count > 0 ? f->count : 1) * 3 * sizeof *u);
        for (int i = 0; u && i < f->count; ++i) {
            u[3 * i] = f->vx[i];
            u[3 * i + 1] = f->vy[i];
            u[3 * i + 2] = 0.0;
        }
        if (u)
            app_vtk_doubles(&v, "velocity", 3, (size_t)f->count, u);
        v.failed |= !u;
        free(u);
    }
    fputs("</PointData>\n", v.out);
    if (vtk_points(&v, f->x, f->y, f->count, NULL, NULL, 0) != 0 ||
        vtk_cells(&v, "Verts", NULL, f->count, 1) != 0)
        v.failed = 1;
    fputs("</Piece>\n", v.out);
    return app_vtk_end(&v, path);
}

/* Segments of an arc wall's polyline. */
#define WALL_ARC_SEGMENTS 32

int app_dump_vtp_walls(const char *path, const SimFrame *f, int binary)
{
    int points = 0;
    for (int w = 0; w < f->wall_count; ++w)
        points += f->walls[w].shape == SIM_WALL_ARC ? WALL_ARC_SEGMENTS + 1 : 2;
    size_t n = (size_t)(points > 0 ? points : 1), walls = (size_t)(f->wall_count + 1);
    double *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y);
    int64_t *connectivity = malloc(n * sizeof *connectivity),
            *offsets = malloc(walls * sizeof *offsets), *index = malloc(walls * sizeof *index),
            *species = malloc(walls * sizeof *species);
    AppVtk v;
    int rc = -1;
    if (x && y && connectivity && offsets && index && species &&
        vtp_begin(&v, path, binary, f->time, points, 0, f->wall_count) == 0) {
        int k = 0;
        for (int w = 0; w < f->wall_count; ++w) { /* sim_wall_point: along the wall, s in [0, 1] */
            int segments = f->walls[w].shape == SIM_WALL_ARC ? WALL_ARC_SEGMENTS : 1;
            for (int s = 0; s <= segments; ++s, ++k) {
                sim_wall_point(&f->walls[w], (double)s / segments, &x[k], &y[k]);
                connectivity[k] = k;
            }
            offsets[w] = k;
            index[w] = w;
            species[w] = f->walls[w].species;
        }
        fputs("<CellData Scalars=\"wall\">\n", v.out);
        app_vtk_int64(&v, "wall", 1, (size_t)f->wall_count, index);
        app_vtk_int64(&v, "species", 1, (size_t)f->wall_count, species);
        fputs("</CellData>\n", v.out);
        if (vtk_points(&v, x, y, points, NULL, NULL, 0) != 0)
            v.failed = 1;
        fputs("<Lines>\n", v.out);
        app_vtk_int64(&v, "connectivity", 1, (size_t)points, connectivity);
        app_vtk_int64(&v, "offsets", 1, (size_t)f->wall_count, offsets);
        fputs("</Lines>\n</Piece>\n", v.out);
        rc = app_vtk_end(&v, path);
    }
    free(x);
    free(y);
    free(connectivity);
    free(offsets);
    free(index);
    free(species);
    return rc;
}

/* The line cells of a frame's contacts: centre to centre, centre to the contact point for a wall,
 * and across a periodic seam each grain to the image of the other (two cells). */
typedef struct ContactLines {
    int count, extra;
    int *pairs;      /* 2 per line: point indices */
    int *contact;    /* the contact of each line */
    double *ex, *ey; /* extra points after the grain centres */
} ContactLines;

static int contact_lines(const SimFrame *f, ContactLines *l)
{
    size_t cap = 2 * (size_t)f->contact_count + 1;
    l->count = l->extra = 0;
    l->pairs = malloc(2 * cap * sizeof *l->pairs);
    l->contact = malloc(cap * sizeof *l->contact);
    l->ex = malloc(cap * sizeof *l->ex);
    l->ey = malloc(cap * sizeof *l->ey);
    if (!l->pairs || !l->contact || !l->ex || !l->ey)
        return -1;
    double width = f->domain_x1 - f->domain_x0;
    for (int c = 0; c < f->contact_count; ++c) {
        const SimContact *k = &f->contacts[c];
        int i = k->i, j = k->j;
        double shift = 0.0;
        if (j >= 0 && f->periodic) {
            double dx = f->x[j] - f->x[i];
            shift = dx > 0.5 * width ? -width : dx < -0.5 * width ? width : 0.0;
        }
        if (j < 0) { /* a wall: to the contact point */
            l->ex[l->extra] = k->x;
            l->ey[l->extra] = k->y;
            j = f->count + l->extra++;
        } else if (shift != 0.0) { /* j's image beside i, and i's image beside j */
            l->ex[l->extra] = f->x[j] + shift;
            l->ey[l->extra] = f->y[j];
            l->ex[l->extra + 1] = f->x[i] - shift;
            l->ey[l->extra + 1] = f->y[i];
            l->pairs[2 * l->count] = i;
            l->pairs[2 * l->count + 1] = f->count + l->extra;
            l->contact[l->count++] = c;
            i = k->j;
            j = f->count + l->extra + 1;
            l->extra += 2;
        }
        l->pairs[2 * l->count] = i;
        l->pairs[2 * l->count + 1] = j;
        l->contact[l->count++] = c;
    }
    return 0;
}

int app_dump_vtp_contacts(const char *path, const SimFrame *f, int binary)
{
    ContactLines l;
    memset(&l, 0, sizeof l);
    AppVtk v;
    int rc = -1;
    double *force = NULL;
    if (contact_lines(f, &l) == 0 &&
        (force = malloc((size_t)(l.count > 0 ? l.count : 1) * sizeof *force)) != NULL &&
        vtp_begin(&v, path, binary, f->time, f->count + l.extra, 0, l.count) == 0) {
        fputs("<CellData Scalars=\"normal_force\">\n", v.out);
        for (int a = 0; a < 2; ++a) { /* F_n (positive: repulsive) and |F_t|, N */
            for (int c = 0; c < l.count; ++c) {
                const SimContact *k = &f->contacts[l.contact[c]];
                force[c] = a ? fabs(k->tangential_force) : k->normal_force;
            }
            app_vtk_doubles(&v, a ? "tangential_force" : "normal_force", 1, (size_t)l.count, force);
        }
        fputs("</CellData>\n", v.out);
        if (vtk_points(&v, f->x, f->y, f->count, l.ex, l.ey, l.extra) != 0 ||
            vtk_cells(&v, "Lines", l.pairs, l.count, 2) != 0)
            v.failed = 1;
        fputs("</Piece>\n", v.out);
        rc = app_vtk_end(&v, path);
    }
    free(force);
    free(l.pairs);
    free(l.contact);
    free(l.ex);
    free(l.ey);
    return rc;
}

/* ---------------------------------------------------------------- a stage's writer */

/* The VTK series of a stage: the suffix of its files and its block in the run's .pvd. */
static const char *const SERIES[] = {"", "_contacts", "_walls"};
#define SERIES_COUNT 3

struct AppDump {
    AppDumpSpec spec;
    const struct Scene *scene; /* masses, species names, the stages before (run.all.pvd) */
    int stage_index;
    const char *species[SIM_MAX_SPECIES];
    char stage[SCENE_NAME_MAX];
    char dir[SCENE_PATH_MAX];
    char lammps_path[DUMP_PATH], bonds_path[DUMP_PATH];
    FILE *lammps, *bonds; /* atoms; contacts as `dump local` entries */
    double *times;        /* s, of each frame */
    int frames, capacity;
    long last_step;
    int failed;
    char message[DUMP_PATH + SCENE_NAME_MAX + 64];
};

/* Series s of the stage is written (grains always; contacts, walls as declared). */
static int series_on(const AppDump *d, int s)
{
    return (d->spec.formats & APP_DUMP_VTK) &&
           (s == 0 || (s == 1 && d->spec.contacts) || (s == 2 && d->spec.walls));
}

/* DIR/<stage>/<stage><series>_NNNNN.vtp, or with folder = 0 the name the .pvd lists. */
static void vtp_path(const AppDump *d, char *out, size_t size, const char *series, int frame,
                     int folder)
{
    snprintf(out, size, "%s%s%s/%s%s_%05d.vtp", folder ? d->dir : "", folder ? "/" : "", d->stage,
             d->stage, series, frame);
}

static void fail(AppDump *d, const char *what, const char *path)
{
    if (!d->failed)
        snprintf(d->message, sizeof d->message, "dump of stage %s: %s %s", d->stage, what, path);
    d->failed = 1;
}

int app_dump_open(AppDump **dump, const struct Scene *scene, int stage, const char *out_dir,
                  char *err, size_t err_size)
{
    const AppDumpSpec *spec = &scene->output.dump[stage];
    *dump = NULL;
    if (!spec->formats)
        return 0;
    AppDump *d = calloc(1, sizeof *d);
    if (!d) {
        snprintf(err, err_size, "dump: out of memory");
        return -1;
    }
    d->spec = *spec;
    d->scene = scene;
    d->stage_index = stage;
    for (int k = 0; k < SIM_MAX_SPECIES; ++k)
        d->species[k] = scene->species_names[k];
    d->last_step = -1;
    if (strlen(out_dir) >= sizeof d->dir) {
        snprintf(err, err_size, "dump: output folder name too long");
        free(d);
        return -1;
    }
    snprintf(d->stage, sizeof d->stage, "%s", scene->stages[stage].name);
    snprintf(d->dir, sizeof d->dir, "%s", out_dir);
    char folder[DUMP_PATH];
    snprintf(folder, sizeof folder, "%s/%s", out_dir, d->stage);
    snprintf(d->lammps_path, sizeof d->lammps_path, "%s/%s.lammpstrj", out_dir, d->stage);
    snprintf(d->bonds_path, sizeof d->bonds_path, "%s/%s.bonds.lammpstrj", out_dir, d->stage);
    const char *bad = NULL;
    int lammps = (spec->formats & APP_DUMP_LAMMPS) != 0;
    if ((spec->formats & APP_DUMP_VTK) && app_make_dirs(folder) != 0)
        bad = folder;
    else if (lammps && !(d->lammps = app_tmp_open(d->lammps_path, NULL)))
        bad = d->lammps_path;
    else if (lammps && spec->contacts && !(d->bonds = app_tmp_open(d->bonds_path, NULL)))
        bad = d->bonds_path;
    if (bad) {
        snprintf(err, err_size, "dump of stage %s: cannot write %s", d->stage, bad);
        app_tmp_discard(&d->lammps, d->lammps_path);
        free(d);
        return -1;
    }
    *dump = d;
    return 0;
}

void app_dump_frame(AppDump *d, const SimFrame *f)
{
    if (!d || d->failed || (d->frames > 0 && f->step == d->last_step))
        return;
    if (d->frames == d->capacity) {
        int capacity = d->capacity ? 2 * d->capacity : 64;
        double *times = realloc(d->times, (size_t)capacity * sizeof *times);
        if (!times) {
            fail(d, "out of memory at", "a frame");
            return;
        }
        d->times = times;
        d->capacity = capacity;
    }
    const AppDumpSpec *s = &d->spec;
    const SimWorldDef *def = &d->scene->def;
    if (d->lammps &&
        app_dump_lammps_frame(d->lammps, f, s->fields, s->field_count, def, d->species) != 0)
        fail(d, "cannot write", d->lammps_path);
    if (d->bonds && app_dump_lammps_contacts(d->bonds, f) != 0)
        fail(d, "cannot write", d->bonds_path);
    char path[DUMP_PATH];
    for (int k = 0; k < SERIES_COUNT; ++k) {
        if (!series_on(d, k))
            continue;
        vtp_path(d, path, sizeof path, SERIES[k], d->frames, 1);
        int rc = k == 0   ? app_dump_vtp_grains(path, f, s->fields, s->field_count, def, s->binary)
                 : k == 1 ? app_dump_vtp_contacts(path, f, s->binary)
                          : app_dump_vtp_walls(path, f, s->binary);
        if (rc != 0)
            fail(d, "cannot write", path);
    }
    d->times[d->frames++] = f->time;
    d->last_step = f->step;
}

void app_dump_checkpoint(const AppDump *d, FILE *out)
{
    const double counts[2] = {(double)d->frames, (double)d->last_step};
    app_checkpoint_put(out, "frames", counts, 2);
    app_checkpoint_put(out, "times", d->times, d->frames);
    if (d->lammps)
        app_checkpoint_file(out, d->lammps_path, d->lammps);
    if (d->bonds)
        app_checkpoint_file(out, d->bonds_path, d->bonds);
}

int app_dump_resume(AppDump *d, const char *record, char *err, size_t err_size)
{
    double counts[2];
    int bad = app_checkpoint_take(record, "frames", counts, 2) != 0 || !(counts[0] >= 0.0) ||
              counts[0] > 1e9;
    int frames = bad ? 0 : (int)counts[0];
    double *times = bad ? NULL : malloc((size_t)(frames > 0 ? frames : 1) * sizeof *times);
    if (!bad && (!times || app_checkpoint_take(record, "times", times, frames) != 0))
        bad = 1;
    const char *reopen = NULL;
    if (!bad && d->lammps && app_checkpoint_reopen(record, d->lammps_path, &d->lammps) != 0)
        reopen = d->lammps_path;
    else if (!bad && d->bonds && app_checkpoint_reopen(record, d->bonds_path, &d->bonds) != 0)
        reopen = d->bonds_path;
    if (reopen) {
        snprintf(err, err_size,
                 "--resume: dump of stage %s: %s.tmp: %s (not as long as the "
                 "checkpoint records)",
                 d->stage, reopen, strerror(errno));
        free(times);
        return -1;
    }
    if (bad) {
        snprintf(err, err_size, "--resume: dump of stage %s: the checkpoint's record is malformed",
                 d->stage);
        free(times);
        return -1;
    }
    free(d->times);
    d->times = times;
    d->frames = d->capacity = frames;
    d->last_step = (long)counts[1];
    for (int k = frames; d->spec.formats & APP_DUMP_VTK; ++k) { /* frames after the checkpoint */
        int gone = 1;
        for (int s = 0; s < SERIES_COUNT; ++s) {
            char path[DUMP_PATH];
            vtp_path(d, path, sizeof path, SERIES[s], k, 1);
            gone &= remove(path) != 0;
        }
        if (gone)
            break;
    }
    return 0;
}

/* DIR/<stage><series>.pvd: the frames' files and times (ParaView's time series). */
static int write_pvd(AppDump *d, int series)
{
    char path[DUMP_PATH], name[DUMP_PATH];
    snprintf(path, sizeof path, "%s/%s%s.pvd", d->dir, d->stage, SERIES[series]);
    FILE *out = app_pvd_open(path);
    if (!out) {
        fail(d, "cannot write", path);
        return -1;
    }
    for (int k = 0; k < d->frames; ++k) {
        vtp_path(d, name, sizeof name, SERIES[series], k, 0);
        app_pvd_entry(out, d->times[k], 0, name);
    }
    if (app_pvd_commit(&out, path) != 0) {
        fail(d, "cannot write", path);
        return -1;
    }
    return 0;
}

/* Copies the data sets of DIR/<stage><series>.pvd into the run's index as block `part`; a data
 * set at the time of the run's last one of that block replaces nothing (a stage's first frame is
 * the end state of the stage before it, listed there). */
static void merge_pvd(FILE *out, const char *dir, const char *stage, int part, double *last)
{
    char path[DUMP_PATH], line[DUMP_PATH + 128];
    snprintf(path, sizeof path, "%s/%s%s.pvd", dir, stage, SERIES[part]);
    FILE *in = fopen(path, "r");
    while (in && fgets(line, sizeof line, in)) {
        const char *t = strstr(line, "timestep=\""), *f = strstr(line, "file=\"");
        const char *end = f ? strchr(f + 6, '"') : NULL;
        if (!t || !end)
            continue;
        double time = strtod(t + 10, NULL);
        if (time <= *last)
            continue;
        char file[DUMP_PATH];
        snprintf(file, sizeof file, "%.*s", (int)(end - f - 6), f + 6);
        app_pvd_entry(out, time, part, file);
        *last = time;
    }
    if (in)
        fclose(in);
}

/* DIR/run.all.pvd: every stage's series so far, grains as block 0, contacts 1, walls 2 (a stage
 * name has no dot: no stage's files can take this name). */
static int write_run_pvd(AppDump *d)
{
    char path[DUMP_PATH];
    snprintf(path, sizeof path, "%s/run.all.pvd", d->dir);
    FILE *out = app_pvd_open(path);
    if (!out)
        return -1;
    for (int s = 0; s < SERIES_COUNT; ++s) {
        double last = -INFINITY;
        for (int k = 0; k <= d->stage_index; ++k)
            if (d->scene->output.dump[k].formats & APP_DUMP_VTK)
                merge_pvd(out, d->dir, d->scene->stages[k].name, s, &last);
    }
    return app_pvd_commit(&out, path);
}

int app_dump_close(AppDump **dump, SimWorld *world, int ok, char *err, size_t err_size)
{
    AppDump *d = *dump;
    if (!d)
        return 0;
    *dump = NULL;
    if (ok && world && (d->frames == 0 || d->last_step != sim_world_step_count(world))) {
        SimFrame frame; /* the stage's end state is the last frame */
        sim_world_frame(world, &frame);
        app_dump_frame(d, &frame);
    }
    if (ok && !d->failed && app_tmp_commit(&d->lammps, d->lammps_path) != 0)
        fail(d, "cannot write", d->lammps_path);
    if (ok && !d->failed && app_tmp_commit(&d->bonds, d->bonds_path) != 0)
        fail(d, "cannot write", d->bonds_path);
    for (int s = 0; s < SERIES_COUNT; ++s)
        if (ok && !d->failed && series_on(d, s))
            write_pvd(d, s);
    if (ok && !d->failed && (d->spec.formats & APP_DUMP_VTK) && write_run_pvd(d) != 0)
        fail(d, "cannot write", "run.all.pvd");
    app_tmp_discard(&d->lammps, d->lammps_path); /* a failed stage leaves no half dump */
    app_tmp_discard(&d->bonds, d->bonds_path);
    int rc = ok && d->failed ? -1 : 0;
    if (rc)
        snprintf(err, err_size, "%s", d->message);
    free(d->times);
    free(d);
    return rc;
}
