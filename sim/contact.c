/* SPDX-License-Identifier: MIT */
/* contact.c: the contact key (which laws a world declares) and the diagnostics that evaluate
 * every contact without applying it. The kernel that applies them, instantiated per key, is
 * sim/isa/contact_pass.c (compiled once per instruction set).
 *
 * Conventions (000 eqs. 3.1-3.5): n points from i to j, s = (n_y, -n_x),
 * v_s = (v_j - v_i).s + omega_i r_i + omega_j r_j. The force on i is -F_n n + F_t s, on j the
 * opposite; both torques are -r F_t (000 eq. 4.4; 004 §1.6). */
#include "contact_scalar.h"
#include "walls.h"

#include <math.h>

unsigned sim_contact_key(const SimWorld *world)
{
    const SimContactModel *c = &world->def.contact;
    unsigned key = 0;
    if (world->effects & SIM_EFFECT_FRICTION)
        key |= (unsigned)c->tangential & KEY_TANGENTIAL;
    if ((world->effects & SIM_EFFECT_ROLLING) && c->rolling != SIM_ROLLING_OFF) {
        key |= KEY_ROLLING;
        if (c->rolling == SIM_ROLLING_CHORD)
            key |= KEY_CHORD;
    }
    if (world->effects & SIM_EFFECT_PERIODIC_X)
        key |= KEY_PERIODIC;
    if (c->normal == SIM_NORMAL_HERTZ)
        key |= KEY_HERTZ;
    if (c->clip_tensile)
        key |= KEY_CLIP;
    if (c->onset == SIM_ONSET_EVENT)
        key |= KEY_EVENT;
    return key;
}

/* ------------------------------------------------------------------ diagnostics (not hot) */

static void visit_one(SimWorld *world, unsigned key, int i, int j, int wall, double nx, double ny,
                      double overlap, double chord, double v_n, double v_s, const PairParams *p,
                      double gamma_n, double xi_t, double m_r, double cx, double cy,
                      ContactVisit *visit, void *context)
{
    double f_el;
    double f_n = normal_force_d(key, p->k_n, gamma_n, overlap, v_n, 0.0, &f_el); /* h = 0: the
                                                                          instantaneous force */
    unsigned law = key & KEY_TANGENTIAL;
    double f_t = 0.0, energy;
    if (law == SIM_TANGENTIAL_REGULARISED) {
        double scratch = 0.0;
        f_t = tangential_force_d(key, p->k_t, p->mu, p->gamma_s, v_s, f_n, f_el, 0.0, &scratch);
    } else if (law == SIM_TANGENTIAL_SPRING) {
        f_t = p->k_t * xi_t; /* with its dashpot (Luding 2008): + gamma_t v_s */
        if (p->gamma_t != 0.0)
            f_t += p->gamma_t * v_s;
    }
    if (key & KEY_HERTZ)
        energy = 0.4 * p->k_n * overlap * overlap * sqrt(overlap);
    else
        energy = 0.5 * p->k_n * overlap * overlap;
    if (law == SIM_TANGENTIAL_SPRING)
        energy += 0.5 * p->k_t * xi_t * xi_t;
    if (key & KEY_ROLLING) {
        double k_r = (key & KEY_CHORD) ? p->k_n * chord * chord : p->k_r;
        if (k_r > 0.0)
            energy += 0.5 * m_r * m_r / k_r;
    }
    SimContact c = {.i = i,
                    .j = wall >= 0 ? -1 - wall : j,
                    .normal_force = f_n,
                    .tangential_force = f_t,
                    .overlap = overlap,
                    .x = cx,
                    .y = cy,
                    .nx = nx,
                    .ny = ny};
    (void)world;
    visit(context, &c, energy);
}

/* Entry k (owner i): 1 when the two disks overlap, with the vector from i to the partner and the
 * distance; the geometry every scan of the list's contacts shares (the visitor, the guard's). */
static inline int entry_touching(const SimWorld *world, unsigned key, int i, int k, double *dx,
                                 double *dy, double *d)
{
    const int j = world->nl.j[k];
    *dx = world->x[j] - world->x[i] + ((key & KEY_PERIODIC) ? world->nl.shift[k] : 0.0);
    *dy = world->y[j] - world->y[i];
    const double rs = world->radius[i] + world->radius[j];
    const double d2 = *dx * *dx + *dy * *dy;
    if (d2 >= rs * rs)
        return 0;
    *d = sqrt(d2);
    return 1;
}

