/* SPDX-License-Identifier: MIT */
/* contact.c: the contact kernel, written once and instantiated per combination of the declared
 * laws, so that no per-contact `if` tests a disabled effect (the `key` argument is a compile-time
 * constant in every instantiation and the branches fold away).
 *
 * Conventions (000 eqs. 3.1-3.5): n points from i to j, s = (n_y, -n_x),
 * v_s = (v_j - v_i).s + omega_i r_i + omega_j r_j. The force on i is -F_n n + F_t s, on j the
 * opposite; both torques are -r F_t (000 eq. 4.4; 004 §1.6). */
#include "world.h"

#include <math.h>

enum {
    KEY_TANGENTIAL = 3u, /* SimTangentialLaw in the low two bits */
    KEY_ROLLING = 1u << 2,
    KEY_PERIODIC = 1u << 3,
    KEY_HERTZ = 1u << 4,
    KEY_CLIP = 1u << 5,
    KEY_CHORD = 1u << 6, /* rolling law from the contact chord (else fixed k_r) */
    KEY_COUNT = 128
};

/* Torques exist only when a tangential law or rolling resistance is declared. */
#define KEY_ROTATION(key) (((key)&KEY_TANGENTIAL) != 0 || ((key)&KEY_ROLLING) != 0)

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
    return key;
}

/* A min that compiles to one instruction: libm's fmin is a function call unless NaN
 * semantics are relaxed, and it spills every register around the kernel's hot loop. */
static inline double min_d(double a, double b)
{
    return a < b ? a : b;
}

/* Normal force magnitude (positive = repulsive) and its elastic part. 000 eq. 3.6 (linear),
 * Hertz-type sqrt(xi) (k_n xi + gamma_n dxi/dt). dxi/dt = -v_n. */
static inline double normal_force(const unsigned key, double k_n, double gamma_n, double xi,
                                  double v_n, double *elastic)
{
    double f;
    if (key & KEY_HERTZ) {
        double root = sqrt(xi);
        *elastic = k_n * xi * root;
        f = *elastic - gamma_n * root * v_n;
    } else {
        *elastic = k_n * xi;
        f = *elastic - gamma_n * v_n;
    }
    if (key & KEY_CLIP)
        f = f > 0.0 ? f : 0.0; /* a branch: the sign is predictable, a max would sit on the chain */
    return f;
}

/* Tangential force along s. Regularised Coulomb: 000 eq. 3.28. Spring: 004 eqs. 1.12-1.13 with
 * the cap on the elastic normal force, xi_t kept at the cap while sliding. */
static inline double tangential_force(const unsigned key, const PairParams *p, double v_s,
                                      double f_n, double f_el, double dt, double *xi_t)
{
    unsigned law = key & KEY_TANGENTIAL;
    /* Written without data-dependent branches: sticking and sliding contacts mix at random. */
    if (law == SIM_TANGENTIAL_REGULARISED)
        return copysign(min_d(p->gamma_s * fabs(v_s), p->mu * fabs(f_n)), v_s);
    if (law == SIM_TANGENTIAL_SPRING) {
        double stretch = *xi_t + v_s * dt;
        double f = p->k_t * stretch;
        double cap = p->mu * f_el;
        double capped = copysign(min_d(fabs(f), cap), f);
        *xi_t = capped != f ? capped / p->k_t : stretch; /* slip: keep the spring at the cap */
        return capped;
    }
    return 0.0;
}

/* Rolling torque M (004 eqs. 4.1-4.2): M <- M - k_r (omega_j - omega_i) dt, |M| <= mu_r f_el.
 * Chord law: k_r = k_n l_c^2, mu_r = mu l_c. */
static inline double rolling_torque(const unsigned key, const PairParams *p, double chord,
                                    double relative_spin, double f_el, double dt, double *m_r)
{
    double k_r = p->k_r, mu_r = p->mu_r;
    if (key & KEY_CHORD) {
        k_r = p->k_n * chord * chord;
        mu_r = p->mu * chord;
    }
    double m = *m_r - k_r * relative_spin * dt;
    double cap = mu_r * f_el;
    if (fabs(m) > cap)
        m = copysign(cap, m);
    *m_r = m;
    return m;
}

/* Common chord of two overlapping disks at centre distance d (004 §1.7). */
static inline double disk_chord(double d, double ri, double rj)
{
    double a = (d * d - (ri - rj) * (ri - rj)) * ((ri + rj) * (ri + rj) - d * d);
    return a > 0.0 ? sqrt(a) / d : 0.0;
}

