/* SPDX-License-Identifier: MIT */
/* world.c: definitions, validation, the step pipeline and the run guard.
 *
 * How to add an effect:
 *   1. an effect bit and a params struct (or SimMaterial fields) in sim.h;
 *   2. a stage function in its own file (or a bit of the contact key in contact.c when it changes
 *      the per-contact arithmetic);
 *   3. its call in sim_world_forces_at() below, behind a test of its effect bit (the contact pass,
 *      the wall pass and the integrator are instead chosen once in sim_world_create(), from the
 *      contact key and the integrator: function pointers in the world);
 *   4. the scene keys in the scene loader, gated by loader_gate (app/scene/scene_keys.c);
 *   5. a validation scene and a test.
 */
#include "internal.h"
#include "walls.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const struct {
    unsigned bit;
    const char *name;
} effect_names[] = {
    {SIM_EFFECT_FRICTION, "friction"},     {SIM_EFFECT_ROLLING, "rolling_resistance"},
    {SIM_EFFECT_PERIODIC_X, "periodic_x"}, {SIM_EFFECT_VIBRATION, "vibration"},
    {SIM_EFFECT_FLUID_DRAG, "fluid_drag"}, {SIM_EFFECT_REMOVAL, "removal"},
};

unsigned sim_effect_from_name(const char *name)
{
    for (size_t k = 0; k < sizeof effect_names / sizeof effect_names[0]; ++k)
        if (strcmp(name, effect_names[k].name) == 0)
            return effect_names[k].bit;
    return 0;
}

const char *sim_effect_name(unsigned effect)
{
    for (size_t k = 0; k < sizeof effect_names / sizeof effect_names[0]; ++k)
        if (effect == effect_names[k].bit)
            return effect_names[k].name;
    return NULL;
}

static const char *const integrator_names[SIM_INTEGRATOR_COUNT] = {
    "velocity_verlet", "symplectic_euler", "stormer_verlet", "gear", "rk4"};

int sim_integrator_from_name(const char *name)
{
    for (int k = 0; k < SIM_INTEGRATOR_COUNT; ++k)
        if (strcmp(name, integrator_names[k]) == 0)
            return k;
    return -1;
}

const char *sim_integrator_name(SimIntegrator integrator)
{
    return (int)integrator >= 0 && integrator < SIM_INTEGRATOR_COUNT ? integrator_names[integrator]
                                                                     : "unknown";
}

SimMaterial sim_material_default(void)
{
    return (SimMaterial){
        .density = 1190.0,
        .normal_stiffness = 7e5,
        .damping_mode = SIM_DAMPING_GAMMA,
        .normal_damping = 1.5e3,
        .restitution = 0.5,
        .critical_fraction = 0.95,
        .friction = 0.5,
        .tangential_damping = 5.0,
        .tangential_stiffness = 5.25e5,
        .rolling_friction = 0.0,
        .rolling_stiffness = 0.0,
        .spring_damping = 0.0,
    };
}

SimWorldDef sim_world_def_default(void)
{
    SimWorldDef def;
    memset(&def, 0, sizeof def);
    def.effects = 0;
    def.contact = (SimContactModel){SIM_NORMAL_LINEAR, SIM_TANGENTIAL_REGULARISED, SIM_ROLLING_OFF,
                                    1, SIM_ONSET_STEP};
    def.mass_model = SIM_MASS_DISK;
    def.species_count = 1;
    for (int s = 0; s < SIM_MAX_SPECIES; ++s)
        def.materials[s] = sim_material_default();
    def.gravity_x = 0.0;
    def.gravity_y = -9.806;
    def.integrator = SIM_INTEGRATOR_VELOCITY_VERLET;
    def.time_step = 0.0;
    def.steps_per_contact = 50.0;
    def.max_dt_fraction = 0.0;
    def.skin = 0.0;
    def.guard_max_overlap = 0.5;
    def.guard_max_speed = 0.0;
    def.guard_every = 100;
    def.max_initial_overlap = 0.1;
    def.length_scale = 0.0;
    return def;
}

/* ------------------------------------------------------------------ errors */

