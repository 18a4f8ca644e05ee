/* SPDX-License-Identifier: MIT */
/* test_dump.c: the per-grain dumps (app/output/dump.c, docs/dumps.md): the LAMMPS frame's header,
 * atom count and values (every double back to the same bits), the VTK PolyData files of grains and
 * contacts by their element counts, the `dump` keys of a scene, and a run's files: committed at
 * the stage end, none left half-written when the run fails. The real readers (lmp, VTK) are
 * tests/clients. */
#include "test.h"

#include "app/output/dump.h"
#include "app/output/vtk_xml.h"
#include "app/run/run.h"
#include "app/scene/scene.h"
#include "sim/sim.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define SCENE "tests/clients/dump.scene"

/* The grains of dump.scene after 0.5 s of falling: contacts with the floor and each other. */
static SimWorld *fallen_world(Scene **scene)
{
    char err[2048];
    *scene = scene_load(SCENE, NULL, 0, err, sizeof err);
    if (!*scene) {
        fprintf(stderr, "%s\n", err);
        return NULL;
    }
    SimWorldDef def = scene_world_def(*scene, 0);
    SimError error;
    SimWorld *w = sim_world_create(&def, &error);
    if (w && sim_world_step(w, 10000, &error) != SIM_OK) {
        sim_world_destroy(w);
        w = NULL;
    }
    return w;
}

static int count_of(const char *text, const char *needle)
{
    int n = 0;
    for (const char *p = strstr(text, needle); p; p = strstr(p + 1, needle))
        ++n;
    return n;
}

/* The numbers of the DataArray named `name` (up to its closing tag) into v; their count. */
static int vtk_array(const char *text, const char *name, double *v, int max)
{
    char tag[80];
    snprintf(tag, sizeof tag, "Name=\"%s\"", name);
    const char *p = strstr(text, tag);
    if (!p || !(p = strchr(p, '>')))
        return -1;
    const char *end = strstr(p, "</DataArray>");
    int n = 0;
    for (char *q = (char *)(uintptr_t)(p + 1); q < end && n < max;) {
        char *next;
        double x = strtod(q, &next);
        if (next == q || next > end)
            break;
        v[n++] = x;
        q = next;
    }
    return n;
}

