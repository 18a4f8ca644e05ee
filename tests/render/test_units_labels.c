/* SPDX-License-Identifier: MIT */
/* The labels of a grain figure in SI and in reduced units (RenderStyle.reduced_units, set from a
 * scene's units = "reduced"): the time stamp reads t in sqrt(d/g) from the frame's time_scale,
 * the scale bar counts mean diameters without metres. */
#include "test.h"

#include "render/internal.h"

#include <string.h>

static int time_stamp(void)
{
    SimFrame frame;
    memset(&frame, 0, sizeof frame);
    frame.time = 0.5;
    frame.time_scale = 0.25;
    RenderStyle style = render_style_default();
    char text[96];
    TEST_ASSERT(strcmp(render_time_label(&frame, &style, text, sizeof text),
                       "t = 0.5000 s    t* = 2.00") == 0);
    style.reduced_units = 1;
    TEST_ASSERT(strcmp(render_time_label(&frame, &style, text, sizeof text),
                       "t = 2.00 \xe2\x88\x9a(d/g)") == 0);
    frame.time_scale = 0.0; /* no gravity: no reduced time, seconds as in SI */
    TEST_ASSERT(strcmp(render_time_label(&frame, &style, text, sizeof text), "t = 0.5000 s") == 0);
    return 0;
}

static int scale_bar(void)
{
    RenderStyle style = render_style_default();
    char text[96];
    TEST_ASSERT(
        strcmp(render_scale_label(5.0, 0.002, &style, text, sizeof text), "5 d   (d = 2 mm)") == 0);
    style.reduced_units = 1;
    TEST_ASSERT(strcmp(render_scale_label(5.0, 0.002, &style, text, sizeof text), "5 d") == 0);
    return 0;
}

/* units = "normalised": the numbers are the scene's own; labels say d, and sqrt(d/g) only when the
 * scene's gravity is 1 (RENDER_UNITS_NORMALISED_G); else the time is written bare. */
static int normalised(void)
{
    SimFrame frame;
    memset(&frame, 0, sizeof frame);
    frame.time = 16.5;
    frame.time_scale = 0.25; /* not used: t is already in the scene's unit */
    RenderStyle style = render_style_default();
    style.normalised_units = RENDER_UNITS_NORMALISED_G;
    char text[96];
    TEST_ASSERT(strcmp(render_time_label(&frame, &style, text, sizeof text),
                       "t = 16.50 \xe2\x88\x9a(d/g)") == 0);
    TEST_ASSERT(strcmp(render_scale_label(2.0, 1.0, &style, text, sizeof text), "2 d") == 0);
    style.normalised_units = RENDER_UNITS_NORMALISED;
    TEST_ASSERT(strcmp(render_time_label(&frame, &style, text, sizeof text), "t = 16.50") == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(time_stamp), TEST_CASE(scale_bar), TEST_CASE(normalised))
