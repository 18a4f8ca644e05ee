/* SPDX-License-Identifier: MIT */
/* sediment.c: the `fluid` group (thesis 002 ch. 6: 1D mixing-length fluid over a periodic bed)
 * and the bed-load measures (002 ch. 7: flux q(t), saturated flux, saturation time).
 *
 * Control numbers (002 eqs. 40-42; d = grain diameter, g = |gravity|, rho_p = grain density):
 *   D_R = rho_p / rho_f,  R = (d / nu) sqrt((D_R - 1) g d),  Theta = u*^2 / ((D_R - 1) g d).
 * A scene gives either these three or rho_f, nu and u* directly. */
#include "sediment.h"

#include "run.h"
#include "util.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#define SEDIMENT_PI 3.14159265358979323846

struct AppSediment {
    SimFluid *fluid;
    AppSedimentNumbers numbers;
    double width;          /* periodic bed width, m */
    double shear_velocity; /* u* once the flow stage starts, m/s */
    char flow_stage[SCENE_NAME_MAX];
    int flowing;              /* 1 once the flow stage started (or no flow stage named) */
    int steady_start;         /* 1: the fluid starts from its steady profile above the bed */
    double flow_start;        /* s */
    SimBodyForce fluid_force; /* the fluid's stage, applied from the flow stage on */
    FILE *csv;
    char csv_path[SCENE_PATH_MAX + 32];
    char json_path[SCENE_PATH_MAX + 32];
    double *t, *q;
    int count, capacity;
};

/* ---------------------------------------------------------------- parsing */

/* 1 found, 0 absent, -1 bad. */
static int number(AppParse *p, const config_setting_t *g, const char *key, double *out)
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
    if (!isfinite(*out))
        return app_parse_fail(p, s, "`%s` must be finite", key);
    return 1;
}

static int positive(AppParse *p, const config_setting_t *g, const char *key, double *out)
{
    int found = number(p, g, key, out);
    if (found > 0 && !(*out > 0.0))
        return app_parse_fail(p, config_setting_get_member(g, key), "`%s` must be > 0, got %g", key,
                              *out);
    return found;
}

static int boolean(AppParse *p, const config_setting_t *g, const char *key, int *out)
{
    const config_setting_t *s = config_setting_get_member(g, key);
    if (!s)
        return 0;
    if (config_setting_type(s) != CONFIG_TYPE_BOOL)
        return app_parse_fail(p, s, "`%s` must be true or false", key);
    *out = config_setting_get_bool(s);
    return 1;
}

/* Before the flow stage the grains settle dry (a viscous fluid at small Galileo numbers would
 * take thousands of time units to let a rain settle); from it on the fluid acts. */
static void sediment_force(void *context, const SimBodyForceView *view)
{
    AppSediment *s = context;
    if (s->flowing)
        s->fluid_force.apply(s->fluid_force.context, view);
}

