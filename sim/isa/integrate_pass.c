/* SPDX-License-Identifier: MIT */
/* integrate_pass.c: the steps of the five integrators behind one interface, each instantiated with
 * and without rotation (rotation only when a declared effect makes torques). Compiled once per
 * instruction set like contact_pass.c (docs/dev/isa.md): the loops over the grains vectorise to
 * that set's width; every operation is exactly rounded, so the bits do not depend on it.
 *
 * Every step computes all forces before any grain moves on (the thesis's sequential update is
 * not reproduced: 000 notes §2.1). Gravity is added here, fused into the kick. */
#include "sim/integrate_scratch.h"

#include <string.h>

/* Squared displacement since the last neighbour build; the loops OR the comparison with the
 * rebuild threshold instead of tracking a maximum, so that they vectorise. */
static inline double displacement2(const SimWorld *w, int i)
{
    double dx = w->x[i] - w->x_ref[i], dy = w->y[i] - w->y_ref[i];
    return dx * dx + dy * dy;
}

/* ---- velocity Verlet: kick-drift, forces, kick. The dissipative forces see the predicted
 * velocity v(t + dt) ~ v(t + dt/2) + a(t) dt/2 (as thesis 004's code does), which keeps the
 * scheme second order with damping; the VV_* scratch arrays hold the half-step velocities. */
/* The opening kick and drift. `closing`: first apply the previous step's closing kick, deferred
 * by sim_world_step (same arithmetic as velocity_verlet_close, so the same bits; it saves one pass
 * over the grains per step). The forces read are then set to +0.0, as the force evaluation
 * would (sim_world_drift_forces_at: one pass less over the force arrays, and the fused contact
 * pass needs each grain's forces cleared when it drifts it). No software prefetch: asking for the
 * next range's 17 arrays (about 500 lines, L1's size) evicted what the contact pass was using; the
 * hardware's prefetch alone is 5 % faster on a 700 000-grain pile (docs/dev/scaling.md). */
static inline __attribute__((always_inline)) int
velocity_verlet_open(SimWorld *w, const int rot, const int closing, const int i0, const int i1)
{
    const double dt = w->dt, half = 0.5 * dt, gx = w->def.gravity_x, gy = w->def.gravity_y;
    double *restrict x = w->x, *restrict y = w->y, *restrict vx = w->vx, *restrict vy = w->vy;
    double *restrict hx = w->scratch[VV_VX_HALF], *restrict hy = w->scratch[VV_VY_HALF];
    double *restrict fx = w->fx, *restrict fy = w->fy;
    const double *restrict im = w->inv_mass;
    const double *restrict xr = w->x_ref, *restrict yr = w->y_ref;
    const double limit2 = w->disp_limit2;
    int moved = 0;
    /* The arrays never alias (restrict is not enough for GCC to vectorise): */
#pragma GCC ivdep
    for (int i = i0; i < i1; ++i) {
        double ax = fx[i] * im[i] + gx, ay = fy[i] * im[i] + gy;
        fx[i] = fy[i] = 0.0;
        double vxi = closing ? hx[i] + half * ax : vx[i];
        double vyi = closing ? hy[i] + half * ay : vy[i];
        double vhx = vxi + half * ax, vhy = vyi + half * ay;
        hx[i] = vhx;
        hy[i] = vhy;
        x[i] += dt * vhx;
        y[i] += dt * vhy;
        vx[i] = vhx + half * ax;
        vy[i] = vhy + half * ay;
        double dx = x[i] - xr[i], dy = y[i] - yr[i];
        moved |= dx * dx + dy * dy > limit2;
    }
    if (rot) {
        double *restrict omega = w->omega, *restrict hw = w->scratch[VV_OMEGA_HALF],
                         *restrict angle = w->angle;
        double *restrict torque = w->torque;
        const double *restrict ii = w->inv_inertia;
#pragma GCC ivdep
        for (int i = i0; i < i1; ++i) {
            double wi = closing ? hw[i] + half * torque[i] * ii[i] : omega[i];
            double alpha = torque[i] * ii[i];
            torque[i] = 0.0;
            double wh = wi + half * alpha;
            hw[i] = wh;
            angle[i] += dt * wh;
            omega[i] = wh + half * alpha;
        }
    }
    return moved;
}

