/* SPDX-License-Identifier: MIT */
/* hello_render (installed): a program outside the tree on the installed libsablier-render and
 * libsablier-sim (docs/install.md). Rains 300 grains into a box, runs 50000 steps, and writes a
 * 640x480 figure coloured by contact force to PATH (default hello_render.png).
 * Build: cc -std=c17 hello_render.c $(pkg-config --cflags --libs sablier-render) -o hello_render */
#include <render/render.h>
#include <sim/sim.h>
#include <stdio.h>

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "hello_render.png";
    const double r_max = 0.105, width = 20 * 2 * r_max;
    const long steps = 50000; /* 0.5 s: the grains land and touch */
    SimGrainBuffer buffer;
    sim_grain_buffer_init(&buffer);
    sim_build_fixed_box(&buffer, 0.0, width, 0.0, 60 * r_max, r_max, 0);
    SimRainDef rain =
        sim_rain_def_thesis000(1.5 * r_max, width - 1.5 * r_max, 1.5 * r_max, 200 * r_max, 300);
    SimRng rng;
    sim_rng_seed(&rng, 1);
    sim_build_rain(&buffer, &rain, &rng);

    SimWorldDef def = sim_world_def_default();
    def.effects = SIM_EFFECT_FRICTION;
    def.mass_model = SIM_MASS_SPHERE;
    def.time_step = 1e-5;
    def.grains = sim_grain_buffer_view(&buffer);
    SimError error;
    SimWorld *world = sim_world_create(&def, &error);
    sim_grain_buffer_free(&buffer);
    if (!world) {
        fprintf(stderr, "hello_render: %s: %s\n", error.field, error.message);
        return 2;
    }
    if (sim_world_step(world, steps, &error) != SIM_OK) {
        fprintf(stderr, "hello_render: %s\n", error.message);
        sim_world_destroy(world);
        return 1;
    }
    RenderStyle style = render_style_default();
    style.width = 640;
    style.height = 480;
    style.color_by = RENDER_COLOR_FORCE;
    style.colorbar = 1;
    RenderMeta meta = {.scene = "hello_render", .seed = 1, .comment = NULL};
    SimFrame frame;
    sim_world_frame(world, &frame);
    char err[512];
    int status = render_figure_write(&frame, &style, &meta, path, err, sizeof err);
    sim_world_destroy(world);
    if (status != 0) {
        fprintf(stderr, "hello_render: %s\n", err);
        return 1;
    }
    RenderImage image;
    if (render_png_read(path, &image, err, sizeof err) != 0) {
        fprintf(stderr, "hello_render: %s\n", err);
        return 1;
    }
    printf("wrote %s (%dx%d)\n", path, image.width, image.height);
    render_image_free(&image);
    return 0;
}
