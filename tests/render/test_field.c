/* SPDX-License-Identifier: MIT */
/* Coarse-grained velocity field (MercuryCG-style V = sum m v W / sum m W): kernel normalisation,
 * uniform motion, mass weighting, linear shear, solid fraction, periodic wrap. */
#include "fixture.h"
#include "test.h"

#define PI 3.14159265358979323846

/* Hexagonal lattice of equal grains (touching) filling [0, w] x [0, h]. */
static int lattice(Fixture *f, double r, double w, double h)
{
    int cols = (int)(w / (2 * r)) + 1, rows = (int)(h / (sqrt(3.0) * r)) + 1;
    if (fixture_init(f, cols * rows, 0, 1) != 0)
        return -1;
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < cols; ++i)
            fixture_add(f, (2 * i + (j % 2)) * r, j * sqrt(3.0) * r, r, 0);
    return 0;
}

/* The integral of W over the plane is 1 (polar quadrature, midpoint rule). */
static int kernel_normalised(void)
{
    for (int kind = 0; kind < 2; ++kind) {
        double width = 0.3, sum = 0;
        int n = 20000;
        double dr = width / n;
        for (int k = 0; k < n; ++k) {
            double r = (k + 0.5) * dr;
            sum += render_kernel((RenderKernel)kind, r, width) * 2 * PI * r * dr;
        }
        TEST_NEAR(sum, 1.0, 1e-6);
        TEST_NEAR(render_kernel((RenderKernel)kind, width, width), 0, 0);
        TEST_NEAR(render_kernel((RenderKernel)kind, 2 * width, width), 0, 0);
        TEST_ASSERT(render_kernel((RenderKernel)kind, 0, width) >
                    render_kernel((RenderKernel)kind, 0.5 * width, width));
    }
    /* Lucy at the centre: 5 / (pi c^2). */
    TEST_REL(render_kernel(RENDER_KERNEL_LUCY, 0, 2.0), 5.0 / (PI * 4.0), 1e-15);
    return 0;
}

/* Every grain moving with the same velocity: every non-empty node has exactly that velocity. */
static int uniform_motion(void)
{
    Fixture f;
    TEST_ASSERT(lattice(&f, 0.01, 0.3, 0.2) == 0);
    for (int i = 0; i < f.frame.count; ++i) {
        f.vx[i] = 0.3;
        f.vy[i] = -0.2;
        f.radius[i] *= 1 + 0.1 * ((i * 7) % 5) / 5.0; /* polydisperse masses */
    }
    for (int kind = 0; kind < 2; ++kind) {
        RenderFieldDef def = {.x0 = 0,
                              .y0 = 0,
                              .x1 = 0.3,
                              .y1 = 0.2,
                              .cell = 0.02,
                              .width = 0.03,
                              .kernel = (RenderKernel)kind,
                              .mass_power = 2};
        RenderField field;
        TEST_ASSERT(render_velocity_field(&f.frame, &def, &field) == 0);
        TEST_ASSERT(field.nx == 15 && field.ny == 10);
        int checked = 0;
        for (int k = 0; k < field.nx * field.ny; ++k) {
            if (field.packing[k] <= 0)
                continue;
            TEST_NEAR(field.vx[k], 0.3, 1e-14);
            TEST_NEAR(field.vy[k], -0.2, 1e-14);
            ++checked;
        }
        TEST_ASSERT(checked == field.nx * field.ny);
        render_field_free(&field);
    }
    fixture_free(&f);
    return 0;
}

/* Two grains at the same distance from a node: V is the mass-weighted mean (m ~ r^2 for disks,
 * r^3 for spheres), not the plain mean of the two velocities. */
static int mass_weighted(void)
{
    Fixture f;
    TEST_ASSERT(fixture_init(&f, 2, 0, 1) == 0);
    int a = fixture_add(&f, 0.5 - 0.1, 0.5, 0.02, 0);
    int b = fixture_add(&f, 0.5 + 0.1, 0.5, 0.01, 0);
    f.vx[a] = 1.0;
    f.vx[b] = -1.0;
    f.vy[a] = 0.5;
    RenderFieldDef def = {.x0 = 0.4,
                          .y0 = 0.4,
                          .x1 = 0.6,
                          .y1 = 0.6,
                          .cell = 0.2,
                          .width = 0.25,
                          .kernel = RENDER_KERNEL_LUCY,
                          .mass_power = 2};
    RenderField field;
    TEST_ASSERT(render_velocity_field(&f.frame, &def, &field) == 0);
    TEST_ASSERT(field.nx == 1 && field.ny == 1); /* the node sits at (0.5, 0.5) */
    TEST_NEAR(field.vx[0], (4.0 - 1.0) / 5.0, 1e-14);
    TEST_NEAR(field.vy[0], 4.0 * 0.5 / 5.0, 1e-14);
    double w = render_kernel(RENDER_KERNEL_LUCY, 0.1, 0.25);
    TEST_REL(field.packing[0], PI * (0.02 * 0.02 + 0.01 * 0.01) * w, 1e-13);
    render_field_free(&field);
    def.mass_power = 3;
    TEST_ASSERT(render_velocity_field(&f.frame, &def, &field) == 0);
    TEST_NEAR(field.vx[0], (8.0 - 1.0) / 9.0, 1e-14);
    render_field_free(&field);
    fixture_free(&f);
    return 0;
}