/* The closing kick with the new forces. */
static inline __attribute__((always_inline)) int velocity_verlet_close(SimWorld *w, const int rot,
                                                                       const int i0, const int i1)
{
    const double half = 0.5 * w->dt, gx = w->def.gravity_x, gy = w->def.gravity_y;
    double *restrict vx = w->vx, *restrict vy = w->vy;
    const double *restrict hx = w->scratch[VV_VX_HALF], *restrict hy = w->scratch[VV_VY_HALF];
    const double *restrict fx = w->fx, *restrict fy = w->fy, *restrict im = w->inv_mass;
#pragma GCC ivdep
    for (int i = i0; i < i1; ++i) {
        vx[i] = hx[i] + half * (fx[i] * im[i] + gx);
        vy[i] = hy[i] + half * (fy[i] * im[i] + gy);
    }
    if (rot) {
        double *restrict omega = w->omega;
        const double *restrict hw = w->scratch[VV_OMEGA_HALF], *restrict torque = w->torque;
        const double *restrict ii = w->inv_inertia;
#pragma GCC ivdep
        for (int i = i0; i < i1; ++i)
            omega[i] = hw[i] + half * torque[i] * ii[i];
    }
    return 0;
}

/* The passes over fixed grain ranges (sim_parallel_ranges, or the fused contact pass): each grain
 * on its own, so the same bits for any thread count; `moved` is an OR. */
#define VV_RANGES(rot, closing)                                                                    \
    static int vv_open_##rot##_##closing(SimWorld *w, int begin, int end)                          \
    {                                                                                              \
        return velocity_verlet_open(w, rot, closing, begin, end);                                  \
    }
VV_RANGES(0, 0)
VV_RANGES(0, 1)
VV_RANGES(1, 0)
VV_RANGES(1, 1)

static int vv_close_0(SimWorld *w, int begin, int end)
{
    return velocity_verlet_close(w, 0, begin, end);
}

static int vv_close_1(SimWorld *w, int begin, int end)
{
    return velocity_verlet_close(w, 1, begin, end);
}

/* Ranges of 8 grains: whole vectors, and no two threads on one cache line of a double array. */
enum { VV_ALIGN = 8 };

static inline void velocity_verlet(SimWorld *w, const int rot)
{
    RangeFn *open = rot ? (w->kick_pending ? vv_open_1_1 : vv_open_1_0)
                        : (w->kick_pending ? vv_open_0_1 : vv_open_0_0);
    w->kick_pending = 0;
    sim_world_drift_forces_at(w, w->time + w->dt, open, VV_ALIGN);
    if (w->defer_kick)
        w->kick_pending = 1;
    else
        sim_parallel_ranges(w, rot ? vv_close_1 : vv_close_0, w->mobile_count, VV_ALIGN);
}

void SIM_ISA_SYMBOL(sim_integrator_finish)(SimWorld *w)
{
    if (w->kick_pending) {
        sim_parallel_ranges(w, w->rotation ? vv_close_1 : vv_close_0, w->mobile_count, VV_ALIGN);
        w->kick_pending = 0;
    }
}

/* ---- semi-implicit (symplectic) Euler, 000 eqs. 4.16-4.17: v += a dt, then x += v dt. */
static inline void symplectic_euler(SimWorld *w, const int rot)
{
    const int n = w->mobile_count;
    const double dt = w->dt, gx = w->def.gravity_x, gy = w->def.gravity_y;
    int moved = 0;
    const double limit2 = w->disp_limit2;
    for (int i = 0; i < n; ++i) {
        w->vx[i] += dt * (w->fx[i] * w->inv_mass[i] + gx);
        w->vy[i] += dt * (w->fy[i] * w->inv_mass[i] + gy);
        w->x[i] += dt * w->vx[i];
        w->y[i] += dt * w->vy[i];
        moved |= displacement2(w, i) > limit2;
    }
    if (rot) {
        for (int i = 0; i < n; ++i) {
            w->omega[i] += dt * w->torque[i] * w->inv_inertia[i];
            w->angle[i] += dt * w->omega[i];
        }
    }
    w->need_rebuild |= moved;
    sim_world_forces_at(w, w->time + dt);
}

