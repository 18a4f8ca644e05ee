/* SPDX-License-Identifier: MIT */
/* bench_accuracy: what accuracy costs in time, for every integrator and a range of time steps
 * dt = t_c / n, n = steps per contact time (t_c of the stiffest, lightest pair, 000 eq. 3.22).
 *
 * Four measurements, each against the CPU time per simulated second:
 *   1. restitution and contact duration of a head-on impact of a grain on a fixed grain, no
 *      gravity, linear spring-dashpot with e_n given (000 eq. 3.25), clip_tensile = 0 so that the
 *      contact ends when the overlap returns to zero as in 000 eqs. 3.19-3.24. Errors against the
 *      analytic e_n and t_n = pi / omega_d (000 eqs. 3.22, 3.24). e_n = 0.2, 0.5 and 0.9.
 *   2. energy drift over 100 elastic bounces (e_n = 1) of a grain dropped on a fixed grain
 *      (000 §5.3.2 geometry), measured at the apex after the 100th bounce, relative to the
 *      bounce energy m g (h0 - h_contact).
 *   3. a reduced crater case (000 §4, a few hundred grains in a box of fixed grains): settle,
 *      sim_world_save, dig a rectangle, collapse for a fixed time; free-surface profile (highest
 *      grain top in bins of one mean diameter) and crater height (lowest point of the profile in
 *      the middle half) compared with a reference run (velocity Verlet at the smallest step).
 *
 * Cost: the crater runs measure process CPU time per simulated second (and wall time) directly.
 * The two-grain tests are overhead-bound, so their cost axis is modelled as the CPU time one grain
 * of the crater case needs per simulated second at the same n: cost per particle-step of that
 * integrator on the crater case (best crater run) x n / t_c(crater). Their own wall time is also
 * written (column direct_cpu_s_per_sim_s).
 *
 * Every integrator runs with the step onset (the default); velocity Verlet and symplectic Euler
 * also with the event-aware onset (SIM_ONSET_EVENT, docs/accuracy.md eqs. A1-A5), written as
 * integrator "velocity_verlet/event" and "symplectic_euler/event" in the CSV.
 *
 * A benchmark reports; it asserts nothing. Integrators whose stability limit is below t_c / n are
 * refused by sim_world_create: recorded as status "refused".
 *
 * Usage: bench_accuracy [--csv PATH] [--quick] [--collapse-time S] [--grains N]
 *                       [--crater-every K] */
#include "sim/sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Thesis 000 material and sizes (000 §4.3), e_n given instead of gamma_n. */
static const double r_max = 0.105;     /* m, boundary grains */
static const double r_med = 0.08;      /* m, mobile grains */
static const double density = 1190.0;  /* kg/m^3, sphere mass model */
static const double stiffness = 7e5;   /* N/m */
static const double gravity = 9.806;   /* m/s^2 */
static const double impact_speed = 1.; /* m/s, head-on test */

enum { MAX_N = 32, MAX_BINS = 256 };

typedef struct Options {
    const char *csv;
    int quick;
    double collapse_time; /* s */
    int grains;
    int crater_every; /* crater on every k-th n of the grid */
} Options;

typedef struct Outcome {
    const char *status; /* "ok", "refused", "unstable", "failed" */
    double measured;    /* observable */
    double error;       /* against analytic or reference */
    double cpu;         /* process CPU s of the run */
    double wall;        /* wall s of the run */
    double simulated;   /* simulated s */
    long steps;
    int mobile;
    double time_step; /* s */
    char note[160];
} Outcome;

/* The first INTEGRATOR_COUNT schemes are the integrators with the default onset, in
 * SimIntegrator order. */
enum { INTEGRATOR_COUNT = SIM_INTEGRATOR_COUNT };

/* A curve: an integrator and an onset option. */
typedef struct Scheme {
    SimIntegrator integrator;
    SimOnset onset;
    const char *name;
} Scheme;

static const Scheme schemes[] = {
    {SIM_INTEGRATOR_VELOCITY_VERLET, SIM_ONSET_STEP, "velocity_verlet"},
    {SIM_INTEGRATOR_SYMPLECTIC_EULER, SIM_ONSET_STEP, "symplectic_euler"},
    {SIM_INTEGRATOR_STORMER_VERLET, SIM_ONSET_STEP, "stormer_verlet"},
    {SIM_INTEGRATOR_GEAR, SIM_ONSET_STEP, "gear"},
    {SIM_INTEGRATOR_RK4, SIM_ONSET_STEP, "rk4"},
    {SIM_INTEGRATOR_VELOCITY_VERLET, SIM_ONSET_EVENT, "velocity_verlet/event"},
    {SIM_INTEGRATOR_SYMPLECTIC_EULER, SIM_ONSET_EVENT, "symplectic_euler/event"},
};

enum { SCHEME_COUNT = (int)(sizeof schemes / sizeof schemes[0]) };

static SimWorldDef base_def(double restitution, const Scheme *scheme)
{
    SimWorldDef def = sim_world_def_default();
    def.mass_model = SIM_MASS_SPHERE;
    def.integrator = scheme->integrator;
    def.contact.onset = scheme->onset;
    SimMaterial *m = &def.materials[0];
    m->density = density;
    m->normal_stiffness = stiffness;
    m->damping_mode = SIM_DAMPING_RESTITUTION;
    m->restitution = restitution;
    return def;
}

