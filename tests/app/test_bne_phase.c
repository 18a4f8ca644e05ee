/* SPDX-License-Identifier: MIT */
/* test_bne_phase.c: the phase-averaged velocity field of the shaken box (bne.phase_field,
 * docs/brazil_nut.md): samples fall on the requested phase of every cycle to within half a step,
 * the runner removes the box's velocity and offset, the accumulation is a true (mass-weighted)
 * average, a small-box run writes phase_field.csv and phase_fields.csv and hands the figure to the
 * render hook without changing the run, and the cycle mean of the small box shows the convection
 * rolls (down along the walls, up in the middle). */
#include "test.h"

#include "run/run.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bne/bne.h"

#define SMALL "scenes/brazil_nut/small.scene"
#define TPI   3.14159265358979323846

/* Distance between two phases (fractions of the period) on the circle. */
static double phase_distance(double a, double b)
{
    double d = fmod(fabs(a - b), 1.0);
    return fmin(d, 1.0 - d);
}

/* (1a) The schedule alone: step m is the step nearest (n + phase + k / phases) T, so its time is
 * within dt / 2 of it and, modulo T, within dt of the requested phase; steps only increase. */
static int phase_steps_hit_the_phase(void)
{
    const struct {
        double phase;
        int phases;
        double period, dt;
    } cases[] = {{0.0, 1, 3.953, 1e-3}, {0.3, 1, 3.95337, 1e-3}, {0.25, 4, 3.95337, 7e-4},
                 {0.9, 3, 4.743, 5e-4}, {0.5, 16, 3.953, 1e-3},  {0.123, 7, 0.0731, 1.5811e-4}};

    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        double T = cases[c].period, dt = cases[c].dt, worst = 0.0;
        int P = cases[c].phases;
        long previous = -1;
        for (long m = 0; m < 5000; ++m) {
            long s = app_bne_phase_step(cases[c].phase, P, T, dt, m);
            long n = m / P, k = m % P;
            double tau = ((double)n + cases[c].phase + (double)k / P) * T;
            TEST_ASSERT(fabs((double)s * dt - tau) <= 0.5 * dt * (1.0 + 1e-9));
            double phase = fmod((double)s * dt, T) / T;
            TEST_ASSERT(phase_distance(phase, cases[c].phase + (double)k / P) * T <= dt);
            TEST_ASSERT(s > previous);
            previous = s;
            worst = fmax(worst, fabs((double)s * dt - tau));
        }
        printf("phase %g x %d, T = %g, dt = %g: worst |t - tau| = %.3g dt\n", cases[c].phase, P, T,
               dt, worst / dt);
    }
    return 0;
}

/* Fake renderer: records the figure the run hands over and writes a placeholder file. */
typedef struct FigureCall {
    int calls;
    char path[512];
    SceneFigure figure;
    int carriers;  /* nodes carrying an arrow */
    int matched;   /* of them, equal to the same node's mean velocity of the field */
    int same_grid; /* the extras' grid is the field's (size, cell) */
    const AppBne *bne;
} FigureCall;

static int fake_figure(void *context, const Scene *scene, const SceneFigure *figure,
                       const SimFrame *frame, const AppFigureExtras *extras, const char *path,
                       char *err, size_t err_size)
{
    (void)scene;
    (void)frame;
    (void)err;
    (void)err_size;
    FigureCall *call = context;
    call->calls++;
    snprintf(call->path, sizeof call->path, "%s", path);
    call->figure = *figure;
    const AppBneField *f = app_bne_phase_field(call->bne);
    call->same_grid = f && extras && extras->field_vx && extras->field_nx == f->nx &&
                      extras->field_ny == f->ny && extras->field_cell == f->cell;
    for (int k = 0; call->same_grid && k < f->nx * f->ny; ++k) {
        if (!isfinite(extras->field_vx[k]))
            continue;
        call->carriers++;
        double vx, vy, solid;
        app_bne_field_node(f, k, &vx, &vy, &solid);
        call->matched += vx == extras->field_vx[k] && vy == extras->field_vy[k] && solid >= 0.1;
    }
    FILE *out = fopen(path, "w");
    if (!out)
        return -1;
    fputs("figure\n", out);
    return fclose(out) == 0 ? 0 : -1;
}

static Scene *load_small(const char *const *sets, int count)
{
    char err[1024] = "";
    Scene *scene = scene_load(SMALL, sets, count, err, sizeof err);
    if (!scene)
        fprintf(stderr, "%s\n", err);
    return scene;
}

