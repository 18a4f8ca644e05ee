/* SPDX-License-Identifier: MIT */
/* bench_render_accuracy_plot: the work-precision figure of bench_accuracy. Reads its CSV and draws
 * error against CPU time per simulated second (log-log), one curve per integrator, the default
 * (velocity Verlet) drawn thick and named "(default)", one panel per measurement. The curves of
 * the event-aware onset (integrator "NAME/event", docs/accuracy.md eqs. A1-A5) are drawn next to
 * the old ones.
 *
 * Usage: bench_render_accuracy_plot accuracy.csv out.png [out.pdf ...] */
#include "render/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_POINTS = 64, PANEL_COUNT = 6, CURVE_COUNT = SIM_INTEGRATOR_COUNT + 2 };

typedef struct Curve {
    int count;
    double x[MAX_POINTS], y[MAX_POINTS];
} Curve;

static const struct {
    const char *test, *title, *y_label;
} panels[PANEL_COUNT] = {
    {"restitution_0.5", "(a) restitution, e_n = 0.5", "|e - e_n| (worst of 16 phases)"},
    {"restitution_0.9", "(b) restitution, e_n = 0.9", "|e - e_n| (worst of 16 phases)"},
    {"contact_time_0.5", "(c) contact duration, e_n = 0.5", "|t_c - t_n| / t_n"},
    {"energy_drift", "(d) energy drift, 100 elastic bounces", "|E_end - E_0| / E_bounce"},
    {"profile", "(e) crater free-surface profile", "max |h - h_ref| / d"},
    {"crater_height", "(f) crater height", "|h_crater - h_ref| / d"},
};

/* The first SIM_INTEGRATOR_COUNT curves are in SimIntegrator order (the default onset). */
static const char *const names[CURVE_COUNT] = {
    "velocity_verlet",       "symplectic_euler",      "stormer_verlet", "gear", "rk4",
    "velocity_verlet/event", "symplectic_euler/event"};
static const char *const labels[CURVE_COUNT] = {"velocity Verlet (default)",
                                                "symplectic Euler",
                                                "Stormer-Verlet",
                                                "Gear",
                                                "RK4",
                                                "velocity Verlet, onset = event",
                                                "symplectic Euler, onset = event"};
static const uint32_t colours[CURVE_COUNT] = {0x000000, 0xd55e00, 0x009e73, 0x0072b2,
                                              0xcc79a7, 0xe69f00, 0x56b4e9};
static const RenderMarker markers[CURVE_COUNT] = {
    RENDER_MARKER_CIRCLE, RENDER_MARKER_SQUARE, RENDER_MARKER_TRIANGLE, RENDER_MARKER_CROSS,
    RENDER_MARKER_SQUARE, RENDER_MARKER_CIRCLE, RENDER_MARKER_TRIANGLE};

static Curve curves[PANEL_COUNT][CURVE_COUNT];

/* Splits a CSV line in place into at most `max` fields (no quoted commas before the last field). */
static int split(char *line, char **fields, int max)
{
    int n = 0;
    char *p = line;
    while (n < max) {
        fields[n++] = p;
        char *c = strchr(p, ',');
        if (!c)
            break;
        *c = '\0';
        p = c + 1;
    }
    return n;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: bench_render_accuracy_plot accuracy.csv out.png [out.pdf ...]\n");
        return 2;
    }
    FILE *f = fopen(argv[1], "r");
    if (!f) {
        perror(argv[1]);
        return 2;
    }
    char line[2048];
    int line_no = 0;
    while (fgets(line, sizeof line, f)) {
        ++line_no;
        if (line_no == 1)
            continue; /* header */
        char *fld[10];
        if (split(line, fld, 10) < 10) {
            fprintf(stderr, "%s:%d: expected at least 10 fields\n", argv[1], line_no);
            fclose(f);
            return 2;
        }
        /* test,integrator,default,steps_per_contact,time_step_s,status,measured,error,
         * cpu_s_per_sim_s_grain,... */
        if (strcmp(fld[5], "ok") != 0)
            continue;
        int p = -1, k = -1;
        for (int q = 0; q < PANEL_COUNT; ++q)
            if (strcmp(fld[0], panels[q].test) == 0)
                p = q;
        for (int q = 0; q < CURVE_COUNT; ++q)
            if (strcmp(fld[1], names[q]) == 0)
                k = q;
        if (p < 0 || k < 0)
            continue;
        Curve *c = &curves[p][k];
        if (c->count >= MAX_POINTS)
            continue;
        c->x[c->count] = atof(fld[8]);
        c->y[c->count] = atof(fld[7]);
        ++c->count;
    }
    fclose(f);

    RenderSeries series[PANEL_COUNT][CURVE_COUNT];
    RenderPanel panel[PANEL_COUNT];
    for (int p = 0; p < PANEL_COUNT; ++p) {
        /* Default drawn last, on top: symplectic Euler and Stormer-Verlet share its positions
         * (all three are leapfrog here) and would hide it. */
        int order[CURVE_COUNT] = {1, 2, 3, 4, 6, 5, 0};
        for (int s = 0; s < CURVE_COUNT; ++s) {
            int k = order[s];
            int is_default = k == SIM_INTEGRATOR_VELOCITY_VERLET, thick = is_default || k == 5;
            series[p][s] = (RenderSeries){.label = labels[k],
                                          .count = curves[p][k].count,
                                          .x = curves[p][k].x,
                                          .y = curves[p][k].y,
                                          .rgb = colours[k],
                                          .line = 1,
                                          .dashed = k == SIM_INTEGRATOR_STORMER_VERLET || k >= 5,
                                          .marker = markers[k],
                                          .line_width = thick ? 4.0 : 1.8,
                                          .marker_size = thick ? 10.0 : 7.0};
        }
        panel[p] = (RenderPanel){
            .title = panels[p].title,
            .x = {.label = "CPU s per simulated s per grain", .log = 1},
            .y = {.label = panels[p].y_label, .log = 1},
            .series_count = CURVE_COUNT,
            .series = series[p],
            .legend = p == 0 ? RENDER_LEGEND_LOWER_LEFT : RENDER_LEGEND_NONE,
        };
    }
    RenderPlot plot = {.width = 1800,
                       .height = 1150,
                       .rows = 2,
                       .cols = 3,
                       .panels = panel,
                       .title = "sablier work-precision: error against CPU time (bench_accuracy)",
                       .font_size = 17.0};
    RenderMeta meta = {.scene = "bench_accuracy", .seed = 2018, .comment = argv[1]};
    for (int a = 2; a < argc; ++a) {
        char err[256];
        if (render_plot_write(&plot, &meta, argv[a], err, sizeof err) != 0) {
            fprintf(stderr, "bench_render_accuracy_plot: %s: %s\n", argv[a], err);
            return 3;
        }
        printf("wrote %s\n", argv[a]);
    }
    return 0;
}