/* Creates the world with dt = t_c / n (t_c <= 0: sim's t_c,min of the stiffest, lightest pair),
 * or records why not. */
static SimWorld *create_at(SimWorldDef *def, double t_c, double n, Outcome *out)
{
    def->time_step = 0.0;
    SimTiming timing = sim_world_def_timing(def);
    def->time_step = (t_c > 0.0 ? t_c : timing.contact_time_min) / n;
    out->time_step = def->time_step;
    SimError err;
    SimWorld *w = sim_world_create(def, &err);
    if (!w) {
        out->status = "refused";
        snprintf(out->note, sizeof out->note, "stability limit %.4g s", timing.stability_limit);
    }
    return w;
}

static void fail_run(Outcome *out, const SimError *err)
{
    out->status = "unstable";
    snprintf(out->note, sizeof out->note, "step %ld", err->step);
}

/* ------------------------------------------------------------------ 1. head-on impact */

static double grain_x(SimWorld *w)
{
    SimFrame f;
    sim_world_frame(w, &f);
    return f.x[0];
}

/* Analytic contact time of a grain of radius r_med on a fixed grain (m_eff = m), 000 eqs.
 * 3.13-3.14, 3.22 with gamma_n from e_n (eq. 3.25); e_n = 1 gives pi / omega_n. */
static double impact_contact_time(double restitution)
{
    const double m = density * 4.0 / 3.0 * SIM_PI * r_med * r_med * r_med;
    const double omega = sqrt(stiffness / m), le = log(restitution);
    const double zeta = -le / sqrt(SIM_PI * SIM_PI + le * le);
    return SIM_PI / (omega * sqrt(1.0 - zeta * zeta));
}

static SimWorldDef impact_def(const Scheme *scheme, double restitution, double gap, double *gx,
                              double *gy, double *gr, double *gvx, unsigned *gflags)
{
    SimWorldDef def = base_def(restitution, scheme);
    def.gravity_y = 0.0;
    def.contact.clip_tensile = 0; /* overlap-defined end of contact, 000 eq. 3.23 */
    gx[0] = -(r_max + r_med + gap);
    gx[1] = 0.0;
    gy[0] = gy[1] = 0.0;
    gr[0] = r_med;
    gr[1] = r_max;
    gvx[0] = impact_speed;
    gvx[1] = 0.0;
    gflags[0] = 0u;
    gflags[1] = SIM_GRAIN_FIXED;
    def.grains =
        (SimGrainSet){.count = 2, .x = gx, .y = gy, .radius = gr, .vx = gvx, .flags = gflags};
    return def;
}

/* Grain of radius r_med at speed v0 onto a fixed grain of radius r_max: e and contact duration.
 * `phase` (fraction of a step) shifts the instant of first touch within a step. */
static void impact_once(const Scheme *scheme, double restitution, double n, double phase,
                        Outcome *e_out, Outcome *t_out)
{
    memset(e_out, 0, sizeof *e_out);
    e_out->status = "ok";
    const double t_c = impact_contact_time(restitution), dt_nominal = t_c / n;
    const double gap = 0.1 * r_med + phase * impact_speed * dt_nominal;
    double gx[2], gy[2], gr[2], gvx[2];
    unsigned gflags[2];
    SimWorldDef def = impact_def(scheme, restitution, gap, gx, gy, gr, gvx, gflags);
    SimWorld *w = create_at(&def, t_c, n, e_out);
    *t_out = *e_out;
    if (!w)
        return;
    const double dt = sim_world_time_step(w);
    const double contact = r_max + r_med; /* centre distance at touch, m */
    double xi_prev = -gap, t_in = NAN, t_out_s = NAN, x1 = NAN, t1 = NAN;
    long max_steps = (long)ceil(12.0 * t_c / dt) + 10;
    SimError err;
    double cpu0 = sim_clock_seconds(SIM_CLOCK_PROCESS), wall0 = sim_clock_seconds(SIM_CLOCK_WALL);
    for (long s = 0; s < max_steps; ++s) {
        if (sim_world_step(w, 1, &err) != SIM_OK) {
            fail_run(e_out, &err);
            *t_out = *e_out;
            sim_world_destroy(w);
            return;
        }
        double t = sim_world_time(w);
        double xi = contact - fabs(grain_x(w));
        /* Crossing times by linear interpolation between steps (sub-step accuracy). */
        if (isnan(t_in) && xi_prev <= 0.0 && xi > 0.0)
            t_in = t - dt * xi / (xi - xi_prev);
        else if (!isnan(t_in) && isnan(t_out_s) && xi_prev > 0.0 && xi <= 0.0)
            t_out_s = t - dt * xi / (xi - xi_prev);
        xi_prev = xi;
        /* Rebound speed from positions in free flight, [t_out + t_c, t_out + 2 t_c]: free of any
         * integrator start-up transient after the force switches off (Gear's higher
         * derivatives). Before the impact the flight is exact, so v_before = v0. */
        if (!isnan(t_out_s) && isnan(x1) && t >= t_out_s + t_c) {
            x1 = grain_x(w);
            t1 = t;
        }
        if (!isnan(x1) && t >= t1 + t_c) {
            double v_after = (grain_x(w) - x1) / (t - t1);
            e_out->measured = -v_after / impact_speed;
            break;
        }
    }
    double cpu = sim_clock_seconds(SIM_CLOCK_PROCESS) - cpu0,
           wall = sim_clock_seconds(SIM_CLOCK_WALL) - wall0;
    const long steps = sim_world_step_count(w);
    const double simulated = sim_world_time(w);
    sim_world_destroy(w);
    if (isnan(t_out_s) || e_out->measured == 0.0) {
        e_out->status = "failed";
        snprintf(e_out->note, sizeof e_out->note, "contact did not end");
        *t_out = *e_out;
        return;
    }
    /* 000 eqs. 3.22 and 3.24: with gamma_n from eq. 3.25 the analytic e is the e_n given. */
    e_out->error = fabs(e_out->measured - restitution);
    t_out->measured = t_out_s - t_in;
    t_out->error = fabs(t_out->measured - t_c) / t_c;
    e_out->cpu = t_out->cpu = cpu;
    e_out->wall = t_out->wall = wall;
    e_out->steps = t_out->steps = steps;
    e_out->simulated = t_out->simulated = simulated;
    e_out->mobile = t_out->mobile = 1;
}

