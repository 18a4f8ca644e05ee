/* SPDX-License-Identifier: MIT */
/* The cell list equals a brute-force O(N^2) search (000 ch. 4.3 planned validation): the contact
 * list of sim_world_frame is compared with our own overlap search over the frame's positions, on
 * random polydisperse sets with 0.1 d grains next to 1.25 d grains, fixed grains, wall segments,
 * with and without the periodic seam, at creation and after many steps (list rebuilds). */
#include "sim_test_util.h"
#include "test.h"

#include <stdlib.h>
#include <unistd.h>

typedef struct Pair {
    long a, b; /* ids; b = -1 - wall index for a wall contact */
    double overlap;
} Pair;

static int pair_cmp(const void *p, const void *q)
{
    const Pair *x = p, *y = q;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    if (x->b != y->b)
        return x->b < y->b ? -1 : 1;
    return 0;
}

/* Distance from (px, py) to the segment. */
static double segment_distance(const SimWall *s, double px, double py)
{
    double ex = s->x1 - s->x0, ey = s->y1 - s->y0;
    double t = ((px - s->x0) * ex + (py - s->y0) * ey) / (ex * ex + ey * ey);
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    return hypot(px - (s->x0 + t * ex), py - (s->y0 + t * ey));
}

/* Brute force over the frame: every mobile-mobile and mobile-fixed pair (minimum image in x when
 * periodic), every mobile grain against every wall (nearest periodic image). */
static int brute(const SimFrame *f, Pair *out)
{
    double period = f->periodic ? f->domain_x1 - f->domain_x0 : 0.0;
    int n = 0;
    for (int i = 0; i < f->count; ++i) {
        int fi = (f->flags[i] & SIM_GRAIN_FIXED) != 0;
        for (int j = i + 1; j < f->count; ++j) {
            if (fi && (f->flags[j] & SIM_GRAIN_FIXED))
                continue;
            double dx = tu_dx(f->x[j], f->x[i], period), dy = f->y[j] - f->y[i];
            double xi = f->radius[i] + f->radius[j] - sqrt(dx * dx + dy * dy);
            if (xi > 0.0) {
                long a = f->id[i], b = f->id[j];
                out[n].a = a < b ? a : b;
                out[n].b = a < b ? b : a;
                out[n].overlap = xi;
                ++n;
            }
        }
        if (fi)
            continue;
        for (int w = 0; w < f->wall_count; ++w) {
            double d = segment_distance(&f->walls[w], f->x[i], f->y[i]);
            if (period > 0.0) {
                double d1 = segment_distance(&f->walls[w], f->x[i] + period, f->y[i]);
                double d2 = segment_distance(&f->walls[w], f->x[i] - period, f->y[i]);
                d = d1 < d ? d1 : d;
                d = d2 < d ? d2 : d;
            }
            if (f->radius[i] - d > 0.0) {
                out[n].a = f->id[i];
                out[n].b = -1 - w;
                out[n].overlap = f->radius[i] - d;
                ++n;
            }
        }
    }
    qsort(out, (size_t)n, sizeof *out, pair_cmp);
    return n;
}

static int engine(const SimFrame *f, Pair *out)
{
    int n = 0;
    for (int k = 0; k < f->contact_count; ++k) {
        const SimContact *c = &f->contacts[k];
        if (c->j >= 0 && (f->flags[c->i] & SIM_GRAIN_FIXED) && (f->flags[c->j] & SIM_GRAIN_FIXED))
            continue;
        long a = f->id[c->i];
        if (c->j < 0) {
            out[n].a = a;
            out[n].b = c->j;
        } else {
            long b = f->id[c->j];
            out[n].a = a < b ? a : b;
            out[n].b = a < b ? b : a;
        }
        out[n].overlap = c->overlap;
        ++n;
    }
    qsort(out, (size_t)n, sizeof *out, pair_cmp);
    return n;
}

