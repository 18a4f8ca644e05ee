/* SPDX-License-Identifier: MIT */
/* bne.c: Brazil-nut measures and samples (thesis 002 ch. 5; see bne.h and docs/brazil_nut.md). */
#include "bne.h"

#include "base/checkpoint.h"
#include "base/config.h"
#include "base/experiments.h"
#include "base/util.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BNE_PATH (SCENE_PATH_MAX + 2 * SCENE_NAME_MAX)

struct AppBne {
    uint32_t intruder;
    int motion;
    int stage; /* the shaking stage */
    double gamma, period, amplitude, frequency, tolerance, gravity;
    double dir_y;
    double last_time; /* world time at the last row: the end of the previous stage */
    double phase;     /* of the motion in the shaking stage, rad */
    int measuring;
    double t0, surface0, radius, h0;
    FILE *csv;
    char csv_path[BNE_PATH], json_path[BNE_PATH];
    double *t, *h;
    int count, capacity;
    char out_dir[BNE_PATH];
    double dir_x;
    SimMassModel mass_model;
    double density[SIM_MAX_SPECIES];
    /* phase-averaged field (bne.phase_field) */
    int pf_on;
    double pf_phase;     /* fraction of the period, [0, 1) */
    int pf_phases;       /* samples per cycle */
    int pf_skip;         /* cycles not sampled at the start */
    double pf_cell;      /* m, 0 = 2 mean diameters */
    double pf_width;     /* m, 0 = 1.5 mean diameters */
    double pf_region[4]; /* box frame x0, y0, x1, y1 (m); x1 <= x0 = automatic */
    int pf_ready;        /* grid allocated for the current shaking stage */
    char pf_error[160];
    AppBneField *pf_fields; /* one per phase */
    AppBneField pf_mean;    /* the cycle mean (the field itself with one phase) */
    int pf_have_mean;
    double pf_dt;
    double pf_diameter; /* mean diameter at the start of shaking, m */
    long pf_next;       /* next sample index m */
    double *pf_times;   /* s from the start of shaking, of the samples taken */
    int pf_count, pf_capacity;
    double pf_max_error; /* largest |t_sample - tau|, s */
};

static void phase_field_start(AppBne *b, SimWorld *world, const SimFrame *f);
static void phase_field_reset(AppBne *b);

/* ---------------------------------------------------------------- parsing */

/* bne.phase_field: the phase-averaged velocity field (docs/brazil_nut.md). */
static int parse_phase_field(AppBne *b, const config_setting_t *g, AppConfig *p)
{
    static const char *const keys[] = {"phase", "phases", "skip_cycles", "cell",
                                       "width", "region", NULL};
    if (app_config_keys(p, g, NULL, keys, NULL) < 0)
        return -1;
    b->pf_on = 1;
    b->pf_phases = 1;
    b->pf_skip = 1;
    if (app_config_number_min(p, g, "phase", 0.0, &b->pf_phase) < 0 ||
        app_config_int_in(p, g, "phases", 1, 1000, &b->pf_phases) < 0 ||
        app_config_int_in(p, g, "skip_cycles", 0, 1000000, &b->pf_skip) < 0 ||
        app_config_number_min(p, g, "cell", 0.0, &b->pf_cell) < 0 ||
        app_config_number_min(p, g, "width", 0.0, &b->pf_width) < 0)
        return -1;
    if (!(b->pf_phase < 1.0))
        return app_config_fail(p, app_config_member(g, "phase"),
                               "`phase` is a fraction of the period in [0, 1), got %g",
                               b->pf_phase);
    const config_setting_t *r = app_config_member(g, "region");
    int ok = !r || (config_setting_type(r) == CONFIG_TYPE_ARRAY && config_setting_length(r) == 4);
    for (int k = 0; r && ok && k < 4; ++k) {
        int type = config_setting_type(config_setting_get_elem(r, (unsigned)k));
        ok = type == CONFIG_TYPE_FLOAT || type == CONFIG_TYPE_INT || type == CONFIG_TYPE_INT64;
    }
    if (!ok || app_config_vector(p, g, "region", b->pf_region, 4) < 0 ||
        (r && (!(b->pf_region[2] > b->pf_region[0]) || !(b->pf_region[3] > b->pf_region[1]))))
        return app_config_fail(p, r,
                               "`region` must be [x0, y0, x1, y1] (m, box frame) with x1 > x0 "
                               "and y1 > y0");
    return 0;
}

/* intruder = grain id; motion = "name" (the motion shaking the box). */
static int parse_intruder_motion(AppConfig *p, const config_setting_t *g, const Scene *scene,
                                 AppBne *b)
{
    const config_setting_t *s = app_config_member(g, "intruder");
    if (!s ||
        (config_setting_type(s) != CONFIG_TYPE_INT &&
         config_setting_type(s) != CONFIG_TYPE_INT64) ||
        config_setting_get_int64(s) < 0 || config_setting_get_int64(s) >= scene->grains.count)
        return app_config_fail(p, s ? s : g,
                               "`intruder` (the id of a grain of the scene) is required");
    b->intruder = (uint32_t)config_setting_get_int64(s);
    const char *motion = NULL;
    b->motion = -1;
    int found = app_config_string(p, g, "motion", &motion);
    if (found < 0)
        return -1;
    if (!found)
        return app_config_fail(p, g,
                               "`motion` (the name of the motion shaking the box) is required");
    for (int m = 0; m < scene->def.motion_count; ++m)
        if (strcmp(scene->motion_names[m], motion) == 0)
            b->motion = m;
    if (b->motion < 0)
        return app_config_fail(p, app_config_member(g, "motion"), "no motion named `%s`", motion);
    return 0;
}