enum { PHASES = 4 };

/* Worst error over PHASES x PHASES runs: the instant of first touch within a step (entry phase)
 * and the contact length n, n + 1/4, n + 1/2, n + 3/4 steps (exit phase relative to entry). A
 * force that switches on or off mid-step (the dashpot term jumps at touch and at separation when
 * clip_tensile = 0) leaves an error that depends on both phases; at integer n the two coincide and
 * can cancel by luck. measured = mean over the runs. */
static void impact(const Scheme *scheme, double restitution, double n, Outcome *e_out,
                   Outcome *t_out)
{
    double e_sum = 0.0, t_sum = 0.0, e_err = 0.0, t_err = 0.0;
    for (int q = 0; q < PHASES; ++q)
        for (int p = 0; p < PHASES; ++p) {
            Outcome e, t;
            impact_once(scheme, restitution, n + (double)q / PHASES, (double)p / PHASES, &e, &t);
            if (strcmp(e.status, "ok") != 0) {
                *e_out = e;
                *t_out = t;
                return;
            }
            e_sum += e.measured;
            t_sum += t.measured;
            e_err = fmax(e_err, e.error);
            t_err = fmax(t_err, t.error);
            if (p == 0 && q == 0) {
                *e_out = e;
                *t_out = t;
            }
        }
    e_out->measured = e_sum / (PHASES * PHASES);
    t_out->measured = t_sum / (PHASES * PHASES);
    e_out->error = e_err;
    t_out->error = t_err;
}

/* Direct cost of the two-grain run: the same run stepped in bulk, best of a few repeats. */
static double impact_cost(const Scheme *scheme, double restitution, double n)
{
    double gx[2], gy[2], gr[2], gvx[2];
    unsigned gflags[2];
    const double t_c = impact_contact_time(restitution);
    SimWorldDef def = impact_def(scheme, restitution, 0.1 * r_med, gx, gy, gr, gvx, gflags);
    double best = INFINITY;
    for (int r = 0; r < 3; ++r) {
        Outcome o = {0};
        SimWorld *w = create_at(&def, t_c, n, &o);
        if (!w)
            return NAN;
        long steps = (long)ceil(4.0 * n);
        SimError err;
        double c0 = sim_clock_seconds(SIM_CLOCK_PROCESS);
        SimStatus s = sim_world_step(w, steps, &err);
        double c = sim_clock_seconds(SIM_CLOCK_PROCESS) - c0;
        const double dt = sim_world_time_step(w);
        sim_world_destroy(w);
        if (s != SIM_OK)
            return NAN;
        best = fmin(best, c / ((double)steps * dt));
    }
    return best;
}

/* ------------------------------------------------------------------ 2. energy drift */

/* 100 elastic bounces of a grain dropped from h0 onto a fixed grain (000 §5.3.2, radii r_med on
 * r_max, fall height 0.32 m). Energy taken at the apex after the last bounce. */
