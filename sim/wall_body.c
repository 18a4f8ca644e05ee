/* SPDX-License-Identifier: MIT */
/* wall_body.c: walls and groups of fixed grains that respond to the grains (sim.h SimWallBody):
 * free pistons of a given mass and servo-controlled walls, each a rigid translation along its
 * axis (plus, for a wall with a motion, the motion's translation across it) and, when asked, a
 * rotation about its centre, and the load the grains put on every wall (SimWallLoad). The wall
 * loads are summed by the wall pass (sim/isa/contact_pass.c) in the wall list's order, serially;
 * a grain body's load sums its grains' contact forces in frame order, serially: the same bits
 * for any thread count. The bodies move once per step, after the step's last force evaluation
 * (symplectic Euler: the speed from the force, then the offset from the new speed; the same for
 * the angle). Their offsets, speeds, angles and angular speeds are kept at the end of a state
 * file (docs/state-format.md, "Responding walls"). */
#include "internal.h"
#include "walls.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Length of a wall: a segment's, an arc's span (a full circle at most), m. */
static double wall_length(const SimWall *w)
{
    if (w->shape == SIM_WALL_ARC)
        return w->radius * fmin(w->angle1 - w->angle0, 2.0 * SIM_PI);
    return hypot(w->x1 - w->x0, w->y1 - w->y0);
}

/* The length a responding body's stress target is taken over (SimWallBody length_kind), m, with
 * the walls where they are (`walls`: now, or as defined before a run): its own length `own` (a
 * wall's, a grain body's extent across its axis, as at rest), a given
 * one, or the distance across its axis t = (-a_y, a_x) between the two walls it names, |(p_1 -
 * p_0).t| for a point p of each (segments parallel to the axis). */
static double servo_length(const SimWall *walls, const SimWallBody *b, double own)
{
    if (b->length_kind == 1)
        return b->length;
    if (b->length_kind == 2) {
        const SimWall *a = &walls[b->between[0]], *c = &walls[b->between[1]];
        return fabs((c->y0 - a->y0) * b->axis_x - (c->x0 - a->x0) * b->axis_y);
    }
    return own;
}

/* The smallest mobile diameter of def's grains (INFINITY without mobile grains), and the largest
 * normal stiffness of a pair of a mobile grain's species with wall species `species`; *gamma_max
 * (when not NULL) the largest normal damping gamma_n of a mobile grain against the wall
 * (sim_damping_gamma, m_eff the grain's mass). Hertz contacts: both at an overlap of 1 % of
 * that diameter (the tangent stiffness 3/2 k_n sqrt(xi), the dashpot gamma_n sqrt(xi)). */
static double wall_stiffness(const SimWorldDef *def, int species, double *d_min, double *gamma_max)
{
    const SimGrainSet *g = &def->grains;
    double k = 0.0, d = INFINITY, gamma = 0.0;
    for (int i = 0; i < g->count; ++i) {
        if (g->flags && (g->flags[i] & SIM_GRAIN_FIXED))
            continue;
        const int s = g->species ? g->species[i] : 0;
        const double k_pair =
            0.5 * (def->materials[s].normal_stiffness + def->materials[species].normal_stiffness);
        d = fmin(d, 2.0 * g->radius[i]);
        k = fmax(k, k_pair);
        if (gamma_max) {
            const double m =
                sim_grain_mass(def->mass_model, def->materials[s].density, g->radius[i]);
            gamma = fmax(gamma, sim_damping_gamma(def->materials, s, species, k_pair, m));
        }
    }
    if (def->contact.normal == SIM_NORMAL_HERTZ && isfinite(d)) {
        k = 1.5 * k * sqrt(0.01 * d);
        gamma *= sqrt(0.01 * d);
    }
    *d_min = d;
    if (gamma_max)
        *gamma_max = gamma;
    return k;
}

/* Body k of def: wall k (k < wall_count; NULL when it does not respond), else grain body
 * k - wall_count. */
static const SimWallBody *def_body(const SimWorldDef *def, int k)
{
    if (k < 0 || k >= def->wall_count + (def->grain_bodies ? def->grain_body_count : 0))
        return NULL;
    if (k < def->wall_count)
        return def->wall_bodies && def->wall_bodies[k].active ? &def->wall_bodies[k] : NULL;
    return &def->grain_bodies[k - def->wall_count];
}

/* A body's shape at rest: its centre, its length (a wall's; a grain body's extent across its
 * axis), the moment of inertia of its mass about the centre (sim.h SimWallBody), its grains
 * and the species its load is measured against (a wall's; a grain body's first grain's). */
typedef struct BodyShape {
    double cx, cy, length, inertia;
    int grains, species;
} BodyShape;

/* Grain i of g is a member of grain body b. */
static int body_member(const SimGrainSet *g, int i, int b)
{
    return g->motion && g->motion[i] == SIM_GRAIN_BODY(b);
}

