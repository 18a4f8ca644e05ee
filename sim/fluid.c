/* SPDX-License-Identifier: MIT */
/* fluid.c: the horizontally averaged 1D fluid column of thesis 002 ch. 6 and its coupling to the
 * grains (drag and buoyancy through a SimBodyForce).
 *
 * Grid: `cells` layers of height h between y0 and y1, velocities at layer centres, stresses at
 * faces. Per unit bed area, layer k obeys (002 eq. 33a with the grain force written per unit
 * volume of mixture, which keeps the momentum budget exact):
 *
 *     rho_f (1 - phi_k) h du_k/dt = tau_{k+1/2} - tau_{k-1/2} + h (source_k - rate_k u_k)
 *     tau = rho_f (nu + l^2 |g|) g,  g = du/dy                                   (002 eqs. 35-36)
 *
 * with u = 0 at y0 (wall half a layer below the first centre) and tau = rho_f u*^2 at y1.
 * Time stepping is backward Euler, fully implicit: the mixing-length stress is linearised by
 * Newton, tau ~ rho_f (nu + 2 l^2 |g_o|) g - rho_f l^2 |g_o| g_o, and iterated to convergence in
 * each step; this reaches the steady law even at huge steps (a plain lagged viscosity
 * oscillates there) and keeps start-ups monotone (a single linearised solve does not). The thesis
 * used an explicit scheme (002 eq. 39) whose step limit dy^2 / (2 (nu + nu_t)) falls below the
 * DEM step at small Galileo numbers (notes 002 §7.11); this scheme has none.
 *
 * Coupling: the body-force stage advances the fluid to the force-evaluation time, then gives each
 * grain the drag of the area-weighted fluid velocity over the layers it covers, and hands the
 * reaction back per layer as an implicit rate (so a stiff drag cannot make the fluid overshoot
 * either). */
#include "sim/sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* 1 - phi never below this: a layer packed full of grains keeps a little fluid inertia. */
#define MIN_FLUID_FRACTION   0.02
/* Newton iterations per turbulent step (2-4 are typical at DEM steps). */
#define SIM_FLUID_NEWTON_MAX 30
/* Largest velocity change per step a drag may impose, as a fraction of the slip. */
#define DRAG_STEP_CAP        (2.0 / 3.0)
/* Layer weights kept per grain. */
#define WEIGHTS_MAX          64

struct SimFluid {
    SimFluidDef def;
    int n;
    double h;
    double time;
    double u_star;
    double bed_level;
    double *y, *u, *phi, *stress, *grain_force, *grain_velocity;
    /* grain coupling recorded at the last force evaluation, used by the next step */
    double *rate, *source, *phi_next, *area_v, *area;
    /* Thomas work arrays */
    double *a, *b, *c, *r, *u_old, *u_next;
    double last_eval; /* time of the last force evaluation, s (NAN before the first) */
    double limit_dt;  /* dt of the drag limiter, s */
    int coupled;      /* 1 once a force evaluation recorded grains */
};

SimFluidDef sim_fluid_def_default(void)
{
    SimFluidDef d;
    memset(&d, 0, sizeof d);
    d.y0 = 0.0;
    d.y1 = 1.0;
    d.cells = 100;
    d.width = 1.0;
    d.depth = 1.0;
    d.density = 1.0;
    d.viscosity = 1.0;
    d.shear_velocity = 0.0;
    d.turbulent = 0;
    d.kappa = 0.4;
    d.van_driest = 26.0;
    d.bed_fraction = 0.4;
    d.drag_c_inf = 0.5;
    d.drag_reynolds = 24.0;
    d.buoyancy = 1;
    d.gravity_x = 0.0;
    d.gravity_y = -9.806;
    d.geometry = SIM_FLUID_DISK;
    d.time_step = 0.0;
    d.drag_limit = 1;
    return d;
}

