/* SPDX-License-Identifier: MIT */
/* sim_test_util.h: small helpers shared by the physics tests (tests/sim/test_*.c).
 * Everything is `static inline` so that a test file using only part of it compiles warning-free. */
#ifndef SIM_TEST_UTIL_H
#define SIM_TEST_UTIL_H

#include "sim/sim.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define TPI 3.14159265358979323846
#define G0  9.806 /* 000 ch. 3: g = 9.806 m/s^2 */

/* Mass and moment of inertia of the two mass models (sim.h SimMassModel). */
static inline double tu_mass(SimMassModel model, double density, double radius)
{
    if (model == SIM_MASS_SPHERE)
        return density * 4.0 / 3.0 * TPI * radius * radius * radius;
    return density * TPI * radius * radius;
}

static inline double tu_inertia(SimMassModel model, double density, double radius)
{
    double m = tu_mass(model, density, radius);
    return (model == SIM_MASS_SPHERE ? 0.4 : 0.5) * m * radius * radius;
}

/* A definition with one species, no friction, no gravity, linear law, damping given as gamma. */
static inline SimWorldDef tu_def(double density, double stiffness, double dt)
{
    SimWorldDef def = sim_world_def_default();
    def.species_count = 1;
    def.materials[0] = sim_material_default();
    def.materials[0].density = density;
    def.materials[0].normal_stiffness = stiffness;
    def.materials[0].damping_mode = SIM_DAMPING_GAMMA;
    def.materials[0].normal_damping = 0.0;
    def.materials[0].friction = 0.0;
    def.contact.normal = SIM_NORMAL_LINEAR;
    def.contact.tangential = SIM_TANGENTIAL_NONE;
    def.contact.rolling = SIM_ROLLING_OFF;
    def.gravity_x = 0.0;
    def.gravity_y = 0.0;
    def.time_step = dt;
    def.max_dt_fraction = 0.0;
    def.guard_max_speed = 1e3;
    return def;
}

/* Create from a grain buffer, printing the error on failure. */
static inline SimWorld *tu_create(SimWorldDef *def, const SimGrainBuffer *buffer)
{
    SimError err;
    def->grains = sim_grain_buffer_view(buffer);
    SimWorld *w = sim_world_create(def, &err);
    if (!w)
        fprintf(stderr, "sim_world_create: %s: %s\n", err.field, err.message);
    return w;
}

/* Step, printing the error on failure; returns 0 on success. */
static inline int tu_step(SimWorld *w, long steps)
{
    SimError err;
    SimStatus s = sim_world_step(w, steps, &err);
    if (s != SIM_OK) {
        fprintf(stderr, "sim_world_step: status %d at step %ld: %s: %s\n", (int)s, err.step,
                err.field, err.message);
        return 1;
    }
    return 0;
}

/* A rain of up to `count` grains of mean radius `radius` (8 % polydisperse) on a lattice of
 * pitch radius `pitch` over [0.1, 1.9] x [y0, 1.8], m. */
static inline void tu_rain(SimGrainBuffer *b, uint64_t seed, double y0, double radius, double pitch,
                           int count)
{
    SimRainDef rd;
    memset(&rd, 0, sizeof rd);
    rd.x0 = 0.1;
    rd.x1 = 1.9;
    rd.y0 = y0;
    rd.y1 = 1.8;
    rd.radius_mean = radius;
    rd.polydispersity = 0.08;
    rd.pitch_radius = pitch;
    rd.column_gap = 0.005 * rd.pitch_radius;
    rd.row_gap = 0.75 * rd.pitch_radius;
    rd.column_jitter = 0.05;
    rd.row_jitter = 0.08;
    rd.max_count = count;
    SimRng rng;
    sim_rng_seed(&rng, seed);
    sim_grain_buffer_init(b);
    sim_build_rain(b, &rd, &rng);
}

/* 150 grains of radius 0.05 m +- 8 % rained (000 §6.1 lattice) into x in [0.1, 1.9] m from height
 * y0 up to 1.8 m, with `seed`: the small polydisperse set of the determinism and golden tests. */
static inline void tu_rain_150(SimGrainBuffer *b, uint64_t seed, double y0)
{
    tu_rain(b, seed, y0, 0.05, 0.054, 150);
}

