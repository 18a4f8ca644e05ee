/* SPDX-License-Identifier: MIT */
/* render_style.c: default drawing style. */
#include "render/render_style.h"

RenderStyle render_style_default(void)
{
    RenderStyle s = {0};
    s.width = 1280;
    s.height = 720;
    s.color_by = RENDER_COLOR_FIXED;
    s.colormap = RENDER_CMAP_VIRIDIS;
    s.fill_rgb = 0xd8c08a; /* sand */
    s.band_rgb = 0x8a9ec0; /* slate blue: contrasts with sand in layered beds */
    s.fixed_rgb = 0x6e6e6e;
    s.background_rgb = 0xffffff;
    s.outline = 1;
    s.chain_threshold = 1.0; /* strong network, f > <f> (Radjai et al. 1998) */
    s.field_kernel = RENDER_KERNEL_LUCY;
    s.colorbar = 1;
    s.time_stamp = 1;
    s.scale_bar = 1;
    s.arch_rgb = 0xd62728;
    return s;
}