static SimStatus invalid(SimError *e, const char *field, const char *message)
{
    if (e) {
        e->status = SIM_ERROR_INVALID;
        snprintf(e->field, sizeof e->field, "%s", field);
        snprintf(e->message, sizeof e->message, "%s", message);
        e->step = -1;
        e->grain = -1;
    }
    return SIM_ERROR_INVALID;
}

SimStatus sim_fluid_def_validate(const SimFluidDef *d, SimError *e)
{
    if (!(isfinite(d->y0) && isfinite(d->y1) && d->y1 > d->y0))
        return invalid(e, "fluid.y1", "the fluid column needs y1 > y0");
    if (d->cells < 2 || d->cells > 1000000)
        return invalid(e, "fluid.cells", "the fluid column needs 2 to 1000000 layers");
    if (!(d->width > 0.0 && isfinite(d->width)))
        return invalid(e, "fluid.width", "the bed width must be > 0");
    if (!(d->depth > 0.0 && isfinite(d->depth)))
        return invalid(e, "fluid.depth", "the slice depth must be > 0");
    if (!(d->density > 0.0 && isfinite(d->density)))
        return invalid(e, "fluid.density", "the fluid density must be > 0");
    if (!(d->viscosity > 0.0 && isfinite(d->viscosity)))
        return invalid(e, "fluid.viscosity", "the viscosity must be > 0");
    if (!(d->shear_velocity >= 0.0 && isfinite(d->shear_velocity)))
        return invalid(e, "fluid.shear_velocity", "the shear velocity must be >= 0");
    if (d->turbulent && !(d->kappa > 0.0 && d->van_driest > 0.0))
        return invalid(e, "fluid.kappa", "kappa and the van Driest constant must be > 0");
    if (!(d->bed_fraction > 0.0 && d->bed_fraction <= 1.0))
        return invalid(e, "fluid.bed_fraction", "bed_fraction must be in (0, 1]");
    if (!(d->drag_c_inf >= 0.0 && d->drag_reynolds >= 0.0 &&
          d->drag_c_inf + d->drag_reynolds > 0.0))
        return invalid(e, "fluid.drag_c_inf",
                       "the drag law needs C_inf >= 0, R_c >= 0, not both 0");
    if (d->geometry != SIM_FLUID_DISK && d->geometry != SIM_FLUID_SPHERE)
        return invalid(e, "fluid.geometry", "unknown geometry");
    if (!(d->time_step >= 0.0 && isfinite(d->time_step)))
        return invalid(e, "fluid.time_step", "time_step must be >= 0");
    return SIM_OK;
}

SimFluid *sim_fluid_create(const SimFluidDef *def, SimError *error)
{
    if (sim_fluid_def_validate(def, error) != SIM_OK)
        return NULL;
    SimFluid *f = calloc(1, sizeof *f);
    if (!f) {
        invalid(error, "", "out of memory");
        return NULL;
    }
    f->def = *def;
    f->n = def->cells;
    f->h = (def->y1 - def->y0) / def->cells;
    f->u_star = def->shear_velocity;
    f->bed_level = def->y0;
    f->last_eval = NAN;
    f->limit_dt = def->time_step;
    size_t n = (size_t)f->n;
    double **arrays[] = {&f->y,     &f->u,      &f->phi,      &f->grain_force, &f->grain_velocity,
                         &f->rate,  &f->source, &f->phi_next, &f->area_v,      &f->area,
                         &f->a,     &f->b,      &f->c,        &f->r,           &f->u_old,
                         &f->u_next};
    for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; ++k)
        if (!(*arrays[k] = calloc(n, sizeof(double)))) {
            sim_fluid_destroy(f);
            invalid(error, "", "out of memory");
            return NULL;
        }
    if (!(f->stress = calloc(n + 1, sizeof(double)))) {
        sim_fluid_destroy(f);
        invalid(error, "", "out of memory");
        return NULL;
    }
    for (int k = 0; k < f->n; ++k)
        f->y[k] = def->y0 + (k + 0.5) * f->h;
    f->stress[f->n] = def->density * f->u_star * f->u_star;
    return f;
}