/* Every field of every grain reads back from the LAMMPS frame with strtod to the same bits. */
static int lammps_frame_round_trip(void)
{
    Scene *scene = NULL;
    SimWorld *w = fallen_world(&scene);
    TEST_ASSERT(w);
    SimFrame f;
    sim_world_frame(w, &f);
    TEST_ASSERT(f.contact_count > 10 && f.count > 100);
    unsigned char fields[APP_DUMP_FIELD_COUNT];
    for (int k = 0; k < APP_DUMP_FIELD_COUNT; ++k)
        fields[k] = (unsigned char)k; /* element last, left out: a name, not a number */
    char path[32];
    TEST_ASSERT(test_tmp_file(path) == 0);
    FILE *out = fopen(path, "w");
    TEST_ASSERT(out);
    TEST_ASSERT(
        app_dump_lammps_frame(out, &f, fields, APP_DUMP_FIELD_COUNT - 1, &scene->def, NULL) == 0);
    fclose(out);
    FILE *in = fopen(path, "r");
    char line[4096];
    long step = -1;
    int atoms = -1;
    double t = -1.0, lo[3], hi[3];
    TEST_ASSERT(fgets(line, sizeof line, in) && strcmp(line, "ITEM: UNITS\n") == 0);
    TEST_ASSERT(fgets(line, sizeof line, in) && strcmp(line, "si\n") == 0);
    TEST_ASSERT(fgets(line, sizeof line, in) && strcmp(line, "ITEM: TIME\n") == 0);
    TEST_ASSERT(fscanf(in, "%lf\n", &t) == 1 && t == f.time);
    TEST_ASSERT(fgets(line, sizeof line, in) && strcmp(line, "ITEM: TIMESTEP\n") == 0);
    TEST_ASSERT(fscanf(in, "%ld\n", &step) == 1 && step == f.step && step == 10000);
    TEST_ASSERT(fgets(line, sizeof line, in) && strcmp(line, "ITEM: NUMBER OF ATOMS\n") == 0);
    TEST_ASSERT(fscanf(in, "%d\n", &atoms) == 1 && atoms == f.count);
    TEST_ASSERT(fgets(line, sizeof line, in) && strcmp(line, "ITEM: BOX BOUNDS ff ff pp\n") == 0);
    for (int a = 0; a < 3; ++a)
        TEST_ASSERT(fscanf(in, "%lf %lf\n", &lo[a], &hi[a]) == 2 && hi[a] > lo[a]);
    TEST_ASSERT(lo[2] < 0.0 && hi[2] == -lo[2]); /* the slab around z = 0 */
    TEST_ASSERT(fgets(line, sizeof line, in));
    TEST_ASSERT(strcmp(line, "ITEM: ATOMS id type x y z vx vy vz omegaz radius fx fy fz mass angle "
                             "species fixed force tqz\n") == 0);
    int rows = 0;
    while (fgets(line, sizeof line, in)) {
        double v[19];
        char *p = line;
        for (int c = 0; c < 19; ++c) {
            char *next;
            v[c] = strtod(p, &next);
            TEST_ASSERT(next != p);
            p = next;
        }
        int i = rows++;
        TEST_ASSERT(i < f.count);
        TEST_ASSERT(lo[0] <= f.x[i] - f.radius[i] && f.x[i] + f.radius[i] <= hi[0]);
        TEST_ASSERT(v[0] == (double)f.id[i] + 1.0 && v[1] == (double)f.species[i] + 1.0);
        TEST_ASSERT(v[2] == f.x[i] && v[3] == f.y[i] && v[4] == 0.0);
        TEST_ASSERT(v[5] == f.vx[i] && v[6] == f.vy[i] && v[7] == 0.0 && v[8] == f.omega[i]);
        TEST_ASSERT(v[9] == f.radius[i] && v[10] == f.fx[i] && v[11] == f.fy[i] && v[12] == 0.0);
        double r = f.radius[i], m = 1190.0 * 4.0 / 3.0 * SIM_PI * r * r * r; /* sphere */
        TEST_ASSERT(v[13] == m && v[14] == f.angle[i] && v[15] == (double)f.species[i]);
        TEST_ASSERT(v[16] == ((f.flags[i] & SIM_GRAIN_FIXED) ? 1.0 : 0.0));
        TEST_ASSERT(v[17] == f.force[i] && v[18] == f.torque[i]);
    }
    TEST_ASSERT(rows == f.count);
    fclose(in);
    remove(path);
    sim_world_destroy(w);
    scene_free(scene);
    return 0;
}

/* A periodic world's box spans its domain in x, flagged pp. */
static int lammps_periodic_box(void)
{
    double x[2] = {0.5, 1.5}, y[2] = {0.2, 0.2}, r[2] = {0.1, 0.1};
    SimWorldDef def = sim_world_def_default();
    def.effects = SIM_EFFECT_PERIODIC_X;
    def.domain_x0 = 0.0;
    def.domain_x1 = 2.0;
    def.time_step = 1e-5;
    def.species_count = 1;
    def.materials[0] = sim_material_default();
    def.grains = (SimGrainSet){.count = 2, .x = x, .y = y, .radius = r};
    SimError e;
    SimWorld *w = sim_world_create(&def, &e);
    TEST_ASSERT(w);
    SimFrame f;
    sim_world_frame(w, &f);
    char path[32];
    TEST_ASSERT(test_tmp_file(path) == 0);
    FILE *out = fopen(path, "w");
    const unsigned char fields[] = {APP_DUMP_ID, APP_DUMP_X, APP_DUMP_Y};
    TEST_ASSERT(app_dump_lammps_frame(out, &f, fields, 3, NULL, NULL) == 0);
    fclose(out);
    char *text = test_read_file(path, NULL);
    TEST_ASSERT(text);
    TEST_ASSERT(strstr(text, "ITEM: BOX BOUNDS pp ff pp\n0 2\n0.10000000000000001 "
                             "0.30000000000000004\n-0.10000000000000001 0.10000000000000001\n"));
    TEST_ASSERT(strstr(text, "ITEM: ATOMS id x y z\n1 0.5 0.20000000000000001 0\n2 1.5 "));
    free(text);
    remove(path);
    sim_world_destroy(w);
    return 0;
}

