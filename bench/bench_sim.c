/* SPDX-License-Identifier: MIT */
/* bench_sim: physics speed benchmark. Reports particle-steps per second of the step pipeline on a
 * settled pile of about 7000 polydisperse disks (thesis 000 standard case: 100p x 100p container
 * of fixed boundary grains of radius r_max, rain-like deposition, 000 §4.3 material), on --threads
 * threads (default one; the state hash printed at the end is the same for every count),
 * for three contact laws: regularised Coulomb (000 eq. 3.28), the tangential spring (004 eqs.
 * 1.12-1.13) and frictionless. It also reports contacts per grain, neighbour-list rebuilds and
 * memory per grain and per contact.
 *
 * A benchmark reports; it asserts nothing about time. Particle-steps count MOBILE grains only
 * (fixed boundary grains are not integrated and own no list entries, but mobile-fixed contacts
 * are computed and so are part of the work).
 *
 * The settled pile is built once and cached with sim_world_save (default
 * /tmp/sablier-bench-pile-<N>.state); later runs reload it with sim_world_load. --lammps-data
 * writes the same settled pile as a LAMMPS data file (atom_style sphere) so that the LAMMPS peer
 * (bench/lammps/pile.in) times the very same grains.
 *
 * Memory is reported two ways: measured (heap growth, mallinfo2, from before sim_world_create to
 * after the warm-up) and accounted from the array layout of sim/internal.h. This file reads that
 * private header on purpose (white-box benchmark): the rebuild counter and the list capacities
 * are not in the public API.
 *
 * Usage: bench_sim [--grains N] [--steps M] [--repeats K] [--warmup W] [--csv PATH]
 *                  [--cache PATH] [--fresh] [--settle-time S] [--lammps-data PATH]
 *                  [--only regularised,spring,frictionless] [--machine NAME] [--skin S]
 *                  [--threads T]
 * --skin S: a fixed Verlet skin of S m for the timed runs (default 0: sablier's automatic skin).
 * --threads T: threads of the timed runs' step (default 1; the results are the same bits).
 * --wide: the box's width grows with N at the standard bed's height (bench/run_scaling.sh): the
 *   settled 7000-grain pile tiled side by side without its inner walls, cut after N grains,
 *   walled and relaxed (cache /tmp/sablier-bench-wide-<N>.state). Without it the box keeps the
 *   standard case's aspect (width as sqrt(N)).
 * The last line gives the process's peak resident memory (getrusage), pile building included. */
#include "sim/internal.h"
#include "sim/sim.h"

#include <inttypes.h>
#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

/* Thesis 000 geometry: boundary grains of r_max, grains 0.08 m +- 8 % (sim_rain_def_thesis000),
 * 100p x 100p for 7284. */
static const double r_max = 0.105;     /* m, 000 §1.6 */
static const double standard_n = 7284; /* 000 standard initial condition */

typedef struct Options {
    int grains, repeats, warmup, fresh;
    int wide;    /* --wide: width proportional to N at the standard height */
    int threads; /* of the timed runs' step (sim_world_set_threads) */
    long steps;
    double settle_time; /* s, cap on the deposition */
    double skin;        /* m, of the timed runs; 0 = automatic */
    const char *csv, *lammps_data, *only, *machine;
    char cache[512];
} Options;

typedef struct Variant {
    const char *name;
    unsigned effects;
    SimTangentialLaw law;
} Variant;

static const Variant variants[] = {
    {"regularised", SIM_EFFECT_FRICTION, SIM_TANGENTIAL_REGULARISED},
    {"spring", SIM_EFFECT_FRICTION, SIM_TANGENTIAL_SPRING},
    {"frictionless", 0u, SIM_TANGENTIAL_NONE},
};

enum { VARIANT_COUNT = (int)(sizeof variants / sizeof variants[0]) };

typedef struct Result {
    const char *name;
    int mobile, fixed;
    long steps;
    int repeats;
    double best_s, median_s, best_cpu_s;
    double mps_best, mps_median; /* million particle-steps per second of wall time */
    double mps_cpu;              /* same per second of process CPU time (best repeat) */
    double contacts_per_grain, coordination, entries_per_grain;
    double rebuilds_per_1000;
    double skin_d; /* skin at the end of the timed runs / mean mobile diameter */
    double layout_bytes_per_grain, layout_bytes_per_entry, layout_bytes_per_contact;
    double heap_bytes, heap_bytes_per_grain;
    double time_step;
    uint64_t hash; /* sim_world_hash at the end: the same for every thread count */
} Result;