AppSediment *app_sediment_parse(const config_setting_t *g, Scene *scene, char *err, size_t err_size)
{
    AppParse p = {scene->path, err, err_size, "fluid"};
    if (err_size)
        err[0] = '\0';
    if (!g)
        return NULL;
    static const char *const keys[] = {
        "density_ratio", "galileo",      "shields", "density",    "viscosity", "shear_velocity",
        "diameter",      "y0",           "y1",      "cells",      "turbulent", "kappa",
        "van_driest",    "bed_fraction", "c_inf",   "reynolds_c", "buoyancy",  "geometry",
        "flow_stage",    "drag_limit",   "start",   NULL};
    if (app_parse_group_keys(&p, g, keys) < 0)
        return NULL;
    if (!(scene->def.effects & SIM_EFFECT_PERIODIC_X)) {
        app_parse_fail(&p, g,
                       "the fluid column is horizontally averaged: it needs effect periodic_x");
        return NULL;
    }
    SimFluidDef fd = sim_fluid_def_default();
    AppSedimentNumbers num = {0};
    const SimWorldDef *def = &scene->def;
    double gravity = hypot(def->gravity_x, def->gravity_y);
    double rho_p = def->materials[0].density;
    /* d: mean diameter of the scene's mobile grains unless given */
    double sum = 0.0;
    int mobile = 0;
    for (int i = 0; i < scene->grains.count; ++i)
        if (!(scene->grains.flags[i] & SIM_GRAIN_FIXED)) {
            sum += 2.0 * scene->grains.radius[i];
            ++mobile;
        }
    num.diameter = mobile ? sum / mobile : 1.0;
    int has_dr = 0, has_ga = 0, has_sh = 0, has_rho = 0, has_nu = 0, has_us = 0, cells = 0;
    double y0 = 0.0, y1 = 0.0;
    const char *geometry = NULL, *flow_stage = NULL;
    if ((has_dr = positive(&p, g, "density_ratio", &num.density_ratio)) < 0 ||
        (has_ga = positive(&p, g, "galileo", &num.galileo)) < 0 ||
        (has_sh = number(&p, g, "shields", &num.shields)) < 0 ||
        (has_rho = positive(&p, g, "density", &fd.density)) < 0 ||
        (has_nu = positive(&p, g, "viscosity", &fd.viscosity)) < 0 ||
        (has_us = number(&p, g, "shear_velocity", &fd.shear_velocity)) < 0 ||
        positive(&p, g, "diameter", &num.diameter) < 0 || positive(&p, g, "kappa", &fd.kappa) < 0 ||
        positive(&p, g, "van_driest", &fd.van_driest) < 0 ||
        positive(&p, g, "bed_fraction", &fd.bed_fraction) < 0 ||
        number(&p, g, "c_inf", &fd.drag_c_inf) < 0 ||
        number(&p, g, "reynolds_c", &fd.drag_reynolds) < 0 ||
        boolean(&p, g, "turbulent", &fd.turbulent) < 0 ||
        boolean(&p, g, "buoyancy", &fd.buoyancy) < 0 ||
        boolean(&p, g, "drag_limit", &fd.drag_limit) < 0)
        return NULL;
    const config_setting_t *s;
    if (!(s = config_setting_get_member(g, "y0")) || number(&p, g, "y0", &y0) < 0 ||
        !(s = config_setting_get_member(g, "y1")) || number(&p, g, "y1", &y1) < 0) {
        if (!err[0])
            app_parse_fail(&p, g, "`y0` and `y1` (the column's bottom and top, m) are required");
        return NULL;
    }
    s = config_setting_get_member(g, "cells");
    if (!s || (config_setting_type(s) != CONFIG_TYPE_INT &&
               config_setting_type(s) != CONFIG_TYPE_INT64)) {
        app_parse_fail(&p, s ? s : g, "`cells` (number of fluid layers, an integer) is required");
        return NULL;
    }
    cells = config_setting_get_int(s);
    if (config_setting_lookup_string(g, "geometry", &geometry)) {
        if (strcmp(geometry, "disk") && strcmp(geometry, "sphere")) {
            app_parse_fail(&p, config_setting_get_member(g, "geometry"),
                           "unknown geometry `%s` (expected disk or sphere)", geometry);
            return NULL;
        }
        fd.geometry = strcmp(geometry, "sphere") == 0 ? SIM_FLUID_SPHERE : SIM_FLUID_DISK;
    } else {
        fd.geometry = def->mass_model == SIM_MASS_SPHERE ? SIM_FLUID_SPHERE : SIM_FLUID_DISK;
    }
    if ((fd.geometry == SIM_FLUID_SPHERE) != (def->mass_model == SIM_MASS_SPHERE)) {
        app_parse_fail(
            &p, config_setting_get_member(g, "geometry"),
            "geometry `%s` disagrees with mass_model: buoyancy and the density ratio would not "
            "match the grains' masses",
            geometry);
        return NULL;
    }
    int dimensionless = has_dr || has_ga || has_sh, dimensional = has_rho || has_nu || has_us;
    if (dimensionless == dimensional) {
        app_parse_fail(&p, g,
                       dimensionless
                           ? "give either density_ratio, galileo and shields or density, "
                             "viscosity and shear_velocity, not both"
                           : "give density_ratio, galileo and shields (002 eqs. 40-42) or density, "
                             "viscosity and shear_velocity");
        return NULL;
    }
    const double d = num.diameter;
    if (dimensionless) {
        if (!(has_dr && has_ga && has_sh)) {
            app_parse_fail(&p, g, "density_ratio, galileo and shields go together");
            return NULL;
        }
        if (!(num.density_ratio > 1.0) || num.shields < 0.0) {
            app_parse_fail(&p, config_setting_get_member(g, "density_ratio"),
                           "density_ratio must be > 1 and shields >= 0");
            return NULL;
        }
        double scale = sqrt((num.density_ratio - 1.0) * gravity * d);
        fd.density = rho_p / num.density_ratio;
        fd.viscosity = d * scale / num.galileo;
        fd.shear_velocity = sqrt(num.shields) * scale;
    } else {
        if (!(has_rho && has_nu && has_us)) {
            app_parse_fail(&p, g, "density, viscosity and shear_velocity go together");
            return NULL;
        }
        num.density_ratio = rho_p / fd.density;
        double scale = sqrt(fmax(num.density_ratio - 1.0, 0.0) * gravity * d);
        num.galileo = d * scale / fd.viscosity;
        num.shields =
            scale > 0.0 ? fd.shear_velocity * fd.shear_velocity / (scale * scale) : (double)NAN;
    }
    num.flux_scale = d * sqrt(fmax(num.density_ratio - 1.0, 0.0) * gravity * d);
    fd.y0 = y0;
    fd.y1 = y1;
    fd.cells = cells;
    fd.width = def->domain_x1 - def->domain_x0;
    fd.depth = fd.geometry == SIM_FLUID_SPHERE ? 2.0 * d / 3.0 : 1.0;
    fd.gravity_x = def->gravity_x;
    fd.gravity_y = def->gravity_y;
    SimTiming timing = sim_world_def_timing(def);
    fd.time_step = scene->stages[0].time_step > 0.0 ? scene->stages[0].time_step : timing.time_step;
    if (config_setting_lookup_string(g, "flow_stage", &flow_stage) &&
        scene_stage_index(scene, flow_stage) < 0) {
        app_parse_fail(&p, config_setting_get_member(g, "flow_stage"), "no stage named `%s`",
                       flow_stage);
        return NULL;
    }
    SimError e;
    if (sim_fluid_def_validate(&fd, &e) != SIM_OK) {
        const char *key = strchr(e.field, '.') ? strchr(e.field, '.') + 1 : e.field;
        app_parse_fail(&p,
                       config_setting_get_member(g, key) ? config_setting_get_member(g, key) : g,
                       "%s", e.message);
        return NULL;
    }
    AppSediment *sed = calloc(1, sizeof *sed);
    if (!sed || !(sed->fluid = sim_fluid_create(&fd, &e))) {
        free(sed);
        app_parse_fail(&p, g, "cannot create the fluid: out of memory");
        return NULL;
    }
    sed->numbers = num;
    sed->width = fd.width;
    sed->shear_velocity = fd.shear_velocity;
    if (flow_stage)
        snprintf(sed->flow_stage, sizeof sed->flow_stage, "%s", flow_stage);
    sed->flowing = flow_stage == NULL;
    sed->steady_start = 1;
    const char *start = NULL;
    if (config_setting_lookup_string(g, "start", &start)) {
        if (strcmp(start, "steady") && strcmp(start, "rest")) {
            app_parse_fail(&p, config_setting_get_member(g, "start"),
                           "unknown start `%s` (expected steady or rest)", start);
            app_sediment_free(sed);
            return NULL;
        }
        sed->steady_start = strcmp(start, "steady") == 0;
    }
    sed->fluid_force = sim_fluid_body_force(sed->fluid);
    scene->def.body_force.apply = sediment_force;
    scene->def.body_force.context = sed;
    return sed;
}

