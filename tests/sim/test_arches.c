/* SPDX-License-Identifier: MIT */
/* Arch search (004 §2.5, one-sided bug fixed) on hand-built frames: a known arch, a one-sided
 * chain that must be rejected, no arch, a concave arch, and the optional force check. */
#include "test.h"

#include "sim/sim.h"

#include <stdlib.h>

#define MAX_GRAINS 256
#define MAX_LINKS  256

typedef struct Fixture {
    SimFrame frame;
    int count, mobile, links;
    double x[MAX_GRAINS], y[MAX_GRAINS], r[MAX_GRAINS];
    unsigned flags[MAX_GRAINS];
    SimContact contacts[MAX_LINKS];
} Fixture;

/* Mobile grains (d = 1) are added first, then fixed base grains (d = 0.1). */
static int add_grain(Fixture *f, double x, double y, double r)
{
    if (f->count >= MAX_GRAINS)
        abort();
    f->x[f->count] = x;
    f->y[f->count] = y;
    f->r[f->count] = r;
    f->flags[f->count] = 0;
    return f->count++;
}

static void link(Fixture *f, int i, int j, double force)
{
    f->contacts[f->links++] = (SimContact){.i = i, .j = j, .normal_force = force};
}

/* Base of fixed grains (radius 0.05) at y = 0 outside the orifice |x| < half_gap; links every
 * mobile grain touching it to the base grain below it. */
static void finish(Fixture *f, double half_gap)
{
    f->mobile = f->count;
    for (double x = -6.0; x <= 6.0 + 1e-9; x += 0.1) {
        if (x > -half_gap && x < half_gap)
            continue;
        int b = add_grain(f, x, 0.0, 0.05);
        f->flags[b] = SIM_GRAIN_FIXED;
        for (int i = 0; i < f->mobile; ++i) {
            double dx = f->x[i] - x, dy = f->y[i];
            if (dx * dx + dy * dy <= (f->r[i] + 0.05) * (f->r[i] + 0.05) * (1.0 + 1e-9))
                link(f, i, b, 1.0);
        }
    }
    f->frame = (SimFrame){.count = f->count,
                          .mobile_count = f->mobile,
                          .x = f->x,
                          .y = f->y,
                          .radius = f->r,
                          .flags = f->flags,
                          .contact_count = f->links,
                          .contacts = f->contacts};
}

/* Keystone at (0, 1.75); branches step 0.8 sideways and 0.6 down (touching, distance 1) to
 * feet at y = 0.55 that touch the base; one grain rests on the keystone. */
static void build_arch(Fixture *f, int right_foot_on_base, double keystone_link_force)
{
    f->count = f->links = 0;
    int k = add_grain(f, 0.0, 1.75, 0.5);
    int l1 = add_grain(f, -0.8, 1.15, 0.5), l2 = add_grain(f, -1.6, 0.55, 0.5);
    int r1 = add_grain(f, 0.8, 1.15, 0.5);
    int r2 = add_grain(f, 1.6, right_foot_on_base ? 0.55 : 0.75, 0.5);
    int top = add_grain(f, 0.0, 2.75, 0.5);
    link(f, k, l1, keystone_link_force);
    link(f, l1, l2, 1.0);
    link(f, k, r1, 1.0);
    link(f, r1, r2, 1.0);
    link(f, k, top, 1.0);
    finish(f, 1.2);
}

static int known_arch(void)
{
    static Fixture f;
    build_arch(&f, 1, 1.0);
    int members[MAX_GRAINS];
    int n = sim_frame_find_arch(&f.frame, 0.0, 0, members, MAX_GRAINS);
    TEST_ASSERT(n == 5);
    /* left to right: l2, l1, keystone, r1, r2 */
    int expected[5] = {2, 1, 0, 3, 4};
    for (int k = 0; k < 5; ++k)
        TEST_ASSERT(members[k] == expected[k]);
    return 0;
}

static int one_sided_chain_rejected(void)
{
    static Fixture f;
    build_arch(&f, 0, 1.0); /* the right foot hangs above the orifice edge: no base contact */
    int members[MAX_GRAINS];
    TEST_ASSERT(sim_frame_find_arch(&f.frame, 0.0, 0, members, MAX_GRAINS) == 0);
    return 0;
}

static int empty_centre_no_arch(void)
{
    static Fixture f;
    f.count = f.links = 0;
    /* two piles on either side of a wide hole: nothing within half a diameter of the axis */
    for (int k = 0; k < 4; ++k) {
        add_grain(&f, -3.0 - k, 0.55, 0.5);
        add_grain(&f, 3.0 + k, 0.55, 0.5);
    }
    finish(&f, 2.0);
    int members[MAX_GRAINS];
    TEST_ASSERT(sim_frame_find_arch(&f.frame, 0.0, 0, members, MAX_GRAINS) == 0);
    return 0;
}

static int grain_on_floor_is_not_an_arch(void)
{
    static Fixture f;
    f.count = f.links = 0;
    /* a lone grain sitting in a narrow orifice with no neighbours: branches find nothing */
    add_grain(&f, 0.0, 0.45, 0.5);
    finish(&f, 0.3);
    int members[MAX_GRAINS];
    TEST_ASSERT(sim_frame_find_arch(&f.frame, 0.0, 0, members, MAX_GRAINS) == 0);
    return 0;
}

static int concave_arch_accepted(void)
{
    static Fixture f;
    f.count = f.links = 0;
    /* left branch first rises (concave region, Garcimartin et al. 2010), then descends */
    int k = add_grain(&f, 0.0, 1.75, 0.5);
    int l1 = add_grain(&f, -0.8, 2.35, 0.5), l2 = add_grain(&f, -1.6, 1.75, 0.5);
    int l3 = add_grain(&f, -2.4, 1.15, 0.5), l4 = add_grain(&f, -3.2, 0.55, 0.5);
    int r1 = add_grain(&f, 0.8, 1.15, 0.5), r2 = add_grain(&f, 1.6, 0.55, 0.5);
    link(&f, k, l1, 1.0);
    link(&f, l1, l2, 1.0);
    link(&f, l2, l3, 1.0);
    link(&f, l3, l4, 1.0);
    link(&f, k, r1, 1.0);
    link(&f, r1, r2, 1.0);
    finish(&f, 1.2);
    int members[MAX_GRAINS];
    int n = sim_frame_find_arch(&f.frame, 0.0, 0, members, MAX_GRAINS);
    TEST_ASSERT(n == 7);
    TEST_ASSERT(members[0] == l4 && members[3] == l1 && members[4] == k && members[6] == r2);
    return 0;
}

static int force_check_rejects_unloaded_link(void)
{
    static Fixture f;
    build_arch(&f, 1, 0.0); /* keystone touches its left neighbour without any force */
    int members[MAX_GRAINS];
    TEST_ASSERT(sim_frame_find_arch(&f.frame, 0.0, 0, members, MAX_GRAINS) == 5);
    TEST_ASSERT(sim_frame_find_arch(&f.frame, 0.0, 1, members, MAX_GRAINS) == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(known_arch), TEST_CASE(one_sided_chain_rejected),
          TEST_CASE(empty_centre_no_arch), TEST_CASE(grain_on_floor_is_not_an_arch),
          TEST_CASE(concave_arch_accepted), TEST_CASE(force_check_rejects_unloaded_link))