void sim_fluid_destroy(SimFluid *f)
{
    if (!f)
        return;
    free(f->y);
    free(f->u);
    free(f->phi);
    free(f->stress);
    free(f->grain_force);
    free(f->grain_velocity);
    free(f->rate);
    free(f->source);
    free(f->phi_next);
    free(f->area_v);
    free(f->area);
    free(f->a);
    free(f->b);
    free(f->c);
    free(f->r);
    free(f->u_old);
    free(f->u_next);
    free(f);
}

const SimFluidDef *sim_fluid_def(const SimFluid *f)
{
    return &f->def;
}

double sim_fluid_time(const SimFluid *f)
{
    return f->time;
}

void sim_fluid_set_velocity(SimFluid *f, const double *u)
{
    memcpy(f->u, u, (size_t)f->n * sizeof(double));
}

void sim_fluid_set_shear_velocity(SimFluid *f, double shear_velocity)
{
    f->u_star = shear_velocity;
    f->def.shear_velocity = shear_velocity;
}

/* The arrays of the state, n doubles each (stress: n + 1, last). */
#define FLUID_SCALARS 6
#define FLUID_ARRAYS  15

static void fluid_arrays(const SimFluid *f, double **out)
{
    double *arrays[FLUID_ARRAYS] = {f->u,    f->phi,    f->grain_force, f->grain_velocity,
                                    f->rate, f->source, f->phi_next,    f->area_v,
                                    f->area, f->a,      f->b,           f->c,
                                    f->r,    f->u_old,  f->u_next};
    memcpy(out, arrays, sizeof arrays);
}

long sim_fluid_state_count(const SimFluid *f)
{
    return FLUID_SCALARS + (long)FLUID_ARRAYS * f->n + f->n + 1;
}

void sim_fluid_get_state(const SimFluid *f, double *state)
{
    double *arrays[FLUID_ARRAYS];
    fluid_arrays(f, arrays);
    const double scalars[FLUID_SCALARS] = {f->time,      f->u_star,   f->bed_level,
                                           f->last_eval, f->limit_dt, (double)f->coupled};
    memcpy(state, scalars, sizeof scalars);
    state += FLUID_SCALARS;
    for (int k = 0; k < FLUID_ARRAYS; ++k, state += f->n)
        memcpy(state, arrays[k], (size_t)f->n * sizeof *state);
    memcpy(state, f->stress, (size_t)(f->n + 1) * sizeof *state);
}

void sim_fluid_set_state(SimFluid *f, const double *state)
{
    double *arrays[FLUID_ARRAYS];
    fluid_arrays(f, arrays);
    f->time = state[0];
    f->u_star = state[1];
    f->def.shear_velocity = state[1];
    f->bed_level = state[2];
    f->last_eval = state[3];
    f->limit_dt = state[4];
    f->coupled = (int)state[5];
    state += FLUID_SCALARS;
    for (int k = 0; k < FLUID_ARRAYS; ++k, state += f->n)
        memcpy(arrays[k], state, (size_t)f->n * sizeof *state);
    memcpy(f->stress, state, (size_t)(f->n + 1) * sizeof *state);
}

/* Prandtl mixing length with van Driest damping (002 eq. 37). */
static double mixing_length(const SimFluidDef *d, double u_star, double bed, double y)
{
    if (!d->turbulent || y <= bed)
        return 0.0;
    double z = y - bed;
    return d->kappa * z * (1.0 - exp(-z * u_star / (d->viscosity * d->van_driest)));
}

/* y_b: top of the highest layer whose solid fraction reaches bed_fraction (y0 when none). */
static double find_bed(const SimFluid *f, const double *phi)
{
    if (!phi)
        return f->def.y0;
    for (int k = f->n - 1; k >= 0; --k)
        if (phi[k] >= f->def.bed_fraction)
            return f->def.y0 + (k + 1) * f->h;
    return f->def.y0;
}

