/* SPDX-License-Identifier: MIT */
/* crater.c: the crater-collapse family (thesis 000) behind app/base/experiment.h, and its
 * observables. The family owns the stages' `dig` keys (a cavity dug at the stage start, 000 §4.1
 * stage 2) and `output.profile_every` / `output.profile_bin` (free-surface profiles), runs the
 * observer during a run and draws the energy and profile figures after it; `sablier sweep`
 * (sweep.c) is its driver. Its hook table, app_crater_experiment, closes this file.
 *
 * Observables (000 §5.4): the profile is the thesis's free surface: per x-bin about one mean
 * diameter wide, the highest top of a grain centred in it (notes §5.4 [D]). The crater height is
 * measured as the depth of the crater below the settled free surface (docs/physics.md, "crater
 * height"). */
#include "crater.h"

#include "sweep.h"

#include "base/checkpoint.h"
#include "base/config.h"
#include "base/experiments.h"
#include "base/util.h"
#include "driver/run_value.h"
#include "sim/sim.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define OBS_PATH 2200

/* ---------------------------------------------------------------- measures */

/* Interior between the container's side columns, and the floor top. */
static void container_interior(const SimFrame *f, double *x0, double *x1, double *floor_top)
{
    double mx0 = INFINITY, mx1 = -INFINITY, mean = 0.0, my0 = INFINITY;
    for (int i = 0; i < f->mobile_count; ++i) {
        mx0 = fmin(mx0, f->x[i] - f->radius[i]);
        mx1 = fmax(mx1, f->x[i] + f->radius[i]);
        my0 = fmin(my0, f->y[i] - f->radius[i]);
        mean += f->x[i];
    }
    mean /= f->mobile_count > 0 ? f->mobile_count : 1;
    double floor_y = INFINITY, floor_r = 0.0;
    for (int i = f->mobile_count; i < f->count; ++i)
        if (f->y[i] < floor_y) {
            floor_y = f->y[i];
            floor_r = f->radius[i];
        }
    *floor_top = isfinite(floor_y) ? floor_y + floor_r : my0;
    double left = -INFINITY, right = INFINITY;
    for (int i = f->mobile_count; i < f->count; ++i) {
        if (f->y[i] <= floor_y + 0.5 * f->radius[i]) /* the floor row is no side wall */
            continue;
        if (f->x[i] < mean)
            left = fmax(left, f->x[i] + f->radius[i]);
        else
            right = fmin(right, f->x[i] - f->radius[i]);
    }
    *x0 = isfinite(left) ? left : mx0;
    *x1 = isfinite(right) ? right : mx1;
}

int app_crater_profile_measure(SimWorld *world, double bin_width, AppCraterProfile *p)
{
    memset(p, 0, sizeof *p);
    SimFrame frame;
    sim_world_frame(world, &frame);
    if (frame.mobile_count == 0)
        return -1;
    container_interior(&frame, &p->x0, &p->x1, &p->floor_top);
    double diameter, mass;
    sim_world_means(world, &diameter, &mass);
    if (!(bin_width > 0.0))
        bin_width = diameter;
    double width = p->x1 - p->x0;
    if (!(width > 0.0) || !(bin_width > 0.0))
        return -1;
    /* at most 1e6 bins (a bin width from a loaded state's grains is not checked at load) */
    p->bins = (int)fmin(1e6, fmax(1.0, floor(width / bin_width + 0.5)));
    p->bin = width / p->bins;
    p->x = malloc((size_t)p->bins * sizeof *p->x);
    p->y = malloc((size_t)p->bins * sizeof *p->y);
    if (!p->x || !p->y) {
        app_crater_profile_free(p);
        return -1;
    }
    sim_world_surface_profile(world, p->x0, p->x1, p->bins, p->y);
    for (int b = 0; b < p->bins; ++b) {
        p->x[b] = p->x0 + (b + 0.5) * p->bin;
        if (isnan(p->y[b]))
            p->y[b] = p->floor_top;
    }
    return 0;
}

void app_crater_profile_free(AppCraterProfile *p)
{
    free(p->x);
    free(p->y);
    p->x = p->y = NULL;
    p->bins = 0;
}

double app_crater_profile_level(const AppCraterProfile *p, int margin)
{
    if (2 * margin >= p->bins)
        margin = 0;
    double sum = 0.0;
    for (int b = margin; b < p->bins - margin; ++b)
        sum += p->y[b];
    return p->bins > 2 * margin ? sum / (p->bins - 2 * margin) : (double)NAN;
}

AppCrater app_crater_measure(const AppCraterProfile *p, double x0, double x1, double level)
{
    AppCrater c = {(double)NAN, (double)NAN, (double)NAN};
    double centre = 0.5 * (x0 + x1), nearest = INFINITY;
    int near_bin = -1;
    for (int b = 0; b < p->bins; ++b) {
        if (fabs(p->x[b] - centre) < nearest) {
            nearest = fabs(p->x[b] - centre);
            near_bin = b;
        }
        if (p->x[b] < x0 || p->x[b] > x1)
            continue;
        if (!(p->y[b] >= c.surface_min)) {
            c.surface_min = p->y[b];
            c.x_min = p->x[b];
        }
    }
    if (isnan(c.surface_min) && near_bin >= 0) {
        c.surface_min = p->y[near_bin];
        c.x_min = p->x[near_bin];
    }
    c.height = level - c.surface_min;
    return c;
}