static int run_scene(Scene *scene, const char *tag, const AppRender *hooks, char *dir,
                     size_t dir_size)
{
    snprintf(dir, dir_size, "/tmp/sablier_test_bne_phase_%ld_%s", (long)getpid(), tag);
    AppRunOptions o = app_run_options_default();
    o.out_dir = dir;
    o.quiet = 1;
    o.render = hooks;
    return app_run(scene, &o);
}

static int count_lines(const char *path, char *header, size_t header_size)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    char line[512];
    int n = 0;
    while (fgets(line, sizeof line, f)) {
        if (n == 0 && header)
            snprintf(header, header_size, "%.*s", (int)strcspn(line, "\n"), line);
        ++n;
    }
    fclose(f);
    return n;
}

/* (1b) In a run: a period that is no whole number of steps (3.95337 / 1e-3), 3 phases from 0.3,
 * the first cycle skipped: every sample time (from the start of shaking) modulo T is the phase
 * 0.3 + k/3 of its bin within dt, the samples come in bin order once per cycle each, and the
 * rounding did happen (not every sample exact). */
static int run_samples_at_the_phase(void)
{
    const char *sets[] = {"bne.period=3.95337", "bne.phase_field.phase=0.3",
                          "bne.phase_field.phases=3", "bne.phase_field.skip_cycles=1",
                          "stages.shake.time.end=20.0"};
    Scene *scene = load_small(sets, 5);
    TEST_ASSERT(scene && app_bne_of(scene));
    char dir[256];
    TEST_ASSERT(run_scene(scene, "times", NULL, dir, sizeof dir) == 0);
    const double *t = NULL;
    int count = app_bne_phase_times(app_bne_of(scene), &t);
    const double T = 3.95337, dt = 1e-3;
    /* cycles 1..4 complete in 20 s (5.06 periods), cycle 5 reaches phase 0.3 at 20.95 > 20 */
    TEST_ASSERT(count == 12);
    double worst = 0.0, exact = 0.0;
    for (int m = 0; m < count; ++m) {
        int k = m % 3, n = 1 + m / 3;
        double want = 0.3 + k / 3.0;
        double phase = fmod(t[m], T) / T;
        TEST_ASSERT(phase_distance(phase, want) * T <= dt);
        TEST_ASSERT(fabs(t[m] - (n + want) * T) <= 0.5 * dt + 1e-9);
        worst = fmax(worst, fabs(t[m] - (n + want) * T));
        exact += fabs(t[m] - (n + want) * T) < 1e-9;
    }
    printf("%d samples, worst |t - (n + phase) T| = %.3g (dt = %g), %g exact\n", count, worst, dt,
           exact);
    TEST_ASSERT(worst > 1e-6); /* the phases fell between steps and were rounded */
    scene_free(scene);
    return 0;
}

/* Reads phase_fields.csv: vy and solid fraction of the nodes of one phase, in file order. */
static int read_phase(const char *path, double phase, double *vy, double *solid, int max)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    char line[256];
    int n = 0;
    if (!fgets(line, sizeof line, f)) {
        fclose(f);
        return -1;
    }
    while (fgets(line, sizeof line, f) && n < max) {
        double p, x, y, vx, v, s;
        int samples;
        if (sscanf(line, "%lf,%lf,%lf,%lf,%lf,%d,%lf", &p, &x, &y, &vx, &v, &samples, &s) == 7 &&
            fabs(p - phase) < 1e-9) {
            vy[n] = v;
            solid[n++] = s;
        }
    }
    fclose(f);
    return n;
}

/* Below Gamma = 1 the bed rides on the box: seen from the box it barely moves, although the box
 * moves at +-A w = 0.31 d per time unit at phases 0 and 0.5 and is displaced by +-A = 0.2 d at
 * phases 0.25 and 0.75. So the runner removes the box's velocity (the bed's mean vy at phases 0
 * and 0.5 differs by less than A w / 2, measured 0.1, where the lab frame differs by 2 A w) and
 * its offset (the bed's centroid at phases 0.25 and 0.75 differs by less than A / 2, where the lab
 * frame differs by 2 A). The bed is no rigid block: it settles and breathes a little. */
