/* SPDX-License-Identifier: MIT */
/* discharge/drivers.h: what the discharge family's commands share (private to app/discharge/):
 * number lists, file names, the scene loaded with its base length, movies and pile figures. */
#ifndef APP_DISCHARGE_DRIVERS_H
#define APP_DISCHARGE_DRIVERS_H

#include "discharge.h"
#include "study.h"

#include <stddef.h>

/// A finite number: 0 and *out, or -1.
int app_discharge_parse_real(const char *text, double *out);
/// "1.0:7.0:0.2" or "1,2.5,3" into at most max values, rounded to 1e-9 (exact names and matches).
/// The count, or -1 when malformed.
int app_discharge_parse_widths(const char *text, double *out, int max);
/// "w2.0" (one decimal when exact, else %g).
void app_discharge_width_name(double w, char *out, size_t size);
/// The scene with `sets` and, when L > 0, discharge.base_length = L; NULL with a message when it
/// is bad or has no `discharge` group.
Scene *app_discharge_load_scene(const char *path, const char *const *sets, int set_count, double L,
                                char *err, size_t err_size);

/// Every width of widths[count] fits the scene's base (app_discharge_width_fits): 0, or -1 with
/// "OPTION W: ..." in err (option: the command line's name of the list, "--width").
int app_discharge_check_widths(const Scene *scene, const double *widths, int count,
                               const char *option, char *err, size_t err_size);

typedef struct AppDischargeMovie {
    const AppRender *render;
    int open;
} AppDischargeMovie;

/// Opens a movie at path (nothing without a renderer) and sets the frame cadence of `frames`.
int app_discharge_movie_start(AppDischargeMovie *m, const Scene *scene, const char *path,
                              AppDischargeFrames *frames, double frame_time, double dt);
int app_discharge_movie_finish(AppDischargeMovie *m);
/// A pile figure in the scene's style, the arch of `result` (may be NULL) highlighted.
int app_discharge_figure(const AppRender *render, const Scene *scene, SimWorld *world,
                         const AppDischarge *result, const char *title, const char *path);

#endif