AppCraterBed app_crater_bed_measure(SimWorld *world, const AppCraterProfile *p)
{
    AppCraterBed bed;
    double diameter, mass;
    sim_world_means(world, &diameter, &mass);
    bed.coordination = sim_world_coordination(world);
    bed.hexatic_order = sim_world_hexatic_order(world);
    bed.level = app_crater_profile_level(p, 2);
    double lowest = INFINITY;
    for (int b = 0; b < p->bins; ++b)
        lowest = fmin(lowest, p->y[b]);
    bed.window[0] = p->x0 + diameter;
    bed.window[1] = p->floor_top + diameter;
    bed.window[2] = p->x1 - diameter;
    bed.window[3] = lowest - 3.0 * diameter;
    bed.packing_fraction = bed.window[3] > bed.window[1] && bed.window[2] > bed.window[0]
                               ? sim_world_packing_fraction(world, bed.window[0], bed.window[1],
                                                            bed.window[2], bed.window[3])
                               : (double)NAN;
    return bed;
}

/* ---------------------------------------------------------------- observer */

struct AppCraterObserver {
    const Scene *scene;
    double profile_bin; /* m, 0 = the mean diameter */
    char out_dir[OBS_PATH];
    FILE *profile, *crater_csv;
    char profile_path[OBS_PATH], crater_path[OBS_PATH];
    int bed_measured;
    AppCraterBed bed;
    int mobile_before_dig, removed;
    int have_cavity;
    double cavity_x0, cavity_x1; /* m */
    int have_crater;
    AppCrater crater;
    double stage_start;  /* s, start of the last stage begun */
    double time_scale;   /* sqrt(D/g), s */
    double energy_scale; /* N m g D, J */
    double diameter, mass;
    int mobile;
};

AppCraterObserver *app_crater_observer_open(const Scene *scene, double profile_bin,
                                            const char *out_dir, char *err, size_t err_size)
{
    AppCraterObserver *o = calloc(1, sizeof *o);
    if (!o) {
        snprintf(err, err_size, "out of memory");
        return NULL;
    }
    o->scene = scene;
    o->profile_bin = profile_bin;
    snprintf(o->out_dir, sizeof o->out_dir, "%s", out_dir);
    snprintf(o->profile_path, sizeof o->profile_path, "%s/profile.csv", out_dir);
    snprintf(o->crater_path, sizeof o->crater_path, "%s/crater.csv", out_dir);
    o->profile = app_tmp_open(o->profile_path, "t,t_stage,stage,x,y");
    o->crater_csv = app_tmp_open(o->crater_path,
                                 "t,t_stage,stage,surface_min,x_min,crater_height,surface_level");
    if (!o->profile || !o->crater_csv) {
        snprintf(err, err_size, "cannot write in %s: %s", out_dir, strerror(errno));
        if (o->profile)
            fclose(o->profile);
        if (o->crater_csv)
            fclose(o->crater_csv);
        free(o);
        return NULL;
    }
    return o;
}

void app_crater_observer_before_dig(AppCraterObserver *o, SimWorld *world, double x0, double x1)
{
    if (!o)
        return;
    AppCraterProfile p;
    if (app_crater_profile_measure(world, o->profile_bin, &p) != 0)
        return;
    if (!o->bed_measured) {
        o->bed = app_crater_bed_measure(world, &p);
        o->bed_measured = 1;
    } else {
        o->bed.level = app_crater_profile_level(&p, 2);
    }
    app_crater_profile_free(&p);
    o->mobile_before_dig = sim_world_mobile_count(world);
    o->have_cavity = 1;
    o->cavity_x0 = x0;
    o->cavity_x1 = x1;
}

void app_crater_observer_stage_start(AppCraterObserver *o, SimWorld *world, int stage)
{
    (void)stage;
    if (!o)
        return;
    if (o->have_cavity && o->removed == 0)
        o->removed = o->mobile_before_dig - sim_world_mobile_count(world);
    const Scene *scene = o->scene;
    double g = hypot(scene->def.gravity_x, scene->def.gravity_y);
    SimFrame frame;
    sim_world_frame(world, &frame);
    double length = scene->output.t_star_length > 0.0 ? scene->output.t_star_length
                                                      : frame.time_scale * frame.time_scale * g;
    sim_world_means(world, &o->diameter, &o->mass);
    o->mobile = sim_world_mobile_count(world);
    o->stage_start = sim_world_time(world);
    o->time_scale = g > 0.0 ? sqrt(length / g) : 0.0;
    o->energy_scale = o->mobile * o->mass * g * length; /* N m g D (000 eq. 6.6, per particle) */
}

void app_crater_observer_sample(AppCraterObserver *o, SimWorld *world, int stage,
                                double stage_start)
{
    if (!o)
        return;
    AppCraterProfile p;
    if (app_crater_profile_measure(world, o->profile_bin, &p) != 0)
        return;
    double t = sim_world_time(world);
    const char *name = o->scene->stages[stage].name;
    for (int b = 0; b < p.bins; ++b)
        fprintf(o->profile, "%.9g,%.9g,%s,%.6g,%.6g\n", t, t - stage_start, name, p.x[b], p.y[b]);
    if (o->have_cavity && o->bed_measured) {
        o->crater = app_crater_measure(&p, o->cavity_x0, o->cavity_x1, o->bed.level);
        o->have_crater = 1;
        fprintf(o->crater_csv, "%.9g,%.9g,%s,%.6g,%.6g,%.6g,%.6g\n", t, t - stage_start, name,
                o->crater.surface_min, o->crater.x_min, o->crater.height, o->bed.level);
    }
    app_crater_profile_free(&p);
}

/* The observer's measures in the order of its checkpoint lines `observer` (doubles) and
 * `observer_counts`: copied into v (load = 0) or from v (load = 1). */
#define OBSERVER_DOUBLES 18
#define OBSERVER_COUNTS  6

