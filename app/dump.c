/* SPDX-License-Identifier: MIT */
/* dump.c: per-grain dumps (docs/dumps.md): the `dump` keys of a scene, checked at load, and the
 * writers of a run: a LAMMPS text dump per stage, streamed into PATH.tmp and renamed at the stage
 * end, and a VTK XML PolyData file per frame (grains as points, contacts as lines), each written
 * through PATH.tmp, with a ParaView .pvd time index per series. VTK data are ASCII with 17
 * significant digits, so every double reads back to the same bits. The export command and the
 * checkpoint frame are dump_export.c. */
#include "dump.h"

#include "checkpoint.h"
#include "run.h"
#include "scene.h"
#include "util.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A path under the output folder (at most SCENE_PATH_MAX): DIR/<stage>/<stage>_contacts_N.vtp */
#define DUMP_PATH (SCENE_PATH_MAX + 3 * SCENE_NAME_MAX + 32)

static const char *const FIELD_NAMES[] = {"id",      "type",   "x",     "y",      "vx",   "vy",
                                          "omega",   "radius", "fx",    "fy",     "mass", "angle",
                                          "species", "fixed",  "force", "torque", NULL};

/* LAMMPS column names of each field: y, vy and fy carry the 2D slab's zero z component. */
static const char *const LAMMPS_NAMES[] = {"id",      "type",   "x",     "y z",   "vx",   "vy vz",
                                           "omegaz",  "radius", "fx",    "fy fz", "mass", "angle",
                                           "species", "fixed",  "force", "tqz"};

static const char *const FORMAT_NAMES[] = {"lammps", "vtk", NULL};

const char *app_dump_field_name(int field)
{
    return field >= 0 && field < APP_DUMP_FIELD_COUNT ? FIELD_NAMES[field] : NULL;
}

/* ---------------------------------------------------------------- scene keys */

static AppDumpSpec spec_default(void)
{
    AppDumpSpec s;
    memset(&s, 0, sizeof s);
    s.formats = APP_DUMP_LAMMPS;
    s.field_count = APP_DUMP_DEFAULT_FIELDS;
    for (int k = 0; k < APP_DUMP_DEFAULT_FIELDS; ++k)
        s.fields[k] = (unsigned char)k; /* id type x y vx vy omega radius fx fy */
    s.contacts = 1;
    s.max_frames = APP_DUMP_MAX_FRAMES;
    return s;
}

static int name_index(const char *const *names, const char *name)
{
    for (int k = 0; names[k]; ++k)
        if (strcmp(names[k], name) == 0)
            return k;
    return -1;
}

/* `key` = ["name", ...] of `names`, each at most once: indices into out, their number in *count
 * (an empty array only for `format`: no dump). 1 when present, 0 absent, -1 bad. */
static int names_list(AppConfig *p, const config_setting_t *g, const char *key, const char *what,
                      const char *const *names, unsigned char *out, int *count)
{
    const config_setting_t *s = app_config_member(g, key);
    if (!s)
        return 0;
    char expected[256] = "";
    for (int k = 0; names[k]; ++k)
        snprintf(expected + strlen(expected), sizeof expected - strlen(expected), "%s%s",
                 k ? ", " : "", names[k]);
    int type = config_setting_type(s);
    int n = type == CONFIG_TYPE_ARRAY || type == CONFIG_TYPE_LIST ? config_setting_length(s) : -1;
    if (n < (strcmp(key, "format") == 0 ? 0 : 1))
        return app_config_fail(p, s, "`%s` must be an array of names (%s)", key, expected);
    for (int j = 0; j < n; ++j) {
        const config_setting_t *e = config_setting_get_elem(s, (unsigned)j);
        const char *name =
            config_setting_type(e) == CONFIG_TYPE_STRING ? config_setting_get_string(e) : NULL;
        int index = name ? name_index(names, name) : -1;
        if (index < 0)
            return app_config_fail(p, e, "unknown %s `%s` (expected: %s)", what,
                                   name ? name : app_config_type_name(e), expected);
        for (int i = 0; i < j; ++i)
            if (out[i] == index)
                return app_config_fail(p, e, "`%s` lists `%s` twice", key, name);
        out[j] = (unsigned char)index;
    }
    *count = n;
    return 1;
}

