/* SPDX-License-Identifier: MIT */
/* study.h: the `sablier discharge` and `sablier study` commands (thesis 004, docs/discharge.md).
 * `discharge` builds one pile and discharges it at a few widths (figures, movies); `study` runs
 * independent samples over base lengths and widths in parallel processes, resumes where it
 * stopped, and reduces them to per-(L, w) tables, fits (w_t, w_c), F(s) and plots. Rendering
 * comes through the AppRender of app/base/render_hooks.h (NULL: figures, movies and plots skipped).
 */
#ifndef APP_STUDY_H
#define APP_STUDY_H

#include "discharge.h"

#include "base/render_hooks.h"
#include "run/run.h"

#include <stddef.h>

/// `sablier study SCENE ...`; returns the exit status (env may be NULL: no rendering).
int app_study_command(int argc, char **argv, const AppEnv *env);

/// Its command line only (AppCommand.parse): 0, or the exit status of a usage error.
int app_study_parse(int argc, char **argv);

extern const char APP_DISCHARGE_USAGE[];
extern const char APP_STUDY_USAGE[];

/// Gaussian fit of sigma(w) through its peak: a parabola fitted to log sigma over the points
/// above half the maximum (at least three, else the arg-max). Returns the peak position w_t.
double app_study_gaussian_peak(const double *w, const double *sigma, int n);

/// Species counts on square cells over piles (004 §3.4: q_s and q_d maps on 5 d squares),
/// summed over samples, so a cell's fraction is a ratio of sums: marked / count. The maps'
/// functions below are in app/discharge/species_map.c.
typedef struct AppStudySpeciesMap {
    int nx, ny;          ///< cells, row-major index j * nx + i
    double x0, y0, cell; ///< lower-left corner of cell (0, 0) and side, d
    long *count;         ///< grains per cell
    long *marked;        ///< of them, grains of the marked species
} AppStudySpeciesMap;

/// Cells of side `cell` for a pile on a base of length L: an odd number of columns with one
/// centred on x = 0 (above the orifice), covering [-L/2, L/2] x [0, L]. 0, or -1 on bad input.
int app_study_species_map_init(AppStudySpeciesMap *map, double L, double cell);
void app_study_species_map_free(AppStudySpeciesMap *map);
/// Adds the mobile grains of one pile (fixed grains skipped; flags and species may be NULL);
/// `marked` is the species counted in map->marked. Returns the grains outside the cells.
int app_study_species_map_add(AppStudySpeciesMap *map, const SimFrame *frame, int marked);
/// Fraction of marked grains in cell (i, j); NaN when the cell is empty or outside.
double app_study_species_map_fraction(const AppStudySpeciesMap *map, int i, int j);
/// One record "TAG,nx,ny,k:count:marked,..." of the non-empty cells (k = j * nx + i), no newline
/// (buf may be NULL to get the length);
/// returns what snprintf returns.
int app_study_species_map_format(const AppStudySpeciesMap *map, const char *tag, char *buf,
                                 size_t size);
/// Adds a record of app_study_species_map_format, given the text after its tag and comma. 0, or -1
/// when the grid differs or the text is malformed (nothing added then).
int app_study_species_map_parse(AppStudySpeciesMap *map, const char *text);
/// The species the maps count: the smaller one when the scene's two discharge species differ in
/// diameter (q_s), else the lighter one when they differ in density (q_d); -1 otherwise. *what
/// (may be NULL) gets "small" or "light".
int app_study_species_marked(const Scene *scene, const char **what);

/// Reduces finished runs of a study folder to tables (per-(L, w) CSV, study.csv, fits.csv, F(s))
/// and plots; returns 0, or -1 with a message.
int app_study_reduce(const Scene *scene, const char *dir, const double *lengths, int length_count,
                     const double *widths, int width_count, int samples, const AppRender *render,
                     char *err, size_t err_size);

#endif