/* The grains' .vtp: one point and one vertex per grain, one array per field (x, y are the
 * points) plus the velocity vector, values to the bit. */
static int vtk_grains_file(void)
{
    Scene *scene = NULL;
    SimWorld *w = fallen_world(&scene);
    TEST_ASSERT(w);
    SimFrame f;
    sim_world_frame(w, &f);
    const unsigned char fields[] = {APP_DUMP_ID, APP_DUMP_TYPE, APP_DUMP_X,     APP_DUMP_Y,
                                    APP_DUMP_VX, APP_DUMP_VY,   APP_DUMP_OMEGA, APP_DUMP_RADIUS,
                                    APP_DUMP_FX, APP_DUMP_FY};
    char path[32];
    TEST_ASSERT(test_tmp_file(path) == 0);
    TEST_ASSERT(app_dump_vtp_grains(path, &f, fields, (int)sizeof fields, &scene->def, 0) == 0);
    char *text = test_read_file(path, NULL);
    TEST_ASSERT(text);
    char expect[128];
    snprintf(expect, sizeof expect, "<Piece NumberOfPoints=\"%d\" NumberOfVerts=\"%d\" ", f.count,
             f.count);
    TEST_ASSERT(strstr(text, "<VTKFile type=\"PolyData\""));
    TEST_ASSERT(strstr(text, expect));
    TEST_ASSERT(strstr(text, "<PointData Scalars=\"radius\" Vectors=\"velocity\">"));
    /* TimeValue + 8 fields + velocity + Points + connectivity + offsets */
    TEST_ASSERT(count_of(text, "<DataArray ") == 13);
    TEST_ASSERT(count_of(text, "</DataArray>") == 13);
    TEST_ASSERT(app_vtk_time_value(path) == f.time);
    TEST_ASSERT(strstr(text, "</VTKFile>\n"));
    double *v = malloc(3 * (size_t)f.count * sizeof *v + 8);
    TEST_ASSERT(vtk_array(text, "radius", v, f.count + 1) == f.count);
    for (int i = 0; i < f.count; ++i)
        TEST_ASSERT(v[i] == f.radius[i]);
    TEST_ASSERT(vtk_array(text, "Points", v, 3 * f.count + 1) == 3 * f.count);
    for (int i = 0; i < f.count; ++i)
        TEST_ASSERT(v[3 * i] == f.x[i] && v[3 * i + 1] == f.y[i] && v[3 * i + 2] == 0.0);
    TEST_ASSERT(vtk_array(text, "id", v, f.count + 1) == f.count);
    for (int i = 0; i < f.count; ++i)
        TEST_ASSERT(v[i] == (double)f.id[i]);
    TEST_ASSERT(vtk_array(text, "offsets", v, f.count + 1) == f.count && v[f.count - 1] == f.count);
    free(v);
    free(text);
    remove(path);
    sim_world_destroy(w);
    scene_free(scene);
    return 0;
}

/* The contacts' .vtp: one line per contact (this box has no walls and no seam), each with its
 * normal and tangential force. */