SimStatus sim_fail(SimError *error, SimStatus status, const char *field, const char *fmt, ...)
{
    if (!error)
        return status;
    error->status = status;
    snprintf(error->field, sizeof error->field, "%s", field ? field : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(error->message, sizeof error->message, fmt, ap);
    va_end(ap);
    error->step = -1;
    error->grain = -1;
    return status;
}

/* ------------------------------------------------------------------ pairs (masses: grains.c) */

/* Harmonic mean 2ab/(a+b): zero when either is zero, so a frictionless species (a smooth wall)
 * makes frictionless contacts with any grain; equal values are unchanged. */
static double harmonic(double a, double b)
{
    return a + b > 0.0 ? 2.0 * a * b / (a + b) : 0.0;
}

static void fill_pairs(PairParams *pairs, const SimWorldDef *def)
{
    for (int a = 0; a < SIM_MAX_SPECIES; ++a)
        for (int b = 0; b < SIM_MAX_SPECIES; ++b) {
            const SimMaterial *p = &def->materials[a], *q = &def->materials[b];
            pairs[a * SIM_MAX_SPECIES + b] = (PairParams){
                .k_n = 0.5 * (p->normal_stiffness + q->normal_stiffness),
                .mu = harmonic(p->friction, q->friction),
                .gamma_s = 0.5 * (p->tangential_damping + q->tangential_damping),
                .k_t = 0.5 * (p->tangential_stiffness + q->tangential_stiffness),
                .mu_r = harmonic(p->rolling_friction, q->rolling_friction),
                .k_r = 0.5 * (p->rolling_stiffness + q->rolling_stiffness),
                .gamma_t = 0.5 * (p->spring_damping + q->spring_damping),
            };
        }
}

/* ------------------------------------------------------------------ timing */

/* One pair's contact time and stability limit. Linear: 000 eqs. 3.13-3.22 (overdamped pairs
 * report pi / omega_n). Hertz: linearised at the overlap of a 1 m/s impact. */
static void pair_timing(const SimWorldDef *def, int a, int b, double m_eff, double *t_c,
                        double *limit, double *restitution)
{
    const SimMaterial *p = &def->materials[a], *q = &def->materials[b];
    double k = 0.5 * (p->normal_stiffness + q->normal_stiffness);
    double gamma = sim_damping_gamma(def->materials, a, b, k, m_eff);
    double omega, zeta;
    if (def->contact.normal == SIM_NORMAL_HERTZ) {
        const double v = 1.0;
        double xi_max = pow(1.25 * m_eff * v * v / k, 0.4);
        double k_lin = 1.5 * k * sqrt(xi_max);
        omega = sqrt(k_lin / m_eff);
        zeta = gamma * sqrt(xi_max) / (2.0 * m_eff * omega);
        *t_c = 2.868 * pow(m_eff * m_eff / (k * k * v), 0.2);
    } else {
        omega = sqrt(k / m_eff);
        zeta = gamma / (2.0 * m_eff * omega);
        *t_c = zeta < 1.0 ? SIM_PI / (omega * sqrt(1.0 - zeta * zeta)) : SIM_PI / omega;
    }
    /* 000 eq. 3.24 (Hertz: of the linearised contact at 1 m/s) */
    *restitution = zeta < 1.0 ? exp(-SIM_PI * zeta / sqrt(1.0 - zeta * zeta)) : 0.0;
    /* A grain in a packing vibrates faster than an isolated pair: the densest 2D packing (a
     * triangular lattice, six contacts) has omega_max^2 = 3 omega_pair^2, and the damping
     * ratio of that mode grows by the same sqrt(3) (damping and stiffness share geometry). */
    const double packing = sqrt(3.0);
    *limit = sim_stability_limit(def->integrator, packing * omega, packing * zeta);
}

/* Worst pair over the species present: lightest mobile grain of each species against each other
 * mobile species and against fixed grains and walls (infinite mass). */
static SimTiming timing_of(const SimWorldDef *def)
{
    SimTiming t = {INFINITY, INFINITY, def->time_step, 0.0, NAN};
    double light[SIM_MAX_SPECIES];
    int present_fixed[SIM_MAX_SPECIES] = {0};
    for (int s = 0; s < SIM_MAX_SPECIES; ++s)
        light[s] = INFINITY;
    const SimGrainSet *g = &def->grains;
    for (int i = 0; i < g->count; ++i) {
        int s = g->species ? g->species[i] : 0;
        if (s < 0 || s >= SIM_MAX_SPECIES || !g->radius)
            continue;
        if (g->flags && (g->flags[i] & SIM_GRAIN_FIXED)) {
            present_fixed[s] = 1;
            continue;
        }
        double m, inertia;
        sim_grain_mass_inertia(def->mass_model, def->materials[s].density, g->radius[i], &m,
                               &inertia);
        if (m < light[s])
            light[s] = m;
    }
    for (int w = 0; w < def->wall_count && def->walls; ++w)
        if (def->walls[w].species >= 0 && def->walls[w].species < SIM_MAX_SPECIES)
            present_fixed[def->walls[w].species] = 1;
    for (int a = 0; a < SIM_MAX_SPECIES; ++a) {
        if (!isfinite(light[a]))
            continue;
        for (int b = 0; b < SIM_MAX_SPECIES; ++b) {
            double t_c, limit, e;
            if (isfinite(light[b])) {
                pair_timing(def, a, b, light[a] * light[b] / (light[a] + light[b]), &t_c, &limit,
                            &e);
                if (t_c < t.contact_time_min)
                    t.restitution = e;
                t.contact_time_min = fmin(t.contact_time_min, t_c);
                t.stability_limit = fmin(t.stability_limit, limit);
            }
            if (present_fixed[b]) {
                pair_timing(def, a, b, light[a], &t_c, &limit, &e);
                if (t_c < t.contact_time_min)
                    t.restitution = e;
                t.contact_time_min = fmin(t.contact_time_min, t_c);
                t.stability_limit = fmin(t.stability_limit, limit);
            }
        }
    }
    if (!(t.time_step > 0.0) && isfinite(t.contact_time_min))
        t.time_step = fmin(t.contact_time_min / def->steps_per_contact, 0.5 * t.stability_limit);
    t.steps_per_contact = t.contact_time_min / t.time_step;
    return t;
}

SimTiming sim_world_def_timing(const SimWorldDef *def)
{
    return timing_of(def);
}

/* ------------------------------------------------------------------ validation */

#define CHECK(cond, field, ...)                                                                    \
    do {                                                                                           \
        if (!(cond))                                                                               \
            return sim_fail(error, SIM_ERROR_INVALID, field, __VA_ARGS__);                         \
    } while (0)

static SimStatus validate_materials(const SimWorldDef *def, SimError *error)
{
    char f[64];
    CHECK(def->species_count >= 1 && def->species_count <= SIM_MAX_SPECIES, "species_count",
          "species count %d outside 1..%d", def->species_count, SIM_MAX_SPECIES);
    for (int s = 0; s < def->species_count; ++s) {
        const SimMaterial *m = &def->materials[s];
#define FIELD(name) (snprintf(f, sizeof f, "materials[%d].%s", s, name), f)
        CHECK(m->density > 0.0 && isfinite(m->density), FIELD("density"),
              "density must be positive (got %g)", m->density);
        CHECK(m->normal_stiffness > 0.0 && isfinite(m->normal_stiffness), FIELD("normal_stiffness"),
              "normal stiffness k_n must be positive (got %g)", m->normal_stiffness);
        switch (m->damping_mode) {
        case SIM_DAMPING_GAMMA:
            CHECK(m->normal_damping >= 0.0 && isfinite(m->normal_damping), FIELD("normal_damping"),
                  "normal damping gamma_n must be >= 0 (got %g)", m->normal_damping);
            break;
        case SIM_DAMPING_RESTITUTION:
            CHECK(m->restitution > 0.0 && m->restitution <= 1.0, FIELD("restitution"),
                  "restitution e_n must be in (0, 1] (got %g)", m->restitution);
            CHECK(def->contact.normal == SIM_NORMAL_LINEAR, FIELD("restitution"),
                  "restitution is defined for the linear normal law only; give gamma_n for hertz");
            break;
        case SIM_DAMPING_CRITICAL:
            CHECK(m->critical_fraction >= 0.0 && isfinite(m->critical_fraction),
                  FIELD("critical_fraction"), "critical damping fraction must be >= 0 (got %g)",
                  m->critical_fraction);
            break;
        default:
            return sim_fail(error, SIM_ERROR_INVALID, FIELD("damping_mode"),
                            "unknown damping mode");
        }
        CHECK(m->friction >= 0.0 && isfinite(m->friction), FIELD("friction"),
              "friction coefficient mu must be >= 0 (got %g)", m->friction);
        CHECK(m->tangential_damping >= 0.0, FIELD("tangential_damping"),
              "tangential damping gamma_s must be >= 0 (got %g)", m->tangential_damping);
        CHECK(m->spring_damping >= 0.0 && isfinite(m->spring_damping), FIELD("spring_damping"),
              "tangential damping gamma_t must be >= 0 (got %g)", m->spring_damping);
        if ((def->effects & SIM_EFFECT_FRICTION) &&
            def->contact.tangential == SIM_TANGENTIAL_SPRING)
            CHECK(m->tangential_stiffness > 0.0, FIELD("tangential_stiffness"),
                  "tangential stiffness k_t must be positive (got %g)", m->tangential_stiffness);
        CHECK(m->rolling_friction >= 0.0, FIELD("rolling_friction"),
              "rolling friction mu_r must be >= 0 (got %g)", m->rolling_friction);
        CHECK(m->rolling_stiffness >= 0.0, FIELD("rolling_stiffness"),
              "rolling stiffness k_r must be >= 0 (got %g)", m->rolling_stiffness);
#undef FIELD
    }
    return SIM_OK;
}

/* `restored`: the grains come from a checkpoint the engine wrote (sim_world_load): they are
 * exempt from the start-overlap bound (see validate_def). */
static SimStatus validate_grains(const SimWorldDef *def, int restored, SimError *error)
{
    const SimGrainSet *g = &def->grains;
    char f[64];
    CHECK(g->count >= 0, "grains", "negative grain count");
    CHECK(g->count == 0 || (g->x && g->y && g->radius), "grains", "grain arrays missing");
    for (int i = 0; i < g->count; ++i) {
        snprintf(f, sizeof f, "grains[%d]", i);
        CHECK(isfinite(g->x[i]) && isfinite(g->y[i]), f, "grain %d has a non-finite position", i);
        CHECK((!g->vx || isfinite(g->vx[i])) && (!g->vy || isfinite(g->vy[i])) &&
                  (!g->omega || isfinite(g->omega[i])) && (!g->angle || isfinite(g->angle[i])),
              f, "grain %d has a non-finite velocity, angle or angular velocity", i);
        CHECK(g->radius[i] > 0.0 && isfinite(g->radius[i]), f,
              "grain %d has radius %g; radii must be positive", i, g->radius[i]);
        int s = g->species ? g->species[i] : 0;
        CHECK(s >= 0 && s < def->species_count, f, "grain %d has species %d, not defined", i, s);
        int mo = g->motion ? g->motion[i] : -1;
        CHECK(mo < def->motion_count, f, "grain %d uses motion %d, not defined", i, mo);
        CHECK(mo >= -1 || (def->grain_bodies && SIM_GRAIN_BODY(mo) < def->grain_body_count), f,
              "grain %d belongs to grain body %d, not defined", i, SIM_GRAIN_BODY(mo));
        if (mo >= 0)
            CHECK(def->effects & SIM_EFFECT_VIBRATION, f,
                  "grain %d has a prescribed motion but the vibration effect is not declared", i);
    }
    for (int w = 0; w < def->wall_count; ++w) {
        const SimWall *wall = &def->walls[w];
        snprintf(f, sizeof f, "walls[%d]", w);
        CHECK(isfinite(wall->x0) && isfinite(wall->y0) && isfinite(wall->x1) && isfinite(wall->y1),
              f, "wall %d has a non-finite end point", w);
        CHECK(wall->shape == SIM_WALL_SEGMENT || wall->shape == SIM_WALL_ARC, f,
              "wall %d has an unknown shape %d", w, (int)wall->shape);
        if (wall->shape == SIM_WALL_ARC) {
            CHECK(isfinite(wall->center_x) && isfinite(wall->center_y), f,
                  "arc wall %d has a non-finite centre", w);
            CHECK(wall->radius > 0.0 && isfinite(wall->radius), f,
                  "arc wall %d has radius %g; it must be positive", w, wall->radius);
            CHECK(isfinite(wall->angle0) && isfinite(wall->angle1) && wall->angle1 > wall->angle0,
                  f, "arc wall %d needs finite angles with angle1 > angle0", w);
            CHECK(wall->side >= SIM_WALL_BOTH && wall->side <= SIM_WALL_OUTSIDE, f,
                  "arc wall %d has an unknown side %d", w, (int)wall->side);
        }
        CHECK(wall->species >= 0 && wall->species < def->species_count, f,
              "wall %d has species %d, not defined", w, wall->species);
        CHECK(wall->motion < def->motion_count, f, "wall %d uses motion %d, not defined", w,
              wall->motion);
        if (wall->motion >= 0)
            CHECK(def->effects & SIM_EFFECT_VIBRATION, f,
                  "wall %d has a prescribed motion but the vibration effect is not declared", w);
        for (int i = 0; i < g->count; ++i) {
            if (restored || (g->flags && (g->flags[i] & SIM_GRAIN_FIXED)))
                continue;
            double d = sim_wall_distance(wall, g->x[i], g->y[i], g->radius[i]);
            /* A settled bed rests on its walls with a small overlap: refuse only above the
             * initial-overlap bound, as for pairs of grains. */
            if (g->radius[i] - d > def->max_initial_overlap * 2.0 * g->radius[i]) {
                snprintf(f, sizeof f, "grains[%d]", i);
                return sim_fail(error, SIM_ERROR_INVALID, f,
                                "grain %d at (%g, %g) overlaps wall %d at start by %.3g of its "
                                "diameter (bound %g)",
                                i, g->x[i], g->y[i], w, (g->radius[i] - d) / (2.0 * g->radius[i]),
                                def->max_initial_overlap);
            }
        }
    }
    return SIM_OK;
}

/* The checks of a definition. The start-overlap bound (max_initial_overlap, grain-grain and
 * grain-wall) is for new grains: a user-supplied grain list that overlaps more is a mistake (a
 * pile placed too densely would explode). Restored grains are exempt (`restored`, from
 * sim_world_load): a state the engine itself saved was reached by the physics, and a deep or
 * soft pile settles with overlaps above the bound, so its checkpoint must reload whatever its
 * overlaps (the run guard, guard_max_overlap, still watches them as the run goes on). */
/* A prescribed motion whose walls or fixed grains move more than half the smallest mobile radius
 * in one step can pass through grains, and grains dragged to that speed skip their contacts: such
 * a motion is refused at set-up, naming the time step that would resolve it. The speed is bounded
 * as the guard bounds it (sim_motion_speed_bound over the grains' and walls' extent). */
static SimStatus validate_motion_speed(const SimWorldDef *def, double dt, SimError *error)
{
    const SimGrainSet *g = &def->grains;
    double r_min = INFINITY, x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int i = 0; i < g->count; ++i) {
        if (!(g->flags && (g->flags[i] & SIM_GRAIN_FIXED)))
            r_min = fmin(r_min, g->radius[i]);
        x0 = fmin(x0, g->x[i] - g->radius[i]);
        y0 = fmin(y0, g->y[i] - g->radius[i]);
        x1 = fmax(x1, g->x[i] + g->radius[i]);
        y1 = fmax(y1, g->y[i] + g->radius[i]);
    }
    for (int k = 0; k < def->wall_count && def->walls; ++k) {
        double a, b, c, d;
        sim_wall_bounds(&def->walls[k], &a, &b, &c, &d);
        x0 = fmin(x0, a);
        y0 = fmin(y0, b);
        x1 = fmax(x1, c);
        y1 = fmax(y1, d);
    }
    if (def->motion_count == 0 || !isfinite(r_min) || !(dt > 0.0) || !(x1 >= x0 && y1 >= y0))
        return SIM_OK;
    const double size = hypot(x1 - x0, y1 - y0);
    for (int m = 0; m < def->motion_count; ++m) {
        SimWorldDef upto = *def; /* motions 0..m: the earlier ones passed, so this is m's */
        upto.motion_count = m + 1;
        const double v = sim_motion_speed_bound(&upto, size);
        if (v * dt > 0.5 * r_min) {
            char f[64];
            snprintf(f, sizeof f, "motions[%d]", m);
            return sim_fail(
                error, SIM_ERROR_INVALID, f,
                "motion %d moves its walls or fixed grains at up to %g m/s, %g m per time "
                "step, more than half the smallest grain radius %g m: grains would be "
                "passed through or dragged past their contacts; the time step must be "
                "below %g s (wall-speed limit), or the motion slower",
                m, v, v * dt, r_min, 0.5 * r_min / v);
        }
    }
    return SIM_OK;
}

