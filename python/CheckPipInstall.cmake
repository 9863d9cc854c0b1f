# `pip install --no-build-isolation .` into a scratch venv (with the system's
# site packages, for Debian's numpy and setuptools), then imports the package
# from the venv and renders (run by CTest as Python.pip_install). Skips when
# the interpreter cannot make a venv with pip (Debian: python3-venv missing).
# Usage: cmake -DSOURCE_DIR=... -DVENV=... -DPIP_BUILD=<a build folder> -DPYTHON=... -P CheckPipInstall.cmake
file(REMOVE_RECURSE ${VENV})
execute_process(COMMAND ${PYTHON} -m venv --system-site-packages ${VENV}
                RESULT_VARIABLE _rc OUTPUT_VARIABLE _out ERROR_VARIABLE _out)
if(NOT _rc EQUAL 0)
  file(REMOVE_RECURSE ${VENV})
  message("SKIP: ${PYTHON} -m venv failed (install python3-venv): ${_out}")
  return()
endif()
set(_env PENUMBRA_BUILD_DIR=${PIP_BUILD})
# --no-index: nothing is downloaded; numpy, setuptools and wheel come from the system.
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH ${_env}
                        ${VENV}/bin/python -m pip install --no-build-isolation --no-index ${SOURCE_DIR}
                RESULT_VARIABLE _rc OUTPUT_VARIABLE _out ERROR_VARIABLE _out)
if(NOT _rc EQUAL 0)
  file(REMOVE_RECURSE ${VENV})
  message(FATAL_ERROR "pip install failed (${_rc}):\n${_out}")
endif()
set(_script [=[
import pathlib, sys
import penumbra
assert pathlib.Path(penumbra.__file__).resolve().is_relative_to(pathlib.Path(sys.prefix).resolve()), penumbra.__file__
s = penumbra.Scene()
s.add_sphere((0, 0, 0), 1.0, s.add_material(kd=0.0, ke=2.0))
image = penumbra.Renderer().render(s, penumbra.Camera(eye=(0, 0, 4), look_at=(0, 0, 0)), width=8, height=8, spp=1)
assert image[4, 4, 0] == 2.0, image[4, 4]
png = image.framebuffer.to_png()
assert png[:8] == b"\x89PNG\r\n\x1a\n"   # the image module loads from the venv too
print("pip-installed module OK:", penumbra.__file__)
]=])
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=LD_LIBRARY_PATH --unset=PYTHONPATH
                        ${VENV}/bin/python -c "${_script}"
                WORKING_DIRECTORY ${VENV} RESULT_VARIABLE _rc)
file(REMOVE_RECURSE ${VENV})
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "the pip-installed module did not import and render (${_rc})")
endif()