/* period, gamma (or the motion's amplitude), tolerance; the motion is set to match. */
static int parse_shaking(AppConfig *p, const config_setting_t *g, Scene *scene, AppBne *b)
{
    SimMotion *mo = &scene->def.motions[b->motion];
    b->gravity = hypot(scene->def.gravity_x, scene->def.gravity_y);
    b->period = mo->frequency > 0.0 ? 1.0 / mo->frequency : 0.0;
    b->tolerance = 0.5;
    b->gamma = NAN;
    if (app_config_number_min(p, g, "period", 1e-12, &b->period) < 0 ||
        app_config_number_min(p, g, "gamma", 0.0, &b->gamma) < 0 ||
        app_config_number_min(p, g, "tolerance", 0.0, &b->tolerance) < 0)
        return -1;
    if (!(b->period > 0.0))
        return app_config_fail(p, g, "`period` is required when the motion has no frequency");
    b->frequency = 1.0 / b->period;
    double omega = 2.0 * SIM_PI * b->frequency;
    if (isfinite(b->gamma)) /* Gamma = A w^2 / g (002 eq. 12) */
        b->amplitude = b->gamma * b->gravity / (omega * omega);
    else {
        b->amplitude = fabs(mo->amplitude);
        b->gamma = b->amplitude * omega * omega / b->gravity;
    }
    if (!isfinite(b->amplitude) || !isfinite(b->frequency) || !isfinite(b->gamma))
        return app_config_fail(p,
                               app_config_member(g, "period") ? app_config_member(g, "period") : g,
                               "period %g s and Gamma %g give a shaking amplitude %g (A = Gamma "
                               "g / omega^2): not a finite number",
                               b->period, b->gamma, b->amplitude);
    mo->amplitude = b->amplitude;
    mo->frequency = b->frequency;
    mo->phase = 0.0;
    b->dir_x = mo->direction_x;
    b->dir_y = mo->direction_y;
    return 0;
}

static AppBne *bne_parse_group(const config_setting_t *g, Scene *scene, char *err, size_t err_size)
{
    AppConfig p = {.path = scene->path, .err = err, .err_size = err_size, .group = "bne"};
    static const char *const keys[] = {"intruder", "motion",    "gamma",       "period",
                                       "stage",    "tolerance", "phase_field", NULL};
    if (app_config_keys(&p, g, NULL, keys, NULL) < 0)
        return NULL;
    if (!(scene->def.effects & SIM_EFFECT_VIBRATION)) {
        app_config_fail(&p, g, "the box is shaken by a motion: declare effect vibration");
        return NULL;
    }
    AppBne *b = calloc(1, sizeof *b);
    if (!b) {
        app_config_fail(&p, g, "out of memory");
        return NULL;
    }
    const char *stage = NULL;
    int ok = parse_intruder_motion(&p, g, scene, b) == 0 && parse_shaking(&p, g, scene, b) == 0 &&
             app_config_string(&p, g, "stage", &stage) >= 0;
    b->mass_model = scene->def.mass_model;
    for (int k = 0; k < SIM_MAX_SPECIES; ++k)
        b->density[k] = scene->def.materials[k].density;
    b->stage = scene->stage_count - 1;
    if (ok && stage && (b->stage = scene_stage_index(scene, stage)) < 0) {
        app_config_fail(&p, app_config_member(g, "stage"), "no stage named `%s`", stage);
        ok = 0;
    }
    AppConfig pf = {
        .path = scene->path, .err = err, .err_size = err_size, .group = "bne.phase_field"};
    const config_setting_t *field = app_config_member(g, "phase_field");
    if (ok && field && parse_phase_field(b, field, &pf) < 0)
        ok = 0;
    if (!ok) {
        free(b);
        return NULL;
    }
    return b;
}

static void bne_free(void *state)
{
    AppBne *b = state;
    if (!b)
        return;
    app_tmp_discard(&b->csv, b->csv_path); /* a run that never finished: no bne.csv */
    free(b->t);
    free(b->h);
    if (b->pf_fields)
        for (int k = 0; k < b->pf_phases; ++k)
            app_bne_field_free(&b->pf_fields[k]);
    free(b->pf_fields);
    app_bne_field_free(&b->pf_mean);
    free(b->pf_times);
    free(b);
}

static void bne_adjust_def(const void *state, int stage, SimWorldDef *def)
{
    const AppBne *b = state;
    SimMotion *mo = &def->motions[b->motion];
    if (stage < b->stage) {
        mo->amplitude = 0.0; /* preparation at rest */
        return;
    }
    /* The shaking stage continues the preparation's own checkpoint: its overlaps are the settled
     * bed's, not a user's placement error. A frictionless bed wedges grains against the walls
     * (0.11 d seen at the bottom corners of frictionless.scene), above the 0.1 d placement bound.
     */
    if (stage == b->stage && stage > 0 && def->max_initial_overlap < 0.5)
        def->max_initial_overlap = 0.5;
    /* offset A sin(w (t - t0)): the box leaves its rest position at the stage start t0; once
     * shaking began, the phase it began with (a world loaded again: --resume, a later stage) */
    mo->phase =
        b->measuring ? b->phase : -fmod(2.0 * SIM_PI * b->frequency * b->last_time, 2.0 * SIM_PI);
}

static int bne_restart(const void *state, int stage)
{
    const AppBne *b = state;
    return stage == b->stage && stage > 0;
}

/* ---------------------------------------------------------------- measures */

static double box_offset(const AppBne *b, double t)
{
    return b->amplitude * sin(2.0 * SIM_PI * b->frequency * t + b->phase) * b->dir_y;
}

static int intruder_index(const SimFrame *f, uint32_t id)
{
    for (int i = 0; i < f->mobile_count; ++i)
        if (f->id[i] == id)
            return i;
    return -1;
}

/* Mean over columns one mean diameter wide of the highest grain top, in the world frame. */
static double surface_height(SimWorld *world, const SimFrame *f)
{
    double x0 = INFINITY, x1 = -INFINITY, d = 0.0, mass = 0.0;
    for (int i = 0; i < f->mobile_count; ++i) {
        x0 = fmin(x0, f->x[i] - f->radius[i]);
        x1 = fmax(x1, f->x[i] + f->radius[i]);
    }
    sim_world_means(world, &d, &mass);
    if (!(x1 > x0) || !(d > 0.0))
        return NAN;
    int bins = (int)floor((x1 - x0) / d);
    bins = bins < 1 ? 1 : bins > 4096 ? 4096 : bins;
    double heights[4096], sum = 0.0;
    int n = 0;
    sim_world_surface_profile(world, x0, x1, bins, heights);
    for (int k = 0; k < bins; ++k)
        if (isfinite(heights[k])) {
            sum += heights[k];
            ++n;
        }
    return n ? sum / n : (double)NAN;
}

