/* SPDX-License-Identifier: MIT */
/* integrate_scratch.h: which SimWorld.scratch array holds what for each integrator, shared by
 * integrate.c (allocation counts, start state) and sim/isa/integrate_pass.c (the steps). */
#ifndef SIM_INTEGRATE_SCRATCH_H
#define SIM_INTEGRATE_SCRATCH_H

#include "internal.h"

/* Scratch arrays (SimWorld.scratch) per integrator, rotational ones last so that a world without
 * rotation allocates only those before them. */
enum { VV_VX_HALF, VV_VY_HALF, VV_OMEGA_HALF, VV_ARRAYS }; /* v(t + dt/2), omega(t + dt/2) */

enum { STORMER_X_PREV, STORMER_Y_PREV, STORMER_ARRAYS }; /* x(t - dt) */

enum { GEAR_AX, GEAR_AY, GEAR_BX, GEAR_BY, GEAR_ALPHA, GEAR_BETA, GEAR_ARRAYS }; /* a, da/dt */

/* RK4: the start state, the weighted sums of the stages' slopes, then the same for rotation. */
enum {
    RK4_X0,
    RK4_Y0,
    RK4_VX0,
    RK4_VY0,
    RK4_SUM_VX,
    RK4_SUM_VY,
    RK4_SUM_AX,
    RK4_SUM_AY,
    RK4_ANGLE0,
    RK4_OMEGA0,
    RK4_SUM_OMEGA,
    RK4_SUM_ALPHA,
    RK4_ARRAYS
};

_Static_assert((int)RK4_ARRAYS == (int)SIM_SCRATCH_MAX, "RK4 uses the most scratch arrays");

#endif
