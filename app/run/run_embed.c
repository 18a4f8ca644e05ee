/* SPDX-License-Identifier: MIT */
/* run_embed.c: the stage runner for bindings (scene_run in run.h): app_run without rendering,
 * with a caller's hook between steps (the Python module's sablier.Run, docs/python.md). */
#include "run/run.h"

int scene_run(const Scene *scene, const char *out_dir, int quiet, int threads, AppRunHook hook,
              void *context, long every)
{
    AppRunOptions options = app_run_options_default();
    options.out_dir = out_dir;
    options.quiet = quiet;
    options.threads = threads < 0 ? 1 : threads;
    options.render_off = 1;
    options.sablier_version = SIM_VERSION;
    options.hook = hook;
    options.hook_context = context;
    options.hook_every = every >= 1 ? every : 1;
    return app_run(scene, &options);
}
