/* SPDX-License-Identifier: MIT */
/* diagnostics.c: energies, the frame view, coordination, packing fraction, loads and hashes.
 * Nothing here runs inside the step; each call evaluates the current state. */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct ContactSums {
    SimWorld *world;
    double elastic;
    int contacts;
    int collect; /* 1: store contacts and per-grain force magnitudes */
} ContactSums;

static void sum_visit(void *context, const SimContact *c, double energy)
{
    ContactSums *sums = context;
    SimWorld *w = sums->world;
    sums->elastic += energy;
    ++sums->contacts;
    if (!sums->collect)
        return;
    if (w->contact_count >= w->contact_capacity) {
        int cap = w->contact_capacity ? 2 * w->contact_capacity : 1024;
        SimContact *p = realloc(w->contacts, (size_t)cap * sizeof *p);
        if (!p) /* sim_world_frame has no error return, and a frame short of contacts would be
                 * drawn and analysed as if complete: stop here */
            abort();
        w->contacts = p;
        w->contact_capacity = cap;
    }
    w->contacts[w->contact_count++] = *c;
    double f = hypot(c->normal_force, c->tangential_force);
    w->force_mag[c->i] += f;
    if (c->j >= 0)
        w->force_mag[c->j] += f;
}

static ContactSums contact_sums(SimWorld *w, int collect)
{
    ContactSums sums = {w, 0.0, 0, collect};
    if (collect) {
        w->contact_count = 0;
        memset(w->force_mag, 0, (size_t)w->count * sizeof(double));
    }
    sim_contacts_visit(w, sum_visit, &sums);
    return sums;
}

void sim_world_frame(SimWorld *w, SimFrame *f)
{
    contact_sums(w, 1);
    double d, m;
    sim_world_means(w, &d, &m);
    double g = hypot(w->def.gravity_x, w->def.gravity_y);
    double length = w->def.length_scale > 0.0 ? w->def.length_scale : d;
    w->time_scale = g > 0.0 && length > 0.0 ? sqrt(length / g) : 0.0;
    *f = (SimFrame){
        .count = w->count,
        .mobile_count = w->mobile_count,
        .step = w->step,
        .time = w->time,
        .time_scale = w->time_scale,
        .x = w->x,
        .y = w->y,
        .angle = w->angle,
        .radius = w->radius,
        .vx = w->vx,
        .vy = w->vy,
        .omega = w->omega,
        .species = w->species,
        .flags = w->flags,
        .id = w->id,
        .force = w->force_mag,
        .fx = w->fx,
        .fy = w->fy,
        .torque = w->torque,
        .contact_count = w->contact_count,
        .contacts = w->contacts,
        .wall_count = w->wall_count,
        .walls = w->walls,
        .periodic = (w->effects & SIM_EFFECT_PERIODIC_X) != 0,
        .domain_x0 = w->def.domain_x0,
        .domain_x1 = w->def.domain_x1,
    };
}

SimEnergy sim_world_energy(SimWorld *w)
{
    SimEnergy e = {0};
    const double gx = w->def.gravity_x, gy = w->def.gravity_y;
    for (int i = 0; i < w->mobile_count; ++i) {
        double m = w->mass[i];
        e.kinetic += 0.5 * m * (w->vx[i] * w->vx[i] + w->vy[i] * w->vy[i]);
        e.potential -= m * (gx * w->x[i] + gy * w->y[i]);
        e.rotational += 0.5 * w->inertia[i] * w->omega[i] * w->omega[i];
    }
    ContactSums sums = contact_sums(w, 0);
    e.elastic = sums.elastic;
    e.contacts = sums.contacts;
    e.mobile = w->mobile_count;
    e.total = e.kinetic + e.potential + e.rotational + e.elastic;
    return e;
}

typedef struct CoordinationCount {
    int *count;
} CoordinationCount;

static void coordination_visit(void *context, const SimContact *c, double energy)
{
    (void)energy;
    int *count = context;
    ++count[c->i];
    if (c->j >= 0)
        ++count[c->j];
}

double sim_world_coordination(SimWorld *w)
{
    if (w->mobile_count == 0)
        return 0.0;
    int *count = calloc((size_t)w->count + 1, sizeof *count);
    if (!count)
        return NAN;
    sim_contacts_visit(w, coordination_visit, count);
    long sum = 0;
    for (int i = 0; i < w->mobile_count; ++i)
        sum += count[i];
    free(count);
    return (double)sum / w->mobile_count;
}

/* Area of the part of a disk inside a rectangle, by integrating the chord length over x
 * (Simpson on a fine grid; exact enough for packing fractions, 1e-6 relative). */
static double disk_rect_area(double cx, double cy, double r, double x0, double y0, double x1,
                             double y1)
{
    double a = fmax(cx - r, x0), b = fmin(cx + r, x1);
    if (b <= a || cy - r >= y1 || cy + r <= y0)
        return 0.0;
    if (cx - r >= x0 && cx + r <= x1 && cy - r >= y0 && cy + r <= y1)
        return SIM_PI * r * r;
    const int n = 256; /* even */
    double h = (b - a) / n, sum = 0.0;
    for (int k = 0; k <= n; ++k) {
        double x = a + k * h, dx = x - cx;
        double half = r * r - dx * dx > 0.0 ? sqrt(r * r - dx * dx) : 0.0;
        double lo = fmax(cy - half, y0), hi = fmin(cy + half, y1);
        double len = hi > lo ? hi - lo : 0.0;
        sum += len * (k == 0 || k == n ? 1.0 : (k % 2 ? 4.0 : 2.0));
    }
    return sum * h / 3.0;
}

