/* SPDX-License-Identifier: MIT */
/* sediment.c: the `sediment` group, older name `fluid` (thesis 002 ch. 6: 1D mixing-length fluid
 * over a periodic bed) and the bed-load measures (002 ch. 7: flux q(t), saturated flux, saturation
 * time).
 *
 * Control numbers (002 eqs. 40-42; d = grain diameter, g = |gravity|, rho_p = grain density):
 *   D_R = rho_p / rho_f,  R = (d / nu) sqrt((D_R - 1) g d),  Theta = u*^2 / ((D_R - 1) g d).
 * A scene gives either these three or rho_f, nu and u* directly. */
#include "sediment.h"

#include "base/checkpoint.h"
#include "base/config.h"
#include "base/experiments.h"
#include "base/util.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

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
    AppPlotPanel side_panels[2]; /* figure_extras: profiles beside the bed */
    AppPlotSeries side_series[2];
    char u_label[32], y_label[32]; /* their axes, in the scene's units */
    char group[16];                /* the group's name in the scene: `sediment` or `fluid` */
};

/* ---------------------------------------------------------------- parsing */

/* Before the flow stage the grains settle dry (a viscous fluid at small Galileo numbers would
 * take thousands of time units to let a rain settle); from it on the fluid acts. */
static void sediment_force(void *context, const SimBodyForceView *view)
{
    AppSediment *s = context;
    if (s->flowing)
        s->fluid_force.apply(s->fluid_force.context, view);
}

/* The fluid's control numbers as given: density_ratio, galileo, shields (002 eqs. 40-42) or
 * density, viscosity, shear_velocity; the other physical keys of the group. */
typedef struct SedimentInput {
    int has_dr, has_ga, has_sh, has_rho, has_nu, has_us;
    double y0, y1;
    const char *flow_stage;
} SedimentInput;

/* A number > 0 when present. */
static int positive(AppConfig *p, const config_setting_t *g, const char *key, double *out)
{
    int found = app_config_number(p, g, key, out);
    if (found > 0 && app_config_positive(p, g, key, *out) < 0)
        return -1;
    return found;
}

/* The six control keys and the physical ones; `diameter` defaults to the mean diameter of the
 * scene's mobile grains. */
static int parse_physical(AppConfig *p, const config_setting_t *g, const Scene *scene,
                          SedimentInput *in, AppSedimentNumbers *num, SimFluidDef *fd)
{
    double sum = 0.0;
    int mobile = 0;
    for (int i = 0; i < scene->grains.count; ++i)
        if (!(scene->grains.flags[i] & SIM_GRAIN_FIXED)) {
            sum += 2.0 * scene->grains.radius[i];
            ++mobile;
        }
    num->diameter = mobile ? sum / mobile : 1.0;
    if ((in->has_dr = positive(p, g, "density_ratio", &num->density_ratio)) < 0 ||
        (in->has_ga = positive(p, g, "galileo", &num->galileo)) < 0 ||
        (in->has_sh = app_config_number(p, g, "shields", &num->shields)) < 0 ||
        (in->has_rho = positive(p, g, "density", &fd->density)) < 0 ||
        (in->has_nu = positive(p, g, "viscosity", &fd->viscosity)) < 0 ||
        (in->has_us = app_config_number(p, g, "shear_velocity", &fd->shear_velocity)) < 0 ||
        positive(p, g, "diameter", &num->diameter) < 0 || positive(p, g, "kappa", &fd->kappa) < 0 ||
        positive(p, g, "van_driest", &fd->van_driest) < 0 ||
        positive(p, g, "bed_fraction", &fd->bed_fraction) < 0 ||
        app_config_number(p, g, "c_inf", &fd->drag_c_inf) < 0 ||
        app_config_number(p, g, "reynolds_c", &fd->drag_reynolds) < 0 ||
        app_config_bool(p, g, "turbulent", &fd->turbulent) < 0 ||
        app_config_bool(p, g, "buoyancy", &fd->buoyancy) < 0 ||
        app_config_bool(p, g, "drag_limit", &fd->drag_limit) < 0)
        return -1;
    return 0;
}