/* The effect bits, the integrator and the contact laws, alone and together. */
static SimStatus validate_laws(const SimWorldDef *def, SimError *error)
{
    CHECK(!(def->effects & ~63u), "effects", "unknown effect bits 0x%x", def->effects);
    CHECK((int)def->integrator >= 0 && def->integrator < SIM_INTEGRATOR_COUNT, "integrator",
          "unknown integrator %d", (int)def->integrator);
    CHECK(def->contact.normal == SIM_NORMAL_LINEAR || def->contact.normal == SIM_NORMAL_HERTZ,
          "contact.normal", "unknown normal law");
    CHECK((int)def->contact.tangential >= 0 && def->contact.tangential <= SIM_TANGENTIAL_SPRING,
          "contact.tangential", "unknown tangential law");
    CHECK((int)def->contact.rolling >= 0 && def->contact.rolling <= SIM_ROLLING_FIXED,
          "contact.rolling", "unknown rolling law");
    CHECK(def->contact.onset == SIM_ONSET_STEP || def->contact.onset == SIM_ONSET_EVENT,
          "contact.onset", "unknown onset");
    CHECK(def->contact.onset != SIM_ONSET_EVENT || def->contact.normal == SIM_NORMAL_LINEAR,
          "contact.onset",
          "onset \"event\" needs the linear normal law (the Hertz force has no jump at touch)");
    CHECK(def->contact.onset != SIM_ONSET_EVENT ||
              (def->integrator != SIM_INTEGRATOR_GEAR && def->integrator != SIM_INTEGRATOR_RK4),
          "contact.onset",
          "onset \"event\" is derived for velocity_verlet, symplectic_euler and stormer_verlet "
          "(one force evaluation per step)");
    int history = ((def->effects & SIM_EFFECT_FRICTION) &&
                   def->contact.tangential == SIM_TANGENTIAL_SPRING) ||
                  ((def->effects & SIM_EFFECT_ROLLING) && def->contact.rolling != SIM_ROLLING_OFF);
    CHECK(!(history && def->integrator == SIM_INTEGRATOR_RK4), "integrator",
          "rk4 cannot integrate history-dependent contacts (tangential spring, rolling "
          "resistance): choose velocity_verlet or gear");
    return SIM_OK;
}

/* The scalar settings (gravity, time step, skin, guards, counts) and each motion. */
static SimStatus validate_settings(const SimWorldDef *def, SimError *error)
{
    CHECK(isfinite(def->gravity_x) && isfinite(def->gravity_y), "gravity", "gravity not finite");
    CHECK(def->time_step >= 0.0 && isfinite(def->time_step), "time_step",
          "time step must be positive (got %g)", def->time_step);
    CHECK(def->time_step > 0.0 || def->steps_per_contact > 0.0, "steps_per_contact",
          "steps per contact must be positive when no time step is given");
    CHECK(def->max_dt_fraction >= 0.0, "max_dt_fraction", "max_dt_fraction must be >= 0");
    CHECK(def->skin >= 0.0, "skin", "skin must be >= 0");
    CHECK(def->guard_max_overlap > 0.0, "guard_max_overlap", "guard overlap bound must be > 0");
    CHECK(def->guard_every >= 1, "guard_every", "guard_every must be >= 1");
    CHECK(def->max_initial_overlap >= 0.0, "max_initial_overlap",
          "max_initial_overlap must be >= 0");
    CHECK(def->length_scale >= 0.0 && isfinite(def->length_scale), "length_scale",
          "length_scale must be >= 0");
    CHECK(!def->grain_bodies || def->grain_body_count >= 0, "bodies",
          "grain_body_count %d is negative", def->grain_body_count);
    CHECK(def->motion_count >= 0 && def->motion_count <= SIM_MAX_MOTIONS, "motions",
          "too many motions (at most %d)", SIM_MAX_MOTIONS);
    CHECK(def->sink_count >= 0 && def->sink_count <= SIM_MAX_SINKS, "sinks",
          "too many sinks (at most %d)", SIM_MAX_SINKS);
    CHECK(def->sink_count == 0 || (def->effects & SIM_EFFECT_REMOVAL), "sinks",
          "sinks are defined but the removal effect is not declared");
    CHECK(!(def->effects & SIM_EFFECT_FLUID_DRAG) || def->body_force.apply, "body_force",
          "fluid_drag is declared but no body-force stage is attached");
    for (int m = 0; m < def->motion_count; ++m) {
        const char *problem = sim_motion_problem(def, m);
        char f[64];
        snprintf(f, sizeof f, "motions[%d]", m);
        CHECK(!problem, f, "motion %d: %s", m, problem);
    }
    return SIM_OK;
}

/* The grains' worst overlap at start against max_initial_overlap (none checked once restored). */
static SimStatus validate_overlap(const SimWorldDef *def, int restored, SimError *error)
{
    int a = -1, b = -1;
    double worst = restored ? 0.0 : sim_def_worst_overlap(def, &a, &b);
    if (isnan(worst))
        return sim_fail(error, SIM_ERROR_MEMORY, "grains", "out of memory checking the overlaps");
    if (worst > def->max_initial_overlap) {
        char f[64];
        snprintf(f, sizeof f, "grains[%d]", a);
        return sim_fail(
            error, SIM_ERROR_INVALID, f,
            "grains %d and %d overlap at start by %.3g of the smaller diameter (bound %g: "
            "max_initial_overlap)",
            a, b, worst, def->max_initial_overlap);
    }
    return SIM_OK;
}

/* A periodic domain holds three of the largest grains plus the skin across. */
static SimStatus validate_periodic(const SimWorldDef *def, SimError *error)
{
    if (!(def->effects & SIM_EFFECT_PERIODIC_X))
        return SIM_OK;
    double r_max = 0.0;
    for (int i = 0; i < def->grains.count; ++i)
        r_max = fmax(r_max, def->grains.radius[i]);
    double span = def->domain_x1 - def->domain_x0;
    CHECK(span > 0.0, "domain", "periodic domain needs x1 > x0");
    CHECK(span >= 3.0 * (2.0 * r_max + fmax(def->skin, 0.4 * r_max)), "domain",
          "periodic domain %g wide is narrower than three largest grains plus skin", span);
    return SIM_OK;
}

