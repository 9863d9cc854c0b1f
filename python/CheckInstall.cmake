# Installs the build tree into a scratch prefix and imports the installed
# package there with a plain python3 (PYTHONPATH = the package folder under
# the prefix), which must find libpenumbra through its $ORIGIN-relative
# RPATH and render (run by CTest as Python.installed).
# Usage: cmake -DBUILD_DIR=... -DPREFIX=... -DPYTHON=... -DPY_DIR=<relative> -P CheckInstall.cmake
file(REMOVE_RECURSE ${PREFIX})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX}
                RESULT_VARIABLE _rc OUTPUT_QUIET)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${_rc})")
endif()
set(_script [=[
import pathlib, sys
import penumbra
assert pathlib.Path(penumbra.__file__).resolve().is_relative_to(pathlib.Path(sys.argv[1]).resolve()), penumbra.__file__
s = penumbra.Scene()
s.add_sphere((0, 0, 0), 1.0, s.add_material(kd=0.0, ke=2.0))
image = penumbra.Renderer().render(s, penumbra.Camera(eye=(0, 0, 4), look_at=(0, 0, 0)), width=8, height=8, spp=1)
assert image[4, 4, 0] == 2.0, image[4, 4]
print("installed module OK:", penumbra.__file__)
]=])
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=LD_LIBRARY_PATH PYTHONPATH=${PREFIX}/${PY_DIR}
                        ${PYTHON} -c "${_script}" ${PREFIX}
                WORKING_DIRECTORY ${PREFIX} RESULT_VARIABLE _rc)
file(REMOVE_RECURSE ${PREFIX})
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "the installed module did not import and render (${_rc})")
endif()
