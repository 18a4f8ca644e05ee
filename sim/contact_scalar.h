/* SPDX-License-Identifier: MIT */
/* contact_scalar.h: what the contact kernel (sim/isa/contact_pass.c, compiled once per instruction
 * set) and the diagnostics (contact.c) share: the contact key's bits, the laws on one contact
 * (scalar lanes) and the wall geometry. Static inline: each includer gets its own copy, compiled
 * for its own instruction set. */
#ifndef SIM_CONTACT_SCALAR_H
#define SIM_CONTACT_SCALAR_H

#include "internal.h"

#include <math.h>

/* The kernel's pieces must inline into each instantiation, or `key` stops being a constant. */
#define KERNEL static inline __attribute__((always_inline))

/* The contact key (sim_contact_key): the declared laws as bits, one kernel instance per value.
 * Its fields are named here only (for contact.c and sim/isa/contact_pass.c); other files decode
 * it through sim_contact_key_rotation and sim_contact_key_history. */
enum {
    KEY_TANGENTIAL = 3u, /* SimTangentialLaw in the low two bits (mask) */
    KEY_ROLLING = 1u << 2,
    KEY_PERIODIC = 1u << 3,
    KEY_HERTZ = 1u << 4,
    KEY_CLIP = 1u << 5,
    KEY_CHORD = 1u << 6, /* rolling law from the contact chord (else fixed k_r) */
    KEY_EVENT = 1u << 7, /* event-aware onset (SIM_ONSET_EVENT; linear normal law only) */
    KEY_COUNT = 256,
    KEY_UNIFORM = 1u << 8 /* one species: pair constants are broadcast, not gathered */
};

/* Torques exist only when a tangential law or rolling resistance is declared. */
#define KEY_ROTATION(key) (((key)&KEY_TANGENTIAL) != 0 || ((key)&KEY_ROLLING) != 0)

/* ------------------------------------------------------------------ the laws, two instances */

/* One contact (scalar lanes): the wall pass and the diagnostics. A min that compiles to one
 * instruction: libm's fmin is a function call unless NaN semantics are relaxed. */
static inline double min_d(double a, double b)
{
    return a < b ? a : b;
}

static inline double sel_d(int m, double a, double b)
{
    return m ? a : b;
}

#define abs_d      fabs
#define copysign_d copysign
#define sqrt_d     sqrt
#define LAW_T      double
#define LAW(name)  name##_d
#define LAW_ZERO   0.0
#define LAW_ONE    1.0
#include "contact_laws.h"
#undef LAW_T
#undef LAW
#undef LAW_ZERO
#undef LAW_ONE

/* The wall geometry (segments and arcs) is sim/walls.h. */

#endif