/* The time step against the bodies on walls and grains and the contacts' stability limit. */
static SimStatus validate_time_step(const SimWorldDef *def, SimTiming t, SimError *error)
{
    char why[320];
    int body_wall = -1;
    const char *body = sim_wall_bodies_problem(def, t.time_step, &body_wall, why, sizeof why);
    if (body) {
        char f[64];
        const int group = body_wall - def->wall_count;
        if (group >= 0) {
            snprintf(f, sizeof f, "bodies[%d]", group);
            return sim_fail(error, SIM_ERROR_INVALID, f, "grain body %d: %s", group, body);
        }
        snprintf(f, sizeof f, "walls[%d]", body_wall);
        return sim_fail(error, SIM_ERROR_INVALID, f, "wall %d: %s", body_wall, body);
    }
    if (def->grains.count > 0 && isfinite(t.contact_time_min)) {
        CHECK(t.time_step <= t.stability_limit, "time_step",
              "time step %g s exceeds the stability limit %g s of %s for the stiffest, lightest "
              "pair (contact time %g s, %.3g steps per contact)",
              t.time_step, t.stability_limit, sim_integrator_name(def->integrator),
              t.contact_time_min, t.steps_per_contact);
        CHECK(def->max_dt_fraction <= 0.0 ||
                  t.time_step <= def->max_dt_fraction * t.contact_time_min,
              "time_step",
              "time step %g s is above %g of the contact time %g s (%.3g steps per contact; the "
              "scene asks for at least %.3g)",
              t.time_step, def->max_dt_fraction, t.contact_time_min, t.steps_per_contact,
              1.0 / def->max_dt_fraction);
    }
    return SIM_OK;
}

static SimStatus validate_def(const SimWorldDef *def, int restored, SimError *error)
{
    SimStatus s;
    if (error)
        memset(error, 0, sizeof *error);
    if ((s = validate_laws(def, error)) != SIM_OK || (s = validate_settings(def, error)) != SIM_OK)
        return s;
    if ((s = validate_materials(def, error)) != SIM_OK)
        return s;
    if ((s = validate_grains(def, restored, error)) != SIM_OK)
        return s;
    if ((s = validate_overlap(def, restored, error)) != SIM_OK ||
        (s = validate_periodic(def, error)) != SIM_OK)
        return s;
    SimTiming t = timing_of(def);
    if ((s = validate_motion_speed(def, t.time_step, error)) != SIM_OK)
        return s;
    return validate_time_step(def, t, error);
}

SimStatus sim_world_def_validate(const SimWorldDef *def, SimError *error)
{
    return validate_def(def, 0, error);
}

/* ------------------------------------------------------------------ grains in and out */

/* Loads grains into the world arrays: mobile first, then fixed, each in input order. */
static int load_grains(SimWorld *w, const SimGrainSet *g)
{
    if (sim_grains_reserve(w, g->count + 1) != 0)
        return -1;
    int mobile = 0;
    for (int i = 0; i < g->count; ++i)
        if (!(g->flags && (g->flags[i] & SIM_GRAIN_FIXED)))
            ++mobile;
    int next_mobile = 0, next_fixed = mobile;
    for (int i = 0; i < g->count; ++i) {
        int fixed = g->flags && (g->flags[i] & SIM_GRAIN_FIXED);
        int k = fixed ? next_fixed++ : next_mobile++;
        w->x[k] = g->x[i];
        w->y[k] = g->y[i];
        w->radius[k] = g->radius[i];
        w->vx[k] = g->vx && !fixed ? g->vx[i] : 0.0;
        w->vy[k] = g->vy && !fixed ? g->vy[i] : 0.0;
        w->angle[k] = g->angle ? g->angle[i] : 0.0;
        w->omega[k] = g->omega && !fixed ? g->omega[i] : 0.0;
        w->species[k] = g->species ? g->species[i] : 0;
        w->flags[k] = g->flags ? (g->flags[i] & SIM_GRAIN_FIXED) : 0;
        w->motion[k] = g->motion ? g->motion[i] : -1;
        w->id[k] = g->id ? g->id[i] : (uint32_t)i;
        w->x_base[k] = w->x[k];
        w->y_base[k] = w->y[k];
        double m, inertia;
        sim_grain_mass_inertia(w->def.mass_model, w->def.materials[w->species[k]].density,
                               w->radius[k], &m, &inertia);
        w->mass[k] = m;
        w->inertia[k] = inertia;
        w->inv_mass[k] = fixed ? 0.0 : 1.0 / m;
        w->inv_inertia[k] = fixed || !w->rotation ? 0.0 : 1.0 / inertia;
        w->fx[k] = w->fy[k] = w->torque[k] = 0.0;
    }
    w->count = g->count;
    w->mobile_count = mobile;
    return 0;
}

/* Is any grain or wall closer to grain i than the two radii plus `reach` (rare: O(N))? */
static int within_reach(const SimWorld *w, int i, double reach)
{
    if (!isfinite(reach))
        return 1;
    const double xi = w->x[i], yi = w->y[i], ri = w->radius[i];
    const double span = w->def.domain_x1 - w->def.domain_x0;
    const int periodic = (w->effects & SIM_EFFECT_PERIODIC_X) != 0;
    for (int j = 0; j < w->count; ++j) {
        if (j == i)
            continue;
        double dx = w->x[j] - xi, dy = w->y[j] - yi;
        if (periodic)
            dx -= span * floor(dx / span + 0.5);
        double cut = ri + w->radius[j] + reach;
        if (dx * dx + dy * dy < cut * cut)
            return 1;
    }
    for (int k = 0; k < w->wall_count; ++k)
        if (sim_wall_distance(&w->walls[k], xi, yi, ri) < ri + reach)
            return 1;
    return 0;
}

static void removal_stage(SimWorld *w);

/* ------------------------------------------------------------------ automatic skin */

/* Cost model of the list (measured with bench_sim on the 7000-grain pile, spring law: a build
 * costs about as much as evaluating 50 list entries per grain; bench/README.md). With entries
 * E0 + rho s per grain at skin s, and the largest displacement growing by u per step, a skin s
 * lasts s / (2u) steps, so the work per grain and step is E0 + rho s + SKIN_BUILD_COST 2u / s,
 * smallest at s = sqrt(2 u SKIN_BUILD_COST / rho). */
enum { SKIN_BUILD_COST = 50, SKIN_PROBE_STEPS = 50 };

#define SKIN_MIN_FRACTION 0.01 /* of the mean mobile diameter */
#define SKIN_MAX_FRACTION 0.2  /* of the mean mobile diameter: the fixed default */

/* The skin the cost model asks for, from the displacement since the last build: u is the largest
 * displacement (grains, prescribed grains, walls) over the steps it took. Only step counts and
 * positions enter, so the choice is the same on every run of a scene. */
static double skin_optimum(const SimWorld *w)
{
    const long n = w->step - w->build_step;
    if (n <= 0)
        return w->skin;
    double d2 = 0.0;
    for (int i = 0; i < w->count; ++i) {
        double dx = w->x[i] - w->x_ref[i], dy = w->y[i] - w->y_ref[i];
        double e = dx * dx + dy * dy;
        d2 = e > d2 ? e : d2;
    }
    const double u = fmax(sqrt(d2), w->wall_shift) / (double)n;
    const double rho = w->skin_density;
    double s = rho > 0.0 ? sqrt(2.0 * u * SKIN_BUILD_COST / rho) : w->skin_max;
    return fmin(fmax(s, w->skin_min), w->skin_max);
}

/* Before a build: the new skin. */
static void skin_tune(SimWorld *w)
{
    if (!w->skin_auto || w->rebuilds == 0)
        return;
    w->skin = skin_optimum(w);
    w->disp_limit2 = 0.25 * w->skin * w->skin;
}

/* Between builds (every SKIN_PROBE_STEPS steps): when the grains move so little that a skin under
 * half the present one would be cheaper, build now with it. (A larger skin is chosen at the next
 * build, which the present skin's displacement bound triggers.) */
static void skin_probe(SimWorld *w)
{
    w->skin_probe = w->step + SKIN_PROBE_STEPS;
    if (skin_optimum(w) < 0.5 * w->skin)
        w->need_rebuild = 1;
}

static void rebuild(SimWorld *w)
{
    if (w->effects & SIM_EFFECT_REMOVAL)
        removal_stage(w);
    skin_tune(w);
    sim_neighbour_build(w);
    w->build_step = w->step;
    sim_motion_mark_build(w);
    /* A grain that moves more than half its radius in one step can pass through a partner
     * between two force evaluations (004 §1.8). Such a grain has moved more than half the skin
     * since the last build, so checking at builds sees every one of them; it is an error only
     * when something lies within its reach (a free fall in empty space is harmless). */
    const double dt2 = w->dt * w->dt;
    for (int i = 0; i < w->mobile_count && w->jump_grain < 0; ++i) {
        double v2 = w->vx[i] * w->vx[i] + w->vy[i] * w->vy[i];
        if (!(v2 * dt2 <= 0.25 * w->radius[i] * w->radius[i]) && within_reach(w, i, sqrt(v2 * dt2)))
            w->jump_grain = i;
    }
}

static void reevaluate_forces(SimWorld *w);

void sim_world_rebuild_now(SimWorld *w)
{
    rebuild(w);
    reevaluate_forces(w);
}

static int probe_due(const SimWorld *w)
{
    return w->skin_auto && w->step >= w->skin_probe;
}

/* A grain may have moved half the skin: 004 §1.9, style notes 8.5. */
static int rebuild_due(const SimWorld *w)
{
    return w->need_rebuild || 2.0 * w->wall_shift > w->skin;
}