void app_sediment_free(AppSediment *s)
{
    if (!s)
        return;
    app_tmp_discard(&s->csv, s->csv_path); /* a run that never finished: no sediment.csv */
    sim_fluid_destroy(s->fluid);
    free(s->t);
    free(s->q);
    free(s);
}

SimFluid *app_sediment_fluid(const AppSediment *s)
{
    return s->fluid;
}

AppSedimentNumbers app_sediment_numbers(const AppSediment *s)
{
    return s->numbers;
}

/* ---------------------------------------------------------------- measures */

double app_sediment_flux(const SimFrame *frame, double width)
{
    double q = 0.0;
    for (int i = 0; i < frame->mobile_count; ++i)
        q += SEDIMENT_PI * frame->radius[i] * frame->radius[i] * frame->vx[i];
    return q / width;
}

double app_sediment_saturation(const double *t, const double *q, int count, double t_start,
                               double *t_sat)
{
    *t_sat = NAN;
    if (count < 1)
        return NAN;
    double t_end = t[count - 1], cut = t_end - (t_end - t_start) / 3.0, sum = 0.0;
    int n = 0;
    for (int k = 0; k < count; ++k)
        if (t[k] >= cut) {
            sum += q[k];
            ++n;
        }
    double q_sat = n ? sum / n : (double)NAN;
    /* T_sat = integral of (1 - q / q_sat) dt from t_start (trapezoids): exactly T for
     * q = q_sat (1 - exp(-t / T)), and robust to the noise of a small bed */
    if (!(isfinite(q_sat) && q_sat != 0.0))
        return q_sat;
    double integral = 0.0;
    for (int k = 1; k < count; ++k)
        if (t[k - 1] >= t_start)
            integral += 0.5 * (t[k] - t[k - 1]) * (2.0 - (q[k] + q[k - 1]) / q_sat);
    *t_sat = integral;
    return q_sat;
}

