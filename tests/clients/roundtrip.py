# SPDX-License-Identifier: MIT
"""Round trips of the per-grain dumps (docs/dumps.md) through real readers (tests/clients/clients.cmake).

    roundtrip.py run SABLIER SCENE WORK     sablier run SCENE --out WORK (the fixture)
    roundtrip.py lammps WORK                LAMMPS `read_dump` reads every atom of every frame
    roundtrip.py vtk WORK                   VTK's XML reader reads every .vtp the .pvd files list
    roundtrip.py export SABLIER WORK        `sablier export` of a checkpoint equals the stage's
                                            last dump frame (LAMMPS, VTK and CSV)

Exit status 0 pass, 1 fail, 77 skipped (the reader is not installed: lammps, python3-vtk9). Runs
under Debian's /usr/bin/python3 (its python3-vtk9); only the vtk case imports vtk."""
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

SKIP = 77


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def read_lammps(path):
    """The frames of a LAMMPS text dump: dicts of time, step, count, box, columns, rows (text)."""
    frames, lines = [], open(path).read().split("\n")
    k = 0
    while k < len(lines) and lines[k]:
        frame = {"time": None, "units": None}
        if lines[k] == "ITEM: UNITS":
            frame["units"] = lines[k + 1]
            k += 2
        if lines[k] == "ITEM: TIME":
            frame["time"] = lines[k + 1]
            k += 2
        if lines[k] != "ITEM: TIMESTEP" or lines[k + 2] != "ITEM: NUMBER OF ATOMS":
            fail("%s: bad frame header at line %d" % (path, k + 1))
        frame["step"], frame["count"] = int(lines[k + 1]), int(lines[k + 3])
        if not lines[k + 4].startswith("ITEM: BOX BOUNDS "):
            fail("%s: no BOX BOUNDS at line %d" % (path, k + 5))
        frame["flags"] = lines[k + 4].split()[3:]
        frame["box"] = [lines[k + 5 + a].split() for a in range(3)]
        if not lines[k + 8].startswith("ITEM: ATOMS "):
            fail("%s: no ITEM: ATOMS at line %d" % (path, k + 9))
        frame["columns"] = lines[k + 8].split()[2:]
        frame["rows"] = [lines[k + 9 + i].split() for i in range(frame["count"])]
        frames.append(frame)
        k += 9 + frame["count"]
    return frames


def by_id(columns, rows, names):
    """{id: [values of `names`]} as text, from rows with these columns."""
    where = [columns.index(n) for n in names]
    ident = columns.index("id")
    return {row[ident]: [row[w] for w in where] for row in rows}


def stage_files(work, suffix):
    """The stages with a file DIR/<stage>SUFFIX (stage names have no dot)."""
    return sorted(f[: -len(suffix)] for f in os.listdir(work)
                  if f.endswith(suffix) and "." not in f[: -len(suffix)])


def read_bonds(path):
    """The frames of a LAMMPS `dump local` file: dicts of time, step, columns, rows (text)."""
    frames, lines = [], open(path).read().split("\n")
    k = 0
    while k < len(lines) and lines[k]:
        if lines[k : k + 5 : 2] != ["ITEM: UNITS", "ITEM: TIME", "ITEM: TIMESTEP"]:
            fail("%s: bad local frame header at line %d" % (path, k + 1))
        if lines[k + 6] != "ITEM: NUMBER OF ENTRIES" or not lines[k + 8].startswith("ITEM: BOX"):
            fail("%s: no NUMBER OF ENTRIES / BOX BOUNDS at line %d" % (path, k + 7))
        count = int(lines[k + 7])
        if not lines[k + 12].startswith("ITEM: ENTRIES "):
            fail("%s: no ITEM: ENTRIES at line %d" % (path, k + 13))
        frames.append({"time": lines[k + 3], "step": int(lines[k + 5]),
                       "columns": lines[k + 12].split()[2:],
                       "rows": [lines[k + 13 + i].split() for i in range(count)]})
        k += 13 + count
    return frames


def case_run(sablier, scene, work):
    shutil.rmtree(work, ignore_errors=True)
    done = subprocess.run([sablier, "run", scene, "--out", work, "--quiet"])
    if done.returncode != 0:
        fail("sablier run %s: exit %d" % (scene, done.returncode))
    if not stage_files(work, ".lammpstrj") or not stage_files(work, ".pvd"):
        fail("no dumps in " + work)
    if [f for f in os.listdir(work) if f.endswith(".tmp")]:
        fail("a .tmp file is left in " + work)


