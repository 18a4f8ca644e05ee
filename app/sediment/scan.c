/* SPDX-License-Identifier: MIT */
/* sediment/scan.c: the sediment family's multi-run driver, `sablier sediment` (thesis 002 ch. 7):
 * a scene with a `sediment` group run once per Shields number through the stage runner, in parallel
 * processes, then flux.csv, threshold.json (the transport threshold) and flux.png. */
#include "sediment.h"

#include "base/util.h"
#include "driver/driver.h"
#include "driver/pool.h"
#include "driver/run_value.h"
#include "sim/sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- Shields scans */

double app_sediment_threshold(const double *shields, const double *q_star, int count, double level,
                              double *below, double *above)
{
    *below = NAN;
    *above = NAN;
    /* the two lowest transporting values, then the highest quiet one under the first */
    double t1 = INFINITY, q1 = NAN, t2 = INFINITY, q2 = NAN;
    for (int k = 0; k < count; ++k) {
        if (!isfinite(q_star[k]) || !isfinite(shields[k]) || !(q_star[k] > level))
            continue;
        if (shields[k] < t1) {
            t2 = t1;
            q2 = q1;
            t1 = shields[k];
            q1 = q_star[k];
        } else if (shields[k] < t2) {
            t2 = shields[k];
            q2 = q_star[k];
        }
    }
    if (!isfinite(t1))
        return NAN;
    *above = t1;
    double t0 = -INFINITY;
    for (int k = 0; k < count; ++k)
        if (isfinite(q_star[k]) && isfinite(shields[k]) && !(q_star[k] > level) &&
            shields[k] < t1 && shields[k] > t0)
            t0 = shields[k];
    if (!isfinite(t0))
        return NAN;
    *below = t0;
    if (!isfinite(t2) || !(q2 > q1))
        return 0.5 * (t0 + t1);
    double c = t1 - q1 * (t2 - t1) / (q2 - q1); /* zero-flux intercept */
    return c < t0 ? t0 : c > t1 ? t1 : c;
}

#define SCAN_MAX  64
#define SCAN_PATH (SCENE_PATH_MAX + 64)

typedef struct Scan {
    AppDriverArgs a; /* the common options: scene, --out, --set, --jobs, --quiet, --resume */
    const char *scene_path, *out_dir;
    int render_runs;
    double shields[SCAN_MAX], level;
    int count;
    const AppRender *render;
    char group[16]; /* the scene's name of the family's group: `sediment` or `fluid` */
} Scan;

static void member_dir(const Scan *sc, int k, char *dir, size_t size)
{
    snprintf(dir, size, "%s/shields=%g", sc->out_dir, sc->shields[k]);
}

/* One member, in a child process: the scene with sediment.shields = Theta_k. */
static int run_member(const Scan *sc, int k)
{
    char dir[SCAN_PATH];
    AppDriverSets sets = {.count = 0};
    app_driver_sets_add(&sets, sc->a.sets, sc->a.set_count);
    app_driver_sets_printf(&sets, "%s.shields=%.17g", sc->group, sc->shields[k]);
    member_dir(sc, k, dir, sizeof dir);
    return app_driver_member(sc->scene_path, &sets, &app_sediment_experiment, dir,
                             sc->render_runs ? sc->render : NULL);
}

static int scan_folder(void *ctx, int k, char *dir, size_t size)
{
    member_dir(ctx, k, dir, size);
    return 0;
}

static int scan_run(void *ctx, int k)
{
    return run_member(ctx, k);
}

static void scan_progress(void *ctx, int k, int status, char *line, size_t size)
{
    const Scan *sc = ctx;
    snprintf(line, size, "Theta = %g %s", sc->shields[k],
             status == 0                      ? "done"
             : status == APP_POOL_INTERRUPTED ? "interrupted"
                                              : "FAILED");
}

/* Member `key` of a member's sediment.json (app_json_path_number; NAN for null or absent). */
static double json_number(const char *text, const char *key)
{
    double v = NAN;
    return text && app_json_path_number(text, key, &v) == 0 ? v : (double)NAN;
}