static int compare(SimWorld *w, int *contacts_seen)
{
    SimFrame f;
    sim_world_frame(w, &f);
    size_t cap = (size_t)f.count * 16 + 64;
    Pair *mine = malloc(cap * sizeof *mine), *theirs = malloc(cap * sizeof *theirs);
    TEST_ASSERT(mine && theirs);
    int nm = brute(&f, mine), nt = engine(&f, theirs);
    int bad = nm != nt;
    for (int k = 0; k < nm && k < nt && !bad; ++k) {
        if (mine[k].a != theirs[k].a || mine[k].b != theirs[k].b) {
            fprintf(stderr, "contact %d: brute force (%ld, %ld), cell list (%ld, %ld)\n", k,
                    mine[k].a, mine[k].b, theirs[k].a, theirs[k].b);
            bad = 1;
        } else if (fabs(mine[k].overlap - theirs[k].overlap) > 1e-12) {
            fprintf(stderr, "contact (%ld, %ld): overlap %.17g vs %.17g\n", mine[k].a, mine[k].b,
                    mine[k].overlap, theirs[k].overlap);
            bad = 1;
        }
    }
    if (nm != nt)
        fprintf(stderr, "step %ld: brute force %d contacts, cell list %d\n", f.step, nm, nt);
    /* each contact once */
    for (int k = 1; k < nt && !bad; ++k)
        if (theirs[k].a == theirs[k - 1].a && theirs[k].b == theirs[k - 1].b)
            bad = 1;
    *contacts_seen += nm;
    free(mine);
    free(theirs);
    TEST_ASSERT(!bad);
    return 0;
}

/* Radii: d = 0.1 m grains with 0.1 d and 1.25 d ones among them. */
static const double radii[] = {0.05, 0.005, 0.0625, 0.046, 0.054, 0.005, 0.0625, 0.05};

static SimWorld *make(int periodic, uint64_t seed, double speed, double skin)
{
    const double lx = 2.0, ly = 1.5;
    SimWorldDef def = tu_def(1.0, 1e4, 5e-6);
    def.max_initial_overlap = 1.0; /* random sets overlap on purpose: an oracle of geometry */
    def.skin = skin;               /* 0: default */
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.5;
    static SimWall walls[2];
    walls[0] = (SimWall){.x0 = 0.0, .y0 = 0.0, .x1 = lx, .y1 = 0.0, .species = 0, .motion = -1};
    walls[1] = (SimWall){.x0 = 0.8,
                         .y0 = 0.6,
                         .x1 = 1.2,
                         .y1 = 0.9,
                         .species = 0,
                         .motion = -1}; /* interior, with two free ends */
    def.wall_count = 2;
    def.walls = walls;
    SimGrainBuffer all, b;
    sim_grain_buffer_init(&all);
    sim_grain_buffer_init(&b);
    if (periodic) {
        def.effects |= SIM_EFFECT_PERIODIC_X;
        def.domain_x0 = 0.0;
        def.domain_x1 = lx;
        /* pairs that touch only across the seam, including two 0.1 d grains */
        sim_grain_buffer_add(&b, 0.03, 0.7, 0.05, 0, 0u, -1);
        sim_grain_buffer_add(&b, lx - 0.07, 0.7, 0.0625, 0, 0u, -1);
        sim_grain_buffer_add(&b, 0.004, 1.2, 0.005, 0, 0u, -1);
        sim_grain_buffer_add(&b, lx - 0.004, 1.2, 0.005, 0, 0u, -1);
        /* above the wall at the seam, falling onto it */
        int g = sim_grain_buffer_add(&b, lx - 0.002, 0.0505, 0.05, 0, 0u, -1);
        b.vy[g] = -speed;
    }
    SimRng rng;
    sim_rng_seed(&rng, seed);
    for (int i = 0; i < b.count; ++i) /* so that the random ones avoid the seam grains */
        sim_grain_buffer_add(&all, b.x[i], b.y[i], b.radius[i], 0, 0u, -1);
    int first = all.count;
    /* overlaps at the start up to 0.2 of the smaller diameter (0.05 when moving, where a 0.1 d
     * grain squeezed between large ones would trip the overlap guard) */
    tu_random_grains(&all, &rng, 260, radii, 8, 0.0, lx, 0.0, ly, periodic ? lx : 0.0,
                     speed > 0.0 ? 0.05 : 0.2);
    /* create refuses grains that overlap a wall at the start: leave those out */
    for (int i = first; i < all.count; ++i) {
        int clear = 1;
        for (int k = 0; k < 2; ++k)
            for (int image = -1; image <= 1; ++image)
                if (segment_distance(&walls[k], all.x[i] + image * (periodic ? lx : 0.0),
                                     all.y[i]) < all.radius[i])
                    clear = 0;
        if (clear)
            sim_grain_buffer_add(&b, all.x[i], all.y[i], all.radius[i], 0, 0u, -1);
    }
    sim_grain_buffer_free(&all);
    for (int i = periodic ? 5 : 0; i < b.count; ++i) {
        if (i % 10 == 9)
            b.flags[i] = SIM_GRAIN_FIXED;
        else {
            b.vx[i] = speed * (2.0 * sim_rng_uniform(&rng) - 1.0);
            b.vy[i] = speed * (2.0 * sim_rng_uniform(&rng) - 1.0);
        }
    }
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    return w;
}