/* ---- position (Stormer) Verlet, 000 eq. 4.18: x' = 2x - x_prev + a dt^2. The velocity used by
 * the dissipative forces and reported is the backward difference (x' - x) / dt: eq. 4.19's
 * central difference needs x' before the forces that produce it (000 notes §2.2). Angles use
 * explicit Euler for omega as in the thesis. STORMER_X_PREV/Y_PREV hold the previous positions. */
static inline void stormer_verlet(SimWorld *w, const int rot)
{
    const int n = w->mobile_count;
    const double dt = w->dt, dt2 = dt * dt, gx = w->def.gravity_x, gy = w->def.gravity_y;
    double *xp = w->scratch[STORMER_X_PREV], *yp = w->scratch[STORMER_Y_PREV];
    int moved = 0;
    const double limit2 = w->disp_limit2;
    for (int i = 0; i < n; ++i) {
        double x = w->x[i], y = w->y[i];
        double xn = 2.0 * x - xp[i] + (w->fx[i] * w->inv_mass[i] + gx) * dt2;
        double yn = 2.0 * y - yp[i] + (w->fy[i] * w->inv_mass[i] + gy) * dt2;
        xp[i] = x;
        yp[i] = y;
        w->x[i] = xn;
        w->y[i] = yn;
        w->vx[i] = (xn - x) / dt;
        w->vy[i] = (yn - y) / dt;
        moved |= displacement2(w, i) > limit2;
    }
    if (rot) {
        for (int i = 0; i < n; ++i) {
            w->angle[i] += dt * w->omega[i];
            w->omega[i] += dt * w->torque[i] * w->inv_inertia[i];
        }
    }
    w->need_rebuild |= moved;
    sim_world_forces_at(w, w->time + dt);
}

/* ---- Gear predictor-corrector with four values (x, v, a, b = da/dt): third order (002).
 * Corrector coefficients for second-order equations: 1/6, 5/6, 1, 1/3 on the scaled values
 * (x, v dt, a dt^2/2, b dt^3/6). Scratch: GEAR_AX..BY = a and b of x and y; GEAR_ALPHA, GEAR_BETA =
 * angular a and b (rotation only). */
static inline void gear(SimWorld *w, const int rot)
{
    int n = w->mobile_count;
    const double dt = w->dt, dt2 = dt * dt, dt3 = dt2 * dt;
    const double gx = w->def.gravity_x, gy = w->def.gravity_y;
    double *ax = w->scratch[GEAR_AX], *ay = w->scratch[GEAR_AY];
    double *bx = w->scratch[GEAR_BX], *by = w->scratch[GEAR_BY];
    double *aw = w->scratch[GEAR_ALPHA], *bw = w->scratch[GEAR_BETA]; /* NULL without rotation */
    int moved = 0;
    const double limit2 = w->disp_limit2;
    for (int i = 0; i < n; ++i) {
        w->x[i] += w->vx[i] * dt + ax[i] * dt2 / 2.0 + bx[i] * dt3 / 6.0;
        w->y[i] += w->vy[i] * dt + ay[i] * dt2 / 2.0 + by[i] * dt3 / 6.0;
        w->vx[i] += ax[i] * dt + bx[i] * dt2 / 2.0;
        w->vy[i] += ay[i] * dt + by[i] * dt2 / 2.0;
        ax[i] += bx[i] * dt;
        ay[i] += by[i] * dt;
        moved |= displacement2(w, i) > limit2;
    }
    if (rot) {
        for (int i = 0; i < n; ++i) {
            w->angle[i] += w->omega[i] * dt + aw[i] * dt2 / 2.0 + bw[i] * dt3 / 6.0;
            w->omega[i] += aw[i] * dt + bw[i] * dt2 / 2.0;
            aw[i] += bw[i] * dt;
        }
    }
    w->need_rebuild |= moved;
    sim_world_forces_at(w, w->time + dt);
    n = w->mobile_count; /* the rebuild may have removed grains (mobile ones come first) */
    for (int i = 0; i < n; ++i) {
        double dax = w->fx[i] * w->inv_mass[i] + gx - ax[i];
        double day = w->fy[i] * w->inv_mass[i] + gy - ay[i];
        w->x[i] += dax * dt2 / 12.0;
        w->y[i] += day * dt2 / 12.0;
        w->vx[i] += dax * dt * 5.0 / 12.0;
        w->vy[i] += day * dt * 5.0 / 12.0;
        ax[i] += dax;
        ay[i] += day;
        bx[i] += dax / dt;
        by[i] += day / dt;
    }
    if (rot) {
        for (int i = 0; i < n; ++i) {
            double da = w->torque[i] * w->inv_inertia[i] - aw[i];
            w->angle[i] += da * dt2 / 12.0;
            w->omega[i] += da * dt * 5.0 / 12.0;
            aw[i] += da;
            bw[i] += da / dt;
        }
    }
}

