/* SPDX-License-Identifier: MIT */
/* analysis.c: observables of the theses: free-surface profile (000 §5.4), hexatic order (no
 * crystallisation, 000 §4.2), static equilibrium (004 §3.1) and arch identification (004 §2.5). */
#include "internal.h"
#include "walls.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void sim_world_surface_profile(const SimWorld *w, double x0, double x1, int bins, double *heights)
{
    for (int b = 0; b < bins; ++b)
        heights[b] = NAN;
    double width = (x1 - x0) / bins;
    if (!(width > 0.0))
        return;
    for (int i = 0; i < w->mobile_count; ++i) {
        double t = (w->x[i] - x0) / width;
        if (!(t >= 0.0 && t < bins))
            continue;
        int b = (int)t;
        double top = w->y[i] + w->radius[i];
        if (isnan(heights[b]) || top > heights[b])
            heights[b] = top;
    }
}

double sim_world_hexatic_order(SimWorld *w)
{
    const int n = w->count;
    double *re = calloc((size_t)n + 1, sizeof *re), *im = calloc((size_t)n + 1, sizeof *im);
    int *count = calloc((size_t)n + 1, sizeof *count);
    if (!re || !im || !count) {
        free(re);
        free(im);
        free(count);
        return NAN;
    }
    const int periodic = (w->effects & SIM_EFFECT_PERIODIC_X) != 0;
    for (int i = 0; i < w->mobile_count; ++i) {
        for (int k = w->nl.start[i]; k < w->nl.start[i + 1]; ++k) {
            int j = w->nl.j[k];
            double dx = w->x[j] - w->x[i] + (periodic ? w->nl.shift[k] : 0.0);
            double dy = w->y[j] - w->y[i];
            double cut = 1.1 * (w->radius[i] + w->radius[j]);
            if (dx * dx + dy * dy >= cut * cut)
                continue;
            double theta = atan2(dy, dx);
            double c = cos(6.0 * theta), s = sin(6.0 * theta); /* e^{6i(theta + pi)} = same */
            re[i] += c;
            im[i] += s;
            ++count[i];
            re[j] += c;
            im[j] += s;
            ++count[j];
        }
    }
    double sum = 0.0;
    int used = 0;
    for (int i = 0; i < w->mobile_count; ++i) {
        if (count[i] < 2)
            continue;
        sum += hypot(re[i], im[i]) / count[i];
        ++used;
    }
    free(re);
    free(im);
    free(count);
    return used ? sum / used : 0.0;
}

typedef struct EquilibriumScan {
    SimWorld *world;
    int *contacts; /* per grain */
    double base_fy;
    int sliding;
    double slip_speed; /* a capped contact slips when |v_s| exceeds this, m/s */
} EquilibriumScan;

/* Slip velocity v_s of a contact from the current state (000 eq. 3.5). */
static double contact_slip(const SimWorld *w, const SimContact *c)
{
    int i = c->i;
    double nx = c->x - w->x[i], ny = c->y - w->y[i];
    double len = hypot(nx, ny);
    if (!(len > 0.0))
        return 0.0;
    nx /= len;
    ny /= len;
    double vjx = 0.0, vjy = 0.0, spin_j = 0.0;
    if (c->j >= 0) {
        vjx = w->vx[c->j];
        vjy = w->vy[c->j];
        spin_j = w->omega[c->j] * w->radius[c->j];
    } else {
        sim_wall_velocity(w, -1 - c->j, c->x, c->y, &vjx, &vjy);
    }
    return (vjx - w->vx[i]) * ny - (vjy - w->vy[i]) * nx + w->omega[i] * w->radius[i] + spin_j;
}

