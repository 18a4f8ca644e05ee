# SPDX-License-Identifier: MIT
# cmake -P measures_vtk.cmake -DSABLIER=... -DSCENE=column.scene -DWORK=dir
# The grid measure's .vti files open in VTK's own XML reader (Debian python3-vtk9 under
# /usr/bin/python3) with a point per node and one array per field; skipped (77) without VTK.
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
import sys, glob, vtk
files = sorted(glob.glob(sys.argv[1] + "/field/field_*.vti"))
assert len(files) == 3, files
for name in files:
    r = vtk.vtkXMLImageDataReader()
    r.SetFileName(name)
    r.Update()
    o = r.GetOutput()
    d = o.GetPointData()
    names = [d.GetArrayName(i) for i in range(d.GetNumberOfArrays())]
    assert o.GetNumberOfPoints() == 20 * 36 and o.GetDimensions() == (20, 36, 1), name
    assert names == ["phi", "vx", "vy", "syy", "p"], names
    assert abs(o.GetOrigin()[0] - 0.5) < 1e-12 and abs(o.GetSpacing()[1] - 1.0) < 1e-12
print("ok", len(files))
]=])
execute_process(COMMAND /usr/bin/python3 -c "${check}" ${WORK} RESULT_VARIABLE rc
                OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "VTK's reader refused the .vti files:\n${out}${err}")
endif()