int app_sediment_begin(AppSediment *s, const char *out_dir, char *err, size_t err_size)
{
    snprintf(s->csv_path, sizeof s->csv_path, "%s/sediment.csv", out_dir);
    snprintf(s->json_path, sizeof s->json_path, "%s/sediment.json", out_dir);
    s->csv = app_tmp_open(s->csv_path, "t,q,q_star,grain_vx_mean,bed_level,u_top,shear_velocity");
    if (!s->csv) {
        snprintf(err, err_size, "cannot write %s.tmp", s->csv_path);
        return -1;
    }
    s->count = 0;
    return 0;
}

void app_sediment_stage(AppSediment *s, const Scene *scene, int stage, SimWorld *world)
{
    if (s->flowing || strcmp(scene->stages[stage].name, s->flow_stage) != 0)
        return;
    s->flowing = 1;
    s->flow_start = sim_world_time(world);
    if (!s->steady_start)
        return;
    /* Start from the steady clear-fluid profile above the bed (002 eq. 45) rather than from
     * rest: the column's own diffusion time H^2 / nu would otherwise dominate T_sat. The bed
     * level is the mean surface height minus half a diameter. */
    SimFrame frame;
    sim_world_frame(world, &frame);
    double bins[512], sum = 0.0;
    int n = 0, count = (int)fmin(512.0, fmax(1.0, s->width / s->numbers.diameter));
    sim_world_surface_profile(world, frame.domain_x0, frame.domain_x1, count, bins);
    for (int k = 0; k < count; ++k)
        if (isfinite(bins[k])) {
            sum += bins[k];
            ++n;
        }
    const SimFluidDef *fd = sim_fluid_def(s->fluid);
    double bed = n ? sum / n - 0.5 * s->numbers.diameter : fd->y0;
    SimFluidProfile p;
    sim_fluid_profile(s->fluid, &p);
    double *u = malloc((size_t)p.cells * sizeof *u);
    if (!u)
        return;
    sim_fluid_steady_reference(fd, bed, p.y, p.cells, u);
    sim_fluid_set_velocity(s->fluid, u);
    free(u);
}