static void equilibrium_visit(void *context, const SimContact *c, double energy)
{
    (void)energy;
    EquilibriumScan *e = context;
    SimWorld *w = e->world;
    ++e->contacts[c->i];
    if (c->j >= 0)
        ++e->contacts[c->j];
    unsigned law = (w->effects & SIM_EFFECT_FRICTION) ? w->def.contact.tangential : 0;
    if (law != SIM_TANGENTIAL_NONE) {
        int sj = c->j >= 0 ? w->species[c->j] : w->walls[-1 - c->j].species;
        const PairParams *p = &w->pairs[w->species[c->i] * SIM_MAX_SPECIES + sj];
        double cap = law == SIM_TANGENTIAL_SPRING ? p->mu * p->k_n * c->overlap
                                                  : p->mu * fabs(c->normal_force);
        /* At the Coulomb cap and still slipping (004 code: capped in this step); a contact that
         * sits exactly at the cap without moving is static. */
        if (cap > 0.0 && fabs(c->tangential_force) >= cap * (1.0 - 1e-9) &&
            fabs(contact_slip(w, c)) > e->slip_speed)
            ++e->sliding;
    }
    if (c->j >= 0 && c->j < w->mobile_count)
        return;
    /* Force on the fixed partner: +F_n n - F_t s, n from the grain centre to the contact. */
    double nx = c->x - w->x[c->i], ny = c->y - w->y[c->i];
    double len = hypot(nx, ny);
    if (!(len > 0.0))
        return;
    nx /= len;
    ny /= len;
    e->base_fy += c->normal_force * ny + c->tangential_force * nx; /* -F_t s_y, s_y = -n_x */
}

SimEquilibrium sim_world_equilibrium(SimWorld *w, double tolerance)
{
    SimEquilibrium q = {0};
    double g = hypot(w->def.gravity_x, w->def.gravity_y);
    double m_min = INFINITY, d, m_mean;
    sim_world_means(w, &d, &m_mean);
    for (int i = 0; i < w->mobile_count; ++i) {
        double k = 0.5 * w->mass[i] * (w->vx[i] * w->vx[i] + w->vy[i] * w->vy[i]);
        q.kinetic_max = fmax(q.kinetic_max, k);
        m_min = fmin(m_min, w->mass[i]);
        q.weight += w->mass[i] * g;
    }
    if (w->mobile_count == 0)
        m_min = 0.0;
    /* slip speeds below the kinetic criterion's speed sqrt(tolerance g d) count as static */
    EquilibriumScan scan = {w, calloc((size_t)w->count + 1, sizeof(int)), 0.0, 0,
                            sqrt(tolerance * g * d)};
    if (!scan.contacts) /* SimEquilibrium has no error field, and "not in equilibrium" would be a
                         * wrong answer that a settle loop acts on: stop here */
        abort();
    sim_contacts_visit(w, equilibrium_visit, &scan);
    for (int i = 0; i < w->mobile_count; ++i)
        if (scan.contacts[i] < 2)
            ++q.underconnected;
    free(scan.contacts);
    q.base_force = -scan.base_fy; /* the base is pushed down */
    q.sliding_contacts = scan.sliding;
    q.kinetic_bound = tolerance * m_min * g * d;
    q.force_bound = tolerance * m_min * g;
    q.equilibrium = q.kinetic_max < q.kinetic_bound &&
                    fabs(q.base_force - q.weight) < q.force_bound && q.sliding_contacts == 0 &&
                    q.underconnected == 0;
    return q;
}

/* ------------------------------------------------------------------ arches */

typedef struct ContactGraph {
    int *start, *partner;
    double *force;
    unsigned char *on_base; /* mobile grain touches a fixed grain or a wall */
} ContactGraph;

static int graph_build(const SimFrame *f, ContactGraph *g)
{
    int n = f->count;
    g->start = calloc((size_t)n + 1, sizeof *g->start);
    g->on_base = calloc((size_t)n + 1, 1);
    if (!g->start || !g->on_base)
        return -1;
    int links = 0;
    for (int c = 0; c < f->contact_count; ++c) {
        const SimContact *k = &f->contacts[c];
        int fixed_j = k->j < 0 || k->j >= f->mobile_count;
        if (fixed_j) {
            if (k->i >= 0 && k->i < n)
                g->on_base[k->i] = 1;
            continue;
        }
        ++links;
    }
    g->partner = malloc(2 * (size_t)(links + 1) * sizeof *g->partner);
    g->force = malloc(2 * (size_t)(links + 1) * sizeof *g->force);
    if (!g->partner || !g->force)
        return -1;
    for (int c = 0; c < f->contact_count; ++c) {
        const SimContact *k = &f->contacts[c];
        if (k->j < 0 || k->j >= f->mobile_count)
            continue;
        ++g->start[k->i + 1];
        ++g->start[k->j + 1];
    }
    for (int i = 0; i < n; ++i)
        g->start[i + 1] += g->start[i];
    int *fill = calloc((size_t)n + 1, sizeof *fill);
    if (!fill)
        return -1;
    for (int c = 0; c < f->contact_count; ++c) {
        const SimContact *k = &f->contacts[c];
        if (k->j < 0 || k->j >= f->mobile_count)
            continue;
        int a = g->start[k->i] + fill[k->i]++, b = g->start[k->j] + fill[k->j]++;
        g->partner[a] = k->j;
        g->force[a] = k->normal_force;
        g->partner[b] = k->i;
        g->force[b] = k->normal_force;
    }
    free(fill);
    return 0;
}