/* The keys of one dump group on top of *spec; *every_at = the setting of `every` when given. */
static int apply_group(AppConfig *p, const config_setting_t *g, AppDumpSpec *spec,
                       const config_setting_t **every_at)
{
    static const char *const keys[] = {"format", "every", "fields", "contacts", "max_frames", NULL};
    unsigned char formats[APP_DUMP_FIELD_COUNT];
    int n = 0, found;
    long long max_frames = spec->max_frames;
    if (app_config_keys(p, g, NULL, keys, NULL) < 0 ||
        (found = names_list(p, g, "format", "format", FORMAT_NAMES, formats, &n)) < 0)
        return -1;
    if (found) {
        spec->formats = 0;
        for (int k = 0; k < n; ++k)
            spec->formats |= formats[k] == 0 ? APP_DUMP_LAMMPS : APP_DUMP_VTK;
    }
    double every = spec->every;
    if ((found = app_config_number(p, g, "every", &every)) < 0)
        return -1;
    if (found) {
        if (!(every > 0.0))
            return app_config_fail(p, app_config_member(g, "every"),
                                   "`every` must be > 0 s of simulated time (got %g)", every);
        spec->every = every;
        *every_at = app_config_member(g, "every");
    }
    if (names_list(p, g, "fields", "field", FIELD_NAMES, spec->fields, &spec->field_count) < 0 ||
        app_config_bool(p, g, "contacts", &spec->contacts) < 0 ||
        app_config_int(p, g, "max_frames", &max_frames) < 0)
        return -1;
    if (max_frames < 1 || max_frames > 1000000000LL)
        return app_config_fail(p, app_config_member(g, "max_frames"),
                               "`max_frames` must be in [1, 1e9]");
    spec->max_frames = (long)max_frames;
    return 0;
}

long app_dump_every_steps(const AppDumpSpec *spec, double dt)
{
    return (long)fmax(1.0, (double)llround(spec->every / dt)); /* as the energy rows' cadence */
}

long app_dump_frame_bound(const AppDumpSpec *spec, double duration, double dt)
{
    if (dt > 0.0) {
        double total = (double)llround(duration / dt),
               every = (double)app_dump_every_steps(spec, dt);
        double n = floor(total / every) + 1.0 + (fmod(total, every) != 0.0);
        return n < (double)(LONG_MAX / 2) ? (long)n : LONG_MAX / 2;
    }
    double n = floor(duration / spec->every) + 2.0; /* the start, every `every`, the end */
    return n < (double)(LONG_MAX / 2) ? (long)n : LONG_MAX / 2;
}

/* Stage k's dump: output.dump (`base`, may be NULL) with the stage's own `dump` on top. */
static int stage_spec(AppConfig *p, const config_setting_t *base, const AppDumpSpec *common,
                      const config_setting_t *common_every, const config_setting_t *stage_group,
                      struct Scene *scene, int k)
{
    const SceneStage *stage = &scene->stages[k];
    const config_setting_t *own = app_config_member(stage_group, "dump");
    const config_setting_t *every_at = common_every, *where = base;
    AppDumpSpec spec = *common;
    int declared = base != NULL;
    char label[SCENE_NAME_MAX + 24];
    snprintf(label, sizeof label, "stage %s: dump", stage->name);
    p->group = own ? label : "output.dump";
    if (own && config_setting_type(own) == CONFIG_TYPE_BOOL) {
        declared = config_setting_get_bool(own);
        if (declared && !base)
            return app_config_fail(p, own, "`dump = true` needs an `output.dump` group to use");
    } else if (own && config_setting_type(own) == CONFIG_TYPE_GROUP) {
        if (apply_group(p, own, &spec, &every_at) < 0)
            return -1;
        declared = 1;
        where = own;
    } else if (own) {
        return app_config_fail(p, own, "`dump` must be a group { every = ...; } or false");
    }
    memset(&scene->output.dump[k], 0, sizeof scene->output.dump[k]);
    if (!declared || !spec.formats) /* dump = false, or format = [] */
        return 0;
    if (!every_at)
        return app_config_fail(p, where, "`every` is required (simulated seconds between frames)");
    long bound = app_dump_frame_bound(&spec, stage->duration, stage->time_step);
    if (!stage->skip && bound > spec.max_frames)
        return app_config_fail(p, every_at,
                               "`every` = %g s over stage `%s` (%g s) makes up to %ld frames, "
                               "more than max_frames = %ld: raise `max_frames` to ask for them",
                               spec.every, stage->name, stage->duration, bound, spec.max_frames);
    scene->output.dump[k] = spec;
    return 0;
}

