/* SPDX-License-Identifier: MIT */
/* Stability hard cases refused (or accepted) at set-up: non-finite and degenerate input. Each
 * refusal must come from sim_world_def_validate and sim_world_create alike, with
 * SIM_ERROR_INVALID, the offending field and a message naming the problem. */
#include "stab_util.h"
#include "test.h"

/* Two grains and a floor wall, valid as given. */
typedef struct Setup {
    SimGrainBuffer b;
    SimWall wall;
    SimWorldDef def;
} Setup;

static void setup_init(Setup *s)
{
    sim_grain_buffer_init(&s->b);
    sim_grain_buffer_add(&s->b, 0.0, 1.0, 0.5, 0, 0u, -1);
    sim_grain_buffer_add(&s->b, 2.0, 1.0, 0.5, 0, 0u, -1);
    s->wall = (SimWall){.x0 = -5.0, .y0 = 0.0, .x1 = 5.0, .y1 = 0.0, .species = 0, .motion = -1};
    s->def = tu_def(1.0, 1e4, 0.0);
    s->def.gravity_y = -G0;
    s->def.wall_count = 1;
    s->def.walls = &s->wall;
    s->def.grains = sim_grain_buffer_view(&s->b);
}

/* Refused by both entry points with `field` and a message containing `word`. */
static int refused(Setup *s, const char *field, const char *word)
{
    SimError err;
    SimStatus v = sim_world_def_validate(&s->def, &err);
    fprintf(stderr, "validate: %d %s: %s\n", (int)v, err.field, err.message);
    TEST_ASSERT(v == SIM_ERROR_INVALID);
    TEST_ASSERT(strcmp(err.field, field) == 0);
    TEST_ASSERT(st_mentions(err.message, word));
    memset(&err, 0, sizeof err);
    SimWorld *w = sim_world_create(&s->def, &err);
    if (w)
        sim_world_destroy(w);
    TEST_ASSERT(w == NULL);
    TEST_ASSERT(err.status == SIM_ERROR_INVALID && strcmp(err.field, field) == 0);
    sim_grain_buffer_free(&s->b);
    return 0;
}

/* Sanity: the unmodified set-up is accepted. */
static int valid_setup_accepted(void)
{
    Setup s;
    setup_init(&s);
    SimError err;
    TEST_ASSERT(sim_world_def_validate(&s.def, &err) == SIM_OK);
    SimWorld *w = sim_world_create(&s.def, &err);
    TEST_ASSERT(w);
    sim_world_destroy(w);
    sim_grain_buffer_free(&s.b);
    return 0;
}

/* NaN and infinite positions: refused on grains[1], message "non-finite position". */
static int nan_position_refused(void)
{
    Setup s;
    setup_init(&s);
    s.b.x[1] = NAN;
    if (refused(&s, "grains[1]", "non-finite"))
        return 1;
    setup_init(&s);
    s.b.y[1] = INFINITY;
    return refused(&s, "grains[1]", "non-finite");
}

/* NaN initial velocity or spin: the state would be NaN from the first step, so it must be refused
 * like a NaN position (grains[1], "non-finite"). */
static int nan_velocity_refused(void)
{
    Setup s;
    setup_init(&s);
    s.b.vx[1] = NAN;
    if (refused(&s, "grains[1]", "non-finite"))
        return 1;
    setup_init(&s);
    s.b.omega[1] = INFINITY;
    return refused(&s, "grains[1]", "non-finite");
}

/* Zero, negative, NaN and infinite radii: refused on grains[0], message mentions "radius". */
static int zero_radius_refused(void)
{
    const double bad[4] = {0.0, -0.5, NAN, INFINITY};
    for (int k = 0; k < 4; ++k) {
        Setup s;
        setup_init(&s);
        s.b.radius[0] = bad[k];
        if (refused(&s, "grains[0]", "radius"))
            return 1;
    }
    return 0;
}

/* A grain overlapping a wall by 0.25 d at the start: refused on grains[0], message "overlaps
 * wall". Also a non-finite wall end point: refused on walls[0]. */
static int wall_overlap_refused(void)
{
    Setup s;
    setup_init(&s);
    s.b.y[0] = 0.25;
    if (refused(&s, "grains[0]", "overlaps wall"))
        return 1;
    setup_init(&s);
    s.wall.x1 = NAN;
    return refused(&s, "walls[0]", "non-finite");
}

/* A grain resting on a floor wall at its equilibrium overlap (m g / k = 4e-4 d here), as a
 * settled pile restarted from a checkpoint would be: this is not an input error and must be
 * accepted (a refusal threshold belongs at a real overlap, e.g. the guard bound, not at 0). */
static int resting_overlap_on_wall_accepted(void)
{
    Setup s;
    setup_init(&s);
    double m = tu_mass(SIM_MASS_DISK, 1.0, 0.5);
    s.b.y[0] = 0.5 - m * G0 / 1e4;
    SimError err;
    SimStatus v = sim_world_def_validate(&s.def, &err);
    fprintf(stderr, "validate: %d %s: %s\n", (int)v, err.field, err.message);
    TEST_ASSERT(v == SIM_OK);
    SimWorld *w = sim_world_create(&s.def, &err);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 1000) == 0);
    TEST_ASSERT(st_finite(w));
    sim_world_destroy(w);
    sim_grain_buffer_free(&s.b);
    return 0;
}

/* Non-finite or non-positive material constants and time step: refused with the material field. */
static int bad_material_refused(void)
{
    Setup s;
    setup_init(&s);
    s.def.materials[0].normal_stiffness = NAN;
    if (refused(&s, "materials[0].normal_stiffness", "stiffness"))
        return 1;
    setup_init(&s);
    s.def.materials[0].density = 0.0;
    if (refused(&s, "materials[0].density", "density"))
        return 1;
    setup_init(&s);
    s.def.time_step = -1e-5;
    return refused(&s, "time_step", "time step");
}

TEST_MAIN(TEST_CASE(valid_setup_accepted), TEST_CASE(nan_position_refused),
          TEST_CASE(nan_velocity_refused), TEST_CASE(zero_radius_refused),
          TEST_CASE(wall_overlap_refused), TEST_CASE(resting_overlap_on_wall_accepted),
          TEST_CASE(bad_material_refused))