/* Forces of grains [from, count) set to +0.0. */
static void clear_forces(SimWorld *w, int from)
{
    const size_t n = (size_t)(w->count - from);
    memset(w->fx + from, 0, n * sizeof(double));
    memset(w->fy + from, 0, n * sizeof(double));
    if (w->rotation)
        memset(w->torque + from, 0, n * sizeof(double));
}

/* The forces at time t once the prescribed motions are there (the list rebuilt first when due).
 * `cleared`: the drift has cleared the mobile grains' forces already (a build may add or drop
 * grains, so after one every force is cleared here). */
static void forces_after_motion(SimWorld *w, int cleared)
{
    if (probe_due(w))
        skin_probe(w);
    if (rebuild_due(w)) {
        rebuild(w);
        cleared = 0;
    }
    clear_forces(w, cleared ? w->mobile_count : 0);
    w->contact_pass(w);
}

/* What follows the grain-grain contacts: walls, then body forces. */
static void forces_after_contacts(SimWorld *w, double t)
{
    if (w->wall_count > 0)
        w->wall_pass(w);
    if (w->effects & SIM_EFFECT_FLUID_DRAG) {
        SimBodyForceView view = {w->mobile_count, t,         w->x,    w->y,  w->vx,
                                 w->vy,           w->radius, w->mass, w->fx, w->fy};
        w->body_force.apply(w->body_force.context, &view);
    }
}

void sim_world_forces_at(SimWorld *w, double t)
{
    if (w->effects & SIM_EFFECT_VIBRATION)
        sim_motion_move(w, t);
    forces_after_motion(w, 0);
    forces_after_contacts(w, t);
}

/* The prescribed motions read and write only the fixed grains and the walls, and the drift only
 * the mobile grains, so the motions go first here. The fused pass needs the list to stay valid:
 * nothing may ask for a rebuild before the drift (an edit, the motions, a skin probe, which reads
 * the drifted positions). */
void sim_world_drift_forces_at(SimWorld *w, double t, RangeFn *drift, int align)
{
    if (w->effects & SIM_EFFECT_VIBRATION)
        sim_motion_move(w, t);
    if (w->fused_pass && (w->threads <= 1 || w->nl.plan.count > 0) && !rebuild_due(w) &&
        !probe_due(w)) {
        clear_forces(w, w->mobile_count); /* the fixed grains' (the drift clears the others) */
        ++w->fused_steps;
        if (w->fused_pass(w, drift, align) == 0) {
            forces_after_contacts(w, t);
            return;
        }
        ++w->fused_trips;
        w->need_rebuild = 1;
    } else {
        w->need_rebuild |= sim_parallel_ranges(w, drift, w->mobile_count, align);
    }
    forces_after_motion(w, 1);
    forces_after_contacts(w, t);
}

/* The pool is parallel.c's; what depends on the thread count (the list's transpose and the fused
 * pass's parts) is rebuilt here for the list the world has now. */
void sim_world_set_threads(SimWorld *w, int threads)
{
    threads = threads > 1 ? threads : 1;
    if (threads == w->threads)
        return;
    sim_parallel_start(w, threads);
    sim_neighbour_build_incoming(w);
}

int sim_world_threads(const SimWorld *w)
{
    return w->threads;
}

void sim_world_set_gravity(SimWorld *w, double gravity_x, double gravity_y)
{
    w->def.gravity_x = gravity_x;
    w->def.gravity_y = gravity_y;
}

/* ------------------------------------------------------------------ create / destroy */

/* The mean diameter of the mobile grains (of all grains when none is mobile), m. */
static double mean_mobile_diameter(const SimGrainSet *g)
{
    double sum = 0.0;
    int n = 0;
    for (int i = 0; i < g->count; ++i)
        if (!(g->flags && (g->flags[i] & SIM_GRAIN_FIXED))) {
            sum += 2.0 * g->radius[i];
            ++n;
        }
    if (n == 0)
        for (int i = 0; i < g->count; ++i, ++n)
            sum += 2.0 * g->radius[i];
    return n ? sum / n : 0.5;
}

static void guard_snapshot(SimWorld *w);
static void reevaluate_forces(SimWorld *w);

/* The diagonal of the grains' bounding box plus the largest diameter, m (1 without grains). */
static double domain_size(const SimWorld *w)
{
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (int i = 0; i < w->count; ++i) {
        x0 = fmin(x0, w->x[i]);
        x1 = fmax(x1, w->x[i]);
        y0 = fmin(y0, w->y[i]);
        y1 = fmax(y1, w->y[i]);
    }
    return w->count ? hypot(x1 - x0, y1 - y0) + 2.0 * w->max_radius : 1.0;
}

static void setup_guard(SimWorld *w)
{
    double v0 = 0.0;
    for (int i = 0; i < w->count; ++i)
        v0 = fmax(v0, hypot(w->vx[i], w->vy[i]));
    const double size = domain_size(w), vm = sim_motion_speed_bound(&w->def, size);
    double vmax = w->def.guard_max_speed;
    if (!(vmax > 0.0)) {
        /* Automatic bound: far above any speed gravity, the initial state or prescribed motion
         * can produce in the domain. */
        double g = hypot(w->def.gravity_x, w->def.gravity_y);
        vmax = 100.0 * fmax(fmax(sqrt(2.0 * g * size), v0), vm);
        if (!(vmax > 0.0))
            vmax = INFINITY;
    }
    w->guard_free_speed = v0 + vm;
    w->guard_t0 = w->time;
    w->guard_speed2 = vmax * vmax;
    w->guard_next = w->step + w->def.guard_every;
}

/* sim_world_create, and sim_world_create_restored for the grains of a checkpoint (validate_def:
 * restored grains are exempt from the start-overlap bound). */
static SimWorld *create(const SimWorldDef *def, int restored, SimError *error)
{
    if (validate_def(def, restored, error) != SIM_OK)
        return NULL;
    SimWorld *w = calloc(1, sizeof *w);
    if (!w) {
        sim_fail(error, SIM_ERROR_MEMORY, "", "out of memory creating the world");
        return NULL;
    }
    w->def = *def;
    w->def.grains = (SimGrainSet){0};
    w->effects = def->effects;
    fill_pairs(w->pairs, def);
    unsigned key = sim_contact_key(w);
    w->rotation = sim_contact_key_rotation(key);
    w->has_history = sim_contact_key_history(key);
    w->kernels = sim_kernels();
    w->contact_key = key;
    w->contact_pass = w->kernels->contact_pass(key);
    w->wall_pass = w->kernels->wall_pass(key);
    w->fused_pass = w->kernels->fused_pass(key);
    w->integrate = w->kernels->integrator(def->integrator, w->rotation);
    w->scratch_count = sim_integrator_scratch_count(def->integrator, w->rotation);
    w->body_force = def->body_force;
    w->threads = 1;
    w->time = def->start_time;
    w->timing = timing_of(def);
    w->dt = w->timing.time_step;
    w->contact_dt = w->dt;

    if (load_grains(w, &def->grains) != 0) {
        sim_world_destroy(w);
        sim_fail(error, SIM_ERROR_MEMORY, "", "out of memory creating the world");
        return NULL;
    }
    w->wall_count = def->wall_count;
    size_t nw = (size_t)(def->wall_count > 0 ? def->wall_count : 1);
    w->walls_base = calloc(nw, sizeof *w->walls_base);
    w->walls = calloc(nw, sizeof *w->walls);
    w->wall_vx = calloc(nw, sizeof(double));
    w->wall_vy = calloc(nw, sizeof(double));
    w->wall_omega = calloc(nw, sizeof(double));
    w->wall_ox = calloc(nw, sizeof(double));
    w->wall_oy = calloc(nw, sizeof(double));
    w->wall_ref_dx = calloc(nw, sizeof(double));
    w->wall_ref_dy = calloc(nw, sizeof(double));
    w->walls_ref = calloc(nw, sizeof *w->walls_ref);
    /* the grain bodies' loads follow the walls' (wall_body.c) */
    const size_t nl = nw + (size_t)(def->grain_bodies ? def->grain_body_count : 0);
    w->wall_load = calloc(4 * nl, sizeof(double));
    w->wall_touch = calloc(nl, sizeof(int));
    if (!w->walls_base || !w->walls || !w->wall_vx || !w->wall_vy || !w->wall_omega ||
        !w->wall_ox || !w->wall_oy || !w->wall_ref_dx || !w->wall_ref_dy || !w->walls_ref ||
        !w->wall_load || !w->wall_touch || sim_wall_bodies_create(w, def) != 0) {
        sim_world_destroy(w);
        sim_fail(error, SIM_ERROR_MEMORY, "", "out of memory creating the world");
        return NULL;
    }
    if (def->wall_count > 0) {
        memcpy(w->walls_base, def->walls, nw * sizeof *w->walls);
        memcpy(w->walls, def->walls, nw * sizeof *w->walls);
        memcpy(w->walls_ref, def->walls, nw * sizeof *w->walls);
    }
    for (int m = 0; m < SIM_MAX_MOTIONS; ++m) {
        w->motion_on[m] = 0.0;
        w->motion_off[m] = INFINITY;
    }
    for (int i = 0; i < w->count; ++i)
        w->max_radius = fmax(w->max_radius, w->radius[i]);
    const double diameter = mean_mobile_diameter(&def->grains);
    w->skin_auto = !(def->skin > 0.0);
    w->skin_max = w->skin_auto ? SKIN_MAX_FRACTION * diameter : def->skin;
    w->skin_min = w->skin_auto ? SKIN_MIN_FRACTION * diameter : def->skin;
    w->skin = w->skin_max;
    w->skin_probe = SKIN_PROBE_STEPS;
    w->disp_limit2 = 0.25 * w->skin * w->skin;
    w->cell_size = 2.0 * w->max_radius + w->skin_max;
    if (!(w->cell_size > 0.0))
        w->cell_size = 1.0;

    if (w->effects & SIM_EFFECT_VIBRATION)
        sim_motion_move(w, w->time);
    w->jump_grain = -1;
    rebuild(w);
    reevaluate_forces(w); /* no time has passed: no contact-history increment */
    if (w->out_of_memory) {
        sim_fail(error, SIM_ERROR_MEMORY, "", "out of memory in %s creating the world",
                 w->out_of_memory);
        sim_world_destroy(w);
        return NULL;
    }
    sim_integrator_start(w);
    setup_guard(w);
    guard_snapshot(w);
    return w;
}

