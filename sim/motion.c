/* SPDX-License-Identifier: MIT */
/* motion.c: prescribed motions of walls and fixed grains (effect vibration): sinusoidal
 * translation, constant velocity, rotation about a point, compositions of these, each on a
 * schedule (start, ramp, stop) and a clock that a stage may start and stop
 * (sim_world_set_motion). Every motion is a rigid pose p = R(theta) p_0 + T applied to the
 * positions as defined, so a rotating wall's points follow the rotation to round-off and
 * nothing drifts over a long run. */
#include "internal.h"
#include "walls.h"

#include <math.h>

/* Progress of a ramped schedule: the distance factor D(s) = integral of the speed factor, which
 * grows linearly from 0 to 1 over `ramp` seconds; *rate = D'(s). */
static double ramp_progress(double s, double ramp, double *rate)
{
    if (ramp > 0.0 && s < ramp) {
        *rate = s / ramp;
        return 0.5 * s * s / ramp;
    }
    *rate = 1.0;
    return ramp > 0.0 ? s - 0.5 * ramp : s;
}

/* B after A (A applied first): theta = theta_A + theta_B, T = R_B T_A + T_B, and the velocity of
 * the point now at q, V + Omega z x (q - T), from d/dt of R_B (R_A p + T_A) + T_B. */
static SimPose pose_then(SimPose a, SimPose b)
{
    const double c = cos(b.angle), s = sin(b.angle);
    const double rx = c * a.x - s * a.y, ry = s * a.x + c * a.y;       /* R_B T_A */
    const double rvx = c * a.vx - s * a.vy, rvy = s * a.vx + c * a.vy; /* R_B V_A */
    return (SimPose){.angle = a.angle + b.angle,
                     .x = rx + b.x,
                     .y = ry + b.y,
                     .omega = a.omega + b.omega,
                     .vx = rvx + b.vx - b.omega * ry,
                     .vy = rvy + b.vy + b.omega * rx};
}

/* The pose of one motion at schedule time s >= 0 (time since its start), moving. */
static SimPose pose_running(const SimMotion *motions, int index, double s)
{
    const SimMotion *m = &motions[index];
    SimPose p = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    double rate;
    switch (m->kind) {
    case SIM_MOTION_SINUSOIDAL: {
        /* amplitude ramped linearly: a(s) A sin(2 pi f s + phase) */
        const double a = m->ramp > 0.0 && s < m->ramp ? s / m->ramp : 1.0;
        const double phase = 2.0 * SIM_PI * m->frequency * s + m->phase;
        double speed = m->amplitude * 2.0 * SIM_PI * m->frequency * cos(phase);
        double offset = m->amplitude * sin(phase);
        if (a < 1.0) {
            speed = a * speed + offset / m->ramp;
            offset *= a;
        }
        p.x = offset * m->direction_x;
        p.y = offset * m->direction_y;
        p.vx = speed * m->direction_x;
        p.vy = speed * m->direction_y;
        break;
    }
    case SIM_MOTION_VELOCITY: {
        const double d = ramp_progress(s, m->ramp, &rate);
        p.x = m->velocity_x * d;
        p.y = m->velocity_y * d;
        p.vx = m->velocity_x * rate;
        p.vy = m->velocity_y * rate;
        break;
    }
    case SIM_MOTION_ROTATION: {
        /* about c: p = R(theta)(p_0 - c) + c, so T = c - R c and V = Omega z x (T - c) */
        p.angle = m->angular_velocity * ramp_progress(s, m->ramp, &rate);
        p.omega = m->angular_velocity * rate;
        const double c = cos(p.angle), sn = sin(p.angle);
        p.x = m->center_x - (c * m->center_x - sn * m->center_y);
        p.y = m->center_y - (sn * m->center_x + c * m->center_y);
        p.vx = -p.omega * (p.y - m->center_y);
        p.vy = p.omega * (p.x - m->center_x);
        break;
    }
    case SIM_MOTION_COMPOSE:
        for (int k = 0; k < m->part_count; ++k)
            if (m->parts[k] >= 0 && m->parts[k] < index)
                p = pose_then(p, sim_motion_pose(motions, m->parts[k], s));
        break;
    }
    return p;
}

SimPose sim_motion_pose(const SimMotion *motions, int index, double tau)
{
    const SimMotion *m = &motions[index];
    SimPose rest = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    if (!(tau >= m->start))
        return rest; /* not started (tau = -inf: never enabled) */
    const int stopped = m->stop > 0.0 && tau >= m->stop;
    SimPose p = pose_running(motions, index, (stopped ? m->stop : tau) - m->start);
    if (stopped)
        p.omega = p.vx = p.vy = 0.0;
    return p;
}

/* The pose of motion m at world time t under the world's clock (motion_on, motion_off). */
static SimPose world_pose(const SimWorld *w, int m, double t)
{
    const double on = w->motion_on[m], off = w->motion_off[m];
    if (t >= off) {
        SimPose p = sim_motion_pose(w->def.motions, m, off - on);
        p.omega = p.vx = p.vy = 0.0;
        return p;
    }
    return sim_motion_pose(w->def.motions, m, t - on);
}