static int bne_begin(void *state, AppContext *c)
{
    AppBne *b = state;
    const char *out_dir = c->out_dir;
    snprintf(b->out_dir, sizeof b->out_dir, "%s", out_dir);
    snprintf(b->csv_path, sizeof b->csv_path, "%s/bne.csv", out_dir);
    snprintf(b->json_path, sizeof b->json_path, "%s/bne.json", out_dir);
    b->csv = app_tmp_open(
        b->csv_path, "t,t_shake,cycles,box_offset,intruder_y,intruder_top,surface,surface_start");
    if (!b->csv) {
        snprintf(c->err, c->err_size, "cannot write %s.tmp", b->csv_path);
        return -1;
    }
    b->count = 0;
    b->measuring = 0;
    b->last_time = 0.0;
    phase_field_reset(b);
    return 0;
}

static int bne_stage_begin(void *state, AppContext *c)
{
    AppBne *b = state;
    SimWorld *world = c->world;
    if (c->stage != b->stage)
        return 0;
    b->t0 = sim_world_time(world);
    b->phase = -fmod(2.0 * SIM_PI * b->frequency * b->last_time, 2.0 * SIM_PI);
    SimFrame f;
    sim_world_frame(world, &f);
    int i = intruder_index(&f, b->intruder);
    b->radius = i >= 0 ? f.radius[i] : (double)NAN;
    b->h0 = i >= 0 ? f.y[i] - box_offset(b, b->t0) : (double)NAN;
    b->surface0 = surface_height(world, &f) - box_offset(b, b->t0);
    b->measuring = 1;
    b->count = 0;
    if (b->pf_on)
        phase_field_start(b, world, &f);
    return 0;
}

static void bne_sample(void *state, AppContext *c)
{
    AppBne *b = state;
    SimWorld *world = c->world;
    double t = sim_world_time(world);
    b->last_time = t;
    if (!b->measuring)
        return;
    SimFrame f;
    sim_world_frame(world, &f);
    int i = intruder_index(&f, b->intruder);
    if (i < 0)
        return;
    double off = box_offset(b, t), h = f.y[i] - off;
    double surface = surface_height(world, &f) - off;
    if (b->csv)
        fprintf(b->csv, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", t, t - b->t0,
                (t - b->t0) * b->frequency, off, h, h + b->radius, surface, b->surface0);
    if (b->count == b->capacity && app_series_grow(&b->t, &b->h, &b->capacity, 512) != 0)
        return;
    b->t[b->count] = t - b->t0;
    b->h[b->count] = h;
    b->count++;
}

double app_bne_rise_time(const double *t, const double *height, int count, double radius,
                         double surface, double tolerance)
{
    for (int k = 0; k < count; ++k)
        if (height[k] + radius >= surface - tolerance)
            return t[k];
    return NAN;
}

AppBneResult app_bne_result(const AppBne *b)
{
    AppBneResult r;
    memset(&r, 0, sizeof r);
    r.gamma = b->gamma;
    r.period = b->period;
    r.amplitude = b->amplitude;
    r.intruder_radius = b->radius;
    r.surface = b->surface0;
    r.start_height = b->h0;
    r.count = b->count;
    r.t = b->t;
    r.height = b->h;
    r.end_height = b->count ? b->h[b->count - 1] : (double)NAN;
    r.shaking_time = b->count ? b->t[b->count - 1] : 0.0;
    r.rise_rate =
        r.shaking_time > 0.0 ? (r.end_height - r.start_height) / r.shaking_time : (double)NAN;
    r.rise_time = app_bne_rise_time(b->t, b->h, b->count, b->radius, b->surface0, b->tolerance);
    return r;
}

static void json_num(char *out, size_t size, double v)
{
    snprintf(out, size, isfinite(v) ? "%.9g" : "null", v);
}

static int bne_end(void *state, AppContext *c, int ok)
{
    AppBne *b = state;
    char *err = c->err;
    size_t err_size = c->err_size;
    if (b->csv && app_tmp_commit(&b->csv, b->csv_path) != 0) {
        snprintf(err, err_size, "cannot write %s", b->csv_path);
        return -1;
    }
    if (!ok)
        return 0;
    AppBneResult r = app_bne_result(b);
    char v[9][40];
    json_num(v[0], 40, r.gamma);
    json_num(v[1], 40, r.period);
    json_num(v[2], 40, r.amplitude);
    json_num(v[3], 40, r.surface);
    json_num(v[4], 40, r.start_height);
    json_num(v[5], 40, r.end_height);
    json_num(v[6], 40, r.rise_time);
    json_num(v[7], 40, r.rise_rate);
    json_num(v[8], 40, r.intruder_radius);
    char phase[400] = "";
    if (b->pf_on && b->pf_have_mean)
        snprintf(phase, sizeof phase,
                 ",\n  \"phase_field\": {\"phase\": %.9g, \"phases\": %d, \"skip_cycles\": %d, "
                 "\"samples\": %d, \"max_phase_error\": %.3g, \"cell\": %.9g, \"width\": %.9g, "
                 "\"nx\": %d, \"ny\": %d}",
                 b->pf_phase, b->pf_phases, b->pf_skip, b->pf_count, b->pf_max_error,
                 b->pf_mean.cell, b->pf_mean.width, b->pf_mean.nx, b->pf_mean.ny);
    char text[2048];
    snprintf(text, sizeof text,
             "{\n  \"gamma\": %s,\n  \"period\": %s,\n  \"amplitude\": %s,\n  \"intruder\": %u,\n"
             "  \"intruder_radius\": %s,\n  \"surface\": %s,\n  \"start_height\": %s,\n"
             "  \"end_height\": %s,\n  \"rise_time\": %s,\n  \"rise_rate\": %s,\n"
             "  \"tolerance\": %.9g,\n  \"samples\": %d%s\n}\n",
             v[0], v[1], v[2], b->intruder, v[8], v[3], v[4], v[5], v[6], v[7], b->tolerance,
             r.count, phase);
    if (app_write_atomic(b->json_path, text) != 0) {
        snprintf(err, err_size, "cannot write %s", b->json_path);
        return -1;
    }
    return 0;
}