int app_dump_parse(AppConfig *p, const config_setting_t *root, struct Scene *scene)
{
    const char *group = p->group;
    const config_setting_t *output = app_config_member(root, "output");
    const config_setting_t *base = app_config_member(output, "dump");
    const config_setting_t *stages = app_config_member(root, "stages"), *common_every = NULL;
    AppDumpSpec common = spec_default();
    int rc = 0;
    p->group = "output.dump";
    if (base && config_setting_type(base) != CONFIG_TYPE_GROUP)
        rc = app_config_fail(p, base, "`dump` must be a group { every = ...; }");
    else if (base)
        rc = apply_group(p, base, &common, &common_every);
    for (int k = 0; rc == 0 && k < scene->stage_count; ++k)
        rc = stage_spec(p, base, &common, common_every,
                        stages ? config_setting_get_elem(stages, (unsigned)k) : NULL, scene, k);
    p->group = group;
    return rc;
}

void app_dump_describe(const AppDumpSpec *spec, double duration, double dt, FILE *out)
{
    if (!spec->formats)
        return;
    fprintf(out, "  dump             %s%s%s every %g s, at most %ld frames (max_frames %ld):",
            spec->formats & APP_DUMP_LAMMPS ? "lammps" : "",
            spec->formats == (APP_DUMP_LAMMPS | APP_DUMP_VTK) ? ", " : "",
            spec->formats & APP_DUMP_VTK ? (spec->contacts ? "vtk (+ contacts)" : "vtk") : "",
            spec->every, app_dump_frame_bound(spec, duration, dt), spec->max_frames);
    for (int k = 0; k < spec->field_count; ++k)
        fprintf(out, " %s", FIELD_NAMES[spec->fields[k]]);
    fputc('\n', out);
}

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