void app_sediment_row(AppSediment *s, SimWorld *world)
{
    SimFrame frame;
    sim_world_frame(world, &frame);
    double q = app_sediment_flux(&frame, s->width), vx = 0.0;
    for (int i = 0; i < frame.mobile_count; ++i)
        vx += frame.vx[i];
    vx = frame.mobile_count ? vx / frame.mobile_count : 0.0;
    SimFluidProfile p;
    sim_fluid_profile(s->fluid, &p);
    double q_star = s->numbers.flux_scale > 0.0 ? q / s->numbers.flux_scale : (double)NAN;
    if (s->csv)
        fprintf(s->csv, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", frame.time, q, q_star, vx,
                p.bed_level, p.u[p.cells - 1], sim_fluid_def(s->fluid)->shear_velocity);
    if (!s->flowing)
        return;
    if (s->count == s->capacity && app_series_grow(&s->t, &s->q, &s->capacity, 256) != 0)
        return;
    s->t[s->count] = frame.time;
    s->q[s->count] = q;
    s->count++;
}

/* Fluid, concentration, grain-velocity and stress profiles: y, u, phi, grain_vx, tau_fluid (at the
 * layer's top face), grain_load (x-force per bed area the fluid exerts on the grains above that
 * face), tau_total = tau_fluid + grain_load (uniform at steady state, 002 fig. 34). */
int app_sediment_stage_end(AppSediment *s, SimWorld *world, const char *out_dir,
                           const char *stage_name, char *err, size_t err_size)
{
    (void)world;
    char path[SCENE_PATH_MAX + 2 * SCENE_NAME_MAX];
    snprintf(path, sizeof path, "%s/%s.fluid.csv", out_dir, stage_name);
    SimFluidProfile p;
    sim_fluid_profile(s->fluid, &p);
    double *load = calloc((size_t)p.cells + 1, sizeof *load);
    if (!load) {
        snprintf(err, err_size, "out of memory");
        return -1;
    }
    FILE *f = app_tmp_open(path, "y,u,phi,grain_vx,tau_fluid,grain_load,tau_total");
    if (!f) {
        free(load);
        snprintf(err, err_size, "cannot write %s.tmp", path);
        return -1;
    }
    for (int k = p.cells - 1; k >= 0; --k)
        load[k] = load[k + 1] + p.grain_force[k] * p.dy;
    for (int k = 0; k < p.cells; ++k)
        fprintf(f, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", p.y[k], p.u[k], p.solid_fraction[k],
                p.grain_velocity[k], p.stress[k + 1], load[k + 1], p.stress[k + 1] + load[k + 1]);
    free(load);
    if (app_tmp_commit(&f, path) != 0) {
        snprintf(err, err_size, "cannot write %s", path);
        return -1;
    }
    return 0;
}

int app_sediment_end(AppSediment *s, int ok, char *err, size_t err_size)
{
    int rc = 0;
    if (app_tmp_commit(&s->csv, s->csv_path) != 0) {
        snprintf(err, err_size, "cannot write %s", s->csv_path);
        rc = -1;
    }
    if (!ok || rc != 0)
        return rc;
    double t_sat = NAN;
    double q_sat = app_sediment_saturation(s->t, s->q, s->count, s->flow_start, &t_sat);
    const AppSedimentNumbers *n = &s->numbers;
    FILE *f = app_tmp_open(s->json_path, NULL);
    if (!f) {
        snprintf(err, err_size, "cannot write %s.tmp", s->json_path);
        return -1;
    }
    const SimFluidDef *fd = sim_fluid_def(s->fluid);
    char qs[32], qss[32], ts[32];
    snprintf(qs, sizeof qs, isfinite(q_sat) ? "%.9g" : "null", q_sat);
    snprintf(qss, sizeof qss, isfinite(q_sat) && n->flux_scale > 0 ? "%.9g" : "null",
             q_sat / n->flux_scale);
    snprintf(ts, sizeof ts, isfinite(t_sat) ? "%.9g" : "null", t_sat);
    fprintf(f,
            "{\n  \"diameter\": %.9g,\n  \"density_ratio\": %.9g,\n  \"galileo\": %.9g,\n"
            "  \"shields\": %.9g,\n  \"fluid_density\": %.9g,\n  \"viscosity\": %.9g,\n"
            "  \"shear_velocity\": %.9g,\n  \"turbulent\": %s,\n  \"flow_start\": %.9g,\n"
            "  \"q_sat\": %s,\n  \"q_sat_star\": %s,\n  \"t_sat\": %s,\n  \"samples\": %d\n}\n",
            n->diameter, n->density_ratio, n->galileo, n->shields, fd->density, fd->viscosity,
            s->shear_velocity, fd->turbulent ? "true" : "false", s->flow_start, qs, qss, ts,
            s->count);
    if (app_tmp_commit(&f, s->json_path) != 0) {
        snprintf(err, err_size, "cannot write %s", s->json_path);
        return -1;
    }
    return 0;
}

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
    const char *scene_path, *out_dir;
    const char *sets[SCAN_MAX + 1];
    int set_count, jobs, quiet, render_runs;
    double shields[SCAN_MAX], level;
    int count;
    const AppSedimentRender *render;
} Scan;