/* ---------------------------------------------------------------- phase-averaged field */

/* Offset and velocity of the box along the motion's direction at world time t (the walls' own
 * formula, sim/world.c: A sin(w t + phase)). */
static double box_motion(const AppBne *b, double t, double *velocity)
{
    double arg = 2.0 * SIM_PI * b->frequency * t + b->phase;
    *velocity = b->amplitude * 2.0 * SIM_PI * b->frequency * cos(arg);
    return b->amplitude * sin(arg);
}

long app_bne_phase_step(double phase, int phases, double period, double dt, long m)
{
    long n = m / phases, k = m % phases;
    double tau = ((double)n + phase + (double)k / (double)phases) * period;
    return (long)llround(tau / dt);
}

static int field_alloc(AppBneField *f, int nx, int ny)
{
    size_t n = (size_t)nx * (size_t)ny;
    f->nx = nx;
    f->ny = ny;
    f->rho = calloc(n, sizeof *f->rho);
    f->jx = calloc(n, sizeof *f->jx);
    f->jy = calloc(n, sizeof *f->jy);
    f->solid = calloc(n, sizeof *f->solid);
    f->hits = calloc(n, sizeof *f->hits);
    f->stamp = malloc(n * sizeof *f->stamp);
    if (!f->rho || !f->jx || !f->jy || !f->solid || !f->hits || !f->stamp) {
        app_bne_field_free(f);
        return -1;
    }
    for (size_t k = 0; k < n; ++k)
        f->stamp[k] = -1;
    return 0;
}

int app_bne_field_init(AppBneField *f, double x0, double y0, double x1, double y1, double cell,
                       double width)
{
    memset(f, 0, sizeof *f);
    if (!(cell > 0.0) || !(width > 0.0) || !(x1 > x0) || !(y1 > y0) || !isfinite(x1 - x0) ||
        !isfinite(y1 - y0))
        return -1;
    double fx = ceil((x1 - x0) / cell), fy = ceil((y1 - y0) / cell);
    if (!(fx * fy <= 4e6))
        return -1;
    int nx = (int)fx, ny = (int)fy;
    f->x0 = 0.5 * (x0 + x1) - 0.5 * nx * cell; /* centred between the side walls */
    f->y0 = y0;
    f->cell = cell;
    f->width = width;
    f->mass_model = SIM_MASS_DISK;
    return field_alloc(f, nx, ny);
}

void app_bne_field_free(AppBneField *f)
{
    if (!f)
        return;
    free(f->rho);
    free(f->jx);
    free(f->jy);
    free(f->solid);
    free(f->hits);
    free(f->stamp);
    f->rho = f->jx = f->jy = f->solid = NULL;
    f->hits = NULL;
    f->stamp = NULL;
    f->nx = f->ny = f->samples = 0;
}

void app_bne_field_add(AppBneField *f, const SimFrame *frame, double shift_x, double shift_y,
                       double velocity_x, double velocity_y)
{
    long sample = f->samples++;
    double w = f->width, cell = f->cell;
    double period = frame->periodic ? frame->domain_x1 - frame->domain_x0 : 0.0;
    for (int g = 0; g < frame->count; ++g) {
        int fixed =
            frame->flags ? (frame->flags[g] & SIM_GRAIN_FIXED) != 0u : g >= frame->mobile_count;
        if (fixed)
            continue;
        double r = frame->radius[g];
        int species = frame->species ? frame->species[g] : 0;
        species = species < 0 || species >= SIM_MAX_SPECIES ? 0 : species;
        double volume =
            f->mass_model == SIM_MASS_SPHERE ? 4.0 / 3.0 * SIM_PI * r * r * r : SIM_PI * r * r;
        double m = f->density[species] * volume, area = SIM_PI * r * r;
        double vx = frame->vx[g] - velocity_x, vy = frame->vy[g] - velocity_y;
        for (int image = -1; image <= 1; ++image) { /* periodic images that reach the grid */
            if (image != 0 && !(period > 0.0))
                continue;
            double x = frame->x[g] - shift_x + image * period, y = frame->y[g] - shift_y;
            double fi0 = ceil((x - w - f->x0) / cell - 0.5),
                   fi1 = floor((x + w - f->x0) / cell - 0.5);
            double fj0 = ceil((y - w - f->y0) / cell - 0.5),
                   fj1 = floor((y + w - f->y0) / cell - 0.5);
            if (!(fi1 >= 0.0) || !(fj1 >= 0.0) || !(fi0 <= f->nx - 1) || !(fj0 <= f->ny - 1))
                continue;
            int i0 = fi0 < 0.0 ? 0 : (int)fi0, i1 = fi1 > f->nx - 1 ? f->nx - 1 : (int)fi1;
            int j0 = fj0 < 0.0 ? 0 : (int)fj0, j1 = fj1 > f->ny - 1 ? f->ny - 1 : (int)fj1;
            for (int j = j0; j <= j1; ++j) {
                double dy = f->y0 + (j + 0.5) * cell - y;
                for (int i = i0; i <= i1; ++i) {
                    double dx = f->x0 + (i + 0.5) * cell - x;
                    double k = sim_kernel_lucy(sqrt(dx * dx + dy * dy), w); /* Lucy 1977 */
                    if (!(k > 0.0))
                        continue;
                    size_t idx = (size_t)j * (size_t)f->nx + (size_t)i;
                    f->rho[idx] += m * k;
                    f->jx[idx] += m * vx * k;
                    f->jy[idx] += m * vy * k;
                    f->solid[idx] += area * k;
                    if (m > 0.0 && f->stamp[idx] != sample) {
                        f->stamp[idx] = sample;
                        f->hits[idx]++;
                    }
                }
            }
        }
    }
}