static BodyShape grain_body_shape(const SimWorldDef *def, int b, const SimWallBody *body)
{
    const SimGrainSet *g = &def->grains;
    BodyShape s = {0.0, 0.0, 0.0, 0.0, 0, 0};
    double area = 0.0, lo = INFINITY, hi = -INFINITY, spread = 0.0;
    for (int i = 0; i < g->count; ++i) {
        if (!body_member(g, i, b))
            continue;
        const double r = g->radius[i], a = SIM_PI * r * r;
        const double across = g->y[i] * body->axis_x - g->x[i] * body->axis_y;
        if (s.grains++ == 0)
            s.species = g->species ? g->species[i] : 0;
        area += a;
        s.cx += a * g->x[i];
        s.cy += a * g->y[i];
        lo = fmin(lo, across - r);
        hi = fmax(hi, across + r);
    }
    if (!s.grains)
        return s;
    s.cx /= area;
    s.cy /= area;
    s.length = hi - lo;
    for (int i = 0; i < g->count; ++i)
        if (body_member(g, i, b)) {
            const double r = g->radius[i], dx = g->x[i] - s.cx, dy = g->y[i] - s.cy;
            spread += SIM_PI * r * r * (dx * dx + dy * dy + 0.5 * r * r);
        }
    s.inertia = body->mass * spread / area;
    return s;
}

static BodyShape body_shape(const SimWorldDef *def, int k)
{
    const SimWallBody *body = def_body(def, k);
    if (k >= def->wall_count) {
        BodyShape s = grain_body_shape(def, k - def->wall_count, body);
        if (body->inertia > 0.0)
            s.inertia = body->inertia;
        return s;
    }
    const SimWall *w = &def->walls[k];
    const int arc = w->shape == SIM_WALL_ARC;
    BodyShape s = {arc ? w->center_x : 0.5 * (w->x0 + w->x1),
                   arc ? w->center_y : 0.5 * (w->y0 + w->y1),
                   wall_length(w),
                   0.0,
                   0,
                   w->species};
    const double m = body ? body->mass : 0.0;
    s.inertia = arc ? m * w->radius * w->radius : m * s.length * s.length / 12.0;
    if (body && body->inertia > 0.0)
        s.inertia = body->inertia;
    return s;
}

double sim_wall_servo_time(const SimWorldDef *def, int wall)
{
    const SimWallBody *b = def_body(def, wall);
    if (!b || !b->servo)
        return INFINITY;
    const BodyShape shape = body_shape(def, wall);
    double d;
    const double k = wall_stiffness(def, shape.species, &d, NULL);
    /* stress: a displacement u changes the stress by k u / d; force: by k u length / d */
    double per_speed = k / d * (b->servo == 2 ? shape.length : 1.0);
    return isfinite(d) && per_speed > 0.0 ? 1.0 / (b->gain * per_speed) : (double)INFINITY;
}

int sim_wall_servo_implicit(const SimWorldDef *def, int wall)
{
    const SimWallBody *b = def_body(def, wall);
    return b && b->servo && wall < def->wall_count && !b->servo_explicit;
}

/* The servo's damping feedback: the wall speed u set at one step enters every contact's normal
 * dashpot at the next (000 eq. 3.4: F_n = k_n xi + gamma_n dxi/dt), so one contact moves the
 * measured load by about gamma_n u and the next speed by gain gamma_n u (stress: divided by the
 * length). With n_c contacts the factor is n_c times that; at 1 or more the speed flips sign
 * every step and grows to max_speed while the stiffness rule still holds. gamma_n of the
 * heaviest mobile grain against the wall (sim_damping_gamma; Hertz: at an overlap of 1 % of
 * d_min, as wall_stiffness). *row: the contacts of a row of the smallest grains along it. */
double sim_wall_servo_damping(const SimWorldDef *def, int wall, double *row)
{
    *row = 0.0;
    const SimWallBody *b = def_body(def, wall);
    if (!b || !b->servo || sim_wall_servo_implicit(def, wall))
        return 0.0;
    const BodyShape shape = body_shape(def, wall);
    double d, gamma;
    wall_stiffness(def, shape.species, &d, &gamma);
    if (!isfinite(d))
        return 0.0;
    const double length = servo_length(def->walls, b, shape.length);
    *row = floor(length / d) + 1.0;
    return b->gain * gamma / (b->servo == 2 ? 1.0 : length);
}

/* Why motion `index` cannot move a wall that responds along (axis_x, axis_y): it turns, or it
 * has a part along the axis; NULL when it only moves across it (an axis (0, 0): turns only). */
static const char *motion_across(const SimMotion *motions, int index, double axis_x, double axis_y)
{
    const SimMotion *m = &motions[index];
    double vx = 0.0, vy = 0.0;
    switch (m->kind) {
    case SIM_MOTION_ROTATION:
        return "its motion turns it (a wall that responds only translates)";
    case SIM_MOTION_COMPOSE:
        for (int k = 0; k < m->part_count; ++k) {
            const char *why = m->parts[k] >= 0 && m->parts[k] < index
                                  ? motion_across(motions, m->parts[k], axis_x, axis_y)
                                  : NULL;
            if (why)
                return why;
        }
        return NULL;
    case SIM_MOTION_SINUSOIDAL:
        vx = m->amplitude * m->direction_x;
        vy = m->amplitude * m->direction_y;
        break;
    case SIM_MOTION_VELOCITY:
        vx = m->velocity_x;
        vy = m->velocity_y;
        break;
    }
    if (fabs(vx * axis_x + vy * axis_y) > 1e-12 * hypot(vx, vy))
        return "its motion moves it along its axis, which its mass or servo controls (give the "
               "motion a direction across the axis)";
    return NULL;
}