/* Bytes the allocator has handed out (small blocks plus mmapped large ones). */
static double heap_in_use(void)
{
    struct mallinfo2 mi = mallinfo2();
    return (double)mi.uordblks + (double)mi.hblkhd;
}

static SimWorldDef base_def(void)
{
    SimWorldDef def = sim_world_def_default(); /* 000 §4.3 material: k_n 7e5, gamma_n 1.5e3 */
    def.mass_model = SIM_MASS_SPHERE;          /* thesis 000 convention */
    def.time_step = 0.0;                       /* t_c,min / 50: sablier's default rule */
    return def;
}

static int usage(const char *msg)
{
    fprintf(stderr,
            "bench_sim: %s\n"
            "usage: bench_sim [--grains N] [--steps M] [--repeats K] [--warmup W] [--csv PATH]\n"
            "                 [--cache PATH] [--fresh] [--settle-time S] [--lammps-data PATH]\n"
            "                 [--only NAME[,NAME]] [--machine NAME] [--skin S] [--threads T]\n"
            "                 [--wide]\n",
            msg);
    return 2;
}

static int parse_options(int argc, char **argv, Options *o)
{
    *o = (Options){.grains = 7000,
                   .repeats = 5,
                   .warmup = 500,
                   .steps = 2000,
                   .settle_time = 8.0,
                   .threads = 1};
    for (int a = 1; a < argc; ++a) {
        const char *arg = argv[a];
        const char *val = a + 1 < argc ? argv[a + 1] : NULL;
        int takes = 1;
        if (!strcmp(arg, "--fresh")) {
            o->fresh = 1;
            takes = 0;
        } else if (!strcmp(arg, "--wide")) {
            o->wide = 1;
            takes = 0;
        } else if (!val) {
            return usage("missing value or unknown option");
        } else if (!strcmp(arg, "--grains")) {
            o->grains = atoi(val);
        } else if (!strcmp(arg, "--steps")) {
            o->steps = atol(val);
        } else if (!strcmp(arg, "--repeats")) {
            o->repeats = atoi(val);
        } else if (!strcmp(arg, "--warmup")) {
            o->warmup = atoi(val);
        } else if (!strcmp(arg, "--settle-time")) {
            o->settle_time = atof(val);
        } else if (!strcmp(arg, "--threads")) {
            o->threads = atoi(val);
        } else if (!strcmp(arg, "--skin")) {
            o->skin = atof(val);
        } else if (!strcmp(arg, "--csv")) {
            o->csv = val;
        } else if (!strcmp(arg, "--cache")) {
            snprintf(o->cache, sizeof o->cache, "%s", val);
        } else if (!strcmp(arg, "--lammps-data")) {
            o->lammps_data = val;
        } else if (!strcmp(arg, "--only")) {
            o->only = val;
        } else if (!strcmp(arg, "--machine")) {
            o->machine = val;
        } else {
            return usage("unknown option");
        }
        a += takes;
    }
    if (o->grains < 10 || o->steps < 1 || o->repeats < 1 || o->warmup < 0 ||
        !(o->settle_time > 0.0) || !(o->skin >= 0.0) || o->threads < 1)
        return usage("grains >= 10, steps >= 1, repeats >= 1, warmup >= 0, settle-time > 0, "
                     "skin >= 0, threads >= 1");
    if (!o->cache[0])
        snprintf(o->cache, sizeof o->cache, "/tmp/sablier-bench-%s-%d.state",
                 o->wide ? "wide" : "pile", o->grains);
    return 0;
}

/* Lets the grains of buffer settle under regularised Coulomb friction until the kinetic energy
 * per grain is below 1e-6 m g d after min_time (the thesis stops on a total-energy tolerance) or
 * until time_cap, then saves the world to o->cache. */