static inline void grain_pass(SimWorld *world, const unsigned key)
{
    const int mobile = world->mobile_count;
    const double dt = world->contact_dt;
    const double *restrict x = world->x, *restrict y = world->y;
    const double *restrict vx = world->vx, *restrict vy = world->vy;
    const double *restrict omega = world->omega, *restrict radius = world->radius;
    double *restrict fx = world->fx, *restrict fy = world->fy, *restrict torque = world->torque;
    const int *restrict start = world->nl.start, *restrict partner = world->nl.j;
    const double *restrict gamma = world->nl.gamma, *restrict shift = world->nl.shift;
    const uint8_t *restrict pair = world->nl.pair;
    double *restrict hist_t = world->nl.hist_t, *restrict hist_r = world->nl.hist_r;
    const PairParams *pairs = world->pairs;
    const unsigned law = key & KEY_TANGENTIAL;

    for (int i = 0; i < mobile; ++i) {
        const double xi0 = x[i], yi0 = y[i], ri = radius[i];
        const double vxi = vx[i], vyi = vy[i], wi = KEY_ROTATION(key) ? omega[i] : 0.0;
        double fxi = 0.0, fyi = 0.0, ti = 0.0;
        const int end = start[i + 1];
        for (int k = start[i]; k < end; ++k) {
            const int j = partner[k];
            double dx = x[j] - xi0;
            if (key & KEY_PERIODIC)
                dx += shift[k];
            const double dy = y[j] - yi0;
            const double rs = ri + radius[j];
            const double d2 = dx * dx + dy * dy;
            if (d2 >= rs * rs) {
                if (law == SIM_TANGENTIAL_SPRING)
                    hist_t[k] = 0.0;
                if (key & KEY_ROLLING)
                    hist_r[k] = 0.0;
                continue;
            }
            const double d = sqrt(d2);
            const double inv = 1.0 / d;
            const double nx = dx * inv, ny = dy * inv;
            const double overlap = rs - d; /* 000 eq. 3.1 */
            const double dvx = vx[j] - vxi, dvy = vy[j] - vyi;
            const double v_n = dvx * nx + dvy * ny; /* 000 eq. 3.4 */
            const PairParams *p = &pairs[pair[k]];
            double f_el;
            const double f_n = normal_force(key, p->k_n, gamma[k], overlap, v_n, &f_el);
            double fxk = -f_n * nx, fyk = -f_n * ny;
            if (law != SIM_TANGENTIAL_NONE) {
                const double sx = ny, sy = -nx;   /* 000 eq. 3.3 */
                double v_s = dvx * sx + dvy * sy; /* 000 eq. 3.5 */
                if (KEY_ROTATION(key))
                    v_s += wi * ri + omega[j] * radius[j];
                double dummy = 0.0;
                double *xi_t = (law == SIM_TANGENTIAL_SPRING) ? &hist_t[k] : &dummy;
                const double f_t = tangential_force(key, p, v_s, f_n, f_el, dt, xi_t);
                fxk += f_t * sx;
                fyk += f_t * sy;
                if (KEY_ROTATION(key)) {
                    ti -= ri * f_t; /* 000 eq. 4.4 */
                    torque[j] -= radius[j] * f_t;
                }
            }
            if (key & KEY_ROLLING) {
                const double chord = (key & KEY_CHORD) ? disk_chord(d, ri, radius[j]) : 0.0;
                const double m = rolling_torque(key, p, chord, omega[j] - wi, f_el, dt, &hist_r[k]);
                ti -= m;
                torque[j] += m;
            }
            fxi += fxk;
            fyi += fyk;
            fx[j] -= fxk;
            fy[j] -= fyk;
        }
        fx[i] += fxi;
        fy[i] += fyi;
        if (KEY_ROTATION(key))
            torque[i] += ti;
    }
}

/* Closest point of wall segment w to (px, py). */
static inline void segment_closest(const SimWall *w, double px, double py, double *cx, double *cy)
{
    double ex = w->x1 - w->x0, ey = w->y1 - w->y0;
    double len2 = ex * ex + ey * ey;
    double t = len2 > 0.0 ? ((px - w->x0) * ex + (py - w->y0) * ey) / len2 : 0.0;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    *cx = w->x0 + t * ex;
    *cy = w->y0 + t * ey;
}

