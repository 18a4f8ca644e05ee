/* SPDX-License-Identifier: MIT */
/* bench_measures: what a declared measure costs (docs/measures.md), and that an undeclared one
 * costs nothing.
 *
 * 1. Runs of one scene through the stage runner (app_run, no rendering): a box of grains raining
 *    onto a floor and resting, 1000 grains, 20000 steps, with no measure, then with one measure of
 *    each kind. The run without measures is timed twice (the noise); each variant's extra time
 *    divided by its samples is the cost per sample (per step for the flux counter, updated every
 *    step). Variants are timed round-robin, best of the repeats, wall time.
 * 2. The sim calls alone on the settled state: sim_world_frame + sim_coarse_add per sample for
 *    each geometry, with and without contacts, and sim_flux_update per call.
 *
 * A benchmark reports; it asserts nothing about time.
 *
 * Usage: bench_measures [--repeats K] */
#include "run/run.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct Variant {
    const char *name;
    const char *measures; /* the scene's top-level measures list, "" = none */
    double samples;       /* samples (or flux updates) the run takes */
    double best;          /* s */
} Variant;

static int write_scene(const char *path, const char *measures)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fprintf(f, "name = \"bench_measures\"; seed = 1; mass_model = \"disk\";\n"
               "effects = []; gravity = [0.0, -1.0]; time = { dt = 1e-3; end = 20.0; };\n"
               "species = ( { name = \"grain\"; density = 1.27323954473516; k_n = 2000.0; "
               "critical_fraction = 0.9; } );\n"
               "walls = ( { from = [0.0, 0.0]; to = [30.0, 0.0]; }, { from = [0.0, 0.0]; "
               "to = [0.0, 80.0]; }, { from = [30.0, 0.0]; to = [30.0, 80.0]; } );\n"
               "grains = { rain = { x0 = 0.6; x1 = 29.4; y0 = 1.0; y1 = 78.0; radius_mean = 0.5; "
               "polydispersity = 0.08; max_count = 1000; }; };\n");
    fprintf(f,
            "%s\nstages = ( { name = \"rain\"; time = { end = 20.0; }; } );\n"
            "output = { energy_every = 0.5; };\n",
            measures);
    return fclose(f) == 0 ? 0 : -1;
}

static double run_once(const char *scene_path, const char *out)
{
    char err[1024];
    Scene *scene = scene_load(scene_path, NULL, 0, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return -1.0;
    }
    AppRunOptions o = app_run_options_default();
    o.out_dir = out;
    o.quiet = 1;
    o.render_off = 1;
    double t0 = sim_clock_seconds(SIM_CLOCK_WALL);
    int rc = app_run(scene, &o);
    double t1 = sim_clock_seconds(SIM_CLOCK_WALL);
    scene_free(scene);
    return rc == 0 ? t1 - t0 : -1.0;
}

/* Part 2: the sim calls on the settled state of the last run. */
static void sim_costs(const char *state, int repeats)
{
    SimWorldDef def = sim_world_def_default();
    def.species_count = 1;
    def.materials[0] = sim_material_default();
    def.mass_model = SIM_MASS_DISK;
    def.time_step = 1e-3;
    def.max_dt_fraction = 0.0;
    SimError e;
    SimWorld *w = sim_world_load(state, &def, &e);
    if (!w) {
        fprintf(stderr, "bench_measures: %s\n", e.message);
        return;
    }
    int n = sim_world_grain_count(w);
    double *mass = malloc((size_t)n * sizeof *mass);
    sim_world_masses(w, mass);
    printf("\nsim calls on the settled state (%d grains), best of %d x 20 calls:\n", n, repeats);

    struct {
        const char *name;
        SimCoarseGeometry geometry;
        int contacts, nx, ny;
    } kinds[] = {{"frame only (sim_world_frame)", SIM_COARSE_GRID, -1, 0, 0},
                 {"profile_y, no contacts", SIM_COARSE_PROFILE_Y, 0, 1, 80},
                 {"profile_y, with contacts", SIM_COARSE_PROFILE_Y, 1, 1, 80},
                 {"grid 30x40, no contacts", SIM_COARSE_GRID, 0, 30, 40},
                 {"grid 30x40, with contacts", SIM_COARSE_GRID, 1, 30, 40},
                 {"grid 60x80, with contacts", SIM_COARSE_GRID, 1, 60, 80}};

    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; ++k) {
        SimCoarseDef d = sim_coarse_def_default();
        d.geometry = kinds[k].geometry;
        d.width = 2.0;
        d.contacts = kinds[k].contacts > 0;
        d.x0 = d.y0 = 0.0;
        d.x1 = 30.0;
        d.y1 = 40.0;
        d.nx = kinds[k].nx > 0 ? kinds[k].nx : 1;
        d.ny = kinds[k].ny > 0 ? kinds[k].ny : 1;
        d.cell_x = 30.0 / d.nx;
        d.cell_y = 40.0 / d.ny;
        SimCoarse *cg = kinds[k].contacts >= 0 ? sim_coarse_create(&d, NULL) : NULL;
        double best = 1e30;
        for (int r = 0; r < repeats; ++r) {
            double t0 = sim_clock_seconds(SIM_CLOCK_WALL);
            for (int s = 0; s < 20; ++s) {
                SimFrame f;
                sim_world_frame(w, &f);
                if (cg)
                    sim_coarse_add(cg, &f, mass, 0.0, 0.0);
            }
            best = fmin(best, (sim_clock_seconds(SIM_CLOCK_WALL) - t0) / 20.0);
        }
        printf("  %-30s %8.3f ms per sample\n", kinds[k].name, 1e3 * best);
        sim_coarse_destroy(cg);
    }
    SimFlux *flux = sim_flux_create(0.0, 10.0, 30.0, 10.0);
    double best = 1e30;
    for (int r = 0; r < repeats; ++r) {
        double t0 = sim_clock_seconds(SIM_CLOCK_WALL);
        for (int s = 0; s < 1000; ++s)
            sim_flux_update(flux, w);
        best = fmin(best, (sim_clock_seconds(SIM_CLOCK_WALL) - t0) / 1000.0);
    }
    double t0 = sim_clock_seconds(SIM_CLOCK_WALL);
    sim_world_step(w, 200, NULL);
    double step = (sim_clock_seconds(SIM_CLOCK_WALL) - t0) / 200.0;
    printf("  %-30s %8.3f us per update (a step: %.3f us)\n", "flux counter", 1e6 * best,
           1e6 * step);
    sim_flux_destroy(flux);
    free(mass);
    sim_world_destroy(w);
}

