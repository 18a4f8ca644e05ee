/* SPDX-License-Identifier: MIT */
/* test_coarse.c: coarse-grained fields (sim/coarse.c; Weinhart et al. 2012) and flux counters:
 * kernel normalisation, the contact-stress virial, a settled column's stress profile, the
 * kinetic stress of a gas, and exact flux counts. */
#include "sim_test_util.h"
#include "test.h"

#include <stdlib.h>

/* The 1D kernels are the 2D ones integrated over x, and integrate to 1. */
static int kernel_1d_integrates(void)
{
    const double c = 0.3;
    for (int kind = 0; kind < 2; ++kind) {
        double total = 0.0;
        const int n = 4000;
        for (int k = 0; k < n; ++k) {
            double y = -c + (k + 0.5) * 2.0 * c / n;
            total += sim_kernel_1d((SimKernel)kind, y, c) * 2.0 * c / n;
        }
        TEST_NEAR(total, 1.0, 1e-6);
        for (double y = 0.0; y < c; y += 0.07) {
            double direct = 0.0;
            for (int k = 0; k < n; ++k) {
                double x = -c + (k + 0.5) * 2.0 * c / n;
                direct += sim_kernel((SimKernel)kind, hypot(x, y), c) * 2.0 * c / n;
            }
            TEST_NEAR(sim_kernel_1d((SimKernel)kind, y, c), direct, 1e-4 * direct + 1e-9);
        }
    }
    return 0;
}

/* A frame of n x n grains on a square lattice of pitch a (origin a/2), velocity (u0, v0). */
typedef struct Lattice {
    SimFrame frame;
    double *x, *y, *r, *vx, *vy, *mass;
    unsigned *flags;
} Lattice;

static int lattice_make(Lattice *l, int n, double a, double radius, double u0, double v0)
{
    memset(l, 0, sizeof *l);
    size_t count = (size_t)n * (size_t)n;
    l->x = calloc(count, sizeof(double));
    l->y = calloc(count, sizeof(double));
    l->r = calloc(count, sizeof(double));
    l->vx = calloc(count, sizeof(double));
    l->vy = calloc(count, sizeof(double));
    l->mass = calloc(count, sizeof(double));
    l->flags = calloc(count, sizeof(unsigned));
    if (!l->x || !l->y || !l->r || !l->vx || !l->vy || !l->mass || !l->flags)
        return -1;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            int k = j * n + i;
            l->x[k] = (i + 0.5) * a;
            l->y[k] = (j + 0.5) * a;
            l->r[k] = radius;
            l->vx[k] = u0 + (((i + j) % 2) ? 0.3 : -0.3); /* checkerboard fluctuation +-0.3 */
            l->vy[k] = v0;
            l->mass[k] = 2.0 * TPI * radius * radius; /* areal density 2 kg/m^2 */
        }
    l->frame = (SimFrame){.count = (int)count,
                          .mobile_count = (int)count,
                          .x = l->x,
                          .y = l->y,
                          .radius = l->r,
                          .vx = l->vx,
                          .vy = l->vy,
                          .flags = l->flags};
    return 0;
}

static void lattice_free(Lattice *l)
{
    free(l->x);
    free(l->y);
    free(l->r);
    free(l->vx);
    free(l->vy);
    free(l->mass);
    free(l->flags);
}

/* A uniform lattice gives its exact packing fraction pi r^2 / a^2 and density m / a^2 away from
 * the borders, its mean velocity, and (checkerboard +-0.3 m/s in x) a kinetic stress m u^2/a^2;
 * the field's mass and momentum integrate to the grains' totals (to rounding). */
