/* SPDX-License-Identifier: MIT */
/* dump.h: per-grain dumps (docs/dumps.md), a core output like energy.csv. The scene declares them
 * in `output.dump` (every stage) and in a stage's own `dump` group (its keys on top; `dump =
 * false` turns a stage's dump off); the loader checks every key, and the frame count against
 * `max_frames`, before anything runs. The runner opens one writer per stage, hands it the frames
 * its clock makes due (the cadence of app_dump_every_steps) and closes it at the stage end:
 *
 *     DIR/<stage>.lammpstrj                      LAMMPS text dump, every frame (OVITO, read_dump)
 *     DIR/<stage>/<stage>_NNNNN.vtp, <stage>.pvd VTK XML PolyData per frame and its time index
 *     DIR/<stage>/<stage>_contacts_NNNNN.vtp, <stage>_contacts.pvd   the contact network
 *
 *     AppDump *dump = NULL;
 *     if (app_dump_open(&dump, scene, k, out_dir, dt, err, sizeof err) != 0) ...;  // NULL: none
 *     ... app_dump_frame(dump, &frame) at every app_dump_every_steps(spec, dt) ...
 *     app_dump_close(&dump, world, ok, err, sizeof err);  // last frame, commit (or discard)
 *
 * `sablier export STATE` (app_dump_export) writes one frame of a checkpoint in the same formats
 * or as CSV. */
#ifndef APP_DUMP_H
#define APP_DUMP_H

#include "scene/dump_spec.h"
#include "sim/sim.h"

#include <stddef.h>
#include <stdio.h>

struct Scene;

/* ---------------------------------------------------------------- writing, during a run */

typedef struct AppDump AppDump;

/// The writer of stage k into out_dir (*dump = NULL when the stage declares no dump). 0, or -1
/// with a message (a file or folder that cannot be made).
int app_dump_open(AppDump **dump, const struct Scene *scene, int stage, const char *out_dir,
                  char *err, size_t err_size);
/// Writes one frame (again at the same step: nothing). Errors are sticky: reported at close.
void app_dump_frame(AppDump *dump, const SimFrame *frame);
/// ok: writes the world's frame when the last one was taken at an earlier step (the stage's end
/// state is always the last frame), commits the LAMMPS file and writes the .pvd indexes; not ok:
/// removes the LAMMPS file's .tmp and writes no index (the .vtp frames written stay, each
/// complete). Frees *dump (NULL: nothing to do). 0, or -1 with a message.
int app_dump_close(AppDump **dump, SimWorld *world, int ok, char *err, size_t err_size);

/// A checkpoint of the running stage: the frames so far, their times and the LAMMPS file's
/// length, as the lines of the dump's section of checkpoint.txt (app/base/checkpoint.h).
void app_dump_checkpoint(const AppDump *dump, FILE *out);
/// --resume: the writer just opened continues from that section: the LAMMPS file cut back to its
/// recorded length, the VTK frames written after the checkpoint removed, the frame count and
/// times restored (the .pvd indexes are written at close). 0, or -1 with a message.
int app_dump_resume(AppDump *dump, const char *record, char *err, size_t err_size);

/* ---------------------------------------------------------------- one frame, any caller */

/// Appends one LAMMPS dump frame (ITEM: UNITS, TIME, TIMESTEP, NUMBER OF ATOMS, BOX BOUNDS,
/// ATOMS). def gives the masses (NULL: field mass not allowed), species[k] the name of species k
/// (field element; NULL: the species index). 0, or -1 on a write error.
int app_dump_lammps_frame(FILE *out, const SimFrame *frame, const unsigned char *fields, int count,
                          const SimWorldDef *def, const char *const *species);
/// Appends the grain-grain contacts of a frame as a LAMMPS `dump local` frame (ITEM: NUMBER OF
/// ENTRIES, ENTRIES index id1 id2 fn ft; ids as in the atom dump), which OVITO loads as bonds.
int app_dump_lammps_contacts(FILE *out, const SimFrame *frame);
/// Writes the walls of a frame as VTK PolyData polylines (arcs as 32 segments) through path.tmp.
int app_dump_vtp_walls(const char *path, const SimFrame *frame, int binary);
/// Writes one VTK PolyData file of the grains through path.tmp. 0, or -1.
/// binary: 1 raw appended data, 0 ASCII, -1 raw above APP_VTK_BINARY_POINTS (vtk_xml.h) points.
/// Every file carries the frame's time as the field data `TimeValue` (s).
int app_dump_vtp_grains(const char *path, const SimFrame *frame, const unsigned char *fields,
                        int count, const SimWorldDef *def, int binary);
/// Writes the contact network of a frame as VTK PolyData lines through path.tmp. 0, or -1.
int app_dump_vtp_contacts(const char *path, const SimFrame *frame, int binary);

/* ---------------------------------------------------------------- checkpoints (dump_export.c) */

/// The columns behind a frame read from a checkpoint (no world: no forces, no contacts).
typedef struct AppStateFrame {
    double *x, *y, *angle, *radius, *vx, *vy, *omega, *zero;
    int *species;
    unsigned *flags;
    uint32_t *id;
} AppStateFrame;

/// A frame straight from saved grains (sim_state_load): mobile first, forces zero. 0, or -1 (out
/// of memory; free what was made with app_state_frame_free).
int app_state_frame(const SimGrainSet *grains, const SimWall *walls, int wall_count, double time,
                    AppStateFrame *columns, SimFrame *frame);
void app_state_frame_free(AppStateFrame *columns);

/// `sablier export STATE [--format lammps|vtk|csv] -o FILE`: the exit status.
int app_dump_export(int argc, char **argv);
/// Its command line only (the `parse` of an AppCommand): 0, or the exit status of a usage error.
int app_dump_export_parse(int argc, char **argv);
extern const char app_dump_export_usage[];

#endif
