/* SPDX-License-Identifier: MIT */
/* discharge.c: thesis 004's open pile (docs/discharge.md). Deposition: a base of touching fixed
 * grains of 0.1 d, rows of grains released at rest from H every free-fall time over one d_max
 * (004 §3.1), relaxation to the static-equilibrium criteria of 004 §3.1. Discharge: the base
 * grains under the orifice are removed (004 §3.2), the pile runs to a new equilibrium, and the
 * grains that fell through the orifice (|x| < 4 d_max, the thesis code's rule) or over the edges
 * are counted by two sinks. Measures: h (004 §3.3), the arch (004 §2.5 with the one-sided fix,
 * sim_frame_find_arch) and the species composition (004 §3.4). The phases run on the stage runner
 * (app_run, bare): the family's hooks below rain the rows, test the equilibrium and open the
 * orifice. */
#include "discharge.h"

#include "base/config.h"
#include "base/experiments.h"
#include "base/util.h"
#include "run/run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- parsing */

/* The defaults of the `discharge` group (docs/scenes.md, `discharge`). */
static void discharge_defaults(AppDischargeDef *def, int species_count)
{
    memset(def, 0, sizeof *def);
    def->base_diameter = 0.1;
    def->thesis_gravity = 1;
    def->row_fill = 0.5;
    def->row_jitter = 0.95;
    def->stationary_rows = 10;
    def->stationary_gain = 0.1;
    def->dt_divisor = 50.0;
    def->tolerance = 1e-6;
    def->check_every = 500;
    def->polydispersity = 0.025;
    def->species_count = species_count;
    def->fractions[0] = 1.0;
    for (int k = 0; k < SIM_MAX_SPECIES; ++k)
        def->diameters[k] = 1.0;
}

/* The group's scalar keys, each within its own bounds. */
static int parse_numbers(AppConfig *p, const config_setting_t *g, AppDischargeDef *def)
{
    if (!config_setting_get_member(g, "base_length"))
        return app_config_fail(p, g, "`base_length` (L, in grain diameters) is required");
    if (app_config_number_min(p, g, "base_length", 2.0, &def->base_length) < 0 ||
        app_config_number_min(p, g, "base_diameter", 1e-3, &def->base_diameter) < 0 ||
        app_config_number_min(p, g, "release_height", 0.0, &def->release_height) < 0 ||
        app_config_number_min(p, g, "row_period", 0.0, &def->row_period) < 0 ||
        app_config_number_min(p, g, "row_fill", 1e-3, &def->row_fill) < 0 ||
        app_config_number_min(p, g, "row_jitter", 0.0, &def->row_jitter) < 0 ||
        app_config_int_in(p, g, "max_rows", 0, 1000000000L, &def->max_rows) < 0 ||
        app_config_int_in(p, g, "stationary_rows", 0, 1000000000L, &def->stationary_rows) < 0 ||
        app_config_number_min(p, g, "stationary_gain", 0.0, &def->stationary_gain) < 0 ||
        app_config_number_min(p, g, "dt_divisor", 0.0, &def->dt_divisor) < 0 ||
        app_config_number_min(p, g, "tolerance", 0.0, &def->tolerance) < 0 ||
        app_config_int_in(p, g, "check_every", 1, 1000000000L, &def->check_every) < 0 ||
        app_config_number_min(p, g, "relax_time", 0.0, &def->relax_time) < 0 ||
        app_config_number_min(p, g, "discharge_time", 0.0, &def->discharge_time) < 0 ||
        app_config_number_min(p, g, "polydispersity", 0.0, &def->polydispersity) < 0 ||
        app_config_int_in(p, g, "base_species", 0, 1000000000L, &def->base_species) < 0 ||
        app_config_number_min(p, g, "exit_half_width", 0.0, &def->exit_half_width) < 0)
        return -1;
    return 0;
}

/* The bounds that join two keys, or a key and the scene's species. */
static int check_numbers(AppConfig *p, const config_setting_t *g, const AppDischargeDef *def,
                         int species_count)
{
    if (def->base_length / def->base_diameter > APP_DISCHARGE_MAX_BASE_GRAINS)
        return app_config_fail(p, config_setting_get_member(g, "base_length"),
                               "`base_length` %g d makes a base of %.3g grains of base_diameter "
                               "%g d; at most 1e7",
                               def->base_length, def->base_length / def->base_diameter,
                               def->base_diameter);
    if (def->dt_divisor > 0.0 && def->dt_divisor < 1.0)
        return app_config_fail(p, config_setting_get_member(g, "dt_divisor"),
                               "`dt_divisor` must be >= 1, or 0 for the scene's time step (got %g)",
                               def->dt_divisor);
    if (def->row_fill > 1.0 || def->row_jitter > 1.0 || def->polydispersity >= 0.5) {
        const config_setting_t *s =
            config_setting_get_member(g, def->row_fill > 1.0     ? "row_fill"
                                         : def->row_jitter > 1.0 ? "row_jitter"
                                                                 : "polydispersity");
        return app_config_fail(p, s, "row_fill and row_jitter must be <= 1, polydispersity < 0.5");
    }
    if (def->base_species >= species_count)
        return app_config_fail(p, config_setting_get_member(g, "base_species"),
                               "`base_species` %d is not a species (0 to %d)", def->base_species,
                               species_count - 1);
    return 0;
}

