/* SPDX-License-Identifier: MIT */
/* bench_app_dump: what a per-grain dump (app/output/dump.c, docs/dumps.md) costs.
 *
 * Part 1, per sample: the grains of a scene's first stage after `--settle` seconds, then each
 * writer timed over `--samples` frames of that state: the frame view alone (sim_world_frame:
 * the contact forces of the state; every writer needs it), one LAMMPS frame (default fields,
 * into a file), one grain .vtp, one contact .vtp; in ms per sample, ns per grain and bytes per
 * sample, against the time of one step of the same world.
 *
 * Part 2, in a run: the scene's first stage run through app_run (the stage runner, no rendering)
 * with no dump declared (twice: the noise), and with dumps declared (--set output.dump...),
 * round-robin over `--repeats`, best CPU time of each. "An undeclared dump costs nothing": the
 * two undeclared variants time alike, and a declared one costs its frames times the per-sample
 * figure.
 *
 * A benchmark reports; it asserts nothing about time.
 *
 * Usage: bench_app_dump [--scene S] [--settle T] [--samples K] [--repeats R] [--end T]
 *        (defaults: scenes/crater/small.scene, 1.0 s, 20 samples, 5 repeats, stage end 1.0 s) */
#include "output/dump.h"
#include "run/run.h"
#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static long file_size(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

typedef struct Sample {
    const char *name;
    double seconds; /* per sample, CPU */
    long bytes;     /* per sample */
} Sample;

/* Part 1: each writer on the same settled state, K times. */
static int per_sample(const Scene *scene, double settle, int samples)
{
    SimWorldDef def = scene_world_def(scene, 0);
    SimError e;
    SimWorld *w = sim_world_create(&def, &e);
    if (!w || sim_world_step(w, (long)(settle / sim_world_time_step(w)), &e) != SIM_OK) {
        fprintf(stderr, "bench_app_dump: cannot settle: %s\n", e.message);
        return -1;
    }
    double t0 = sim_clock_seconds(SIM_CLOCK_PROCESS);
    long steps = 200;
    sim_world_step(w, steps, &e);
    double step_s = (sim_clock_seconds(SIM_CLOCK_PROCESS) - t0) / (double)steps;
    SimFrame f;
    sim_world_frame(w, &f);
    char lammps[64], vtp[64], contacts[64];
    snprintf(lammps, sizeof lammps, "/tmp/bench_app_dump_%ld.lammpstrj", (long)getpid());
    snprintf(vtp, sizeof vtp, "/tmp/bench_app_dump_%ld.vtp", (long)getpid());
    snprintf(contacts, sizeof contacts, "/tmp/bench_app_dump_%ld_c.vtp", (long)getpid());
    const unsigned char fields[] = {APP_DUMP_ID, APP_DUMP_TYPE, APP_DUMP_X,     APP_DUMP_Y,
                                    APP_DUMP_VX, APP_DUMP_VY,   APP_DUMP_OMEGA, APP_DUMP_RADIUS,
                                    APP_DUMP_FX, APP_DUMP_FY};
    int n = (int)sizeof fields;
    Sample s[4] = {{"frame view (sim_world_frame)", 0, 0},
                   {"LAMMPS frame (10 fields)", 0, 0},
                   {"VTK grains .vtp (10 fields)", 0, 0},
                   {"VTK contacts .vtp", 0, 0}};
    FILE *out = fopen(lammps, "w");
    for (int k = 0; k < samples && out; ++k) {
        double a = sim_clock_seconds(SIM_CLOCK_PROCESS);
        sim_world_frame(w, &f);
        double b = sim_clock_seconds(SIM_CLOCK_PROCESS);
        app_dump_lammps_frame(out, &f, fields, n, &scene->def, NULL);
        double c = sim_clock_seconds(SIM_CLOCK_PROCESS);
        app_dump_vtp_grains(vtp, &f, fields, n, &scene->def, 0);
        double d = sim_clock_seconds(SIM_CLOCK_PROCESS);
        app_dump_vtp_contacts(contacts, &f, 0);
        double e2 = sim_clock_seconds(SIM_CLOCK_PROCESS);
        s[0].seconds += b - a;
        s[1].seconds += c - b;
        s[2].seconds += d - c;
        s[3].seconds += e2 - d;
    }
    if (out)
        fclose(out);
    s[1].bytes = file_size(lammps) / samples;
    s[2].bytes = file_size(vtp);
    s[3].bytes = file_size(contacts);
    printf("per sample: %d grains, %d contacts, one step %.3f ms (CPU), %d samples\n", f.count,
           f.contact_count, 1e3 * step_s, samples);
    printf("%-30s %10s %12s %10s %14s\n", "writer", "ms/sample", "ns/grain", "kB/sample",
           "steps' worth");
    for (int k = 0; k < 4; ++k) {
        double per = s[k].seconds / samples;
        printf("%-30s %10.3f %12.1f %10.1f %14.1f\n", s[k].name, 1e3 * per, 1e9 * per / f.count,
               s[k].bytes / 1024.0, per / step_s);
    }
    remove(lammps);
    remove(vtp);
    remove(contacts);
    sim_world_destroy(w);
    return 0;
}

