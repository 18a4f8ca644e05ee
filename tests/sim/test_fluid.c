/* SPDX-License-Identifier: MIT */
/* test_fluid.c: the 1D fluid column of thesis 002 ch. 6 (sim/fluid.c) against analytic and RK4
 * references, its momentum budget, the drag law and the body-force adapter. */
#include "test.h"

#include "sim/sim_test_util.h"

#include <stdlib.h>

static SimFluidDef laminar_def(double height, int cells, double nu, double u_star)
{
    SimFluidDef d = sim_fluid_def_default();
    d.y0 = 0.0;
    d.y1 = height;
    d.cells = cells;
    d.width = 10.0;
    d.density = 0.5;
    d.viscosity = nu;
    d.shear_velocity = u_star;
    d.turbulent = 0;
    return d;
}

/* Steady laminar profile u = u*^2 y / nu (002 eq. 43), reached exactly by big implicit steps. */
static int laminar_steady(void)
{
    SimFluidDef d = laminar_def(10.0, 100, 2.0, 0.1);
    SimFluid *f = sim_fluid_create(&d, NULL);
    TEST_ASSERT(f);
    for (int s = 0; s < 400; ++s)
        sim_fluid_step(f, 10.0, NULL, NULL, NULL);
    SimFluidProfile p;
    sim_fluid_profile(f, &p);
    double slope = 0.1 * 0.1 / 2.0;
    for (int k = 0; k < p.cells; ++k)
        TEST_NEAR(p.u[k], slope * p.y[k], 1e-12);
    for (int k = 0; k <= p.cells; ++k)
        TEST_REL(p.stress[k], 0.5 * 0.01, 1e-10);
    TEST_NEAR(sim_fluid_velocity_at(f, 5.0), slope * 5.0, 1e-12);
    TEST_NEAR(sim_fluid_velocity_at(f, 0.0), 0.0, 0.0);
    sim_fluid_destroy(f);
    return 0;
}

/* Start-up flow from rest under an imposed top stress: u = G y + sum_n b_n sin(l_n y)
 * exp(-nu l_n^2 t), l_n = (n + 1/2) pi / H, b_n = -2 G (-1)^n / (H l_n^2), G = u*^2 / nu. */
static double startup_exact(double y, double t, double height, double nu, double u_star)
{
    double grad = u_star * u_star / nu, u = grad * y;
    for (int n = 0; n < 2000; ++n) {
        double l = (n + 0.5) * TPI / height;
        double b = -2.0 * grad * (n % 2 ? -1.0 : 1.0) / (height * l * l);
        u += b * sin(l * y) * exp(-nu * l * l * t);
    }
    return u;
}

static int laminar_transient(void)
{
    const double height = 1.0, nu = 1.0, u_star = 1.0;
    SimFluidDef d = laminar_def(height, 200, nu, u_star);
    SimFluid *f = sim_fluid_create(&d, NULL);
    TEST_ASSERT(f);
    const double dt = 2e-5, t_end = 0.1; /* about a quarter of the diffusion time H^2 / nu */
    long steps = lround(t_end / dt);
    for (long s = 0; s < steps; ++s)
        sim_fluid_step(f, dt, NULL, NULL, NULL);
    SimFluidProfile p;
    sim_fluid_profile(f, &p);
    TEST_NEAR(p.time, t_end, 1e-9);
    double err = 0.0, top = startup_exact(height, t_end, height, nu, u_star);
    for (int k = 0; k < p.cells; ++k)
        err = fmax(err, fabs(p.u[k] - startup_exact(p.y[k], t_end, height, nu, u_star)));
    printf("start-up flow: max error %.3g of top velocity %.4g\n", err, top);
    TEST_ASSERT(err < 1e-4 * top);
    sim_fluid_destroy(f);
    return 0;
}

static SimFluidDef turbulent_def(void)
{
    SimFluidDef d = laminar_def(20.0, 1000, 0.1, 1.0);
    d.turbulent = 1;
    d.kappa = 0.4;
    d.van_driest = 26.0;
    return d;
}