static int lattice_fields_exact(void)
{
    const int n = 40;
    const double a = 0.1, radius = 0.04;
    Lattice l;
    TEST_ASSERT(lattice_make(&l, n, a, radius, 0.5, -0.2) == 0);
    SimCoarseDef d = sim_coarse_def_default();
    d.width = 0.35;
    d.x0 = d.y0 = -0.5; /* the grains' supports lie inside the nodes */
    d.cell_x = d.cell_y = 0.05;
    d.nx = d.ny = (int)((n * a + 1.0) / 0.05);
    SimCoarse *cg = sim_coarse_create(&d, NULL);
    TEST_ASSERT(cg);
    TEST_ASSERT(sim_coarse_add(cg, &l.frame, l.mass, 0.0, 0.0) == SIM_OK);
    int nodes = sim_coarse_nodes(cg);
    double *phi = malloc((size_t)nodes * sizeof *phi), *rho = malloc((size_t)nodes * sizeof *rho);
    double *jx = malloc((size_t)nodes * sizeof *jx), *vx = malloc((size_t)nodes * sizeof *vx);
    double *kxx = malloc((size_t)nodes * sizeof *kxx), *t = malloc((size_t)nodes * sizeof *t);
    TEST_ASSERT(phi && rho && jx && vx && kxx && t);
    sim_coarse_field(cg, SIM_CG_PHI, phi);
    sim_coarse_field(cg, SIM_CG_RHO, rho);
    sim_coarse_field(cg, SIM_CG_JX, jx);
    sim_coarse_field(cg, SIM_CG_VX, vx);
    sim_coarse_field(cg, SIM_CG_KXX, kxx);
    sim_coarse_field(cg, SIM_CG_T, t);
    double mass = 0.0, px = 0.0, field_mass = 0.0, field_px = 0.0, area = 0.05 * 0.05;
    for (int k = 0; k < l.frame.count; ++k) {
        mass += l.mass[k];
        px += l.mass[k] * l.vx[k];
    }
    int inner = 0;
    for (int k = 0; k < nodes; ++k) {
        field_mass += rho[k] * area;
        field_px += jx[k] * area;
        double x, y;
        sim_coarse_node(cg, k, &x, &y);
        if (x < 0.6 || x > n * a - 0.6 || y < 0.6 || y > n * a - 0.6)
            continue;
        ++inner;
        double m = l.mass[0];
        TEST_REL(phi[k], TPI * radius * radius / (a * a), 1e-4);
        TEST_REL(rho[k], m / (a * a), 1e-4);
        TEST_REL(vx[k], 0.5, 1e-3); /* the checkerboard averages out to 1e-4 */
        TEST_REL(kxx[k], m * 0.09 / (a * a), 1e-3);
        TEST_REL(t[k], 0.5 * 0.09, 1e-3);
    }
    TEST_ASSERT(inner > 100);
    TEST_REL(field_mass, mass, 1e-12);
    TEST_REL(field_px, px, 1e-12);
    free(phi);
    free(rho);
    free(jx);
    free(vx);
    free(kxx);
    free(t);
    sim_coarse_destroy(cg);
    lattice_free(&l);
    return 0;
}

/* A pile settling in a box of walls [0, L] x [0, ...] (frictionless walls; grain friction as
 * given): rain, then `steps` steps. */
static SimWorld *box_pile(double width, double height, int friction, long steps)
{
    SimWorldDef def = tu_def(1000.0, 1e5, 0.0);
    def.time_step = 8e-5;
    def.gravity_y = -G0;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.2;
    def.species_count = 2;
    def.materials[1] = def.materials[0]; /* walls: frictionless (harmonic mean with 0) */
    if (friction) {
        def.effects |= SIM_EFFECT_FRICTION;
        def.contact.tangential = SIM_TANGENTIAL_REGULARISED;
        def.materials[0].friction = 0.5;
        def.materials[0].tangential_damping = 50.0;
    }
    static SimWall walls[3];
    walls[0] = (SimWall){.x1 = width, .species = 1, .motion = -1};
    walls[1] = (SimWall){.y1 = 4.0 * height, .species = 1, .motion = -1};
    walls[2] = (SimWall){.x0 = width, .x1 = width, .y1 = 4.0 * height, .species = 1, .motion = -1};
    def.walls = walls;
    def.wall_count = 3;
    SimGrainBuffer buffer;
    sim_grain_buffer_init(&buffer);
    SimRainDef rain = sim_rain_def_thesis000(0.0, width, 0.0, height, 0);
    rain.radius_mean = 0.01;
    rain.pitch_radius = 0.0108;
    rain.column_gap = 0.005 * 0.0108;
    rain.row_gap = 0.75 * 0.0108;
    SimRng rng;
    sim_rng_seed(&rng, 7);
    sim_build_rain(&buffer, &rain, &rng);
    SimWorld *w = tu_create(&def, &buffer);
    sim_grain_buffer_free(&buffer);
    if (w && sim_world_step(w, steps, NULL) != SIM_OK) {
        sim_world_destroy(w);
        return NULL;
    }
    return w;
}

/* The domain-integrated contact stress equals the virial sum over contacts, sum f_i (x) b, to
 * rounding, on a grid and on a profile (friction on, so tangential forces count too). */