int main(int argc, char **argv)
{
    int repeats = 3;
    for (int i = 1; i + 1 < argc; ++i)
        if (strcmp(argv[i], "--repeats") == 0)
            repeats = atoi(argv[++i]);
    char dir[128], scene[200], out[200];
    snprintf(dir, sizeof dir, "/tmp/sablier_bench_measures_%ld", (long)getpid());
    snprintf(scene, sizeof scene, "%s/bench.scene", dir);
    snprintf(out, sizeof out, "%s/out", dir);
    char command[300];
    snprintf(command, sizeof command, "mkdir -p '%s'", dir);
    if (system(command) != 0)
        return 1;
    Variant variants[] = {
        {"no measure", "", 0, 1e30},
        {"no measure (again: noise)", "", 0, 1e30},
        {"profile_y phi rho vx vy",
         "measures = ( { name = \"m\"; kind = \"profile_y\"; width = 2.0; "
         "fields = [\"phi\", \"rho\", \"vx\", \"vy\"]; every = 0.1; } );",
         201, 1e30},
        {"profile_y syy sxy phi z",
         "measures = ( { name = \"m\"; kind = \"profile_y\"; width = 2.0; "
         "fields = [\"syy\", \"sxy\", \"phi\", \"z\"]; every = 0.1; } );",
         201, 1e30},
        {"grid 30x80 phi vx vy syy",
         "measures = ( { name = \"m\"; kind = \"grid\"; width = 2.0; bin = 1.0; "
         "fields = [\"phi\", \"vx\", \"vy\", \"syy\"]; every = 0.1; } );",
         201, 1e30},
        {"flux (every step)",
         "measures = ( { name = \"m\"; kind = \"flux\"; "
         "line = [0.0, 10.0, 30.0, 10.0]; every = 0.1; } );",
         20000, 1e30},
    };
    int count = (int)(sizeof variants / sizeof variants[0]);
    for (int r = 0; r < repeats; ++r)
        for (int v = 0; v < count; ++v) {
            if (write_scene(scene, variants[v].measures) != 0)
                return 1;
            double t = run_once(scene, out);
            if (t < 0.0)
                return 1;
            variants[v].best = fmin(variants[v].best, t);
        }
    double base = fmin(variants[0].best, variants[1].best);
    printf("sablier run of a 1000-grain box, 20000 steps, best of %d (wall):\n", repeats);
    for (int v = 0; v < count; ++v) {
        printf("  %-30s %7.3f s", variants[v].name, variants[v].best);
        if (variants[v].samples > 0)
            printf("  +%6.3f s, %8.3f ms per %s", variants[v].best - base,
                   1e3 * (variants[v].best - base) / variants[v].samples,
                   variants[v].samples > 1000 ? "step" : "sample");
        printf("\n");
    }
    char state[300];
    snprintf(state, sizeof state, "%s/rain.state", out);
    sim_costs(state, repeats);
    snprintf(command, sizeof command, "rm -rf '%s'", dir);
    return system(command) == 0 ? 0 : 1;
}
