/* SPDX-License-Identifier: MIT */
/* Stability hard cases about removing grains that are in contact: sinks under an orifice opened
 * beneath a loaded pile (004 §7.5), sim_world_remove_rect and sim_world_remove_ids on a settled
 * pile with tangential-spring history. */
#include "stab_util.h"
#include "test.h"

#include <stdlib.h>

enum { PILE = 150 };

/* The material of these piles: disk r 0.5, density 1, k 1e5, e_n 0.3, gravity; the tangential law
 * `law` (mu 0.5: spring k_t 0.75e5, regularised gamma_s 5), a sink below y = -2 when `sink`. */
static SimWorldDef pile_def(SimTangentialLaw law, int sink)
{
    SimWorldDef def = tu_def(1.0, 1e5, 0.0);
    def.gravity_y = -G0;
    def.guard_max_speed = 0.0;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.3;
    if (law != SIM_TANGENTIAL_NONE) {
        def.effects |= SIM_EFFECT_FRICTION;
        def.contact.tangential = law;
        def.materials[0].friction = 0.5;
        def.materials[0].tangential_stiffness = 0.75e5;
        def.materials[0].tangential_damping = 5.0;
    }
    if (sink) {
        def.effects |= SIM_EFFECT_REMOVAL;
        def.sink_count = 1;
        def.sinks[0] = (SimSink){.shape = SIM_SINK_BELOW, .level = -2.0};
    }
    return def;
}

/* A settled pile of PILE grains (disk r 0.5, density 1, k 1e5, e_n 0.3) in a box of fixed grains
 * (r 0.5, floor centres at y = 0, inner width 16), tangential spring (mu 0.5) when `spring`, a
 * sink below y = -2 when `sink`. Settled for 1.5 s. */
static SimWorld *settled_pile(int spring, int sink, double *top)
{
    const double r = 0.5;
    SimWorldDef def = pile_def(spring ? SIM_TANGENTIAL_SPRING : SIM_TANGENTIAL_NONE, sink);
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    st_fixed_box(&b, 17.0, 30.0, r, 0);
    SimRng rng;
    sim_rng_seed(&rng, 17);
    st_lattice(&b, &rng, PILE, 0.5, 16.5, r, 0.45, 0.5, 0.02);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    if (!w)
        return NULL;
    if (tu_step(w, (long)(1.5 / sim_world_time_step(w))) != 0) {
        sim_world_destroy(w);
        return NULL;
    }
    SimFrame f;
    sim_world_frame(w, &f);
    *top = -INFINITY;
    for (int i = 0; i < f.mobile_count; ++i)
        *top = fmax(*top, f.y[i] + f.radius[i]);
    return w;
}

/* Every force in the frame finite and the per-grain force sums finite. */
static int forces_finite(SimWorld *w)
{
    return st_finite(w);
}

/* Open an orifice 3 d wide under the loaded pile by removing fixed floor grains
 * (sim_world_remove_ids), let grains drain into the sink below y = -2 for 2 s. Bounds: the call
 * returns the number of ids found (3); no NaN and finite forces right after the removal and at
 * every sample; mobile count + removed by the sink = PILE at every sample; some grains drained;
 * no grain ever faster than 1.5 x the free-fall speed from the pile top to the sink,
 * sqrt(2 g (top + 2)) (no explosion from the sudden unbalanced load). */