SimWorld *sim_world_create(const SimWorldDef *def, SimError *error)
{
    return create(def, 0, error);
}

SimWorld *sim_world_create_restored(const SimWorldDef *def, SimError *error)
{
    return create(def, 1, error);
}

void sim_world_destroy(SimWorld *w)
{
    if (!w)
        return;
    sim_parallel_free(w);
    sim_grains_free(w);
    sim_neighbour_free(w);
    free(w->walls_base);
    free(w->walls);
    free(w->wall_vx);
    free(w->wall_vy);
    free(w->wall_omega);
    free(w->wall_ox);
    free(w->wall_oy);
    free(w->wall_ref_dx);
    free(w->wall_ref_dy);
    free(w->walls_ref);
    free(w->wall_load);
    free(w->wall_touch);
    sim_wall_bodies_free(w);
    free(w->good.data);
    free(w->good.ints);
    free(w->good.flags);
    free(w->good.ids);
    free(w->contacts);
    free(w);
}

/* ------------------------------------------------------------------ removal */

static int in_sink(const SimSink *s, double x, double y)
{
    switch (s->shape) {
    case SIM_SINK_BELOW:
        return y < s->level;
    case SIM_SINK_ABOVE:
        return y > s->level;
    case SIM_SINK_LEFT:
        return x < s->level;
    case SIM_SINK_RIGHT:
        return x > s->level;
    case SIM_SINK_RECT:
        return x >= s->x0 && x <= s->x1 && y >= s->y0 && y <= s->y1;
    }
    return 0;
}

/* Flags grains for removal, then rebuilds (history is collected before compaction) and
 * recomputes the forces without them. */
static void apply_removal(SimWorld *w)
{
    w->pending_removal = 1;
    rebuild(w);
    reevaluate_forces(w);
}

/* Forces at the current state after an edit (removal, addition, freeze): the step's contact
 * history increments are already in, so this evaluation adds none. */
static void reevaluate_forces(SimWorld *w)
{
    w->contact_dt = 0.0;
    sim_world_forces_at(w, w->time);
    w->contact_dt = w->dt;
}

/* Sinks are checked at every neighbour build, not every step: a grain has to move to enter a
 * sink, and a grain that moved half a skin triggers a build, so a grain is removed within about
 * half a skin of entering (and costs nothing in between). The build then compacts it away. */
static void removal_stage(SimWorld *w)
{
    for (int i = 0; i < w->mobile_count; ++i)
        for (int s = 0; s < w->def.sink_count; ++s)
            if (in_sink(&w->def.sinks[s], w->x[i], w->y[i])) {
                w->flags[i] |= SIM_GRAIN_REMOVED;
                ++w->removed[s];
                w->pending_removal = 1;
                break;
            }
}

int sim_world_remove_rect(SimWorld *w, double x0, double y0, double x1, double y1)
{
    int n = 0;
    for (int i = 0; i < w->mobile_count; ++i)
        if (w->x[i] >= x0 && w->x[i] <= x1 && w->y[i] >= y0 && w->y[i] <= y1) {
            w->flags[i] |= SIM_GRAIN_REMOVED;
            ++n;
        }
    if (n)
        apply_removal(w);
    return n;
}

int sim_world_remove_ids(SimWorld *w, const uint32_t *ids, int count)
{
    int n = 0;
    for (int i = 0; i < w->count; ++i)
        for (int k = 0; k < count; ++k)
            if (w->id[i] == ids[k] && !(w->flags[i] & SIM_GRAIN_REMOVED)) {
                w->flags[i] |= SIM_GRAIN_REMOVED;
                ++n;
                break;
            }
    if (n)
        apply_removal(w);
    return n;
}

/* The newcomers' pairs with the grains in place must be resolved by the time step too
 * (validate_def saw the newcomers alone): the timing of the newcomers with the lightest mobile
 * grain of each species in place and one fixed grain of each fixed species. */
SimStatus sim_world_check_timing(const SimWorld *w, const SimGrainSet *g, SimError *error)
{
    const int n = g->count + 2 * SIM_MAX_SPECIES;
    double *radius = malloc((size_t)n * sizeof *radius);
    int *species = malloc((size_t)n * sizeof *species);
    unsigned *flags = malloc((size_t)n * sizeof *flags);
    if (!radius || !species || !flags) {
        free(radius);
        free(species);
        free(flags);
        return sim_fail(error, SIM_ERROR_MEMORY, "grains", "out of memory adding %d grains",
                        g->count);
    }
    int light[SIM_MAX_SPECIES], fixed[SIM_MAX_SPECIES], count = 0;
    for (int s = 0; s < SIM_MAX_SPECIES; ++s)
        light[s] = fixed[s] = -1;
    for (int i = 0; i < w->count; ++i) {
        int s = w->species[i];
        if (w->flags[i] & SIM_GRAIN_FIXED)
            fixed[s] = i;
        else if (light[s] < 0 || w->mass[i] < w->mass[light[s]])
            light[s] = i;
    }
    for (int k = 0; k < g->count; ++k, ++count) {
        radius[count] = g->radius[k];
        species[count] = g->species ? g->species[k] : 0;
        flags[count] = g->flags ? (g->flags[k] & SIM_GRAIN_FIXED) : 0u;
    }
    for (int s = 0; s < SIM_MAX_SPECIES; ++s)
        for (int a = 0; a < 2; ++a) {
            int i = a ? fixed[s] : light[s];
            if (i < 0)
                continue;
            radius[count] = w->radius[i];
            species[count] = s;
            flags[count++] = a ? SIM_GRAIN_FIXED : 0u;
        }
    SimWorldDef d = w->def;
    d.grains = (SimGrainSet){.count = count, .radius = radius, .species = species, .flags = flags};
    d.wall_count = w->wall_count;
    d.walls = w->walls;
    d.time_step = w->dt;
    const SimTiming t = timing_of(&d);
    free(radius);
    free(species);
    free(flags);
    if (isfinite(t.stability_limit) && w->dt > t.stability_limit)
        return sim_fail(
            error, SIM_ERROR_INVALID, "grains",
            "the new grains and the grains in place make a pair whose stability limit %g "
            "s (contact time %g s) is below the time step %g s of %s: the run would blow "
            "up; choose a time step for every species from the start",
            t.stability_limit, t.contact_time_min, w->dt, sim_integrator_name(w->def.integrator));
    return SIM_OK;
}

void sim_world_grains_changed(SimWorld *w)
{
    for (int i = 0; i < w->count; ++i) /* never shrinks: a larger cell is always safe */
        w->max_radius = fmax(w->max_radius, w->radius[i]);
    if (w->skin_auto && w->mobile_count > 0) { /* the range follows the mobile grains' size */
        double diameter, mass;
        sim_world_means(w, &diameter, &mass);
        w->skin_max = SKIN_MAX_FRACTION * diameter;
        w->skin_min = SKIN_MIN_FRACTION * diameter;
        w->skin = fmin(fmax(w->skin, w->skin_min), w->skin_max);
        w->disp_limit2 = 0.25 * w->skin * w->skin;
    }
    w->cell_size = 2.0 * w->max_radius + w->skin_max;
    rebuild(w);
    reevaluate_forces(w);
}

/* The newcomers alone (positions, radii, species, walls), then against the grains in place
 * through a combined definition, and the grain bodies they join. */
static SimStatus check_newcomers(const SimWorld *w, const SimGrainSet *g, SimError *error)
{
    SimWorldDef check = w->def;
    check.grains = *g;
    check.wall_count = w->wall_count;
    check.walls = w->walls;
    check.time_step = w->dt;
    check.max_dt_fraction = 0.0;
    SimStatus s = sim_world_def_validate(&check, error);
    if (s == SIM_OK)
        s = sim_world_check_timing(w, g, error);
    if (s != SIM_OK)
        return s;
    char why[320];
    int body = 0;
    const char *join = sim_wall_bodies_join_problem(w, g, &body, why, sizeof why);
    if (join) {
        char f[64];
        snprintf(f, sizeof f, "bodies[%d]", body - w->wall_count);
        return sim_fail(error, SIM_ERROR_INVALID, f, "grain body %d: %s", body - w->wall_count,
                        join);
    }
    return SIM_OK;
}