/* Fluid stress at the faces from the current velocities (bottom face: wall half a layer below). */
static void compute_stress(SimFluid *f)
{
    const SimFluidDef *d = &f->def;
    const double rho = d->density, h = f->h;
    f->stress[0] = rho * d->viscosity * f->u[0] / (0.5 * h);
    for (int k = 1; k < f->n; ++k) {
        double g = (f->u[k] - f->u[k - 1]) / h;
        double l = mixing_length(d, f->u_star, f->bed_level, d->y0 + k * h);
        f->stress[k] = rho * (d->viscosity + l * l * fabs(g)) * g;
    }
    f->stress[f->n] = rho * f->u_star * f->u_star;
}

/* One linear solve of backward Euler with the mixing-length stress linearised around the
 * iterate `it` (velocities at the start of the step in f->u_old); result in `out`. */
static void solve_linearised(SimFluid *f, double dt, const double *phi, const double *rate,
                             const double *source, const double *it, double *out)
{
    const SimFluidDef *d = &f->def;
    const int n = f->n;
    const double rho = d->density, h = f->h, nu = d->viscosity;
    double *a = f->a, *b = f->b, *c = f->c, *r = f->r;
    /* Face k+1/2 between layers k and k+1 is face index k+1 (at y0 + (k+1) h). */
    double d_lo = 2.0 * rho * nu / h, e_lo = 0.0; /* bottom face: no slip, l = 0 */
    for (int k = 0; k < n; ++k) {
        double fluid = 1.0 - (phi ? phi[k] : 0.0);
        if (fluid < MIN_FLUID_FRACTION)
            fluid = MIN_FLUID_FRACTION;
        double m = rho * fluid * h / dt;
        double rk = rate ? rate[k] : 0.0, sk = source ? source[k] : 0.0;
        double d_hi = 0.0, e_hi = 0.0;
        if (k < n - 1) {
            double g = (it[k + 1] - it[k]) / h;
            double l = mixing_length(d, f->u_star, f->bed_level, d->y0 + (k + 1) * h);
            double lg = l * l * fabs(g);
            d_hi = rho * (nu + 2.0 * lg) / h; /* Newton: tau(g) ~ tau(g_o) + tau'(g_o) (g - g_o) */
            e_hi = rho * lg * g;
        }
        a[k] = -d_lo;
        c[k] = -d_hi;
        b[k] = m + d_lo + d_hi + h * rk;
        r[k] = m * f->u_old[k] - e_hi + e_lo + h * sk;
        if (k == n - 1)
            r[k] += rho * f->u_star * f->u_star; /* imposed top stress */
        d_lo = d_hi;
        e_lo = e_hi;
    }
    /* Thomas algorithm (diagonally dominant: b > |a| + |c|). */
    for (int k = 1; k < n; ++k) {
        double w = a[k] / b[k - 1];
        b[k] -= w * c[k - 1];
        r[k] -= w * r[k - 1];
    }
    out[n - 1] = r[n - 1] / b[n - 1];
    for (int k = n - 2; k >= 0; --k)
        out[k] = (r[k] - c[k] * out[k + 1]) / b[k];
}