static int box_frame_removes_the_box_motion(void)
{
    const char *sets[] = {"bne.gamma=0.5", "bne.phase_field.phases=4",
                          "stages.shake.time.end=11.5"};
    Scene *scene = load_small(sets, 3);
    TEST_ASSERT(scene && app_bne_of(scene));
    char dir[256], path[512];
    TEST_ASSERT(run_scene(scene, "rest", NULL, dir, sizeof dir) == 0);
    const AppBneField *f = app_bne_phase_field(app_bne_of(scene));
    TEST_ASSERT(f && f->samples == 8); /* cycles 1 and 2 */
    double A = app_bne_result(app_bne_of(scene)).amplitude, Aw = A * 2.0 * TPI / 3.953;
    int nodes = f->nx * f->ny;
    double *vy = malloc(4 * (size_t)nodes * sizeof *vy);
    double *solid = malloc(4 * (size_t)nodes * sizeof *solid);
    TEST_ASSERT(vy && solid);
    snprintf(path, sizeof path, "%s/phase_fields.csv", dir);
    double mean_vy[4], centroid[4];
    for (int k = 0; k < 4; ++k) {
        double *v = vy + k * nodes, *s = solid + k * nodes;
        TEST_ASSERT(read_phase(path, 0.25 * k, v, s, nodes) == nodes);
        double sum_v = 0.0, sum_s = 0.0, sum_y = 0.0;
        int bed = 0;
        for (int n = 0; n < nodes; ++n) {
            sum_s += s[n];
            sum_y += s[n] * (f->y0 + (n / f->nx + 0.5) * f->cell);
            if (s[n] >= 0.5) {
                sum_v += v[n];
                ++bed;
            }
        }
        TEST_ASSERT(bed > 50 && sum_s > 0.0);
        mean_vy[k] = sum_v / bed;
        centroid[k] = sum_y / sum_s;
    }
    printf("Gamma 0.5 (A = %.3f, A w = %.3f): box-frame mean vy of the bed at phases 0, 0.25, 0.5, "
           "0.75: %.3f %.3f %.3f %.3f; centroid %.4f %.4f %.4f %.4f\n",
           A, Aw, mean_vy[0], mean_vy[1], mean_vy[2], mean_vy[3], centroid[0], centroid[1],
           centroid[2], centroid[3]);
    TEST_ASSERT(fabs(mean_vy[0] - mean_vy[2]) < 0.5 * Aw);
    TEST_ASSERT(fabs(centroid[1] - centroid[3]) < 0.5 * A);
    free(vy);
    free(solid);
    scene_free(scene);
    return 0;
}

/* A square lattice of disks (spacing 2r, density 1/pi: m = r^2) moved rigidly: positions plus
 * (0, y_box), velocities u + (0, v_box), as the grains of a box moving at v_box. */
#define LATTICE_N 12

typedef struct Lattice {
    double x[LATTICE_N * LATTICE_N], y[LATTICE_N * LATTICE_N], r[LATTICE_N * LATTICE_N];
    double vx[LATTICE_N * LATTICE_N], vy[LATTICE_N * LATTICE_N];
    int species[LATTICE_N * LATTICE_N];
    uint32_t id[LATTICE_N * LATTICE_N];
    SimFrame frame;
} Lattice;

static void lattice_frame(Lattice *l, int count, double y_box, double v_box, double ux, double uy)
{
    memset(&l->frame, 0, sizeof l->frame);
    for (int j = 0, g = 0; j < LATTICE_N; ++j)
        for (int i = 0; i < LATTICE_N; ++i, ++g) {
            l->x[g] = 0.5 + i;
            l->y[g] = 0.5 + j + y_box;
            l->r[g] = 0.5;
            l->vx[g] = ux;
            l->vy[g] = uy + v_box;
            l->species[g] = 0;
            l->id[g] = (uint32_t)g;
        }
    l->frame.count = l->frame.mobile_count = count;
    l->frame.x = l->x;
    l->frame.y = l->y;
    l->frame.radius = l->r;
    l->frame.vx = l->vx;
    l->frame.vy = l->vy;
    l->frame.species = l->species;
    l->frame.id = l->id;
}

static int new_field(AppBneField *f)
{
    if (app_bne_field_init(f, 0.0, 0.0, 12.0, 12.0, 2.0, 1.5) != 0)
        return -1;
    f->density[0] = 1.0 / TPI;
    f->mass_model = SIM_MASS_DISK;
    return 0;
}

/* (2) A true average: five samples of a lattice moving with known velocities u_s in a box that
 * is at a different offset and speed each time give, at every node the lattice covers in every
 * sample, V = mean u_s (the box's motion removed); the solid fraction of the square lattice,
 * pi / 4, comes out of the kernel's normalisation; the sums are mass-weighted (a sample with
 * twice the mass counts twice); phases weigh equally in the cycle mean whatever their sample
 * counts; a periodic frame wraps. */
