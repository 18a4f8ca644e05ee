/* SPDX-License-Identifier: MIT */
/* advice.h: the time step that reaches a target error in the restitution coefficient, from the
 * measured convergence law |e - e_n| ~ C / n^p of each integrator and onset option
 * (docs/accuracy.md "dt advice"), and the CPU cost that implies. */
#ifndef APP_ADVICE_H
#define APP_ADVICE_H

#include "sim/sim.h"

#include <stddef.h>
#include <stdio.h>

typedef struct AppAdvice {
    double target;               /* |e - e_n| asked for */
    double restitution;          /* e_n of the stiffest pair (the one of t_c,min) */
    double law_restitution;      /* e_n of the table row used (the nearest measured, 0.2-0.9) */
    double c, p;                 /* the law: error ~ c / n^p */
    double contact_time;         /* t_c,min, s (NAN without grains) */
    double stability_limit;      /* s */
    double steps_per_contact;    /* n = (c / target)^(1/p) */
    double time_step;            /* t_c,min / n, s (NAN without grains) */
    int stability_capped;        /* the stability limit is below t_c / n: n is raised to it */
    double ns_per_particle_step; /* measured CPU cost of one grain for one step, ns */
    int mobile;                  /* grains that the cost counts */
    double cpu_per_sim_s;        /* estimate: ns_per_particle_step x mobile / time_step, s */
} AppAdvice;

/* Advice for `def` (its grains give t_c,min and the stiffest pair; without grains, the smallest
 * restitution of the species when every species gives e_n). 0, or -1 with a message (the target
 * outside (0, 0.5), no e_n to read, Hertz law). */
int app_dt_advice(const SimWorldDef *def, int mobile, double target, AppAdvice *out, char *err,
                  size_t err_size);

/* Prints the advice as `sablier check` shows it. */
void app_dt_advice_print(const AppAdvice *a, const SimWorldDef *def, FILE *out);

#endif
