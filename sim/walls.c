/* SPDX-License-Identifier: MIT */
/* walls.c: the public wall geometry (sim.h): distances and points of segments and arcs. */
#include "walls.h"

#include "internal.h"

double sim_wall_contact_distance(const SimWall *wall, double x, double y, double radius)
{
    return sim_wall_distance(wall, x, y, radius);
}

void sim_wall_point(const SimWall *wall, double s, double *x, double *y)
{
    if (wall->shape == SIM_WALL_ARC) {
        const double a = wall->angle0 + s * (wall->angle1 - wall->angle0);
        *x = wall->center_x + wall->radius * cos(a);
        *y = wall->center_y + wall->radius * sin(a);
        return;
    }
    *x = wall->x0 + s * (wall->x1 - wall->x0);
    *y = wall->y0 + s * (wall->y1 - wall->y0);
}

void sim_wall_bounds(const SimWall *wall, double *x0, double *y0, double *x1, double *y1)
{
    if (wall->shape == SIM_WALL_ARC) { /* the whole circle: simple and enough for a view */
        *x0 = wall->center_x - wall->radius;
        *x1 = wall->center_x + wall->radius;
        *y0 = wall->center_y - wall->radius;
        *y1 = wall->center_y + wall->radius;
        return;
    }
    *x0 = fmin(wall->x0, wall->x1);
    *x1 = fmax(wall->x0, wall->x1);
    *y0 = fmin(wall->y0, wall->y1);
    *y1 = fmax(wall->y0, wall->y1);
}