/* Wall contact geometry: n from the grain centre to the closest point. Returns the distance. */
static inline double wall_geometry(const SimWall *w, double px, double py, double *nx, double *ny)
{
    double cx, cy;
    segment_closest(w, px, py, &cx, &cy);
    double dx = cx - px, dy = cy - py;
    double d = sqrt(dx * dx + dy * dy);
    if (d > 0.0) {
        *nx = dx / d;
        *ny = dy / d;
    } else { /* centre exactly on the wall: push along the wall's left normal */
        double ex = w->x1 - w->x0, ey = w->y1 - w->y0;
        double len = sqrt(ex * ex + ey * ey);
        *nx = len > 0.0 ? ey / len : 0.0;
        *ny = len > 0.0 ? -ex / len : -1.0;
    }
    return d;
}

/* Grain-wall contacts: the wall acts as a partner of infinite mass, zero radius, no spin. */
static inline void wall_pass(SimWorld *world, const unsigned key)
{
    const WallList *wl = &world->wl;
    const double dt = world->contact_dt;
    const unsigned law = key & KEY_TANGENTIAL;
    for (int k = 0; k < wl->count; ++k) {
        const int i = wl->grain[k], w = wl->wall[k];
        const double ri = world->radius[i];
        double nx, ny;
        const double d = wall_geometry(&world->walls[w], world->x[i], world->y[i], &nx, &ny);
        if (d >= ri) {
            if (law == SIM_TANGENTIAL_SPRING)
                wl->hist_t[k] = 0.0;
            if (key & KEY_ROLLING)
                wl->hist_r[k] = 0.0;
            continue;
        }
        const double overlap = ri - d;
        const double dvx = world->wall_vx[w] - world->vx[i];
        const double dvy = world->wall_vy[w] - world->vy[i];
        const double v_n = dvx * nx + dvy * ny;
        const PairParams *p = &world->pairs[wl->pair[k]];
        double f_el;
        const double f_n = normal_force(key, p->k_n, wl->gamma[k], overlap, v_n, &f_el);
        double fxk = -f_n * nx, fyk = -f_n * ny;
        const double wi = KEY_ROTATION(key) ? world->omega[i] : 0.0;
        if (law != SIM_TANGENTIAL_NONE) {
            const double sx = ny, sy = -nx;
            double v_s = dvx * sx + dvy * sy + wi * ri;
            double dummy = 0.0;
            double *xi_t = (law == SIM_TANGENTIAL_SPRING) ? &wl->hist_t[k] : &dummy;
            const double f_t = tangential_force(key, p, v_s, f_n, f_el, dt, xi_t);
            fxk += f_t * sx;
            fyk += f_t * sy;
            if (KEY_ROTATION(key))
                world->torque[i] -= ri * f_t;
        }
        if (key & KEY_ROLLING) {
            const double chord = (key & KEY_CHORD) ? 2.0 * sqrt(ri * ri - d * d) : 0.0;
            world->torque[i] -= rolling_torque(key, p, chord, -wi, f_el, dt, &wl->hist_r[k]);
        }
        world->fx[i] += fxk;
        world->fy[i] += fyk;
    }
}

/* One instantiation per key = 8 * high + low: low = tangential law (0..2) | rolling (4);
 * high = periodic | hertz << 1 | clip << 2 | chord << 3, chord only with rolling. */
/* clang-format off */
#define KEYS_LOW(X, h)  X(h, 0) X(h, 1) X(h, 2) X(h, 4) X(h, 5) X(h, 6)
#define KEYS_ROLL(X, h) X(h, 4) X(h, 5) X(h, 6)
#define KEYS_ALL(X)                                                                     \
    KEYS_LOW(X, 0) KEYS_LOW(X, 1) KEYS_LOW(X, 2) KEYS_LOW(X, 3) KEYS_LOW(X, 4)         \
    KEYS_LOW(X, 5) KEYS_LOW(X, 6) KEYS_LOW(X, 7) KEYS_ROLL(X, 8) KEYS_ROLL(X, 9)       \
    KEYS_ROLL(X, 10) KEYS_ROLL(X, 11) KEYS_ROLL(X, 12) KEYS_ROLL(X, 13)                \
    KEYS_ROLL(X, 14) KEYS_ROLL(X, 15)
/* clang-format on */

#define DEFINE_PASS(h, l)                                                                          \
    static void grain_pass_##h##_##l(SimWorld *world)                                              \
    {                                                                                              \
        grain_pass(world, (unsigned)((h)*8 + (l)));                                                \
    }                                                                                              \
    static void wall_pass_##h##_##l(SimWorld *world)                                               \
    {                                                                                              \
        wall_pass(world, (unsigned)((h)*8 + (l)));                                                 \
    }
KEYS_ALL(DEFINE_PASS)

