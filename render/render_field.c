/* SPDX-License-Identifier: MIT */
/* render_field.c: the coarse-grained velocity field a figure draws, computed by sim's one
 * coarse-graining implementation (sim/coarse.c: V = j / rho with rho = sum m_i W and j = sum m_i
 * v_i W; Goldhirsch 2010, Weinhart et al. 2012) with the plain kernel values on the nodes. The
 * solid fraction sum pi r_i^2 W comes with it and masks empty nodes. */
#include "render/internal.h"

#include <math.h>
#include <stdlib.h>

double render_kernel(RenderKernel kernel, double r, double width)
{
    return sim_kernel(kernel == RENDER_KERNEL_GAUSSIAN ? SIM_KERNEL_GAUSSIAN : SIM_KERNEL_LUCY, r,
                      width);
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
    SimCoarseDef cd = sim_coarse_def_default();
    cd.kernel = def->kernel == RENDER_KERNEL_GAUSSIAN ? SIM_KERNEL_GAUSSIAN : SIM_KERNEL_LUCY;
    cd.width = def->width;
    cd.geometry = SIM_COARSE_GRID;
    cd.x0 = def->x0;
    cd.y0 = def->y0;
    cd.cell_x = cd.cell_y = def->cell;
    cd.nx = (int)fx;
    cd.ny = (int)fy;
    cd.normalise = 0; /* the plain kernel: V does not depend on it, the packing mask did */
    SimCoarse *cg = sim_coarse_create(&cd, NULL);
    size_t n = (size_t)cd.nx * (size_t)cd.ny;
    double *mass = malloc(((size_t)frame->count + 1) * sizeof *mass);
    out->vx = malloc(n * sizeof *out->vx);
    out->vy = malloc(n * sizeof *out->vy);
    out->packing = malloc(n * sizeof *out->packing);
    int ok = cg && mass && out->vx && out->vy && out->packing;
    for (int g = 0; ok && g < frame->count; ++g)
        mass[g] = pow(frame->radius[g], (double)def->mass_power);
    if (ok && sim_coarse_add(cg, frame, mass, 0.0, 0.0) == SIM_OK) {
        sim_coarse_field(cg, SIM_CG_VX, out->vx);
        sim_coarse_field(cg, SIM_CG_VY, out->vy);
        sim_coarse_field(cg, SIM_CG_PHI, out->packing);
        out->nx = cd.nx;
        out->ny = cd.ny;
        out->x0 = def->x0;
        out->y0 = def->y0;
        out->cell = def->cell;
    } else {
        ok = 0;
    }
    free(mass);
    sim_coarse_destroy(cg);
    if (!ok)
        render_field_free(out);
    return ok ? 0 : -1;
}