static char *read_text(const char *path)
{
    FILE *f = sim_open_input(path, NULL);
    if (!f)
        return NULL;
    char *text = malloc(65536);
    size_t n = text ? fread(text, 1, 65535, f) : 0;
    fclose(f);
    if (text)
        text[n] = '\0';
    return text;
}

/* The members' results, read back from their sediment.json, and the threshold. */
typedef struct ScanResult {
    double q[SCAN_MAX], q_star[SCAN_MAX], t_sat[SCAN_MAX];
    int idx[SCAN_MAX]; /* members by Shields number */
    double theta_c, below, above;
    double xs[SCAN_MAX], ys[SCAN_MAX]; /* the flux curve: finite q* */
    int n;
} ScanResult;

static void read_results(const Scan *sc, const int *status, ScanResult *r)
{
    for (int k = 0; k < sc->count; ++k) {
        char dir[SCAN_PATH], path[SCAN_PATH + 32];
        member_dir(sc, k, dir, sizeof dir);
        snprintf(path, sizeof path, "%s/sediment.json", dir);
        char *text = status[k] == 0 ? read_text(path) : NULL;
        r->q[k] = json_number(text, "q_sat");
        r->q_star[k] = json_number(text, "q_sat_star");
        r->t_sat[k] = json_number(text, "t_sat");
        free(text);
        r->idx[k] = k;
    }
    int *idx = r->idx;
    for (int a = 1; a < sc->count; ++a) /* by Shields number, for the CSV and the curve */
        for (int b = a; b > 0 && sc->shields[idx[b]] < sc->shields[idx[b - 1]]; --b) {
            int t = idx[b];
            idx[b] = idx[b - 1];
            idx[b - 1] = t;
        }
    r->theta_c =
        app_sediment_threshold(sc->shields, r->q_star, sc->count, sc->level, &r->below, &r->above);
    r->n = 0;
    for (int j = 0; j < sc->count; ++j) {
        int k = idx[j];
        if (isfinite(r->q_star[k])) {
            r->xs[r->n] = sc->shields[k];
            r->ys[r->n++] = r->q_star[k];
        }
    }
}

/* flux.csv: one row per member by Shields number. 0, or 1. */
static int write_flux(const Scan *sc, const int *status, const ScanResult *r)
{
    char path[SCAN_PATH];
    snprintf(path, sizeof path, "%s/flux.csv", sc->out_dir);
    FILE *f = app_tmp_open(path, "shields,q_sat,q_sat_star,t_sat,transport,status");
    if (!f) {
        fprintf(stderr, "sablier: sediment: cannot write %s.tmp\n", path);
        return 1;
    }
    for (int j = 0; j < sc->count; ++j) {
        int k = r->idx[j];
        char text[16];
        fprintf(f, "%.9g,%.9g,%.9g,%.9g,%d,%s\n", sc->shields[k], r->q[k], r->q_star[k],
                r->t_sat[k], r->q_star[k] > sc->level, app_pool_status_text(status[k], text));
    }
    if (app_tmp_commit(&f, path) != 0) {
        fprintf(stderr, "sablier: sediment: cannot write %s\n", path);
        return 1;
    }
    return 0;
}

