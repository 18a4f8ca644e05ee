/* SPDX-License-Identifier: MIT */
/* bne.c: Brazil-nut measures and samples (thesis 002 ch. 5; see bne.h and docs/brazil_nut.md). */
#include "bne.h"

#include "run.h"
#include "util.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BNE_PI   3.14159265358979323846
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
};

/* ---------------------------------------------------------------- parsing */

static int number(AppParse *p, const config_setting_t *g, const char *key, double min, double *out)
{
    const config_setting_t *s = config_setting_get_member(g, key);
    if (!s)
        return 0;
    int type = config_setting_type(s);
    if (type == CONFIG_TYPE_FLOAT)
        *out = config_setting_get_float(s);
    else if (type == CONFIG_TYPE_INT || type == CONFIG_TYPE_INT64)
        *out = (double)config_setting_get_int64(s);
    else
        return app_parse_fail(p, s, "`%s` must be a number", key);
    if (!isfinite(*out) || *out < min)
        return app_parse_fail(p, s, "`%s` must be a finite number >= %g, got %g", key, min, *out);
    return 1;
}

AppBne *app_bne_parse(const config_setting_t *g, Scene *scene, char *err, size_t err_size)
{
    AppParse p = {scene->path, err, err_size, "bne"};
    static const char *const keys[] = {"intruder", "motion",    "gamma", "period",
                                       "stage",    "tolerance", NULL};
    if (app_parse_group_keys(&p, g, keys) < 0)
        return NULL;
    if (!(scene->def.effects & SIM_EFFECT_VIBRATION)) {
        app_parse_fail(&p, g, "the box is shaken by a motion: declare effect vibration");
        return NULL;
    }
    AppBne *b = calloc(1, sizeof *b);
    if (!b) {
        app_parse_fail(&p, g, "out of memory");
        return NULL;
    }
    const config_setting_t *s = config_setting_get_member(g, "intruder");
    if (!s ||
        (config_setting_type(s) != CONFIG_TYPE_INT &&
         config_setting_type(s) != CONFIG_TYPE_INT64) ||
        config_setting_get_int64(s) < 0 || config_setting_get_int64(s) >= scene->grains.count) {
        app_parse_fail(&p, s ? s : g, "`intruder` (the id of a grain of the scene) is required");
        free(b);
        return NULL;
    }
    b->intruder = (uint32_t)config_setting_get_int64(s);
    const char *motion = NULL, *stage = NULL;
    b->motion = -1;
    if (!config_setting_lookup_string(g, "motion", &motion)) {
        app_parse_fail(&p, g, "`motion` (the name of the motion shaking the box) is required");
        free(b);
        return NULL;
    }
    for (int m = 0; m < scene->def.motion_count; ++m)
        if (strcmp(scene->motion_names[m], motion) == 0)
            b->motion = m;
    if (b->motion < 0) {
        app_parse_fail(&p, config_setting_get_member(g, "motion"), "no motion named `%s`", motion);
        free(b);
        return NULL;
    }
    SimMotion *mo = &scene->def.motions[b->motion];
    b->gravity = hypot(scene->def.gravity_x, scene->def.gravity_y);
    b->period = mo->frequency > 0.0 ? 1.0 / mo->frequency : 0.0;
    b->tolerance = 0.5;
    b->gamma = NAN;
    if (number(&p, g, "period", 1e-12, &b->period) < 0 ||
        number(&p, g, "gamma", 0.0, &b->gamma) < 0 ||
        number(&p, g, "tolerance", 0.0, &b->tolerance) < 0) {
        free(b);
        return NULL;
    }
    if (!(b->period > 0.0)) {
        app_parse_fail(&p, g, "`period` is required when the motion has no frequency");
        free(b);
        return NULL;
    }
    b->frequency = 1.0 / b->period;
    double omega = 2.0 * BNE_PI * b->frequency;
    if (isfinite(b->gamma)) /* Gamma = A w^2 / g (002 eq. 12) */
        b->amplitude = b->gamma * b->gravity / (omega * omega);
    else {
        b->amplitude = fabs(mo->amplitude);
        b->gamma = b->amplitude * omega * omega / b->gravity;
    }
    mo->amplitude = b->amplitude;
    mo->frequency = b->frequency;
    mo->phase = 0.0;
    b->dir_y = mo->direction_y;
    b->stage = scene->stage_count - 1;
    if (config_setting_lookup_string(g, "stage", &stage)) {
        b->stage = scene_stage_index(scene, stage);
        if (b->stage < 0) {
            app_parse_fail(&p, config_setting_get_member(g, "stage"), "no stage named `%s`", stage);
            free(b);
            return NULL;
        }
    }
    return b;
}