/* y0, y1 (the column's bottom and top) and cells: required. */
static int parse_column(AppConfig *p, const config_setting_t *g, SedimentInput *in, SimFluidDef *fd)
{
    if (app_config_number(p, g, "y0", &in->y0) <= 0 || app_config_number(p, g, "y1", &in->y1) <= 0)
        return app_config_fail(p, g, "`y0` and `y1` (the column's bottom and top, m) are required");
    const config_setting_t *s = app_config_member(g, "cells");
    if (!s ||
        (config_setting_type(s) != CONFIG_TYPE_INT && config_setting_type(s) != CONFIG_TYPE_INT64))
        return app_config_fail(p, s ? s : g,
                               "`cells` (number of fluid layers, an integer) is required");
    fd->cells = config_setting_get_int(s);
    fd->y0 = in->y0;
    fd->y1 = in->y1;
    return 0;
}

/* geometry = "disk" | "sphere", by default and necessarily that of mass_model. */
static int parse_geometry(AppConfig *p, const config_setting_t *g, const SimWorldDef *def,
                          SimFluidDef *fd)
{
    static const char *const geometries[] = {"disk", "sphere", NULL};
    int sphere = def->mass_model == SIM_MASS_SPHERE;
    int found = app_config_choice(p, g, "geometry", geometries, &sphere);
    if (found < 0)
        return -1;
    fd->geometry = sphere ? SIM_FLUID_SPHERE : SIM_FLUID_DISK;
    if (sphere != (def->mass_model == SIM_MASS_SPHERE))
        return app_config_fail(p, app_config_member(g, "geometry"),
                               "geometry `%s` disagrees with mass_model: buoyancy and the density "
                               "ratio would not match the grains' masses",
                               geometries[sphere]);
    return 0;
}

/* The numbers from the fluid or the fluid from the numbers (002 eqs. 40-42). */
static int derive_numbers(AppConfig *p, const config_setting_t *g, const Scene *scene,
                          const SedimentInput *in, AppSedimentNumbers *num, SimFluidDef *fd)
{
    const SimWorldDef *def = &scene->def;
    double gravity = hypot(def->gravity_x, def->gravity_y);
    double rho_p = def->materials[0].density;
    int dimensionless = in->has_dr || in->has_ga || in->has_sh;
    int dimensional = in->has_rho || in->has_nu || in->has_us;
    if (dimensionless == dimensional)
        return app_config_fail(p, g,
                               dimensionless
                                   ? "give either density_ratio, galileo and shields or density, "
                                     "viscosity and shear_velocity, not both"
                                   : "give density_ratio, galileo and shields (002 eqs. 40-42) or "
                                     "density, viscosity and shear_velocity");
    const double d = num->diameter;
    if (dimensionless) {
        if (!(in->has_dr && in->has_ga && in->has_sh))
            return app_config_fail(p, g, "density_ratio, galileo and shields go together");
        if (!(num->density_ratio > 1.0) || num->shields < 0.0)
            return app_config_fail(p, app_config_member(g, "density_ratio"),
                                   "density_ratio must be > 1 and shields >= 0");
        double scale = sqrt((num->density_ratio - 1.0) * gravity * d);
        fd->density = rho_p / num->density_ratio;
        fd->viscosity = d * scale / num->galileo;
        fd->shear_velocity = sqrt(num->shields) * scale;
    } else {
        if (!(in->has_rho && in->has_nu && in->has_us))
            return app_config_fail(p, g, "density, viscosity and shear_velocity go together");
        num->density_ratio = rho_p / fd->density;
        double scale = sqrt(fmax(num->density_ratio - 1.0, 0.0) * gravity * d);
        num->galileo = d * scale / fd->viscosity;
        num->shields =
            scale > 0.0 ? fd->shear_velocity * fd->shear_velocity / (scale * scale) : (double)NAN;
    }
    num->flux_scale = d * sqrt(fmax(num->density_ratio - 1.0, 0.0) * gravity * d);
    return 0;
}

