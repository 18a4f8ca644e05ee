/* SPDX-License-Identifier: MIT */
/* bench_stream: what the velocity-Verlet drift's memory stream costs per grain on this machine, by
 * size and by layout, outside the simulation (docs/dev/scaling.md, "the large piles'
 * cost against LAMMPS and the drift's stream alone"). A model of the drift, not the drift: the same
 * arrays read and written per grain (the opening kick with the deferred closing kick, rotation on:
 * 13 read, 12 written, 3 of those write-only) and the same arithmetic, one loop over N grains for
 * both layouts (sablier's drift runs its rotation in a second loop over the same short range, in
 * cache), in two layouts: split   every per-grain quantity its own array (sablier's layout), each a
 * block of sim/stagger.c's, so that they fall into different L1 sets as sablier's arrays do; packed
 * the seven quantities only the drift reads (half-step velocities, reference positions, inverse
 * mass and inertia) interleaved in one 64-byte record per grain, the nine others (positions,
 * velocities, angle, forces, torque) as in `split`. The drift loops are built for AVX2 as well as
 * the baseline and the best one this CPU runs is taken (target_clones), as sim/isa.c does for
 * sablier's own passes, so that in cache the loop is as fast as the simulation's and the figures
 * from memory show the stream, not the arithmetic. Prints CSV: layout,grains,ns_per_grain,GB_per_s
 * (best of --repeats, each timing about
 * --seconds of passes). Nothing here is asserted; figures only.
 *
 *   bench_stream [--sizes "7000 70000 700000 1001000"] [--repeats 5] [--seconds 0.3] */
#define _POSIX_C_SOURCE 200809L
#include "sim/internal.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { SPLIT_ARRAYS = 16, RECORD = 8 };

/* Array number k of the layout, n doubles in a staggered block (sim_stagger_grow), filled. */
static double *staggered(size_t n, int k)
{
    double *a = sim_stagger_grow(NULL, n * sizeof(double), k);
    if (!a) {
        fprintf(stderr, "bench_stream: out of memory\n");
        exit(1);
    }
    for (size_t i = 0; i < n; ++i)
        a[i] = 1.0 + 1e-3 * (double)(i % 97);
    return a;
}

/* The per-grain quantities. In the packed layout the seven from HX on are fields of the record
 * (at their index minus HX), the others arrays as in the split layout. */
enum { HX, HY, HW, XR, YR, IM, II, X, Y, VX, VY, FX, FY, OMEGA, ANGLE, TORQUE };

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define BEST_ISA __attribute__((target_clones("avx2", "default")))
#else
#define BEST_ISA
#endif

typedef struct Consts {
    double dt, half, gx, gy, limit2;
} Consts;

/* The drift over n grains; q[k] is quantity k of grain 0, and the drift-only quantities (HX..II)
 * of grain i are at q[k][i * s]: s = 1 split, RECORD packed. */
static inline __attribute__((always_inline)) int drift(double *const *q, const int s, int n,
                                                       Consts c)
{
    double *restrict x = q[X], *restrict y = q[Y], *restrict vx = q[VX], *restrict vy = q[VY];
    double *restrict fx = q[FX], *restrict fy = q[FY], *restrict om = q[OMEGA];
    double *restrict an = q[ANGLE], *restrict tq = q[TORQUE];
    double *restrict hx = q[HX], *restrict hy = q[HY], *restrict hw = q[HW];
    const double *restrict im = q[IM], *restrict ii = q[II], *restrict xr = q[XR],
                           *restrict yr = q[YR];
    int moved = 0;
#pragma GCC ivdep
    for (int i = 0; i < n; ++i) {
        const size_t d = (size_t)i * (size_t)s;
        double ax = fx[i] * im[d] + c.gx, ay = fy[i] * im[d] + c.gy;
        fx[i] = fy[i] = 1e-9; /* not zero: the next pass must not see a constant */
        double vhx = hx[d] + c.dt * ax, vhy = hy[d] + c.dt * ay;
        hx[d] = vhx;
        hy[d] = vhy;
        x[i] += c.dt * vhx;
        y[i] += c.dt * vhy;
        vx[i] = vhx + c.half * ax;
        vy[i] = vhy + c.half * ay;
        double dx = x[i] - xr[d], dy = y[i] - yr[d];
        moved |= dx * dx + dy * dy > c.limit2;
        double alpha = tq[i] * ii[d];
        tq[i] = 1e-9;
        double wh = hw[d] + c.dt * alpha;
        hw[d] = wh;
        an[i] += c.dt * wh;
        om[i] = wh + c.half * alpha;
    }
    return moved;
}