void sim_fluid_step(SimFluid *f, double dt, const double *phi, const double *rate,
                    const double *source)
{
    const int n = f->n;
    if (!(dt > 0.0))
        return;
    f->bed_level = find_bed(f, phi);
    memcpy(f->u_old, f->u, (size_t)n * sizeof(double));
    /* Fully implicit (the nonlinear backward-Euler equations solved by Newton iterations): the
     * converged step keeps the comparison principle of the exact equation, so a start-up never
     * overshoots, whatever dt; one linearised solve alone can (the tangent of the convex stress
     * lies below it). Laminar: one solve is exact. */
    int iterations = f->def.turbulent ? SIM_FLUID_NEWTON_MAX : 1;
    for (int it = 0; it < iterations; ++it) {
        solve_linearised(f, dt, phi, rate, source, f->u, f->u_next);
        double change = 0.0, size = 0.0;
        for (int k = 0; k < n; ++k) {
            change = fmax(change, fabs(f->u_next[k] - f->u[k]));
            size = fmax(size, fabs(f->u_next[k]));
        }
        memcpy(f->u, f->u_next, (size_t)n * sizeof(double));
        if (change <= 1e-13 * size)
            break;
    }
    for (int k = 0; k < n; ++k) {
        f->phi[k] = phi ? phi[k] : 0.0;
        /* the force on the grains as the fluid saw it: exact steady budget */
        f->grain_force[k] = (rate ? rate[k] : 0.0) * f->u[k] - (source ? source[k] : 0.0);
    }
    f->time += dt;
    compute_stress(f);
}

void sim_fluid_profile(const SimFluid *f, SimFluidProfile *p)
{
    p->cells = f->n;
    p->y0 = f->def.y0;
    p->dy = f->h;
    p->y = f->y;
    p->u = f->u;
    p->solid_fraction = f->phi;
    p->stress = f->stress;
    p->grain_force = f->grain_force;
    p->grain_velocity = f->grain_velocity;
    p->bed_level = f->bed_level;
    p->time = f->time;
}

double sim_fluid_velocity_at(const SimFluid *f, double y)
{
    double s = (y - f->def.y0) / f->h - 0.5;
    if (s <= 0.0) {
        /* between the wall (u = 0 at y0) and the first centre */
        double t = (y - f->def.y0) / (0.5 * f->h);
        return t <= 0.0 ? 0.0 : t * f->u[0];
    }
    int k = (int)s;
    if (k >= f->n - 1)
        return f->u[f->n - 1];
    double t = s - k;
    return (1.0 - t) * f->u[k] + t * f->u[k + 1];
}

double sim_fluid_explicit_limit(const SimFluid *f)
{
    const SimFluidDef *d = &f->def;
    double nu_max = d->viscosity;
    for (int k = 1; k < f->n; ++k) {
        double g = (f->u[k] - f->u[k - 1]) / f->h;
        double l = mixing_length(d, f->u_star, f->bed_level, d->y0 + k * f->h);
        /* the linearised diffusivity of tau(g) is nu + 2 l^2 |g| */
        double nu_k = d->viscosity + 2.0 * l * l * fabs(g);
        nu_max = nu_k > nu_max ? nu_k : nu_max;
    }
    return f->h * f->h / (2.0 * nu_max);
}

double sim_fluid_drag_coefficient(const SimFluidDef *d, double reynolds)
{
    double s = sqrt(d->drag_c_inf) + sqrt(d->drag_reynolds / reynolds);
    return s * s;
}

/* Inline min/max: fmin/fmax are library calls here (no -ffast-math). */
static inline double max2(double a, double b)
{
    return a > b ? a : b;
}

static inline double min2(double a, double b)
{
    return a < b ? a : b;
}

/* The fluid advanced to `time` with the coupling recorded at the last evaluation. */
static void advance_to(SimFluid *f, double time)
{
    if (isfinite(f->last_eval) && time > f->last_eval) {
        double dt = time - f->last_eval;
        f->limit_dt = dt;
        sim_fluid_step(f, dt, f->coupled ? f->phi_next : NULL, f->coupled ? f->rate : NULL,
                       f->coupled ? f->source : NULL);
    } else if (!isfinite(f->last_eval)) {
        f->time = time;
    }
    if (!isfinite(f->last_eval) || time > f->last_eval)
        f->last_eval = time;
}

/* The span of layer k that a grain at height yc of radius r covers, and in *half_chord the half
 * chord at the middle of that span. */
