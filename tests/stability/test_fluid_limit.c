/* SPDX-License-Identifier: MIT */
/* test_fluid_limit.c: hard cases of the fluid column (notes 002 §7.11-7.12). An explicit scheme
 * needs dt <= dy^2 / (2 (nu + nu_t)), below the DEM step at small Galileo numbers; sablier's
 * solver is implicit, so these tests take steps far above that limit and check that the column
 * stays finite, approaches its steady state monotonically and converges to it. A stiff drag
 * (relaxation time at or below dt) must not overshoot the fluid velocity. */
#include "stab_util.h"
#include "test.h"

#include <stdlib.h>

/* Galileo number R, density ratio 2, Shields 0.1, d = g = 1 (notes 002 §4.3): nu = 1 / R,
 * u* = sqrt(0.1). */
static SimFluidDef column(double galileo, int turbulent)
{
    SimFluidDef d = sim_fluid_def_default();
    d.y0 = 0.0;
    d.y1 = 20.0;
    d.cells = 200; /* dy = 0.1 d (002 ch. 6) */
    d.width = 20.0;
    d.density = 0.5;
    d.viscosity = 1.0 / galileo;
    d.shear_velocity = sqrt(0.1);
    d.turbulent = turbulent;
    return d;
}

/* Steps `steps` times by dt; checks finiteness and that the top velocity rises monotonically
 * (start-up under a constant stress: du/dt >= 0 everywhere for the exact equation). Returns the
 * last top velocity, or NAN on failure. */
static double march(SimFluid *f, double dt, int steps)
{
    SimFluidProfile p;
    sim_fluid_profile(f, &p);
    double last = p.u[p.cells - 1];
    for (int s = 0; s < steps; ++s) {
        sim_fluid_step(f, dt, NULL, NULL, NULL);
        sim_fluid_profile(f, &p);
        for (int k = 0; k < p.cells; ++k)
            if (!isfinite(p.u[k])) {
                fprintf(stderr, "non-finite velocity at step %d layer %d\n", s, k);
                return NAN;
            }
        double top = p.u[p.cells - 1];
        if (top < last - 1e-9 * fabs(last)) {
            fprintf(stderr, "top velocity fell from %.17g to %.17g at step %d (dt %g)\n", last, top,
                    s, dt);
            return NAN;
        }
        last = top;
    }
    return last;
}

/* R = 0.01 (nu = 100): the explicit limit 5e-5 is below the thesis's DEM step 1.58e-4. */
static int laminar_small_galileo(void)
{
    SimFluidDef d = column(0.01, 0);
    SimFluid *f = sim_fluid_create(&d, NULL);
    TEST_ASSERT(f);
    double limit = sim_fluid_explicit_limit(f);
    TEST_REL(limit, 0.1 * 0.1 / (2.0 * 100.0), 1e-12);
    const double dem_dt = 1.0 / (2000.0 * sqrt(10.0)); /* notes 002 §1.9 */
    TEST_ASSERT(dem_dt > 3.0 * limit);
    TEST_ASSERT(isfinite(march(f, dem_dt, 2000)));
    TEST_ASSERT(isfinite(march(f, 1e4 * limit, 200)));
    double top = march(f, 1e6 * limit, 200); /* 10^6 times the explicit limit */
    TEST_ASSERT(isfinite(top));
    double exact = d.shear_velocity * d.shear_velocity / d.viscosity * (20.0 - 0.05);
    TEST_REL(top, exact, 1e-10);
    sim_fluid_destroy(f);
    return 0;
}

/* R = 1000 with the mixing length: nu_t dominates near the top; steps 10^3 to 10^6 times the
 * explicit limit still converge to the steady law (the RK4 reference, within the 1 % error of a
 * grid that barely resolves the viscous sublayer). */
static int turbulent_large_galileo(void)
{
    SimFluidDef d = column(1000.0, 1);
    d.cells = 4000; /* dy = 0.005, against the viscous sublayer nu / u* = 0.003 */
    SimFluid *f = sim_fluid_create(&d, NULL);
    TEST_ASSERT(f);
    TEST_ASSERT(isfinite(march(f, 1e-3, 50)));
    double limit = sim_fluid_explicit_limit(f);
    printf("explicit limit with nu_t: %.3g\n", limit);
    TEST_ASSERT(limit < 1e-3); /* nu_t made an explicit step impossible at this dt */
    TEST_ASSERT(isfinite(march(f, 1e3 * limit, 200)));
    TEST_ASSERT(isfinite(march(f, 1e6 * limit, 200)));
    double top = march(f, 1e8 * limit, 200);
    TEST_ASSERT(isfinite(top));
    double y = 20.0 - 0.005, ref;
    sim_fluid_steady_reference(&d, 0.0, &y, 1, &ref);
    printf("turbulent top velocity %.6g, RK4 %.6g\n", top, ref);
    TEST_REL(top, ref, 0.01);
    SimFluidProfile p;
    sim_fluid_profile(f, &p);
    for (int k = 0; k <= p.cells; ++k)
        TEST_REL(p.stress[k], d.density * 0.1, 1e-6);
    sim_fluid_destroy(f);
    return 0;
}