/* `fractions` (normalised to sum 1), `diameters` and the orifice `widths`. */
static int parse_lists(AppConfig *p, const config_setting_t *g, AppDischargeDef *def,
                       int species_count)
{
    int n = 0;
    int got = app_config_array(p, g, "fractions", SIM_MAX_SPECIES, def->fractions, &n);
    if (got < 0)
        return -1;
    if (got > 0) {
        double sum = 0.0;
        for (int k = 0; k < n; ++k)
            sum += def->fractions[k];
        if (n > species_count || !(sum > 0.0))
            return app_config_fail(
                p, config_setting_get_member(g, "fractions"),
                "`fractions` needs one entry per species (%d) and a positive sum", species_count);
        for (int k = 0; k < n; ++k)
            def->fractions[k] /= sum;
    }
    got = app_config_array(p, g, "diameters", SIM_MAX_SPECIES, def->diameters, &n);
    if (got < 0)
        return -1;
    for (int k = 0; got > 0 && k < n; ++k)
        if (!(def->diameters[k] > 0.0) || n > species_count)
            return app_config_fail(p, config_setting_get_member(g, "diameters"),
                                   "`diameters` needs one positive entry per species (%d)",
                                   species_count);
    got = app_config_array(p, g, "widths", 64, def->widths, &def->width_count);
    if (got < 0)
        return -1;
    for (int k = 0; k < def->width_count; ++k)
        if (!app_discharge_width_fits(def, def->widths[k]))
            return app_config_fail(p, config_setting_get_member(g, "widths"),
                                   "orifice width %g d out of [1, base_length = %g] d",
                                   def->widths[k], def->base_length);
    return 0;
}

int app_discharge_parse(const config_setting_t *g, const char *scene_path, int species_count,
                        AppDischargeDef *def, char *err, size_t err_size)
{
    AppConfig p = {.path = scene_path, .err = err, .err_size = err_size, .group = "discharge"};
    static const char *const keys[] = {
        "base_length",      "base_diameter", "gravity",     "release_height",  "row_period",
        "row_fill",         "row_jitter",    "max_rows",    "stationary_rows", "stationary_gain",
        "dt_divisor",       "tolerance",     "check_every", "relax_time",      "discharge_time",
        "polydispersity",   "fractions",     "diameters",   "base_species",    "exit_half_width",
        "arch_force_check", "widths",        NULL};
    static const char *const gravities[] = {"thesis", "scene", NULL};
    discharge_defaults(def, species_count);
    if (app_config_keys(&p, g, NULL, keys, NULL) < 0 || parse_numbers(&p, g, def) < 0 ||
        check_numbers(&p, g, def, species_count) < 0)
        return -1;
    int gravity = 0;
    if (app_config_choice(&p, g, "gravity", gravities, &gravity) < 0 ||
        app_config_bool(&p, g, "arch_force_check", &def->arch_force_check) < 0)
        return -1;
    if (app_config_member(g, "gravity"))
        def->thesis_gravity = gravity == 0;
    return parse_lists(&p, g, def, species_count);
}

int app_discharge_width_fits(const AppDischargeDef *def, double w)
{
    return w >= 1.0 && w <= def->base_length;
}

/* ---------------------------------------------------------------- geometry */