/* No newcomer overlaps a grain in place by more than max_initial_overlap or takes its id. */
static SimStatus check_newcomers_fit(const SimWorld *w, const SimGrainSet *g, SimError *error)
{
    const double span = w->def.domain_x1 - w->def.domain_x0;
    for (int k = 0; k < g->count; ++k)
        for (int i = 0; i < w->count; ++i) {
            double dx = g->x[k] - w->x[i], dy = g->y[k] - w->y[i];
            if (w->effects & SIM_EFFECT_PERIODIC_X)
                dx -= span * floor(dx / span + 0.5);
            double d = sqrt(dx * dx + dy * dy), rs = g->radius[k] + w->radius[i];
            double ratio = (rs - d) / (2.0 * fmin(g->radius[k], w->radius[i]));
            if (ratio > w->def.max_initial_overlap) {
                char f[64];
                snprintf(f, sizeof f, "grains[%d]", k);
                return sim_fail(error, SIM_ERROR_INVALID, f,
                                "new grain %d overlaps grain %u by %.3g of the smaller diameter "
                                "(bound %g: max_initial_overlap)",
                                k, w->id[i], ratio, w->def.max_initial_overlap);
            }
        }
    for (int k = 0; k < g->count && g->id; ++k)
        for (int i = 0; i < w->count; ++i)
            if (w->id[i] == g->id[k]) {
                char f[64];
                snprintf(f, sizeof f, "grains[%d]", k);
                return sim_fail(error, SIM_ERROR_INVALID, f, "grain id %u is already in use",
                                g->id[k]);
            }
    return SIM_OK;
}

/* Writes the newcomers after the `old` grains in place (room reserved), with fresh ids above
 * the largest in place when the set has none. */
static void write_newcomers(SimWorld *w, const SimGrainSet *g, int old)
{
    uint32_t next_id = 0;
    for (int i = 0; i < w->count; ++i)
        next_id = w->id[i] >= next_id ? w->id[i] + 1 : next_id;
    for (int k = 0; k < g->count; ++k) {
        int i = old + k, fixed = g->flags && (g->flags[k] & SIM_GRAIN_FIXED);
        w->x[i] = w->x_base[i] = w->x_ref[i] = g->x[k];
        w->y[i] = w->y_base[i] = w->y_ref[i] = g->y[k];
        w->radius[i] = g->radius[k];
        w->vx[i] = g->vx && !fixed ? g->vx[k] : 0.0;
        w->vy[i] = g->vy && !fixed ? g->vy[k] : 0.0;
        w->angle[i] = g->angle ? g->angle[k] : 0.0;
        w->omega[i] = g->omega && !fixed ? g->omega[k] : 0.0;
        w->species[i] = g->species ? g->species[k] : 0;
        w->flags[i] = fixed ? SIM_GRAIN_FIXED : 0;
        w->motion[i] = g->motion ? g->motion[k] : -1;
        w->id[i] = g->id ? g->id[k] : next_id++;
        double m, inertia;
        sim_grain_mass_inertia(w->def.mass_model, w->def.materials[w->species[i]].density,
                               w->radius[i], &m, &inertia);
        w->mass[i] = m;
        w->inertia[i] = inertia;
        w->inv_mass[i] = fixed ? 0.0 : 1.0 / m;
        w->inv_inertia[i] = fixed || !w->rotation ? 0.0 : 1.0 / inertia;
        w->fx[i] = w->fy[i] = w->torque[i] = 0.0;
        for (int a = 0; a < w->scratch_count; ++a)
            w->scratch[a][i] = 0.0;
    }
}

/* The order that puts mobile grains first: old mobile, new mobile, old fixed, new fixed (the
 * newcomers at old .. total - 1). Returns the mobile count. */
static int mobile_first(const SimWorld *w, int old, int old_mobile, int total, int *order)
{
    int n = 0;
    for (int i = 0; i < old_mobile; ++i)
        order[n++] = i;
    for (int i = old; i < total; ++i)
        if (!(w->flags[i] & SIM_GRAIN_FIXED))
            order[n++] = i;
    int mobile = n;
    for (int i = old_mobile; i < old; ++i)
        order[n++] = i;
    for (int i = old; i < total; ++i)
        if (w->flags[i] & SIM_GRAIN_FIXED)
            order[n++] = i;
    return mobile;
}

SimStatus sim_world_add_grains(SimWorld *w, const SimGrainSet *g, SimError *error)
{
    if (g->count <= 0)
        return SIM_OK;
    SimStatus s = check_newcomers(w, g, error);
    if (s == SIM_OK)
        s = check_newcomers_fit(w, g, error);
    if (s != SIM_OK)
        return s;
    int old = w->count, old_mobile = w->mobile_count;
    if (sim_grains_reserve(w, old + g->count + 1) != 0)
        return sim_fail(error, SIM_ERROR_MEMORY, "grains", "out of memory adding %d grains",
                        g->count);
    /* Write the newcomers after the grains in place, then reorder. */
    write_newcomers(w, g, old);
    int total = old + g->count, *order = malloc((size_t)total * sizeof *order);
    if (!order) /* nothing changed yet: the newcomers lie beyond count */
        return sim_fail(error, SIM_ERROR_MEMORY, "grains", "out of memory adding %d grains",
                        g->count);
    int mobile = mobile_first(w, old, old_mobile, total, order);
    /* Contact history is keyed by ids: stash it before the indices move. */
    if (sim_neighbour_stash_history(w) != 0 || sim_grains_permute(w, order, total) != 0) {
        free(order); /* the world as it was (a stash, if made, holds the same history by ids) */
        return sim_fail(error, SIM_ERROR_MEMORY, "grains", "out of memory adding %d grains",
                        g->count);
    }
    free(order);
    w->count = total;
    w->mobile_count = mobile;
    sim_wall_bodies_join(w); /* a dormant grain body whose grains came moves from now on */
    sim_world_grains_changed(w);
    if (w->out_of_memory)
        return sim_fail(error, SIM_ERROR_MEMORY, "grains",
                        "out of memory in %s after adding grains", w->out_of_memory);
    return SIM_OK;
}

void sim_world_freeze(SimWorld *w)
{
    for (int i = 0; i < w->mobile_count; ++i)
        w->vx[i] = w->vy[i] = w->omega[i] = 0.0;
    reevaluate_forces(w);
    sim_integrator_start(w);
}

/* ------------------------------------------------------------------ guard */

/* The length of each snapshot array for `count` grains (at least 1, so that realloc never frees).
 */
static size_t snapshot_stride(int count)
{
    return (size_t)(count > 0 ? count : 1);
}

/* Copies grains [begin, end) of the world's w->count into the snapshot. */
static int snapshot_range(SimWorld *w, int begin, int end)
{
    const size_t n = snapshot_stride(w->count), count = (size_t)(end - begin);
    const double *src[7] = {w->x, w->y, w->vx, w->vy, w->angle, w->omega, w->radius};
    double *d = w->good.data;
    int *q = w->good.ints;
    for (int a = 0; a < 7; ++a)
        memcpy(d + (size_t)a * n + begin, src[a] + begin, count * sizeof *d);
    memcpy(q + begin, w->species + begin, count * sizeof *q);
    memcpy(q + n + begin, w->motion + begin, count * sizeof *q);
    memcpy(w->good.flags + begin, w->flags + begin, count * sizeof *w->good.flags);
    memcpy(w->good.ids + begin, w->id + begin, count * sizeof *w->good.ids);
    return 0;
}

/* The state the guard rolls back to, copied on the world's threads (a pass over every grain
 * array each guard_every steps: serial, it kept the other threads waiting). */
static void guard_snapshot(SimWorld *w)
{
    size_t n = snapshot_stride(w->count);
    double *d = realloc(w->good.data, 7 * n * sizeof *d);
    w->good.data = d ? d : w->good.data;
    int *q = realloc(w->good.ints, 2 * n * sizeof *q);
    w->good.ints = q ? q : w->good.ints;
    unsigned *flags = realloc(w->good.flags, n * sizeof *flags);
    w->good.flags = flags ? flags : w->good.flags;
    uint32_t *ids = realloc(w->good.ids, n * sizeof *ids);
    w->good.ids = ids ? ids : w->good.ids;
    if (!d || !q || !flags || !ids) { /* no snapshot: a failing guard then cannot roll back */
        w->good.valid = 0;
        return;
    }
    sim_parallel_ranges(w, snapshot_range, w->count, 8);
    w->good.count = w->count;
    w->good.mobile_count = w->mobile_count;
    w->good.time = w->time;
    w->good.step = w->step;
    w->good.valid = 1;
}

/* Puts the world back at the last good guard check (contact history restarts from zero). */
static void guard_restore(SimWorld *w)
{
    if (!w->good.valid)
        return;
    size_t n = snapshot_stride(w->good.count);
    const double *d = w->good.data;
    const int *q = w->good.ints;
    SimGrainSet g = {.count = w->good.count,
                     .x = d,
                     .y = d + n,
                     .vx = d + 2 * n,
                     .vy = d + 3 * n,
                     .angle = d + 4 * n,
                     .omega = d + 5 * n,
                     .radius = d + 6 * n,
                     .species = q,
                     .motion = q + n,
                     .flags = w->good.flags,
                     .id = w->good.ids};
    /* load_grains writes the world's arrays from the snapshot (separate storage); the capacity
     * holds the snapshot's grains already, so it cannot fail. */
    load_grains(w, &g);
    w->time = w->good.time;
    w->step = w->good.step;
    w->need_rebuild = 1;
    w->drop_history = 1; /* the old list refers to other indices */
    sim_world_forces_at(w, w->time);
    sim_integrator_start(w);
}