static int orifice_opened_under_load(void)
{
    double top;
    SimWorld *w = settled_pile(0, 1, &top);
    TEST_ASSERT(w);
    SimFrame f;
    sim_world_frame(w, &f);
    uint32_t ids[3];
    int found = 0;
    for (int i = f.mobile_count; i < f.count && found < 3; ++i) /* floor grains near x = 8.5 */
        if (f.y[i] == 0.0 && fabs(f.x[i] - 8.5) < 1.6)
            ids[found++] = f.id[i];
    TEST_ASSERT(found == 3);
    int fixed_before = f.count - f.mobile_count;
    TEST_ASSERT(sim_world_remove_ids(w, ids, 3) == 3);
    TEST_ASSERT(forces_finite(w));
    sim_world_frame(w, &f);
    TEST_ASSERT(f.count - f.mobile_count == fixed_before - 3);
    double v_max = 1.5 * sqrt(2.0 * G0 * (top + 2.0)), worst = 0.0;
    long chunk = 100, steps = (long)(2.0 / sim_world_time_step(w));
    for (long done = 0; done < steps; done += chunk) {
        TEST_ASSERT(tu_step(w, chunk) == 0);
        TEST_ASSERT(forces_finite(w));
        TEST_ASSERT(sim_world_mobile_count(w) + sim_world_removed_count(w, 0) == PILE);
        sim_world_frame(w, &f);
        for (int i = 0; i < f.mobile_count; ++i)
            worst = fmax(worst, hypot(f.vx[i], f.vy[i]));
    }
    fprintf(stderr, "orifice: removed %ld, max speed %.3g of bound\n",
            sim_world_removed_count(w, 0), worst / v_max);
    TEST_ASSERT(sim_world_removed_count(w, 0) > 10);
    TEST_ASSERT(worst < v_max);
    sim_world_destroy(w);
    return 0;
}

/* sim_world_remove_rect through the middle of a settled pile with spring history: returns exactly
 * the number of mobile centres in the rectangle (counted from the frame before), the mobile count
 * drops by that much, the fixed grains are untouched, forces stay finite, and the remaining grains
 * then run 1 s with no NaN, overlap < 0.05 d and the Coulomb cap |F_t| <= mu k_n xi on every
 * contact. */
static int remove_rect_settled(void)
{
    double top;
    SimWorld *w = settled_pile(1, 0, &top);
    TEST_ASSERT(w);
    SimFrame f;
    sim_world_frame(w, &f);
    const double x0 = 6.0, x1 = 11.0, y0 = 1.0, y1 = 3.0;
    int inside = 0, mobile = f.mobile_count, fixed = f.count - f.mobile_count;
    for (int i = 0; i < f.mobile_count; ++i)
        inside += f.x[i] >= x0 && f.x[i] <= x1 && f.y[i] >= y0 && f.y[i] <= y1;
    TEST_ASSERT(inside > 5);
    TEST_ASSERT(sim_world_remove_rect(w, x0, y0, x1, y1) == inside);
    TEST_ASSERT(forces_finite(w));
    TEST_ASSERT(sim_world_mobile_count(w) == mobile - inside);
    TEST_ASSERT(sim_world_grain_count(w) - sim_world_mobile_count(w) == fixed);
    StRun run = st_run(w, (long)(1.0 / sim_world_time_step(w)), 50);
    st_report("remove_rect_settled", &run);
    TEST_ASSERT(run.status == SIM_OK && run.finite);
    TEST_ASSERT(run.overlap_max < 0.05);
    sim_world_frame(w, &f);
    for (int c = 0; c < f.contact_count; ++c)
        TEST_ASSERT(fabs(f.contacts[c].tangential_force) <=
                    0.5 * 1e5 * f.contacts[c].overlap * (1.0 + 1e-12) + 1e-300);
    sim_world_destroy(w);
    return 0;
}

/* sim_world_remove_ids on every third mobile grain of the settled spring pile (all in contact),
 * with two unknown ids and one duplicate in the list: returns the number found, counts drop
 * accordingly, forces stay finite, the removed ids are gone from the frame, and the rest runs 0.5 s
 * without NaN and with overlap < 0.05 d. */
static int remove_ids_in_contact(void)
{
    double top;
    SimWorld *w = settled_pile(1, 0, &top);
    TEST_ASSERT(w);
    SimFrame f;
    sim_world_frame(w, &f);
    uint32_t ids[PILE + 3];
    int n = 0, mobile = f.mobile_count;
    for (int i = 0; i < f.mobile_count; i += 3)
        ids[n++] = f.id[i];
    int expected = n;
    ids[n++] = 999999u;
    ids[n++] = 888888u;
    ids[n++] = ids[0]; /* duplicate */
    TEST_ASSERT(sim_world_remove_ids(w, ids, n) == expected);
    TEST_ASSERT(forces_finite(w));
    TEST_ASSERT(sim_world_mobile_count(w) == mobile - expected);
    sim_world_frame(w, &f);
    for (int k = 0; k < expected; ++k)
        TEST_ASSERT(tu_index(&f, ids[k]) < 0);
    StRun run = st_run(w, (long)(0.5 / sim_world_time_step(w)), 50);
    st_report("remove_ids_in_contact", &run);
    TEST_ASSERT(run.status == SIM_OK && run.finite);
    TEST_ASSERT(run.overlap_max < 0.05);
    sim_world_destroy(w);
    return 0;
}