void app_discharge_geometry(const Scene *scene, AppDischargeGeometry *geo)
{
    const AppDischargeDef *def = app_discharge_of(scene);
    const double L = def->base_length, p = def->polydispersity;
    memset(geo, 0, sizeof *geo);
    geo->d_min = INFINITY;
    geo->m_min = INFINITY;
    for (int k = 0; k < def->species_count; ++k) {
        if (!(def->fractions[k] > 0.0))
            continue;
        double d_lo = def->diameters[k] * (1.0 - p), d_hi = def->diameters[k] * (1.0 + p);
        geo->d_max = fmax(geo->d_max, d_hi);
        geo->d_min = fmin(geo->d_min, d_lo);
        geo->d_mean += def->fractions[k] * def->diameters[k];
        double rho = scene->def.materials[k].density, r = 0.5 * d_lo;
        double m = sim_grain_mass(scene->def.mass_model, rho, r);
        geo->m_min = fmin(geo->m_min, m);
    }
    /* g = 2/(L(L+1)) in the thesis code's length unit L/2 is 1/(L+1) in diameters: the
     * stiffness ratio k_n d/(m g) = 1000 (L+1) of the thesis (notes §1.10) is kept. */
    geo->g =
        def->thesis_gravity ? 1.0 / (L + 1.0) : hypot(scene->def.gravity_x, scene->def.gravity_y);
    double k_n = scene->def.materials[0].normal_stiffness;
    for (int k = 1; k < scene->def.species_count; ++k)
        k_n = fmax(k_n, scene->def.materials[k].normal_stiffness);
    /* the thesis code's dt (notes §1.8), or with dt_divisor = 0 the scene's own */
    geo->dt = def->dt_divisor > 0.0 ? sqrt(geo->m_min / k_n) / def->dt_divisor
                                    : app_discharge_timing(scene).time_step;
    geo->row_period = def->row_period > 0.0 ? def->row_period : sqrt(2.0 * geo->d_max / geo->g);
    geo->height = def->release_height > 0.0 ? def->release_height : L;
    geo->row_size = (int)fmax(1.0, floor(def->row_fill * L / geo->d_mean + 0.5));
    geo->max_rows = def->max_rows > 0 ? def->max_rows : (int)ceil(1.5 * (L + 1.0));
    if (geo->max_rows > 1024)
        geo->max_rows = 1024;
    /* Caps: many times the free-fall time over the pile and the fall from H. */
    double fall = sqrt(2.0 * geo->height / geo->g);
    geo->relax_time = def->relax_time > 0.0 ? def->relax_time : 20.0 * fall;
    geo->discharge_time = def->discharge_time > 0.0 ? def->discharge_time : 20.0 * fall;
    geo->exit_half_width = def->exit_half_width > 0.0 ? def->exit_half_width : 4.0 * geo->d_max;
}

/* The timing of the protocol's world with the scene's time step (time.dt, or
 * time.steps_per_contact when time.dt = 0): its grains are not in the scene, so the lightest grain
 * of every species the rows draw (radius d (1 - p) / 2) and a base grain stand for them. */
static SimTiming protocol_timing(const AppDischargeDef *def, const Scene *scene)
{
    double radius[SIM_MAX_SPECIES + 1], zero[SIM_MAX_SPECIES + 1] = {0};
    int species[SIM_MAX_SPECIES + 1];
    unsigned flags[SIM_MAX_SPECIES + 1] = {0};
    int n = 0;
    for (int k = 0; k < def->species_count; ++k)
        if (def->fractions[k] > 0.0) {
            radius[n] = 0.5 * def->diameters[k] * (1.0 - def->polydispersity);
            species[n++] = k;
        }
    radius[n] = 0.5 * def->base_diameter;
    species[n] = def->base_species;
    flags[n++] = SIM_GRAIN_FIXED;
    SimWorldDef world = scene_world_def(scene, 0);
    world.grains = (SimGrainSet){
        .count = n, .x = zero, .y = zero, .radius = radius, .species = species, .flags = flags};
    world.wall_count = 0;
    return sim_world_def_timing(&world);
}

SimTiming app_discharge_timing(const Scene *scene)
{
    return protocol_timing(app_discharge_of(scene), scene);
}

/* dt_divisor = 0: the scene's time step, held to the protocol world's stability limit; checked
 * here, at parse, so that every caller of scene_load (`discharge`, `study`, the ensemble's
 * levels) refuses such a scene with dt_divisor's line. */
static int check_scene_time_step(const config_setting_t *group, const Scene *scene,
                                 const AppDischargeDef *def, char *err, size_t err_size)
{
    if (def->dt_divisor > 0.0)
        return 0;
    SimTiming t = protocol_timing(def, scene);
    if (t.time_step > 0.0 && t.time_step <= t.stability_limit)
        return 0;
    AppConfig p = {.path = scene->path, .err = err, .err_size = err_size, .group = "discharge"};
    return app_config_fail(&p, config_setting_get_member(group, "dt_divisor"),
                           "`dt_divisor` = 0 takes the scene's time step, %g s, which is not in "
                           "(0, %g s], the stability limit of the protocol's stiffest pair",
                           t.time_step, t.stability_limit);
}

static SimTiming discharge_member_timing(const void *state, const Scene *scene)
{
    (void)state;
    AppDischargeGeometry geo;
    app_discharge_geometry(scene, &geo);
    SimTiming t = app_discharge_timing(scene);
    t.time_step = geo.dt;
    t.steps_per_contact = t.contact_time_min / geo.dt;
    return t;
}

/* ---------------------------------------------------------------- measures */

int app_discharge_open_orifice(SimWorld *world, double width, double center_x)
{
    SimFrame frame;
    sim_world_frame(world, &frame);
    int n = 0;
    uint32_t *ids = malloc((size_t)(frame.count + 1) * sizeof *ids);
    if (!ids)
        abort();
    for (int i = frame.mobile_count; i < frame.count; ++i)
        if ((frame.flags[i] & SIM_GRAIN_FIXED) && fabs(frame.x[i] - center_x) < 0.5 * width)
            ids[n++] = frame.id[i];
    int removed = n ? sim_world_remove_ids(world, ids, n) : 0;
    free(ids);
    return removed;
}