typedef struct RunVariant {
    const char *name;
    const char *sets[4];
    int set_count;
} RunVariant;

/* Part 2: the first stage through the runner with and without dumps. */
static int in_run(const char *path, double end, int repeats)
{
    char end_set[64], skip[SCENE_MAX_STAGES][96];
    snprintf(end_set, sizeof end_set, "time.end=%g", end);
    const RunVariant variants[] = {
        {"no dump", {NULL}, 0},
        {"no dump (again)", {NULL}, 0},
        {"lammps every 0.1 s", {"output.dump.every=0.1"}, 1},
        {"vtk+contacts every 0.1 s", {"output.dump.every=0.1", "output.dump.format=[vtk]"}, 2},
        {"lammps+vtk every 0.01 s",
         {"output.dump.every=0.01", "output.dump.format=[lammps,vtk]"},
         2},
    };

    enum { V = sizeof variants / sizeof variants[0] };

    double best[V];
    long frames[V];
    char dir[64];
    snprintf(dir, sizeof dir, "/tmp/bench_app_dump_run_%ld", (long)getpid());
    for (int v = 0; v < V; ++v)
        best[v] = 1e30;
    char err[4096];
    Scene *probe = scene_load(path, NULL, 0, err, sizeof err);
    if (!probe) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    int stages = probe->stage_count;
    for (int k = 1; k < stages; ++k)
        snprintf(skip[k], sizeof skip[k], "stages.%s.skip=true", probe->stages[k].name);
    char first_end[96];
    snprintf(first_end, sizeof first_end, "stages.%s.time.end=%g", probe->stages[0].name, end);
    scene_free(probe);
    for (int r = 0; r < repeats; ++r)
        for (int v = 0; v < V; ++v) {
            const char *sets[4 + SCENE_MAX_STAGES + 2];
            int n = 0;
            sets[n++] = end_set;
            sets[n++] = first_end;
            for (int k = 1; k < stages; ++k)
                sets[n++] = skip[k];
            for (int j = 0; j < variants[v].set_count; ++j)
                sets[n++] = variants[v].sets[j];
            Scene *scene = scene_load(path, sets, n, err, sizeof err);
            if (!scene) {
                fprintf(stderr, "%s\n", err);
                return -1;
            }
            frames[v] =
                scene->output.dump[0].formats
                    ? app_dump_frame_bound(&scene->output.dump[0], end, scene->stages[0].time_step)
                    : 0;
            AppRunOptions o = app_run_options_default();
            o.out_dir = dir;
            o.quiet = 1;
            o.render_off = 1;
            double t0 = sim_clock_seconds(SIM_CLOCK_PROCESS);
            int rc = app_run(scene, &o);
            double t = sim_clock_seconds(SIM_CLOCK_PROCESS) - t0;
            scene_free(scene);
            if (rc != 0)
                return -1;
            if (t < best[v])
                best[v] = t;
        }
    printf("\nin a run: the first stage of %s for %g s, best CPU time of %d repeats\n", path, end,
           repeats);
    printf("%-28s %10s %8s %12s %14s\n", "variant", "run CPU s", "frames", "vs no dump",
           "ms per frame");
    for (int v = 0; v < V; ++v) {
        double extra = best[v] - best[0];
        printf("%-28s %10.3f %8ld %+11.2f%%", variants[v].name, best[v], frames[v],
               100.0 * extra / best[0]);
        if (frames[v])
            printf(" %14.3f\n", 1e3 * extra / (double)frames[v]);
        else
            printf(" %14s\n", "-");
    }
    char command[128];
    snprintf(command, sizeof command, "rm -rf '%s'", dir);
    return system(command) == 0 ? 0 : -1;
}

int main(int argc, char **argv)
{
    const char *path = "scenes/crater/small.scene";
    double settle = 1.0, end = 1.0;
    int samples = 20, repeats = 5;
    for (int a = 1; a + 1 < argc; a += 2) {
        if (strcmp(argv[a], "--scene") == 0)
            path = argv[a + 1];
        else if (strcmp(argv[a], "--settle") == 0)
            settle = atof(argv[a + 1]);
        else if (strcmp(argv[a], "--samples") == 0)
            samples = atoi(argv[a + 1]);
        else if (strcmp(argv[a], "--repeats") == 0)
            repeats = atoi(argv[a + 1]);
        else if (strcmp(argv[a], "--end") == 0)
            end = atof(argv[a + 1]);
    }
    if (samples < 1 || repeats < 1 || !(end > 0.0)) {
        fprintf(stderr, "usage: bench_app_dump [--scene S] [--settle T] [--samples K] "
                        "[--repeats R] [--end T]\n");
        return 2;
    }
    char err[4096];
    Scene *scene = scene_load(path, NULL, 0, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    int rc = per_sample(scene, settle, samples);
    scene_free(scene);
    if (rc == 0)
        rc = in_run(path, end, repeats);
    return rc == 0 ? 0 : 1;
}
