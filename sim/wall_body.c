/* SPDX-License-Identifier: MIT */
/* wall_body.c: walls that respond to the grains (sim.h SimWallBody): free pistons of a given
 * mass and servo-controlled walls, each a rigid translation along its axis (plus, with a motion,
 * the motion's translation across it), and the load the
 * grains put on every wall (SimWallLoad). The loads are summed by the wall pass
 * (sim/isa/contact_pass.c) in the wall list's order, serially: the same bits for any thread
 * count. The bodies move once per step, after the step's last force evaluation (symplectic
 * Euler: the speed from the force, then the offset from the new speed). Their offsets and speeds
 * are kept at the end of a state file (docs/state-format.md, "Responding walls"). */
#include "internal.h"
#include "walls.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Length of a wall: a segment's, an arc's span (a full circle at most), m. */
static double wall_length(const SimWall *w)
{
    if (w->shape == SIM_WALL_ARC)
        return w->radius * fmin(w->angle1 - w->angle0, 2.0 * SIM_PI);
    return hypot(w->x1 - w->x0, w->y1 - w->y0);
}

/* The length responding wall k's stress target is taken over (SimWallBody length_kind), m, with
 * the walls where they are (`walls`: now, or as defined before a run): its own length, a given
 * one, or the distance across its axis t = (-a_y, a_x) between the two walls it names, |(p_1 -
 * p_0).t| for a point p of each (segments parallel to the axis). */