double app_discharge_central_height(const SimFrame *frame, double center_x, double half_width)
{
    double h = 0.0;
    for (int i = 0; i < frame->mobile_count; ++i)
        if (fabs(frame->x[i] - center_x) < half_width && frame->y[i] > h)
            h = frame->y[i];
    return h;
}

void app_discharge_measure(SimWorld *world, const AppDischargeDef *def, AppDischarge *out)
{
    SimFrame frame;
    sim_world_frame(world, &frame);
    out->through = sim_world_removed_count(world, 0);
    out->edges = sim_world_removed_count(world, 1);
    out->pile = frame.mobile_count;
    memset(out->pile_species, 0, sizeof out->pile_species);
    memset(out->arch_species, 0, sizeof out->arch_species);
    double d_sum = 0.0;
    for (int i = 0; i < frame.mobile_count; ++i) {
        if (frame.species[i] >= 0 && frame.species[i] < SIM_MAX_SPECIES)
            ++out->pile_species[frame.species[i]];
        d_sum += 2.0 * frame.radius[i];
    }
    double d_mean = frame.mobile_count ? d_sum / frame.mobile_count : 1.0;
    out->height = app_discharge_central_height(&frame, 0.0, 0.5 * d_mean);
    int members[APP_DISCHARGE_ARCH_MAX];
    out->arch =
        sim_frame_find_arch(&frame, 0.0, def->arch_force_check, members, APP_DISCHARGE_ARCH_MAX);
    for (int k = 0; k < out->arch; ++k) {
        int i = members[k];
        out->arch_ids[k] = frame.id[i];
        if (frame.species[i] >= 0 && frame.species[i] < SIM_MAX_SPECIES)
            ++out->arch_species[frame.species[i]];
    }
}

void app_discharge_arch_marks(const SimFrame *frame, const AppDischarge *result, int *marks)
{
    for (int i = 0; i < frame->count; ++i) {
        marks[i] = -1;
        for (int k = 0; k < result->arch; ++k)
            if (frame->id[i] == result->arch_ids[k]) {
                marks[i] = 0;
                break;
            }
    }
}

const char *app_discharge_csv_header(void)
{
    return "sample,L,w,s,edges,h,pile,arch,arch_sp0,arch_sp1,pile_sp0,pile_sp1,equilibrium,"
           "settled_before,time,steps,wall_seconds";
}

void app_discharge_csv_row(const AppDischarge *r, long sample, double base_length, char *out,
                           size_t size)
{
    snprintf(out, size, "%ld,%.10g,%.10g,%ld,%ld,%.10g,%d,%d,%d,%d,%d,%d,%d,%d,%.10g,%ld,%.4g",
             sample, base_length, r->width, r->through, r->edges, r->height, r->pile, r->arch,
             r->arch_species[0], r->arch_species[1], r->pile_species[0], r->pile_species[1],
             r->equilibrium, r->settled_before, r->time, r->steps, r->wall_seconds);
}

/* ---------------------------------------------------------------- the protocol on the runner */

/* The protocol on the stage runner (app_run, bare). Each phase is a
 * copy of the scene whose stages are its steps: the deposition is one stage (a row released every
 * T_dep onto the base, 004 §3.1, then relaxation to the static-equilibrium criteria of 004 §3.1);
 * a discharge is two (the pile loaded with its contacts and relaxed; then the orifice opened,
 * 004 §3.2, and the pile run to a new equilibrium). The family's hooks rain the rows (step), test
 * the equilibrium at the steps the protocol tests it on (next_step, stage_done), open the orifice
 * (stage_edit) and feed the movie's frames. Where the runner splits the steps into chunks does not
 * change the bits.
 *
 * The family's state in a scene: its settings, and, in the copy a phase runs, the phase. A loaded
 * scene has none (`sablier run` of a discharge scene runs its stages as any scene's: every hook
 * does nothing there). */
struct DischargePhase;

typedef struct DischargeState {
    AppDischargeDef def;
    struct DischargePhase *phase; /* NULL: no protocol phase (a scene as loaded) */
} DischargeState;

/* A phase under way: what its hooks read and write. */
typedef struct DischargePhase {
    const AppDischargeDef *def;
    AppDischargeGeometry geo;
    const AppDischargeFrames *frames; /* NULL: no frames */
    int frames_on;                    /* 1: the current stage feeds frames */
    long frame_last;                  /* the world's step count at the last frame */
    /* deposition (dep != NULL) */
    AppDischargeDeposit *dep;
    FILE *trace;
    SimRng rng;
    int raining;
    long row_steps, next_row;
    /* relaxation: tested every check_every steps from relax_from, capped at relax_steps */
    int relaxing, equilibrium;
    long relax_from, relax_steps;
    /* discharge (result != NULL) */
    AppDischarge *result;
    long before[2], steps0;
    double t0;
    char message[512]; /* a hook's failure ("" when none) */
} DischargePhase;