static int field_is_true_average(void)
{
    static Lattice lat;
    AppBneField f;
    TEST_ASSERT(new_field(&f) == 0);
    TEST_ASSERT(f.nx == 6 && f.ny == 6);
    const double ux[5] = {0.3, -0.1, 0.25, 0.05, 0.7}, uy[5] = {-0.2, 0.4, 0.0, 1.1, -0.6};
    double mean_x = 0.0, mean_y = 0.0;
    for (int s = 0; s < 5; ++s) {
        double y_box = 1.2 * sin(0.7 * s), v_box = 1.9 * cos(0.7 * s);
        lattice_frame(&lat, LATTICE_N * LATTICE_N, y_box, v_box, ux[s], uy[s]);
        app_bne_field_add(&f, &lat.frame, 0.0, y_box, 0.0, v_box);
        mean_x += ux[s] / 5.0;
        mean_y += uy[s] / 5.0;
    }
    TEST_ASSERT(f.samples == 5);
    int checked = 0;
    for (int k = 0; k < f.nx * f.ny; ++k) {
        double vx, vy, solid;
        app_bne_field_node(&f, k, &vx, &vy, &solid);
        TEST_ASSERT(f.hits[k] == 5);
        TEST_NEAR(vx, mean_x, 1e-13);
        TEST_NEAR(vy, mean_y, 1e-13);
        int i = k % f.nx, j = k / f.nx;
        if (i > 0 && j > 0 && i < f.nx - 1 && j < f.ny - 1) { /* kernel inside the lattice */
            TEST_REL(solid, TPI / 4.0, 0.02);
            ++checked;
        }
    }
    TEST_ASSERT(checked == 16);
    printf("V = (%.6f, %.6f) = mean u; interior solid fraction %.5f (pi/4 = %.5f)\n", mean_x,
           mean_y, f.solid[14] / f.samples, TPI / 4.0);
    app_bne_field_free(&f);

    /* mass weighting: sample A at u = (1, 0), sample B with twice the density at u = (0, 1) */
    AppBneField g;
    TEST_ASSERT(new_field(&g) == 0);
    lattice_frame(&lat, LATTICE_N * LATTICE_N, 0.0, 0.0, 1.0, 0.0);
    app_bne_field_add(&g, &lat.frame, 0.0, 0.0, 0.0, 0.0);
    g.density[0] *= 2.0;
    lattice_frame(&lat, LATTICE_N * LATTICE_N, 0.0, 0.0, 0.0, 1.0);
    app_bne_field_add(&g, &lat.frame, 0.0, 0.0, 0.0, 0.0);
    double vx, vy, solid;
    app_bne_field_node(&g, 14, &vx, &vy, &solid);
    TEST_NEAR(vx, 1.0 / 3.0, 1e-13);
    TEST_NEAR(vy, 2.0 / 3.0, 1e-13);
    app_bne_field_free(&g);

    /* cycle mean: phase 0 has two samples at u = (1, 0), phase 1 one at u = (0, 1): each phase
     * weighs 1/2 (not 2/3 and 1/3) */
    AppBneField phases[2], mean;
    TEST_ASSERT(new_field(&phases[0]) == 0 && new_field(&phases[1]) == 0);
    lattice_frame(&lat, LATTICE_N * LATTICE_N, 0.0, 0.0, 1.0, 0.0);
    app_bne_field_add(&phases[0], &lat.frame, 0.0, 0.0, 0.0, 0.0);
    app_bne_field_add(&phases[0], &lat.frame, 0.0, 0.0, 0.0, 0.0);
    lattice_frame(&lat, LATTICE_N * LATTICE_N, 0.0, 0.0, 0.0, 1.0);
    app_bne_field_add(&phases[1], &lat.frame, 0.0, 0.0, 0.0, 0.0);
    TEST_ASSERT(app_bne_field_combine(phases, 2, &mean) == 0);
    app_bne_field_node(&mean, 14, &vx, &vy, &solid);
    TEST_NEAR(vx, 0.5, 1e-13);
    TEST_NEAR(vy, 0.5, 1e-13);
    TEST_REL(solid, TPI / 4.0, 0.02);
    TEST_ASSERT(mean.samples == 3 && mean.hits[14] == 3);
    app_bne_field_free(&phases[0]);
    app_bne_field_free(&phases[1]);
    app_bne_field_free(&mean);

    /* periodic: one grain at x = 0.2 of a frame periodic over [0, 12] reaches the last column */
    AppBneField p;
    TEST_ASSERT(new_field(&p) == 0);
    lattice_frame(&lat, 1, 0.0, 0.0, 0.5, 0.0);
    lat.x[0] = 0.2;
    lat.y[0] = 1.0;
    lat.frame.periodic = 1;
    lat.frame.domain_x0 = 0.0;
    lat.frame.domain_x1 = 12.0;
    app_bne_field_add(&p, &lat.frame, 0.0, 0.0, 0.0, 0.0);
    TEST_ASSERT(p.rho[p.nx - 1] > 0.0 && p.hits[p.nx - 1] == 1); /* node (11, 1), 1.2 away */
    app_bne_field_node(&p, p.nx - 1, &vx, &vy, &solid);
    TEST_NEAR(vx, 0.5, 1e-15);
    app_bne_field_free(&p);
    return 0;
}