static int settle_and_save(const Options *o, const SimGrainBuffer *buffer, double min_time,
                           double time_cap)
{
    SimWorldDef def = base_def();
    def.effects = SIM_EFFECT_FRICTION;
    def.contact.tangential = SIM_TANGENTIAL_REGULARISED;
    def.grains = sim_grain_buffer_view(buffer);
    def.max_initial_overlap = 0.5; /* a settled pile's own overlaps (wide piles) */
    SimError err;
    SimWorld *world = sim_world_create(&def, &err);
    if (!world) {
        fprintf(stderr, "bench_sim: %s: %s\n", err.field, err.message);
        return 2;
    }
    double d_mean, m_mean;
    sim_world_means(world, &d_mean, &m_mean);
    const double threshold = 1e-6 * m_mean * 9.806 * d_mean; /* J per grain */
    const double dt = sim_world_time_step(world);
    fprintf(stderr,
            "bench_sim: settling %d grains, dt %.4g s, until E_kin/N < %.3g J or t = %g s\n",
            sim_world_grain_count(world), dt, threshold, time_cap);
    const long chunk = (long)ceil(0.1 / dt);
    double t0 = sim_clock_seconds(SIM_CLOCK_WALL), per_grain = 0.0;
    while (sim_world_time(world) < time_cap) {
        if (sim_world_step(world, chunk, &err) != SIM_OK) {
            fprintf(stderr, "bench_sim: settling failed: %s\n", err.message);
            sim_world_destroy(world);
            return 1;
        }
        SimEnergy e = sim_world_energy(world);
        per_grain = (e.kinetic + e.rotational) / e.mobile;
        if (sim_world_time(world) > min_time && per_grain < threshold)
            break;
    }
    fprintf(stderr,
            "bench_sim: settling reached t = %.2f s (%ld steps, %.1f s wall), E_kin/N = %.3g J "
            "(%s)\n",
            sim_world_time(world), sim_world_step_count(world),
            sim_clock_seconds(SIM_CLOCK_WALL) - t0, per_grain,
            per_grain < threshold ? "below threshold" : "time cap");
    SimStatus s = sim_world_save(world, o->cache, &err);
    if (s != SIM_OK)
        fprintf(stderr, "bench_sim: %s\n", err.message);
    sim_world_destroy(world);
    return s == SIM_OK ? 0 : 1;
}

/* Deposits the grains (000 §6.1 rain-like lattice) into a box of fixed boundary grains and lets
 * them settle (settle_and_save). */
static int build_pile(const Options *o)
{
    /* Width scales with sqrt(N) so that other N keep the standard case's aspect. */
    int columns = (int)lround(100.0 * sqrt((double)o->grains / standard_n));
    if (columns < 8)
        columns = 8;
    const double width = columns * 2.0 * r_max;
    SimGrainBuffer buffer;
    sim_grain_buffer_init(&buffer);
    SimRainDef rain = sim_rain_def_thesis000(1.5 * r_max, width - 1.5 * r_max, 1.5 * r_max,
                                             4000.0 * r_max, o->grains);
    SimRng rng;
    sim_rng_seed(&rng, 2024);
    int added = sim_build_rain(&buffer, &rain, &rng);
    double top = 0.0;
    for (int i = 0; i < buffer.count; ++i)
        top = fmax(top, buffer.y[i] + buffer.radius[i]);
    double wall_top = fmax(top, width);
    sim_build_fixed_row(&buffer, 0.0, width, 0.0, r_max, 0, -1);
    sim_build_fixed_column(&buffer, 0.0, 2 * r_max, wall_top, r_max, 0, -1);
    sim_build_fixed_column(&buffer, width, 2 * r_max, wall_top, r_max, 0, -1);
    fprintf(stderr, "bench_sim: depositing %d grains in a %d p wide box\n", added, columns);
    int s = settle_and_save(o, &buffer, 2.0, o->settle_time);
    sim_grain_buffer_free(&buffer);
    return s;
}

static int by_x(const void *a, const void *b)
{
    const double *p = a, *q = b;
    return (p[0] > q[0]) - (p[0] < q[0]);
}

/* The tile's mobile grains (x, y, radius triples), sorted by x, and its width: the settled
 * standard pile (built first when not cached). 0, or the exit status. */