static void graph_free(ContactGraph *g)
{
    free(g->start);
    free(g->partner);
    free(g->force);
    free(g->on_base);
}

/* Normal force of the contact a-b, or -1 when they do not touch. */
static double graph_link(const ContactGraph *g, int a, int b)
{
    for (int k = g->start[a]; k < g->start[a + 1]; ++k)
        if (g->partner[k] == b)
            return g->force[k];
    return -1.0;
}

/* Walks one branch (direction -1 left, +1 right) from the keystone; appends grains to path.
 * Returns the number appended when the branch reached the base, -1 when it failed. */
static int arch_branch(const SimFrame *f, const ContactGraph *g, int keystone, int direction,
                       double r_min, double r_max, int check_forces, int *path, int room)
{
    const double d_mean = r_min + r_max, d_max = 2.0 * r_max;
    int current = keystone, added = 0;
    for (;;) {
        double window = f->radius[current] < 0.5 * (r_min + r_max) ? d_mean : d_max;
        double xc = f->x[current], yc = f->y[current];
        int best = -1;
        for (int j = 0; j < f->mobile_count; ++j) {
            double dx = (f->x[j] - xc) * direction;
            if (!(dx > 0.0 && dx < window && f->y[j] > yc - window))
                continue;
            if (best < 0 || f->y[j] < f->y[best])
                best = j;
        }
        if (best < 0) /* no candidate: the branch fails (no backtracking, as the thesis) */
            return -1;
        double force = graph_link(g, current, best);
        if (force < 0.0 || (check_forces && !(force > 0.0)))
            return -1;
        if (added >= room)
            return -1;
        path[added++] = best;
        if (g->on_base[best])
            return added;
        current = best;
    }
}

int sim_frame_find_arch(const SimFrame *f, double center_x, int check_forces, int *members,
                        int max_members)
{
    if (f->mobile_count <= 0)
        return 0;
    double r_min = INFINITY, r_max = 0.0;
    for (int i = 0; i < f->mobile_count; ++i) {
        r_min = fmin(r_min, f->radius[i]);
        r_max = fmax(r_max, f->radius[i]);
    }
    const double d_mean = r_min + r_max;
    int keystone = -1;
    for (int i = 0; i < f->mobile_count; ++i)
        if (fabs(f->x[i] - center_x) < 0.5 * d_mean && (keystone < 0 || f->y[i] < f->y[keystone]))
            keystone = i;
    if (keystone < 0)
        return 0; /* the central strip is empty: the pile was destroyed */
    ContactGraph g = {0};
    int n = 0;
    int *left = malloc((size_t)f->mobile_count * sizeof *left);
    int *right = malloc((size_t)f->mobile_count * sizeof *right);
    if (graph_build(f, &g) == 0 && left && right) {
        int nl =
            arch_branch(f, &g, keystone, -1, r_min, r_max, check_forces, left, f->mobile_count);
        int nr = nl < 0 ? -1
                        : arch_branch(f, &g, keystone, +1, r_min, r_max, check_forces, right,
                                      f->mobile_count);
        /* Each branch must reach the base on its own (fixing the thesis's shared counter). */
        if (nl > 0 && nr > 0 && nl + nr + 1 >= 3 && nl + nr + 1 <= max_members) {
            for (int k = nl - 1; k >= 0; --k)
                members[n++] = left[k];
            members[n++] = keystone;
            for (int k = 0; k < nr; ++k)
                members[n++] = right[k];
        }
    }
    free(left);
    free(right);
    graph_free(&g);
    return n;
}