static void observer_numbers(AppCraterObserver *o, double *v, double *n, int load)
{
    double *d[OBSERVER_DOUBLES] = {&o->bed.coordination,   &o->bed.packing_fraction,
                                   &o->bed.hexatic_order,  &o->bed.level,
                                   &o->bed.window[0],      &o->bed.window[1],
                                   &o->bed.window[2],      &o->bed.window[3],
                                   &o->cavity_x0,          &o->cavity_x1,
                                   &o->crater.surface_min, &o->crater.x_min,
                                   &o->crater.height,      &o->stage_start,
                                   &o->time_scale,         &o->energy_scale,
                                   &o->diameter,           &o->mass};
    int *c[OBSERVER_COUNTS] = {&o->bed_measured, &o->mobile_before_dig, &o->removed,
                               &o->have_cavity,  &o->have_crater,       &o->mobile};
    for (int k = 0; k < OBSERVER_DOUBLES; ++k)
        if (load)
            *d[k] = v[k];
        else
            v[k] = *d[k];
    for (int k = 0; k < OBSERVER_COUNTS; ++k)
        if (load)
            *c[k] = (int)n[k];
        else
            n[k] = (double)*c[k];
}

void app_crater_observer_checkpoint(const AppCraterObserver *o, FILE *out)
{
    double v[OBSERVER_DOUBLES], n[OBSERVER_COUNTS];
    AppCraterObserver copy = *o; /* read only */
    observer_numbers(&copy, v, n, 0);
    app_checkpoint_put(out, "observer", v, OBSERVER_DOUBLES);
    app_checkpoint_put(out, "observer_counts", n, OBSERVER_COUNTS);
    app_checkpoint_file(out, o->profile_path, o->profile);
    app_checkpoint_file(out, o->crater_path, o->crater_csv);
}

int app_crater_observer_resume(AppCraterObserver *o, const char *record, char *err, size_t err_size)
{
    double v[OBSERVER_DOUBLES], n[OBSERVER_COUNTS];
    if (app_checkpoint_take(record, "observer", v, OBSERVER_DOUBLES) != 0 ||
        app_checkpoint_take(record, "observer_counts", n, OBSERVER_COUNTS) != 0) {
        snprintf(err, err_size, "--resume: the crater section of the checkpoint is malformed");
        return -1;
    }
    observer_numbers(o, v, n, 1);
    const char *bad =
        app_checkpoint_reopen(record, o->profile_path, &o->profile) != 0     ? o->profile_path
        : app_checkpoint_reopen(record, o->crater_path, &o->crater_csv) != 0 ? o->crater_path
                                                                             : NULL;
    if (bad)
        snprintf(err, err_size, "--resume: %s: %s (not as long as the checkpoint records)", bad,
                 strerror(errno));
    return bad ? -1 : 0;
}

static void number(char *out, size_t size, double v)
{
    if (isfinite(v))
        snprintf(out, size, "%.8g", v);
    else
        snprintf(out, size, "null");
}

void app_crater_observer_json(const AppCraterObserver *o, char *out, size_t size)
{
    out[0] = '\0';
    if (!o || !o->bed_measured)
        return;
    char a[32], b[32], c[32], d[32];
    number(a, sizeof a, o->bed.coordination);
    number(b, sizeof b, o->bed.packing_fraction);
    number(c, sizeof c, o->bed.hexatic_order);
    number(d, sizeof d, o->bed.level);
    size_t n = (size_t)snprintf(out, size,
                                "  \"bed\": {\"coordination\": %s, \"packing_fraction\": %s, "
                                "\"hexatic_order\": %s, \"surface_level\": %s},\n",
                                a, b, c, d);
    if (!o->have_crater || n >= size)
        return;
    number(a, sizeof a, o->crater.height);
    number(b, sizeof b, o->crater.surface_min);
    number(c, sizeof c, o->crater.x_min);
    snprintf(out + n, size - n,
             "  \"crater\": {\"crater_height\": %s, \"surface_min\": %s, \"x_min\": %s, "
             "\"cavity_x0\": %.8g, \"cavity_x1\": %.8g, \"removed\": %d},\n",
             a, b, c, o->cavity_x0, o->cavity_x1, o->removed);
}

int app_crater_observer_close(AppCraterObserver *o, SimWorld *world, char *err, size_t err_size)
{
    if (!o)
        return 0;
    int rc = 0;
    if (app_tmp_commit(&o->profile, o->profile_path) != 0 ||
        app_tmp_commit(&o->crater_csv, o->crater_path) != 0)
        rc = -1;
    char path[OBS_PATH + 32];
    snprintf(path, sizeof path, "%s/observables.csv", o->out_dir);
    FILE *f = app_tmp_open(path, "key,value");
    if (!f) {
        rc = -1;
    } else {
        const double nan = (double)NAN;
        SimEnergy e = {0};
        if (world)
            e = sim_world_energy(world);

        const struct {
            const char *key;
            double value;
        } rows[] = {
            {"bed_coordination", o->bed_measured ? o->bed.coordination : nan},
            {"bed_packing_fraction", o->bed_measured ? o->bed.packing_fraction : nan},
            {"bed_hexatic_order", o->bed_measured ? o->bed.hexatic_order : nan},
            {"surface_level_m", o->bed_measured ? o->bed.level : nan},
            {"cavity_x0_m", o->have_cavity ? o->cavity_x0 : nan},
            {"cavity_x1_m", o->have_cavity ? o->cavity_x1 : nan},
            {"removed", o->have_cavity ? (double)o->removed : nan},
            {"crater_height_m", o->have_crater ? o->crater.height : nan},
            {"surface_min_m", o->have_crater ? o->crater.surface_min : nan},
            {"crater_x_m", o->have_crater ? o->crater.x_min : nan},
            {"stage_start_s", o->stage_start},
            {"time_scale_s", o->time_scale},
            {"energy_scale_J", o->energy_scale},
            {"mean_diameter_m", o->diameter},
            {"mean_mass_kg", o->mass},
            {"mobile_grains", (double)o->mobile},
            {"final_time_s", world ? sim_world_time(world) : nan},
            {"e_kin_J", world ? e.kinetic : nan},
            {"e_pot_J", world ? e.potential : nan},
            {"e_rot_J", world ? e.rotational : nan},
            {"e_el_J", world ? e.elastic : nan},
        };

        for (size_t k = 0; k < sizeof rows / sizeof rows[0]; ++k)
            fprintf(f, "%s,%.10g\n", rows[k].key, rows[k].value);
        if (app_tmp_commit(&f, path) != 0)
            rc = -1;
    }
    if (rc != 0)
        snprintf(err, err_size, "cannot finish the observables in %s: %s", o->out_dir,
                 strerror(errno));
    free(o);
    return rc;
}

