/* SPDX-License-Identifier: MIT */
/* edit.c: grains written in place between steps (sim_world_set_grains): positions, velocities,
 * angles, radii and the fixed flag, by stable id or for every grain in frame order. */
#include "internal.h"

#include <math.h>
#include <stdlib.h>

typedef struct IdIndex {
    uint32_t id;
    int index;
} IdIndex;

static int by_id(const void *a, const void *b)
{
    uint32_t x = ((const IdIndex *)a)->id, y = ((const IdIndex *)b)->id;
    return (x > y) - (x < y);
}

/* The world index of every addressed grain (values->id, or frame order). */
static SimStatus edit_targets(const SimWorld *w, const SimGrainSet *v, int *target, SimError *error)
{
    if (!v->id) {
        for (int k = 0; k < v->count; ++k)
            target[k] = k;
        return SIM_OK;
    }
    IdIndex *map = malloc((size_t)(w->count > 0 ? w->count : 1) * sizeof *map);
    if (!map)
        return sim_fail(error, SIM_ERROR_MEMORY, "grains.id", "out of memory editing grains");
    for (int i = 0; i < w->count; ++i)
        map[i] = (IdIndex){w->id[i], i};
    qsort(map, (size_t)w->count, sizeof *map, by_id);
    SimStatus s = SIM_OK;
    for (int k = 0; k < v->count && s == SIM_OK; ++k) {
        IdIndex key = {v->id[k], 0};
        const IdIndex *hit = bsearch(&key, map, (size_t)w->count, sizeof *map, by_id);
        if (!hit) {
            char field[64];
            snprintf(field, sizeof field, "grains.id[%d]", k);
            s = sim_fail(error, SIM_ERROR_INVALID, field, "no grain has id %u", v->id[k]);
        } else {
            target[k] = hit->index;
        }
    }
    free(map);
    return s;
}

/* SIM_OK when every given value is usable. */
static SimStatus edit_check(const SimGrainSet *v, SimError *error)
{
    if ((v->x == NULL) != (v->y == NULL) || (v->vx == NULL) != (v->vy == NULL))
        return sim_fail(error, SIM_ERROR_INVALID, "grains",
                        "x and y (and vx and vy) are set together");
    if (v->species || v->motion)
        return sim_fail(error, SIM_ERROR_INVALID, v->species ? "grains.species" : "grains.motion",
                        "species and motions cannot be changed in place");
    const double *arrays[] = {v->x, v->y, v->vx, v->vy, v->angle, v->omega, v->radius};
    const char *names[] = {"x", "y", "vx", "vy", "angle", "omega", "radius"};
    for (int a = 0; a < 7; ++a)
        for (int k = 0; arrays[a] && k < v->count; ++k) {
            double value = arrays[a][k];
            if (!isfinite(value) || (a == 6 && !(value > 0.0))) {
                char field[64];
                snprintf(field, sizeof field, "grains.%s[%d]", names[a], k);
                return sim_fail(error, SIM_ERROR_INVALID, field, "%g is not %s", value,
                                a == 6 ? "a positive radius" : "finite");
            }
        }
    for (int k = 0; v->flags && k < v->count; ++k)
        if (v->flags[k] & ~(unsigned)SIM_GRAIN_FIXED) {
            char field[64];
            snprintf(field, sizeof field, "grains.flags[%d]", k);
            return sim_fail(error, SIM_ERROR_INVALID, field, "unknown flag bits 0x%x",
                            v->flags[k] & ~(unsigned)SIM_GRAIN_FIXED);
        }
    return SIM_OK;
}

/* The pairs the edited grains make must stay resolved by the time step (radius or fixed flag
 * changed): the same test as for added grains. */
static SimStatus edit_timing(const SimWorld *w, const SimGrainSet *v, const int *target,
                             SimError *error)
{
    if (!v->radius && !v->flags)
        return SIM_OK;
    double *radius = malloc((size_t)v->count * sizeof *radius);
    int *species = malloc((size_t)v->count * sizeof *species);
    unsigned *flags = malloc((size_t)v->count * sizeof *flags);
    SimStatus s = SIM_OK;
    if (!radius || !species || !flags) {
        s = sim_fail(error, SIM_ERROR_MEMORY, "grains", "out of memory editing grains");
    } else {
        for (int k = 0; k < v->count; ++k) {
            radius[k] = v->radius ? v->radius[k] : w->radius[target[k]];
            species[k] = w->species[target[k]];
            flags[k] = v->flags ? v->flags[k] : w->flags[target[k]] & SIM_GRAIN_FIXED;
        }
        SimGrainSet g = {.count = v->count, .radius = radius, .species = species, .flags = flags};
        s = sim_world_check_timing(w, &g, error);
    }
    free(radius);
    free(species);
    free(flags);
    return s;
}