/* Steady mixing-length profile against RK4 of (nu + l^2 |u'|) u' = u*^2 (002 eq. 45). */
static int van_driest_steady(void)
{
    SimFluidDef d = turbulent_def();
    SimFluid *f = sim_fluid_create(&d, NULL);
    TEST_ASSERT(f);
    for (int s = 0; s < 300; ++s)
        sim_fluid_step(f, 100.0, NULL, NULL, NULL);
    SimFluidProfile p;
    sim_fluid_profile(f, &p);
    double *ref = malloc((size_t)p.cells * sizeof *ref);
    TEST_ASSERT(ref);
    sim_fluid_steady_reference(&d, d.y0, p.y, p.cells, ref);
    double err = 0.0;
    for (int k = 0; k < p.cells; ++k)
        err = fmax(err, fabs(p.u[k] - ref[k]));
    double top = ref[p.cells - 1];
    printf("van Driest: max |u - u_RK4| = %.3g, u_top = %.4g\n", err, top);
    TEST_ASSERT(err < 2e-3 * top);
    /* stress uniform (steady criterion of 002 fig. 33b) */
    for (int k = 0; k <= p.cells; ++k)
        TEST_REL(p.stress[k], 0.5 * 1.0, 1e-8);
    /* far from the wall the profile is logarithmic: du/dy -> u* / (kappa y) */
    double g = (p.u[900] - p.u[899]) / p.dy, y = p.y0 + 900 * p.dy;
    TEST_REL(g, 1.0 / (0.4 * y), 0.02);
    free(ref);
    sim_fluid_destroy(f);
    return 0;
}

/* RK4 reference of the laminar case is the line u*^2 y / nu (checks the reference itself). */
static int reference_laminar(void)
{
    SimFluidDef d = laminar_def(4.0, 10, 0.5, 0.3);
    double y[3] = {-1.0, 1.0, 3.5}, u[3];
    sim_fluid_steady_reference(&d, 0.0, y, 3, u);
    TEST_NEAR(u[0], 0.0, 0.0);
    TEST_REL(u[1], 0.09 / 0.5 * 1.0, 1e-12);
    TEST_REL(u[2], 0.09 / 0.5 * 3.5, 1e-12);
    return 0;
}

/* A porous layer (fixed drag rate, still grains) absorbs the stress: at steady state the fluid
 * stress plus the grain load above each face equals rho_f u*^2 everywhere (002 fig. 34). */
static int stress_budget_porous(void)
{
    SimFluidDef d = turbulent_def();
    d.cells = 200;
    d.viscosity = 0.5;
    SimFluid *f = sim_fluid_create(&d, NULL);
    TEST_ASSERT(f);
    double *phi = calloc(200, sizeof(double)), *rate = calloc(200, sizeof(double));
    TEST_ASSERT(phi && rate);
    for (int k = 0; k < 60; ++k) { /* bed up to y = 6 */
        phi[k] = 0.8;
        rate[k] = 5.0;
    }
    for (int s = 0; s < 400; ++s)
        sim_fluid_step(f, 100.0, phi, rate, NULL);
    SimFluidProfile p;
    sim_fluid_profile(f, &p);
    TEST_NEAR(p.bed_level, 6.0, 1e-12);
    double target = d.density * d.shear_velocity * d.shear_velocity, load = 0.0, worst = 0.0;
    for (int k = p.cells; k >= 0; --k) {
        if (k < p.cells)
            load += p.grain_force[k] * p.dy;
        worst = fmax(worst, fabs(p.stress[k] + load - target));
    }
    printf("porous bed: max |tau_f + grain load - rho u*^2| = %.3g (rho u*^2 = %.3g)\n", worst,
           target);
    TEST_ASSERT(worst < 1e-9 * target);
    /* the bed carried a real part of the stress */
    TEST_ASSERT(p.stress[0] < 0.5 * target);
    free(phi);
    free(rate);
    sim_fluid_destroy(f);
    return 0;
}