static int load_tile(const Options *o, double **grains, int *count, double *width)
{
    Options tile = *o;
    tile.grains = 7000;
    tile.wide = 0;
    snprintf(tile.cache, sizeof tile.cache, "/tmp/sablier-bench-pile-%d.state", tile.grains);
    FILE *f = fopen(tile.cache, "rb");
    if (f)
        fclose(f);
    else if (build_pile(&tile) != 0)
        return 1;
    SimGrainSet g;
    SimWall *walls = NULL;
    int wall_count = 0;
    double t = 0.0;
    SimError err;
    if (sim_state_load(tile.cache, &g, &walls, &wall_count, &t, &err) != SIM_OK) {
        fprintf(stderr, "bench_sim: %s\n", err.message);
        return 1;
    }
    free(walls);
    double *out = malloc(3 * (size_t)g.count * sizeof *out);
    if (!out)
        abort(); /* a benchmark: nothing to recover */
    int n = 0;
    *width = 0.0;
    for (int i = 0; i < g.count; ++i) {
        *width = fmax(*width, g.x[i]);
        if (g.flags && (g.flags[i] & SIM_GRAIN_FIXED))
            continue;
        out[3 * n] = g.x[i];
        out[3 * n + 1] = g.y[i];
        out[3 * n + 2] = g.radius[i];
        ++n;
    }
    sim_grain_set_free(&g);
    qsort(out, (size_t)n, 3 * sizeof *out, by_x);
    *grains = out;
    *count = n;
    return 0;
}

/* --wide: N grains of the standard bed's height in a box as wide as they need: copies of the
 * settled standard pile side by side, each in its compartment (its walls of fixed grains stay
 * between the copies), so that every size has the same grains, contacts and motion per grain and
 * only the size changes; the last copy cut after the N-th grain (by x) and walled at the next
 * place of the bottom row's lattice, then settled again (at least 0.5 s) when a copy was cut.
 * Sizes that are multiples of 7000 are exact copies, not relaxed. */
static int build_wide_pile(const Options *o)
{
    double *tile, width;
    int tile_count;
    if (load_tile(o, &tile, &tile_count, &width) != 0)
        return 1;
    SimGrainBuffer buffer;
    sim_grain_buffer_init(&buffer);
    double right = 0.0, top = 0.0;
    int last = 0, whole = 0; /* the last copy, and whether all of it is in */
    for (int k = 0; buffer.count < o->grains; ++k) {
        int i = 0;
        for (; i < tile_count && buffer.count < o->grains; ++i) {
            const double *g = &tile[3 * i];
            sim_grain_buffer_add(&buffer, g[0] + k * width, g[1], g[2], 0, 0u, -1);
            right = fmax(right, g[0] + k * width + g[2]);
            top = fmax(top, g[1] + g[2]);
        }
        last = k;
        whole = i == tile_count;
    }
    free(tile);
    right = whole ? (last + 1) * width : 2.0 * r_max * ceil((right + r_max) / (2.0 * r_max));
    sim_build_fixed_row(&buffer, 0.0, right, 0.0, r_max, 0, -1);
    for (int k = 0; k <= last + 1; ++k)
        sim_build_fixed_column(&buffer, k <= last ? k * width : right, 2 * r_max, top + 4 * r_max,
                               r_max, 0, -1);
    fprintf(stderr, "bench_sim: %d grains of the standard pile's height, box %.1f p wide\n",
            o->grains, right / (2.0 * r_max));
    int s = whole ? settle_and_save(o, &buffer, 0.0, 0.0) : settle_and_save(o, &buffer, 0.5, 4.0);
    sim_grain_buffer_free(&buffer);
    return s;
}

/* The settled pile as a LAMMPS data file: type 1 mobile, type 2 fixed boundary grains; columns
 * of atom_style sphere: id type diameter density x y z. */
static int write_lammps_data(const char *path, const SimGrainSet *g, double density)
{
    char tmp[600];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f) {
        perror(tmp);
        return 1;
    }
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (int i = 0; i < g->count; ++i) {
        x0 = fmin(x0, g->x[i] - g->radius[i]);
        x1 = fmax(x1, g->x[i] + g->radius[i]);
        y0 = fmin(y0, g->y[i] - g->radius[i]);
        y1 = fmax(y1, g->y[i] + g->radius[i]);
    }
    fprintf(
        f, "sablier settled pile for bench/lammps/pile.in (SI units)\n\n%d atoms\n2 atom types\n\n",
        g->count);
    fprintf(f, "%.10g %.10g xlo xhi\n%.10g %.10g ylo yhi\n-0.5 0.5 zlo zhi\n\nAtoms # sphere\n\n",
            x0 - 0.5, x1 + 0.5, y0 - 0.5, y1 + 0.5);
    for (int i = 0; i < g->count; ++i) {
        int fixed = g->flags && (g->flags[i] & SIM_GRAIN_FIXED);
        fprintf(f, "%d %d %.17g %.17g %.17g %.17g 0\n", i + 1, fixed ? 2 : 1, 2.0 * g->radius[i],
                density, g->x[i], g->y[i]);
    }
    fprintf(f, "\nVelocities\n\n");
    for (int i = 0; i < g->count; ++i)
        fprintf(f, "%d %.17g %.17g 0 0 0 %.17g\n", i + 1, g->vx ? g->vx[i] : 0.0,
                g->vy ? g->vy[i] : 0.0, g->omega ? g->omega[i] : 0.0);
    int ok = fclose(f) == 0;
    if (!ok || rename(tmp, path) != 0) {
        perror(path);
        return 1;
    }
    return 0;
}