/* threshold.json and the threshold's line on stderr. 0, or 1. */
static int write_threshold(const Scan *sc, const ScanResult *r)
{
    char path[SCAN_PATH];
    snprintf(path, sizeof path, "%s/threshold.json", sc->out_dir);
    FILE *f = app_tmp_open(path, NULL);
    if (!f) {
        fprintf(stderr, "sablier: sediment: cannot write %s.tmp\n", path);
        return 1;
    }
    char v[3][32];
    const double vals[3] = {r->theta_c, r->below, r->above};
    for (int k = 0; k < 3; ++k)
        snprintf(v[k], sizeof v[k], isfinite(vals[k]) ? "%.9g" : "null", vals[k]);
    fprintf(f,
            "{\n  \"level\": %.9g,\n  \"shields_threshold\": %s,\n  \"bracket_below\": %s,\n"
            "  \"bracket_above\": %s,\n  \"members\": %d\n}\n",
            sc->level, v[0], v[1], v[2], sc->count);
    if (app_tmp_commit(&f, path) != 0) {
        fprintf(stderr, "sablier: sediment: cannot write %s\n", path);
        return 1;
    }
    fprintf(stderr, "sablier: sediment: threshold Theta_c = %s (bracket %s .. %s, q* > %g)\n", v[0],
            v[1], v[2], sc->level);
    return 0;
}

/* flux.png: q* against Theta, the transport level and the threshold (a failure is reported, not
 * fatal). */
static void plot_flux(const Scan *sc, const ScanResult *r)
{
    int n = r->n;
    double theta_c = r->theta_c, y_lo = INFINITY, y_hi = -INFINITY;
    for (int k = 0; k < n; ++k) {
        y_lo = fmin(y_lo, r->ys[k]);
        y_hi = fmax(y_hi, r->ys[k]);
    }
    double cx[2] = {theta_c, theta_c}, cy[2] = {fmin(0.0, y_lo), y_hi};
    double lx[2] = {r->xs[0], r->xs[n - 1]}, ly[2] = {sc->level, sc->level};
    char label[96];
    snprintf(label, sizeof label, "threshold %.3g", theta_c);
    AppPlotSeries curves[3] = {
        {.label = "q^*_{sat} (mean over the last third)",
         .count = n,
         .x = r->xs,
         .y = r->ys,
         .line = 1,
         .marker = APP_MARKER_CIRCLE,
         .rgb = APP_RGB_AUTO},
        {.label = "transport level",
         .count = 2,
         .x = lx,
         .y = ly,
         .line = 1,
         .dashed = 1,
         .rgb = APP_RGB_AUTO},
        {.label = label,
         .count = isfinite(theta_c) ? 2 : 0,
         .x = cx,
         .y = cy,
         .line = 1,
         .dashed = 1,
         .rgb = APP_RGB_AUTO},
    };
    AppPlotPanel panel = {.x_label = "Shields number \\Theta (1)",
                          .y_label = "q^* = q / (d \\sqrt{(D_R - 1) g d})",
                          .legend = APP_LEGEND_UPPER_LEFT,
                          .series_count = isfinite(theta_c) ? 3 : 2,
                          .series = curves};
    AppPlot plot = {.title = "Bed-load flux against Shields number",
                    .width = 1000,
                    .height = 700,
                    .rows = 1,
                    .cols = 1,
                    .panel_count = 1,
                    .panels = &panel,
                    .scene = "sediment",
                    .data_beside = 1}; /* flux.csv */
    char path[SCAN_PATH], err[512] = "";
    /* the scene with the command's --set: its print keys (render.plot_format, size, style) */
    Scene *scene = scene_load(sc->scene_path, sc->a.sets, sc->a.set_count, err, sizeof err);
    plot.print = scene ? &scene->style : NULL;
    snprintf(path, sizeof path, "%s/flux.png", sc->out_dir);
    if (sc->render->plot(sc->render->context, &plot, path, err, sizeof err) != 0)
        fprintf(stderr, "sablier: sediment: %s: %s\n", path, err);
    scene_free(scene);
}

static int write_scan_outputs(const Scan *sc, const int *status)
{
    ScanResult r;
    read_results(sc, status, &r);
    if (write_flux(sc, status, &r) != 0 || write_threshold(sc, &r) != 0)
        return 1;
    if (sc->render && sc->render->plot && r.n > 0)
        plot_flux(sc, &r);
    return 0;
}

static const AppDriverSpec SCAN_SPEC = {
    .usage = APP_SEDIMENT_USAGE, .jobs_max = 64, .missing = "missing SCENE"};