/* ---------------------------------------------------------------- plots */

void app_crater_chart_init(AppCraterChart *plot, int rows, int cols, const char *title)
{
    memset(plot, 0, sizeof *plot);
    plot->rows = rows;
    plot->cols = cols;
    plot->width = cols > 1 ? 1400 : 900;
    plot->height = rows > 1 ? 1000 : 640;
    snprintf(plot->title, sizeof plot->title, "%s", title ? title : "");
}

void app_crater_chart_free(AppCraterChart *plot)
{
    for (int p = 0; p < APP_CRATER_CHART_MAX_PANELS; ++p)
        for (int s = 0; s < plot->panels[p].series_count; ++s) {
            free(plot->panels[p].series[s].x);
            free(plot->panels[p].series[s].y);
        }
    memset(plot, 0, sizeof *plot);
}

int app_crater_chart_add(AppCraterChart *plot, int panel, const char *label, const double *x,
                         const double *y, int count, int line, int marker)
{
    AppCraterChartPanel *p = &plot->panels[panel];
    if (panel < 0 || panel >= APP_CRATER_CHART_MAX_PANELS ||
        p->series_count >= APP_CRATER_CHART_MAX_SERIES || count < 0)
        return -1;
    AppCraterChartSeries *s = &p->series[p->series_count];
    size_t n = (size_t)(count > 0 ? count : 1);
    s->x = malloc(n * sizeof *s->x);
    s->y = malloc(n * sizeof *s->y);
    if (!s->x || !s->y) {
        free(s->x);
        free(s->y);
        s->x = s->y = NULL;
        return -1;
    }
    memcpy(s->x, x, (size_t)count * sizeof *x);
    memcpy(s->y, y, (size_t)count * sizeof *y);
    s->count = count;
    s->line = line;
    s->marker = marker;
    snprintf(s->label, sizeof s->label, "%s", label ? label : "");
    p->series_count++;
    return 0;
}

double app_crater_observable(const char *run_dir, const char *key)
{
    char name[128], err[256];
    double value = NAN;
    snprintf(name, sizeof name, "observables.csv:%s", key); /* its `key,value` rows */
    return app_run_value(run_dir, name, &value, err, sizeof err) == 0 ? value : (double)NAN;
}

/* A growable column store of CSV rows. */
typedef struct Columns {
    int count, capacity, width;
    double *v;                   /* count x width */
    char (*tag)[SCENE_NAME_MAX]; /* the `stage` column */
} Columns;

static int columns_push(Columns *c, const double *row, const char *tag)
{
    if (c->count == c->capacity) {
        int capacity = c->capacity ? 2 * c->capacity : 1024;
        double *v = realloc(c->v, (size_t)capacity * (size_t)c->width * sizeof *v);
        if (!v)
            return -1;
        c->v = v;
        char(*t)[SCENE_NAME_MAX] = realloc(c->tag, (size_t)capacity * sizeof *t);
        if (!t)
            return -1;
        c->tag = t;
        c->capacity = capacity;
    }
    memcpy(c->v + (size_t)c->count * (size_t)c->width, row, (size_t)c->width * sizeof *row);
    snprintf(c->tag[c->count], SCENE_NAME_MAX, "%s", tag);
    c->count++;
    return 0;
}

static void columns_free(Columns *c)
{
    free(c->v);
    free(c->tag);
    memset(c, 0, sizeof *c);
}

/* Reads a CSV whose column `tag_column` is text and the others numbers. */
static int read_csv(const char *path, int width, int tag_column, Columns *out)
{
    memset(out, 0, sizeof *out);
    out->width = width;
    FILE *f = sim_open_input(path, NULL);
    if (!f)
        return -1;
    char line[1024];
    int rc = fgets(line, sizeof line, f) ? 0 : -1; /* header */
    double row[16];
    while (rc == 0 && fgets(line, sizeof line, f)) {
        char tag[SCENE_NAME_MAX] = "", *save = NULL;
        int k = 0, v = 0;
        for (char *item = strtok_r(line, ",\n", &save); item && k <= width;
             item = strtok_r(NULL, ",\n", &save), ++k) {
            if (k == tag_column)
                snprintf(tag, sizeof tag, "%s", item);
            else if (v < width && v < 16)
                row[v++] = strtod(item, NULL);
        }
        if (v == width && columns_push(out, row, tag) != 0)
            rc = -1;
    }
    fclose(f);
    if (rc != 0)
        columns_free(out);
    return rc;
}