static void bounces_once(const Scheme *scheme, double n, int count, double phase, Outcome *out)
{
    memset(out, 0, sizeof *out);
    out->status = "ok";
    SimWorldDef def = base_def(1.0, scheme);
    const double y_ground = 0.5, y_contact = y_ground + r_max + r_med;
    /* phase: touch-down shifted by a fraction of a step (2.505 m/s impact speed). */
    const double h0 = y_contact + 0.32 + phase * 2.505 * impact_contact_time(1.0) / n;
    const double gx[2] = {0.0, 0.0}, gy[2] = {h0, y_ground}, gr[2] = {r_med, r_max};
    const unsigned gflags[2] = {0u, SIM_GRAIN_FIXED};
    def.grains = (SimGrainSet){.count = 2, .x = gx, .y = gy, .radius = gr, .flags = gflags};
    SimWorld *w = create_at(&def, impact_contact_time(1.0), n, out);
    if (!w)
        return;
    double mass;
    double diameter;
    sim_world_means(w, &diameter, &mass);
    SimEnergy e0 = sim_world_energy(w);
    const double bounce_energy = e0.total - mass * gravity * y_contact;
    SimTiming timing = sim_world_timing(w);
    const long chunk = n >= 20.0 ? (long)(n / 10.0) : 1;
    const double period = 2.0 * sqrt(2.0 * (h0 - y_contact) / gravity) + impact_contact_time(1.0);
    const long max_steps = (long)((count + 2) * period / timing.time_step);
    int bounced = 0, in_contact = 0;
    SimError err;
    double cpu0 = sim_clock_seconds(SIM_CLOCK_PROCESS), wall0 = sim_clock_seconds(SIM_CLOCK_WALL);
    while (sim_world_step_count(w) < max_steps) {
        long k = bounced >= count ? 1 : chunk;
        if (sim_world_step(w, k, &err) != SIM_OK) {
            fail_run(out, &err);
            sim_world_destroy(w);
            return;
        }
        SimFrame f;
        sim_world_frame(w, &f);
        int touching = f.y[0] - y_contact < 0.0;
        if (in_contact && !touching)
            ++bounced;
        in_contact = touching;
        if (bounced >= count && !touching && f.vy[0] <= 0.0)
            break;
    }
    out->cpu = sim_clock_seconds(SIM_CLOCK_PROCESS) - cpu0;
    out->wall = sim_clock_seconds(SIM_CLOCK_WALL) - wall0;
    out->simulated = sim_world_time(w);
    out->steps = sim_world_step_count(w);
    out->mobile = 1;
    SimEnergy e1 = sim_world_energy(w);
    sim_world_destroy(w);
    if (bounced < count) {
        out->status = "failed";
        snprintf(out->note, sizeof out->note, "only %d bounces", bounced);
        return;
    }
    out->measured = (e1.total - mass * gravity * y_contact) / bounce_energy;
    out->error = fabs(e1.total - e0.total) / bounce_energy;
}

/* Worst drift over PHASES touch-down instants within a step; measured = mean. */
static void bounces(const Scheme *scheme, double n, int count, Outcome *out)
{
    double sum = 0.0, worst = 0.0;
    for (int p = 0; p < PHASES; ++p) {
        Outcome o;
        bounces_once(scheme, n, count, (double)p / PHASES, &o);
        if (strcmp(o.status, "ok") != 0) {
            *out = o;
            return;
        }
        if (p == 0)
            *out = o;
        sum += o.measured;
        worst = fmax(worst, o.error);
    }
    out->measured = sum / PHASES;
    out->error = worst;
}

/* ------------------------------------------------------------------ 3. reduced crater */

typedef struct Crater {
    char state_path[256];
    double width;    /* m, inner box */
    double surface;  /* m, settled free surface (median profile) */
    double x0, x1;   /* dug rectangle, m */
    double depth;    /* m */
    double diameter; /* mean mobile diameter, m */
    int bins;
    double bin_x0, bin_w;
    int grains;
} Crater;

static SimWorldDef crater_def(const Scheme *scheme)
{
    SimWorldDef def = base_def(0.5, scheme);
    def.effects = SIM_EFFECT_FRICTION; /* regularised Coulomb, 000 eq. 3.28, mu 0.5 */
    return def;
}

/* Free-surface profile: highest grain top (y + r) of mobile grains per bin. */
static void profile_of(SimWorld *w, const Crater *c, double *profile)
{
    SimFrame f;
    sim_world_frame(w, &f);
    for (int b = 0; b < c->bins; ++b)
        profile[b] = 0.0;
    for (int i = 0; i < f.mobile_count; ++i) {
        int b = (int)floor((f.x[i] - c->bin_x0) / c->bin_w);
        if (b < 0 || b >= c->bins)
            continue;
        profile[b] = fmax(profile[b], f.y[i] + f.radius[i]);
    }
}

static double crater_height(const Crater *c, const double *profile)
{
    double h = INFINITY;
    for (int b = c->bins / 4; b < c->bins - c->bins / 4; ++b)
        h = fmin(h, profile[b]);
    return h;
}