/* Frame index of the grain with stable id `id`, or -1. */
static inline int tu_index(const SimFrame *f, uint32_t id)
{
    for (int k = 0; k < f->count; ++k)
        if (f->id[k] == id)
            return k;
    return -1;
}

/* Linear spring-dashpot analytics (000 eqs. 3.13-3.25). */
static inline double tu_gamma_from_e(double e, double m_eff, double k)
{
    /* eq. 3.25 with t_n from eq. 3.22 solved together: gamma = -2 ln e sqrt(m k / (pi^2 + ln^2 e))
     */
    double l = log(e);
    return -2.0 * l * sqrt(m_eff * k / (TPI * TPI + l * l));
}

/* Tolerance on e_n measured with t_n/dt = steps: the dashpot force jumps by gamma v when a
 * contact opens and closes, and velocity Verlet's damping sees the half-step velocity, so e_n
 * carries an O(gamma dt / m_eff) = O(|ln e| dt / t_n) relative error whose coefficient depends on
 * where the contact starts within a step (measured worst case over phases: 1 to 2.8). */
static inline double tu_e_tol(double e, double steps)
{
    return 4.0 * fabs(log(e)) / steps;
}

static inline double tu_contact_time(double m_eff, double k, double gamma)
{
    double w2 = k / m_eff - (gamma / (2.0 * m_eff)) * (gamma / (2.0 * m_eff));
    return TPI / sqrt(w2); /* eq. 3.22 */
}

/* Restitution with the attractive part clipped: the pair separates freely once
 * k xi + gamma xidot reaches 0 (000 eqs. 3.19-3.20 evaluated at that instant). */
static inline double tu_e_clipped(double e, double m_eff, double k)
{
    double gamma = tu_gamma_from_e(e, m_eff, k);
    double wn = sqrt(k / m_eff);
    double zeta = gamma / (2.0 * m_eff * wn);
    double wd = wn * sqrt(1.0 - zeta * zeta);
    double phase = TPI - atan2(2.0 * zeta * sqrt(1.0 - zeta * zeta), 1.0 - 2.0 * zeta * zeta);
    double t1 = phase / wd;
    double xidot = exp(-zeta * wn * t1) * (wd * cos(wd * t1) - zeta * wn * sin(wd * t1)) / wd;
    return -xidot; /* per unit impact speed */
}

/* ---------------------------------------------------------------- head-on collision harness */

enum { TU_PAIR = 0, TU_FIXED = 1, TU_WALL = 2 };

/* A head-on collision along x without gravity: grain 0 (radius r0) moves at +v towards grain 1
 * (radius r1, mobile for TU_PAIR, fixed for TU_FIXED) or towards a vertical SimWall (TU_WALL). */
typedef struct TuCollision {
    int kind;
    double r0, r1;
    double v;         /* approach speed, m/s */
    double gap_steps; /* initial gap in units of v dt (sets the phase of the first contact step) */
    long max_steps;
} TuCollision;

typedef struct TuCollisionResult {
    double e;          /* -(relative normal velocity after) / (before) */
    double t_contact;  /* duration of positive overlap, zero crossings interpolated, s */
    double peak_force; /* largest F_n in the frame contact list, N */
    double min_force;  /* smallest F_n in the frame contact list, N */
    double t_start;    /* time of first positive overlap (interpolated), s */
    long steps_in_contact;
} TuCollisionResult;

/* Runs the collision in a world built from `def` (gravity, integrator, materials taken from it).
 * Returns 0 on success. */