/* C_d = (sqrt(C_inf) + sqrt(R_c / Re))^2 and its limits (002 eq. 24). */
static int drag_coefficient(void)
{
    SimFluidDef d = sim_fluid_def_default();
    TEST_NEAR(sim_fluid_drag_coefficient(&d, 24.0), (sqrt(0.5) + 1.0) * (sqrt(0.5) + 1.0), 1e-12);
    TEST_REL(sim_fluid_drag_coefficient(&d, 1e-8) * 1e-8, 24.0, 1e-3); /* Stokes: 24 / Re */
    TEST_REL(sim_fluid_drag_coefficient(&d, 1e12), 0.5, 1e-4);
    return 0;
}

/* A world with one grain in a uniform fluid: drag F = 1/2 rho C_d A |du| du, buoyancy rho V g,
 * and the grain area spread over the layers. */
static int adapter_forces(void)
{
    for (int geometry = 0; geometry < 2; ++geometry) {
        SimFluidDef fd = laminar_def(10.0, 100, 0.2, 0.0);
        fd.geometry = geometry ? SIM_FLUID_SPHERE : SIM_FLUID_DISK;
        fd.depth = geometry ? 2.0 / 3.0 : 1.0;
        fd.gravity_y = -1.0;
        fd.drag_limit = 0;
        SimFluid *f = sim_fluid_create(&fd, NULL);
        TEST_ASSERT(f);
        double u0[100];
        for (int k = 0; k < 100; ++k)
            u0[k] = 0.3;
        sim_fluid_set_velocity(f, u0);
        SimWorldDef def = tu_def(2.0, 1000.0, 1e-3);
        def.mass_model = geometry ? SIM_MASS_SPHERE : SIM_MASS_DISK;
        def.gravity_y = -1.0;
        def.effects = SIM_EFFECT_FLUID_DRAG;
        def.body_force = sim_fluid_body_force(f);
        SimGrainBuffer b;
        sim_grain_buffer_init(&b);
        sim_grain_buffer_add(&b, 5.0, 5.0, 0.5, 0, 0, -1); /* spans layers 45..54 exactly */
        SimWorld *w = tu_create(&def, &b);
        TEST_ASSERT(w);
        SimFrame fr;
        sim_world_frame(w, &fr);
        double re = 0.3 * 1.0 / 0.2;
        double cd = sim_fluid_drag_coefficient(&fd, re);
        double frontal = geometry ? TPI / 4.0 : 1.0;
        double drag = 0.5 * 0.5 * cd * frontal * 0.3 * 0.3;
        double volume = geometry ? TPI / 6.0 : TPI / 4.0;
        TEST_REL(fr.fx[0], drag, 1e-9);
        TEST_REL(fr.fy[0], 0.5 * volume * 1.0, 1e-9);
        /* reaction: sum_k (source - rate u) V_layer = -drag; grain area in the layers = disk area
         */
        SimFluidProfile p;
        sim_fluid_profile(f, &p);
        (void)p;
        sim_world_destroy(w);
        sim_fluid_destroy(f);
        sim_grain_buffer_free(&b);
    }
    return 0;
}

/* Only a declared fluid_drag effect runs the stage: without it the grain falls freely and the
 * fluid never advances. */
static int drag_only_when_declared(void)
{
    SimFluidDef fd = laminar_def(10.0, 50, 0.2, 0.1);
    fd.gravity_y = -1.0;
    SimFluid *f = sim_fluid_create(&fd, NULL);
    TEST_ASSERT(f);
    SimWorldDef def = tu_def(2.0, 1000.0, 1e-3);
    def.gravity_y = -1.0;
    def.effects = 0;
    def.body_force = sim_fluid_body_force(f); /* set, but the effect is not declared */
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 5.0, 8.0, 0.5, 0, 0, -1);
    SimWorld *w = tu_create(&def, &b);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 1000) == 0);
    SimFrame fr;
    sim_world_frame(w, &fr);
    TEST_NEAR(fr.vx[0], 0.0, 0.0);
    TEST_REL(fr.vy[0], -1.0, 1e-9); /* free fall for t = 1 */
    TEST_NEAR(sim_fluid_time(f), 0.0, 0.0);
    sim_world_destroy(w);
    /* declared: the fluid advances with the world and drags the grain downstream */
    def.effects = SIM_EFFECT_FLUID_DRAG;
    w = tu_create(&def, &b);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 1000) == 0);
    sim_world_frame(w, &fr);
    TEST_NEAR(sim_fluid_time(f), 1.0, 1e-9);
    TEST_ASSERT(fr.vx[0] > 0.0);
    TEST_ASSERT(fr.vy[0] > -1.0); /* buoyancy and drag slow the fall */
    sim_world_destroy(w);
    sim_fluid_destroy(f);
    sim_grain_buffer_free(&b);
    return 0;
}