static int vtk_contacts_file(void)
{
    Scene *scene = NULL;
    SimWorld *w = fallen_world(&scene);
    TEST_ASSERT(w);
    SimFrame f;
    sim_world_frame(w, &f);
    char path[32];
    TEST_ASSERT(test_tmp_file(path) == 0);
    TEST_ASSERT(app_dump_vtp_contacts(path, &f, 0) == 0);
    char *text = test_read_file(path, NULL);
    TEST_ASSERT(text);
    char expect[160];
    snprintf(expect, sizeof expect,
             "NumberOfPoints=\"%d\" NumberOfVerts=\"0\" NumberOfLines=\"%d\"", f.count,
             f.contact_count);
    TEST_ASSERT(strstr(text, expect));
    double *v = malloc(2 * (size_t)f.contact_count * sizeof *v + 16);
    TEST_ASSERT(vtk_array(text, "normal_force", v, f.contact_count + 1) == f.contact_count);
    for (int c = 0; c < f.contact_count; ++c)
        TEST_ASSERT(v[c] == f.contacts[c].normal_force);
    TEST_ASSERT(vtk_array(text, "tangential_force", v, f.contact_count + 1) == f.contact_count);
    for (int c = 0; c < f.contact_count; ++c)
        TEST_ASSERT(v[c] == fabs(f.contacts[c].tangential_force));
    TEST_ASSERT(vtk_array(text, "connectivity", v, 2 * f.contact_count + 1) == 2 * f.contact_count);
    for (int c = 0; c < f.contact_count; ++c)
        TEST_ASSERT(v[2 * c] == f.contacts[c].i && v[2 * c + 1] == f.contacts[c].j);
    free(v);
    free(text);
    remove(path);
    sim_world_destroy(w);
    scene_free(scene);
    return 0;
}

/* Across the periodic seam a contact is two lines, each grain to the image of the other; with a
 * wall, a line from the centre to the contact point. */
static int vtk_contacts_seam_and_wall(void)
{
    double x[3] = {0.099, 1.910, 1.5}, y[3] = {0.5, 0.5, 0.095}, r[3] = {0.1, 0.1, 0.1};
    SimWall wall = {.x0 = 1.0, .y0 = 0.0, .x1 = 2.0, .y1 = 0.0, .species = 0, .motion = -1};
    SimWorldDef def = sim_world_def_default();
    def.effects = SIM_EFFECT_PERIODIC_X;
    def.domain_x0 = 0.0;
    def.domain_x1 = 2.0;
    def.time_step = 1e-5;
    def.species_count = 1;
    def.materials[0] = sim_material_default();
    def.grains = (SimGrainSet){.count = 3, .x = x, .y = y, .radius = r};
    def.walls = &wall;
    def.wall_count = 1;
    SimError e;
    SimWorld *w = sim_world_create(&def, &e);
    if (!w)
        fprintf(stderr, "%s: %s\n", e.field, e.message);
    TEST_ASSERT(w);
    SimFrame f;
    sim_world_frame(w, &f);
    TEST_ASSERT(f.contact_count == 2);
    char path[32];
    TEST_ASSERT(test_tmp_file(path) == 0);
    TEST_ASSERT(app_dump_vtp_contacts(path, &f, 0) == 0);
    char *text = test_read_file(path, NULL);
    TEST_ASSERT(text);
    /* 3 grains + 2 images + 1 wall contact point; 2 + 1 lines */
    TEST_ASSERT(strstr(text, "NumberOfPoints=\"6\" NumberOfVerts=\"0\" NumberOfLines=\"3\""));
    double v[20];
    TEST_ASSERT(vtk_array(text, "Points", v, 20) == 18);
    int seam = f.contacts[0].j >= 0 ? 0 : 1, i = f.contacts[seam].i, j = f.contacts[seam].j;
    double shift = f.x[j] > f.x[i] ? -2.0 : 2.0; /* j's image beside i */
    int images = 0, contact_point = 0;
    for (int p = 3; p < 6; ++p) {
        images += (v[3 * p] == f.x[j] + shift && v[3 * p + 1] == f.y[j]) ||
                  (v[3 * p] == f.x[i] - shift && v[3 * p + 1] == f.y[i]);
        contact_point +=
            v[3 * p] == f.contacts[1 - seam].x && v[3 * p + 1] == f.contacts[1 - seam].y;
    }
    TEST_ASSERT(images == 2 && contact_point == 1);
    double force[4];
    TEST_ASSERT(vtk_array(text, "normal_force", force, 4) == 3);
    int lines_of_seam = (force[0] == f.contacts[seam].normal_force) +
                        (force[1] == f.contacts[seam].normal_force) +
                        (force[2] == f.contacts[seam].normal_force);
    TEST_ASSERT(lines_of_seam == 2 && f.contacts[seam].normal_force > 0.0);
    free(text);
    remove(path);
    sim_world_destroy(w);
    return 0;
}