static DischargePhase *phase_of(const void *state)
{
    return ((const DischargeState *)state)->phase;
}

/* ---------------------------------------------------------------- the protocol's world */

/* The protocol's gravity, time step and sinks on a stage's definition. The skin is the scene's
 * (automatic by default: its range follows the rows as they are added, a still pile lists few
 * pairs, a discharging one gets a larger skin). */
static void discharge_adjust_def(const void *state, int stage, SimWorldDef *def)
{
    (void)stage;
    const DischargePhase *p = phase_of(state);
    if (!p)
        return;
    def->gravity_x = 0.0;
    def->gravity_y = -p->geo.g;
    def->time_step = p->geo.dt;
    def->max_dt_fraction = 0.0;
    def->effects |= SIM_EFFECT_REMOVAL;
    def->length_scale = p->geo.d_mean;
    /* Sinks are tested in order, first match wins: the orifice column first, then the edges. */
    def->sink_count = 2;
    def->sinks[0] = (SimSink){.shape = SIM_SINK_RECT,
                              .x0 = -p->geo.exit_half_width,
                              .y0 = -1e9,
                              .x1 = p->geo.exit_half_width,
                              .y1 = -1e-12};
    def->sinks[1] = (SimSink){.shape = SIM_SINK_BELOW, .level = 0.0};
}

/* ---------------------------------------------------------------- rows */

/* Contacts per mobile grain from a frame; returns the grains with at least one. */
static int pile_population(SimWorld *world)
{
    SimFrame frame;
    sim_world_frame(world, &frame);
    unsigned char *touch = calloc((size_t)frame.mobile_count + 1, 1);
    if (!touch)
        abort();
    for (int c = 0; c < frame.contact_count; ++c) {
        const SimContact *k = &frame.contacts[c];
        if (k->i >= 0 && k->i < frame.mobile_count)
            touch[k->i] = 1;
        if (k->j >= 0 && k->j < frame.mobile_count)
            touch[k->j] = 1;
    }
    int n = 0;
    for (int i = 0; i < frame.mobile_count; ++i)
        n += touch[i];
    free(touch);
    return n;
}

static int draw_species(const AppDischargeDef *def, SimRng *rng)
{
    double u = sim_rng_uniform(rng), acc = 0.0;
    int last = 0;
    for (int k = 0; k < def->species_count; ++k) {
        if (!(def->fractions[k] > 0.0))
            continue;
        last = k;
        acc += def->fractions[k];
        if (u < acc)
            return k;
    }
    return last;
}

/* One row at rest at height H: equal slots over the base, each grain jittered within its slot by
 * at most row_jitter x (half slot - r_max), so no two grains of a row can overlap (the listing's
 * jitter could: notes §2.7). 0, or -1 with the message. */
static int rain_row(DischargePhase *p, SimWorld *world)
{
    const AppDischargeDef *def = p->def;
    SimGrainBuffer row;
    sim_grain_buffer_init(&row);
    const double L = def->base_length, slot = L / p->geo.row_size;
    const double room = fmax(0.0, 0.5 * slot - 0.5 * p->geo.d_max) * def->row_jitter;
    for (int k = 0; k < p->geo.row_size; ++k) {
        int species = draw_species(def, &p->rng);
        double r = 0.5 * def->diameters[species] *
                   (1.0 + def->polydispersity * (2.0 * sim_rng_uniform(&p->rng) - 1.0));
        double x = -0.5 * L + (k + 0.5) * slot + room * (2.0 * sim_rng_uniform(&p->rng) - 1.0);
        sim_grain_buffer_add(&row, x, p->geo.height, r, species, 0u, -1);
    }
    SimGrainSet set = sim_grain_buffer_view(&row);
    set.id = NULL; /* fresh ids above every id in use */
    SimError error;
    SimStatus s = sim_world_add_grains(world, &set, &error);
    sim_grain_buffer_free(&row);
    if (s != SIM_OK) {
        snprintf(p->message, sizeof p->message, "cannot release a row: %s: %s", error.field,
                 error.message);
        return -1;
    }
    p->dep->released += p->geo.row_size;
    p->dep->rows += 1;
    return 0;
}

/* The pile after row `row` (its population, the trace's line): 1 when construction ends there,
 * the population being stationary (004 fig. 2.8). */
static int row_ended(DischargePhase *p, SimWorld *world, int row)
{
    AppDischargeDeposit *out = p->dep;
    const int window = p->def->stationary_rows;
    int pile = pile_population(world);
    if (row < (int)(sizeof out->pile_count / sizeof out->pile_count[0])) {
        out->pile_count[row] = pile;
        out->pile_count_rows = row + 1;
    }
    if (p->trace)
        fprintf(p->trace, "%.9g,%d,%d,%d,%d\n", sim_world_time(world), row + 1, out->released, pile,
                sim_world_mobile_count(world));
    return window > 0 && row >= window && row < out->pile_count_rows &&
           out->pile_count[row] - out->pile_count[row - window] <
               p->def->stationary_gain * window * p->geo.row_size;
}