int app_dump_lammps_frame(FILE *out, const SimFrame *f, const unsigned char *fields, int count,
                          const SimWorldDef *def)
{
    double lo[3], hi[3];
    frame_box(f, lo, hi);
    fprintf(out,
            "ITEM: TIME\n%.17g\nITEM: TIMESTEP\n%ld\nITEM: NUMBER OF ATOMS\n%d\n"
            "ITEM: BOX BOUNDS %s ff pp\n%.17g %.17g\n%.17g %.17g\n%.17g %.17g\nITEM: ATOMS",
            f->time, f->step, f->count, f->periodic ? "pp" : "ff", lo[0], hi[0], lo[1], hi[1],
            lo[2], hi[2]);
    for (int k = 0; k < count; ++k)
        fprintf(out, " %s", LAMMPS_NAMES[fields[k]]);
    fputc('\n', out);
    for (int i = 0; i < f->count; ++i) {
        for (int k = 0; k < count; ++k) {
            double v = 0.0;
            long long n = 0;
            const char *gap = k ? " " : "";
            if (field_value(f, def, fields[k], i, 1, &v, &n))
                fprintf(out, "%s%lld", gap, n);
            else
                fprintf(out, "%s%.17g", gap, v);
            if (fields[k] == APP_DUMP_Y || fields[k] == APP_DUMP_VY || fields[k] == APP_DUMP_FY)
                fputs(" 0", out); /* z, vz, fz of the slab */
        }
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}

static void vtk_open(FILE *out, int points, int verts, int lines)
{
    fprintf(out,
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
            "<PolyData>\n<Piece NumberOfPoints=\"%d\" NumberOfVerts=\"%d\" NumberOfLines=\"%d\" "
            "NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n",
            points, verts, lines);
}

static int vtk_close(FILE **out, const char *path)
{
    fputs("</Piece>\n</PolyData>\n</VTKFile>\n", *out);
    if (ferror(*out)) {
        app_tmp_discard(out, path);
        return -1;
    }
    return app_tmp_commit(out, path);
}

/* Cells of `count` single points (verts) or point pairs (lines): connectivity and offsets. */
static void vtk_cells(FILE *out, const char *what, const int *pairs, int count, int size)
{
    fprintf(out, "<%s>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n", what);
    for (int c = 0; c < count; ++c)
        if (size == 1)
            fprintf(out, "%d\n", c);
        else
            fprintf(out, "%d %d\n", pairs[2 * c], pairs[2 * c + 1]);
    fputs("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n", out);
    for (int c = 0; c < count; ++c)
        fprintf(out, "%d\n", (c + 1) * size);
    fprintf(out, "</DataArray>\n</%s>\n", what);
}

static void vtk_points(FILE *out, const double *x, const double *y, int n, const double *x2,
                       const double *y2, int n2)
{
    fputs("<Points>\n<DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" "
          "format=\"ascii\">\n",
          out);
    for (int i = 0; i < n; ++i)
        fprintf(out, "%.17g %.17g 0\n", x[i], y[i]);
    for (int i = 0; i < n2; ++i)
        fprintf(out, "%.17g %.17g 0\n", x2[i], y2[i]);
    fputs("</DataArray>\n</Points>\n", out);
}

int app_dump_vtp_grains(const char *path, const SimFrame *f, const unsigned char *fields, int count,
                        const SimWorldDef *def)
{
    FILE *out = app_tmp_open(path, NULL);
    if (!out)
        return -1;
    int has[APP_DUMP_FIELD_COUNT] = {0};
    for (int k = 0; k < count; ++k)
        has[fields[k]] = 1;
    int velocity = has[APP_DUMP_VX] && has[APP_DUMP_VY];
    vtk_open(out, f->count, f->count, 0);
    fprintf(out, "<PointData%s%s>\n", has[APP_DUMP_RADIUS] ? " Scalars=\"radius\"" : "",
            velocity ? " Vectors=\"velocity\"" : "");
    for (int k = 0; k < count; ++k) {
        if (fields[k] == APP_DUMP_X || fields[k] == APP_DUMP_Y)
            continue; /* the points */
        double v = 0.0;
        long long n = 0;
        int integer = f->count > 0 && field_value(f, def, fields[k], 0, 0, &v, &n);
        if (f->count == 0) /* the type of an empty array still names the field's kind */
            integer = fields[k] == APP_DUMP_ID || fields[k] == APP_DUMP_TYPE ||
                      fields[k] == APP_DUMP_SPECIES || fields[k] == APP_DUMP_FIXED;
        fprintf(out, "<DataArray type=\"%s\" Name=\"%s\" format=\"ascii\">\n",
                integer ? "Int64" : "Float64", FIELD_NAMES[fields[k]]);
        for (int i = 0; i < f->count; ++i)
            if (field_value(f, def, fields[k], i, 0, &v, &n))
                fprintf(out, "%lld\n", n);
            else
                fprintf(out, "%.17g\n", v);
        fputs("</DataArray>\n", out);
    }
    if (velocity) { /* vx, vy, 0 for glyphs */
        fputs("<DataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\" "
              "format=\"ascii\">\n",
              out);
        for (int i = 0; i < f->count; ++i)
            fprintf(out, "%.17g %.17g 0\n", f->vx[i], f->vy[i]);
        fputs("</DataArray>\n", out);
    }
    fputs("</PointData>\n", out);
    vtk_points(out, f->x, f->y, f->count, NULL, NULL, 0);
    vtk_cells(out, "Verts", NULL, f->count, 1);
    return vtk_close(&out, path);
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

int app_dump_vtp_contacts(const char *path, const SimFrame *f)
{
    ContactLines l;
    memset(&l, 0, sizeof l);
    FILE *out = NULL;
    int rc = -1;
    if (contact_lines(f, &l) == 0 && (out = app_tmp_open(path, NULL)) != NULL) {
        vtk_open(out, f->count + l.extra, 0, l.count);
        fputs("<CellData Scalars=\"normal_force\">\n", out);
        for (int a = 0; a < 2; ++a) { /* F_n (positive: repulsive) and |F_t|, N */
            fprintf(out, "<DataArray type=\"Float64\" Name=\"%s\" format=\"ascii\">\n",
                    a ? "tangential_force" : "normal_force");
            for (int c = 0; c < l.count; ++c) {
                const SimContact *k = &f->contacts[l.contact[c]];
                fprintf(out, "%.17g\n", a ? fabs(k->tangential_force) : k->normal_force);
            }
            fputs("</DataArray>\n", out);
        }
        fputs("</CellData>\n", out);
        vtk_points(out, f->x, f->y, f->count, l.ex, l.ey, l.extra);
        vtk_cells(out, "Lines", l.pairs, l.count, 2);
        rc = vtk_close(&out, path);
    }
    free(l.pairs);
    free(l.contact);
    free(l.ex);
    free(l.ey);
    return rc;
}

/* ---------------------------------------------------------------- a stage's writer */

struct AppDump {
    AppDumpSpec spec;
    const SimWorldDef *def; /* masses */
    char stage[SCENE_NAME_MAX];
    char dir[SCENE_PATH_MAX];
    char lammps_path[DUMP_PATH];
    FILE *lammps;
    double *times; /* s, of each frame */
    int frames, capacity;
    long last_step;
    int failed;
    char message[DUMP_PATH + SCENE_NAME_MAX + 64];
};

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
    d->def = &scene->def;
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
    const char *bad = NULL;
    if ((spec->formats & APP_DUMP_VTK) && app_make_dirs(folder) != 0)
        bad = folder;
    else if ((spec->formats & APP_DUMP_LAMMPS) && !(d->lammps = app_tmp_open(d->lammps_path, NULL)))
        bad = d->lammps_path;
    if (bad) {
        snprintf(err, err_size, "dump of stage %s: cannot write %s", d->stage, bad);
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
    if (d->lammps && app_dump_lammps_frame(d->lammps, f, s->fields, s->field_count, d->def) != 0)
        fail(d, "cannot write", d->lammps_path);
    char path[DUMP_PATH];
    if (s->formats & APP_DUMP_VTK) {
        vtp_path(d, path, sizeof path, "", d->frames, 1);
        if (app_dump_vtp_grains(path, f, s->fields, s->field_count, d->def) != 0)
            fail(d, "cannot write", path);
        vtp_path(d, path, sizeof path, "_contacts", d->frames, 1);
        if (s->contacts && app_dump_vtp_contacts(path, f) != 0)
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
    if (!bad && (d->spec.formats & APP_DUMP_LAMMPS) &&
        app_checkpoint_reopen(record, d->lammps_path, &d->lammps) != 0) {
        snprintf(err, err_size,
                 "--resume: dump of stage %s: %s.tmp: %s (not as long as the "
                 "checkpoint records)",
                 d->stage, d->lammps_path, strerror(errno));
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
        char path[DUMP_PATH];
        vtp_path(d, path, sizeof path, "", k, 1);
        int gone = remove(path) != 0;
        vtp_path(d, path, sizeof path, "_contacts", k, 1);
        if ((remove(path) != 0) && gone)
            break;
    }
    return 0;
}

/* DIR/<stage><series>.pvd: the frames' files and times (ParaView's time series). */
static int write_pvd(AppDump *d, const char *series)
{
    char path[DUMP_PATH], name[DUMP_PATH];
    snprintf(path, sizeof path, "%s/%s%s.pvd", d->dir, d->stage, series);
    FILE *out = app_tmp_open(path, "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" "
                                   "version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>");
    if (!out) {
        fail(d, "cannot write", path);
        return -1;
    }
    for (int k = 0; k < d->frames; ++k) {
        vtp_path(d, name, sizeof name, series, k, 0);
        fprintf(out, "<DataSet timestep=\"%.17g\" group=\"\" part=\"0\" file=\"%s\"/>\n",
                d->times[k], name);
    }
    fputs("</Collection>\n</VTKFile>\n", out);
    if (ferror(out)) {
        app_tmp_discard(&out, path);
        fail(d, "cannot write", path);
        return -1;
    }
    if (app_tmp_commit(&out, path) != 0) {
        fail(d, "cannot write", path);
        return -1;
    }
    return 0;
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
    if (ok && !d->failed && (d->spec.formats & APP_DUMP_VTK) && write_pvd(d, "") == 0 &&
        d->spec.contacts)
        write_pvd(d, "_contacts");
    app_tmp_discard(&d->lammps, d->lammps_path); /* a failed stage leaves no half dump */
    int rc = ok && d->failed ? -1 : 0;
    if (rc)
        snprintf(err, err_size, "%s", d->message);
    free(d->times);
    free(d);
    return rc;
}