LAMMPS_INPUT = """dimension 2
units si
atom_style sphere
boundary {flags} p
region box block 0 1 0 1 -0.5 0.5
create_box {types} box
read_dump {dump} {step} x y vx vy add keep box yes
variable n equal count(all)
print "read_dump atoms ${{n}}"
write_dump all custom {out} id type x y vx vy modify format float %.17g
"""


def case_lammps(work):
    lmp = shutil.which("lmp")
    if not lmp:
        print("SKIP: no `lmp` on PATH (Debian package lammps, scripts/setup.sh)")
        sys.exit(SKIP)
    frames_read = 0
    for stage in stage_files(work, ".lammpstrj"):
        dump = os.path.join(work, stage + ".lammpstrj")
        for frame in read_lammps(dump):
            types = max(int(r[frame["columns"].index("type")]) for r in frame["rows"])
            script = os.path.join(work, "read_dump.in")
            out = os.path.join(work, "read_dump.out")
            with open(script, "w") as f:
                f.write(LAMMPS_INPUT.format(flags=" ".join(f[0] for f in frame["flags"][:2]),
                                            types=types, dump=dump, step=frame["step"], out=out))
            done = subprocess.run([lmp, "-in", script, "-log", "none", "-screen", "none"],
                                  capture_output=True, text=True)
            # -screen none keeps the print on stdout only when run on a terminal: read the file
            back = read_lammps(out)[0] if os.path.exists(out) else None
            if done.returncode != 0 or back is None:
                fail("lmp read_dump %s step %d: exit %d\n%s%s" % (dump, frame["step"],
                     done.returncode, done.stdout, done.stderr))
            if back["count"] != frame["count"]:
                fail("%s step %d: LAMMPS read %d atoms of %d" % (dump, frame["step"],
                     back["count"], frame["count"]))
            names = ["type", "x", "y", "vx", "vy"]
            ours = by_id(frame["columns"], frame["rows"], names)
            theirs = by_id(back["columns"], back["rows"], names)
            for ident, values in ours.items():
                if [float(v) for v in theirs.get(ident, [])] != [float(v) for v in values]:
                    fail("%s step %d: atom %s reads back as %s, not %s" % (dump, frame["step"],
                         ident, theirs.get(ident), values))
            os.remove(out)
            frames_read += 1
            # the default fields: fixed (base grains are not mobile) and the species names
            if frame["units"] != "si" or frame["columns"][-2:] != ["fixed", "element"]:
                fail("%s: units %s, columns %s" % (dump, frame["units"], frame["columns"]))
            if {r[-1] for r in frame["rows"]} != {"acrylic"} or \
                    {r[-2] for r in frame["rows"]} != {"0", "1"}:
                fail("%s step %d: element or fixed columns wrong" % (dump, frame["step"]))
        bonds = read_bonds(os.path.join(work, stage + ".bonds.lammpstrj"))
        atoms = read_lammps(dump)
        if [b["step"] for b in bonds] != [a["step"] for a in atoms]:
            fail("%s: bond frames at other steps than the atoms" % stage)
        for b, a in zip(bonds, atoms):  # OVITO's bonds: both ends are atoms of that frame
            ids = {r[0] for r in a["rows"]}
            if b["columns"] != ["index", "id1", "id2", "fn", "ft"]:
                fail("%s step %d: bond columns %s" % (stage, b["step"], b["columns"]))
            if any(r[1] not in ids or r[2] not in ids for r in b["rows"]):
                fail("%s step %d: a bond to an atom not in the frame" % (stage, b["step"]))
        if not bonds[-1]["rows"]:
            fail("%s: no bonds in the last frame of a settled pile" % stage)
    print("LAMMPS read_dump: %d frames, every atom, values to the bit; bond dumps consistent"
          % frames_read)


def pvd_files(work, pvd):
    root = ET.parse(os.path.join(work, pvd)).getroot()
    if root.get("type") != "Collection":
        fail(pvd + ": not a VTK Collection")
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def time_value(data):
    """The TimeValue field data of a data set read by VTK (None without it)."""
    array = data.GetFieldData().GetArray("TimeValue")
    return array.GetValue(0) if array is not None else None