static void member_dir(const Scan *sc, int k, char *dir, size_t size)
{
    snprintf(dir, size, "%s/shields=%g", sc->out_dir, sc->shields[k]);
}

/* One member, in a child process: the scene with fluid.shields = Theta_k. */
static int run_member(const Scan *sc, int k)
{
    const char *sets[SCAN_MAX + 2];
    char shields_set[64], dir[SCAN_PATH], err[2048] = "";
    for (int j = 0; j < sc->set_count; ++j)
        sets[j] = sc->sets[j];
    snprintf(shields_set, sizeof shields_set, "fluid.shields=%.17g", sc->shields[k]);
    sets[sc->set_count] = shields_set;
    Scene *scene = scene_load(sc->scene_path, sets, sc->set_count + 1, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    if (!scene->sediment) {
        fprintf(stderr, "sablier: sediment: %s has no `fluid` group\n", sc->scene_path);
        scene_free(scene);
        return 2;
    }
    member_dir(sc, k, dir, sizeof dir);
    AppRunOptions ro = app_run_options_default();
    ro.out_dir = dir;
    ro.quiet = 1;
    ro.render = sc->render_runs && sc->render ? sc->render->run : NULL;
    int rc = app_run(scene, &ro);
    scene_free(scene);
    return rc;
}

/* The number after "key": in a member's sediment.json (NAN for null or absent). */
static double json_number(const char *text, const char *key)
{
    char pattern[64];
    snprintf(pattern, sizeof pattern, "\"%s\":", key);
    const char *p = text ? strstr(text, pattern) : NULL;
    if (!p)
        return NAN;
    p += strlen(pattern);
    char *end;
    double v = strtod(p, &end);
    return end == p ? (double)NAN : v;
}

static char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *text = malloc(65536);
    size_t n = text ? fread(text, 1, 65535, f) : 0;
    fclose(f);
    if (text)
        text[n] = '\0';
    return text;
}