/* A light grain in a fast fluid (notes 002 §7.12). With the drag limiter (exact exponential
 * relaxation per step, capped at 2/3 of the slip for velocity Verlet's predicted velocity) its
 * velocity relaxes monotonically to the fluid's and never overshoots, for tau_p / dt from 10 down
 * to 0.01, and is relaxed within 60 steps when tau_p <= dt. Without the limiter the same grain
 * blows up at tau_p / dt = 0.1. */
static double stiff_run(double ratio, int limit, double *overshoot, int *monotone)
{
    SimFluidDef fd = column(1.0, 0);
    fd.shear_velocity = 0.0;
    fd.buoyancy = 0;
    fd.gravity_y = 0.0;
    fd.width = 1e12;     /* a huge column: the fluid does not notice the grain */
    fd.time_step = 1e-3; /* the limiter acts from the first evaluation */
    fd.drag_limit = limit;
    SimFluid *f = sim_fluid_create(&fd, NULL);
    double u0[200];
    for (int k = 0; k < 200; ++k)
        u0[k] = 1.0;
    sim_fluid_set_velocity(f, u0);
    /* Coefficient at slip 1: 1/2 rho d (sqrt(C_inf) + sqrt(24 nu / d))^2; choose the grain
     * density so that tau_p = m / coef = ratio dt. */
    const double dt = 1e-3, radius = 0.5;
    double s = sqrt(0.5) + sqrt(24.0 * 1.0 / 1.0);
    double coef = 0.5 * fd.density * 1.0 * s * s;
    double mass = ratio * dt * coef;
    SimWorldDef def = tu_def(mass / (TPI * radius * radius), 1e-3, dt); /* no contacts */
    def.effects = SIM_EFFECT_FLUID_DRAG;
    def.body_force = sim_fluid_body_force(f);
    def.guard_max_speed = 1e300;
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 0.0, 10.0, radius, 0, 0, -1);
    SimWorld *w = tu_create(&def, &b);
    double last = 0.0, v = NAN;
    *overshoot = 0.0;
    *monotone = 1;
    for (int step = 0; w && step < 200; ++step) {
        SimError err;
        if (sim_world_step(w, 1, &err) != SIM_OK)
            break;
        SimFrame fr;
        sim_world_frame(w, &fr);
        v = fr.vx[0];
        if (!isfinite(v))
            break;
        *overshoot = fmax(*overshoot, v - 1.0);
        if (v < last - 1e-12)
            *monotone = 0;
        if (ratio <= 1.0 && step == 59 && fabs(v - 1.0) > 1e-3)
            *overshoot = fmax(*overshoot, 1.0); /* not relaxed after 60 steps */
        last = v;
    }
    if (w)
        sim_world_destroy(w);
    sim_fluid_destroy(f);
    sim_grain_buffer_free(&b);
    return v;
}

static int stiff_drag_no_overshoot(void)
{
    const double ratios[] = {10.0, 1.0, 0.1, 0.01};
    for (int r = 0; r < 4; ++r) {
        double overshoot;
        int monotone;
        double v = stiff_run(ratios[r], 1, &overshoot, &monotone);
        printf("tau_p/dt = %g: final v = %.12g, overshoot %.3g, monotone %d\n", ratios[r], v,
               overshoot, monotone);
        TEST_REL(v, 1.0, 1e-6);
        TEST_ASSERT(monotone);
        TEST_ASSERT(overshoot <= 1e-12);
    }
    /* the same stiff grain without the limiter: the explicit drag overshoots and diverges */
    double overshoot;
    int monotone;
    double v = stiff_run(0.1, 0, &overshoot, &monotone);
    printf("tau_p/dt = 0.1 without the limiter: final v = %g, overshoot %g\n", v, overshoot);
    TEST_ASSERT(!(fabs(v - 1.0) < 1e-3) || overshoot > 1.0);
    return 0;
}

TEST_MAIN(TEST_CASE(laminar_small_galileo), TEST_CASE(turbulent_large_galileo),
          TEST_CASE(stiff_drag_no_overshoot))