def case_vtk(work):
    try:
        import vtk
    except ImportError:
        print("SKIP: %s cannot import vtk (Debian package python3-vtk9)" % sys.executable)
        sys.exit(SKIP)
    grains = {}  # the grain count of each stage, from its first .vtp
    files = binary = 0
    at_time = {}  # time: [(file, {id: point})] of the grain files
    for name in stage_files(work, ".pvd"):
        series_name = next((s for s in ("_contacts", "_walls") if name.endswith(s)), "")
        stage = name[: len(name) - len(series_name)]
        contacts = series_name == "_contacts"
        series = pvd_files(work, name + ".pvd")
        if not series:
            fail(name + ".pvd lists no files")
        times = [t for t, _ in series]
        if times != sorted(times):
            fail(name + ".pvd: times not increasing")
        for t, rel in series:
            path = os.path.join(work, rel)
            if not os.path.exists(path):
                fail("%s.pvd lists %s, which does not exist" % (name, rel))
            binary += b'encoding="raw"' in open(path, "rb").read()
            reader = vtk.vtkXMLPolyDataReader()
            reader.SetFileName(path)
            reader.Update()
            data = reader.GetOutput()
            if time_value(data) != t:
                fail("%s: TimeValue %s, the .pvd's timestep %r" % (rel, time_value(data), t))
            if series_name == "_walls":
                if data.GetNumberOfLines() != data.GetCellData().GetArray("wall").GetNumberOfTuples():
                    fail("%s: wall lines and wall indices differ" % rel)
            elif contacts:
                cells = data.GetCellData()
                arrays = [cells.GetArrayName(i) for i in range(cells.GetNumberOfArrays())]
                if arrays != ["normal_force", "tangential_force"]:
                    fail("%s: contact arrays %s" % (rel, arrays))
                if data.GetNumberOfLines() != cells.GetArray(0).GetNumberOfTuples():
                    fail("%s: %d lines, %d forces" % (rel, data.GetNumberOfLines(),
                         cells.GetArray(0).GetNumberOfTuples()))
                if data.GetNumberOfPoints() < grains.get(stage, 0):
                    fail("%s: fewer points than grains" % rel)
            else:
                count = data.GetNumberOfPoints()
                if count == 0 or data.GetNumberOfVerts() != count:
                    fail("%s: %d points, %d verts" % (rel, count, data.GetNumberOfVerts()))
                grains.setdefault(stage, count)
                points = data.GetPointData()
                at_time.setdefault(t, []).append((rel, {int(points.GetArray("id").GetValue(i)):
                                                        data.GetPoint(i) for i in range(count)}))
                arrays = [points.GetArrayName(i) for i in range(points.GetNumberOfArrays())]
                if "radius" not in arrays or "id" not in arrays:
                    fail("%s: arrays %s lack radius or id" % (rel, arrays))
                for i in range(points.GetNumberOfArrays()):
                    if points.GetArray(i).GetNumberOfTuples() != count:
                        fail("%s: array %s has %d values for %d points" % (rel, arrays[i],
                             points.GetArray(i).GetNumberOfTuples(), count))
                lammps = os.path.join(work, stage + ".lammpstrj")
                if os.path.exists(lammps):  # the same frame in the LAMMPS dump
                    frame = [f for f in read_lammps(lammps) if float(f["time"]) == t]
                    if len(frame) != 1 or frame[0]["count"] != count:
                        fail("%s: no LAMMPS frame of %d atoms at t = %r" % (rel, count, t))
                    ids = sorted(int(points.GetArray("id").GetValue(i)) + 1 for i in range(count))
                    theirs = sorted(int(r[0]) for r in frame[0]["rows"])
                    if ids != theirs:
                        fail("%s: ids differ from the LAMMPS frame" % rel)
                    x = {int(r[0]): float(r[2]) for r in frame[0]["rows"]}
                    for i in range(count):  # the points to the bit, ASCII or binary
                        if data.GetPoint(i)[0] != x[int(points.GetArray("id").GetValue(i)) + 1]:
                            fail("%s: point %d differs from the LAMMPS frame" % (rel, i))
            files += 1
    for series_name in ("_contacts", "_walls"):
        if not any(n.endswith(series_name) for n in stage_files(work, ".pvd")):
            fail("no %s series" % series_name[1:])
    if not binary:
        fail("no binary (raw appended) VTK file among the dumps")
    # a stage's first frame is the end state of the stage before: ASCII and binary agree to the bit
    shared = [v for v in at_time.values() if len(v) > 1]
    if not shared:
        fail("no two grain files at the same time (ASCII against binary)")
    for files_at in shared:
        if any(points != files_at[0][1] for _, points in files_at[1:]):
            fail("%s differ at the same time" % [rel for rel, _ in files_at])
    # the run's index (VTK 9 has no .pvd reader, ParaView's vtkPVDReader parses it like this):
    # every data set it lists opens, at the times of the stages' series
    run = pvd_files(work, "run.all.pvd")
    steps = sorted({t for t, _ in run})
    for t, rel in run:
        reader = vtk.vtkXMLPolyDataReader()
        reader.SetFileName(os.path.join(work, rel))
        reader.Update()
        if time_value(reader.GetOutput()) != t:
            fail("run.all.pvd: %s is not at %r" % (rel, t))
    stage_steps = sorted({t for name in stage_files(work, ".pvd")
                          if not name.endswith(("_contacts", "_walls"))
                          for t, _ in pvd_files(work, name + ".pvd")})
    if steps != stage_steps:
        fail("run.all.pvd: times %s, the stages' %s" % (steps, stage_steps))
    print("VTK vtkXMLPolyDataReader: %d files of %d stages read (%d binary), TimeValue = timestep;"
          " run.all.pvd: %d time steps" % (files, len(grains), binary, len(steps)))