/* The problem of responding wall k's stress length (SimWallBody length_kind); NULL: sound. */
static const char *length_problem(const SimWorldDef *def, int k, const SimWallBody *b, char *buf,
                                  size_t size)
{
    if (b->length_kind == 0)
        return NULL;
    if (b->servo != 1)
        return "a servo's length is for a stress target (a force needs none)";
    if (b->length_kind == 1)
        return b->length > 0.0 && isfinite(b->length) ? NULL : "its servo length must be > 0";
    if (b->length_kind != 2)
        return "unknown servo length kind";
    for (int j = 0; j < 2; ++j) {
        const int n = b->between[j];
        if (n < 0 || n >= def->wall_count || n == k || n == b->between[1 - j]) {
            snprintf(buf, size,
                     "its servo's `between` names wall %d: it needs two other walls of the %d", n,
                     def->wall_count);
            return buf;
        }
        const SimWall *w = &def->walls[n];
        const double ex = w->x1 - w->x0, ey = w->y1 - w->y0;
        if (w->shape == SIM_WALL_ARC ||
            !(fabs(ex * b->axis_y - ey * b->axis_x) <= 1e-9 * hypot(ex, ey)) ||
            (w->motion >= 0 && w->motion < def->motion_count &&
             motion_across(def->motions, w->motion, 0.0, 0.0))) {
            snprintf(buf, size,
                     "its servo's `between` names wall %d, which is not a segment parallel to "
                     "its axis (that stays so: no turning motion)",
                     n);
            return buf;
        }
    }
    if (!(servo_length(def->walls, b, body_shape(def, k).length) > 0.0))
        return "its servo's `between` walls are at no distance from each other";
    return NULL;
}

/* The problem of body k's shape (a grain body's grains, a rotation's inertia); NULL if none. */
static const char *shape_problem(const SimWorldDef *def, int k, const SimWallBody *b)
{
    if (k >= def->wall_count) {
        const SimGrainSet *g = &def->grains;
        const int body = k - def->wall_count;
        for (int i = 0; i < g->count; ++i)
            if (body_member(g, i, body) && !(g->flags && (g->flags[i] & SIM_GRAIN_FIXED)))
                return "the grains of a grain body must be fixed grains";
    }
    if (!(isfinite(b->inertia) && b->inertia >= 0.0))
        return "its moment of inertia must be >= 0 (finite; 0: from the mass)";
    if (b->rotation && !(body_shape(def, k).inertia > 0.0))
        return "a body that turns needs a mass or a moment of inertia > 0";
    return NULL;
}

/* The problem of one responding body k, written into buf; NULL when it is sound. */
static const char *body_problem(const SimWorldDef *def, int k, double dt, double r_min, char *buf,
                                size_t size)
{
    const SimWallBody *b = def_body(def, k);
    if (!b)
        return NULL; /* it does not respond */
    const double norm = hypot(b->axis_x, b->axis_y);
    if (norm == 0.0 && !(b->rotation && !b->servo))
        return "a body without an axis (hinged at its centre) must turn and have no servo";
    if (norm != 0.0 && !(fabs(norm - 1.0) < 1e-9))
        return "the axis of a responding wall must be a unit vector (or zero: it only turns)";
    const char *shape = shape_problem(def, k, b);
    if (shape)
        return shape;
    const int motion = k < def->wall_count ? def->walls[k].motion : -1;
    const char *across = motion >= 0 && motion < def->motion_count
                             ? motion_across(def->motions, motion, b->axis_x, b->axis_y)
                             : NULL;
    if (across)
        return across;
    const char *length = length_problem(def, k, b, buf, size);
    if (length)
        return length;
    if (!(isfinite(b->force_x) && isfinite(b->force_y)))
        return "its applied force is not finite";
    if (!b->servo) {
        if (!(b->mass > 0.0) || !isfinite(b->mass))
            return "a responding wall without a servo needs a mass > 0 (finite)";
        return NULL;
    }
    if (!(b->gain > 0.0 && isfinite(b->gain) && b->max_speed > 0.0 && isfinite(b->max_speed) &&
          isfinite(b->target)))
        return "a servo needs a finite target, gain > 0 and max_speed > 0";
    if (b->max_speed * dt > 0.5 * r_min) {
        snprintf(buf, size,
                 "its servo's max_speed %g m/s moves it %g m per time step, more than half the "
                 "smallest grain radius %g m (wall-speed limit): max_speed must be below %g m/s",
                 b->max_speed, b->max_speed * dt, r_min, 0.5 * r_min / dt);
        return buf;
    }
    const double tau = sim_wall_servo_time(def, k);
    if (dt > tau) {
        snprintf(buf, size,
                 "its servo gain %g makes the wall unstable: the servo's time scale tau = "
                 "d_min / (gain k_n%s) = %g s is below the time step %g s, so each step "
                 "overshoots the target (diverging from dt > 2 tau); the gain must be below %g",
                 b->gain, b->servo == 2 ? " length" : "", tau, dt, b->gain * tau / dt);
        return buf;
    }
    double row;
    const double feedback = sim_wall_servo_damping(def, k, &row);
    if (feedback >= 1.0) {
        snprintf(buf, size,
                 "its servo gain %g makes the wall unstable through the contacts' damping: a speed "
                 "set at one step changes the next step's measured load, through one contact's "
                 "dashpot, by gain gamma_n%s = %.3g times itself (1 or more: the speed flips sign "
                 "every step); the gain must be below %g",
                 b->gain, b->servo == 2 ? "" : " / length", feedback, b->gain / feedback);
        return buf;
    }
    return NULL;
}

