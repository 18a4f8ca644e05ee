/* SPDX-License-Identifier: MIT */
/* bench_effects: what each physical effect costs. The same settled pile (thesis 000 material,
 * rain-like deposition in a box of fixed grains) is stepped with each effect declared or not, and
 * the time per particle-step is compared with the baseline (no effect declared, no effect
 * parameter set).
 *
 * "An undeclared effect costs nothing" is tested by variants that set an effect's parameters in
 * the material (friction, rolling) but do not declare it: they must time like the baseline within
 * the noise, which is estimated by a second, identical baseline. Each declared effect is then
 * timed:
 *   friction          regularised Coulomb (000 eq. 3.28) and the tangential spring (004 eqs.
 *                     1.12-1.13); both switch rotation on;
 *   rolling           chord law (004 ch. 4) on top of regularised friction;
 *   periodic_x        periodic in x over the box (the side columns meet across the seam);
 *   vibration         declared with the floor bound to a motion of amplitude 0 (the stage runs,
 *                     nothing moves: pure overhead), and with the floor shaking (0.05 d, 10 Hz);
 *   fluid_drag        a linear drag F = -c m v (c = 0.1 1/s) as the body-force stage; the real
 *                     fluid model comes later, this measures the stage's overhead;
 *   removal           a sink below the floor (never reached);
 *   onset_event       contact.onset = "event" (docs/accuracy.md eqs. A1-A5), alone and with
 *                     regularised friction: the cost of the option per particle-step.
 *
 * Variants are timed round-robin (each repeat times every variant once), so slow drifts of the
 * machine load hit all of them alike; the best of the repeats is reported, by process CPU time and
 * by wall time. Each variant runs on its own world created from the same settled state.
 *
 * A benchmark reports; it asserts nothing about time.
 *
 * Usage: bench_effects [--grains N] [--steps M] [--repeats K] [--csv PATH] */
#include "sim/sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const double r_max = 0.105; /* m, 000 §4.3 boundary grains */
static const double r_med = 0.08;  /* m */

typedef struct Variant {
    const char *name;
    unsigned effects;
    int params_set;  /* friction and rolling parameters in the material */
    int motion;      /* 0: none, 1: amplitude 0 on the floor, 2: floor shaking */
    int rolling_law; /* SimRollingLaw */
    SimTangentialLaw tangential;
    const char *compare; /* the variant it differs from by this effect */
    SimOnset onset;      /* contact.onset (docs/accuracy.md eqs. A1-A5) */
} Variant;

static const Variant variants[] = {
    {"baseline", 0u, 0, 0, SIM_ROLLING_OFF, SIM_TANGENTIAL_REGULARISED, "baseline_again",
     SIM_ONSET_STEP},
    {"baseline_again", 0u, 0, 0, SIM_ROLLING_OFF, SIM_TANGENTIAL_REGULARISED, "baseline",
     SIM_ONSET_STEP},
    {"params_undeclared", 0u, 1, 0, SIM_ROLLING_CHORD, SIM_TANGENTIAL_REGULARISED, "baseline",
     SIM_ONSET_STEP},
    {"friction_regularised", SIM_EFFECT_FRICTION, 1, 0, SIM_ROLLING_OFF, SIM_TANGENTIAL_REGULARISED,
     "baseline", SIM_ONSET_STEP},
    {"friction_spring", SIM_EFFECT_FRICTION, 1, 0, SIM_ROLLING_OFF, SIM_TANGENTIAL_SPRING,
     "baseline", SIM_ONSET_STEP},
    {"friction_rolling_undeclared", SIM_EFFECT_FRICTION, 1, 0, SIM_ROLLING_CHORD,
     SIM_TANGENTIAL_REGULARISED, "friction_regularised", SIM_ONSET_STEP},
    {"friction_rolling", SIM_EFFECT_FRICTION | SIM_EFFECT_ROLLING, 1, 0, SIM_ROLLING_CHORD,
     SIM_TANGENTIAL_REGULARISED, "friction_regularised", SIM_ONSET_STEP},
    {"periodic_x", SIM_EFFECT_PERIODIC_X, 0, 0, SIM_ROLLING_OFF, SIM_TANGENTIAL_REGULARISED,
     "baseline", SIM_ONSET_STEP},
    {"vibration_still", SIM_EFFECT_VIBRATION, 0, 1, SIM_ROLLING_OFF, SIM_TANGENTIAL_REGULARISED,
     "baseline", SIM_ONSET_STEP},
    {"vibration_shaking", SIM_EFFECT_VIBRATION, 0, 2, SIM_ROLLING_OFF, SIM_TANGENTIAL_REGULARISED,
     "baseline", SIM_ONSET_STEP},
    {"fluid_drag", SIM_EFFECT_FLUID_DRAG, 0, 0, SIM_ROLLING_OFF, SIM_TANGENTIAL_REGULARISED,
     "baseline", SIM_ONSET_STEP},
    {"removal", SIM_EFFECT_REMOVAL, 0, 0, SIM_ROLLING_OFF, SIM_TANGENTIAL_REGULARISED, "baseline",
     SIM_ONSET_STEP},
    {"onset_event", 0u, 0, 0, SIM_ROLLING_OFF, SIM_TANGENTIAL_REGULARISED, "baseline",
     SIM_ONSET_EVENT},
    {"friction_onset_event", SIM_EFFECT_FRICTION, 1, 0, SIM_ROLLING_OFF, SIM_TANGENTIAL_REGULARISED,
     "friction_regularised", SIM_ONSET_EVENT},
};