/* The column's place in the scene: width, depth, gravity and time step; then sim's checks. */
static int complete_fluid(AppConfig *p, const config_setting_t *g, const Scene *scene,
                          const AppSedimentNumbers *num, SimFluidDef *fd)
{
    const SimWorldDef *def = &scene->def;
    fd->width = def->domain_x1 - def->domain_x0;
    fd->depth = fd->geometry == SIM_FLUID_SPHERE ? 2.0 * num->diameter / 3.0 : 1.0;
    fd->gravity_x = def->gravity_x;
    fd->gravity_y = def->gravity_y;
    SimTiming timing = sim_world_def_timing(def);
    fd->time_step =
        scene->stages[0].time_step > 0.0 ? scene->stages[0].time_step : timing.time_step;
    SimError e;
    if (sim_fluid_def_validate(fd, &e) != SIM_OK) {
        const char *key = strchr(e.field, '.') ? strchr(e.field, '.') + 1 : e.field;
        return app_config_fail(p, app_config_member(g, key) ? app_config_member(g, key) : g, "%s",
                               e.message);
    }
    return 0;
}

/* flow_stage = "name": the fluid acts from that stage on (default: from the start). */
static int parse_flow_stage(AppConfig *p, const config_setting_t *g, const Scene *scene,
                            SedimentInput *in)
{
    if (app_config_string(p, g, "flow_stage", &in->flow_stage) < 0)
        return -1;
    if (in->flow_stage && scene_stage_index(scene, in->flow_stage) < 0)
        return app_config_fail(p, app_config_member(g, "flow_stage"), "no stage named `%s`",
                               in->flow_stage);
    return 0;
}

/* start = "steady" (the steady profile above the bed, the default) | "rest". */
static int parse_start(AppConfig *p, const config_setting_t *g, int *steady)
{
    static const char *const starts[] = {"steady", "rest", NULL};
    int start = 0;
    if (app_config_choice(p, g, "start", starts, &start) < 0)
        return -1;
    *steady = start == 0;
    return 0;
}

/* The fluid and the state; the fluid's force becomes the scene's body force. */
static AppSediment *sediment_create(AppConfig *p, const config_setting_t *g, Scene *scene,
                                    const SimFluidDef *fd, const AppSedimentNumbers *num,
                                    const SedimentInput *in, int steady)
{
    SimError e;
    AppSediment *sed = calloc(1, sizeof *sed);
    if (!sed || !(sed->fluid = sim_fluid_create(fd, &e))) {
        free(sed);
        app_config_fail(p, g, "cannot create the fluid: out of memory");
        return NULL;
    }
    sed->numbers = *num;
    sed->width = fd->width;
    sed->shear_velocity = fd->shear_velocity;
    if (in->flow_stage)
        snprintf(sed->flow_stage, sizeof sed->flow_stage, "%s", in->flow_stage);
    sed->flowing = in->flow_stage == NULL;
    sed->steady_start = steady;
    sed->fluid_force = sim_fluid_body_force(sed->fluid);
    scene->def.body_force.apply = sediment_force;
    scene->def.body_force.context = sed;
    return sed;
}