/* The smallest radius of def's mobile grains (INFINITY without any). */
static double mobile_r_min(const SimWorldDef *def)
{
    double r_min = INFINITY;
    for (int i = 0; i < def->grains.count; ++i)
        if (!(def->grains.flags && (def->grains.flags[i] & SIM_GRAIN_FIXED)))
            r_min = fmin(r_min, def->grains.radius[i]);
    return r_min;
}

/* Body k of def is a grain body whose group has no grain yet: dormant (sim.h SimWorldDef
 * grain_bodies), checked when its grains join (sim_wall_bodies_join_problem). */
static int dormant(const SimWorldDef *def, int k)
{
    return k >= def->wall_count && body_shape(def, k).grains == 0;
}

const char *sim_wall_bodies_problem(const SimWorldDef *def, double dt, int *wall, char *buf,
                                    size_t size)
{
    const int bodies = def->wall_count + (def->grain_bodies ? def->grain_body_count : 0);
    if (!def->wall_bodies && bodies == def->wall_count)
        return NULL;
    const double r_min = mobile_r_min(def);
    for (int k = 0; k < bodies; ++k) {
        if (!def_body(def, k) || dormant(def, k))
            continue;
        const char *why = body_problem(def, k, dt, r_min, buf, size);
        if (why) {
            *wall = k;
            return why;
        }
    }
    return NULL;
}

/* Body k's rest geometry (body_rest): its centre, length and moment of inertia. */
static void set_rest(SimWorld *w, int k, BodyShape shape)
{
    double *rest = &w->body_rest[4 * k];
    rest[0] = shape.cx;
    rest[1] = shape.cy;
    rest[2] = shape.length;
    rest[3] = shape.inertia;
}

int sim_wall_bodies_create(SimWorld *w, const SimWorldDef *def)
{
    const int groups = def->grain_bodies ? def->grain_body_count : 0;
    if (!(def->wall_bodies && def->wall_count > 0) && groups <= 0)
        return 0;
    const int n = def->wall_count + groups;
    w->body_count = n;
    w->bodies = calloc((size_t)n, sizeof *w->bodies);
    double **arrays[] = {&w->body_s, &w->body_u, &w->body_a, &w->body_w};
    w->body_m = calloc(4 * (size_t)n, sizeof(double));
    for (size_t a = 0; a < sizeof arrays / sizeof arrays[0]; ++a)
        *arrays[a] = calloc((size_t)n, sizeof(double));
    w->body_rest = calloc(4 * (size_t)n, sizeof(double));
    w->wall_damp = calloc((size_t)n, sizeof(double));
    w->body_flip = calloc(3 * (size_t)n, sizeof(double));
    if (!w->bodies || !w->body_s || !w->body_u || !w->body_a || !w->body_w || !w->body_rest ||
        !w->body_m || !w->wall_damp || !w->body_flip)
        return -1;
    for (int k = 0; k < n; ++k)
        w->body_flip[3 * k + 2] = NAN;
    for (int k = 0; k < n; ++k) {
        const SimWallBody *b = def_body(def, k);
        if (!b)
            continue;
        w->bodies[k] = *b;
        w->bodies[k].active = !dormant(def, k);
        set_rest(w, k, body_shape(def, k));
    }
    w->def.wall_bodies = def->wall_bodies ? w->bodies : NULL;
    w->def.grain_bodies = groups > 0 ? w->bodies + def->wall_count : NULL;
    w->def.grain_body_count = groups;
    return 0;
}

/* The world's grains (their rest positions) and g after them, as one set in `def` (arrays in
 * *store, freed by the caller); -1 out of memory. */