enum { VARIANT_COUNT = (int)(sizeof variants / sizeof variants[0]) };

typedef struct Timing {
    double best_cpu, best_wall;
    double samples[64];
    int count;
    int mobile;
    double contacts_per_grain;
} Timing;

/* Linear drag F = -c m v: a stand-in body-force stage for SIM_EFFECT_FLUID_DRAG. */
static void linear_drag(void *context, const SimBodyForceView *view)
{
    const double c = *(const double *)context; /* 1/s */
    for (int i = 0; i < view->count; ++i) {
        view->fx[i] -= c * view->mass[i] * view->vx[i];
        view->fy[i] -= c * view->mass[i] * view->vy[i];
    }
}

static double drag_rate = 0.1; /* 1/s */

static SimWorldDef material_def(int params_set)
{
    SimWorldDef def = sim_world_def_default(); /* 000 §4.3 material */
    def.mass_model = SIM_MASS_SPHERE;
    def.steps_per_contact = 50.0;
    SimMaterial *m = &def.materials[0];
    if (params_set) {
        m->friction = 0.5;
        m->tangential_damping = 5.0;
        m->tangential_stiffness = 5.25e5;
        m->rolling_friction = 0.01;
        m->rolling_stiffness = 10.0;
    } else {
        m->friction = 0.0;
        m->tangential_damping = 0.0;
        m->tangential_stiffness = 0.0;
        m->rolling_friction = 0.0;
        m->rolling_stiffness = 0.0;
    }
    return def;
}