static int contact_stress_virial(void)
{
    SimWorld *w = box_pile(0.3, 0.3, 1, 3000);
    TEST_ASSERT(w);
    SimFrame f;
    sim_world_frame(w, &f);
    TEST_ASSERT(f.contact_count > 100);
    double virial[4] = {0};
    for (int k = 0; k < f.contact_count; ++k) {
        const SimContact *c = &f.contacts[k];
        double dx = c->j >= 0 ? f.x[c->j] - f.x[c->i] : c->x - f.x[c->i];
        double dy = c->j >= 0 ? f.y[c->j] - f.y[c->i] : c->y - f.y[c->i];
        double d = hypot(dx, dy), nx = dx / d, ny = dy / d;
        double fx = -c->normal_force * nx + c->tangential_force * ny;
        double fy = -c->normal_force * ny - c->tangential_force * nx;
        virial[0] += fx * -dx;
        virial[1] += fx * -dy;
        virial[2] += fy * -dx;
        virial[3] += fy * -dy;
    }
    double *mass = malloc((size_t)f.count * sizeof *mass);
    TEST_ASSERT(mass);
    sim_world_masses(w, mass);
    for (int geometry = 0; geometry < 2; ++geometry) {
        SimCoarseDef d = sim_coarse_def_default();
        d.width = 0.04;
        d.contacts = 1;
        d.geometry = geometry ? SIM_COARSE_PROFILE_Y : SIM_COARSE_GRID;
        d.x0 = d.y0 = -0.1;
        d.x1 = 0.4; /* the strip of the profile holds every branch */
        d.cell_x = d.cell_y = 0.01;
        d.nx = 50;
        d.ny = 60;
        SimCoarse *cg = sim_coarse_create(&d, NULL);
        TEST_ASSERT(cg);
        TEST_ASSERT(sim_coarse_add(cg, &f, mass, 0.0, 0.0) == SIM_OK);
        int nodes = sim_coarse_nodes(cg);
        double *v = malloc((size_t)nodes * sizeof *v);
        TEST_ASSERT(v);
        const SimCoarseField fields[4] = {SIM_CG_CXX, SIM_CG_CXY, SIM_CG_CYX, SIM_CG_CYY};
        double cell = geometry ? d.cell_y * (d.x1 - d.x0) : d.cell_x * d.cell_y;
        for (int q = 0; q < 4; ++q) {
            sim_coarse_field(cg, fields[q], v);
            double integral = 0.0;
            for (int k = 0; k < nodes; ++k)
                integral += v[k] * cell;
            TEST_NEAR(integral, virial[q], 1e-12 * fabs(virial[3]));
        }
        free(v);
        sim_coarse_destroy(cg);
    }
    free(mass);
    sim_world_destroy(w);
    return 0;
}

/* A settled column between frictionless walls: sigma_yy(y) is the weight per unit width of the
 * material above y (each grain's weight shared by the part of its disk above y) within 3 % over
 * the middle of the column, and sigma_xy is below 1 % of the base stress (momentum balance,
 * Weinhart et al. 2012 eq. 17). */