void app_bne_field_node(const AppBneField *f, int k, double *vx, double *vy, double *solid)
{
    *vx = f->rho[k] > 0.0 ? f->jx[k] / f->rho[k] : 0.0;
    *vy = f->rho[k] > 0.0 ? f->jy[k] / f->rho[k] : 0.0;
    *solid = f->samples > 0 ? f->solid[k] / f->samples : 0.0;
}

int app_bne_field_combine(const AppBneField *phases, int count, AppBneField *out)
{
    memset(out, 0, sizeof *out);
    if (count < 1)
        return -1;
    const AppBneField *g = &phases[0];
    out->x0 = g->x0;
    out->y0 = g->y0;
    out->cell = g->cell;
    out->width = g->width;
    out->mass_model = g->mass_model;
    memcpy(out->density, g->density, sizeof out->density);
    if (field_alloc(out, g->nx, g->ny) != 0)
        return -1;
    int used = 0;
    for (int p = 0; p < count; ++p) {
        const AppBneField *f = &phases[p];
        if (f->samples < 1 || f->nx != out->nx || f->ny != out->ny)
            continue;
        ++used;
        out->samples += f->samples;
        for (size_t k = 0; k < (size_t)out->nx * (size_t)out->ny; ++k) {
            out->rho[k] += f->rho[k] / f->samples; /* this phase's mean density and flux */
            out->jx[k] += f->jx[k] / f->samples;
            out->jy[k] += f->jy[k] / f->samples;
            out->solid[k] += f->solid[k] / f->samples;
            out->hits[k] += f->hits[k];
        }
    }
    /* solid: sum of the phases' means; stored as a sum over samples so that node() divides it */
    for (size_t k = 0; used > 0 && k < (size_t)out->nx * (size_t)out->ny; ++k)
        out->solid[k] *= (double)out->samples / used;
    return 0;
}

void app_bne_field_rows(const AppBneField *f, double phase, FILE *csv)
{
    for (int j = 0; j < f->ny; ++j)
        for (int i = 0; i < f->nx; ++i) {
            int k = j * f->nx + i;
            double vx, vy, solid;
            app_bne_field_node(f, k, &vx, &vy, &solid);
            if (phase >= 0.0)
                fprintf(csv, "%.9g,", phase);
            fprintf(csv, "%.9g,%.9g,%.9g,%.9g,%d,%.6g\n", f->x0 + (i + 0.5) * f->cell,
                    f->y0 + (j + 0.5) * f->cell, vx, vy, f->hits[k], solid);
        }
}

const AppBneField *app_bne_phase_field(const AppBne *b)
{
    return b && b->pf_have_mean ? &b->pf_mean : NULL;
}

int app_bne_phase_times(const AppBne *b, const double **times)
{
    *times = b ? b->pf_times : NULL;
    return b ? b->pf_count : 0;
}

static void phase_field_reset(AppBne *b)
{
    if (b->pf_fields)
        for (int k = 0; k < b->pf_phases; ++k)
            app_bne_field_free(&b->pf_fields[k]);
    free(b->pf_fields);
    b->pf_fields = NULL;
    app_bne_field_free(&b->pf_mean);
    b->pf_have_mean = 0;
    b->pf_ready = 0;
    b->pf_error[0] = '\0';
    b->pf_next = 0;
    b->pf_count = 0;
    b->pf_max_error = 0.0;
}

/* At the start of shaking: the node grid, in the box's frame. Default region: x between the
 * walls moved by the box's motion (the periodic range when periodic, else the grains' extent),
 * y from the floor (or the lowest grain) to 1.5 times the bed's height above it. */
static void phase_field_start(AppBne *b, SimWorld *world, const SimFrame *f)
{
    phase_field_reset(b);
    double speed, off = box_motion(b, b->t0, &speed);
    double diameter = 0.0, mass = 0.0;
    sim_world_means(world, &diameter, &mass);
    double cell = b->pf_cell > 0.0 ? b->pf_cell : 2.0 * diameter;
    double width = b->pf_width > 0.0 ? b->pf_width : 1.5 * diameter;
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, top = -INFINITY;
    for (int i = 0; i < f->mobile_count; ++i) {
        x0 = fmin(x0, f->x[i] - f->radius[i] - off * b->dir_x);
        x1 = fmax(x1, f->x[i] + f->radius[i] - off * b->dir_x);
        y0 = fmin(y0, f->y[i] - f->radius[i] - off * b->dir_y);
        top = fmax(top, f->y[i] + f->radius[i] - off * b->dir_y);
    }
    double wx0 = INFINITY, wx1 = -INFINITY, wy0 = INFINITY;
    for (int k = 0; k < f->wall_count; ++k) {
        const SimWall *w = &f->walls[k];
        if (w->motion != b->motion)
            continue;
        wx0 = fmin(wx0, fmin(w->x0, w->x1) - off * b->dir_x);
        wx1 = fmax(wx1, fmax(w->x0, w->x1) - off * b->dir_x);
        wy0 = fmin(wy0, fmin(w->y0, w->y1) - off * b->dir_y);
    }
    if (f->periodic) {
        x0 = f->domain_x0;
        x1 = f->domain_x1;
    } else if (wx1 > wx0) {
        x0 = wx0;
        x1 = wx1;
    }
    if (wy0 < y0)
        y0 = wy0;
    double y1 = top + 0.5 * (top - y0);
    if (b->pf_region[2] > b->pf_region[0]) {
        x0 = b->pf_region[0];
        y0 = b->pf_region[1];
        x1 = b->pf_region[2];
        y1 = b->pf_region[3];
    }
    b->pf_dt = sim_world_time_step(world);
    b->pf_diameter = diameter;
    b->pf_fields = calloc((size_t)b->pf_phases, sizeof *b->pf_fields);
    if (!b->pf_fields) {
        snprintf(b->pf_error, sizeof b->pf_error, "out of memory");
        return;
    }
    for (int k = 0; k < b->pf_phases; ++k) {
        AppBneField *field = &b->pf_fields[k];
        if (app_bne_field_init(field, x0, y0, x1, y1, cell, width) != 0) {
            snprintf(b->pf_error, sizeof b->pf_error,
                     "cannot make a grid of cell %g over [%g, %g] x [%g, %g] (too many nodes, "
                     "no grains, or no memory)",
                     cell, x0, x1, y0, y1);
            return;
        }
        field->mass_model = b->mass_model;
        memcpy(field->density, b->density, sizeof field->density);
    }
    b->pf_ready = 1;
}

