/* SPDX-License-Identifier: MIT */
/* stab_util.h: helpers shared by the stability tests (tests/stability/test_*.c), on top of the
 * physics-test helpers. Everything is `static inline` so each test file compiles warning-free. */
#ifndef STAB_UTIL_H
#define STAB_UTIL_H

#include "sim/sim_test_util.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* 1 when every position, velocity, force and torque in the frame is finite. */
static inline int st_finite(SimWorld *w)
{
    SimFrame f;
    sim_world_frame(w, &f);
    for (int i = 0; i < f.count; ++i)
        if (!isfinite(f.x[i]) || !isfinite(f.y[i]) || !isfinite(f.vx[i]) || !isfinite(f.vy[i]) ||
            !isfinite(f.omega[i]) || !isfinite(f.angle[i]) || !isfinite(f.fx[i]) ||
            !isfinite(f.fy[i]) || !isfinite(f.torque[i]) || !isfinite(f.force[i])) {
            fprintf(stderr, "grain %u (index %d) has a non-finite state\n", f.id[i], i);
            return 0;
        }
    for (int k = 0; k < f.contact_count; ++k)
        if (!isfinite(f.contacts[k].normal_force) || !isfinite(f.contacts[k].tangential_force) ||
            !isfinite(f.contacts[k].overlap))
            return 0;
    return 1;
}

/* What a checked run saw. */
typedef struct StRun {
    SimStatus status;
    SimError error;
    double e0;          /* total energy at the start, J */
    double e_max;       /* largest total energy sampled, J */
    double e_last;      /* total energy at the end, J */
    double ke_max;      /* largest kinetic energy sampled (translational + rotational), J */
    double overlap_max; /* largest xi / d_min sampled */
    int finite;         /* 1 when every sampled state was finite */
    long steps_done;
} StRun;

/* Runs `steps` steps in chunks of `every`, sampling energy, overlap and finiteness after each
 * chunk. Stops at the first non-OK status. */
static inline StRun st_run(SimWorld *w, long steps, long every)
{
    StRun r;
    memset(&r, 0, sizeof r);
    SimEnergy e = sim_world_energy(w);
    r.e0 = r.e_max = r.e_last = e.total;
    r.ke_max = e.kinetic + e.rotational;
    r.overlap_max = sim_world_max_overlap_ratio(w);
    r.finite = st_finite(w);
    r.status = SIM_OK;
    for (long done = 0; done < steps;) {
        long n = steps - done < every ? steps - done : every;
        r.status = sim_world_step(w, n, &r.error);
        if (r.status != SIM_OK)
            break;
        done += n;
        r.steps_done = done;
        e = sim_world_energy(w);
        r.e_last = e.total;
        r.e_max = fmax(r.e_max, e.total);
        r.ke_max = fmax(r.ke_max, e.kinetic + e.rotational);
        r.overlap_max = fmax(r.overlap_max, sim_world_max_overlap_ratio(w));
        if (!st_finite(w) || !isfinite(e.total)) {
            r.finite = 0;
            break;
        }
    }
    return r;
}

/* Prints a run summary (shown only when a test fails or is run by hand). */
static inline void st_report(const char *name, const StRun *r)
{
    fprintf(stderr,
            "%s: status %d after %ld steps, E0 %.9g, E_max %.9g, E_last %.9g, KE_max %.3g, "
            "overlap_max %.3g d, finite %d%s%s\n",
            name, (int)r->status, r->steps_done, r->e0, r->e_max, r->e_last, r->ke_max,
            r->overlap_max, r->finite, r->status != SIM_OK ? ": " : "",
            r->status != SIM_OK ? r->error.message : "");
}

/* A box of fixed grains (floor row and two columns) of radius rg, inner width `width`, walls up
 * to `height`. The floor centres are at y = 0. */
static inline void st_fixed_box(SimGrainBuffer *b, double width, double height, double rg,
                                int species)
{
    sim_build_fixed_row(b, 0.0, width, 0.0, rg, species, -1);
    sim_build_fixed_column(b, 0.0, 2.0 * rg, height, rg, species, -1);
    sim_build_fixed_column(b, width, 2.0 * rg, height, rg, species, -1);
}

/* Non-overlapping grains on a jittered square lattice in [x0, x1] x [y0, ...), radius drawn
 * uniformly in [r_lo, r_hi], pitch 2 r_hi + gap. Returns the number added. */
static inline int st_lattice(SimGrainBuffer *b, SimRng *rng, int n, double x0, double x1, double y0,
                             double r_lo, double r_hi, double gap)
{
    double pitch = 2.0 * r_hi + gap;
    int per_row = (int)floor((x1 - x0) / pitch);
    if (per_row < 1)
        return 0;
    for (int k = 0; k < n; ++k) {
        int row = k / per_row, col = k % per_row;
        double r = r_lo + (r_hi - r_lo) * sim_rng_uniform(rng);
        double jitter = (r_hi - r) * (2.0 * sim_rng_uniform(rng) - 1.0);
        sim_grain_buffer_add(b, x0 + pitch * (col + 0.5) + jitter, y0 + pitch * (row + 0.5), r, 0,
                             0u, -1);
    }
    return n;
}

/* 1 when `needle` occurs in `text`. */
static inline int st_mentions(const char *text, const char *needle)
{
    return strstr(text, needle) != NULL;
}

#endif