double sim_world_packing_fraction(const SimWorld *w, double x0, double y0, double x1, double y1)
{
    double area = (x1 - x0) * (y1 - y0);
    if (!(area > 0.0))
        return 0.0;
    double covered = 0.0;
    for (int i = 0; i < w->mobile_count; ++i)
        covered += disk_rect_area(w->x[i], w->y[i], w->radius[i], x0, y0, x1, y1);
    return covered / area;
}

typedef struct OverlapMax {
    const double *radius;
    double worst;
} OverlapMax;

static void overlap_max_visit(void *context, const SimContact *c, double energy)
{
    (void)energy;
    OverlapMax *o = context;
    double d = 2.0 * o->radius[c->i];
    if (c->j >= 0)
        d = fmin(d, 2.0 * o->radius[c->j]);
    o->worst = fmax(o->worst, c->overlap / d);
}

double sim_world_max_overlap_ratio(SimWorld *w)
{
    OverlapMax o = {w->radius, 0.0};
    sim_contacts_visit(w, overlap_max_visit, &o);
    return o.worst;
}

typedef struct LoadSum {
    const SimWorld *world;
    int species;
    double fx, fy;
} LoadSum;

static void load_visit(void *context, const SimContact *c, double energy)
{
    (void)energy;
    LoadSum *l = context;
    const SimWorld *w = l->world;
    if (c->j < 0 || c->j < w->mobile_count)
        return;
    if (l->species >= 0 && w->species[c->j] != l->species)
        return;
    /* Force on j (the fixed grain): +F_n n - F_t s, with n from i to j. */
    double dx = w->x[c->j] - w->x[c->i], dy = w->y[c->j] - w->y[c->i];
    double d = hypot(dx, dy);
    if (!(d > 0.0))
        return;
    double nx = dx / d, ny = dy / d, sx = ny, sy = -nx;
    l->fx += c->normal_force * nx - c->tangential_force * sx;
    l->fy += c->normal_force * ny - c->tangential_force * sy;
}

void sim_world_fixed_load(SimWorld *w, int species, double *fx, double *fy)
{
    LoadSum l = {w, species, 0.0, 0.0};
    sim_contacts_visit(w, load_visit, &l);
    *fx = l.fx;
    *fy = l.fy;
}

void sim_world_means(const SimWorld *w, double *diameter, double *mass)
{
    double d = 0.0, m = 0.0;
    for (int i = 0; i < w->mobile_count; ++i) {
        d += 2.0 * w->radius[i];
        m += w->mass[i];
    }
    int n = w->mobile_count;
    *diameter = n ? d / n : 0.0;
    *mass = n ? m / n : 0.0;
}

long sim_world_removed_count(const SimWorld *w, int sink)
{
    return sink >= 0 && sink < SIM_MAX_SINKS ? w->removed[sink] : 0;
}

void sim_world_momentum(const SimWorld *w, double *px, double *py)
{
    double sx = 0.0, sy = 0.0;
    for (int i = 0; i < w->mobile_count; ++i) {
        sx += w->mass[i] * w->vx[i];
        sy += w->mass[i] * w->vy[i];
    }
    *px = sx;
    *py = sy;
}

static uint64_t fnv_bytes(uint64_t h, const void *data, size_t size)
{
    const unsigned char *p = data;
    for (size_t k = 0; k < size; ++k) {
        h ^= p[k];
        h *= 1099511628211ull;
    }
    return h;
}

typedef struct IdIndex {
    uint32_t id;
    int index;
} IdIndex;

static int by_id(const void *a, const void *b)
{
    uint32_t ia = ((const IdIndex *)a)->id, ib = ((const IdIndex *)b)->id;
    return (ia > ib) - (ia < ib);
}

/* In stable-id order, so that a state reloaded from a checkpoint (and stored in another order)
 * hashes the same. */
uint64_t sim_world_hash(const SimWorld *w)
{
    uint64_t h = 1469598103934665603ull;
    IdIndex *order = malloc((size_t)(w->count > 0 ? w->count : 1) * sizeof *order);
    if (!order) /* every uint64_t is a valid hash: no value can say "failed", and a wrong one
                 * would pass or fail a determinism check falsely: stop here */
        abort();
    for (int i = 0; i < w->count; ++i)
        order[i] = (IdIndex){w->id[i], i};
    qsort(order, (size_t)w->count, sizeof *order, by_id);
    h = fnv_bytes(h, &w->count, sizeof w->count);
    for (int k = 0; k < w->count; ++k) {
        int i = order[k].index;
        double state[6] = {w->x[i], w->y[i], w->vx[i], w->vy[i], w->angle[i], w->omega[i]};
        h = fnv_bytes(h, &w->id[i], sizeof w->id[i]);
        h = fnv_bytes(h, state, sizeof state);
    }
    free(order);
    return h;
}

double sim_kernel_lucy(double r, double c)
{
    if (!(c > 0.0) || !(r < c))
        return 0.0;
    /* the integral 2 pi c^2 int_0^1 s (1 + 3 s)(1 - s)^3 ds = pi c^2 / 5 */
    double s = r / c, u = 1.0 - s;
    return 5.0 / (SIM_PI * c * c) * (1.0 + 3.0 * s) * u * u * u;
}