static long bne_next_step(const void *state, const AppContext *c, long done, long next)
{
    const AppBne *b = state;
    if (!b->pf_ready || c->stage != b->stage)
        return next;
    long s = app_bne_phase_step(b->pf_phase, b->pf_phases, b->period, b->pf_dt, b->pf_next);
    return s > done && s < next ? s : next;
}

static void bne_step(void *state, AppContext *c, long done)
{
    AppBne *b = state;
    SimWorld *world = c->world;
    if (!b->pf_ready || c->stage != b->stage)
        return;
    SimFrame f;
    int framed = 0;
    for (;;) {
        long m = b->pf_next, n = m / b->pf_phases, k = m % b->pf_phases;
        long s = app_bne_phase_step(b->pf_phase, b->pf_phases, b->period, b->pf_dt, m);
        if (s > done)
            break;
        b->pf_next++;
        /* s < done: a step the runner did not stop at (app_bne_next_step prevents it) */
        if (s < done || n < b->pf_skip)
            continue;
        if (!framed) {
            sim_world_frame(world, &f);
            framed = 1;
        }
        double t = sim_world_time(world), speed, off = box_motion(b, t, &speed);
        app_bne_field_add(&b->pf_fields[k], &f, off * b->dir_x, off * b->dir_y, speed * b->dir_x,
                          speed * b->dir_y);
        double tau = ((double)n + b->pf_phase + (double)k / b->pf_phases) * b->period;
        b->pf_max_error = fmax(b->pf_max_error, fabs(t - b->t0 - tau));
        if (b->pf_count == b->pf_capacity) {
            int capacity = b->pf_capacity ? 2 * b->pf_capacity : 256;
            double *times = realloc(b->pf_times, (size_t)capacity * sizeof *times);
            if (!times)
                continue;
            b->pf_times = times;
            b->pf_capacity = capacity;
        }
        b->pf_times[b->pf_count++] = t - b->t0;
    }
}

/* The field as arrows on its own grid nodes over the final pile, through the runner's figure hook
 * (app/ knows no renderer): the grid moves with the box (its offset at the frame's time), each
 * node's arrow is its mean velocity, nodes never hit or with a mean solid fraction below 0.1 are
 * left out (as the renderer masks its own field), and a reference arrow gives the scale. */
static int phase_figure(AppBne *b, const Scene *scene, SimWorld *world, const AppRender *render,
                        const char *path, char *err, size_t err_size)
{
    const AppBneField *field = &b->pf_mean;
    SimFrame f;
    sim_world_frame(world, &f);
    size_t n = (size_t)field->nx * (size_t)field->ny;
    double *vx = malloc((n ? n : 1) * sizeof *vx), *vy = malloc((n ? n : 1) * sizeof *vy);
    if (!vx || !vy) {
        free(vx);
        free(vy);
        snprintf(err, err_size, "out of memory");
        return -1;
    }
    double speed, off = box_motion(b, f.time, &speed);
    int arrows = 0;
    for (size_t k = 0; k < n; ++k) {
        double ux, uy, solid;
        app_bne_field_node(field, (int)k, &ux, &uy, &solid);
        vx[k] = vy[k] = (double)NAN;
        if (field->hits[k] == 0 || solid < 0.1)
            continue;
        vx[k] = ux;
        vy[k] = uy;
        ++arrows;
    }
    AppFigureExtras extras = {.field_vx = vx,
                              .field_vy = vy,
                              .field_nx = field->nx,
                              .field_ny = field->ny,
                              .field_x0 = field->x0 + off * b->dir_x,
                              .field_y0 = field->y0 + off * b->dir_y,
                              .field_cell = field->cell};
    SceneFigure figure;
    memset(&figure, 0, sizeof figure);
    snprintf(figure.name, sizeof figure.name, "phase_field");
    figure.stage = b->stage;
    figure.at_end = 1;
    snprintf(figure.format, sizeof figure.format, "png");
    figure.style = scene->style;
    figure.style.velocity_arrows = 0;
    figure.style.velocity_field = 0;
    figure.style.force_chains = 0;
    /* faint grains under dark arrows (the arrows are the nodes', not the grains' own) */
    figure.style.color_by = SCENE_COLOR_FIXED;
    figure.style.fill_rgb = 0xe4e4e4;
    figure.style.colorbar = 0;
    /* the scene's view (else the occupied grid), enlarged to at least 20 pixels per mean
     * diameter so that arrows of a tenth of the largest speed still show */
    SceneStyle *st = &figure.style;
    if (!(st->view_x1 > st->view_x0) || !(st->view_y1 > st->view_y0)) {
        double top = field->y0 + field->cell;
        for (int k = 0; k < field->nx * field->ny; ++k)
            if (field->hits[k] > 0 && field->solid[k] >= 0.1 * field->samples)
                top = fmax(top, field->y0 + (k / field->nx + 1.5) * field->cell);
        st->view_x0 = field->x0 + off * b->dir_x;
        st->view_x1 = st->view_x0 + field->nx * field->cell;
        st->view_y0 = field->y0 + off * b->dir_y - 0.5 * field->cell;
        st->view_y1 = top + off * b->dir_y;
    }
    double width = st->width > 0 ? st->width : 1280.0, height = st->height > 0 ? st->height : 720.0;
    double scale = fmin(width / (st->view_x1 - st->view_x0), height / (st->view_y1 - st->view_y0));
    double wanted = b->pf_diameter > 0.0 ? 20.0 / b->pf_diameter : 0.0;
    if (scale < wanted) {
        double grow = fmin(wanted / scale, 4000.0 / fmax(width, height));
        st->width = (int)ceil(width * grow);
        st->height = (int)ceil(height * grow);
    }
    if (b->pf_phases == 1)
        snprintf(figure.style.title, sizeof figure.style.title, "box-frame velocity at phase %.3g",
                 b->pf_phase);
    else
        snprintf(figure.style.title, sizeof figure.style.title, "box-frame cycle-mean velocity");
    int rc = arrows > 0
                 ? render->figure(render->context, scene, &figure, &f, &extras, path, err, err_size)
                 : 0;
    free(vx);
    free(vy);
    return rc == 0 ? 0 : -1;
}