static int compare(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    int grains = 2000, repeats = 9;
    long steps = 400;
    const char *csv = "effects.csv";
    for (int a = 1; a < argc; ++a) {
        if (strcmp(argv[a], "--grains") == 0 && a + 1 < argc)
            grains = atoi(argv[++a]);
        else if (strcmp(argv[a], "--steps") == 0 && a + 1 < argc)
            steps = atol(argv[++a]);
        else if (strcmp(argv[a], "--repeats") == 0 && a + 1 < argc)
            repeats = atoi(argv[++a]);
        else if (strcmp(argv[a], "--csv") == 0 && a + 1 < argc)
            csv = argv[++a];
        else {
            fprintf(stderr, "usage: bench_effects [--grains N] [--steps M] [--repeats K] "
                            "[--csv PATH]\n");
            return 2;
        }
    }
    if (repeats > 64)
        repeats = 64;

    /* Settled pile: 000 geometry, box about as wide as the pile is high. */
    const int columns = (int)ceil(sqrt(grains * SIM_PI * r_med * r_med / 0.8) / (2 * r_max));
    const double width = columns * 2.0 * r_max;
    SimGrainBuffer buffer;
    sim_grain_buffer_init(&buffer);
    int floor_begin = buffer.count;
    sim_build_fixed_row(&buffer, 0.0, width, 0.0, r_max, 0, -1);
    int floor_end = buffer.count;
    /* Side columns three pile heights tall: the rain lattice is about 2.4 times as tall as the
     * settled pile. */
    const double pile_height = grains * SIM_PI * r_med * r_med / (0.8 * width);
    sim_build_fixed_column(&buffer, 0.0, 2 * r_max, 3.0 * pile_height + 4 * r_max, r_max, 0, -1);
    sim_build_fixed_column(&buffer, width, 2 * r_max, 3.0 * pile_height + 4 * r_max, r_max, 0, -1);
    SimRainDef rain =
        sim_rain_def_thesis000(1.5 * r_max, width - 1.5 * r_max, 1.5 * r_max, 1000 * r_max, grains);
    SimRng rng;
    sim_rng_seed(&rng, 7);
    sim_build_rain(&buffer, &rain, &rng);
    SimWorldDef def = material_def(1);
    def.effects = SIM_EFFECT_FRICTION;
    def.grains = sim_grain_buffer_view(&buffer);
    SimError err;
    SimWorld *pile = sim_world_create(&def, &err);
    if (!pile) {
        fprintf(stderr, "bench_effects: %s: %s\n", err.field, err.message);
        return 2;
    }
    const double settle = 2.0 + 0.02 * columns; /* s */
    if (sim_world_step(pile, (long)(settle / sim_world_time_step(pile)), &err) != SIM_OK) {
        fprintf(stderr, "bench_effects: settle: %s\n", err.message);
        return 1;
    }
    sim_world_freeze(pile);
    char state[256];
    snprintf(state, sizeof state, "/tmp/sablier-bench-effects-%ld.state", (long)getpid());
    if (sim_world_save(pile, state, &err) != SIM_OK) {
        fprintf(stderr, "bench_effects: %s\n", err.message);
        return 3;
    }
    sim_world_destroy(pile);
    sim_grain_buffer_free(&buffer);

    SimGrainSet settled;
    SimWall *walls;
    int wall_count;
    double t0;
    if (sim_state_load(state, &settled, &walls, &wall_count, &t0, &err) != SIM_OK) {
        fprintf(stderr, "bench_effects: %s\n", err.message);
        return 3;
    }
    remove(state);
    /* Floor grains get motion 0 in the vibration variants: the fixed row was built first, so its
     * ids are [floor_begin, floor_end). */
    int *motion_still = malloc((size_t)settled.count * sizeof *motion_still);
    if (!motion_still)
        return 1;
    for (int i = 0; i < settled.count; ++i) {
        uint32_t id = settled.id ? settled.id[i] : (uint32_t)i;
        motion_still[i] = (int)id >= floor_begin && (int)id < floor_end ? 0 : -1;
    }

    SimWorld *worlds[VARIANT_COUNT];
    Timing timing[VARIANT_COUNT];
    double dt = 0.0;
    for (int v = 0; v < VARIANT_COUNT; ++v) {
        const Variant *var = &variants[v];
        SimWorldDef d = material_def(var->params_set);
        d.effects = var->effects;
        d.contact.tangential = var->tangential;
        d.contact.rolling = (SimRollingLaw)var->rolling_law;
        d.contact.onset = var->onset;
        d.grains = settled;
        d.walls = walls;
        d.wall_count = wall_count;
        d.start_time = t0;
        if (var->motion) {
            d.grains.motion = motion_still;
            d.motion_count = 1;
            d.motions[0] = (SimMotion){.amplitude = var->motion == 2 ? 0.05 * 2 * r_med : 0.0,
                                       .frequency = 10.0,
                                       .direction_x = 0.0,
                                       .direction_y = 1.0};
        }
        if (var->effects & SIM_EFFECT_PERIODIC_X) {
            d.domain_x0 = -r_max;
            d.domain_x1 = width + r_max;
        }
        if (var->effects & SIM_EFFECT_FLUID_DRAG)
            d.body_force = (SimBodyForce){linear_drag, &drag_rate};
        if (var->effects & SIM_EFFECT_REMOVAL) {
            d.sink_count = 1;
            d.sinks[0] = (SimSink){.shape = SIM_SINK_BELOW, .level = -10.0 * r_max};
        }
        worlds[v] = sim_world_create(&d, &err);
        if (!worlds[v]) {
            fprintf(stderr, "bench_effects: %s: %s: %s\n", var->name, err.field, err.message);
            return 2;
        }
        dt = sim_world_time_step(worlds[v]);
        /* Warm-up: caches, lists, the first rebuilds. */
        if (sim_world_step(worlds[v], steps / 4 + 1, &err) != SIM_OK) {
            fprintf(stderr, "bench_effects: %s: %s\n", var->name, err.message);
            return 1;
        }
        timing[v] = (Timing){.best_cpu = INFINITY, .best_wall = INFINITY};
        timing[v].mobile = sim_world_mobile_count(worlds[v]);
    }
    double load[3] = {0};
    FILE *lf = fopen("/proc/loadavg", "r");
    if (lf) {
        if (fscanf(lf, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3)
            load[0] = NAN;
        fclose(lf);
    }
    fprintf(stderr, "# %d mobile grains, dt %.3g s, %ld steps x %d repeats, load %.2f\n",
            timing[0].mobile, dt, steps, repeats, load[0]);
    for (int r = 0; r < repeats; ++r)
        for (int v = 0; v < VARIANT_COUNT; ++v) {
            double c0 = sim_clock_seconds(SIM_CLOCK_PROCESS),
                   w0 = sim_clock_seconds(SIM_CLOCK_WALL);
            if (sim_world_step(worlds[v], steps, &err) != SIM_OK) {
                fprintf(stderr, "bench_effects: %s: %s\n", variants[v].name, err.message);
                return 1;
            }
            double c = sim_clock_seconds(SIM_CLOCK_PROCESS) - c0,
                   w = sim_clock_seconds(SIM_CLOCK_WALL) - w0;
            double work = (double)steps * timing[v].mobile;
            timing[v].best_cpu = fmin(timing[v].best_cpu, c / work);
            timing[v].best_wall = fmin(timing[v].best_wall, w / work);
            timing[v].samples[timing[v].count++] = c / work;
        }
    for (int v = 0; v < VARIANT_COUNT; ++v) {
        SimEnergy e = sim_world_energy(worlds[v]);
        timing[v].contacts_per_grain = (double)e.contacts / e.mobile;
        sim_world_destroy(worlds[v]);
    }
    sim_grain_set_free(&settled);
    free(walls);
    free(motion_still);

    /* Noise: relative spread between the two identical baselines, and within-variant spread. */
    const double base = timing[0].best_cpu;
    const double noise = fabs(timing[1].best_cpu - timing[0].best_cpu) / base;
    char tmp[1024];
    snprintf(tmp, sizeof tmp, "%s.tmp", csv);
    FILE *f = fopen(tmp, "w");
    if (!f) {
        perror(tmp);
        return 3;
    }
    fprintf(f, "variant,effects,params_set,compared_with,mobile,steps,repeats,ns_per_particle_"
               "step_cpu,ns_per_particle_step_wall,median_ns_cpu,spread,vs_baseline,vs_compared,"
               "contacts_per_grain,time_step_s,load_1min\n");
    printf("%-28s %9s %9s %9s %8s %11s %11s %9s\n", "variant", "ns_cpu", "ns_wall", "median",
           "spread", "vs_base", "vs_compared", "cont/gr");
    for (int v = 0; v < VARIANT_COUNT; ++v) {
        Timing *t = &timing[v];
        qsort(t->samples, (size_t)t->count, sizeof t->samples[0], compare);
        double median = t->samples[t->count / 2];
        double spread = (median - t->best_cpu) / t->best_cpu;
        int c = 0;
        for (int k = 0; k < VARIANT_COUNT; ++k)
            if (strcmp(variants[k].name, variants[v].compare) == 0)
                c = k;
        double vs_base = t->best_cpu / base - 1.0;
        double vs_cmp = t->best_cpu / timing[c].best_cpu - 1.0;
        char effects[128] = "";
        for (unsigned bit = 1; bit < 64u; bit <<= 1)
            if (variants[v].effects & bit) {
                if (effects[0])
                    strcat(effects, "+");
                strcat(effects, sim_effect_name(bit));
            }
        fprintf(f, "%s,%s,%d,%s,%d,%ld,%d,%.3f,%.3f,%.3f,%.4f,%.4f,%.4f,%.3f,%.4g,%.2f\n",
                variants[v].name, effects[0] ? effects : "none", variants[v].params_set,
                variants[v].compare, t->mobile, steps, repeats, 1e9 * t->best_cpu,
                1e9 * t->best_wall, 1e9 * median, spread, vs_base, vs_cmp, t->contacts_per_grain,
                dt, load[0]);
        printf("%-28s %9.2f %9.2f %9.2f %7.1f%% %+10.1f%% %+10.1f%% %9.3f\n", variants[v].name,
               1e9 * t->best_cpu, 1e9 * t->best_wall, 1e9 * median, 100.0 * spread, 100.0 * vs_base,
               100.0 * vs_cmp, t->contacts_per_grain);
    }
    printf("# noise: the two identical baselines differ by %.1f%%\n", 100.0 * noise);
    if (fclose(f) != 0 || rename(tmp, csv) != 0) {
        perror(csv);
        return 3;
    }
    return 0;
}
