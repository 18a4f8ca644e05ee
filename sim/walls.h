/* SPDX-License-Identifier: MIT */
/* walls.h: wall geometry shared by the wall contact pass (contact.c), the wall list build
 * (neighbour.c) and the checks (world.c): segments and circular arcs (sim.h SimWall), and the
 * surface velocity of a moving wall. Private to sim/. */
#ifndef SIM_WALLS_H
#define SIM_WALLS_H

#include "internal.h"

#include <math.h>

/* Closest point of wall segment w to (px, py). */
static inline void sim_segment_closest(const SimWall *w, double px, double py, double *cx,
                                       double *cy)
{
    double ex = w->x1 - w->x0, ey = w->y1 - w->y0;
    double len2 = ex * ex + ey * ey;
    double t = len2 > 0.0 ? ((px - w->x0) * ex + (py - w->y0) * ey) / len2 : 0.0;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    *cx = w->x0 + t * ex;
    *cy = w->y0 + t * ey;
}

/* 1 when the direction (rx, ry) from an arc's centre lies within its span. */
static inline int sim_arc_covers(const SimWall *w, double rx, double ry)
{
    const double span = w->angle1 - w->angle0;
    if (span >= 2.0 * SIM_PI)
        return 1;
    double phi = atan2(ry, rx) - w->angle0;
    phi -= 2.0 * SIM_PI * floor(phi / (2.0 * SIM_PI));
    return phi <= span;
}

/* Arc contact geometry: n (unit) from the grain centre towards the wall, and the distance d
 * along it. On a one-sided arc (SIM_WALL_INSIDE / OUTSIDE) d is signed: a centre pushed past
 * the arc has d < 0 and is still pushed back to its side (no tunnelling); beyond one radius
 * past it (r: the grain's radius) it is on the far side, out of reach (HUGE_VAL); beside the
 * span, the grain meets the ends as points. */
static inline double sim_arc_geometry(const SimWall *w, double px, double py, double r, double *nx,
                                      double *ny)
{
    const double rx = px - w->center_x, ry = py - w->center_y;
    const double rho = sqrt(rx * rx + ry * ry);
    if (sim_arc_covers(w, rx, ry)) {
        const double ux = rho > 0.0 ? rx / rho : 0.0, uy = rho > 0.0 ? ry / rho : -1.0;
        const double inside = w->radius - rho; /* > 0 within the circle */
        const int in = w->side == SIM_WALL_INSIDE || (w->side == SIM_WALL_BOTH && inside >= 0.0);
        const double d = in ? inside : -inside;
        *nx = in ? ux : -ux;
        *ny = in ? uy : -uy;
        if (!(d >= -r)) /* on the far side of a one-sided arc: not in touch */
            return HUGE_VAL;
        return d;
    }
    /* the nearer end point */
    double ex0 = w->center_x + w->radius * cos(w->angle0) - px;
    double ey0 = w->center_y + w->radius * sin(w->angle0) - py;
    double ex1 = w->center_x + w->radius * cos(w->angle1) - px;
    double ey1 = w->center_y + w->radius * sin(w->angle1) - py;
    double d0 = sqrt(ex0 * ex0 + ey0 * ey0), d1 = sqrt(ex1 * ex1 + ey1 * ey1);
    double ex = d0 <= d1 ? ex0 : ex1, ey = d0 <= d1 ? ey0 : ey1, d = d0 <= d1 ? d0 : d1;
    *nx = d > 0.0 ? ex / d : 0.0;
    *ny = d > 0.0 ? ey / d : -1.0;
    return d;
}

/* Wall contact geometry: n from the grain centre to the closest point. Returns the distance
 * (signed on one-sided arcs, see sim_arc_geometry). */
static inline double sim_wall_geometry(const SimWall *w, double px, double py, double r, double *nx,
                                       double *ny)
{
    if (w->shape == SIM_WALL_ARC)
        return sim_arc_geometry(w, px, py, r, nx, ny);
    double cx, cy;
    sim_segment_closest(w, px, py, &cx, &cy);
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

/* A grain of radius r at (px, py) is a wall-list candidate when this is below (r + skin)^2:
 * the squared distance of a segment, the squared contact distance of an arc (negative
 * distances, centres past a one-sided arc, count as 0). */
static inline double sim_wall_distance2(const SimWall *w, double px, double py, double r)
{
    if (w->shape == SIM_WALL_ARC) {
        double nx, ny, d = sim_arc_geometry(w, px, py, r, &nx, &ny);
        return d > 0.0 ? d * d : 0.0;
    }
    double cx, cy;
    sim_segment_closest(w, px, py, &cx, &cy);
    double dx = cx - px, dy = cy - py;
    return dx * dx + dy * dy;
}

/* Contact distance for the start-overlap check and the reach test (signed on one-sided arcs). */
static inline double sim_wall_distance(const SimWall *w, double px, double py, double r)
{
    if (w->shape == SIM_WALL_ARC) {
        double nx, ny;
        return sim_arc_geometry(w, px, py, r, &nx, &ny);
    }
    double ex = w->x1 - w->x0, ey = w->y1 - w->y0;
    double len2 = ex * ex + ey * ey;
    double t = len2 > 0.0 ? ((px - w->x0) * ex + (py - w->y0) * ey) / len2 : 0.0;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    return hypot(w->x0 + t * ex - px, w->y0 + t * ey - py);
}

/* Velocity of wall k's surface at the point (qx, qy): its translation rate plus, when it
 * rotates, omega z x (q - o) about the image o of the origin (sim.h SimPose). */
static inline void sim_wall_velocity(const SimWorld *world, int k, double qx, double qy, double *vx,
                                     double *vy)
{
    double ux = world->wall_vx[k], uy = world->wall_vy[k];
    const double omega = world->wall_omega[k];
    if (omega != 0.0) {
        ux -= omega * (qy - world->wall_oy[k]);
        uy += omega * (qx - world->wall_ox[k]);
    }
    *vx = ux;
    *vy = uy;
}

#endif
