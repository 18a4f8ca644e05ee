/* SPDX-License-Identifier: MIT */
/* render_glue.h: the AppRender of the `sablier` command, drawn with render/ (app/render_glue.c).
 * Built only with rendering (SABLIER_WITH_RENDER). */
#ifndef APP_RENDER_GLUE_H
#define APP_RENDER_GLUE_H

#include "render_hooks.h"
#include "scene.h"

#include "render/render.h"

/// The renderer's services (one static instance; movies open one at a time).
const AppRender *app_render_glue(void);

/// A scene's plain style data onto RenderStyle (unset fields keep the renderer's defaults).
RenderStyle app_render_style(const SceneStyle *style);

#endif