void app_bne_free(AppBne *b)
{
    if (!b)
        return;
    if (b->csv) {
        fclose(b->csv);
        char tmp[BNE_PATH + 8];
        snprintf(tmp, sizeof tmp, "%s.tmp", b->csv_path);
        remove(tmp);
    }
    free(b->t);
    free(b->h);
    free(b);
}

void app_bne_adjust_def(const AppBne *b, int stage, SimWorldDef *def)
{
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
    /* offset A sin(w (t - t0)): the box leaves its rest position at the stage start t0 */
    mo->phase = -fmod(2.0 * BNE_PI * b->frequency * b->last_time, 2.0 * BNE_PI);
}

int app_bne_restart(const AppBne *b, int stage)
{
    return b && stage == b->stage && stage > 0;
}

/* ---------------------------------------------------------------- measures */

static double box_offset(const AppBne *b, double t)
{
    return b->amplitude * sin(2.0 * BNE_PI * b->frequency * t + b->phase) * b->dir_y;
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

int app_bne_begin(AppBne *b, const char *out_dir, char *err, size_t err_size)
{
    snprintf(b->csv_path, sizeof b->csv_path, "%s/bne.csv", out_dir);
    snprintf(b->json_path, sizeof b->json_path, "%s/bne.json", out_dir);
    char tmp[BNE_PATH + 8];
    snprintf(tmp, sizeof tmp, "%s.tmp", b->csv_path);
    if (!(b->csv = fopen(tmp, "w"))) {
        snprintf(err, err_size, "cannot write %s", tmp);
        return -1;
    }
    fprintf(b->csv, "t,t_shake,cycles,box_offset,intruder_y,intruder_top,surface,surface_start\n");
    b->count = 0;
    b->measuring = 0;
    b->last_time = 0.0;
    return 0;
}

void app_bne_stage(AppBne *b, const Scene *scene, int stage, SimWorld *world)
{
    (void)scene;
    if (stage != b->stage)
        return;
    b->t0 = sim_world_time(world);
    b->phase = -fmod(2.0 * BNE_PI * b->frequency * b->last_time, 2.0 * BNE_PI);
    SimFrame f;
    sim_world_frame(world, &f);
    int i = intruder_index(&f, b->intruder);
    b->radius = i >= 0 ? f.radius[i] : (double)NAN;
    b->h0 = i >= 0 ? f.y[i] - box_offset(b, b->t0) : (double)NAN;
    b->surface0 = surface_height(world, &f) - box_offset(b, b->t0);
    b->measuring = 1;
    b->count = 0;
}

void app_bne_row(AppBne *b, SimWorld *world)
{
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
    if (b->count == b->capacity) {
        int capacity = b->capacity ? 2 * b->capacity : 512;
        double *tt = realloc(b->t, (size_t)capacity * sizeof *tt);
        if (!tt)
            return;
        b->t = tt;
        double *hh = realloc(b->h, (size_t)capacity * sizeof *hh);
        if (!hh)
            return;
        b->h = hh;
        b->capacity = capacity;
    }
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

int app_bne_end(AppBne *b, int ok, char *err, size_t err_size)
{
    if (b->csv) {
        int closed = fclose(b->csv) == 0;
        b->csv = NULL;
        char tmp[BNE_PATH + 8];
        snprintf(tmp, sizeof tmp, "%s.tmp", b->csv_path);
        if (!closed || rename(tmp, b->csv_path) != 0) {
            snprintf(err, err_size, "cannot write %s", b->csv_path);
            return -1;
        }
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
    char tmp[BNE_PATH + 8];
    snprintf(tmp, sizeof tmp, "%s.tmp", b->json_path);
    FILE *f = fopen(tmp, "w");
    if (!f) {
        snprintf(err, err_size, "cannot write %s", tmp);
        return -1;
    }
    fprintf(f,
            "{\n  \"gamma\": %s,\n  \"period\": %s,\n  \"amplitude\": %s,\n  \"intruder\": %u,\n"
            "  \"intruder_radius\": %s,\n  \"surface\": %s,\n  \"start_height\": %s,\n"
            "  \"end_height\": %s,\n  \"rise_time\": %s,\n  \"rise_rate\": %s,\n"
            "  \"tolerance\": %.9g,\n  \"samples\": %d\n}\n",
            v[0], v[1], v[2], b->intruder, v[8], v[3], v[4], v[5], v[6], v[7], b->tolerance,
            r.count);
    if (fclose(f) != 0 || rename(tmp, b->json_path) != 0) {
        remove(tmp);
        snprintf(err, err_size, "cannot write %s", b->json_path);
        return -1;
    }
    return 0;
}

/* ---------------------------------------------------------------- large deviations */

int app_bne_ldf(const double *const *t, const double *const *height, const int *count, int records,
                double tau, int bins, double v_min, double v_max, double *centre,
                double *probability, double *rate_function)
{
    /* windows: from each record, consecutive non-overlapping spans of length tau */
    int capacity = 0, n = 0;
    for (int r = 0; r < records; ++r)
        capacity += count[r];
    double *v = malloc((size_t)(capacity > 0 ? capacity : 1) * sizeof *v);
    if (!v || bins < 1)
        return free(v), 0;
    for (int r = 0; r < records; ++r) {
        int k = 0;
        while (k < count[r]) {
            int j = k;
            while (j < count[r] && t[r][j] < t[r][k] + tau - 1e-9 * tau)
                ++j;
            if (j >= count[r])
                break;
            v[n++] = (height[r][j] - height[r][k]) / (t[r][j] - t[r][k]);
            k = j;
        }
    }
    if (!(v_min < v_max)) {
        v_min = INFINITY;
        v_max = -INFINITY;
        for (int k = 0; k < n; ++k) {
            v_min = fmin(v_min, v[k]);
            v_max = fmax(v_max, v[k]);
        }
        if (!(v_min < v_max)) {
            v_min -= 0.5;
            v_max += 0.5;
        }
    }
    double width = (v_max - v_min) / bins, p_max = 0.0;
    for (int b = 0; b < bins; ++b) {
        centre[b] = v_min + (b + 0.5) * width;
        probability[b] = 0.0;
    }
    for (int k = 0; k < n; ++k) {
        int b = (int)floor((v[k] - v_min) / width);
        b = b < 0 ? 0 : b >= bins ? bins - 1 : b;
        probability[b] += 1.0 / n;
    }
    for (int b = 0; b < bins; ++b)
        p_max = fmax(p_max, probability[b]);
    for (int b = 0; b < bins; ++b)
        rate_function[b] = probability[b] > 0.0 ? -log(probability[b] / p_max) / tau : (double)NAN;
    free(v);
    return n;
}

/* ---------------------------------------------------------------- samples */

typedef struct Record {
    double value;
    long seed;
    AppBneResult result;
    double *t, *h;
} Record;

static int split_vary(const char *vary, char *key, size_t key_size, double *values, int max)
{
    const char *eq = vary ? strchr(vary, '=') : NULL;
    if (!eq || eq == vary || (size_t)(eq - vary) >= key_size)
        return -1;
    snprintf(key, key_size, "%.*s", (int)(eq - vary), vary);
    int n = 0;
    const char *p = eq + 1;
    while (*p && n < max) {
        char *end;
        values[n] = strtod(p, &end);
        if (end == p || !isfinite(values[n]))
            return -1;
        ++n;
        p = end;
        if (*p == ',')
            ++p;
        else if (*p)
            return -1;
    }
    return n;
}

int app_bne_samples(const AppBneSamplesOptions *o)
{
    char key[128] = "";
    double values[64];
    int value_count = 1;
    values[0] = NAN;
    if (o->vary) {
        value_count = split_vary(o->vary, key, sizeof key, values, 64);
        if (value_count < 1) {
            fprintf(stderr, "sablier: bne: --vary must read KEY=v1,v2,..., got %s\n", o->vary);
            return 2;
        }
    }
    if (o->seeds < 1 || o->set_count > 60) {
        fprintf(stderr, "sablier: bne: --seeds must be >= 1\n");
        return 2;
    }
    if (app_make_dirs(o->out_dir) != 0) {
        fprintf(stderr, "sablier: bne: cannot create %s\n", o->out_dir);
        return 2;
    }
    int total = value_count * o->seeds, done = 0, status = 0;
    Record *records = calloc((size_t)total, sizeof *records);
    if (!records)
        return 2;
    for (int v = 0; v < value_count && status == 0; ++v)
        for (int s = 0; s < o->seeds && status == 0; ++s) {
            const char *sets[64];
            char seed_set[64], vary_set[200], dir[BNE_PATH], err[2048] = "";
            int n = 0;
            for (int k = 0; k < o->set_count; ++k)
                sets[n++] = o->sets[k];
            long seed = o->seed0 + s;
            snprintf(seed_set, sizeof seed_set, "seed=%ld", seed);
            sets[n++] = seed_set;
            if (o->vary) {
                snprintf(vary_set, sizeof vary_set, "%s=%.17g", key, values[v]);
                sets[n++] = vary_set;
                snprintf(dir, sizeof dir, "%s/%s=%g/seed-%ld", o->out_dir, key, values[v], seed);
            } else {
                snprintf(dir, sizeof dir, "%s/seed-%ld", o->out_dir, seed);
            }
            Scene *scene = scene_load(o->scene_path, sets, n, err, sizeof err);
            if (!scene) {
                fprintf(stderr, "%s\n", err);
                status = 2;
                break;
            }
            if (!scene->bne) {
                fprintf(stderr, "sablier: bne: %s has no `bne` group\n", o->scene_path);
                scene_free(scene);
                status = 2;
                break;
            }
            AppRunOptions ro = app_run_options_default();
            ro.out_dir = dir;
            ro.quiet = 1;
            ro.render = o->render;
            int rc = app_run(scene, &ro);
            Record *rec = &records[done];
            rec->value = values[v];
            rec->seed = seed;
            if (rc == 0) {
                rec->result = app_bne_result(scene->bne);
                size_t bytes =
                    (size_t)(rec->result.count > 0 ? rec->result.count : 1) * sizeof(double);
                rec->t = malloc(bytes);
                rec->h = malloc(bytes);
                if (rec->t && rec->h && rec->result.count > 0) {
                    memcpy(rec->t, rec->result.t, bytes);
                    memcpy(rec->h, rec->result.height, bytes);
                }
                rec->result.t = rec->t;
                rec->result.height = rec->h;
                ++done;
                if (!o->quiet)
                    fprintf(stderr, "sablier: bne: %s%s%g seed %ld: rise time %g, rate %g\n", key,
                            o->vary ? "=" : "", o->vary ? values[v] : 0.0, seed,
                            rec->result.rise_time, rec->result.rise_rate);
            } else {
                status = rc;
            }
            scene_free(scene);
        }
    /* samples.csv, rise.csv (mean +- std of the rise h - h0 against time), ldf.csv */
    char path[BNE_PATH];
    snprintf(path, sizeof path, "%s/samples.csv", o->out_dir);
    FILE *f = fopen(path, "w");
    FILE *rise = NULL, *ldf = NULL;
    if (f) {
        fprintf(f, "value,seed,gamma,period,rise_time,rise_rate,start_height,end_height,surface\n");
        for (int k = 0; k < done; ++k) {
            const AppBneResult *r = &records[k].result;
            fprintf(f, "%.9g,%ld,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", records[k].value,
                    records[k].seed, r->gamma, r->period, r->rise_time, r->rise_rate,
                    r->start_height, r->end_height, r->surface);
        }
        fclose(f);
    }
    snprintf(path, sizeof path, "%s/rise.csv", o->out_dir);
    rise = fopen(path, "w");
    snprintf(path, sizeof path, "%s/ldf.csv", o->out_dir);
    ldf = o->ldf_periods > 0.0 ? fopen(path, "w") : NULL;
    if (rise)
        fprintf(rise, "value,t,mean_rise,std_rise,samples\n");
    if (ldf)
        fprintf(ldf, "value,tau,v,probability,rate_function\n");
    AppBneCurve curves[64], ldf_curves[64];
    double *store[5 * 64];
    int stored = 0, curve_count = 0;
    char labels[64][192];
    for (int v = 0; v < value_count; ++v) {
        int first = -1, n = 0, len = 0;
        for (int k = 0; k < done; ++k)
            if (records[k].value == values[v] || (isnan(values[v]) && isnan(records[k].value))) {
                if (first < 0)
                    first = k;
                len = n == 0 || records[k].result.count < len ? records[k].result.count : len;
                ++n;
            }
        if (n == 0 || len == 0)
            continue;
        double *mean = calloc((size_t)len, sizeof *mean), *sd = calloc((size_t)len, sizeof *sd);
        if (!mean || !sd) {
            free(mean);
            free(sd);
            continue;
        }
        for (int j = 0; j < len; ++j) {
            double sum = 0.0, sum2 = 0.0;
            for (int k = first; k < done; ++k)
                if (records[k].value == values[v] ||
                    (isnan(values[v]) && isnan(records[k].value))) {
                    double x = records[k].h[j] - records[k].result.start_height;
                    sum += x;
                    sum2 += x * x;
                }
            mean[j] = sum / n;
            sd[j] = n > 1 ? sqrt(fmax(0.0, (sum2 - sum * sum / n) / (n - 1))) : 0.0;
            if (rise)
                fprintf(rise, "%.9g,%.9g,%.9g,%.9g,%d\n", values[v], records[first].t[j], mean[j],
                        sd[j], n);
        }
        snprintf(labels[curve_count], sizeof labels[0], "%s%s%g (%d)", o->vary ? key : "samples",
                 o->vary ? " = " : "", o->vary ? values[v] : (double)n, n);
        /* the plot shows about 15 error bars per curve, staggered between curves (every sample's
         * spread is in rise.csv) */
        double *bar = malloc((size_t)len * sizeof *bar);
        int step = len / 15 > 1 ? len / 15 : 1, offset = step * v / value_count;
        for (int j = 0; bar && j < len; ++j)
            bar[j] = j % step == offset ? sd[j] : (double)NAN;
        curves[curve_count] =
            (AppBneCurve){labels[curve_count], len, records[first].t, mean, bar ? bar : sd};
        store[stored++] = mean;
        store[stored++] = sd;
        if (bar)
            store[stored++] = bar;
        if (ldf) {
            const double *ts[256], *hs[256];
            int cs[256], r = 0;
            for (int k = first; k < done && r < 256; ++k)
                if (records[k].value == values[v] ||
                    (isnan(values[v]) && isnan(records[k].value))) {
                    ts[r] = records[k].t;
                    hs[r] = records[k].h;
                    cs[r] = records[k].result.count;
                    ++r;
                }
            double tau = o->ldf_periods * records[first].result.period;
            double *c = calloc(24, sizeof *c), *pr = calloc(24, sizeof *pr),
                   *rf = calloc(24, sizeof *rf);
            if (c && pr && rf) {
                int windows = app_bne_ldf(ts, hs, cs, r, tau, 24, 0.0, 0.0, c, pr, rf);
                for (int b = 0; b < 24 && windows > 0; ++b)
                    fprintf(ldf, "%.9g,%.9g,%.9g,%.9g,%.9g\n", values[v], tau, c[b], pr[b], rf[b]);
                ldf_curves[curve_count] = (AppBneCurve){labels[curve_count], 24, c, rf, NULL};
                store[stored++] = c;
                store[stored++] = rf;
                free(pr);
            } else {
                free(c);
                free(pr);
                free(rf);
                ldf_curves[curve_count] = (AppBneCurve){labels[curve_count], 0, NULL, NULL, NULL};
            }
        }
        ++curve_count;
    }
    if (rise)
        fclose(rise);
    if (ldf)
        fclose(ldf);
    if (o->plot && curve_count > 0) {
        char err[512] = "";
        snprintf(path, sizeof path, "%s/rise.png", o->out_dir);
        if (o->plot(o->plot_context, path, "Intruder rise (mean +- std over seeds)",
                    "time since shaking starts", "intruder height rise", curves, curve_count, err,
                    sizeof err) != 0)
            fprintf(stderr, "sablier: bne: %s: %s\n", path, err);
        if (ldf) {
            snprintf(path, sizeof path, "%s/ldf.png", o->out_dir);
            if (o->plot(o->plot_context, path, "Large-deviation function of the rise rate",
                        "windowed rise rate v", "I(v) = -ln(P(v)/P_max) / tau", ldf_curves,
                        curve_count, err, sizeof err) != 0)
                fprintf(stderr, "sablier: bne: %s: %s\n", path, err);
        }
    }
    for (int k = 0; k < stored; ++k)
        free(store[k]);
    for (int k = 0; k < total; ++k) {
        free(records[k].t);
        free(records[k].h);
    }
    free(records);
    return status;
}