static int cells_match_brute_force(void)
{
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        SimWorld *w = make(0, seed, 0.0, 0.0);
        TEST_ASSERT(w);
        TEST_ASSERT(sim_world_max_overlap_ratio(w) <= 0.2 + 1e-12);
        int seen = 0;
        TEST_ASSERT(compare(w, &seen) == 0);
        TEST_ASSERT(seen > 50);
        sim_world_destroy(w);
    }
    return 0;
}

static int cells_match_brute_force_periodic(void)
{
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        SimWorld *w = make(1, seed, 0.0, 0.0);
        TEST_ASSERT(w);
        TEST_ASSERT(sim_world_max_overlap_ratio(w) <= 0.2 + 1e-12);
        SimFrame f;
        sim_world_frame(w, &f);
        TEST_ASSERT(f.periodic == 1);
        /* the seam pairs are there */
        int found = 0;
        for (int k = 0; k < f.contact_count; ++k) {
            if (f.contacts[k].j < 0)
                continue;
            uint32_t a = f.id[f.contacts[k].i], b = f.id[f.contacts[k].j];
            if ((a == 0 && b == 1) || (a == 1 && b == 0) || (a == 2 && b == 3) ||
                (a == 3 && b == 2))
                ++found;
        }
        TEST_ASSERT(found == 2);
        int seen = 0;
        TEST_ASSERT(compare(w, &seen) == 0);
        TEST_ASSERT(seen > 50);
        sim_world_destroy(w);
    }
    return 0;
}

/* After motion: with a 2 mm skin the lists are rebuilt every millimetre or so; grains move
 * ~7 mm (0.5 m/s for 15 ms, 0.1 d grains faster), cross the seam and land on the walls; the lists
 * are compared every 150 steps. */
static int cells_match_after_motion(void)
{
    for (int periodic = 0; periodic < 2; ++periodic) {
        SimWorld *w = make(periodic, 5, 0.5, 0.002);
        TEST_ASSERT(w);
        int seen = 0;
        for (int s = 0; s < 20; ++s) {
            TEST_ASSERT(compare(w, &seen) == 0);
            TEST_ASSERT(tu_step(w, 150) == 0);
        }
        TEST_ASSERT(compare(w, &seen) == 0);
        TEST_ASSERT(seen > 200);
        sim_world_destroy(w);
    }
    return 0;
}

/* The automatic skin (SimWorldDef.skin = 0) changes the skin at list builds. Moving grains at
 * 0.5 m/s (mean d = 0.1 m, so the skin may range over 1-20 mm) make it shrink from 20 mm and then
 * follow the motion; the lists must still hold every contact of the brute force, compared every
 * 25 steps over 60 ms, across the seam too. */
static int auto_skin_matches_brute_force(void)
{
    for (int periodic = 0; periodic < 2; ++periodic) {
        SimWorld *w = make(periodic, 5, 0.5, 0.0);
        TEST_ASSERT(w);
        double mean_d;
        double mean_m;
        sim_world_means(w, &mean_d, &mean_m);
        const double s0 = sim_world_skin(w);
        TEST_ASSERT(fabs(s0 - 0.2 * mean_d) < 1e-12); /* it starts at its largest */
        double lo = s0, hi = s0;
        const long builds0 = sim_world_list_builds(w);
        int seen = 0;
        for (int s = 0; s < 480; ++s) {
            TEST_ASSERT(compare(w, &seen) == 0);
            TEST_ASSERT(tu_step(w, 25) == 0);
            lo = fmin(lo, sim_world_skin(w));
            hi = fmax(hi, sim_world_skin(w));
        }
        TEST_ASSERT(compare(w, &seen) == 0);
        fprintf(stderr, "periodic %d: skin %.3g..%.3g m, %ld builds, %d contacts checked\n",
                periodic, lo, hi, sim_world_list_builds(w) - builds0, seen);
        TEST_ASSERT(lo >= 0.01 * mean_d * (1.0 - 1e-12) && hi <= s0);
        TEST_ASSERT(lo < 0.5 * s0);                           /* it moved */
        TEST_ASSERT(sim_world_list_builds(w) - builds0 >= 5); /* and the lists were rebuilt */
        TEST_ASSERT(seen > 1000);
        sim_world_destroy(w);
    }
    return 0;
}