/* (3) A small-box run (7.8 periods, 4 phases) writes phase_field.csv (x,y,vx,vy,samples,
 * solid_fraction, one row per node, the values of the drawn field) and phase_fields.csv (4 blocks),
 * reports the field in bne.json, leaves no .tmp, hands phase_field.png to the figure hook with
 * the field on its own grid nodes (each arrow the node's value), and changes nothing in the run
 * (the intruder heights equal those of a run without the field, bit for bit). */
static int run_writes_csv_and_figure(void)
{
    const char *sets[] = {"stages.shake.time.end=31.0", "bne.phase_field.phases=4"};
    Scene *scene = load_small(sets, 2);
    TEST_ASSERT(scene && app_bne_of(scene));
    FigureCall call;
    memset(&call, 0, sizeof call);
    call.bne = app_bne_of(scene);
    AppRender hooks = {.context = &call, .figure = fake_figure};
    char dir[256], path[512], header[256];
    TEST_ASSERT(run_scene(scene, "outputs", &hooks, dir, sizeof dir) == 0);
    const AppBneField *f = app_bne_phase_field(app_bne_of(scene));
    TEST_ASSERT(f && f->nx > 4 && f->ny > 4);
    TEST_ASSERT(f->samples == 4 * 7); /* cycles 1..7 of 8, the first skipped */

    snprintf(path, sizeof path, "%s/phase_field.csv", dir);
    TEST_ASSERT(count_lines(path, header, sizeof header) == 1 + f->nx * f->ny);
    TEST_ASSERT(strcmp(header, "x,y,vx,vy,samples,solid_fraction") == 0);
    FILE *csv = fopen(path, "r");
    TEST_ASSERT(csv);
    char line[256];
    TEST_ASSERT(fgets(line, sizeof line, csv));
    int rows = 0, occupied = 0;
    for (int k = 0; k < f->nx * f->ny && fgets(line, sizeof line, csv); ++k) {
        double x, y, vx, vy, solid, ex, ey, es;
        int samples;
        TEST_ASSERT(sscanf(line, "%lf,%lf,%lf,%lf,%d,%lf", &x, &y, &vx, &vy, &samples, &solid) ==
                    6);
        app_bne_field_node(f, k, &ex, &ey, &es);
        TEST_NEAR(x, f->x0 + (k % f->nx + 0.5) * f->cell, 1e-6);
        TEST_NEAR(y, f->y0 + (k / f->nx + 0.5) * f->cell, 1e-6);
        TEST_NEAR(vx, ex, 1e-8 * (1.0 + fabs(ex)));
        TEST_NEAR(vy, ey, 1e-8 * (1.0 + fabs(ey)));
        TEST_ASSERT(samples == f->hits[k] && samples <= f->samples);
        occupied += samples > 0;
        ++rows;
    }
    fclose(csv);
    TEST_ASSERT(rows == f->nx * f->ny && occupied > 20);
    snprintf(path, sizeof path, "%s/phase_fields.csv", dir);
    TEST_ASSERT(count_lines(path, header, sizeof header) == 1 + 4 * f->nx * f->ny);
    TEST_ASSERT(strcmp(header, "phase,x,y,vx,vy,samples,solid_fraction") == 0);
    snprintf(path, sizeof path, "%s/phase_field.csv.tmp", dir);
    TEST_ASSERT(access(path, F_OK) != 0);
    snprintf(path, sizeof path, "%s/bne.json", dir);
    FILE *json = fopen(path, "r");
    TEST_ASSERT(json);
    char text[4096];
    size_t n = fread(text, 1, sizeof text - 1, json);
    text[n] = '\0';
    fclose(json);
    TEST_ASSERT(strstr(text, "\"phase_field\": {\"phase\": 0, \"phases\": 4"));

    /* the figure */
    TEST_ASSERT(call.calls == 1);
    snprintf(path, sizeof path, "%s/phase_field.png", dir);
    TEST_ASSERT(strcmp(call.path, path) == 0 && access(path, F_OK) == 0);
    TEST_ASSERT(call.figure.style.velocity_arrows == 0 && call.figure.style.velocity_field == 0);
    printf("%dx%d nodes, %d occupied; figure: %d arrows on nodes, %d equal to node values\n", f->nx,
           f->ny, occupied, call.carriers, call.matched);
    TEST_ASSERT(call.same_grid && call.carriers > 20 && call.matched == call.carriers);

    /* the sampling does not perturb the run: the same scene without the phase_field line */
    char plain_path[256];
    snprintf(plain_path, sizeof plain_path, "/tmp/sablier_test_bne_phase_%ld_plain.scene",
             (long)getpid());
    FILE *in = fopen(SMALL, "r"), *out = fopen(plain_path, "w");
    TEST_ASSERT(in && out);
    int dropped = 0;
    while (fgets(line, sizeof line, in)) {
        if (strstr(line, "phase_field = {")) {
            ++dropped;
            continue;
        }
        fputs(line, out);
    }
    fclose(in);
    TEST_ASSERT(fclose(out) == 0 && dropped == 1);
    char err[1024] = "";
    const char *plain_sets[] = {"stages.shake.time.end=31.0"};
    Scene *plain = scene_load(plain_path, plain_sets, 1, err, sizeof err);
    TEST_ASSERT(plain && app_bne_of(plain));
    char plain_dir[256];
    TEST_ASSERT(run_scene(plain, "plain", NULL, plain_dir, sizeof plain_dir) == 0);
    TEST_ASSERT(app_bne_phase_field(app_bne_of(plain)) == NULL);
    AppBneResult with = app_bne_result(app_bne_of(scene)),
                 without = app_bne_result(app_bne_of(plain));
    TEST_ASSERT(with.count == without.count && with.count > 50);
    for (int k = 0; k < with.count; ++k)
        TEST_ASSERT(with.height[k] == without.height[k]);
    remove(plain_path);
    scene_free(plain);
    scene_free(scene);
    return 0;
}