/* Rain, settle with velocity Verlet at 50 steps per contact, save. */
static int crater_prepare(Crater *c, int grains)
{
    const int columns = 25; /* box inner width in boundary diameters (000 containers 20-100p) */
    c->width = columns * 2.0 * r_max;
    c->grains = grains;
    SimGrainBuffer buffer;
    sim_grain_buffer_init(&buffer);
    sim_build_fixed_box(&buffer, 0.0, c->width, 0.0, 60 * r_max, r_max, 0);
    SimRainDef rain = sim_rain_def_thesis000(1.5 * r_max, c->width - 1.5 * r_max, 1.5 * r_max,
                                             200 * r_max, grains);
    SimRng rng;
    sim_rng_seed(&rng, 2018);
    sim_build_rain(&buffer, &rain, &rng);
    SimWorldDef def = crater_def(&schemes[0]);
    def.steps_per_contact = 50.0;
    def.grains = sim_grain_buffer_view(&buffer);
    SimError err;
    SimWorld *w = sim_world_create(&def, &err);
    sim_grain_buffer_free(&buffer);
    if (!w) {
        fprintf(stderr, "bench_accuracy: crater: %s: %s\n", err.field, err.message);
        return -1;
    }
    const double dt = sim_world_time_step(w);
    /* Settle: fall, then freeze twice to drain the residual motion. */
    for (int stage = 0; stage < 3; ++stage) {
        double seconds = stage == 0 ? 2.5 : 1.0;
        if (sim_world_step(w, (long)(seconds / dt), &err) != SIM_OK) {
            fprintf(stderr, "bench_accuracy: crater settle: %s\n", err.message);
            sim_world_destroy(w);
            return -1;
        }
        if (stage < 2)
            sim_world_freeze(w);
    }
    SimEnergy e = sim_world_energy(w);
    double mass;
    sim_world_means(w, &c->diameter, &mass);
    fprintf(stderr, "# crater: %d grains settled, kinetic energy per grain %.3g J\n",
            sim_world_mobile_count(w), e.kinetic / e.mobile);
    sim_world_freeze(w);
    snprintf(c->state_path, sizeof c->state_path, "/tmp/sablier-bench-accuracy-%ld.state",
             (long)getpid());
    if (sim_world_save(w, c->state_path, &err) != SIM_OK) {
        fprintf(stderr, "bench_accuracy: %s\n", err.message);
        sim_world_destroy(w);
        return -1;
    }
    c->bin_w = c->diameter;
    c->bin_x0 = r_max;
    c->bins = (int)floor((c->width - 2.0 * r_max) / c->bin_w);
    if (c->bins > MAX_BINS)
        c->bins = MAX_BINS;
    double profile[MAX_BINS], sorted[MAX_BINS];
    profile_of(w, c, profile);
    memcpy(sorted, profile, (size_t)c->bins * sizeof *sorted);
    for (int a = 0; a < c->bins; ++a) /* median surface, insertion sort */
        for (int b = a; b > 0 && sorted[b] < sorted[b - 1]; --b) {
            double t = sorted[b];
            sorted[b] = sorted[b - 1];
            sorted[b - 1] = t;
        }
    c->surface = sorted[c->bins / 2];
    /* A pit 7 d wide and 0.55 of the bed deep, centred (000 §4.5, H/L about 1). */
    c->depth = 0.55 * c->surface;
    c->x0 = 0.5 * c->width - 3.5 * c->diameter;
    c->x1 = 0.5 * c->width + 3.5 * c->diameter;
    sim_world_destroy(w);
    return 0;
}

static void crater_run(const Crater *c, const Scheme *scheme, double n, double seconds,
                       double *profile, Outcome *out)
{
    memset(out, 0, sizeof *out);
    out->status = "ok";
    SimGrainSet grains;
    SimWall *walls;
    int wall_count;
    double t0;
    SimError err;
    if (sim_state_load(c->state_path, &grains, &walls, &wall_count, &t0, &err) != SIM_OK) {
        out->status = "failed";
        snprintf(out->note, sizeof out->note, "%.150s", err.message);
        return;
    }
    SimWorldDef def = crater_def(scheme);
    def.grains = grains;
    def.walls = walls;
    def.wall_count = wall_count;
    def.start_time = t0;
    SimWorld *w = create_at(&def, 0.0, n, out);
    if (!w) {
        sim_grain_set_free(&grains);
        free(walls);
        return;
    }
    sim_world_remove_rect(w, c->x0, c->surface - c->depth, c->x1, c->surface + 10.0 * r_max);
    const double dt = sim_world_time_step(w);
    const long steps = (long)ceil(seconds / dt);
    out->mobile = sim_world_mobile_count(w);
    double cpu0 = sim_clock_seconds(SIM_CLOCK_PROCESS), wall0 = sim_clock_seconds(SIM_CLOCK_WALL);
    SimStatus s = sim_world_step(w, steps, &err);
    out->cpu = sim_clock_seconds(SIM_CLOCK_PROCESS) - cpu0;
    out->wall = sim_clock_seconds(SIM_CLOCK_WALL) - wall0;
    out->steps = steps;
    out->simulated = (double)steps * dt;
    if (s != SIM_OK)
        fail_run(out, &err);
    else
        profile_of(w, c, profile);
    sim_world_destroy(w);
    sim_grain_set_free(&grains);
    free(walls);
}

/* ------------------------------------------------------------------ output */

typedef struct Row {
    const char *test;
    const Scheme *scheme;
    double n;
    Outcome o;
    double model_cost; /* CPU s per simulated s per grain, crater-case model */
    double direct_cost;
} Row;

static Row *rows;
static int row_count, row_capacity;

static Row *add_row(const char *test, const Scheme *scheme, double n, const Outcome *o)
{
    if (row_count == row_capacity) {
        row_capacity = row_capacity ? 2 * row_capacity : 256;
        Row *p = realloc(rows, (size_t)row_capacity * sizeof *p);
        if (!p) {
            fprintf(stderr, "bench_accuracy: out of memory\n");
            exit(1);
        }
        rows = p;
    }
    Row *r = &rows[row_count++];
    *r = (Row){test, scheme, n, *o, NAN, NAN};
    return r;
}

static void progress(const char *test, const Scheme *scheme, double n, const Outcome *o)
{
    fprintf(stderr, "%-14s %-16s n %7.1f  %-8s error %-10.3g measured %-10.6g cpu %.3g s %s\n",
            test, scheme->name, n, o->status, o->error, o->measured, o->cpu, o->note);
}