/* A settled pile: the automatic skin shrinks towards its floor (few grains move) and lists are
 * seldom rebuilt; the same pile with its fixed largest skin gives the same motion to rounding
 * (the skin changes which pairs are listed, never which touch). Grains that move fast get a
 * larger skin than grains at rest. */
static SimWorldDef pile_def(double skin)
{
    static const SimWall box[3] = {
        {.x0 = 0.0, .y0 = 0.0, .x1 = 2.0, .y1 = 0.0, .species = 0, .motion = -1},
        {.x0 = 0.0, .y0 = 0.0, .x1 = 0.0, .y1 = 3.0, .species = 0, .motion = -1},
        {.x0 = 2.0, .y0 = 0.0, .x1 = 2.0, .y1 = 3.0, .species = 0, .motion = -1}};
    SimWorldDef def = tu_def(1000.0, 1e5, 1e-4);
    def.gravity_y = -G0;
    def.skin = skin;
    def.effects = SIM_EFFECT_FRICTION;
    def.contact.tangential = SIM_TANGENTIAL_SPRING;
    def.materials[0].damping_mode = SIM_DAMPING_RESTITUTION;
    def.materials[0].restitution = 0.3;
    def.materials[0].friction = 0.5;
    def.materials[0].tangential_stiffness = 0.75e5;
    def.wall_count = 3;
    def.walls = box;
    return def;
}

/* 150 grains rained into a 2 m box, their vertical speeds +-speed. */
static SimWorld *pile(double skin, double speed)
{
    SimGrainBuffer b;
    tu_rain_150(&b, 3, 0.06);
    for (int k = 0; k < b.count; ++k)
        b.vy[k] = speed * (k % 2 ? 1.0 : -1.0);
    SimWorldDef def = pile_def(skin);
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    return w;
}

/* A world with `skin` from the state saved at `path`. */
static SimWorld *pile_from(const char *path, double skin)
{
    SimError err;
    SimWorldDef def = pile_def(skin);
    return sim_world_load(path, &def, &err);
}

static int auto_skin_follows_motion(void)
{
    SimWorld *w = pile(0.0, 0.0);
    TEST_ASSERT(w);
    double mean_d, mean_m;
    sim_world_means(w, &mean_d, &mean_m);
    TEST_ASSERT(tu_step(w, 80000) == 0); /* 8 s: rained and settled */
    const double rest = sim_world_skin(w);
    const long builds = sim_world_list_builds(w);
    TEST_ASSERT(tu_step(w, 5000) == 0);
    fprintf(stderr, "at rest: skin %.3g d, %ld builds in 5000 steps\n", rest / mean_d,
            sim_world_list_builds(w) - builds);
    TEST_ASSERT(rest < 0.03 * mean_d);
    TEST_ASSERT(sim_world_list_builds(w) - builds <= 5); /* one per 1000 steps or fewer */

    /* from the settled state, a fixed 0.2 d skin and the automatic one: the same motion */
    char path[32];
    TEST_ASSERT(test_tmp_file(path) == 0);
    SimError err;
    TEST_ASSERT(sim_world_save(w, path, &err) == SIM_OK);
    SimWorld *a = pile_from(path, 0.0), *f = pile_from(path, 0.2 * mean_d);
    unlink(path);
    TEST_ASSERT(a && f);
    TEST_ASSERT(tu_step(a, 5000) == 0 && tu_step(f, 5000) == 0);
    TEST_ASSERT(sim_world_skin(a) < 0.5 * sim_world_skin(f)); /* a smaller list */
    SimFrame fa, ff;
    sim_world_frame(a, &fa);
    sim_world_frame(f, &ff);
    TEST_ASSERT(fa.count == ff.count);
    double worst = 0.0;
    for (int k = 0; k < fa.count; ++k) {
        int m = tu_index(&ff, fa.id[k]);
        TEST_ASSERT(m >= 0);
        worst = fmax(worst, hypot(fa.x[k] - ff.x[m], fa.y[k] - ff.y[m]));
    }
    fprintf(stderr, "automatic vs fixed skin: largest position difference %.3g d\n",
            worst / mean_d);
    TEST_ASSERT(worst < 1e-9 * mean_d);
    sim_world_destroy(a);
    sim_world_destroy(f);
    sim_world_destroy(w);

    /* grains thrown at 2 m/s: a skin many times the one at rest */
    SimWorld *g = pile(0.0, 2.0);
    TEST_ASSERT(g);
    TEST_ASSERT(tu_step(g, 400) == 0);
    fprintf(stderr, "moving: skin %.3g d\n", sim_world_skin(g) / mean_d);
    TEST_ASSERT(sim_world_skin(g) > 3.0 * rest);
    sim_world_destroy(g);
    return 0;
}