/* ---------------------------------------------------------------- relaxation */

/* A relaxation from step `from` of the stage, capped at `cap` simulation time. */
static void relax_start(DischargePhase *p, SimWorld *world, long from, double cap)
{
    p->relaxing = 1;
    p->equilibrium = 0;
    p->relax_from = from;
    p->relax_steps = (long)ceil(cap / sim_world_time_step(world));
}

/* The frame of the movie due at the world's step count, once. */
static void phase_frame(DischargePhase *p, SimWorld *world, int now)
{
    long n = sim_world_step_count(world);
    if (!p->frames || !p->frames->sink.consume ||
        (!now && (!p->frames_on || n == p->frame_last || n % p->frames->every != 0)))
        return;
    SimFrame frame;
    sim_world_frame(world, &frame);
    p->frames->sink.consume(p->frames->sink.context, &frame);
    p->frame_last = n;
}

static long discharge_next_step(const void *state, const AppContext *c, long done, long next)
{
    const DischargePhase *p = phase_of(state);
    if (!p)
        return next;
    if (p->raining && p->next_row > done && p->next_row < next)
        next = p->next_row;
    if (p->relaxing) {
        long k = done - p->relax_from, every = p->def->check_every;
        long check = p->relax_from + (k / every + 1) * every;
        if (check > p->relax_from + p->relax_steps)
            check = p->relax_from + p->relax_steps;
        if (check > done && check < next)
            next = check;
    }
    if (p->frames_on) {
        long every = p->frames->every;
        long frame = done + (every - sim_world_step_count(c->world) % every);
        if (frame < next)
            next = frame;
    }
    return next;
}

static void discharge_step(void *state, AppContext *c, long done)
{
    DischargePhase *p = phase_of(state);
    if (!p)
        return;
    phase_frame(p, c->world, 0);
    if (!p->raining || done != p->next_row || p->message[0])
        return;
    int rows = p->dep->rows;
    int ended = rows > 0 && row_ended(p, c->world, rows - 1); /* the row before this step */
    if (ended || rows >= p->geo.max_rows) {
        p->raining = 0; /* then relaxation, the fall from H included in its cap */
        relax_start(p, c->world, done, p->geo.relax_time + sqrt(2.0 * p->geo.height / p->geo.g));
        return;
    }
    if (rain_row(p, c->world) == 0)
        p->next_row = done + p->row_steps;
}

/* 1 at static equilibrium (or an empty pile) or at the cap, tested where the protocol tests it:
 * every check_every steps of the relaxation and at its cap (004 §3.1). */
static int discharge_stage_done(void *state, AppContext *c, long done)
{
    DischargePhase *p = phase_of(state);
    if (!p)
        return 0;
    if (p->message[0]) {
        snprintf(c->err, c->err_size, "%s", p->message);
        return -1;
    }
    long k = done - p->relax_from;
    if (!p->relaxing || (k % p->def->check_every != 0 && k != p->relax_steps))
        return 0;
    if (sim_world_mobile_count(c->world) == 0 ||
        sim_world_equilibrium(c->world, p->def->tolerance).equilibrium) {
        p->equilibrium = 1;
        return 1;
    }
    return k >= p->relax_steps;
}

/* ---------------------------------------------------------------- stages */

/* The discharge's second stage: the frame before, the sinks' counts, the orifice opened. */
static int discharge_stage_edit(void *state, AppContext *c)
{
    DischargePhase *p = phase_of(state);
    if (!p || !p->result || c->stage != 1)
        return 0;
    phase_frame(p, c->world, 1);
    p->t0 = sim_world_time(c->world);
    p->before[0] = sim_world_removed_count(c->world, 0);
    p->before[1] = sim_world_removed_count(c->world, 1);
    p->result->opened = app_discharge_open_orifice(c->world, p->result->width, 0.0);
    c->removed += p->result->opened;
    return 0;
}

static int discharge_stage_begin(void *state, AppContext *c)
{
    DischargePhase *p = phase_of(state);
    if (!p)
        return 0;
    p->frame_last = sim_world_step_count(c->world);
    p->frames_on = p->frames && p->frames->sink.consume && p->frames->every > 0;
    if (p->dep) { /* the deposition: rows from step 0 */
        p->raining = 1;
        p->next_row = 0;
        return 0;
    }
    if (c->stage == 0) {
        /* The springs come back from the checkpoint, so a pile saved at equilibrium opens at once
         * (004 §2.4). A pile whose deposition reached the relaxation cap (rattlers, undamped
         * rolling modes) gets one more free-fall time with the base intact, not another full
         * cap: repeating the cap at every width doubled the cost of a study without settling
         * such piles. No frames here. */
        p->frames_on = 0;
        p->steps0 = sim_world_step_count(c->world);
        relax_start(p, c->world, 0, sqrt(2.0 * p->geo.height / p->geo.g));
    } else {
        relax_start(p, c->world, 0, p->geo.discharge_time);
    }
    return 0;
}