#define GRAIN_ENTRY(h, l) [(h)*8 + (l)] = grain_pass_##h##_##l,
#define WALL_ENTRY(h, l)  [(h)*8 + (l)] = wall_pass_##h##_##l,
static StageFn *const grain_passes[KEY_COUNT] = {KEYS_ALL(GRAIN_ENTRY)};
static StageFn *const wall_passes[KEY_COUNT] = {KEYS_ALL(WALL_ENTRY)};

StageFn *sim_contact_pass_select(unsigned key)
{
    return key < KEY_COUNT ? grain_passes[key] : NULL;
}

StageFn *sim_wall_pass_select(unsigned key)
{
    return key < KEY_COUNT ? wall_passes[key] : NULL;
}

/* ------------------------------------------------------------------ diagnostics (not hot) */

static void visit_one(SimWorld *world, unsigned key, int i, int j, int wall, double nx, double ny,
                      double overlap, double chord, double v_n, double v_s, const PairParams *p,
                      double gamma_n, double xi_t, double m_r, double cx, double cy,
                      ContactVisit *visit, void *context)
{
    double f_el;
    double f_n = normal_force(key, p->k_n, gamma_n, overlap, v_n, &f_el);
    unsigned law = key & KEY_TANGENTIAL;
    double f_t = 0.0, energy;
    if (law == SIM_TANGENTIAL_REGULARISED) {
        double scratch = 0.0;
        f_t = tangential_force(key, p, v_s, f_n, f_el, 0.0, &scratch);
    } else if (law == SIM_TANGENTIAL_SPRING) {
        f_t = p->k_t * xi_t;
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
    (void)nx;
    (void)ny;
    SimContact c = {.i = i,
                    .j = wall >= 0 ? -1 - wall : j,
                    .normal_force = f_n,
                    .tangential_force = f_t,
                    .overlap = overlap,
                    .x = cx,
                    .y = cy};
    (void)world;
    visit(context, &c, energy);
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
            double dx = x[j] - x[i] + ((key & KEY_PERIODIC) ? world->nl.shift[k] : 0.0);
            double dy = y[j] - y[i];
            double rs = r[i] + r[j];
            double d2 = dx * dx + dy * dy;
            if (d2 >= rs * rs)
                continue;
            double d = sqrt(d2);
            double nx = d > 0.0 ? dx / d : 1.0, ny = d > 0.0 ? dy / d : 0.0;
            double dvx = world->vx[j] - world->vx[i], dvy = world->vy[j] - world->vy[i];
            double wj = world->rotation ? world->omega[j] : 0.0;
            double v_s = dvx * ny - dvy * nx + wi * r[i] + wj * r[j];
            double xi_t = law == SIM_TANGENTIAL_SPRING ? world->nl.hist_t[k] : 0.0;
            double m_r = (key & KEY_ROLLING) ? world->nl.hist_r[k] : 0.0;
            double overlap = rs - d;
            double lever = r[i] - 0.5 * overlap;
            visit_one(world, key, i, j, -1, nx, ny, overlap, disk_chord(d, r[i], r[j]),
                      dvx * nx + dvy * ny, v_s, &world->pairs[world->nl.pair[k]],
                      world->nl.gamma[k], xi_t, m_r, x[i] + lever * nx, y[i] + lever * ny, visit,
                      context);
        }
    }
    for (int k = 0; k < world->wl.count; ++k) {
        int i = world->wl.grain[k], w = world->wl.wall[k];
        double nx, ny;
        double d = wall_geometry(&world->walls[w], x[i], y[i], &nx, &ny);
        if (d >= r[i])
            continue;
        double dvx = world->wall_vx[w] - world->vx[i], dvy = world->wall_vy[w] - world->vy[i];
        double wi = world->rotation ? world->omega[i] : 0.0;
        double v_s = dvx * ny - dvy * nx + wi * r[i];
        double xi_t = law == SIM_TANGENTIAL_SPRING ? world->wl.hist_t[k] : 0.0;
        double m_r = (key & KEY_ROLLING) ? world->wl.hist_r[k] : 0.0;
        visit_one(world, key, i, -1, w, nx, ny, r[i] - d, 2.0 * sqrt(r[i] * r[i] - d * d),
                  dvx * nx + dvy * ny, v_s, &world->pairs[world->wl.pair[k]], world->wl.gamma[k],
                  xi_t, m_r, x[i] + d * nx, y[i] + d * ny, visit, context);
    }
}

int sim_contact_key_rotation(unsigned key)
{
    return KEY_ROTATION(key);
}