/* The walls' .vtp: a polyline per wall (a segment: 2 points, an arc: 33 along its span), the
 * wall index and species as cell data, the frame's time as TimeValue; raw appended when asked,
 * its blocks the same bytes as the ASCII numbers. */
static int vtk_walls_file(void)
{
    SimWall walls[2] = {{.x0 = 0.0, .y0 = 0.0, .x1 = 2.0, .y1 = 0.5, .motion = -1},
                        {.shape = SIM_WALL_ARC,
                         .species = 0,
                         .motion = -1,
                         .center_x = 1.0,
                         .center_y = 1.0,
                         .radius = 0.5,
                         .angle0 = 0.0,
                         .angle1 = 3.0}};
    SimFrame f;
    memset(&f, 0, sizeof f);
    f.time = 0.25;
    f.walls = walls;
    f.wall_count = 2;
    char path[32];
    TEST_ASSERT(test_tmp_file(path) == 0);
    TEST_ASSERT(app_dump_vtp_walls(path, &f, 0) == 0);
    char *text = test_read_file(path, NULL);
    TEST_ASSERT(text &&
                strstr(text, "NumberOfPoints=\"35\" NumberOfVerts=\"0\" NumberOfLines=\"2\""));
    double v[3 * 35 + 1], end[2];
    TEST_ASSERT(vtk_array(text, "offsets", v, 3) == 2 && v[0] == 2.0 && v[1] == 35.0);
    TEST_ASSERT(vtk_array(text, "Points", v, 3 * 35 + 1) == 3 * 35);
    TEST_ASSERT(v[3] == 2.0 && v[4] == 0.5); /* the segment's end */
    sim_wall_point(&walls[1], 1.0, &end[0], &end[1]);
    TEST_ASSERT(v[3 * 34] == end[0] && v[3 * 34 + 1] == end[1]); /* the arc's end */
    TEST_ASSERT(app_vtk_time_value(path) == 0.25);
    free(text);
    TEST_ASSERT(app_dump_vtp_walls(path, &f, 1) == 0); /* binary */
    text = test_read_file(path, NULL);
    TEST_ASSERT(text && strstr(text, "format=\"appended\"") &&
                !strstr(text, "format=\"ascii\">\n"));
    const char *data = strstr(text, "<AppendedData encoding=\"raw\">\n_");
    const char *points = strstr(text, "Name=\"Points\"");
    TEST_ASSERT(data && points);
    long offset = strtol(strstr(points, "offset=\"") + 8, NULL, 10);
    const char *block = data + strlen("<AppendedData encoding=\"raw\">\n_") + offset;
    uint64_t bytes;
    memcpy(&bytes, block, sizeof bytes);
    TEST_ASSERT(bytes == 3 * 35 * sizeof(double));
    double raw[3 * 35];
    memcpy(raw, block + sizeof bytes, sizeof raw);
    TEST_ASSERT(memcmp(raw, v, sizeof raw) == 0); /* the same doubles as the ASCII file */
    free(text);
    remove(path);
    return 0;
}