def case_export(sablier, work):
    checked = 0
    for stage in stage_files(work, ".lammpstrj"):
        last = read_lammps(os.path.join(work, stage + ".lammpstrj"))[-1]
        state = os.path.join(work, stage + ".state")
        out = os.path.join(work, "export_" + stage)
        for fmt, ext in (("lammps", ".lammpstrj"), ("csv", ".csv"), ("vtk", ".vtp")):
            done = subprocess.run([sablier, "export", state, "--format", fmt, "-o", out + ext])
            if done.returncode != 0 or not os.path.exists(out + ext):
                fail("sablier export %s --format %s: exit %d" % (state, fmt, done.returncode))
        exported = read_lammps(out + ".lammpstrj")
        if len(exported) != 1 or exported[0]["time"] != last["time"]:
            fail("%s: export time %s, last dump frame %s" % (stage, exported[0]["time"],
                 last["time"]))
        common = [c for c in exported[0]["columns"] if c in last["columns"] and c != "id"]
        if len(common) < 8:
            fail("%s: too few common columns %s" % (stage, common))
        ours = by_id(last["columns"], last["rows"], common)
        theirs = by_id(exported[0]["columns"], exported[0]["rows"], common)
        if ours != theirs:
            bad = [i for i in ours if ours[i] != theirs.get(i)][:3]
            fail("%s: export differs from the last frame at ids %s" % (stage, bad))
        if exported[0]["box"] != last["box"] or exported[0]["flags"] != last["flags"]:
            fail("%s: export box %s, dump box %s" % (stage, exported[0]["box"], last["box"]))
        # CSV: the header names and the same numbers (CSV ids are the grain ids, LAMMPS's + 1)
        rows = [line.split(",") for line in open(out + ".csv").read().split("\n") if line]
        header = "id,x,y,r,species,fixed,vx,vy,omega,angle".split(",")
        if rows[0] != header or len(rows) - 1 != last["count"]:
            fail("%s: CSV header %s, %d rows" % (stage, rows[0], len(rows) - 1))
        pairs = [("x", "x"), ("y", "y"), ("r", "radius"), ("vx", "vx"), ("vy", "vy"),
                 ("omega", "omegaz")]
        dump = by_id(last["columns"], last["rows"], [p[1] for p in pairs])
        for row in rows[1:]:
            ident = str(int(row[0]) + 1)
            if [row[header.index(p[0])] for p in pairs] != dump.get(ident):
                fail("%s: CSV row of grain %s differs from the dump" % (stage, row[0]))
        text = open(out + ".vtp").read()
        if 'NumberOfPoints="%d"' % last["count"] not in text or 'Name="radius"' not in text:
            fail("%s: the exported .vtp lacks its points or radius" % stage)
        checked += 1
    print("sablier export equals the last dump frame of %d stages (lammps, csv, vtk)" % checked)


def main(argv):
    if len(argv) == 5 and argv[1] == "run":
        case_run(argv[2], argv[3], argv[4])
    elif len(argv) == 3 and argv[1] == "lammps":
        case_lammps(argv[2])
    elif len(argv) == 3 and argv[1] == "vtk":
        case_vtk(argv[2])
    elif len(argv) == 4 and argv[1] == "export":
        case_export(argv[2], argv[3])
    else:
        print(__doc__)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