/* 1 when a motion can turn what it moves (rotation, or a composition with one). */
static int motion_turns(const SimMotion *motions, int index)
{
    const SimMotion *m = &motions[index];
    if (m->kind == SIM_MOTION_ROTATION)
        return 1;
    if (m->kind == SIM_MOTION_COMPOSE)
        for (int k = 0; k < m->part_count; ++k)
            if (m->parts[k] >= 0 && m->parts[k] < index && motion_turns(motions, m->parts[k]))
                return 1;
    return 0;
}

/* (x, y) under the pose; a pure translation adds the offset (the sinusoidal shaker's bits). */
static void pose_apply(const SimPose *p, double x, double y, double *ox, double *oy)
{
    if (p->angle == 0.0) {
        *ox = x + p->x;
        *oy = y + p->y;
        return;
    }
    const double c = cos(p->angle), s = sin(p->angle);
    *ox = c * x - s * y + p->x;
    *oy = s * x + c * y + p->y;
}

/* x wrapped into a periodic domain [x0, x0 + span). */
static double wrap_x(double x, double x0, double span)
{
    if (x >= x0 && x < x0 + span)
        return x;
    double wrapped = x - span * floor((x - x0) / span);
    return wrapped < x0 + span ? wrapped : x0;
}

/* `only` >= 0: just what motion `only` moves (-1: every motion's grains and walls). */
static void move_grains(SimWorld *w, const SimPose *pose, const int *turns, int only)
{
    int moved = 0;
    const int periodic = (w->effects & SIM_EFFECT_PERIODIC_X) != 0;
    const double x0 = w->def.domain_x0, span = w->def.domain_x1 - w->def.domain_x0;
    for (int i = w->mobile_count; i < w->count; ++i) {
        const int m = w->motion[i];
        if (m < 0 || (only >= 0 && m != only))
            continue;
        const SimPose *p = &pose[m];
        pose_apply(p, w->x_base[i], w->y_base[i], &w->x[i], &w->y[i]);
        /* a rough wall sliding along a periodic x stays in the domain (a shaker's grains are
         * left where they were: they never travel) */
        if (periodic && w->def.motions[m].kind != SIM_MOTION_SINUSOIDAL)
            w->x[i] = wrap_x(w->x[i], x0, span);
        w->vx[i] = p->vx;
        w->vy[i] = p->vy;
        if (turns[m]) { /* a fixed grain turning with its motion carries its contacts along */
            w->vx[i] -= p->omega * (w->y[i] - p->y);
            w->vy[i] += p->omega * (w->x[i] - p->x);
            w->omega[i] = p->omega;
        }
        double dx = w->x[i] - w->x_ref[i], dy = w->y[i] - w->y_ref[i];
        moved |= dx * dx + dy * dy > w->disp_limit2;
    }
    w->need_rebuild |= moved;
}

/* How far wall k's shape has moved since the last build: a translation's offset change (as
 * the list build recorded it), the end points of a turned segment, the centre (and the ends)
 * of a turned arc. */
static double wall_moved(const SimWorld *w, int k, const SimPose *p, int turns)
{
    const SimWall *now = &w->walls[k], *ref = &w->walls_ref[k];
    if (!turns)
        return hypot(p->x - w->wall_ref_dx[k], p->y - w->wall_ref_dy[k]);
    if (now->shape == SIM_WALL_ARC) {
        double shift = hypot(now->center_x - ref->center_x, now->center_y - ref->center_y);
        if (now->angle1 - now->angle0 < 2.0 * SIM_PI)
            shift += now->radius * fabs(now->angle0 - ref->angle0);
        return shift;
    }
    return fmax(hypot(now->x0 - ref->x0, now->y0 - ref->y0),
                hypot(now->x1 - ref->x1, now->y1 - ref->y1));
}

static void move_walls(SimWorld *w, const SimPose *pose, const int *turns, int only)
{
    for (int k = 0; k < w->wall_count; ++k) {
        const int m = w->walls_base[k].motion;
        if (m < 0 || (only >= 0 && m != only))
            continue;
        const SimPose *p = &pose[m];
        if (w->bodies && w->bodies[k].active) { /* a translation across its axis (wall_body.c) */
            double *mine = &w->body_m[4 * k];
            mine[0] = p->x;
            mine[1] = p->y;
            mine[2] = p->vx;
            mine[3] = p->vy;
            sim_wall_body_place(w, k);
            continue;
        }
        const SimWall *base = &w->walls_base[k];
        SimWall *now = &w->walls[k];
        pose_apply(p, base->x0, base->y0, &now->x0, &now->y0);
        pose_apply(p, base->x1, base->y1, &now->x1, &now->y1);
        if (base->shape == SIM_WALL_ARC) {
            pose_apply(p, base->center_x, base->center_y, &now->center_x, &now->center_y);
            now->angle0 = base->angle0 + p->angle;
            now->angle1 = base->angle1 + p->angle;
        }
        w->wall_vx[k] = p->vx;
        w->wall_vy[k] = p->vy;
        w->wall_omega[k] = p->omega;
        w->wall_ox[k] = p->x;
        w->wall_oy[k] = p->y;
        const double shift = wall_moved(w, k, p, turns[m]);
        w->wall_shift = shift > w->wall_shift ? shift : w->wall_shift;
    }
}

