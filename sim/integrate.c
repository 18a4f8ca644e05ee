/* SPDX-License-Identifier: MIT */
/* integrate.c: the integrators' scratch arrays and start state, and the linear stability limit of
 * each, used to refuse unstable time steps at set-up. Their steps are sim/isa/integrate_pass.c
 * (compiled once per instruction set).
 *
 * Every step computes all forces before any grain moves on (the thesis's sequential update is
 * not reproduced: 000 notes §2.1). Gravity is added here, fused into the kick. */
#include "integrate_scratch.h"

#include <math.h>
#include <string.h>

int sim_integrator_scratch_count(SimIntegrator integrator, int rotation)
{
    switch (integrator) {
    case SIM_INTEGRATOR_VELOCITY_VERLET:
        return rotation ? VV_ARRAYS : VV_OMEGA_HALF;
    case SIM_INTEGRATOR_STORMER_VERLET:
        return STORMER_ARRAYS;
    case SIM_INTEGRATOR_GEAR:
        return rotation ? GEAR_ARRAYS : GEAR_ALPHA;
    case SIM_INTEGRATOR_RK4:
        return rotation ? RK4_ARRAYS : RK4_ANGLE0;
    default: /* symplectic Euler keeps nothing */
        return 0;
    }
}

/* Applies a deferred closing kick with the world's instruction set (sim/isa/integrate_pass.c). */
void sim_integrator_finish(SimWorld *w)
{
    w->kernels->integrator_finish(w);
}

/* Initial integrator state from the forces at the start (create and after a state reload). */
void sim_integrator_start(SimWorld *w)
{
    const int n = w->mobile_count;
    const double dt = w->dt, gx = w->def.gravity_x, gy = w->def.gravity_y;
    if (w->def.integrator == SIM_INTEGRATOR_STORMER_VERLET) {
        double *xp = w->scratch[STORMER_X_PREV], *yp = w->scratch[STORMER_Y_PREV];
        for (int i = 0; i < n; ++i) { /* Taylor start: x_prev = x - v dt + a dt^2 / 2 */
            double ax = w->fx[i] * w->inv_mass[i] + gx, ay = w->fy[i] * w->inv_mass[i] + gy;
            xp[i] = w->x[i] - w->vx[i] * dt + 0.5 * ax * dt * dt;
            yp[i] = w->y[i] - w->vy[i] * dt + 0.5 * ay * dt * dt;
        }
    } else if (w->def.integrator == SIM_INTEGRATOR_GEAR) {
        double *ax = w->scratch[GEAR_AX], *ay = w->scratch[GEAR_AY];
        double *bx = w->scratch[GEAR_BX], *by = w->scratch[GEAR_BY];
        for (int i = 0; i < n; ++i) {
            ax[i] = w->fx[i] * w->inv_mass[i] + gx;
            ay[i] = w->fy[i] * w->inv_mass[i] + gy;
            bx[i] = by[i] = 0.0;
        }
        if (w->rotation) {
            double *aw = w->scratch[GEAR_ALPHA], *bw = w->scratch[GEAR_BETA];
            for (int i = 0; i < n; ++i) {
                aw[i] = w->torque[i] * w->inv_inertia[i];
                bw[i] = 0.0;
            }
        }
    }
}

/* ------------------------------------------------------------------ linear stability */

/* One step of each integrator on the damped oscillator x'' = -w^2 x - 2 z w x' (h = w dt, time in
 * units of 1/w), written on a state vector so the amplification matrix can be formed. */
static void oscillator_step(SimIntegrator integrator, double h, double z, const double in[4],
                            double out[4])
{
#define ACC(x, v) (-(x)-2.0 * z * (v))
    double x = in[0], v = in[1];
    switch (integrator) {
    case SIM_INTEGRATOR_VELOCITY_VERLET: {
        /* state (x, v, a); damping on the predicted velocity */
        double a = in[2];
        double vh = v + 0.5 * h * a;
        double xn = x + h * vh;
        double an = ACC(xn, vh + 0.5 * h * a);
        out[0] = xn;
        out[1] = vh + 0.5 * h * an;
        out[2] = an;
        out[3] = 0.0;
        break;
    }
    case SIM_INTEGRATOR_SYMPLECTIC_EULER:
    case SIM_INTEGRATOR_STORMER_VERLET: {
        /* Both reduce to leapfrog with the damping on the lagged (half-step) velocity:
         * state (x_n, v_{n-1/2}). */
        double vn = v + h * ACC(x, v);
        out[0] = x + h * vn;
        out[1] = vn;
        out[2] = out[3] = 0.0;
        break;
    }
    case SIM_INTEGRATOR_GEAR: {
        double a = in[2], b = in[3];
        double xp = x + v * h + a * h * h / 2.0 + b * h * h * h / 6.0;
        double vp = v + a * h + b * h * h / 2.0;
        double ap = a + b * h;
        double da = ACC(xp, vp) - ap;
        out[0] = xp + da * h * h / 12.0;
        out[1] = vp + da * h * 5.0 / 12.0;
        out[2] = ap + da;
        out[3] = b + da / h;
        break;
    }
    case SIM_INTEGRATOR_RK4: {
        double k1x = v, k1v = ACC(x, v);
        double k2x = v + 0.5 * h * k1v, k2v = ACC(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
        double k3x = v + 0.5 * h * k2v, k3v = ACC(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
        double k4x = v + h * k3v, k4v = ACC(x + h * k3x, v + h * k3v);
        out[0] = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        out[1] = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        out[2] = out[3] = 0.0;
        break;
    }
    default:
        memset(out, 0, 4 * sizeof *out);
    }
#undef ACC
}

/* Spectral radius of the one-step matrix, from ||A^(2^k)||^(1/2^k) with renormalisation. */
static double spectral_radius(SimIntegrator integrator, double h, double z)
{
    double a[4][4] = {{0}};
    for (int c = 0; c < 4; ++c) {
        double e[4] = {0}, out[4];
        e[c] = 1.0;
        oscillator_step(integrator, h, z, e, out);
        for (int r = 0; r < 4; ++r)
            a[r][c] = out[r];
    }
    double log_scale = 0.0;
    const int squarings = 14;
    for (int s = 0; s < squarings; ++s) {
        double b[4][4] = {{0}}, norm = 0.0;
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) {
                for (int k = 0; k < 4; ++k)
                    b[r][c] += a[r][k] * a[k][c];
                norm = fabs(b[r][c]) > norm ? fabs(b[r][c]) : norm;
            }
        if (!(norm > 0.0) || !isfinite(norm))
            return norm > 0.0 ? (double)INFINITY : 0.0;
        log_scale = 2.0 * log_scale + log(norm);
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c)
                a[r][c] = b[r][c] / norm;
    }
    return exp(log_scale / (double)(1 << squarings));
}

/* Largest dt with spectral radius <= 1 (plus a small margin for the norm estimate), for an
 * oscillator of natural frequency omega (1/s) and damping ratio zeta. */
double sim_stability_limit(SimIntegrator integrator, double omega, double zeta)
{
    if (!(omega > 0.0))
        return INFINITY;
    double lo = 0.0, hi = 8.0;
    const double tolerance = 1.0 + 1e-3;
    if (spectral_radius(integrator, hi, zeta) <= tolerance)
        return hi / omega;
    for (int k = 0; k < 60; ++k) {
        double mid = 0.5 * (lo + hi);
        if (spectral_radius(integrator, mid, zeta) <= tolerance)
            lo = mid;
        else
            hi = mid;
    }
    return lo / omega;
}
