/* SPDX-License-Identifier: MIT */
/* render_field.c: coarse-grained (MercuryCG-style) velocity field on a node grid. With a kernel W
 * normalised over the plane, rho = sum m_i W(r - r_i) and j = sum m_i v_i W(r - r_i); the mean
 * velocity is V = j / rho (mass-weighted, not a plain average of grain velocities; Goldhirsch 2010,
 * Weinhart et al. 2012). The solid fraction sum pi r_i^2 W comes for free and masks empty nodes. */
#include "render/render.h"

#include <math.h>
#include <stdlib.h>

double render_kernel(RenderKernel kernel, double r, double width)
{
    if (!(width > 0) || !(r < width))
        return 0;
    if (kernel == RENDER_KERNEL_GAUSSIAN) {
        /* sigma = width / 3, cut at 3 sigma and renormalised for the cut tail (1 - e^-4.5). */
        double sigma = width / 3.0;
        double norm = 2 * SIM_PI * sigma * sigma * (1.0 - exp(-4.5));
        return exp(-0.5 * (r * r) / (sigma * sigma)) / norm;
    }
    return sim_kernel_lucy(r, width); /* the kernel the app's coarse-grained fields use too */
}

void render_field_free(RenderField *field)
{
    if (!field)
        return;
    free(field->vx);
    free(field->vy);
    free(field->packing);
    field->vx = field->vy = field->packing = NULL;
    field->nx = field->ny = 0;
}

int render_velocity_field(const SimFrame *frame, const RenderFieldDef *def, RenderField *out)
{
    out->vx = out->vy = out->packing = NULL;
    out->nx = out->ny = 0;
    if (!(def->cell > 0) || !(def->width > 0) || !(def->x1 > def->x0) || !(def->y1 > def->y0))
        return -1;
    double fx = ceil((def->x1 - def->x0) / def->cell), fy = ceil((def->y1 - def->y0) / def->cell);
    if (!(fx * fy <= 4e6))
        return -1;
    int nx = (int)fx, ny = (int)fy;
    size_t n = (size_t)nx * (size_t)ny;
    double *mass = calloc(n, sizeof *mass);
    out->vx = calloc(n, sizeof *out->vx);
    out->vy = calloc(n, sizeof *out->vy);
    out->packing = calloc(n, sizeof *out->packing);
    if (!mass || !out->vx || !out->vy || !out->packing) {
        free(mass);
        render_field_free(out);
        return -1;
    }
    out->nx = nx;
    out->ny = ny;
    out->x0 = def->x0;
    out->y0 = def->y0;
    out->cell = def->cell;
    double w = def->width, cell = def->cell;
    double period = frame->periodic ? frame->domain_x1 - frame->domain_x0 : 0;
    for (int g = 0; g < frame->count; ++g) {
        if (frame->flags && (frame->flags[g] & SIM_GRAIN_FIXED))
            continue;
        double r = frame->radius[g];
        double m = pow(r, (double)def->mass_power);
        double vx = frame->vx ? frame->vx[g] : 0, vy = frame->vy ? frame->vy[g] : 0;
        double area = SIM_PI * r * r;
        /* Periodic images that can reach the region. */
        for (int image = -1; image <= 1; ++image) {
            if (image != 0 && !(period > 0))
                continue;
            double x = frame->x[g] + image * period, y = frame->y[g];
            int i0 = (int)ceil((x - w - def->x0) / cell - 0.5);
            int i1 = (int)floor((x + w - def->x0) / cell - 0.5);
            int j0 = (int)ceil((y - w - def->y0) / cell - 0.5);
            int j1 = (int)floor((y + w - def->y0) / cell - 0.5);
            if (i0 < 0)
                i0 = 0;
            if (j0 < 0)
                j0 = 0;
            if (i1 > nx - 1)
                i1 = nx - 1;
            if (j1 > ny - 1)
                j1 = ny - 1;
            for (int j = j0; j <= j1; ++j) {
                double dy = def->y0 + (j + 0.5) * cell - y;
                for (int i = i0; i <= i1; ++i) {
                    double dx = def->x0 + (i + 0.5) * cell - x;
                    double k = render_kernel(def->kernel, sqrt(dx * dx + dy * dy), w);
                    if (k == 0)
                        continue;
                    size_t idx = (size_t)j * (size_t)nx + (size_t)i;
                    mass[idx] += m * k;
                    out->vx[idx] += m * vx * k;
                    out->vy[idx] += m * vy * k;
                    out->packing[idx] += area * k;
                }
            }
        }
    }
    for (size_t k = 0; k < n; ++k) {
        if (mass[k] > 0) {
            out->vx[k] /= mass[k];
            out->vy[k] /= mass[k];
        } else {
            out->vx[k] = out->vy[k] = 0;
        }
    }
    free(mass);
    return 0;
}