static void move_motions(SimWorld *w, double t, int only)
{
    SimPose pose[SIM_MAX_MOTIONS];
    int turns[SIM_MAX_MOTIONS];
    for (int m = 0; m < w->def.motion_count; ++m) {
        pose[m] = world_pose(w, m, t);
        turns[m] = motion_turns(w->def.motions, m);
    }
    move_grains(w, pose, turns, only);
    move_walls(w, pose, turns, only);
}

void sim_motion_move(SimWorld *w, double t)
{
    move_motions(w, t, -1);
}

void sim_motion_mark_build(SimWorld *w)
{
    for (int k = 0; k < w->wall_count; ++k) {
        w->wall_ref_dx[k] = w->walls[k].x0 - w->walls_base[k].x0;
        w->wall_ref_dy[k] = w->walls[k].y0 - w->walls_base[k].y0;
        w->walls_ref[k] = w->walls[k];
    }
}

void sim_world_set_motion(SimWorld *w, int motion, double on, double off)
{
    if (!w || motion < 0 || motion >= w->def.motion_count)
        return;
    w->motion_on[motion] = on;
    w->motion_off[motion] = off;
    /* The poses and velocities of what this motion moves follow its new clock now; the others
     * stay where they are. A pose depends on its own motion's clock only (a composition's parts
     * run on the composition's clock), and moving the others here would place them by clocks
     * not yet set: a world resumed from a state, whose walls sit where the saved run left them
     * while its clocks are still the defaults until each is set, would count those transient
     * poses in the walls' shift since the last list build and rebuild earlier than the run it
     * continues. */
    if (w->effects & SIM_EFFECT_VIBRATION)
        move_motions(w, w->time, motion);
}

/* Speed bound of one motion for points within `size` of the origin, m/s (compositions: the
 * sum of their parts'). */
static double speed_bound(const SimMotion *motions, int index, double size)
{
    const SimMotion *mo = &motions[index];
    switch (mo->kind) {
    case SIM_MOTION_VELOCITY:
        return hypot(mo->velocity_x, mo->velocity_y);
    case SIM_MOTION_ROTATION:
        return fabs(mo->angular_velocity) * (size + hypot(mo->center_x, mo->center_y));
    case SIM_MOTION_COMPOSE: {
        double v = 0.0;
        for (int k = 0; k < mo->part_count; ++k)
            if (mo->parts[k] >= 0 && mo->parts[k] < index)
                v += speed_bound(motions, mo->parts[k], size);
        return v;
    }
    case SIM_MOTION_SINUSOIDAL:
    default:
        return fabs(mo->amplitude) * 2.0 * SIM_PI * mo->frequency;
    }
}

double sim_motion_speed_bound(const SimWorldDef *def, double size)
{
    double vm = 0.0;
    for (int m = 0; m < def->motion_count; ++m)
        vm = fmax(vm, speed_bound(def->motions, m, size));
    return vm;
}

const char *sim_motion_problem(const SimWorldDef *def, int index)
{
    const SimMotion *m = &def->motions[index];
    if (!(isfinite(m->start) && m->start >= 0.0 && isfinite(m->ramp) && m->ramp >= 0.0 &&
          isfinite(m->stop) && m->stop >= 0.0))
        return "its schedule needs start >= 0, ramp >= 0, stop >= 0 (finite)";
    if (m->stop > 0.0 && !(m->stop > m->start))
        return "it stops before it starts (stop must be > start)";
    switch (m->kind) {
    case SIM_MOTION_SINUSOIDAL:
        if (!(isfinite(m->amplitude) && m->frequency >= 0.0 && isfinite(m->frequency) &&
              isfinite(m->phase) && isfinite(m->direction_x) && isfinite(m->direction_y)))
            return "its amplitude, frequency, phase or direction is invalid";
        return NULL;
    case SIM_MOTION_VELOCITY:
        return isfinite(m->velocity_x) && isfinite(m->velocity_y) ? NULL
                                                                  : "its velocity is not finite";
    case SIM_MOTION_ROTATION:
        return isfinite(m->center_x) && isfinite(m->center_y) && isfinite(m->angular_velocity)
                   ? NULL
                   : "its centre or angular velocity is not finite";
    case SIM_MOTION_COMPOSE:
        if (m->part_count < 1 || m->part_count > SIM_MOTION_MAX_PARTS)
            return "a composition needs 1 to 4 parts";
        if (m->ramp > 0.0)
            return "a composition has no ramp of its own (ramp its parts)";
        for (int k = 0; k < m->part_count; ++k)
            if (m->parts[k] < 0 || m->parts[k] >= index)
                return "a composition's parts must be motions defined before it";
        return NULL;
    }
    return "unknown motion kind";
}