/* Mobile grains first, each part in its present order; -1 when out of memory. */
static int edit_reorder(SimWorld *w)
{
    int *order = malloc((size_t)(w->count > 0 ? w->count : 1) * sizeof *order), n = 0;
    if (!order)
        return -1;
    for (int fixed = 0; fixed < 2; ++fixed)
        for (int i = 0; i < w->count; ++i)
            if (!(w->flags[i] & SIM_GRAIN_FIXED) == !fixed)
                order[n++] = i;
    int mobile = 0;
    while (mobile < w->count && !(w->flags[order[mobile]] & SIM_GRAIN_FIXED))
        ++mobile;
    int rc = sim_neighbour_stash_history(w) != 0 || sim_grains_permute(w, order, w->count) != 0;
    free(order);
    if (rc)
        return -1;
    w->mobile_count = mobile;
    return 0;
}

static void edit_write(SimWorld *w, const SimGrainSet *v, int k, int i)
{
    if (v->x) {
        w->x[i] = w->x_base[i] = v->x[k];
        w->y[i] = w->y_base[i] = v->y[k];
    }
    if (v->angle)
        w->angle[i] = v->angle[k];
    if (v->radius)
        w->radius[i] = v->radius[k];
    if (v->flags) {
        if ((v->flags[k] & SIM_GRAIN_FIXED) && !(w->flags[i] & SIM_GRAIN_FIXED)) {
            w->x_base[i] = w->x[i]; /* a grain made fixed rests where it is */
            w->y_base[i] = w->y[i];
            w->motion[i] = -1;
        }
        w->flags[i] = (w->flags[i] & ~(unsigned)SIM_GRAIN_FIXED) | v->flags[k];
    }
    const int fixed = (w->flags[i] & SIM_GRAIN_FIXED) != 0;
    if (v->vx && !fixed) {
        w->vx[i] = v->vx[k];
        w->vy[i] = v->vy[k];
    }
    if (v->omega && !fixed)
        w->omega[i] = v->omega[k];
    if (fixed)
        w->vx[i] = w->vy[i] = w->omega[i] = 0.0;
    double m, inertia;
    sim_grain_mass_inertia(w->def.mass_model, w->def.materials[w->species[i]].density, w->radius[i],
                           &m, &inertia);
    w->mass[i] = m;
    w->inertia[i] = inertia;
    w->inv_mass[i] = fixed ? 0.0 : 1.0 / m;
    w->inv_inertia[i] = fixed || !w->rotation ? 0.0 : 1.0 / inertia;
}

SimStatus sim_world_set_grains(SimWorld *w, const SimGrainSet *values, SimError *error)
{
    if (values->count < 0 || (!values->id && values->count != w->count))
        return sim_fail(error, SIM_ERROR_INVALID, "grains.count",
                        "%d values for %d grains (give ids to edit some of them)", values->count,
                        w->count);
    if (values->count == 0)
        return SIM_OK;
    int *target = malloc((size_t)values->count * sizeof *target);
    if (!target)
        return sim_fail(error, SIM_ERROR_MEMORY, "grains", "out of memory editing grains");
    SimStatus s = edit_check(values, error);
    if (s == SIM_OK)
        s = edit_targets(w, values, target, error);
    if (s == SIM_OK)
        s = edit_timing(w, values, target, error);
    if (s != SIM_OK) {
        free(target);
        return s;
    }
    int reorder = 0;
    for (int k = 0; k < values->count; ++k) {
        int i = target[k];
        reorder |= values->flags && ((values->flags[k] ^ w->flags[i]) & SIM_GRAIN_FIXED);
        edit_write(w, values, k, i);
    }
    free(target);
    if (reorder && edit_reorder(w) != 0)
        w->out_of_memory = "reordering edited grains";
    sim_world_grains_changed(w);
    sim_integrator_start(w);
    if (w->out_of_memory)
        return sim_fail(error, SIM_ERROR_MEMORY, "grains",
                        "out of memory in %s after editing "
                        "grains",
                        w->out_of_memory);
    return SIM_OK;
}