/* ---- classical Runge-Kutta of order 4 on (x, v). Four force evaluations per step (the last one
 * serves the next step). Scratch: RK4_X0..VY0, RK4_ANGLE0, RK4_OMEGA0 = start state; RK4_SUM_* =
 * weighted sums of the slopes (angular ones with rotation only). */
static void rk4_stage(SimWorld *w, const int rot, double position_step, double velocity_step,
                      double weight, double time)
{
    const int n = w->mobile_count;
    const double gx = w->def.gravity_x, gy = w->def.gravity_y;
    int moved = 0;
    const double limit2 = w->disp_limit2;
    for (int i = 0; i < n; ++i) {
        double ax = w->fx[i] * w->inv_mass[i] + gx, ay = w->fy[i] * w->inv_mass[i] + gy;
        w->scratch[RK4_SUM_VX][i] += weight * w->vx[i];
        w->scratch[RK4_SUM_VY][i] += weight * w->vy[i];
        w->scratch[RK4_SUM_AX][i] += weight * ax;
        w->scratch[RK4_SUM_AY][i] += weight * ay;
        double vx = w->vx[i], vy = w->vy[i];
        w->x[i] = w->scratch[RK4_X0][i] + position_step * vx;
        w->y[i] = w->scratch[RK4_Y0][i] + position_step * vy;
        w->vx[i] = w->scratch[RK4_VX0][i] + velocity_step * ax;
        w->vy[i] = w->scratch[RK4_VY0][i] + velocity_step * ay;
        moved |= displacement2(w, i) > limit2;
    }
    if (rot) {
        for (int i = 0; i < n; ++i) {
            double alpha = w->torque[i] * w->inv_inertia[i];
            w->scratch[RK4_SUM_OMEGA][i] += weight * w->omega[i];
            w->scratch[RK4_SUM_ALPHA][i] += weight * alpha;
            double om = w->omega[i];
            w->angle[i] = w->scratch[RK4_ANGLE0][i] + position_step * om;
            w->omega[i] = w->scratch[RK4_OMEGA0][i] + velocity_step * alpha;
        }
    }
    w->need_rebuild |= moved;
    sim_world_forces_at(w, time);
}