static int joined_grains(const SimWorld *w, const SimGrainSet *g, SimWorldDef *def, void **store)
{
    const size_t n = (size_t)w->count, total = n + (size_t)g->count;
    char *p = malloc(total * (3 * sizeof(double) + 2 * sizeof(int) + sizeof(unsigned)) + 1);
    *store = p;
    if (!p)
        return -1;
    double *x = (double *)p, *y = x + total, *r = y + total;
    int *species = (int *)(r + total), *motion = species + total;
    unsigned *flags = (unsigned *)(motion + total);
    memcpy(x, w->x_base, n * sizeof *x);
    memcpy(y, w->y_base, n * sizeof *y);
    memcpy(r, w->radius, n * sizeof *r);
    memcpy(species, w->species, n * sizeof *species);
    memcpy(motion, w->motion, n * sizeof *motion);
    memcpy(flags, w->flags, n * sizeof *flags);
    for (int k = 0; k < g->count; ++k) {
        const size_t i = n + (size_t)k;
        x[i] = g->x[k];
        y[i] = g->y[k];
        r[i] = g->radius[k];
        species[i] = g->species ? g->species[k] : 0;
        motion[i] = g->motion ? g->motion[k] : -1;
        flags[i] = g->flags ? g->flags[k] : 0u;
    }
    *def = w->def;
    def->grains = (SimGrainSet){.count = (int)total,
                                .x = x,
                                .y = y,
                                .radius = r,
                                .species = species,
                                .flags = flags,
                                .motion = motion};
    def->wall_count = w->wall_count;
    def->walls = w->walls;
    return 0;
}

const char *sim_wall_bodies_join_problem(const SimWorld *w, const SimGrainSet *g, int *body,
                                         char *buf, size_t size)
{
    int joins = 0;
    for (int k = 0; k < g->count && g->motion; ++k) {
        const int m = g->motion[k];
        if (m >= -1 || !w->bodies || SIM_GRAIN_BODY(m) >= w->body_count - w->wall_count)
            continue;
        *body = w->wall_count + SIM_GRAIN_BODY(m);
        if (w->bodies[*body].active)
            return "its grains are in place and it moves: grains join a grain body only while "
                   "its group is empty (dormant), all of them at once";
        joins = 1;
    }
    if (!joins)
        return NULL;
    SimWorldDef def;
    void *store;
    if (joined_grains(w, g, &def, &store) != 0)
        return "out of memory checking the grain bodies the new grains join";
    const double r_min = mobile_r_min(&def);
    const char *why = NULL;
    for (int k = w->wall_count; k < w->body_count && !why; ++k)
        if (!w->bodies[k].active && !dormant(&def, k)) {
            *body = k;
            why = body_problem(&def, k, w->dt, r_min, buf, size);
        }
    free(store);
    return why;
}

void sim_wall_bodies_join(SimWorld *w)
{
    if (!w->bodies)
        return;
    SimWorldDef def = w->def;
    def.grains = (SimGrainSet){.count = w->count,
                               .x = w->x_base,
                               .y = w->y_base,
                               .radius = w->radius,
                               .species = w->species,
                               .flags = w->flags,
                               .motion = w->motion};
    for (int k = w->wall_count; k < w->body_count; ++k) {
        if (w->bodies[k].active || dormant(&def, k))
            continue;
        set_rest(w, k, body_shape(&def, k)); /* at rest: where the grains were put */
        w->body_s[k] = w->body_u[k] = w->body_a[k] = w->body_w[k] = 0.0;
        w->bodies[k].active = 1;
    }
}

void sim_wall_bodies_free(SimWorld *w)
{
    free(w->bodies);
    free(w->body_s);
    free(w->body_u);
    free(w->body_a);
    free(w->body_w);
    free(w->body_rest);
    free(w->body_m);
    free(w->wall_damp);
    free(w->body_flip);
}

/* (x, y) turned by the angle whose cosine and sine are c and s about (cx, cy), then moved by
 * (ox, oy). */
static void turn_point(double c, double s, double cx, double cy, double ox, double oy, double *x,
                       double *y)
{
    const double dx = *x - cx, dy = *y - cy;
    *x = cx + (c * dx - s * dy) + ox;
    *y = cy + (s * dx + c * dy) + oy;
}

/* Wall k at offset (ox, oy), turned by its angle about its centre when it turns; returns how
 * far it moved since the last build. */
static double place_wall(SimWorld *w, int k, double ox, double oy)
{
    const SimWall *base = &w->walls_base[k];
    SimWall *now = &w->walls[k];
    const double *rest = &w->body_rest[4 * k];
    if (!w->bodies[k].rotation) {
        now->x0 = base->x0 + ox;
        now->y0 = base->y0 + oy;
        now->x1 = base->x1 + ox;
        now->y1 = base->y1 + oy;
        now->center_x = base->center_x + ox;
        now->center_y = base->center_y + oy;
        return hypot(ox - w->wall_ref_dx[k], oy - w->wall_ref_dy[k]);
    }
    const double a = w->body_a[k], c = cos(a), s = sin(a);
    *now = *base;
    turn_point(c, s, rest[0], rest[1], ox, oy, &now->x0, &now->y0);
    turn_point(c, s, rest[0], rest[1], ox, oy, &now->x1, &now->y1);
    turn_point(c, s, rest[0], rest[1], ox, oy, &now->center_x, &now->center_y);
    now->angle0 = base->angle0 + a;
    now->angle1 = base->angle1 + a;
    const SimWall *ref = &w->walls_ref[k];
    double shift = fmax(hypot(now->x0 - ref->x0, now->y0 - ref->y0),
                        hypot(now->x1 - ref->x1, now->y1 - ref->y1));
    if (now->shape == SIM_WALL_ARC)
        shift = hypot(now->center_x - ref->center_x, now->center_y - ref->center_y) +
                now->radius * fabs(now->angle0 - ref->angle0);
    return shift;
}