static double layer_span(const SimFluidDef *d, double h, int k, double yc, double r,
                         double *half_chord)
{
    double a = max2(d->y0 + k * h, yc - r), b = min2(d->y0 + (k + 1) * h, yc + r);
    double m = 0.5 * (a + b) - yc;
    *half_chord = sqrt(max2(r * r - m * m, 0.0));
    return b - a;
}

/* The drag coefficient coef (kg/s) of a grain of diameter dia and mass m at relative speed
 * `speed`: F = coef (u - v), 002 eqs. 23-25, limited to an exact relaxation over one step. */
static double drag_coefficient(const SimFluid *f, double speed, double dia, double mass)
{
    const SimFluidDef *d = &f->def;
    /* C_d |du| = (sqrt(C_inf |du|) + sqrt(R_c nu / d))^2: finite as |du| -> 0 */
    double s = sqrt(d->drag_c_inf * speed) + sqrt(d->drag_reynolds * d->viscosity / dia);
    double frontal = d->geometry == SIM_FLUID_SPHERE ? 0.25 * SIM_PI * dia * dia : dia;
    double coef = 0.5 * d->density * frontal * s * s; /* 002 eqs. 23-25 */
    if (d->drag_limit && f->limit_dt > 0.0 && mass > 0.0) {
        /* exact relaxation over one step: no overshoot however small tau_p = m / coef */
        double x = coef * f->limit_dt / mass;
        if (x > 1e-8) {
            /* Velocity Verlet hands the stage a predicted velocity v_half + a dt / 2; with
             * c = coef dt / m that recursion has eigenvalues of (1 - 3c/2) +- ..., one negative
             * and reaching -1 as c -> 1. Capping c at 2/3 keeps both within 0.58. */
            double c = -expm1(-x);
            coef = mass * (c < DRAG_STEP_CAP ? c : DRAG_STEP_CAP) / f->limit_dt;
        }
    }
    return coef;
}

