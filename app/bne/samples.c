/* SPDX-License-Identifier: MIT */
/* bne/samples.c: the Brazil-nut family's multi-run driver, `sablier bne` (thesis 002 ch. 5): a
 * scene run for several seeds and values of one key through the stage runner, reduced to mean
 * +- standard deviation rise curves, rise times and the large-deviation function of the windowed
 * rise rate (docs/brazil_nut.md). */
#include "bne.h"

#include "base/util.h"
#include "driver/driver.h"
#include "driver/pool.h"
#include "sim/sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BNE_PATH (SCENE_PATH_MAX + 2 * SCENE_NAME_MAX)

/* ---------------------------------------------------------------- large deviations */

int app_bne_ldf(const double *const *t, const double *const *height, const int *count, int records,
                double tau, int bins, double v_min, double v_max, double *centre,
                double *probability, double *rate_function)
{
    /* windows: from each record, consecutive non-overlapping spans of length tau; each spans at
     * least one sample (j > k), so there are fewer than a record's samples (a tau that is not a
     * positive finite number: none) */
    int capacity = 0, n = 0;
    for (int r = 0; r < records; ++r)
        capacity += count[r];
    double *v = malloc((size_t)(capacity > 0 ? capacity : 1) * sizeof *v);
    if (!v || bins < 1 || !(tau > 0.0) || !isfinite(tau))
        return free(v), 0;
    for (int r = 0; r < records; ++r) {
        int k = 0;
        while (k < count[r]) {
            int j = k + 1;
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

/* One panel of curves, as every `sablier bne` plot (legend where it hides the fewest data). */
static int bne_plot(const AppRender *render, const SceneStyle *print, const char *path,
                    const char *title, const char *x_label, const char *y_label,
                    const AppPlotSeries *series, int count, char *err, size_t err_size)
{
    AppPlotPanel panel = {.x_label = x_label,
                          .y_label = y_label,
                          .legend = APP_LEGEND_AUTO,
                          .series_count = count < 64 ? count : 64,
                          .series = series};
    AppPlot plot = {.title = title,
                    .width = 1000,
                    .height = 700,
                    .rows = 1,
                    .cols = 1,
                    .panel_count = 1,
                    .panels = &panel,
                    .scene = "bne",
                    .print = print,
                    .data_beside = 1}; /* rise.csv, ldf.csv */
    return render->plot(render->context, &plot, path, err, err_size);
}

/* What `sablier bne` runs and what its runs gave. */
typedef struct Samples {
    const AppBneSamplesOptions *o;
    char key[128];
    double values[64];
    int value_count;
    Record *records;    /* by run: values outer, seeds inner */
    int *status;        /* each run's exit status (-1: not run) */
    int done;           /* the runs before the first that failed: those reduced */
    double bed_density; /* species 0's density (the bed's grains), for density ratios */
} Samples;

/* The curves of the reduction, and the arrays they point to (freed at the end). */
typedef struct Curves {
    AppPlotSeries rise[64], ldf[64];
    double *store[5 * 64];
    int stored, count;
    char labels[64][192];
} Curves;

static int same_value(double a, double b)
{
    return a == b || (isnan(a) && isnan(b));
}

/* The output folder of the run of value (key = value) and seed. */
static void run_dir(const Samples *S, double value, long seed, char *dir, size_t size)
{
    if (S->o->vary)
        snprintf(dir, size, "%s/%s=%g/seed-%ld", S->o->out_dir, S->key, value, seed);
    else
        snprintf(dir, size, "%s/seed-%ld", S->o->out_dir, seed);
}

/* A run's record in its folder, for the parent (the run is a child process): the result, then
 * its t and height samples, as raw doubles (the same bits come back). Read and removed by the
 * parent. */
static void record_path(const Samples *S, const Record *rec, char *path, size_t size)
{
    char dir[BNE_PATH];
    run_dir(S, rec->value, rec->seed, dir, sizeof dir);
    snprintf(path, size, "%s/bne.record", dir);
}

static int write_record(const Samples *S, const Record *rec)
{
    char path[BNE_PATH + 16];
    record_path(S, rec, path, sizeof path);
    size_t n = (size_t)(rec->result.count > 0 ? rec->result.count : 0);
    FILE *f = fopen(path, "wb");
    int ok = f && fwrite(&rec->result, sizeof rec->result, 1, f) == 1 &&
             fwrite(rec->result.t, sizeof(double), n, f) == n &&
             fwrite(rec->result.height, sizeof(double), n, f) == n;
    if (f && fclose(f) != 0)
        ok = 0;
    if (!ok)
        fprintf(stderr, "sablier: bne: cannot write %s\n", path);
    return ok ? 0 : -1;
}

static int read_record(const Samples *S, Record *rec)
{
    char path[BNE_PATH + 16];
    record_path(S, rec, path, sizeof path);
    FILE *f = sim_open_input(path, NULL);
    int ok = f && fread(&rec->result, sizeof rec->result, 1, f) == 1 && rec->result.count >= 0;
    size_t n = ok ? (size_t)rec->result.count : 0;
    rec->t = ok ? malloc((n > 0 ? n : 1) * sizeof(double)) : NULL;
    rec->h = ok ? malloc((n > 0 ? n : 1) * sizeof(double)) : NULL;
    ok = ok && rec->t && rec->h && fread(rec->t, sizeof(double), n, f) == n &&
         fread(rec->h, sizeof(double), n, f) == n;
    if (f)
        fclose(f);
    remove(path);
    rec->result.t = rec->t;
    rec->result.height = rec->h;
    if (!ok) {
        fprintf(stderr, "sablier: bne: cannot read the run's record %s\n", path);
        rec->result.count = 0;
    }
    return ok ? 0 : -1;
}

/* The scene of the run at (key = value, seed), with a `bne` group: NULL with a message on
 * stderr when it does not load. */
static Scene *load_run_scene(const Samples *S, double value, long seed)
{
    const AppBneSamplesOptions *o = S->o;
    AppDriverSets sets = {.count = 0};
    app_driver_sets_add(&sets, o->sets, o->set_count);
    app_driver_sets_printf(&sets, "seed=%ld", seed);
    if (o->vary)
        app_driver_sets_printf(&sets, "%s=%.17g", S->key, value);
    return app_driver_load(o->scene_path, &sets, &app_bne_experiment);
}

static int run_one(Samples *S, double value, long seed, Record *rec)
{
    const AppBneSamplesOptions *o = S->o;
    char dir[BNE_PATH];
    run_dir(S, value, seed, dir, sizeof dir);
    Scene *scene = load_run_scene(S, value, seed);
    if (!scene)
        return 2;
    int rc = app_driver_run(scene, dir, o->render); /* render NULL: --movies not given */
    rec->value = value;
    rec->seed = seed;
    if (rc == 0) {
        rec->result = app_bne_result(app_bne_of(scene));
        if (!o->quiet)
            fprintf(stderr, "sablier: bne: %s%s%g seed %ld: rise time %g, rate %g\n", S->key,
                    o->vary ? "=" : "", o->vary ? value : 0.0, seed, rec->result.rise_time,
                    rec->result.rise_rate);
    }
    if (rc == 0 && write_record(S, rec) != 0)
        rc = 2;
    scene_free(scene);
    return rc;
}

/* The runs are the pool's tasks, values outer: task k is value k / seeds, seed seed0 + k % seeds.
 * Each runs in a child process (app/driver/pool.h) and hands its record back through a file. */
static int sample_run(void *ctx, int k)
{
    Samples *S = ctx;
    Record rec;
    memset(&rec, 0, sizeof rec);
    return run_one(S, S->values[k / S->o->seeds], S->o->seed0 + k % S->o->seeds, &rec);
}

/* After a failure no later run starts (as the serial loop stopped there). */
static int sample_start(void *ctx, int k)
{
    const Samples *S = ctx;
    for (int j = 0; j < k; ++j)
        if (S->status[j] > 0)
            return 1;
    return 0;
}

/* A run that ended: its record read back (status 2 when it cannot be). */
static int sample_ended(void *ctx, int k, int status)
{
    Samples *S = ctx;
    Record *rec = &S->records[k];
    rec->value = S->values[k / S->o->seeds];
    rec->seed = S->o->seed0 + k % S->o->seeds;
    return status == 0 && read_record(S, rec) != 0 ? 2 : status;
}

static int sample_folder(void *ctx, int k, char *dir, size_t size)
{
    const Samples *S = ctx;
    run_dir(S, S->values[k / S->o->seeds], S->o->seed0 + k % S->o->seeds, dir, size);
    return 0;
}

/* Every value and seed, until one fails: 0, the exit status of the first that failed, or 128 +
 * the signal that stopped the pool (samples.csv then holds the runs finished before). */
static int run_samples(Samples *S)
{
    int total = S->value_count * S->o->seeds;
    AppDriverPool pool = {.command = "bne",
                          .not_started = "cannot start a run",
                          .count = total,
                          .jobs = S->o->jobs,
                          .resume = S->o->resume,
                          .signal_status = 1,
                          .ctx = S,
                          .status = S->status,
                          .start = sample_start,
                          .run = sample_run,
                          .folder = sample_folder,
                          .ended = sample_ended};
    int pool_rc = app_driver_pool_run(&pool);
    int rc = pool_rc > APP_EXIT_SIGNAL ? pool_rc : pool_rc != 0 ? 2 : 0;
    for (S->done = 0; S->done < total && S->status[S->done] == 0; ++S->done)
        ;
    if (S->done < total && S->status[S->done] > 0 && rc <= APP_EXIT_SIGNAL)
        rc = S->status[S->done];
    return rc;
}

/* samples.csv: every run, its status (app_pool_status_text: 0, the exit status of one that
 * failed, -1 not run, "interrupted") and, for a run that finished, its rise time and rate. */
static void write_samples_csv(const Samples *S, const char *path)
{
    FILE *f = app_tmp_open(
        path, "value,seed,status,gamma,period,rise_time,rise_rate,start_height,end_height,surface");
    if (!f) {
        fprintf(stderr, "sablier: bne: cannot write %s\n", path);
        return;
    }
    for (int k = 0; k < S->value_count * S->o->seeds; ++k) {
        const AppBneResult *r = &S->records[k].result;
        char status[16];
        fprintf(f, "%.9g,%ld,%s", S->values[k / S->o->seeds], S->o->seed0 + k % S->o->seeds,
                app_pool_status_text(S->status[k], status));
        if (S->status[k] == 0)
            fprintf(f, ",%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", r->gamma, r->period, r->rise_time,
                    r->rise_rate, r->start_height, r->end_height, r->surface);
        else
            fprintf(f, ",,,,,,,\n");
    }
    if (app_tmp_commit(&f, path) != 0)
        fprintf(stderr, "sablier: bne: cannot write %s\n", path);
}

/* The large-deviation function of the runs of values[v] (the first at records[first]): its
 * ldf.csv rows and curve C->ldf[C->count]. */
static void ldf_curve(const Samples *S, int v, int first, FILE *ldf, Curves *C)
{
    const double *ts[256], *hs[256];
    int cs[256], r = 0;
    for (int k = first; k < S->done && r < 256; ++k)
        if (same_value(S->records[k].value, S->values[v])) {
            ts[r] = S->records[k].t;
            hs[r] = S->records[k].h;
            cs[r] = S->records[k].result.count;
            ++r;
        }
    double tau = S->o->ldf_periods * S->records[first].result.period;
    double *c = calloc(24, sizeof *c), *pr = calloc(24, sizeof *pr), *rf = calloc(24, sizeof *rf);
    if (c && pr && rf) {
        int windows = app_bne_ldf(ts, hs, cs, r, tau, 24, 0.0, 0.0, c, pr, rf);
        for (int b = 0; b < 24 && windows > 0; ++b)
            fprintf(ldf, "%.9g,%.9g,%.9g,%.9g,%.9g\n", S->values[v], tau, c[b], pr[b], rf[b]);
        C->ldf[C->count] = (AppPlotSeries){.label = C->labels[C->count],
                                           .count = 24,
                                           .x = c,
                                           .y = rf,
                                           .line = 1,
                                           .rgb = APP_RGB_AUTO};
        C->store[C->stored++] = c;
        C->store[C->stored++] = rf;
        free(pr);
    } else {
        free(c);
        free(pr);
        free(rf);
        C->ldf[C->count] =
            (AppPlotSeries){.label = C->labels[C->count], .line = 1, .rgb = APP_RGB_AUTO};
    }
}

/* A ratio as a small fraction when it is one within 1e-6 ("1/3", "3"), else %g. */
static void ratio_text(double r, char *buf, size_t size)
{
    for (int q = 1; q <= 10; ++q) {
        double p = round(r * q);
        if (p >= 1.0 && fabs(r * q - p) <= 1e-6 * p) {
            if (q == 1)
                snprintf(buf, size, "%.0f", p);
            else
                snprintf(buf, size, "%.0f/%d", p, q);
            return;
        }
    }
    snprintf(buf, size, "%g", r);
}

/* A curve's legend (markup, docs/figures.md#markup): the varied quantity by its name, not its
 * key, and the number of runs it averages: "\Gamma = 1.5 (n = 3)", "\rho_{intruder}/\rho = 1/3
 * (n = 3)" (the density over the bed's, species 0), "\mu_{wall} = 0.5 (n = 3)"; "n = 3"
 * without --vary; any other key as it is. */
static void value_label(const Samples *S, double value, int n, char *buf, size_t size)
{
    if (!S->o->vary) {
        snprintf(buf, size, "n = %d", n);
        return;
    }
    const char *key = S->key, *dot = strrchr(key, '.');
    char species[64] = "", ratio[32];
    if (strncmp(key, "species.", 8) == 0 && dot && dot > key + 8)
        snprintf(species, sizeof species, "%.*s", (int)(dot - key - 8), key + 8);
    if (strcmp(key, "bne.gamma") == 0)
        snprintf(buf, size, "\\Gamma = %g (n = %d)", value, n);
    else if (species[0] && strcmp(dot, ".density") == 0 && S->bed_density > 0.0) {
        ratio_text(value / S->bed_density, ratio, sizeof ratio);
        snprintf(buf, size, "\\rho_{%s}/\\rho = %s (n = %d)", species, ratio, n);
    } else if (species[0] && strcmp(dot, ".mu") == 0)
        snprintf(buf, size, "\\mu_{%s} = %g (n = %d)", species, value, n);
    else
        snprintf(buf, size, "%s = %g (n = %d)", key, value, n);
}

/* The runs of values[v]: mean +- std of the rise h - h0 against time (rise.csv rows and curve
 * C->rise[C->count]) and their LDF (when ldf is open); nothing when there is no run. */
static void value_curves(const Samples *S, int v, FILE *rise, FILE *ldf, Curves *C)
{
    const Record *records = S->records;
    double value = S->values[v];
    int first = -1, n = 0, len = 0;
    for (int k = 0; k < S->done; ++k)
        if (same_value(records[k].value, value)) {
            if (first < 0)
                first = k;
            len = n == 0 || records[k].result.count < len ? records[k].result.count : len;
            ++n;
        }
    if (n == 0 || len == 0)
        return;
    double *mean = calloc((size_t)len, sizeof *mean), *sd = calloc((size_t)len, sizeof *sd);
    if (!mean || !sd) {
        free(mean);
        free(sd);
        return;
    }
    for (int j = 0; j < len; ++j) {
        double sum = 0.0, sum2 = 0.0;
        for (int k = first; k < S->done; ++k)
            if (same_value(records[k].value, value)) {
                double x = records[k].h[j] - records[k].result.start_height;
                sum += x;
                sum2 += x * x;
            }
        mean[j] = sum / n;
        sd[j] = n > 1 ? sqrt(fmax(0.0, (sum2 - sum * sum / n) / (n - 1))) : 0.0;
        if (rise)
            fprintf(rise, "%.9g,%.9g,%.9g,%.9g,%d\n", value, records[first].t[j], mean[j], sd[j],
                    n);
    }
    value_label(S, value, n, C->labels[C->count], sizeof C->labels[0]);
    /* the plot shows about 15 error bars per curve, staggered between curves (every sample's
     * spread is in rise.csv) */
    double *bar = malloc((size_t)len * sizeof *bar);
    int step = len / 15 > 1 ? len / 15 : 1, offset = step * v / S->value_count;
    for (int j = 0; bar && j < len; ++j)
        bar[j] = j % step == offset ? sd[j] : (double)NAN;
    C->rise[C->count] = (AppPlotSeries){.label = C->labels[C->count],
                                        .count = len,
                                        .x = records[first].t,
                                        .y = mean,
                                        .y_err = n < 2 ? NULL
                                                 : bar ? bar
                                                       : sd,
                                        .line = 1,
                                        .rgb = APP_RGB_AUTO};
    C->store[C->stored++] = mean;
    C->store[C->stored++] = sd;
    if (bar)
        C->store[C->stored++] = bar;
    if (ldf)
        ldf_curve(S, v, first, ldf, C);
    ++C->count;
}

/* rise.csv and ldf.csv (when ldf_periods > 0), and their curves, through temporary names. 1
 * when ldf.csv was written. */
static int write_curves(const Samples *S, Curves *C)
{
    char rise_path[BNE_PATH], ldf_path[BNE_PATH];
    snprintf(rise_path, sizeof rise_path, "%s/rise.csv", S->o->out_dir);
    snprintf(ldf_path, sizeof ldf_path, "%s/ldf.csv", S->o->out_dir);
    FILE *rise = app_tmp_open(rise_path, "value,t,mean_rise,std_rise,samples");
    FILE *ldf = S->o->ldf_periods > 0.0
                    ? app_tmp_open(ldf_path, "value,tau,v,probability,rate_function")
                    : NULL;
    if (!rise)
        fprintf(stderr, "sablier: bne: cannot write %s\n", rise_path);
    if (!ldf && S->o->ldf_periods > 0.0)
        fprintf(stderr, "sablier: bne: cannot write %s\n", ldf_path);
    for (int v = 0; v < S->value_count; ++v)
        value_curves(S, v, rise, ldf, C);
    if (rise && app_tmp_commit(&rise, rise_path) != 0)
        fprintf(stderr, "sablier: bne: cannot write %s\n", rise_path);
    if (!ldf)
        return 0;
    if (app_tmp_commit(&ldf, ldf_path) != 0) {
        fprintf(stderr, "sablier: bne: cannot write %s\n", ldf_path);
        return 0;
    }
    return 1;
}

void app_bne_axis_labels(const Scene *scene, char time[64], char rise[64], char rate[64])
{
    if (scene) {
        scene_axis_label(scene, "time since shaking starts", SCENE_TIME, time, 64);
        scene_axis_label(scene, "intruder height rise", SCENE_LENGTH, rise, 64);
        scene_axis_label(scene, "windowed rise rate v", SCENE_SPEED, rate, 64);
    } else {
        snprintf(time, 64, "time since shaking starts");
        snprintf(rise, 64, "intruder height rise");
        snprintf(rate, 64, "windowed rise rate v");
    }
}

/* rise.png, and ldf.png when ldf.csv was written (with_ldf). */
static void write_plots(const Samples *S, const Curves *C, int with_ldf)
{
    const AppBneSamplesOptions *o = S->o;
    if (!o->plot || !o->plot->plot || C->count == 0)
        return;
    char path[BNE_PATH], err[512] = "", x_label[64], y_label[64], v_label[64];
    /* the scene with the command's --set: its print keys (render.plot_format, size, style) */
    Scene *scene = scene_load(o->scene_path, o->sets, o->set_count, err, sizeof err);
    const SceneStyle *print = scene ? &scene->style : NULL;
    app_bne_axis_labels(scene, x_label, y_label, v_label);
    snprintf(path, sizeof path, "%s/rise.png", o->out_dir);
    if (bne_plot(o->plot, print, path, "Intruder rise (mean +- std over seeds)", x_label, y_label,
                 C->rise, C->count, err, sizeof err) != 0)
        fprintf(stderr, "sablier: bne: %s: %s\n", path, err);
    if (with_ldf) {
        snprintf(path, sizeof path, "%s/ldf.png", o->out_dir);
        if (bne_plot(o->plot, print, path, "Large-deviation function of the rise rate", v_label,
                     "I(v) = -ln(P(v)/P_max) / tau", C->ldf, C->count, err, sizeof err) != 0)
            fprintf(stderr, "sablier: bne: %s: %s\n", path, err);
    }
    scene_free(scene);
}

/* The options' checks and the output folder: 0, or the exit status. */
static int samples_setup(Samples *S)
{
    const AppBneSamplesOptions *o = S->o;
    S->value_count = 1;
    S->values[0] = NAN;
    if (o->vary) {
        S->value_count = app_parse_key_values(o->vary, S->key, sizeof S->key, S->values, 64);
        if (S->value_count < 1) {
            fprintf(stderr, "sablier: bne: --vary must read KEY=v1,v2,..., got %s\n", o->vary);
            return 2;
        }
    }
    if (o->seeds < 1 || o->set_count > 60) {
        fprintf(stderr, "sablier: bne: --seeds must be >= 1\n");
        return 2;
    }
    /* every value's scene (with the first seed) loads before any folder or file is made */
    for (int v = 0; v < S->value_count; ++v) {
        Scene *scene = load_run_scene(S, S->values[v], o->seed0);
        if (!scene)
            return 2;
        scene_free(scene);
    }
    char err[512];
    Scene *base = scene_load(o->scene_path, NULL, 0, err, sizeof err);
    if (base) {
        S->bed_density = base->def.materials[0].density;
        scene_free(base);
    }
    if (app_make_dirs(o->out_dir) != 0) {
        fprintf(stderr, "sablier: bne: cannot create %s\n", o->out_dir);
        return 2;
    }
    return 0;
}

int app_bne_samples(const AppBneSamplesOptions *o)
{
    Samples S = {.o = o};
    int status = samples_setup(&S);
    if (status != 0)
        return status;
    int total = S.value_count * o->seeds;
    S.records = calloc((size_t)total, sizeof *S.records);
    S.status = calloc((size_t)total, sizeof *S.status);
    Curves *C = calloc(1, sizeof *C);
    if (!S.records || !S.status || !C) {
        free(S.records);
        free(S.status);
        free(C);
        return 2;
    }
    status = run_samples(&S);
    /* samples.csv, rise.csv (mean +- std of the rise h - h0 against time), ldf.csv */
    char path[BNE_PATH];
    snprintf(path, sizeof path, "%s/samples.csv", o->out_dir);
    write_samples_csv(&S, path);
    int with_ldf = write_curves(&S, C);
    write_plots(&S, C, with_ldf);
    for (int k = 0; k < C->stored; ++k)
        free(C->store[k]);
    for (int k = 0; k < total; ++k) {
        free(S.records[k].t);
        free(S.records[k].h);
    }
    free(S.records);
    free(S.status);
    free(C);
    return status;
}

/* ---------------------------------------------------------------- the command */

static const char USAGE_BNE[] =
    "usage: sablier bne SCENE [--seeds N] [--seed0 S] [--vary KEY=v1,v2,...] [--ldf PERIODS]\n"
    "                   [--jobs N] [--out DIR] [--set KEY=VALUE]... [--movies] [--resume]\n"
    "                   [--quiet|-q]\n"
    "Runs a scene with a `bne` group for N seeds (default 5) and each value of KEY; writes\n"
    "DIR/samples.csv (rise time and rate per run), rise.csv and rise.png (mean +- std of the\n"
    "intruder's rise against time), ldf.csv and ldf.png (large-deviation function of the rise\n"
    "rate over windows of PERIODS shaking periods, default 5; docs/brazil_nut.md). Each run's own\n"
    "outputs go to DIR/KEY=value/seed-S/ (movies and figures only with --movies). The runs are\n"
    "separate processes, --jobs N at a time (default 2; results do not depend on N). SIGINT or\n"
    "SIGTERM stops the runs, writes the tables of those finished and exits 130 or 143.\n"
    "\n"
    "exit status: 0 every run succeeded, 1 a run failed, 2 bad input (nothing runs) or a table\n"
    "that cannot be written, 130/143 SIGINT/SIGTERM\n";

/* The command line of `sablier bne`. */
typedef struct BneArgs {
    AppBneSamplesOptions o;
    AppDriverArgs d; /* the common options */
    char default_out[SCENE_PATH_MAX];
    long seeds, seed0;
    int movies;
} BneArgs;

static const AppDriverSpec BNE_SPEC = {
    .usage = USAGE_BNE, .jobs_max = 64, .vary_max = 1, .missing = "missing SCENE"};

/* The options of `sablier bne` alone (app_driver_parse's `own`). */
static int bne_option(void *ctx, int argc, char **argv, int *i)
{
    BneArgs *a = ctx;
    const char *value;
    int m;
    if ((m = app_option(argc, argv, i, "--seeds", &value)) != 0) {
        if (m < 0 || app_parse_count(value, 1, 10000, &a->seeds) < 0)
            return app_usage_error(USAGE_BNE, "--seeds needs a count in [1, 10000], got",
                                   m < 0 ? "nothing" : value);
    } else if ((m = app_option(argc, argv, i, "--seed0", &value)) != 0) {
        if (m < 0 || app_parse_count(value, 0, 1000000000, &a->seed0) < 0)
            return app_usage_error(USAGE_BNE, "--seed0 needs a seed >= 0, got",
                                   m < 0 ? "nothing" : value);
    } else if ((m = app_option(argc, argv, i, "--ldf", &value)) != 0) {
        /* windows longer than a run are empty: 1e6 shaking periods is past any run */
        static const AppNumberList periods = {.min = 0.0, .strict = 1, .exact = 1};
        if (m < 0 || app_parse_numbers(value, &periods, &a->o.ldf_periods, 1) != 1 ||
            a->o.ldf_periods > 1e6)
            return app_usage_error(USAGE_BNE,
                                   "--ldf needs a number of periods in [0, 1e6] (0: no LDF), got",
                                   m < 0 ? "nothing" : value);
    } else if (strcmp(argv[*i], "--movies") == 0) {
        a->movies = 1;
    } else {
        return 0;
    }
    return 1;
}

/* The command line into *a: 0, or the exit status of a usage error (message on stderr). */
static int bne_arguments(int argc, char **argv, BneArgs *a)
{
    memset(a, 0, sizeof *a);
    a->seeds = 5;
    a->seed0 = 1;
    a->o.ldf_periods = 5.0;
    int rc = app_driver_parse(&BNE_SPEC, argc, argv, &a->d, bne_option, a);
    if (rc != 0)
        return rc;
    app_driver_default_out("bne", a->d.scene, a->default_out, sizeof a->default_out);
    a->o.scene_path = a->d.scene;
    a->o.out_dir = a->d.out ? a->d.out : a->default_out;
    a->o.sets = a->d.sets;
    a->o.set_count = a->d.set_count;
    a->o.vary = a->d.vary_count > 0 ? a->d.vary[0] : NULL;
    a->o.quiet = a->d.quiet;
    a->o.resume = a->d.resume;
    a->o.seeds = (int)a->seeds;
    a->o.seed0 = a->seed0;
    a->o.jobs = (int)a->d.jobs;
    return 0;
}

static int bne_parse(int argc, char **argv)
{
    BneArgs a;
    return bne_arguments(argc, argv, &a);
}

static int bne_command(int argc, char **argv, const AppEnv *env)
{
    BneArgs a;
    int status = bne_arguments(argc, argv, &a);
    if (status != 0)
        return status;
    if (a.movies)
        a.o.render = env->render;
    a.o.plot = env->render;
    return app_bne_samples(&a.o);
}

const AppCommand app_bne_commands[] = {
    {"bne",
     "bne SCENE      Brazil-nut samples over seeds and one varied key: rise curves, LDF (002)",
     USAGE_BNE, bne_command, bne_parse},
};