static int settled_column_stress(void)
{
    const double width = 0.3;
    SimWorld *w = box_pile(width, 0.6, 0, 25000);
    TEST_ASSERT(w);
    SimEnergy e = sim_world_energy(w);
    SimFrame f;
    sim_world_frame(w, &f);
    double top = 0.0;
    for (int i = 0; i < f.mobile_count; ++i)
        top = fmax(top, f.y[i]);
    TEST_ASSERT(e.kinetic < 1e-4 * e.potential);
    double *mass = malloc((size_t)f.count * sizeof *mass);
    TEST_ASSERT(mass);
    sim_world_masses(w, mass);
    SimCoarseDef d = sim_coarse_def_default();
    d.geometry = SIM_COARSE_PROFILE_Y;
    d.width = 0.04;
    d.contacts = 1;
    d.x0 = 0.0;
    d.x1 = width;
    d.y0 = 0.0;
    d.cell_y = 0.01;
    d.ny = (int)(top / 0.01) + 1;
    SimCoarse *cg = sim_coarse_create(&d, NULL);
    TEST_ASSERT(cg && sim_coarse_add(cg, &f, mass, 0.0, 0.0) == SIM_OK);
    double *syy = malloc((size_t)d.ny * sizeof *syy), *sxy = malloc((size_t)d.ny * sizeof *sxy);
    TEST_ASSERT(syy && sxy);
    sim_coarse_field(cg, SIM_CG_SYY, syy);
    sim_coarse_field(cg, SIM_CG_SXY, sxy);
    double base = 0.0;
    for (int i = 0; i < f.mobile_count; ++i)
        base += mass[i] * G0 / width;
    int checked = 0;
    for (int k = 0; k < d.ny; ++k) {
        double x, y;
        sim_coarse_node(cg, k, &x, &y);
        if (getenv("SABLIER_TEST_VERBOSE"))
            fprintf(stderr, "y %.3f syy %.4g sxy %.4g\n", y, syy[k], sxy[k]);
        if (y < 0.2 * top || y > 0.8 * top)
            continue;
        TEST_NEAR(sxy[k], 0.0, 0.05 * base);
        double above = 0.0;
        for (int i = 0; i < f.mobile_count; ++i) {
            double r = f.radius[i], h = f.y[i] - y; /* disk area above y, as a fraction */
            double share = h >= r ? 1.0
                           : h <= -r
                               ? 0.0
                               : 0.5 + (asin(h / r) + h / r * sqrt(1 - h * h / (r * r))) / TPI;
            above += share * mass[i] * G0 / width;
        }
        if (getenv("SABLIER_TEST_VERBOSE"))
            fprintf(stderr, "  above %.4g (%.3g)\n", above, syy[k] / above - 1);
        TEST_REL(syy[k], above, 0.03);
        ++checked;
    }
    TEST_ASSERT(checked > 10);
    free(syy);
    free(sxy);
    free(mass);
    sim_coarse_destroy(cg);
    sim_world_destroy(w);
    return 0;
}

/* A dilute gas (no contacts, no gravity) in a world: the kinetic stress over the region is
 * sum m v'v' / area with v' the velocity about the mean flow, and the contact stress is 0. */
static int kinetic_stress_gas(void)
{
    SimWorldDef def = tu_def(1000.0, 1e5, 1e-4);
    SimGrainBuffer buffer;
    sim_grain_buffer_init(&buffer);
    const int n = 30;
    const double a = 0.1;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            int k = sim_grain_buffer_add(&buffer, (i + 0.5) * a, (j + 0.5) * a, 0.02, 0, 0, -1);
            buffer.vx[k] = 1.0 + (((i + j) % 2) ? 0.5 : -0.5);
            buffer.vy[k] = ((j % 2) ? 0.2 : -0.2);
        }
    SimWorld *w = tu_create(&def, &buffer);
    sim_grain_buffer_free(&buffer);
    TEST_ASSERT(w);
    SimFrame f;
    sim_world_frame(w, &f);
    TEST_ASSERT(f.contact_count == 0);
    double *mass = malloc((size_t)f.count * sizeof *mass);
    TEST_ASSERT(mass);
    sim_world_masses(w, mass);
    SimCoarseDef d = sim_coarse_def_default();
    d.width = 0.3;
    d.contacts = 1;
    d.x0 = d.y0 = 0.0;
    d.cell_x = d.cell_y = 0.05;
    d.nx = d.ny = 60;
    SimCoarse *cg = sim_coarse_create(&d, NULL);
    TEST_ASSERT(cg && sim_coarse_add(cg, &f, mass, 0.0, 0.0) == SIM_OK);
    double mxx = 0.0, myy = 0.0, mxy = 0.0; /* sum m v'v' / area of the lattice */
    for (int i = 0; i < f.count; ++i) {
        double ux = f.vx[i] - 1.0, uy = f.vy[i];
        mxx += mass[i] * ux * ux / (n * a * n * a);
        mxy += mass[i] * ux * uy / (n * a * n * a);
        myy += mass[i] * uy * uy / (n * a * n * a);
    }
    double *v = malloc((size_t)sim_coarse_nodes(cg) * sizeof *v);
    TEST_ASSERT(v);
    const SimCoarseField fields[5] = {SIM_CG_SXX, SIM_CG_SXY, SIM_CG_SYY, SIM_CG_KXX, SIM_CG_CYY};
    const double expect[5] = {mxx, mxy, myy, mxx, 0.0};
    for (int q = 0; q < 5; ++q) {
        sim_coarse_field(cg, fields[q], v);
        for (int k = 0; k < sim_coarse_nodes(cg); ++k) {
            double x, y;
            sim_coarse_node(cg, k, &x, &y);
            if (x > 0.5 && x < n * a - 0.5 && y > 0.5 && y < n * a - 0.5)
                TEST_NEAR(v[k], expect[q], 2e-3 * mxx);
        }
    }
    free(v);
    free(mass);
    sim_coarse_destroy(cg);
    sim_world_destroy(w);
    return 0;
}