void sim_contacts_visit(SimWorld *world, ContactVisit *visit, void *context)
{
    const unsigned key = sim_contact_key(world);
    const unsigned law = key & KEY_TANGENTIAL;
    const double *x = world->x, *y = world->y, *r = world->radius;
    for (int i = 0; i < world->mobile_count; ++i) {
        double wi = world->rotation ? world->omega[i] : 0.0;
        for (int k = world->nl.start[i]; k < world->nl.start[i + 1]; ++k) {
            int j = world->nl.j[k];
            double dx, dy, d;
            if (!entry_touching(world, key, i, k, &dx, &dy, &d))
                continue;
            double rs = r[i] + r[j];
            double nx = d > 0.0 ? dx / d : 1.0, ny = d > 0.0 ? dy / d : 0.0;
            double dvx = world->vx[j] - world->vx[i], dvy = world->vy[j] - world->vy[i];
            double wj = world->rotation ? world->omega[j] : 0.0;
            double v_s = dvx * ny - dvy * nx + wi * r[i] + wj * r[j];
            double xi_t = law == SIM_TANGENTIAL_SPRING ? world->nl.hist_t[k] : 0.0;
            double m_r = (key & KEY_ROLLING) ? world->nl.hist_r[k] : 0.0;
            double overlap = rs - d;
            double lever = r[i] - 0.5 * overlap;
            visit_one(world, key, i, j, -1, nx, ny, overlap, disk_chord_d(d, r[i], r[j]),
                      dvx * nx + dvy * ny, v_s, &world->pairs[world->nl.pair[k]],
                      world->nl.gamma[k], xi_t, m_r, x[i] + lever * nx, y[i] + lever * ny, visit,
                      context);
        }
    }
    for (int k = 0; k < world->wl.count; ++k) {
        int i = world->wl.grain[k], w = world->wl.wall[k];
        double nx, ny;
        double d = sim_wall_geometry(&world->walls[w], x[i], y[i], r[i], &nx, &ny);
        if (d >= r[i])
            continue;
        double wvx, wvy;
        sim_wall_velocity(world, w, x[i] + d * nx, y[i] + d * ny, &wvx, &wvy);
        double dvx = wvx - world->vx[i], dvy = wvy - world->vy[i];
        double wi = world->rotation ? world->omega[i] : 0.0;
        double v_s = dvx * ny - dvy * nx + wi * r[i];
        double xi_t = law == SIM_TANGENTIAL_SPRING ? world->wl.hist_t[k] : 0.0;
        double m_r = (key & KEY_ROLLING) ? world->wl.hist_r[k] : 0.0;
        visit_one(world, key, i, -1, w, nx, ny, r[i] - d,
                  2.0 * sqrt(fmax(r[i] * r[i] - d * d, 0.0)), dvx * nx + dvy * ny, v_s,
                  &world->pairs[world->wl.pair[k]], world->wl.gamma[k], xi_t, m_r, x[i] + d * nx,
                  y[i] + d * ny, visit, context);
    }
}

/* The largest overlap ratio among the entries of the owners [i0, i1) that beats *worst (the
 * visitor's arithmetic for the overlap, the first on a tie), with its pair in *worst_i, *worst_j.
 */
static void worst_pair_overlap(const SimWorld *world, unsigned key, int i0, int i1, double *worst,
                               int *worst_i, int *worst_j)
{
    const double *r = world->radius;
    double best = *worst;
    for (int i = i0; i < i1; ++i) {
        for (int k = world->nl.start[i]; k < world->nl.start[i + 1]; ++k) {
            const int j = world->nl.j[k];
            double dx, dy, d;
            if (!entry_touching(world, key, i, k, &dx, &dy, &d))
                continue;
            const double ratio = (r[i] + r[j] - d) / fmin(2.0 * r[i], 2.0 * r[j]);
            if (ratio > best) {
                best = ratio;
                *worst_i = i;
                *worst_j = j;
            }
        }
    }
    *worst = best;
}

/* The same over the wall entries, with *worst_j = -1 - wall (2 r_i is the smaller diameter). */
static void worst_wall_overlap(const SimWorld *world, double *worst, int *worst_i, int *worst_j)
{
    const double *x = world->x, *y = world->y, *r = world->radius;
    for (int k = 0; k < world->wl.count; ++k) {
        const int i = world->wl.grain[k], w = world->wl.wall[k];
        double nx, ny;
        const double d = sim_wall_geometry(&world->walls[w], x[i], y[i], r[i], &nx, &ny);
        if (d >= r[i])
            continue;
        const double ratio = (r[i] - d) / (2.0 * r[i]);
        if (ratio > *worst) {
            *worst = ratio;
            *worst_i = i;
            *worst_j = -1 - w;
        }
    }
}

/* The guard's scan (world.c): the contact whose overlap is the largest fraction of the smaller
 * diameter (2 r_i against a wall), the first one in sim_contacts_visit's order on a tie, with the
 * visitor's arithmetic for the overlap; *i and *j as SimContact's (j = -1 - wall), -1 and -1
 * when nothing overlaps. It evaluates no law: on a 7000-grain pile the full visitor every 100
 * steps was 2 % of the step's time, serial while other threads waited. */
double sim_contacts_worst_overlap(const SimWorld *world, int *worst_i, int *worst_j)
{
    double worst = 0.0;
    *worst_i = *worst_j = -1;
    worst_pair_overlap(world, sim_contact_key(world), 0, world->mobile_count, &worst, worst_i,
                       worst_j);
    worst_wall_overlap(world, &worst, worst_i, worst_j);
    return worst;
}

/* 1 when a pair among the owners [begin, end) overlaps by more than the guard's bound. */
static int pairs_over_bound(SimWorld *world, int begin, int end)
{
    double worst = world->def.guard_max_overlap;
    int i = -1, j = -1;
    worst_pair_overlap(world, sim_contact_key(world), begin, end, &worst, &i, &j);
    return i >= 0;
}

/* 1 when sim_contacts_worst_overlap's answer exceeds the guard's bound def.guard_max_overlap
 * (> 0), found without the serial scan: the pairs on the world's threads, each owner's entries on
 * one of them (a yes-or-no answer, so the same for any thread count), then the walls' few
 * entries. The guard asks this every guard_every steps; on 2 threads the serial scan was a
 * quarter of the time the second thread waited (docs/dev/scaling.md). */
int sim_contacts_overlap_over_bound(SimWorld *world)
{
    if (sim_parallel_ranges(world, pairs_over_bound, world->mobile_count, 1))
        return 1;
    double worst = world->def.guard_max_overlap;
    int i = -1, j = -1;
    worst_wall_overlap(world, &worst, &i, &j);
    return i >= 0;
}

int sim_contact_key_rotation(unsigned key)
{
    return KEY_ROTATION(key);
}

int sim_contact_key_history(unsigned key)
{
    return (key & KEY_TANGENTIAL) == SIM_TANGENTIAL_SPRING || (key & KEY_ROLLING) != 0;
}