static inline int tu_collide(SimWorldDef def, const TuCollision *c, TuCollisionResult *out)
{
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    double dt = def.time_step;
    double gap = c->gap_steps * c->v * dt;
    int g0 = sim_grain_buffer_add(&b, 0.0, 0.0, c->r0, 0, 0u, -1);
    b.vx[g0] = c->v;
    SimWall wall = {.x0 = c->r0 + gap, .y0 = -1.0, .x1 = c->r0 + gap, .y1 = 1.0, .motion = -1};
    if (c->kind == TU_WALL) {
        def.wall_count = 1;
        def.walls = &wall;
    } else {
        sim_grain_buffer_add(&b, c->r0 + c->r1 + gap, 0.0, c->r1, 0,
                             c->kind == TU_FIXED ? (unsigned)SIM_GRAIN_FIXED : 0u, -1);
    }
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    if (!w)
        return 1;
    TuCollisionResult r = {0.0, 0.0, -1e300, 1e300, -1.0, 0};
    double prev = -gap, t_in = -1.0;
    int done = 0;
    SimFrame f;
    for (long s = 0; s < c->max_steps && !done; ++s) {
        if (tu_step(w, 1)) {
            sim_world_destroy(w);
            return 1;
        }
        sim_world_frame(w, &f);
        int i0 = tu_index(&f, 0), i1 = c->kind == TU_WALL ? -1 : tu_index(&f, 1);
        double xi =
            c->kind == TU_WALL ? c->r0 - (wall.x0 - f.x[i0]) : c->r0 + c->r1 - (f.x[i1] - f.x[i0]);
        for (int k = 0; k < f.contact_count; ++k) {
            if (f.contacts[k].normal_force > r.peak_force)
                r.peak_force = f.contacts[k].normal_force;
            if (f.contacts[k].normal_force < r.min_force)
                r.min_force = f.contacts[k].normal_force;
        }
        if (prev <= 0.0 && xi > 0.0 && t_in < 0.0) {
            t_in = f.time - dt + dt * (-prev) / (xi - prev);
            r.t_start = t_in;
        }
        if (xi > 0.0)
            r.steps_in_contact++;
        if (t_in >= 0.0 && prev > 0.0 && xi <= 0.0) {
            double t_out = f.time - dt + dt * prev / (prev - xi);
            r.t_contact = t_out - t_in;
            /* multistep schemes (Gear) relax their stored derivatives for a few steps after the
             * force vanishes: read the velocities a while later */
            if (tu_step(w, 200)) {
                sim_world_destroy(w);
                return 1;
            }
            sim_world_frame(w, &f);
            i0 = tu_index(&f, 0);
            i1 = c->kind == TU_WALL ? -1 : tu_index(&f, 1);
            double v0 = f.vx[i0], v1 = c->kind == TU_PAIR ? f.vx[i1] : 0.0;
            r.e = (v1 - v0) / c->v;
            done = 1;
        }
        prev = xi;
    }
    sim_world_destroy(w);
    if (!done) {
        fprintf(stderr, "tu_collide: contact did not end within %ld steps\n", c->max_steps);
        return 1;
    }
    *out = r;
    return 0;
}

/* ---------------------------------------------------------------- random packings */

/* x distance with the minimum-image convention when period > 0. */
static inline double tu_dx(double a, double b, double period)
{
    double d = a - b;
    if (period > 0.0) {
        d = fmod(d, period);
        if (d > 0.5 * period)
            d -= period;
        else if (d < -0.5 * period)
            d += period;
    }
    return d;
}

/* Adds up to `n` grains with radii drawn from `radii` (cycled) at random positions in
 * [x0, x1) x [y0, y1), rejecting any placement whose overlap with a grain already in the buffer
 * exceeds `max_overlap` times the smaller diameter (0: no overlap). Returns the number added. */
static inline int tu_random_grains(SimGrainBuffer *b, SimRng *rng, int n, const double *radii,
                                   int radius_count, double x0, double x1, double y0, double y1,
                                   double period, double max_overlap)
{
    int added = 0, first = 0;
    for (int k = 0; k < n; ++k) {
        double r = radii[k % radius_count];
        for (int attempt = 0; attempt < 2000; ++attempt) {
            double x = x0 + (x1 - x0) * sim_rng_uniform(rng);
            double y = y0 + r + (y1 - y0 - 2.0 * r) * sim_rng_uniform(rng);
            int ok = 1;
            for (int j = first; j < b->count && ok; ++j) {
                double dx = tu_dx(x, b->x[j], period), dy = y - b->y[j];
                double d = sqrt(dx * dx + dy * dy);
                double xi = r + b->radius[j] - d;
                double dmin = 2.0 * (r < b->radius[j] ? r : b->radius[j]);
                if (xi > max_overlap * dmin)
                    ok = 0;
            }
            if (ok) {
                sim_grain_buffer_add(b, x, y, r, 0, 0u, -1);
                ++added;
                break;
            }
        }
    }
    return added;
}

#endif
