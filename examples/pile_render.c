/* SPDX-License-Identifier: MIT */
/* pile_render: the library API end to end without a scene file. Rains grains into a box of
 * fixed grains (thesis 000 parameters), settles them, and writes a figure coloured by contact
 * force with force chains, plus a short MP4 of the deposition.
 * Usage: example_pile_render [OUT_DIR (default .)] [grains (default 400)] */
#include "render/render.h"
#include "sim/sim.h"

#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : ".";
    int grains = argc > 2 ? atoi(argv[2]) : 400;
    const double r_max = 0.105, width = 24 * 2 * r_max;
    char path[1024], err[512];

    SimGrainBuffer buffer;
    sim_grain_buffer_init(&buffer);
    sim_build_fixed_box(&buffer, 0.0, width, 0.0, 40 * r_max, r_max, 0);
    SimRainDef rain =
        sim_rain_def_thesis000(1.5 * r_max, width - 1.5 * r_max, 1.5 * r_max, 200 * r_max, grains);
    SimRng rng;
    sim_rng_seed(&rng, 7);
    sim_build_rain(&buffer, &rain, &rng);

    SimWorldDef def = sim_world_def_default();
    def.effects = SIM_EFFECT_FRICTION;
    def.mass_model = SIM_MASS_SPHERE;
    def.time_step = 5e-5;
    def.grains = sim_grain_buffer_view(&buffer);
    SimError error;
    SimWorld *world = sim_world_create(&def, &error);
    sim_grain_buffer_free(&buffer);
    if (!world) {
        fprintf(stderr, "pile_render: %s: %s\n", error.field, error.message);
        return 2;
    }

    RenderStyle style = render_style_default();
    style.width = 800;
    style.height = 600;
    style.color_by = RENDER_COLOR_FORCE;
    style.colormap = RENDER_CMAP_YELLOW_RED;
    style.force_chains = 1;
    style.colorbar = 1;
    style.colorbar_label = "contact force";
    style.colorbar_unit = "N";
    style.time_stamp = 1;
    RenderMeta meta = {.scene = "pile_render example", .seed = 7};

    snprintf(path, sizeof path, "%s/pile.mp4", dir);
    RenderMovieDef movie_def = {
        .path = path, .drawer = RENDER_DRAWER_CAIRO, .fps = 25, .quiet = 1, .meta = meta};
    RenderMovie *movie = render_movie_open(&movie_def, &style, err, sizeof err);
    if (!movie) {
        fprintf(stderr, "pile_render: %s\n", err);
        sim_world_destroy(world);
        return 1;
    }
    SimFrameSink sink = render_movie_sink(movie);
    SimFrame frame;
    for (int k = 0; k < 50; ++k) { /* 2.5 s, one frame every 0.05 s */
        if (sim_world_step(world, 1000, &error) != SIM_OK) {
            fprintf(stderr, "pile_render: %s\n", error.message);
            break;
        }
        sim_world_frame(world, &frame);
        sink.consume(sink.context, &frame);
    }
    int status = render_movie_close(movie, err, sizeof err) == 0 ? 0 : 1;
    if (status)
        fprintf(stderr, "pile_render: %s\n", err);

    sim_world_frame(world, &frame);
    snprintf(path, sizeof path, "%s/pile.png", dir);
    if (render_figure_write(&frame, &style, &meta, path, err, sizeof err) != 0) {
        fprintf(stderr, "pile_render: %s\n", err);
        status = 1;
    } else {
        printf("wrote %s/pile.png and %s/pile.mp4 (%d grains, t = %.2f s)\n", dir, dir,
               sim_world_mobile_count(world), sim_world_time(world));
    }
    sim_world_destroy(world);
    return status;
}