static int write_scan_outputs(const Scan *sc, const int *status)
{
    double q[SCAN_MAX], q_star[SCAN_MAX], t_sat[SCAN_MAX];
    int idx[SCAN_MAX];
    for (int k = 0; k < sc->count; ++k) {
        char dir[SCAN_PATH], path[SCAN_PATH + 32];
        member_dir(sc, k, dir, sizeof dir);
        snprintf(path, sizeof path, "%s/sediment.json", dir);
        char *text = status[k] == 0 ? read_text(path) : NULL;
        q[k] = json_number(text, "q_sat");
        q_star[k] = json_number(text, "q_sat_star");
        t_sat[k] = json_number(text, "t_sat");
        free(text);
        idx[k] = k;
    }
    for (int a = 1; a < sc->count; ++a) /* by Shields number, for the CSV and the curve */
        for (int b = a; b > 0 && sc->shields[idx[b]] < sc->shields[idx[b - 1]]; --b) {
            int t = idx[b];
            idx[b] = idx[b - 1];
            idx[b - 1] = t;
        }
    double below, above;
    double theta_c =
        app_sediment_threshold(sc->shields, q_star, sc->count, sc->level, &below, &above);
    char path[SCAN_PATH];
    snprintf(path, sizeof path, "%s/flux.csv", sc->out_dir);
    FILE *f = app_tmp_open(path, "shields,q_sat,q_sat_star,t_sat,transport,status");
    if (!f) {
        fprintf(stderr, "sablier: sediment: cannot write %s.tmp\n", path);
        return 1;
    }
    double xs[SCAN_MAX], ys[SCAN_MAX];
    int n = 0;
    for (int j = 0; j < sc->count; ++j) {
        int k = idx[j];
        fprintf(f, "%.9g,%.9g,%.9g,%.9g,%d,%d\n", sc->shields[k], q[k], q_star[k], t_sat[k],
                q_star[k] > sc->level, status[k]);
        if (isfinite(q_star[k])) {
            xs[n] = sc->shields[k];
            ys[n++] = q_star[k];
        }
    }
    if (app_tmp_commit(&f, path) != 0) {
        fprintf(stderr, "sablier: sediment: cannot write %s\n", path);
        return 1;
    }
    snprintf(path, sizeof path, "%s/threshold.json", sc->out_dir);
    f = app_tmp_open(path, NULL);
    if (!f) {
        fprintf(stderr, "sablier: sediment: cannot write %s.tmp\n", path);
        return 1;
    }
    char v[3][32];
    const double vals[3] = {theta_c, below, above};
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
    if (sc->render && sc->render->plot && n > 0) {
        double y_lo = INFINITY, y_hi = -INFINITY;
        for (int k = 0; k < n; ++k) {
            y_lo = fmin(y_lo, ys[k]);
            y_hi = fmax(y_hi, ys[k]);
        }
        double cx[2] = {theta_c, theta_c}, cy[2] = {fmin(0.0, y_lo), y_hi};
        double lx[2] = {xs[0], xs[n - 1]}, ly[2] = {sc->level, sc->level};
        char label[96];
        snprintf(label, sizeof label, "threshold %.3g", theta_c);
        AppSedimentCurve curves[3] = {
            {"q*_sat (mean over the last third)", n, xs, ys, 1, 1, 0},
            {"transport level", 2, lx, ly, 1, 0, 1},
            {label, isfinite(theta_c) ? 2 : 0, cx, cy, 1, 0, 1},
        };
        char err[512] = "";
        snprintf(path, sizeof path, "%s/flux.png", sc->out_dir);
        if (sc->render->plot(sc->render->context, path, "Bed-load flux against Shields number",
                             "Shields number Theta", "q* = q / (d sqrt((D_R - 1) g d))", curves,
                             isfinite(theta_c) ? 3 : 2, err, sizeof err) != 0)
            fprintf(stderr, "sablier: sediment: %s: %s\n", path, err);
    }
    return 0;
}