static double servo_length(const SimWall *walls, int k, const SimWallBody *b)
{
    if (b->length_kind == 1)
        return b->length;
    if (b->length_kind == 2) {
        const SimWall *a = &walls[b->between[0]], *c = &walls[b->between[1]];
        return fabs((c->y0 - a->y0) * b->axis_x - (c->x0 - a->x0) * b->axis_y);
    }
    return wall_length(&walls[k]);
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

double sim_wall_servo_time(const SimWorldDef *def, int wall)
{
    if (!def->wall_bodies || wall < 0 || wall >= def->wall_count)
        return INFINITY;
    const SimWallBody *b = &def->wall_bodies[wall];
    if (!b->active || !b->servo)
        return INFINITY;
    double d;
    const double k = wall_stiffness(def, def->walls[wall].species, &d, NULL);
    /* stress: a displacement u changes the stress by k u / d; force: by k u length / d */
    double per_speed = k / d * (b->servo == 2 ? wall_length(&def->walls[wall]) : 1.0);
    return isfinite(d) && per_speed > 0.0 ? 1.0 / (b->gain * per_speed) : (double)INFINITY;
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
    if (!def->wall_bodies || wall < 0 || wall >= def->wall_count)
        return 0.0;
    const SimWallBody *b = &def->wall_bodies[wall];
    if (!b->active || !b->servo)
        return 0.0;
    double d, gamma;
    wall_stiffness(def, def->walls[wall].species, &d, &gamma);
    if (!isfinite(d))
        return 0.0;
    const double length = servo_length(def->walls, wall, b);
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
static const char *length_problem(const SimWorldDef *def, int k, char *buf, size_t size)
{
    const SimWallBody *b = &def->wall_bodies[k];
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
    if (!(servo_length(def->walls, k, b) > 0.0))
        return "its servo's `between` walls are at no distance from each other";
    return NULL;
}

/* The problem of one responding wall k, written into buf; NULL when it is sound. */
static const char *body_problem(const SimWorldDef *def, int k, double dt, double r_min, char *buf,
                                size_t size)
{
    const SimWallBody *b = &def->wall_bodies[k];
    const double norm = hypot(b->axis_x, b->axis_y);
    if (!(fabs(norm - 1.0) < 1e-9))
        return "the axis of a responding wall must be a unit vector";
    const int motion = def->walls[k].motion;
    const char *across = motion >= 0 && motion < def->motion_count
                             ? motion_across(def->motions, motion, b->axis_x, b->axis_y)
                             : NULL;
    if (across)
        return across;
    const char *length = length_problem(def, k, buf, size);
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

const char *sim_wall_bodies_problem(const SimWorldDef *def, double dt, int *wall, char *buf,
                                    size_t size)
{
    if (!def->wall_bodies)
        return NULL;
    double r_min = INFINITY;
    for (int i = 0; i < def->grains.count; ++i)
        if (!(def->grains.flags && (def->grains.flags[i] & SIM_GRAIN_FIXED)))
            r_min = fmin(r_min, def->grains.radius[i]);
    for (int k = 0; k < def->wall_count; ++k) {
        if (!def->wall_bodies[k].active)
            continue;
        const char *why = body_problem(def, k, dt, r_min, buf, size);
        if (why) {
            *wall = k;
            return why;
        }
    }
    return NULL;
}

void sim_wall_body_place(SimWorld *w, int k)
{
    const SimWallBody *b = &w->bodies[k];
    const double *mine = &w->body_m[4 * k]; /* its motion, across the axis */
    const double ox = mine[0] + w->body_s[k] * b->axis_x, oy = mine[1] + w->body_s[k] * b->axis_y;
    const SimWall *base = &w->walls_base[k];
    SimWall *now = &w->walls[k];
    now->x0 = base->x0 + ox;
    now->y0 = base->y0 + oy;
    now->x1 = base->x1 + ox;
    now->y1 = base->y1 + oy;
    now->center_x = base->center_x + ox;
    now->center_y = base->center_y + oy;
    w->wall_vx[k] = mine[2] + w->body_u[k] * b->axis_x;
    w->wall_vy[k] = mine[3] + w->body_u[k] * b->axis_y;
    w->wall_ox[k] = ox;
    w->wall_oy[k] = oy;
    const double shift = hypot(ox - w->wall_ref_dx[k], oy - w->wall_ref_dy[k]);
    w->wall_shift = fmax(shift, w->wall_shift);
}

void sim_wall_bodies_place(SimWorld *w)
{
    if (!w->bodies)
        return;
    for (int k = 0; k < w->wall_count; ++k)
        if (w->bodies[k].active)
            sim_wall_body_place(w, k);
}

/* The speed of responding wall k after this step, m/s. */
static double body_speed(const SimWorld *w, int k)
{
    const SimWallBody *b = &w->bodies[k];
    const double *load = &w->wall_load[4 * k];
    const double along = load[0] * b->axis_x + load[1] * b->axis_y; /* the grains' force */
    if (b->servo) {
        double measured = -along;
        if (b->servo == 1)
            measured /= servo_length(w->walls, k, b);
        const double u = b->gain * (b->target - measured);
        return fmax(-b->max_speed, fmin(b->max_speed, u));
    }
    double f = along + b->force_x * b->axis_x + b->force_y * b->axis_y;
    if (b->gravity)
        f += b->mass * (w->def.gravity_x * b->axis_x + w->def.gravity_y * b->axis_y);
    return w->body_u[k] + w->dt * (f / b->mass);
}

void sim_wall_bodies_step(SimWorld *w)
{
    if (!w->bodies)
        return;
    for (int k = 0; k < w->wall_count; ++k) {
        if (!w->bodies[k].active)
            continue;
        w->body_u[k] = body_speed(w, k);
        w->body_s[k] += w->dt * w->body_u[k];
    }
    sim_wall_bodies_place(w);
}

int sim_world_wall_load(const SimWorld *w, int wall, SimWallLoad *load)
{
    if (!w || wall < 0 || wall >= w->wall_count || !load)
        return -1;
    const SimWall *now = &w->walls[wall];
    const double *l = &w->wall_load[4 * wall];
    memset(load, 0, sizeof *load);
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
    if (w->bodies && w->bodies[wall].active) {
        if (w->bodies[wall].servo == 1) /* the length its stress target is taken over */
            load->length = servo_length(w->walls, wall, &w->bodies[wall]);
        load->offset = w->body_s[wall];
        load->speed = w->body_u[wall];
    }
    return 0;
}

/* ------------------------------------------------------------------ state file footer */

/* The footer: the offsets and speeds of every wall (wall_count each), then the wall count
 * (int32) and this tag, at the very end of the file, written only when a wall responds. */
static const char body_tag[8] = "WBODY-1\n";

int sim_wall_bodies_write(FILE *f, const SimWorld *w)
{
    if (!w->bodies)
        return 0;
    const size_t n = (size_t)w->wall_count;
    const int32_t count = w->wall_count;
    return fwrite(w->body_s, sizeof(double), n, f) == n &&
                   fwrite(w->body_u, sizeof(double), n, f) == n &&
                   fwrite(&count, sizeof count, 1, f) == 1 &&
                   fwrite(body_tag, sizeof body_tag, 1, f) == 1
               ? 0
               : -1;
}

void sim_wall_bodies_read(SimWorld *w, FILE *f)
{
    if (!w->bodies)
        return;
    char tag[8];
    int32_t count = -1;
    const long tail = (long)(sizeof count + sizeof tag);
    if (fseek(f, -tail, SEEK_END) != 0 || fread(&count, sizeof count, 1, f) != 1 ||
        fread(tag, sizeof tag, 1, f) != 1 || memcmp(tag, body_tag, sizeof tag) != 0 ||
        count != w->wall_count)
        return; /* none saved: the walls start at rest where they are defined */
    const size_t n = (size_t)count;
    if (fseek(f, -(tail + (long)(2 * n * sizeof(double))), SEEK_END) != 0)
        return;
    double *s = w->body_s, *u = w->body_u;
    const int read = fread(s, sizeof(double), n, f) == n && fread(u, sizeof(double), n, f) == n;
    for (size_t k = 0; k < n; ++k)
        if (!read || !isfinite(s[k]) || !isfinite(u[k]))
            s[k] = u[k] = 0.0;
    /* The list's wall shift is the saved one (an exact continuation restored it; otherwise the
     * world is rebuilt): a wall that also follows a motion is placed here with its motion's pose
     * under the clock the world was created with, which the stage's clock then replaces
     * (sim_world_set_motion), and that interim place must not ask for a list build. */
    const double shift = w->wall_shift;
    sim_wall_bodies_place(w);
    w->wall_shift = shift;
}