/* The body-force stage (see sim.h). */
static void fluid_apply(void *context, const SimBodyForceView *view)
{
    SimFluid *f = context;
    const SimFluidDef *d = &f->def;
    const int n = f->n;
    const double h = f->h, rho = d->density;
    const double layer_volume = d->width * h * d->depth;
    /* 1. advance the fluid to this evaluation with the coupling recorded at the last one */
    advance_to(f, view->time);
    /* 2. drag and buoyancy on every grain; the reaction per layer */
    memset(f->phi_next, 0, (size_t)n * sizeof(double));
    memset(f->rate, 0, (size_t)n * sizeof(double));
    memset(f->source, 0, (size_t)n * sizeof(double));
    memset(f->area_v, 0, (size_t)n * sizeof(double));
    memset(f->area, 0, (size_t)n * sizeof(double));
    const double g_x = d->gravity_x, g_y = d->gravity_y;
    for (int i = 0; i < view->count; ++i) {
        const double yc = view->y[i], r = view->radius[i], dia = 2.0 * r;
        const double area = SIM_PI * r * r;
        /* area-weighted fluid velocity over the layers the grain covers */
        int k0 = (int)floor((yc - r - d->y0) / h), k1 = (int)floor((yc + r - d->y0) / h);
        double inside = 0.0, uw = 0.0;
        int lo = k0 < 0 ? 0 : k0, hi = k1 >= n ? n - 1 : k1;
        /* The grain's area in each layer: chord at the middle of the covered span times the
         * span (one sqrt per layer instead of the exact segment areas' acos), rescaled so the
         * layers of a grain inside the column sum to its area exactly. Kept for the reaction
         * below; grains spanning more than WEIGHTS_MAX layers recompute. */
        double weights[WEIGHTS_MAX], raw = 0.0;
        for (int k = k0; k <= k1; ++k) {
            double half, span = layer_span(d, h, k, yc, r, &half), chord = 2.0 * half;
            raw += chord * span;
        }
        double scale = raw > 0.0 ? area / raw : 0.0;
        for (int k = lo; k <= hi; ++k) {
            double half, span = layer_span(d, h, k, yc, r, &half);
            double w = scale * 2.0 * half * span;
            if (k - lo < WEIGHTS_MAX)
                weights[k - lo] = w;
            inside += w;
            uw += w * f->u[k];
        }
        /* the part outside the column sees the top velocity above it, still fluid below it */
        double u_f;
        if (inside > 1e-12 * area)
            u_f = (uw + (area - inside) * (k1 >= n ? f->u[n - 1] : 0.0)) / area;
        else
            u_f = yc > d->y0 ? f->u[n - 1] : 0.0;
        double rel_x = u_f - view->vx[i], rel_y = -view->vy[i];
        double speed = sqrt(rel_x * rel_x + rel_y * rel_y);
        const double mass = view->mass[i];
        double coef = drag_coefficient(f, speed, dia, mass);
        view->fx[i] += coef * rel_x;
        view->fy[i] += coef * rel_y;
        if (d->buoyancy) {
            double volume = d->geometry == SIM_FLUID_SPHERE ? area * dia * (2.0 / 3.0) : area;
            view->fx[i] -= rho * volume * g_x;
            view->fy[i] -= rho * volume * g_y;
        }
        /* reaction: f_k += w_k / A (coef v - coef u_k) / V_layer, implicit in u_k */
        for (int k = lo; k <= hi; ++k) {
            double w;
            if (k - lo < WEIGHTS_MAX) {
                w = weights[k - lo];
            } else {
                double half, span = layer_span(d, h, k, yc, r, &half);
                w = scale * 2.0 * half * span;
            }
            double share = w / area;
            f->rate[k] += share * coef / layer_volume;
            f->source[k] += share * coef * view->vx[i] / layer_volume;
            f->phi_next[k] += w / (d->width * h);
            f->area_v[k] += w * view->vx[i];
            f->area[k] += w;
        }
    }
    for (int k = 0; k < n; ++k)
        f->grain_velocity[k] = f->area[k] > 0.0 ? f->area_v[k] / f->area[k] : 0.0;
    f->coupled = 1;
}

SimBodyForce sim_fluid_body_force(SimFluid *fluid)
{
    SimBodyForce b = {fluid_apply, fluid};
    return b;
}

/* du/dy of the steady law: (nu + l^2 |g|) g = u*^2 -> g = 2 u*^2 / (nu + sqrt(nu^2 + 4 l^2 u*^2))
 */
static double steady_gradient(const SimFluidDef *d, double bed, double y)
{
    double l = mixing_length(d, d->shear_velocity, bed, y);
    double us2 = d->shear_velocity * d->shear_velocity;
    return 2.0 * us2 / (d->viscosity + sqrt(d->viscosity * d->viscosity + 4.0 * l * l * us2));
}

void sim_fluid_steady_reference(const SimFluidDef *d, double bed, const double *y, int count,
                                double *u)
{
    for (int j = 0; j < count; ++j) {
        if (y[j] <= bed) {
            u[j] = 0.0;
            continue;
        }
        /* RK4 on u' = g(y) from the bed, steps of at most 1/1000 of the column */
        double span = y[j] - bed;
        double step_max = (d->y1 - d->y0) / 1000.0;
        int steps = (int)ceil(span / step_max);
        if (steps < 8)
            steps = 8;
        double dy = span / steps, v = 0.0, yy = bed;
        for (int s = 0; s < steps; ++s) {
            double k1 = steady_gradient(d, bed, yy);
            double k2 = steady_gradient(d, bed, yy + 0.5 * dy);
            double k4 = steady_gradient(d, bed, yy + dy);
            v += dy * (k1 + 4.0 * k2 + k4) / 6.0; /* k3 = k2: the right side does not depend on u */
            yy = bed + (s + 1) * dy;
        }
        u[j] = v;
    }
}
