/* SPDX-License-Identifier: MIT */
/* bench_render_cairo.c: Cairo figure speed at 1920x1080 for a packed bed of 7284 synthetic grains
 * (the size of the crater scene) with their force chains (~1.9 contacts per grain), grains
 * coloured by force with outlines, colour bar, time stamp and scale bar. Reports milliseconds per
 * figure, the minimum over repeats (target <= 100 ms), for drawing alone, for drawing in a movie's
 * two bands (render_cairo_draw_split: the lower rows in a helper thread; its CPU time against one
 * band's is what the split costs), the same for a square movie frame of the bed in a box twice
 * its height (the grains in the lower half, as in the crater's collapse), and for drawing plus
 * the PNG write.
 *
 *     bench_render_cairo [repeats]      (default 5; writes out/bench/bench_render_cairo.png)
 */
#include "render/render.h"

#include "../tests/render/fixture.h"

enum { GRAINS = 7284, WIDTH = 1920, HEIGHT = 1080 };

/* Trims mobile grains from the top of the bed (the end of the mobile block) until `target`
 * grains remain, keeping the fixed base row. */
static void trim(Fixture *f, int target)
{
    int excess = f->frame.count - target;
    if (excess <= 0)
        return;
    int mobile = f->frame.mobile_count, fixed = f->frame.count - mobile;
    int keep = mobile - excess;
    size_t n = (size_t)fixed;
    memmove(f->x + keep, f->x + mobile, n * sizeof *f->x);
    memmove(f->y + keep, f->y + mobile, n * sizeof *f->y);
    memmove(f->radius + keep, f->radius + mobile, n * sizeof *f->radius);
    memmove(f->angle + keep, f->angle + mobile, n * sizeof *f->angle);
    memmove(f->flags + keep, f->flags + mobile, n * sizeof *f->flags);
    f->frame.count = target;
    f->frame.mobile_count = keep;
    for (int i = 0; i < target; ++i) {
        f->id[i] = (uint32_t)i;
        f->force[i] = 0;
        f->species[i] = 0;
    }
    f->frame.contact_count = 0;
}

/* Best wall and process CPU seconds of `repeats` drawings (after one that warms caches and fonts),
 * in two bands when `helper` is given. */
static int time_draw(const Fixture *f, const RenderStyle *s, RenderHelper *helper, int repeats,
                     double *wall, double *cpu)
{
    *wall = *cpu = 1e30;
    for (int k = 0; k < repeats + 1; ++k) {
        RenderImage image;
        double c0 = sim_clock_seconds(SIM_CLOCK_PROCESS);
        double t0 = sim_clock_seconds(SIM_CLOCK_WALL);
        if (render_cairo_draw_split(&f->frame, s, &image, helper) != 0)
            return -1;
        double t1 = sim_clock_seconds(SIM_CLOCK_WALL);
        double c1 = sim_clock_seconds(SIM_CLOCK_PROCESS);
        render_image_free(&image);
        if (k > 0) {
            *wall = fmin(*wall, t1 - t0);
            *cpu = fmin(*cpu, c1 - c0);
        }
    }
    return 0;
}

static void report(const char *what, double wall, double cpu)
{
    printf("%-34s %8.1f %9.1f\n", what, 1e3 * wall, 1e3 * cpu);
}

int main(int argc, char **argv)
{
    int repeats = argc > 1 ? atoi(argv[1]) : 5;
    if (repeats < 1)
        repeats = 1;
    Fixture f;
    if (fixture_bed(&f, 118, 62, 0.001, 7) != 0) {
        fprintf(stderr, "out of memory\n");
        return 1;
    }
    trim(&f, GRAINS);
    /* Slack chosen for ~1.9 contacts per grain in this lattice. */
    fixture_find_contacts(&f, 0.135 * 0.001, 1.0);
    RenderStyle s = render_style_default();
    s.width = WIDTH;
    s.height = HEIGHT;
    s.color_by = RENDER_COLOR_FORCE;
    s.range_min = 0;
    s.range_max = 6;
    s.force_chains = 1;
    s.title = "bench: 7284 grains, strong force network";
    printf("grains %d (mobile %d), contacts %d (%.2f per grain), %dx%d\n", f.frame.count,
           f.frame.mobile_count, f.frame.contact_count,
           (double)f.frame.contact_count / f.frame.count, WIDTH, HEIGHT);
    /* Wall time, and process CPU time, which a busy shared machine disturbs less. */
    double best_draw, cpu_draw, best_split = 0, cpu_split = 0, best_png = 1e30, cpu_png = 1e30;
    RenderHelper *helper = render_helper_create();
    if (time_draw(&f, &s, NULL, repeats, &best_draw, &cpu_draw) != 0 ||
        (helper && time_draw(&f, &s, helper, repeats, &best_split, &cpu_split) != 0)) {
        fprintf(stderr, "draw failed\n");
        return 1;
    }
    /* A movie frame of a bed in its box (the crater's collapse): a square image whose view is
     * twice the bed's height, the grains in the lower half, drawn in two bands. */
    RenderStyle box = s;
    box.width = box.height = HEIGHT;
    box.view_x0 = box.view_y0 = 0;
    box.view_x1 = box.view_y1 = 2.2 * (f.frame.mobile_count / 118) * 0.001 * sqrt(3.0);
    double best_box = 0, cpu_box = 0, best_box_split = 0, cpu_box_split = 0;
    if (time_draw(&f, &box, NULL, repeats, &best_box, &cpu_box) != 0 ||
        (helper && time_draw(&f, &box, helper, repeats, &best_box_split, &cpu_box_split) != 0)) {
        fprintf(stderr, "draw failed\n");
        return 1;
    }
    render_helper_destroy(helper);
    mkdir("out", 0777);
    mkdir("out/bench", 0777);
    for (int k = 0; k < repeats + 1; ++k) { /* first round warms caches and fonts */
        char err[256];
        double c2 = sim_clock_seconds(SIM_CLOCK_PROCESS);
        double t2 = sim_clock_seconds(SIM_CLOCK_WALL);
        if (render_figure_write(&f.frame, &s, NULL, "out/bench/bench_render_cairo.png", err,
                                sizeof err) != 0) {
            fprintf(stderr, "%s\n", err);
            return 1;
        }
        double t3 = sim_clock_seconds(SIM_CLOCK_WALL);
        double c3 = sim_clock_seconds(SIM_CLOCK_PROCESS);
        if (k > 0) {
            best_png = fmin(best_png, t3 - t2);
            cpu_png = fmin(cpu_png, c3 - c2);
        }
    }
    char head[64];
    snprintf(head, sizeof head, "ms per figure, min of %d", repeats);
    printf("%-34s %8s %9s\n", head, "wall", "CPU");
    report("cairo draw", best_draw, cpu_draw);
    if (helper)
        report("cairo two bands", best_split, cpu_split);
    report("bed in a box (1080 px), one band", best_box, cpu_box);
    if (helper)
        report("bed in a box, two bands", best_box_split, cpu_box_split);
    report("cairo draw + PNG", best_png, cpu_png);
    fixture_free(&f);
    return 0;
}