BEST_ISA static int drift_split(double *const *q, int n, Consts c)
{
    return drift(q, 1, n, c);
}

BEST_ISA static int drift_packed(double *const *q, int n, Consts c)
{
    return drift(q, RECORD, n, c);
}

typedef enum { SPLIT, PACKED, LAYOUTS } Layout;

static const char *const layout_name[LAYOUTS] = {"split", "packed"};

/* Bytes a pass moves per grain, write-allocate reads counted (a written line is read first):
 * split, 16 arrays read (3 only for ownership) and 12 written back; packed, 9 arrays read (3 for
 * ownership) and written back, and the 64-byte record read and written back. */
static const double layout_bytes[LAYOUTS] = {8.0 * (16 + 12), 8.0 * (9 + 9) + 64.0 * 2};

/* Best ns per grain of `repeats` timings of about `seconds` of passes each. */
static double time_layout(Layout l, int n, int repeats, double seconds, double *sink)
{
    double *q[SPLIT_ARRAYS];
    int count = 0;
    for (int k = l == SPLIT ? 0 : X; k < SPLIT_ARRAYS; ++k)
        q[k] = staggered((size_t)n, count++);
    if (l == PACKED) {
        q[HX] = staggered((size_t)n * RECORD, count);
        for (int k = HX + 1; k < X; ++k)
            q[k] = q[HX] + (k - HX);
    }
    const Consts c = {1e-6, 0.5e-6, 0.0, -9.81, 1e-4};
    double best = 1e30;
    int passes = 1;
    for (int r = -1; r < repeats; ++r) { /* r = -1 warms up and sizes the timing */
        const double t0 = sim_clock_seconds(SIM_CLOCK_WALL);
        for (int p = 0; p < passes; ++p)
            *sink += l == SPLIT ? drift_split(q, n, c) : drift_packed(q, n, c);
        const double t = sim_clock_seconds(SIM_CLOCK_WALL) - t0;
        if (r < 0) {
            const double per_pass = t / passes;
            passes = per_pass > 0.0 ? (int)(seconds / per_pass) + 1 : 1000;
            continue;
        }
        const double ns = 1e9 * t / ((double)passes * n);
        best = ns < best ? ns : best;
    }
    /* the packed layout's record is q[HX]; its other fields point into it */
    for (int k = 0; k < SPLIT_ARRAYS; ++k)
        if (l == SPLIT || k == HX || k >= X)
            sim_stagger_free(q[k]);
    return best;
}

int main(int argc, char **argv)
{
    const char *sizes = "7000 70000 700000 1001000";
    int repeats = 5;
    double seconds = 0.3;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--sizes") && i + 1 < argc)
            sizes = argv[++i];
        else if (!strcmp(argv[i], "--repeats") && i + 1 < argc)
            repeats = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--seconds") && i + 1 < argc)
            seconds = atof(argv[++i]);
        else {
            fprintf(stderr,
                    "usage: bench_stream [--sizes \"N ...\"] [--repeats K] [--seconds S]\n");
            return 2;
        }
    }
    if (repeats < 1 || !(seconds > 0.0)) {
        fprintf(stderr, "bench_stream: --repeats must be >= 1 and --seconds > 0\n");
        return 2;
    }

    /* every size checked before anything runs */
    enum { MAX_SIZES = 64 };

    long size[MAX_SIZES];
    int sizes_count = 0;
    for (const char *s = sizes;;) {
        while (*s == ' ')
            ++s;
        if (!*s)
            break;
        char *end;
        const long n = strtol(s, &end, 10);
        if (end == s || (*end && *end != ' ') || n < 1 || n > INT32_MAX / RECORD ||
            sizes_count == MAX_SIZES) {
            fprintf(stderr, "bench_stream: --sizes: '%s' is not a grain count from 1 to %d%s\n", s,
                    INT32_MAX / RECORD, sizes_count == MAX_SIZES ? " (64 sizes at most)" : "");
            return 2;
        }
        size[sizes_count++] = n;
        s = end;
    }
    double sink = 0.0;
    printf("layout,grains,ns_per_grain,GB_per_s\n");
    for (int z = 0; z < sizes_count; ++z)
        for (int l = 0; l < LAYOUTS; ++l) {
            const double ns = time_layout((Layout)l, (int)size[z], repeats, seconds, &sink);
            printf("%s,%ld,%.3f,%.1f\n", layout_name[l], size[z], ns, layout_bytes[l] / ns);
            fflush(stdout);
        }
    fprintf(stderr, "(checksum %g)\n", sink);
    return 0;
}
