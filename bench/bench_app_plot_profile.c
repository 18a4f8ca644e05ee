/* SPDX-License-Identifier: MIT */
/* bench_app_plot_profile: the time sablier takes to draw a run's profile.csv (the free-surface
 * profiles of 000 fig. 7.30, as `sablier run` draws profiles.png) at single-column size, as PNG
 * and PDF, through the same chart code and renderer hook as the sablier command. Compared with
 * matplotlib by bench/plot_vs_matplotlib.sh (docs/figures.md#sablier-and-matplotlib).
 *
 * Usage: bench_app_plot_profile RUN_DIR OUT_DIR [REPEATS]
 * RUN_DIR holds profile.csv and scene.resolved.cfg (a crater run's folder); writes
 * OUT_DIR/profiles.png and OUT_DIR/profiles.pdf, and prints the mean wall time per figure. */
#include "cli/render_glue.h"
#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>

#include "crater/crater.h"

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: bench_app_plot_profile RUN_DIR OUT_DIR [REPEATS]\n");
        return 2;
    }
    int repeats = argc > 3 ? atoi(argv[3]) : 20;
    char path[4096], err[2048] = "";
    snprintf(path, sizeof path, "%s/scene.resolved.cfg", argv[1]);
    const char *sets[] = {"render.style=\"single_column\"", "render.plot_format=\"pdf\""};
    Scene *scene = scene_load(path, sets, 2, err, sizeof err);
    if (!scene || repeats < 1) {
        fprintf(stderr, "bench_app_plot_profile: %s\n", scene ? "REPEATS must be >= 1" : err);
        return 2;
    }
    double t0 = sim_clock_seconds(SIM_CLOCK_WALL);
    AppCraterChart *chart = malloc(sizeof *chart);
    int rc = chart ? 0 : 1;
    for (int k = 0; k < repeats && rc == 0; ++k) {
        /* read and drawn each time, as a plotting script does */
        app_crater_chart_init(chart, 1, 1, "free-surface profiles");
        chart->print = &scene->style;
        snprintf(path, sizeof path, "%s/profiles.png", argv[2]);
        if (app_crater_chart_profiles_run(chart, 0, argv[1], 8, NULL) != 0 ||
            app_crater_chart_write(chart, app_render_glue(), path, err, sizeof err) != 0) {
            fprintf(stderr, "bench_app_plot_profile: %s\n", err[0] ? err : "no profile.csv");
            rc = 1;
        }
        app_crater_chart_free(chart);
    }
    double t = (sim_clock_seconds(SIM_CLOCK_WALL) - t0) / repeats;
    if (rc == 0)
        printf("sablier: %.1f ms per figure (profile.csv read, PNG and PDF written), %d repeats\n",
               1e3 * t, repeats);
    free(chart);
    scene_free(scene);
    return rc;
}