/* Grain-proportional and contact-proportional storage from the layout of sim/internal.h. */
#define COUNT_ONE(name) +1

static void layout_bytes(const SimWorld *w, double *per_grain, double *per_entry,
                         double *list_total)
{
    const size_t doubles = 0 SIM_GRAIN_DOUBLE_ARRAYS(COUNT_ONE) + (size_t)w->scratch_count;
    const size_t ints = 0 SIM_GRAIN_INT_ARRAYS(COUNT_ONE);
    /* SoA arrays with the integrator's scratch arrays (capacity), flags + id, cells (items, of),
     * guard snapshot (7 doubles, 4 ints) */
    double grain =
        (double)w->capacity * (double)(doubles * sizeof(double) + ints * sizeof(int) +
                                       sizeof(unsigned) + sizeof(uint32_t)) +
        (double)w->count * (2.0 * sizeof(int) + 7.0 * sizeof(double) + 4.0 * sizeof(int)) +
        (double)w->cell_capacity * sizeof(int) + (double)(w->mobile_count + 1) * sizeof(int) +
        (double)w->nl.in_capacity * sizeof(int) +
        (double)(doubles * SIM_GRAIN_SLACK * sizeof(double)) + /* the parts' sinks */
        (double)w->nl.plan.grain_capacity * 3.0 * sizeof(int); /* the parts' plan, per grain */
    /* partner, owner, gamma_n, pair index; the contact history and the fused pass's spare copy;
     * with threads, the vector pass's four per-entry results and the transposed list of the
     * threaded separate passes (in_entry, out_capacity entries; they run on rebuild steps) */
    double entry = 2.0 * sizeof(int) + sizeof(double) + sizeof(uint8_t);
    if (w->effects & SIM_EFFECT_PERIODIC_X)
        entry += sizeof(double);
    if (w->has_history)
        entry += 4.0 * sizeof(double);
    const double threaded = sizeof(int) + 4.0 * sizeof(double);
    double wall_entry = 2.0 * sizeof(int) + sizeof(double) + sizeof(uint8_t) +
                        (w->has_history ? 2.0 * sizeof(double) : 0.0);
    *per_grain = grain / w->count;
    const double out_share = w->nl.capacity > 0 ? (double)w->nl.out_capacity / w->nl.capacity : 0.0;
    *per_entry = entry + out_share * threaded;
    /* with threads, the parts' targets (per entry) and slots (entries that reach a shared
     * grain: entry, place in the grain's run, four results) */
    const double parts =
        (double)w->nl.plan.target_capacity * sizeof(int) +
        (double)w->nl.plan.slot_capacity * (2.0 * sizeof(int) + 4.0 * sizeof(double));
    *per_entry += w->nl.capacity > 0 ? parts / w->nl.capacity : 0.0;
    *list_total = (double)w->nl.capacity * entry + (double)w->nl.out_capacity * threaded +
                  (double)w->wl.capacity * wall_entry + parts;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int run_variant(const Options *o, const Variant *v, Result *r)
{
    SimError err;
    SimWorldDef def = base_def();
    def.effects = v->effects;
    def.contact.tangential = v->law;
    def.skin = o->skin;

    /* sim_world_load, not sim_state_load + sim_world_create: the settled pile is a state the
     * engine saved, exempt from the start-overlap bound (a large pile settles above it). */
    const double heap0 = heap_in_use();
    SimWorld *w = sim_world_load(o->cache, &def, &err);
    if (!w) {
        fprintf(stderr, "bench_sim: %s: %s: %s\n", o->cache, err.field, err.message);
        return err.status == SIM_ERROR_IO ? 1 : 2;
    }
    sim_world_set_threads(w, o->threads);
    /* Warm-up: spring history builds up, caches and the branch predictor settle. */
    if (sim_world_step(w, o->warmup, &err) != SIM_OK) {
        fprintf(stderr, "bench_sim: %s: warm-up failed: %s\n", v->name, err.message);
        sim_world_destroy(w);
        return 1;
    }
    const double heap1 = heap_in_use();

    double *times = malloc(2 * (size_t)o->repeats * sizeof *times);
    if (!times)
        abort();
    double *cpu = times + o->repeats;
    const long rebuilds0 = w->rebuilds;
    for (int k = 0; k < o->repeats; ++k) {
        double t0 = sim_clock_seconds(SIM_CLOCK_WALL), c0 = sim_clock_seconds(SIM_CLOCK_PROCESS);
        SimStatus s = sim_world_step(w, o->steps, &err);
        times[k] = sim_clock_seconds(SIM_CLOCK_WALL) - t0;
        cpu[k] = sim_clock_seconds(SIM_CLOCK_PROCESS) - c0;
        if (s != SIM_OK) {
            fprintf(stderr, "bench_sim: %s: run failed: %s\n", v->name, err.message);
            free(times);
            sim_world_destroy(w);
            return 1;
        }
    }
    const long rebuilds = w->rebuilds - rebuilds0;
    qsort(times, (size_t)o->repeats, sizeof *times, cmp_double);
    qsort(cpu, (size_t)o->repeats, sizeof *cpu, cmp_double);

    SimEnergy e = sim_world_energy(w);
    const int mobile = sim_world_mobile_count(w);
    double mean_d, mean_m;
    sim_world_means(w, &mean_d, &mean_m);
    const double work = (double)mobile * (double)o->steps;
    double per_grain, per_entry, list_total;
    layout_bytes(w, &per_grain, &per_entry, &list_total);
    *r = (Result){
        .name = v->name,
        .mobile = mobile,
        .fixed = sim_world_grain_count(w) - mobile,
        .steps = o->steps,
        .repeats = o->repeats,
        .best_s = times[0],
        .median_s = times[o->repeats / 2],
        .best_cpu_s = cpu[0],
        .mps_cpu = work / cpu[0] / 1e6,
        .mps_best = work / times[0] / 1e6,
        .mps_median = work / times[o->repeats / 2] / 1e6,
        .contacts_per_grain = (double)e.contacts / mobile,
        .coordination = sim_world_coordination(w),
        .entries_per_grain = (double)(w->nl.start[mobile] + w->wl.count) / mobile,
        .rebuilds_per_1000 = 1000.0 * (double)rebuilds / ((double)o->steps * o->repeats),
        .skin_d = sim_world_skin(w) / mean_d,
        .layout_bytes_per_grain = per_grain,
        .layout_bytes_per_entry = per_entry,
        .layout_bytes_per_contact = e.contacts > 0 ? list_total / e.contacts : 0.0,
        .heap_bytes = heap1 - heap0,
        .heap_bytes_per_grain = (heap1 - heap0) / mobile,
        .time_step = sim_world_time_step(w),
        .hash = sim_world_hash(w),
    };
    free(times);
    sim_world_destroy(w);
    return 0;
}

static int write_csv(const char *path, const char *machine, const Result *r, int n)
{
    char tmp[600];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f) {
        perror(tmp);
        return 1;
    }
    fprintf(
        f,
        "machine,code,law,mobile,fixed,steps,repeats,best_s,median_s,mps_best,mps_median,mps_cpu,"
        "contacts_per_grain,coordination,list_entries_per_grain,rebuilds_per_1000_steps,"
        "bytes_per_grain,bytes_per_contact,bytes_per_list_entry,heap_bytes_per_grain,dt_s\n");
    for (int k = 0; k < n; ++k)
        fprintf(f,
                "%s,sablier,%s,%d,%d,%ld,%d,%.6f,%.6f,%.3f,%.3f,%.3f,%.4f,%.4f,%.4f,%.3f,%.1f,%.1f,"
                "%.1f,"
                "%.1f,%.6g\n",
                machine, r[k].name, r[k].mobile, r[k].fixed, r[k].steps, r[k].repeats, r[k].best_s,
                r[k].median_s, r[k].mps_best, r[k].mps_median, r[k].mps_cpu,
                r[k].contacts_per_grain, r[k].coordination, r[k].entries_per_grain,
                r[k].rebuilds_per_1000, r[k].layout_bytes_per_grain, r[k].layout_bytes_per_contact,
                r[k].layout_bytes_per_entry, r[k].heap_bytes_per_grain, r[k].time_step);
    if (fclose(f) != 0 || rename(tmp, path) != 0) {
        perror(path);
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    Options o;
    if (parse_options(argc, argv, &o) != 0)
        return 2;
    char host[256] = "unknown";
    if (!o.machine) {
        gethostname(host, sizeof host - 1);
        o.machine = host;
    }

    int cached = 0;
    if (!o.fresh) {
        FILE *f = fopen(o.cache, "rb");
        if (f) {
            cached = 1;
            fclose(f);
        }
    }
    if (!cached) {
        int s = o.wide ? build_wide_pile(&o) : build_pile(&o);
        if (s != 0)
            return s;
    } else {
        fprintf(stderr, "bench_sim: reusing settled pile %s (--fresh rebuilds it)\n", o.cache);
    }

    if (o.lammps_data) {
        SimGrainSet g;
        SimWall *walls = NULL;
        int wc = 0;
        double t = 0.0;
        SimError err;
        if (sim_state_load(o.cache, &g, &walls, &wc, &t, &err) != SIM_OK) {
            fprintf(stderr, "bench_sim: %s\n", err.message);
            return 1;
        }
        int s = write_lammps_data(o.lammps_data, &g, base_def().materials[0].density);
        sim_grain_set_free(&g);
        free(walls);
        if (s != 0)
            return 1;
    }

    Result results[VARIANT_COUNT];
    int n = 0;
    for (int k = 0; k < VARIANT_COUNT; ++k) {
        if (o.only && !strstr(o.only, variants[k].name))
            continue;
        int s = run_variant(&o, &variants[k], &results[n]);
        if (s != 0)
            return s;
        ++n;
    }

    printf("# sablier %s, kernels %s, %d thread(s); %d mobile + %d fixed grains, dt %.4g s, %d x "
           "%ld steps "
           "after %d warm-up steps; M/s = million particle-steps per second (mobile grains "
           "only; best and median repeat of wall time, best of CPU time); rebuild/k = list "
           "rebuilds per 1000 steps; skin/d = Verlet skin at the end / mean diameter (%s); "
           "B/grain, B/contact from the array layout\n",
           SIM_VERSION, sim_isa_name(sim_isa()), o.threads, n ? results[0].mobile : 0,
           n ? results[0].fixed : 0, n ? results[0].time_step : 0.0, o.repeats, o.steps, o.warmup,
           o.skin > 0.0 ? "fixed by --skin" : "automatic");
    printf("%-13s %9s %9s %9s %9s %8s %8s %9s %9s %7s %9s %9s\n", "law", "best_M/s", "median",
           "cpu_M/s", "best_s", "cont/gr", "z", "list/gr", "rebuild/k", "skin/d", "B/grain",
           "B/contact");
    for (int k = 0; k < n; ++k)
        printf("%-13s %9.2f %9.2f %9.2f %9.4f %8.3f %8.3f %9.3f %9.2f %7.4f %9.0f %9.0f\n",
               results[k].name, results[k].mps_best, results[k].mps_median, results[k].mps_cpu,
               results[k].best_s, results[k].contacts_per_grain, results[k].coordination,
               results[k].entries_per_grain, results[k].rebuilds_per_1000, results[k].skin_d,
               results[k].layout_bytes_per_grain, results[k].layout_bytes_per_contact);
    for (int k = 0; k < n; ++k)
        printf("# %s: state hash after the timed runs 0x%016" PRIx64 "\n", results[k].name,
               results[k].hash);
    for (int k = 0; k < n; ++k) {
        if (results[k].heap_bytes > 0.0)
            printf("# %s: heap grown by create + warm-up: %.0f B (%.0f B per mobile grain)\n",
                   results[k].name, results[k].heap_bytes, results[k].heap_bytes_per_grain);
        else
            printf("# %s: heap growth not measurable (mallinfo2 reports nothing, e.g. under "
                   "ASan)\n",
                   results[k].name);
    }
    struct rusage usage;
    getrusage(RUSAGE_SELF, &usage);
    printf("# peak resident memory %ld kB (%.0f B per mobile grain)\n", usage.ru_maxrss,
           n ? 1024.0 * (double)usage.ru_maxrss / results[0].mobile : 0.0);
    if (o.csv && write_csv(o.csv, o.machine, results, n) != 0)
        return 3;
    return 0;
}