/* Grains raining through a line across the box: the net count through it (updated every step)
 * equals the change of the count below it, at every check, exactly; mass likewise. */
static int flux_counts_exactly(void)
{
    SimWorld *w = box_pile(0.3, 0.6, 0, 0);
    TEST_ASSERT(w);
    const double level = 0.2;
    SimFlux *flux = sim_flux_create(0.0, level, 0.3, level); /* drawn left to right: down = + */
    TEST_ASSERT(flux && sim_flux_update(flux, w) == SIM_OK);
    double *mass = malloc((size_t)sim_world_grain_count(w) * sizeof *mass);
    TEST_ASSERT(mass);
    long below0 = -1, moved = 0;
    double mass0 = 0.0;
    for (int check = 0; check <= 40; ++check) {
        if (check > 0)
            for (int s = 0; s < 250; ++s) {
                TEST_ASSERT(sim_world_step(w, 1, NULL) == SIM_OK);
                TEST_ASSERT(sim_flux_update(flux, w) == SIM_OK);
            }
        SimFrame f;
        sim_world_frame(w, &f);
        sim_world_masses(w, mass);
        long below = 0;
        double below_mass = 0.0;
        for (int i = 0; i < f.mobile_count; ++i)
            if (!(f.y[i] - level > 0.0)) { /* the right of the segment: on it or below */
                ++below;
                below_mass += mass[i];
            }
        if (below0 < 0) {
            below0 = below;
            mass0 = below_mass;
        }
        long count;
        double flux_mass;
        sim_flux_totals(flux, &count, &flux_mass);
        TEST_ASSERT(count == below - below0);
        TEST_NEAR(flux_mass, below_mass - mass0, 1e-9 * below_mass);
        moved = count;
    }
    TEST_ASSERT(moved > 50);
    free(mass);
    sim_flux_destroy(flux);
    sim_world_destroy(w);
    return 0;
}

/* Profiles along x of the lattice (Lucy and Gaussian kernels): the exact packing fraction away
 * from the ends, and the mean velocity in a frame moving with the lattice is 0. */
static int lattice_profile_x_in_frame(void)
{
    const int n = 40;
    const double a = 0.1, radius = 0.04;
    Lattice l;
    TEST_ASSERT(lattice_make(&l, n, a, radius, 0.5, -0.2) == 0);
    for (int kind = 0; kind < 2; ++kind) {
        SimCoarseDef d = sim_coarse_def_default();
        d.kernel = (SimKernel)kind;
        d.geometry = SIM_COARSE_PROFILE_X;
        d.width = 0.35;
        d.x0 = -0.5;
        d.cell_x = 0.05;
        d.nx = (int)((n * a + 1.0) / 0.05);
        d.y0 = 0.0;
        d.y1 = n * a; /* the strip holds every grain */
        SimCoarse *cg = sim_coarse_create(&d, NULL);
        TEST_ASSERT(cg && sim_coarse_add(cg, &l.frame, l.mass, 0.5, -0.2) == SIM_OK);
        double phi[200], vy[200];
        TEST_ASSERT(sim_coarse_nodes(cg) <= 200);
        sim_coarse_field(cg, SIM_CG_PHI, phi);
        sim_coarse_field(cg, SIM_CG_VY, vy);
        for (int k = 0; k < sim_coarse_nodes(cg); ++k) {
            double x, y;
            sim_coarse_node(cg, k, &x, &y);
            if (x < 0.6 || x > n * a - 0.6)
                continue;
            TEST_REL(phi[k], TPI * radius * radius / (a * a), 1e-4);
            TEST_NEAR(vy[k], 0.0, 1e-12);
        }
        sim_coarse_destroy(cg);
    }
    lattice_free(&l);
    return 0;
}

TEST_MAIN(TEST_CASE(kernel_1d_integrates), TEST_CASE(lattice_fields_exact),
          TEST_CASE(lattice_profile_x_in_frame), TEST_CASE(contact_stress_virial),
          TEST_CASE(settled_column_stress), TEST_CASE(kinetic_stress_gas),
          TEST_CASE(flux_counts_exactly))