AppSediment *app_sediment_parse(const config_setting_t *g, Scene *scene, char *err, size_t err_size)
{
    static const char *const keys[] = {
        "density_ratio", "galileo",      "shields", "density",    "viscosity", "shear_velocity",
        "diameter",      "y0",           "y1",      "cells",      "turbulent", "kappa",
        "van_driest",    "bed_fraction", "c_inf",   "reynolds_c", "buoyancy",  "geometry",
        "flow_stage",    "drag_limit",   "start",   NULL};
    if (err_size)
        err[0] = '\0';
    if (!g)
        return NULL;
    /* messages name the group as the scene gives it (`fluid` is its older name) */
    AppConfig p = {
        .path = scene->path, .err = err, .err_size = err_size, .group = config_setting_name(g)};
    if (app_config_keys(&p, g, NULL, keys, NULL) < 0)
        return NULL;
    if (!(scene->def.effects & SIM_EFFECT_PERIODIC_X)) {
        app_config_fail(&p, g,
                        "the fluid column is horizontally averaged: it needs effect periodic_x");
        return NULL;
    }
    SimFluidDef fd = sim_fluid_def_default();
    AppSedimentNumbers num = {0};
    SedimentInput in = {0};
    int steady = 1;
    if (parse_physical(&p, g, scene, &in, &num, &fd) < 0 || parse_column(&p, g, &in, &fd) < 0 ||
        parse_geometry(&p, g, &scene->def, &fd) < 0 ||
        derive_numbers(&p, g, scene, &in, &num, &fd) < 0 ||
        parse_flow_stage(&p, g, scene, &in) < 0 || complete_fluid(&p, g, scene, &num, &fd) < 0 ||
        parse_start(&p, g, &steady) < 0)
        return NULL;
    AppSediment *s = sediment_create(&p, g, scene, &fd, &num, &in, steady);
    if (s)
        snprintf(s->group, sizeof s->group, "%s", config_setting_name(g));
    if (s) { /* "u (m/s)", "y (m)" in SI; "u / sqrt(g d)", "y / d" normalised */
        scene_axis_label(scene, "u", SCENE_SPEED, s->u_label, sizeof s->u_label);
        scene_axis_label(scene, "y", SCENE_LENGTH, s->y_label, sizeof s->y_label);
    }
    return s;
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

const char *app_sediment_group(const AppSediment *s)
{
    return s->group;
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
        q += SIM_PI * frame->radius[i] * frame->radius[i] * frame->vx[i];
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

/* ---------------------------------------------------------------- the experiment */

static int sediment_parse(const config_setting_t *root, const config_setting_t *group, Scene *scene,
                          void **state, char *err, size_t err_size)
{
    (void)root;
    *state = NULL;
    if (!group)
        return 0;
    *state = app_sediment_parse(group, scene, err, err_size);
    return *state ? 0 : -1;
}

static void sediment_free(void *state)
{
    app_sediment_free(state);
}

static int sediment_begin(void *state, AppContext *c)
{
    return app_sediment_begin(state, c->out_dir, c->err, c->err_size);
}

static int sediment_stage_begin(void *state, AppContext *c)
{
    app_sediment_stage(state, c->scene, c->stage, c->world);
    return 0;
}

static void sediment_sample(void *state, AppContext *c)
{
    app_sediment_row(state, c->world);
}

static int sediment_stage_end(void *state, AppContext *c)
{
    return app_sediment_stage_end(state, c->world, c->out_dir, c->scene->stages[c->stage].name,
                                  c->err, c->err_size);
}

static int sediment_end(void *state, AppContext *c, int ok)
{
    return app_sediment_end(state, ok, c->err, c->err_size);
}

/* A checkpoint: the flow's start, the flux record, sediment.csv's length and the fluid column's
 * whole state (sim_fluid_get_state). */
static int sediment_checkpoint(const void *state, const AppContext *c, FILE *out)
{
    const AppSediment *s = state;
    const double v[3] = {s->flowing, s->flow_start, s->count};
    app_checkpoint_put(out, "sediment", v, 3);
    app_checkpoint_put(out, "sediment_t", s->t, s->count);
    app_checkpoint_put(out, "sediment_q", s->q, s->count);
    long n = sim_fluid_state_count(s->fluid);
    double *fluid = malloc((size_t)n * sizeof *fluid);
    if (!fluid) {
        snprintf(c->err, c->err_size, "out of memory");
        return -1;
    }
    sim_fluid_get_state(s->fluid, fluid);
    app_checkpoint_put(out, "fluid", fluid, n);
    free(fluid);
    app_checkpoint_file(out, s->csv_path, s->csv);
    return 0;
}

static int sediment_resume(void *state, AppContext *c, const char *record)
{
    AppSediment *s = state;
    double v[3];
    int bad = app_checkpoint_take(record, "sediment", v, 3) != 0 || !(v[2] >= 0.0) || v[2] > 1e9;
    while (!bad && s->capacity < (int)v[2])
        bad = app_series_grow(&s->t, &s->q, &s->capacity, 256) != 0;
    if (!bad) {
        s->flowing = (int)v[0];
        s->flow_start = v[1];
        s->count = (int)v[2];
        bad = s->count > 0 && (app_checkpoint_take(record, "sediment_t", s->t, s->count) != 0 ||
                               app_checkpoint_take(record, "sediment_q", s->q, s->count) != 0);
    }
    long n = sim_fluid_state_count(s->fluid);
    double *fluid = bad ? NULL : malloc((size_t)n * sizeof *fluid);
    bad = bad || !fluid || app_checkpoint_take(record, "fluid", fluid, n) != 0;
    if (!bad)
        sim_fluid_set_state(s->fluid, fluid);
    free(fluid);
    if (bad || app_checkpoint_reopen(record, s->csv_path, &s->csv) != 0) {
        snprintf(c->err, c->err_size,
                 "--resume: the sediment section of the checkpoint is malformed, or %s is "
                 "shorter than it records",
                 s->csv_path);
        return -1;
    }
    return 0;
}

/* Thesis 002 fig. 31 analogue: the fluid column's velocity and concentration profiles beside the
 * bed, on the bed view's heights. */
static int sediment_figure_extras(void *state, const SimFrame *frame, AppFigureExtras *extras)
{
    (void)frame;
    AppSediment *s = state;
    SimFluidProfile p;
    sim_fluid_profile(s->fluid, &p);
    s->side_series[0] = (AppPlotSeries){
        .label = "u(y)", .count = p.cells, .x = p.u, .y = p.y, .line = 1, .rgb = 0x1f77b4};
    s->side_series[1] = (AppPlotSeries){.label = "\\phi(y)",
                                        .count = p.cells,
                                        .x = p.solid_fraction,
                                        .y = p.y,
                                        .line = 1,
                                        .rgb = 0xd62728};
    s->side_panels[0] = (AppPlotPanel){.title = "fluid velocity",
                                       .x_label = s->u_label,
                                       .y_label = s->y_label,
                                       .legend = APP_LEGEND_NONE,
                                       .series_count = 1,
                                       .series = &s->side_series[0]};
    s->side_panels[1] = (AppPlotPanel){.title = "grain fraction",
                                       .x_label = "\\phi (1)",
                                       .y_label = s->y_label,
                                       .legend = APP_LEGEND_NONE,
                                       .x_max = 1.0,
                                       .series_count = 1,
                                       .series = &s->side_series[1]};
    extras->side_panels = s->side_panels;
    extras->side_panel_count = 2;
    return 1;
}

AppSediment *app_sediment_of(const Scene *scene)
{
    return scene_experiment_state(scene, &app_sediment_experiment);
}

static const char *const OUTPUTS[] = {"sediment.csv", "sediment.json", NULL};
const AppExperiment app_sediment_experiment = {
    .name = "sediment",
    .outputs = OUTPUTS,
    .group = "sediment",
    .group_alias = "fluid",
    .effects = SIM_EFFECT_FLUID_DRAG,
    .parse = sediment_parse,
    .free = sediment_free,
    .begin = sediment_begin,
    .stage_begin = sediment_stage_begin,
    .sample = sediment_sample,
    .stage_end = sediment_stage_end,
    .end = sediment_end,
    .checkpoint = sediment_checkpoint,
    .resume = sediment_resume,
    .figure_extras = sediment_figure_extras,
    .commands = app_sediment_commands,
    .command_count = 1,
};