/* Momentum exchange: a grain moving through still fluid (no gravity, no top stress) hands its
 * momentum to the fluid; fluid + grain momentum stays constant to the coupling's O(dt) lag. */
static int momentum_exchange(void)
{
    SimFluidDef fd = laminar_def(4.0, 40, 0.05, 0.0);
    fd.width = 4.0;
    fd.buoyancy = 0;
    fd.gravity_y = 0.0;
    SimFluid *f = sim_fluid_create(&fd, NULL);
    TEST_ASSERT(f);
    SimWorldDef def = tu_def(2.0, 1000.0, 1e-3);
    def.effects = SIM_EFFECT_FLUID_DRAG | SIM_EFFECT_PERIODIC_X;
    def.domain_x0 = 0.0;
    def.domain_x1 = 4.0;
    def.body_force = sim_fluid_body_force(f);
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, 2.0, 2.0, 0.5, 0, 0, -1);
    b.vx[0] = 1.0;
    SimWorld *w = tu_create(&def, &b);
    TEST_ASSERT(w);
    double mass = 2.0 * TPI * 0.25, p0 = mass * 1.0;
    TEST_ASSERT(tu_step(w, 2000) == 0);
    SimFrame fr;
    sim_world_frame(w, &fr);
    SimFluidProfile p;
    sim_fluid_profile(f, &p);
    double pf = 0.0;
    for (int k = 0; k < p.cells; ++k)
        pf += fd.density * (1.0 - p.solid_fraction[k]) * p.dy * fd.width * p.u[k];
    double pg = mass * fr.vx[0];
    printf("momentum: grain %.6g + fluid %.6g = %.6g (start %.6g); wall stress %.3g\n", pg, pf,
           pg + pf, p0, p.stress[0]);
    TEST_ASSERT(pg < 0.9 * p0); /* the grain did slow down */
    /* what left through the bottom wall is small at t = 2 (viscous diffusion time H^2/nu = 320) */
    TEST_REL(pg + pf, p0, 1e-3);
    sim_world_destroy(w);
    sim_fluid_destroy(f);
    sim_grain_buffer_free(&b);
    return 0;
}

static int invalid_defs(void)
{
    SimFluidDef d = sim_fluid_def_default();
    SimError e;
    TEST_ASSERT(sim_fluid_def_validate(&d, &e) == SIM_OK);
    d.cells = 1;
    TEST_ASSERT(sim_fluid_create(&d, &e) == NULL && e.status == SIM_ERROR_INVALID);
    TEST_ASSERT(strcmp(e.field, "fluid.cells") == 0);
    d = sim_fluid_def_default();
    d.viscosity = 0.0;
    TEST_ASSERT(sim_fluid_def_validate(&d, &e) == SIM_ERROR_INVALID);
    d = sim_fluid_def_default();
    d.y1 = d.y0;
    TEST_ASSERT(sim_fluid_def_validate(&d, &e) == SIM_ERROR_INVALID);
    return 0;
}

TEST_MAIN(TEST_CASE(laminar_steady), TEST_CASE(laminar_transient), TEST_CASE(van_driest_steady),
          TEST_CASE(reference_laminar), TEST_CASE(stress_budget_porous),
          TEST_CASE(drag_coefficient), TEST_CASE(adapter_forces),
          TEST_CASE(drag_only_when_declared), TEST_CASE(momentum_exchange), TEST_CASE(invalid_defs))