/* Smallest n of the grid from which the error stays at or below target; 0 if none. */
static double n_for(const char *test, const Scheme *scheme, double target, double *cost)
{
    double best = 0.0;
    *cost = NAN;
    for (int k = row_count - 1; k >= 0; --k) { /* rows are in increasing n per integrator */
        const Row *r = &rows[k];
        if (strcmp(r->test, test) != 0 || r->scheme != scheme)
            continue;
        if (strcmp(r->o.status, "ok") != 0 || !(r->o.error <= target))
            break;
        best = r->n;
        *cost = r->model_cost;
    }
    return best;
}

/* The convergence law of the restitution error, |e - e_n| <= C / n^p over n in [30, 3000]: p the
 * least-squares order, C the envelope max(error n^p) (so the law bounds every measured point).
 * app/scene/advice.c stores these for `sablier check --target-error` and `time.target_error`. */
static void print_laws(void)
{
    static const char *const tests[3] = {"restitution_0.2", "restitution_0.5", "restitution_0.9"};
    printf("\nconvergence law of the restitution error: error <= C / n^p (n in [30, 3000]; p "
           "least squares, C envelope)\n| scheme | e_n | C | p |\n|---|---|---|---|\n");
    for (int i = 0; i < SCHEME_COUNT; ++i)
        for (int q = 0; q < 3; ++q) {
            double sx = 0, sy = 0, sxx = 0, sxy = 0;
            int m = 0;
            for (int pass = 0; pass < 2; ++pass) {
                double p = m >= 3 ? -(m * sxy - sx * sy) / (m * sxx - sx * sx) : (double)NAN,
                       c = 0.0;
                for (int k = 0; k < row_count; ++k) {
                    const Row *r = &rows[k];
                    if (strcmp(r->test, tests[q]) != 0 || r->scheme != &schemes[i] ||
                        strcmp(r->o.status, "ok") != 0 || r->n < 29.0 || r->n > 3100.0 ||
                        !(r->o.error > 0.0))
                        continue;
                    if (pass == 0) {
                        double lx = log(r->n), ly = log(r->o.error);
                        sx += lx;
                        sy += ly;
                        sxx += lx * lx;
                        sxy += lx * ly;
                        ++m;
                    } else {
                        c = fmax(c, r->o.error * pow(r->n, p));
                    }
                }
                if (pass == 1 && m >= 3)
                    printf("| %s | %s | %.3g | %.3f |\n", schemes[i].name, tests[q] + 12, c, p);
            }
        }
}