static inline void rk4(SimWorld *w, const int rot)
{
    int n = w->mobile_count;
    const double dt = w->dt, t = w->time;
    memcpy(w->scratch[RK4_X0], w->x, (size_t)n * sizeof(double));
    memcpy(w->scratch[RK4_Y0], w->y, (size_t)n * sizeof(double));
    memcpy(w->scratch[RK4_VX0], w->vx, (size_t)n * sizeof(double));
    memcpy(w->scratch[RK4_VY0], w->vy, (size_t)n * sizeof(double));
    memset(w->scratch[RK4_SUM_VX], 0, (size_t)n * sizeof(double));
    memset(w->scratch[RK4_SUM_VY], 0, (size_t)n * sizeof(double));
    memset(w->scratch[RK4_SUM_AX], 0, (size_t)n * sizeof(double));
    memset(w->scratch[RK4_SUM_AY], 0, (size_t)n * sizeof(double));
    if (rot) {
        memcpy(w->scratch[RK4_ANGLE0], w->angle, (size_t)n * sizeof(double));
        memcpy(w->scratch[RK4_OMEGA0], w->omega, (size_t)n * sizeof(double));
        memset(w->scratch[RK4_SUM_OMEGA], 0, (size_t)n * sizeof(double));
        memset(w->scratch[RK4_SUM_ALPHA], 0, (size_t)n * sizeof(double));
    }
    /* k1 at the start state (forces already there), k2, k3 at t + dt/2, k4 at t + dt. */
    rk4_stage(w, rot, 0.5 * dt, 0.5 * dt, 1.0, t + 0.5 * dt);
    rk4_stage(w, rot, 0.5 * dt, 0.5 * dt, 2.0, t + 0.5 * dt);
    rk4_stage(w, rot, dt, dt, 2.0, t + dt);
    n = w->mobile_count; /* a stage's rebuild may have removed grains (mobile ones come first) */
    const double gx = w->def.gravity_x, gy = w->def.gravity_y, sixth = dt / 6.0;
    int moved = 0;
    const double limit2 = w->disp_limit2;
    for (int i = 0; i < n; ++i) {
        double sx = w->scratch[RK4_SUM_VX][i] + w->vx[i], sy = w->scratch[RK4_SUM_VY][i] + w->vy[i];
        double sax = w->scratch[RK4_SUM_AX][i] + w->fx[i] * w->inv_mass[i] + gx;
        double say = w->scratch[RK4_SUM_AY][i] + w->fy[i] * w->inv_mass[i] + gy;
        w->x[i] = w->scratch[RK4_X0][i] + sixth * sx;
        w->y[i] = w->scratch[RK4_Y0][i] + sixth * sy;
        w->vx[i] = w->scratch[RK4_VX0][i] + sixth * sax;
        w->vy[i] = w->scratch[RK4_VY0][i] + sixth * say;
        moved |= displacement2(w, i) > limit2;
    }
    if (rot) {
        for (int i = 0; i < n; ++i) {
            double so = w->scratch[RK4_SUM_OMEGA][i] + w->omega[i];
            double sa = w->scratch[RK4_SUM_ALPHA][i] + w->torque[i] * w->inv_inertia[i];
            w->angle[i] = w->scratch[RK4_ANGLE0][i] + sixth * so;
            w->omega[i] = w->scratch[RK4_OMEGA0][i] + sixth * sa;
        }
    }
    w->need_rebuild |= moved;
    sim_world_forces_at(w, t + dt);
}

#define DEFINE_INTEGRATOR(name)                                                                    \
    static void name##_0(SimWorld *w)                                                              \
    {                                                                                              \
        name(w, 0);                                                                                \
    }                                                                                              \
    static void name##_1(SimWorld *w)                                                              \
    {                                                                                              \
        name(w, 1);                                                                                \
    }
DEFINE_INTEGRATOR(velocity_verlet)
DEFINE_INTEGRATOR(symplectic_euler)
DEFINE_INTEGRATOR(stormer_verlet)
DEFINE_INTEGRATOR(gear)
DEFINE_INTEGRATOR(rk4)

StageFn *SIM_ISA_SYMBOL(sim_integrator_select)(SimIntegrator integrator, int rotation)
{
    static StageFn *const table[SIM_INTEGRATOR_COUNT][2] = {
        [SIM_INTEGRATOR_VELOCITY_VERLET] = {velocity_verlet_0, velocity_verlet_1},
        [SIM_INTEGRATOR_SYMPLECTIC_EULER] = {symplectic_euler_0, symplectic_euler_1},
        [SIM_INTEGRATOR_STORMER_VERLET] = {stormer_verlet_0, stormer_verlet_1},
        [SIM_INTEGRATOR_GEAR] = {gear_0, gear_1},
        [SIM_INTEGRATOR_RK4] = {rk4_0, rk4_1},
    };
    if ((int)integrator < 0 || integrator >= SIM_INTEGRATOR_COUNT)
        return NULL;
    return table[integrator][rotation ? 1 : 0];
}
