/* SPDX-License-Identifier: MIT */
/* discharge/drivers.c: what the discharge family's two commands share (drivers.h). */
#include "drivers.h"

#include "base/util.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int app_discharge_parse_real(const char *text, double *out)
{
    char *end;
    errno = 0;
    *out = strtod(text, &end);
    return end != text && !*end && !errno && isfinite(*out) ? 0 : -1;
}

/* "1.0:7.0:0.2" or "1,2.5,3"; widths rounded to 1e-9 so names and matches are exact. */
int app_discharge_parse_widths(const char *text, double *out, int max)
{
    char buffer[1024];
    snprintf(buffer, sizeof buffer, "%s", text);
    int n = 0;
    if (strchr(buffer, ':')) {
        double a, b, step;
        char *p1 = strchr(buffer, ':'), *p2;
        *p1 = '\0';
        p2 = strchr(p1 + 1, ':');
        if (!p2)
            return -1;
        *p2 = '\0';
        if (app_discharge_parse_real(buffer, &a) || app_discharge_parse_real(p1 + 1, &b) ||
            app_discharge_parse_real(p2 + 1, &step) || !(step > 0.0) || b < a)
            return -1;
        for (long k = 0; n < max; ++k) {
            double v = a + (double)k * step;
            if (v > b + 1e-9 * step)
                break;
            out[n++] = floor(v * 1e9 + 0.5) / 1e9;
        }
        return n;
    }
    static const AppNumberList list = {.min = -INFINITY, .strict = 1};
    n = app_parse_numbers(buffer, &list, out, max);
    for (int k = 0; k < n; ++k)
        out[k] = floor(out[k] * 1e9 + 0.5) / 1e9;
    return n;
}

void app_discharge_width_name(double w, char *out, size_t size)
{
    snprintf(out, size, "w%.1f", w);
    if (fabs(w * 10.0 - floor(w * 10.0 + 0.5)) > 1e-6)
        snprintf(out, size, "w%g", w);
}

Scene *app_discharge_load_scene(const char *path, const char *const *sets, int set_count, double L,
                                char *err, size_t err_size)
{
    const char *all[APP_MAX_SETS + 1];
    char length[64];
    int n = 0;
    for (int k = 0; k < set_count && n < APP_MAX_SETS; ++k)
        all[n++] = sets[k];
    if (L > 0.0) {
        snprintf(length, sizeof length, "discharge.base_length=%.10g", L);
        all[n++] = length;
    }
    Scene *scene = scene_load(path, all, n, err, err_size);
    if (scene && !app_discharge_of(scene)) {
        snprintf(err, err_size, "%s:1: the scene has no `discharge` group (docs/discharge.md)",
                 path);
        scene_free(scene);
        return NULL;
    }
    return scene;
}

int app_discharge_check_widths(const Scene *scene, const double *widths, int count,
                               const char *option, char *err, size_t err_size)
{
    const AppDischargeDef *def = app_discharge_of(scene);
    for (int k = 0; k < count; ++k)
        if (!app_discharge_width_fits(def, widths[k])) {
            snprintf(err, err_size,
                     "sablier: %s %g: an orifice width must be in [1, base_length = %g] d (a "
                     "narrower one passes no grain, a wider one leaves no base)",
                     option, widths[k], def->base_length);
            return -1;
        }
    return 0;
}

/* ---------------------------------------------------------------- movies and figures */

int app_discharge_movie_start(AppDischargeMovie *m, const Scene *scene, const char *path,
                              AppDischargeFrames *frames, double frame_time, double dt)
{
    memset(frames, 0, sizeof *frames);
    if (!m->render || !m->render->movie_open)
        return 0;
    char err[512] = "";
    if (m->render->movie_open(m->render->context, scene, 0, path, &frames->sink, err, sizeof err) !=
        0) {
        fprintf(stderr, "sablier: movie %s: %s\n", path, err);
        return -1;
    }
    frames->every = (long)fmax(1.0, floor(frame_time / dt + 0.5));
    m->open = 1;
    return 0;
}

int app_discharge_movie_finish(AppDischargeMovie *m)
{
    if (!m->open)
        return 0;
    m->open = 0;
    char err[512] = "";
    if (m->render->movie_close(m->render->context, err, sizeof err) != 0) {
        fprintf(stderr, "sablier: movie: %s\n", err);
        return -1;
    }
    return 0;
}

int app_discharge_figure(const AppRender *render, const Scene *scene, SimWorld *world,
                         const AppDischarge *result, const char *title, const char *path)
{
    if (!render || !render->figure)
        return 0;
    SimFrame frame;
    sim_world_frame(world, &frame);
    int *marks = NULL;
    if (result && result->arch > 0) {
        marks = malloc((size_t)(frame.count + 1) * sizeof *marks);
        if (!marks)
            return -1;
        app_discharge_arch_marks(&frame, result, marks);
    }
    /* the scene's style; force chains only through an arch */
    SceneFigure fig;
    memset(&fig, 0, sizeof fig);
    fig.style = scene->style;
    fig.style.force_chains = marks != NULL;
    snprintf(fig.format, sizeof fig.format, "png");
    AppFigureExtras extras = {.title = title, .marks = marks};
    char err[512] = "";
    int rc = render->figure(render->context, scene, &fig, &frame, &extras, path, err, sizeof err);
    if (rc != 0)
        fprintf(stderr, "sablier: figure %s: %s\n", path, err);
    free(marks);
    return rc;
}