/* The grains of the grain bodies at their bodies' poses, with their bodies' velocities. */
static void place_grains(SimWorld *w)
{
    int moved = 0;
    for (int i = w->mobile_count; i < w->count; ++i) {
        const int m = w->motion[i];
        if (m >= -1)
            continue;
        const int k = w->wall_count + SIM_GRAIN_BODY(m); /* SIM_GRAIN_BODY is its own inverse */
        const SimWallBody *b = &w->bodies[k];
        const double *rest = &w->body_rest[4 * k];
        const double s = w->body_s[k], u = w->body_u[k];
        if (b->rotation) {
            const double a = w->body_a[k], c = cos(a), sn = sin(a);
            double x = w->x_base[i], y = w->y_base[i];
            turn_point(c, sn, rest[0], rest[1], s * b->axis_x, s * b->axis_y, &x, &y);
            w->x[i] = x;
            w->y[i] = y;
            const double rx = x - (rest[0] + s * b->axis_x), ry = y - (rest[1] + s * b->axis_y);
            w->vx[i] = u * b->axis_x - w->body_w[k] * ry;
            w->vy[i] = u * b->axis_y + w->body_w[k] * rx;
            w->omega[i] = w->body_w[k];
        } else {
            w->x[i] = w->x_base[i] + s * b->axis_x;
            w->y[i] = w->y_base[i] + s * b->axis_y;
            w->vx[i] = u * b->axis_x;
            w->vy[i] = u * b->axis_y;
        }
        const double dx = w->x[i] - w->x_ref[i], dy = w->y[i] - w->y_ref[i];
        moved |= dx * dx + dy * dy > w->disp_limit2;
    }
    w->need_rebuild |= moved;
}

void sim_wall_body_place(SimWorld *w, int k)
{
    const SimWallBody *b = &w->bodies[k];
    const double *mine = &w->body_m[4 * k]; /* its motion, across the axis */
    const double ox = mine[0] + w->body_s[k] * b->axis_x, oy = mine[1] + w->body_s[k] * b->axis_y;
    const double shift = place_wall(w, k, ox, oy);
    w->wall_vx[k] = mine[2] + w->body_u[k] * b->axis_x;
    w->wall_vy[k] = mine[3] + w->body_u[k] * b->axis_y;
    w->wall_omega[k] = b->rotation ? w->body_w[k] : 0.0;
    /* the surface speed turns about the centre now (walls.h sim_wall_velocity) */
    w->wall_ox[k] = b->rotation ? w->body_rest[4 * k] + ox : ox;
    w->wall_oy[k] = b->rotation ? w->body_rest[4 * k + 1] + oy : oy;
    w->wall_shift = fmax(shift, w->wall_shift);
}

void sim_wall_bodies_place(SimWorld *w)
{
    if (!w->bodies)
        return;
    for (int k = 0; k < w->wall_count; ++k)
        if (w->bodies[k].active)
            sim_wall_body_place(w, k);
    if (w->body_count > w->wall_count)
        place_grains(w);
}

/* The load of grain body k (4 values as a wall's, its touching grains in *touch): the contact
 * forces on its grains summed in frame order, the torque about its centre now. */
static void grain_body_load(const SimWorld *w, int k, double load[4], int *touch)
{
    const SimWallBody *b = &w->bodies[k];
    const double cx = w->body_rest[4 * k] + w->body_s[k] * b->axis_x;
    const double cy = w->body_rest[4 * k + 1] + w->body_s[k] * b->axis_y;
    const int m = SIM_GRAIN_BODY(k - w->wall_count);
    double fx = 0.0, fy = 0.0, torque = 0.0;
    int n = 0;
    for (int i = w->mobile_count; i < w->count; ++i) {
        if (w->motion[i] != m)
            continue;
        fx += w->fx[i];
        fy += w->fy[i];
        torque += (w->x[i] - cx) * w->fy[i] - (w->y[i] - cy) * w->fx[i];
        if (w->rotation)
            torque += w->torque[i];
        n += w->fx[i] != 0.0 || w->fy[i] != 0.0;
    }
    load[0] = fx;
    load[1] = fy;
    load[2] = -(fx * b->axis_x + fy * b->axis_y);
    load[3] = torque;
    *touch = n;
}

/* The speed of responding body k after this step, m/s, from its load (4 values). The servo's
 * gain law u = gain (target - N(u)), where the measured load N depends on u through the normal
 * dashpots of the wall's contacts, N(u) ~ N + c (u - u_old) with c = wall_damp (per length for a
 * stress), u_old the speed the contacts saw: explicit, u from N alone (stable only while
 * gain c < 1); implicit, u solved with the dashpot part at the new speed, the linearised
 * backward Euler step of the stiff part (the linearly implicit Euler method of Hairer & Wanner,
 * Solving Ordinary Differential Equations II, Rosenbrock-type methods): u = gain (target - N +
 * c u_old) / (1 + gain c), then capped. */