static int bne_stage_end(void *state, AppContext *c)
{
    AppBne *b = state;
    const Scene *scene = c->scene;
    SimWorld *world = c->world;
    const AppRender *render = c->render;
    char *err = c->err;
    size_t err_size = c->err_size;
    if (!b->pf_on || c->stage != b->stage)
        return 0;
    if (!b->pf_ready) {
        snprintf(err, err_size, "%s: bne.phase_field: %s", scene->path, b->pf_error);
        return -1;
    }
    app_bne_field_free(&b->pf_mean);
    b->pf_have_mean = app_bne_field_combine(b->pf_fields, b->pf_phases, &b->pf_mean) == 0;
    if (!b->pf_have_mean) {
        snprintf(err, err_size, "bne.phase_field: out of memory");
        return -1;
    }
    char path[BNE_PATH + 32];
    snprintf(path, sizeof path, "%s/phase_field.csv", b->out_dir);
    FILE *csv = app_tmp_open(path, "x,y,vx,vy,samples,solid_fraction");
    if (csv)
        app_bne_field_rows(&b->pf_mean, -1.0, csv);
    if (!csv || app_tmp_commit(&csv, path) != 0) {
        snprintf(err, err_size, "cannot write %s", path);
        return -1;
    }
    if (b->pf_phases > 1) {
        snprintf(path, sizeof path, "%s/phase_fields.csv", b->out_dir);
        csv = app_tmp_open(path, "phase,x,y,vx,vy,samples,solid_fraction");
        for (int k = 0; csv && k < b->pf_phases; ++k)
            app_bne_field_rows(&b->pf_fields[k], fmod(b->pf_phase + (double)k / b->pf_phases, 1.0),
                               csv);
        if (!csv || app_tmp_commit(&csv, path) != 0) {
            snprintf(err, err_size, "cannot write %s", path);
            return -1;
        }
    }
    if (b->pf_count == 0)
        fprintf(stderr,
                "sablier: warning: bne.phase_field: no samples (the shaking stage ended before "
                "cycle %d reached phase %g): phase_field.csv holds no data, no figure\n",
                b->pf_skip, b->pf_phase);
    if (!render || !render->figure)
        return 0;
    snprintf(path, sizeof path, "%s/phase_field.png", b->out_dir);
    char message[512] = "";
    if (phase_figure(b, scene, world, render, path, message, sizeof message) != 0) {
        snprintf(err, err_size, "figure %s: %s", path, message);
        return -1;
    }
    return 0;
}

/* ---------------------------------------------------------------- checkpoints */

/* `KEY_k v ...`: an int or long array as doubles (exact below 2^53). */
static void put_counts(FILE *out, const char *key, int k, const int *ints, const long *longs,
                       size_t n)
{
    char name[48];
    snprintf(name, sizeof name, "%s_%d", key, k);
    double *v = malloc((n ? n : 1) * sizeof *v);
    for (size_t j = 0; v && j < n; ++j)
        v[j] = ints ? (double)ints[j] : (double)longs[j];
    if (v)
        app_checkpoint_put(out, name, v, (long)n);
    free(v);
}

static int take_counts(const char *record, const char *key, int k, int *ints, long *longs, size_t n)
{
    char name[48];
    snprintf(name, sizeof name, "%s_%d", key, k);
    double *v = malloc((n ? n : 1) * sizeof *v);
    int rc = v ? app_checkpoint_take(record, name, v, (long)n) : -1;
    for (size_t j = 0; rc == 0 && j < n; ++j)
        if (ints)
            ints[j] = (int)v[j];
        else
            longs[j] = (long)v[j];
    free(v);
    return rc;
}

static void put_array(FILE *out, const char *key, int k, const double *v, size_t n)
{
    char name[48];
    snprintf(name, sizeof name, "%s_%d", key, k);
    app_checkpoint_put(out, name, v, (long)n);
}

static int take_array(const char *record, const char *key, int k, double *v, size_t n)
{
    char name[48];
    snprintf(name, sizeof name, "%s_%d", key, k);
    return app_checkpoint_take(record, name, v, (long)n);
}

/* One phase's field: its grid and sums. */
static void field_checkpoint(FILE *out, const AppBneField *f, int k)
{
    const double grid[7] = {f->nx, f->ny, f->x0, f->y0, f->cell, f->width, f->samples};
    size_t n = (size_t)f->nx * (size_t)f->ny;
    put_array(out, "pf_grid", k, grid, 7);
    put_array(out, "pf_rho", k, f->rho, n);
    put_array(out, "pf_jx", k, f->jx, n);
    put_array(out, "pf_jy", k, f->jy, n);
    put_array(out, "pf_solid", k, f->solid, n);
    put_counts(out, "pf_hits", k, f->hits, NULL, n);
    put_counts(out, "pf_stamp", k, NULL, f->stamp, n);
}

static int field_resume(const AppBne *b, const char *record, AppBneField *f, int k)
{
    double grid[7];
    memset(f, 0, sizeof *f);
    if (take_array(record, "pf_grid", k, grid, 7) != 0 || !(grid[0] >= 1.0) || !(grid[1] >= 1.0) ||
        !(grid[0] * grid[1] <= 4e6) || field_alloc(f, (int)grid[0], (int)grid[1]) != 0)
        return -1;
    f->x0 = grid[2];
    f->y0 = grid[3];
    f->cell = grid[4];
    f->width = grid[5];
    f->samples = (int)grid[6];
    f->mass_model = b->mass_model;
    memcpy(f->density, b->density, sizeof f->density);
    size_t n = (size_t)f->nx * (size_t)f->ny;
    return take_array(record, "pf_rho", k, f->rho, n) != 0 ||
                   take_array(record, "pf_jx", k, f->jx, n) != 0 ||
                   take_array(record, "pf_jy", k, f->jy, n) != 0 ||
                   take_array(record, "pf_solid", k, f->solid, n) != 0 ||
                   take_counts(record, "pf_hits", k, f->hits, NULL, n) != 0 ||
                   take_counts(record, "pf_stamp", k, NULL, f->stamp, n) != 0
               ? -1
               : 0;
}