/* The likely cause of grain i's speed v for the guard's messages: a flow that gravity keeps
 * accelerating (grain i moves with the bulk, within twice its mean velocity, and no faster than
 * free fall since the guard's set-up from the initial and wall speeds), else `otherwise` (a
 * numerical blow-up). */
static void speed_cause(const SimWorld *w, int i, double v, const char *otherwise, char *out,
                        size_t size)
{
    double px = 0.0, py = 0.0, mass = 0.0;
    for (int k = 0; k < w->mobile_count; ++k) {
        px += w->mass[k] * w->vx[k];
        py += w->mass[k] * w->vy[k];
        mass += w->mass[k];
    }
    const double ux = mass > 0.0 ? px / mass : 0.0, uy = mass > 0.0 ? py / mass : 0.0;
    const double bulk = hypot(ux, uy), own = hypot(w->vx[i] - ux, w->vy[i] - uy);
    const double g = hypot(w->def.gravity_x, w->def.gravity_y), elapsed = w->time - w->guard_t0;
    const double free_fall = w->guard_free_speed + g * elapsed;
    if (g > 0.0 && v <= 1.01 * free_fall && own <= 2.0 * bulk)
        snprintf(out, size,
                 "likely cause: the flow accelerates without bound (the grains move together at "
                 "%.3g m/s, within free fall's %.3g m/s after %.3g s), not a blow-up: a chute "
                 "above its angle of repose or too little dissipation; tilt less, add friction "
                 "or stop earlier",
                 bulk, free_fall, elapsed);
    else
        snprintf(out, size, "%s", otherwise);
}

/* 1 when grain i (speed squared v2) has a non-finite state. */
static int grain_nonfinite(const SimWorld *w, int i, double v2)
{
    return !isfinite(w->x[i]) || !isfinite(w->y[i]) || !isfinite(v2) || !isfinite(w->omega[i]);
}

/* 1 when a grain of [begin, end) has a non-finite state or moves faster than the guard's bound. */
static int grains_unsound(SimWorld *w, int begin, int end)
{
    int bad = 0;
    for (int i = begin; i < end; ++i) {
        const double v2 = w->vx[i] * w->vx[i] + w->vy[i] * w->vy[i];
        bad |= grain_nonfinite(w, i, v2) || v2 > w->guard_speed2;
    }
    return bad;
}

/* The first unsound grain's failure (grains_unsound), SIM_OK when there is none. */
static SimStatus speed_failure(SimWorld *w, const char *cause, SimError *error)
{
    for (int i = 0; i < w->mobile_count; ++i) {
        double v2 = w->vx[i] * w->vx[i] + w->vy[i] * w->vy[i];
        if (grain_nonfinite(w, i, v2)) {
            sim_fail(error, SIM_ERROR_UNSTABLE, "grains",
                     "step %ld: grain %u has a non-finite state "
                     "(NaN or infinity); %s",
                     w->step, w->id[i], cause);
            error->step = w->step;
            error->grain = w->id[i];
            return SIM_ERROR_UNSTABLE;
        }
        if (v2 > w->guard_speed2) {
            char why[300], blowup[260];
            snprintf(blowup, sizeof blowup, "energy blow-up; %s", cause);
            speed_cause(w, i, sqrt(v2), blowup, why, sizeof why);
            sim_fail(error, SIM_ERROR_UNSTABLE, "grains",
                     "step %ld (t = %g s): grain %u at (%g, %g) moves at %g m/s, above the blow-up "
                     "bound %g m/s; %s",
                     w->step, w->time, w->id[i], w->x[i], w->y[i], sqrt(v2), sqrt(w->guard_speed2),
                     why);
            error->step = w->step;
            error->grain = w->id[i];
            return SIM_ERROR_UNSTABLE;
        }
    }
    return SIM_OK;
}

/* The guard's default likely cause: the time step against the stiffest, lightest pair's contact
 * time. Formatted only once a check has failed (it used to be at every check). */
static void time_step_cause(const SimWorld *w, char *out, size_t size)
{
    const SimTiming *t = &w->timing;
    snprintf(out, size,
             "likely cause: time step %g s is %.3g of the contact time %g s of the stiffest, "
             "lightest pair (%.3g steps per contact; stability limit %g s)",
             w->dt, w->dt / t->contact_time_min, t->contact_time_min, t->steps_per_contact,
             t->stability_limit);
}

/* The guard's two scans run on the world's threads as yes-or-no questions; only a failing one is
 * repeated on one thread to name the first (or worst) grain, so the messages do not depend on
 * the thread count either. */
static SimStatus guard_check(SimWorld *w, SimError *error)
{
    char cause[200];
    if (sim_parallel_ranges(w, grains_unsound, w->mobile_count, 8)) {
        time_step_cause(w, cause, sizeof cause);
        if (speed_failure(w, cause, error) != SIM_OK)
            return SIM_ERROR_UNSTABLE;
    }
    if (!sim_contacts_overlap_over_bound(w))
        return SIM_OK;
    time_step_cause(w, cause, sizeof cause);
    int oi, oj;
    const double worst = sim_contacts_worst_overlap(w, &oi, &oj);
    sim_fail(error, SIM_ERROR_UNSTABLE, "grains",
             "step %ld: grain %u overlaps %s%d by %.3g of the smaller diameter (bound %g); %s",
             w->step, w->id[oi], oj >= 0 ? "grain " : "wall ", oj >= 0 ? (int)w->id[oj] : -1 - oj,
             worst, w->def.guard_max_overlap, cause);
    error->step = w->step;
    error->grain = w->id[oi];
    return SIM_ERROR_UNSTABLE;
}

/* ------------------------------------------------------------------ stepping */

static SimStatus jump_failure(SimWorld *w, SimError *error)
{
    int i = w->jump_grain;
    double v = hypot(w->vx[i], w->vy[i]);
    char why[300], blowup[160];
    snprintf(blowup, sizeof blowup,
             "likely cause: time step %g s too large for this speed (impact too fast or energy "
             "blow-up)",
             w->dt);
    speed_cause(w, i, v, blowup, why, sizeof why);
    sim_fail(error, SIM_ERROR_UNSTABLE, "grains",
             "step %ld (t = %g s): grain %u at (%g, %g) moves %g m per step (%g m/s), over half "
             "its radius: contacts would be missed; %s",
             w->step, w->time, w->id[i], w->x[i], w->y[i], v * w->dt, v, why);
    error->step = w->step;
    error->grain = w->id[i];
    w->jump_grain = -1;
    return SIM_ERROR_UNSTABLE;
}

/* A pass inside a step or an edit ran out of memory (world->out_of_memory): the lists are empty,
 * so the state no longer follows the physics. Sticky: every later step reports it too. */
static SimStatus memory_failure(SimWorld *w, SimError *error)
{
    sim_integrator_finish(w);
    sim_fail(error, SIM_ERROR_MEMORY, "", "step %ld: out of memory in %s; the run cannot continue",
             w->step, w->out_of_memory);
    error->step = w->step;
    return SIM_ERROR_MEMORY;
}

SimStatus sim_world_step(SimWorld *w, long steps, SimError *error)
{
    SimError local;
    if (!error)
        error = &local;
    if (w->out_of_memory && steps > 0)
        return memory_failure(w, error);
    for (long s = 0; s < steps; ++s) {
        /* Nothing looks at the velocities between two steps of this loop unless the guard is
         * due: the closing kick can wait for the next step's opening loop. */
        w->defer_kick = s + 1 < steps && w->step + 1 < w->guard_next;
        w->integrate(w);
        if (w->bodies)
            sim_wall_bodies_step(w);
        ++w->step;
        w->time = w->def.start_time + (double)w->step * w->dt;
        if (w->out_of_memory)
            return memory_failure(w, error);
        if (w->jump_grain >= 0) {
            sim_integrator_finish(w);
            jump_failure(w, error);
            guard_restore(w);
            return SIM_ERROR_UNSTABLE;
        }
        if (w->step >= w->guard_next) {
            w->guard_next = w->step + w->def.guard_every;
            if (guard_check(w, error) != SIM_OK) {
                guard_restore(w);
                return SIM_ERROR_UNSTABLE;
            }
            guard_snapshot(w);
        }
    }
    return SIM_OK;
}

double sim_world_time(const SimWorld *w)
{
    return w->time;
}

long sim_world_step_count(const SimWorld *w)
{
    return w->step;
}

double sim_world_time_step(const SimWorld *w)
{
    return w->dt;
}

unsigned sim_world_effects(const SimWorld *w)
{
    return w->effects;
}

SimTiming sim_world_timing(const SimWorld *w)
{
    return w->timing;
}

int sim_world_grain_count(const SimWorld *w)
{
    return w->count;
}

int sim_world_mobile_count(const SimWorld *w)
{
    return w->mobile_count;
}

double sim_world_skin(const SimWorld *w)
{
    return w->skin;
}

long sim_world_list_builds(const SimWorld *w)
{
    return w->rebuilds;
}

long sim_world_list_entries(const SimWorld *w)
{
    return w->nl.start ? w->nl.start[w->mobile_count] : 0; /* start: capacity + 1 entries */
}
