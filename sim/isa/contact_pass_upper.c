/* SPDX-License-Identifier: MIT */
/* contact_pass_upper.c: the other half of the contact kernel's folded key instances (KEYS_UPPER in
 * contact_pass.c: the linear keys with tensile clipping by default), a translation unit of its own
 * so that a two-core build compiles the two halves of each instruction set's copy side by side;
 * contact_pass.c's selectors ask it for its keys.
 * Not built with SIM_ISA_KEY_AT_RUN_TIME (sim/CMakeLists.txt), whose one run-time copy needs no
 * split. */
#define SIM_CONTACT_UPPER 1
#include "sim/isa/contact_pass.c"
