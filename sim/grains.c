/* SPDX-License-Identifier: MIT */
/* grains.c: the structure-of-arrays grain storage: growth, permutation (spatial sort), removal of
 * flagged grains, release; a grain's mass and moment of inertia (world.c, wall_body.c and edit.c
 * ask for them, so they sit below all three). */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

/* A disc (m = rho pi r^2, I = m r^2 / 2) or a sphere (m = rho 4/3 pi r^3, I = 2/5 m r^2), as the
 * definition's mass model says (sim.h, SimMassModel). */
double sim_grain_mass(SimMassModel model, double density, double r)
{
    return model == SIM_MASS_SPHERE ? density * 4.0 / 3.0 * SIM_PI * r * r * r
                                    : density * SIM_PI * r * r;
}

void sim_grain_mass_inertia(SimMassModel model, double density, double r, double *m,
                            double *inertia)
{
    *m = sim_grain_mass(model, density, r);
    *inertia = (model == SIM_MASS_SPHERE ? 0.4 : 0.5) * *m * r * r;
}

/* The double grain arrays are staggered blocks (sim_stagger_grow, internal.h): without it every
 * array of a large pile begins at the same offset in its page (blocks over glibc's mmap threshold,
 * about 16 000 grains, at first), and grain i of each of the arrays the velocity-Verlet drift
 * streams (14 read, 12 written) falls into the same set of the L1 cache. The 22 arrays (19 and 3
 * integrator scratch) are numbered 0-21: 22 different sets (docs/dev/scaling.md, "the grain
 * arrays staggered within their pages"). */

/* *a (capacity `old`, NULL when 0; array number k) grown to n + SIM_GRAIN_SLACK doubles (the
 * parts' sinks, internal.h), the new ones +0.0. -1 when out of memory, *a as it was. */
static int grow_staggered(double **a, int old, size_t n, int k)
{
    double *p = sim_stagger_grow(*a, (n + SIM_GRAIN_SLACK) * sizeof *p, k);
    if (!p)
        return -1;
    *a = p;
    memset(p + old, 0, (n + SIM_GRAIN_SLACK - (size_t)old) * sizeof *p);
    return 0;
}

/* Grows the grain arrays, and the per-grain arrays of the neighbour build (list starts, cells), to
 * `capacity` grains, so that a build inside a step has only the lists themselves to grow. */
int sim_grains_reserve(SimWorld *world, int capacity)
{
    if (capacity <= world->capacity)
        return 0;
    size_t n = (size_t)capacity;
    {
        size_t old = world->nl.start ? (size_t)world->capacity + 1 : 0;
        int *p = realloc(world->nl.start, (n + 1) * sizeof *p);
        if (!p)
            return -1;
        memset(p + old, 0, (n + 1 - old) * sizeof *p); /* an empty list until the first build */
        world->nl.start = p;
    }
#define GROW_BY(name, slack)                                                                       \
    {                                                                                              \
        void *p = realloc(world->name, (n + (slack)) * sizeof *world->name);                       \
        if (!p)                                                                                    \
            return -1;                                                                             \
        world->name = p;                                                                           \
        memset(world->name + world->capacity, 0,                                                   \
               (n + (slack) - (size_t)world->capacity) * sizeof *world->name);                     \
    }
#define GROW(name) GROW_BY(name, 0)
    int k = 0;
#define GROW_DOUBLE(name)                                                                          \
    if (grow_staggered(&world->name, world->capacity, n, k++) != 0)                                \
        return -1;
    SIM_GRAIN_DOUBLE_ARRAYS(GROW_DOUBLE)
    for (int s = 0; s < world->scratch_count; ++s)
        GROW_DOUBLE(scratch[s])
    SIM_GRAIN_INT_ARRAYS(GROW)
    GROW(flags)
    GROW(id)
    GROW(cell_items)
    GROW(cell_of)
#undef GROW
#undef GROW_DOUBLE
#undef GROW_BY
    world->capacity = capacity;
    return 0;
}

/* Reorders the first `count` grains so that new index k holds old index order[k]. Grains beyond
 * `count` are dropped (used for removal as well as sorting). -1 when out of memory, with the
 * grains as they were. */
int sim_grains_permute(SimWorld *world, const int *order, int count)
{
    size_t bytes = (size_t)(world->capacity > 0 ? world->capacity : 1) * sizeof(double);
    void *buffer = malloc(bytes);
    if (!buffer)
        return -1;
#define PERMUTE_AS(type, name)                                                                     \
    {                                                                                              \
        type *tmp = buffer;                                                                        \
        for (int k = 0; k < count; ++k)                                                            \
            tmp[k] = world->name[order[k]];                                                        \
        memcpy(world->name, tmp, (size_t)count * sizeof *world->name);                             \
    }
#define PERMUTE_DOUBLE(name) PERMUTE_AS(double, name)
#define PERMUTE_INT(name)    PERMUTE_AS(int, name)
    SIM_GRAIN_DOUBLE_ARRAYS(PERMUTE_DOUBLE)
    SIM_GRAIN_INT_ARRAYS(PERMUTE_INT)
    PERMUTE_AS(unsigned, flags)
    PERMUTE_AS(uint32_t, id)
    for (int a = 0; a < world->scratch_count; ++a)
        PERMUTE_DOUBLE(scratch[a])
#undef PERMUTE_AS
    free(buffer);
    return 0;
}

void sim_grains_free(SimWorld *world)
{
#define RELEASE_DOUBLE(name) sim_stagger_free(world->name);
#define RELEASE(name)        free(world->name);
    SIM_GRAIN_DOUBLE_ARRAYS(RELEASE_DOUBLE)
    for (int s = 0; s < SIM_SCRATCH_MAX; ++s)
        RELEASE_DOUBLE(scratch[s])
    SIM_GRAIN_INT_ARRAYS(RELEASE)
    RELEASE(flags)
    RELEASE(id)
#undef RELEASE
#undef RELEASE_DOUBLE
}

/* Drops flagged grains (keeping order) after contact history was collected; called from the
 * neighbour build, which ends with empty lists when this fails. */
int sim_world_compact(SimWorld *w)
{
    if (!w->pending_removal)
        return 0;
    int *order = malloc((size_t)(w->count > 0 ? w->count : 1) * sizeof *order);
    if (!order) {
        sim_world_out_of_memory(w, "removing grains");
        return -1;
    }
    int k = 0, mobile = 0;
    for (int i = 0; i < w->count; ++i)
        if (!(w->flags[i] & SIM_GRAIN_REMOVED)) {
            order[k++] = i;
            if (i < w->mobile_count)
                ++mobile;
        }
    int rc = sim_grains_permute(w, order, k);
    free(order);
    if (rc != 0) {
        sim_world_out_of_memory(w, "removing grains");
        return -1;
    }
    w->count = k;
    w->mobile_count = mobile;
    w->pending_removal = 0;
    return 0;
}