/* The list is built in parts on the world's threads (neighbour.c, ListSink): on 3 threads it
 * must still hold every contact of the brute force (moving grains, the automatic skin, the seam),
 * and give the bits of one thread, the automatic skin included (its pair counts are summed over
 * the parts); on the settled pile, whose tangential springs are carried over at each build, the
 * same bits on 1 and 3 threads after 3000 steps. */
static int cells_match_on_threads(void)
{
    for (int periodic = 0; periodic < 2; ++periodic) {
        SimWorld *w[2];
        for (int run = 0; run < 2; ++run) {
            w[run] = make(periodic, 7, 0.5, 0.0);
            TEST_ASSERT(w[run]);
            sim_world_set_threads(w[run], run == 0 ? 1 : 3);
        }
        TEST_ASSERT(sim_world_threads(w[1]) == 3);
        const long builds0 = sim_world_list_builds(w[1]);
        int seen = 0;
        for (int s = 0; s < 120; ++s) {
            TEST_ASSERT(compare(w[1], &seen) == 0);
            TEST_ASSERT(tu_step(w[0], 25) == 0 && tu_step(w[1], 25) == 0);
            TEST_ASSERT(sim_world_skin(w[0]) == sim_world_skin(w[1]));
        }
        TEST_ASSERT(sim_world_list_builds(w[1]) - builds0 >= 5);
        TEST_ASSERT(seen > 500);
        TEST_ASSERT(sim_world_hash(w[0]) == sim_world_hash(w[1]));
        sim_world_destroy(w[0]);
        sim_world_destroy(w[1]);
    }
    uint64_t hashes[2];
    for (int run = 0; run < 2; ++run) {
        SimWorld *p = pile(0.0, 0.5);
        TEST_ASSERT(p);
        sim_world_set_threads(p, run == 0 ? 1 : 3);
        TEST_ASSERT(tu_step(p, 3000) == 0);
        TEST_ASSERT(sim_world_energy(p).contacts > 50);
        hashes[run] = sim_world_hash(p);
        sim_world_destroy(p);
    }
    TEST_ASSERT(hashes[0] == hashes[1]);
    return 0;
}

/* Grains spread over more than DBL_MAX (x1 - x0 overflows to inf): the grid falls back to one
 * cell instead of coarsening forever (fuzz finding), and a touching pair among them is found. */
static int spread_beyond_double_range(void)
{
    SimWorldDef def = tu_def(2500.0, 1e5, 1e-5);
    SimGrainBuffer b;
    sim_grain_buffer_init(&b);
    sim_grain_buffer_add(&b, -1e308, 0.0, 0.05, 0, 0u, -1);
    sim_grain_buffer_add(&b, 1e308, 0.0, 0.05, 0, 0u, -1);
    sim_grain_buffer_add(&b, 0.0, 0.0, 0.05, 0, 0u, -1);
    sim_grain_buffer_add(&b, 0.095, 0.0, 0.05, 0, 0u, -1); /* overlaps the one at 0 by 0.005 */
    SimWorld *w = tu_create(&def, &b);
    sim_grain_buffer_free(&b);
    TEST_ASSERT(w);
    TEST_ASSERT(tu_step(w, 2) == 0);
    SimFrame f;
    sim_world_frame(w, &f);
    TEST_ASSERT(f.contact_count == 1);
    sim_world_destroy(w);
    return 0;
}

TEST_MAIN(TEST_CASE(cells_match_brute_force), TEST_CASE(cells_match_brute_force_periodic),
          TEST_CASE(cells_match_after_motion), TEST_CASE(auto_skin_matches_brute_force),
          TEST_CASE(auto_skin_follows_motion), TEST_CASE(spread_beyond_double_range),
          TEST_CASE(cells_match_on_threads))