/* A checkpoint: the shaking stage's measures, the rise record, bne.csv's length and, with
 * bne.phase_field, every phase's sums. */
static int bne_checkpoint(const void *state, const AppContext *c, FILE *out)
{
    (void)c;
    const AppBne *b = state;
    const double v[8] = {b->last_time, b->phase,  b->measuring, b->t0,
                         b->surface0,  b->radius, b->h0,        b->count};
    app_checkpoint_put(out, "bne", v, 8);
    app_checkpoint_put(out, "bne_t", b->t, b->count);
    app_checkpoint_put(out, "bne_h", b->h, b->count);
    app_checkpoint_file(out, b->csv_path, b->csv);
    if (!b->pf_on)
        return 0;
    const double pf[7] = {b->pf_ready, b->pf_dt,        b->pf_diameter, (double)b->pf_next,
                          b->pf_count, b->pf_max_error, b->pf_have_mean};
    app_checkpoint_put(out, "pf", pf, 7);
    app_checkpoint_put(out, "pf_times", b->pf_times, b->pf_count);
    for (int k = 0; b->pf_ready && k < b->pf_phases; ++k)
        field_checkpoint(out, &b->pf_fields[k], k);
    return 0;
}

/* The arrays of the rise record and the phase samples, `count` long. */
static int bne_resume_series(AppBne *b, const char *record, int count)
{
    while (b->capacity < count)
        if (app_series_grow(&b->t, &b->h, &b->capacity, 512) != 0)
            return -1;
    b->count = count;
    return count == 0 || (app_checkpoint_take(record, "bne_t", b->t, count) == 0 &&
                          app_checkpoint_take(record, "bne_h", b->h, count) == 0)
               ? 0
               : -1;
}

static int bne_resume_field(AppBne *b, const char *record)
{
    double pf[7];
    if (app_checkpoint_take(record, "pf", pf, 7) != 0 || !(pf[4] >= 0.0) || pf[4] > 1e9)
        return -1;
    phase_field_reset(b);
    b->pf_dt = pf[1];
    b->pf_diameter = pf[2];
    b->pf_next = (long)pf[3];
    b->pf_max_error = pf[5];
    int count = (int)pf[4];
    if (count > 0) {
        double *times = realloc(b->pf_times, (size_t)count * sizeof *times);
        if (!times)
            return -1;
        b->pf_times = times;
        if (app_checkpoint_take(record, "pf_times", b->pf_times, count) != 0)
            return -1;
        b->pf_capacity = b->pf_count = count;
    }
    if (pf[0] == 0.0)
        return 0;
    b->pf_fields = calloc((size_t)b->pf_phases, sizeof *b->pf_fields);
    for (int k = 0; k < b->pf_phases; ++k)
        if (!b->pf_fields || field_resume(b, record, &b->pf_fields[k], k) != 0)
            return -1;
    b->pf_ready = 1;
    if (pf[6] != 0.0) /* the shaking stage ended before the checkpoint: its mean again */
        b->pf_have_mean = app_bne_field_combine(b->pf_fields, b->pf_phases, &b->pf_mean) == 0;
    return 0;
}

static int bne_resume(void *state, AppContext *c, const char *record)
{
    AppBne *b = state;
    double v[8];
    int bad = app_checkpoint_take(record, "bne", v, 8) != 0 || !(v[7] >= 0.0) || v[7] > 1e9;
    if (!bad) {
        b->last_time = v[0];
        b->phase = v[1];
        b->measuring = (int)v[2];
        b->t0 = v[3];
        b->surface0 = v[4];
        b->radius = v[5];
        b->h0 = v[6];
    }
    bad = bad || bne_resume_series(b, record, (int)v[7]) != 0 ||
          (b->pf_on && bne_resume_field(b, record) != 0);
    if (bad) {
        snprintf(c->err, c->err_size, "--resume: the bne section of the checkpoint is malformed");
        return -1;
    }
    if (app_checkpoint_reopen(record, b->csv_path, &b->csv) != 0) {
        snprintf(c->err, c->err_size, "--resume: %s: %s (not as long as the checkpoint records)",
                 b->csv_path, strerror(errno));
        return -1;
    }
    return 0;
}

/* ---------------------------------------------------------------- the experiment */

static int bne_parse(const config_setting_t *root, const config_setting_t *group, Scene *scene,
                     void **state, char *err, size_t err_size)
{
    (void)root;
    *state = NULL;
    if (!group)
        return 0;
    *state = bne_parse_group(group, scene, err, err_size);
    return *state ? 0 : -1;
}

AppBne *app_bne_of(const Scene *scene)
{
    return scene_experiment_state(scene, &app_bne_experiment);
}

static const char *const OUTPUTS[] = {"bne.csv",          "bne.json",        "phase_field.csv",
                                      "phase_fields.csv", "phase_field.png", NULL};
const AppExperiment app_bne_experiment = {
    .name = "bne",
    .outputs = OUTPUTS,
    .group = "bne",
    .parse = bne_parse,
    .free = bne_free,
    .adjust_def = bne_adjust_def,
    .restart = bne_restart,
    .begin = bne_begin,
    .stage_begin = bne_stage_begin,
    .sample = bne_sample,
    .next_step = bne_next_step,
    .step = bne_step,
    .stage_end = bne_stage_end,
    .end = bne_end,
    .checkpoint = bne_checkpoint,
    .resume = bne_resume,
    .commands = app_bne_commands,
    .command_count = 1,
};