/* The options of `sablier sediment` alone (app_driver_parse's `own`). */
static int scan_option(void *ctx, int argc, char **argv, int *i)
{
    Scan *sc = ctx;
    const char *value;
    int m;
    if ((m = app_option(argc, argv, i, "--shields", &value)) != 0) {
        if (m < 0)
            return 2;
        static const AppNumberList shields_list = {.min = 0.0, .exact = 1};
        sc->count = app_parse_numbers(value, &shields_list, sc->shields, SCAN_MAX);
        if (sc->count < 1)
            return app_usage_error(APP_SEDIMENT_USAGE,
                                   "--shields needs up to 64 numbers >= 0 separated by commas, got",
                                   value);
    } else if ((m = app_option(argc, argv, i, "--level", &value)) != 0) {
        char *end;
        if (m < 0)
            return 2;
        sc->level = strtod(value, &end);
        if (*end || !isfinite(sc->level))
            return app_usage_error(APP_SEDIMENT_USAGE, "--level needs a number, got", value);
    } else if (strcmp(argv[*i], "--render") == 0) {
        sc->render_runs = 1;
    } else {
        return 0;
    }
    return 1;
}

/* A Scan with the defaults and the command line: 0, or the exit status of a usage error. */
static int scan_arguments(int argc, char **argv, Scan *sc)
{
    memset(sc, 0, sizeof *sc);
    sc->level = 1e-3;
    int rc = app_driver_parse(&SCAN_SPEC, argc, argv, &sc->a, scan_option, sc);
    if (rc != 0)
        return rc;
    if (sc->count < 1)
        return app_usage_error(APP_SEDIMENT_USAGE, "missing --shields T1,T2,...", NULL);
    sc->scene_path = sc->a.scene;
    sc->out_dir = sc->a.out;
    return 0;
}

static int sediment_parse(int argc, char **argv)
{
    Scan sc;
    return scan_arguments(argc, argv, &sc);
}

int app_sediment_command(int argc, char **argv, const AppEnv *env)
{
    Scan sc;
    int rc = scan_arguments(argc, argv, &sc);
    if (rc != 0)
        return rc;
    sc.render = env ? env->render : NULL;
    char default_out[SCAN_PATH];
    app_driver_default_out("sediment", sc.scene_path, default_out, sizeof default_out);
    if (!sc.out_dir)
        sc.out_dir = default_out;
    AppDriverSets sets = {.count = 0}; /* checked once before forking: bad input exits 2 */
    app_driver_sets_add(&sets, sc.a.sets, sc.a.set_count);
    Scene *scene = app_driver_load(sc.scene_path, &sets, &app_sediment_experiment);
    if (!scene)
        return 2;
    snprintf(sc.group, sizeof sc.group, "%s", app_sediment_group(app_sediment_of(scene)));
    scene_free(scene);
    if (app_make_dirs(sc.out_dir) != 0) {
        fprintf(stderr, "sablier: sediment: cannot create %s\n", sc.out_dir);
        return 2;
    }
    int status[SCAN_MAX];
    AppDriverPool pool = {.command = "sediment",
                          .not_started = "fork failed",
                          .count = sc.count,
                          .jobs = sc.a.jobs,
                          .resume = sc.a.resume,
                          .signal_status = 1,
                          .quiet = sc.a.quiet,
                          .ctx = &sc,
                          .status = status,
                          .run = scan_run,
                          .folder = scan_folder,
                          .progress = scan_progress};
    int pool_rc = app_driver_pool_run(&pool);
    rc = write_scan_outputs(&sc, status); /* interrupted: the finished members */
    return pool_rc > APP_EXIT_SIGNAL ? pool_rc : pool_rc != 0 || pool.failed ? 1 : rc;
}

const AppCommand app_sediment_commands[] = {
    {"sediment",
     "sediment SCENE Shields scan of bed-load transport: flux against Shields, threshold (002)",
     APP_SEDIMENT_USAGE, app_sediment_command, sediment_parse},
};