/* (4) The physics the field is for: the small box's cycle mean over 30 periods (16 phases) goes
 * down along both frictional walls and up in the middle, the BNE's convection rolls. */
static int convection_rolls_in_small_box(void)
{
    Scene *scene = load_small(NULL, 0);
    TEST_ASSERT(scene && app_bne_of(scene));
    char dir[256];
    TEST_ASSERT(run_scene(scene, "rolls", NULL, dir, sizeof dir) == 0);
    const AppBneField *f = app_bne_phase_field(app_bne_of(scene));
    TEST_ASSERT(f && f->nx >= 6);
    double wall = 0.0, middle = 0.0;
    int n_wall = 0, n_middle = 0;
    for (int k = 0; k < f->nx * f->ny; ++k) {
        double vx, vy, solid;
        app_bne_field_node(f, k, &vx, &vy, &solid);
        if (solid < 0.5)
            continue; /* inside the bed */
        int i = k % f->nx;
        if (i == 0 || i == f->nx - 1) {
            wall += vy;
            ++n_wall;
        } else if (i >= f->nx / 2 - 1 && i <= f->nx / 2) {
            middle += vy;
            ++n_middle;
        }
    }
    TEST_ASSERT(n_wall > 6 && n_middle > 6);
    wall /= n_wall;
    middle /= n_middle;
    printf("cycle-mean vy: wall columns %.3f, middle columns %.3f (d per time unit)\n", wall,
           middle);
    /* seeds 1-5: wall -0.15 to -0.21, middle +0.05 to +0.07 */
    TEST_ASSERT(wall < -0.08);
    TEST_ASSERT(middle > 0.01);
    scene_free(scene);
    return 0;
}

TEST_MAIN(TEST_CASE(phase_steps_hit_the_phase), TEST_CASE(run_samples_at_the_phase),
          TEST_CASE(box_frame_removes_the_box_motion), TEST_CASE(field_is_true_average),
          TEST_CASE(run_writes_csv_and_figure), TEST_CASE(convection_rolls_in_small_box))