/* The keys: output.dump for every stage, a stage's own group on top, `dump = false`. */
static int scene_dump_keys(void)
{
    char err[2048];
    Scene *s = scene_load(SCENE, NULL, 0, err, sizeof err);
    TEST_ASSERT(s);
    const AppDumpSpec *fall = &s->output.dump[0], *pile = &s->output.dump[1];
    TEST_ASSERT(fall->formats == (APP_DUMP_LAMMPS | APP_DUMP_VTK) && fall->every == 0.2);
    TEST_ASSERT(fall->field_count == APP_DUMP_DEFAULT_FIELDS && fall->contacts == 1);
    TEST_ASSERT(fall->max_frames == APP_DUMP_MAX_FRAMES);
    TEST_ASSERT(app_dump_frame_bound(fall, 0.8, 5e-5) == 5); /* 0, 0.2, ..., 0.8 */
    TEST_ASSERT(app_dump_frame_bound(fall, 0.9, 5e-5) == 6); /* and the end */
    TEST_ASSERT(app_dump_frame_bound(fall, 0.9, 0.0) == 6);  /* from the times alone */
    TEST_ASSERT(pile->formats == APP_DUMP_VTK && pile->every == 0.1 && pile->contacts == 1);
    TEST_ASSERT(pile->field_count == 8 && pile->fields[1] == APP_DUMP_MASS);
    TEST_ASSERT(s->output.dump[2].formats == 0); /* dump = false */
    scene_free(s);
    const char *sets[] = {"output.dump.every=1e-6"};
    TEST_ASSERT(!scene_load(SCENE, sets, 1, err, sizeof err));
    TEST_ASSERT(strstr(err, "--set output.dump.every: ") && strstr(err, "max_frames = 10000"));
    const char *raised[] = {"output.dump.every=1e-6", "output.dump.max_frames=20000"};
    s = scene_load(SCENE, raised, 2, err, sizeof err);
    TEST_ASSERT(s && s->output.dump[0].max_frames == 20000);
    TEST_ASSERT(app_dump_every_steps(&s->output.dump[0], 5e-5) == 1); /* never faster than dt */
    scene_free(s);
    return 0;
}

static int exists(const char *dir, const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return access(path, F_OK) == 0;
}

static int run_scene(const char *dir, const char *const *sets, int set_count)
{
    char err[2048], command[600];
    snprintf(command, sizeof command, "rm -rf '%s'", dir);
    if (system(command) != 0)
        return -1;
    Scene *s = scene_load(SCENE, sets, set_count, err, sizeof err);
    if (!s)
        return -1;
    AppRunOptions o = app_run_options_default();
    o.out_dir = dir;
    o.quiet = 1;
    o.render_off = 1;
    int rc = app_run(s, &o);
    scene_free(s);
    return rc;
}

/* A run writes a frame at the start, every 0.2 s and the end of each dumped stage; the last one
 * is the checkpoint's state; nothing is left under .tmp. */