static double body_speed(const SimWorld *w, int k, const double *load)
{
    const SimWallBody *b = &w->bodies[k];
    const double along = load[0] * b->axis_x + load[1] * b->axis_y; /* the grains' force */
    if (b->servo) {
        double measured = -along, c = sim_wall_servo_implicit(&w->def, k) ? w->wall_damp[k] : 0.0;
        if (b->servo == 1) {
            const double length = servo_length(w->walls, b, w->body_rest[4 * k + 2]);
            measured /= length;
            c /= length;
        }
        const double u =
            c > 0.0 ? b->gain * (b->target - measured + c * w->body_u[k]) / (1.0 + b->gain * c)
                    : b->gain * (b->target - measured);
        return fmax(-b->max_speed, fmin(b->max_speed, u));
    }
    double f = along + b->force_x * b->axis_x + b->force_y * b->axis_y;
    if (b->gravity)
        f += b->mass * (w->def.gravity_x * b->axis_x + w->def.gravity_y * b->axis_y);
    return w->body_u[k] + w->dt * (f / b->mass);
}

/* A servo's speed flipping between its caps (sim.h SimWallLoad servo_flips): the step from the
 * speed the contacts saw to the new one u goes from one cap to the other. */
static void count_flips(SimWorld *w, int k, double u)
{
    const double cap = w->bodies[k].max_speed, old = w->body_u[k];
    double *f = &w->body_flip[3 * k];
    if (!(fabs(u) == cap && old == -u)) {
        f[0] = 0.0;
        return;
    }
    f[0] += 1.0;
    if (f[0] <= SIM_SERVO_FLIP_STEPS)
        return;
    f[1] += f[0] == SIM_SERVO_FLIP_STEPS + 1 ? f[0] : 1.0; /* the whole run, once it counts */
    if (isnan(f[2])) /* the end of this step: the time sim_world_step reports after it */
        f[2] = w->def.start_time + (double)(w->step + 1) * w->dt;
}

void sim_wall_bodies_step(SimWorld *w)
{
    if (!w->bodies)
        return;
    for (int k = 0; k < w->body_count; ++k) {
        if (!w->bodies[k].active)
            continue;
        double group[4];
        int touch;
        if (k >= w->wall_count)
            grain_body_load(w, k, group, &touch);
        const double *load = k < w->wall_count ? &w->wall_load[4 * k] : group;
        const double u = body_speed(w, k, load);
        if (w->bodies[k].servo)
            count_flips(w, k, u);
        w->body_u[k] = u;
        w->body_s[k] += w->dt * w->body_u[k];
        if (w->bodies[k].rotation) { /* I domega/dt = T, then the angle: as the translation */
            w->body_w[k] += w->dt * (load[3] / w->body_rest[4 * k + 3]);
            w->body_a[k] += w->dt * w->body_w[k];
        }
    }
    sim_wall_bodies_place(w);
}

/* Grain body k's load (sim_world_wall_load). */
static void grain_body_view(const SimWorld *w, int k, SimWallLoad *load)
{
    const SimWallBody *b = &w->bodies[k];
    double l[4];
    grain_body_load(w, k, l, &load->contacts);
    load->fx = l[0];
    load->fy = l[1];
    load->normal = l[2];
    load->torque = l[3];
    load->tangential = l[1] * b->axis_x - l[0] * b->axis_y;
    load->length = w->body_rest[4 * k + 2];
    load->x = w->body_rest[4 * k] + w->body_s[k] * b->axis_x;
    load->y = w->body_rest[4 * k + 1] + w->body_s[k] * b->axis_y;
}

int sim_world_wall_load(const SimWorld *w, int wall, SimWallLoad *load)
{
    if (!w || wall < 0 || wall >= (w->bodies ? w->body_count : w->wall_count) || !load)
        return -1;
    memset(load, 0, sizeof *load);
    if (wall >= w->wall_count) {
        grain_body_view(w, wall, load);
    } else {
        const SimWall *now = &w->walls[wall];
        const double *l = &w->wall_load[4 * wall];
        load->fx = l[0];
        load->fy = l[1];
        load->normal = l[2];
        load->torque = l[3];
        load->length = wall_length(now);
        load->contacts = w->wall_touch[wall];
        if (now->shape == SIM_WALL_ARC) {
            load->x = now->center_x;
            load->y = now->center_y;
            load->tangential = now->radius > 0.0 ? l[3] / now->radius : 0.0;
        } else {
            load->x = 0.5 * (now->x0 + now->x1);
            load->y = 0.5 * (now->y0 + now->y1);
            const double len = load->length;
            load->tangential =
                len > 0.0 ? (l[0] * (now->x1 - now->x0) + l[1] * (now->y1 - now->y0)) / len : 0.0;
        }
    }
    if (w->bodies && w->bodies[wall].active) {
        if (w->bodies[wall].servo == 1) /* the length its stress target is taken over */
            load->length = servo_length(w->walls, &w->bodies[wall], w->body_rest[4 * wall + 2]);
        load->offset = w->body_s[wall];
        load->speed = w->body_u[wall];
        load->servo_flips = (long)w->body_flip[3 * wall + 1];
        load->servo_flip_time = w->body_flip[3 * wall + 2];
    } else {
        load->servo_flip_time = NAN;
    }
    return 0;
}

