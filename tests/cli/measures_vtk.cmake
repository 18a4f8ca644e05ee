# SPDX-License-Identifier: MIT
# cmake -P measures_vtk.cmake -DSABLIER=... -DSCENE=column.scene -DWORK=dir
# The grid measure's .vti files open in VTK's own XML reader (Debian python3-vtk9 under
# /usr/bin/python3) with a point per node and one array per field, each at the time the measure's
# .pvd gives it (the file's TimeValue = the .pvd's timestep); skipped (77) without VTK.
execute_process(COMMAND /usr/bin/python3 -c "import vtk" RESULT_VARIABLE have_vtk
                OUTPUT_QUIET ERROR_QUIET)
if(NOT have_vtk EQUAL 0)
  message("python3-vtk9 is not installed: skipped")
  return() # ctest sees the SKIP_REGULAR_EXPRESSION
endif()
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${SABLIER} run ${SCENE} --out ${WORK} --quiet
                        --set stages.rain.time.end=4 --set stages.rest.time.end=2
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "sablier run ${SCENE}: exit ${rc}\n${err}")
endif()
set(check [=[
import sys, glob, os, vtk
import xml.etree.ElementTree as ET
files = sorted(glob.glob(sys.argv[1] + "/field/field_*.vti"))
assert len(files) == 3, files
pvd = ET.parse(sys.argv[1] + "/field.pvd").getroot()
listed = [(float(d.get("timestep")), d.get("file")) for d in pvd.iter("DataSet")]
assert [os.path.join(sys.argv[1], f) for _, f in listed] == files, listed
times = [t for t, _ in listed]
assert times == sorted(times) and len(set(times)) == 3, times
for t, name in zip(times, files):
    r = vtk.vtkXMLImageDataReader()
    r.SetFileName(name)
    r.Update()
    o = r.GetOutput()
    d = o.GetPointData()
    names = [d.GetArrayName(i) for i in range(d.GetNumberOfArrays())]
    assert o.GetNumberOfPoints() == 20 * 36 and o.GetDimensions() == (20, 36, 1), name
    assert names == ["phi", "vx", "vy", "syy", "p"], names
    assert abs(o.GetOrigin()[0] - 0.5) < 1e-12 and abs(o.GetSpacing()[1] - 1.0) < 1e-12
    assert o.GetFieldData().GetArray("TimeValue").GetValue(0) == t, name
print("ok", len(files))
]=])
execute_process(COMMAND /usr/bin/python3 -c "${check}" ${WORK} RESULT_VARIABLE rc
                OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "VTK's reader refused the .vti files:\n${out}${err}")
endif()