static int run_writes_dumps(void)
{
    char dir[128];
    snprintf(dir, sizeof dir, "/tmp/sablier_test_dump_%ld", (long)getpid());
    TEST_ASSERT(run_scene(dir, NULL, 0) == 0);
    const char *files[] = {"fall.lammpstrj",
                           "fall.pvd",
                           "fall_contacts.pvd",
                           "fall/fall_00004.vtp",
                           "fall/fall_contacts_00004.vtp",
                           "pile.pvd",
                           "pile/pile_00002.vtp",
                           "fall.bonds.lammpstrj",
                           "fall_walls.pvd",
                           "run.all.pvd"};
    for (size_t k = 0; k < sizeof files / sizeof files[0]; ++k)
        TEST_ASSERT(exists(dir, files[k]));
    const char *absent[] = {"fall.lammpstrj.tmp", "fall/fall_00005.vtp", "pile.lammpstrj",
                            "rest.pvd",           "rest.lammpstrj",      "rest"};
    for (size_t k = 0; k < sizeof absent / sizeof absent[0]; ++k)
        TEST_ASSERT(!exists(dir, absent[k]));
    char path[256];
    snprintf(path, sizeof path, "%s/fall.lammpstrj", dir);
    char *text = test_read_file(path, NULL);
    TEST_ASSERT(text && count_of(text, "ITEM: TIMESTEP\n") == 5);
    TEST_ASSERT(strstr(text, "ITEM: TIMESTEP\n4000\n") && strstr(text, "ITEM: TIMESTEP\n16000\n"));
    /* the last frame's grains are the checkpoint's, to the bit */
    SimGrainSet g;
    SimWall *walls = NULL;
    int wall_count = 0;
    double t = 0.0;
    SimError e;
    snprintf(path, sizeof path, "%s/fall.state", dir);
    TEST_ASSERT(sim_state_load(path, &g, &walls, &wall_count, &t, &e) == SIM_OK);
    const char *last = strstr(text, "ITEM: TIMESTEP\n16000\n");
    last = strstr(last, "fz fixed element\n") + 17; /* the default fields */
    int fixed = 0;
    for (int i = 0; i < g.count; ++i) {
        char *end;
        double id = strtod(last, &end), type = strtod(end, &end), x = strtod(end, &end),
               y = strtod(end, &end);
        TEST_ASSERT(id == (double)g.id[i] + 1.0 && type == 1.0 && x == g.x[i] && y == g.y[i]);
        const char *line_end = strchr(end, '\n'), *flag = line_end - strlen(" 1 acrylic");
        TEST_ASSERT(strncmp(flag + 2, " acrylic", 8) == 0);
        TEST_ASSERT(flag[1] == ((g.flags[i] & SIM_GRAIN_FIXED) ? '1' : '0'));
        fixed += flag[1] == '1';
        last = line_end + 1;
    }
    TEST_ASSERT(fixed > 0 && strncmp(text, "ITEM: UNITS\nsi\n", 15) == 0);
    sim_grain_set_free(&g);
    free(walls);
    free(text);
    snprintf(path, sizeof path, "%s/pile.pvd", dir);
    text = test_read_file(path, NULL);
    TEST_ASSERT(text && count_of(text, "<DataSet ") == 3);
    TEST_ASSERT(strstr(text, "timestep=\"0.80000000000000004\" group=\"\" part=\"0\" "
                             "file=\"pile/pile_00000.vtp\""));
    free(text);
    /* the run's index: fall's 5 frames, then pile's 2 after its first (fall's end state) */
    snprintf(path, sizeof path, "%s/run.all.pvd", dir);
    text = test_read_file(path, NULL);
    TEST_ASSERT(text && count_of(text, "part=\"0\" file=\"fall/fall_") == 5);
    TEST_ASSERT(count_of(text, "part=\"0\" file=\"pile/pile_") == 2);
    TEST_ASSERT(count_of(text, "part=\"1\" file=\"pile/pile_contacts_") == 2);
    TEST_ASSERT(count_of(text, "part=\"2\" file=\"fall/fall_walls_") == 5);
    free(text);
    char command[300];
    snprintf(command, sizeof command, "rm -rf '%s'", dir);
    TEST_ASSERT(system(command) == 0);
    return 0;
}

/* A run that blows up in a dumped stage leaves no LAMMPS dump, not even its .tmp, and no index. */
static int failed_run_leaves_no_dump(void)
{
    char dir[128];
    snprintf(dir, sizeof dir, "/tmp/sablier_test_dump_fail_%ld", (long)getpid());
    const char *sets[] = {"guard.max_overlap=1e-6"};
    TEST_ASSERT(run_scene(dir, sets, 1) == 1);
    TEST_ASSERT(exists(dir, "summary.json") && exists(dir, "fall.last_good.state"));
    TEST_ASSERT(!exists(dir, "fall.lammpstrj") && !exists(dir, "fall.lammpstrj.tmp"));
    TEST_ASSERT(!exists(dir, "fall.pvd") && !exists(dir, "fall_contacts.pvd"));
    char command[300];
    snprintf(command, sizeof command, "rm -rf '%s'", dir);
    TEST_ASSERT(system(command) == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(lammps_frame_round_trip), TEST_CASE(lammps_periodic_box),
          TEST_CASE(vtk_grains_file), TEST_CASE(vtk_contacts_file),
          TEST_CASE(vtk_contacts_seam_and_wall), TEST_CASE(vtk_walls_file),
          TEST_CASE(scene_dump_keys), TEST_CASE(run_writes_dumps),
          TEST_CASE(failed_run_leaves_no_dump))