/* ------------------------------------------------------------------ state file footer */

/* The footer: per body its offset, speed, angle and angular speed (body_count each), its
 * motion's offset and velocity across its axis (body_m, 4 each), its rest geometry (body_rest,
 * 4 each) and its servo's flip counters (body_flip, 3 each: internal.h), then the body count
 * (int32) and this tag, at the very end of the file, written only when a body responds. The
 * first version held the walls' offsets and speeds only, the second the first four arrays (both
 * read as such: the flip counters then start afresh). */
static const char body_tag[8] = "WBODY-3\n";

/* The version of footer tag `tag` (1 to 3), or 0. */
static int footer_version(const char tag[8])
{
    static const char *const tags[] = {"WBODY-1\n", "WBODY-2\n", body_tag};
    for (int v = 0; v < 3; ++v)
        if (memcmp(tag, tags[v], sizeof body_tag) == 0)
            return v + 1;
    return 0;
}

/* Doubles per body in a footer of version v. */
static size_t footer_doubles(int version)
{
    return version == 1 ? 2 : version == 2 ? 4 : 15;
}

int sim_wall_bodies_write(FILE *f, const SimWorld *w)
{
    if (!w->bodies)
        return 0;
    const size_t n = (size_t)w->body_count;
    const int32_t count = w->body_count;
    const double *arrays[] = {w->body_s, w->body_u,    w->body_a,   w->body_w,
                              w->body_m, w->body_rest, w->body_flip};
    const size_t sizes[] = {n, n, n, n, 4 * n, 4 * n, 3 * n};
    int ok = 1;
    for (size_t a = 0; a < sizeof arrays / sizeof arrays[0]; ++a)
        ok = ok && fwrite(arrays[a], sizeof(double), sizes[a], f) == sizes[a];
    return ok && fwrite(&count, sizeof count, 1, f) == 1 &&
                   fwrite(body_tag, sizeof body_tag, 1, f) == 1
               ? 0
               : -1;
}

/* Body k from footer `saved` of version v over n bodies (the arrays one after another, as
 * written): its offset, speed, angle and angular speed, and from a third version its motion's
 * offset and velocity, its rest geometry and its flip counters. A body with a value that is not
 * finite stays as created (at rest where it is defined); the flip time is NaN until a flip. */
static void footer_body(SimWorld *w, const double *saved, size_t n, int version, size_t k)
{
    int finite = 1;
    for (size_t a = 0; a < 4 && a < footer_doubles(version); ++a) /* offset, speed, angle, ... */
        finite &= isfinite(saved[a * n + k]) != 0;
    for (size_t b = 0; version > 2 && b < 2; ++b) /* body_m, then body_rest: 4 a body */
        for (size_t j = 0; j < 4; ++j)
            finite &= isfinite(saved[(4 + 4 * b) * n + 4 * k + j]) != 0;
    if (!finite)
        return;
    w->body_s[k] = saved[k];
    w->body_u[k] = saved[n + k];
    w->body_a[k] = version > 1 ? saved[2 * n + k] : 0.0;
    w->body_w[k] = version > 1 ? saved[3 * n + k] : 0.0;
    if (version > 2) {
        memcpy(&w->body_m[4 * k], &saved[4 * n + 4 * k], 4 * sizeof(double));
        memcpy(&w->body_rest[4 * k], &saved[8 * n + 4 * k], 4 * sizeof(double));
        memcpy(&w->body_flip[3 * k], &saved[12 * n + 3 * k], 3 * sizeof(double));
    }
}

void sim_wall_bodies_read(SimWorld *w, FILE *f)
{
    if (!w->bodies)
        return;
    char tag[8];
    int32_t count = -1;
    const long tail = (long)(sizeof count + sizeof tag);
    if (fseek(f, -tail, SEEK_END) != 0 || fread(&count, sizeof count, 1, f) != 1 ||
        fread(tag, sizeof tag, 1, f) != 1)
        return;
    const int version = footer_version(tag);
    if (!version || count != (version == 1 ? w->wall_count : w->body_count))
        return; /* none saved: the bodies start at rest where they are defined */
    const size_t n = (size_t)count, total = footer_doubles(version) * n;
    double *saved = malloc((total > 0 ? total : 1) * sizeof *saved);
    if (saved && fseek(f, -(tail + (long)(total * sizeof(double))), SEEK_END) == 0 &&
        fread(saved, sizeof(double), total, f) == total)
        for (size_t k = 0; k < n; ++k)
            footer_body(w, saved, n, version, k);
    free(saved);
    /* Every body where the saved run left it: its own offset and its motion's (body_m), so the
     * shift since the last list build it counts is the one the saved run counted last (the
     * list's bookkeeping continues; a motion's clock set afterwards, sim_world_set_motion, moves
     * it by that clock). A file of an older version has no body_m: a wall that follows a motion
     * is placed by the motion's pose under the clock the world was created with until its clock
     * is set, and may then rebuild its list earlier than the saved run did. */
    sim_wall_bodies_place(w);
}