int app_crater_chart_energy_run(AppCraterChart *plot, const char *run_dir, const char *label,
                                const char *stage)
{
    char path[OBS_PATH + 32];
    snprintf(path, sizeof path, "%s/energy.csv", run_dir);
    double t0 = app_crater_observable(run_dir, "stage_start_s");
    double ts = app_crater_observable(run_dir, "time_scale_s");
    double es = app_crater_observable(run_dir, "energy_scale_J");
    double mobile = app_crater_observable(run_dir, "mobile_grains");
    Columns c;
    /* t,t_star,e_kin,e_pot,e_rot,e_el,e_total,grains,contacts,stage */
    if (!isfinite(t0) || !(ts > 0.0) || !(es > 0.0) || !(mobile > 0.0) ||
        read_csv(path, 9, 9, &c) != 0)
        return -1;
    if (c.count == 0) {
        columns_free(&c);
        return -1;
    }
    const char *last = c.tag[c.count - 1];
    int earlier = stage && strcmp(stage, last) != 0;
    if (earlier) { /* an earlier stage: t0 is its first row's time */
        int r = 0;
        while (r < c.count && strcmp(c.tag[r], stage) != 0)
            ++r;
        if (r == c.count) {
            columns_free(&c);
            return -1;
        }
        last = c.tag[r];
        t0 = c.v[(size_t)r * 9];
    }
    double *x = malloc((size_t)c.count * sizeof *x), *y[4];
    for (int k = 0; k < 4; ++k)
        y[k] = malloc((size_t)c.count * sizeof *y[k]);
    int n = 0, rc = x && y[0] && y[1] && y[2] && y[3] ? 0 : -1;
    double pot0 = (double)NAN;
    for (int r = 0; rc == 0 && r < c.count; ++r) {
        const double *v = c.v + (size_t)r * 9;
        if (strcmp(c.tag[r], last) != 0 || v[0] < t0 - 1e-9)
            continue;
        if (isnan(pot0))
            pot0 = v[3];
        /* an earlier stage's E* per grain of its own (000 eq. 6.6: N m g D with N = the row's
         * mobile grains, m the mean mass at the last stage's start): a deposit has more grains
         * than the collapse that follows its dig */
        double e = earlier ? es * v[7] / mobile : es;
        x[n] = (v[0] - t0) / ts;
        y[0][n] = v[2] / e;
        y[1][n] = (v[3] - pot0) / e;
        y[2][n] = v[4] / e;
        y[3][n] = v[5] / e;
        ++n;
    }
    static const char *const titles[4] = {"(a) kinetic", "(b) potential - start", "(c) rotational",
                                          "(d) elastic"};
    static const char *const ylabels[4] = {"E^*_{kin}", "E^*_{pot} \xe2\x88\x92 E^*_{pot}(0)",
                                           "E^*_{rot}", "E^*_{el}"};
    for (int k = 0; rc == 0 && k < 4; ++k) {
        AppCraterChartPanel *p = &plot->panels[k];
        snprintf(p->title, sizeof p->title, "%s", titles[k]);
        snprintf(p->x_label, sizeof p->x_label, "t^* = (t \xe2\x88\x92 t_0) / \\sqrt{D/g}");
        snprintf(p->y_label, sizeof p->y_label, "%s", ylabels[k]);
        rc = app_crater_chart_add(plot, k, label, x, y[k], n, 1, 0);
    }
    free(x);
    for (int k = 0; k < 4; ++k)
        free(y[k]);
    columns_free(&c);
    return rc;
}

int app_crater_chart_profiles_run(AppCraterChart *plot, int panel, const char *run_dir, int curves,
                                  const char *label)
{
    char path[OBS_PATH + 32];
    snprintf(path, sizeof path, "%s/profile.csv", run_dir);
    Columns c;
    /* t,t_stage,stage,x,y */
    if (read_csv(path, 4, 2, &c) != 0)
        return -1;
    if (c.count == 0) {
        columns_free(&c);
        return -1;
    }
    const char *last = c.tag[c.count - 1];
    /* distinct sample times of the last stage, in file order */
    int first = c.count - 1;
    while (first > 0 && strcmp(c.tag[first - 1], last) == 0)
        --first;
    int *starts = malloc((size_t)(c.count - first + 1) * sizeof *starts), samples = 0;
    if (!starts) {
        columns_free(&c);
        return -1;
    }
    for (int r = first; r < c.count; ++r)
        if (r == first || c.v[(size_t)r * 4] != c.v[(size_t)(r - 1) * 4])
            starts[samples++] = r;
    starts[samples] = c.count;
    if (curves < 1)
        curves = 1;
    if (curves > samples)
        curves = samples;
    int rc = 0;
    AppCraterChartPanel *p = &plot->panels[panel];
    snprintf(p->x_label, sizeof p->x_label, "x (m)");
    snprintf(p->y_label, sizeof p->y_label, "free surface y (m)");
    double *x = malloc((size_t)c.count * sizeof *x), *y = malloc((size_t)c.count * sizeof *y);
    rc = x && y ? 0 : -1;
    /* the profile's bins span the box's interior (centres half a bin inside its walls): the
     * plot's x axis never runs past it */
    p->x_domain[0] = INFINITY;
    p->x_domain[1] = -INFINITY;
    for (int r = first; r < c.count; ++r) {
        p->x_domain[0] = fmin(p->x_domain[0], c.v[(size_t)r * 4 + 2]);
        p->x_domain[1] = fmax(p->x_domain[1], c.v[(size_t)r * 4 + 2]);
    }
    int bins = starts[1] - starts[0];
    double half = bins > 1 ? 0.5 * (p->x_domain[1] - p->x_domain[0]) / (bins - 1) : 0.0;
    p->x_domain[0] -= half;
    p->x_domain[1] += half;
    for (int k = 0; rc == 0 && k < curves; ++k) {
        int s = curves == 1 ? samples - 1 : (int)lround((double)k * (samples - 1) / (curves - 1));
        int n = 0;
        for (int r = starts[s]; r < starts[s + 1]; ++r, ++n) {
            x[n] = c.v[(size_t)r * 4 + 2];
            y[n] = c.v[(size_t)r * 4 + 3];
        }
        char text[64];
        if (curves == 1 && label)
            snprintf(text, sizeof text, "%s", label);
        else
            snprintf(text, sizeof text, "t \xe2\x88\x92 t_0 = %.2f s",
                     c.v[(size_t)starts[s] * 4 + 1]);
        rc = app_crater_chart_add(plot, panel, text, x, y, n, 1, 0);
    }
    free(x);
    free(y);
    free(starts);
    columns_free(&c);
    return rc;
}

int app_crater_surface_height(const SimFrame *frame, double x, double half_width, double *top)
{
    int found = 0;
    for (int i = 0; i < frame->mobile_count; ++i) {
        if (fabs(frame->x[i] - x) > half_width)
            continue;
        double y = frame->y[i] + frame->radius[i];
        if (!found || y > *top)
            *top = y;
        found = 1;
    }
    return found ? 0 : -1;
}