/* Grains drain through a 3 d gap in the floor into a sink during ONE long sim_world_step call, so
 * that sinks remove grains at list builds inside steps (the arrays are compacted in the middle of
 * an integrator step). For every integrator, the fixed grains must come out exactly as they went
 * in: same positions, zero velocity and spin. (Velocity Verlet's closing kick, Gear's corrector
 * and RK4's final sum once looped over the mobile count of the step's start, which after a
 * removal includes fixed grains: they were given velocities, and under RK4 moved.) */
static int fixed_grains_still_through_removal(void)
{
    static const SimIntegrator integrators[] = {
        SIM_INTEGRATOR_VELOCITY_VERLET, SIM_INTEGRATOR_SYMPLECTIC_EULER,
        SIM_INTEGRATOR_STORMER_VERLET, SIM_INTEGRATOR_GEAR, SIM_INTEGRATOR_RK4};
    for (int n = 0; n < (int)(sizeof integrators / sizeof integrators[0]); ++n) {
        const double r = 0.5;
        SimWorldDef def = pile_def(SIM_TANGENTIAL_REGULARISED, 1); /* RK4 refuses history */
        def.integrator = integrators[n];
        SimGrainBuffer b;
        sim_grain_buffer_init(&b);
        st_fixed_box(&b, 17.0, 30.0, r, 0);
        SimRng rng;
        sim_rng_seed(&rng, 17);
        st_lattice(&b, &rng, 60, 0.5, 16.5, r, 0.45, 0.5, 0.02);
        SimWorld *w = tu_create(&def, &b);
        sim_grain_buffer_free(&b);
        TEST_ASSERT(w);
        SimFrame f;
        sim_world_frame(w, &f);
        uint32_t gap[3];
        int found = 0;
        for (int i = f.mobile_count; i < f.count && found < 3; ++i)
            if (f.y[i] == 0.0 && fabs(f.x[i] - 8.5) < 1.6)
                gap[found++] = f.id[i];
        TEST_ASSERT(found == 3);
        TEST_ASSERT(sim_world_remove_ids(w, gap, 3) == 3);
        sim_world_frame(w, &f);
        const int fixed = f.count - f.mobile_count;
        double *x0 = malloc((size_t)fixed * 2 * sizeof *x0);
        uint32_t *id0 = malloc((size_t)fixed * sizeof *id0);
        TEST_ASSERT(x0 && id0);
        for (int k = 0; k < fixed; ++k) {
            id0[k] = f.id[f.mobile_count + k];
            x0[2 * k] = f.x[f.mobile_count + k];
            x0[2 * k + 1] = f.y[f.mobile_count + k];
        }
        TEST_ASSERT(tu_step(w, (long)(1.5 / sim_world_time_step(w))) == 0); /* one call */
        TEST_ASSERT(sim_world_removed_count(w, 0) >= 5);
        sim_world_frame(w, &f);
        TEST_ASSERT(f.count - f.mobile_count == fixed);
        for (int i = f.mobile_count; i < f.count; ++i) {
            int k = 0;
            while (k < fixed && id0[k] != f.id[i])
                ++k;
            TEST_ASSERT(k < fixed);
            TEST_ASSERT(f.x[i] == x0[2 * k] && f.y[i] == x0[2 * k + 1]);
            TEST_ASSERT(f.vx[i] == 0.0 && f.vy[i] == 0.0 && f.omega[i] == 0.0);
        }
        free(x0);
        free(id0);
        sim_world_destroy(w);
    }
    return 0;
}

TEST_MAIN(TEST_CASE(orifice_opened_under_load), TEST_CASE(remove_rect_settled),
          TEST_CASE(remove_ids_in_contact), TEST_CASE(fixed_grains_still_through_removal))