int main(int argc, char **argv)
{
    Options opt = {
        .csv = "accuracy.csv", .quick = 0, .collapse_time = 1.5, .grains = 400, .crater_every = 1};
    for (int a = 1; a < argc; ++a) {
        if (strcmp(argv[a], "--csv") == 0 && a + 1 < argc)
            opt.csv = argv[++a];
        else if (strcmp(argv[a], "--quick") == 0)
            opt.quick = 1;
        else if (strcmp(argv[a], "--collapse-time") == 0 && a + 1 < argc)
            opt.collapse_time = atof(argv[++a]);
        else if (strcmp(argv[a], "--grains") == 0 && a + 1 < argc)
            opt.grains = atoi(argv[++a]);
        else if (strcmp(argv[a], "--crater-every") == 0 && a + 1 < argc)
            opt.crater_every = atoi(argv[++a]) > 0 ? atoi(argv[a]) : 1;
        else {
            fprintf(stderr, "usage: bench_accuracy [--csv PATH] [--quick] [--collapse-time S] "
                            "[--grains N] [--crater-every K]\n");
            return 2;
        }
    }
    /* n: geometric series, 6 per decade (2 with --quick): 10..10^4 for the cheap two-grain
     * impacts (to reach e_n errors of 1e-4), 10..1000 for the bounces and the crater. */
    double ns[MAX_N];
    int n_count = 0, n_count_long = 0;
    const int per_decade = opt.quick ? 2 : 6;
    for (int k = 0; k <= 3 * per_decade; ++k) {
        ns[n_count++] = 10.0 * pow(10.0, (double)k / per_decade);
        if (k <= 2 * per_decade)
            n_count_long = n_count;
    }
    const double reference_n = opt.quick ? 1000.0 : 2000.0;

    /* 0. stability limits, as steps per contact: sim refuses dt above them. */
    for (int i = 0; i < INTEGRATOR_COUNT; ++i) {
        double gx[2], gy[2], gr[2], gvx[2];
        unsigned gflags[2];
        SimWorldDef def = impact_def(&schemes[i], 0.5, 0.1 * r_med, gx, gy, gr, gvx, gflags);
        SimTiming timing = sim_world_def_timing(&def);
        Outcome o = {.status = "ok", .time_step = timing.stability_limit};
        o.measured = impact_contact_time(0.5) / timing.stability_limit;
        snprintf(o.note, sizeof o.note, "smallest n accepted (worst pair: two mobile grains)");
        add_row("stability_limit", &schemes[i], o.measured, &o);
    }

    /* 1. head-on impacts */
    const double restitutions[3] = {0.2, 0.5, 0.9};
    const char *e_tests[3] = {"restitution_0.2", "restitution_0.5", "restitution_0.9"};
    const char *t_tests[3] = {"contact_time_0.2", "contact_time_0.5", "contact_time_0.9"};
    for (int q = 0; q < 3; ++q)
        for (int i = 0; i < SCHEME_COUNT; ++i)
            for (int k = 0; k < n_count; ++k) {
                Outcome e, t;
                impact(&schemes[i], restitutions[q], ns[k], &e, &t);
                double direct = strcmp(e.status, "ok") == 0
                                    ? impact_cost(&schemes[i], restitutions[q], ns[k])
                                    : (double)NAN;
                add_row(e_tests[q], &schemes[i], ns[k], &e)->direct_cost = direct;
                add_row(t_tests[q], &schemes[i], ns[k], &t)->direct_cost = direct;
                progress(e_tests[q], &schemes[i], ns[k], &e);
                progress(t_tests[q], &schemes[i], ns[k], &t);
            }

    /* 2. energy drift over 100 elastic bounces */
    const int bounce_count = opt.quick ? 20 : 100;
    for (int i = 0; i < SCHEME_COUNT; ++i)
        for (int k = 0; k < n_count_long; ++k) {
            Outcome o;
            bounces(&schemes[i], ns[k], bounce_count, &o);
            Row *r = add_row("energy_drift", &schemes[i], ns[k], &o);
            r->direct_cost = o.simulated > 0.0 ? o.cpu / o.simulated : (double)NAN;
            progress("energy_drift", &schemes[i], ns[k], &o);
        }

    /* 3. reduced crater */
    Crater crater;
    if (crater_prepare(&crater, opt.grains) != 0)
        return 1;
    double reference[MAX_BINS];
    Outcome ref;
    crater_run(&crater, &schemes[0], reference_n, opt.collapse_time, reference, &ref);
    if (strcmp(ref.status, "ok") != 0) {
        fprintf(stderr, "bench_accuracy: reference crater run %s (%s)\n", ref.status, ref.note);
        return 1;
    }
    const double h_ref = crater_height(&crater, reference);
    fprintf(stderr,
            "# crater: %d grains after digging, reference n %.0f, crater height %.3f d, "
            "surface %.3f d, cpu %.1f s\n",
            ref.mobile, reference_n, h_ref / crater.diameter, crater.surface / crater.diameter,
            ref.cpu);
    ref.measured = h_ref / crater.diameter;
    Row *rr = add_row("crater_reference", &schemes[0], reference_n, &ref);
    rr->direct_cost = ref.cpu / ref.simulated / ref.mobile;
    /* Chaos floor: the reference again with dt changed by 1 part in 10^9. Any difference from the
     * reference is the divergence of nearby trajectories, not integration error. */
    {
        double profile[MAX_BINS];
        Outcome o;
        crater_run(&crater, &schemes[0], reference_n * (1.0 + 1e-9), opt.collapse_time, profile,
                   &o);
        if (strcmp(o.status, "ok") == 0) {
            double worst = 0.0;
            for (int b = 0; b < crater.bins; ++b)
                worst = fmax(worst, fabs(profile[b] - reference[b]));
            o.error = worst / crater.diameter;
            o.measured = crater_height(&crater, profile) / crater.diameter;
            snprintf(o.note, sizeof o.note, "reference with dt x (1 + 1e-9); measured = height");
            Row *r = add_row("profile_chaos_floor", &schemes[0], reference_n, &o);
            r->direct_cost = o.cpu / o.simulated / o.mobile;
            Outcome h = o;
            h.error = fabs(o.measured - h_ref / crater.diameter);
            r = add_row("crater_height_chaos_floor", &schemes[0], reference_n, &h);
            r->direct_cost = o.cpu / o.simulated / o.mobile;
            fprintf(stderr, "# crater chaos floor: profile %.3g d, height %.3g d\n", o.error,
                    h.error);
        }
    }
    double cost_pps[SCHEME_COUNT]; /* CPU s per particle-step, best crater run */
    for (int i = 0; i < SCHEME_COUNT; ++i)
        cost_pps[i] = INFINITY;
    cost_pps[0] = ref.cpu / ((double)ref.steps * ref.mobile);
    double crater_tc;
    {
        SimWorldDef def = crater_def(&schemes[0]);
        SimGrainSet g;
        SimWall *walls;
        int wc;
        double t0;
        SimError err;
        sim_state_load(crater.state_path, &g, &walls, &wc, &t0, &err);
        def.grains = g;
        crater_tc = sim_world_def_timing(&def).contact_time_min;
        sim_grain_set_free(&g);
        free(walls);
    }
    for (int i = 0; i < SCHEME_COUNT; ++i)
        for (int k = 0; k < n_count_long; k += opt.crater_every) {
            double profile[MAX_BINS];
            Outcome o;
            crater_run(&crater, &schemes[i], ns[k], opt.collapse_time, profile, &o);
            Outcome h = o;
            double rms = NAN;
            if (strcmp(o.status, "ok") == 0) {
                double worst = 0.0, sum2 = 0.0;
                for (int b = 0; b < crater.bins; ++b) {
                    double d = fabs(profile[b] - reference[b]);
                    worst = fmax(worst, d);
                    sum2 += d * d;
                }
                o.error = worst / crater.diameter;
                rms = sqrt(sum2 / crater.bins) / crater.diameter;
                o.measured = NAN;
                h.measured = crater_height(&crater, profile) / crater.diameter;
                h.error = fabs(h.measured - h_ref / crater.diameter);
                double pps = o.cpu / ((double)o.steps * o.mobile);
                cost_pps[i] = fmin(cost_pps[i], pps);
            }
            double cost = o.simulated > 0.0 ? o.cpu / o.simulated / o.mobile : (double)NAN;
            Row *r = add_row("profile", &schemes[i], ns[k], &o);
            r->direct_cost = r->model_cost = cost;
            r = add_row("crater_height", &schemes[i], ns[k], &h);
            r->direct_cost = r->model_cost = cost;
            Outcome m = o;
            m.error = rms;
            r = add_row("profile_rms", &schemes[i], ns[k], &m);
            r->direct_cost = r->model_cost = cost;
            progress("profile", &schemes[i], ns[k], &o);
            progress("crater_height", &schemes[i], ns[k], &h);
        }
    remove(crater.state_path);

    /* Cost model for the two-grain tests: crater cost per particle-step x n / t_c(crater). */
    for (int k = 0; k < row_count; ++k) {
        Row *r = &rows[k];
        const int i = (int)(r->scheme - schemes);
        if (isnan(r->model_cost) && isfinite(cost_pps[i]) && strcmp(r->o.status, "ok") == 0)
            r->model_cost = cost_pps[i] * r->n / crater_tc;
    }

    char tmp[1024];
    snprintf(tmp, sizeof tmp, "%s.tmp", opt.csv);
    FILE *f = fopen(tmp, "w");
    if (!f) {
        perror(tmp);
        return 3;
    }
    fprintf(f, "test,integrator,default,steps_per_contact,time_step_s,status,measured,error,"
               "cpu_s_per_sim_s_grain,direct_cpu_s_per_sim_s,cpu_s,wall_s,simulated_s,steps,"
               "mobile,note\n");
    for (int k = 0; k < row_count; ++k) {
        const Row *r = &rows[k];
        fprintf(f, "%s,%s,%d,%.6g,%.6g,%s,%.10g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%ld,%d,\"%s\"\n",
                r->test, r->scheme->name, r->scheme == &schemes[0], r->n, r->o.time_step,
                r->o.status, r->o.measured, r->o.error, r->model_cost, r->direct_cost, r->o.cpu,
                r->o.wall, r->o.simulated, r->o.steps, r->o.mobile, r->o.note);
    }
    if (fclose(f) != 0 || rename(tmp, opt.csv) != 0) {
        perror(opt.csv);
        return 3;
    }

    /* Summary: what an error of 1e-2, 1e-3, 1e-4 in e_n (e_n = 0.5) costs. */
    printf("# crater case: %d grains, t_c,min %.4g s; CPU per particle-step (best run):",
           ref.mobile, crater_tc);
    for (int i = 0; i < SCHEME_COUNT; ++i)
        printf(" %s %.1f ns", schemes[i].name, 1e9 * cost_pps[i]);
    printf("\n");
    const char *summary_tests[4] = {"restitution_0.2", "restitution_0.5", "restitution_0.9",
                                    "contact_time_0.5"};
    for (int q = 0; q < 4; ++q) {
        printf("\n%s: smallest n (steps per contact) with error <= target from there on, and "
               "CPU s per simulated s per grain\n",
               summary_tests[q]);
        printf("| integrator | 1e-2 | 1e-3 | 1e-4 |\n|---|---|---|---|\n");
        for (int i = 0; i < SCHEME_COUNT; ++i) {
            printf("| %s |", schemes[i].name);
            for (int p = 2; p <= 4; ++p) {
                double cost, n = n_for(summary_tests[q], &schemes[i], pow(10.0, -p), &cost);
                if (n > 0.0)
                    printf(" n = %.0f, %.2g s |", n, cost);
                else
                    printf(" > %.0f |", ns[n_count - 1]);
            }
            printf("\n");
        }
    }

    /* Observed order: least-squares slope of log(error) against log(n) over n in [30, 3000]. */
    const char *order_tests[6] = {"restitution_0.2",  "restitution_0.5",  "restitution_0.9",
                                  "contact_time_0.5", "contact_time_0.9", "energy_drift"};
    printf("\nobserved order (-slope of log error vs log n, n in [30, 3000])\n");
    printf("| integrator |");
    for (int q = 0; q < 6; ++q)
        printf(" %s |", order_tests[q]);
    printf("\n|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < SCHEME_COUNT; ++i) {
        printf("| %s |", schemes[i].name);
        for (int q = 0; q < 6; ++q) {
            double sx = 0, sy = 0, sxx = 0, sxy = 0;
            int m = 0;
            for (int k = 0; k < row_count; ++k) {
                const Row *r = &rows[k];
                if (strcmp(r->test, order_tests[q]) != 0 || r->scheme != &schemes[i] ||
                    strcmp(r->o.status, "ok") != 0 || r->n < 29.0 || r->n > 3100.0 ||
                    !(r->o.error > 0.0))
                    continue;
                double lx = log(r->n), ly = log(r->o.error);
                sx += lx;
                sy += ly;
                sxx += lx * lx;
                sxy += lx * ly;
                ++m;
            }
            if (m >= 3)
                printf(" %.2f |", -(m * sxy - sx * sy) / (m * sxx - sx * sx));
            else
                printf(" - |");
        }
        printf("\n");
    }
    print_laws();
    free(rows);
    return 0;
}