/* AppCraterChart (owned series) as the AppPlot the renderer draws. */
int app_crater_chart_write(const AppCraterChart *chart, const AppRender *render, const char *path,
                           char *err, size_t err_size)
{
    if (!render || !render->plot)
        return 0;
    AppPlotSeries series[APP_CRATER_CHART_MAX_PANELS][APP_CRATER_CHART_MAX_SERIES];
    AppPlotPanel panels[APP_CRATER_CHART_MAX_PANELS];
    int count = chart->rows * chart->cols;
    memset(panels, 0, sizeof panels);
    for (int p = 0; p < count && p < APP_CRATER_CHART_MAX_PANELS; ++p) {
        const AppCraterChartPanel *a = &chart->panels[p];
        for (int k = 0; k < a->series_count; ++k) {
            const AppCraterChartSeries *in = &a->series[k];
            series[p][k] =
                (AppPlotSeries){.label = in->label[0] ? in->label : NULL,
                                .count = in->count,
                                .x = in->x,
                                .y = in->y,
                                .line = in->line,
                                .marker = in->marker ? APP_MARKER_CIRCLE : APP_MARKER_NONE,
                                .rgb = APP_RGB_AUTO};
        }
        panels[p].title = a->title[0] ? a->title : NULL;
        panels[p].x_label = a->x_label[0] ? a->x_label : NULL;
        panels[p].y_label = a->y_label[0] ? a->y_label : NULL;
        panels[p].series_count = a->series_count;
        panels[p].series = series[p];
        panels[p].legend = a->series_count > 1 ? APP_LEGEND_AUTO : APP_LEGEND_NONE;
        panels[p].x_domain_min = a->x_domain[0];
        panels[p].x_domain_max = a->x_domain[1];
    }
    AppPlot plot = {.title = chart->title[0] ? chart->title : NULL,
                    .width = chart->width,
                    .height = chart->height,
                    .rows = chart->rows,
                    .cols = chart->cols,
                    .panel_count =
                        count < APP_CRATER_CHART_MAX_PANELS ? count : APP_CRATER_CHART_MAX_PANELS,
                    .panels = panels,
                    .print = chart->print};
    return render->plot(render->context, &plot, path, err, err_size);
}

int app_crater_plots(const Scene *scene, int energy_stage, const char *out_dir,
                     const AppRender *render, char *err, size_t err_size)
{
    if (!render || !render->plot)
        return 0;
    char path[OBS_PATH + 32], title[160];
    AppCraterChart plot;
    const char *stage = energy_stage >= 0 && energy_stage < scene->stage_count
                            ? scene->stages[energy_stage].name
                            : NULL;
    if (stage)
        snprintf(title, sizeof title, "%s: dimensionless energies of stage %s", scene->name, stage);
    else
        snprintf(title, sizeof title, "%s: dimensionless energies of the last stage", scene->name);
    app_crater_chart_init(&plot, 2, 2, title);
    plot.print = &scene->style;
    int rc = 0;
    if (app_crater_chart_energy_run(&plot, out_dir, scene->name, stage) == 0) {
        snprintf(path, sizeof path, "%s/energy_panels.png", out_dir);
        rc = app_crater_chart_write(&plot, render, path, err, err_size);
    }
    app_crater_chart_free(&plot);
    snprintf(title, sizeof title, "%s: free-surface profile evolution (000 fig. 7.30)",
             scene->name);
    app_crater_chart_init(&plot, 1, 1, title);
    plot.print = &scene->style;
    if (rc == 0 && app_crater_chart_profiles_run(&plot, 0, out_dir, 8, NULL) == 0) {
        snprintf(path, sizeof path, "%s/profiles.png", out_dir);
        rc = app_crater_chart_write(&plot, render, path, err, err_size);
    }
    app_crater_chart_free(&plot);
    return rc;
}

/* -------------------------------------------------- the family's hooks (app/base/experiment.h) */

struct AppCraterState {
    AppCraterDig dig[SCENE_MAX_STAGES];
    double profile_every; /* s between free-surface profiles (0 = stage ends only) */
    double profile_bin;   /* m, 0 = the mean diameter */
    int energy_stage;     /* the stage energy_panels.png draws, -1 = the last */
    AppCraterObserver *observer;
    long every_profile; /* steps, in the current stage; > stage steps: off */
    long done;          /* steps of the current stage, as last seen */
    char json[1024];    /* summary.json members, taken before the observer closes */
};

const AppCraterState *app_crater_of(const Scene *scene)
{
    return scene_experiment_state(scene, &app_crater_experiment);
}

AppCraterDig app_crater_dig(const Scene *scene, int stage)
{
    const AppCraterState *c = app_crater_of(scene);
    AppCraterDig none = {0};
    return c && stage >= 0 && stage < SCENE_MAX_STAGES ? c->dig[stage] : none;
}

/* ---------------------------------------------------------------- parse */

/* dig = { center_x; width; height; top = "surface" | m; } (000 §4.1 stage 2), in stage g */
static int parse_dig(AppConfig *p, const config_setting_t *stage, AppCraterDig *dig)
{
    static const char *const keys[] = {"center_x", "width", "height", "top", NULL};
    const config_setting_t *g;
    int found = app_config_group(p, stage, "dig", &g);
    if (found <= 0)
        return found;
    if (app_config_keys(p, g, "dig", keys, NULL) < 0)
        return -1;
    dig->dig = 1;
    dig->top_surface = 1;
    if (app_config_need_number(p, g, "center_x", "dig", &dig->center_x) < 0 ||
        app_config_need_number(p, g, "width", "dig", &dig->width) < 0 ||
        app_config_positive(p, g, "width", dig->width) < 0 ||
        app_config_need_number(p, g, "height", "dig", &dig->height) < 0 ||
        app_config_positive(p, g, "height", dig->height) < 0)
        return -1;
    const config_setting_t *top = app_config_member(g, "top");
    if (top && config_setting_type(top) == CONFIG_TYPE_STRING) {
        if (strcmp(config_setting_get_string(top), "surface") != 0)
            return app_config_fail(p, top, "`top` must be \"surface\" or a height in m");
    } else if (top) {
        dig->top_surface = 0;
        if (app_config_number(p, g, "top", &dig->top) < 0)
            return -1;
    }
    return 0;
}

