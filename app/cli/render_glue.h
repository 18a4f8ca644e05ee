/* SPDX-License-Identifier: MIT */
/* render_glue.h: the AppRender of the `sablier` command, drawn with render/
 * (app/cli/render_glue.c). Built only with rendering (SABLIER_WITH_RENDER). */
#ifndef APP_RENDER_GLUE_H
#define APP_RENDER_GLUE_H

#include "base/render_hooks.h"
#include "render/render.h"
#include "scene/scene.h"

/// The renderer's services (one static instance; movies open one at a time).
const AppRender *app_render_glue(void);

/// A scene's plain style data onto RenderStyle (unset fields keep the renderer's defaults).
/// Axes are on only when the style says `axes = true` (movies); figures turn them on when unset.
RenderStyle app_render_style(const SceneStyle *style);
/// Reduced units: force and speed colour bars in m g and sqrt(g d), given in N and m/s
/// (RenderStyle.force_unit, speed_unit, and the bar's unit); nothing when either is 0.
void app_reduced_style(double force_unit, double speed_unit, RenderStyle *style);
/// Points the style's legend names at the scene's species names (`names` must outlive the style;
/// scene NULL: "species N").
void app_render_names(const Scene *scene, const char *names[SIM_MAX_SPECIES], RenderStyle *style);

#endif
