/* SPDX-License-Identifier: MIT */
/* dump_spec.h: a stage's per-grain dump as the scene declares it (docs/dumps.md): `output.dump`
 * and a stage's own `dump` group, read into Scene.output.dump by the loader
 * (app/scene/scene_dump.c). The writers of a run that follow it are in app/output/dump.h. */
#ifndef APP_DUMP_SPEC_H
#define APP_DUMP_SPEC_H

#include "base/config.h"

#include <stdio.h>

struct Scene;

/// Dump formats (bits of AppDumpSpec.formats).
enum {
    APP_DUMP_LAMMPS = 1u << 0,
    APP_DUMP_VTK = 1u << 1,
};

/// Per-grain fields, in the order of their names (app_dump_field_name).
typedef enum AppDumpField {
    APP_DUMP_ID,      ///< stable id (LAMMPS: id + 1, ids start at 1 there)
    APP_DUMP_TYPE,    ///< species + 1 (LAMMPS atom type)
    APP_DUMP_X,       ///< m
    APP_DUMP_Y,       ///< m (LAMMPS: also z = 0)
    APP_DUMP_VX,      ///< m/s
    APP_DUMP_VY,      ///< m/s (LAMMPS: also vz = 0)
    APP_DUMP_OMEGA,   ///< rad/s, counter-clockwise (LAMMPS omegaz)
    APP_DUMP_RADIUS,  ///< m
    APP_DUMP_FX,      ///< contact + body force of the last evaluation, N
    APP_DUMP_FY,      ///< N (LAMMPS: also fz = 0)
    APP_DUMP_MASS,    ///< kg (the scene's mass model; fixed grains as if mobile)
    APP_DUMP_ANGLE,   ///< rad
    APP_DUMP_SPECIES, ///< species index
    APP_DUMP_FIXED,   ///< 1 for a fixed grain
    APP_DUMP_FORCE,   ///< sum of contact-force magnitudes, N
    APP_DUMP_TORQUE,  ///< N m (LAMMPS tqz)
    APP_DUMP_ELEMENT, ///< species name (LAMMPS `element`, OVITO's type names; not in VTK)
    APP_DUMP_FIELD_COUNT
} AppDumpField;

/// The fields when `fields` is not given: id type x y vx vy omega radius fx fy fixed element.
#define APP_DUMP_DEFAULT_FIELDS 12

/// Default bound on the frames of one stage's dump.
#define APP_DUMP_MAX_FRAMES 10000

/// One stage's dump as declared (plain data; formats == 0: no dump).
typedef struct AppDumpSpec {
    unsigned formats; ///< APP_DUMP_LAMMPS | APP_DUMP_VTK
    double every;     ///< simulated time between frames, s
    int field_count;
    unsigned char fields[APP_DUMP_FIELD_COUNT]; ///< AppDumpField, in column order
    int contacts;                               ///< 1: the contact series too (VTK, LAMMPS local)
    int walls;                                  ///< 1: the VTK wall series too
    int binary;                                 ///< VTK encoding: 0 ascii, 1 raw appended, -1 auto
    long max_frames;                            ///< frames allowed per stage
} AppDumpSpec;

/// "id", "type", "x", ... (NULL past the last field).
const char *app_dump_field_name(int field);

/// Reads `output.dump` and every stage's `dump` of the scene file's root into
/// scene->output.dump[k] (the stages already parsed: their times bound the frames). 0, or -1 with
/// "file:line: ..." in p's buffer.
int app_dump_parse(AppConfig *p, const config_setting_t *root, struct Scene *scene);

/// Steps between frames at time step dt (at least 1: a dump never runs faster than the steps).
long app_dump_every_steps(const AppDumpSpec *spec, double dt);

/// Upper bound of the frames a stage of `duration` s makes (the start, every `every`, the end);
/// dt = 0: not known yet (a bound from the times alone).
long app_dump_frame_bound(const AppDumpSpec *spec, double duration, double dt);

/// One line for `sablier check` ("  dump  lammps, vtk every 0.5 s: ..."); nothing without a dump.
void app_dump_describe(const AppDumpSpec *spec, double duration, double dt, FILE *out);

#endif