static int parse_list(const char *text, double *values, int max)
{
    int n = 0;
    const char *p = text;
    while (*p) {
        if (n == max)
            return -1;
        char *end;
        values[n] = strtod(p, &end);
        if (end == p || !isfinite(values[n]) || values[n] < 0.0)
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

static int scan_usage(const char *message, const char *arg)
{
    fprintf(stderr, "sablier: sediment: %s%s%s\n\n%s", message, arg ? " " : "", arg ? arg : "",
            APP_SEDIMENT_USAGE);
    return 2;
}

int app_sediment_command(int argc, char **argv, const AppSedimentRender *render)
{
    Scan sc;
    memset(&sc, 0, sizeof sc);
    sc.jobs = 2;
    sc.level = 1e-3;
    sc.render = render;
    const char *list = NULL;
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i];
        int has_value = i + 1 < argc;
        if (strcmp(a, "--shields") == 0 && has_value) {
            list = argv[++i];
        } else if (strcmp(a, "--jobs") == 0 && has_value) {
            char *end;
            long j = strtol(argv[++i], &end, 10);
            if (*end || j < 1 || j > 64)
                return scan_usage("--jobs needs a count in [1, 64], got", argv[i]);
            sc.jobs = (int)j;
        } else if (strcmp(a, "--level") == 0 && has_value) {
            char *end;
            sc.level = strtod(argv[++i], &end);
            if (*end || !isfinite(sc.level))
                return scan_usage("--level needs a number, got", argv[i]);
        } else if (strcmp(a, "--out") == 0 && has_value) {
            sc.out_dir = argv[++i];
        } else if (strcmp(a, "--set") == 0 && has_value) {
            if (sc.set_count == SCAN_MAX)
                return scan_usage("too many --set options", NULL);
            sc.sets[sc.set_count++] = argv[++i];
        } else if (strcmp(a, "--render") == 0) {
            sc.render_runs = 1;
        } else if (strcmp(a, "--quiet") == 0 || strcmp(a, "-q") == 0) {
            sc.quiet = 1;
        } else if (a[0] == '-' && a[1]) {
            return scan_usage(has_value ? "unknown option" : "unknown option or missing value", a);
        } else if (!sc.scene_path) {
            sc.scene_path = a;
        } else {
            return scan_usage("one scene at a time; extra argument", a);
        }
    }
    if (!sc.scene_path)
        return scan_usage("missing SCENE", NULL);
    if (!list)
        return scan_usage("missing --shields T1,T2,...", NULL);
    sc.count = parse_list(list, sc.shields, SCAN_MAX);
    if (sc.count < 1)
        return scan_usage("--shields needs up to 64 numbers >= 0 separated by commas, got", list);
    char default_out[SCAN_PATH];
    const char *base =
        strrchr(sc.scene_path, '/') ? strrchr(sc.scene_path, '/') + 1 : sc.scene_path;
    snprintf(default_out, sizeof default_out, "out/sediment-%.*s", (int)strcspn(base, "."), base);
    if (!sc.out_dir)
        sc.out_dir = default_out;
    { /* check the scene once before forking: bad input exits 2 with its file:line message */
        char err[2048] = "";
        Scene *scene = scene_load(sc.scene_path, sc.sets, sc.set_count, err, sizeof err);
        if (!scene) {
            fprintf(stderr, "%s\n", err);
            return 2;
        }
        int has_fluid = scene->sediment != NULL;
        scene_free(scene);
        if (!has_fluid) {
            fprintf(stderr, "%s:1: sediment: the scene has no `fluid` group\n", sc.scene_path);
            return 2;
        }
    }
    if (app_make_dirs(sc.out_dir) != 0) {
        fprintf(stderr, "sablier: sediment: cannot create %s\n", sc.out_dir);
        return 2;
    }
    int status[SCAN_MAX];
    pid_t pids[SCAN_MAX];
    int slot_member[SCAN_MAX], next = 0, running = 0, failed = 0;
    for (int k = 0; k < sc.count; ++k)
        status[k] = -1;
    for (int j = 0; j < sc.jobs; ++j)
        pids[j] = 0;
    fflush(NULL);
    while (next < sc.count || running > 0) {
        while (running < sc.jobs && next < sc.count) {
            int slot = 0;
            while (pids[slot] != 0)
                ++slot;
            pid_t pid = fork();
            if (pid < 0) {
                fprintf(stderr, "sablier: sediment: fork failed: %s\n", strerror(errno));
                failed = 1;
                next = sc.count;
                break;
            }
            if (pid == 0) {
                int rc = run_member(&sc, next);
                fflush(NULL);
                _exit(rc);
            }
            pids[slot] = pid;
            slot_member[slot] = next++;
            ++running;
        }
        if (running == 0)
            break;
        int wstatus;
        pid_t pid = wait(&wstatus);
        if (pid < 0)
            break;
        for (int slot = 0; slot < sc.jobs; ++slot) {
            if (pids[slot] != pid)
                continue;
            pids[slot] = 0;
            --running;
            int k = slot_member[slot];
            status[k] = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : 1;
            failed |= status[k] != 0;
            if (!sc.quiet)
                fprintf(stderr, "sablier: sediment: Theta = %g %s\n", sc.shields[k],
                        status[k] == 0 ? "done" : "FAILED");
        }
    }
    int rc = write_scan_outputs(&sc, status);
    return failed ? 1 : rc;
}