/* A dig whose cavity lies beside everything the scene defines (its grains and walls, x) can
 * only fail after the earlier stages ran: refused at load (a centre of 1e308). Scenes whose
 * grains all come from elsewhere (a loaded state, sources) are not checked. */
static int dig_within(AppConfig *p, const config_setting_t *stage, const Scene *scene,
                      const AppCraterDig *dig)
{
    if (!dig->dig)
        return 0;
    double x0 = INFINITY, x1 = -INFINITY;
    for (int i = 0; i < scene->grains.count; ++i) {
        x0 = fmin(x0, scene->grains.x[i] - scene->grains.radius[i]);
        x1 = fmax(x1, scene->grains.x[i] + scene->grains.radius[i]);
    }
    for (int k = 0; k < scene->def.wall_count; ++k) {
        double a, b, c, d;
        sim_wall_bounds(&scene->def.walls[k], &a, &b, &c, &d);
        x0 = fmin(x0, a);
        x1 = fmax(x1, c);
    }
    if (!(x1 >= x0) || scene->source_count > 0)
        return 0;
    const double left = dig->center_x - 0.5 * dig->width, right = dig->center_x + 0.5 * dig->width;
    if (right > x0 && left < x1)
        return 0;
    const config_setting_t *g = config_setting_get_member(stage, "dig");
    return app_config_fail(p, g ? config_setting_get_member(g, "center_x") : stage,
                           "dig: the cavity [%g, %g] m lies outside the scene's grains and walls "
                           "(x in [%g, %g] m)",
                           left, right, x0, x1);
}

/* energy_stage = "NAME": the stage whose energies energy_panels.png draws (000 fig. 6.15 shows
 * the deposit, figs. 7.1-7.8 the collapse); a stage that runs for some time */
static int parse_energy_stage(AppConfig *p, const config_setting_t *output, const Scene *scene,
                              int *stage)
{
    const char *name = NULL;
    *stage = -1;
    if (app_config_string(p, output, "energy_stage", &name) < 0)
        return -1;
    if (!name)
        return 0;
    const config_setting_t *at = config_setting_get_member(output, "energy_stage");
    *stage = scene_stage_index(scene, name);
    if (*stage < 0)
        return app_config_fail(p, at, "`energy_stage`: no stage named `%s`", name);
    if (!(scene->stages[*stage].duration > 0.0))
        return app_config_fail(p, at, "`energy_stage`: stage `%s` runs no time (time.end = 0)",
                               name);
    return 0;
}

static int crater_parse(const config_setting_t *root, const config_setting_t *group, Scene *scene,
                        void **state, char *err, size_t err_size)
{
    (void)group;
    AppConfig p = {.path = scene->path, .err = err, .err_size = err_size, .group = NULL};
    AppCraterState c;
    memset(&c, 0, sizeof c);
    c.energy_stage = -1;
    const config_setting_t *output = config_setting_get_member(root, "output");
    if (output && (app_config_number(&p, output, "profile_every", &c.profile_every) < 0 ||
                   app_config_non_negative(&p, output, "profile_every", c.profile_every) < 0 ||
                   app_config_number(&p, output, "profile_bin", &c.profile_bin) < 0 ||
                   app_config_non_negative(&p, output, "profile_bin", c.profile_bin) < 0))
        return -1;
    if (output && parse_energy_stage(&p, output, scene, &c.energy_stage) < 0)
        return -1;
    /* a bin far below a grain measures nothing but memory (profile_bin = 1e-12 took 7.5 GB) */
    double r_min = INFINITY;
    for (int i = 0; i < scene->grains.count; ++i)
        r_min = fmin(r_min, scene->grains.radius[i]);
    if (c.profile_bin > 0.0 && c.profile_bin < 0.1 * r_min)
        return app_config_fail(&p, config_setting_get_member(output, "profile_bin"),
                               "`profile_bin` = %g m is below a tenth of the smallest grain "
                               "radius (%g m); use 0 (the mean diameter) or a larger bin",
                               c.profile_bin, r_min);
    const config_setting_t *stages = config_setting_get_member(root, "stages");
    int used = c.profile_every > 0.0;
    for (int k = 0; stages && k < scene->stage_count && k < config_setting_length(stages); ++k) {
        const config_setting_t *g = config_setting_get_elem(stages, (unsigned)k);
        if (parse_dig(&p, g, &c.dig[k]) < 0 || dig_within(&p, g, scene, &c.dig[k]) < 0)
            return -1;
        used |= c.dig[k].dig;
    }
    *state = NULL;
    if (!used)
        return 0;
    AppCraterState *out = malloc(sizeof *out);
    if (!out) {
        snprintf(err, err_size, "%s: out of memory", scene->path);
        return -1;
    }
    *out = c;
    *state = out;
    return 0;
}

static void crater_free(void *state)
{
    free(state);
}

static void crater_describe_stage(const void *state, int stage, FILE *out)
{
    const AppCraterDig *d = &((const AppCraterState *)state)->dig[stage];
    if (!d->dig)
        return;
    fprintf(out, ", dig center_x %g m width %g m height %g m top ", d->center_x, d->width,
            d->height);
    if (d->top_surface)
        fprintf(out, "surface");
    else
        fprintf(out, "%g m", d->top);
}

/* ---------------------------------------------------------------- run hooks */