/* Simple shear v_x = gamma y on a lattice: interior nodes recover gamma y_node to a fraction of
 * gamma d (lattice discreteness), and the solid fraction is that of the hexagonal packing,
 * pi / (2 sqrt 3). */
static int shear_and_packing(void)
{
    Fixture f;
    double r = 0.01, gamma = 3.0;
    TEST_ASSERT(lattice(&f, r, 0.4, 0.4) == 0);
    for (int i = 0; i < f.frame.count; ++i)
        f.vx[i] = gamma * f.y[i];
    RenderFieldDef def = {.x0 = 0,
                          .y0 = 0,
                          .x1 = 0.4,
                          .y1 = 0.4,
                          .cell = 0.04,
                          .width = 0.08,
                          .kernel = RENDER_KERNEL_GAUSSIAN,
                          .mass_power = 2};
    RenderField field;
    TEST_ASSERT(render_velocity_field(&f.frame, &def, &field) == 0);
    int checked = 0;
    for (int j = 3; j < field.ny - 3; ++j)
        for (int i = 3; i < field.nx - 3; ++i) {
            size_t k = (size_t)j * (size_t)field.nx + (size_t)i;
            double y = field.y0 + (j + 0.5) * field.cell;
            TEST_NEAR(field.vx[k], gamma * y, 0.02 * gamma * 2 * r);
            TEST_NEAR(field.vy[k], 0, 1e-15);
            TEST_NEAR(field.packing[k], PI / (2 * sqrt(3.0)), 0.01);
            ++checked;
        }
    TEST_ASSERT(checked == 16);
    render_field_free(&field);
    fixture_free(&f);
    return 0;
}

/* Periodic frames: a grain just inside the right edge feeds nodes near the left edge. */
static int periodic_wrap(void)
{
    Fixture f;
    TEST_ASSERT(fixture_init(&f, 1, 0, 1) == 0);
    fixture_add(&f, 0.99, 0.5, 0.01, 0);
    f.vx[0] = 2.0;
    RenderFieldDef def = {.x0 = 0,
                          .y0 = 0,
                          .x1 = 1,
                          .y1 = 1,
                          .cell = 0.1,
                          .width = 0.08,
                          .kernel = RENDER_KERNEL_LUCY,
                          .mass_power = 2};
    RenderField field;
    TEST_ASSERT(render_velocity_field(&f.frame, &def, &field) == 0);
    size_t left = 4 * (size_t)field.nx + 0; /* node (0.05, 0.45) */
    TEST_ASSERT(field.packing[left] == 0);  /* not periodic: out of reach */
    render_field_free(&field);
    f.frame.periodic = 1;
    f.frame.domain_x0 = 0;
    f.frame.domain_x1 = 1;
    TEST_ASSERT(render_velocity_field(&f.frame, &def, &field) == 0);
    /* The image at x = -0.01 is 0.06 from the node in x and 0.05 in y. */
    double w = render_kernel(RENDER_KERNEL_LUCY, hypot(0.06, 0.05), 0.08);
    TEST_ASSERT(w > 0);
    TEST_REL(field.packing[left], PI * 0.01 * 0.01 * w, 1e-12);
    TEST_NEAR(field.vx[left], 2.0, 1e-15);
    render_field_free(&field);
    fixture_free(&f);
    return 0;
}

/* Fixed grains are not part of the flow; bad definitions are refused. */
static int fixed_and_bad_input(void)
{
    Fixture f;
    TEST_ASSERT(fixture_init(&f, 2, 0, 1) == 0);
    fixture_add(&f, 0.5, 0.5, 0.01, SIM_GRAIN_FIXED);
    f.vx[0] = 5;
    RenderFieldDef def = {.x0 = 0,
                          .y0 = 0,
                          .x1 = 1,
                          .y1 = 1,
                          .cell = 0.1,
                          .width = 0.2,
                          .kernel = RENDER_KERNEL_LUCY,
                          .mass_power = 2};
    RenderField field;
    TEST_ASSERT(render_velocity_field(&f.frame, &def, &field) == 0);
    for (int k = 0; k < field.nx * field.ny; ++k)
        TEST_ASSERT(field.packing[k] == 0 && field.vx[k] == 0);
    render_field_free(&field);
    def.cell = 0;
    TEST_ASSERT(render_velocity_field(&f.frame, &def, &field) == -1);
    TEST_ASSERT(field.vx == NULL);
    def.cell = 0.1;
    def.x1 = -1;
    TEST_ASSERT(render_velocity_field(&f.frame, &def, &field) == -1);
    fixture_free(&f);
    return 0;
}

TEST_MAIN(TEST_CASE(kernel_normalised), TEST_CASE(uniform_motion), TEST_CASE(mass_weighted),
          TEST_CASE(shear_and_packing), TEST_CASE(periodic_wrap), TEST_CASE(fixed_and_bad_input))