static int discharge_stage_end(void *state, AppContext *c)
{
    DischargePhase *p = phase_of(state);
    if (!p)
        return 0;
    if (p->dep)
        p->dep->equilibrium = p->equilibrium;
    else if (c->stage == 0)
        p->result->settled_before = p->equilibrium;
    else
        p->result->equilibrium = p->equilibrium;
    return 0;
}

/* A scene's run keeps nothing of the protocol between steps: nothing to restore. */
static int discharge_resume(void *state, AppContext *c, const char *record)
{
    (void)state;
    (void)c;
    (void)record;
    return 0;
}

/* ---------------------------------------------------------------- phases */

/* Runs `stages` stages of a copy of `scene` with the phase `p` in its discharge state: the first
 * stage from `grains` (a new world) or from the state file `load` (contacts restored), the next
 * ones in memory; each capped by `caps[k]` steps (the hooks end them). The world at the end, or
 * NULL with a message. */
static SimWorld *run_phase(const Scene *scene, DischargePhase *p, const SimGrainBuffer *grains,
                           const char *load, const long *caps, int stages, char *err,
                           size_t err_size)
{
    Scene *copy = malloc(sizeof *copy);
    if (!copy) {
        snprintf(err, err_size, "out of memory");
        return NULL;
    }
    *copy = *scene;
    DischargeState state = {.def = *p->def, .phase = p};
    memset(copy->experiments, 0, sizeof copy->experiments); /* no other family, no measures */
    copy->experiments[app_experiment_index(&app_discharge_experiment)] = &state;
    copy->source_count = 0;
    copy->sources = NULL;
    if (grains)
        copy->grains = *grains;
    SceneOutput *out = &copy->output;
    out->figure_count = 0;
    out->trace_count = 0;
    out->checkpoint_every = 0.0;
    out->checkpoint_minutes = 0.0;
    out->energy_every = 1e300; /* no energy rows between the phase's own stops */
    memset(out->dump, 0, sizeof out->dump);
    SceneStage stage = scene->stages[0];
    stage.time_step = p->geo.dt;
    stage.gravity_x = 0.0;
    stage.gravity_y = -p->geo.g;
    stage.effects |= SIM_EFFECT_REMOVAL;
    stage.settle_kinetic = stage.settle_per_grain = 0.0;
    stage.remove_count = stage.add_count = stage.movie = stage.skip = 0;
    stage.remove_ids = NULL;
    stage.adds = NULL;
    stage.motions = stage.restart_motions = 0;
    stage.declares_motions = 0;
    copy->stage_count = stages;
    for (int k = 0; k < stages; ++k) {
        copy->stages[k] = stage;
        snprintf(copy->stages[k].name, sizeof copy->stages[k].name, "%s",
                 p->dep   ? "deposition"
                 : k == 0 ? "settle"
                          : "discharge");
        copy->stages[k].load = k > 0  ? SCENE_LOAD_PREVIOUS
                               : load ? SCENE_LOAD_FILE
                                      : SCENE_LOAD_SCENE;
        copy->stages[k].duration = (double)caps[k] * p->geo.dt;
    }
    if (load)
        snprintf(copy->stages[0].load_path, sizeof copy->stages[0].load_path, "%s", load);
    SimWorld *world = NULL;
    AppRunOptions options = app_run_options_default();
    options.bare = 1;
    options.quiet = 1;
    options.err = err;
    options.err_size = err_size;
    options.world = &world;
    app_run(copy, &options);
    free(copy);
    return world;
}