static int crater_begin(void *state, AppContext *ctx)
{
    AppCraterState *c = state;
    const Scene *scene = ctx->scene;
    int observe = c->profile_every > 0.0;
    for (int k = 0; k < scene->stage_count; ++k)
        observe |= c->dig[k].dig && !scene->stages[k].skip;
    c->json[0] = '\0';
    if (!observe)
        return 0;
    c->observer =
        app_crater_observer_open(scene, c->profile_bin, ctx->out_dir, ctx->err, ctx->err_size);
    return c->observer ? 0 : -1;
}

/* The bed measured, then the cavity dug (000 §4.1 stage 2). */
static int crater_stage_edit(void *state, AppContext *ctx)
{
    AppCraterState *c = state;
    const AppCraterDig *d = &c->dig[ctx->stage];
    if (!d->dig)
        return 0;
    double x0 = d->center_x - 0.5 * d->width, x1 = d->center_x + 0.5 * d->width;
    app_crater_observer_before_dig(c->observer, ctx->world, x0, x1);
    SimFrame frame;
    sim_world_frame(ctx->world, &frame);
    double top = d->top;
    if (d->top_surface &&
        app_crater_surface_height(&frame, d->center_x, 0.5 * d->width, &top) != 0) {
        snprintf(ctx->err, ctx->err_size,
                 "stage %s: dig: no mobile grain within width/2 of center_x = %g m",
                 ctx->scene->stages[ctx->stage].name, d->center_x);
        return -1;
    }
    ctx->removed += sim_world_remove_rect(ctx->world, x0, top - d->height, x1, top + d->height);
    return 0;
}

static int crater_stage_begin(void *state, AppContext *ctx)
{
    AppCraterState *c = state;
    c->done = 0;
    c->every_profile = ctx->stage_steps + 1;
    if (!c->observer)
        return 0;
    if (c->profile_every > 0.0) {
        double dt = sim_world_time_step(ctx->world);
        c->every_profile = (long)fmax(1.0, (double)llround(c->profile_every / dt));
    }
    app_crater_observer_stage_start(c->observer, ctx->world, ctx->stage);
    app_crater_observer_sample(c->observer, ctx->world, ctx->stage, ctx->stage_start);
    return 0;
}

static long crater_next_step(const void *state, const AppContext *ctx, long done, long next)
{
    const AppCraterState *c = state;
    long every = c->every_profile;
    if (every <= ctx->stage_steps && (done / every + 1) * every < next)
        next = (done / every + 1) * every;
    return next;
}

static void crater_step(void *state, AppContext *ctx, long done)
{
    AppCraterState *c = state;
    c->done = done;
    if (c->observer && done > 0 && done < ctx->stage_steps && done % c->every_profile == 0)
        app_crater_observer_sample(c->observer, ctx->world, ctx->stage, ctx->stage_start);
}

static int crater_stage_end(void *state, AppContext *ctx)
{
    AppCraterState *c = state;
    if (c->observer && c->done > 0)
        app_crater_observer_sample(c->observer, ctx->world, ctx->stage, ctx->stage_start);
    return 0;
}

static int crater_end(void *state, AppContext *ctx, int ok)
{
    (void)ok;
    AppCraterState *c = state;
    if (!c->observer)
        return 0;
    app_crater_observer_json(c->observer, c->json, sizeof c->json);
    int rc = app_crater_observer_close(c->observer, ctx->world, ctx->err, ctx->err_size);
    c->observer = NULL;
    return rc;
}

/* A checkpoint: the profile cadence and the step last seen, then the observer's measures. */
static int crater_checkpoint(const void *state, const AppContext *ctx, FILE *out)
{
    (void)ctx;
    const AppCraterState *c = state;
    const double v[2] = {(double)c->every_profile, (double)c->done};
    app_checkpoint_put(out, "crater", v, 2);
    if (c->observer)
        app_crater_observer_checkpoint(c->observer, out);
    return 0;
}

static int crater_resume(void *state, AppContext *ctx, const char *record)
{
    AppCraterState *c = state;
    double v[2];
    if (app_checkpoint_take(record, "crater", v, 2) != 0) {
        snprintf(ctx->err, ctx->err_size,
                 "--resume: the crater section of the checkpoint is "
                 "malformed");
        return -1;
    }
    c->every_profile = (long)v[0];
    c->done = (long)v[1];
    return c->observer ? app_crater_observer_resume(c->observer, record, ctx->err, ctx->err_size)
                       : 0;
}

static void crater_summary_json(const void *state, char *out, size_t size)
{
    snprintf(out, size, "%s", ((const AppCraterState *)state)->json);
}

static int crater_figures(const void *state, const AppContext *ctx)
{
    const AppCraterState *c = state;
    if (!(c->profile_every > 0.0))
        return 0;
    return app_crater_plots(ctx->scene, c->energy_stage, ctx->out_dir, ctx->render, ctx->err,
                            ctx->err_size);
}

static const char *const STAGE_KEYS[] = {"dig", NULL};
static const char *const OUTPUT_KEYS[] = {"profile_every", "profile_bin", "energy_stage", NULL};

static const char *const OUTPUTS[] = {"profile.csv", "crater.csv", "observables.csv", NULL};
const AppExperiment app_crater_experiment = {
    .name = "crater",
    .outputs = OUTPUTS,
    .group = NULL,
    .stage_keys = STAGE_KEYS,
    .output_keys = OUTPUT_KEYS,
    .parse = crater_parse,
    .free = crater_free,
    .describe_stage = crater_describe_stage,
    .begin = crater_begin,
    .stage_edit = crater_stage_edit,
    .stage_begin = crater_stage_begin,
    .next_step = crater_next_step,
    .step = crater_step,
    .stage_end = crater_stage_end,
    .end = crater_end,
    .checkpoint = crater_checkpoint,
    .resume = crater_resume,
    .summary_json = crater_summary_json,
    .figures = crater_figures,
    .commands = app_crater_commands,
    .command_count = 1,
};