SimWorld *app_discharge_deposit(const Scene *scene, uint64_t seed, const AppDischargeFrames *frames,
                                FILE *trace, AppDischargeDeposit *out, char *err, size_t err_size)
{
    const AppDischargeDef *def = app_discharge_of(scene);
    memset(out, 0, sizeof *out);
    if (!def) {
        snprintf(err, err_size, "%s: the scene has no `discharge` group", scene->path);
        return NULL;
    }
    double wall0 = sim_clock_seconds(SIM_CLOCK_WALL);
    DischargePhase p = {.def = def, .frames = frames, .dep = out, .trace = trace};
    app_discharge_geometry(scene, &p.geo);
    sim_rng_seed(&p.rng, seed);
    p.row_steps = (long)fmax(1.0, floor(p.geo.row_period / p.geo.dt + 0.5));
    /* The base: touching fixed grains; the rows come during the stage. */
    SimGrainBuffer base;
    sim_grain_buffer_init(&base);
    const double L = def->base_length, rb = 0.5 * def->base_diameter;
    int n_base = (int)floor(L / def->base_diameter + 0.5);
    for (int k = 0; k < n_base; ++k)
        sim_grain_buffer_add(&base, -0.5 * L + rb + def->base_diameter * k, 0.0, rb,
                             def->base_species, SIM_GRAIN_FIXED, -1);
    const double fall = sqrt(2.0 * p.geo.height / p.geo.g);
    long cap =
        (long)p.geo.max_rows * p.row_steps + (long)ceil((p.geo.relax_time + fall) / p.geo.dt) + 2;
    SimWorld *world = run_phase(scene, &p, &base, NULL, &cap, 1, err, err_size);
    sim_grain_buffer_free(&base);
    if (!world)
        return NULL;
    out->steps = sim_world_step_count(world);
    out->pile = sim_world_mobile_count(world);
    out->lost = sim_world_removed_count(world, 0) + sim_world_removed_count(world, 1);
    out->time = sim_world_time(world);
    SimFrame frame;
    sim_world_frame(world, &frame);
    out->height = app_discharge_central_height(&frame, 0.0, 0.5 * p.geo.d_mean);
    out->wall_seconds = sim_clock_seconds(SIM_CLOCK_WALL) - wall0;
    return world;
}

SimWorld *app_discharge(const Scene *scene, const char *pile_path, double width,
                        const AppDischargeFrames *frames, AppDischarge *out, char *err,
                        size_t err_size)
{
    const AppDischargeDef *def = app_discharge_of(scene);
    memset(out, 0, sizeof *out);
    out->width = width;
    if (!def) {
        snprintf(err, err_size, "%s: the scene has no `discharge` group", scene->path);
        return NULL;
    }
    double wall0 = sim_clock_seconds(SIM_CLOCK_WALL);
    DischargePhase p = {.def = def, .frames = frames, .result = out};
    app_discharge_geometry(scene, &p.geo);
    const double fall = sqrt(2.0 * p.geo.height / p.geo.g);
    long caps[2] = {(long)ceil(fall / p.geo.dt) + 2,
                    (long)ceil(p.geo.discharge_time / p.geo.dt) + 2};
    SimWorld *world = run_phase(scene, &p, NULL, pile_path, caps, 2, err, err_size);
    if (!world)
        return NULL;
    app_discharge_measure(world, def, out);
    out->through -= p.before[0];
    out->edges -= p.before[1];
    out->time = sim_world_time(world) - p.t0;
    out->steps = sim_world_step_count(world) - p.steps0;
    out->wall_seconds = sim_clock_seconds(SIM_CLOCK_WALL) - wall0;
    return world;
}

/* ---------------------------------------------------------------- the experiment */

static int discharge_parse(const config_setting_t *root, const config_setting_t *group,
                           Scene *scene, void **state, char *err, size_t err_size)
{
    (void)root;
    *state = NULL;
    if (!group)
        return 0;
    DischargeState *s = calloc(1, sizeof *s); /* no phase: a scene as loaded */
    if (!s) {
        snprintf(err, err_size, "%s: out of memory", scene->path);
        return -1;
    }
    if (app_discharge_parse(group, scene->path, scene->def.species_count, &s->def, err, err_size) !=
            0 ||
        check_scene_time_step(group, scene, &s->def, err, err_size) != 0) {
        free(s);
        return -1;
    }
    *state = s;
    return 0;
}

static void discharge_free(void *state)
{
    free(state);
}

const AppDischargeDef *app_discharge_of(const Scene *scene)
{
    const DischargeState *s = scene_experiment_state(scene, &app_discharge_experiment);
    return s ? &s->def : NULL;
}

/* A member of `sablier ensemble` is one `sablier discharge` (every width of the scene's list)
 * with the time step the ensemble sets (time.dt or time.steps_per_contact). */
static const char *const discharge_member_sets[] = {"discharge.dt_divisor=0", NULL};
static const AppMember discharge_member = {
    .command = "discharge", .sets = discharge_member_sets, .timing = discharge_member_timing};

/* The commands `discharge` and `study` (command.c, study.c) run the protocol's phases on the
 * stage runner, each a copy of the scene whose stages are its steps (run_phase); the hooks act
 * in those copies only: `sablier run` of a discharge scene runs its stages as any scene's. */
const AppExperiment app_discharge_experiment = {
    .name = "discharge",
    .group = "discharge",
    .grains_from_run = 1, /* rows rained during the protocol onto a fixed base */
    .parse = discharge_parse,
    .free = discharge_free,
    .adjust_def = discharge_adjust_def,
    .stage_edit = discharge_stage_edit,
    .stage_begin = discharge_stage_begin,
    .next_step = discharge_next_step,
    .step = discharge_step,
    .stage_done = discharge_stage_done,
    .stage_end = discharge_stage_end,
    .resume = discharge_resume,
    .commands = app_discharge_commands,
    .command_count = 2,
    .member = &discharge_member,
};
